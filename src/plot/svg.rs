//! A small hand-written SVG writer with linear or logarithmic axes, for the plots that the
//! plotters-based [`super::Figure`] does not cover (heat maps, log-scaled trade plots).
//!
//! Coordinates are SVG pixels (origin top-left, y down); [`AxisMap`] maps data to pixels.

use std::fmt::Write as _;

use super::scale::{format_value, text_width};

/// Font size of tick labels (px).
pub(crate) const TICK_PX: f64 = 12.0;
/// Font size of axis titles (px).
pub(crate) const LABEL_PX: f64 = 13.5;
/// Font size of the title (px).
pub(crate) const TITLE_PX: f64 = 16.0;

/// Escape text for SVG content and attribute values.
pub(crate) fn esc(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// `#rrggbb` of an RGB colour.
pub(crate) fn hex(c: plotters::style::RGBColor) -> String {
    format!("#{:02x}{:02x}{:02x}", c.0, c.1, c.2)
}

/// One axis: data interval `[lo, hi]` drawn on pixels `[p0, p1]` (p1 may be < p0 for y).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct AxisMap {
    pub lo: f64,
    pub hi: f64,
    pub log: bool,
    pub p0: f64,
    pub p1: f64,
}

impl AxisMap {
    fn t(&self, v: f64) -> f64 {
        if self.log {
            (v.ln() - self.lo.ln()) / (self.hi.ln() - self.lo.ln())
        } else {
            (v - self.lo) / (self.hi - self.lo)
        }
    }

    /// Pixel position of data value `v`.
    pub fn px(&self, v: f64) -> f64 {
        self.p0 + self.t(v) * (self.p1 - self.p0)
    }

    /// Tick values inside `[lo, hi]`: "nice" 1-2-5 steps (linear), or decades, with 2 and 5
    /// added when fewer than three decades are shown (log).
    pub fn ticks(&self) -> Vec<f64> {
        if self.log {
            log_ticks(self.lo, self.hi)
        } else {
            nice_ticks(self.lo, self.hi, 6)
        }
    }
}

/// Values `k·step` in `[lo, hi]` with `step` 1, 2 or 5 × 10ⁿ giving about `n` ticks.
pub(crate) fn nice_ticks(lo: f64, hi: f64, n: usize) -> Vec<f64> {
    let span = hi - lo;
    if !(span.is_finite() && span > 0.0) {
        return vec![lo];
    }
    let raw = span / n.max(1) as f64;
    let mag = 10f64.powf(raw.log10().floor());
    let step = [1.0, 2.0, 5.0, 10.0]
        .iter()
        .map(|m| m * mag)
        .find(|s| *s >= raw)
        .unwrap_or(10.0 * mag);
    let first = (lo / step).ceil() as i64;
    let last = (hi / step).floor() as i64;
    // index-based, never accumulated
    (first..=last).map(|k| k as f64 * step).collect()
}

pub(crate) fn log_ticks(lo: f64, hi: f64) -> Vec<f64> {
    let (e0, e1) = (lo.log10().floor() as i32, hi.log10().ceil() as i32);
    let mults: &[f64] = match e1 - e0 {
        0..=1 => &[1.0, 2.0, 3.0, 5.0],
        2..=3 => &[1.0, 2.0, 5.0],
        _ => &[1.0],
    };
    let inside = |v: &f64| *v >= lo * (1.0 - 1e-9) && *v <= hi * (1.0 + 1e-9);
    (e0..=e1)
        .flat_map(|e| mults.iter().map(move |m| m * 10f64.powi(e)))
        .filter(inside)
        .collect()
}

/// An SVG document being written.
pub(crate) struct Doc {
    pub out: String,
}

impl Doc {
    /// Start a `w`×`h` document with a white background and `defs` (patterns etc.).
    pub fn new(w: f64, h: f64, defs: &str) -> Doc {
        let mut out = String::new();
        let _ = write!(
            out,
            "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{w}\" height=\"{h}\" \
             viewBox=\"0 0 {w} {h}\" font-family=\"sans-serif\">\n<defs>{defs}</defs>\n\
             <rect x=\"0\" y=\"0\" width=\"{w}\" height=\"{h}\" fill=\"#ffffff\"/>\n"
        );
        Doc { out }
    }

    /// Append a raw element.
    pub fn raw(&mut self, s: &str) {
        self.out.push_str(s);
        self.out.push('\n');
    }

    /// Text at `(x, y)`; `anchor` is start/middle/end; `rotate` in degrees about `(x, y)`.
    pub fn text(&mut self, x: f64, y: f64, size: f64, anchor: &str, rotate: f64, s: &str) {
        let rot = if rotate == 0.0 {
            String::new()
        } else {
            format!(" transform=\"rotate({rotate:.0} {x:.1} {y:.1})\"")
        };
        let _ = writeln!(
            self.out,
            "<text x=\"{x:.1}\" y=\"{y:.1}\" font-size=\"{size}\" text-anchor=\"{anchor}\" \
             fill=\"#222222\"{rot}>{}</text>",
            esc(s)
        );
    }

    /// Text on a translucent white box, centred at `(x, y)`.
    pub fn label(&mut self, x: f64, y: f64, size: f64, colour: &str, s: &str) {
        let w = text_width(s, size) + 6.0;
        let _ = writeln!(
            self.out,
            "<rect x=\"{:.1}\" y=\"{:.1}\" width=\"{w:.1}\" height=\"{:.1}\" fill=\"#ffffff\" \
             fill-opacity=\"0.8\"/><text x=\"{x:.1}\" y=\"{:.1}\" font-size=\"{size}\" \
             text-anchor=\"middle\" fill=\"{colour}\">{}</text>",
            x - w / 2.0,
            y - 0.75 * size,
            1.5 * size,
            y + 0.35 * size,
            esc(s)
        );
    }

    /// Polyline through pixel points with a stroke colour, width and optional dash pattern.
    pub fn polyline(&mut self, pts: &[(f64, f64)], colour: &str, width: f64, dash: Option<&str>) {
        let mut d = String::new();
        for (x, y) in pts {
            let _ = write!(d, "{x:.2},{y:.2} ");
        }
        let dash = dash.map_or(String::new(), |p| format!(" stroke-dasharray=\"{p}\""));
        let _ = writeln!(
            self.out,
            "<polyline points=\"{}\" fill=\"none\" stroke=\"{colour}\" stroke-width=\"{width}\" \
             stroke-linejoin=\"round\"{dash}/>",
            d.trim_end()
        );
    }

    /// Filled rectangle between two pixel corners (any order).
    pub fn rect(&mut self, a: (f64, f64), b: (f64, f64), fill: &str, stroke: Option<&str>) {
        let (x, y) = (a.0.min(b.0), a.1.min(b.1));
        let (w, h) = ((a.0 - b.0).abs(), (a.1 - b.1).abs());
        let stroke = stroke.map_or(String::new(), |s| format!(" stroke=\"{s}\""));
        let _ = writeln!(
            self.out,
            "<rect x=\"{x:.2}\" y=\"{y:.2}\" width=\"{w:.2}\" height=\"{h:.2}\" \
             fill=\"{fill}\"{stroke}/>"
        );
    }

    /// A legend line centred at `x` under the title: a line sample, then `label`.
    pub fn key_line(&mut self, x: f64, label: &str, colour: &str, width: f64, dash: &str) {
        let w = text_width(label, LABEL_PX) + 34.0;
        let x = x - w / 2.0;
        self.polyline(&[(x, 47.0), (x + 26.0, 47.0)], colour, width, Some(dash));
        self.text(x + 34.0, 51.5, LABEL_PX, "start", 0.0, label);
    }

    /// Finish the document.
    pub fn finish(mut self) -> String {
        self.out.push_str("</svg>\n");
        self.out
    }
}

/// The plot frame, ticks with labels, grid-free axis titles and the title.
pub(crate) struct Frame<'a> {
    pub x: AxisMap,
    pub y: AxisMap,
    pub title: &'a str,
    pub x_label: &'a str,
    pub y_label: &'a str,
}

impl Frame<'_> {
    /// Draw the frame, ticks, tick labels and titles.
    pub fn draw(&self, doc: &mut Doc, grid: bool) {
        let (x0, x1, y0, y1) = (self.x.p0, self.x.p1, self.y.p0, self.y.p1);
        for v in self.x.ticks() {
            let p = self.x.px(v);
            if grid {
                doc.polyline(&[(p, y0), (p, y1)], "#e3e3e3", 1.0, None);
            }
            doc.polyline(&[(p, y0), (p, y0 + 5.0)], "#555555", 1.0, None);
            doc.text(p, y0 + 19.0, TICK_PX, "middle", 0.0, &format_value(v));
        }
        for v in self.y.ticks() {
            let p = self.y.px(v);
            if grid {
                doc.polyline(&[(x0, p), (x1, p)], "#e3e3e3", 1.0, None);
            }
            doc.polyline(&[(x0 - 5.0, p), (x0, p)], "#555555", 1.0, None);
            doc.text(x0 - 8.0, p + 4.0, TICK_PX, "end", 0.0, &format_value(v));
        }
        doc.rect((x0, y0), (x1, y1), "none", Some("#555555"));
        let xm = (x0 + x1) / 2.0;
        doc.text(xm, y0 + 42.0, LABEL_PX, "middle", 0.0, self.x_label);
        let ym = (y0 + y1) / 2.0;
        doc.text(x0 - 58.0, ym, LABEL_PX, "middle", -90.0, self.y_label);
        doc.text(xm, y1 - 16.0, TITLE_PX, "middle", 0.0, self.title);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ticks_are_nice_and_inside() {
        assert_eq!(
            nice_ticks(0.0, 10.0, 5),
            vec![0.0, 2.0, 4.0, 6.0, 8.0, 10.0]
        );
        let t = nice_ticks(0.13, 0.91, 6);
        assert!(t.iter().all(|v| (0.13..=0.91).contains(v)) && t.len() >= 4);
        let l = log_ticks(100.0, 3000.0);
        assert_eq!(l.first().copied(), Some(100.0));
        assert!(l.iter().all(|v| (100.0..=3000.0).contains(v)));
        assert!(l.contains(&1000.0) && l.contains(&2000.0));
        let m = AxisMap {
            lo: 10.0,
            hi: 1000.0,
            log: true,
            p0: 0.0,
            p1: 200.0,
        };
        assert!((m.px(100.0) - 100.0).abs() < 1e-9);
        assert_eq!(esc("a<b & \"c\""), "a&lt;b &amp; &quot;c&quot;");
    }
}
