//! Bench of the contact-geometry table: the rigid two-point contact solve (cone on the seed's
//! circular rail head) at 1001 lateral positions, with exact slopes and the Hertz patch at
//! each (issue 5 asks < 50 ms for 1000 positions of a profile pair; profiles are not in yet).

use criterion::{criterion_group, criterion_main, Criterion};
use critspeed::contact::table::ContactTable;
use critspeed::study;
use std::hint::black_box;

fn benches(c: &mut Criterion) {
    let plan = study::parse(study::DEFAULT_STUDY, "seed").expect("seed study");
    let mut spec = plan.table_spec();
    spec.nodes = 1001;
    c.bench_function("geometry_table_1001_positions", |b| {
        b.iter(|| ContactTable::build(black_box(&plan.contact.geometry), black_box(&spec)))
    });
}

criterion_group!(geometry, benches);
criterion_main!(geometry);
