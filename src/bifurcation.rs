//! The nonlinear analysis of a study: the branch of hunting limit cycles from the Hopf point
//! of the study's creep law, its stability, folds and the nonlinear critical speed (MODEL §9).
//!
//! This is the driver that joins the wheelset to the generic continuation: it finds the Hopf
//! point and its eigenvector, chooses scales (1 mm of lateral amplitude ≈ 1 m/s of speed),
//! measures amplitudes on each cycle, and turns the branch into plain result rows.

use nalgebra::{DVector, SVector};

use crate::model::Vehicle;

use crate::contact::creep::CreepLaw;
use crate::continuation::{
    Branch, BranchStats, BranchStop, Continuation, ContinuationParams, OrbitPoint, Shooting,
    SpecialKind,
};
use crate::stability::{critical_speeds, Crossing, LinearOptions, LinearSystem};
use crate::system::ode::{OdeOptions, Tolerances};

/// Options of the bifurcation analysis (study section `[bifurcation]`).
#[derive(Clone, Debug, PartialEq)]
pub struct BifurcationOptions {
    /// speeds the branch may visit (m/s); default: the linear range
    pub speed_range: (f64, f64),
    /// largest lateral amplitude followed (m); default 20 mm
    pub max_amplitude: f64,
    /// integrator relative tolerance; default 1e-10 (atol = rtol × 1 mm)
    pub rtol: f64,
    /// largest continuation step (scaled: 1 ≈ 1 mm or 1 m/s); default 2 (AUTO-07p's DSMAX in
    /// the peer comparison): the step grows to it only on easy stretches (Newton at or below
    /// its target count, tangents within 0.3 rad), special points are located regardless
    pub ds_max: f64,
    /// most cycles computed; default 400
    pub max_points: usize,
    /// run each Newton step's independent integrations (per shooting segment: the flow with
    /// its monodromy and the speed perturbation) on rayon threads (default true; results are
    /// bitwise identical to the serial run)
    pub parallel: bool,
    /// shooting segments of the half period (study key `[bifurcation] segments`); 0 (default):
    /// one per rayon thread when `parallel` (at most 8), else 1. Each segment is an equal piece of independent work;
    /// for a given count the results do not depend on `parallel`, and different counts agree
    /// to the Newton tolerance
    pub segments: usize,
}

impl BifurcationOptions {
    /// Defaults for a speed range.
    pub fn new(speed_range: (f64, f64)) -> Self {
        Self {
            speed_range,
            max_amplitude: 0.020,
            rtol: 1e-10,
            ds_max: 2.0,
            max_points: 400,
            parallel: true,
            segments: 0,
        }
    }
}

impl BifurcationOptions {
    /// The shooting segments used: `segments`, or for 0 one per rayon thread when `parallel`
    /// (at most 8), else 1.
    pub fn segment_count(&self) -> usize {
        match (self.segments, self.parallel) {
            (0, true) => rayon::current_num_threads().clamp(1, 8),
            (0, false) => 1,
            (m, _) => m,
        }
    }
}

/// Sub- or supercritical Hopf bifurcation.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum HopfType {
    /// the cycle branch starts towards lower speeds, unstable
    Subcritical,
    /// the cycle branch starts towards higher speeds, stable
    Supercritical,
}

impl HopfType {
    /// `"subcritical"` or `"supercritical"`.
    pub fn name(self) -> &'static str {
        match self {
            HopfType::Subcritical => "subcritical",
            HopfType::Supercritical => "supercritical",
        }
    }
}

/// One cycle of the branch, for output.
#[derive(Clone, Debug, PartialEq)]
pub struct CycleRow {
    /// speed (m/s)
    pub speed_m_s: f64,
    /// lateral amplitude max |y| (m)
    pub amplitude_y_m: f64,
    /// yaw amplitude max |ψ| (rad)
    pub amplitude_psi_rad: f64,
    /// period (s)
    pub period_s: f64,
    /// all nontrivial Floquet multipliers inside the unit circle
    pub stable: bool,
    /// largest modulus of the nontrivial multipliers
    pub max_multiplier_abs: f64,
    /// |trivial multiplier − 1|: the accuracy figure
    pub trivial_multiplier_error: f64,
    /// Newton iterations of the corrector (solver statistic)
    pub newton_iterations: usize,
    /// the cycle's start state, in [`BifurcationReport::state_names`] order (y m, ψ rad,
    /// ẏ m/s, ψ̇ rad/s for the wheelset): integrating from it at this speed reproduces the cycle
    pub x0: Vec<f64>,
    /// the Floquet multipliers (re, im), one per state, by decreasing modulus
    pub multipliers: Vec<(f64, f64)>,
    /// each body's amplitudes (max |y| m, max |ψ| rad) over the cycle, in body order
    /// (vehicles only; empty for the single wheelset, whose are the two columns above)
    pub body_amplitudes: Vec<(f64, f64)>,
}

/// A special point of the branch, for output.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpecialRow {
    /// kind
    pub kind: SpecialKind,
    /// speed (m/s)
    pub speed_m_s: f64,
    /// lateral amplitude (m)
    pub amplitude_y_m: f64,
    /// located to tolerance (true) or only bracketed
    pub located: bool,
}

/// Everything the nonlinear analysis produces.
#[derive(Clone, Debug, PartialEq)]
pub struct BifurcationReport {
    /// study name
    pub study: String,
    /// the study's creep law
    pub law: CreepLaw,
    /// linear (Kalker) critical speed, if in range (m/s)
    pub kalker_critical_speed_m_s: Option<f64>,
    /// the Hopf point of the study's law where the branch starts
    pub hopf: Option<Crossing>,
    /// its type, from the branch's initial direction
    pub hopf_type: Option<HopfType>,
    /// the first Lyapunov coefficient at the Hopf point (MODEL §12), whose sign decides the
    /// type independently of the branch ([`crate::stability::first_lyapunov`])
    pub first_lyapunov: Option<crate::stability::Lyapunov>,
    /// lowest speed with a stable cycle (m/s), and whether it was located (a located fold or
    /// the supercritical Hopf point) or is only the lowest stable computed cycle
    pub nonlinear_critical_speed: Option<(f64, bool)>,
    /// the cycles
    pub cycles: Vec<CycleRow>,
    /// special points
    pub special: Vec<SpecialRow>,
    /// why the branch ended, in words
    pub stop_reason: String,
    /// centred motion: speed ranges (m/s) where it is stable (Kalker model of the study law)
    pub speed_range: (f64, f64),
    /// the layout ("wheelset", "bogie", "car")
    pub layout: &'static str,
    /// the bodies, in state order
    pub body_names: Vec<String>,
    /// the state components with their SI units ([`state_names`])
    pub state_names: Vec<String>,
    /// the continuation's solver statistics (failed steps, Newton iterations, integrator
    /// steps)
    pub stats: BranchStats,
}

fn ode_options(rtol: f64) -> Result<OdeOptions, String> {
    let tol = Tolerances::new(rtol, rtol * 1e-3).map_err(|e| e.to_string())?;
    Ok(OdeOptions {
        tol,
        ..OdeOptions::default()
    })
}

/// One periodic-orbit solve: the symmetric hunting cycle of `model` at `speed` (m/s), by
/// Newton from a guess of its start state and period (e.g. a neighbouring branch cycle, or a
/// settled simulation). Returns the cycle, its Floquet multipliers and the iterations used.
pub fn cycle_at<const N: usize>(
    model: &Vehicle,
    speed: f64,
    x0: [f64; N],
    period: f64,
    rtol: f64,
) -> Result<(OrbitPoint<N>, crate::continuation::Floquet, usize), String> {
    if N != model.states() {
        return Err(format!(
            "a start state of {N} values for a model of {} states",
            model.states()
        ));
    }
    let ode = ode_options(rtol)?;
    let amplitude = |_: &OrbitPoint<N>, _: &SVector<f64, N>| 0.0;
    let mut scale: Vec<f64> = (0..N)
        .map(|i| if i < N / 2 { 1e-3 } else { 1e-2 })
        .collect();
    scale.extend([period, 1.0]);
    let mut params = ContinuationParams::new((0.0, f64::INFINITY), f64::INFINITY, scale);
    params.newton_tol = (10.0 * rtol).max(1e-10);
    params.newton_max_iter = 20;
    let c = Continuation {
        shooting: Shooting {
            field: model,
            symmetric: true,
            ode,
            dp_rel: rtol.sqrt(),
            parallel: true,
            segments: 1,
        },
        params,
        amplitude: &amplitude,
        progress: None,
        cancel: None,
    };
    c.solve_at(OrbitPoint {
        x0: SVector::from(x0),
        period,
        param: speed,
    })
    .map_err(|e| format!("no cycle found at {speed} m/s: Newton stopped with {e:?}"))
}

/// The Hopf crossing of `law` in the range, and the eigenvector of its critical pair
/// normalised so that its y-component is 1.
fn hopf_point<const N: usize>(
    model: &Vehicle,
    range: (f64, f64),
) -> Option<(Crossing, Vec<nalgebra::Complex<f64>>)> {
    let sys = LinearSystem::<N>::at_centre(model);
    let opts = LinearOptions {
        speed_range: range,
        ..LinearOptions::default()
    };
    let found = critical_speeds(&sys, model.creep_law(), &opts).ok()?;
    let c = *found.critical()?;
    let pair = c.eigenpair(&sys)?;
    let q: Vec<nalgebra::Complex<f64>> = pair
        .vector
        .iter()
        .map(|v| nalgebra::Complex::new(v.0, v.1))
        .collect();
    let qy = *q.first()?;
    if qy.norm() == 0.0 {
        return None;
    }
    Some((c, q.into_iter().map(|v| v / qy).collect()))
}

/// Runs the bifurcation analysis of `model` (its own creep law), any layout.
pub fn analyse(
    study: &str,
    model: &Vehicle,
    opts: &BifurcationOptions,
) -> Result<BifurcationReport, String> {
    analyse_with_progress(study, model, opts, None)
}

/// [`analyse`], calling `progress(cycle index, speed m/s, amplitude m)` after each cycle.
pub fn analyse_with_progress(
    study: &str,
    model: &Vehicle,
    opts: &BifurcationOptions,
    progress: Option<&(dyn Fn(usize, f64, f64) + Sync)>,
) -> Result<BifurcationReport, String> {
    analyse_with_hooks(
        study,
        model,
        opts,
        Hooks {
            progress,
            cancel: None,
        },
    )
}

/// The state components with their SI units: the 4-state names of `branch.csv` for the
/// wheelset, `<coordinate>_m`, `<coordinate>_rad` and their rates for a vehicle.
pub fn state_names(model: &Vehicle) -> Vec<String> {
    if model.states() == 4 {
        return ["y_m", "psi_rad", "ydot_m_s", "psidot_rad_s"]
            .map(String::from)
            .to_vec();
    }
    let coordinates = model.coordinate_names();
    let unit = |n: &str, rate: bool| {
        let (head, tail) = n.split_once('_').unwrap_or((n, ""));
        let dot = if rate { "dot" } else { "" };
        let si = match (head, rate) {
            ("y", false) => "m",
            ("y", true) => "m_s",
            (_, false) => "rad",
            (_, true) => "rad_s",
        };
        format!("{head}{dot}_{tail}_{si}")
    };
    let pos = coordinates.iter().map(|n| unit(n, false));
    pos.chain(coordinates.iter().map(|n| unit(n, true)))
        .collect()
}

/// What a caller can attach to a running analysis.
#[derive(Clone, Copy, Default)]
pub struct Hooks<'a> {
    /// called as `progress(cycle index, speed m/s, amplitude m)` after each cycle
    pub progress: Option<&'a (dyn Fn(usize, f64, f64) + Sync)>,
    /// asked before each continuation step; `true` ends the branch there (stop reason
    /// "cancelled"): how a Python caller's Ctrl-C reaches the computation
    pub cancel: Option<&'a (dyn Fn() -> bool + Sync)>,
}

/// [`analyse`] with a progress report and a cancellation hook, any layout.
pub fn analyse_with_hooks(
    study: &str,
    model: &Vehicle,
    opts: &BifurcationOptions,
    hooks: Hooks<'_>,
) -> Result<BifurcationReport, String> {
    crate::with_states!(model.states(), N => analyse_states::<N>(study, model, opts, hooks),
        _ => Err(format!("no analysis is compiled for {} states", model.states())))
}

fn analyse_states<const N: usize>(
    study: &str,
    model: &Vehicle,
    opts: &BifurcationOptions,
    hooks: Hooks<'_>,
) -> Result<BifurcationReport, String> {
    let Hooks { progress, cancel } = hooks;
    let ode = ode_options(opts.rtol)?;
    let kalker = model.with_law(CreepLaw::Kalker);
    let kalker_critical_speed_m_s = critical_speeds(
        &LinearSystem::<N>::at_centre(&kalker),
        CreepLaw::Kalker,
        &LinearOptions {
            speed_range: opts.speed_range,
            ..LinearOptions::default()
        },
    )
    .ok()
    .and_then(|c| c.critical().map(|x| x.speed_m_s));
    let mut report = BifurcationReport {
        study: study.to_string(),
        law: model.creep_law(),
        kalker_critical_speed_m_s,
        hopf: None,
        hopf_type: None,
        first_lyapunov: None,
        nonlinear_critical_speed: None,
        cycles: Vec::new(),
        special: Vec::new(),
        stop_reason: String::new(),
        speed_range: opts.speed_range,
        layout: model.layout.name(),
        body_names: model.bodies.iter().map(|b| b.name.clone()).collect(),
        state_names: state_names(model),
        stats: BranchStats::default(),
    };
    let Some((hopf, q)) = hopf_point::<N>(model, opts.speed_range) else {
        report.stop_reason = format!(
            "no Hopf point of the {} model in [{}, {}] m/s: the centred motion does not lose stability there",
            model.creep_law().name(),
            opts.speed_range.0,
            opts.speed_range.1
        );
        return Ok(report);
    };
    report.hopf = Some(hopf);
    let omega = 2.0 * std::f64::consts::PI * hopf.frequency_hz;
    report.first_lyapunov =
        crate::stability::first_lyapunov::<N, _>(model, hopf.speed_m_s, omega, &Default::default())
            .ok();
    let a_ref = 1e-3;
    // each coordinate scaled by its share of the Hopf eigenvector (the leading wheelset's y is
    // 1): 1 mm of lateral amplitude ≈ 1 m/s of speed in the arclength
    let shares = coordinate_shares(model, &q);
    let mut scale: Vec<f64> = (0..N)
        .map(|i| {
            let share = shares.get(i % (N / 2)).copied().unwrap_or(1.0);
            if i < N / 2 {
                a_ref * share
            } else {
                a_ref * omega * share
            }
        })
        .collect();
    scale.extend([1.0 / hopf.frequency_hz, 1.0]);
    let mut params = ContinuationParams::new(opts.speed_range, opts.max_amplitude, scale.clone());
    params.ds_initial = 0.1;
    params.ds_max = opts.ds_max;
    params.max_points = opts.max_points;
    // Newton cannot converge below the integration noise: tie its tolerance to rtol.
    params.newton_tol = newton_tol(opts.rtol, N);
    // max |y| over the cycle, located on the shooting integration's dense output
    let amplitude = |_: &OrbitPoint<N>, peaks: &SVector<f64, N>| peaks[0];
    let counter = std::sync::atomic::AtomicUsize::new(0);
    let report_point = |p: &crate::continuation::BranchPoint<N>| {
        if let Some(f) = progress {
            let k = counter.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
            f(k, p.orbit.param, p.amplitude);
        }
    };
    let cont = Continuation {
        shooting: Shooting {
            field: model,
            symmetric: true,
            ode,
            dp_rel: opts.rtol.sqrt(),
            parallel: opts.parallel,
            segments: opts.segment_count(),
        },
        params,
        amplitude: &amplitude,
        progress: Some(&report_point),
        cancel,
    };
    let start = OrbitPoint {
        x0: SVector::zeros(),
        period: 1.0 / hopf.frequency_hz,
        param: hopf.speed_m_s,
    };
    let direction = DVector::from_fn(N + 2, |i, _| {
        if i < N {
            a_ref * q[i].re / scale[i]
        } else {
            0.0
        }
    });
    let branch = cont.run(start, direction);
    fill(&mut report, &branch, model);
    Ok(report)
}

/// Newton's tolerance on the scaled update: it cannot converge below the integration noise,
/// so it is tied to rtol: 10 rtol (at least 1e-10) for the single wheelset, 100 rtol for a
/// vehicle. On the DTU bogie and car the orbits run through the C¹-interpolated contact
/// table's curvature jumps at several millimetres (trivial multipliers only within 1e-7 of 1
/// there against 1e-12 on the wheelset's cone): near the folds Newton could not reach 10 rtol
/// in its 8 iterations with Φ error-controlled per column (see `dopri::phi_rms`), so the
/// bogie stopped at its 150.5 m/s fold; at 100 rtol it passes every fold, and the folds and
/// V_NL move by about 1e-8 m/s.
fn newton_tol(rtol: f64, states: usize) -> f64 {
    let factor = if states > 4 { 100.0 } else { 10.0 };
    (factor * rtol).max(1e-10)
}

/// The share of each coordinate in the arclength's scales: the largest share in the Hopf
/// eigenvector `q` of the coordinates of its kind (lateral displacements in m, angles in rad).
/// Scaling each coordinate by its own share made the car body's yaw (4e-4 of the largest yaw
/// share in the car's Hopf mode) a coordinate of scale 4e-7 rad: on the branch, where one bogie
/// hunts and the car body yaws by 8e-6 rad, it dominated both the arclength and Newton's
/// scaled update (to be converged to ~1e-16 rad), and the continuation crept along at steps of
/// 1e-5 m/s near the 149.8 m/s fold. The single wheelset has one coordinate of each kind, so
/// its scales are unchanged.
fn coordinate_shares(model: &Vehicle, q: &[nalgebra::Complex<f64>]) -> Vec<f64> {
    let names = model.coordinate_names();
    let n = names.len().min(q.len());
    let lateral = |i: usize| names[i].starts_with("y_");
    let largest = |kind: bool| {
        (0..n)
            .filter(|&i| lateral(i) == kind)
            .map(|i| q[i].norm())
            .fold(1e-6, f64::max)
    };
    let (y, angle) = (largest(true), largest(false));
    (0..n).map(|i| if lateral(i) { y } else { angle }).collect()
}

fn fill<const N: usize>(report: &mut BifurcationReport, branch: &Branch<N>, model: &Vehicle) {
    report.stats = branch.stats;
    report.cycles = branch
        .points
        .iter()
        .map(|p| CycleRow {
            speed_m_s: p.orbit.param,
            amplitude_y_m: p.amplitude,
            amplitude_psi_rad: p.peaks[1],
            period_s: p.orbit.period,
            stable: p.floquet.stable(),
            max_multiplier_abs: p.floquet.max_nontrivial,
            trivial_multiplier_error: p.floquet.trivial_error,
            newton_iterations: p.newton_iterations,
            x0: p.orbit.x0.iter().copied().collect(),
            multipliers: (0..N)
                .map(|k| {
                    p.floquet
                        .multipliers
                        .get(k)
                        .map_or((f64::NAN, f64::NAN), |m| (m.re, m.im))
                })
                .collect(),
            // every body's max |y| and max |ψ|, located on the same dense output
            body_amplitudes: if N == 4 {
                Vec::new()
            } else {
                model
                    .bodies
                    .iter()
                    .map(|b| (p.peaks[b.dof], p.peaks[b.dof + 1]))
                    .collect()
            },
        })
        .collect();
    report.special = branch
        .special
        .iter()
        .map(|s| SpecialRow {
            kind: s.kind,
            speed_m_s: s.orbit.param,
            amplitude_y_m: s.amplitude,
            located: s.located,
        })
        .collect();
    report.stop_reason = match branch.stop {
        BranchStop::ParamBound { param } => format!("speed bound reached ({param:.4} m/s)"),
        BranchStop::AmplitudeBound { amplitude } => {
            format!("amplitude bound reached ({:.3} mm)", amplitude * 1e3)
        }
        BranchStop::MaxPoints => format!("step limit reached ({} cycles)", branch.points.len()),
        BranchStop::StepTooSmall { param, newton } => {
            format!("step too small at {param:.4} m/s (Newton: {newton:?})")
        }
        BranchStop::Cancelled => format!("cancelled after {} cycles", branch.points.len()),
    };
    let hopf_speed = report.hopf.map(|h| h.speed_m_s);
    report.hopf_type = match (hopf_speed, report.cycles.first()) {
        (Some(v), Some(c)) if c.speed_m_s < v => Some(HopfType::Subcritical),
        (Some(_), Some(_)) => Some(HopfType::Supercritical),
        _ => None,
    };
    report.nonlinear_critical_speed = nonlinear_critical_speed(report);
}

/// MODEL §9: the lowest speed at which a stable cycle exists: the supercritical Hopf speed, a
/// located fold next to a stable stretch, or else the lowest stable computed cycle, whichever is
/// lowest. A supercritical branch can fold back below its Hopf point further on (flange contact
/// of real profiles does this): its stable cycles there set V_NL, not the Hopf speed.
fn nonlinear_critical_speed(r: &BifurcationReport) -> Option<(f64, bool)> {
    let hopf = (r.hopf_type == Some(HopfType::Supercritical)
        && r.cycles.first().is_some_and(|c| c.stable))
    .then(|| r.hopf.map(|h| (h.speed_m_s, true)))
    .flatten();
    let folds = r
        .special
        .iter()
        .filter(|s| s.kind == SpecialKind::Fold)
        .map(|s| (s.speed_m_s, s.located));
    let stable = r
        .cycles
        .iter()
        .filter(|c| c.stable)
        .map(|c| (c.speed_m_s, false));
    let lowest_stable = stable.clone().map(|s| s.0).fold(f64::INFINITY, f64::min);
    // a fold counts when it lies at (or below) the lowest stable cycle: the stable part turns there
    folds
        .filter(|(v, _)| *v <= lowest_stable + 1e-9 * lowest_stable.abs().max(1.0))
        .chain(stable)
        .chain(hopf)
        .min_by(|a, b| a.0.total_cmp(&b.0))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::stability::Direction;

    fn cycle(speed_m_s: f64, stable: bool) -> CycleRow {
        CycleRow {
            speed_m_s,
            amplitude_y_m: 1e-3,
            amplitude_psi_rad: 1e-3,
            period_s: 0.1,
            stable,
            max_multiplier_abs: if stable { 0.5 } else { 2.0 },
            trivial_multiplier_error: 0.0,
            newton_iterations: 2,
            x0: vec![0.0; 4],
            multipliers: vec![(1.0, 0.0); 4],
            body_amplitudes: Vec::new(),
        }
    }

    fn fold(speed_m_s: f64) -> SpecialRow {
        SpecialRow {
            kind: SpecialKind::Fold,
            speed_m_s,
            amplitude_y_m: 5e-3,
            located: true,
        }
    }

    /// A supercritical branch (stable from V_H = 100) that turns back at 110, comes down to a
    /// fold at 80 and is stable again above it: the lowest stable cycle is near 80, so V_NL is the
    /// fold at 80 (MODEL §9), not the Hopf speed. Without the fold-back V_NL is V_H.
    #[test]
    fn nonlinear_critical_speed_is_the_lowest_stable_cycle() {
        let hopf = Crossing {
            speed_m_s: 100.0,
            frequency_hz: 5.0,
            wavelength_m: 20.0,
            direction: Direction::Onset,
            bracket_m_s: 1e-12,
        };
        let mut r = BifurcationReport {
            study: "synthetic".into(),
            law: CreepLaw::Shen { friction: 0.3 },
            kalker_critical_speed_m_s: Some(100.0),
            hopf: Some(hopf),
            hopf_type: Some(HopfType::Supercritical),
            first_lyapunov: None,
            nonlinear_critical_speed: None,
            cycles: vec![cycle(100.5, true), cycle(110.0, true), cycle(95.0, false)],
            special: vec![fold(110.2)],
            stop_reason: String::new(),
            speed_range: (1.0, 200.0),
            layout: "wheelset",
            body_names: vec!["wheelset 1".into()],
            state_names: Vec::new(),
            stats: BranchStats::default(),
        };
        let v = nonlinear_critical_speed(&r).map(|v| v.0);
        assert!(v.is_some_and(|v| (v - 100.0).abs() < 1e-12), "{v:?}");
        r.cycles
            .extend([cycle(80.0, false), cycle(80.5, true), cycle(90.0, true)]);
        r.special.push(fold(79.9));
        let v = nonlinear_critical_speed(&r);
        assert!(
            v.is_some_and(|(v, located)| (v - 79.9).abs() < 1e-12 && located),
            "{v:?}"
        );
    }
}
