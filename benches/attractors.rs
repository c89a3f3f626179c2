//! Benches of issue 19's goals, each on one and on two rayon threads:
//!
//! * `bifurcation_switching_dtu_bogie`: the continuation with branch switching of
//!   `studies/dtu-cooperrider-bogie.toml` (the whole diagram: Hopf point, every branch;
//!   goal < 5 s on 2 threads);
//! * `attractor_search_dtu_bogie`: the search for every attractor on the same study, from its
//!   continuation (24 initial states at 6 speeds, the descents and their bisections; goal
//!   < 30 s on 2 threads);
//! * `attractor_search_dtu_car`: the same on `studies/dtu-cooperrider-car.toml` (51 initial
//!   states at 6 speeds; goal < 3 min on 2 threads).
//!
//! The search is timed alone: its continuation is computed once, outside the loop, as the
//! command does before it searches. The whole commands are timed in docs/performance.md.
//!
//! Worst cases (issue 30: a plausible-looking change to a shipped study that made a run many
//! times slower), on the machine's threads:
//!
//! The tangent vector of the largest Lyapunov exponent (issue 30):
//!
//! * `lyapunov_tangent_s1002_bogie/{checked,free}`: 8 s (about 100 returns) of a chaotic
//!   motion of `studies/dtu-cooperrider-bogie-s1002.toml` at 135.96 m/s (the search's top
//!   speed) with one tangent vector, the vector in the error test or carried on the state's
//!   steps ([`critspeed::system::ode::TangentControl`]); the search computes one such exponent
//!   per chaotic initial state.
//!
//! * `worst_case/bifurcation_dtu_bogie_e2100`: the DTU bogie's diagram with
//!   `young_modulus = "2100 GPa"`, whose branch turns down to low speeds where the creep
//!   forces make the model stiff; it now ends with the stiffness stop at 7.2 m/s.

use criterion::{criterion_group, criterion_main, Criterion};
use critspeed::api::{self, Hooks, Prepared, Source};
use std::hint::black_box;
use std::path::PathBuf;
use std::time::Duration;

fn pool(threads: usize) -> rayon::ThreadPool {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("thread pool")
}

fn prepared(name: &str) -> Prepared {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("studies")
        .join(name);
    let plan = Source::file(&path).and_then(|s| s.plan()).expect("study");
    Prepared::new(plan).expect("model")
}

/// A shipped study with one line replaced (`key = …` at the start of a line), read from
/// `studies/` so that its relative paths resolve there.
fn perturbed(name: &str, key: &str, value: &str) -> Prepared {
    let folder = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("studies");
    let text = std::fs::read_to_string(folder.join(name)).expect("study text");
    let text: String = text
        .lines()
        .map(|l| {
            if l.starts_with(&format!("{key} =")) {
                format!("{key} = {value}\n")
            } else {
                format!("{l}\n")
            }
        })
        .collect();
    let source = Source {
        text,
        origin: format!("{name} with {key} = {value}"),
        folder: Some(folder),
    };
    Prepared::new(source.plan().expect("study")).expect("model")
}

fn worst_cases(c: &mut Criterion) {
    let stiff = perturbed(
        "dtu-cooperrider-bogie.toml",
        "young_modulus",
        "\"2100 GPa\"",
    );
    let mut g = c.benchmark_group("worst_case");
    g.sample_size(10).measurement_time(Duration::from_secs(40));
    g.bench_function("bifurcation_dtu_bogie_e2100", |b| {
        b.iter(|| api::bifurcation(black_box(&stiff), Hooks::default()).map(|r| r.cycles.len()))
    });
    g.finish();
}

fn lyapunov_tangent(c: &mut Criterion) {
    use critspeed::system::ode::{
        integrate, integrate_tangent, OdeOptions, TangentControl, Tolerances,
    };
    use nalgebra::SVector;
    const N: usize = 12;
    let plan = prepared("dtu-cooperrider-bogie-s1002.toml").plan().clone();
    let model = plan.model().expect("model");
    assert_eq!(model.states(), N, "the S1002 bogie has 12 states");
    let speed = 135.96;
    let opts = OdeOptions {
        tol: Tolerances::new(1e-8, 1e-11).expect("valid"),
        ..OdeOptions::default()
    };
    // onto the chaotic attractor: a 6 mm kick of the leading wheelset, 20 s
    let mut x0 = SVector::<f64, N>::zeros();
    x0[0] = 6e-3;
    let x = integrate(&model, speed, &x0, 20.0, &opts)
        .expect("simulates")
        .x;
    let w = SVector::<f64, N>::from_element(1.0).normalize();
    let mut g = c.benchmark_group("lyapunov_tangent_s1002_bogie");
    g.sample_size(10).measurement_time(Duration::from_secs(20));
    for (name, control) in [
        ("checked", TangentControl::Checked),
        ("free", TangentControl::Free),
    ] {
        g.bench_function(name, |b| {
            b.iter(|| integrate_tangent(&model, speed, black_box(&x), &w, 8.0, &opts, control))
        });
    }
    g.finish();
}

fn benches(c: &mut Criterion) {
    let bogie = prepared("dtu-cooperrider-bogie.toml");
    let mut g = c.benchmark_group("bifurcation_switching_dtu_bogie");
    g.sample_size(10).measurement_time(Duration::from_secs(30));
    for threads in [1, 2] {
        let p = pool(threads);
        g.bench_function(format!("{threads}_thread"), |b| {
            b.iter(|| p.install(|| api::bifurcation(black_box(&bogie), Hooks::default())))
        });
    }
    g.finish();
    for (study, name, secs) in [
        (&bogie, "attractor_search_dtu_bogie", 60),
        (
            &prepared("dtu-cooperrider-car.toml"),
            "attractor_search_dtu_car",
            300,
        ),
    ] {
        let branches = api::bifurcation(study, Hooks::default()).expect("continuation");
        let mut g = c.benchmark_group(name);
        g.sample_size(10)
            .measurement_time(Duration::from_secs(secs));
        for threads in [1, 2] {
            let p = pool(threads);
            g.bench_function(format!("{threads}_thread"), |b| {
                b.iter(|| p.install(|| api::search(black_box(study), &branches, None, None)))
            });
        }
        g.finish();
    }
}

criterion_group!(attractor_benches, lyapunov_tangent, worst_cases, benches);
criterion_main!(attractor_benches);
