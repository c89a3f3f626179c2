//! `curve.json` and `curve.csv`: the curves of `critspeed curve`.

use std::fmt::Write as _;

use serde_json::{json, Value};

use crate::curve::{Curve, CurvePoint, CurveReport};
use crate::sweep::spec::unit_suffix;

/// What the curve outputs report.
pub const CURVE_KIND: &str = "critical speeds as curves over a design key: Hopf points of the \
centred motion continued in (speed, key), with the first Lyapunov coefficient and the \
codimension-two points, and the folds of cycles located at each key value, with V_NL";

fn point_json(p: &CurvePoint) -> Value {
    json!({
        "parameter": p.parameter,
        "speed_m_s": p.speed_m_s,
        "frequency_hz": p.frequency_hz,
        "amplitude_m": p.amplitude_m,
        "first_lyapunov_coefficient": p.first_lyapunov_coefficient,
        "first_lyapunov_coefficient_error": p.first_lyapunov_error,
        "hopf_type": p.hopf_type.map(|k| k.name()),
        "stable_side": p.stable_side.name(),
        "stable_cycle": p.stable_cycle,
        "torus_angle_rad": p.torus_angle_rad,
    })
}

fn curve_json_one(c: &Curve) -> Value {
    json!({
        "kind": c.kind.name(),
        "creep_law": c.creep_law.name(),
        "label": c.label,
        "seed_parameter": c.seed_parameter,
        "stops": [c.stops.0.describe(), c.stops.1.describe()],
        "points": c.points.iter().map(point_json).collect::<Vec<_>>(),
    })
}

/// The whole report as one JSON object (`curve --json` and `curve.json`). Every `parameter`
/// is the key's value in the SI unit `unit`; `first_lyapunov_coefficient` is in 1/m²
/// (normalised to the leading wheelset's lateral amplitude, docs/model.md §12).
pub fn curve_json(r: &CurveReport) -> Value {
    let special: Vec<Value> = r
        .special_points
        .iter()
        .map(|s| {
            json!({
                "kind": s.kind.name(),
                "label": s.kind.label(),
                "curve": s.curve,
                "other_curve": s.other_curve,
                "creep_law": r.curves.get(s.curve).map(|c| c.creep_law.name()),
                "parameter": s.parameter,
                "speed_m_s": s.speed_m_s,
                "frequency_hz": s.frequency_hz,
                "second_frequency_hz": s.second_frequency_hz,
                "located": s.located,
            })
        })
        .collect();
    let vnl: Vec<Value> = r
        .nonlinear_critical_speed
        .iter()
        .enumerate()
        .map(|(i, (p, v))| {
            let method = r.nonlinear_methods.get(i).map(|m| m.name());
            json!({"parameter": p, "speed_m_s": v, "method": method})
        })
        .collect();
    let search: Vec<Value> = r
        .attractor_search
        .iter()
        .map(|a| {
            json!({
                "parameter": a.parameter,
                "continuation_m_s": a.continuation_m_s,
                "search_m_s": a.search_m_s,
                "bracket_m_s": a.bracket_m_s.map(|b| [b.0, b.1]),
                "bracket_open": a.bracket_open,
                "error": a.error,
            })
        })
        .collect();
    json!({
        "study": r.study,
        "kind": CURVE_KIND,
        "key": r.key,
        "unit": r.dimension.si_unit(),
        "from": r.range.0,
        "to": r.range.1,
        "spacing": if r.log { "log" } else { "linear" },
        "speed_range_m_s": [r.speed_range.0, r.speed_range.1],
        "curves": r.curves.iter().map(curve_json_one).collect::<Vec<_>>(),
        "special_points": special,
        "nonlinear_critical_speed": vnl,
        "attractor_search": search,
        "notes": r.notes,
        "stats": {
            "models_built": r.stats.models_built,
            "newton_iterations": r.stats.newton_iterations,
            "rejected_steps": r.stats.rejected_steps,
        },
    })
}

/// The name of `curve.csv`'s key column: the key with its SI unit as a suffix, as in
/// `sweep.csv` (`suspension.lateral_stiffness_n_per_m`).
pub fn curve_key_column(r: &CurveReport) -> String {
    format!("{}{}", r.key, unit_suffix(r.dimension))
}

/// `curve.csv`: one row per point of every curve, in curve order.
pub fn curve_csv(r: &CurveReport) -> String {
    let mut s = format!(
        "curve,kind,creep_law,label,{},speed_m_s,frequency_hz,amplitude_m,\
first_lyapunov_coefficient_per_m2,first_lyapunov_error_per_m2,hopf_type,stable_side,stable_cycle,torus_angle_rad\n",
        curve_key_column(r)
    );
    let opt = |v: Option<f64>| v.map_or(String::new(), |v| v.to_string());
    for (k, c) in r.curves.iter().enumerate() {
        for p in &c.points {
            let _ = writeln!(
                s,
                "{k},{},{},{},{},{},{},{},{},{},{},{},{},{}",
                c.kind.name(),
                c.creep_law.name(),
                c.label,
                p.parameter,
                p.speed_m_s,
                p.frequency_hz,
                p.amplitude_m,
                opt(p.first_lyapunov_coefficient),
                opt(p.first_lyapunov_error),
                p.hopf_type.map_or("", |h| h.name()),
                p.stable_side.name(),
                p.stable_cycle.map_or(String::new(), |b| b.to_string()),
                opt(p.torus_angle_rad),
            );
        }
    }
    s
}
