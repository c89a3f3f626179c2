//! Results to [`crate::plot::Figure`]s: what each SVG shows. Sees results, never the model.

use crate::analysis::{GeometryReport, LinearReport};
use crate::plot::{render_grid, render_svg, Figure, Marker, PlotError, Series, Style};
use crate::stability::{CriticalSpeeds, Spectrum};

fn figure(title: &str, x_label: &str, y_label: &str) -> Figure {
    Figure {
        title: title.into(),
        x_label: x_label.into(),
        y_label: y_label.into(),
        series: Vec::new(),
        vlines: Vec::new(),
        hlines: Vec::new(),
        x_range: None,
        y_range: None,
    }
}

fn crossing_markers(c: &CriticalSpeeds, symbol: &str) -> Vec<Marker> {
    c.crossings
        .iter()
        .map(|x| Marker {
            at: x.speed_m_s,
            label: format!("{symbol} {} {:.2} m/s", x.direction.name(), x.speed_m_s),
        })
        .collect()
}

fn root_locus_series(name: &str, spectra: &[Spectrum]) -> Series {
    let mut points = Vec::new();
    let mut values = Vec::new();
    for sp in spectra {
        // oscillatory modes only: the real (creep-damped) modes reach −10⁴ 1/s at low speed
        for p in sp.pairs.iter().filter(|p| p.im > 0.0) {
            points.push((p.re, p.im / (2.0 * std::f64::consts::PI)));
            values.push(sp.speed_m_s);
        }
    }
    Series {
        name: name.into(),
        points,
        style: Style::PointsColoured {
            values,
            label: "speed (m/s)".into(),
        },
    }
}

fn damping_series(name: &str, spectra: &[Spectrum], dashed: bool) -> Series {
    Series {
        name: name.into(),
        points: spectra
            .iter()
            .map(|s| (s.speed_m_s, s.least_damping_ratio()))
            .collect(),
        style: Style::Line { dashed },
    }
}

/// `root_locus.svg` and `damping.svg`.
pub fn linear(r: &LinearReport) -> Result<Vec<(String, String)>, PlotError> {
    let mut locus = figure(
        &format!(
            "{}: root locus of the oscillatory modes (Kalker creep; real modes off scale)",
            r.study
        ),
        "real part (1/s)",
        "frequency Im/2π (Hz)",
    );
    let series = root_locus_series("", &r.spectrum_kalker);
    // Show the real parts from the 5 % quantile up to the largest: at the lowest speeds the
    // oscillatory modes too are damped by creep ∝ 1/V and would squash the interesting part.
    let mut re: Vec<f64> = series
        .points
        .iter()
        .map(|p| p.0)
        .filter(|x| x.is_finite())
        .collect();
    re.sort_by(f64::total_cmp);
    if let (Some(&lo), Some(&hi)) = (re.get(re.len() / 20), re.last()) {
        let hi = hi.max(0.0);
        let pad = 0.05 * (hi - lo).max(1e-9);
        locus.x_range = Some((lo - pad, hi + pad));
    }
    locus.series.push(series);
    locus.vlines.push(Marker {
        at: 0.0,
        label: "stability boundary".into(),
    });
    let mut damping = figure(
        &format!("{}: least damping ratio of the centred motion", r.study),
        "speed (m/s)",
        "least damping ratio ζ (–)",
    );
    damping
        .series
        .push(damping_series("Kalker (linear)", &r.spectrum_kalker, false));
    if let Some(c) = &r.creep_law {
        damping.series.push(damping_series(
            &format!("{} (own Jacobian)", c.law.name()),
            &r.spectrum_creep_law,
            true,
        ));
        damping.vlines.extend(crossing_markers(c, "V_H"));
    }
    damping.vlines.extend(crossing_markers(&r.kalker, "V_L"));
    damping.hlines.push(Marker {
        at: 0.0,
        label: "ζ = 0".into(),
    });
    Ok(vec![
        ("root_locus.svg".into(), render_svg(&locus, 900, 650)?),
        ("damping.svg".into(), render_svg(&damping, 900, 600)?),
    ])
}

fn line(name: &str, points: Vec<(f64, f64)>, dashed: bool) -> Series {
    Series {
        name: name.into(),
        points,
        style: Style::Line { dashed },
    }
}

/// `geometry.svg`: rolling-radius difference, contact angles, roll, and the centred Hertz
/// ellipse (the seed's Figs. 6, 5 and 8), lengths in mm.
pub fn geometry(g: &GeometryReport) -> Result<String, PlotError> {
    let n = g.rows.len();
    let ymm = |k: usize| g.rows[k].y * 1e3;
    let mut dr = figure(
        "rolling-radius difference",
        "lateral displacement y (mm)",
        "r_R − r_L (mm)",
    );
    dr.series.push(line(
        "",
        (0..n)
            .map(|k| {
                (
                    ymm(k),
                    (g.rows[k].point.radius - g.rows[n - 1 - k].point.radius) * 1e3,
                )
            })
            .collect(),
        false,
    ));
    let mut angle = figure(
        "contact angles",
        "lateral displacement y (mm)",
        "contact angle (rad)",
    );
    angle.series.push(line(
        "right δ_R",
        (0..n).map(|k| (ymm(k), g.rows[k].point.angle)).collect(),
        false,
    ));
    angle.series.push(line(
        "left δ_L",
        (0..n)
            .map(|k| (ymm(k), g.rows[n - 1 - k].point.angle))
            .collect(),
        true,
    ));
    let mut roll = figure(
        "wheelset roll",
        "lateral displacement y (mm)",
        "roll φ (mrad)",
    );
    roll.series.push(line(
        "",
        (0..n)
            .map(|k| (ymm(k), g.rows[k].point.roll * 1e3))
            .collect(),
        false,
    ));
    let mut panels = vec![dr, angle, roll];
    if let Some((a, b)) = g.rows.get(n / 2).and_then(|r| r.semi_axes) {
        let mut ellipse = figure(
            &format!(
                "Hertz patch at y = 0: a = {:.3} mm, b = {:.3} mm",
                a * 1e3,
                b * 1e3
            ),
            "rolling direction x (mm)",
            "lateral (mm)",
        );
        let pts = (0..=120)
            .map(|i| {
                let t = i as f64 / 120.0 * std::f64::consts::TAU;
                (a * 1e3 * t.cos(), b * 1e3 * t.sin())
            })
            .collect();
        ellipse.series.push(line("", pts, false));
        let r = a.max(b) * 1e3 * 1.15;
        ellipse.x_range = Some((-r, r));
        ellipse.y_range = Some((-r, r));
        panels.push(ellipse);
    }
    render_grid(&panels, 2, 1200, 900)
}
