//! Benches of the linear analysis on the seed study (embedded) and the seed cone reference.
//!
//! * `rhs`: one evaluation of f(x; V) (Shen law, away from the centre), through the vehicle
//!   assembly (`rhs`) and through docs/model.md §8 written out for the single wheelset (`rhs_direct`):
//!   the cost of the assembly on the 4-state path.
//! * `jacobian`, `jacobian_direct`: the exact Jacobian the same two ways.
//! * `jacobian_eigen`: the exact Jacobian at the centre plus its eigen-decomposition.
//! * `critical_speed`: one complete linear critical-speed solve (Kalker), scan + Brent.
//! * `linearise_and_solve`: the same from the model, including building J0, J1.

use criterion::{criterion_group, criterion_main, Criterion};
use critspeed::contact::creep::CreepLaw;
use critspeed::stability::{critical_speeds, spectrum_at, LinearOptions, LinearSystem};
use critspeed::study;
use critspeed::system::ode::VectorField;
use nalgebra::Vector4;
use std::hint::black_box;

fn benches(c: &mut Criterion) {
    let plan = study::parse(study::DEFAULT_STUDY, "seed").expect("seed study");
    let model = plan.model().expect("seed model");
    let kalker = model.with_law(CreepLaw::Kalker);
    let direct = plan.wheelset_model().expect("seed wheelset");
    let x = Vector4::new(3e-3, 1e-3, 0.02, -0.01);
    c.bench_function("rhs", |b| {
        b.iter(|| VectorField::<4>::rhs(&model, black_box(&x), black_box(40.0)))
    });
    c.bench_function("rhs_direct", |b| {
        b.iter(|| direct.rhs_vec(black_box(&x), black_box(40.0)))
    });
    c.bench_function("jacobian", |b| {
        b.iter(|| VectorField::<4>::jacobian(&model, black_box(&x), black_box(40.0)))
    });
    c.bench_function("jacobian_direct", |b| {
        b.iter(|| direct.jacobian(black_box(&x), black_box(40.0)))
    });
    c.bench_function("jacobian_eigen", |b| {
        b.iter(|| {
            let j =
                VectorField::<4>::jacobian(&model, black_box(&Vector4::zeros()), black_box(40.0));
            spectrum_at(&j, 40.0)
        })
    });
    let sys = LinearSystem::<4>::at_centre(&kalker);
    let opts = LinearOptions::default();
    c.bench_function("critical_speed", |b| {
        b.iter(|| critical_speeds(black_box(&sys), CreepLaw::Kalker, black_box(&opts)))
    });
    c.bench_function("linearise_and_solve", |b| {
        b.iter(|| {
            let sys = LinearSystem::<4>::at_centre(black_box(&kalker));
            critical_speeds(&sys, CreepLaw::Kalker, &opts)
        })
    });
}

criterion_group!(linear, benches);
criterion_main!(linear);
