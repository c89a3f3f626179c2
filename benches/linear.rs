//! Benches of the linear analysis on the seed study (embedded) and the seed cone reference.
//!
//! * `rhs`: one evaluation of f(x; V) (Shen law, away from the centre).
//! * `jacobian_eigen`: the exact Jacobian at the centre plus its eigen-decomposition.
//! * `critical_speed`: one complete linear critical-speed solve (Kalker), scan + Brent.
//! * `linearise_and_solve`: the same from the model, including building J0, J1.

use criterion::{criterion_group, criterion_main, Criterion};
use critspeed::contact::creep::CreepLaw;
use critspeed::stability::{critical_speeds, spectrum_at, LinearOptions, LinearSystem};
use critspeed::study;
use nalgebra::Vector4;
use std::hint::black_box;

fn benches(c: &mut Criterion) {
    let plan = study::parse(study::DEFAULT_STUDY, "seed").expect("seed study");
    let model = plan.model().expect("seed model");
    let kalker = model.with_law(CreepLaw::Kalker);
    let x = Vector4::new(3e-3, 1e-3, 0.02, -0.01);
    c.bench_function("rhs", |b| {
        b.iter(|| model.rhs_vec(black_box(&x), black_box(40.0)))
    });
    c.bench_function("jacobian_eigen", |b| {
        b.iter(|| {
            let (j, _) = model.jacobian(black_box(&Vector4::zeros()), black_box(40.0));
            spectrum_at(&j, 40.0)
        })
    });
    let sys = LinearSystem::at_centre(&kalker);
    let opts = LinearOptions::default();
    c.bench_function("critical_speed", |b| {
        b.iter(|| critical_speeds(black_box(&sys), CreepLaw::Kalker, black_box(&opts)))
    });
    c.bench_function("linearise_and_solve", |b| {
        b.iter(|| {
            let sys = LinearSystem::at_centre(black_box(&kalker));
            critical_speeds(&sys, CreepLaw::Kalker, &opts)
        })
    });
}

criterion_group!(linear, benches);
criterion_main!(linear);
