//! critspeed's right-hand side at pseudo-random states, for checking another code's copy of the
//! equations (scripts/auto07p-bogie compares AUTO's `bogie.f90` with it):
//! `cargo run --release --example vehicle_rhs -- STUDY [COUNT] [HALF_WIDTH_M] [--jacobian]`
//! prints one line per state, `V x_1 … x_n f_1 … f_n` in SI with 17 significant digits, and with
//! `--jacobian` the exact Jacobian ∂f/∂x column by column after them. The states are uniform in
//! ±HALF_WIDTH_M (default 8 mm) for the lateral displacements, ±5 mrad for the yaws, ±0.2 m/s
//! and ±0.2 rad/s for the rates; V in [40, 160] m/s. HALF_WIDTH_M = 0 gives the centre x = 0
//! (and V in [200, 230] m/s, around the study's Hopf point).

use std::path::Path;
use std::process::ExitCode;

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().collect();
    let Some(path) = args.get(1) else {
        eprintln!("usage: vehicle_rhs STUDY [COUNT] [HALF_WIDTH_M]");
        return ExitCode::from(2);
    };
    let count: usize = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(20);
    let half_width: f64 = args.get(3).and_then(|s| s.parse().ok()).unwrap_or(8e-3);
    let jacobian = args.iter().any(|a| a == "--jacobian");
    let centre = half_width == 0.0;
    let model = match critspeed::study::load(Path::new(path)).map(|p| p.model()) {
        Ok(Ok(m)) => m,
        Ok(Err(e)) => {
            eprintln!("{e}");
            return ExitCode::from(2);
        }
        Err(e) => {
            eprintln!("{e}");
            return ExitCode::from(2);
        }
    };
    let n = model.dofs();
    // a 64-bit linear congruential generator (Knuth's MMIX constants): reproducible, no crate
    let mut state: u64 = 0x2545_f491_4f6c_dd1d;
    let mut uniform = move || {
        state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (state >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    };
    let coordinates = model.coordinate_names();
    for _ in 0..count {
        let v = if centre {
            215.0 + 15.0 * uniform()
        } else {
            100.0 + 60.0 * uniform()
        };
        let x: Vec<f64> = (0..2 * n)
            .map(|i| {
                if centre {
                    return 0.0;
                }
                let lateral = coordinates[i % n].starts_with("y_");
                match (i < n, lateral) {
                    (true, true) => half_width * uniform(),
                    (true, false) => 5e-3 * uniform(),
                    (false, _) => 0.2 * uniform(),
                }
            })
            .collect();
        let mut f = vec![0.0; 2 * n];
        model.rhs_into(&x, v, &mut f);
        let mut jac = vec![0.0; if jacobian { 4 * n * n } else { 0 }];
        if jacobian {
            model.jacobian_into(&x, v, &mut jac);
        }
        let line: Vec<String> = std::iter::once(v)
            .chain(x)
            .chain(f)
            .chain(jac)
            .map(|a| format!("{a:.16e}"))
            .collect();
        println!("{}", line.join(" "));
    }
    ExitCode::SUCCESS
}
