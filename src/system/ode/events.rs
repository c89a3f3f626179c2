//! Switching surfaces $g_k(x) = 0$: detection in a trial step, location of the crossing
//! time, and the re-taken step that ends on the surface; with the root finders they use.
//!
//! A trial step whose end has crossed a surface (sign of $g_k$ opposite to the side it
//! started on) is never accepted as it is. The crossing is first located on the trial's
//! continuous extension (Brent's method, cheap: no field evaluations), which is only a
//! guess: the trial straddles the kink, so its dense output is polluted by it. The guess
//! seeds a bracketed Illinois iteration on the step length $\tau$ of *re-taken* steps,
//! $\varphi(\tau) = g_k(x_{RK}(t_0 + \tau))$, whose steps up to the crossing are smooth and
//! accurate; it ends with the shortest step found past the surface, to a few ulps of $t$.
//! So a genuine Runge–Kutta step ends on the surface (a hair past it), the next one starts on
//! the new side, and no accepted step straddles a kink. This is done before the error test,
//! since a straddling step's error estimate is polluted too and would only make the
//! controller creep up to the surface with rejected steps.
//!
//! A crossed surface's side is flipped when that step is accepted: the restart point is then
//! on the new side (the "sign just after"), so the crossing is not detected again there.

use nalgebra::SVector;

use super::dopri::{Carried, Dense, Point, Rk, Trial};
use super::VectorField;

/// A crossing closer than this fraction of the step to its start or end is taken to lie
/// there (a shorter step would be round-off). Stepping over a kink by $\delta = 10^{-12}h$
/// costs $O(\delta^2)$ in $x$ (only $\ddot x = Jf$ jumps) but $O(\delta\,|[J]|\,|\Phi|)$ in
/// $\Phi$, whose derivative $J\Phi$ jumps: $10^{-12}$ keeps that far below rtol.
const END_FRACTION: f64 = 1e-12;
/// Bound on the Illinois iterations (4 to 7 from the dense-output guess in the tests).
const MAX_ITER: usize = 60;
/// Successive re-takes of one step (normally one; more when several surfaces are crossed in
/// one step), after which the crossings are accepted where they are: a safeguard against a
/// switching function so noisy that each re-take finds a new, earlier root.
const MAX_SHORTENINGS: usize = 8;

/// What the scan of a trial step found.
enum Scan {
    /// Accept the step; crossings at its end are marked for [`Switches::commit`].
    Accept,
    /// Surface `k` is crossed first, inside the step: re-take it with the step length
    /// bracketed by `lo` and `hi`, `(τ, g_k)` pairs on either side, starting from `guess`.
    Shorten {
        k: usize,
        lo: (f64, f64),
        hi: (f64, f64),
        guess: f64,
    },
}

/// Side of each surface the trajectory is on (+1, −1, or 0 while still undecided because the
/// start lies exactly on it), and which surfaces the step under trial has crossed.
pub(super) struct Switches {
    side: Vec<i8>,
    pending: Vec<bool>,
}

fn sign(v: f64) -> i8 {
    if v > 0.0 {
        1
    } else if v < 0.0 {
        -1
    } else {
        0
    }
}

impl Switches {
    /// Allocated once per integration (nothing when the field has no surfaces).
    pub fn new<const N: usize, F: VectorField<N>>(field: &F, x0: &SVector<f64, N>) -> Self {
        let m = field.switch_count();
        Switches {
            side: (0..m).map(|k| sign(field.switch_value(k, x0))).collect(),
            pending: vec![false; m],
        }
    }

    /// Submits `trial` (from `p0`) to the surfaces: while one is crossed inside it, replaces
    /// it by the step that lands on the first crossed. Returns whether it was shortened; its
    /// crossings are marked for [`Switches::commit`]. (The trial is changed in place: moving
    /// it in and out, with a vehicle's monodromy matrix in it, was a tenth of a variational
    /// step's time in `memmove`.)
    pub fn settle<const N: usize, F: VectorField<N>, C: Carried<N>>(
        &mut self,
        rk: &mut Rk<'_, N, F>,
        p0: &Point<N, C>,
        trial: &mut Trial<N, C>,
    ) -> bool {
        if self.side.is_empty() {
            return false;
        }
        let field = rk.field;
        let mut settled = None;
        for n in 0..=MAX_SHORTENINGS {
            match self.scan(rk, p0, trial, settled, n < MAX_SHORTENINGS) {
                Scan::Accept => break,
                Scan::Shorten { k, lo, hi, guess } => {
                    *trial = land_on(rk, p0, |x| field.switch_value(k, x), lo, hi, guess);
                    settled = Some(k);
                }
            }
        }
        settled.is_some()
    }

    /// Looks for surfaces crossed by `trial` (started at `p0`) and locates each crossing on
    /// the dense output. Reports the first unless it is at the step's end, or `settled` (the
    /// surface the step was just re-taken to reach, whose crossing is at the end by
    /// construction), or `may_shorten` is false; then all crossings found are marked.
    fn scan<const N: usize, F: VectorField<N>, C>(
        &mut self,
        rk: &mut Rk<'_, N, F>,
        p0: &Point<N, C>,
        trial: &Trial<N, C>,
        settled: Option<usize>,
        may_shorten: bool,
    ) -> Scan {
        let field = rk.field;
        let (t0, t1) = (p0.t, trial.end.t);
        let h = t1 - t0;
        let near = END_FRACTION * h + 8.0 * f64::EPSILON * t1.abs();
        let mut dense: Option<Dense<N>> = None;
        let mut first: Option<(f64, Scan)> = None;
        for k in 0..self.side.len() {
            let s = f64::from(self.side[k]);
            let g1 = field.switch_value(k, &trial.end.x);
            self.pending[k] = g1 * s < 0.0;
            if !self.pending[k] || settled == Some(k) {
                continue;
            }
            let d = dense.get_or_insert_with(|| rk.dense(p0, trial));
            let mut g = |t: f64| field.switch_value(k, &d.eval(t));
            // No point strictly on the old side: the surface was left at the step's start.
            let Some((a, ga)) = bracket(&mut g, t0, h, field.switch_value(k, &p0.x), s) else {
                continue;
            };
            let tc = brent(&mut g, a, t1, ga, g1, 4.0 * f64::EPSILON * t1.abs());
            let inside = tc - t0 > near && t1 - tc > near;
            if inside && first.as_ref().is_none_or(|(t, _)| tc < *t) {
                let shorten = Scan::Shorten {
                    k,
                    lo: (a - t0, ga),
                    hi: (h, g1),
                    guess: tc - t0,
                };
                first = Some((tc, shorten));
            }
        }
        match first {
            Some((_, shorten)) if may_shorten => shorten,
            _ => Scan::Accept,
        }
    }

    /// After a step is accepted: flip the side of every surface it crossed, settle undecided
    /// ones from the end point. Returns the number of crossings recorded.
    pub fn commit<const N: usize, F: VectorField<N>>(
        &mut self,
        field: &F,
        x1: &SVector<f64, N>,
    ) -> usize {
        let mut events = 0;
        for k in 0..self.side.len() {
            if self.pending[k] {
                self.side[k] = -self.side[k];
                self.pending[k] = false;
                events += 1;
            } else if self.side[k] == 0 {
                self.side[k] = sign(field.switch_value(k, x1));
            }
        }
        events
    }
}

/// A point where $g$ is strictly on side `s`, from which the crossing at the step end can be
/// bracketed: the step start, or else (the start lies on the surface) the first of seven
/// interior dense-output samples that is.
fn bracket(g: &mut impl FnMut(f64) -> f64, t0: f64, h: f64, g0: f64, s: f64) -> Option<(f64, f64)> {
    if g0 * s > 0.0 {
        return Some((t0, g0));
    }
    (1..8)
        .map(|j| t0 + h * j as f64 / 8.0)
        .map(|t| (t, g(t)))
        .find(|&(_, v)| v * s > 0.0)
}

/// The re-taken step from `p0` that ends where $g$ changes sign: the Illinois variant of
/// regula falsi (Dowell & Jarratt 1971) on the step length $\tau$, bracketed by `lo` (old
/// side) and `hi` (new side), each a pair $(\tau, g)$. Returns the step at the smallest
/// $\tau$ found strictly on the new side, with the bracket below 4 ulps of $t$.
/// The iterates are taken without $\Phi$, which only the returned step needs.
///
/// These steps are always the 5th-order pair's, also when the integration uses the 8th-order
/// one: its stages near $c = 1$ lie within their (larger) stage error of the surface, on
/// either side, and a stage on the new side puts the new side's Jacobian into $\Phi$. On
/// the dead-band oscillator at rtol 1e-12, leaving the contact with 8th-order landing steps
/// left $\Phi$ off its closed form by 2.3e-4, with 5th-order ones by 8e-14.
pub(super) fn land_on<const N: usize, F: VectorField<N>, C: Carried<N>>(
    rk: &mut Rk<'_, N, F>,
    p0: &Point<N, C>,
    g: impl Fn(&SVector<f64, N>) -> f64,
    lo: (f64, f64),
    hi: (f64, f64),
    guess: f64,
) -> Trial<N, C> {
    let ((mut a, mut fa), (mut b, mut fb)) = (lo, hi);
    let variational = rk.variational;
    rk.variational = false;
    let (mut tau, mut last) = (guess, 0_i8);
    let tol = 4.0 * f64::EPSILON * (p0.t.abs() + b);
    for _ in 0..MAX_ITER {
        // Outside the open bracket (or NaN): bisect instead.
        if !(tau > a && tau < b) {
            tau = 0.5 * (a + b);
        }
        let v = g(&rk.step5(p0, tau).end.x);
        if v * fb > 0.0 {
            (b, fb) = (tau, v);
            // The same end kept twice: halve its value so that the next secant moves it.
            if last > 0 {
                fa *= 0.5;
            }
            last = 1;
        } else {
            // On the surface exactly counts as the old side: the step returned must end
            // strictly on the new side, where the field (and its Jacobian, which starts the
            // next step's variational equations) is the new side's.
            a = tau;
            if v != 0.0 {
                fa = v;
            }
            if last < 0 {
                fb *= 0.5;
            }
            last = -1;
        }
        if b - a <= tol {
            break;
        }
        tau = (a * fb - b * fa) / (fb - fa);
    }
    rk.variational = variational;
    let mut trial = rk.step5(p0, b);
    trial.end.t = p0.t + b;
    if b - a <= tol {
        // The step a few ulps past the surface evaluates its last (FSAL) stage on the new
        // side: f is continuous there but J is not, so Φ's error estimate would carry the
        // jump of J. The step to the old end of the bracket has the honest estimate.
        trial.err = rk.step5(p0, a).err;
    }
    trial
}

/// Brent's method (R. P. Brent, *Algorithms for Minimization without Derivatives*, 1973,
/// ch. 4, "zeroin"): inverse quadratic interpolation or secant, safeguarded by bisection, on a
/// bracket $[a, b]$ with $g(a)\,g(b) < 0$; converges superlinearly and never leaves the bracket.
/// Stops when the bracket is below $2\varepsilon|b| + \mathrm{tol}/2$.
pub(super) fn brent(
    g: &mut impl FnMut(f64) -> f64,
    a: f64,
    b: f64,
    fa: f64,
    fb: f64,
    tol: f64,
) -> f64 {
    let (mut a, mut b, mut fa, mut fb) = (a, b, fa, fb);
    // c is the other end of the bracket; d the last step, e the one before.
    let (mut c, mut fc) = (a, fa);
    let (mut d, mut e) = (b - a, b - a);
    for _ in 0..200 {
        if fb * fc > 0.0 {
            (c, fc) = (a, fa);
            (d, e) = (b - a, b - a);
        }
        if fc.abs() < fb.abs() {
            (a, fa) = (b, fb);
            (b, fb) = (c, fc);
            (c, fc) = (a, fa);
        }
        let tol1 = 2.0 * f64::EPSILON * b.abs() + 0.5 * tol;
        let xm = 0.5 * (c - b);
        if xm.abs() <= tol1 || fb == 0.0 {
            return b;
        }
        if e.abs() >= tol1 && fa.abs() > fb.abs() {
            let s = fb / fa;
            // After a bracket reset a == c: only two points, use the secant.
            let (mut p, mut q) = if a.to_bits() == c.to_bits() {
                (2.0 * xm * s, 1.0 - s)
            } else {
                let (q, r) = (fa / fc, fb / fc);
                (
                    s * (2.0 * xm * q * (q - r) - (b - a) * (r - 1.0)),
                    (q - 1.0) * (r - 1.0) * (s - 1.0),
                )
            };
            if p > 0.0 {
                q = -q;
            }
            p = p.abs();
            if 2.0 * p < (3.0 * xm * q - (tol1 * q).abs()).min((e * q).abs()) {
                (e, d) = (d, p / q);
            } else {
                (d, e) = (xm, xm);
            }
        } else {
            (d, e) = (xm, xm);
        }
        (a, fa) = (b, fb);
        b += if d.abs() > tol1 { d } else { tol1.copysign(xm) };
        fb = g(b);
    }
    b
}
