//! Benches of `critspeed curve`'s Hopf and fold curves and of the first Lyapunov coefficient.
//!
//! * `curve_seed_stiffness_hopf`: V_L and V_H over the primary lateral stiffness of
//!   `studies/seed-stiffness-map.toml` (its `[curve]`: 100 to 3000 N/mm, log), both curves
//!   with l1 at every point and the stable region (the command's Hopf work; goal < 50 ms).
//! * `curve_dtu_bogie_yaw_damping_hopf`: the six Hopf curves of the DTU bogie over the
//!   yaw-damper rate (0 to 400 kN s/m), with its two double Hopf points.
//! * `curve_cubic_fold_friction_folds`: the fold curves and V_NL of `studies/cubic-fold.toml`
//!   over friction 0.05 to 0.6 (the diagrams at the study's own and at five grid values, the
//!   fold continued as the fold system over the range, solved at 12 friction values).
//! * `curve_flange_hysteresis_folds`: the two fold curves of `studies/flange-hysteresis.toml`
//!   over its lateral stiffness (800 to 1200 N/mm), whose cycles cross the flange clearance
//!   (the fixed-step tangents split at each crossing).
//! * `curve_dtu_bogie_yaw_damping_folds` and `curve_dtu_car_yaw_damping_folds`: the whole
//!   `critspeed curve` of `studies/dtu-cooperrider-bogie.toml` (0 to 400 kN s/m) and of
//!   `studies/dtu-car-yaw-damper-trade.toml` (20 to 640 kN s/m, log): Hopf curves, the six
//!   diagrams, every fold curve and V_NL (goals 10 s and 60 s on two threads); the bogie's
//!   symmetry-breaking curve is left out. Ten samples
//!   each: minutes; run them alone with `cargo bench --bench curve -- _folds`.
//! * `curve_dtu_bogie_yaw_damping_torus`: the torus (Neimark–Sacker) curves of the DTU bogie
//!   over the yaw-damper rate: its six diagrams and the one torus curve from them
//!   (`cargo bench --bench curve -- torus`).
//! * `first_lyapunov_seed_hunting`: l1 at the Shen Hopf point of `studies/seed-hunting.toml`
//!   (Richardson tableau of central differences of the exact Jacobian).

use criterion::{criterion_group, criterion_main, Criterion};
use critspeed::api::{self, Source};
use critspeed::curve::CurveKind;
use critspeed::stability::{critical_speeds, first_lyapunov, LinearSystem, LyapunovOptions};
use std::hint::black_box;
use std::path::PathBuf;

fn study(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("studies")
        .join(name)
}

/// The curve study of `studies/NAME` continuing only `curves`.
fn with_curves(name: &str, curves: &[CurveKind]) -> api::curve::CurveStudy {
    let source = Source::file(&study(name)).expect("study file");
    let mut s = api::curve::curve_study(&source).expect("curve study");
    s.spec.curves = curves.to_vec();
    s
}

fn hopf_only(name: &str) -> api::curve::CurveStudy {
    with_curves(name, &[CurveKind::Hopf])
}

fn benches(c: &mut Criterion) {
    let seed = hopf_only("seed-stiffness-map.toml");
    c.bench_function("curve_seed_stiffness_hopf", |b| {
        b.iter(|| api::curve::curve(black_box(&seed), None).expect("curves"))
    });
    let bogie = hopf_only("dtu-cooperrider-bogie.toml");
    let mut group = c.benchmark_group("slow");
    group.sample_size(10);
    group.bench_function("curve_dtu_bogie_yaw_damping_hopf", |b| {
        b.iter(|| api::curve::curve(black_box(&bogie), None).expect("curves"))
    });
    let cubic = with_curves("cubic-fold.toml", &[CurveKind::Fold]);
    group.bench_function("curve_cubic_fold_friction_folds", |b| {
        b.iter(|| api::curve::curve(black_box(&cubic), None).expect("curves"))
    });
    let flange = with_curves("flange-hysteresis.toml", &[CurveKind::Fold]);
    group.bench_function("curve_flange_hysteresis_folds", |b| {
        b.iter(|| api::curve::curve(black_box(&flange), None).expect("curves"))
    });
    let torus = with_curves("dtu-cooperrider-bogie.toml", &[CurveKind::Torus]);
    group.bench_function("curve_dtu_bogie_yaw_damping_torus", |b| {
        b.iter(|| api::curve::curve(black_box(&torus), None).expect("curves"))
    });
    group.finish();
    // V_L, V_H and V_NL: the Hopf and fold curves (the bogie's study also asks for its
    // symmetry-breaking curve, which V_NL does not need)
    let whole = |name: &str| with_curves(name, &[CurveKind::Hopf, CurveKind::Fold]);
    let (bogie, car) = (
        whole("dtu-cooperrider-bogie.toml"),
        whole("dtu-car-yaw-damper-trade.toml"),
    );
    let mut group = c.benchmark_group("very_slow");
    group.sample_size(10);
    group.sampling_mode(criterion::SamplingMode::Flat);
    group.bench_function("curve_dtu_bogie_yaw_damping_folds", |b| {
        b.iter(|| api::curve::curve(black_box(&bogie), None).expect("curves"))
    });
    group.bench_function("curve_dtu_car_yaw_damping_folds", |b| {
        b.iter(|| api::curve::curve(black_box(&car), None).expect("curves"))
    });
    group.finish();
    let plan = critspeed::study::load(&study("seed-hunting.toml")).expect("study");
    let model = plan.model().expect("model");
    let sys = LinearSystem::<4>::at_centre(&model);
    let found = critical_speeds(&sys, model.creep_law(), &plan.linear).expect("linear");
    let h = *found.critical().expect("a Hopf point");
    let omega = 2.0 * std::f64::consts::PI * h.frequency_hz;
    c.bench_function("first_lyapunov_seed_hunting", |b| {
        b.iter(|| {
            first_lyapunov::<4, _>(
                black_box(&model),
                h.speed_m_s,
                omega,
                &LyapunovOptions::default(),
            )
            .expect("l1")
        })
    });
}

criterion_group!(curve_benches, benches);
criterion_main!(curve_benches);
