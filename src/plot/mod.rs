//! TEMPORARY stub of the plot API (replaced by the real module).
#![allow(missing_docs)]
pub struct Figure {
    pub title: String,
    pub x_label: String,
    pub y_label: String,
    pub series: Vec<Series>,
    pub vlines: Vec<Marker>,
    pub hlines: Vec<Marker>,
    pub x_range: Option<(f64, f64)>,
    pub y_range: Option<(f64, f64)>,
}
pub struct Series {
    pub name: String,
    pub points: Vec<(f64, f64)>,
    pub style: Style,
}
pub enum Style {
    Line { dashed: bool },
    Points,
    PointsColoured { values: Vec<f64>, label: String },
}
pub struct Marker {
    pub at: f64,
    pub label: String,
}
#[derive(Debug, thiserror::Error)]
pub enum PlotError {
    #[error("empty {title}")]
    Empty { title: String },
    #[error("nonfinite")]
    NonFinite { title: String, series: String },
    #[error("backend {0}")]
    Backend(String),
}
pub fn render_svg(fig: &Figure, _w: u32, _h: u32) -> Result<String, PlotError> {
    Ok(format!("<svg>{}</svg>", fig.title))
}
pub fn render_grid(figs: &[Figure], _c: usize, _w: u32, _h: u32) -> Result<String, PlotError> {
    Ok(format!("<svg>{}</svg>", figs.len()))
}
