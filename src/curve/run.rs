//! The driver: one analysis per requested [`CurveKind`], the Hopf curves of each creep law
//! started from every crossing at the seed values of the key, and the report.

use crate::contact::creep::CreepLaw;
use crate::stability::{critical_speeds, LinearOptions, LinearSystem};

use super::family::{HopfFamily, StudyFamily};
use super::hopf::{HopfParams, State};
use super::keyed::KeyedStudy;
use super::spec::CurveSpec;
use super::trace::{walk, Half, TracedPoint};
use super::{
    Curve, CurveError, CurveKind, CurvePoint, CurveReport, CurveStats, CurveStop, SpecialPoint,
    StableRegion, StableSide,
};

/// Newton's tolerance on the scaled update of the Hopf system: the points are then far more
/// accurate than the 1e-8 relative agreement with `critspeed linear` the tests ask.
const NEWTON_TOL: f64 = 1e-11;

/// Every curve `spec` asks for; `cancel` is asked before each step.
pub fn analyse(
    study: &KeyedStudy,
    spec: &CurveSpec,
    cancel: Option<&(dyn Fn() -> bool + Sync)>,
) -> Result<CurveReport, CurveError> {
    analyse_with_progress(study, spec, cancel, None)
}

/// [`analyse`], calling `progress` with a line of text as each diagram and fold curve is done
/// (a long run says where it is).
pub fn analyse_with_progress(
    study: &KeyedStudy,
    spec: &CurveSpec,
    cancel: Option<&(dyn Fn() -> bool + Sync)>,
    progress: Option<&(dyn Fn(&str) + Sync)>,
) -> Result<CurveReport, CurveError> {
    let mut report = CurveReport {
        study: study.base.name.clone(),
        key: spec.key.clone(),
        dimension: spec.dimension,
        range: spec.range,
        log: spec.log,
        speed_range: spec.speed_range,
        curves: Vec::new(),
        special_points: Vec::new(),
        stable_regions: Vec::new(),
        nonlinear_critical_speed: Vec::new(),
        nonlinear_unknown: Vec::new(),
        nonlinear_methods: Vec::new(),
        attractor_search: Vec::new(),
        notes: Vec::new(),
        stats: CurveStats::default(),
    };
    let mut cycles_done = false;
    for kind in &spec.curves {
        match kind {
            CurveKind::Hopf => {
                let started = std::time::Instant::now();
                hopf_curves(study, spec, cancel, &mut report)?;
                if let Some(p) = progress {
                    p(&format!(
                        "Hopf curves: {} ({:.2} s)",
                        report.curves.len(),
                        started.elapsed().as_secs_f64()
                    ));
                }
            }
            // the folds, flips (symmetry breaking, period doubling) and torus bifurcations of
            // cycles: from the same diagrams, in one pass
            CurveKind::Fold
            | CurveKind::SymmetryBreaking
            | CurveKind::PeriodDoubling
            | CurveKind::Torus => {
                if !cycles_done {
                    super::folds::fold_curves(study, spec, cancel, progress, &mut report)?;
                    cycles_done = true;
                }
            }
        }
    }
    if report.curves.is_empty() {
        let asked: Vec<&str> = spec.curves.iter().map(|k| k.name()).collect();
        let why = if spec.curves.contains(&CurveKind::Hopf) {
            format!(
                "no Hopf point in [{}, {}] m/s at any of the {} values of {} searched between {} and {} {}: the centred motion does not lose stability there",
                spec.speed_range.0,
                spec.speed_range.1,
                spec.seed_points,
                spec.key,
                spec.range.0,
                spec.range.1,
                spec.dimension.si_unit()
            )
        } else if report.notes.is_empty() {
            format!(
                "none of the curves asked for ({}) was found in the diagrams computed",
                asked.join(", ")
            )
        } else {
            // the notes say why: no such point in the diagrams, or none could be followed
            format!(
                "none of the curves asked for ({}) was found: {}",
                asked.join(", "),
                report.notes.join("; ")
            )
        };
        return Err(CurveError::Nothing(why));
    }
    Ok(report)
}

/// The creep laws whose Hopf curves are drawn: Kalker's (V_L) and the study's own (V_H).
fn laws(study: &KeyedStudy) -> Vec<(CreepLaw, &'static str)> {
    match study.base.contact.creep_law {
        CreepLaw::Kalker => vec![(CreepLaw::Kalker, "V_L")],
        law => vec![(CreepLaw::Kalker, "V_L"), (law, "V_H")],
    }
}

fn hopf_curves(
    study: &KeyedStudy,
    spec: &CurveSpec,
    cancel: Option<&(dyn Fn() -> bool + Sync)>,
    report: &mut CurveReport,
) -> Result<(), CurveError> {
    let states = study.base.model().map_or(0, |m| m.states());
    for (law, label) in laws(study) {
        crate::with_states!(states,
        N => hopf_curves_of::<N>(study, spec, law, label, cancel, report)?,
        _ => return Err(CurveError::Model {
            parameter: f64::NAN,
            message: format!("no analysis is compiled for {states} states"),
        }))
    }
    Ok(())
}

/// `P` of a key value, and the `P` range (lower bound first).
pub(super) fn to_p(spec: &CurveSpec, v: f64) -> f64 {
    if spec.log {
        v.ln()
    } else {
        v
    }
}

fn hopf_curves_of<const N: usize>(
    study: &KeyedStudy,
    spec: &CurveSpec,
    law: CreepLaw,
    label: &'static str,
    cancel: Option<&(dyn Fn() -> bool + Sync)>,
    report: &mut CurveReport,
) -> Result<(), CurveError> {
    let (p0, p1) = (to_p(spec, spec.range.0), to_p(spec, spec.range.1));
    let range = (p0.min(p1), p0.max(p1));
    let kalker = law == CreepLaw::Kalker;
    let family = StudyFamily::<N>::new(study, kalker, spec.log, range.1 - range.0)
        .exact_at(p0, spec.range.0)
        .exact_at(p1, spec.range.1);
    let params = HopfParams {
        speed_range: spec.speed_range,
        param_range: range,
        ds_initial: 0.25 * spec.max_step,
        ds_max: spec.max_step,
        ds_min: 1e-7,
        max_points: spec.max_points,
        newton_tol: NEWTON_TOL,
    };
    let first_curve = report.curves.len();
    let n = spec.seed_points;
    for i in 0..n {
        // by index, the ends exactly as written
        let p = match i {
            0 => p0,
            _ if i + 1 == n => p1,
            _ => p0 + (p1 - p0) * i as f64 / (n - 1) as f64,
        };
        for start in seeds::<N>(&family, study, kalker, spec, p)? {
            let covered = report.curves[first_curve..]
                .iter()
                .any(|c| passes(c, family.value(p), &start, spec, &params));
            if covered {
                continue;
            }
            let back = walk(&family, &start, -1.0, &params, cancel)?;
            let fore = if back.stop == CurveStop::Closed {
                // the backward side went all the way round
                Half {
                    points: back.points[..1].to_vec(),
                    special: Vec::new(),
                    stop: CurveStop::Closed,
                    newton: 0,
                    rejected: 0,
                }
            } else {
                walk(&family, &start, 1.0, &params, cancel)?
            };
            let curve = join(&family, law, label, back, fore, report, family.value(p));
            report.curves.push(curve);
        }
    }
    let top = stable_band(&family, spec, &report.curves[first_curve..], &params)?;
    report.stable_regions.push(StableRegion {
        creep_law: law,
        label,
        top,
    });
    report.stats.models_built += *family.builds.borrow();
    Ok(())
}

/// Key values at which the stable band is sampled for the plot.
const BAND_POINTS: usize = 101;

/// The top of the stable band at [`BAND_POINTS`] key values: NaN where an eigenvalue of
/// $J$ at the bottom of the speed range has a non-negative real part, else the lowest point
/// of the curves at that value whose stable side is below, else the top of the range.
fn stable_band<const N: usize>(
    family: &StudyFamily<'_, N>,
    spec: &CurveSpec,
    curves: &[Curve],
    params: &HopfParams,
) -> Result<Vec<(f64, f64)>, CurveError> {
    let (p0, p1) = (to_p(spec, spec.range.0), to_p(spec, spec.range.1));
    let (vlo, vhi) = params.speed_range;
    let mut out = Vec::with_capacity(BAND_POINTS);
    for i in 0..BAND_POINTS {
        let p = p0 + (p1 - p0) * i as f64 / (BAND_POINTS - 1) as f64;
        let value = family.value(p);
        let stable = match family.jacobian(vlo, p) {
            Ok(j) => {
                crate::stability::eigenvalues(&j).is_some_and(|ev| ev.iter().all(|z| z.0 < 0.0))
            }
            Err(_) => false,
        };
        if !stable {
            out.push((value, f64::NAN));
            continue;
        }
        let onset = lowest_onset(curves, |v| to_p(spec, v), p).map_or(vhi, |v| v.min(vhi));
        out.push((value, onset));
    }
    Ok(out)
}

/// The lowest onset of instability at `p` on `curves`: the speed, interpolated linearly on
/// the continuation's axis (`axis(key value)`), of each segment that crosses `p` with a
/// stable side below; `None` when no such segment crosses it.
pub fn lowest_onset<'c>(
    curves: impl IntoIterator<Item = &'c Curve>,
    axis: impl Fn(f64) -> f64,
    p: f64,
) -> Option<f64> {
    curves
        .into_iter()
        .flat_map(|c| c.points.windows(2))
        .filter_map(|w| {
            let (a, b) = (axis(w[0].parameter), axis(w[1].parameter));
            let below =
                w[0].stable_side == StableSide::Below || w[1].stable_side == StableSide::Below;
            if !(below && a.min(b) <= p && p <= a.max(b)) {
                return None;
            }
            let t = if a != b { (p - a) / (b - a) } else { 0.0 };
            Some(w[0].speed_m_s + t * (w[1].speed_m_s - w[0].speed_m_s))
        })
        .reduce(f64::min)
}

/// The Hopf crossings of Kalker's law (`kalker`) or the study's own at `P` = `p`, as start
/// states.
fn seeds<const N: usize>(
    family: &StudyFamily<'_, N>,
    study: &KeyedStudy,
    kalker: bool,
    spec: &CurveSpec,
    p: f64,
) -> Result<Vec<State<N>>, CurveError> {
    let mut model = study.model_at(family.value(p))?;
    if kalker {
        model.contact.creep_law = CreepLaw::Kalker;
    }
    let law = model.contact.creep_law;
    let sys = LinearSystem::<N>::at_centre(&model);
    let opts = LinearOptions {
        speed_range: spec.speed_range,
        ..study.base.linear
    };
    let found = critical_speeds(&sys, law, &opts).map_err(|e| CurveError::Model {
        parameter: family.value(p),
        message: e.to_string(),
    })?;
    Ok(found
        .crossings
        .iter()
        .filter_map(|c| {
            let pair = c.eigenpair(&sys)?;
            Some(State {
                a: nalgebra::SVector::from_fn(|k, _| pair.vector[k].0),
                b: nalgebra::SVector::from_fn(|k, _| pair.vector[k].1),
                omega: pair.im,
                v: c.speed_m_s,
                p,
            })
        })
        .collect())
}

/// Whether `curve` passes through the crossing `s` at key value `value`: it crosses that
/// value at a speed within 1e-3 of the speed range and a frequency within 1 % of the
/// crossing's (linear interpolation between its points).
fn passes<const N: usize>(
    curve: &Curve,
    value: f64,
    s: &State<N>,
    spec: &CurveSpec,
    params: &HopfParams,
) -> bool {
    let f = s.omega / (2.0 * std::f64::consts::PI);
    let sv = params.speed_range.1 - params.speed_range.0;
    let at = |x: f64| to_p(spec, x);
    curve.points.windows(2).any(|w| {
        let (a, b) = (at(w[0].parameter), at(w[1].parameter));
        let target = at(value);
        let lo = a.min(b);
        let hi = a.max(b);
        if !(lo <= target && target <= hi) {
            return false;
        }
        let t = if hi > lo { (target - a) / (b - a) } else { 0.0 };
        let v = w[0].speed_m_s + t * (w[1].speed_m_s - w[0].speed_m_s);
        let fr = w[0].frequency_hz + t * (w[1].frequency_hz - w[0].frequency_hz);
        (v - s.v).abs() < 1e-3 * sv && (fr - f).abs() < 1e-2 * f
    })
}

fn point<const N: usize, F: HopfFamily<N>>(family: &F, p: &TracedPoint<N>) -> CurvePoint {
    let e = &p.eval;
    let stable_side = match e.rate {
        Some(r) if e.others < 0.0 && r > 0.0 => StableSide::Below,
        Some(r) if e.others < 0.0 && r < 0.0 => StableSide::Above,
        _ => StableSide::Neither,
    };
    CurvePoint {
        parameter: family.value(p.state.p),
        speed_m_s: p.state.v,
        frequency_hz: p.state.omega / (2.0 * std::f64::consts::PI),
        amplitude_m: 0.0,
        first_lyapunov_coefficient: e.l1.as_ref().map(|l| l.l1),
        first_lyapunov_error: e.l1.as_ref().map(|l| l.error),
        hopf_type: e.l1.as_ref().map(|l| l.kind()),
        stable_side,
        stable_cycle: None,
        torus_angle_rad: None,
        cycle_state: Vec::new(),
    }
}

/// The two sides as one curve (the backward side reversed, then the forward one), with its
/// special points added to the report.
fn join<const N: usize, F: HopfFamily<N>>(
    family: &F,
    law: CreepLaw,
    label: &'static str,
    back: Half<N>,
    fore: Half<N>,
    report: &mut CurveReport,
    seed: f64,
) -> Curve {
    let index = report.curves.len();
    for h in [&back, &fore] {
        report.stats.newton_iterations += h.newton;
        report.stats.rejected_steps += h.rejected;
        for s in &h.special {
            let p = family.value(s.state.p);
            // the same point seen from another curve of this law (a double Hopf point)
            let curves = &report.curves;
            let same = report.special_points.iter_mut().find(|o| {
                o.kind == s.kind
                    && o.curve != index
                    && curves.get(o.curve).map(|c| c.creep_law) == Some(law)
                    && (o.parameter - p).abs() <= 1e-6 * p.abs().max(1e-300)
                    && (o.speed_m_s - s.state.v).abs() <= 1e-6 * s.state.v.abs()
            });
            if let Some(o) = same {
                o.other_curve = Some(index);
                continue;
            }
            report.special_points.push(SpecialPoint {
                kind: s.kind,
                curve: index,
                other_curve: None,
                parameter: p,
                speed_m_s: s.state.v,
                frequency_hz: s.state.omega / (2.0 * std::f64::consts::PI),
                second_frequency_hz: match s.kind {
                    super::SpecialKind::DoubleHopf => s
                        .eval
                        .as_ref()
                        .and_then(|e| e.second)
                        .map(|z| z.1 / (2.0 * std::f64::consts::PI)),
                    _ => None,
                },
                located: s.located,
            });
        }
    }
    let mut points: Vec<CurvePoint> = back.points.iter().rev().map(|p| point(family, p)).collect();
    points.extend(fore.points.iter().skip(1).map(|p| point(family, p)));
    Curve {
        kind: CurveKind::Hopf,
        creep_law: law,
        label,
        points,
        stops: (back.stop, fore.stop),
        seed_parameter: seed,
    }
}
