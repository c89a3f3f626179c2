//! Continuation of a Hopf point in (V, P): pseudo-arclength on the standard extended system.
//!
//! **System.** Unknowns $u = (a, b, ω, V, P) ∈ \mathbb R^{2N+3}$ with $v = a + ib$:
//! $$J a + ω b = 0,\quad J b − ω a = 0,\quad a_r·a + b_r·b = 1,\quad a_r·b − b_r·a = 0,$$
//! ($J = J(V, P)$; the last two fix the scale and phase of $v$ against the previous point's
//! normalised eigenvector $v_r = a_r + ib_r$: $\langle v_r, v\rangle = 1$), and one more
//! equation: the pseudo-arclength condition $\hat t_V(\hat V − \hat V_{pred}) +
//! \hat t_P(\hat P − \hat P_{pred}) = 0$ in the scaled plane $\hat V = V/s_V$,
//! $\hat P = P/s_P$ ($s_V$, $s_P$ the widths of the speed and key ranges), or $P$ or $V$
//! fixed at a bound. The standard (rather than a minimally augmented or bialternate) form is
//! chosen because $N ≤ 34$: Newton's matrix is $(2N+3)^2 ≤ 71^2$, an LU of about 0.1 ms,
//! against the bialternate product's $N(N−1)/2 = 561$ unknowns; and it gives the eigenvector,
//! which $l_1$ and the special points need anyway. At a simple Hopf point with a transversal
//! crossing the system is regular (as for [`crate::stability`]'s Newton at fixed $P$), so the
//! curve passes folds in $P$ (where $dP/ds = 0$) without trouble.
//!
//! **Derivatives.** $∂/∂a$, $∂/∂b$, $∂/∂ω$ exactly; $∂J/∂V = −J_1/V^2$ exactly; $∂J/∂P$ from
//! the family ([`super::family::HopfFamily::jacobian_p`]), taken at the last converged point
//! and kept through the corrector (a chord in that one column). The residual is always exact,
//! so the points are as accurate as Newton's tolerance whatever the difference's error.
//!
//! **Steps.** Predictor along the unit tangent (the null vector of the $2N+2$ equations,
//! oriented with the previous one), corrector by Newton (at most [`NEWTON_ITERATIONS`]);
//! a failed corrector or a turn of the tangent by more than [`MAX_TURN`] halves the step; an
//! easy one (at most 3 iterations) grows it by 1.5 up to `ds_max`.

use nalgebra::{DMatrix, DVector, SMatrix, SVector};

use super::family::HopfFamily;
use super::CurveError;

/// The most Newton iterations of one corrector.
pub const NEWTON_ITERATIONS: usize = 12;
/// The largest turn of the tangent between two points (rad) before the step is halved.
pub const MAX_TURN: f64 = 0.25;

/// Options of one curve's continuation (in the family's $P$).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HopfParams {
    /// the speeds the curve may visit (m/s)
    pub speed_range: (f64, f64),
    /// the $P$ range, lower bound first
    pub param_range: (f64, f64),
    /// first step (scaled arclength)
    pub ds_initial: f64,
    /// largest step (scaled arclength)
    pub ds_max: f64,
    /// smallest step before giving up (scaled arclength)
    pub ds_min: f64,
    /// most points on each side of the start
    pub max_points: usize,
    /// Newton's tolerance on the scaled update
    pub newton_tol: f64,
}

impl HopfParams {
    pub(super) fn scales(&self) -> (f64, f64) {
        (
            self.speed_range.1 - self.speed_range.0,
            self.param_range.1 - self.param_range.0,
        )
    }
}

/// A point of the extended system: the eigenvector $v = a + ib$, ω (rad/s), V (m/s), P.
#[derive(Clone, Debug, PartialEq)]
pub struct State<const N: usize> {
    pub a: SVector<f64, N>,
    pub b: SVector<f64, N>,
    pub omega: f64,
    pub v: f64,
    pub p: f64,
}

impl<const N: usize> State<N> {
    /// The unknowns as one vector.
    fn pack(&self) -> DVector<f64> {
        let mut u = DVector::zeros(2 * N + 3);
        for k in 0..N {
            u[k] = self.a[k];
            u[N + k] = self.b[k];
        }
        u[2 * N] = self.omega;
        u[2 * N + 1] = self.v;
        u[2 * N + 2] = self.p;
        u
    }

    fn unpack(u: &DVector<f64>) -> Self {
        Self {
            a: SVector::from_fn(|k, _| u[k]),
            b: SVector::from_fn(|k, _| u[N + k]),
            omega: u[2 * N],
            v: u[2 * N + 1],
            p: u[2 * N + 2],
        }
    }

    /// The eigenvector scaled to unit norm (the next point's reference).
    pub fn normalised(mut self) -> Self {
        let n = (self.a.norm_squared() + self.b.norm_squared()).sqrt();
        if n > 0.0 && n.is_finite() {
            self.a /= n;
            self.b /= n;
        }
        self
    }
}

/// The last equation of the corrector.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Constraint {
    /// $\hat t·(\hat X − \hat X_{pred}) = 0$ with the scaled tangent $(t_V, t_P)$ and the
    /// predicted $(V, P)$
    Arclength { tangent: (f64, f64), at: (f64, f64) },
    /// $P$ fixed
    Parameter(f64),
    /// $V$ fixed
    Speed(f64),
}

/// Newton's matrix and residual of the extended system at `s` with reference `r`.
fn assemble<const N: usize>(
    j: &SMatrix<f64, N, N>,
    jv: &SMatrix<f64, N, N>,
    jp: &SMatrix<f64, N, N>,
    s: &State<N>,
    r: &State<N>,
    last: Option<(Constraint, (f64, f64))>,
) -> (DMatrix<f64>, DVector<f64>) {
    let m = 2 * N + 2 + usize::from(last.is_some());
    let mut jac = DMatrix::<f64>::zeros(m, 2 * N + 3);
    let mut res = DVector::<f64>::zeros(m);
    let (ja, jb) = (j * s.a, j * s.b);
    let (jva, jvb) = (jv * s.a, jv * s.b);
    let (jpa, jpb) = (jp * s.a, jp * s.b);
    for row in 0..N {
        res[row] = ja[row] + s.omega * s.b[row];
        res[N + row] = jb[row] - s.omega * s.a[row];
        for c in 0..N {
            jac[(row, c)] = j[(row, c)];
            jac[(N + row, N + c)] = j[(row, c)];
        }
        jac[(row, N + row)] = s.omega;
        jac[(N + row, row)] = -s.omega;
        jac[(row, 2 * N)] = s.b[row];
        jac[(N + row, 2 * N)] = -s.a[row];
        jac[(row, 2 * N + 1)] = jva[row];
        jac[(N + row, 2 * N + 1)] = jvb[row];
        jac[(row, 2 * N + 2)] = jpa[row];
        jac[(N + row, 2 * N + 2)] = jpb[row];
        jac[(2 * N, row)] = r.a[row];
        jac[(2 * N, N + row)] = r.b[row];
        jac[(2 * N + 1, row)] = -r.b[row];
        jac[(2 * N + 1, N + row)] = r.a[row];
    }
    res[2 * N] = r.a.dot(&s.a) + r.b.dot(&s.b) - 1.0;
    res[2 * N + 1] = r.a.dot(&s.b) - r.b.dot(&s.a);
    if let Some((c, (sv, sp))) = last {
        let k = 2 * N + 2;
        match c {
            Constraint::Arclength { tangent, at } => {
                jac[(k, 2 * N + 1)] = tangent.0 / sv;
                jac[(k, 2 * N + 2)] = tangent.1 / sp;
                res[k] = tangent.0 * (s.v - at.0) / sv + tangent.1 * (s.p - at.1) / sp;
            }
            Constraint::Parameter(p) => {
                jac[(k, 2 * N + 2)] = 1.0;
                res[k] = s.p - p;
            }
            Constraint::Speed(v) => {
                jac[(k, 2 * N + 1)] = 1.0;
                res[k] = s.v - v;
            }
        }
    }
    (jac, res)
}

/// Newton from `guess` with reference `r` under `constraint`; $∂J/∂P$ = `jp` throughout.
/// Returns the converged state and the iterations used.
pub fn correct<const N: usize, F: HopfFamily<N>>(
    family: &F,
    guess: &State<N>,
    r: &State<N>,
    constraint: Constraint,
    jp: &SMatrix<f64, N, N>,
    params: &HopfParams,
) -> Result<(State<N>, usize), CurveError> {
    let scales = params.scales();
    let mut s = guess.clone();
    for it in 1..=NEWTON_ITERATIONS {
        if !(s.v > 0.0 || params.speed_range.0 <= 0.0) || !s.omega.is_finite() {
            break;
        }
        let j = family.jacobian(s.v, s.p)?;
        let jv = family.jacobian_v(s.v, s.p)?;
        let (jac, res) = assemble(&j, &jv, jp, &s, r, Some((constraint, scales)));
        let Some(step) = jac.lu().solve(&res) else {
            break;
        };
        if !step.iter().all(|x| x.is_finite()) {
            break;
        }
        let mut u = s.pack();
        u -= &step;
        let next = State::unpack(&u);
        let size = (0..2 * N)
            .map(|k| step[k].abs())
            .fold(0.0, f64::max)
            .max(step[2 * N].abs() / s.omega.abs().max(1e-12))
            .max(step[2 * N + 1].abs() / scales.0)
            .max(step[2 * N + 2].abs() / scales.1);
        s = next;
        if size <= params.newton_tol {
            return Ok((s, it));
        }
    }
    Err(CurveError::Corrector {
        speed_m_s: s.v,
        parameter: family.value(s.p),
    })
}

/// The unit tangent at `s` (scaled so that $\hat t_V^2 + \hat t_P^2 = 1$) oriented along the
/// scaled direction `previous`; `None` if the bordered system is singular.
pub fn tangent<const N: usize, F: HopfFamily<N>>(
    family: &F,
    s: &State<N>,
    jp: &SMatrix<f64, N, N>,
    previous: (f64, f64),
    params: &HopfParams,
) -> Result<Option<DVector<f64>>, CurveError> {
    let (sv, sp) = params.scales();
    let j = family.jacobian(s.v, s.p)?;
    let jv = family.jacobian_v(s.v, s.p)?;
    let (mut jac, _) = assemble(&j, &jv, jp, s, s, None);
    // border with the previous direction: its component along the new tangent is 1
    jac = jac.insert_row(2 * N + 2, 0.0);
    jac[(2 * N + 2, 2 * N + 1)] = previous.0 / sv;
    jac[(2 * N + 2, 2 * N + 2)] = previous.1 / sp;
    let mut rhs = DVector::<f64>::zeros(2 * N + 3);
    rhs[2 * N + 2] = 1.0;
    let Some(mut t) = jac.lu().solve(&rhs) else {
        return Ok(None);
    };
    let n = ((t[2 * N + 1] / sv).powi(2) + (t[2 * N + 2] / sp).powi(2)).sqrt();
    if !(n > 0.0 && n.is_finite()) {
        return Ok(None);
    }
    t /= n;
    Ok(Some(t))
}

/// The scaled $(V, P)$ part of a tangent.
pub fn scaled(t: &DVector<f64>, params: &HopfParams) -> (f64, f64) {
    let (sv, sp) = params.scales();
    let k = t.len() - 2;
    (t[k] / sv, t[k + 1] / sp)
}

/// `s` moved by `ds` along `t` (unscaled components).
pub fn advance<const N: usize>(s: &State<N>, t: &DVector<f64>, ds: f64) -> State<N> {
    let mut u = s.pack();
    u.axpy(ds, t, 1.0);
    State::unpack(&u)
}
