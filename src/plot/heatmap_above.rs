//! Heat-map cells whose value is only known to exceed a bound (e.g. no onset of hunting up to
//! the top of the speed range): their fill, the threshold values through them, their legend.

use super::{HeatMap, BAR_X};
use crate::plot::svg::{Doc, TICK_PX};

/// Cells of a [`HeatMap`] whose value lies above a known bound. They are filled in
/// [`ABOVE_FILL`] (beyond the top of the colour bar, not hatched) and no contour is drawn
/// through a square touching one, except the threshold contour when the threshold is at or
/// below the bound: there the cell is known to lie above the threshold, and the contour is
/// drawn as if its value were the bound. Linear interpolation then puts the crossing at or
/// beyond where the true (larger) value would put it, i.e. on the side of the above-range cell:
/// the region drawn below the threshold is never smaller than the interpolated one.
#[derive(Debug, Clone, PartialEq)]
pub struct AboveRange {
    /// One flag per cell, in the order of [`HeatMap::z`]; the cell's `z` should be `None`.
    pub cells: Vec<bool>,
    /// The bound the values exceed, in the unit of `z` (e.g. 300 for `"> 300 m/s"`).
    pub bound: f64,
    /// Legend and colour-bar text, e.g. `"> 300 m/s (no onset in range)"`.
    pub label: String,
}

/// Fill of above-range cells: a pale pink, outside the viridis range and unlike the grey hatch.
pub const ABOVE_FILL: &str = "#f4b6d2";

/// Whether cell `k` is above range.
pub(super) fn is_above(h: &HeatMap, k: usize) -> bool {
    h.above
        .as_ref()
        .is_some_and(|a| a.cells.get(k).copied().unwrap_or(false))
}

/// The values the threshold contour is drawn through: `z`, with above-range cells at the
/// bound when the threshold `t` is at or below it (see [`AboveRange`]).
pub(super) fn threshold_z(h: &HeatMap, t: f64) -> Vec<Option<f64>> {
    match &h.above {
        Some(a) if t <= a.bound => (h.z.iter().enumerate())
            .map(|(k, z)| if is_above(h, k) { Some(a.bound) } else { *z })
            .collect(),
        _ => h.z.clone(),
    }
}

/// `"> 300 m/s (no onset in range)"` → (`"> 300 m/s"`, `Some("(no onset in range)")`).
pub(super) fn split_label(label: &str) -> (&str, Option<&str>) {
    match label.find(" (") {
        Some(i) => (&label[..i], Some(&label[i + 1..])),
        None => (label, None),
    }
}

/// The above-range entry of the colour bar: a box of [`ABOVE_FILL`] over its top.
pub(super) fn above_box(doc: &mut Doc, h: &HeatMap, top: f64) {
    let Some(a) = &h.above else { return };
    if !a.cells.contains(&true) {
        return;
    }
    doc.rect(
        (BAR_X, top - 24.0),
        (BAR_X + 18.0, top - 40.0),
        ABOVE_FILL,
        Some("#555555"),
    );
    let (head, _) = split_label(&a.label);
    doc.text(BAR_X + 24.0, top - 28.0, TICK_PX - 1.0, "start", 0.0, head);
}
