//! Contour levels in pixel coordinates, drawn as polylines, with one label each placed where
//! it does not collide with labels already placed.

use super::contour::contour_lines;
use super::heatmap::{HeatMap, PLOT, THRESHOLD};
use super::scale::{format_value, text_width};
use super::svg::{AxisMap, Doc, LABEL_PX, TICK_PX};

/// One contour level in pixel coordinates, with its label text.
pub(crate) struct Contour {
    lines: Vec<Vec<(f64, f64)>>,
    /// the label (the level's value)
    pub text: String,
    threshold: bool,
}

/// A placed label box `(x0, x1, y0, y1)` in pixels.
pub(crate) type LabelBox = (f64, f64, f64, f64);

impl Contour {
    /// The contour of `z` (on `h`'s grid) at `level`.
    pub fn new(
        h: &HeatMap,
        z: &[Option<f64>],
        (xm, ym): (&AxisMap, &AxisMap),
        level: f64,
        threshold: bool,
    ) -> Self {
        let lines = contour_lines(&h.x, &h.y, z, level)
            .iter()
            .map(|l| l.iter().map(|p| (xm.px(p.0), ym.px(p.1))).collect())
            .collect();
        Contour {
            lines,
            text: format_value(level),
            threshold,
        }
    }

    pub fn colour(&self) -> &'static str {
        if self.threshold {
            THRESHOLD
        } else {
            "#1a1a1a"
        }
    }

    pub fn size(&self) -> f64 {
        if self.threshold {
            LABEL_PX
        } else {
            TICK_PX - 1.0
        }
    }

    pub fn draw_lines(&self, doc: &mut Doc) {
        let (width, dash) = if self.threshold {
            (3.0, Some("9 5"))
        } else {
            (1.1, None)
        };
        for l in &self.lines {
            doc.polyline(l, self.colour(), width, dash);
        }
    }

    /// A label position on one of the lines (longest first, middle first) whose box does not
    /// overlap a label already placed; `None` when every candidate collides.
    pub fn place_label(&self, placed: &mut Vec<LabelBox>) -> Option<(f64, f64)> {
        let len = |l: &[(f64, f64)]| -> f64 {
            l.windows(2)
                .map(|w| (w[1].0 - w[0].0).hypot(w[1].1 - w[0].1))
                .sum()
        };
        let mut lines: Vec<&Vec<(f64, f64)>> =
            self.lines.iter().filter(|l| len(l) > 40.0).collect();
        lines.sort_by(|a, b| len(b).total_cmp(&len(a)));
        let (w, hh) = (
            text_width(&self.text, self.size()) / 2.0 + 4.0,
            0.75 * self.size() + 2.0,
        );
        let free = |b: &LabelBox| {
            !placed
                .iter()
                .any(|p| b.0 < p.1 && p.0 < b.1 && b.2 < p.3 && p.2 < b.3)
        };
        for l in lines {
            for f in [0.5, 0.35, 0.65, 0.2, 0.8] {
                let (x, y) = l[((l.len() - 1) as f64 * f).round() as usize];
                let x = x.clamp(PLOT.0 + w, PLOT.1 - w);
                let b = (x - w, x + w, y - hh, y + hh);
                if free(&b) {
                    placed.push(b);
                    return Some((x, y));
                }
            }
        }
        None
    }
}
