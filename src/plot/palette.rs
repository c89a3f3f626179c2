//! Fixed colours: the Okabe–Ito qualitative palette for series and a hand-coded
//! viridis-like sequential scale for value-coloured points.

use plotters::style::RGBColor;

/// Okabe–Ito palette, reordered so that the low-contrast yellow comes last.
const OKABE_ITO: [RGBColor; 8] = [
    RGBColor(0x00, 0x72, 0xB2), // blue
    RGBColor(0xD5, 0x5E, 0x00), // vermillion
    RGBColor(0x00, 0x9E, 0x73), // bluish green
    RGBColor(0xCC, 0x79, 0xA7), // reddish purple
    RGBColor(0xE6, 0x9F, 0x00), // orange
    RGBColor(0x56, 0xB4, 0xE9), // sky blue
    RGBColor(0x00, 0x00, 0x00), // black
    RGBColor(0xF0, 0xE4, 0x42), // yellow
];

/// Nine evenly spaced stops of the viridis colour map (matplotlib).
const VIRIDIS: [(u8, u8, u8); 9] = [
    (0x44, 0x01, 0x54),
    (0x47, 0x2C, 0x7A),
    (0x3B, 0x52, 0x8B),
    (0x2C, 0x72, 0x8E),
    (0x21, 0x91, 0x8C),
    (0x28, 0xAE, 0x80),
    (0x5E, 0xC9, 0x62),
    (0xAD, 0xDC, 0x30),
    (0xFD, 0xE7, 0x25),
];

/// Grid line colour.
pub(crate) const GRID: RGBColor = RGBColor(0xE3, 0xE3, 0xE3);
/// Axis and frame colour.
pub(crate) const AXIS: RGBColor = RGBColor(0x55, 0x55, 0x55);
/// Main text colour.
pub(crate) const TEXT: RGBColor = RGBColor(0x22, 0x22, 0x22);
/// Reference-line colour.
pub(crate) const MARKER: RGBColor = RGBColor(0x66, 0x66, 0x66);
/// Colour for points whose colour value is missing or not finite.
pub(crate) const MISSING: RGBColor = RGBColor(0xA0, 0xA0, 0xA0);
/// Plain white.
pub(crate) const WHITE: RGBColor = RGBColor(0xFF, 0xFF, 0xFF);

/// Colour of the `i`-th ordinary series (cycles through the palette).
pub(crate) fn series_colour(i: usize) -> RGBColor {
    OKABE_ITO[i % OKABE_ITO.len()]
}

/// Viridis colour at `t` in `[0, 1]` (clamped; NaN maps to [`MISSING`]).
pub(crate) fn viridis(t: f64) -> RGBColor {
    if !t.is_finite() {
        return MISSING;
    }
    let pos = t.clamp(0.0, 1.0) * (VIRIDIS.len() - 1) as f64;
    let i = (pos.floor() as usize).min(VIRIDIS.len() - 2);
    let f = pos - i as f64;
    let (a, b) = (VIRIDIS[i], VIRIDIS[i + 1]);
    let mix = |p: u8, q: u8| (f64::from(p) + (f64::from(q) - f64::from(p)) * f).round() as u8;
    RGBColor(mix(a.0, b.0), mix(a.1, b.1), mix(a.2, b.2))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn viridis_endpoints_and_clamping() {
        assert_eq!(viridis(0.0), RGBColor(0x44, 0x01, 0x54));
        assert_eq!(viridis(1.0), RGBColor(0xFD, 0xE7, 0x25));
        assert_eq!(viridis(7.0), viridis(1.0));
        assert_eq!(viridis(-3.0), viridis(0.0));
        assert_eq!(viridis(f64::NAN), MISSING);
        assert_eq!(series_colour(8), series_colour(0));
    }
}
