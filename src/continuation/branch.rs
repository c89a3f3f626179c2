//! Pseudo-arclength continuation of periodic orbits in (x0, T, p).
//!
//! Predictor: a step `ds` along the unit tangent (in scaled coordinates `z/scale`).
//! Corrector: Newton on the shooting residual, the phase condition through the predicted
//! point, and the arclength condition $⟨τ, (z − z_{pred})/s⟩ = 0$ (Keller 1977). The tangent of
//! the accepted point solves the bordered system with the old tangent as last row, so it is
//! oriented consistently; it passes through folds (where dp/ds changes sign) and vertical
//! stretches (dp/ds ≈ 0) alike. Step control by the Newton iteration count, with an angle
//! guard between consecutive tangents. Special points are found by sign changes along the
//! branch and located by the Illinois method on the arclength from the last point.

use std::sync::atomic::{AtomicBool, AtomicU64, AtomicUsize, Ordering, Ordering::Relaxed};

use nalgebra::{DMatrix, DVector, SVector};

use super::orbit::{solve_dense, Floquet, NewtonStop, OrbitPoint, SegmentSeed, Shooting};
use crate::system::ode::VectorField;

/// Continuation settings. Defaults are for orbits scaled to O(1) by `scale`.
#[derive(Clone, Debug, PartialEq)]
pub struct ContinuationParams {
    /// first step (scaled units); default 0.05
    pub ds_initial: f64,
    /// smallest step before giving up; default 1e-6
    pub ds_min: f64,
    /// largest step; default 0.5
    pub ds_max: f64,
    /// accepted points at most; default 300
    pub max_points: usize,
    /// Newton tolerance on the scaled update; default 1e-9
    pub newton_tol: f64,
    /// Newton iterations at most; default 8
    pub newton_max_iter: usize,
    /// the iteration count the step control aims at; default 4
    pub target_iterations: usize,
    /// Inexact first iteration: the first Newton iteration of a corrector integrates its
    /// flows at the relative tolerance `inexact_first` × (the previous corrector's first scaled
    /// update), within [rtol, 1e-6]; 0 keeps every iteration at the problem's tolerance.
    /// Default 1e-3. From a predicted point the first update is of order 1e-3 (scaled), and
    /// an update need only be accurate to a small fraction of itself for Newton to keep its
    /// rate; the iterations after it, and so every accepted orbit with its monodromy, use the
    /// problem's tolerance. Measured: a quarter fewer integrator steps on the cone and on
    /// S1002, the same Newton iteration counts (52 and 575 against 52 and 586).
    pub inexact_first: f64,
    /// largest angle between consecutive tangents (rad); default 0.3
    pub max_angle: f64,
    /// parameter bounds
    pub param_range: (f64, f64),
    /// amplitude bound (units of the caller's amplitude measure)
    pub max_amplitude: f64,
    /// scale of each unknown (x0 components, T, p): the arclength is measured in z/scale
    pub scale: Vec<f64>,
    /// relative tolerance of located special points, on the arclength
    pub locate_tol: f64,
    /// the most integrator steps (accepted and rejected) one Newton iteration of an accepted
    /// corrector may take before the branch stops there ([`BranchStop::TooStiff`]); `None`:
    /// no limit. Where a branch goes to low speeds the creep forces' time constant shrinks
    /// as 1/V, the explicit integrator's step is then set by stability rather than accuracy,
    /// and each cycle can cost minutes; the limit makes such a branch end with a reason.
    pub max_steps_per_iteration: Option<f64>,
    /// how many times a branch may double its shooting segments where the step falls below
    /// `ds_min` (it then goes on from its last cycle with the finer shooting); default 0.
    /// Multiple shooting with more, shorter segments is better conditioned where the flow
    /// over a segment is sensitive (near flange contact, at sharp turns of asymmetric
    /// branches), and the count depends only on the branch, never on the machine.
    pub refinements: usize,
    /// chord (Shamanskii) correctors: keep a linearisation's matrix for the following
    /// iterations, which then integrate the plain flows alone (see `correct`); `false`:
    /// Newton, a linearisation at every iteration. Default `false`: on the DTU bogie and car
    /// the chord halves the diagram's time with the same V_NL, but on the S1002 bogie it
    /// changed the branch's path (docs/performance.md, "Chord correctors") and on the S1002
    /// car it took 800 cycles and 121 s where Newton takes 579 cycles and 71 s.
    pub chord: bool,
}

impl ContinuationParams {
    /// Defaults with the given bounds and scales.
    pub fn new(param_range: (f64, f64), max_amplitude: f64, scale: Vec<f64>) -> Self {
        Self {
            ds_initial: 0.05,
            ds_min: 1e-6,
            ds_max: 0.5,
            max_points: 300,
            newton_tol: 1e-9,
            newton_max_iter: 8,
            target_iterations: 4,
            inexact_first: 1e-3,
            max_angle: 0.3,
            param_range,
            max_amplitude,
            scale,
            locate_tol: 1e-9,
            max_steps_per_iteration: None,
            refinements: 0,
            chord: false,
        }
    }
}

/// Why the branch ended.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum BranchStop {
    /// the parameter left its range at this value
    ParamBound { param: f64 },
    /// the amplitude exceeded its bound
    AmplitudeBound { amplitude: f64 },
    /// `max_points` were computed
    MaxPoints,
    /// the branch came back to the branch it was switched from (its [`Rejoin`] measure changed
    /// sign: an asymmetric branch meeting the symmetric one at a second symmetry-breaking
    /// point, a doubled branch meeting its parent at a second period-doubling point); the
    /// meeting point is the branch's last special point
    Rejoined { param: f64 },
    /// the step fell below `ds_min` without a converged corrector
    StepTooSmall { param: f64, newton: NewtonStop },
    /// the caller's cancellation hook asked to stop (checked before each step)
    Cancelled,
    /// the last cycle's Newton iterations took more integrator steps each than
    /// [`ContinuationParams::max_steps_per_iteration`]: the branch ends at that cycle
    TooStiff {
        param: f64,
        steps_per_iteration: f64,
        /// the cycle's integrated time over its steps (s)
        mean_step: f64,
        /// Dormand–Prince's stability bound 3.3/|λ|max at the centre there (s)
        stability_bound: f64,
    },
}

/// One accepted orbit of the branch.
#[derive(Clone, Debug, PartialEq)]
pub struct BranchPoint<const N: usize> {
    /// the orbit
    pub orbit: OrbitPoint<N>,
    /// its multipliers
    pub floquet: Floquet,
    /// the caller's amplitude measure
    pub amplitude: f64,
    /// the largest |x_k| over the orbit, per component (from the last Newton iteration's
    /// integration, one update of at most `newton_tol` away)
    pub peaks: SVector<f64, N>,
    /// the largest x_k over the orbit (same integration)
    pub high: SVector<f64, N>,
    /// the smallest x_k over the orbit (same integration)
    pub low: SVector<f64, N>,
    /// unit tangent (scaled)
    pub tangent: DVector<f64>,
    /// corrector iterations used (with chord correctors, linearisations and chord iterations)
    pub newton_iterations: usize,
    /// the shooting segments of the last linearisation (interior starts for the next solve)
    pub seed: SegmentSeed<N>,
}

/// Kinds of special points on a branch of cycles.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SpecialKind {
    /// fold (saddle-node) of cycles: dp/ds = 0
    Fold,
    /// a real multiplier passes −1
    PeriodDoubling,
    /// symmetric orbit: a half-period multiplier ν passes −1 (μ = +1 without a fold)
    SymmetryBreaking,
    /// a complex pair of multipliers leaves the unit circle (Neimark–Sacker)
    Torus,
}

impl SpecialKind {
    /// Name as written in outputs.
    pub fn name(self) -> &'static str {
        match self {
            SpecialKind::Fold => "fold",
            SpecialKind::PeriodDoubling => "period_doubling",
            SpecialKind::SymmetryBreaking => "symmetry_breaking",
            SpecialKind::Torus => "torus",
        }
    }
}

/// A special point between accepted points `after` and `after + 1`.
#[derive(Clone, Debug, PartialEq)]
pub struct SpecialPoint<const N: usize> {
    /// kind
    pub kind: SpecialKind,
    /// index of the accepted point before it
    pub after: usize,
    /// the located (or best bracketing) orbit
    pub orbit: OrbitPoint<N>,
    /// amplitude there
    pub amplitude: f64,
    /// the largest |x_k| over its orbit, per component
    pub peaks: SVector<f64, N>,
    /// whether it was located to `locate_tol`, or only bracketed
    pub located: bool,
    /// width of the final arclength bracket (scaled)
    pub bracket: f64,
}

/// A computed branch.
#[derive(Clone, Debug, PartialEq)]
pub struct Branch<const N: usize> {
    /// accepted orbits in order
    pub points: Vec<BranchPoint<N>>,
    /// special points in order
    pub special: Vec<SpecialPoint<N>>,
    /// why it ended
    pub stop: BranchStop,
    /// where the work went
    pub stats: BranchStats,
    /// where the segments were doubled (`ContinuationParams::refinements`): the speed of the
    /// last cycle before and the new segment count
    pub refined: Vec<(f64, usize)>,
}

/// A cycle of an earlier run to go on from, with that run's first rejoin measure.
type Resume<const N: usize> = (BranchPoint<N>, Option<DVector<f64>>);

impl<const N: usize> Branch<N> {
    /// This branch followed by `more`, a run resumed from this branch's last cycle (its first
    /// point, dropped here; with no cycles here, a fresh start) with the segments of
    /// `refined` (the speed where it resumed, the new count).
    fn followed_by(mut self, more: Branch<N>, refined: (f64, usize)) -> Branch<N> {
        let offset = self.points.len().saturating_sub(1);
        let skip = usize::from(!self.points.is_empty());
        self.points.extend(more.points.into_iter().skip(skip));
        self.special
            .extend(more.special.into_iter().map(|sp| SpecialPoint {
                after: sp.after + offset,
                ..sp
            }));
        self.stop = more.stop;
        self.stats = self.stats.plus(&more.stats);
        self.refined.push(refined);
        self.refined.extend(more.refined);
        self
    }
}

impl BranchStats {
    fn plus(&self, o: &BranchStats) -> BranchStats {
        BranchStats {
            failed_steps: self.failed_steps + o.failed_steps,
            angle_rejections: self.angle_rejections + o.angle_rejections,
            locate_corrections: self.locate_corrections + o.locate_corrections,
            newton_iterations: self.newton_iterations + o.newton_iterations,
            chord_iterations: self.chord_iterations + o.chord_iterations,
            integrator_steps: self.integrator_steps + o.integrator_steps,
            integrator_rejected: self.integrator_rejected + o.integrator_rejected,
        }
    }
}

/// Solver statistics of a branch: where the work went (all counts include the location of
/// special points).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct BranchStats {
    /// continuation steps whose corrector failed (each halves the step)
    pub failed_steps: usize,
    /// converged steps refused by the angle guard (each halves the step)
    pub angle_rejections: usize,
    /// correctors run to locate special points
    pub locate_corrections: usize,
    /// Newton iterations, i.e. shooting linearisations (failed correctors included)
    pub newton_iterations: usize,
    /// chord iterations (the plain flows alone, with the matrix of the last linearisation)
    pub chord_iterations: usize,
    /// accepted integrator steps of all flows (linearisations and chord iterations)
    pub integrator_steps: usize,
    /// integrator steps rejected by the error test (the same flows)
    pub integrator_rejected: usize,
}

/// A corrector stops when, from its third iteration on, the scaled update shrinks by less than
/// this factor while the previous one was still above the noise floor: Newton that does not
/// contract there will not converge in the iterations left. Measured over every corrector of
/// the studies in `studies/` (1 to 2 threads): the converging ones shrank their third update
/// by at least 1/0.54, and every larger ratio came after an update below 1e3 × the Newton
/// tolerance (integration noise); the correctors that ended at the iteration limit (S1002's
/// and the vehicles' near their folds) oscillated between 0.02 and 0.3 from their second
/// iteration, eight linearisations each for nothing.
const NOT_CONTRACTING: f64 = 0.75;
/// … the noise floor, in Newton tolerances.
const NOISE_FLOOR: f64 = 1e3;
/// A chord update that shrinks by less than this factor renews the corrector's matrix (a new
/// linearisation). A chord iteration costs the plain flows, a fifteenth of a linearisation on
/// the DTU car and a fifth on a wheelset; at this rate a decade of the update costs about two
/// chord iterations.
const CHORD_RATE: f64 = 0.3;
/// With chord correctors, a corrected orbit farther than this many steps from its prediction
/// is refused like a sharp turn (the step halves): on a smooth branch the correction is about
/// κ ds²/2 for a curvature κ, which the angle guard keeps below `max_angle`/2 × ds; a
/// correction half the step or longer has likely landed on another sheet. Measured on the
/// S1002 bogie (`studies/dtu-cooperrider-bogie-s1002.toml`): without the guard, a chord
/// corrector near the fold at 75.8 m/s converged onto another sheet and the branch missed its
/// folds at 75.83 and 49.82 m/s (V_NL 53.19 instead of 49.82 m/s); with it the folds are
/// found, but the branch needs more than its 400 cycles (Newton: 377).
const MAX_CORRECTION: f64 = 0.5;
/// Chord iterations a corrector may take, per Newton iteration allowed
/// ([`ContinuationParams::newton_max_iter`]); at the limit the matrix is renewed.
const CHORDS_PER_LIMIT: usize = 3;
/// Chord iterations end where their update falls below this many Newton tolerances: the plain
/// flows and the flows with their monodromies are integrated on different step sequences (the
/// monodromy's error enters the step control), and their orbits differ by their integration
/// errors, about 1e-8 scaled at rtol 1e-10 (measured on seed-hunting: the linearisation's
/// update after converged chords stayed at 1.1e-8 to 2.9e-8). The linearisation that follows
/// is accepted when its update is within the same bound: a Newton step from that close leaves
/// an error of second order in it.
const CONFIRM: f64 = 100.0;

/// Counters the corrector adds to (atomic: the driver is shared by reference).
#[derive(Default)]
struct Counters {
    /// bits of the last corrector's first scaled Newton update (0: none yet)
    first_update: AtomicU64,
    newton: AtomicUsize,
    chord: AtomicUsize,
    steps: AtomicUsize,
    rejected: AtomicUsize,
}

/// The corrector's result.
struct Corrected<const N: usize> {
    orbit: OrbitPoint<N>,
    floquet: Floquet,
    peaks: SVector<f64, N>,
    high: SVector<f64, N>,
    low: SVector<f64, N>,
    tangent: DVector<f64>,
    iterations: usize,
    seed: SegmentSeed<N>,
}

/// The orbit as the continuation's unknowns (x0, T, V).
pub(crate) fn pack<const N: usize>(z: &OrbitPoint<N>) -> DVector<f64> {
    DVector::from_fn(N + 2, |i, _| match i {
        i if i < N => z.x0[i],
        i if i == N => z.period,
        _ => z.param,
    })
}

/// The inverse of [`pack`].
pub(crate) fn unpack<const N: usize>(v: &DVector<f64>) -> OrbitPoint<N> {
    OrbitPoint {
        x0: SVector::from_fn(|i, _| v[i]),
        period: v[N],
        param: v[N + 1],
    }
}

/// How a branch switched from another one recognises that it has come back to it, from the
/// interior start $x_m$ of the middle shooting segment (the problem needs an even number of
/// segments $2m$; with an odd number the test is off):
///
/// * [`Rejoin::Mirror`]: an asymmetric branch of an odd field; $d = x_m + x_0$ ($x(T/2) + x(0)$)
///   vanishes on symmetric cycles, and the mirror image $−x(t + T/2)$ of a cycle has $−d$;
/// * [`Rejoin::Shift`]: a doubled branch; $d = x_m − x_0$ ($x(T) − x(0)$ of a cycle of period
///   2T) vanishes on the single cycle traversed twice, and the shift by T has $−d$.
///
/// At the meeting point the continuation would pass from the cycle to its image; so the branch
/// ends where $⟨d, d_1⟩$ ($d_1$ of its first cycle, in scaled units) changes sign.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Rejoin {
    /// asymmetric cycles of an odd field
    Mirror,
    /// cycles of doubled period
    Shift,
}

impl Rejoin {
    /// The kind of the point where the branch meets its parent.
    pub fn kind(self) -> SpecialKind {
        match self {
            Rejoin::Mirror => SpecialKind::SymmetryBreaking,
            Rejoin::Shift => SpecialKind::PeriodDoubling,
        }
    }
}

/// A measure of an orbit's size from its largest |x_k| per component (see `extent` below).
pub type Extent<'a, const N: usize> = dyn Fn(&SVector<f64, N>) -> f64 + Sync + 'a;

/// The continuation driver: a shooting problem plus settings and an amplitude measure.
pub struct Continuation<'a, const N: usize, F: VectorField<N>> {
    /// the shooting problem
    pub shooting: Shooting<'a, N, F>,
    /// settings
    pub params: ContinuationParams,
    /// the amplitude of an orbit (e.g. max |y| over a period), given the orbit and the largest
    /// |x_k| per component over it (located on the shooting integration's dense output)
    pub amplitude: &'a (dyn Fn(&OrbitPoint<N>, &SVector<f64, N>) -> f64 + Sync),
    /// called with each accepted orbit (progress reporting); `None` for silence
    pub progress: Option<&'a (dyn Fn(&BranchPoint<N>) + Sync)>,
    /// asked before each step whether to stop (`true`: the branch ends with
    /// [`BranchStop::Cancelled`], keeping the points so far); `None`: never
    pub cancel: Option<&'a (dyn Fn() -> bool + Sync)>,
    /// the measure that `params.max_amplitude` bounds, from the largest |x_k| per component
    /// (e.g. the largest lateral excursion of any wheelset, which must stay where the contact
    /// geometry is known); `None`: the amplitude
    pub extent: Option<&'a Extent<'a, N>>,
    /// end the branch where it meets the branch it was switched from; `None`: never
    pub rejoin: Option<Rejoin>,
}

impl<'a, const N: usize, F: VectorField<N>> Continuation<'a, N, F> {
    fn scale(&self) -> DVector<f64> {
        DVector::from_fn(N + 2, |i, _| {
            self.params.scale.get(i).copied().unwrap_or(1.0)
        })
    }

    /// Newton from the prediction `zp` with the arclength row `tangent` (scaled); `seed`: the
    /// segments of a nearby orbit's linearisation (interior shooting starts).
    ///
    /// A chord (Shamanskii) iteration: after a linearisation (the flows with their
    /// monodromies) the bordered matrix is kept, factorised, and the following iterations
    /// integrate the plain flows alone for the residual ([`Shooting::residual_chord`]). The
    /// matrix is renewed when a chord update shrinks by less than [`CHORD_RATE`], and once more
    /// at the orbit the chords converged to: every accepted orbit ends, as with Newton, on a
    /// linearisation at the problem's tolerance, whose update is at most `newton_tol` (Newton)
    /// or [`CONFIRM`] × `newton_tol` (after converged chords), and its multipliers, extremes
    /// and tangent are that linearisation's. Only with `params.chord`; otherwise Newton.
    fn correct(
        &self,
        zp: &DVector<f64>,
        tangent: &DVector<f64>,
        seed: Option<&SegmentSeed<N>>,
        counters: &Counters,
    ) -> Result<Corrected<N>, NewtonStop> {
        let s = self.scale();
        let xr: SVector<f64, N> = SVector::from_fn(|i, _| zp[i]);
        let fr = self.shooting.field.rhs(&xr, zp[N + 1]);
        let mut z = zp.clone();
        let mut last_seed = seed.cloned();
        let rtol = self.shooting.ode.tol.rtol;
        let max_chords = if self.params.chord {
            CHORDS_PER_LIMIT
        } else {
            0
        } * self.params.newton_max_iter;
        // the rows that do not change within a corrector: the phase and arclength conditions
        let mut a = DMatrix::zeros(N + 2, N + 2);
        for i in 0..N {
            a[(N, i)] = fr[i];
        }
        for i in 0..N + 2 {
            a[(N + 1, i)] = tangent[i] / s[i];
        }
        let rhs = |residual: &SVector<f64, N>, z: &DVector<f64>| {
            let mut b = DVector::zeros(N + 2);
            for i in 0..N {
                b[i] = -residual[i];
            }
            b[N] = -(0..N).map(|i| fr[i] * (z[i] - xr[i])).sum::<f64>();
            b[N + 1] = -(0..N + 2)
                .map(|i| tangent[i] * (z[i] - zp[i]) / s[i])
                .sum::<f64>();
            b
        };
        let mut factor: Option<nalgebra::LU<f64, nalgebra::Dyn, nalgebra::Dyn>> = None;
        let (mut linearisations, mut chords, mut iterations) = (0, 0, 0);
        let mut renew = true;
        let (mut confirming, mut newton_only) = (false, false);
        let mut previous = f64::INFINITY;
        loop {
            iterations += 1;
            let (delta, lin) = match factor.as_ref() {
                Some(lu) if !renew => {
                    chords += 1;
                    let frozen = last_seed.as_ref().ok_or(NewtonStop::Singular)?;
                    let ch = self
                        .shooting
                        .residual_chord(&unpack::<N>(&z), frozen, rtol)
                        .map_err(|_| NewtonStop::Diverged)?;
                    counters.chord.fetch_add(1, Relaxed);
                    counters.steps.fetch_add(ch.steps, Relaxed);
                    counters.rejected.fetch_add(ch.rejected, Relaxed);
                    let delta = lu
                        .solve(&rhs(&ch.residual, &z))
                        .ok_or(NewtonStop::Singular)?;
                    last_seed = Some(ch.seed);
                    (delta, None)
                }
                _ => {
                    linearisations += 1;
                    if linearisations > self.params.newton_max_iter {
                        return Err(NewtonStop::MaxIterations);
                    }
                    let first = f64::from_bits(counters.first_update.load(Relaxed));
                    let it_rtol = if iterations == 1 && self.params.inexact_first > 0.0 {
                        (self.params.inexact_first * first).clamp(rtol, rtol.max(1e-6))
                    } else {
                        rtol
                    };
                    let lin = self
                        .shooting
                        .linearise_at(&unpack::<N>(&z), last_seed.as_ref(), it_rtol)
                        .map_err(|_| NewtonStop::Diverged)?;
                    counters.newton.fetch_add(1, Relaxed);
                    counters.steps.fetch_add(lin.steps, Relaxed);
                    counters.rejected.fetch_add(lin.rejected, Relaxed);
                    last_seed = Some(lin.seed.clone());
                    a.view_mut((0, 0), (N, N + 2)).copy_from(&lin.jacobian);
                    let lu = a.clone().lu();
                    let delta = lu
                        .solve(&rhs(&lin.residual, &z))
                        .filter(|d| d.iter().all(|v| v.is_finite()))
                        .ok_or(NewtonStop::Singular)?;
                    factor = Some(lu);
                    (delta, Some((lin, it_rtol == rtol)))
                }
            };
            z += &delta;
            let size = delta
                .iter()
                .zip(s.iter())
                .map(|(d, sc)| (d / sc).abs())
                .fold(0.0, f64::max);
            if !size.is_finite() {
                return Err(NewtonStop::Diverged);
            }
            if iterations == 1 {
                counters.first_update.store(size.to_bits(), Relaxed);
            }
            match lin {
                Some((lin, exact)) => {
                    // After chords converged, this linearisation's Newton update is the last:
                    // from within `CONFIRM` tolerances its own error is of second order.
                    let accept = if confirming {
                        CONFIRM * self.params.newton_tol
                    } else {
                        self.params.newton_tol
                    };
                    if size <= accept && exact {
                        return self.corrected(&a, tangent, &z, lin, iterations);
                    }
                    if linearisations >= 3
                        && size > NOT_CONTRACTING * previous
                        && previous > NOISE_FLOOR * self.params.newton_tol
                    {
                        return Err(NewtonStop::NotContracting);
                    }
                    // Newton from here on once a confirmation failed: the plain flows' orbit
                    // and the linearisation's differ by more than their integration error
                    newton_only |= confirming;
                    confirming = false;
                    renew = newton_only || chords >= max_chords;
                }
                None => {
                    // converged by chords: a linearisation at the orbit confirms it and gives
                    // its multipliers; a poor contraction renews the matrix
                    confirming = size <= CONFIRM * self.params.newton_tol;
                    renew = confirming || size > CHORD_RATE * previous || chords >= max_chords;
                }
            }
            previous = size;
        }
    }

    /// The length of a corrector's correction from its prediction `zp`, in scaled units.
    fn correction(&self, zp: &DVector<f64>, c: &Corrected<N>) -> f64 {
        let s = self.scale();
        let z = pack(&c.orbit);
        (0..N + 2)
            .map(|i| ((z[i] - zp[i]) / s[i]).powi(2))
            .sum::<f64>()
            .sqrt()
    }

    /// The accepted orbit `z` of a corrector whose last linearisation `lin` (bordered matrix
    /// `a`) gave an update within the tolerance: its tangent and multipliers.
    fn corrected(
        &self,
        a: &DMatrix<f64>,
        tangent: &DVector<f64>,
        z: &DVector<f64>,
        lin: super::orbit::Linearised<N>,
        iterations: usize,
    ) -> Result<Corrected<N>, NewtonStop> {
        let s = self.scale();
        // New tangent: the same bordered matrix with the old tangent as last row.
        let mut e = DVector::zeros(N + 2);
        e[N + 1] = 1.0;
        let mut t = solve_dense(a.clone(), e).ok_or(NewtonStop::Singular)?;
        for i in 0..N + 2 {
            t[i] /= s[i];
        }
        let n = t.norm();
        if !(n > 0.0 && n.is_finite()) {
            return Err(NewtonStop::Singular);
        }
        t /= n;
        if t.dot(tangent) < 0.0 {
            t = -t;
        }
        Ok(Corrected {
            orbit: unpack(z),
            floquet: Floquet::from_monodromy(&lin.monodromy, self.shooting.symmetric),
            peaks: lin.peaks,
            high: lin.high,
            low: lin.low,
            tangent: t,
            iterations,
            seed: lin.seed,
        })
    }

    /// Newton at a fixed parameter from `guess` (the arclength row pins p): one periodic
    /// orbit solve. Returns the orbit, its multipliers and the iterations used.
    pub fn solve_at(
        &self,
        guess: OrbitPoint<N>,
    ) -> Result<(OrbitPoint<N>, Floquet, usize), NewtonStop> {
        let mut pin = DVector::zeros(N + 2);
        pin[N + 1] = 1.0;
        let c = self.correct(&pack(&guess), &pin, None, &Counters::default())?;
        Ok((c.orbit, c.floquet, c.iterations))
    }

    fn predict(&self, from: &DVector<f64>, tangent: &DVector<f64>, ds: f64) -> DVector<f64> {
        let s = self.scale();
        DVector::from_fn(N + 2, |i, _| from[i] + ds * tangent[i] * s[i])
    }

    /// Continues from `start` (need not be an orbit: the Hopf point with x0 = 0 serves)
    /// along the scaled direction `direction`.
    ///
    /// With parallel shooting on more than one rayon thread, the whole run executes on a
    /// worker of the current pool: a `join` from outside the pool hands its work to sleeping
    /// workers, whose wake-up took 0.3–0.7 ms on the 2-core machine measured (longer than
    /// many shooting integrations), so that the second thread often joined too late; from a
    /// worker, two 1 ms tasks ran 1.63–1.80× faster than in series against 1.14–1.39× when
    /// injected from outside (`examples/join_latency.rs`). The pool's other workers are kept
    /// awake for the run (`keep_awake`), also when it starts on a worker already (under
    /// `ThreadPool::install`); serial runs (a sweep's points) leave the pool as it is.
    ///
    /// Where the step falls below `ds_min`, the branch goes on from its last cycle (or, with
    /// none, from `start` again) with twice the segments, at most `params.refinements` times;
    /// [`Branch::refined`] lists where.
    pub fn run(&self, start: OrbitPoint<N>, direction: DVector<f64>) -> Branch<N> {
        let (mut branch, mut first) = self.run_awake(&start, &direction, None);
        let mut m = self.shooting.segments.max(1);
        for _ in 0..self.params.refinements {
            if !matches!(branch.stop, BranchStop::StepTooSmall { .. })
                || branch.points.len() >= self.params.max_points
            {
                break;
            }
            m *= 2;
            let mut finer = self.with_segments(m);
            // the resumed cycle counts again in the finer run's points
            finer.params.max_points = self.params.max_points + 1 - branch.points.len().max(1);
            let at = branch.points.last().map_or(start.param, |q| q.orbit.param);
            let resume = branch.points.last().map(|q| (q.clone(), first.clone()));
            let (more, f) = finer.run_awake(&start, &direction, resume);
            first = f;
            branch = branch.followed_by(more, (at, m));
        }
        branch
    }

    /// This continuation with `m` shooting segments.
    fn with_segments(&self, m: usize) -> Continuation<'a, N, F> {
        let s = &self.shooting;
        Continuation {
            shooting: Shooting {
                field: s.field,
                symmetric: s.symmetric,
                ode: s.ode,
                parallel: s.parallel,
                busy: s.busy.clone(),
                dp_rel: s.dp_rel,
                segments: m,
            },
            params: self.params.clone(),
            amplitude: self.amplitude,
            progress: self.progress,
            cancel: self.cancel,
            extent: self.extent,
            rejoin: self.rejoin,
        }
    }

    /// [`Self::run_here`] on a worker of the pool with its other workers awake, when the
    /// shooting is parallel.
    fn run_awake(
        &self,
        start: &OrbitPoint<N>,
        direction: &DVector<f64>,
        resume: Option<Resume<N>>,
    ) -> (Branch<N>, Option<DVector<f64>>) {
        if self.shooting.parallel
            && rayon::current_num_threads() > 1
            && self.shooting.busy.is_none()
        {
            return keep_awake(|| self.run_here(start, direction, resume));
        }
        self.run_here(start, direction, resume)
    }

    /// One run from `start` along `direction`, or from a `resume`d cycle of an earlier run
    /// (with that run's first rejoin measure); returns the branch (the resumed cycle is its
    /// first point) and the first rejoin measure.
    fn run_here(
        &self,
        start: &OrbitPoint<N>,
        direction: &DVector<f64>,
        resume: Option<Resume<N>>,
    ) -> (Branch<N>, Option<DVector<f64>>) {
        let p = &self.params;
        let mut z = pack(start);
        let mut tangent = direction.normalize();
        let mut ds = p.ds_initial;
        let mut points: Vec<BranchPoint<N>> = Vec::new();
        let mut special = Vec::new();
        let mut last_failure = NewtonStop::Converged;
        let mut seed: Option<SegmentSeed<N>> = None;
        let mut first_measure: Option<DVector<f64>> = None;
        if let Some((point, first)) = resume {
            z = pack(&point.orbit);
            tangent = point.tangent.clone();
            first_measure = first;
            points.push(point);
        }
        let counters = Counters::default();
        let mut stats = BranchStats::default();
        let stop = loop {
            if self.cancel.is_some_and(|c| c()) {
                break BranchStop::Cancelled;
            }
            if points.len() >= p.max_points {
                break BranchStop::MaxPoints;
            }
            if ds < p.ds_min {
                break BranchStop::StepTooSmall {
                    param: z[N + 1],
                    newton: last_failure,
                };
            }
            let zp = self.predict(&z, &tangent, ds);
            let steps_before = counters.steps.load(Relaxed) + counters.rejected.load(Relaxed);
            let c = match self.correct(&zp, &tangent, seed.as_ref(), &counters) {
                Ok(c)
                    if points.is_empty()
                        || (c.tangent.dot(&tangent) >= p.max_angle.cos()
                            && (!p.chord || self.correction(&zp, &c) <= MAX_CORRECTION * ds)) =>
                {
                    c
                }
                Ok(_) => {
                    stats.angle_rejections += 1;
                    ds *= 0.5;
                    continue;
                }
                Err(e) => {
                    stats.failed_steps += 1;
                    last_failure = e;
                    ds *= 0.5;
                    continue;
                }
            };
            // the corrector's own steps (the locating correctors below are not counted)
            let corrector_steps =
                counters.steps.load(Relaxed) + counters.rejected.load(Relaxed) - steps_before;
            let amplitude = (self.amplitude)(&c.orbit, &c.peaks);
            let extent = self.extent.map_or(amplitude, |e| e(&c.peaks));
            let here = self.rejoin_measure(&c);
            let point = BranchPoint {
                orbit: c.orbit,
                floquet: c.floquet,
                amplitude,
                peaks: c.peaks,
                high: c.high,
                low: c.low,
                tangent: c.tangent.clone(),
                newton_iterations: c.iterations,
                seed: c.seed.clone(),
            };
            if let Some(prev) = points.last() {
                let at = (points.len() - 1, ds);
                stats.locate_corrections += self.detect(prev, &point, at, &mut special, &counters);
                // back on the parent branch: locate the meeting point and end there
                let met = match (&first_measure, &here) {
                    (Some(d1), Some(d)) if d.dot(d1) < 0.0 => self.rejoin.map(|r| (r, d1)),
                    _ => None,
                };
                if let Some((r, d1)) = met {
                    // Where a branch of a pitchfork (symmetry breaking, or period doubling in
                    // the doubled problem) meets its parent it turns in p (p − p* ∝ d²), so the
                    // step found a fold there: that located turning point is the meeting point.
                    // Without one, the sign change of ⟨d, d₁⟩ is located, whose correctors near
                    // the parent branch may land on it (d = 0) a little away in p.
                    let fold_here = special
                        .last()
                        .is_some_and(|s| s.after == at.0 && s.kind == SpecialKind::Fold);
                    let sp = if fold_here {
                        special.pop().map(|s| SpecialPoint {
                            kind: r.kind(),
                            ..s
                        })
                    } else {
                        None
                    };
                    let sp = match sp {
                        Some(sp) => sp,
                        None => {
                            let g = |q: &Corrected<N>| {
                                self.rejoin_measure(q).map_or(f64::NAN, |d| d.dot(d1))
                            };
                            let (sp, n) = self.locate(prev, at, r.kind(), &g, &counters);
                            stats.locate_corrections += n;
                            sp
                        }
                    };
                    let param = sp.orbit.param;
                    special.push(sp);
                    break BranchStop::Rejoined { param };
                }
            } else {
                first_measure = here;
            }
            let param = point.orbit.param;
            let steps_per_iteration =
                corrector_steps as f64 / point.newton_iterations.max(1) as f64;
            if let Some(report) = self.progress {
                report(&point);
            }
            points.push(point);
            if p.max_steps_per_iteration
                .is_some_and(|limit| steps_per_iteration > limit)
            {
                let period = points.last().map_or(f64::NAN, |q| q.orbit.period);
                if let Some(stiff) = self.stiffness(param, period, steps_per_iteration) {
                    break stiff;
                }
            }
            z = pack(&c.orbit);
            tangent = c.tangent;
            seed = Some(c.seed);
            // Step control: aim at the target iteration count. Newton from a good predictor
            // often takes the same count over a wide range of steps, so at the target the step
            // still grows a little; the angle guard and ds_max bound it.
            let factor = match c.iterations.cmp(&p.target_iterations) {
                std::cmp::Ordering::Less => 1.6,
                std::cmp::Ordering::Equal => 1.25,
                std::cmp::Ordering::Greater => 0.6,
            };
            ds = (ds * factor).min(p.ds_max);
            if param < p.param_range.0 || param > p.param_range.1 {
                break BranchStop::ParamBound { param };
            }
            if extent > p.max_amplitude {
                break BranchStop::AmplitudeBound { amplitude: extent };
            }
        };
        stats.newton_iterations = counters.newton.load(Relaxed);
        stats.chord_iterations = counters.chord.load(Relaxed);
        stats.integrator_steps = counters.steps.load(Relaxed);
        stats.integrator_rejected = counters.rejected.load(Relaxed);
        let branch = Branch {
            points,
            special,
            stop,
            stats,
            refined: Vec::new(),
        };
        (branch, first_measure)
    }

    /// Whether the last cycle's steps (`steps_per_iteration` per Newton iteration) are set by
    /// stiffness: its mean step is within a factor 2 of Dormand–Prince's stability bound on
    /// the negative real axis, $3.3/|λ|_{max}$, with $|λ|_{max}$ the spectral radius of the
    /// Jacobian of the centred motion at `param` (the creep forces' modes, whose rates grow
    /// as 1/V). Steps far below that bound are set by accuracy (steep contact transitions,
    /// long periods) and do not stop the branch. `period` is the cycle's whole period (the
    /// symmetric form integrates half of it). `Some` stop with the figures, else `None`.
    fn stiffness(&self, param: f64, period: f64, steps_per_iteration: f64) -> Option<BranchStop> {
        let j = self.shooting.field.jacobian(&SVector::zeros(), param);
        let rho = crate::stability::eigenvalues(&j)?
            .iter()
            .map(|z| z.0.hypot(z.1))
            .fold(0.0, f64::max);
        let time = if self.shooting.symmetric {
            0.5 * period
        } else {
            period
        };
        let mean_step = time / steps_per_iteration;
        let bound = 3.3 / rho;
        (mean_step.is_finite() && rho > 0.0 && mean_step >= 0.5 * bound).then_some(
            BranchStop::TooStiff {
                param,
                steps_per_iteration,
                mean_step,
                stability_bound: bound,
            },
        )
    }

    /// The [`Rejoin`] measure $d$ of a corrected orbit, in scaled units; `None` when the test
    /// is off (no rejoin asked, or an odd number of segments).
    fn rejoin_measure(&self, c: &Corrected<N>) -> Option<DVector<f64>> {
        let r = self.rejoin?;
        let m = c.seed.len();
        if m < 2 || m % 2 == 1 {
            return None;
        }
        let mid = c.seed.start(m / 2)?;
        let x0 = c.orbit.x0;
        let sign = if r == Rejoin::Mirror { 1.0 } else { -1.0 };
        let s = self.scale();
        Some(DVector::from_fn(N, |i, _| (mid[i] + sign * x0[i]) / s[i]))
    }

    /// Sign changes between consecutive points, each located along the arclength from point
    /// `a` (`at`: its index and the step to `b`): the fold from the tangent, the multipliers'
    /// crossings of the unit circle from their census ([`super::special`]); returns the
    /// correctors run.
    fn detect(
        &self,
        a: &BranchPoint<N>,
        b: &BranchPoint<N>,
        at: (usize, f64),
        out: &mut Vec<SpecialPoint<N>>,
        counters: &Counters,
    ) -> usize {
        let mut runs = 0;
        let fold = |q: &Corrected<N>| q.tangent[N + 1];
        if a.tangent[N + 1].signum() != b.tangent[N + 1].signum() {
            let (sp, n) = self.locate(a, at, SpecialKind::Fold, &fold, counters);
            out.push(sp);
            runs += n;
        }
        for kind in super::special::crossings(&a.floquet, &b.floquet, self.shooting.symmetric) {
            let g = |q: &Corrected<N>| super::special::test_value(kind, &q.floquet);
            let (sp, n) = self.locate(a, at, kind, &g, counters);
            out.push(sp);
            runs += n;
        }
        runs
    }

    /// Illinois on the arclength s ∈ (0, ds) from point `a` (`at`: its index and ds) for a
    /// sign change of `g`; also returns the correctors run.
    fn locate(
        &self,
        a: &BranchPoint<N>,
        at: (usize, f64),
        kind: SpecialKind,
        g: &dyn Fn(&Corrected<N>) -> f64,
        counters: &Counters,
    ) -> (SpecialPoint<N>, usize) {
        let (index, ds) = at;
        let za = pack(&a.orbit);
        let runs = std::cell::Cell::new(0usize);
        let eval = |s: f64| {
            runs.set(runs.get() + 1);
            let zp = self.predict(&za, &a.tangent, s);
            self.correct(&zp, &a.tangent, Some(&a.seed), counters).ok()
        };
        let a_c = Corrected {
            orbit: a.orbit,
            floquet: a.floquet.clone(),
            peaks: a.peaks,
            high: a.high,
            low: a.low,
            tangent: a.tangent.clone(),
            iterations: 0,
            seed: a.seed.clone(),
        };
        let Some(end) = eval(ds) else {
            return (self.bracketed(kind, index, a, ds), runs.get());
        };
        let tol = self.params.locate_tol * ds.max(1.0);
        let (best, bracket) = illinois(g(&a_c), ds, end, tol, eval, g);
        let sp = SpecialPoint {
            kind,
            after: index,
            amplitude: (self.amplitude)(&best.orbit, &best.peaks),
            peaks: best.peaks,
            orbit: best.orbit,
            located: bracket <= tol,
            bracket,
        };
        (sp, runs.get())
    }

    fn bracketed(
        &self,
        kind: SpecialKind,
        index: usize,
        a: &BranchPoint<N>,
        ds: f64,
    ) -> SpecialPoint<N> {
        SpecialPoint {
            kind,
            after: index,
            orbit: a.orbit,
            amplitude: a.amplitude,
            peaks: a.peaks,
            located: false,
            bracket: ds,
        }
    }
}

/// Illinois (regula falsi with the retained end's value halved) on the arclength
/// $s ∈ (0, ds)$ for a sign change of `g`: `g0` is its value at $s = 0$, `end` the corrected
/// point at $s = ds$, `eval(s)` the corrector at $s$ (`None`: it failed). Returns the last
/// corrected point and the width of the final bracket (at most `tol` when located). Shared by
/// the special points of branches and of fold curves (`crate::bifurcation::fold_track`).
pub(crate) fn illinois<T>(
    g0: f64,
    ds: f64,
    end: T,
    tol: f64,
    mut eval: impl FnMut(f64) -> Option<T>,
    g: impl Fn(&T) -> f64,
) -> (T, f64) {
    let (mut lo, mut glo) = (0.0, g0);
    let (mut hi, mut ghi) = (ds, g(&end));
    let mut best = end;
    let mut side = 0i8;
    for _ in 0..60 {
        if (hi - lo).abs() <= tol {
            break;
        }
        let s = (lo * ghi - hi * glo) / (ghi - glo);
        let s = if s.is_finite() && s > lo && s < hi {
            s
        } else {
            0.5 * (lo + hi)
        };
        // A secant point within tol/2 of the end moved last would shrink the bracket by
        // less than that: step tol/2 past it instead, which closes the bracket when the root
        // lies there (the secant points otherwise crowd one end, where g is only as exact
        // as the correctors: S1002's fold took 13 correctors on two segments, 7 at s equal
        // to 5 digits).
        let s = match side {
            -1 if s - lo < 0.5 * tol => (lo + 0.5 * tol).min(hi),
            1 if hi - s < 0.5 * tol => (hi - 0.5 * tol).max(lo),
            _ => s,
        };
        // a corrector that fails at the secant point may converge at the bisection
        // point (near a fold the secant point can sit where the predictor is poor)
        let mid = 0.5 * (lo + hi);
        let Some((s, c)) = eval(s)
            .map(|c| (s, c))
            .or_else(|| (s != mid).then(|| eval(mid).map(|c| (mid, c))).flatten())
        else {
            break;
        };
        let gs = g(&c);
        if gs.signum() == glo.signum() {
            (lo, glo) = (s, gs);
            if side == -1 {
                ghi *= 0.5;
            }
            side = -1;
        } else {
            (hi, ghi) = (s, gs);
            if side == 1 {
                glo *= 0.5;
            }
            side = 1;
        }
        best = c;
    }
    (best, (hi - lo).abs())
}

/// Runs `work` on a worker of the current rayon pool while the pool's other workers stay
/// awake, executing the jobs `work` spawns as soon as they appear.
///
/// A rayon worker with nothing to steal spins for a few tens of microseconds and then
/// sleeps; the next `join` must wake it, which took 0.3–0.7 ms on the 2-core virtual machine
/// measured (`examples/join_latency.rs`), as long as a whole shooting integration of the
/// wheelset. Between two linearisations of a continuation there are only microseconds of
/// serial work, so helpers loop on [`rayon::yield_now`] (which runs any pending job) until
/// `work` returns: they use their cores for the whole run, as OpenMP's spin-waiting threads
/// do in AUTO-07p. S1002's diagram on two threads, medians of 10 and 16 alternating runs:
/// 788.6 against 840.2 ms and 731.7 against 751.4 ms with sleeping workers (1 thread: 1312.0
/// and 1204.2 ms).
fn keep_awake<R: Send>(work: impl FnOnce() -> R + Send) -> R {
    /// Tells the helpers to stop when `work` ends, also by a panic (the scope waits for them).
    struct Done<'a>(&'a AtomicBool);
    impl Drop for Done<'_> {
        fn drop(&mut self) {
            self.0.store(true, Ordering::Release);
        }
    }
    let done = AtomicBool::new(false);
    let done = &done;
    rayon::scope(|s| {
        let me = rayon::current_thread_index();
        for _ in 1..rayon::current_num_threads() {
            s.spawn(move |s| helper(s, done, me));
        }
        let _done = Done(done);
        work()
    })
}

/// One turn of a [`keep_awake`] helper: at most [`HELPER_TURN`] of running pending jobs, then
/// a successor job for the next turn.
///
/// A turn is bounded because a worker waiting inside a job (its own `join`) may steal a
/// helper: a helper that spun there until `work` ended would block the job beneath it, and
/// `work` may be waiting for that job. Ending the turn hands the worker back to the job;
/// the successor goes on the worker's deque, where the next idle worker takes it. On
/// `work`'s own thread a helper only hands itself on.
fn helper<'s>(s: &rayon::Scope<'s>, done: &'s AtomicBool, me: Option<usize>) {
    if done.load(Ordering::Acquire) {
        return;
    }
    if rayon::current_thread_index() != me {
        let start = std::time::Instant::now();
        while !done.load(Ordering::Acquire) && start.elapsed() < HELPER_TURN {
            if rayon::yield_now() != Some(rayon::Yield::Executed) {
                // the OS's yield rather than a pause loop: a core another process needs is
                // handed over, and a hypervisor sees no spinning lock
                std::thread::yield_now();
            }
        }
    }
    if !done.load(Ordering::Acquire) {
        s.spawn(move |s| helper(s, done, me));
    }
}

/// The longest turn of a [`keep_awake`] helper.
const HELPER_TURN: std::time::Duration = std::time::Duration::from_millis(1);

#[cfg(test)]
mod tests {
    use super::keep_awake;

    #[test]
    fn keep_awake_returns_the_work_and_its_joins_results() {
        let sum = keep_awake(|| {
            let (a, b) = rayon::join(
                || (1..=1000u64).sum::<u64>(),
                || (1..=10u64).product::<u64>(),
            );
            a + b
        });
        assert_eq!(sum, 500_500 + 3_628_800);
    }

    #[test]
    fn keep_awake_ends_its_helpers_when_the_work_panics() {
        // the helpers stop through the drop guard; without it the scope would never end
        let r = std::panic::catch_unwind(|| keep_awake(|| -> u32 { panic!("work failed") }));
        assert!(r.is_err());
        // and the pool still serves work afterwards
        assert_eq!(keep_awake(|| rayon::join(|| 2, || 3)), (2, 3));
    }

    /// Nested joins in several runs at once on a 3-thread pool, started on its workers and
    /// inside other joins: every run ends with its exact sum. (The stall that bounded turns
    /// rule out, a helper stolen inside a job its run waits for, needs a rare interleaving:
    /// this test did not stall with unbounded turns either.)
    #[test]
    fn concurrent_runs_with_nested_joins_all_end() -> Result<(), rayon::ThreadPoolBuildError> {
        fn tree(depth: u32) -> u64 {
            if depth == 0 {
                return (0..20_000u64).map(|k| k * k % 7).sum();
            }
            let (a, b) = rayon::join(|| tree(depth - 1), || tree(depth - 1));
            a + b
        }
        let expected = tree(0) << 6;
        let pool = rayon::ThreadPoolBuilder::new().num_threads(3).build()?;
        let results: Vec<u64> = std::thread::scope(|s| {
            let runs: Vec<_> = (0..4)
                .map(|k| {
                    let pool = &pool;
                    s.spawn(move || {
                        (0..20)
                            .map(|_| {
                                if k % 2 == 0 {
                                    pool.install(|| keep_awake(|| tree(6)))
                                } else {
                                    pool.install(|| {
                                        rayon::join(|| keep_awake(|| tree(6)), || tree(3)).0
                                    })
                                }
                            })
                            .sum::<u64>()
                    })
                })
                .collect();
            runs.into_iter().map(|r| r.join().unwrap_or(0)).collect()
        });
        assert_eq!(results, vec![20 * expected; 4]);
        Ok(())
    }
}
