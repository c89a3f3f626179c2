//! Sweep figures: critical speeds against one axis (`sweep.svg`), or a map over two axes
//! (`sweep_map_<result>.svg`). Failed points are drawn as failed, never interpolated over;
//! points with no onset in their speed range ("above range") are drawn as such: an up-triangle
//! at the top of the range on the line plot, a cell beyond the top of the colour bar on a map.

use super::{figure, line, render, Rendered};
use crate::curve::CurveReport;
use crate::plot::{AboveRange, Figure, Marker, PlotError, Series, Style};
use crate::sweep::{Axis, Computed, Outcome, PointRecord, SweepSpec};

pub use crate::plot::HeatMap;

/// The map of one result over two axes: cells coloured by value, labelled contours, the
/// operating-speed boundary; failed points hatched, never interpolated over; above-range
/// points (no onset up to the top of the speed range) filled beyond the colour bar.
pub fn sweep_map(h: &HeatMap) -> Result<String, PlotError> {
    crate::plot::heat_map_svg(h)
}

/// The results a sweep can compute: (name in file names, legend, value of a point).
type Pick = (&'static str, &'static str, fn(&PointRecord) -> Option<f64>);

fn picks(spec: &SweepSpec) -> Vec<Pick> {
    let c = spec.compute;
    let all: [(bool, Pick); 3] = [
        (
            c.kalker,
            ("kalker", "Kalker critical speed V_L", |r| r.kalker_m_s),
        ),
        (
            c.hopf,
            ("hopf", "Hopf speed of the creep law V_H", |r| r.hopf_m_s),
        ),
        (
            c.nonlinear,
            ("nonlinear", "nonlinear critical speed V_NL", |r| {
                r.nonlinear_m_s
            }),
        ),
    ];
    all.into_iter()
        .filter(|(on, _)| *on)
        .map(|(_, p)| p)
        .collect()
}

/// `sweep.svg` for one axis; one `sweep_map_<result>.svg` per result for two axes. `rows`
/// need not be complete: absent points are drawn as failed.
pub fn sweep(study: &str, spec: &SweepSpec, rows: &[PointRecord]) -> Vec<Rendered> {
    sweep_with_curves(study, spec, rows, None)
}

/// As [`sweep`], with `curves` over the axis key drawn on `sweep.svg` as dashed lines on top
/// of the points (in the colour of the same result): V_L(curve) and V_H(curve), the lowest
/// onset on the Kalker and creep-law Hopf curves (the critical speed the curves give, broken
/// where there is none in the speed range), and V_NL(curve), the curves' V_NL points. A map
/// (two varying axes) draws no curves: they are one slice of it, at the other key's own value.
pub fn sweep_with_curves(
    study: &str,
    spec: &SweepSpec,
    rows: &[PointRecord],
    curves: Option<&CurveReport>,
) -> Vec<Rendered> {
    let mut by_id: Vec<Option<&PointRecord>> = vec![None; spec.len()];
    for r in rows {
        if let Some(slot) = by_id.get_mut(r.id) {
            *slot = Some(r);
        }
    }
    // What the operating speed's line means depends on the speed it is compared with: where
    // V_NL is below it, hunting is possible at the operating speed; where V_L or V_H is below
    // it, the centred running is unstable there (and where they are above it, it is stable
    // but a large enough disturbance may still start hunting).
    let threshold = spec.operating_speed.map(|v| {
        (
            v,
            format!(
                "operating speed {:.0} km/h ({v:.2} m/s): hunting possible where V_NL < it",
                v * 3.6
            ),
        )
    });
    let threshold_for = |file: &str| {
        spec.operating_speed.map(|v| {
            let meaning = match file {
                "nonlinear" => "V_NL below it: hunting possible; above: no hunting",
                "kalker" => "V_L below it: unstable; above: stable, may hunt if disturbed",
                _ => "V_H below it: unstable; above: stable, may hunt if disturbed",
            };
            (v, format!("{:.0} km/h ({v:.2} m/s): {meaning}", v * 3.6))
        })
    };
    // An axis with one value does not span a map: plot against the other one. The point ids
    // then run along the varying axis in order, so the line plot below applies unchanged.
    let varying: Vec<_> = spec.axes.iter().filter(|a| a.values.len() > 1).collect();
    let line_axis = match (spec.axes.as_slice(), varying.as_slice()) {
        ([a], _) => Some(a),
        (_, [a]) => Some(*a),
        (_, []) => spec.axes.first(),
        _ => None,
    };
    if let Some(a) = line_axis {
        let mut f = line_plot(study, spec, a, &by_id, threshold);
        if let Some(r) = curves.filter(|r| r.key == a.key && spec.axes.len() == 1) {
            draw_curves(&mut f, spec, r);
        }
        return vec![render("sweep.svg", &f, 900, 600)];
    }
    picks(spec)
        .into_iter()
        .map(|(file, name, get)| {
            let mut h = heat_map(study, spec, &by_id, name, get, threshold_for(file));
            h.above = above_range(&by_id, Computed::from_name(file));
            Rendered {
                file: format!("sweep_map_{file}.svg"),
                size: (880, 600),
                svg: sweep_map(&h),
            }
        })
        .collect()
}

/// The critical speeds against one axis: a line per result (broken where a point has none);
/// points with a result above range as up-triangles at the top of their speed range (the
/// value lies above); failed or absent points as crosses along the bottom of the plot.
fn line_plot(
    study: &str,
    spec: &SweepSpec,
    a: &Axis,
    by_id: &[Option<&PointRecord>],
    threshold: Option<(f64, String)>,
) -> Figure {
    let mut f = figure(
        &format!("{study}: critical speeds against {}", a.key),
        &a.label(),
        "speed (m/s)",
    );
    f.x_log = a.spacing == crate::sweep::Spacing::Log;
    let mut ys: Vec<f64> = threshold.iter().map(|t| t.0).collect();
    for (_, name, get) in picks(spec) {
        let pts: Vec<(f64, f64)> = a
            .values
            .iter()
            .zip(by_id)
            .map(|(x, r)| (*x, r.and_then(get).unwrap_or(f64::NAN)))
            .collect();
        ys.extend(pts.iter().map(|p| p.1).filter(|y| y.is_finite()));
        // a result found nowhere has no line (its points are marked below)
        if pts.iter().any(|p| p.1.is_finite()) {
            f.series.push(line(name, pts, false));
        }
    }
    let points = a.values.iter().zip(by_id);
    let above: Vec<(f64, f64)> = points
        .clone()
        .filter_map(|(x, r)| Some((*x, r.filter(|r| r.has_above_range())?.stable_up_to_m_s?)))
        .collect();
    ys.extend(above.iter().map(|p| p.1));
    let (lo, hi) = ys
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), y| {
            (l.min(*y), h.max(*y))
        });
    let (lo, hi) = if lo <= hi { (lo, hi) } else { (0.0, 1.0) };
    let pad = if hi > lo { 0.06 * (hi - lo) } else { 1.0 };
    // a band under the data for the failed points, which have no value
    f.y_range = Some((lo - 3.0 * pad, hi + 1.5 * pad));
    let failed: Vec<(f64, f64)> = points
        .clone()
        .filter(|(_, r)| !r.is_some_and(PointRecord::ok))
        .map(|(x, _)| (*x, lo - 1.8 * pad))
        .collect();
    let no_hopf: Vec<(f64, f64)> = points
        .filter(|(_, r)| r.is_some_and(|r| r.ok() && r.no_hopf))
        .map(|(x, _)| (*x, lo - 1.8 * pad))
        .collect();
    if let Some(top) = above.first().map(|p| p.1) {
        f.series.push(Series {
            name: format!("above range: no onset up to {top:.0} m/s"),
            points: above,
            style: Style::Above,
        });
    }
    if !failed.is_empty() {
        f.series.push(Series {
            name: "failed point (no value; reason in sweep.csv)".into(),
            points: failed,
            style: Style::Crosses,
        });
    }
    if !no_hopf.is_empty() {
        f.series.push(Series {
            name: "V_NL not computed: no Hopf point in range".into(),
            points: no_hopf,
            style: Style::Crosses,
        });
    }
    if let Some((v, label)) = threshold {
        f.hlines.push(Marker { at: v, label });
    }
    f
}

/// The curves' critical speeds on the line plot, each in the colour of the grid's line of the
/// same result (the grid's lines take the palette's colours in [`picks`] order), widening the
/// speed range to hold them.
fn draw_curves(f: &mut Figure, spec: &SweepSpec, r: &CurveReport) {
    let c = spec.compute;
    let colour = |which: usize| {
        let on = [c.kalker, c.hopf, c.nonlinear];
        on[..which].iter().filter(|x| **x).count()
    };
    let mut added: Vec<Series> = Vec::new();
    for region in &r.stable_regions {
        // the creep law's own Hopf speed; Kalker's is V_L (a study on Kalker's law has only it)
        let (name, which) = match region.label {
            "V_L" => ("V_L(curve): lowest onset on the Kalker Hopf curves", 0),
            _ => ("V_H(curve): lowest onset on the creep law's Hopf curves", 1),
        };
        let top = r.speed_range.1;
        let pts: Vec<(f64, f64)> = region
            .top
            .iter()
            .map(|&(x, v)| (x, if v < top { v } else { f64::NAN }))
            .collect();
        if pts.iter().any(|p| p.1.is_finite()) {
            added.push(Series {
                name: name.into(),
                points: pts,
                style: Style::LineIn {
                    dashed: true,
                    colour: colour(which),
                },
            });
        }
    }
    if !r.nonlinear_critical_speed.is_empty() {
        added.push(Series {
            name: "V_NL(curve): the curves' V_NL points".into(),
            points: r.nonlinear_critical_speed.clone(),
            style: Style::PointsIn {
                colour: colour(2),
                crosses: false,
            },
        });
    }
    let ys = added.iter().flat_map(|s| s.points.iter().map(|p| p.1));
    if let Some((lo, hi)) = f.y_range {
        let (l, h) = ys
            .filter(|y| y.is_finite())
            .fold((lo, hi), |(l, h), y| (l.min(y), h.max(y)));
        f.y_range = Some((l, h));
    }
    f.series.extend(added);
}

/// The map of one result over two axes: each cell is its point's value, `None` where the
/// point failed or is absent (never interpolated).
fn heat_map(
    study: &str,
    spec: &SweepSpec,
    by_id: &[Option<&PointRecord>],
    name: &str,
    get: fn(&PointRecord) -> Option<f64>,
    threshold: Option<(f64, String)>,
) -> HeatMap {
    let (ax, ay) = (&spec.axes[0], &spec.axes[1]);
    HeatMap {
        title: format!("{study}: {name}"),
        x_label: ax.label(),
        y_label: ay.label(),
        x: ax.values.clone(),
        y: ay.values.clone(),
        x_log: ax.spacing == crate::sweep::Spacing::Log,
        y_log: ay.spacing == crate::sweep::Spacing::Log,
        z: by_id.iter().map(|r| r.and_then(get)).collect(),
        z_label: format!("{name} (m/s)"),
        threshold,
        above: None,
    }
}

/// The cells where result `which` is above range, with the lowest top of range among them.
fn above_range(by_id: &[Option<&PointRecord>], which: Option<Computed>) -> Option<AboveRange> {
    let which = which?;
    let tops: Vec<Option<f64>> = by_id
        .iter()
        .map(|r| match r.map(|r| r.outcome(which)) {
            Some(Outcome::AboveRange { stable_up_to_m_s }) => Some(stable_up_to_m_s),
            _ => None,
        })
        .collect();
    let bound = tops.iter().flatten().copied().reduce(f64::min)?;
    Some(AboveRange {
        cells: tops.iter().map(Option::is_some).collect(),
        bound,
        label: format!("> {bound:.0} m/s (no onset in range)"),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::study::units::Dimension;
    use crate::sweep::{Axis, Compute, Spacing};

    fn spec(axes: usize) -> SweepSpec {
        let axis = |key: &str| Axis {
            key: key.into(),
            dim: Dimension::Stiffness,
            spacing: Spacing::Linear,
            values: vec![1e5, 2e5, 3e5],
            files: Vec::new(),
        };
        SweepSpec {
            axes: (0..axes).map(|k| axis(["a", "b"][k])).collect(),
            compute: Compute {
                kalker: true,
                hopf: false,
                nonlinear: false,
            },
            operating_speed: Some(50.0),
            attractors: false,
        }
    }

    fn row(id: usize, v: Option<f64>) -> PointRecord {
        PointRecord {
            id,
            values: vec![],
            kalker_m_s: v,
            hopf_m_s: None,
            nonlinear_m_s: None,
            failures: if v.is_some() {
                vec![]
            } else {
                vec!["kalker: none".into()]
            },
            kalker_frequency_hz: None,
            hopf_frequency_hz: None,
            nonlinear_located: None,
            above_range: vec![],
            stable_up_to_m_s: None,
            no_hopf: false,
        }
    }

    /// (file, SVG) of each figure, all drawn.
    fn svgs(figs: Vec<Rendered>) -> Vec<(String, String)> {
        figs.into_iter()
            .map(|f| (f.file, f.svg.expect("svg")))
            .collect()
    }

    #[test]
    fn failed_cells_stay_empty_in_the_map() {
        let s = spec(2);
        // point 4 (the centre) failed, point 8 was never computed
        let rows: Vec<PointRecord> = (0..8)
            .map(|i| row(i, (i != 4).then_some(10.0 * i as f64)))
            .collect();
        let mut by_id: Vec<Option<&PointRecord>> = vec![None; 9];
        for r in &rows {
            by_id[r.id] = Some(r);
        }
        let h = heat_map("t", &s, &by_id, "V_L", |r| r.kalker_m_s, None);
        assert_eq!(h.z[4], None);
        assert_eq!(h.z[8], None);
        assert_eq!(h.z[5], Some(50.0));
        assert!(sweep("t", &s, &rows).iter().all(|f| f.svg.is_ok()));
    }

    #[test]
    fn above_range_is_not_failed_on_plots() {
        let above = |id: usize| PointRecord {
            failures: vec![],
            above_range: vec![Computed::Kalker],
            stable_up_to_m_s: Some(300.0),
            ..row(id, None)
        };
        let mut rows: Vec<PointRecord> = (0..3).map(|i| row(i, Some(40.0 + i as f64))).collect();
        rows[1] = above(1);
        let line = svgs(sweep("t", &spec(1), &rows));
        assert!(line[0].1.contains("above range: no onset up to 300 m/s"));
        assert!(!line[0].1.contains("failed point"));
        // on a map: one above-range cell, one failed, one absent (also failed)
        let mut rows: Vec<PointRecord> = (0..8).map(|i| row(i, Some(40.0 + i as f64))).collect();
        rows[4] = above(4);
        rows[5] = row(5, None);
        let map = svgs(sweep("t", &spec(2), &rows));
        let svg = &map[0].1;
        let cells = |fill: &str| svg.matches(&format!("fill=\"{fill}\"/>")).count();
        assert_eq!(cells(crate::plot::ABOVE_FILL), 1);
        assert_eq!(cells("url(#failed)"), 2);
        assert!(svg.contains("300 m/s (1)"));
    }

    #[test]
    fn failed_points_are_marked_on_the_line_plot() {
        let s = spec(1);
        let rows = vec![row(0, Some(40.0)), row(1, None), row(2, Some(60.0))];
        let figs = svgs(sweep("t", &s, &rows));
        assert_eq!(figs[0].0, "sweep.svg");
        assert!(figs[0].1.contains("failed point"));
        // a V_NL without a Hopf point is said so, apart from the failed points
        let mut no_hopf = rows.clone();
        no_hopf[1] = PointRecord {
            failures: vec![],
            no_hopf: true,
            ..row(1, None)
        };
        let figs = svgs(sweep("t", &s, &no_hopf));
        assert!(figs[0]
            .1
            .contains("V_NL not computed: no Hopf point in range"));
        assert!(!figs[0].1.contains("failed point"));
        // a result found nowhere gives no line, and no error
        let none = vec![row(0, None), row(1, None)];
        assert!(sweep("t", &s, &none).iter().all(|f| f.svg.is_ok()));
    }
}
