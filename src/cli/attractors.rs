//! `critspeed attractors STUDY [--json]`: the continuation with branch switching, then the
//! search for every attractor, and the one V_NL of both.

use std::path::Path;

use super::commands::{bifurcation_hooks, out_dir, write_all};
use super::console::{results, statusln};
use super::Failure;
use crate::api::{self, files, Prepared};
use crate::attractors::AttractorReport;
use crate::bifurcation::BifurcationReport;

/// Runs the search on a prepared study, writes its files (and the continuation's), returns both
/// reports.
pub(super) fn run(
    p: &Prepared,
    root: &Path,
) -> Result<(AttractorReport, BifurcationReport), Failure> {
    let plan = p.plan();
    let started = std::time::Instant::now();
    let b = super::commands::continuation(p)?;
    statusln!("searching for the attractors of '{}'", plan.name);
    let progress = |line: &str| statusln!("{line}");
    let r = api::search(p, &b, bifurcation_hooks().cancel, Some(&progress))?;
    let mut b = b;
    crate::reconcile::combine(&mut b, &r);
    finished(&r, started);
    let dir = out_dir(root, plan)?;
    write_all(&dir, &files::bifurcation(&b)?)?;
    write_all(&dir, &files::attractors(&r, &b)?)?;
    Ok((r, b))
}

/// The search's closing status line: simulations, attractors, the time since `started`.
pub(super) fn finished(r: &AttractorReport, started: std::time::Instant) {
    statusln!(
        "  {} simulations, {} attractors in {:.1} s",
        r.simulations,
        r.attractors.len(),
        started.elapsed().as_secs_f64()
    );
}

/// The command.
pub(super) fn command(study: &Path, json: bool, root: &Path) -> Result<(), Failure> {
    let p = super::commands::prepare(super::commands::load(study)?)?;
    let (r, b) = run(&p, root)?;
    if json {
        let text = serde_json::to_string_pretty(&crate::output::attractors_json(&r, &b))
            .map_err(super::commands::compute)?;
        results(&format!("{text}\n"))
    } else {
        results(&table(&r, &b))
    }
}

/// The summary: the one V_NL and how it was found, each attractor with its speed range and
/// fate, the basin fractions at each grid speed, the notes.
pub(super) fn table(r: &AttractorReport, b: &BifurcationReport) -> String {
    use std::fmt::Write as _;
    let mut s = String::new();
    let _ = writeln!(
        s,
        "\nstudy '{}': attractors over [{:.2}, {:.2}] m/s ({} speeds{}, up to {} initial states each, {} simulations)",
        r.study,
        r.options.speed_range.0,
        r.options.speed_range.1,
        r.speeds.iter().filter(|x| !x.refined).count(),
        match r.speeds.iter().filter(|x| x.refined).count() {
            0 => String::new(),
            k => format!(" and {k} between them below the lowest hunting speed"),
        },
        r.starts.len(),
        r.simulations
    );
    match b.nonlinear_critical_speed {
        Some((v, _)) => {
            let _ = writeln!(
                s,
                "  nonlinear critical speed V_NL          {v:.4} m/s ({:.1} km/h)",
                v * 3.6
            );
        }
        None => {
            let _ = writeln!(
                s,
                "  nonlinear critical speed V_NL          no hunting attractor found"
            );
        }
    }
    for c in &b.nonlinear_sources {
        let _ = writeln!(
            s,
            "    by the {}: {:.4} m/s, {}{}",
            c.method.name(),
            c.speed_m_s,
            c.what,
            c.bracket_words(4)
        );
    }
    for a in &r.attractors {
        let top = a.path.first();
        let _ = writeln!(
            s,
            "  attractor {} ({}): found at {:.2} m/s ({:.3} mm{}), exists down to {:.4} m/s; {}{}",
            a.id,
            a.kind.name(),
            a.found_at_m_s,
            top.map_or(0.0, |m| m.amplitude_m() * 1e3),
            top.and_then(|m| m.period_s)
                .map_or(String::new(), |t| format!(", period {t:.5} s")),
            a.lowest_m_s(),
            a.fate,
            a.branch
                .map_or(String::new(), |x| format!("; on continued branch {}", x.0))
        );
    }
    for sp in &r.speeds {
        let parts: Vec<String> = sp
            .outcomes
            .iter()
            .map(|o| {
                let what = o
                    .attractor
                    .map_or(o.kind.name(), |i| format!("attractor {i}"));
                format!("{what} {:.0} %", o.fraction * 100.0)
            })
            .collect();
        let _ = writeln!(s, "  {:8.2} m/s: {}", sp.speed_m_s, parts.join(", "));
    }
    for n in b.notes.iter().chain(&r.notes) {
        let _ = writeln!(s, "  note: {n}");
    }
    s
}
