//! Benches of vehicles (docs/model.md §11) on the shipped DTU Cooperrider studies.
//!
//! * `vehicle/rhs_{bogie,car}`: one f(x; V) of 12 and 28 states; `vehicle/rhs_car_s1002`: the
//!   car on S1002/UIC60 profiles (the profile-contact table, flange included).
//! * `vehicle/eigenvalues_car`: the eigenvalues of the car's 28-state Jacobian at 100 m/s
//!   (one point of that scan).
//! * `vehicle/variational_{bogie,car}`: f and JΦ of the DTU bogie and car (one stage of the
//!   variational equations, as every shooting Newton step integrates them).
//! * `vehicle/simulate_car_s1002_30s`: `critspeed simulate` of the S1002 car without the
//!   files: 30 s at 100 m/s from y = 6 mm, rtol 1e-9, sampled every 2 ms.
//! * `vehicle/linear_{bogie,car}`: the linear (Kalker) critical-speed solve from the model:
//!   J0, J1 and the eigenvalue scan over the study's range and grid.
//! * `vehicle/map_bogie_20x20`: a 20×20 stability map of the bogie (V_L and V_H over
//!   primary longitudinal stiffness × secondary yaw damping), on the machine's threads.
//!
//! * `vehicle/diagram_bogie/{1,2}`: the bogie's whole bifurcation diagram (Hopf point, the
//!   branch through its three folds to 7 mm), library call, on a rayon pool of 1 and 2 threads
//!   (the default segments: one per thread).
//! * `vehicle/diagram_car_60/{1,2}`: the first 60 cycles of the car's diagram (through the
//!   torus point and the 222.9 m/s fold), the same way.
//! * `vehicle/rhs_car_series`, `vehicle/variational_car_series`,
//!   `vehicle/diagram_car_60_series/1`: the same car with its eight yaw and secondary lateral
//!   dampers on series stiffness (10 and 5 MN/m; docs/model.md §13: four strokes, 32 states),
//!   against `rhs_car`, `variational_car` and `diagram_car_60/1` (issue 32's aim: the diagram
//!   within 1.3 times the rigid car's).
//! * `vehicle/rhs_car_stops`, `vehicle/variational_car_stops`: the same car with a 5 mm
//!   secondary and a 2 mm primary bump stop (docs/model.md §13: six stops, 28 states), at a state
//!   where every stop is engaged, against `rhs_car` and `variational_car`.
//! * `vehicle/diagram_car_whole/{1,2}`: the car's whole diagram (about 140 cycles to 7 mm,
//!   its folds, V_NL) on 1 and 2 threads: the vehicle issue's aim (under 10 s on this 2-core
//!   machine) and issue 11's rayon speed-up; ten samples each take about four minutes.

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use critspeed::bifurcation;
use critspeed::contact::creep::CreepLaw;
use critspeed::stability::{critical_speeds, eigenvalues, LinearSystem};
use critspeed::study;
use critspeed::sweep::{self, Shard, SweepOptions, SweepStudy};
use critspeed::system::ode::VectorField;
use nalgebra::SVector;
use std::hint::black_box;
use std::path::Path;

fn load(name: &str) -> (study::Plan, critspeed::model::Vehicle) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("studies")
        .join(name);
    let plan = study::load(&path).expect("study");
    let model = plan.model().expect("model");
    (plan, model)
}

fn benches(c: &mut Criterion) {
    let (bp, bogie) = load("dtu-cooperrider-bogie.toml");
    let (cp, car) = load("dtu-cooperrider-car.toml");
    let xb = SVector::<f64, 12>::from_fn(|i, _| 1e-4 * (i as f64 + 1.0).sin());
    let xc = SVector::<f64, 28>::from_fn(|i, _| 1e-4 * (i as f64 + 1.0).sin());
    c.bench_function("vehicle/rhs_bogie", |b| {
        b.iter(|| VectorField::<12>::rhs(&bogie, black_box(&xb), black_box(100.0)))
    });
    c.bench_function("vehicle/rhs_car", |b| {
        b.iter(|| VectorField::<28>::rhs(&car, black_box(&xc), black_box(100.0)))
    });
    let (_, s1002) = load("dtu-cooperrider-car-s1002.toml");
    c.bench_function("vehicle/rhs_car_s1002", |b| {
        b.iter(|| VectorField::<28>::rhs(&s1002, black_box(&xc), black_box(100.0)))
    });
    let phi = nalgebra::SMatrix::<f64, 28, 28>::from_fn(|i, j| {
        f64::from(u8::from(i == j)) + 1e-3 * ((i * 28 + j) as f64).sin()
    });
    let phib = nalgebra::SMatrix::<f64, 12, 12>::from_fn(|i, j| {
        f64::from(u8::from(i == j)) + 1e-3 * ((i * 12 + j) as f64).sin()
    });
    c.bench_function("vehicle/variational_bogie", |b| {
        b.iter(|| {
            VectorField::<12>::rhs_variational(&bogie, black_box(&xb), 100.0, black_box(&phib))
        })
    });
    c.bench_function("vehicle/variational_car", |b| {
        b.iter(|| VectorField::<28>::rhs_variational(&car, black_box(&xc), 100.0, black_box(&phi)))
    });
    let sim_opts = critspeed::system::ode::OdeOptions {
        tol: critspeed::system::ode::Tolerances::new(1e-9, 1e-12).expect("tolerances"),
        ..Default::default()
    };
    let x6 = critspeed::simulate::lateral_start(&s1002, 6e-3);
    let mut group = c.benchmark_group("vehicle");
    group.sample_size(10);
    group.bench_function("simulate_car_s1002_30s", |b| {
        b.iter(|| {
            critspeed::simulate::simulate(black_box(&s1002), 100.0, &x6, 30.0, 2e-3, &sim_opts)
                .map(|h| h.t.len())
        })
    });
    group.finish();
    let kb = bogie.with_law(CreepLaw::Kalker);
    let kc = car.with_law(CreepLaw::Kalker);
    // once faer's eigenvector solve of a 28×28 matrix has run in the process, the vector
    // registers' upper halves are left dirty on this machine and all SSE code runs 2 to 3
    // times slower; `eigenvalues` clears them first (src/stability/small_eigen.rs says more)
    let jc = LinearSystem::<28>::at_centre(&kc).jacobian(100.0);
    c.bench_function("vehicle/eigenvalues_car", |b| {
        b.iter(|| eigenvalues(black_box(&jc)))
    });
    c.bench_function("vehicle/linear_bogie", |b| {
        b.iter(|| {
            let sys = LinearSystem::<12>::at_centre(black_box(&kb));
            critical_speeds(&sys, CreepLaw::Kalker, &bp.linear)
        })
    });
    c.bench_function("vehicle/linear_car", |b| {
        b.iter(|| {
            let sys = LinearSystem::<28>::at_centre(black_box(&kc));
            critical_speeds(&sys, CreepLaw::Kalker, &cp.linear)
        })
    });
    let text = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("studies/dtu-cooperrider-bogie.toml"),
    )
    .expect("study text")
        + "\n[sweep]\naxes = [ { key = \"suspension.longitudinal_stiffness\", from = \"1 MN/m\", to = \"10 MN/m\", count = 20, spacing = \"log\" },\n\
           { key = \"secondary.yaw_damping\", from = \"20 kN s/m\", to = \"400 kN s/m\", count = 20, spacing = \"log\" } ]\n\
           compute = [\"kalker\", \"hopf\"]\n";
    let folder = Path::new(env!("CARGO_MANIFEST_DIR")).join("studies");
    let sweep = SweepStudy::parse_in(&text, "bench", Some(&folder)).expect("sweep study");
    let mut group = c.benchmark_group("vehicle");
    group.sample_size(10);
    group.bench_function("map_bogie_20x20", |b| {
        b.iter(|| {
            let opts = SweepOptions {
                threads: None,
                shard: Shard::ALL,
                records: None,
            };
            sweep::run(black_box(&sweep), &opts, None).map(|r| r.rows.len())
        })
    });
    group.finish();
    series(c);
    stops(c);
    diagrams(c, &bp, &bogie, &cp, &car);
}

/// The DTU car with its yaw and secondary lateral dampers on series stiffness.
fn series(c: &mut Criterion) {
    let folder = Path::new(env!("CARGO_MANIFEST_DIR")).join("studies");
    let text = std::fs::read_to_string(folder.join("dtu-cooperrider-car.toml"))
        .expect("study text")
        .replace(
            "[secondary]",
            "[secondary]\nyaw_damper_series_stiffness = \"10 MN/m\"\n\
             lateral_damper_series_stiffness = \"5 MN/m\"",
        );
    let plan = study::parse_in(&text, "series", Some(&folder)).expect("study");
    let car = plan.model().expect("model");
    assert_eq!(car.states(), 32);
    let x = SVector::<f64, 32>::from_fn(|i, _| 1e-4 * (i as f64 + 1.0).sin());
    c.bench_function("vehicle/rhs_car_series", |b| {
        b.iter(|| VectorField::<32>::rhs(&car, black_box(&x), black_box(100.0)))
    });
    let phi = nalgebra::SMatrix::<f64, 32, 32>::from_fn(|i, j| {
        f64::from(u8::from(i == j)) + 1e-3 * ((i * 32 + j) as f64).sin()
    });
    c.bench_function("vehicle/variational_car_series", |b| {
        b.iter(|| VectorField::<32>::rhs_variational(&car, black_box(&x), 100.0, black_box(&phi)))
    });
    let mut group = c.benchmark_group("vehicle");
    group
        .sample_size(10)
        .sampling_mode(criterion::SamplingMode::Flat);
    group.measurement_time(std::time::Duration::from_secs(60));
    let mut opts = plan.bifurcation_options();
    opts.max_points = 60;
    time_diagram(&mut group, "diagram_car_60_series", 1, &car, &opts);
    group.finish();
}

/// The DTU car with lateral bump stops on its primary and secondary, all engaged.
fn stops(c: &mut Criterion) {
    let folder = Path::new(env!("CARGO_MANIFEST_DIR")).join("studies");
    let text = std::fs::read_to_string(folder.join("dtu-cooperrider-car.toml"))
        .expect("study text")
        .replace(
            "[secondary]",
            "[secondary]\nbump_stop_clearance = \"5 mm\"\nbump_stop_stiffness = \"2 MN/m\"",
        )
        .replace(
            "[suspension]",
            "[suspension]\nbump_stop_clearance = \"2 mm\"\nbump_stop_stiffness = \"5 MN/m\"",
        );
    let plan = study::parse_in(&text, "stops", Some(&folder)).expect("study");
    let car = plan.model().expect("model");
    assert_eq!((car.states(), car.stops.len()), (28, 6));
    // wheelsets 6 mm out one way, frames 8 mm the other: every stop engaged
    let x = SVector::<f64, 28>::from_fn(|i, _| match i {
        0 | 2 | 4 | 6 => 6e-3,
        8 | 10 => -8e-3,
        _ => 1e-4 * (i as f64 + 1.0).sin(),
    });
    c.bench_function("vehicle/rhs_car_stops", |b| {
        b.iter(|| VectorField::<28>::rhs(&car, black_box(&x), black_box(100.0)))
    });
    let phi = nalgebra::SMatrix::<f64, 28, 28>::from_fn(|i, j| {
        f64::from(u8::from(i == j)) + 1e-3 * ((i * 28 + j) as f64).sin()
    });
    c.bench_function("vehicle/variational_car_stops", |b| {
        b.iter(|| VectorField::<28>::rhs_variational(&car, black_box(&x), 100.0, black_box(&phi)))
    });
}

/// The bifurcation diagrams on rayon pools of 1 and 2 threads.
fn diagrams(
    c: &mut Criterion,
    bp: &study::Plan,
    bogie: &critspeed::model::Vehicle,
    cp: &study::Plan,
    car: &critspeed::model::Vehicle,
) {
    let mut group = c.benchmark_group("vehicle");
    // flat sampling: ten runs of several seconds each (linear sampling needs 55)
    group
        .sample_size(10)
        .sampling_mode(criterion::SamplingMode::Flat);
    group.measurement_time(std::time::Duration::from_secs(60));
    let bogie_opts = bp.bifurcation_options();
    let mut car_opts = cp.bifurcation_options();
    car_opts.max_points = 60;
    for threads in [1, 2] {
        time_diagram(&mut group, "diagram_bogie", threads, bogie, &bogie_opts);
        time_diagram(&mut group, "diagram_car_60", threads, car, &car_opts);
    }
    let whole = cp.bifurcation_options();
    group.measurement_time(std::time::Duration::from_secs(100));
    for threads in [1, 2] {
        time_diagram(&mut group, "diagram_car_whole", threads, car, &whole);
    }
    group.finish();
}

/// Times `bifurcation::analyse` of `model` with `opts` on a rayon pool of `threads` threads.
fn time_diagram(
    group: &mut criterion::BenchmarkGroup<'_, criterion::measurement::WallTime>,
    id: &str,
    threads: usize,
    model: &critspeed::model::Vehicle,
    opts: &critspeed::bifurcation::BifurcationOptions,
) {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("thread pool");
    group.bench_with_input(BenchmarkId::new(id, threads), &threads, |b, _| {
        b.iter(|| pool.install(|| bifurcation::analyse(id, black_box(model), opts)))
    });
}

criterion_group!(vehicle, benches);
criterion_main!(vehicle);
