//! The nonlinear analysis of a study: the branches of hunting limit cycles from the Hopf point
//! of the study's creep law, their stability, special points and the nonlinear critical speed
//! (docs/model.md §9, §12).
//!
//! This is the driver that joins the wheelset to the generic continuation: it finds the Hopf
//! point and its eigenvector, chooses scales (1 mm of lateral amplitude ≈ 1 m/s of speed),
//! continues the symmetric branch from the Hopf point, switches onto the asymmetric branch at
//! each symmetry-breaking point and onto the doubled branch at each period doubling, and so on
//! recursively within the study's limits ([`driver`]); measures amplitudes on each cycle, turns
//! the branches into plain result rows, and takes the nonlinear critical speed over all of them
//! ([`vnl`]).

mod driver;
pub mod fold_track;
pub mod vnl;

pub use vnl::{VnlCandidate, VnlMethod};

use nalgebra::SVector;

use crate::model::Vehicle;

use crate::contact::creep::CreepLaw;
use crate::continuation::{
    BranchStats, Continuation, ContinuationParams, OrbitPoint, Shooting, SpecialKind,
};
use crate::stability::{critical_speeds, Crossing, LinearOptions, LinearSystem};
use crate::system::ode::{Method, OdeOptions, Tolerances};

/// Options of the bifurcation analysis (study section `[bifurcation]`).
#[derive(Clone, Debug, PartialEq)]
pub struct BifurcationOptions {
    /// speeds the branch may visit (m/s); default: the linear range
    pub speed_range: (f64, f64),
    /// largest lateral excursion of any wheelset followed (m); default 20 mm. A branch is
    /// also cut where it leaves `geometry_limit`.
    pub max_amplitude: f64,
    /// the half-width (m) of the lateral range where the contact geometry is known (a table's
    /// or a profile solve's range; beyond it the geometry is extended linearly); `None` where
    /// the extension is exact (the cone) or the study asks for extrapolation. Branches are cut
    /// where a wheelset's excursion leaves it, so that no cycle (and no V_NL) rests on
    /// extrapolated geometry.
    pub geometry_limit: Option<f64>,
    /// switch onto the asymmetric branch at every symmetry-breaking point and onto the doubled
    /// branch at every period doubling, recursively (study key `[bifurcation] switch`; default
    /// true)
    pub switch: bool,
    /// branches continued at most, the symmetric one from the Hopf point included (study key
    /// `[bifurcation] max_branches`; default 8)
    pub max_branches: usize,
    /// integrator relative tolerance; default 1e-10 (atol = rtol × 1 mm)
    pub rtol: f64,
    /// relative tolerance of the monodromy matrix's error test (study key `[bifurcation]
    /// floquet_rtol`); `None` (default): `rtol`. The cycles keep `rtol`; Newton's Jacobian and
    /// the Floquet multipliers are solved to this one, so that a vehicle whose stiff modes the
    /// variational equations excite (but the cycle does not) takes the cycle's steps: on
    /// studies/passenger-car-s1002.toml 1e-7 takes 3.7× less time over the first 40 cycles, at
    /// a cost in multiplier accuracy and Newton convergence (docs/nonlinear.md)
    pub floquet_rtol: Option<f64>,
    /// largest continuation step (scaled: 1 ≈ 1 mm or 1 m/s); default 2 (AUTO-07p's DSMAX in
    /// the peer comparison): the step grows to it only on easy stretches (Newton at or below
    /// its target count, tangents within 0.3 rad), special points are located regardless
    pub ds_max: f64,
    /// most cycles computed on each branch; default 400
    pub max_points: usize,
    /// run each Newton step's independent integrations (per shooting segment: the flow with
    /// its monodromy and the speed perturbation) on rayon threads (default true; results are
    /// bitwise identical to the serial run)
    pub parallel: bool,
    /// shooting segments of the half period (study key `[bifurcation] segments`); 0 (default):
    /// [`DEFAULT_SEGMENTS`], whatever the thread count. Each segment is an equal piece of
    /// independent work, run on rayon threads when `parallel`; for a given count the results
    /// do not depend on `parallel` nor on the thread count (bit for bit), and different counts
    /// agree to the Newton tolerance on the cycles they both find
    pub segments: usize,
    /// the cycles' corrector (study key `[bifurcation] corrector`): `false` (default,
    /// `"newton"`): every iteration linearises; `true` (`"chord"`): a linearisation is kept
    /// for the iterations after it, which integrate the plain flows alone
    /// ([`crate::continuation::ContinuationParams::chord`]). About 2× faster on the DTU
    /// table's bogie and car with the same V_NL; on the S1002 car its branch zig-zags and
    /// takes twice as long, and on a flange's period-doubling cascade it took another path
    /// (docs/performance.md), so it is not the default
    pub chord: bool,
    /// the Runge–Kutta pair of the shooting flows (study key `[bifurcation] integrator`):
    /// [`Method::DormandPrince5`] (default, `"dopri5"`) or [`Method::DormandPrince8`]
    /// (`"dop853"`). The 8th-order pair takes 2–3× less time on smooth fields (the closed-form
    /// cone, a polynomial table) and is far more accurate at the same rtol; on contact tables
    /// and profiles, whose Jacobian jumps at nodes, and across a flange's dead band it is
    /// slower and its Newton iterations can stall at a fold (docs/performance.md)
    pub integrator: Method,
    /// a flag another computation raises while it has the rayon pool busy: the diagram's
    /// integrations run serially while it is up (the same diagram); default `None`
    pub busy: Option<crate::continuation::PoolBusy>,
}

impl BifurcationOptions {
    /// Defaults for a speed range.
    pub fn new(speed_range: (f64, f64)) -> Self {
        Self {
            speed_range,
            max_amplitude: 0.020,
            geometry_limit: None,
            switch: true,
            max_branches: 8,
            rtol: 1e-10,
            floquet_rtol: None,
            ds_max: 2.0,
            max_points: 400,
            parallel: true,
            segments: 0,
            chord: false,
            integrator: Method::DormandPrince5,
            busy: None,
        }
    }
}

impl BifurcationOptions {
    /// The excursion at which a branch is cut (m): `max_amplitude`, or the geometry's range
    /// when that is smaller.
    pub fn amplitude_bound(&self) -> f64 {
        self.geometry_limit
            .map_or(self.max_amplitude, |g| g.min(self.max_amplitude))
    }

    /// The shooting segments used: `segments`, or [`DEFAULT_SEGMENTS`] for 0.
    pub fn segment_count(&self) -> usize {
        match self.segments {
            0 => DEFAULT_SEGMENTS,
            m => m,
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

/// What kind of cycles a branch holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BranchKind {
    /// symmetric cycles, x(t + T/2) = −x(t): the branch from the Hopf point
    Symmetric,
    /// asymmetric cycles (one of each mirror pair x(t), −x(t + T/2)), from a symmetry-breaking
    /// point
    Asymmetric,
    /// cycles of `k` times the period of the cycles they branched from at the first of a
    /// cascade of period doublings (2, 4, …)
    Period(usize),
}

impl BranchKind {
    /// As written in outputs: `symmetric`, `asymmetric`, `period-2`, `period-4`, …
    pub fn name(self) -> String {
        match self {
            BranchKind::Symmetric => "symmetric".into(),
            BranchKind::Asymmetric => "asymmetric".into(),
            BranchKind::Period(k) => format!("period-{k}"),
        }
    }
}

/// One branch of cycles, for output.
#[derive(Clone, Debug, PartialEq)]
pub struct BranchRow {
    /// its id: the index in [`BifurcationReport::branches`] (0: the branch from the Hopf point)
    pub id: usize,
    /// what it holds
    pub kind: BranchKind,
    /// the branch it was switched from, and the index in [`BifurcationReport::special`] of the
    /// point where it was (`None` for the branch from the Hopf point)
    pub parent: Option<(usize, usize)>,
    /// the critical multiplier at the switching point (ν = −1 of the half-period map for
    /// symmetry breaking, μ = −1 for period doubling; its distance from −1 shows how well the
    /// point was located)
    pub switch_multiplier: Option<f64>,
    /// why it ended, in words
    pub stop_reason: String,
    /// the cycles computed on it
    pub cycles: usize,
    /// the shooting segments it started with (of the half period on symmetric branches, of
    /// the whole period otherwise)
    pub segments: usize,
    /// where the continuation doubled its segments after Newton had failed at every step
    /// size: the speed of the last cycle before (m/s) and the new count
    pub segments_doubled: Vec<(f64, usize)>,
}

/// One cycle of a branch, for output.
#[derive(Clone, Debug, PartialEq)]
pub struct CycleRow {
    /// the branch it lies on ([`BranchRow::id`])
    pub branch: usize,
    /// speed (m/s)
    pub speed_m_s: f64,
    /// lateral amplitude of the leading wheelset, max |y| (m)
    pub amplitude_y_m: f64,
    /// the leading wheelset's largest excursion to the right, max y (m), and to the left,
    /// max −y (m): equal on symmetric cycles, the two sides of an asymmetric one
    pub amplitude_sides_y_m: (f64, f64),
    /// the largest wheelset's lateral amplitude max |y| (m): the leading wheelset's for the
    /// single wheelset; on a car one bogie may hunt while the other is nearly still
    pub wheelset_amplitude_m: f64,
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

/// A special point of a branch, for output.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpecialRow {
    /// the branch it lies on ([`BranchRow::id`])
    pub branch: usize,
    /// kind
    pub kind: SpecialKind,
    /// speed (m/s)
    pub speed_m_s: f64,
    /// lateral amplitude of the leading wheelset (m)
    pub amplitude_y_m: f64,
    /// the largest wheelset's lateral amplitude (m; as [`CycleRow::wheelset_amplitude_m`])
    pub wheelset_amplitude_m: f64,
    /// located to tolerance (true) or only bracketed
    pub located: bool,
    /// index in [`BifurcationReport::cycles`] of the branch's cycle just before it
    pub after: usize,
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
    /// the first Lyapunov coefficient at the Hopf point (docs/model.md §12), whose sign decides
    /// the type independently of the branch ([`crate::stability::first_lyapunov`])
    pub first_lyapunov: Option<crate::stability::Lyapunov>,
    /// lowest speed with a stable cycle on any branch (m/s), and whether it was located (a
    /// located special point or the supercritical Hopf point) or is only the lowest stable
    /// computed cycle
    pub nonlinear_critical_speed: Option<(f64, bool)>,
    /// what sets it: the lowest candidate of each kind (docs/model.md §9: every stable cycle counts)
    pub nonlinear_sources: Vec<VnlCandidate>,
    /// the branches, the one from the Hopf point first
    pub branches: Vec<BranchRow>,
    /// the cycles of every branch, branch by branch
    pub cycles: Vec<CycleRow>,
    /// special points of every branch
    pub special: Vec<SpecialRow>,
    /// why the branch from the Hopf point ended, in words
    pub stop_reason: String,
    /// notes in words: branches not followed (the `max_branches` limit, a failed switch),
    /// branches cut where the contact geometry ends
    pub notes: Vec<String>,
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

/// The integrator's options for cycles at `rtol`, the monodromy matrix at `floquet_rtol`
/// (`None`: `rtol` too; never below `rtol`), with the Runge–Kutta pair `method`.
fn ode_options(rtol: f64, floquet_rtol: Option<f64>, method: Method) -> Result<OdeOptions, String> {
    let tol = Tolerances::new(rtol, rtol * 1e-3).map_err(|e| e.to_string())?;
    let opts = OdeOptions {
        tol,
        monodromy_tol_factor: floquet_rtol.map_or(1.0, |f| (f / rtol).max(1.0)),
        method,
        ..OdeOptions::default()
    };
    opts.validate().map_err(|e| e.to_string())?;
    Ok(opts)
}

/// The most trial steps per hunting period the explicit integrator may need for the model's
/// stiffest mode before the continuation is refused. Dormand–Prince is stable for
/// $h|\lambda| \lesssim 3.3$ on the negative real axis, so a period takes at least
/// $|\lambda|_{max}/(3.3 f)$ steps. The shipped studies need 4 to 25; 10⁴ is 400 times the
/// stiffest of them, and already makes one shooting solve of a car take seconds.
pub const MAX_STIFF_STEPS_PER_PERIOD: f64 = 1e4;

/// Shooting segments of the half period when the study does not say
/// (`[bifurcation] segments`): a property of the computation, never of the machine, so that
/// every machine computes the same diagram; the thread count changes only the speed. Four
/// pieces keep up to four cores busy with the flows and their monodromies (eight with the
/// speed-perturbed flows). Measured on 2 threads of the 2-core machine, 1/2/4/8 segments:
/// DTU bogie at 72.7 kN s/m 7.4/6.5/5.6/9.1 s, DTU car 14.7/9.0/8.6/10.3 s, S1002 wheelset
/// 0.94/0.65/0.69/0.70 s, S1002 bogie 20.5/12.7/14.5/15.6 s.
pub const DEFAULT_SEGMENTS: usize = 4;

/// How many times a branch may double its shooting segments where Newton fails at every
/// step size ([`crate::continuation::ContinuationParams::refinements`]).
pub const SEGMENT_REFINEMENTS: usize = 2;

/// Refuses a model too stiff for the explicit shooting integration (a mass or an inertia far
/// too small, a stiffness or a damping far too large), in milliseconds and with the figures,
/// where integrating it would take hours: the spectral radius of the centred Jacobian at
/// `speed` (m/s) against the hunting frequency `frequency_hz`.
fn stiffness_check<const N: usize>(
    model: &Vehicle,
    speed: f64,
    frequency_hz: f64,
) -> Result<(), String> {
    let j = LinearSystem::<N>::at_centre(model).jacobian(speed);
    let Some(ev) = crate::stability::eigenvalues(&j) else {
        return Err(format!(
            "the Jacobian of the centred motion at {speed:.2} m/s has no finite eigenvalues"
        ));
    };
    let rho = ev.iter().map(|z| z.0.hypot(z.1)).fold(0.0, f64::max);
    let steps = rho / (3.3 * frequency_hz);
    if steps.is_finite() && steps <= MAX_STIFF_STEPS_PER_PERIOD {
        return Ok(());
    }
    Err(format!(
        "the model is too stiff to integrate: at V_H = {speed:.2} m/s its fastest mode has \
         |lambda| = {rho:.3e} 1/s against the hunting frequency {frequency_hz:.3} Hz, so the \
         explicit integrator would need about {steps:.1e} steps per cycle (at most {:.0e}); a \
         mass or an inertia far too small, or a stiffness or a damping far too large, is the \
         usual cause (`critspeed check` warns of values outside their plausible range)",
        MAX_STIFF_STEPS_PER_PERIOD
    ))
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
    solve_cycle(model, speed, x0, period, rtol, true)
}

/// [`cycle_at`] with the Runge–Kutta pair `method` (a study's `[bifurcation] integrator`)
/// instead of the default 5th-order one.
pub fn cycle_at_with<const N: usize>(
    model: &Vehicle,
    speed: f64,
    x0: [f64; N],
    period: f64,
    rtol: f64,
    method: Method,
) -> Result<(OrbitPoint<N>, crate::continuation::Floquet, usize), String> {
    solve_cycle_with(model, speed, x0, period, rtol, true, method)
}

/// [`cycle_at`] for any cycle: `symmetric` solves $φ_{T/2}(x_0) = −x_0$ (a symmetric cycle,
/// `period` its whole period), else $φ_T(x_0) = x_0$ (an asymmetric cycle, or one of several
/// periods: `period` is then the whole of it).
pub fn solve_cycle<const N: usize>(
    model: &Vehicle,
    speed: f64,
    x0: [f64; N],
    period: f64,
    rtol: f64,
    symmetric: bool,
) -> Result<(OrbitPoint<N>, crate::continuation::Floquet, usize), String> {
    solve_cycle_with(
        model,
        speed,
        x0,
        period,
        rtol,
        symmetric,
        Method::DormandPrince5,
    )
}

fn solve_cycle_with<const N: usize>(
    model: &Vehicle,
    speed: f64,
    x0: [f64; N],
    period: f64,
    rtol: f64,
    symmetric: bool,
    method: Method,
) -> Result<(OrbitPoint<N>, crate::continuation::Floquet, usize), String> {
    if N != model.states() {
        return Err(format!(
            "a start state of {N} values for a model of {} states",
            model.states()
        ));
    }
    let ode = ode_options(rtol, None, method)?;
    let amplitude = |_: &OrbitPoint<N>, _: &SVector<f64, N>| 0.0;
    let n = model.dofs();
    let mut scale: Vec<f64> = (0..N)
        .map(|i| if i < n || i >= 2 * n { 1e-3 } else { 1e-2 })
        .collect();
    scale.extend([period, 1.0]);
    let mut params = ContinuationParams::new((0.0, f64::INFINITY), f64::INFINITY, scale);
    params.newton_tol = newton_tol(rtol, N);
    params.newton_max_iter = 20;
    let c = Continuation {
        shooting: Shooting {
            field: model,
            symmetric,
            ode,
            dp_rel: rtol.sqrt(),
            parallel: true,
            busy: None,
            segments: 1,
        },
        params,
        amplitude: &amplitude,
        progress: None,
        cancel: None,
        extent: None,
        rejoin: None,
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
            branches: None,
        },
    )
}

/// The state components with their SI units: the 4-state names of `branch.csv` for the
/// wheelset, `<coordinate>_m`, `<coordinate>_rad` and their rates for a vehicle, then its
/// damper strokes `z_<damper>_m`.
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
    let strokes = model.stroke_names().into_iter().map(|n| format!("{n}_m"));
    pos.chain(coordinates.iter().map(|n| unit(n, true)))
        .chain(strokes)
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
    /// called with a line of text when a branch ends (its cycles and why it ended) and when
    /// a switched branch starts (from which point): what a long diagram is doing
    pub branches: Option<&'a (dyn Fn(&str) + Sync)>,
}

/// [`analyse`] with a progress report and a cancellation hook, any layout.
pub fn analyse_with_hooks(
    study: &str,
    model: &Vehicle,
    opts: &BifurcationOptions,
    hooks: Hooks<'_>,
) -> Result<BifurcationReport, String> {
    crate::with_states!(model.states(), N => driver::analyse_states::<N>(study, model, opts, hooks),
        _ => Err(format!("no analysis is compiled for {} states", model.states())))
}

/// [`analyse_with_hooks`], then every located fold of cycles of the diagram followed over the
/// key values of `track` ([`fold_track`]).
pub fn analyse_with_fold_tracks(
    study: &str,
    model: &Vehicle,
    opts: &BifurcationOptions,
    hooks: Hooks<'_>,
    track: &fold_track::FoldTracking<'_>,
) -> Result<(BifurcationReport, Vec<fold_track::FoldTrack>), String> {
    crate::with_states!(model.states(), N => driver::analyse_and_track::<N>(study, model, opts, hooks, Some(track)),
        _ => Err(format!("no analysis is compiled for {} states", model.states())))
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
fn coordinate_shares_of(model: &Vehicle, q: &[nalgebra::Complex<f64>]) -> Vec<f64> {
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
