//! `trade.svg` of a curve trade: the critical speeds the trade reads against the key, the
//! constraints' bounds as lines, the feasible intervals shaded, the best design and its
//! verification marked.

use super::{figure, line, render, Rendered};
use crate::plot::{Marker, Series, Style};
use crate::trade::curve::KeyAxis;
use crate::trade::intervals::CurveTrade;
use crate::trade::{display_unit, Target, TradePlan};

/// The curve trade's figure (key in display units, speeds in m/s).
pub fn trade_curve(study: &str, plan: &TradePlan, axis: &KeyAxis, t: &CurveTrade) -> Rendered {
    let (unit, f) = display_unit(axis.dim);
    let mut fig = figure(
        &format!("{study}: critical speeds on curves against {}", axis.key),
        &format!("{} ({unit})", axis.key),
        "speed (m/s)",
    );
    fig.x_log = axis.log;
    // the whole axis, so that key values without a known result show as such
    fig.x_range = Some((axis.range.0 * f, axis.range.1 * f));
    let reads = plan.read_results();
    let mut ys: Vec<f64> = Vec::new();
    let mut lines = Vec::new();
    for (k, r) in crate::trade::ResultKind::ALL.into_iter().enumerate() {
        if !reads.contains(&r) {
            continue;
        }
        let pts: Vec<(f64, f64)> = t
            .samples
            .iter()
            .map(|(s, _)| (s.x * f, s.row.results[k].unwrap_or(f64::NAN)))
            .collect();
        ys.extend(pts.iter().map(|p| p.1).filter(|y| y.is_finite()));
        if pts.iter().any(|p| p.1.is_finite()) {
            lines.push(line(&format!("{} (curves)", r.name()), pts, false));
        }
    }
    for c in &plan.constraints {
        if let Target::Result(_) = c.target {
            for b in [c.at_least, c.at_most].into_iter().flatten() {
                ys.push(b);
                fig.hlines.push(Marker {
                    at: b,
                    label: c.text.clone(),
                });
            }
        }
    }
    let (lo, hi) = ys
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), y| {
            (l.min(*y), h.max(*y))
        });
    let (lo, hi) = if lo <= hi { (lo, hi) } else { (0.0, 1.0) };
    let pad = if hi > lo { 0.08 * (hi - lo) } else { 1.0 };
    let (y0, y1) = (lo - pad, hi + pad);
    fig.y_range = Some((y0, y1));
    // where the settlement moved the best design, the stretch it left is not shaded feasible
    let settled_best = t
        .verification
        .as_ref()
        .and_then(|v| v.settled.as_ref())
        .map(|se| se.x);
    for (k, i) in t.intervals.iter().enumerate() {
        let (mut a, mut b) = (i.from.x * f, i.to.x * f);
        if let (Some(best), Some(moved)) = (&t.best, settled_best) {
            if best.interval == k {
                match (plan.objective.sense, moved) {
                    (_, None) => continue,
                    (crate::trade::Sense::Minimize, Some(x)) => a = x * f,
                    (crate::trade::Sense::Maximize, Some(x)) => b = x * f,
                }
            }
        }
        fig.series.push(Series {
            name: if k == 0 {
                "feasible".into()
            } else {
                String::new()
            },
            points: vec![(a, y0), (b, y0), (b, y1), (a, y1)],
            style: Style::Shade,
        });
    }
    fig.series.extend(lines);
    if let Some(b) = &t.best {
        fig.vlines.push(Marker {
            at: b.x * f,
            label: format!("best {}", crate::trade::plan::fmt_si(b.x * f)),
        });
    }
    if let Some(v) = &t.verification {
        let pts: Vec<(f64, f64)> = (0..3)
            .filter_map(|k| v.computed.results[k].map(|y| (v.x * f, y)))
            .collect();
        if !pts.is_empty() {
            fig.series.push(Series {
                name: format!(
                    "verification (one-point computation): {}",
                    if v.feasible {
                        "feasible"
                    } else {
                        "NOT feasible"
                    }
                ),
                points: pts,
                style: Style::Points,
            });
        }
        // the settled V_NL (a fold cycle's attractor simulated) at the verification's value and,
        // where the best design moved, its judged V_NL there
        let mut settled: Vec<(f64, f64)> = Vec::new();
        if let Some(y) = v.settlement.as_ref().and_then(|s| s.nonlinear_m_s) {
            settled.push((v.x * f, y));
        }
        let mut moved: Vec<(f64, f64)> = Vec::new();
        if let Some(se) = &v.settled {
            if let Some(x) = se.x {
                let label = match se.by {
                    crate::trade::intervals::Inward::Simulation => "settled best",
                    crate::trade::intervals::Inward::OnePoint => "best moved inward",
                };
                fig.vlines.push(Marker {
                    at: x * f,
                    label: format!("{label} {}", crate::trade::plan::fmt_si(x * f)),
                });
                if let Some(y) = se.nonlinear_m_s {
                    match se.by {
                        crate::trade::intervals::Inward::Simulation => settled.push((x * f, y)),
                        crate::trade::intervals::Inward::OnePoint => moved.push((x * f, y)),
                    }
                }
            }
        }
        if !settled.is_empty() {
            fig.series.push(Series {
                name: "V_NL settled by simulating the fold cycles".into(),
                points: settled,
                style: Style::Points,
            });
        }
        if !moved.is_empty() {
            fig.series.push(Series {
                name: "V_NL by the one-point computation at the best moved inward".into(),
                points: moved,
                style: Style::Points,
            });
        }
    }
    render("trade.svg", &fig, 900, 580)
}
