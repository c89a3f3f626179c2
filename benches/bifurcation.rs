//! Benches of the nonlinear analysis on `studies/flange-hysteresis.toml`:
//! * `periodic_orbit_solve`: one cycle by Newton from a neighbouring cycle (speed +0.1 %);
//! * `bifurcation_diagram`: the whole branch, Hopf point to the 12 mm amplitude bound,
//!   with both folds located;
//! * `seed_hunting_v_nl`: V_NL of `studies/seed-hunting.toml` (compare `benches/ramp.rs`).

use criterion::{criterion_group, criterion_main, Criterion};
use critspeed::bifurcation::{analyse, cycle_at};
use critspeed::study;
use std::hint::black_box;
use std::time::Duration;

fn benches(c: &mut Criterion) {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/studies/flange-hysteresis.toml"
    );
    let plan = study::load(std::path::Path::new(path)).expect("study");
    let model = plan.model().expect("model");
    let opts = plan.bifurcation_options();
    let branch = analyse(&plan.name, &model, &opts).expect("branch");
    let mid = branch.cycles[branch.cycles.len() / 2].clone();
    let x0: [f64; 4] = mid.x0.as_slice().try_into().expect("4 states");
    let mut g = c.benchmark_group("continuation");
    g.sample_size(20).measurement_time(Duration::from_secs(8));
    g.bench_function("periodic_orbit_solve", |b| {
        b.iter(|| {
            cycle_at(
                black_box(&model),
                mid.speed_m_s * 1.001,
                x0,
                mid.period_s,
                opts.rtol,
            )
        })
    });
    g.sample_size(10).measurement_time(Duration::from_secs(15));
    g.bench_function("bifurcation_diagram", |b| {
        b.iter(|| analyse(&plan.name, black_box(&model), &opts))
    });
    // The same quantity the ramp bench estimates (benches/ramp.rs, studies/seed-hunting.toml):
    // V_NL from the continuation: Hopf point, branch direction and stability of the first
    // cycles up to 1 mm amplitude, which settle sub- or supercritical.
    let sh = study::load(std::path::Path::new(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/studies/seed-hunting.toml"
    )))
    .expect("study");
    let sh_model = sh.model().expect("model");
    let mut sh_opts = sh.bifurcation_options();
    sh_opts.max_amplitude = 0.001;
    g.sample_size(20).measurement_time(Duration::from_secs(5));
    g.bench_function("seed_hunting_v_nl", |b| {
        b.iter(|| analyse(&sh.name, black_box(&sh_model), &sh_opts))
    });
    g.finish();
}

criterion_group!(continuation, benches);
criterion_main!(continuation);
