//! Validation and conversion of a [`Figure`] into drawable, clipped data in
//! plotted (scaled) units.

use super::geom::{visible_runs, Rect};
use super::palette::{series_colour, viridis};
use super::scale::Axis;
use super::{Figure, Marker, PlotError, Style};
use plotters::style::RGBColor;

/// How an [`Item`] is drawn.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Mark {
    /// Polyline runs.
    Line { dashed: bool },
    /// Filled circles in the series colour.
    Points,
    /// Filled circles coloured by value.
    Coloured,
    /// Filled up-pointing triangles in the series colour.
    Above,
    /// Crosses in the series colour.
    Crosses,
    /// A filled polygon (its one run) in a tint of the series colour.
    Shade,
}

/// One series, ready to draw.
#[derive(Debug, Clone)]
pub(crate) struct Item {
    pub name: String,
    /// Legend/series colour.
    pub colour: RGBColor,
    pub mark: Mark,
    /// Visible polyline runs (lines only).
    pub runs: Vec<Vec<(f64, f64)>>,
    /// Visible points with their fill colour (points only).
    pub points: Vec<((f64, f64), RGBColor)>,
}

/// A colour bar shared by all coloured series with the same label.
#[derive(Debug, Clone)]
pub(crate) struct Bar {
    pub label: String,
    pub lo: f64,
    pub hi: f64,
}

impl Bar {
    /// Whether any finite value was seen.
    pub fn is_valid(&self) -> bool {
        self.lo <= self.hi
    }

    fn colour(&self, v: Option<&f64>) -> RGBColor {
        let t = match v {
            Some(v) if v.is_finite() && self.hi > self.lo => (v - self.lo) / (self.hi - self.lo),
            Some(v) if v.is_finite() => 0.5,
            _ => f64::NAN,
        };
        viridis(t)
    }
}

/// A figure converted to plotted units.
#[derive(Debug, Clone)]
pub(crate) struct Prepared {
    pub title: String,
    pub x_title: String,
    pub y_title: String,
    pub x: Axis,
    pub y: Axis,
    pub items: Vec<Item>,
    pub bars: Vec<Bar>,
    /// Visible vertical markers (scaled x, label).
    pub vlines: Vec<(f64, String)>,
    /// Visible horizontal markers (scaled y, label).
    pub hlines: Vec<(f64, String)>,
    /// The x axis is logarithmic: plotted x is log10 of the data.
    pub x_log: bool,
}

fn finite(p: &(f64, f64)) -> bool {
    p.0.is_finite() && p.1.is_finite()
}

fn extent(values: impl Iterator<Item = f64>) -> Option<(f64, f64)> {
    values
        .filter(|v| v.is_finite())
        .fold(None, |acc, v| match acc {
            None => Some((v, v)),
            Some((a, b)) => Some((a.min(v), b.max(v))),
        })
}

fn visible_markers(marks: &[Marker], axis: &Axis) -> Vec<(f64, String)> {
    marks
        .iter()
        .map(|m| (m.at * axis.factor, m.label.clone()))
        .filter(|(v, _)| v.is_finite() && axis.contains(*v))
        .collect()
}

fn colour_bars(fig: &Figure) -> Vec<Bar> {
    let mut bars: Vec<Bar> = Vec::new();
    for s in &fig.series {
        if let Style::PointsColoured { values, label } = &s.style {
            let i = match bars.iter().position(|b| b.label == *label) {
                Some(i) => i,
                None => {
                    bars.push(Bar {
                        label: label.clone(),
                        lo: f64::INFINITY,
                        hi: f64::NEG_INFINITY,
                    });
                    bars.len() - 1
                }
            };
            let used = values.iter().take(s.points.len());
            if let Some((lo, hi)) = extent(used.copied()) {
                bars[i].lo = bars[i].lo.min(lo);
                bars[i].hi = bars[i].hi.max(hi);
            }
        }
    }
    bars
}

/// Validate `fig` and convert it to plotted units.
pub(crate) fn prepare(fig: &Figure) -> Result<Prepared, PlotError> {
    if fig.series.iter().all(|s| s.points.is_empty()) {
        return Err(PlotError::Empty {
            title: fig.title.clone(),
        });
    }
    if let Some(s) = fig
        .series
        .iter()
        .find(|s| !s.points.is_empty() && !s.points.iter().any(finite))
    {
        return Err(PlotError::NonFinite {
            title: fig.title.clone(),
            series: s.name.clone(),
        });
    }
    // a log x axis plots log10(x); non-positive x become NaN and are not drawn
    let lx = |v: f64| match (fig.x_log, v > 0.0) {
        (false, _) => v,
        (true, true) => v.log10(),
        (true, false) => f64::NAN,
    };
    let all = || {
        fig.series
            .iter()
            .flat_map(|s| s.points.iter())
            .map(|p| (lx(p.0), p.1))
            .filter(finite)
    };
    let vlines: Vec<Marker> = fig
        .vlines
        .iter()
        .map(|m| Marker {
            at: lx(m.at),
            label: m.label.clone(),
        })
        .collect();
    let vx = vlines.iter().map(|m| m.at);
    let hy = fig.hlines.iter().map(|m| m.at);
    let x_extent = extent(all().map(|p| p.0).chain(vx));
    let x = if fig.x_log {
        Axis::resolve_log(fig.x_range.map(|(a, b)| (lx(a), lx(b))), x_extent)
    } else {
        Axis::resolve(fig.x_range, x_extent)
    };
    let y = Axis::resolve(fig.y_range, extent(all().map(|p| p.1).chain(hy)));
    let rect = Rect {
        x0: x.lo,
        x1: x.hi,
        y0: y.lo,
        y1: y.hi,
    };
    let scaled = |p: &(f64, f64)| (lx(p.0) * x.factor, p.1 * y.factor);
    let bars = colour_bars(fig);
    let mut items = Vec::new();
    let mut next_colour = 0;
    for s in fig.series.iter().filter(|s| !s.points.is_empty()) {
        let mut item = Item {
            name: s.name.clone(),
            colour: series_colour(next_colour),
            mark: Mark::Points,
            runs: Vec::new(),
            points: Vec::new(),
        };
        let visible = s.points.iter().map(scaled).enumerate();
        let visible = visible.filter(|(_, p)| finite(p) && rect.contains(*p));
        match &s.style {
            Style::Line { dashed } => {
                item.mark = Mark::Line { dashed: *dashed };
                item.runs = visible_runs(s.points.iter().map(scaled), &rect);
                next_colour += 1;
            }
            Style::LineIn { dashed, colour } => {
                item.colour = series_colour(*colour);
                item.mark = Mark::Line { dashed: *dashed };
                item.runs = visible_runs(s.points.iter().map(scaled), &rect);
            }
            Style::Points | Style::Above | Style::Crosses => {
                item.mark = match s.style {
                    Style::Above => Mark::Above,
                    Style::Crosses => Mark::Crosses,
                    _ => Mark::Points,
                };
                item.points = visible.map(|(_, p)| (p, item.colour)).collect();
                next_colour += 1;
            }
            Style::PointsIn { colour, crosses } => {
                item.colour = series_colour(*colour);
                item.mark = if *crosses {
                    Mark::Crosses
                } else {
                    Mark::Points
                };
                item.points = visible.map(|(_, p)| (p, item.colour)).collect();
            }
            Style::Shade | Style::ShadeRgb(..) => {
                item.mark = Mark::Shade;
                if let Style::ShadeRgb(r, g, b) = s.style {
                    item.colour = RGBColor(r, g, b);
                }
                let clamp =
                    |(x, y): (f64, f64)| (x.clamp(rect.x0, rect.x1), y.clamp(rect.y0, rect.y1));
                item.runs = vec![s
                    .points
                    .iter()
                    .map(scaled)
                    .filter(finite)
                    .map(clamp)
                    .collect()];
            }
            Style::PointsColoured { values, label } => {
                let bar = bars.iter().find(|b| b.label == *label);
                let colour = |i: usize| bar.map_or(viridis(0.5), |b| b.colour(values.get(i)));
                item.colour = viridis(0.5);
                item.mark = Mark::Coloured;
                item.points = visible.map(|(i, p)| (p, colour(i))).collect();
            }
        }
        items.push(item);
    }
    Ok(Prepared {
        title: fig.title.clone(),
        x_title: x.title(&fig.x_label),
        y_title: y.title(&fig.y_label),
        x,
        y,
        items,
        bars,
        vlines: visible_markers(&vlines, &x),
        hlines: visible_markers(&fig.hlines, &y),
        x_log: fig.x_log,
    })
}
