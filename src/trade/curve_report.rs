//! A curve trade as a printed summary, a JSON object and `trade.csv`.

use std::fmt::Write as _;

use serde_json::{json, Map, Value};

use super::curve::{KeyAxis, VnlSource};
use super::intervals::{CurveTrade, End, Inward};
use super::plan::fmt_si;
use super::table::{csv_field, Row};
use super::{display_unit, ResultKind, Sense, TradePlan};
use crate::curve::CurveReport;

fn sense_word(s: Sense) -> &'static str {
    match s {
        Sense::Minimize => "minimize",
        Sense::Maximize => "maximize",
    }
}

/// A key value in display units with the unit, e.g. `"412.3 N/mm"`.
pub(super) fn key_text(plan: &TradePlan, si: f64) -> String {
    match display_unit(plan.objective.dim) {
        ("-", f) => fmt_si(si * f),
        (unit, f) => format!("{} {unit}", fmt_si(si * f)),
    }
}

/// A result of a row in words: `62.7 m/s (225.8 km/h)`, `> 300 m/s (no onset in range)`, `-`.
fn result_text(row: &Row, r: ResultKind) -> String {
    match (row.result(r), row.above_range(r)) {
        (Some(v), _) => format!("{} m/s ({} km/h)", fmt_si(v), fmt_si(v * 3.6)),
        (None, Some(top)) => format!(
            "> {} m/s (stable to {} m/s: no onset in range)",
            fmt_si(top),
            fmt_si(top)
        ),
        (None, None) => "-".into(),
    }
}

fn results_text(plan: &TradePlan, row: &Row) -> String {
    plan.read_results()
        .into_iter()
        .map(|r| format!("{} = {}", r.name(), result_text(row, r)))
        .collect::<Vec<_>>()
        .join("; ")
}

/// The human-readable summary of a curve trade.
pub fn summary(
    study: &str,
    plan: &TradePlan,
    axis: &KeyAxis,
    report: &CurveReport,
    t: &CurveTrade,
) -> String {
    let key = &plan.objective.key;
    let mut s = format!(
        "{study}: {} {key} on curves (method = \"curve\")\n",
        sense_word(plan.objective.sense)
    );
    for c in &plan.constraints {
        let _ = writeln!(s, "  subject to {}", c.text);
    }
    let feasible = t.samples.iter().filter(|x| x.1.is_none()).count();
    let _ = writeln!(
        s,
        "curves: {} over {} = {} .. {}{}; {} samples of the key, {feasible} feasible",
        report.curves.len(),
        axis.key,
        key_text(plan, axis.range.0),
        key_text(plan, axis.range.1),
        if axis.log { " (log)" } else { "" },
        t.samples.len()
    );
    let _ = writeln!(s, "feasible intervals of {key}: {}", t.intervals.len());
    for i in &t.intervals {
        let _ = writeln!(
            s,
            "  {} .. {}",
            key_text(plan, i.from.x),
            key_text(plan, i.to.x)
        );
        let _ = writeln!(s, "    from: {}", i.from.how);
        let _ = writeln!(s, "    to:   {}", i.to.how);
        for n in &i.notes {
            let _ = writeln!(s, "    note: {n}");
        }
    }
    match &t.best {
        Some(b) => {
            let _ = writeln!(
                s,
                "best: {key} = {}; on the curves {}",
                key_text(plan, b.x),
                results_text(plan, &b.predicted)
            );
        }
        None => s.push_str("best: none (no key value is feasible on the curves)\n"),
    }
    if let Some(v) = &t.verification {
        let _ = writeln!(
            s,
            "verification at {key} = {} ({}):",
            key_text(plan, v.x),
            v.nudge
        );
        let _ = writeln!(
            s,
            "  computed (the sweep's one-point computation): {}",
            results_text(plan, &v.computed)
        );
        let _ = writeln!(
            s,
            "  on the curves:                                {}",
            results_text(plan, &v.predicted)
        );
        // the two methods' values apart: said in words, whichever way the constraint goes
        for r in plan.read_results() {
            if let (Some(c), Some(p)) = (v.computed.result(r), v.predicted.result(r)) {
                if (c - p).abs() > 1e-3 * p.abs() {
                    let why = if r != ResultKind::NonlinearCriticalSpeed {
                        ""
                    } else if c > p {
                        if v.settlement.is_some() {
                            ": settled by simulation below"
                        } else {
                            ": not settled"
                        }
                    } else {
                        ": the one-point computation's is the lower (a hunting motion the curves do not follow) and is taken"
                    };
                    let _ = writeln!(
                        s,
                        "  the methods differ: {} {} m/s from the one-point computation, {} m/s on the curves ({:+.2} %){why}",
                        r.name(),
                        fmt_si(c),
                        fmt_si(p),
                        100.0 * (c - p) / p
                    );
                }
            }
        }
        if let Some(st) = &v.settlement {
            let _ = writeln!(
                s,
                "  settled by simulation ({} simulations): {}",
                st.simulations, st.words
            );
        }
        if v.feasible {
            let _ = writeln!(
                s,
                "  agrees: the computed design meets every constraint (smallest margin {:+.3} %)",
                100.0 * v.margin
            );
        } else if let Some(se) = &v.settled {
            let (once, moved) = match se.by {
                Inward::Simulation => ("once settled", "settled by simulation"),
                Inward::OnePoint => (
                    "by the one-point computation",
                    "moved inward by one-point computations",
                ),
            };
            let _ = writeln!(
                s,
                "  the curves' best design does not meet the constraints {once}: {}",
                v.reason
            );
            match se.x {
                Some(x) => {
                    let _ = writeln!(
                        s,
                        "best ({moved}): {key} = {}; {}",
                        key_text(plan, x),
                        se.how
                    );
                    if let Some(row) = &se.computed {
                        let _ = writeln!(
                            s,
                            "  there (smallest margin {:+.3} %): computed {}",
                            100.0 * se.margin,
                            results_text(plan, row)
                        );
                    }
                    if let Some(st) = &se.settlement {
                        let _ = writeln!(
                            s,
                            "  there ({} simulations, smallest margin {:+.3} %): {}",
                            st.simulations,
                            100.0 * se.margin,
                            st.words
                        );
                    }
                }
                None => {
                    let _ = writeln!(s, "best ({moved}): none; {}", se.how);
                }
            }
        } else {
            let _ = writeln!(
                s,
                "  DISAGREES: the computed design does not meet the constraints: {} (the curves' interval end is off by more than the nudge)",
                v.reason
            );
        }
    }
    for n in &report.notes {
        let _ = writeln!(s, "curve note: {n}");
    }
    s
}

/// A settlement ([`crate::trade::settle`]) as JSON: both methods' V_NL, the one after
/// settling, the verdict, and each fold cycle's simulations.
fn settlement_json(st: &crate::trade::settle::Settlement) -> Value {
    json!({
        "one_point_m_s": st.one_point_m_s,
        "curves_m_s": st.curves_m_s,
        "nonlinear_critical_speed_m_s": st.nonlinear_m_s,
        "confirmed": st.confirmed,
        "verdict": st.words,
        "simulations": st.simulations,
        "checks": st.checks.iter().map(|c| json!({
            "curve": c.curve,
            "label": c.label,
            "fold_m_s": c.fold_m_s,
            "lowest_m_s": c.lowest_m_s(),
            "simulations": c.seeds.iter()
                .map(|x| crate::output::seed_check_json(x, &st.bodies))
                .collect::<Vec<_>>(),
        })).collect::<Vec<_>>(),
    })
}

fn end_json(e: &End) -> Value {
    json!({ "value": e.x, "how": e.how, "curve_estimate": e.curve_estimate, "evaluations": e.evaluations })
}

/// The speeds of a row the trade reads, by result name (null: none), and the top of the
/// speed range where some is above range.
fn speeds(plan: &TradePlan, row: &Row) -> Value {
    let mut m = Map::new();
    for r in plan.read_results() {
        m.insert(r.name().into(), json!(row.result(r)));
    }
    Value::Object(m)
}

/// `trade.json` of a curve trade (`critspeed trade --json`); values in SI units.
pub fn json(
    study: &str,
    plan: &TradePlan,
    axis: &KeyAxis,
    report: &CurveReport,
    t: &CurveTrade,
) -> Value {
    let unit = axis.dim.si_unit();
    let intervals: Vec<Value> = t
        .intervals
        .iter()
        .map(|i| {
            json!({ "from": i.from.x, "to": i.to.x, "unit": unit,
                    "from_end": end_json(&i.from), "to_end": end_json(&i.to), "notes": i.notes })
        })
        .collect();
    let best = t.best.as_ref().map(|b| {
        json!({ "objective_si": b.x, "unit": unit, "interval": b.interval,
                "speeds_m_s": speeds(plan, &b.predicted),
                "stable_up_to_m_s": b.predicted.stable_up_to_m_s,
                "status": b.predicted.status, "source": "curves" })
    });
    let verification = t.verification.as_ref().map(|v| {
        json!({ "objective_si": v.x, "unit": unit, "nudge": v.nudge,
                "predicted_m_s": speeds(plan, &v.predicted),
                "computed_m_s": speeds(plan, &v.computed),
                "computed_status": v.computed.status,
                "stable_up_to_m_s": v.computed.stable_up_to_m_s,
                "feasible": v.feasible, "agrees": v.feasible, "reason": v.reason,
                "margin": v.margin.is_finite().then_some(v.margin),
                "settlement": v.settlement.as_ref().map(settlement_json),
                "settled_best": v.settled.as_ref().map(|se| json!({
                    "objective_si": se.x, "unit": unit, "margin": se.margin.is_finite().then_some(se.margin),
                    "by": se.by.name(), "nonlinear_critical_speed_m_s": se.nonlinear_m_s,
                    "computed_m_s": se.computed.as_ref().map(|r| speeds(plan, r)),
                    "evaluations": se.evaluations, "how": se.how,
                    "settlement": se.settlement.as_ref().map(settlement_json) })) })
    });
    json!({
        "study": study,
        "method": "curve",
        "objective": { "key": plan.objective.key, "sense": sense_word(plan.objective.sense),
                       "si_unit": plan.objective.dim.si_unit() },
        "constraints": plan.constraints.iter().map(|c| c.text.clone()).collect::<Vec<_>>(),
        "pareto_result": plan.pareto.name(),
        "key": { "name": axis.key, "si_unit": unit, "from": axis.range.0, "to": axis.range.1,
                 "spacing": if axis.log { "log" } else { "linear" } },
        "curves": report.curves.len(),
        "samples": t.samples.len(),
        "feasible_samples": t.samples.iter().filter(|s| s.1.is_none()).count(),
        "intervals": intervals,
        "best": best,
        "verification": verification,
        "notes": report.notes,
    })
}

fn cell(v: Option<f64>) -> String {
    v.map_or(String::new(), |v| format!("{v}"))
}

/// `trade.csv` of a curve trade: one row per sample of the key: the key with its SI unit,
/// the three result columns (empty where not read or not known), `status`,
/// `stable_up_to_m_s`, `nonlinear_source` (`point`, `on curves`, `interpolated`, `unknown` or empty),
/// `feasible` and `reason`.
pub fn csv(axis: &KeyAxis, t: &CurveTrade) -> String {
    let col = format!("{}{}", axis.key, crate::sweep::spec::unit_suffix(axis.dim));
    let mut out = format!(
        "{},kalker_critical_speed_m_s,hopf_speed_m_s,nonlinear_critical_speed_m_s,status,stable_up_to_m_s,nonlinear_source,feasible,reason\n",
        csv_field(&col)
    );
    for (s, why) in &t.samples {
        let r = &s.row;
        let source = match s.vnl {
            VnlSource::NotRead => "",
            VnlSource::Point => "point",
            VnlSource::Between { .. } => "interpolated",
            VnlSource::OnCurves { .. } => "on curves",
            VnlSource::Unknown(_) => "unknown",
        };
        let fields = [
            format!("{}", s.x),
            cell(r.results[0]),
            cell(r.results[1]),
            cell(r.results[2]),
            csv_field(&r.status),
            cell(r.stable_up_to_m_s),
            source.to_string(),
            why.is_none().to_string(),
            csv_field(why.as_deref().unwrap_or("")),
        ];
        out.push_str(&fields.join(","));
        out.push('\n');
    }
    out
}
