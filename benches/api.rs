//! Benches of the library's front door (`critspeed::api`) on studies/seed-hunting.toml: what a
//! Python `critspeed.linear(path)` call computes, without Python, so that the difference with a
//! `timeit` of the Python call is the binding's overhead (docs/python.md).
//!
//! * `api_linear_file`: read the file, validate the plan, build the model, the linear analysis
//!   (critical speeds and both 300-speed spectra), the JSON object.
//! * `api_linear_prepared`: the linear analysis and its JSON object from a built model.
//! * `api_linear_small_text`: `api_linear_file` from TOML text with a small linear section
//!   (`grid_points = 16`, `spectrum_points = 2`), so that the computation is short and a
//!   Python call's overhead shows: the same text is timed from Python in docs/python.md.

use criterion::{criterion_group, criterion_main, Criterion};
use critspeed::api::{self, Prepared, Source};
use std::hint::black_box;
use std::path::Path;

fn benches(c: &mut Criterion) {
    let path = Path::new(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/studies/seed-hunting.toml"
    ));
    c.bench_function("api_linear_file", |b| {
        b.iter(|| {
            let p = Prepared::new(Source::file(black_box(path))?.plan()?)?;
            Ok::<_, api::Failure>(critspeed::output::linear_json(&api::linear(&p)?))
        })
    });
    let small = std::fs::read_to_string(path)
        .expect("seed-hunting study")
        .replace(
            "[linear]",
            "[linear]\ngrid_points = 16\nspectrum_points = 2",
        );
    c.bench_function("api_linear_small_text", |b| {
        b.iter(|| {
            let p = Prepared::new(Source::text(black_box(&small), "<TOML text>").plan()?)?;
            Ok::<_, api::Failure>(critspeed::output::linear_json(&api::linear(&p)?))
        })
    });
    let p = Source::file(path)
        .and_then(|s| s.plan())
        .and_then(Prepared::new)
        .expect("seed-hunting study");
    c.bench_function("api_linear_prepared", |b| {
        b.iter(|| api::linear(black_box(&p)).map(|r| critspeed::output::linear_json(&r)))
    });
}

criterion_group!(api_benches, benches);
criterion_main!(api_benches);
