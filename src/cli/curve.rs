//! `critspeed curve STUDY`: the critical speeds as curves over the `[curve]` key.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use super::commands::{compute, out_dir, write_all};
use super::console::{results, statusln};
use super::Failure;
use crate::api::{self, Source};
use crate::curve::CurveReport;

/// Arguments of `critspeed curve`.
#[derive(Debug, clap::Args)]
pub struct CurveArgs {
    /// Study file (TOML) with a `[curve]` section.
    pub study: PathBuf,
    /// Print one JSON object on stdout instead of the summary.
    #[arg(long)]
    pub json: bool,
    /// Worker threads (default: all cores); the results are the same on any count.
    #[arg(long)]
    pub threads: Option<usize>,
}

/// Computes the curves, writes curve.json, curve.csv and curve.svg, prints the summary.
pub fn run(a: &CurveArgs, root: &Path) -> Result<(), Failure> {
    let study = api::curve::curve_study(&Source::file(&a.study)?)?;
    let s = &study.spec;
    let kinds: Vec<&str> = s.curves.iter().map(|k| k.name()).collect();
    statusln!(
        "continuing {} curves of '{}' over {} in [{}, {}]{} and [{}, {}] m/s",
        kinds.join(", "),
        study.keyed.base.name,
        s.key,
        s.range.0,
        s.range.1,
        match s.dimension.si_unit() {
            "" => String::new(),
            u => format!(" {u}"),
        },
        s.speed_range.0,
        s.speed_range.1
    );
    let started = std::time::Instant::now();
    let progress = |line: &str| statusln!("  {line}");
    let report = api::curve::curve_with_progress(&study, None, Some(&progress))?;
    statusln!(
        "  {} curves, {} points in {:.2} s",
        report.curves.len(),
        report.curves.iter().map(|c| c.points.len()).sum::<usize>(),
        started.elapsed().as_secs_f64()
    );
    for n in &report.notes {
        statusln!("note: {n}");
    }
    write_all(
        &out_dir(root, &study.keyed.base)?,
        &api::curve::files(&report)?,
    )?;
    if a.json {
        let text =
            serde_json::to_string_pretty(&crate::output::curve_json(&report)).map_err(compute)?;
        results(&format!("{text}\n"))
    } else {
        results(&summary(&report))
    }
}

/// The summary table: each curve's ends, then the special points and the notes.
pub fn summary(r: &CurveReport) -> String {
    let unit = match r.dimension.si_unit() {
        "" => String::new(),
        u => format!(" {u}"),
    };
    let mut s = format!(
        "\nstudy '{}': critical speeds against {}{}, V in [{}, {}] m/s\n",
        r.study,
        r.key,
        if unit.is_empty() {
            String::new()
        } else {
            format!(" ({})", unit.trim())
        },
        r.speed_range.0,
        r.speed_range.1
    );
    let _ = writeln!(
        s,
        "  {:<5} {:<6} {:>7} {:>14} {:>12} {:>14} {:>12}  stops",
        "curve", "speed", "points", "first key", "V (m/s)", "last key", "V (m/s)"
    );
    for (k, c) in r.curves.iter().enumerate() {
        let (Some(a), Some(b)) = (c.points.first(), c.points.last()) else {
            continue;
        };
        let _ = writeln!(
            s,
            "  {k:<5} {:<6} {:>7} {:>14.6e} {:>12.4} {:>14.6e} {:>12.4}  {}; {}",
            c.label,
            c.points.len(),
            a.parameter,
            a.speed_m_s,
            b.parameter,
            b.speed_m_s,
            c.stops.0.describe(),
            c.stops.1.describe()
        );
    }
    for p in &r.special_points {
        let _ = writeln!(
            s,
            "  {} on curve {}{}: {} = {:.6e}{unit}, V = {:.4} m/s, {:.4} Hz{} ({})",
            p.kind.words(),
            p.curve,
            p.other_curve.map_or(String::new(), |o| format!(" and {o}")),
            r.key,
            p.parameter,
            p.speed_m_s,
            p.frequency_hz,
            p.second_frequency_hz
                .map_or(String::new(), |f| format!(" and {f:.4} Hz")),
            if p.located { "located" } else { "bracketed" }
        );
    }
    if !r.nonlinear_critical_speed.is_empty() {
        let how = if r.attractor_search.is_empty() {
            "continuation: the lowest fold with a stable side, or V_H where supercritical; no attractor search, which can find hunting lower"
        } else {
            "the lower of the continuation (the lowest fold with a stable side, or V_H where supercritical) and the attractor search at each value"
        };
        let _ = writeln!(s, "  V_NL against {} ({how}):", r.key);
        for (i, (p, v)) in r.nonlinear_critical_speed.iter().enumerate() {
            let method = r
                .nonlinear_methods
                .get(i)
                .map_or("continuation", |m| m.name());
            let _ = writeln!(s, "    {} = {p:.6e}: V_NL {v:.4} m/s ({method})", r.key);
        }
    }
    for n in &r.notes {
        let _ = writeln!(s, "  note: {n}");
    }
    s
}
