//! Two-axis maps: cells coloured by a value, labelled contour lines, failed points hatched,
//! and one distinguished threshold contour (e.g. the operating speed on a critical-speed map).

use super::contour::contour_lines;
use super::contour_labels::Contour;
use super::palette::viridis;
use super::scale::format_value;
use super::svg::{hex, nice_ticks, AxisMap, Doc, Frame, LABEL_PX, TICK_PX};
use super::PlotError;

#[path = "heatmap_above.rs"]
mod above;
use above::{above_box, is_above, split_label, threshold_z};
pub use above::{AboveRange, ABOVE_FILL};

/// A value `z` sampled on the grid `x × y`, to be drawn as a heat map with contours.
#[derive(Debug, Clone, PartialEq)]
pub struct HeatMap {
    /// Title drawn above the map.
    pub title: String,
    /// X-axis title including units, e.g. `"longitudinal stiffness (N/mm)"`.
    pub x_label: String,
    /// Y-axis title including units.
    pub y_label: String,
    /// Grid abscissae, strictly increasing, at least 2 (positive when `x_log`).
    pub x: Vec<f64>,
    /// Grid ordinates, strictly increasing, at least 2 (positive when `y_log`).
    pub y: Vec<f64>,
    /// Logarithmic x axis.
    pub x_log: bool,
    /// Logarithmic y axis.
    pub y_log: bool,
    /// Values, `z[j·nx + i]` at `(x[i], y[j])`; `None` (or non-finite) = failed point.
    pub z: Vec<Option<f64>>,
    /// Colour-bar title including units, e.g. `"critical speed (m/s)"`.
    pub z_label: String,
    /// A distinguished contour level and its label, e.g.
    /// `(55.56, "stable above / unstable below: V = 55.6 m/s")`.
    pub threshold: Option<(f64, String)>,
    /// Cells whose value is only known to exceed a bound (e.g. no onset of hunting up to the
    /// top of the speed range); `None` = there are none.
    pub above: Option<AboveRange>,
}

const W: f64 = 880.0;
const H: f64 = 600.0;
pub(crate) const PLOT: (f64, f64, f64, f64) = (95.0, W - 215.0, H - 70.0, 72.0); // x0, x1, y0 (bottom), y1
const BAR_X: f64 = W - 185.0;
pub(crate) const THRESHOLD: &str = "#d55e00";
const FAILED_DEFS: &str = "<pattern id=\"failed\" width=\"8\" height=\"8\" \
    patternUnits=\"userSpaceOnUse\" patternTransform=\"rotate(45)\">\
    <rect width=\"8\" height=\"8\" fill=\"#c8c8c8\"/>\
    <line x1=\"0\" y1=\"0\" x2=\"0\" y2=\"8\" stroke=\"#808080\" stroke-width=\"3\"/></pattern>";

fn invalid(h: &HeatMap, rule: String) -> PlotError {
    PlotError::Invalid {
        title: h.title.clone(),
        rule,
    }
}

fn check_axis(h: &HeatMap, name: &str, v: &[f64], log: bool) -> Result<(), PlotError> {
    if v.len() < 2 {
        return Err(invalid(
            h,
            format!("{name} has {} points; at least 2 needed", v.len()),
        ));
    }
    if let Some(i) = v.iter().position(|a| !a.is_finite() || (log && *a <= 0.0)) {
        let need = if log {
            "finite and positive (log axis)"
        } else {
            "finite"
        };
        return Err(invalid(h, format!("{name}[{i}] = {} must be {need}", v[i])));
    }
    if let Some(i) = v.windows(2).position(|w| w[1] <= w[0]) {
        let rule = format!(
            "{name} must increase strictly; {name}[{}] = {} follows {}",
            i + 1,
            v[i + 1],
            v[i]
        );
        return Err(invalid(h, rule));
    }
    Ok(())
}

/// Range of the finite values of `z`, or an error when there are none.
fn validate(h: &HeatMap) -> Result<(f64, f64), PlotError> {
    check_axis(h, "x", &h.x, h.x_log)?;
    check_axis(h, "y", &h.y, h.y_log)?;
    let n = h.x.len() * h.y.len();
    if h.z.len() != n {
        let rule = format!(
            "z has {} values; x × y needs {} × {} = {n}",
            h.z.len(),
            h.x.len(),
            h.y.len()
        );
        return Err(invalid(h, rule));
    }
    if let Some((t, _)) = h.threshold.as_ref().filter(|(t, _)| !t.is_finite()) {
        return Err(invalid(h, format!("threshold {t} is not finite")));
    }
    if let Some(a) = &h.above {
        if a.cells.len() != n || !a.bound.is_finite() {
            let rule = format!(
                "above-range cells: {} flags (x × y needs {n}) and bound {} (must be finite)",
                a.cells.len(),
                a.bound
            );
            return Err(invalid(h, rule));
        }
    }
    let finite = h.z.iter().flatten().filter(|v| v.is_finite());
    let range = finite.fold(None, |acc: Option<(f64, f64)>, &v| match acc {
        None => Some((v, v)),
        Some((a, b)) => Some((a.min(v), b.max(v))),
    });
    // a map of above-range cells only is still a result: scale up to the bound
    let bound = h.above.as_ref().filter(|a| a.cells.contains(&true));
    range
        .or_else(|| bound.map(|a| (a.bound, a.bound)))
        .ok_or_else(|| PlotError::Empty {
            title: h.title.clone(),
        })
}

/// Cell boundaries around each node: midpoints (geometric on a log axis), half a step
/// beyond the end nodes.
fn cell_edges(v: &[f64], log: bool) -> Vec<f64> {
    let mid = |a: f64, b: f64| if log { (a * b).sqrt() } else { 0.5 * (a + b) };
    let n = v.len();
    let mut e = Vec::with_capacity(n + 1);
    let first = if log {
        v[0] * (v[0] / v[1]).sqrt()
    } else {
        v[0] - 0.5 * (v[1] - v[0])
    };
    e.push(first);
    e.extend(v.windows(2).map(|w| mid(w[0], w[1])));
    let last = if log {
        v[n - 1] * (v[n - 1] / v[n - 2]).sqrt()
    } else {
        v[n - 1] + 0.5 * (v[n - 1] - v[n - 2])
    };
    e.push(last);
    e
}

/// Contour levels: multiples of the largest "nice" step (1, 2, 2.5 or 5 × 10ⁿ) that gives at
/// least five levels strictly inside the data range (so five to about nine of them).
pub(crate) fn contour_levels(lo: f64, hi: f64) -> Vec<f64> {
    let span = hi - lo;
    if !(span.is_finite() && span > 0.0) {
        return Vec::new();
    }
    let top = 10f64.powf(span.log10().floor());
    let inside = |step: f64| -> Vec<f64> {
        let (first, last) = (
            (lo / step).floor() as i64 + 1,
            (hi / step).ceil() as i64 - 1,
        );
        (first..=last)
            .map(|k| k as f64 * step)
            .filter(|l| *l > lo + 1e-9 * span && *l < hi - 1e-9 * span)
            .collect()
    };
    let steps = (0..4).flat_map(|e| [5.0, 2.5, 2.0, 1.0].map(|m| m * top / 10f64.powi(e)));
    steps
        .map(inside)
        .find(|l| l.len() >= 5)
        .unwrap_or_else(|| nice_ticks(lo, hi, 6))
}

/// Render the heat map as an SVG document (880×600 px).
///
/// Errors: [`PlotError::Invalid`] for fewer than 2 points on an axis, non-finite or (log)
/// non-positive or non-increasing axis values, a `z` of the wrong length or a non-finite
/// threshold; [`PlotError::Empty`] when no `z` is finite.
pub fn heat_map_svg(h: &HeatMap) -> Result<String, PlotError> {
    let (zlo, zhi) = validate(h)?;
    let (zlo, zhi) = if zhi > zlo {
        (zlo, zhi)
    } else {
        (zlo - 1.0, zhi + 1.0)
    };
    let (ex, ey) = (cell_edges(&h.x, h.x_log), cell_edges(&h.y, h.y_log));
    let ax = |v: &[f64], log, p0, p1| AxisMap {
        lo: v[0],
        hi: v[v.len() - 1],
        log,
        p0,
        p1,
    };
    let xm = ax(&ex, h.x_log, PLOT.0, PLOT.1);
    let ym = ax(&ey, h.y_log, PLOT.2, PLOT.3);
    let mut doc = Doc::new(W, H, FAILED_DEFS);
    let failed = draw_cells(&mut doc, h, (&xm, &ym), (&ex, &ey), (zlo, zhi));
    let levels = contour_levels(zlo, zhi);
    let mut contours: Vec<Contour> = levels
        .iter()
        .map(|&l| Contour::new(h, &h.z, (&xm, &ym), l, false))
        .collect();
    if let Some((t, _)) = &h.threshold {
        let z = threshold_z(h, *t);
        contours.push(Contour::new(h, &z, (&xm, &ym), *t, true));
    }
    // the threshold's label is placed first, the others where they do not collide
    let mut placed = Vec::new();
    let spots: Vec<Option<(f64, f64)>> = (0..contours.len())
        .rev()
        .map(|k| contours[k].place_label(&mut placed))
        .collect();
    for c in &contours {
        c.draw_lines(&mut doc);
    }
    for (c, spot) in contours.iter().zip(spots.into_iter().rev()) {
        if let Some((x, y)) = spot {
            doc.label(x, y, c.size(), c.colour(), &c.text);
        }
    }
    let frame = Frame {
        x: xm,
        y: ym,
        title: "",
        x_label: &h.x_label,
        y_label: &h.y_label,
    };
    frame.draw(&mut doc, false);
    let centre = (PLOT.0 + PLOT.1) / 2.0;
    doc.text(centre, 26.0, super::svg::TITLE_PX, "middle", 0.0, &h.title);
    if let Some((_, label)) = &h.threshold {
        // the full threshold label as a key line under the title
        doc.key_line(centre, label, THRESHOLD, 3.0, "9 5");
    }
    colour_bar(&mut doc, h, (zlo, zhi), &levels);
    legend(&mut doc, h, failed);
    Ok(doc.finish())
}

/// Cells around each node coloured by its value, above-range ones in [`ABOVE_FILL`], failed
/// ones hatched; returns how many failed.
fn draw_cells(
    doc: &mut Doc,
    h: &HeatMap,
    (xm, ym): (&AxisMap, &AxisMap),
    (ex, ey): (&[f64], &[f64]),
    (zlo, zhi): (f64, f64),
) -> usize {
    let nx = h.x.len();
    let mut failed = 0;
    for (k, z) in h.z.iter().enumerate() {
        let (i, j) = (k % nx, k / nx);
        let a = (xm.px(ex[i]), ym.px(ey[j]));
        let b = (xm.px(ex[i + 1]), ym.px(ey[j + 1]));
        let fill = match z.filter(|v| v.is_finite()) {
            Some(v) => hex(viridis((v - zlo) / (zhi - zlo))),
            None if is_above(h, k) => ABOVE_FILL.to_string(),
            None => {
                failed += 1;
                "url(#failed)".to_string()
            }
        };
        // a hair of overlap hides anti-aliasing seams between cells
        doc.rect((a.0 - 0.3, a.1 + 0.3), (b.0 + 0.3, b.1 - 0.3), &fill, None);
    }
    failed
}

fn colour_bar(doc: &mut Doc, h: &HeatMap, (lo, hi): (f64, f64), levels: &[f64]) {
    let (top, bottom) = (PLOT.3, PLOT.2 - 90.0);
    let bar = AxisMap {
        lo,
        hi,
        log: false,
        p0: bottom,
        p1: top,
    };
    let steps = 64;
    for s in 0..steps {
        let (a, b) = (s as f64 / steps as f64, (s + 1) as f64 / steps as f64);
        let ya = bottom + a * (top - bottom);
        let yb = bottom + b * (top - bottom);
        let c = hex(viridis((a + b) / 2.0));
        doc.rect((BAR_X, ya + 0.3), (BAR_X + 18.0, yb - 0.3), &c, None);
    }
    doc.rect(
        (BAR_X, bottom),
        (BAR_X + 18.0, top),
        "none",
        Some("#555555"),
    );
    for &v in levels {
        let y = bar.px(v);
        doc.polyline(&[(BAR_X, y), (BAR_X + 23.0, y)], "#1a1a1a", 1.0, None);
        doc.text(
            BAR_X + 27.0,
            y + 4.0,
            TICK_PX,
            "start",
            0.0,
            &format_value(v),
        );
    }
    for (v, anchor) in [(lo, bottom + 14.0), (hi, top - 5.0)] {
        doc.text(
            BAR_X + 9.0,
            anchor,
            TICK_PX - 1.0,
            "middle",
            0.0,
            &format_value(v),
        );
    }
    if let Some((t, _)) = h.threshold.as_ref().filter(|(t, _)| *t >= lo && *t <= hi) {
        let y = bar.px(*t);
        doc.polyline(&[(BAR_X - 4.0, y), (BAR_X + 22.0, y)], THRESHOLD, 3.0, None);
    }
    above_box(doc, h, top);
    let mid = (top + bottom) / 2.0;
    doc.text(BAR_X + 80.0, mid, LABEL_PX, "middle", 90.0, &h.z_label);
}

fn legend(doc: &mut Doc, h: &HeatMap, failed: usize) {
    let (x, mut y) = (BAR_X - 10.0, PLOT.2 - 62.0);
    if let Some((t, _)) = &h.threshold {
        doc.polyline(&[(x, y), (x + 26.0, y)], THRESHOLD, 3.0, Some("9 5"));
        let text = format!("threshold {}", format_value(*t));
        doc.text(x + 32.0, y + 4.0, TICK_PX, "start", 0.0, &text);
        if contour_lines(&h.x, &h.y, &threshold_z(h, *t), *t).is_empty() {
            y += 16.0;
            let note = "(not reached on this map)";
            doc.text(x + 32.0, y + 4.0, TICK_PX - 2.0, "start", 0.0, note);
        }
        y += 22.0;
    }
    if failed > 0 {
        doc.rect(
            (x, y - 7.0),
            (x + 26.0, y + 7.0),
            "url(#failed)",
            Some("#555555"),
        );
        let text = format!("no value ({failed})");
        doc.text(x + 32.0, y + 4.0, TICK_PX, "start", 0.0, &text);
        let note = "(status in sweep.csv)";
        doc.text(x + 32.0, y + 18.0, TICK_PX - 2.0, "start", 0.0, note);
        y += 36.0;
    }
    let above = (0..h.z.len()).filter(|&k| is_above(h, k)).count();
    if let Some(a) = h.above.as_ref().filter(|_| above > 0) {
        doc.rect(
            (x, y - 7.0),
            (x + 26.0, y + 7.0),
            ABOVE_FILL,
            Some("#555555"),
        );
        let (head, note) = split_label(&a.label);
        let text = format!("{head} ({above})");
        doc.text(x + 32.0, y + 4.0, TICK_PX, "start", 0.0, &text);
        if let Some(note) = note {
            doc.text(x + 32.0, y + 18.0, TICK_PX - 2.0, "start", 0.0, note);
        }
    }
}
