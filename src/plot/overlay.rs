//! Reference lines with labels, the legend (placed away from the data) and
//! colour bars.

use super::geom::{sample_run, Rect};
use super::palette::{viridis, AXIS, MARKER, TEXT, WHITE};
use super::panel::{font, Area, Chart, Metrics};
use super::prepare::{Bar, Prepared};
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
/// top, beside their line (the side not crossing another marker line),
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
        let sides = [px + gap, px - gap - w];
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

/// Pixel positions of everything drawn in the plot area (for legend placement).
fn obstacles(p: &Prepared, pw: f64, ph: f64, step: f64) -> Vec<(f64, f64)> {
    let to_px = |(x, y): (f64, f64)| (p.x.frac(x) * pw, (1.0 - p.y.frac(y)) * ph);
    let mut out = Vec::new();
    for it in &p.items {
        for run in &it.runs {
            sample_run(run, to_px, step, &mut out);
        }
        out.extend(it.points.iter().map(|(pt, _)| to_px(*pt)));
    }
    for (at, _) in &p.vlines {
        sample_run(&[(*at, p.y.lo), (*at, p.y.hi)], to_px, step, &mut out);
    }
    for (at, _) in &p.hlines {
        sample_run(&[(p.x.lo, *at), (p.x.hi, *at)], to_px, step, &mut out);
    }
    out
}

/// Draw the legend (if any series is named) at the candidate position that
/// covers the fewest data samples and no marker label.
pub(crate) fn draw_legend<'a, 'b: 'a>(
    chart: &mut Chart<'a, 'b>,
    p: &Prepared,
    labels: &[LabelBox],
    m: &Metrics,
) -> Result<(), PlotError> {
    let names: Vec<&str> = p
        .items
        .iter()
        .map(|i| i.name.as_str())
        .filter(|n| !n.is_empty())
        .collect();
    if names.is_empty() {
        return Ok(());
    }
    let (pw, ph) = chart.plotting_area().dim_in_pixel();
    let (pw, ph) = (f64::from(pw), f64::from(ph));
    let (pad, swatch, inset) = (m.px(8.0), m.px(32.0), m.px(8.0));
    // Same estimate as plotters' font-less layout, so the avoided box is the drawn box.
    let text_w = names
        .iter()
        .map(|n| n.len() as f64 * 0.7 * m.small / 1.24)
        .fold(0.0, f64::max);
    let lw = text_w + swatch + 2.0 * pad;
    let lh = (names.len() - 1) as f64 * 1.25 * 1.24 * m.small + m.small + 2.0 * pad;
    let samples = obstacles(p, pw, ph, m.px(4.0));
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
    let score = |&(x0, y0): &(f64, f64)| {
        let e = m.px(3.0);
        let r = Rect {
            x0: x0 - e,
            x1: x0 + lw + e,
            y0: y0 - e,
            y1: y0 + lh + e,
        };
        let hits = samples.iter().filter(|s| r.contains(**s)).count();
        hits + 10_000 * labels.iter().filter(|b| b.rect.overlaps(&r)).count()
    };
    let (x0, y0) = candidates
        .iter()
        .min_by_key(|c| score(c))
        .copied()
        .unwrap_or((inset, inset));
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::Coordinate(x0 as i32, y0 as i32))
        .margin(pad as u32)
        .legend_area_size(swatch as u32)
        .border_style(AXIS.mix(0.5))
        .background_style(WHITE.mix(0.9))
        .label_font(font(m.small).color(&TEXT))
        .draw()
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
