//! SVG plotting for `critspeed`.
//!
//! Plots are pure functions from plain data ([`Figure`]) to SVG text; this
//! module knows nothing about the wheelset model. Text is emitted as SVG
//! `<text>` elements (sans-serif), so no fonts are needed at render time.
//!
//! Axis numbers are kept short: when the magnitudes on an axis are below 0.01
//! or at least 10⁴, a power of ten (multiple of 3) is factored out of the tick
//! labels and shown in the axis title, e.g. `"semi-axis (m) [×10⁻³]"` (tick
//! value × 10⁻³ = data value). Pass data in convenient units (mm, kN) to
//! avoid the factor altogether.

mod check;
mod contour;
mod contour_labels;
mod geom;
mod heatmap;
#[cfg(test)]
mod heatmap_tests;
mod note;
mod overlay;
mod palette;
mod panel;
mod prepare;
mod scale;
mod svg;
#[cfg(test)]
mod tests;
mod tradeplot;

pub use check::{legend_clashes, legend_count};
pub use heatmap::{heat_map_svg, AboveRange, HeatMap, ABOVE_FILL};
pub use note::{drawing, note_svg, Drawing};
pub use tradeplot::{trade_svg, TradePlot, TradePoint};

use plotters::prelude::{IntoDrawingArea, SVGBackend};

/// One plot panel: series, reference lines, labels and optional fixed ranges.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Figure {
    /// Title drawn above the plot (omitted when empty).
    pub title: String,
    /// X-axis title, including units, e.g. `"speed (m/s)"`.
    pub x_label: String,
    /// Y-axis title, including units.
    pub y_label: String,
    /// Data series, drawn in order (later series on top).
    pub series: Vec<Series>,
    /// Vertical reference lines, e.g. the critical speed `"V_L = 184.3 m/s"`.
    pub vlines: Vec<Marker>,
    /// Horizontal reference lines, e.g. zero damping.
    pub hlines: Vec<Marker>,
    /// Fixed x range; `None` = data and vertical markers plus a small margin.
    pub x_range: Option<(f64, f64)>,
    /// Fixed y range; `None` = data and horizontal markers plus a small margin.
    pub y_range: Option<(f64, f64)>,
    /// Logarithmic x axis (ticks at 1-2-5 × 10ⁿ or decades); non-positive x are not drawn.
    pub x_log: bool,
}

/// A named set of `(x, y)` points with a drawing style.
#[derive(Debug, Clone, PartialEq)]
pub struct Series {
    /// Legend entry; series with an empty name are left out of the legend.
    pub name: String,
    /// Data points. Non-finite points are skipped (lines get a gap there).
    pub points: Vec<(f64, f64)>,
    /// How the points are drawn.
    pub style: Style,
}

/// Drawing style of a [`Series`]. Ordinary series take successive colours
/// of the colour-blind-safe Okabe–Ito palette.
#[derive(Debug, Clone, PartialEq)]
pub enum Style {
    /// Connected line, solid or dashed.
    Line {
        /// Draw the line dashed.
        dashed: bool,
    },
    /// Connected line in the palette's colour number `colour` (it does not take the next
    /// colour): series that belong together (one kind of branch, stable and unstable) share it.
    LineIn {
        /// Draw the line dashed.
        dashed: bool,
        /// Index into the series palette.
        colour: usize,
    },
    /// Unconnected filled circles.
    Points,
    /// Unconnected filled circles (`crosses`: crosses ×) in the palette's colour number
    /// `colour` (it does not take the next colour).
    PointsIn {
        /// Index into the series palette.
        colour: usize,
        /// Draw crosses instead of circles.
        crosses: bool,
    },
    /// Filled triangles pointing up: each value is a lower bound (the true one lies above).
    Above,
    /// Unconnected crosses (×), e.g. points that have no value, drawn at a chosen place.
    Crosses,
    /// A closed polygon through the points, filled with a light tint of the colour the next
    /// series gets (so a region and the curve that bounds it match); vertices outside the
    /// plotted range are moved onto its edge.
    Shade,
    /// A closed polygon like [`Style::Shade`], filled with a light tint of the colour
    /// (red, green, blue) given: regions whose colour says what they are (no hunting,
    /// hunting after a disturbance, unstable) rather than which curve bounds them.
    ShadeRgb(u8, u8, u8),
    /// Filled circles coloured by a value on a viridis-like scale, with a
    /// colour bar showing `label` and the value range. Series sharing the
    /// same `label` share one scale and one colour bar.
    PointsColoured {
        /// One value per point; missing or non-finite values are drawn grey.
        values: Vec<f64>,
        /// Colour-bar title including units, e.g. `"speed (m/s)"`.
        label: String,
    },
}

/// A labelled reference line at a data coordinate. Markers that are not
/// finite or fall outside the plotted range are not drawn.
#[derive(Debug, Clone, PartialEq)]
pub struct Marker {
    /// Position on the axis (x for vertical lines, y for horizontal ones).
    pub at: f64,
    /// Text written next to the line inside the plot area (may be empty).
    pub label: String,
}

/// Errors from rendering.
#[derive(Debug, thiserror::Error)]
pub enum PlotError {
    /// The figure (or grid) has no data points at all.
    #[error("figure \"{title}\" has no data points")]
    Empty {
        /// Title of the offending figure.
        title: String,
    },
    /// A series has points but none of them is finite.
    #[error("series \"{series}\" of figure \"{title}\" has no finite points")]
    NonFinite {
        /// Title of the figure.
        title: String,
        /// Name of the series.
        series: String,
    },
    /// The input breaks a rule (lengths, finite and increasing axes, ...).
    #[error("figure \"{title}\": {rule}")]
    Invalid {
        /// Title of the figure.
        title: String,
        /// The rule broken, with the offending value.
        rule: String,
    },
    /// The drawing backend failed or the canvas is unusable (too small or too large).
    #[error("plot backend error: {0}")]
    Backend(String),
}

/// Device units per output pixel: drawing is done on a canvas this many times
/// larger and scaled down through the SVG `viewBox`, because plotters rounds
/// every coordinate to an integer.
pub(crate) const SUPERSAMPLE: u32 = 4;
/// Smallest accepted panel size in pixels.
const MIN_PANEL: (u32, u32) = (200, 150);
/// Largest accepted canvas side in pixels.
const MAX_SIDE: u32 = 20_000;

pub(crate) fn backend_err<E: std::fmt::Display>(e: E) -> PlotError {
    PlotError::Backend(e.to_string())
}

fn check_canvas(width: u32, height: u32, rows: usize, cols: usize) -> Result<(), PlotError> {
    let (pw, ph) = (width as usize / cols, height as usize / rows);
    if width > MAX_SIDE || height > MAX_SIDE {
        return Err(PlotError::Backend(format!(
            "canvas {width}×{height} exceeds {MAX_SIDE} px"
        )));
    }
    if pw < MIN_PANEL.0 as usize || ph < MIN_PANEL.1 as usize {
        return Err(PlotError::Backend(format!(
            "panel {pw}×{ph} px is smaller than the minimum {}×{} px",
            MIN_PANEL.0, MIN_PANEL.1
        )));
    }
    Ok(())
}

/// Render one figure as a standalone SVG document of `width`×`height` pixels.
///
/// Errors: [`PlotError::Empty`] when no series has any point,
/// [`PlotError::NonFinite`] when a series has points but none finite,
/// [`PlotError::Backend`] for canvas sizes outside 200×150 ..= 20000×20000.
pub fn render_svg(fig: &Figure, width: u32, height: u32) -> Result<String, PlotError> {
    render_grid(std::slice::from_ref(fig), 1, width, height)
}

/// Render several figures as panels of one SVG document, filled row by row
/// in a grid of `cols` columns (clamped to `1..=figs.len()`). `width` and
/// `height` are the size of the whole document. Errors as for [`render_svg`]
/// (checked for every panel before drawing); an empty slice gives
/// [`PlotError::Empty`] with an empty title.
pub fn render_grid(
    figs: &[Figure],
    cols: usize,
    width: u32,
    height: u32,
) -> Result<String, PlotError> {
    if figs.is_empty() {
        return Err(PlotError::Empty {
            title: String::new(),
        });
    }
    let cols = cols.clamp(1, figs.len());
    let rows = figs.len().div_ceil(cols);
    check_canvas(width, height, rows, cols)?;
    let prepared = figs
        .iter()
        .map(prepare::prepare)
        .collect::<Result<Vec<_>, _>>()?;
    let device = (width * SUPERSAMPLE, height * SUPERSAMPLE);
    let mut buf = String::new();
    {
        let root = SVGBackend::with_string(&mut buf, device).into_drawing_area();
        root.fill(&palette::WHITE).map_err(backend_err)?;
        for (area, p) in root.split_evenly((rows, cols)).iter().zip(&prepared) {
            panel::draw(area, p)?;
        }
        root.present().map_err(backend_err)?;
    }
    // Present the device canvas at the requested size (viewBox stays).
    let header = format!("<svg width=\"{}\" height=\"{}\" ", device.0, device.1);
    Ok(match buf.strip_prefix(&header) {
        Some(rest) => format!("<svg width=\"{width}\" height=\"{height}\" {rest}"),
        None => buf,
    })
}
