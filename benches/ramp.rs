//! The ramp method on `studies/seed-hunting.toml` (supercritical Hopf point at 70.71 m/s).
//!
//! Setup (not timed): [`ramp_converged`] from 72 m/s halves the GENSYS rate (1.389 m/s²) until
//! two successive ramp estimates agree to 1e-3 relative. The bench then times **one** ramp at
//! the rate that needed (≈ 3.4e-4 m/s², some 4 400 s of simulated time): the cost of a ramp
//! estimate whose successive-halving change is 1e-3. Its error against the continuation's
//! V_NL is still about 0.1 m/s (1.5e-3: the lag shrinks only like √rate), while the
//! continuation locates V_NL to ~1e-9 and computes the whole branch in a few seconds: this time
//! is a lower bound on what the ramp needs to match the continuation.

use std::hint::black_box;
use std::path::Path;
use std::time::Duration;

use criterion::{criterion_group, criterion_main, Criterion, SamplingMode};
use critspeed::simulate::{ramp, ramp_converged, RampOptions};
use critspeed::study;

fn ramp_at_converged_rate(c: &mut Criterion) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("studies/seed-hunting.toml");
    let plan = study::load(&path).expect("studies/seed-hunting.toml is valid");
    let model = plan.model().expect("its contact table builds");
    let mut opts = RampOptions::new(72.0, 40.0);
    let conv = ramp_converged(&model, &opts, 16, 1e-3).expect("valid options");
    let Some((estimate, rate)) = conv.converged else {
        panic!("ramp did not converge: {:?}", conv.stop);
    };
    eprintln!(
        "ramp_converged: {} rates, estimate {estimate:.4} m/s at {rate:.3e} m/s²",
        conv.rows.len()
    );
    opts.rate = rate;
    let mut g = c.benchmark_group("ramp");
    g.sampling_mode(SamplingMode::Flat)
        .sample_size(10)
        .warm_up_time(Duration::from_millis(1))
        .measurement_time(Duration::from_secs(1));
    g.bench_function("seed_hunting_ramp_at_converged_rate", |b| {
        b.iter(|| ramp(black_box(&model), black_box(&opts)))
    });
    g.finish();
}

criterion_group!(benches, ramp_at_converged_rate);
criterion_main!(benches);
