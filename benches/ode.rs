//! Integrator throughput on the Hopf normal form: 10 periods of the Stuart–Landau cycle with
//! the monodromy matrix, at the default tolerances (rtol 1e-10, atol 1e-12).

use std::hint::black_box;

use criterion::{criterion_group, criterion_main, Criterion};
use critspeed::system::ode::models::StuartLandau;
use critspeed::system::ode::{integrate, OdeOptions};
use nalgebra::Vector2;

fn stuart_landau_10_periods(c: &mut Criterion) {
    let (sl, mu) = (StuartLandau { omega: 1.3 }, 0.8);
    let x0 = Vector2::new(sl.radius(mu), 0.0);
    let opts = OdeOptions {
        monodromy: true,
        ..OdeOptions::default()
    };
    let t_end = 10.0 * sl.period();
    c.bench_function("stuart_landau_10_periods_monodromy", |b| {
        b.iter(|| integrate(black_box(&sl), black_box(mu), black_box(&x0), t_end, &opts))
    });
}

criterion_group!(benches, stuart_landau_10_periods);
criterion_main!(benches);
