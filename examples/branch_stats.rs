//! Where a bifurcation diagram's work goes: `cargo run --release --example branch_stats --
//! STUDY [SEGMENTS]` prints the branch's solver statistics, its end, V_NL and the wall time.
//! The thread count is rayon's (`RAYON_NUM_THREADS`).

use std::path::Path;
use std::process::ExitCode;
use std::time::Instant;

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().collect();
    let Some(path) = args.get(1) else {
        eprintln!("usage: branch_stats STUDY [SEGMENTS]");
        return ExitCode::from(2);
    };
    let plan = match critspeed::study::load(Path::new(path)) {
        Ok(p) => p,
        Err(e) => {
            eprintln!("{e}");
            return ExitCode::from(2);
        }
    };
    let model = match plan.model() {
        Ok(m) => m,
        Err(e) => {
            eprintln!("{e}");
            return ExitCode::from(2);
        }
    };
    let mut opts = plan.bifurcation_options();
    if let Some(m) = args.get(2).and_then(|s| s.parse().ok()) {
        opts.segments = m;
    }
    let t = Instant::now();
    let r = match critspeed::bifurcation::analyse(&plan.name, &model, &opts) {
        Ok(r) => r,
        Err(e) => {
            eprintln!("{e}");
            return ExitCode::FAILURE;
        }
    };
    let wall = t.elapsed().as_secs_f64();
    let s = r.stats;
    let cycles = r.cycles.len();
    println!(
        "{}: {} states, {} threads, {} segments",
        plan.name,
        model.states(),
        rayon::current_num_threads(),
        opts.segment_count()
    );
    println!(
        "  wall {wall:.2} s, {cycles} cycles, {:.1} ms per cycle",
        1e3 * wall / cycles.max(1) as f64
    );
    println!("  stop: {}", r.stop_reason);
    println!(
        "  failed steps {}, angle rejections {}, locate correctors {}",
        s.failed_steps, s.angle_rejections, s.locate_corrections
    );
    println!(
        "  linearisations {} ({:.2} per cycle), chord iterations {} ({:.2} per cycle), integrator steps {} (+{} rejected), {:.0} per iteration",
        s.newton_iterations,
        s.newton_iterations as f64 / cycles.max(1) as f64,
        s.chord_iterations,
        s.chord_iterations as f64 / cycles.max(1) as f64,
        s.integrator_steps,
        s.integrator_rejected,
        s.integrator_steps as f64 / (s.newton_iterations + s.chord_iterations).max(1) as f64
    );
    for p in &r.special {
        println!(
            "  {} {:.6} m/s at {:.4} mm ({})",
            p.kind.name(),
            p.speed_m_s,
            p.amplitude_y_m * 1e3,
            if p.located { "located" } else { "bracketed" }
        );
    }
    if let Some((v, located)) = r.nonlinear_critical_speed {
        println!("  V_NL {v:.9} m/s (located: {located})");
    }
    if let Ok(path) = std::env::var("BRANCH_STATS_CSV") {
        let rows: String = r
            .cycles
            .iter()
            .map(|c| {
                format!(
                    "{},{},{},{},{}\n",
                    c.speed_m_s,
                    c.amplitude_y_m,
                    c.newton_iterations,
                    c.max_multiplier_abs,
                    c.trivial_multiplier_error
                )
            })
            .collect();
        if let Err(e) = std::fs::write(&path, rows) {
            eprintln!("{path}: {e}");
        }
    }
    ExitCode::SUCCESS
}
