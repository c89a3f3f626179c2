//! Reference lines with labels, the legend (placed away from the data) and
//! colour bars.

use super::geom::{segment_meets, Rect};
use super::palette::{viridis, AXIS, MARKER, TEXT, WHITE};
use super::panel::{font, Area, Chart, Metrics};
use super::prepare::{Bar, Item, Mark, Prepared};
use super::scale::{format_value, text_width};
use super::{backend_err, PlotError};
use plotters::element::DashedPathElement;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

/// A marker label box in plot-area pixels (origin top-left, y down).
pub(crate) struct LabelBox {
    rect: Rect,
    text: String,
}

/// Draw the dashed grey reference lines (under the data).
pub(crate) fn draw_marker_lines(
    chart: &mut Chart,
    p: &Prepared,
    m: &Metrics,
) -> Result<(), PlotError> {
    let style = MARKER.stroke_width(m.px(1.2).round().max(1.0) as u32);
    let (dash, gap) = (m.px(5.0) as u32, m.px(4.0) as u32);
    let (x, y) = (p.x, p.y);
    let v = p
        .vlines
        .iter()
        .map(|(at, _)| vec![(*at, y.lo), (*at, y.hi)]);
    let h = p
        .hlines
        .iter()
        .map(|(at, _)| vec![(x.lo, *at), (x.hi, *at)]);
    chart
        .draw_series(
            v.chain(h)
                .map(|pts| DashedPathElement::new(pts, dash, gap, style)),
        )
        .map_err(backend_err)?;
    Ok(())
}

/// Place marker labels inside the plot area: vertical-line labels along the
/// top, beside their line (the side not crossing another marker line; one too
/// wide for either side across its own line, against an edge of the area),
/// stacked in rows when they would overlap; horizontal-line labels at the
/// right end just above (or below) their line, slid left past other labels.
pub(crate) fn layout_labels(chart: &Chart, p: &Prepared, m: &Metrics) -> Vec<LabelBox> {
    let (pw, ph) = chart.plotting_area().dim_in_pixel();
    let (pw, ph) = (f64::from(pw), f64::from(ph));
    let (gap, bh) = (m.px(4.0), 1.5 * m.small);
    let bw = |t: &str| text_width(t, m.small) + 2.0 * gap;
    let taken = |out: &[LabelBox], r: &Rect| {
        let wide = Rect {
            x0: r.x0 - gap,
            x1: r.x1 + gap,
            ..*r
        };
        out.iter().any(|b| b.rect.overlaps(&wide))
    };
    let lines: Vec<f64> = p.vlines.iter().map(|(at, _)| p.x.frac(*at) * pw).collect();
    let mut out: Vec<LabelBox> = Vec::new();
    let mut vl: Vec<_> = p.vlines.iter().filter(|(_, t)| !t.is_empty()).collect();
    vl.sort_by(|a, b| a.0.total_cmp(&b.0));
    for (at, text) in vl {
        let (px, w) = (p.x.frac(*at) * pw, bw(text));
        let fits = |x0: &f64| *x0 >= gap && x0 + w <= pw - gap;
        let clear = |x0: &f64| {
            !lines
                .iter()
                .any(|&l| (l - px).abs() > 0.5 && l > x0 - gap && l < x0 + w + gap)
        };
        // beside the line, right then left; a label too wide for either side spans its own
        // line, against the right or the left edge, rather than crossing another line
        let beside = [px + gap, px - gap - w];
        let sides = if beside.iter().any(fits) {
            beside
        } else {
            [pw - gap - w, gap]
        };
        let x0 = sides.iter().copied().filter(fits).find(clear);
        let x0 = x0.or(sides.iter().copied().find(fits)).unwrap_or(gap);
        let mut rect = Rect {
            x0,
            x1: x0 + w,
            y0: gap,
            y1: gap + bh,
        };
        while taken(&out, &rect) && rect.y1 + bh < ph {
            (rect.y0, rect.y1) = (rect.y0 + bh + gap, rect.y1 + bh + gap);
        }
        out.push(LabelBox {
            rect,
            text: text.clone(),
        });
    }
    for (at, text) in p.hlines.iter().filter(|(_, t)| !t.is_empty()) {
        let (py, w) = ((1.0 - p.y.frac(*at)) * ph, bw(text));
        let y0 = if py - gap - bh >= gap {
            py - gap - bh
        } else {
            py + gap
        };
        let mut rect = Rect {
            x0: pw - gap - w,
            x1: pw - gap,
            y0,
            y1: y0 + bh,
        };
        while rect.x0 > gap && taken(&out, &rect) {
            (rect.x0, rect.x1) = (rect.x0 - 3.0 * gap, rect.x1 - 3.0 * gap);
        }
        out.push(LabelBox {
            rect,
            text: text.clone(),
        });
    }
    out
}

/// Draw the marker labels on a translucent white box.
pub(crate) fn draw_labels(
    chart: &Chart,
    labels: &[LabelBox],
    m: &Metrics,
) -> Result<(), PlotError> {
    let area = chart.plotting_area().strip_coord_spec();
    let style = font(m.small)
        .color(&TEXT)
        .pos(Pos::new(HPos::Left, VPos::Center));
    for b in labels {
        let r = b.rect;
        let corners = [(r.x0 as i32, r.y0 as i32), (r.x1 as i32, r.y1 as i32)];
        area.draw(&Rectangle::new(corners, WHITE.mix(0.85).filled()))
            .map_err(backend_err)?;
        let at = ((r.x0 + m.px(4.0)) as i32, ((r.y0 + r.y1) / 2.0) as i32);
        area.draw(&Text::new(b.text.as_str(), at, style.clone()))
            .map_err(backend_err)?;
    }
    Ok(())
}

/// Everything drawn in the plot area, in plot-area pixels, as segments (a point is a
/// segment of zero length; the dot's radius is added by the caller's margin).
fn obstacles(p: &Prepared, pw: f64, ph: f64) -> Vec<((f64, f64), (f64, f64))> {
    let to_px = |(x, y): (f64, f64)| (p.x.frac(x) * pw, (1.0 - p.y.frac(y)) * ph);
    let mut out = Vec::new();
    let mut run = |r: &[(f64, f64)]| {
        out.extend(r.windows(2).map(|w| (to_px(w[0]), to_px(w[1]))));
    };
    for it in &p.items {
        for r in &it.runs {
            run(r);
        }
        if it.mark == Mark::Shade {
            // a region's closing edge is drawn too (its fill is no mark)
            if let (Some(a), Some(b)) = (
                it.runs.first().and_then(|r| r.last()),
                it.runs.first().and_then(|r| r.first()),
            ) {
                run(&[*a, *b]);
            }
        }
        for (pt, _) in &it.points {
            run(&[*pt, *pt]);
        }
    }
    for (at, _) in &p.vlines {
        run(&[(*at, p.y.lo), (*at, p.y.hi)]);
    }
    for (at, _) in &p.hlines {
        run(&[(p.x.lo, *at), (p.x.hi, *at)]);
    }
    out
}

/// The legend's shape: entries top to bottom in `rows` rows, column after column, each
/// column as wide as its widest entry (`col_x`: each column's left edge from the box's), and
/// the whole box (device units).
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct LegendShape {
    pub rows: usize,
    pub col_x: Vec<f64>,
    pub w: f64,
    pub h: f64,
}

/// The legend's shape (if any series is named): one column, or the most columns that fit
/// in `max_w` when given.
pub(crate) fn legend_shape(p: &Prepared, m: &Metrics, max_w: Option<f64>) -> Option<LegendShape> {
    let widths: Vec<f64> = p
        .items
        .iter()
        .filter(|i| !i.name.is_empty())
        .map(|i| text_width(&i.name, m.small) + LEGEND_SWATCH * m.u)
        .collect();
    if widths.is_empty() {
        return None;
    }
    let (pad, gap) = (LEGEND_PAD * m.u, LEGEND_GAP * m.u);
    let n = widths.len();
    let shape = |cols: usize| {
        let rows = n.div_ceil(cols);
        let mut col_x = Vec::new();
        let mut x = pad;
        for col in widths.chunks(rows) {
            col_x.push(x);
            x += col.iter().copied().fold(0.0, f64::max) + gap;
        }
        let w = x - gap + pad;
        let h = (rows - 1) as f64 * legend_pitch(m) + m.small + 2.0 * pad;
        LegendShape { rows, col_x, w, h }
    };
    let one = shape(1);
    Some(match max_w {
        None => one,
        Some(max_w) => (2..=n)
            .map(shape)
            .take_while(|s| s.w <= max_w)
            .last()
            .unwrap_or(one),
    })
}

/// The legend's padding, the width of its swatch column and the gap between columns
/// (before scaling).
const LEGEND_PAD: f64 = 8.0;
const LEGEND_SWATCH: f64 = 32.0;
const LEGEND_GAP: f64 = 16.0;

/// From one legend line to the next (device units).
fn legend_pitch(m: &Metrics) -> f64 {
    1.55 * m.small
}

/// The free place inside the plot area (top-left corner, plot-area pixels) for a legend of
/// size `(lw, lh)`: a corner first, then the middle of an edge or just below the reference
/// lines' labels, where it covers no data mark, reference line or label. `None` when every
/// candidate covers something.
pub(crate) fn legend_inside(
    chart: &Chart,
    p: &Prepared,
    labels: &[LabelBox],
    (lw, lh): (f64, f64),
    m: &Metrics,
) -> Option<(f64, f64)> {
    let (pw, ph) = chart.plotting_area().dim_in_pixel();
    let (pw, ph) = (f64::from(pw), f64::from(ph));
    let inset = m.px(8.0);
    let segments = obstacles(p, pw, ph);
    let (right, bottom) = (pw - lw - inset, ph - lh - inset);
    let (mid_x, mid_y) = ((pw - lw) / 2.0, (ph - lh) / 2.0);
    // just below the reference lines' labels, which sit at the top of the plot
    let below = labels
        .iter()
        .map(|b| b.rect.y1)
        .filter(|y| *y < 0.5 * ph)
        .fold(inset, f64::max)
        + inset;
    let candidates = [
        (right, inset),
        (inset, inset),
        (right, bottom),
        (inset, bottom),
        (mid_x, inset),
        (mid_x, bottom),
        (right, below),
        (inset, below),
        (right, mid_y),
        (inset, mid_y),
    ];
    // the widest mark (a dot or a line) plus a little air
    let e = f64::from(m.dot.max(m.line)) + m.px(3.0);
    let free = |&(x0, y0): &(f64, f64)| {
        let r = Rect {
            x0: x0 - e,
            x1: x0 + lw + e,
            y0: y0 - e,
            y1: y0 + lh + e,
        };
        x0 >= 0.0
            && y0 >= 0.0
            && y0 + lh <= ph
            && !labels.iter().any(|b| b.rect.overlaps(&r))
            && !segments.iter().any(|(a, b)| segment_meets(&r, *a, *b))
    };
    candidates.into_iter().find(free)
}

/// Horizontal space (device units) a legend of width `lw` takes right of the plot.
pub(crate) fn legend_outside_width(lw: f64, m: &Metrics) -> f64 {
    lw + m.px(12.0)
}

/// Draw the legend of shape `shape` with its top-left corner at `at` (plot-area pixels;
/// right of the plot area when `at.0` is beyond its width, below it when `at.1` is beyond
/// its height).
///
/// Drawn here on the whole panel, not with plotters' series labels: those are clipped to
/// the plot area, and a legend beside or below the plot lies outside it.
pub(crate) fn draw_legend(
    area: &Area,
    chart: &Chart,
    p: &Prepared,
    shape: &LegendShape,
    at: (f64, f64),
    m: &Metrics,
) -> Result<(), PlotError> {
    let (lw, lh) = (shape.w, shape.h);
    let (xr, yr) = chart.plotting_area().get_pixel_range();
    let (bx, by) = area.get_base_pixel();
    let x0 = f64::from(xr.start - bx) + at.0;
    let y0 = f64::from(yr.start - by) + at.1;
    let corners = [(x0 as i32, y0 as i32), ((x0 + lw) as i32, (y0 + lh) as i32)];
    area.draw(&Rectangle::new(corners, WHITE.mix(0.9).filled()))
        .map_err(backend_err)?;
    area.draw(&Rectangle::new(corners, AXIS.mix(0.5).stroke_width(m.thin)))
        .map_err(backend_err)?;
    let pad = LEGEND_PAD * m.u;
    let style = font(m.small)
        .color(&TEXT)
        .pos(Pos::new(HPos::Left, VPos::Center));
    let named = p.items.iter().filter(|i| !i.name.is_empty());
    for (k, it) in named.enumerate() {
        let (row, col) = (k % shape.rows, k / shape.rows);
        let x = x0 + shape.col_x.get(col).copied().unwrap_or(pad);
        let y = (y0 + pad + 0.5 * m.small + row as f64 * legend_pitch(m)) as i32;
        draw_swatch(area, it, (x as i32, y), m)?;
        let tx = (x + LEGEND_SWATCH * m.u) as i32;
        area.draw(&Text::new(it.name.as_str(), (tx, y), style.clone()))
            .map_err(backend_err)?;
    }
    Ok(())
}

/// An item's mark in the legend, its left end at `(x, y)` (panel pixels).
fn draw_swatch(area: &Area, it: &Item, (x, y): (i32, i32), m: &Metrics) -> Result<(), PlotError> {
    let (dash, gap) = m.dash;
    let dot = m.dot;
    let (len, step) = (m.px(24.0) as i32, m.px(9.0) as i32);
    let style = it.colour.stroke_width(m.line);
    let fill = it.colour.filled();
    let mid = (x + len / 2, y);
    match it.mark {
        Mark::Line { dashed: false } => {
            area.draw(&PathElement::new(vec![(x, y), (x + len, y)], style))
        }
        Mark::Line { dashed: true } => area.draw(&DashedPathElement::new(
            vec![(x, y), (x + len, y)],
            dash,
            gap,
            style,
        )),
        Mark::Points => area.draw(&Circle::new(mid, dot, fill)),
        Mark::Above => area.draw(&TriangleMarker::new(mid, 2 * dot, fill)),
        Mark::Crosses => area.draw(&Cross::new(mid, 2 * dot, style)),
        Mark::Shade => area.draw(&Rectangle::new(
            [(x, y - dot as i32), (x + len, y + dot as i32)],
            it.colour.mix(0.16).filled(),
        )),
        Mark::Coloured => {
            let c = |t: f64| {
                let dx = ((t - 0.5) * 2.0 * f64::from(step)) as i32;
                Circle::new((mid.0 + dx, y), dot, viridis(t).filled())
            };
            area.draw(&c(0.1))
                .and_then(|()| area.draw(&c(0.5)))
                .and_then(|()| area.draw(&c(0.9)))
        }
    }
    .map_err(backend_err)
}

fn value_width(b: &Bar, m: &Metrics) -> f64 {
    [b.lo, b.hi]
        .iter()
        .map(|v| text_width(&format_value(*v), m.small))
        .fold(0.0, f64::max)
}

/// Horizontal space (device units) a colour bar needs right of the plot.
pub(crate) fn bar_width(b: &Bar, m: &Metrics) -> f64 {
    m.px(16.0 + 14.0 + 5.0 + 8.0 + 4.0) + value_width(b, m) + 1.2 * m.label
}

/// Draw colour bars right of the plot area, spanning its height.
pub(crate) fn draw_bars(
    area: &Area,
    chart: &Chart,
    bars: &[&Bar],
    m: &Metrics,
) -> Result<(), PlotError> {
    let (xr, yr) = chart.plotting_area().get_pixel_range();
    let (bx, by) = area.get_base_pixel();
    let (top, bottom) = (yr.start - by, yr.end - by);
    let mut left = f64::from(xr.end - bx);
    let steps = 64;
    let value_style = font(m.small).color(&TEXT);
    let label_style = font(m.label)
        .color(&TEXT)
        .transform(FontTransform::Rotate270);
    let label_style = label_style.pos(Pos::new(HPos::Center, VPos::Top));
    for b in bars {
        let x0 = (left + m.px(16.0)) as i32;
        let x1 = x0 + m.px(14.0) as i32;
        for i in 0..steps {
            let y = |k: i32| bottom - (bottom - top) * k / steps;
            let colour = viridis((f64::from(i) + 0.5) / f64::from(steps));
            // Overlap neighbouring cells slightly so anti-aliasing leaves no seams.
            let cell = Rectangle::new([(x0, (y(i + 1) - 3).max(top)), (x1, y(i))], colour.filled());
            area.draw(&cell).map_err(backend_err)?;
        }
        let frame = Rectangle::new([(x0, top), (x1, bottom)], AXIS.stroke_width(m.thin));
        area.draw(&frame).map_err(backend_err)?;
        let tx = x1 + m.px(5.0) as i32;
        let hi = value_style.pos(Pos::new(HPos::Left, VPos::Top));
        let lo = value_style.pos(Pos::new(HPos::Left, VPos::Bottom));
        area.draw(&Text::new(format_value(b.hi), (tx, top), hi))
            .map_err(backend_err)?;
        area.draw(&Text::new(format_value(b.lo), (tx, bottom), lo))
            .map_err(backend_err)?;
        let lx = tx + (value_width(b, m) + m.px(8.0)) as i32;
        let label = Text::new(
            b.label.as_str(),
            (lx, (top + bottom) / 2),
            label_style.clone(),
        );
        area.draw(&label).map_err(backend_err)?;
        left += bar_width(b, m);
    }
    Ok(())
}
