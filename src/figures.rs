//! Results to [`crate::plot::Figure`]s: what each SVG shows. Sees results, never the model.

mod curve;
mod sweep;
mod trade;
mod uncertainty;

pub use curve::curve;
pub use sweep::{sweep, sweep_map, sweep_with_curves, HeatMap};
pub use trade::trade_curve;
pub use uncertainty::uncertainty;

use crate::analysis::{GeometryReport, LinearReport};
use crate::plot::{render_grid, render_svg, Figure, Marker, PlotError, Series, Style};
use crate::stability::{CriticalSpeeds, Spectrum};

/// A figure file: its name, its size (px) and its SVG, or why it could not be rendered (the
/// caller writes a note in its place: [`crate::plot::drawing`]).
#[derive(Debug)]
pub struct Rendered {
    /// file name, e.g. `damping.svg`
    pub file: String,
    /// width and height (px)
    pub size: (u32, u32),
    /// the SVG, or the reason it could not be drawn
    pub svg: Result<String, PlotError>,
}

fn render(file: &str, fig: &Figure, width: u32, height: u32) -> Rendered {
    Rendered {
        file: file.into(),
        size: (width, height),
        svg: render_svg(fig, width, height),
    }
}

fn render_panels(file: &str, figs: &[Figure], cols: usize, width: u32, height: u32) -> Rendered {
    Rendered {
        file: file.into(),
        size: (width, height),
        svg: render_grid(figs, cols, width, height),
    }
}

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
        x_log: false,
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
pub fn linear(r: &LinearReport) -> Vec<Rendered> {
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
    vec![
        render("root_locus.svg", &locus, 900, 650),
        render("damping.svg", &damping, 900, 600),
    ]
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
pub fn geometry(g: &GeometryReport) -> Rendered {
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
    render_panels("geometry.svg", &panels, 2, 1200, 900)
}

/// The runs of equal stability along the cycles of one branch, as (stable, points) with each
/// run overlapping the next by one point so that they join.
fn stability_runs(cycles: &[&crate::bifurcation::CycleRow]) -> Vec<(bool, Vec<(f64, f64)>)> {
    let mut out = Vec::new();
    let mut start = 0;
    for k in 1..=cycles.len() {
        if k == cycles.len() || cycles[k].stable != cycles[start].stable {
            let end = (k + 1).min(cycles.len());
            let pts = cycles[start..end]
                .iter()
                .map(|c| (c.speed_m_s, c.wheelset_amplitude_m * 1e3))
                .collect();
            out.push((cycles[start].stable, pts));
            start = k;
        }
    }
    out
}

/// `bifurcation.svg`: lateral amplitude against speed, every branch in the colour of its kind
/// (symmetric, asymmetric, period-2, …), stable cycles solid, unstable dashed, the centred
/// solution along the axis, the special points by kind, Hopf, Kalker and V_NL marked.
pub fn bifurcation(r: &crate::bifurcation::BifurcationReport) -> Rendered {
    let mut fig = bifurcation_figure(r);
    headroom(&mut fig);
    hunting_regions(&mut fig, r);
    let h = diagram_height(650, &fig);
    render("bifurcation.svg", &fig, 1000, h)
}

/// `attractors.svg`: every attractor the search found, amplitude (the leading wheelset's max
/// |y|) against speed along its descent, drawn over the continued branches, with the speeds
/// where each dies and V_NL marked.
pub fn attractors(
    r: &crate::attractors::AttractorReport,
    b: &crate::bifurcation::BifurcationReport,
) -> Rendered {
    let mut fig = bifurcation_figure(b);
    fig.title = format!("{}: attractors over the continued branches", r.study);
    for a in &r.attractors {
        let dies = a.dies_m_s.map_or(String::new(), |d| {
            let open = if a.open_below { ", open below" } else { "" };
            format!(", dies in [{:.2}, {:.2}] m/s{open}", d.0, d.1)
        });
        use crate::attractors::MotionKind as M;
        // an attractor in its kind's colour (the branches' colours for cycles)
        let colour = match a.kind {
            M::SymmetricCycle => 0,
            M::AsymmetricCycle => 1,
            M::PeriodK(_) => 2,
            M::QuasiPeriodic => 4,
            _ => 5,
        };
        fig.series.push(Series {
            name: format!("attractor {}: {}{dies}", a.id, a.kind.name()),
            points: a
                .path
                .iter()
                .map(|m| (m.speed_m_s, m.amplitude_m() * 1e3))
                .collect(),
            style: Style::PointsIn {
                colour,
                crosses: false,
            },
        });
    }
    headroom(&mut fig);
    hunting_regions(&mut fig, b);
    let h = diagram_height(700, &fig);
    render("attractors.svg", &fig, 1100, h)
}

/// The speeds where the vehicle can hunt, shaded under the diagram's data over its whole
/// height (after [`headroom`] has fixed it), in the colours of the curves' regions
/// (`curve.svg`): from V_NL to the Hopf speed the centred motion is stable to small
/// disturbances but a large enough one starts hunting (amber), above the Hopf speed it is
/// unstable (red). Below V_NL nothing is shaded: the diagram's V_NL is the lowest hunting
/// motion its methods found, not a proof that none lives lower. The centred line's own
/// legend says "linearly stable", so no part of the picture calls a speed where a motion
/// hunts stable.
/// The colours of the speed regions, the same in every picture: green where no hunting was
/// found (below V_NL), amber where the vehicle hunts after a disturbance (V_NL to V_H), red
/// where it hunts from any disturbance (above V_H).
const NO_HUNTING: Style = Style::ShadeRgb(0x2c, 0xa0, 0x2c);
/// … amber: hunts if disturbed.
const HUNTS_IF_DISTURBED: Style = Style::ShadeRgb(0xff, 0xb0, 0x00);
/// … red: hunts.
const HUNTS: Style = Style::ShadeRgb(0xd6, 0x27, 0x28);

fn hunting_regions(fig: &mut Figure, r: &crate::bifurcation::BifurcationReport) {
    let Some((y0, y1)) = fig.y_range else {
        return;
    };
    let (lo, hi) = r.speed_range;
    let v_h = r.hopf.map(|h| h.speed_m_s).filter(|v| v.is_finite());
    let v_nl = r
        .nonlinear_critical_speed
        .map(|v| v.0)
        .filter(|v| v.is_finite());
    let band = |a: f64, b: f64| vec![(a, y0), (b, y0), (b, y1), (a, y1)];
    let mut shades = Vec::new();
    if let Some(v) = v_nl {
        let top = v_h.unwrap_or(hi).min(hi);
        if v < top {
            shades.push(Series {
                name: "hunts if disturbed (V_NL–V_H)".into(),
                points: band(v.max(lo), top),
                style: HUNTS_IF_DISTURBED,
            });
        }
    }
    if let Some(v) = v_h.filter(|&v| v < hi) {
        shades.push(Series {
            name: "hunts (above V_H)".into(),
            points: band(v.max(lo), hi),
            style: HUNTS,
        });
    }
    // drawn first, under the branches
    fig.series.splice(0..0, shades);
}

/// The canvas height of a diagram: `base` up to 8 legend entries, 32 px more for each further
/// one, so that a legend that goes below the plot (a car's search lists a dozen attractors)
/// takes its room from a taller canvas, not from the plot.
fn diagram_height(base: u32, fig: &Figure) -> u32 {
    let entries = fig.series.iter().filter(|s| !s.name.is_empty()).count();
    let extra = u32::try_from(entries.saturating_sub(8)).unwrap_or(u32::MAX / 64);
    base.saturating_add(32 * extra.min(100))
}

/// Room above the data for the legend: the y range from just below 0 to well above the largest
/// amplitude drawn, so that the legend sits above the branches instead of on them.
fn headroom(fig: &mut Figure) {
    let top = fig
        .series
        .iter()
        .flat_map(|s| s.points.iter().map(|p| p.1))
        .filter(|v| v.is_finite())
        .fold(0.0, f64::max);
    if top > 0.0 {
        fig.y_range = Some((-0.04 * top * 2.8, top * 2.8));
    }
}

fn bifurcation_figure(r: &crate::bifurcation::BifurcationReport) -> Figure {
    use crate::bifurcation::BranchKind;
    let mut fig = figure(
        &format!("{}: hunting limit cycles ({} creep)", r.study, r.law.name()),
        "speed V (m/s)",
        if r.state_names.len() > 4 {
            "largest wheelset's lateral amplitude max|y| (mm)"
        } else {
            "lateral amplitude max|y| (mm)"
        },
    );
    let colour = |k: BranchKind| match k {
        BranchKind::Symmetric => 0,
        BranchKind::Asymmetric => 1,
        BranchKind::Period(2) => 2,
        BranchKind::Period(_) => 3,
    };
    // one series per kind and stability; branches separated by a NaN point (a gap)
    let mut kinds: Vec<BranchKind> = Vec::new();
    for b in &r.branches {
        if !kinds.contains(&b.kind) {
            kinds.push(b.kind);
        }
    }
    if r.branches.is_empty() && !r.cycles.is_empty() {
        kinds.push(BranchKind::Symmetric);
    }
    for kind in kinds {
        let mut lines: [Vec<(f64, f64)>; 2] = [Vec::new(), Vec::new()];
        let ids: Vec<usize> = r
            .branches
            .iter()
            .filter(|b| b.kind == kind)
            .map(|b| b.id)
            .collect();
        for id in ids
            .iter()
            .copied()
            .chain(r.branches.is_empty().then_some(0))
        {
            let cycles: Vec<_> = r.cycles.iter().filter(|c| c.branch == id).collect();
            for (stable, pts) in stability_runs(&cycles) {
                let line = &mut lines[usize::from(!stable)];
                if !line.is_empty() {
                    line.push((f64::NAN, f64::NAN));
                }
                line.extend(pts);
            }
        }
        let [stable, unstable] = lines;
        let name = kind.name();
        for (pts, dashed, what) in [(stable, false, "stable"), (unstable, true, "unstable")] {
            if !pts.is_empty() {
                fig.series.push(Series {
                    name: format!("{name} cycles, {what}"),
                    points: pts,
                    style: Style::LineIn {
                        dashed,
                        colour: colour(kind),
                    },
                });
            }
        }
    }
    // the centred motion in black, along the axis
    let (lo, hi) = r.speed_range;
    let centred = |name: &str, pts: Vec<(f64, f64)>, dashed: bool| Series {
        name: name.into(),
        points: pts,
        style: Style::LineIn { dashed, colour: 6 },
    };
    match r.hopf {
        Some(h) => {
            fig.series.push(centred(
                "centred: linearly stable",
                vec![(lo, 0.0), (h.speed_m_s, 0.0)],
                false,
            ));
            fig.series.push(centred(
                "centred: linearly unstable",
                vec![(h.speed_m_s, 0.0), (hi, 0.0)],
                true,
            ));
            fig.vlines.push(Marker {
                at: h.speed_m_s,
                label: format!(
                    "Hopf ({}) {:.2} m/s",
                    r.hopf_type.map_or("?", |t| t.name()),
                    h.speed_m_s
                ),
            });
        }
        None => fig.series.push(centred(
            "centred: linearly stable",
            vec![(lo, 0.0), (hi, 0.0)],
            false,
        )),
    }
    if let Some(v) = r.kalker_critical_speed_m_s {
        fig.vlines.push(Marker {
            at: v,
            label: format!("Kalker V_L {v:.2} m/s"),
        });
    }
    // the special points, one series per kind, each listed with its speeds when there are few
    let mut kinds: Vec<crate::continuation::SpecialKind> = Vec::new();
    for s in &r.special {
        if !kinds.contains(&s.kind) {
            kinds.push(s.kind);
        }
    }
    for kind in kinds {
        let of: Vec<_> = r.special.iter().filter(|s| s.kind == kind).collect();
        let speeds: Vec<String> = of.iter().map(|s| format!("{:.2}", s.speed_m_s)).collect();
        let name = if of.len() <= 4 {
            format!(
                "{} {} m/s",
                kind.name().replace('_', " "),
                speeds.join(", ")
            )
        } else {
            format!("{} ({} points)", kind.name().replace('_', " "), of.len())
        };
        fig.series.push(Series {
            name,
            points: of
                .iter()
                .map(|s| (s.speed_m_s, s.wheelset_amplitude_m * 1e3))
                .collect(),
            style: {
                use crate::continuation::SpecialKind as K;
                // folds black dots; symmetry breaking, period doubling, torus crosses
                let (colour, crosses) = match kind {
                    K::Fold => (6, false),
                    K::SymmetryBreaking => (4, true),
                    K::PeriodDoubling => (5, true),
                    K::Torus => (3, true),
                };
                Style::PointsIn { colour, crosses }
            },
        });
    }
    if let Some((v, located)) = r.nonlinear_critical_speed {
        let how = r
            .nonlinear_sources
            .iter()
            .find(|c| (c.speed_m_s - v).abs() <= 1e-9 * v.abs().max(1.0))
            .map_or(String::new(), |c| format!(": {}", c.what));
        fig.vlines.push(Marker {
            at: v,
            label: format!(
                "V_NL {v:.2} m/s{}{how}",
                if located { "" } else { " (bracketed)" }
            ),
        });
    }
    fig
}

/// `simulate.svg`: y(t) and ψ(t) for each speed, and the y–ẏ phase portrait, of the wheelset
/// that hunts most at that speed (the largest |y| over the second half of the run: the
/// amplitude the summary prints and the diagrams plot), named in the legend on a vehicle.
pub fn simulate(study: &str, runs: &[crate::simulate::TimeHistory]) -> Rendered {
    let vehicle = runs.iter().any(|h| h.largest_wheelset().name.is_some());
    let what = if vehicle {
        "lateral displacement of the wheelset that hunts most"
    } else {
        "lateral displacement"
    };
    let mut y = figure(&format!("{study}: {what}"), "time t (s)", "y (mm)");
    let mut psi = figure("yaw angle", "time t (s)", "ψ (mrad)");
    let mut phase = figure("phase portrait", "y (mm)", "dy/dt (mm/s)");
    for h in runs {
        let w = h.largest_wheelset();
        let (iy, ipsi, iyd) = (w.y, w.psi, w.ydot);
        let name = match w.name {
            Some(w) => format!("{:.1} m/s, {w}", h.speed_m_s),
            None => format!("{:.1} m/s", h.speed_m_s),
        };
        let at = |x: &Vec<f64>, k: usize| x.get(k).copied().unwrap_or(f64::NAN);
        let pts = |k: usize, scale: f64| -> Vec<(f64, f64)> {
            h.t.iter()
                .zip(&h.x)
                .map(|(t, x)| (*t, at(x, k) * scale))
                .collect()
        };
        y.series.push(line(&name, pts(iy, 1e3), false));
        psi.series.push(line(&name, pts(ipsi, 1e3), false));
        phase.series.push(line(
            &name,
            h.x.iter()
                .map(|x| (at(x, iy) * 1e3, at(x, iyd) * 1e3))
                .collect(),
            false,
        ));
    }
    render_panels("simulate.svg", &[y, psi, phase], 1, 1100, 1300)
}

/// `ramp.svg`: the leading wheelset's peak amplitude against speed during the ramp, and the
/// EN 14363 sliding r.m.s. of the sum of guiding forces of every wheelset against its limit.
pub fn ramp(study: &str, r: &crate::simulate::RampResult) -> Rendered {
    let mut amp = figure(
        &format!("{study}: ramp at {:.4} m/s² (peaks of |y|)", r.options.rate),
        "speed V (m/s)",
        "peak lateral amplitude (mm)",
    );
    amp.series.push(Series {
        name: String::new(),
        points: r
            .envelope
            .iter()
            .map(|p| (p.speed_m_s, p.amplitude_m * 1e3))
            .collect(),
        style: Style::Points,
    });
    if let Some(v) = r.died_at_m_s {
        amp.vlines.push(Marker {
            at: v,
            label: format!("died {v:.2} m/s"),
        });
    }
    amp.hlines.push(Marker {
        at: r.options.threshold * 1e3,
        label: "threshold".into(),
    });
    let mut panels = vec![amp];
    if let Some(e) = &r.en14363 {
        let mut en = figure(
            "EN 14363: sliding rms of ΣY (f0 ± 2 Hz, 100 m)",
            "speed V (m/s)",
            "ΣY rms (kN)",
        );
        // one line per wheelset (the single wheelset's unnamed, as before)
        let named = r.en14363_wheelsets.len() > 1;
        for w in &r.en14363_wheelsets {
            en.series.push(line(
                if named { &w.name } else { "" },
                w.series
                    .iter()
                    .map(|p| (p.speed_m_s, p.rms_n / 1e3))
                    .collect(),
                false,
            ));
        }
        en.hlines.push(Marker {
            at: e.limit_n / 1e3,
            label: format!("limit {:.2} kN", e.limit_n / 1e3),
        });
        panels.push(en);
    }
    let height = 450 * panels.len() as u32;
    render_panels("ramp.svg", &panels, 1, 1000, height)
}

/// `conicity.svg`: equivalent conicity against amplitude.
pub fn conicity(name: &str, c: &[crate::conicity::Conicity]) -> Rendered {
    let mut fig = figure(
        &format!("{name}: equivalent conicity (EN 15302)"),
        "amplitude ŷ (mm)",
        "equivalent conicity tan γe (–)",
    );
    fig.series.push(line(
        "",
        c.iter()
            .map(|p| (p.amplitude_m * 1e3, p.conicity))
            .collect(),
        false,
    ));
    render("conicity.svg", &fig, 900, 600)
}
