//! One Dormand–Prince 5(4) step on the augmented system $(x, \Phi)$, its error estimate, its
//! continuous extension, and the step-size controller.
//!
//! Tableau: J. R. Dormand & P. J. Prince, "A family of embedded Runge–Kutta formulae",
//! J. Comput. Appl. Math. 6 (1980) 19–26; as printed in Hairer, Nørsett & Wanner, *Solving
//! Ordinary Differential Equations I* (2nd ed.), §II.5, Table 5.2. Dense output: Shampine
//! (1986), HNW I §II.6 (the `CONTD5` of Hairer's DOPRI5). Controller: DOPRI5's PI controller
//! (see [`Controller`]).
//!
//! The field is autonomous, so the nodes $c_i$ never enter a stage (only the tests use them).

use nalgebra::{SMatrix, SVector};

use super::{Method, Tolerances, VectorField};

/// Stage coefficients $a_{ij}$, row $i$ = stage $i + 2$. Row 6 (stage 7) equals $b$: the
/// method is FSAL, the 7th stage is $f$ at the new point.
const A: [[f64; 6]; 6] = [
    [1.0 / 5.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    [3.0 / 40.0, 9.0 / 40.0, 0.0, 0.0, 0.0, 0.0],
    [44.0 / 45.0, -56.0 / 15.0, 32.0 / 9.0, 0.0, 0.0, 0.0],
    [
        19372.0 / 6561.0,
        -25360.0 / 2187.0,
        64448.0 / 6561.0,
        -212.0 / 729.0,
        0.0,
        0.0,
    ],
    [
        9017.0 / 3168.0,
        -355.0 / 33.0,
        46732.0 / 5247.0,
        49.0 / 176.0,
        -5103.0 / 18656.0,
        0.0,
    ],
    [
        35.0 / 384.0,
        0.0,
        500.0 / 1113.0,
        125.0 / 192.0,
        -2187.0 / 6784.0,
        11.0 / 84.0,
    ],
];

/// Nodes $c_i$ (only used to check the order conditions).
#[cfg(test)]
pub(super) const C: [f64; 7] = [0.0, 0.2, 0.3, 0.8, 8.0 / 9.0, 1.0, 1.0];
#[cfg(test)]
pub(super) const TABLEAU: [[f64; 6]; 6] = A;

/// $e_i = b_i - \hat b_i$: the difference between the 5th- and the embedded 4th-order weights.
pub(super) const E: [f64; 7] = [
    71.0 / 57600.0,
    0.0,
    -71.0 / 16695.0,
    71.0 / 1920.0,
    -17253.0 / 339200.0,
    22.0 / 525.0,
    -1.0 / 40.0,
];

/// Shampine's dense-output coefficients $d_i$ (HNW I, §II.6).
const D: [f64; 7] = [
    -12715105075.0 / 11282082432.0,
    0.0,
    87487479700.0 / 32700410799.0,
    -10690763975.0 / 1880347072.0,
    701980252875.0 / 199316789632.0,
    -1453857185.0 / 822651844.0,
    69997945.0 / 29380423.0,
];

/// What the variational equations carry along with the state: nothing (`()`), the monodromy
/// matrix $\Phi$ (an `N × N` matrix, $\dot\Phi = J\Phi$), or one tangent vector
/// ([`Column`], $\dot w = Jw$).
///
/// **Why a type and not a flag.** The carried value lives in every point and every stage of a
/// step. When it was always the full matrix, a plain simulation of the 34-state car moved and
/// zeroed 7 stage matrices of 9 KB each per step although it never used them: a profile of
/// 30 s of the S1002 car spent 34 % of its time in `memmove`, 7 % in `memset` and 15 % in the
/// finiteness test of the unused matrices, against 20 % in the model's f. With the carried
/// value a type, a simulation carries nothing (zero bytes) and a Lyapunov exponent one
/// column; the arithmetic on $x$ is unchanged, so the trajectories are the same to the bit.
pub(super) trait Carried<const N: usize>: Copy {
    /// Carried whatever [`OdeOptions::monodromy`](super::OdeOptions::monodromy) says (a
    /// tangent vector); the monodromy matrix rides along only when the options ask for it.
    const ALWAYS: bool;
    /// The value with every entry zero (the stage of a step taken without it).
    fn zero() -> Self;
    /// The value at $t = 0$ when the caller gives none: $\Phi(0) = I$ (the first unit
    /// vector for a column).
    fn identity() -> Self;
    /// $s = y + h\sum_j a_j k_j$, as [`combine`] does for the state.
    fn combine(y: &Self, h: f64, a: &[f64], k: &[Self]) -> Self;
    /// $s = y + h\sum_{(j, a)} a\,k_j$ over a sparse row of `(stage, coefficient)` pairs.
    fn combine_sparse(y: &Self, h: f64, row: &[(usize, f64)], k: &[Self]) -> Self;
    /// The scaled error of the value (see [`phi_rms`]); 0 for nothing.
    fn error(e: &Self, y0: &Self, y1: &Self, tol: &Tolerances) -> f64;
    /// The sum of the entries (finite exactly when every entry is, short of overflow).
    fn sum(&self) -> f64;
    /// $f(x; p)$ and the carried value's derivative $J(x)\,c$.
    fn field<F: VectorField<N>>(
        f: &F,
        x: &SVector<f64, N>,
        p: f64,
        c: &Self,
    ) -> (SVector<f64, N>, Self);
    /// The monodromy matrix, when this is it.
    fn monodromy(&self) -> Option<SMatrix<f64, N, N>>;
}

impl<const N: usize> Carried<N> for () {
    const ALWAYS: bool = false;
    fn zero() -> Self {}
    fn identity() -> Self {}
    fn combine(_: &Self, _: f64, _: &[f64], _: &[Self]) -> Self {}
    fn combine_sparse(_: &Self, _: f64, _: &[(usize, f64)], _: &[Self]) -> Self {}
    fn error(_: &Self, _: &Self, _: &Self, _: &Tolerances) -> f64 {
        0.0
    }
    fn sum(&self) -> f64 {
        0.0
    }
    #[inline(always)]
    fn field<F: VectorField<N>>(
        f: &F,
        x: &SVector<f64, N>,
        p: f64,
        _: &Self,
    ) -> (SVector<f64, N>, Self) {
        (f.rhs(x, p), ())
    }
    fn monodromy(&self) -> Option<SMatrix<f64, N, N>> {
        None
    }
}

impl<const N: usize> Carried<N> for SMatrix<f64, N, N> {
    const ALWAYS: bool = false;
    fn zero() -> Self {
        SMatrix::zeros()
    }
    fn identity() -> Self {
        SMatrix::identity()
    }
    #[inline(always)]
    fn combine(y: &Self, h: f64, a: &[f64], k: &[Self]) -> Self {
        combine(y, h, a, k)
    }
    #[inline(always)]
    fn combine_sparse(y: &Self, h: f64, row: &[(usize, f64)], k: &[Self]) -> Self {
        super::dop853::sparse(y, h, row, k)
    }
    fn error(e: &Self, y0: &Self, y1: &Self, tol: &Tolerances) -> f64 {
        phi_rms(e, y0, y1, tol)
    }
    fn sum(&self) -> f64 {
        SMatrix::sum(self)
    }
    #[inline(always)]
    fn field<F: VectorField<N>>(
        f: &F,
        x: &SVector<f64, N>,
        p: f64,
        c: &Self,
    ) -> (SVector<f64, N>, Self) {
        f.rhs_variational(x, p, c)
    }
    fn monodromy(&self) -> Option<SMatrix<f64, N, N>> {
        Some(*self)
    }
}

/// One tangent vector $w$ with $\dot w = J(x)\,w$: $\Phi(t)\,w_0$ without $\Phi$ (the
/// largest Lyapunov exponent needs no more). With `CHECKED` its error is measured as one
/// column of $\Phi$ and joins the step control; without, the steps are the state's alone
/// and $w$ rides along on them (see [`integrate_tangent`](super::integrate_tangent)).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Column<const N: usize, const CHECKED: bool>(pub SVector<f64, N>);

impl<const N: usize, const CHECKED: bool> Carried<N> for Column<N, CHECKED> {
    const ALWAYS: bool = true;
    fn zero() -> Self {
        Column(SVector::zeros())
    }
    fn identity() -> Self {
        let mut e = SVector::zeros();
        if N > 0 {
            e[0] = 1.0;
        }
        Column(e)
    }
    #[inline(always)]
    fn combine(y: &Self, h: f64, a: &[f64], k: &[Self]) -> Self {
        let mut s = y.0;
        for (aj, kj) in a.iter().zip(k) {
            s.axpy(h * aj, &kj.0, 1.0);
        }
        Column(s)
    }
    #[inline(always)]
    fn combine_sparse(y: &Self, h: f64, row: &[(usize, f64)], k: &[Self]) -> Self {
        let mut s = y.0;
        for &(j, a) in row {
            s.axpy(h * a, &k[j].0, 1.0);
        }
        Column(s)
    }
    fn error(e: &Self, y0: &Self, y1: &Self, tol: &Tolerances) -> f64 {
        if CHECKED {
            phi_rms(&e.0, &y0.0, &y1.0, tol)
        } else {
            0.0
        }
    }
    fn sum(&self) -> f64 {
        self.0.sum()
    }
    #[inline(always)]
    fn field<F: VectorField<N>>(
        f: &F,
        x: &SVector<f64, N>,
        p: f64,
        c: &Self,
    ) -> (SVector<f64, N>, Self) {
        let (fx, jw) = f.rhs_tangent(x, p, &c.0);
        (fx, Column(jw))
    }
    fn monodromy(&self) -> Option<SMatrix<f64, N, N>> {
        None
    }
}

/// A point of the trajectory with the (augmented) field there, kept so that the next step can
/// reuse it as its first stage (FSAL): $f = f(x)$, $f_\Phi = J(x)\,\Phi$ ($\Phi$ being
/// whatever `C` carries).
#[derive(Clone, Copy, Debug)]
pub(super) struct Point<const N: usize, C> {
    pub t: f64,
    pub x: SVector<f64, N>,
    pub phi: C,
    pub f: SVector<f64, N>,
    pub f_phi: C,
}

/// A trial step: the candidate end point, its scaled error, and the stages of $x$ (needed only
/// if a continuous extension is asked for).
pub(super) struct Trial<const N: usize, C> {
    pub end: Point<N, C>,
    pub err: f64,
    /// the 5th-order method's stages; the 8th-order method's partial sums for its continuous
    /// extension (see `dop853.rs`)
    pub(super) k: [SVector<f64, N>; 7],
    /// the pair that took the step (a step landing on a switching surface is always the
    /// 5th-order pair's, see `events::land_on`)
    pub(super) method: Method,
}

/// The method bound to a field: the parameter, whether $\Phi$ rides along, the tolerances, and
/// the count of field evaluations.
pub(super) struct Rk<'a, const N: usize, F> {
    pub field: &'a F,
    pub p: f64,
    pub variational: bool,
    pub tol: Tolerances,
    /// the tolerances of the carried value's error test (`tol` scaled by
    /// [`OdeOptions::monodromy_tol_factor`](super::OdeOptions::monodromy_tol_factor))
    pub tol_phi: Tolerances,
    pub rhs_evals: usize,
    pub method: Method,
}

/// $s = y + h\sum_j a_j k_j$ (at most 7 terms). Blocks of 64 entries or more (Φ of 8 states
/// and up) are combined entry by entry: each entry's sum runs over the terms in order (the
/// same additions as one pass per term, so the same result to the bit), but the result is
/// written once instead of once per term: on the 28-state car's $\Phi$ (6 KB per matrix) the
/// passes per term were memory traffic (the bogie's diagram took 1.6× less CPU). Smaller
/// blocks keep one pass per term, faster there.
#[inline(always)]
fn combine<const R: usize, const CC: usize>(
    y: &SMatrix<f64, R, CC>,
    h: f64,
    a: &[f64],
    k: &[SMatrix<f64, R, CC>],
) -> SMatrix<f64, R, CC> {
    if R * CC < 64 {
        // small blocks (the wheelset's x and Φ, every state vector): one pass per term is
        // faster than the dispatch below
        // on slices, not nalgebra's strided iterators, so that the loop vectorises (the same
        // operations in the same order: bit-identical)
        let mut s = *y;
        for (aj, kj) in a.iter().zip(k) {
            let c = h * aj;
            for (si, ki) in s.as_mut_slice().iter_mut().zip(kj.as_slice()) {
                *si += c * ki;
            }
        }
        return s;
    }
    match a.len().min(k.len()) {
        0 => *y,
        1 => combine_n::<R, CC, 1>(y, h, a, k),
        2 => combine_n::<R, CC, 2>(y, h, a, k),
        3 => combine_n::<R, CC, 3>(y, h, a, k),
        4 => combine_n::<R, CC, 4>(y, h, a, k),
        5 => combine_n::<R, CC, 5>(y, h, a, k),
        6 => combine_n::<R, CC, 6>(y, h, a, k),
        _ => combine_n::<R, CC, 7>(y, h, a, k),
    }
}

/// [`combine`] with `M` terms (`a` and `k` hold at least `M`): the term loop unrolls and the
/// entry loop vectorises.
#[inline(always)]
fn combine_n<const R: usize, const CC: usize, const M: usize>(
    y: &SMatrix<f64, R, CC>,
    h: f64,
    a: &[f64],
    k: &[SMatrix<f64, R, CC>],
) -> SMatrix<f64, R, CC> {
    let c: [f64; M] = std::array::from_fn(|j| h * a[j]);
    let ks: [&[f64]; M] = std::array::from_fn(|j| k[j].as_slice());
    let mut s = *y;
    for (e, si) in s.as_mut_slice().iter_mut().enumerate() {
        let mut acc = *si;
        for j in 0..M {
            acc += c[j] * ks[j][e];
        }
        *si = acc;
    }
    s
}

/// RMS of $e_i / (\mathrm{atol} + \mathrm{rtol}\max(|y_{0,i}|, |y_{1,i}|))$ (HNW I, (4.11)).
pub(super) fn scaled_rms<const R: usize, const CC: usize>(
    e: &SMatrix<f64, R, CC>,
    y0: &SMatrix<f64, R, CC>,
    y1: &SMatrix<f64, R, CC>,
    tol: &Tolerances,
) -> f64 {
    let mut sum = 0.0;
    for ((ei, a), b) in e.as_slice().iter().zip(y0.as_slice()).zip(y1.as_slice()) {
        let r = ei / (tol.atol + tol.rtol * a.abs().max(b.abs()));
        sum += r * r;
    }
    (sum / (R * CC) as f64).sqrt()
}

/// The RMS error of $\Phi$ with each column measured against its own size: entry $(i, j)$ is
/// scaled by $\mathrm{atol} + \mathrm{rtol}\max(1, \max_k |\Phi_{0,kj}|, \max_k
/// |\Phi_{1,kj}|)$, the 1 being the column's size at the start ($\Phi(0) = I$). A column of
/// $\Phi$ is the response to one initial perturbation; the Newton matrix and the Floquet
/// multipliers need it accurate relative to the larger of its initial and current size
/// (normwise: a multiplier's error is about the norm of the error of $\Phi$), not each entry
/// to its own relative tolerance: the entrywise test resolved the decay of the fast creep modes
/// (the zeros of $\Phi(0) = I$ filling in, then the decaying columns) down to `atol`. On the
/// wheelset's cone branch (rtol 1e-10) this takes a quarter fewer steps than the entrywise
/// test, with trivial multipliers still within 2.5e-12 of 1; on the DTU bogie and car 40 %
/// fewer (241 against 397 and 207 against 357 steps per linearisation). (Loosening $\Phi$'s
/// tolerance further, 10 or 100 times the state's, saves another quarter of the steps on the
/// cone but stalls Newton near the fold of the S1002 branch: not done.)
///
/// **Why the vehicles' Newton failed at folds with this control** (it was entrywise for
/// N > 4 until the cause was found), measured on `studies/dtu-cooperrider-{bogie,car}.toml`:
///
/// * Two things, not one. On the car the continuation scaled each coordinate by its own share
///   of the Hopf eigenvector: the car body's yaw got a scale of 4e-7 rad, so Newton's
///   scaled tolerance (1e-9) asked for that yaw to 4e-16 rad, far below what the integration
///   resolves, and only the entrywise control, which keeps that small row of $\Phi$ accurate
///   relative to itself, let Newton converge at all (slowly: the car crept along at 1e-5 m/s
///   per cycle near its 149.8 m/s fold, 1169 cycles). The scales are now per kind of
///   coordinate (`bifurcation::coordinate_shares`).
/// * With sane scales the bogie still stopped at its 150.5 m/s fold (Newton: 8 iterations
///   without reaching 10 rtol), with one or two shooting segments alike, while the entrywise
///   control passed it. These orbits cross the contact table's curvature jumps (the table is
///   C¹, so $J$ jumps there and the error estimate of $\Phi$, whose derivative is $J\Phi$,
///   is not asymptotically valid): a fifth of the steps are rejected and the trivial
///   multiplier is only within 1e-7 of 1 (1e-12 on the cone). Newton with an inexact matrix
///   converges linearly at a rate of about $\|A^{-1}\delta A\|$, and near a fold the
///   (x0, T) block is nearly singular, so $\|A^{-1}\|$ grows; the per-column control, which
///   lets every entry of a column carry an error of rtol times the column's largest entry,
///   leaves $\delta A$ larger in the small entries (position rows are about ω ≈ 63 s⁻¹ smaller
///   than velocity rows) than the entrywise control does, and the rate near 150.5 m/s was too
///   slow for 8 iterations to reach 10 rtol. (A mechanism consistent with the measurements,
///   not proven: the Newton rate itself was not logged.) Newton at 100 rtol for vehicles
///   (`bifurcation::newton_tol`) passes all three folds of the bogie and the car with this
///   control; the folds and V_NL move by about 1e-8 m/s.
fn phi_rms<const N: usize, const M: usize>(
    e: &SMatrix<f64, N, M>,
    y0: &SMatrix<f64, N, M>,
    y1: &SMatrix<f64, N, M>,
    tol: &Tolerances,
) -> f64 {
    let mut sum = 0.0;
    for j in 0..M {
        let mut size = 1.0f64;
        for i in 0..N {
            size = size.max(y0[(i, j)].abs()).max(y1[(i, j)].abs());
        }
        let w = 1.0 / (tol.atol + tol.rtol * size);
        for i in 0..N {
            let r = e[(i, j)] * w;
            sum += r * r;
        }
    }
    (sum / (N * M) as f64).sqrt()
}

impl<const N: usize, F: VectorField<N>> Rk<'_, N, F> {
    /// The augmented field at $(x, \Phi)$; $J$ is only evaluated when $\Phi$ rides along.
    #[inline(always)]
    pub(super) fn eval<C: Carried<N>>(
        &mut self,
        x: &SVector<f64, N>,
        phi: &C,
    ) -> (SVector<f64, N>, C) {
        self.rhs_evals += 1;
        if self.variational {
            C::field(self.field, x, self.p, phi)
        } else {
            (self.field.rhs(x, self.p), C::zero())
        }
    }

    /// A point with its field evaluated (the start of the integration).
    pub fn point<C: Carried<N>>(&mut self, t: f64, x: SVector<f64, N>, phi: C) -> Point<N, C> {
        let (f, f_phi) = self.eval(&x, &phi);
        Point {
            t,
            x,
            phi,
            f,
            f_phi,
        }
    }

    /// One step of size `h` from `p0` by the pair `method` names (6 new evaluations for the
    /// 5th-order pair thanks to FSAL, 12 for the 8th-order one). The error is
    /// $\max(\|e_x\|, \|e_\Phi\|)$ with the scaled RMS norm of each block (see
    /// [`phi_rms`]): taking the max rather than one RMS over all $N + N^2$ components means
    /// switching the monodromy on never loosens the control of the state (the $N^2$ entries of
    /// $\Phi$ would otherwise dilute it), and $\Phi$ is normwise as accurate as $x$ — which
    /// is what Floquet multipliers accurate to ~1e-9 need.
    pub fn step<C: Carried<N>>(&mut self, p0: &Point<N, C>, h: f64) -> Trial<N, C> {
        match self.method {
            Method::DormandPrince5 => self.step5(p0, h),
            Method::DormandPrince8 => self.step8(p0, h),
        }
    }

    /// The continuous extension of the step `trial` from `p0` (the 8th-order method spends
    /// three evaluations of $f$ on it).
    pub fn dense<C>(&mut self, p0: &Point<N, C>, trial: &Trial<N, C>) -> Dense<N> {
        match trial.method {
            Method::DormandPrince5 => Dense::new(p0, trial),
            Method::DormandPrince8 => self.dense8(p0, trial),
        }
    }

    /// The largest and smallest value of each component over the step (see
    /// [`Dense::extremes`]). The 8th-order method builds its continuous extension only when
    /// some component's derivative changes sign between the step's ends (else the extremes
    /// are the end values): a component with a maximum and a minimum inside one step, and
    /// the same sign of $f_k$ at both ends, is not seen.
    pub fn extremes<C>(
        &mut self,
        p0: &Point<N, C>,
        trial: &Trial<N, C>,
    ) -> (SVector<f64, N>, SVector<f64, N>) {
        match trial.method {
            Method::DormandPrince5 => Dense::new(p0, trial).extremes(),
            Method::DormandPrince8 => {
                let turns =
                    p0.f.iter()
                        .zip(trial.end.f.iter())
                        .any(|(a, b)| a * b <= 0.0);
                if turns {
                    self.dense8(p0, trial).extremes()
                } else {
                    (p0.x.sup(&trial.end.x), p0.x.inf(&trial.end.x))
                }
            }
        }
    }

    /// One Dormand–Prince 5(4) step (see [`Rk::step`]), whatever `method` says.
    pub(super) fn step5<C: Carried<N>>(&mut self, p0: &Point<N, C>, h: f64) -> Trial<N, C> {
        let mut k = [SVector::<f64, N>::zeros(); 7];
        let mut kp = [C::zero(); 7];
        k[0] = p0.f;
        kp[0] = p0.f_phi;
        for s in 1..6 {
            let a = &A[s - 1][..s];
            let xs = combine(&p0.x, h, a, &k[..s]);
            if self.variational {
                let phis = C::combine(&p0.phi, h, a, &kp[..s]);
                (k[s], kp[s]) = self.eval(&xs, &phis);
            } else {
                (k[s], kp[s]) = self.eval(&xs, &p0.phi);
            }
        }
        // the 7th stage is the new point (FSAL): kept, not copied at every stage
        let a = &A[5][..6];
        let x1 = combine(&p0.x, h, a, &k[..6]);
        let phi1 = if self.variational {
            C::combine(&p0.phi, h, a, &kp[..6])
        } else {
            p0.phi
        };
        (k[6], kp[6]) = self.eval(&x1, &phi1);
        let ex = combine(&SVector::zeros(), h, &E, &k);
        let mut err = scaled_rms(&ex, &p0.x, &x1, &self.tol);
        if self.variational {
            let ep = C::combine(&C::zero(), h, &E, &kp);
            let e_phi = C::error(&ep, &p0.phi, &phi1, &self.tol_phi);
            err = err.max(e_phi);
        }
        let end = Point {
            t: p0.t + h,
            x: x1,
            phi: phi1,
            f: k[6],
            f_phi: kp[6],
        };
        Trial {
            end,
            err,
            k,
            method: Method::DormandPrince5,
        }
    }

    /// Starting step size, HNW I §II.4 ("Starting step size", the `HINIT` of DOPRI5), on the
    /// state only: $h_0 = 0.01\|x_0\|/\|f_0\|$, one Euler step for a second-derivative
    /// estimate, $h_1 = (0.01/\max(\|f'\|, \|f_0\|))^{1/5}$, $h = \min(100h_0, h_1, h_{\max})$.
    pub fn initial_step<C>(&mut self, p0: &Point<N, C>, h_max: f64) -> f64 {
        let sk = p0.x.map(|v| self.tol.atol + self.tol.rtol * v.abs());
        let rms = |v: &SVector<f64, N>| (v.component_div(&sk).norm_squared() / N as f64).sqrt();
        let (dy, df) = (rms(&p0.x), rms(&p0.f));
        let h0 = if dy <= 1e-10 || df <= 1e-10 {
            1e-6
        } else {
            0.01 * dy / df
        }
        .min(h_max);
        let x1 = p0.x + p0.f * h0;
        self.rhs_evals += 1;
        let f1 = self.field.rhs(&x1, self.p);
        let d2 = rms(&(f1 - p0.f)) / h0;
        let d12 = d2.max(df);
        let h1 = if d12 <= 1e-15 {
            (h0 * 1e-3).max(1e-6)
        } else {
            match self.method {
                Method::DormandPrince5 => (0.01 / d12).powf(0.2),
                Method::DormandPrince8 => (0.01 / d12).powf(0.125),
            }
        };
        let h = (100.0 * h0).min(h1).min(h_max);
        // A NaN here (non-finite field) is caught by the first step's error test.
        if h.is_finite() && h > 0.0 {
            h
        } else {
            h0
        }
    }
}

/// Shampine's 4th-order continuous extension of one step,
/// $x(t_0 + \theta h) = r_0 + \theta\,(r_1 + (1-\theta)(r_2 + \theta\,(r_3 + (1-\theta)\,r_4)))$,
/// $\theta \in [0, 1]$, with $r_0 = x_0$, $r_1 = x_1 - x_0$, $r_2 = h k_1 - r_1$,
/// $r_3 = r_1 - h k_7 - r_2$, $r_4 = h\sum_i d_i k_i$. It matches $x_0, x_1, f_0, f_1$
/// (so it is $C^1$ across steps) and has local error $O(h^5)$.
///
/// The 8th-order method's extension ([`Dense::degree7`], HNW I §II.6 and DOP853's `CONTD8`) is
/// $x = r_0 + \theta(r_1 + \bar\theta(r_2 + \theta(r_3 + \bar\theta(r_4 + \theta(r_5 +
/// \bar\theta(r_6 + \theta r_7))))))$, $\bar\theta = 1 - \theta$, of local error $O(h^8)$.
pub(super) struct Dense<const N: usize> {
    t0: f64,
    h: f64,
    r: [SVector<f64, N>; 8],
    degree7: bool,
}

impl<const N: usize> Dense<N> {
    pub fn new<C>(p0: &Point<N, C>, trial: &Trial<N, C>) -> Self {
        let h = trial.end.t - p0.t;
        let r1 = trial.end.x - p0.x;
        let r2 = trial.k[0] * h - r1;
        let r3 = r1 - trial.k[6] * h - r2;
        let r4 = combine(&SVector::zeros(), h, &D, &trial.k);
        let z = SVector::zeros();
        Dense {
            t0: p0.t,
            h,
            r: [p0.x, r1, r2, r3, r4, z, z, z],
            degree7: false,
        }
    }

    /// The 8th-order method's extension from its eight coefficient vectors.
    pub fn degree7(t0: f64, h: f64, r: [SVector<f64, N>; 8]) -> Self {
        Dense {
            t0,
            h,
            r,
            degree7: true,
        }
    }

    /// The state at time `t` (within the step).
    pub fn eval(&self, t: f64) -> SVector<f64, N> {
        let th = (t - self.t0) / self.h;
        let th1 = 1.0 - th;
        if self.degree7 {
            let r = &self.r;
            let inner = (r[5] + (r[6] + r[7] * th) * th1) * th;
            return r[0] + (r[1] + (r[2] + (r[3] + (r[4] + inner) * th1) * th) * th1) * th;
        }
        let [r0, r1, r2, r3, r4, ..] = &self.r;
        r0 + (r1 + (r2 + (r3 + r4 * th1) * th) * th1) * th
    }

    /// The power-basis coefficients of component `i` of the degree-7 extension, from its
    /// nested form (inside out: a factor $\theta$ shifts the coefficients up, a factor
    /// $1 - \theta$ subtracts the shifted ones).
    fn power7(&self, i: usize) -> [f64; 8] {
        let mut c = [0.0; 8];
        c[0] = self.r[7][i];
        for (n, r) in self.r.iter().enumerate().take(7).rev() {
            // r_n + θ·P for even n, r_n + (1 − θ)·P for odd n (degree of P: 6 − n)
            let mut shifted = [0.0; 8];
            shifted[1..].copy_from_slice(&c[..7]);
            if n % 2 == 0 {
                c = shifted;
            } else {
                for (cj, sj) in c.iter_mut().zip(shifted) {
                    *cj -= sj;
                }
            }
            c[0] += r[i];
        }
        c
    }

    /// [`Dense::extremes`] of the degree-7 extension: the derivative (degree 6) sampled at
    /// eighths of the step, each sign change refined by bisection.
    fn extremes7(&self) -> (SVector<f64, N>, SVector<f64, N>) {
        let mut high = SVector::<f64, N>::zeros();
        let mut low = SVector::<f64, N>::zeros();
        for i in 0..N {
            let c = self.power7(i);
            let x = |t: f64| c.iter().rev().fold(0.0, |acc, &cj| acc * t + cj);
            let dx = |t: f64| (1..8).rev().fold(0.0, |acc, j| acc * t + j as f64 * c[j]);
            (high[i], low[i]) = extremes_on(x, dx, 8);
        }
        (high, low)
    }

    /// The largest and the smallest value of each component over the step, on the continuous
    /// extension, `(max x_k, min x_k)`: the end values, and the interior zeros of
    /// $dx_k/d\theta$ (an asymmetric cycle's amplitude on each side comes from these). In the power basis
    /// $x = r_0 + \theta(r_1 + r_2) + \theta^2(r_3 + r_4 - r_2) - \theta^3(r_3 + 2r_4) + \theta^4 r_4$
    /// the derivative is a cubic; its sign is sampled at $\theta = 0, 1/4, \dots, 1$ and each
    /// sign change is refined by bisection to round-off (an extremum of $x_k$ is flat, so the
    /// value there is as accurate as the continuous extension itself). Two extrema of one
    /// component within a quarter step (a wiggle far below the step's resolution) are not seen.
    pub fn extremes(&self) -> (SVector<f64, N>, SVector<f64, N>) {
        if self.degree7 {
            return self.extremes7();
        }
        let [r0, r1, r2, r3, r4, ..] = &self.r;
        let mut high = SVector::<f64, N>::zeros();
        let mut low = SVector::<f64, N>::zeros();
        for i in 0..N {
            let c = [
                r0[i],
                r1[i] + r2[i],
                r3[i] + r4[i] - r2[i],
                -(r3[i] + 2.0 * r4[i]),
                r4[i],
            ];
            let x = |t: f64| c[0] + t * (c[1] + t * (c[2] + t * (c[3] + t * c[4])));
            let dx = |t: f64| c[1] + t * (2.0 * c[2] + t * (3.0 * c[3] + t * 4.0 * c[4]));
            (high[i], low[i]) = extremes_on(x, dx, 4);
        }
        (high, low)
    }
}

/// The largest and the smallest value of the polynomial `x` on $[0, 1]$: its end values and
/// its values at the sign changes of its derivative `dx`, sampled at `parts` equal pieces and
/// refined by [`bisect`].
fn extremes_on(x: impl Fn(f64) -> f64, dx: impl Fn(f64) -> f64, parts: usize) -> (f64, f64) {
    let (a, b) = (x(0.0), x(1.0));
    let (mut hi_v, mut lo_v) = (a.max(b), a.min(b));
    let (mut t0, mut d0) = (0.0, dx(0.0));
    for q in 1..=parts {
        let t1 = q as f64 / parts as f64;
        let d1 = dx(t1);
        if d0 * d1 < 0.0 {
            let v = x(bisect(&dx, t0, t1, d0));
            hi_v = hi_v.max(v);
            lo_v = lo_v.min(v);
        }
        (t0, d0) = (t1, d1);
    }
    (hi_v, lo_v)
}

/// The root of `dx` in `[lo, hi]`, where it changes sign (`dx(lo) = dlo`), by bisection to
/// round-off.
fn bisect(dx: &impl Fn(f64) -> f64, lo: f64, hi: f64, dlo: f64) -> f64 {
    let (mut lo, mut hi) = (lo, hi);
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if mid <= lo || mid >= hi {
            break;
        }
        if dx(mid) * dlo > 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

/// The PI step-size controller of Hairer & Wanner's DOPRI5 (HNW I §II.4 for the I-part;
/// the PI form after Gustafsson, Lundh & Söderlind, BIT 28 (1988), as in HNW II §IV.2):
/// $h_{new} = h \cdot \mathrm{clamp}(0.9\,\mathrm{err}_n^{-\alpha}\,\mathrm{err}_{n-1}^{\beta},
/// 1/5, 10)$ with $\beta = 0.04$, $\alpha = 1/5 - 0.75\beta$ (DOPRI5's defaults). The
/// $\beta$ term damps the oscillation of $h$ a pure I-controller shows when stability, not
/// accuracy, limits the step. After a rejection the next step may not grow.
pub(super) struct Controller {
    /// $\ln \max(\mathrm{err}_{n-1}, 10^{-4})$: with logarithms the factor costs one `ln`
    /// and one `exp` instead of two `powf`, which were a quarter of a step on small systems.
    ln_err_old: f64,
    alpha: f64,
    beta: f64,
    fac_min: f64,
    fac_max: f64,
}

const SAFETY: f64 = 0.9;
const BETA: f64 = 0.04;
const ALPHA: f64 = 0.2 - 0.75 * BETA;
/// Largest shrink (1/5) and growth (10) of one step: HNW's defaults.
pub(super) const FAC_MIN: f64 = 0.2;
const FAC_MAX: f64 = 10.0;
/// DOPRI5's floor on the remembered error (and its initial value).
const ERR_OLD_MIN: f64 = 1e-4;

impl Controller {
    /// DOPRI5's controller for the 5th-order method; DOP853's defaults for the 8th-order one
    /// (no $\beta$ term, $\alpha = 1/8$, factors within $[0.333, 6]$).
    pub fn new(method: Method) -> Self {
        let (alpha, beta, fac_min, fac_max) = match method {
            Method::DormandPrince5 => (ALPHA, BETA, FAC_MIN, FAC_MAX),
            Method::DormandPrince8 => (0.125, 0.0, 0.333, 6.0),
        };
        Controller {
            ln_err_old: ERR_OLD_MIN.ln(),
            alpha,
            beta,
            fac_min,
            fac_max,
        }
    }

    /// Factor for the next step after an accepted one (err <= 1).
    pub fn accepted(&mut self, err: f64) -> f64 {
        // err = 0 gives ln = -inf, a factor of +inf, which the clamp turns into growth 10.
        let ln_err = err.ln();
        let fac = SAFETY * (self.beta * self.ln_err_old - self.alpha * ln_err).exp();
        self.ln_err_old = ln_err.max(ERR_OLD_MIN.ln());
        fac.clamp(self.fac_min, self.fac_max)
    }

    /// Factor for retrying a rejected step (err > 1): the I-part only, never growing.
    pub fn rejected(&self, err: f64) -> f64 {
        (SAFETY * err.powf(-self.alpha)).max(self.fac_min)
    }
}
