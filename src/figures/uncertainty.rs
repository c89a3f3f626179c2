//! `uncertainty.svg`: per computed speed, its distribution (histogram and empirical CDF, the
//! operating speed marked) and its Sobol indices (total-index bars with their 95 % intervals,
//! first-order indices with theirs, sorted by total index, largest at the top).

use super::{figure, render_panels, Rendered};
use crate::plot::{Figure, Marker, Series, Style};
use crate::uncertainty::{QuantityReport, UncertaintyReport};

/// Okabe–Ito sky blue, lightened: the total-index bars.
const BAR: (u8, u8, u8) = (0x56, 0xB4, 0xE9);

fn speed_name(name: &str) -> &'static str {
    match name {
        "kalker" => "Kalker critical speed V_L",
        "hopf" => "creep-law Hopf speed V_H",
        _ => "nonlinear critical speed V_NL",
    }
}

/// Equal-width bins over the values' range: (edges, fraction of the values in each).
fn histogram(values: &[f64]) -> (Vec<f64>, Vec<f64>) {
    let lo = values.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = values.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let (lo, hi) = if hi > lo {
        (lo, hi)
    } else {
        (lo - 0.5, hi + 0.5)
    };
    let bins = ((values.len() as f64).sqrt().round() as usize).clamp(5, 40);
    let width = (hi - lo) / bins as f64;
    let edges: Vec<f64> = (0..=bins).map(|k| lo + width * k as f64).collect();
    let mut counts = vec![0usize; bins];
    for v in values {
        let k = (((v - lo) / width).floor() as usize).min(bins - 1);
        counts[k] += 1;
    }
    let n = values.len() as f64;
    (edges, counts.iter().map(|c| *c as f64 / n).collect())
}

fn distribution(q: &QuantityReport, operating: Option<f64>) -> Figure {
    let mut f = figure(
        &format!(
            "{}: {} sampled speeds",
            speed_name(&q.name),
            q.values_m_s.len()
        ),
        "speed (m/s)",
        "fraction per bin; cumulative probability",
    );
    if q.values_m_s.is_empty() {
        return f;
    }
    let (edges, frac) = histogram(&q.values_m_s);
    // the bars' outline as one closed polygon along the axis
    let mut outline = vec![(edges[0], 0.0)];
    for (k, h) in frac.iter().enumerate() {
        outline.push((edges[k], *h));
        outline.push((edges[k + 1], *h));
    }
    outline.push((edges[edges.len() - 1], 0.0));
    f.series.push(Series {
        name: "histogram".into(),
        points: outline,
        style: Style::ShadeRgb(BAR.0, BAR.1, BAR.2),
    });
    let mut sorted = q.values_m_s.clone();
    sorted.sort_by(f64::total_cmp);
    let n = sorted.len() as f64;
    let mut cdf = Vec::with_capacity(2 * sorted.len());
    for (k, v) in sorted.iter().enumerate() {
        cdf.push((*v, k as f64 / n));
        cdf.push((*v, (k + 1) as f64 / n));
    }
    f.series.push(Series {
        name: "empirical CDF".into(),
        points: cdf,
        style: Style::LineIn {
            dashed: false,
            colour: 0,
        },
    });
    if let Some(v) = operating {
        let p = q
            .probability_below_operating_speed
            .map_or(String::new(), |p| format!(", P(below) = {p:.3}"));
        f.vlines.push(Marker {
            at: v,
            label: format!("operating speed {v:.1} m/s ({:.0} km/h){p}", v * 3.6),
        });
    }
    f.y_range = Some((0.0, 1.05));
    f
}

/// Whiskers as one line with gaps: `(lo, y) – (hi, y)` per row.
fn whiskers(rows: &[(f64, f64, f64)]) -> Vec<(f64, f64)> {
    let mut pts = Vec::with_capacity(3 * rows.len());
    for (lo, hi, y) in rows {
        pts.push((*lo, *y));
        pts.push((*hi, *y));
        pts.push((f64::NAN, f64::NAN));
    }
    pts
}

fn indices(q: &QuantityReport) -> Figure {
    let mut f = figure(
        &format!("Sobol indices of {}", speed_name(&q.name)),
        "index (fraction of the variance)",
        "parameter rank (by total index)",
    );
    let mut ix: Vec<_> = q.indices.iter().collect();
    // smallest first: the largest total index is drawn at the top
    ix.sort_by(|a, b| a.total.total_cmp(&b.total));
    let mut bars = vec![(0.0, 0.6)];
    for (k, i) in ix.iter().enumerate() {
        let y = k as f64 + 1.0;
        bars.extend([
            (0.0, y - 0.3),
            (i.total, y - 0.3),
            (i.total, y + 0.3),
            (0.0, y + 0.3),
        ]);
        f.hlines.push(Marker {
            at: y,
            label: i.key.clone(),
        });
    }
    bars.push((0.0, ix.len() as f64 + 0.4));
    f.series.push(Series {
        name: "total index".into(),
        points: bars,
        style: Style::ShadeRgb(BAR.0, BAR.1, BAR.2),
    });
    let at = |off: f64| {
        move |(k, _): (usize, &&crate::uncertainty::report::IndexReport)| k as f64 + 1.0 + off
    };
    let total: Vec<(f64, f64, f64)> = ix
        .iter()
        .enumerate()
        .map(|e| (e.1.total_ci[0], e.1.total_ci[1], at(0.12)(e)))
        .collect();
    let first: Vec<(f64, f64, f64)> = ix
        .iter()
        .enumerate()
        .map(|e| (e.1.first_order_ci[0], e.1.first_order_ci[1], at(-0.12)(e)))
        .collect();
    f.series.push(Series {
        name: "total index, 95 % interval".into(),
        points: whiskers(&total),
        style: Style::LineIn {
            dashed: false,
            colour: 0,
        },
    });
    f.series.push(Series {
        name: String::new(),
        points: ix
            .iter()
            .enumerate()
            .map(|e| (e.1.total, at(0.12)(e)))
            .collect(),
        style: Style::PointsIn {
            colour: 0,
            crosses: false,
        },
    });
    f.series.push(Series {
        name: "first-order index, 95 % interval".into(),
        points: whiskers(&first),
        style: Style::LineIn {
            dashed: false,
            colour: 1,
        },
    });
    f.series.push(Series {
        name: String::new(),
        points: ix
            .iter()
            .enumerate()
            .map(|e| (e.1.first_order, at(-0.12)(e)))
            .collect(),
        style: Style::PointsIn {
            colour: 1,
            crosses: true,
        },
    });
    f.y_range = Some((0.4, ix.len() as f64 + 0.9));
    // the data on the left half, the keys' labels (at the right end of their lines) beside it
    let ends = ix.iter().flat_map(|i| {
        [
            i.first_order_ci[0],
            i.first_order_ci[1],
            i.total_ci[0],
            i.total_ci[1],
        ]
    });
    let (lo, hi) = ends
        .filter(|v| v.is_finite())
        .fold((0.0_f64, 0.1_f64), |(a, b), v| (a.min(v), b.max(v)));
    f.x_range = Some((lo - 0.03 * (hi - lo), hi + 1.1 * (hi - lo)));
    f
}

/// `uncertainty.svg`: one row of panels per computed speed (its distribution, and its indices
/// when estimated).
pub fn uncertainty(report: &UncertaintyReport) -> Rendered {
    let with_indices = report.quantities.iter().any(|q| !q.indices.is_empty());
    let cols = if with_indices { 2 } else { 1 };
    let mut figs = Vec::new();
    for q in &report.quantities {
        figs.push(distribution(q, report.operating_speed_m_s));
        if with_indices {
            figs.push(indices(q));
        }
    }
    let rows = report.quantities.len().max(1) as u32;
    render_panels(
        "uncertainty.svg",
        &figs,
        cols,
        760 * cols as u32,
        460 * rows,
    )
}
