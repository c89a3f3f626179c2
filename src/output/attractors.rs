//! The attractor search's results as JSON (`attractors.json`, `attractors --json`) and CSV
//! (`attractors.csv`).

use std::fmt::Write as _;

use serde_json::{json, Value};

use crate::attractors::{AttractorReport, Motion};
use crate::bifurcation::BifurcationReport;

/// What `attractors.json` calls the speed it reports.
pub const ATTRACTOR_KIND: &str = "nonlinear critical speed: the lowest speed at which any hunting \
attractor exists (cycles of any symmetry or period, tori, chaos), over the continuation with \
branch switching and the search from many initial states";

fn motion_json(m: &Motion, bodies: &[String]) -> Value {
    json!({
        "speed_m_s": m.speed_m_s,
        "kind": m.kind.name(),
        "period_s": m.period_s,
        "amplitude_m": m.amplitude_m(),
        "amplitude_y_right_m": m.amplitudes.first().map(|a| a.y_right_m),
        "amplitude_y_left_m": m.amplitudes.first().map(|a| a.y_left_m),
        "max_multiplier_abs": m.max_multiplier,
        "lyapunov_per_s": m.lyapunov_per_s,
        "state": m.state,
        "bodies": m.amplitudes.iter().zip(bodies).map(|(a, b)| json!({
            "body": b,
            "y_right_m": a.y_right_m,
            "y_left_m": a.y_left_m,
            "psi_rad": a.psi_rad,
        })).collect::<Vec<_>>(),
    })
}

/// A seed's verdict: where it came from, the motion its simulation settled on (with a state
/// on it, the model's state order, SI), and the attractor it is (with where that attractor
/// dies) when it hunts.
pub fn seed_check_json(c: &crate::attractors::SeedCheck, bodies: &[String]) -> Value {
    json!({
        "source": c.source,
        "speed_m_s": c.speed_m_s,
        "confirmed": c.confirmed(),
        "motion": motion_json(&c.motion, bodies),
        "note": c.motion.note,
        "attractor": c.attractor,
        "lowest_m_s": c.lowest_m_s,
        "dies_bracket_m_s": c.dies_m_s.map(|d| [d.0, d.1]),
        "dies_bracket_open": c.open_below,
    })
}

/// `attractors.json`: the one V_NL (with `b`, the continuation that ran before the search),
/// the search's own V_NL and bracket, every attractor with its speed range and amplitudes, and
/// the basin fractions at each speed of the grid.
pub fn attractors_json(r: &AttractorReport, b: &BifurcationReport) -> Value {
    let attractors: Vec<Value> = r
        .attractors
        .iter()
        .map(|a| {
            let top = a.path.first();
            json!({
                "id": a.id,
                "kind": a.kind.name(),
                "found_at_m_s": a.found_at_m_s,
                "speed_range_m_s": [a.lowest_m_s(), a.found_at_m_s],
                "dies_bracket_m_s": a.dies_m_s.map(|d| [d.0, d.1]),
                "dies_bracket_open": a.open_below,
                "fate": a.fate,
                "branch": a.branch.map(|x| x.0),
                "branch_difference": a.branch.map(|x| json!({"amplitude": x.1, "period": x.2})),
                "amplitude_m_at_found": top.map(|m| m.amplitude_m()),
                "path": a.path.iter().map(|m| motion_json(m, &r.body_names)).collect::<Vec<_>>(),
            })
        })
        .collect();
    let speeds: Vec<Value> = r
        .speeds
        .iter()
        .map(|s| {
            json!({
                "speed_m_s": s.speed_m_s,
                "refined": s.refined,
                "initial_states": s.starts,
                "outcomes": s.outcomes.iter().map(|o| json!({
                    "attractor": o.attractor,
                    "kind": o.kind.name(),
                    "count": o.count,
                    "basin_fraction": o.fraction,
                    "amplitude_y_m": o.amplitude_m,
                })).collect::<Vec<_>>(),
            })
        })
        .collect();
    let o = &r.options;
    json!({
        "study": r.study,
        "kind": ATTRACTOR_KIND,
        "nonlinear_critical_speed_m_s": b.nonlinear_critical_speed.map(|v| v.0),
        "nonlinear_critical_speed_sources": b.nonlinear_sources.iter().map(super::vnl_candidate_json).collect::<Vec<_>>(),
        "search_critical_speed_m_s": r.nonlinear_critical_speed.map(|v| v.0),
        "bracket_m_s": r.nonlinear_critical_speed.and_then(|v| v.1).map(|d| [d.0, d.1]),
        "bracket_open": r.nonlinear_critical_speed.and_then(|v| r.attractors.iter().find(|a| a.id == v.2)).is_some_and(|a| a.open_below),
        "search_attractor": r.nonlinear_critical_speed.map(|v| v.2),
        "attractors": attractors,
        "speeds": speeds,
        "initial_states": r.starts.iter().map(|(k, d)| json!({"kind": k.name(), "state": d})).collect::<Vec<_>>(),
        "options": {
            "speed_range_m_s": [o.speed_range.0, o.speed_range.1],
            "speeds": o.speeds,
            "amplitudes_m": o.amplitudes,
            "settle_s": o.settle,
            "bracket_m_s": o.bracket,
            "descent_step": o.descent_step,
            "lowest_m_s": o.lowest,
            "threshold_m": o.threshold,
            "rtol": o.rtol,
            "max_period": o.max_period,
            "geometry_limit_m": o.geometry_limit,
        },
        "seed_checks": r.seed_checks.iter().map(|c| seed_check_json(c, &r.body_names)).collect::<Vec<_>>(),
        "notes": r.notes,
        "disagreement": b.notes.iter().filter(|n| n.starts_with("the continuation and the attractor search")).collect::<Vec<_>>(),
        "simulations": r.simulations,
    })
}

/// `attractors.csv`: one row per motion of the search: every outcome at each grid speed (with
/// its basin fraction) and every speed of every attractor's descent (`source` = `grid` or
/// `descent`), with the leading wheelset's sides and every body's amplitudes.
pub fn attractors_csv(r: &AttractorReport) -> String {
    let mut s = String::from(
        "source,speed_m_s,attractor,kind,basin_fraction,amplitude_y_right_m,amplitude_y_left_m,\
period_s,max_multiplier_abs,lyapunov_per_s",
    );
    for b in &r.body_names {
        let b = b.replace(' ', "_");
        let _ = write!(s, ",amp_y_{b}_m,amp_psi_{b}_rad");
    }
    s.push('\n');
    let opt = |v: Option<f64>| v.map_or(String::new(), |x| x.to_string());
    let nb = r.body_names.len();
    let row = |s: &mut String, source: &str, id: Option<usize>, frac: Option<f64>, m: &Motion| {
        let first = m.amplitudes.first();
        let _ = write!(
            s,
            "{source},{},{},{},{},{},{},{},{},{}",
            m.speed_m_s,
            id.map_or(String::new(), |i| i.to_string()),
            m.kind.name(),
            opt(frac),
            opt(first.map(|a| a.y_right_m)),
            opt(first.map(|a| a.y_left_m)),
            opt(m.period_s),
            opt(m.max_multiplier),
            opt(m.lyapunov_per_s),
        );
        for k in 0..nb {
            let a = m.amplitudes.get(k);
            let _ = write!(
                s,
                ",{},{}",
                opt(a.map(|a| a.y_m())),
                opt(a.map(|a| a.psi_rad))
            );
        }
        s.push('\n');
    };
    for sp in &r.speeds {
        for o in &sp.outcomes {
            let motion = o
                .attractor
                .and_then(|i| r.attractors.iter().find(|a| a.id == i))
                .and_then(|a| {
                    a.path
                        .iter()
                        .find(|m| (m.speed_m_s - sp.speed_m_s).abs() < 1e-9)
                });
            match motion {
                Some(m) => row(&mut s, "grid", o.attractor, Some(o.fraction), m),
                None => row(
                    &mut s,
                    "grid",
                    o.attractor,
                    Some(o.fraction),
                    &Motion::simple(o.kind, sp.speed_m_s, 0.0),
                ),
            }
        }
    }
    for a in &r.attractors {
        for m in &a.path {
            row(&mut s, "descent", Some(a.id), None, m);
        }
    }
    s
}
