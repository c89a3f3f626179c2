//! A reader's check of a drawn figure: does a legend box hide anything?
//!
//! This reads the SVG text that the plot code wrote, not the geometry the placement used, so
//! that it judges the result as a viewer would see it: every legend box (the white, 90 %
//! opaque rectangle of a [`super::Figure`] panel) against every data mark drawn before it
//! (polylines, circles and polygons other than grid lines and shaded regions), every
//! reference line's label box, and every text of the figure that is not the legend's own.

use super::geom::Rect;

/// One SVG element as the plot code writes it: its tag, attributes and text content.
struct Element<'a> {
    tag: &'a str,
    attrs: Vec<(&'a str, &'a str)>,
    text: &'a str,
}

impl Element<'_> {
    fn attr(&self, name: &str) -> Option<&str> {
        self.attrs.iter().find(|(k, _)| *k == name).map(|(_, v)| *v)
    }

    fn num(&self, name: &str) -> Option<f64> {
        self.attr(name).and_then(|v| v.trim().parse().ok())
    }

    fn rect(&self) -> Option<Rect> {
        let (x, y) = (self.num("x")?, self.num("y")?);
        let (w, h) = (self.num("width")?, self.num("height")?);
        Some(Rect {
            x0: x,
            x1: x + w,
            y0: y,
            y1: y + h,
        })
    }

    fn points(&self) -> Vec<(f64, f64)> {
        self.attr("points")
            .unwrap_or("")
            .split_whitespace()
            .filter_map(|p| {
                let (x, y) = p.split_once(',')?;
                Some((x.parse().ok()?, y.parse().ok()?))
            })
            .collect()
    }

    fn is_white(&self, opacity: &str) -> bool {
        self.tag == "rect"
            && self.attr("opacity") == Some(opacity)
            && self
                .attr("fill")
                .is_some_and(|f| f.eq_ignore_ascii_case("#FFFFFF"))
    }
}

/// The elements of `svg` in drawing order (a tolerant reader of the subset plotters and
/// the hand-written writer emit: no nesting beyond `<text>` content).
fn elements(svg: &str) -> Vec<Element<'_>> {
    let mut out = Vec::new();
    let mut rest = svg;
    while let Some(start) = rest.find('<') {
        rest = &rest[start + 1..];
        let Some(end) = rest.find('>') else { break };
        let head = &rest[..end];
        rest = &rest[end + 1..];
        if head.starts_with('/') || head.starts_with('?') || head.starts_with('!') {
            continue;
        }
        let head = head.trim_end_matches('/');
        let (tag, body) = head.split_once(char::is_whitespace).unwrap_or((head, ""));
        let text = if tag == "text" {
            let close = rest.find("</text>").unwrap_or(0);
            let t = rest[..close].trim();
            rest = &rest[close..];
            t
        } else {
            ""
        };
        out.push(Element {
            tag,
            attrs: attributes(body),
            text,
        });
    }
    out
}

/// `name="value"` pairs of a start tag's body.
fn attributes(mut body: &str) -> Vec<(&str, &str)> {
    let mut out = Vec::new();
    while let Some(eq) = body.find("=\"") {
        let name = body[..eq].trim();
        let after = &body[eq + 2..];
        let Some(close) = after.find('"') else { break };
        out.push((name, &after[..close]));
        body = &after[close + 1..];
    }
    out
}

/// The box a text covers, estimated from its anchor, size and length (the plot code's own
/// width estimate is not used, so that a wrong estimate there shows here). `None` for
/// rotated text (the y-axis title, which lies outside every plot area).
fn text_box(e: &Element) -> Option<Rect> {
    if e.attr("transform").is_some() || e.text.is_empty() {
        return None;
    }
    let (x, y, size) = (e.num("x")?, e.num("y")?, e.num("font-size")?);
    let w = 0.55 * size * e.text.chars().count() as f64;
    let x0 = match e.attr("text-anchor") {
        Some("middle") => x - w / 2.0,
        Some("end") => x - w,
        _ => x,
    };
    // plotters places text by `dy`: 0.76em puts the top at y, -0.5ex the baseline near y
    // plus half an x-height; the hand-written writer uses baselines. Take the union.
    let (y0, y1) = match e.attr("dy") {
        Some(d) if d.starts_with("0.76") => (y, y + size),
        Some(d) if d.starts_with("-0.5") => (y - size, y + 0.25 * size),
        _ => (y - 0.8 * size, y + 0.25 * size),
    };
    Some(Rect {
        x0,
        x1: x0 + w,
        y0,
        y1,
    })
}

/// Whether segment `a`–`b` meets the rectangle `r`.
fn segment_meets(r: &Rect, a: (f64, f64), b: (f64, f64)) -> bool {
    if r.contains(a) || r.contains(b) {
        return true;
    }
    let steps = ((b.0 - a.0).abs().max((b.1 - a.1).abs()) / 0.5)
        .ceil()
        .max(1.0) as usize;
    (1..steps).any(|k| {
        let t = k as f64 / steps as f64;
        r.contains((a.0 + t * (b.0 - a.0), a.1 + t * (b.1 - a.1)))
    })
}

/// A grid line, an axis, a tick mark or a region's fill: not a data mark.
fn is_furniture(e: &Element) -> bool {
    let stroke = e.attr("stroke").unwrap_or("").to_ascii_uppercase();
    let grid = ["#E3E3E3", "#DDDDDD", "#E6E6E6", "#EEEEEE"].contains(&stroke.as_str());
    let region = e.tag == "polygon" && e.num("opacity").is_some_and(|o| o < 0.5);
    grid || region
}

/// Everything a legend box in `svg` hides: data marks, reference-line labels and texts that
/// are not its own, each described in words. Empty when every legend leaves the data free.
pub fn legend_clashes(svg: &str) -> Vec<String> {
    let els = elements(svg);
    let mut found = Vec::new();
    for (k, legend) in els.iter().enumerate() {
        if !legend.is_white("0.9") {
            continue;
        }
        let Some(r) = legend.rect() else { continue };
        // A hair inside the box, so that a mark touching its border from outside is no clash.
        let inner = Rect {
            x0: r.x0 + 1.0,
            x1: r.x1 - 1.0,
            y0: r.y0 + 1.0,
            y1: r.y1 - 1.0,
        };
        let what = |e: &Element| match e.tag {
            "circle" => format!(
                "a point at ({}, {})",
                e.attr("cx").unwrap_or("?"),
                e.attr("cy").unwrap_or("?")
            ),
            "text" => format!("the text \"{}\"", e.text),
            "rect" => "a reference line's label".to_string(),
            t => format!(
                "a {t} in {}",
                e.attr("stroke").or(e.attr("fill")).unwrap_or("?")
            ),
        };
        for e in &els[..k] {
            let hit = match e.tag {
                "polyline" | "polygon" if !is_furniture(e) => {
                    let p = e.points();
                    let closing = match (p.first(), p.last()) {
                        (Some(a), Some(b)) if e.tag == "polygon" => Some((*b, *a)),
                        _ => None,
                    };
                    p.windows(2)
                        .map(|w| (w[0], w[1]))
                        .chain(closing)
                        .any(|(a, b)| segment_meets(&inner, a, b))
                        || (p.len() == 1 && inner.contains(p[0]))
                }
                "circle" => match (e.num("cx"), e.num("cy"), e.num("r")) {
                    (Some(x), Some(y), Some(rad)) => inner.overlaps(&Rect {
                        x0: x - rad,
                        x1: x + rad,
                        y0: y - rad,
                        y1: y + rad,
                    }),
                    _ => false,
                },
                "rect" if e.is_white("0.85") => e.rect().is_some_and(|b| b.overlaps(&inner)),
                "text" => text_box(e).is_some_and(|b| b.overlaps(&inner)),
                _ => false,
            };
            if hit {
                found.push(format!("the legend at {r:?} hides {}", what(e)));
            }
        }
        // Texts drawn later that are not the legend's own entries (those start inside it).
        for e in els[k + 1..].iter().filter(|e| e.tag == "text") {
            let own = e.num("x").zip(e.num("y")).is_some_and(|p| r.contains(p));
            if !own && text_box(e).is_some_and(|b| b.overlaps(&inner)) {
                found.push(format!("the legend at {r:?} hides {}", what(e)));
            }
        }
    }
    found
}

/// How many legend boxes `svg` draws (for tests that must know one was checked).
pub fn legend_count(svg: &str) -> usize {
    elements(svg).iter().filter(|e| e.is_white("0.9")).count()
}

#[cfg(test)]
mod tests {
    use super::*;

    const LEGEND: &str = r##"<rect x="100" y="100" width="200" height="80" opacity="0.9" fill="#FFFFFF" stroke="none"/>"##;

    #[test]
    fn a_line_through_the_legend_is_a_clash_and_one_beside_it_is_not() {
        let through = format!(
            r##"<polyline fill="none" stroke="#0072B2" points="50,150 400,150"/>{LEGEND}"##
        );
        assert_eq!(legend_clashes(&through).len(), 1);
        let beside = format!(
            r##"<polyline fill="none" stroke="#0072B2" points="50,190 400,190"/>{LEGEND}"##
        );
        assert!(legend_clashes(&beside).is_empty());
        // a long segment crossing the box with both ends outside
        let crossing =
            format!(r##"<polyline fill="none" stroke="#0072B2" points="200,0 200,400"/>{LEGEND}"##);
        assert_eq!(legend_clashes(&crossing).len(), 1);
    }

    #[test]
    fn grid_lines_regions_and_marks_drawn_after_the_legend_are_not_clashes() {
        let svg = format!(
            r##"<polyline stroke="#E3E3E3" points="0,150 400,150"/><polygon opacity="0.16" fill="#2CA02C" points="0,0 400,0 400,400"/>{LEGEND}<circle cx="120" cy="120" r="5" fill="#000000"/><text x="150" y="120" font-size="20">entry</text>"##
        );
        assert!(
            legend_clashes(&svg).is_empty(),
            "{:?}",
            legend_clashes(&svg)
        );
        assert_eq!(legend_count(&svg), 1);
    }

    #[test]
    fn points_labels_and_texts_under_the_legend_are_clashes() {
        let svg = format!(
            r##"<circle cx="95" cy="140" r="10" fill="#000000"/><rect x="250" y="90" width="100" height="20" opacity="0.85" fill="#FFFFFF"/><text x="50" y="170" dy="0.76em" font-size="20">speed V (m/s)</text>{LEGEND}"##
        );
        assert_eq!(legend_clashes(&svg).len(), 3, "{:?}", legend_clashes(&svg));
    }
}
