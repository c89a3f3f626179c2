//! The grid of speeds and initial states, the basin fractions, the descents and the bisection.
//!
//! At each speed of the grid (highest first) every initial state is simulated (in parallel) and
//! classified ([`super::classify`]). Motions of one kind whose leading-wheelset amplitudes (on
//! either side: mirror images are one attractor) and periods agree within 1 % are one attractor.
//! An attractor not met before is followed down in speed from its own state (quasi-static
//! descent: each speed starts from the state the motion had at the speed above, so there is no
//! lag as in the ramp) through every lower grid speed and steps of at most `descent_step` of the
//! speed, until the motion is no longer the same attractor (it decays, jumps to another one,
//! leaves the geometry's range or stops settling); the speed where it dies is then bracketed by
//! bisection, each trial again started from the lowest state where it lived, to `bracket`.
//! Below the lowest speed of a hunting motion known (of the attractors and of the continuation's
//! V_NL), where another attractor would lower V_NL, the grid's spacing is then halved
//! ([`refined_speeds`]) and the speeds added are searched like the grid's.

use nalgebra::SVector;
use rayon::prelude::*;

use super::classify::{classify, Settle};
use super::{
    Attractor, AttractorReport, BodyAmplitude, Motion, MotionKind, Outcome, SeedCheck, SpeedRow,
};
use crate::bifurcation::BifurcationReport;
use crate::model::{BodyKind, Vehicle};

/// Options of the search (study section `[attractors]`).
#[derive(Clone, Debug, PartialEq)]
pub struct AttractorOptions {
    /// the speeds of the grid (m/s), from the lowest to the highest
    pub speed_range: (f64, f64),
    /// grid speeds (default 6; 0: no grid, [`descents_only`](Self::descents_only))
    pub speeds: usize,
    /// the amplitudes of the initial kicks (m); default 30, 60 and 90 % of the contact
    /// geometry's range (of 10 mm where it has none)
    pub amplitudes: Vec<f64>,
    /// the longest simulation of one motion (s); default 30 s
    pub settle: f64,
    /// the width to which the speed where an attractor dies is bracketed (m/s); default 0.1
    pub bracket: f64,
    /// the largest step of a descent, relative to the speed; default 0.05
    pub descent_step: f64,
    /// the lowest speed a descent goes to (m/s); default the bottom of the bifurcation range
    pub lowest: f64,
    /// equilibrium threshold on every body's lateral excursion (m); default 0.01 mm
    pub threshold: f64,
    /// integrator relative tolerance of the simulations; default 1e-8
    pub rtol: f64,
    /// largest period (in returns to the section) recognised as a cycle; default 8
    pub max_period: usize,
    /// the contact geometry's half-width (m); `None`: no limit (the cone, or extrapolation)
    pub geometry_limit: Option<f64>,
    /// simulate the initial states of one speed on rayon threads (default true)
    pub parallel: bool,
    /// motions known from elsewhere (a fold curve's cycle), each simulated at its speed and,
    /// where it hunts, followed down like the continuation's lowest stable cycles; each gets
    /// a verdict in [`AttractorReport::seed_checks`](super::AttractorReport::seed_checks)
    pub seeds: Vec<Seed>,
}

/// An initial state known from another method, to be tested by simulation.
#[derive(Clone, Debug, PartialEq)]
pub struct Seed {
    /// the speed to simulate at (m/s)
    pub speed_m_s: f64,
    /// the state (the model's order, SI)
    pub state: Vec<f64>,
    /// where it comes from, in words ("the cycle of fold curve 3 at 199.9 N s/mm")
    pub source: String,
}

impl AttractorOptions {
    /// Defaults around the Hopf speed `v_h` (m/s) of the study's law, when there is one in the
    /// bifurcation range `range`: the grid from 1.1 V_H down to 0.5 V_H (within the range),
    /// else the whole range.
    pub fn new(range: (f64, f64), v_h: Option<f64>, geometry_limit: Option<f64>) -> Self {
        let speed_range = match v_h {
            Some(v) => ((0.5 * v).max(range.0), (1.1 * v).min(range.1)),
            None => range,
        };
        let reference = geometry_limit.unwrap_or(0.010);
        AttractorOptions {
            speed_range,
            speeds: 6,
            amplitudes: vec![0.3 * reference, 0.6 * reference, 0.9 * reference],
            settle: 30.0,
            bracket: 0.1,
            descent_step: 0.05,
            lowest: range.0,
            threshold: 1e-5,
            rtol: 1e-8,
            max_period: 8,
            geometry_limit,
            parallel: true,
            seeds: Vec::new(),
        }
    }

    /// The fast form of the search that sweeps use: no grid of initial states, only the
    /// descents from the continuation's lowest stable cycles (each checked by simulation and
    /// followed down, through any jump to another attractor, until it dies).
    pub fn descents_only(mut self) -> Self {
        self.speeds = 0;
        self
    }

    /// The grid's spacing (m/s); `None` with fewer than two speeds.
    pub fn spacing(&self) -> Option<f64> {
        let (lo, hi) = self.speed_range;
        (self.speeds >= 2).then(|| (hi - lo) / (self.speeds - 1) as f64)
    }

    /// The grid, highest speed first (one speed: the top of the range; none for
    /// [`descents_only`](Self::descents_only)).
    pub fn grid(&self) -> Vec<f64> {
        let (lo, hi) = self.speed_range;
        let n = self.speeds;
        if n == 0 {
            return Vec::new();
        }
        if n == 1 {
            return vec![hi];
        }
        (0..n)
            .map(|i| hi - (hi - lo) * i as f64 / (n - 1) as f64)
            .collect()
    }
}

/// What an initial state is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StartKind {
    /// one body's lateral coordinate displaced
    Lateral,
    /// one body's yaw displaced (its ends by the amplitude)
    Yaw,
    /// every wheelset displaced the same way
    WheelsetsInPhase,
    /// the wheelsets displaced in turn one way and the other
    WheelsetsInAntiphase,
    /// the wheelsets of the front bogie one way, of the rear bogie the other
    BogiesInAntiphase,
    /// a stable cycle of the continuation
    ContinuedCycle,
}

impl StartKind {
    /// As written in outputs.
    pub fn name(self) -> &'static str {
        match self {
            StartKind::Lateral => "lateral kick",
            StartKind::Yaw => "yaw kick",
            StartKind::WheelsetsInPhase => "wheelsets in phase",
            StartKind::WheelsetsInAntiphase => "wheelsets in antiphase",
            StartKind::BogiesInAntiphase => "bogies in antiphase",
            StartKind::ContinuedCycle => "continued stable cycle",
        }
    }
}

/// The kicks: every body's y and ψ (the ends moved by the amplitude), the wheelsets in phase
/// and in antiphase, the bogies in antiphase, at every amplitude; positive only (a negative kick
/// is the mirror image of a positive one, and so are the attractors it reaches).
fn kicks(model: &Vehicle, amplitudes: &[f64]) -> Vec<(StartKind, String, Vec<f64>)> {
    let n = model.states();
    let (a, lb) = model.layout_arms();
    let l0 = model.contact.params.half_contact_distance;
    let wheelsets = model.wheelset_dofs().to_vec();
    let mut out = Vec::new();
    for &amp in amplitudes {
        let mm = amp * 1e3;
        for b in &model.bodies {
            let mut x = vec![0.0; n];
            x[b.dof] = amp;
            out.push((
                StartKind::Lateral,
                format!("y of {} = {mm:.2} mm", b.name),
                x,
            ));
            let arm = match b.kind {
                BodyKind::Wheelset => l0,
                BodyKind::Frame => a,
                BodyKind::CarBody => lb,
            };
            if arm > 0.0 {
                let mut x = vec![0.0; n];
                x[b.dof + 1] = amp / arm;
                out.push((
                    StartKind::Yaw,
                    format!(
                        "yaw of {} = {:.3} mrad (ends {mm:.2} mm)",
                        b.name,
                        amp / arm * 1e3
                    ),
                    x,
                ));
            }
        }
        if wheelsets.len() >= 2 {
            let mut x = vec![0.0; n];
            for &d in &wheelsets {
                x[d] = amp;
            }
            out.push((
                StartKind::WheelsetsInPhase,
                format!("every wheelset y = {mm:.2} mm"),
                x,
            ));
            let mut x = vec![0.0; n];
            for (k, &d) in wheelsets.iter().enumerate() {
                x[d] = if k % 2 == 0 { amp } else { -amp };
            }
            out.push((
                StartKind::WheelsetsInAntiphase,
                format!("wheelsets y = ±{mm:.2} mm in turn"),
                x,
            ));
        }
        if wheelsets.len() >= 4 {
            let mut x = vec![0.0; n];
            let half = wheelsets.len() / 2;
            for (k, &d) in wheelsets.iter().enumerate() {
                x[d] = if k < half { amp } else { -amp };
            }
            out.push((
                StartKind::BogiesInAntiphase,
                format!("front bogie's wheelsets +{mm:.2} mm, rear -{mm:.2} mm"),
                x,
            ));
        }
    }
    out
}

/// The continuation's stable cycles at `speed`: on every branch, each pair of consecutive
/// stable cycles on either side of it gives a start, the nearer cycle's state (the search's
/// classification then solves the cycle at `speed` exactly).
fn continued_starts(
    r: Option<&BifurcationReport>,
    speed: f64,
) -> Vec<(StartKind, String, Vec<f64>)> {
    let Some(r) = r else {
        return Vec::new();
    };
    let mut out = Vec::new();
    for pair in r.cycles.windows(2) {
        let (a, b) = (&pair[0], &pair[1]);
        if a.branch != b.branch || !(a.stable && b.stable) {
            continue;
        }
        if (a.speed_m_s - speed) * (b.speed_m_s - speed) > 0.0 {
            continue;
        }
        let c = if (a.speed_m_s - speed).abs() <= (b.speed_m_s - speed).abs() {
            a
        } else {
            b
        };
        let kind = r
            .branches
            .get(c.branch)
            .map_or("symmetric".to_string(), |k| k.kind.name());
        out.push((
            StartKind::ContinuedCycle,
            format!(
                "stable {kind} cycle of branch {} at {:.2} m/s ({:.2} mm)",
                c.branch,
                c.speed_m_s,
                c.amplitude_y_m * 1e3
            ),
            c.x0.clone(),
        ));
    }
    out
}

/// The lowest cycle of every stable stretch of every branch (speed, state, description): the
/// descents that check each of the continuation's lowest stable motions by simulation.
fn stretch_ends(r: Option<&BifurcationReport>) -> Vec<(f64, Vec<f64>, String)> {
    let Some(r) = r else {
        return Vec::new();
    };
    let mut out = Vec::new();
    let mut k = 0;
    while k < r.cycles.len() {
        let c = &r.cycles[k];
        if !c.stable {
            k += 1;
            continue;
        }
        let mut end = k;
        while end + 1 < r.cycles.len()
            && r.cycles[end + 1].stable
            && r.cycles[end + 1].branch == c.branch
        {
            end += 1;
        }
        // the lowest cycle that is clearly stable (next to a fold the multiplier is 1 and the
        // cycle neither attracts nor repels within a simulation); the descent from it finds the
        // fold by bisection
        // the stretch that starts at a supercritical Hopf point: its small cycles shrink to
        // the centred motion there (no jump below is possible), which the continuation has
        // located; a descent would spend its time in the slow decay next to V_H
        if k == 0
            && c.branch == 0
            && r.hopf_type == Some(crate::bifurcation::HopfType::Supercritical)
        {
            k = end + 1;
            continue;
        }
        let stretch = &r.cycles[k..=end];
        let clear = stretch
            .iter()
            .filter(|c| c.max_multiplier_abs < 0.99)
            .min_by(|x, y| x.speed_m_s.total_cmp(&y.speed_m_s));
        let low = clear.or_else(|| {
            stretch
                .iter()
                .min_by(|x, y| x.max_multiplier_abs.total_cmp(&y.max_multiplier_abs))
        });
        if let Some(low) = low {
            let kind = r
                .branches
                .get(low.branch)
                .map_or("symmetric".to_string(), |b| b.kind.name());
            out.push((
                low.speed_m_s,
                low.x0.clone(),
                format!(
                    "the lowest stable {kind} cycle of a stretch of branch {} ({:.2} m/s, {:.2} mm)",
                    low.branch,
                    low.speed_m_s,
                    low.amplitude_y_m * 1e3
                ),
            ));
        }
        k = end + 1;
    }
    out
}

/// Whether two motions are the same attractor: the same kind, the leading wheelset's sides
/// within `tol` (in either order: the mirror image is the same attractor) and periods within
/// `tol`.
fn same(a: &Motion, b: &Motion, tol: f64) -> bool {
    if a.kind != b.kind || !a.kind.is_hunting() {
        return false;
    }
    // a torus or chaos has no exact amplitude: its extremes over a finite run vary by a few
    // per cent from run to run
    let tol = if a.period_s.is_none() {
        tol.max(0.1)
    } else {
        tol
    };
    let close = |x: f64, y: f64| (x - y).abs() <= tol * x.abs().max(y.abs()).max(1e-6);
    let sides = |m: &Motion| {
        m.amplitudes
            .first()
            .map_or((0.0, 0.0), |a: &BodyAmplitude| (a.y_right_m, a.y_left_m))
    };
    let (sa, sb) = (sides(a), sides(b));
    let amp = (close(sa.0, sb.0) && close(sa.1, sb.1)) || (close(sa.0, sb.1) && close(sa.1, sb.0));
    let period = match (a.period_s, b.period_s) {
        (Some(x), Some(y)) => close(x, y),
        (None, None) => true,
        _ => false,
    };
    amp && period
}

/// What the search shares with its workers.
struct Ctx<'a> {
    model: &'a Vehicle,
    opts: &'a AttractorOptions,
    settle: Settle,
    progress: Option<&'a (dyn Fn(&str) + Sync)>,
    cancel: Option<&'a (dyn Fn() -> bool + Sync)>,
    simulations: std::sync::atomic::AtomicUsize,
    /// the kicks, the same at every speed ([`kicks`])
    kicked: Vec<(StartKind, String, Vec<f64>)>,
    /// the continuation the search starts from, where one ran
    continued: Option<&'a BifurcationReport>,
}

impl Ctx<'_> {
    fn say(&self, text: &str) {
        if let Some(p) = self.progress {
            p(text);
        }
    }

    fn cancelled(&self) -> bool {
        self.cancel.is_some_and(|c| c())
    }

    /// The cycle of `here` carried to speed `v` by four Newton steps in speed
    /// (natural-parameter continuation: the cycle of the same branch, even where its amplitude
    /// changes fast, as near a Hopf point): its start, period and whether it is stable. `None`
    /// for a motion that is not a cycle, or where a step moves the start by more than 30 % of
    /// its size (past a fold there is no cycle nearby, and Newton from far would land on
    /// another). The steps solve at [`track_rtol`].
    fn track<const N: usize>(&self, here: &Motion, v_to: f64) -> Option<(Vec<f64>, f64, bool)> {
        let t0 = here.period_s?;
        if here.state.len() != N {
            return None;
        }
        let symmetric = here.kind == MotionKind::SymmetricCycle;
        let mut x = nalgebra::SVector::<f64, N>::from_fn(|i, _| here.state[i]);
        let mut period = t0;
        let mut stable = false;
        for j in 1..=4 {
            let v = here.speed_m_s + (v_to - here.speed_m_s) * j as f64 / 4.0;
            let x0: [f64; N] = std::array::from_fn(|i| x[i]);
            let (orbit, floquet, _) = crate::bifurcation::solve_cycle::<N>(
                self.model,
                v,
                x0,
                period,
                track_rtol(self.opts.rtol),
                symmetric,
            )
            .ok()?;
            if (orbit.x0 - x).norm() > 0.3 * x.norm().max(1e-12) {
                return None;
            }
            (x, period) = (orbit.x0, orbit.period);
            stable = floquet.stable();
        }
        Some((x.iter().copied().collect(), period, stable))
    }

    /// Whether `m` (a speed below `here`) is still the attractor of `here`: the same kind,
    /// and for a cycle the stable cycle `tracked` from `here`'s by [`Self::track`], with `m`'s
    /// period; for a torus or chaos, amplitudes within a fifth.
    fn continues(
        &self,
        here: &Motion,
        m: &Motion,
        tracked: Option<&(Vec<f64>, f64, bool)>,
    ) -> bool {
        if m.kind != here.kind || !m.kind.is_hunting() || lost(here, tracked) {
            return false;
        }
        let (Some(_), Some(t1)) = (here.period_s, m.period_s) else {
            return same(m, here, 0.2);
        };
        matches!(tracked, Some((_, period, true)) if (period - t1).abs() <= 1e-6 * t1.abs())
    }

    /// The motion at `v` reached from `here` (a speed above): for a cycle, the simulation
    /// starts on the cycle tracked to `v` when it is stable there (so that a cycle with a
    /// narrow basin is not lost to the jump of a large step), else from `here`'s state.
    /// Returns the motion and whether it is still `here`'s attractor.
    fn step_to<const N: usize>(&self, here: &Motion, v: f64) -> (Motion, bool) {
        let tracked = self.track::<N>(here, v);
        self.simulate_step::<N>(here, v, tracked)
    }

    /// [`Self::step_to`] with the cycle of `here` already tracked to `v` by [`Self::track`].
    fn simulate_step<const N: usize>(
        &self,
        here: &Motion,
        v: f64,
        tracked: Option<(Vec<f64>, f64, bool)>,
    ) -> (Motion, bool) {
        let start = match &tracked {
            Some((x, _, true)) => x.as_slice(),
            _ => here.state.as_slice(),
        };
        let m = self.until_settled::<N>(v, self.classify::<N>(v, start));
        let kept = self.continues(here, &m, tracked.as_ref());
        (m, kept)
    }

    /// An unsettled motion `m` at `v` simulated on from where it stopped, up to
    /// [`UNSETTLED_EXTENSIONS`] more times the settle time, until it has a verdict (it
    /// decays, settles on an attractor, or leaves the geometry); a motion with a verdict is
    /// returned as it is. A bracket of death or a jump must not rest on a motion that was
    /// merely slow (the bottleneck just below a fold of cycles).
    fn until_settled<const N: usize>(&self, v: f64, mut m: Motion) -> Motion {
        let mut time = m.time_s;
        let mut runs = 1;
        // the excursions of the successive unsettled runs (over each one's second half)
        let mut excursions = vec![m.excursion_m];
        while m.kind == MotionKind::Unsettled
            && m.state.len() == N
            && runs <= UNSETTLED_EXTENSIONS
            && !self.cancelled()
        {
            let state = std::mem::take(&mut m.state);
            m = self.classify::<N>(v, &state);
            time += m.time_s;
            runs += 1;
            if m.kind == MotionKind::Unsettled {
                excursions.push(m.excursion_m);
            }
        }
        if m.kind == MotionKind::Unsettled {
            if let Some(note) = slow_decay(&excursions) {
                m.kind = MotionKind::Equilibrium;
                m.note = note;
            }
        }
        if runs > 1 {
            m.note = format!(
                "{}{}{runs} simulations of up to {:.0} s each, each from where the last \
                 stopped: {time:.1} s in all",
                m.note,
                if m.note.is_empty() { "" } else { "; " },
                self.settle.max_time
            );
            m.time_s = time;
        }
        m
    }

    fn classify<const N: usize>(&self, speed: f64, x: &[f64]) -> Motion {
        self.simulations
            .fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        if x.len() != N {
            let mut m = Motion::simple(MotionKind::Diverged, speed, 0.0);
            m.note = format!("a start of {} values for {N} states", x.len());
            return m;
        }
        classify::<N>(
            self.model,
            speed,
            &SVector::from_fn(|i, _| x[i]),
            &self.settle,
        )
    }
}

/// Whether the excursions of successive unsettled runs of one motion (each over its run's
/// second half, m; runs of equal length) show a decay to the centred motion too slow for one
/// run's test. Near a Hopf point the amplitude r obeys the normal form r' = μr − ar³, for
/// which u = 1/r² obeys the linear u' = −2μu + 2a: u's increments over equal times grow
/// (μ < 0: r decays exponentially), stay equal (μ = 0: r ∝ 1/√t) or shrink towards a cycle of
/// r² = μ/a (μ > 0). So the motion decays when, over at least four runs, every excursion is
/// smaller than the one before and the increments of 1/r² do not shrink. A slow passage below
/// a fold of cycles (a bottleneck) also speeds up as it leaves. `Some` note in words.
fn slow_decay(excursions: &[f64]) -> Option<String> {
    let n = excursions.len();
    if n < 4 || excursions.iter().any(|&e| !(e.is_finite() && e > 0.0)) {
        return None;
    }
    let u: Vec<f64> = excursions.iter().map(|e| 1.0 / (e * e)).collect();
    let d: Vec<f64> = u.windows(2).map(|w| w[1] - w[0]).collect();
    // equal increments (μ = 0) within rounding count as not shrinking
    let growing = d.iter().all(|&x| x > 0.0) && d.windows(2).all(|w| w[1] >= w[0] * (1.0 - 1e-9));
    let (first, last) = (excursions[0], excursions[n - 1]);
    growing.then(|| {
        format!(
            "decaying slowly: the largest wheelset excursion fell from {first:.3e} m to \
             {last:.3e} m over {n} runs, 1/amplitude^2 growing by increments that do not \
             shrink (the normal form's decay to the centred motion, not an approach to a cycle)"
        )
    })
}

/// Whether the cycle `here` is lost at a speed whatever a simulation there gives: `here` is a
/// cycle (it has a period) and [`Ctx::track`] found no stable cycle of its branch there
/// (`tracked`, `None` or unstable). [`Ctx::continues`] then keeps no motion: a motion of a cycle's
/// kind is the same attractor only as the stable tracked cycle with its period.
fn lost(here: &Motion, tracked: Option<&(Vec<f64>, f64, bool)>) -> bool {
    here.period_s.is_some() && !matches!(tracked, Some((_, _, true)))
}

/// What a descent found: the motion at every speed where the attractor lives (highest
/// first), the bracket of its death, what the motion does below in words, and that motion.
struct Descent {
    path: Vec<Motion>,
    dies: Option<(f64, f64)>,
    fate: String,
    below: Option<Motion>,
    /// the motion below the bracket has no verdict: the attractor may live lower
    open: bool,
}

/// The integrator's relative tolerance of the Newton-refined cycles that the simulations
/// settle on (their period, amplitudes and multipliers): a hundredth of the simulations' own
/// `rtol`, within [1e-10, 1e-8]. At the default `rtol` (1e-8) that is 1e-10; a search run
/// looser for speed (an uncertainty study at 1e-6) refines at 1e-8. The refinement was 40 % of
/// such a run's time at a fixed 1e-10 (docs/performance.md).
pub fn cycle_rtol(rtol: f64) -> f64 {
    (rtol * 1e-2).clamp(1e-10, 1e-8)
}

/// The integrator's relative tolerance of [`Ctx::track`]'s Newton steps: the simulations' own
/// `rtol` within [1e-8, 1e-7], looser than [`cycle_rtol`]. A tracked cycle is a starting state
/// for the next simulation and a period to compare with the one the simulation settles on (same
/// attractor when they agree to 1e-6), and 1e-7 gives both with room. At the default `rtol`
/// (1e-8) that is 1e-8: on the S1002 bogie's search the descents of its cycles took 3.4, 2.1,
/// 1.1 and 2.8 s instead of 7.4, 4.4, 1.8 and 5.4 s at 1e-10, with the same report.
pub fn track_rtol(rtol: f64) -> f64 {
    rtol.clamp(1e-8, 1e-7)
}

/// How many more times the settle time an unsettled motion of a descent is simulated on
/// before it counts as unsettled ([`Ctx::until_settled`]).
pub const UNSETTLED_EXTENSIONS: usize = 3;

/// The descent of one attractor from `start` (its motion at the speed where it was found):
/// every grid speed below, with steps of at most `descent_step` of the speed, then the
/// bisection of the death speed. Returns the path, the bracket and the fate.
fn descend<const N: usize>(ctx: &Ctx<'_>, start: &Motion, grid: &[f64]) -> Descent {
    let opts = ctx.opts;
    // where the model turns stiff the descent stops, as the continuation's branches do
    // (docs/nonlinear.md, "Where a branch ends"): `Some((speed, steps per period))`
    let centre = crate::stability::LinearSystem::<N>::at_centre(ctx.model);
    let too_stiff = |v: f64, period: Option<f64>| -> Option<(f64, f64)> {
        let t = period?;
        let rho = crate::stability::eigenvalues(&centre.jacobian(v))?
            .iter()
            .map(|z| z.0.hypot(z.1))
            .fold(0.0, f64::max);
        let steps = rho * t / 3.3;
        (steps > crate::bifurcation::MAX_STIFF_STEPS_PER_PERIOD).then_some((v, steps))
    };
    let mut stiff: Option<(f64, f64)> = None;
    let mut path = vec![start.clone()];
    let mut targets: Vec<f64> = grid
        .iter()
        .copied()
        .filter(|&v| v < start.speed_m_s - 1e-9 && v >= opts.lowest)
        .collect();
    targets.push(opts.lowest);
    let mut dead: Option<(f64, Motion)> = None;
    // the step: halved after a failure, down to the bracket, before the attractor counts as
    // dead there (the amplitude of a branch varies like a square root near a Hopf point or a
    // fold); doubled after a success, up to `descent_step` of the speed
    let mut step = (opts.descent_step * start.speed_m_s).max(opts.bracket);
    'targets: for target in targets {
        loop {
            let Some(here) = path.last().cloned() else {
                break 'targets;
            };
            if here.speed_m_s <= target + 1e-9 || ctx.cancelled() {
                break;
            }
            let largest = (opts.descent_step * here.speed_m_s).max(opts.bracket);
            step = step.min(largest);
            let next = (here.speed_m_s - step).max(target);
            if let Some(s) = too_stiff(next, here.period_s) {
                stiff = Some(s);
                break 'targets;
            }
            let (v, m, kept) = loop {
                let v = (here.speed_m_s - step).max(target);
                let last = step <= opts.bracket;
                let tracked = ctx.track::<N>(&here, v);
                // a try before the last is used only when it keeps the attractor, which a
                // cycle that tracking lost at `v` does not whatever the simulation gives
                // (`lost`): the step is halved without simulating (the same descent and
                // report, fewer simulations; near a fold or a Hopf point these were slow
                // transients of up to 1 + UNSETTLED_EXTENSIONS settle times each)
                if !last && lost(&here, tracked.as_ref()) {
                    step *= 0.5;
                    continue;
                }
                let (m, kept) = ctx.simulate_step::<N>(&here, v, tracked);
                if kept || last {
                    break (v, m, kept);
                }
                step *= 0.5;
            };
            if kept {
                path.push(m);
                step = (2.0 * step).min(largest);
            } else {
                dead = Some((v, m));
                break 'targets;
            }
        }
    }
    let Some((mut lo, mut below)) = dead else {
        let fate = match stiff {
            Some((v, steps)) => format!(
                "not followed below: at {v:.2} m/s the model is too stiff for the explicit \
                 integrator (about {steps:.0} steps per period of the cycle, more than {:.0}, \
                 set by the stability bound 3.3/|lambda|max of the centred motion); it may \
                 live lower",
                crate::bifurcation::MAX_STIFF_STEPS_PER_PERIOD
            ),
            None => "exists down to the lowest speed searched".into(),
        };
        return Descent {
            path,
            dies: None,
            fate,
            below: None,
            open: false,
        };
    };
    // bisection: each trial from the lowest state where it lived
    while let Some(alive) = path.last().cloned() {
        if alive.speed_m_s - lo <= opts.bracket || ctx.cancelled() {
            break;
        }
        let mid = 0.5 * (lo + alive.speed_m_s);
        let (m, kept) = ctx.step_to::<N>(&alive, mid);
        if kept {
            path.push(m);
        } else {
            (lo, below) = (mid, m);
        }
    }
    let alive = path.last().map_or(start.speed_m_s, |m| m.speed_m_s);
    let fate = match below.kind {
        MotionKind::Equilibrium if below.note.is_empty() => {
            "decays to the centred motion below".to_string()
        }
        MotionKind::Equilibrium => format!(
            "decays to the centred motion below (at {lo:.4} m/s: {})",
            below.note
        ),
        k if k.is_hunting() => {
            let name = k.name();
            let article = if name.starts_with(['a', 'e', 'i', 'o', 'u']) {
                "an"
            } else {
                "a"
            };
            format!(
                "jumps to {article} {name} of {:.3} mm below",
                below.amplitude_m() * 1e3
            )
        }
        MotionKind::OutOfRange => format!(
            "leaves the contact geometry's range below ({:.3} mm)",
            below.excursion_m * 1e3
        ),
        MotionKind::Unsettled => format!(
            "dies in an open bracket: at {lo:.4} m/s the motion has no verdict ({}), so the \
             attractor may live lower",
            below.note
        ),
        k => format!("{} below ({})", k.name(), below.note),
    };
    let open = below.kind == MotionKind::Unsettled;
    Descent {
        path,
        dies: Some((lo, alive)),
        fate,
        below: Some(below),
        open,
    }
}

/// The continuation's branch whose cycle equals the motion within 1 % in amplitude (either
/// side) and period, interpolated between the branch's cycles on either side of its speed.
fn match_branch(r: Option<&BifurcationReport>, m: &Motion) -> Option<(usize, f64, f64)> {
    let r = r?;
    let period = m.period_s?;
    let (right, left) = m.amplitudes.first().map(|a| (a.y_right_m, a.y_left_m))?;
    let v = m.speed_m_s;
    let mut best: Option<(usize, f64, f64)> = None;
    for pair in r.cycles.windows(2) {
        let (a, b) = (&pair[0], &pair[1]);
        if a.branch != b.branch || (a.speed_m_s - v) * (b.speed_m_s - v) > 0.0 {
            continue;
        }
        let span = b.speed_m_s - a.speed_m_s;
        let t = if span.abs() > 0.0 {
            (v - a.speed_m_s) / span
        } else {
            0.0
        };
        let lerp = |x: f64, y: f64| x + t * (y - x);
        let ar = lerp(a.amplitude_sides_y_m.0, b.amplitude_sides_y_m.0);
        let al = lerp(a.amplitude_sides_y_m.1, b.amplitude_sides_y_m.1);
        let ap = lerp(a.period_s, b.period_s);
        let rel = |x: f64, y: f64| (x - y).abs() / y.abs().max(1e-9);
        let da = (rel(right, ar).max(rel(left, al))).min(rel(right, al).max(rel(left, ar)));
        let dp = rel(period, ap);
        if da < 0.01 && dp < 0.01 && best.is_none_or(|x| da + dp < x.1 + x.2) {
            best = Some((a.branch, da, dp));
        }
    }
    best
}

/// The attractor a hunting motion is: one already followed whose path passes its speed with
/// the same motion, or a new one (its id pushed onto `fresh`).
fn identify(
    attractors: &mut Vec<Attractor>,
    fresh: &mut Vec<usize>,
    m: &Motion,
    continued: Option<&BifurcationReport>,
) -> usize {
    let v = m.speed_m_s;
    let known = attractors.iter().position(|a| {
        a.path
            .iter()
            .any(|p| (p.speed_m_s - v).abs() < 1e-9 && same(p, m, 0.01))
    });
    if let Some(k) = known {
        return k;
    }
    let id = attractors.len();
    attractors.push(Attractor {
        id,
        kind: m.kind,
        found_at_m_s: v,
        path: vec![m.clone()],
        dies_m_s: None,
        open_below: false,
        fate: String::new(),
        branch: match_branch(continued, m),
    });
    fresh.push(id);
    id
}

/// Whether an attractor already followed covers the motion `m`: its descent passes within 5 %
/// of `m`'s speed with the same motion (amplitudes within a fifth).
fn covered(attractors: &[Attractor], m: &Motion) -> bool {
    covering(attractors, m).is_some()
}

/// The attractor (its index) whose descent covers the motion `m`, as in [`covered`].
fn covering(attractors: &[Attractor], m: &Motion) -> Option<usize> {
    attractors.iter().position(|a| {
        a.path
            .iter()
            .any(|p| (p.speed_m_s - m.speed_m_s).abs() <= 0.05 * m.speed_m_s && same(p, m, 0.2))
    })
}

/// Follows the attractors `fresh` down from where they were found (in parallel), and then
/// every attractor one of them jumped to where it died, until no new one appears.
fn follow<const N: usize>(
    ctx: &Ctx<'_>,
    attractors: &mut Vec<Attractor>,
    fresh: &[usize],
    grid: &[f64],
    continued: Option<&BifurcationReport>,
) {
    let mut fresh = fresh.to_vec();
    while !fresh.is_empty() && !ctx.cancelled() {
        let work = |&id: &usize| {
            let a = &attractors[id];
            ctx.say(&format!(
                "  following attractor {id} ({}, {:.3} mm) down from {:.2} m/s",
                a.kind.name(),
                a.path[0].amplitude_m() * 1e3,
                a.found_at_m_s
            ));
            let started = std::time::Instant::now();
            let d = descend::<N>(ctx, &a.path[0], grid);
            let lowest = d.path.last().map_or(a.found_at_m_s, |m| m.speed_m_s);
            ctx.say(&format!(
                "  attractor {id} exists down to {lowest:.2} m/s, {} ({:.1} s)",
                d.fate,
                started.elapsed().as_secs_f64()
            ));
            (id, d)
        };
        let followed: Vec<_> = if ctx.opts.parallel {
            fresh.par_iter().map(work).collect()
        } else {
            fresh.iter().map(work).collect()
        };
        let mut landed = Vec::new();
        for (
            id,
            Descent {
                path,
                dies,
                fate,
                below,
                open,
            },
        ) in followed
        {
            if let Some(a) = attractors.get_mut(id) {
                a.path = path;
                a.dies_m_s = dies;
                a.open_below = open;
                a.fate = fate;
            }
            landed.extend(below.filter(|m| m.kind.is_hunting()));
        }
        fresh.clear();
        for m in landed {
            if !covered(attractors, &m) {
                identify(attractors, &mut fresh, &m, continued);
            }
        }
    }
}

/// The verdict on seed `s`, whose simulation at its speed gave `m`: the attractor (after
/// merging) whose path holds that motion, or what the motion was instead.
fn seed_check(attractors: &[Attractor], s: &Seed, m: &Motion) -> SeedCheck {
    let attractor = m.kind.is_hunting().then(|| {
        attractors.iter().find(|a| {
            a.path
                .iter()
                .any(|p| (p.speed_m_s - m.speed_m_s).abs() < 1e-9 && same(p, m, 0.01))
        })
    });
    SeedCheck {
        source: s.source.clone(),
        speed_m_s: s.speed_m_s,
        motion: m.clone(),
        attractor: attractor.flatten().map(|a| a.id),
        lowest_m_s: attractor.flatten().map(|a| a.lowest_m_s()),
        dies_m_s: attractor.flatten().and_then(|a| a.dies_m_s),
        open_below: attractor.flatten().is_some_and(|a| a.open_below),
    }
}

/// Joins the attractors that are one: of the same kind, where one (found lower) lies on the
/// other's descent (a motion of that path within 5 % of its speed has amplitudes within 5 %)
/// and both die within two brackets of each other. A jump lands on an attractor that a grid
/// speed below finds again; since descents go down only, the two are followed separately and
/// meet. The lower one's grid outcomes count as the other's. Ids are kept (the progress lines
/// already used them), so a merged attractor's id is missing from the list; returns the merges
/// as (merged id, the id it joined).
fn merge_duplicates(
    attractors: &mut Vec<Attractor>,
    rows: &mut [SpeedRow],
    bracket: f64,
) -> Vec<(usize, usize)> {
    let n = attractors.len();
    let mut into: Vec<usize> = (0..n).collect();
    for b in 0..n {
        for a in 0..n {
            if a == b {
                continue;
            }
            let (x, y) = (&attractors[a], &attractors[b]);
            if x.kind != y.kind || x.found_at_m_s < y.found_at_m_s {
                continue;
            }
            let dies = (x.lowest_m_s() - y.lowest_m_s()).abs() <= 2.0 * bracket;
            let Some(first) = y.path.first() else {
                continue;
            };
            let on_path = x.path.iter().any(|p| {
                (p.speed_m_s - first.speed_m_s).abs() <= 0.05 * first.speed_m_s
                    && same(p, first, 0.05)
            });
            if dies && on_path && (x.found_at_m_s > y.found_at_m_s || a < b) {
                into[b] = a;
                break;
            }
        }
    }
    if into.iter().enumerate().all(|(i, &j)| i == j) {
        return Vec::new();
    }
    let root = |mut i: usize| {
        while into[i] != i {
            i = into[i];
        }
        i
    };
    let kept: Vec<usize> = (0..n).filter(|&i| root(i) == i).collect();
    // ids are the attractors' indices before merging: a merged one's outcomes go to its root
    let new_id = |old: usize| Some(attractors.get(root(old)).map_or(old, |a| a.id));
    for row in rows.iter_mut() {
        let mut merged: Vec<Outcome> = Vec::new();
        for mut o in std::mem::take(&mut row.outcomes) {
            o.attractor = o.attractor.and_then(new_id);
            match merged
                .iter_mut()
                .find(|m| m.attractor.is_some() && m.attractor == o.attractor)
            {
                Some(m) => {
                    m.count += o.count;
                    m.fraction += o.fraction;
                }
                None => merged.push(o),
            }
        }
        row.outcomes = merged;
    }
    let mut out: Vec<Attractor> = Vec::with_capacity(kept.len());
    let merges: Vec<(usize, usize)> = (0..n)
        .filter(|&b| root(b) != b)
        .map(|b| (attractors[b].id, attractors[root(b)].id))
        .collect();
    for &k in &kept {
        let mut a = attractors[k].clone();
        // the merged ones' motions join the path (their grid speeds among them), and the
        // lowest death is the attractor's
        for b in (0..n).filter(|&b| b != k && root(b) == k) {
            let other = &attractors[b];
            for m in &other.path {
                if !a
                    .path
                    .iter()
                    .any(|p| (p.speed_m_s - m.speed_m_s).abs() < 1e-9)
                {
                    a.path.push(m.clone());
                }
            }
            if other.lowest_m_s() < a.lowest_m_s() {
                a.dies_m_s = other.dies_m_s;
                a.fate = other.fate.clone();
            }
        }
        a.path.sort_by(|x, y| y.speed_m_s.total_cmp(&x.speed_m_s));
        out.push(a);
    }
    *attractors = out;
    merges
}

/// What the initial states of one speed ended on, with the basin fractions.
fn outcomes(motions: &[Motion], ids: &[Option<usize>]) -> Vec<Outcome> {
    let n = motions.len().max(1);
    let mut out: Vec<Outcome> = Vec::new();
    for (m, id) in motions.iter().zip(ids) {
        let key = |o: &Outcome| match (id, o.attractor) {
            (Some(i), Some(j)) => *i == j,
            (None, None) => o.kind == m.kind,
            _ => false,
        };
        match out.iter_mut().find(|o| key(o)) {
            Some(o) => o.count += 1,
            None => out.push(Outcome {
                attractor: *id,
                kind: m.kind,
                count: 1,
                fraction: 0.0,
                amplitude_m: if m.kind.is_hunting() {
                    m.amplitude_m()
                } else {
                    0.0
                },
            }),
        }
    }
    for o in &mut out {
        o.fraction = o.count as f64 / n as f64;
    }
    out
}

/// One note per kind of motion that is no verdict on an attractor (out of the geometry's
/// range, unsettled, diverged) at speed `v`, with the starts that ended so.
fn non_attractors(
    v: f64,
    motions: &[Motion],
    starts: &[(StartKind, String, Vec<f64>)],
    limit: Option<f64>,
) -> Vec<String> {
    let mut out = Vec::new();
    for kind in [
        MotionKind::OutOfRange,
        MotionKind::Unsettled,
        MotionKind::Diverged,
    ] {
        let which: Vec<&str> = motions
            .iter()
            .zip(starts)
            .filter(|(m, _)| m.kind == kind)
            .map(|(_, s)| s.1.as_str())
            .collect();
        if which.is_empty() {
            continue;
        }
        let what = match (kind, limit) {
            (MotionKind::OutOfRange, Some(g)) => format!(
                "left the contact geometry's range (±{:.3} mm): no attractor is derived from extrapolated geometry (contact.extrapolate = \"linear\" follows them)",
                g * 1e3
            ),
            (MotionKind::Unsettled, _) => "had not settled at the time limit (attractors.settle)".into(),
            _ => format!("ended {}", kind.name()),
        };
        let listed = which.len().min(4);
        out.push(format!(
            "at {v:.2} m/s {} of {} initial states {what} ({}{})",
            which.len(),
            motions.len(),
            which[..listed].join("; "),
            if which.len() > listed { "; …" } else { "" }
        ));
    }
    out
}

/// What the search has found so far, grown speed by speed.
#[derive(Default)]
struct Found {
    attractors: Vec<Attractor>,
    rows: Vec<SpeedRow>,
    notes: Vec<String>,
    /// every initial state used, in words (the kicks, then the continued cycles as they occur)
    starts_listed: Vec<(StartKind, String)>,
}

/// One speed of the grid: the kicks and the continuation's stable cycles there simulated (in
/// parallel) and classified, each hunting motion identified (a known attractor or a new one),
/// the new ones followed down through the speeds `searched` (highest first), the speed's row
/// added. At a `refined` speed, between the grid's, a motion is a known attractor also where
/// that attractor's descent passed within 5 % of the speed with the same motion ([`covered`]),
/// since no descent stopped at it.
fn search_speed<const N: usize>(
    ctx: &Ctx<'_>,
    found: &mut Found,
    v: f64,
    searched: &[f64],
    refined: bool,
) {
    let mut starts = ctx.kicked.clone();
    for c in continued_starts(ctx.continued, v) {
        if !found.starts_listed.iter().any(|s| s.1 == c.1) {
            found.starts_listed.push((c.0, c.1.clone()));
        }
        starts.push(c);
    }
    ctx.say(&format!(
        "  {v:.2} m/s{}: {} initial states",
        if refined { " (refined)" } else { "" },
        starts.len()
    ));
    let motions: Vec<Motion> = if ctx.opts.parallel {
        starts
            .par_iter()
            .map(|s| ctx.classify::<N>(v, &s.2))
            .collect()
    } else {
        starts.iter().map(|s| ctx.classify::<N>(v, &s.2)).collect()
    };
    // each motion: a known attractor (its path passes this speed), a new one, or none
    let mut ids: Vec<Option<usize>> = Vec::with_capacity(motions.len());
    let mut fresh: Vec<usize> = Vec::new();
    for m in &motions {
        if !m.kind.is_hunting() {
            ids.push(None);
            continue;
        }
        let near = refined.then(|| covering(&found.attractors, m)).flatten();
        let id =
            near.unwrap_or_else(|| identify(&mut found.attractors, &mut fresh, m, ctx.continued));
        ids.push(Some(id));
    }
    found.notes.extend(non_attractors(
        v,
        &motions,
        &starts,
        ctx.opts.geometry_limit,
    ));
    follow::<N>(ctx, &mut found.attractors, &fresh, searched, ctx.continued);
    found.rows.push(SpeedRow {
        speed_m_s: v,
        starts: motions.len(),
        outcomes: outcomes(&motions, &ids),
        refined,
    });
}

/// The lowest speed at which a hunting motion is known: the lowest of the search's attractors
/// and the continuation's V_NL.
fn lowest_hunting(attractors: &[Attractor], continued: Option<&BifurcationReport>) -> Option<f64> {
    attractors
        .iter()
        .filter(|a| a.kind.is_hunting())
        .map(Attractor::lowest_m_s)
        .chain(
            continued
                .and_then(|r| r.nonlinear_critical_speed)
                .map(|v| v.0),
        )
        .min_by(f64::total_cmp)
}

/// The speeds that halve the grid's spacing `h` (m/s) below `top` (the lowest speed of a
/// hunting motion known, m/s): the midpoint of every gap wider than h/2 between neighbouring
/// speeds of `top` and the speeds `searched` below it. Any attractor that would lower V_NL
/// lives below `top`; one that lives over a span of speeds wider than h/2 there (within the
/// grid's range) then meets a speed of the grid or of these. Highest first.
fn refined_speeds(searched: &[f64], top: f64, h: f64) -> Vec<f64> {
    let mut points: Vec<f64> = searched
        .iter()
        .copied()
        .filter(|&v| v < top - 1e-9)
        .collect();
    points.push(top);
    points.sort_by(|x, y| y.total_cmp(x));
    points
        .windows(2)
        .filter(|w| w[0] - w[1] > 0.5 * h * (1.0 + 1e-9))
        .map(|w| 0.5 * (w[0] + w[1]))
        .collect()
}

/// Runs the search; `progress` gets a line of text per speed and per descent, `cancel` is asked
/// between simulations' batches.
pub fn search(
    study: &str,
    model: &Vehicle,
    opts: &AttractorOptions,
    continued: Option<&BifurcationReport>,
) -> Result<AttractorReport, String> {
    search_with_hooks(study, model, opts, continued, None, None)
}

/// [`search`] with a progress report and a cancellation hook.
pub fn search_with_hooks(
    study: &str,
    model: &Vehicle,
    opts: &AttractorOptions,
    continued: Option<&BifurcationReport>,
    progress: Option<&(dyn Fn(&str) + Sync)>,
    cancel: Option<&(dyn Fn() -> bool + Sync)>,
) -> Result<AttractorReport, String> {
    crate::with_states!(model.states(), N => search_states::<N>(study, model, opts, continued, progress, cancel),
        _ => Err(format!("no analysis is compiled for {} states", model.states())))
}

fn search_states<const N: usize>(
    study: &str,
    model: &Vehicle,
    opts: &AttractorOptions,
    continued: Option<&BifurcationReport>,
    progress: Option<&(dyn Fn(&str) + Sync)>,
    cancel: Option<&(dyn Fn() -> bool + Sync)>,
) -> Result<AttractorReport, String> {
    let ctx = Ctx {
        model,
        opts,
        settle: Settle {
            max_time: opts.settle,
            threshold: opts.threshold,
            max_period: opts.max_period,
            geometry_limit: opts.geometry_limit,
            rtol: opts.rtol,
            cycle_rtol: cycle_rtol(opts.rtol),
        },
        progress,
        cancel,
        simulations: std::sync::atomic::AtomicUsize::new(0),
        kicked: kicks(model, &opts.amplitudes),
        continued,
    };
    let grid = opts.grid();
    let mut found = Found {
        starts_listed: ctx.kicked.iter().map(|k| (k.0, k.1.clone())).collect(),
        ..Found::default()
    };
    for &v in &grid {
        if ctx.cancelled() {
            found.notes.push("cancelled".into());
            break;
        }
        search_speed::<N>(&ctx, &mut found, v, &grid, false);
    }
    // the continuation's lowest stable cycles, each checked by a descent of its own unless an
    // attractor already followed passes there
    let mut fresh = Vec::new();
    let mut ends: Vec<(f64, Vec<f64>, String)> = stretch_ends(continued)
        .into_iter()
        .filter(|e| e.0 >= opts.lowest)
        .collect();
    // the seeds (motions other methods know) after them, each with a verdict of its own
    let first_seed = ends.len();
    ends.extend(
        opts.seeds
            .iter()
            .map(|s| (s.speed_m_s, s.state.clone(), s.source.clone())),
    );
    let checked: Vec<Motion> = if opts.parallel {
        ends.par_iter()
            .map(|e| ctx.classify::<N>(e.0, &e.1))
            .collect()
    } else {
        ends.iter().map(|e| ctx.classify::<N>(e.0, &e.1)).collect()
    };
    for (k, (m, e)) in checked.iter().zip(&ends).enumerate() {
        if k >= first_seed {
            // a seed that hunts: followed as a motion of its own unless an attractor already
            // followed passes its speed with its motion (then it is that attractor)
            if m.kind.is_hunting() {
                identify(&mut found.attractors, &mut fresh, m, continued);
            }
            continue;
        }
        if !m.kind.is_hunting() {
            found.notes.push(format!(
                "{} is not an attractor by simulation: {}{}",
                e.2,
                m.kind.name(),
                if m.note.is_empty() {
                    String::new()
                } else {
                    format!(" ({})", m.note)
                }
            ));
            continue;
        }
        let covered = found.attractors.iter().any(|a| {
            a.dies_m_s
                .is_some_and(|d| d.1 <= m.speed_m_s + 2.0 * opts.bracket)
                && a.path.iter().any(|p| same(p, m, 0.2))
        });
        if !covered {
            identify(&mut found.attractors, &mut fresh, m, continued);
        }
    }
    follow::<N>(&ctx, &mut found.attractors, &fresh, &grid, continued);
    // below the lowest hunting speed known, where another attractor would lower V_NL, the
    // grid's spacing is halved (and again below a lower one that the new speeds find)
    let mut searched = grid.clone();
    while let (Some(h), Some(top)) = (opts.spacing(), lowest_hunting(&found.attractors, continued))
    {
        let new = refined_speeds(&searched, top, h);
        if new.is_empty() || ctx.cancelled() {
            break;
        }
        let listed: Vec<String> = new.iter().map(|v| format!("{v:.2}")).collect();
        found.notes.push(format!(
            "below {top:.2} m/s, the lowest speed of a hunting motion known then, the grid's spacing of {h:.2} m/s was halved: kicks also at {} m/s",
            listed.join(", ")
        ));
        for v in new {
            searched.push(v);
            searched.sort_by(|x, y| y.total_cmp(x));
            search_speed::<N>(&ctx, &mut found, v, &searched, true);
        }
    }
    let Found {
        mut attractors,
        mut rows,
        notes,
        starts_listed,
    } = found;
    rows.sort_by(|x, y| y.speed_m_s.total_cmp(&x.speed_m_s));
    for (b, a) in merge_duplicates(&mut attractors, &mut rows, opts.bracket) {
        ctx.say(&format!(
            "  attractor {b} is attractor {a} (found again lower on its descent, dying in the same bracket): counted as attractor {a}"
        ));
    }
    let seed_checks: Vec<SeedCheck> = checked
        .iter()
        .skip(first_seed)
        .zip(&opts.seeds)
        .map(|(m, s)| seed_check(&attractors, s, m))
        .collect();
    let vnl = attractors
        .iter()
        .filter(|a| a.kind.is_hunting())
        .min_by(|a, b| a.lowest_m_s().total_cmp(&b.lowest_m_s()))
        .map(|a| (a.lowest_m_s(), a.dies_m_s, a.id));
    Ok(AttractorReport {
        study: study.to_string(),
        body_names: model.bodies.iter().map(|b| b.name.clone()).collect(),
        options: opts.clone(),
        starts: starts_listed,
        speeds: rows,
        attractors,
        nonlinear_critical_speed: vnl,
        seed_checks,
        notes,
        simulations: ctx.simulations.load(std::sync::atomic::Ordering::Relaxed),
    })
}

#[cfg(test)]
mod slow_decay_tests {
    use super::slow_decay;

    /// The normal form r' = μr − ar³ in closed form: u = 1/r² = u∞ + (u0 − u∞)e^{−2μt} with
    /// u∞ = a/μ (u0 + 2at at μ = 0), sampled at the ends of equal runs.
    fn normal_form(mu: f64, a: f64, r0: f64, runs: usize, length: f64) -> Vec<f64> {
        let u0 = 1.0 / (r0 * r0);
        (0..runs)
            .map(|k| {
                let t = (k as f64 + 1.0) * length;
                let u = if mu == 0.0 {
                    u0 + 2.0 * a * t
                } else {
                    a / mu + (u0 - a / mu) * (-2.0 * mu * t).exp()
                };
                1.0 / u.sqrt()
            })
            .collect()
    }

    #[test]
    fn the_normal_forms_decay_is_recognised_and_its_approach_to_a_cycle_is_not() {
        let a = 1e5; // 1/(m² s)
        for mu in [-0.05, -1e-3, 0.0] {
            let e = normal_form(mu, a, 2e-3, 4, 30.0);
            assert!(slow_decay(&e).is_some(), "mu {mu}: {e:?}");
        }
        // μ > 0: towards the cycle of r² = μ/a from above, falling all the way
        for mu in [1e-3, 0.05] {
            let e = normal_form(mu, a, 2e-3, 4, 30.0);
            assert!(e.windows(2).all(|w| w[1] < w[0]), "{e:?}");
            assert!(slow_decay(&e).is_none(), "mu {mu}: {e:?}");
        }
        // three runs are not enough, and a run that grows is no decay
        assert!(slow_decay(&normal_form(-0.05, a, 2e-3, 3, 30.0)).is_none());
        assert!(slow_decay(&[1e-3, 8e-4, 9e-4, 5e-4]).is_none());
    }
}

#[cfg(test)]
mod refine_tests {
    use super::refined_speeds;

    /// Below the lowest hunting speed every gap wider than half the spacing gets its midpoint;
    /// the gap to that speed itself counts, the speeds above it do not.
    #[test]
    fn the_gaps_below_the_lowest_hunting_speed_are_halved() {
        let grid: Vec<f64> = (0..7).map(|i| 236.0 - 25.0 * i as f64).collect();
        // 111 and 86 lie below 124: the gaps (124, 111) of 13 and (111, 86) of 25 exceed 12.5
        let v = refined_speeds(&grid, 124.0, 25.0);
        assert_eq!(v.len(), 2, "{v:?}");
        assert!(
            (v[0] - 117.5).abs() < 1e-12 && (v[1] - 98.5).abs() < 1e-12,
            "{v:?}"
        );
        // a gap of exactly half the spacing is not split again, and nothing lies below 86
        let v = refined_speeds(&[111.0, 98.5, 86.0], 110.9, 25.0);
        assert!(v.is_empty(), "{v:?}");
        assert!(refined_speeds(&grid, 80.0, 25.0).is_empty());
    }
}
