//! Layout and drawing of one figure panel: frame, axes, grid, series.

use super::overlay;
use super::palette::{AXIS, GRID, TEXT};
use super::prepare::{Mark, Prepared};
use super::scale::{format_tick, format_value, text_width, tick_decimals, Axis};
use super::{backend_err, PlotError, SUPERSAMPLE};
use plotters::coord::types::RangedCoordf64;
use plotters::coord::Shift;
use plotters::element::DashedPathElement;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

/// A panel's drawing area.
pub(crate) type Area<'a> = DrawingArea<SVGBackend<'a>, Shift>;
/// A panel's chart (plotted units on both axes).
pub(crate) type Chart<'a, 'b> =
    ChartContext<'a, SVGBackend<'b>, Cartesian2d<RangedCoordf64, RangedCoordf64>>;

/// Sizes in device units for one panel. Everything is scaled by `u` device
/// units per logical pixel (supersampling × panel-size scale).
pub(crate) struct Metrics {
    pub u: f64,
    pub title: f64,
    pub label: f64,
    pub tick: f64,
    pub small: f64,
    pub margin: f64,
    pub line: u32,
    pub thin: u32,
    pub dot: u32,
    pub dash: (u32, u32),
}

impl Metrics {
    fn new(w: u32, h: u32) -> Self {
        let k = f64::from(SUPERSAMPLE);
        let s = (f64::from(w) / k / 760.0)
            .min(f64::from(h) / k / 480.0)
            .clamp(0.9, 2.0);
        let u = k * s;
        let units = |v: f64| (v * u).round().max(1.0) as u32;
        Metrics {
            u,
            title: 16.0 * u,
            label: 13.5 * u,
            tick: 12.0 * u,
            small: 11.5 * u,
            margin: 12.0 * u,
            line: units(1.8),
            thin: units(1.0),
            dot: units(3.2),
            dash: (units(7.0), units(4.5)),
        }
    }

    /// Device units for `v` logical pixels.
    pub fn px(&self, v: f64) -> f64 {
        v * self.u
    }
}

/// Sans-serif font whose SVG `font-size` is `px` (plotters writes size / 1.24).
pub(crate) fn font(px: f64) -> FontDesc<'static> {
    FontDesc::new(FontFamily::SansSerif, px * 1.24, FontStyle::Normal)
}

fn widest(ticks: &[f64], decimals: usize, px: f64) -> f64 {
    ticks
        .iter()
        .map(|v| text_width(&format_tick(*v, decimals), px))
        .fold(0.0, f64::max)
}

/// Largest x tick count (and its decimals) whose labels do not collide.
fn x_ticks(axis: &Axis, len: f64, m: &Metrics) -> (usize, usize) {
    for n in (3..=9).rev() {
        let t = axis.ticks(n);
        let d = tick_decimals(&t);
        let spacing = match t.as_slice() {
            [a, b, ..] => (b - a).abs() / (axis.hi - axis.lo) * len,
            _ => len,
        };
        if widest(&t, d, m.tick) + 2.0 * m.tick <= spacing && spacing >= 5.0 * m.tick {
            return (n, d);
        }
    }
    (2, tick_decimals(&axis.ticks(2)))
}

/// Draw figure `p` into `area` (device units).
pub(crate) fn draw(area: &Area, p: &Prepared) -> Result<(), PlotError> {
    let (w, h) = area.dim_in_pixel();
    let m = Metrics::new(w, h);
    let (w, h) = (f64::from(w), f64::from(h));
    // Colour bars get at most 40 % of the panel width; extra ones are dropped.
    let (mut bars, mut bar_space) = (Vec::new(), 0.0);
    for b in p.bars.iter().filter(|b| b.is_valid()) {
        let bw = overlay::bar_width(b, &m);
        if bar_space + bw > 0.4 * w {
            break;
        }
        bars.push(b);
        bar_space += bw;
    }
    let title_px = if p.title.is_empty() {
        0.0
    } else {
        let fit = (w - 2.0 * m.margin) / text_width(&p.title, m.title).max(1.0);
        m.title * fit.clamp(0.7, 1.0)
    };
    let title_h = if p.title.is_empty() {
        0.0
    } else {
        1.7 * title_px
    };
    let x_area = m.px(10.0) + 1.2 * m.tick + m.px(6.0) + 1.2 * m.label;
    let plot_h = h - 2.0 * m.margin - title_h - x_area;
    let ny = ((plot_h / (4.0 * m.tick)) as usize).clamp(3, 8);
    let yd = tick_decimals(&p.y.ticks(ny));
    let y_area = m.px(18.0) + widest(&p.y.ticks(ny), yd, m.tick) + 1.2 * m.label;
    // `right` and `below`: room for colour bars and a legend beside or below the plot
    let build = |right: f64, below: f64| {
        ChartBuilder::on(area)
            .margin(m.margin as u32)
            .margin_top((m.margin + title_h) as u32)
            .margin_right((m.margin + right) as u32)
            .margin_bottom((m.margin + below) as u32)
            .x_label_area_size(x_area as u32)
            .y_label_area_size(y_area as u32)
            .build_cartesian_2d(p.x.lo..p.x.hi, p.y.lo..p.y.hi)
            .map_err(backend_err)
    };
    let log_x = p.x_log.then(|| log_x_ticks(&p.x));
    // Room for half of the last x tick label when it sits at the right edge.
    let overhang = |nx: usize, xd: usize| {
        let half = match &log_x {
            None => widest(&p.x.ticks(nx), xd, m.tick) / 2.0,
            Some(t) => {
                t.iter()
                    .map(|t| text_width(&t.1, m.tick))
                    .fold(0.0, f64::max)
                    / 2.0
            }
        };
        (half - m.margin + m.px(2.0)).max(0.0)
    };
    let plot_w = w - 2.0 * m.margin - y_area - bar_space;
    let (nx, xd) = x_ticks(&p.x, plot_w, &m);
    let mut chart = build(bar_space.max(overhang(nx, xd)), 0.0)?;
    let mut labels = overlay::layout_labels(&chart, p, &m);
    // The legend goes inside the plot where a place is free of data marks, reference lines
    // and labels; else right of the plot (and of the colour bars) if that leaves the plot at
    // least half the width and the legend fits its height; else below the plot, in as many
    // columns as fit. It never covers data.
    let shape = overlay::legend_shape(p, &m, None);
    let mut legend = None;
    let (mut nx, mut xd) = (nx, xd);
    if let Some(one) = shape.clone() {
        let (_, ph) = chart.plotting_area().dim_in_pixel();
        let outside = overlay::legend_outside_width(one.w, &m);
        if let Some(at) = overlay::legend_inside(&chart, p, &labels, (one.w, one.h), &m) {
            legend = Some((one, at));
        } else if plot_w - outside >= 0.5 * (w - 2.0 * m.margin) && one.h <= f64::from(ph) {
            (nx, xd) = x_ticks(&p.x, plot_w - outside, &m);
            chart = build((bar_space + outside).max(overhang(nx, xd)), 0.0)?;
            labels = overlay::layout_labels(&chart, p, &m);
            let (pw, _) = chart.plotting_area().dim_in_pixel();
            legend = Some((one, (f64::from(pw) + bar_space + m.px(12.0), 0.0)));
        } else if let Some(wide) = overlay::legend_shape(p, &m, Some(w - 2.0 * m.margin)) {
            let gap = m.px(10.0);
            chart = build(bar_space.max(overhang(nx, xd)), wide.h + gap)?;
            labels = overlay::layout_labels(&chart, p, &m);
            let (pw, ph) = chart.plotting_area().dim_in_pixel();
            let left = 0.5 * (f64::from(pw) - wide.w);
            let top = f64::from(ph) + x_area + gap;
            legend = Some((wide, (left, top)));
        }
    }
    // The axis titles shrink (to 70 % at most) where the y title is longer than the plot is
    // high, e.g. above a legend below the plot.
    let (_, ph) = chart.plotting_area().dim_in_pixel();
    let desc_px =
        m.label * (f64::from(ph) / text_width(&p.y_title, m.label).max(1.0)).clamp(0.7, 1.0);
    let fx = move |v: &f64| format_tick(*v, xd);
    let fy = move |v: &f64| format_tick(*v, yd);
    chart
        .configure_mesh()
        .x_labels(if log_x.is_some() { 0 } else { nx })
        .y_labels(ny)
        .max_light_lines(0)
        .bold_line_style(GRID.stroke_width(m.thin))
        .axis_style(AXIS.stroke_width(m.thin))
        .set_all_tick_mark_size(m.px(5.0) as i32)
        .label_style(font(m.tick).color(&TEXT))
        .axis_desc_style(font(desc_px).color(&TEXT))
        .x_label_formatter(&fx)
        .y_label_formatter(&fy)
        .x_desc(p.x_title.as_str())
        .y_desc(p.y_title.as_str())
        .draw()
        .map_err(backend_err)?;
    if let Some(ticks) = &log_x {
        draw_log_x(&mut chart, p, ticks, &m)?;
    }
    overlay::draw_marker_lines(&mut chart, p, &m)?;
    draw_series(&mut chart, p, &m)?;
    let frame = Rectangle::new(
        [(p.x.lo, p.y.lo), (p.x.hi, p.y.hi)],
        AXIS.stroke_width(m.thin),
    );
    chart.plotting_area().draw(&frame).map_err(backend_err)?;
    overlay::draw_labels(&chart, &labels, &m)?;
    if let Some((shape, at)) = legend {
        overlay::draw_legend(area, &chart, p, &shape, at, &m)?;
    }
    overlay::draw_bars(area, &chart, &bars, &m)?;
    draw_title(area, &chart, &p.title, title_px, &m)
}

/// Ticks of a log x axis (plotted units are log10 of the data): 1-2-5 × 10ⁿ or decades, with
/// the data value as the label.
fn log_x_ticks(x: &Axis) -> Vec<(f64, String)> {
    super::svg::log_ticks(10f64.powf(x.lo), 10f64.powf(x.hi))
        .into_iter()
        .map(|v| (v.log10(), format_value(v)))
        .filter(|(t, _)| x.contains(*t))
        .collect()
}

/// Grid lines, tick marks and labels of a log x axis (plotters' own mesh is linear).
fn draw_log_x(
    chart: &mut Chart,
    p: &Prepared,
    ticks: &[(f64, String)],
    m: &Metrics,
) -> Result<(), PlotError> {
    let grid = GRID.stroke_width(m.thin);
    let axis = AXIS.stroke_width(m.thin);
    let mark = m.px(5.0) as i32;
    let style = font(m.tick)
        .color(&TEXT)
        .pos(Pos::new(HPos::Center, VPos::Top));
    for (t, label) in ticks {
        let area = chart.plotting_area();
        area.draw(&PathElement::new(vec![(*t, p.y.lo), (*t, p.y.hi)], grid))
            .map_err(backend_err)?;
        let at = EmptyElement::at((*t, p.y.lo))
            + PathElement::new(vec![(0, 0), (0, mark)], axis)
            + Text::new(label.clone(), (0, mark + m.px(5.0) as i32), style.clone());
        area.draw(&at).map_err(backend_err)?;
    }
    Ok(())
}

/// Title centred over the plot area, shifted if needed to stay inside the panel.
fn draw_title(
    area: &Area,
    chart: &Chart,
    title: &str,
    px: f64,
    m: &Metrics,
) -> Result<(), PlotError> {
    if title.is_empty() {
        return Ok(());
    }
    let (xr, _) = chart.plotting_area().get_pixel_range();
    let (bx, _) = area.get_base_pixel();
    let w = f64::from(area.dim_in_pixel().0);
    let half = (text_width(title, px) / 2.0)
        .min(w / 2.0 - m.margin)
        .max(0.0);
    let centre = (f64::from(xr.start + xr.end) / 2.0 - f64::from(bx))
        .clamp(m.margin + half, (w - m.margin - half).max(m.margin + half));
    let style = font(px).color(&TEXT).pos(Pos::new(HPos::Center, VPos::Top));
    let text = Text::new(title, (centre as i32, m.margin as i32), style);
    area.draw(&text).map_err(backend_err)
}

fn draw_series<'a, 'b: 'a>(
    chart: &mut Chart<'a, 'b>,
    p: &Prepared,
    m: &Metrics,
) -> Result<(), PlotError> {
    let (dash, gap) = m.dash;
    let dot = m.dot;
    for it in &p.items {
        let style = it.colour.stroke_width(m.line);
        match it.mark {
            Mark::Line { dashed: false } => {
                chart.draw_series(it.runs.iter().map(|r| PathElement::new(r.clone(), style)))
            }
            Mark::Line { dashed: true } => chart.draw_series(
                it.runs
                    .iter()
                    .map(|r| DashedPathElement::new(r.clone(), dash, gap, style)),
            ),
            Mark::Points | Mark::Coloured => chart.draw_series(
                it.points
                    .iter()
                    .map(|(pt, c)| Circle::new(*pt, dot, c.filled())),
            ),
            Mark::Above => chart.draw_series(
                it.points
                    .iter()
                    .map(|(pt, c)| TriangleMarker::new(*pt, 2 * dot, c.filled())),
            ),
            Mark::Crosses => chart.draw_series(
                it.points
                    .iter()
                    .map(|(pt, c)| Cross::new(*pt, 2 * dot, c.stroke_width(m.line))),
            ),
            Mark::Shade => chart.draw_series(
                it.runs
                    .iter()
                    .map(|r| Polygon::new(r.clone(), it.colour.mix(0.16).filled())),
            ),
        }
        .map_err(backend_err)?;
    }
    Ok(())
}
