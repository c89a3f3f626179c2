//! The trade-study plot: a result (e.g. critical speed) against the objective axis, with
//! infeasible points greyed, the Pareto front joined, the best design marked and the
//! constraint drawn as a labelled line.

use super::scale::format_value;
use super::svg::{AxisMap, Doc, Frame, TICK_PX};
use super::PlotError;

/// One design point of a trade plot.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TradePoint {
    /// Objective-axis value (in the plot's x units).
    pub x: f64,
    /// Result value (y units); `None` when not computed or failed.
    pub y: Option<f64>,
    /// `y` is only a lower bound (no onset up to the top of the speed range): drawn as an
    /// up-triangle.
    pub above: bool,
    /// Meets every constraint.
    pub feasible: bool,
    /// On the Pareto front.
    pub pareto: bool,
    /// The best design.
    pub best: bool,
}

/// Data of a trade plot.
#[derive(Debug, Clone, PartialEq)]
pub struct TradePlot {
    /// Title drawn above the plot.
    pub title: String,
    /// X-axis title including units.
    pub x_label: String,
    /// Y-axis title including units.
    pub y_label: String,
    /// Logarithmic x axis (all x must then be positive).
    pub x_log: bool,
    /// The design points.
    pub points: Vec<TradePoint>,
    /// Horizontal constraint line `(y, label)`, e.g. `(61.1, "V_nl ≥ 1.1 × 55.6 m/s")`.
    pub constraint: Option<(f64, String)>,
}

const W: f64 = 900.0;
const H: f64 = 580.0;
const BLUE: &str = "#0072b2";
const ORANGE: &str = "#d55e00";
const GREY: &str = "#a0a0a0";

fn range(v: impl Iterator<Item = f64>) -> Option<(f64, f64)> {
    v.fold(None, |acc, a| match acc {
        None => Some((a, a)),
        Some((lo, hi)) => Some((lo.min(a), hi.max(a))),
    })
}

fn padded((lo, hi): (f64, f64), log: bool) -> (f64, f64) {
    if log {
        let k = if hi > lo { (hi / lo).powf(0.04) } else { 1.2 };
        (lo / k, hi * k)
    } else {
        let d = if hi > lo {
            0.05 * (hi - lo)
        } else {
            0.1 * lo.abs().max(1.0)
        };
        (lo - d, hi + d)
    }
}

fn validate(p: &TradePlot) -> Result<(), PlotError> {
    let bad = |rule: String| PlotError::Invalid {
        title: p.title.clone(),
        rule,
    };
    if p.points.is_empty() {
        return Err(PlotError::Empty {
            title: p.title.clone(),
        });
    }
    for (i, t) in p.points.iter().enumerate() {
        if !t.x.is_finite() || (p.x_log && t.x <= 0.0) {
            return Err(bad(format!(
                "point {i}: x = {} must be finite (and > 0 on a log axis)",
                t.x
            )));
        }
    }
    Ok(())
}

/// Render the trade plot as an SVG document (900×580 px).
///
/// Errors: [`PlotError::Empty`] without points; [`PlotError::Invalid`] for a non-finite x
/// or a non-positive x on a log axis.
pub fn trade_svg(p: &TradePlot) -> Result<String, PlotError> {
    validate(p)?;
    let ys = p
        .points
        .iter()
        .filter_map(|t| t.y)
        .filter(|y| y.is_finite());
    let ys = ys.chain(p.constraint.iter().map(|c| c.0).filter(|y| y.is_finite()));
    let (ylo, yhi) = padded(range(ys).unwrap_or((0.0, 1.0)), false);
    let xr = range(p.points.iter().map(|t| t.x)).unwrap_or((1.0, 2.0));
    let (xlo, xhi) = padded(xr, p.x_log);
    let (x0, x1, yb, yt) = (95.0, W - 215.0, H - 70.0, 72.0);
    let xm = AxisMap {
        lo: xlo,
        hi: xhi,
        log: p.x_log,
        p0: x0,
        p1: x1,
    };
    let ym = AxisMap {
        lo: ylo,
        hi: yhi,
        log: false,
        p0: yb,
        p1: yt,
    };
    let mut doc = Doc::new(W, H, "");
    let frame = Frame {
        x: xm,
        y: ym,
        title: "",
        x_label: &p.x_label,
        y_label: &p.y_label,
    };
    frame.draw(&mut doc, true);
    doc.text(
        (x0 + x1) / 2.0,
        26.0,
        super::svg::TITLE_PX,
        "middle",
        0.0,
        &p.title,
    );
    let pt = |t: &TradePoint| {
        t.y.filter(|y| y.is_finite())
            .map(|y| (xm.px(t.x), ym.px(y)))
    };
    if let Some((c, label)) = p.constraint.as_ref().filter(|c| c.0.is_finite()) {
        let y = ym.px(*c);
        doc.polyline(&[(x0, y), (x1, y)], "#444444", 1.5, Some("7 4"));
        // the full text as a key line under the title, the value beside the line
        doc.key_line((x0 + x1) / 2.0, label, "#444444", 1.5, "7 4");
        let short = format!("{} {}", format_value(*c), unit_of(&p.y_label));
        let drawn: Vec<(f64, f64)> = p.points.iter().filter_map(pt).collect();
        let (cx, cy) = label_spot(&drawn, &short, (x0, x1), y);
        doc.label(cx, cy, TICK_PX, "#222222", &short);
    }
    let mut front: Vec<&TradePoint> = p
        .points
        .iter()
        .filter(|t| t.pareto && pt(t).is_some())
        .collect();
    front.sort_by(|a, b| a.x.total_cmp(&b.x));
    let line: Vec<(f64, f64)> = front.iter().filter_map(|t| pt(t)).collect();
    if line.len() >= 2 {
        doc.polyline(&line, ORANGE, 2.0, None);
    }
    for t in &p.points {
        match pt(t) {
            Some((x, y)) if t.above => {
                let fill = if t.feasible { BLUE } else { GREY };
                doc.raw(&triangle(x, y, fill));
            }
            Some((x, y)) => {
                let fill = if t.feasible { BLUE } else { GREY };
                doc.raw(&format!(
                    "<circle cx=\"{x:.2}\" cy=\"{y:.2}\" r=\"4\" fill=\"{fill}\"/>"
                ));
            }
            None => {
                let (x, y) = (xm.px(t.x), yb - 8.0);
                let d = 4.0;
                doc.polyline(&[(x - d, y - d), (x + d, y + d)], GREY, 1.5, None);
                doc.polyline(&[(x - d, y + d), (x + d, y - d)], GREY, 1.5, None);
            }
        }
    }
    for (x, y) in p.points.iter().filter(|t| t.best).filter_map(pt) {
        doc.raw(&format!(
            "<circle cx=\"{x:.2}\" cy=\"{y:.2}\" r=\"9\" fill=\"none\" stroke=\"#000000\" stroke-width=\"2.2\"/>"
        ));
    }
    legend(&mut doc, p, x1 + 20.0, yt + 10.0);
    Ok(doc.finish())
}

fn legend(doc: &mut Doc, p: &TradePlot, x: f64, y: f64) {
    let circle = |doc: &mut Doc, y: f64, r: f64, style: &str| {
        doc.raw(&format!(
            "<circle cx=\"{:.1}\" cy=\"{y:.1}\" r=\"{r}\" {style}/>",
            x + 12.0
        ));
    };
    let mut y = y;
    let mut entry = |doc: &mut Doc, text: &str| {
        doc.text(x + 32.0, y + 4.0, TICK_PX, "start", 0.0, text);
        y += 22.0;
        y - 22.0
    };
    let count = |f: &dyn Fn(&TradePoint) -> bool| p.points.iter().filter(|t| f(t)).count();
    let yy = entry(doc, &format!("feasible ({})", count(&|t| t.feasible)));
    circle(doc, yy, 4.0, &format!("fill=\"{BLUE}\""));
    let yy = entry(
        doc,
        &format!("infeasible ({})", count(&|t| !t.feasible && t.y.is_some())),
    );
    circle(doc, yy, 4.0, &format!("fill=\"{GREY}\""));
    let above = count(&|t| t.above && t.y.is_some());
    if above > 0 {
        let yy = entry(doc, &format!("above range ({above})"));
        doc.raw(&triangle(x + 12.0, yy, GREY));
    }
    let missing = count(&|t| t.y.is_none());
    if missing > 0 {
        let yy = entry(doc, &format!("no result ({missing})"));
        doc.text(x + 12.0, yy + 4.0, TICK_PX, "middle", 0.0, "×");
    }
    let yy = entry(doc, &format!("Pareto front ({})", count(&|t| t.pareto)));
    doc.polyline(&[(x, yy), (x + 24.0, yy)], ORANGE, 2.0, None);
    if let Some(b) = p.points.iter().find(|t| t.best) {
        let yy = entry(doc, "best design");
        circle(
            doc,
            yy,
            7.0,
            "fill=\"none\" stroke=\"#000000\" stroke-width=\"2.2\"",
        );
        let v = b.y.map_or("-".to_string(), format_value);
        let v = if b.above { format!("> {v}") } else { v };
        let (ux, uy) = (unit_of(&p.x_label), unit_of(&p.y_label));
        entry(doc, &format!("  {} {ux}, {v} {uy}", format_value(b.x)));
    }
    if p.constraint.is_some() {
        let yy = entry(doc, "constraint");
        doc.polyline(&[(x, yy), (x + 24.0, yy)], "#444444", 1.5, Some("7 4"));
    }
}

/// An up-pointing triangle centred at `(x, y)`: the value lies above.
fn triangle(x: f64, y: f64, fill: &str) -> String {
    format!(
        "<polygon points=\"{:.2},{:.2} {:.2},{:.2} {:.2},{:.2}\" fill=\"{fill}\"/>",
        x,
        y - 6.0,
        x - 5.5,
        y + 4.0,
        x + 5.5,
        y + 4.0
    )
}

/// The unit in the last parentheses of an axis title, e.g. `"N/mm"` from `"k (N/mm)"`.
fn unit_of(label: &str) -> &str {
    match (label.rfind('('), label.rfind(')')) {
        (Some(a), Some(b)) if b > a => &label[a + 1..b],
        _ => "",
    }
}

/// Centre of the constraint label: right or left end, above or below the line at pixel `y`,
/// whichever box holds the fewest drawn points (ties: right, above).
fn label_spot(drawn: &[(f64, f64)], label: &str, (x0, x1): (f64, f64), y: f64) -> (f64, f64) {
    let half_w = super::scale::text_width(label, TICK_PX) / 2.0 + 3.0;
    let spots = [
        (x1 - 8.0 - half_w, y - 11.0),
        (x1 - 8.0 - half_w, y + 13.0),
        (x0 + 8.0 + half_w, y - 11.0),
        (x0 + 8.0 + half_w, y + 13.0),
    ];
    let hits = |(cx, cy): (f64, f64)| {
        let inside =
            |(px, py): &(f64, f64)| (px - cx).abs() < half_w + 10.0 && (py - cy).abs() < 20.0;
        drawn.iter().filter(|p| inside(p)).count()
    };
    spots
        .into_iter()
        .min_by_key(|s| hits(*s))
        .unwrap_or(spots[0])
}
