//! Benches of issue 11's goals, each on one and on two rayon threads:
//! * `cone_branch`: `studies/seed-hunting-cone.toml`, Hopf point and the branch to 8 mm with
//!   Floquet multipliers (the AUTO-07p peer comparison, docs/performance.md);
//! * `s1002_diagram`: `studies/s1002-uic60.toml`, the whole diagram (Hopf point, subcritical
//!   branch, fold, stable branch to 150 m/s);
//! * `cubic_fold_branch`: `studies/cubic-fold.toml` (subcritical, one fold);
//! * `padded_30_states`: one shooting linearisation of a 30-state field (the Hopf normal form
//!   plus 28 decaying states) with 1 and 2 segments: the variational equations' cost at the
//!   vehicle models' size.

use criterion::{criterion_group, criterion_main, Criterion};
use critspeed::bifurcation::analyse;
use critspeed::continuation::{OrbitPoint, Shooting};
use critspeed::reference::HopfNormalForm;
use critspeed::study;
use critspeed::system::ode::{OdeOptions, Tolerances, VectorField};
use nalgebra::{SMatrix, SVector};
use std::hint::black_box;
use std::time::Duration;

fn pool(threads: usize) -> rayon::ThreadPool {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("thread pool")
}

fn study_bench(c: &mut Criterion, name: &str, file: &str, samples: usize, secs: u64) {
    let path = std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("studies")
        .join(file);
    let plan = study::load(&path).expect("study");
    let model = plan.model().expect("model");
    let mut g = c.benchmark_group(name);
    g.sample_size(samples)
        .measurement_time(Duration::from_secs(secs));
    for threads in [1, 2] {
        let p = pool(threads);
        // default segments (0): one per thread of the pool `analyse` runs in
        let opts = plan.bifurcation_options();
        g.bench_function(format!("{threads}_thread"), |b| {
            b.iter(|| p.install(|| analyse(&plan.name, black_box(&model), &opts)))
        });
    }
    g.finish();
}

/// The Hopf normal form in (x0, x1) plus 28 states decaying at rates 0.3 to 1.65.
struct Padded {
    core: HopfNormalForm,
}

impl VectorField<30> for Padded {
    fn rhs(&self, x: &SVector<f64, 30>, mu: f64) -> SVector<f64, 30> {
        let f = self.core.rhs(&SVector::<f64, 2>::new(x[0], x[1]), mu);
        SVector::from_fn(|k, _| {
            if k < 2 {
                f[k]
            } else {
                -(0.3 + 0.05 * k as f64) * x[k]
            }
        })
    }
    fn jacobian(&self, x: &SVector<f64, 30>, mu: f64) -> SMatrix<f64, 30, 30> {
        let j = self.core.jacobian(&SVector::<f64, 2>::new(x[0], x[1]), mu);
        SMatrix::from_fn(|r, c| match (r, c) {
            (r, c) if r < 2 && c < 2 => j[(r, c)],
            (r, c) if r == c => -(0.3 + 0.05 * r as f64),
            _ => 0.0,
        })
    }
}

fn padded(c: &mut Criterion) {
    let field = Padded {
        core: HopfNormalForm {
            omega: 2.0,
            a: 1.0,
            b: -1.0,
        },
    };
    let mut x0 = SVector::<f64, 30>::zeros();
    x0[0] = 0.8;
    let z = OrbitPoint {
        x0,
        period: std::f64::consts::PI,
        param: 0.8f64.powi(4) - 0.8f64.powi(2),
    };
    let mut g = c.benchmark_group("padded_30_states");
    g.sample_size(20).measurement_time(Duration::from_secs(5));
    for (threads, segments) in [(1, 1), (2, 1), (2, 2)] {
        let p = pool(threads);
        let s = Shooting {
            field: &field,
            symmetric: true,
            ode: OdeOptions {
                tol: Tolerances::new(1e-10, 1e-13).expect("tolerances"),
                ..OdeOptions::default()
            },
            parallel: true,
            busy: None,
            dp_rel: 1e-5,
            segments,
        };
        let seed = p.install(|| s.linearise(&z)).expect("linearisation").seed;
        g.bench_function(format!("{threads}_thread_{segments}_segment"), |b| {
            b.iter(|| p.install(|| s.linearise_from(black_box(&z), Some(&seed))))
        });
    }
    g.finish();
}

fn benches(c: &mut Criterion) {
    study_bench(c, "cone_branch", "seed-hunting-cone.toml", 20, 8);
    study_bench(c, "cubic_fold_branch", "cubic-fold.toml", 10, 8);
    study_bench(c, "s1002_diagram", "s1002-uic60.toml", 10, 40);
    padded(c);
}

criterion_group!(auto_peer, benches);
criterion_main!(auto_peer);
