//! A figure that could not be drawn becomes an SVG that says why, in words: the computation
//! that produced its numbers has finished and its files are written, so a figure never turns
//! it into a failure.

use super::svg::{Doc, LABEL_PX, TITLE_PX};
use super::PlotError;

/// What became of a figure file: its SVG, and why it is empty when it could not be drawn.
#[derive(Clone, Debug, PartialEq)]
pub struct Drawing {
    /// the SVG document (the figure, or the note)
    pub svg: String,
    /// why the figure is empty (`None`: drawn)
    pub empty: Option<String>,
}

/// Words of `text` in lines of at most `width` characters.
fn wrap(text: &str, width: usize) -> Vec<String> {
    let mut lines = vec![String::new()];
    for word in text.split_whitespace() {
        let last = lines.last_mut().expect("one line at least");
        if !last.is_empty() && last.chars().count() + 1 + word.chars().count() > width {
            lines.push(word.to_string());
        } else {
            if !last.is_empty() {
                last.push(' ');
            }
            last.push_str(word);
        }
    }
    lines
}

/// An SVG of `width`×`height` px saying that `file` has nothing to draw, why, and where the
/// numbers are.
pub fn note_svg(file: &str, why: &str, numbers: &str, width: u32, height: u32) -> String {
    let (w, h) = (f64::from(width.max(300)), f64::from(height.max(200)));
    let mut doc = Doc::new(w, h, "");
    doc.rect((1.0, 1.0), (w - 1.0, h - 1.0), "#ffffff", Some("#999999"));
    doc.text(
        w / 2.0,
        60.0,
        TITLE_PX,
        "middle",
        0.0,
        &format!("{file}: nothing to draw"),
    );
    let chars = ((w - 80.0) / (0.55 * LABEL_PX)).max(20.0) as usize;
    let mut y = 100.0;
    for para in [why, numbers] {
        for line in wrap(para, chars) {
            doc.text(40.0, y, LABEL_PX, "start", 0.0, &line);
            y += 1.5 * LABEL_PX;
        }
        y += LABEL_PX;
    }
    doc.finish()
}

/// The figure's SVG, or (when rendering failed) a note of the same size saying why and that
/// `numbers` holds the results.
pub fn drawing(
    file: &str,
    rendered: Result<String, PlotError>,
    numbers: &str,
    size: (u32, u32),
) -> Drawing {
    match rendered {
        Ok(svg) => Drawing { svg, empty: None },
        Err(e) => {
            let why = format!("The figure could not be drawn: {e}.");
            let where_ = format!("The computation finished; its numbers are in {numbers}.");
            Drawing {
                svg: note_svg(file, &why, &where_, size.0, size.1),
                empty: Some(e.to_string()),
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_failed_figure_becomes_a_note_naming_the_reason_and_the_numbers() {
        let d = drawing(
            "damping.svg",
            Err(PlotError::Empty {
                title: "least damping".into(),
            }),
            "spectrum.csv & linear.json",
            (900, 600),
        );
        assert_eq!(
            d.empty.as_deref(),
            Some("figure \"least damping\" has no data points")
        );
        assert!(d.svg.starts_with("<svg") && d.svg.trim_end().ends_with("</svg>"));
        assert!(d.svg.contains("damping.svg: nothing to draw"));
        assert!(d.svg.contains("has no data points"));
        assert!(d.svg.contains("spectrum.csv &amp; linear.json"), "escaped");
        let ok = drawing("a.svg", Ok("<svg/>".into()), "a.csv", (900, 600));
        assert_eq!(
            ok,
            Drawing {
                svg: "<svg/>".into(),
                empty: None
            }
        );
    }

    #[test]
    fn long_reasons_wrap_inside_the_width() {
        let words = "word ".repeat(100);
        let lines = wrap(&words, 30);
        assert!(lines.len() > 10 && lines.iter().all(|l| l.len() <= 30));
        assert_eq!(lines.join(" ").split_whitespace().count(), 100);
    }
}
