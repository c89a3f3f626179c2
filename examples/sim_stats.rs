//! Where a time simulation's work goes: `cargo run --release --example sim_stats -- STUDY
//! SPEED_M_S Y0_MM SECONDS [RTOL]` integrates the study's model from the leading wheelset
//! displaced by Y0 and prints the integrator's counts (accepted and rejected steps, field
//! evaluations, flange crossings), the mean step, the wall time and the time per evaluation.

use std::path::Path;
use std::process::ExitCode;
use std::time::Instant;

use critspeed::system::ode::{integrate_partial, OdeOptions, Tolerances};
use nalgebra::SVector;

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().collect();
    let num = |i: usize| args.get(i).and_then(|s| s.parse::<f64>().ok());
    let (Some(path), Some(v), Some(y0), Some(secs)) = (args.get(1), num(2), num(3), num(4)) else {
        eprintln!("usage: sim_stats STUDY SPEED_M_S Y0_MM SECONDS [RTOL]");
        return ExitCode::from(2);
    };
    let rtol = num(5).unwrap_or(1e-9);
    let model = match critspeed::study::load(Path::new(path))
        .map_err(|e| e.to_string())
        .and_then(|p| p.model().map_err(|e| e.to_string()))
    {
        Ok(m) => m,
        Err(e) => {
            eprintln!("{e}");
            return ExitCode::from(2);
        }
    };
    let opts = match Tolerances::new(rtol, rtol * 1e-3) {
        Ok(tol) => OdeOptions {
            tol,
            max_steps: 50_000_000,
            ..OdeOptions::default()
        },
        Err(e) => {
            eprintln!("{e}");
            return ExitCode::from(2);
        }
    };
    let x0 = critspeed::simulate::lateral_start(&model, y0 * 1e-3);
    critspeed::with_states!(model.states(), N => {
        let x = SVector::<f64, N>::from_fn(|i, _| x0[i]);
        let t = Instant::now();
        match integrate_partial(&model, v, &x, secs, &opts) {
            Ok(sol) => {
                let wall = t.elapsed().as_secs_f64();
                let s = sol.stats;
                println!(
                    "{N} states, {v} m/s, {secs} s, rtol {rtol:e}: {:?} at t = {:.3} s; {} steps, {} rejected, {} f evaluations, {} flange crossings; mean step {:.3e} s; {:.3} s wall, {:.0} ns per evaluation; y1 at the end {:.4e} m",
                    sol.stop, sol.t, s.steps, s.rejected, s.rhs_evals, s.events,
                    sol.t / s.steps.max(1) as f64, wall, wall * 1e9 / s.rhs_evals.max(1) as f64, sol.x[0]
                );
                ExitCode::SUCCESS
            }
            Err(e) => {
                eprintln!("{e}");
                ExitCode::FAILURE
            }
        }
    }, _ => {
        eprintln!("no analysis compiled for {} states", model.states());
        ExitCode::FAILURE
    })
}
