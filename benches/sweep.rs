//! Benches of parameter sweeps on `studies/seed-hunting.toml` (lateral × longitudinal
//! primary stiffness, log-spaced):
//! * `kalker_map_100x100`: 10 000 Kalker critical speeds (aim: < 0.2 s);
//! * `nonlinear_map_20x20`: 400 nonlinear critical speeds from the continuation, cycles up to
//!   1 mm amplitude as in `benches/bifurcation.rs` `seed_hunting_v_nl` (aim: < 1 min);
//!
//! each with 1 and 2 threads (a local rayon pool per case; parallel efficiency =
//! t1 / (2 t2), aim > 85 %). In memory: no records file.

use criterion::{criterion_group, criterion_main, Criterion};
use critspeed::sweep::{self, Shard, SweepOptions, SweepStudy};
use std::hint::black_box;
use std::time::Duration;

fn study(name: &str, n: usize, compute: &str, extra: &str) -> SweepStudy {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/studies/seed-hunting.toml");
    let text = std::fs::read_to_string(path).expect("study");
    let text = text.replace("name = \"seed-hunting\"", &format!("name = \"{name}\""))
        + extra
        + &format!(
            "\n[sweep]\naxes = [ {{ key = \"suspension.longitudinal_stiffness\", from = \"100 N/mm\", \
to = \"10000 N/mm\", count = {n}, spacing = \"log\" }},\n{{ key = \"suspension.lateral_stiffness\", \
from = \"100 N/mm\", to = \"3000 N/mm\", count = {n}, spacing = \"log\" }} ]\ncompute = [{compute}]\n"
        );
    SweepStudy::parse(&text, name).expect("sweep study")
}

fn run(s: &SweepStudy, threads: usize) -> usize {
    let opts = SweepOptions {
        threads: Some(threads),
        shard: Shard::ALL,
        records: None,
    };
    sweep::run(s, &opts, None).expect("sweep").rows.len()
}

fn benches(c: &mut Criterion) {
    let linear = study("kalker-map", 100, "\"kalker\"", "");
    let nonlinear = study(
        "nonlinear-map",
        20,
        "\"nonlinear\"",
        "\n[bifurcation]\nmax_amplitude = \"1 mm\"\n",
    );
    let mut g = c.benchmark_group("sweep");
    g.sample_size(10).warm_up_time(Duration::from_secs(1));
    for threads in [1, 2] {
        g.measurement_time(Duration::from_secs(5));
        g.bench_function(format!("kalker_map_100x100/threads_{threads}"), |b| {
            b.iter(|| run(black_box(&linear), threads))
        });
    }
    for threads in [1, 2] {
        g.measurement_time(Duration::from_secs(30));
        g.bench_function(format!("nonlinear_map_20x20/threads_{threads}"), |b| {
            b.iter(|| run(black_box(&nonlinear), threads))
        });
    }
    g.finish();
}

criterion_group!(sweep_benches, benches);
criterion_main!(sweep_benches);
