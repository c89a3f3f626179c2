//! Bench of the tabulated geometry (docs/model.md §3 method 3): reading and splining the DTU RSGEO
//! table (69 rows, 10 columns), and sampling it with the Hertz patch and the table's Kalker
//! coefficients onto a 1001-node contact table over ±8 mm.

use std::path::Path;

use criterion::{criterion_group, criterion_main, Criterion};
use critspeed::contact::table::ContactTable;
use critspeed::contact::tabulated::TabulatedGeometry;
use critspeed::study;
use std::hint::black_box;

fn benches(c: &mut Criterion) {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let file = root.join("studies/tables/dtu-rsgeo-1o40.csv");
    c.bench_function("tabulated_read_and_spline_dtu", |b| {
        b.iter(|| TabulatedGeometry::read(black_box(&file), 0.4248829))
    });
    let plan = study::load(&root.join("studies/dtu-rsgeo-wheelset.toml")).expect("DTU study");
    let mut spec = plan.table_spec();
    spec.nodes = 1001;
    c.bench_function("tabulated_contact_table_1001_positions", |b| {
        b.iter(|| ContactTable::build(black_box(&plan.contact.geometry), black_box(&spec)))
    });
}

criterion_group!(tabulated, benches);
criterion_main!(tabulated);
