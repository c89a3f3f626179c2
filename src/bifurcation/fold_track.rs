//! Folds of cycles continued over a design key (`critspeed curve`'s `"fold"` curves).
//!
//! A fold (saddle-node) of cycles is a cycle at which the shooting problem's Jacobian in the
//! orbit's own unknowns is singular. With $G(x_0, T, V; p)$ the shooting residual (half period
//! for symmetric cycles, [`crate::continuation::Shooting`]) and the Poincaré phase row
//! $⟨f_r, x_0 − x_r⟩$, let
//!
//! $$A = \begin{pmatrix} G_{x_0} & G_T \\ f_r^⊤ & 0 \end{pmatrix}, \qquad
//! \begin{pmatrix} A & b \\ c^⊤ & 0 \end{pmatrix} \begin{pmatrix} v \\ g \end{pmatrix} =
//! \begin{pmatrix} 0 \\ 1 \end{pmatrix}.$$
//!
//! The bordered matrix is regular near the fold when $b$ and $c$ approximate $A$'s left and
//! right null vectors, and the scalar $g(x_0, T, V, p)$ vanishes exactly where $A$ is singular
//! (the minimally augmented system of Govaerts, *Numerical Methods for Bifurcations of
//! Dynamical Equilibria*, SIAM 2000, §4; AUTO-07p's and MatCont's fold-of-cycles curves solve
//! the same condition on a collocation discretisation). The fold curve is the solution set of
//!
//! $$G = 0, \quad ⟨f_r, x_0 − x_r⟩ = 0, \quad g = 0$$
//!
//! in the $N + 3$ unknowns $(x_0, T, V, p)$, continued by pseudo-arclength in scaled units
//! (Keller), so that it is followed round turns in the key: where the curve turns in $p$ two
//! folds meet and vanish, a **cusp** of cycles (CPC), located on the arclength. The borders are
//! taken afresh from the null vectors at each corrector's first iterate. $∂G/∂p$ is a one-sided
//! difference of two plain flows (the model rebuilt at the shifted key value). The gradient
//! of $g$ is $−w^⊤ (∂A/∂u)\,v$ with $v$, $w$ the bordered system's right and left null
//! vectors: the first $N$ rows of $Av$ are the derivative of the shooting map in the direction
//! $(v_x, v_T)$, one tangent of the time-normalised flow, so each component of the gradient is
//! a one-sided difference of two such tangents, all integrated on one fixed step sequence (so
//! that the differences are smooth in the unknowns). That is $N + 4$ flows with one tangent
//! each, on rayon threads, instead of $N + 3$ monodromies: cheap enough to take at every
//! iterate, so the corrector is Newton's method proper and converges quadratically.
//!
//! The key's values of the curve's grid are user points: wherever an accepted step crosses
//! one, the fold there is solved with the key pinned to it, so that V_NL can be compared across
//! curves at the same values. Along the curve the multipliers other than the two at +1 (the
//! trivial one and the fold's) are watched: a real one through −1 is a fold–flip point
//! (LPPD; on a symmetric branch the fold meets a symmetry-breaking point, LPSB), a complex pair
//! through the unit circle a fold–torus point (LPNS); these change which side of the fold is
//! stable. A fold whose amplitude falls to zero has reached the Hopf curve at a generalised
//! Hopf (Bautin) point, where the curve ends.
//!
//! The same system with another test matrix continues the **flips** of the shooting map, where
//! one of its multipliers passes −1: on a symmetric branch (half-period map, multiplier ν) the
//! symmetry-breaking points, where asymmetric cycles branch off; on a full-period branch the
//! period doublings. There $A = Φ - I$ (symmetric: the residual is $φ(T/2, x_0) + x_0$, so
//! ν = −1 is an eigenvalue +1 of Φ) or $A = Φ + I$, $N × N$ without the phase row; its
//! $Av = Φv ± v$ has the derivative of one tangent in the direction $(v_x, 0)$, so the gradient
//! is the fold's with $v_T = 0$.

use nalgebra::{Complex, DMatrix, DVector, SVector};
use rayon::prelude::*;

use super::driver::{Run, Setup};
use super::BranchKind;

use crate::continuation::branch::{illinois, pack};
use crate::continuation::{
    orbit::Linearised, Floquet, OrbitPoint, SegmentSeed, Shooting, SpecialKind,
};
use crate::model::Vehicle;
use crate::system::ode::{integrate, step_times, tangent_on_steps, OdeOptions, VectorField};

/// A located "fold" of smaller amplitude (m) is the Hopf point itself: the fold curve has
/// reached a generalised Hopf point and ends.
/// The relative step of the differences of the tangents in the state, period and speed: the
/// tangents are computed on one fixed step sequence, so they are smooth in these unknowns and
/// the step can be far below the integration tolerance's square root.
const TANGENT_STEP: f64 = 1e-7;

const MIN_FOLD_AMPLITUDE: f64 = 2e-5;

/// One scaled unit of a torus curve's angle θ (rad).
const THETA_UNIT: f64 = 0.05;

/// A torus curve ends where sin θ falls below this: its pair of multipliers on the unit
/// circle is about to become real (a 1:1 resonance, where it meets a fold curve, or a 1:2
/// resonance, where it meets a flip curve), and the system degenerates.
const MIN_SIN_THETA: f64 = 0.01;

/// A fold curve that cannot be continued further with a smaller amplitude (m) ends near a
/// generalised Hopf point: the fold system degenerates as the amplitude falls to zero.
const NEAR_HOPF_AMPLITUDE: f64 = 2.5e-4;

/// The step (scaled) below which a fold curve under [`NEAR_HOPF_AMPLITUDE`] ends.
const NEAR_HOPF_DS: f64 = 0.01;

/// Accepted points of one direction of a fold curve at most.
const MAX_POINTS: usize = 400;

/// Newton iterations of one corrector at most.
const MAX_ITERATIONS: usize = 12;

/// A corrector whose update shrinks by less than this factor has stalled: its borders are
/// taken afresh once, and a second stall in a row fails it.
const STALL: f64 = 0.3;

/// Updates that stall below this many Newton tolerances are integration noise: the corrector
/// has converged.
const NOISE_FLOOR: f64 = 100.0;

/// The largest angle between consecutive tangents (rad).
const MAX_ANGLE: f64 = 0.3;

/// Steps along the curve (scaled units: the key's range is [`KEY_UNITS`] units, 1 m/s of speed
/// and about 1 mm of amplitude one unit).
const DS_INITIAL: f64 = 0.5;
const DS_MAX: f64 = 12.0;
const DS_MIN: f64 = 1e-4;

/// The key's whole range in scaled units.
const KEY_UNITS: f64 = 100.0;

/// What a curve of the fold system continues.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TrackKind {
    /// folds of cycles (the shooting Jacobian singular with the phase row)
    Fold,
    /// a multiplier of the shooting map at −1: symmetry breaking on a symmetric branch,
    /// period doubling on a full-period one
    Flip,
    /// a complex pair of multipliers of the shooting map on the unit circle, e^{±iθ}
    /// (Neimark–Sacker: a torus branches off)
    Torus,
}

/// A family of models over a design key.
pub struct FoldTracking<'a> {
    /// the grid's key values (SI) after the one the diagram was computed at, in order
    pub values: &'a [f64],
    /// the grid's key values (SI) before it, nearest first
    pub back: &'a [f64],
    /// the key's value of the diagram (SI)
    pub first: f64,
    /// the model at a key value
    pub model_at: &'a (dyn Fn(f64) -> Result<Vehicle, String> + Sync),
    /// what to continue from the diagram's points: its folds, its flips (symmetry-breaking
    /// and period-doubling points), or both
    pub kinds: &'a [TrackKind],
    /// `skip(kind, symmetric branch, speed m/s, amplitude m)`: a point of the diagram not to
    /// follow (one a curve of that kind already passes through, or a flip of a kind not asked
    /// for: a symmetry-breaking point is a flip of a symmetric branch, a period doubling one of
    /// a full-period branch)
    pub skip: &'a (dyn Fn(TrackKind, bool, f64, f64) -> bool + Sync),
    /// called once per fold curve when it is done, with the curve and its wall time (s)
    pub done: Option<&'a Done<'a>>,
    /// called once the diagram is done, before its first point is considered for a curve:
    /// the caller may wait there (for other diagrams' curves, which `skip` reads)
    pub ready: Option<&'a (dyn Fn() + Sync)>,
}

/// `done(curve, wall time s)`, called as each fold curve is finished (progress).
pub type Done<'a> = dyn Fn(&FoldTrack, f64) + Sync + 'a;

/// One point of a fold curve.
#[derive(Clone, Debug, PartialEq)]
pub struct FoldTrackPoint {
    /// the key's value (SI)
    pub parameter: f64,
    /// the fold's speed (m/s)
    pub speed_m_s: f64,
    /// the cycle's period (s)
    pub period_s: f64,
    /// the leading wheelset's max |y| over the cycle (m)
    pub amplitude_m: f64,
    /// whether a stable cycle branch ends at the fold (every multiplier but the two at +1
    /// inside the unit circle): such a fold is where a hunting motion disappears, a candidate
    /// for V_NL
    pub stable_side: bool,
    /// a solution of the fold system to Newton's tolerance
    pub located: bool,
    /// a user point: the key pinned to a value of the grid
    pub on_grid: bool,
    /// on a torus curve, the angle θ (rad, in (0, π)) of the shooting map's multipliers
    /// e^{±iθ} on the unit circle
    pub angle_rad: Option<f64>,
    /// the cycle's state at its section (t = 0), in the model's state order: where a
    /// simulation or a search can start on the motion the curve follows
    pub state: Vec<f64>,
}

/// Codimension-two points on a fold curve.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FoldSpecialKind {
    /// the curve turns in the key: two folds meet and vanish (cusp of cycles)
    Cusp,
    /// a real multiplier passes −1 on the fold (fold–flip)
    FoldFlip,
    /// on a symmetric branch, a half-period multiplier passes −1 on the fold: the fold meets a
    /// symmetry-breaking point
    FoldSymmetryBreaking,
    /// a complex pair passes the unit circle on the fold (fold–Neimark–Sacker)
    FoldTorus,
}

/// A codimension-two point on a fold curve.
#[derive(Clone, Debug, PartialEq)]
pub struct FoldSpecial {
    /// what it is
    pub kind: FoldSpecialKind,
    /// the key's value (SI)
    pub parameter: f64,
    /// speed (m/s)
    pub speed_m_s: f64,
    /// the cycle's period (s)
    pub period_s: f64,
    /// amplitude (m)
    pub amplitude_m: f64,
    /// located on the arclength to the locator's tolerance (else bracketed between two points)
    pub located: bool,
}

/// A fold (or flip) of cycles of the diagram continued over the key.
#[derive(Clone, Debug, PartialEq)]
pub struct FoldTrack {
    /// what the curve continues
    pub kind: TrackKind,
    /// the branch of the diagram it starts on (its id in `branch.csv`)
    pub branch: usize,
    /// that branch's kind
    pub branch_kind: BranchKind,
    /// the points in order along the curve (the diagram's fold among them)
    pub points: Vec<FoldTrackPoint>,
    /// cusps, fold–flip, fold–torus points on the curve, in order along it
    pub special: Vec<FoldSpecial>,
    /// why each end stopped: (the first point's end, the last point's end)
    pub stops: (TrackStop, TrackStop),
}

/// Why one end of a [`FoldTrack`] stopped.
#[derive(Clone, Debug, PartialEq)]
pub enum TrackStop {
    /// the corrector found no point beyond the last one at the smallest step (or the steps
    /// shrank without end next to the Hopf curve): the key value and speed of the last point,
    /// and why, in words
    Unsolved {
        parameter: f64,
        speed_m_s: f64,
        message: String,
    },
    /// any other end (a bound, a limit, a codimension-two point, cancelled), in words
    Ended(String),
}

impl TrackStop {
    /// In words, with the numbers.
    pub fn describe(&self) -> &str {
        match self {
            TrackStop::Unsolved { message, .. } | TrackStop::Ended(message) => message,
        }
    }
}

/// Bordering vectors of the test condition: `b` ≈ the left and `c` ≈ the right null vector of
/// A (unit norm), real for the fold and flip, complex (`zb`, `zc`, with `b`, `c` empty) for
/// the torus.
#[derive(Clone, Debug)]
struct Border {
    b: DVector<f64>,
    c: DVector<f64>,
    zb: DVector<Complex<f64>>,
    zc: DVector<Complex<f64>>,
}

impl Border {
    fn real(b: DVector<f64>, c: DVector<f64>) -> Self {
        Border {
            b,
            c,
            zb: DVector::zeros(0),
            zc: DVector::zeros(0),
        }
    }

    fn complex(zb: DVector<Complex<f64>>, zc: DVector<Complex<f64>>) -> Self {
        Border {
            b: DVector::zeros(0),
            c: DVector::zeros(0),
            zb,
            zc,
        }
    }
}

/// An accepted point of the fold curve.
#[derive(Clone)]
struct Point<const N: usize> {
    /// (x0, T, V, p)
    u: DVector<f64>,
    /// unit tangent in scaled units
    tangent: DVector<f64>,
    floquet: Floquet,
    amplitude: f64,
    extent: f64,
    border: Border,
    seed: SegmentSeed<N>,
}

/// A complex vector (the torus's null vectors and borders).
type CVector = DVector<Complex<f64>>;

/// The test function's rows of the corrector: (value, gradient in all unknowns), one row for
/// the fold and the flip, two (real and imaginary parts) for the torus.
type TestRows = Vec<(f64, DVector<f64>)>;

/// Where a corrector starts from: the borders, shooting segments and tangent (orientation)
/// of a nearby point.
struct From<'p, const N: usize> {
    border: &'p Border,
    seed: &'p SegmentSeed<N>,
    tangent: &'p DVector<f64>,
}

impl<const N: usize> Point<N> {
    fn from(&self) -> From<'_, N> {
        From {
            border: &self.border,
            seed: &self.seed,
            tangent: &self.tangent,
        }
    }
}

/// The corrector's last row.
enum Row<'r> {
    /// pseudo-arclength through the prediction `zp` along `tangent`
    Arclength {
        tangent: &'r DVector<f64>,
        zp: &'r DVector<f64>,
    },
    /// the key pinned to a value
    Pin(f64),
}

/// The fold system of one branch's fold: what every corrector shares.
struct FoldSystem<'a, const N: usize> {
    setup: &'a Setup<'a, N>,
    run: &'a Run<N>,
    model_at: &'a (dyn Fn(f64) -> Result<Vehicle, String> + Sync),
    /// scales of (x0, T, V, p)
    scale: DVector<f64>,
    /// the key's range (low, high)
    bounds: (f64, f64),
    /// the grid's key values (user points)
    grid: Vec<f64>,
    /// relative difference step
    eps: f64,
    /// the test matrix: the fold's or the flip's
    kind: TrackKind,
}

/// Follows every located fold of `runs` over `track`'s key range.
pub(super) fn follow<const N: usize>(
    setup: &Setup<'_, N>,
    runs: &[Run<N>],
    track: &FoldTracking<'_>,
) -> Vec<FoldTrack> {
    // the user points: the grid and the diagram's own value
    let mut grid: Vec<f64> = track.back.iter().chain(track.values).copied().collect();
    grid.push(track.first);
    grid.sort_by(f64::total_cmp);
    grid.dedup();
    let low = grid
        .first()
        .copied()
        .unwrap_or(track.first)
        .min(track.first);
    let high = grid.last().copied().unwrap_or(track.first).max(track.first);
    let mut jobs = Vec::new();
    for &kind in track.kinds {
        for run in runs.iter() {
            for sp in run.branch.special.iter() {
                let wanted = match kind {
                    TrackKind::Fold => SpecialKind::Fold,
                    TrackKind::Flip if run.symmetric => SpecialKind::SymmetryBreaking,
                    TrackKind::Flip => SpecialKind::PeriodDoubling,
                    TrackKind::Torus => SpecialKind::Torus,
                };
                // a fold the diagram only bracketed is a start too: the fold system's Newton
                // locates it (or says why not, in a note)
                if sp.kind != wanted
                    || sp.amplitude < MIN_FOLD_AMPLITUDE
                    || (track.skip)(kind, run.symmetric, sp.orbit.param, sp.amplitude)
                {
                    continue;
                }
                jobs.push((run, sp.orbit, kind));
            }
        }
    }
    // one fold at a time (each curve's sides and differences run in parallel): a fold of the
    // diagram that an earlier curve passed through (round a cusp) is not followed again
    let mut tracks: Vec<FoldTrack> = Vec::new();
    for (run, orbit, kind) in jobs {
        let on_known = tracks.iter().filter(|t| t.kind == kind).any(|t| {
            t.points.iter().any(|p| {
                p.parameter == track.first
                    && (p.speed_m_s - orbit.param).abs() <= 1e-4 * orbit.param.abs()
            })
        });
        if on_known {
            continue;
        }
        let mut scale = setup.params(run.period_factor).scale;
        scale.resize(N + 2, 1.0);
        scale.push(((high - low) / KEY_UNITS).max(f64::MIN_POSITIVE));
        if kind == TrackKind::Torus {
            scale.push(THETA_UNIT);
        }
        let system = FoldSystem {
            setup,
            run,
            model_at: track.model_at,
            scale: DVector::from_vec(scale),
            bounds: (low, high),
            grid: grid.clone(),
            eps: setup.opts.rtol.sqrt().max(1e-7),
            kind,
        };
        let id = runs
            .iter()
            .position(|r| std::ptr::eq(r, run))
            .unwrap_or_default();
        let started = std::time::Instant::now();
        // the same fold reached from two branches of the diagram (its estimate there may
        // differ from the solved fold by more than the test above allows)
        let known = |speed: f64| {
            tracks.iter().filter(|t| t.kind == kind).any(|t| {
                t.points.iter().any(|p| {
                    p.parameter == track.first && (p.speed_m_s - speed).abs() <= 1e-7 * speed
                })
            }) || (track.skip)(kind, run.symmetric, speed, 0.0)
        };
        let Some(curve) = system.curve(id, &orbit, track.first, &known) else {
            continue;
        };
        if let Some(done) = track.done {
            done(&curve, started.elapsed().as_secs_f64());
        }
        tracks.push(curve);
    }
    tracks
}

/// The multipliers of the shooting map (ν on a symmetric branch) other than the two nearest +1.
fn others(f: &Floquet) -> Vec<Complex<f64>> {
    let mut m: Vec<Complex<f64>> = f.shooting_multipliers().to_vec();
    m.sort_by(|a, b| (a - 1.0).norm().total_cmp(&(b - 1.0).norm()));
    m.into_iter().skip(2).collect()
}

/// Whether a stable cycle branch ends at a fold with multipliers `f`.
fn stable_side(f: &Floquet) -> bool {
    others(f).iter().all(|m| m.norm() < 1.0)
}

/// Multipliers (other than the two at +1) outside the unit circle: (real below −1, complex).
fn census(f: &Floquet) -> (usize, usize) {
    let real = |m: &Complex<f64>| m.im.abs() <= 1e-9 * m.norm();
    others(f)
        .iter()
        .filter(|m| m.norm() > 1.0)
        .fold((0, 0), |(n, c), m| {
            if !real(m) {
                (n, c + 1)
            } else if m.re < 0.0 {
                (n + 1, c)
            } else {
                (n, c)
            }
        })
}

/// The test function of a crossing on the fold: ∏(1 + ν) over the others (a real multiplier
/// through −1), or the signed distance from the circle of the complex one nearest it.
fn crossing_value(kind: FoldSpecialKind, f: &Floquet) -> f64 {
    let m = others(f);
    match kind {
        FoldSpecialKind::FoldTorus => m
            .iter()
            .filter(|v| v.im.abs() > 1e-9 * v.norm())
            .map(|v| v.norm() - 1.0)
            .min_by(|a, b| a.abs().total_cmp(&b.abs()))
            .unwrap_or(f64::NAN),
        _ => {
            m.iter()
                .fold(Complex::new(1.0, 0.0), |acc, v| acc * (v + 1.0))
                .re
        }
    }
}

/// A of the module's documentation for `kind`: the fold's N × N block and one column of a
/// linearisation with the phase row ((N + 1) × (N + 1)), or the flip's Φ ∓ I (N × N).
fn test_matrix<const N: usize>(
    kind: TrackKind,
    symmetric: bool,
    lin: &Linearised<N>,
    fr: &SVector<f64, N>,
) -> DMatrix<f64> {
    match kind {
        TrackKind::Fold => {
            let mut a = DMatrix::zeros(N + 1, N + 1);
            a.view_mut((0, 0), (N, N + 1))
                .copy_from(&lin.jacobian.columns(0, N + 1));
            for i in 0..N {
                a[(N, i)] = fr[i];
            }
            a
        }
        // (the torus's test matrix is complex, [`torus_matrix`]; it never comes here)
        TrackKind::Flip | TrackKind::Torus => {
            // the half-period map's ν = −1 is Φ's +1; the full period's μ = −1 is Φ's −1
            let shift = if symmetric { -1.0 } else { 1.0 };
            DMatrix::from_fn(N, N, |i, j| {
                lin.monodromy[(i, j)] + if i == j { shift } else { 0.0 }
            })
        }
    }
}

/// The left and right singular vectors of `a`'s smallest singular value (for a complex `a`,
/// the right one is the column of V in A = U Σ Vᴴ).
fn smallest_singular_pair<T: nalgebra::ComplexField<RealField = f64>>(
    a: DMatrix<T>,
) -> Option<(DVector<T>, DVector<T>)> {
    // nalgebra's `svd` iterates without a limit (its eigenvalues did not return on one
    // monodromy: `tests/monodromy_eigenvalues.rs`): a bounded one, `None` when it fails
    if !a.iter().all(|x| x.is_finite()) {
        return None;
    }
    let n = a.nrows().max(a.ncols()).max(1);
    let svd = a.try_svd(true, true, f64::EPSILON, 60 * n)?;
    let k = svd
        .singular_values
        .iter()
        .enumerate()
        .min_by(|x, y| x.1.total_cmp(y.1))
        .map(|(k, _)| k)?;
    let (uu, vt) = (svd.u?, svd.v_t?);
    Some((uu.column(k).into_owned(), vt.row(k).adjoint()))
}

/// The torus's test matrix σΦ − e^{iθ} I, σΦ the shooting map's derivative (σ = −1 on a
/// symmetric branch, whose map is the half period's composed with the symmetry).
fn torus_matrix<const N: usize>(
    symmetric: bool,
    lin: &Linearised<N>,
    theta: f64,
) -> DMatrix<Complex<f64>> {
    let sigma = if symmetric { -1.0 } else { 1.0 };
    let z = Complex::from_polar(1.0, theta);
    DMatrix::from_fn(N, N, |i, j| {
        Complex::new(sigma * lin.monodromy[(i, j)], 0.0) - if i == j { z } else { 0.0.into() }
    })
}

/// `a` bordered by the complex borders (zb as the last column, zcᴴ as the last row).
fn bordered_complex(a: &DMatrix<Complex<f64>>, border: &Border) -> DMatrix<Complex<f64>> {
    let n = a.nrows();
    let mut m = DMatrix::zeros(n + 1, n + 1);
    m.view_mut((0, 0), (n, n)).copy_from(a);
    for i in 0..n {
        m[(i, n)] = border.zb.get(i).copied().unwrap_or_default();
        m[(n, i)] = border.zc.get(i).copied().unwrap_or_default().conj();
    }
    m
}

/// The complex g and the right and left null vectors (v, w) of A from its bordered matrix M:
/// M (v, g) = e and Mᴴ (w, ·) = e, so that dg = −wᴴ (dA) v.
fn torus_value(m: &DMatrix<Complex<f64>>) -> Option<(Complex<f64>, CVector, CVector)> {
    let n = m.nrows();
    let mut e = DVector::zeros(n);
    e[n - 1] = Complex::new(1.0, 0.0);
    let x = m.clone().lu().solve(&e)?;
    let y = m.adjoint().lu().solve(&e)?;
    let g = x[n - 1];
    (x.iter()
        .chain(y.iter())
        .all(|v| v.re.is_finite() && v.im.is_finite()))
    .then(|| {
        (
            g,
            x.rows(0, n - 1).into_owned(),
            y.rows(0, n - 1).into_owned(),
        )
    })
}

fn unit_complex(v: CVector) -> Option<CVector> {
    let n = v.norm();
    (n > 0.0 && n.is_finite()).then(|| v.unscale(n))
}

/// `a` bordered by `border` (b as the last column, cᵀ as the last row).
fn bordered(a: &DMatrix<f64>, border: &Border) -> DMatrix<f64> {
    let n = a.nrows();
    let mut m = DMatrix::zeros(n + 1, n + 1);
    m.view_mut((0, 0), (n, n)).copy_from(a);
    for i in 0..n {
        m[(i, n)] = border.b[i];
        m[(n, i)] = border.c[i];
    }
    m
}

/// g and the right and left null vectors (v, w) of A from the bordered matrix.
fn fold_value(m: &DMatrix<f64>) -> Option<(f64, DVector<f64>, DVector<f64>)> {
    let n = m.nrows();
    let mut e = DVector::zeros(n);
    e[n - 1] = 1.0;
    let x = m.clone().lu().solve(&e)?;
    let y = m.transpose().lu().solve(&e)?;
    let g = x[n - 1];
    (g.is_finite() && x.iter().chain(y.iter()).all(|v| v.is_finite())).then(|| {
        (
            g,
            x.rows(0, n - 1).into_owned(),
            y.rows(0, n - 1).into_owned(),
        )
    })
}

fn unit(v: DVector<f64>) -> Option<DVector<f64>> {
    let n = v.norm();
    (n > 0.0 && n.is_finite()).then(|| v / n)
}

/// The orbit of the unknowns (x0, T, V, p).
fn orbit_of<const N: usize>(u: &DVector<f64>) -> OrbitPoint<N> {
    OrbitPoint {
        x0: SVector::from_fn(|i, _| u[i]),
        period: u[N],
        param: u[N + 1],
    }
}

/// A converged corrector.
struct Corrected<const N: usize> {
    point: Point<N>,
    iterations: usize,
}

impl<const N: usize> FoldSystem<'_, N> {
    fn p(u: &DVector<f64>) -> f64 {
        u[N + 2]
    }

    /// The number of unknowns: (x0, T, V, p), and θ for the torus.
    fn dim(&self) -> usize {
        N + 3 + usize::from(self.kind == TrackKind::Torus)
    }

    /// What the curve's points are, in messages.
    fn what(&self) -> &'static str {
        match (self.kind, self.run.symmetric) {
            (TrackKind::Fold, _) => "fold",
            (TrackKind::Flip, true) => "symmetry-breaking point",
            (TrackKind::Flip, false) => "period doubling",
            (TrackKind::Torus, _) => "torus bifurcation",
        }
    }

    fn shooting<'m>(&self, model: &'m Vehicle) -> Shooting<'m, N, Vehicle> {
        Shooting {
            field: model,
            symmetric: self.run.symmetric,
            ode: self.setup.ode,
            dp_rel: self.setup.opts.rtol.sqrt(),
            parallel: false,
            busy: None,
            // single shooting: with interior starts carried from linearisation to
            // linearisation (multiple shooting's condensation), g would depend on where those
            // starts were left, a different function at each iteration; the parallel work is
            // in the differences instead
            segments: 1,
        }
    }

    fn model(&self, p: f64) -> Result<Vehicle, String> {
        (self.model_at)(p)
    }

    /// The linearisation at `u` of `model` (built at `u`'s key value).
    fn linearise(
        &self,
        model: &Vehicle,
        u: &DVector<f64>,
        seed: Option<&SegmentSeed<N>>,
    ) -> Result<Linearised<N>, String> {
        self.shooting(model)
            .linearise_from(&orbit_of::<N>(u), seed)
            .map_err(|e| format!("integration failed: {e}"))
    }

    /// ∂G/∂p at `u` by a one-sided difference of two plain flows (no monodromy): of the model
    /// at `u`'s key value and at the shifted one.
    fn g_p(&self, model: &Vehicle, u: &DVector<f64>) -> Result<DVector<f64>, String> {
        let p = Self::p(u);
        let hp = self.eps * self.scale[N + 2].max(p.abs() * 1e-3);
        let hp = if p + hp > self.bounds.1 { -hp } else { hp };
        let shifted = self.model(p + hp)?;
        let o = orbit_of::<N>(u);
        let span = if self.run.symmetric {
            0.5 * o.period
        } else {
            o.period
        };
        let opts = OdeOptions {
            monodromy: false,
            ..self.setup.ode
        };
        let end = |m: &Vehicle| {
            integrate(m, o.param, &o.x0, span, &opts)
                .map(|s| s.x)
                .map_err(|e| format!("integration failed: {e}"))
        };
        let (a, b) = rayon::join(|| end(model), || end(&shifted));
        let d = (b? - a?) / hp;
        Ok(DVector::from_column_slice(d.as_slice()))
    }

    /// The derivatives of the shooting map's tangents in the unknowns (x0, T, V, p): for each
    /// direction (δx, δT) of `dirs`, the N + 3 vectors ∂(A d)/∂u_k, where the first N rows of
    /// A d are ξ(1) of the time-normalised flow in that direction ([`tangent_on_steps`]).
    ///
    /// Each is a one-sided difference of two such tangents, all on one step sequence (a plain
    /// flow's at `u`), so the differences are smooth in the unknowns: (N + 4) flows with one
    /// tangent each per direction, in parallel, instead of N + 3 monodromies (each a flow
    /// with N tangents). With them ∇g = −wᵀ (∂A/∂u) v (Govaerts), v and w the right and left
    /// null vectors of the bordered A.
    fn tangent_derivatives(
        &self,
        model: &Vehicle,
        u: &DVector<f64>,
        dirs: &[(SVector<f64, N>, f64)],
    ) -> Result<Vec<Vec<SVector<f64, N>>>, String> {
        let p = Self::p(u);
        let hp = self.eps * self.scale[N + 2].max(p.abs() * 1e-3);
        let hp = if p + hp > self.bounds.1 { -hp } else { hp };
        let shifted = self.model(p + hp)?;
        let o = orbit_of::<N>(u);
        let dtau = if self.run.symmetric { 0.5 } else { 1.0 };
        let opts = OdeOptions {
            monodromy: false,
            tol: crate::system::ode::Tolerances {
                rtol: (self.setup.ode.tol.rtol * 10.0).min(1e-6),
                ..self.setup.ode.tol
            },
            ..self.setup.ode
        };
        let horizon = dtau * o.period;
        let taus: Vec<f64> = step_times(model, o.param, &o.x0, horizon, &opts)
            .map_err(|e| format!("integration failed: {e}"))?
            .into_iter()
            .map(|t| t / horizon)
            .collect();
        // direction d's tangent with unknown k shifted by h (k = N + 3: none)
        let tangent = |d: usize, k: usize, h: f64| -> Result<SVector<f64, N>, String> {
            let (vx, vt) = &dirs[d];
            let mut x0 = o.x0;
            let (mut period, mut speed, mut m) = (o.period, o.param, model);
            match k {
                _ if k < N => x0[k] += h,
                _ if k == N => period += h,
                _ if k == N + 1 => speed += h,
                _ if k == N + 2 => m = &shifted,
                _ => {}
            }
            tangent_on_steps(m, speed, &x0, vx, (dtau * period, dtau * vt), &taus)
                .map(|(_, xi)| xi)
                .map_err(|e| format!("integration failed: {e}"))
        };
        let steps: Vec<f64> = (0..N + 3)
            .map(|k| match k {
                _ if k == N + 2 => hp,
                _ => TANGENT_STEP * self.scale[k].max(u[k].abs() * 1e-3),
            })
            .collect();
        let jobs: Vec<(usize, usize)> = (0..dirs.len())
            .flat_map(|d| (0..N + 4).map(move |k| (d, k)))
            .collect();
        let flows: Vec<Result<SVector<f64, N>, String>> = jobs
            .into_par_iter()
            .map(|(d, k)| tangent(d, k, steps.get(k).copied().unwrap_or(0.0)))
            .collect();
        let flows = flows.into_iter().collect::<Result<Vec<_>, String>>()?;
        Ok(flows
            .chunks(N + 4)
            .map(|c| (0..N + 3).map(|k| (c[k] - c[N + 3]) / steps[k]).collect())
            .collect())
    }

    /// The test rows at `u` (see [`TestRows`]) from the linearisation `lin`, the borders
    /// taken afresh from the null vectors first when `reset`.
    fn test_rows(
        &self,
        model: &Vehicle,
        u: &DVector<f64>,
        lin: &Linearised<N>,
        fr: &SVector<f64, N>,
        border: &mut Border,
        reset: bool,
    ) -> Result<TestRows, String> {
        let singular = "the bordered test matrix is singular";
        let dim = self.dim();
        if self.kind == TrackKind::Torus {
            let theta = u[N + 3];
            let a = torus_matrix(self.run.symmetric, lin, theta);
            let (mut g, mut v, mut w) =
                torus_value(&bordered_complex(&a, border)).ok_or(singular)?;
            if reset {
                if let (Some(b), Some(c)) = (unit_complex(w.clone()), unit_complex(v.clone())) {
                    *border = Border::complex(b, c);
                    (g, v, w) = torus_value(&bordered_complex(&a, border)).ok_or(singular)?;
                }
            }
            let re: SVector<f64, N> = SVector::from_fn(|i, _| v[i].re);
            let im: SVector<f64, N> = SVector::from_fn(|i, _| v[i].im);
            let d = self.tangent_derivatives(model, u, &[(re, 0.0), (im, 0.0)])?;
            // A = σΦ − e^{iθ} I: ∂g/∂u_k = −σ wᴴ (∂Φ/∂u_k) v, ∂g/∂θ = i e^{iθ} wᴴ v
            let sigma = if self.run.symmetric { -1.0 } else { 1.0 };
            let mut grad = vec![Complex::new(0.0, 0.0); dim];
            for k in 0..N + 3 {
                grad[k] = -(0..N)
                    .map(|j| w[j].conj() * Complex::new(d[0][k][j], d[1][k][j]))
                    .sum::<Complex<f64>>()
                    * sigma;
            }
            let wv: Complex<f64> = (0..N).map(|j| w[j].conj() * v[j]).sum();
            grad[N + 3] = Complex::new(0.0, 1.0) * Complex::from_polar(1.0, theta) * wv;
            return Ok(vec![
                (g.re, DVector::from_fn(dim, |k, _| grad[k].re)),
                (g.im, DVector::from_fn(dim, |k, _| grad[k].im)),
            ]);
        }
        let a_test = test_matrix(self.kind, self.run.symmetric, lin, fr);
        let (mut g, mut v, mut w) = fold_value(&bordered(&a_test, border)).ok_or(singular)?;
        if reset {
            if let (Some(b), Some(c)) = (unit(w.clone()), unit(v.clone())) {
                *border = Border::real(b, c);
                (g, v, w) = fold_value(&bordered(&a_test, border)).ok_or(singular)?;
            }
        }
        // a flip's null vector has no period component
        let vx: SVector<f64, N> = SVector::from_fn(|i, _| v[i]);
        let vt = v.get(N).copied().unwrap_or(0.0);
        let wx: SVector<f64, N> = SVector::from_fn(|i, _| w[i]);
        let d = self.tangent_derivatives(model, u, &[(vx, vt)])?;
        let grad = DVector::from_fn(dim, |k, _| if k < N + 3 { -wx.dot(&d[0][k]) } else { 0.0 });
        Ok(vec![(g, grad)])
    }

    /// Newton on the fold system from `zp` with the last row `row`; every iterate's
    /// derivatives are fresh ([`Self::tangent_derivatives`] is a few plain flows' cost), so it
    /// converges quadratically.
    fn correct(
        &self,
        zp: &DVector<f64>,
        row: Row<'_>,
        from: &From<'_, N>,
    ) -> Result<Corrected<N>, String> {
        let old_tangent = from.tangent;
        // g's borders: set at the first iterate from its null vectors, then kept (g is one
        // function during a corrector); reset once if Newton stalls
        let mut border = from.border.clone();
        let mut reset = true;
        let s = &self.scale;
        let mut u = zp.clone();
        if let Row::Pin(q) = row {
            u[N + 2] = q;
        }
        let reference = self.model(Self::p(&u))?;
        let xr: SVector<f64, N> = SVector::from_fn(|i, _| u[i]);
        let fr = reference.rhs(&xr, u[N + 1]);
        let mut last_seed = Some(from.seed.clone());
        let mut previous = f64::INFINITY;
        let mut was_reset = false;
        let tol = self.setup.params.newton_tol;
        let dim = self.dim();
        let last = dim - 1;
        for it in 1..=MAX_ITERATIONS {
            let model = self.model(Self::p(&u))?;
            let lin = self.linearise(&model, &u, last_seed.as_ref())?;
            let tests = self.test_rows(&model, &u, &lin, &fr, &mut border, reset)?;
            reset = false;
            let gp = self.g_p(&model, &u)?;
            let mut a = DMatrix::zeros(dim, dim);
            let mut rhs = DVector::zeros(dim);
            a.view_mut((0, 0), (N, N + 2)).copy_from(&lin.jacobian);
            a.view_mut((0, N + 2), (N, 1)).copy_from(&gp);
            for i in 0..N {
                rhs[i] = -lin.residual[i];
                a[(N, i)] = fr[i];
            }
            rhs[N] = -(0..N).map(|i| fr[i] * (u[i] - xr[i])).sum::<f64>();
            for (r, (g, grad)) in tests.iter().enumerate() {
                for k in 0..dim {
                    a[(N + 1 + r, k)] = grad[k];
                }
                rhs[N + 1 + r] = -g;
            }
            match &row {
                Row::Arclength { tangent, zp } => {
                    for k in 0..dim {
                        a[(last, k)] = tangent[k] / s[k];
                    }
                    rhs[last] = -(0..dim)
                        .map(|k| tangent[k] * (u[k] - zp[k]) / s[k])
                        .sum::<f64>();
                }
                Row::Pin(q) => {
                    a[(last, N + 2)] = 1.0;
                    rhs[last] = q - u[N + 2];
                }
            }
            let mut delta = a
                .clone()
                .lu()
                .solve(&rhs)
                .filter(|d| d.iter().all(|x| x.is_finite()))
                .ok_or("the fold system's Jacobian is singular")?;
            u += &delta;
            if let Row::Pin(q) = row {
                u[N + 2] = q;
                delta[N + 2] = 0.0;
            }
            if u[N].is_nan() || u[N] <= 0.0 {
                return Err(format!(
                    "Newton left the cycles (period {:.3e} s at iteration {it})",
                    u[N]
                ));
            }
            last_seed = Some(lin.seed.clone());
            let size = delta
                .iter()
                .zip(s.iter())
                .map(|(d, sc)| (d / sc).abs())
                .fold(0.0, f64::max);
            if !size.is_finite() {
                return Err("Newton diverged".into());
            }
            // an update that shrinks too slowly: the borders afresh once, then failure
            let stalled = it >= 2 && size > STALL * previous;
            if stalled && previous > NOISE_FLOOR * tol {
                if was_reset {
                    return Err(format!("Newton did not contract (update {size:.1e})"));
                }
                reset = true;
                was_reset = true;
            } else {
                was_reset = false;
            }
            previous = size;
            // near a generalised Hopf point g's gradient vanishes with the amplitude and the
            // updates stall at the integration noise: converged there
            if size <= tol || (stalled && size <= NOISE_FLOOR * tol) {
                // the last linearisation, one update of at most the tolerance away, gives the
                // multipliers and the amplitude (as on the branches)
                // the tangent: the Jacobian's rows with the old tangent as last row
                for k in 0..dim {
                    a[(last, k)] = old_tangent[k] / s[k];
                }
                let mut e = DVector::zeros(dim);
                e[last] = 1.0;
                let t = a
                    .lu()
                    .solve(&e)
                    .ok_or("the fold curve's tangent is undefined")?;
                let t = DVector::from_fn(dim, |k, _| t[k] / s[k]);
                let mut t = unit(t).ok_or("the fold curve's tangent is undefined")?;
                if t.dot(old_tangent) < 0.0 {
                    t = -t;
                }
                let orbit = orbit_of::<N>(&u);
                let amplitude = (self.setup.amplitude)(&orbit, &lin.peaks);
                let extent = (self.setup.extent)(&lin.peaks);
                return Ok(Corrected {
                    point: Point {
                        u,
                        tangent: t,
                        floquet: Floquet::from_monodromy(&lin.monodromy, self.run.symmetric),
                        amplitude,
                        extent,
                        border,
                        seed: lin.seed,
                    },
                    iterations: it,
                });
            }
        }
        Err("Newton reached its iteration limit".into())
    }

    fn predict(&self, u: &DVector<f64>, t: &DVector<f64>, ds: f64) -> DVector<f64> {
        DVector::from_fn(self.dim(), |k, _| u[k] + ds * t[k] * self.scale[k])
    }

    fn track_point(&self, p: &Point<N>, on_grid: bool) -> FoldTrackPoint {
        FoldTrackPoint {
            parameter: Self::p(&p.u),
            speed_m_s: p.u[N + 1],
            period_s: p.u[N],
            amplitude_m: p.amplitude,
            stable_side: stable_side(&p.floquet),
            located: true,
            on_grid,
            angle_rad: (self.kind == TrackKind::Torus).then(|| p.u[N + 3]),
            state: p.u.rows(0, N).iter().copied().collect(),
        }
    }

    /// The fold curve through the diagram's fold `orbit`, or `None` when the fold, solved as a
    /// point of the fold system, is one `known(speed)` says a curve already passes through.
    fn curve(
        &self,
        branch: usize,
        orbit: &OrbitPoint<N>,
        first: f64,
        known: &dyn Fn(f64) -> bool,
    ) -> Option<FoldTrack> {
        let lost = |why: String| FoldTrack {
            kind: self.kind,
            branch,
            branch_kind: self.run.kind,
            points: Vec::new(),
            special: Vec::new(),
            stops: (TrackStop::Ended(why.clone()), TrackStop::Ended(why)),
        };
        let start = match self.start(orbit, first) {
            Ok(s) => s,
            Err(e) => {
                return Some(lost(format!(
                "the diagram's {what} at {:.3} m/s could not be solved on the extended system: {e}",
                orbit.param,
                what = self.what()
            )))
            }
        };
        if known(start.u[N + 1]) {
            return None;
        }
        let (back, fore) = rayon::join(|| self.side(&start, -1.0), || self.side(&start, 1.0));
        let (mut back_points, back_special, back_stop) = back;
        let (fore_points, fore_special, fore_stop) = fore;
        back_points.reverse();
        let on_grid = self.grid.contains(&first);
        back_points.push(self.track_point(&start, on_grid));
        back_points.extend(fore_points);
        let mut special: Vec<FoldSpecial> = back_special.into_iter().rev().collect();
        special.extend(fore_special);
        Some(FoldTrack {
            kind: self.kind,
            branch,
            branch_kind: self.run.kind,
            points: back_points,
            special,
            stops: (back_stop, fore_stop),
        })
    }

    /// The diagram's fold solved as a point of the fold system at `first`, with the curve's
    /// tangent pointing towards increasing key.
    fn start(&self, orbit: &OrbitPoint<N>, first: f64) -> Result<Point<N>, String> {
        let mut u = pack(orbit);
        u.extend([first]);
        let model = self.model(first)?;
        let lin = self.linearise(&model, &u, None)?;
        // the borders: A's singular vectors of its smallest singular value
        let xr: SVector<f64, N> = orbit.x0;
        let fr = model.rhs(&xr, orbit.param);
        let border = if self.kind == TrackKind::Torus {
            // θ: the angle of the complex shooting multiplier nearest the unit circle
            let f = Floquet::from_monodromy(&lin.monodromy, self.run.symmetric);
            let nu = f
                .shooting_multipliers()
                .iter()
                .filter(|m| m.im > 1e-9 * m.norm())
                .min_by(|a, b| (a.norm() - 1.0).abs().total_cmp(&(b.norm() - 1.0).abs()))
                .copied()
                .ok_or("no complex pair of multipliers at the diagram's torus point")?;
            u.extend([nu.arg()]);
            let a = torus_matrix(self.run.symmetric, &lin, nu.arg());
            let (b, c) = smallest_singular_pair(a).ok_or("no singular vectors")?;
            Border::complex(b, c)
        } else {
            let a = test_matrix(self.kind, self.run.symmetric, &lin, &fr);
            let (b, c) = smallest_singular_pair(a).ok_or("no singular vectors")?;
            Border::real(b, c)
        };
        let mut towards = DVector::zeros(self.dim());
        towards[N + 2] = 1.0;
        let from = From {
            border: &border,
            seed: &lin.seed,
            tangent: &towards,
        };
        let c = self.correct(&u, Row::Pin(first), &from)?;
        let mut point = c.point;
        if point.tangent[N + 2] < 0.0 {
            point.tangent = -point.tangent;
        }
        Ok(point)
    }

    /// The grid values strictly beyond `a` up to and including `b` (in the order met).
    fn crossed(&self, a: f64, b: f64) -> Vec<f64> {
        let mut q: Vec<f64> = self
            .grid
            .iter()
            .copied()
            .filter(|&v| (v - a) * (b - a) > 0.0 && (v - a).abs() <= (b - a).abs())
            .collect();
        q.sort_by(|x, y| ((x - a).abs()).total_cmp(&(y - a).abs()));
        q
    }

    /// One direction of the curve from `start` (`sign` +1: towards increasing key).
    fn side(
        &self,
        start: &Point<N>,
        sign: f64,
    ) -> (Vec<FoldTrackPoint>, Vec<FoldSpecial>, TrackStop) {
        let mut out = Vec::new();
        let mut special = Vec::new();
        let mut a = start.clone();
        a.tangent = &a.tangent * sign;
        let mut ds = DS_INITIAL;
        let mut last_error = String::new();
        let mut iterations = 0;
        let cancelled = || self.setup.cancel.is_some_and(|c| c());
        let stop = loop {
            if cancelled() {
                break TrackStop::Ended("cancelled".to_string());
            }
            if out.len() >= MAX_POINTS {
                break TrackStop::Ended(format!("{MAX_POINTS} points computed"));
            }
            // near a generalised Hopf point the fold system degenerates with the amplitude:
            // steps there shrink without end, so the curve ends once they are small
            let crawling = a.amplitude < NEAR_HOPF_AMPLITUDE && ds < NEAR_HOPF_DS;
            if ds < DS_MIN || crawling {
                let near = if a.amplitude < NEAR_HOPF_AMPLITUDE {
                    "; the fold's amplitude has fallen this far towards the Hopf curve: a generalised Hopf (Bautin) point is near"
                } else {
                    ""
                };
                let angle = if self.kind == TrackKind::Torus {
                    format!(
                        ", θ = {:.4} rad",
                        a.u[N + 3].rem_euclid(std::f64::consts::TAU)
                    )
                } else {
                    String::new()
                };
                break TrackStop::Unsolved {
                    parameter: Self::p(&a.u),
                    speed_m_s: a.u[N + 1],
                    message: format!(
                        "no {} could be solved beyond key value {} ({:.4} m/s, {:.3} mm{angle}): {last_error}{near}",
                        self.what(),
                        Self::p(&a.u),
                        a.u[N + 1],
                        a.amplitude * 1e3
                    ),
                };
            }
            let zp = self.predict(&a.u, &a.tangent, ds);
            let pa = Self::p(&a.u);
            let pz = Self::p(&zp);
            // the key's range ends here: the fold at the bound, then stop
            let bound = if pz > self.bounds.1 {
                Some(self.bounds.1)
            } else if pz < self.bounds.0 {
                Some(self.bounds.0)
            } else {
                None
            };
            if let Some(bound) = bound {
                if pa == bound {
                    break TrackStop::Ended(format!("end of the key's range ({bound})"));
                }
                let t = (bound - pa) / (pz - pa);
                let zq = &a.u + (&zp - &a.u) * t;
                match self.correct(&zq, Row::Pin(bound), &a.from()) {
                    Ok(c) => {
                        let mut grid_points = Vec::new();
                        for q in self.crossed(pa, bound) {
                            if q == bound {
                                continue;
                            }
                            let t = (q - pa) / (pz - pa);
                            let zq = &a.u + (&zp - &a.u) * t;
                            if let Ok(g) = self.correct(&zq, Row::Pin(q), &a.from()) {
                                grid_points.push(self.track_point(&g.point, true));
                            }
                        }
                        out.extend(grid_points);
                        out.push(self.track_point(&c.point, self.grid.contains(&bound)));
                        break TrackStop::Ended(format!("end of the key's range ({bound})"));
                    }
                    Err(e) => {
                        last_error = e;
                        ds *= 0.5;
                        continue;
                    }
                }
            }
            let trouble = match self.correct(
                &zp,
                Row::Arclength {
                    tangent: &a.tangent,
                    zp: &zp,
                },
                &a.from(),
            ) {
                Ok(c) if c.point.tangent.dot(&a.tangent) >= MAX_ANGLE.cos() => {
                    iterations = c.iterations;
                    Ok(c.point)
                }
                Ok(_) => Err("the curve turns too sharply".to_string()),
                Err(e) => Err(e),
            };
            let c = match trouble {
                Ok(c) => c,
                Err(e) => {
                    last_error = e;
                    ds *= 0.5;
                    continue;
                }
            };
            // the grid's values crossed: the fold there, the key pinned
            let pc = Self::p(&c.u);
            let mut grid_points = Vec::new();
            let mut failed = None;
            for q in self.crossed(pa, pc) {
                let t = (q - pa) / (pc - pa);
                let zq = &a.u + (&c.u - &a.u) * t;
                match self.correct(&zq, Row::Pin(q), &a.from()) {
                    Ok(g) => grid_points.push(self.track_point(&g.point, true)),
                    Err(e) => {
                        failed = Some(e);
                        break;
                    }
                }
            }
            if let Some(e) = failed {
                last_error = format!("at a grid value: {e}");
                ds *= 0.5;
                continue;
            }
            // a turn in the key between a and c: a cusp (on a fold curve; the flips' turns and
            // crossings are not classified)
            let fold = self.kind == TrackKind::Fold;
            if fold && a.tangent[N + 2] * c.tangent[N + 2] < 0.0 {
                special.push(self.locate(&a, &c, ds, FoldSpecialKind::Cusp));
            }
            let (ca, cc) = (census(&a.floquet), census(&c.floquet));
            if fold && (ca.0 + cc.0) % 2 == 1 {
                let kind = if self.run.symmetric {
                    FoldSpecialKind::FoldSymmetryBreaking
                } else {
                    FoldSpecialKind::FoldFlip
                };
                special.push(self.locate(&a, &c, ds, kind));
            }
            if fold && ca.1 != cc.1 && ca.0 == cc.0 {
                special.push(self.locate(&a, &c, ds, FoldSpecialKind::FoldTorus));
            }
            out.extend(grid_points);
            let on_grid = self.grid.contains(&pc);
            if !on_grid {
                out.push(self.track_point(&c, false));
            }
            // step control by the corrector's iterations (Newton: 3 or 4 at a good step)
            let factor = match iterations {
                0..=3 => 2.0,
                4 => 1.2,
                5 | 6 => 1.0,
                _ => 0.6,
            };
            ds = (ds * factor).min(DS_MAX);
            let reason = if c.amplitude < MIN_FOLD_AMPLITUDE {
                let point = if self.kind == TrackKind::Torus {
                    "a double Hopf point (where a second pair of the centred motion's eigenvalues is on the imaginary axis)"
                } else {
                    "a generalised Hopf (Bautin) point"
                };
                Some(format!(
                    "the {}'s amplitude falls to zero ({:.1} µm at {:.4} m/s): the curve ends on the Hopf curve, at {point}",
                    self.what(),
                    c.amplitude * 1e6,
                    c.u[N + 1]
                ))
            } else if self.kind == TrackKind::Torus && c.u[N + 3].sin().abs() < MIN_SIN_THETA {
                let theta = c.u[N + 3].rem_euclid(std::f64::consts::TAU);
                let near = if theta.cos() > 0.0 {
                    "θ → 0: a 1:1 resonance, where the torus curve meets a fold curve (a fold–torus point)"
                } else {
                    "θ → π: a 1:2 resonance, where the torus curve meets a flip curve"
                };
                Some(format!(
                    "the multipliers e^(±iθ) on the unit circle become real at {:.4} m/s (θ = {:.4} rad, {near})",
                    c.u[N + 1], theta
                ))
            } else if c.extent > self.setup.params.max_amplitude {
                Some(format!(
                    "the cycles reach the amplitude bound ({:.3} mm)",
                    c.extent * 1e3
                ))
            } else if c.u[N + 1] < self.setup.params.param_range.0
                || c.u[N + 1] > self.setup.params.param_range.1
            {
                Some(format!(
                    "the {} leaves the speed range ({:.3} m/s)",
                    self.what(),
                    c.u[N + 1]
                ))
            } else {
                None
            };
            a = c;
            if let Some(r) = reason {
                break TrackStop::Ended(r);
            }
        };
        (out, special, stop)
    }

    /// A sign change of `kind`'s test between the accepted points `a` and `b` (`ds` apart),
    /// located by the Illinois method on the arclength from `a`; bracketed when a corrector
    /// fails.
    fn locate(&self, a: &Point<N>, b: &Point<N>, ds: f64, kind: FoldSpecialKind) -> FoldSpecial {
        let test = |p: &Point<N>| match kind {
            FoldSpecialKind::Cusp => p.tangent[N + 2],
            _ => crossing_value(kind, &p.floquet),
        };
        let make = |p: &Point<N>, located: bool| FoldSpecial {
            kind,
            parameter: Self::p(&p.u),
            speed_m_s: p.u[N + 1],
            period_s: p.u[N],
            amplitude_m: p.amplitude,
            located,
        };
        let tol = 1e-6 * ds.max(1.0);
        let eval = |s: f64| {
            let zp = self.predict(&a.u, &a.tangent, s);
            let row = Row::Arclength {
                tangent: &a.tangent,
                zp: &zp,
            };
            self.correct(&zp, row, &a.from()).ok().map(|c| c.point)
        };
        let (best, bracket) = illinois(test(a), ds, b.clone(), tol, eval, test);
        make(&best, bracket <= tol)
    }
}
