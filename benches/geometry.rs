//! Bench of the contact-geometry table: the rigid two-point contact solve at 1001 lateral
//! positions, with slopes and the Hertz patch at each: (1) the seed's cone on its circular
//! rail head, (2) the S1002 / UIC60 1:40 point-list profiles (issue 5 asks < 50 ms for 1000
//! positions of a profile pair).

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
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("studies/s1002-uic60.toml");
    let plan = study::load(&path).expect("S1002/UIC60 study");
    let mut spec = plan.table_spec();
    spec.nodes = 1001;
    c.bench_function("profiles_s1002_uic60_table_1001_positions", |b| {
        b.iter(|| ContactTable::build(black_box(&plan.contact.geometry), black_box(&spec)))
    });
}

criterion_group!(geometry, benches);
criterion_main!(geometry);
