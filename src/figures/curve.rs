//! `curve.svg`: the critical speeds against the design key.

use super::{figure, line, render, Rendered};
use crate::curve::{CurveKind, CurveReport, SpecialKind};
use crate::plot::{Series, Style};
use crate::stability::HopfKind;

/// V_NL as the pictures read it between its points: at a key value between two adjacent
/// known V_NL points (no value where it is unknown between them) the lower of the two, at a
/// point its own value; `None` outside them. The lower of the two, since between its points
/// V_NL can dip below a straight line (near a cusp of folds it bends: docs/curves.md), so the
/// region drawn below it never takes in a speed where a neighbouring point says it hunts.
fn vnl_floor(known: &[(f64, f64)], unknown: &[f64], k: f64) -> Option<f64> {
    if let Some(&(_, v)) = known.iter().find(|p| p.0 == k) {
        return Some(v);
    }
    known.windows(2).find_map(|w| {
        let (a, b) = (w[0].0.min(w[1].0), w[0].0.max(w[1].0));
        let gap = unknown.iter().any(|&u| a < u && u < b);
        (a < k && k < b && !gap).then(|| w[0].1.min(w[1].1))
    })
}

/// The three regions of a stable band `top` (key, V_H or V_L there): below V_NL "no hunting",
/// from V_NL (or the bottom, where V_NL is unknown) to the top "centred running stable, hunting
/// after a large enough disturbance", above the top "unstable"; polygons of each, runs split
/// where the band is undefined (NaN).
type Polygons = Vec<Vec<(f64, f64)>>;
fn regions(r: &CurveReport, top: &[(f64, f64)]) -> (Polygons, Polygons, Polygons) {
    let (bottom, ceiling) = r.speed_range;
    let mut known: Vec<(f64, f64)> = r.nonlinear_critical_speed.clone();
    known.sort_by(|a, b| a.0.total_cmp(&b.0));
    // the band's keys and the V_NL points' keys, in order
    let mut keys: Vec<f64> = top.iter().map(|t| t.0).collect();
    keys.extend(known.iter().map(|k| k.0));
    keys.sort_by(f64::total_cmp);
    keys.dedup();
    let top_at = |k: f64| -> f64 {
        // the band's top at k: linear between its samples, NaN where either is NaN
        if let Some(&(_, v)) = top.iter().find(|t| t.0 == k) {
            return v;
        }
        top.windows(2)
            .find(|w| w[0].0.min(w[1].0) < k && k < w[0].0.max(w[1].0))
            .map_or(f64::NAN, |w| {
                let t = (k - w[0].0) / (w[1].0 - w[0].0);
                w[0].1 + t * (w[1].1 - w[0].1)
            })
    };
    let mut none: Polygons = Vec::new();
    let mut middle: Polygons = Vec::new();
    let mut above: Polygons = Vec::new();
    // (key, floor, top) runs where the band is defined
    let mut run: Vec<(f64, f64, f64)> = Vec::new();
    let flush = |run: &mut Vec<(f64, f64, f64)>,
                 none: &mut Polygons,
                 middle: &mut Polygons,
                 above: &mut Polygons| {
        if run.len() > 1 {
            let mut mid: Vec<(f64, f64)> = run.iter().map(|q| (q.0, q.2)).collect();
            mid.extend(run.iter().rev().map(|q| (q.0, q.1)));
            middle.push(mid);
            let mut up: Vec<(f64, f64)> = run.iter().map(|q| (q.0, ceiling)).collect();
            up.extend(run.iter().rev().map(|q| (q.0, q.2)));
            above.push(up);
            // "no hunting" only over the stretches where the floor is above the bottom
            let mut low: Vec<(f64, f64, f64)> = Vec::new();
            for &q in run.iter() {
                if q.1 > bottom {
                    low.push(q);
                } else if low.len() > 1 {
                    let mut poly: Vec<(f64, f64)> = low.iter().map(|q| (q.0, q.1)).collect();
                    poly.extend(low.iter().rev().map(|q| (q.0, bottom)));
                    none.push(std::mem::take(&mut poly));
                    low.clear();
                } else {
                    low.clear();
                }
            }
            if low.len() > 1 {
                let mut poly: Vec<(f64, f64)> = low.iter().map(|q| (q.0, q.1)).collect();
                poly.extend(low.iter().rev().map(|q| (q.0, bottom)));
                none.push(poly);
            }
        }
        run.clear();
    };
    for k in keys {
        let t = top_at(k);
        if !t.is_finite() {
            flush(&mut run, &mut none, &mut middle, &mut above);
            continue;
        }
        let floor =
            vnl_floor(&known, &r.nonlinear_unknown, k).map_or(bottom, |v| v.clamp(bottom, t));
        run.push((k, floor, t));
    }
    flush(&mut run, &mut none, &mut middle, &mut above);
    (none, middle, above)
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
        if Some(region.label) == shaded {
            // below V_NL no hunting; up to the band's top the centred motion is stable but a
            // large enough disturbance can start hunting; above it the centred motion is
            // unstable. Where V_NL is unknown the middle region reaches down to the bottom.
            let (none, middle, above) = regions(r, &region.top);
            let law = region.creep_law.name();
            // short words: the legend must leave the plot its width (docs/curves.md has them
            // in full)
            let unknown = if r.nonlinear_critical_speed.is_empty() {
                " (V_NL not computed)"
            } else if !r.nonlinear_unknown.is_empty() {
                " (V_NL unknown in part)"
            } else {
                ""
            };
            for (polys, name, style) in [
                (
                    none,
                    "no hunting (below V_NL)".to_string(),
                    super::NO_HUNTING,
                ),
                (
                    middle,
                    format!("stable, hunts if disturbed{unknown}"),
                    super::HUNTS_IF_DISTURBED,
                ),
                (
                    above,
                    format!("unstable (above {}, {law})", region.label),
                    super::HUNTS,
                ),
            ] {
                for (k, poly) in polys.into_iter().enumerate() {
                    fig.series.push(Series {
                        name: if k == 0 { name.clone() } else { String::new() },
                        points: poly,
                        style: style.clone(),
                    });
                }
            }
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
            name: format!("{}: {listed}", kind.words()),
            points: here.iter().map(|s| (s.parameter, s.speed_m_s)).collect(),
            style: Style::Points,
        });
    }
    render("curve.svg", &fig, 1000, 640)
}

#[cfg(test)]
mod region_tests {
    use super::vnl_floor;

    /// The "no hunting" region's top between V_NL points is the lower neighbour, a point's own
    /// value at the point, nothing outside the points or across a value where V_NL is unknown:
    /// it never reaches above a speed where a neighbouring point says a hunting motion exists.
    #[test]
    fn the_no_hunting_region_never_rises_above_a_neighbouring_vnl() {
        let known = [(0.0, 50.0), (1.0, 60.0), (2.0, 40.0)];
        assert_eq!(vnl_floor(&known, &[], 0.5), Some(50.0));
        assert_eq!(vnl_floor(&known, &[], 1.0), Some(60.0));
        assert_eq!(vnl_floor(&known, &[], 1.5), Some(40.0));
        assert_eq!(vnl_floor(&known, &[], 2.5), None);
        assert_eq!(vnl_floor(&known, &[], -0.1), None);
        assert_eq!(vnl_floor(&known, &[1.5], 1.7), None);
        assert_eq!(vnl_floor(&known, &[1.5], 0.7), Some(50.0));
    }
}
