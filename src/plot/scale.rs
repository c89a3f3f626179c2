//! Axis ranges (auto/degenerate handling), power-of-ten factoring and number
//! formatting for tick labels and colour-bar limits.

use plotters::coord::ranged1d::Ranged;
use plotters::coord::types::RangedCoordf64;

/// Relative margin added on each side of an automatic range.
const MARGIN: f64 = 0.04;

/// A resolved axis. `lo`/`hi` are in *plotted* units: raw value × `factor`,
/// where `factor = 10^-exp` keeps tick labels short (e.g. 0.007 m → 7 ×10⁻³).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Axis {
    /// Lower end of the plotted interval (scaled units).
    pub lo: f64,
    /// Upper end of the plotted interval (scaled units, always `> lo`).
    pub hi: f64,
    /// Power of ten factored out of the tick labels.
    pub exp: i32,
    /// Multiplier from raw data to plotted units.
    pub factor: f64,
}

impl Axis {
    /// Resolve an axis from an optional caller range and the finite data extent.
    ///
    /// A caller range that is not finite is ignored; a reversed one is swapped.
    /// Automatic ranges get a small margin; zero-width ranges are widened by
    /// ±10 % of the value (or ±1 around zero).
    pub fn resolve(requested: Option<(f64, f64)>, extent: Option<(f64, f64)>) -> Axis {
        Self::resolve_with(requested, extent, None)
    }

    /// As [`Axis::resolve`] for an axis whose values are log10 of the data: no power of ten
    /// is factored out (the tick labels show the data values themselves).
    pub fn resolve_log(requested: Option<(f64, f64)>, extent: Option<(f64, f64)>) -> Axis {
        Self::resolve_with(requested, extent, Some(0))
    }

    fn resolve_with(
        requested: Option<(f64, f64)>,
        extent: Option<(f64, f64)>,
        exp: Option<i32>,
    ) -> Axis {
        let user = requested
            .filter(|(a, b)| a.is_finite() && b.is_finite())
            .map(|(a, b)| (a.min(b), a.max(b)));
        let (raw, auto) = match (user, extent) {
            (Some(r), _) => (r, false),
            (None, Some(e)) => (e, true),
            (None, None) => ((0.0, 1.0), false),
        };
        let exp = exp.unwrap_or_else(|| engineering_exponent(raw.0.abs().max(raw.1.abs())));
        let factor = 10f64.powi(-exp);
        let (mut lo, mut hi) = (raw.0 * factor, raw.1 * factor);
        let mag = lo.abs().max(hi.abs());
        let span = hi - lo;
        if !(span.is_normal() && span > mag * 1e-9) {
            let mid = 0.5 * (lo + hi);
            let half = if mid.abs() * 0.1 > 0.0 {
                mid.abs() * 0.1
            } else {
                1.0
            };
            (lo, hi) = (mid - half, mid + half);
        } else if auto {
            (lo, hi) = (lo - span * MARGIN, hi + span * MARGIN);
        }
        Axis {
            lo,
            hi,
            exp,
            factor,
        }
    }

    /// The tick positions plotters will use for `max_n` labels.
    pub fn ticks(&self, max_n: usize) -> Vec<f64> {
        RangedCoordf64::from(self.lo..self.hi).key_points(max_n)
    }

    /// Fraction of the way from `lo` to `hi` (0 at `lo`, 1 at `hi`).
    pub fn frac(&self, v: f64) -> f64 {
        (v - self.lo) / (self.hi - self.lo)
    }

    /// Whether a plotted value lies inside the axis interval.
    pub fn contains(&self, v: f64) -> bool {
        v >= self.lo && v <= self.hi
    }

    /// Axis title with the factored-out power of ten appended, e.g. `"a (m) [×10⁻³]"`.
    pub fn title(&self, label: &str) -> String {
        if self.exp == 0 {
            label.to_string()
        } else {
            format!("{label} [×10{}]", superscript(self.exp))
        }
    }
}

/// Engineering exponent (multiple of 3) for magnitudes outside `[0.01, 10⁴)`, else 0.
fn engineering_exponent(mag: f64) -> i32 {
    if !(mag.is_finite() && mag > 0.0) {
        return 0;
    }
    let e = mag.log10().floor() as i32;
    if (-2..=3).contains(&e) {
        0
    } else {
        (3 * e.div_euclid(3)).clamp(-300, 300)
    }
}

fn superscript(n: i32) -> String {
    n.to_string()
        .chars()
        .map(|c| match c {
            '-' => '⁻',
            '0' => '⁰',
            '1' => '¹',
            '2' => '²',
            '3' => '³',
            '4' => '⁴',
            '5' => '⁵',
            '6' => '⁶',
            '7' => '⁷',
            '8' => '⁸',
            _ => '⁹',
        })
        .collect()
}

/// Smallest number of decimals (≤ 8) that represents every tick exactly
/// enough, so all labels on an axis share one precision.
pub(crate) fn tick_decimals(ticks: &[f64]) -> usize {
    let step = ticks
        .windows(2)
        .map(|w| (w[1] - w[0]).abs())
        .filter(|d| *d > 0.0)
        .fold(f64::INFINITY, f64::min);
    let tol = if step.is_finite() { step * 1e-3 } else { 1e-9 };
    (0..=8)
        .find(|&d| {
            let p = 10f64.powi(d);
            ticks.iter().all(|t| ((t * p).round() / p - t).abs() <= tol)
        })
        .unwrap_or(8) as usize
}

/// Format a tick value with a fixed number of decimals (never prints `-0`).
pub(crate) fn format_tick(v: f64, decimals: usize) -> String {
    let p = 10f64.powi(decimals as i32);
    let v = if (v * p).round() == 0.0 { 0.0 } else { v };
    format!("{v:.decimals$}")
}

/// Format a stand-alone value with about four significant digits; scientific
/// notation for magnitudes outside `[10⁻³, 10⁵)`.
pub(crate) fn format_value(v: f64) -> String {
    let a = v.abs();
    if !v.is_finite() || a == 0.0 {
        return if v.is_finite() {
            "0".into()
        } else {
            v.to_string()
        };
    }
    if (1e-3..1e5).contains(&a) {
        let d = (3 - a.log10().floor() as i32).clamp(0, 8) as usize;
        trim_zeros(&format!("{v:.d$}"))
    } else {
        let s = format!("{v:.3e}");
        match s.split_once('e') {
            Some((m, e)) => format!("{}e{e}", trim_zeros(m)),
            None => s,
        }
    }
}

fn trim_zeros(s: &str) -> String {
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s.to_string()
    }
}

/// Rough rendered width in pixels of `text` at font size `px` (sans-serif).
pub(crate) fn text_width(text: &str, px: f64) -> f64 {
    text.chars().count() as f64 * 0.58 * px
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn degenerate_and_scaled_axes() {
        let a = Axis::resolve(None, Some((5.0, 5.0)));
        assert!((a.lo - 4.5).abs() < 1e-12 && (a.hi - 5.5).abs() < 1e-12);
        let z = Axis::resolve(None, Some((0.0, 0.0)));
        assert_eq!((z.lo, z.hi), (-1.0, 1.0));
        let s = Axis::resolve(Some((0.0, 0.008)), None);
        assert_eq!((s.exp, s.lo, s.hi), (-3, 0.0, 8.0));
        assert_eq!(s.title("a (m)"), "a (m) [×10⁻³]");
        let r = Axis::resolve(Some((3.0, 1.0)), Some((0.0, 9.0)));
        assert_eq!((r.lo, r.hi), (1.0, 3.0));
        let inf = Axis::resolve(Some((f64::NEG_INFINITY, 1.0)), None);
        assert!(inf.hi > inf.lo);
        let huge = Axis::resolve(None, Some((-f64::MAX, f64::MAX)));
        assert!(huge.hi > huge.lo && huge.ticks(5).len() > 1);
    }

    #[test]
    fn number_formatting() {
        assert_eq!(tick_decimals(&[0.0, 0.25, 0.5]), 2);
        assert_eq!(tick_decimals(&[100.0, 150.0, 200.0]), 0);
        assert_eq!(format_tick(-1e-17, 1), "0.0");
        assert_eq!(format_value(184.3), "184.3");
        assert_eq!(format_value(0.007_123_4), "0.007123");
        assert_eq!(format_value(1.2e-5), "1.2e-5");
        assert_eq!(format_value(300.0), "300");
    }
}
