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

criterion_group!(attractor_benches, benches);
criterion_main!(attractor_benches);
