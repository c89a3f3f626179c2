//! `curve.svg`: the critical speeds against the design key.

use super::{figure, line, render, Rendered};
use crate::curve::{CurveKind, CurveReport, SpecialKind};
use crate::plot::{Series, Style};
use crate::stability::HopfKind;

/// The stable region's polygons: one per run of key values where the centred motion is stable
/// at the bottom of the speed range, closed along that bottom.
fn shades(top: &[(f64, f64)], bottom: f64) -> Vec<Vec<(f64, f64)>> {
    let mut out = Vec::new();
    let mut run: Vec<(f64, f64)> = Vec::new();
    let close = |run: &mut Vec<(f64, f64)>, out: &mut Vec<Vec<(f64, f64)>>| {
        if run.len() > 1 {
            let (first, last) = (run[0].0, run[run.len() - 1].0);
            let mut poly = vec![(first, bottom)];
            poly.append(run);
            poly.push((last, bottom));
            out.push(poly);
        }
        run.clear();
    };
    for &(p, v) in top {
        if v.is_finite() {
            run.push((p, v));
        } else {
            close(&mut run, &mut out);
        }
    }
    close(&mut run, &mut out);
    out
}

fn number(v: f64) -> String {
    if v != 0.0 && (v.abs() >= 1e4 || v.abs() < 1e-2) {
        format!("{v:.4e}")
    } else {
        format!("{v:.4}")
    }
}

/// $V_L$ (dashed) and $V_H$ (solid) against the key, every curve of each; the region where the
/// centred motion is stable shaded in its curves' colour; the folds of cycles (dashed) and
/// V_NL's points; subcritical stretches of the creep law's curves marked with crosses; the
/// codimension-two points labelled in the legend.
pub fn curve(r: &CurveReport) -> Rendered {
    let unit = r.dimension.si_unit();
    let x_label = if unit.is_empty() {
        format!("{} (–)", r.key)
    } else {
        format!("{} ({unit})", r.key)
    };
    let mut fig = figure(
        &format!("{}: critical speeds against {}", r.study, r.key),
        &x_label,
        "speed V (m/s)",
    );
    fig.x_log = r.log;
    fig.y_range = Some(r.speed_range);
    // the study's own model is the one whose stable region is shaded (Kalker's when the study
    // uses Kalker); V_L is drawn as the line it is
    let shaded = r.stable_regions.last().map(|s| s.label);
    for region in &r.stable_regions {
        let polys = if Some(region.label) == shaded {
            shades(&region.top, r.speed_range.0)
        } else {
            Vec::new()
        };
        for (k, poly) in polys.into_iter().enumerate() {
            fig.series.push(Series {
                name: if k == 0 {
                    format!("stable ({} model)", region.creep_law.name())
                } else {
                    String::new()
                },
                points: poly,
                style: Style::Shade,
            });
        }
        let mut points: Vec<(f64, f64)> = Vec::new();
        for c in r.curves.iter().filter(|c| c.label == region.label) {
            if !points.is_empty() {
                points.push((f64::NAN, f64::NAN));
            }
            points.extend(c.points.iter().map(|p| (p.parameter, p.speed_m_s)));
        }
        if !points.is_empty() {
            let name = match region.label {
                "V_L" => "V_L (Kalker)".to_string(),
                other => format!("{other} ({})", region.creep_law.name()),
            };
            fig.series.push(line(&name, points, region.label == "V_L"));
        }
    }
    // the folds of cycles, each curve a dashed line of one colour, and V_NL's points on top
    let mut folds: Vec<(f64, f64)> = Vec::new();
    for c in r.curves.iter().filter(|c| c.kind == CurveKind::Fold) {
        if !folds.is_empty() {
            folds.push((f64::NAN, f64::NAN));
        }
        folds.extend(c.points.iter().map(|p| (p.parameter, p.speed_m_s)));
    }
    if !folds.is_empty() {
        fig.series.push(Series {
            name: "folds of cycles".into(),
            points: folds,
            style: Style::Line { dashed: true },
        });
    }
    // the flips of cycles, where asymmetric (symmetry breaking) or doubled (period doubling)
    // cycles branch off, and the torus bifurcations: one dashed line per kind
    for (kind, name) in [
        (CurveKind::SymmetryBreaking, "symmetry breaking of cycles"),
        (CurveKind::PeriodDoubling, "period doubling of cycles"),
        (CurveKind::Torus, "torus bifurcations of cycles"),
    ] {
        let mut points: Vec<(f64, f64)> = Vec::new();
        for c in r.curves.iter().filter(|c| c.kind == kind) {
            if !points.is_empty() {
                points.push((f64::NAN, f64::NAN));
            }
            points.extend(c.points.iter().map(|p| (p.parameter, p.speed_m_s)));
        }
        if !points.is_empty() {
            fig.series.push(Series {
                name: name.into(),
                points,
                style: Style::Line { dashed: true },
            });
        }
    }
    if !r.nonlinear_critical_speed.is_empty() {
        fig.series.push(Series {
            // short: the legend shares the plot with the curves (the rule is in the docs)
            name: if r.attractor_search.is_empty() {
                "V_NL (continuation)".into()
            } else {
                "V_NL (continuation or attractor search)".into()
            },
            points: r.nonlinear_critical_speed.clone(),
            style: Style::Points,
        });
    }
    // every third point of the subcritical stretches: a mark, not a second line
    let subcritical: Vec<(f64, f64)> = r
        .curves
        .iter()
        .filter(|c| Some(c.label) == shaded)
        .flat_map(|c| c.points.iter().step_by(3))
        .filter(|p| p.hopf_type == Some(HopfKind::Subcritical))
        .map(|p| (p.parameter, p.speed_m_s))
        .collect();
    if !subcritical.is_empty() {
        fig.series.push(Series {
            name: "subcritical Hopf (l1 > 0)".into(),
            points: subcritical,
            style: Style::Crosses,
        });
    }
    for kind in [
        SpecialKind::Bautin,
        SpecialKind::DoubleHopf,
        SpecialKind::ZeroHopf,
        SpecialKind::BogdanovTakens,
        SpecialKind::Cusp,
        SpecialKind::FoldTorus,
        SpecialKind::FoldFlip,
        SpecialKind::FoldSymmetryBreaking,
    ] {
        let here: Vec<_> = r.special_points.iter().filter(|s| s.kind == kind).collect();
        if here.is_empty() {
            continue;
        }
        let names: Vec<String> = here
            .iter()
            .map(|s| {
                format!(
                    "{} {:.2} m/s{}",
                    number(s.parameter),
                    s.speed_m_s,
                    if s.located { "" } else { " (bracketed)" }
                )
            })
            .collect();
        // more than one point: their count (the printout and curve.json list them), which
        // keeps the legend narrow enough to leave the curves visible
        let listed = if names.len() > 1 {
            format!("{} points", names.len())
        } else {
            names.join(", ")
        };
        fig.series.push(Series {
            name: format!("{}: {listed}", kind.label()),
            points: here.iter().map(|s| (s.parameter, s.speed_m_s)).collect(),
            style: Style::Points,
        });
    }
    render("curve.svg", &fig, 1000, 640)
}
