//! A trade's verdicts as a printed summary, a JSON object and the plot's data.

use std::fmt::Write as _;

use serde_json::{json, Value};

use super::plan::fmt_si;
use super::select::{failed_for, Assessment};
use super::table::Row;
use super::{display_unit, Sense, TradePlan};
use crate::plot::{TradePlot, TradePoint};

fn sense_word(s: Sense) -> &'static str {
    match s {
        Sense::Minimize => "minimize",
        Sense::Maximize => "maximize",
    }
}

/// The objective value in display units with the unit, e.g. `"412.3 N/mm"`.
fn objective_text(plan: &TradePlan, si: Option<f64>) -> String {
    let (unit, f) = display_unit(plan.objective.dim);
    si.map_or("-".into(), |v| format!("{} {unit}", fmt_si(v * f)))
}

fn speed_text(v: Option<f64>) -> String {
    v.map_or("-".into(), |v| {
        format!("{} m/s ({} km/h)", fmt_si(v), fmt_si(v * 3.6))
    })
}

/// The Pareto result of a row: its value, `> v_max` when above range, or `-`.
fn result_text(plan: &TradePlan, r: &Row, long: bool) -> String {
    match (r.result(plan.pareto), r.above_range(plan.pareto)) {
        (Some(v), _) if long => speed_text(Some(v)),
        (Some(v), _) => fmt_si(v),
        (None, Some(top)) if long => format!(
            "> {} m/s (stable to {} m/s: no onset in range)",
            fmt_si(top),
            fmt_si(top)
        ),
        (None, Some(top)) => format!("> {}", fmt_si(top)),
        (None, None) => "-".into(),
    }
}

/// The human-readable summary printed by `critspeed trade`.
pub fn summary(study: &str, plan: &TradePlan, rows: &[Row], a: &[Assessment]) -> String {
    let key = &plan.objective.key;
    let mut s = format!("{study}: {} {key}\n", sense_word(plan.objective.sense));
    for c in &plan.constraints {
        let _ = writeln!(s, "  subject to {}", c.text);
    }
    let failed = rows.iter().filter(|r| failed_for(plan, r)).count();
    let feasible = a.iter().filter(|x| x.feasible).count();
    let above = rows
        .iter()
        .filter(|r| !failed_for(plan, r) && r.above.contains(&true))
        .count();
    let _ = writeln!(
        s,
        "feasible: {feasible} of {} points ({failed} failed, {} not failed but infeasible; {above} with results above the speed range)",
        rows.len(),
        rows.len().saturating_sub(feasible + failed)
    );
    let p = plan.pareto.name();
    match a.iter().position(|x| x.best) {
        Some(b) => {
            let r = &rows[b];
            let _ = writeln!(
                s,
                "best: point {}: {key} = {}; {p} = {}",
                r.id,
                objective_text(plan, r.axis(key)),
                result_text(plan, r, true)
            );
        }
        None => s.push_str("best: none (no point is feasible)\n"),
    }
    let (unit, f) = display_unit(plan.objective.dim);
    let front = front_order(plan, rows, a);
    let _ = writeln!(
        s,
        "Pareto front ({p} against {key}), {} points:",
        front.len()
    );
    let short = key.rsplit('.').next().unwrap_or(key);
    let (xh, vh) = (format!("{short} ({unit})"), format!("{p} (m/s)"));
    let (wx, wv) = (xh.chars().count(), vh.chars().count());
    let _ = writeln!(s, "  {:>8}  {xh}  {vh}  feasible", "point");
    for i in front {
        let x = rows[i].axis(key).map_or("-".into(), |v| fmt_si(v * f));
        let v = result_text(plan, &rows[i], false);
        let mark = if a[i].best { " (best)" } else { "" };
        let id = &rows[i].id;
        let _ = writeln!(s, "  {id:>8}  {x:>wx$}  {v:>wv$}  {}{mark}", a[i].feasible);
    }
    s
}

/// Indices of the front, by increasing objective.
fn front_order(plan: &TradePlan, rows: &[Row], a: &[Assessment]) -> Vec<usize> {
    let mut f: Vec<usize> = (0..rows.len()).filter(|&i| a[i].pareto).collect();
    let x = |i: usize| rows[i].axis(&plan.objective.key).unwrap_or(f64::NAN);
    f.sort_by(|&i, &j| x(i).total_cmp(&x(j)));
    f
}

/// The trade as one JSON object (`critspeed trade --json`); values in SI units.
pub fn json(study: &str, plan: &TradePlan, rows: &[Row], a: &[Assessment]) -> Value {
    let key = &plan.objective.key;
    let point = |i: usize| {
        json!({
            "point_id": rows[i].id,
            "objective_si": rows[i].axis(key),
            "speed_m_s": rows[i].result(plan.pareto),
            "stable_up_to_m_s": rows[i].above_range(plan.pareto),
            "feasible": a[i].feasible,
        })
    };
    json!({
        "study": study,
        "objective": { "key": key, "sense": sense_word(plan.objective.sense),
                       "si_unit": plan.objective.dim.si_unit() },
        "constraints": plan.constraints.iter().map(|c| c.text.clone()).collect::<Vec<_>>(),
        "pareto_result": plan.pareto.name(),
        "points": rows.len(),
        "feasible": a.iter().filter(|x| x.feasible).count(),
        "failed": rows.iter().filter(|r| failed_for(plan, r)).count(),
        "best": a.iter().position(|x| x.best).map(point),
        "front": front_order(plan, rows, a).into_iter().map(point).collect::<Vec<_>>(),
    })
}

/// The data of `trade.svg`: the Pareto result against the objective (display units), the
/// first constraint on that result as the line.
pub fn plot(study: &str, plan: &TradePlan, rows: &[Row], a: &[Assessment]) -> TradePlot {
    let (unit, f) = display_unit(plan.objective.dim);
    let key = &plan.objective.key;
    let points: Vec<TradePoint> = rows
        .iter()
        .zip(a)
        .filter_map(|(r, x)| {
            Some(TradePoint {
                x: r.axis(key)? * f,
                y: r.capped(plan.pareto).filter(|_| !failed_for(plan, r)),
                above: r.result(plan.pareto).is_none() && r.above_range(plan.pareto).is_some(),
                feasible: x.feasible,
                pareto: x.pareto,
                best: x.best,
            })
        })
        .collect();
    let xs = points.iter().map(|p| p.x);
    let (lo, hi) = xs.fold((f64::INFINITY, 0.0_f64), |(a, b), x| (a.min(x), b.max(x)));
    let constraint = plan.constraints.iter().find_map(|c| match c.target {
        super::Target::Result(r) if r == plan.pareto => {
            let v = c.at_least.or(c.at_most)?;
            Some((v, c.text.clone()))
        }
        _ => None,
    });
    TradePlot {
        title: format!("{study}: {} against {key}", plan.pareto.name()),
        x_label: format!("{key} ({unit})"),
        y_label: format!("{} (m/s)", plan.pareto.name()),
        x_log: lo > 0.0 && hi / lo >= 10.0,
        points,
        constraint,
    }
}
