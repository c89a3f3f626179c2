//! The first Lyapunov coefficient $l_1$ at a Hopf point of the centred motion (docs/model.md §12): it
//! decides the Hopf point's type, so that sub- or supercriticality is computed, not read off
//! the direction in which a cycle branch happens to leave.
//!
//! **Formula** (Kuznetsov, *Elements of Applied Bifurcation Theory*, 3rd ed., §3.5 eq. (3.20)
//! and its $n$-dimensional form in §5.4): with $Jq = iωq$, $J^{\mathsf T}p = −iωp$,
//! $\langle p, q\rangle = \bar p^{\mathsf T} q = 1$, and $B$, $C$ the second and third
//! derivatives of $f$ at the equilibrium,
//! $$l_1 = \frac{1}{2ω}\,\mathrm{Re}\Big[\langle p, C(q,q,\bar q)\rangle −
//!   2\langle p, B(q, J^{-1}B(q,\bar q))\rangle +
//!   \langle p, B(\bar q, (2iωI − J)^{-1}B(q,q))\rangle\Big].$$
//! In the coordinate $z$ of $x = zq + \bar z\bar q + O(|z|^2)$ the normal form is
//! $\dot z = (σ + iω)z + c_1 z|z|^2$, $\mathrm{Re}\,c_1 = ω l_1$, so $r = |z|$ obeys
//! $\dot r = r(σ + ω l_1 r^2)$: $l_1 < 0$ supercritical, $l_1 > 0$ subcritical.
//!
//! **Normalisation and unit.** $l_1$ scales with $|q|^2$, so the scale of $q$ must be stated.
//! Here $q$ is scaled so that the *reference coordinate* (the leading wheelset's lateral
//! displacement $y$ for every vehicle, state 0) is $x_{ref} = \mathrm{Re}\,z$: its amplitude
//! is $r$. Then $l_1$ is in $1/\text{(unit of that coordinate)}^2$, **1/m²** for the railway
//! models, and near the Hopf speed $V_H$ the cycles' lateral amplitude $A$ of the leading
//! wheelset is, to leading order,
//! $$A^2 ≈ −\frac{σ'(V_H)\,(V − V_H)}{ω\, l_1},\qquad σ' = \mathrm{Re}\,\frac{dλ}{dV}
//!   = \mathrm{Re}\,\langle p, J_V q\rangle$$
//! ([`Lyapunov::amplitude_squared`]): an independent check against the continuation's first
//! cycles (`tests/curve.rs`).
//!
//! **Derivatives.** The model's dual numbers are first order, but its Jacobian is exact, so
//! $B$ and $C$ come from differences of $J$ along real directions $d$:
//! $B(u, d) = DJ[d]\,u ≈ (J(hd) − J(−hd))u/2h$ and $C(u, d, d) = D^2J[d,d]\,u ≈
//! (J(hd) − 2J(0) + J(−hd))u/h^2$, both with truncation error $O(h^2)$; complex arguments by
//! linearity and polarisation ($q = a + ib$):
//! $D^2J[q,q] = D^2J[a,a] − D^2J[b,b] + \tfrac{i}{2}(D^2J[a{+}b,a{+}b] − D^2J[a{−}b,a{−}b])$,
//! $C(q,q,\bar q) = D^2J[q,q]\,\bar q$, and every $B$ term uses only $DJ[a]$ and $DJ[b]$
//! ($B(q, w) = DJ[q]\,w$ by symmetry). That is 8 Jacobians a step. Because $l_1(h) = l_1 +
//! c_2h^2 + c_4h^4 + …$, the steps $h_k = h_0/2^k$ are combined in a Richardson tableau
//! (Ridders' method): the estimate with the smallest error estimate is returned with that
//! estimate ([`Lyapunov::error`]), so a result whose truncation and rounding errors cannot be
//! balanced says so instead of being silently wrong. The steps are in units of the reference
//! coordinate (m): $h_0$ = 1 mm by default.
//!
//! **Non-smooth models.** On tangent track every layout is odd, $f(−x) = −f(x)$, so $B = 0$
//! and $J$ is even: the symmetric differences see $D^2J$ as the average of its one-sided limits
//! wherever those differ. The equilibrium $y = 0$ is a node of the contact table; a C¹
//! (cubic Hermite) table has a curvature jump there of $O(h_t^3)$ for node spacing $h_t$,
//! which enters $D^2J$ as a term growing like $1/h$: the tableau then stops improving where
//! that term meets the truncation error, and the error estimate shows it. A C² table has no
//! curvature jump, and the odd symmetry makes the one-sided third derivatives equal. The Shen
//! law without spin creep is not twice differentiable at zero creep force (an $|F|F$ term):
//! $l_1$ does not exist there, and the estimate does not converge.

use nalgebra::{Complex, DMatrix, DVector, SMatrix, SVector};

use super::spectrum::spectrum_at;
use crate::system::ode::VectorField;

type C64 = Complex<f64>;

/// Options of [`first_lyapunov`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LyapunovOptions {
    /// state whose amplitude normalises $l_1$ (module docs); default 0, the leading
    /// wheelset's lateral displacement
    pub reference: usize,
    /// first difference step $h_0$, in units of the reference coordinate (m for the railway
    /// models); default 1e-3 (1 mm, inside every contact table and flange clearance)
    pub initial_step: f64,
    /// the most halvings of the step in the Richardson tableau; default 12 (down to 0.24 µm
    /// from 1 mm: far below where rounding takes over on every shipped study)
    pub halvings: usize,
}

impl Default for LyapunovOptions {
    fn default() -> Self {
        Self {
            reference: 0,
            initial_step: 1e-3,
            halvings: 12,
        }
    }
}

impl LyapunovOptions {
    /// The rules: a positive finite step and 1 to 30 halvings.
    pub fn validate(&self) -> Result<(), LyapunovError> {
        if !(self.initial_step.is_finite() && self.initial_step > 0.0) {
            return Err(LyapunovError::Options(format!(
                "initial_step = {}: must be positive and finite",
                self.initial_step
            )));
        }
        if !(1..=30).contains(&self.halvings) {
            return Err(LyapunovError::Options(format!(
                "halvings = {}: must lie in [1, 30]",
                self.halvings
            )));
        }
        Ok(())
    }
}

/// The type of a Hopf point, decided by the sign of $l_1$.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum HopfKind {
    /// $l_1 < 0$: stable small cycles on the unstable side of the equilibrium
    Supercritical,
    /// $l_1 > 0$: unstable small cycles on the stable side (a fold of cycles lies below)
    Subcritical,
    /// $|l_1|$ is within three times its error estimate: the sign is not decided (a point
    /// near a generalised Hopf, Bautin, point)
    Undecided,
}

impl HopfKind {
    /// `"supercritical"`, `"subcritical"` or `"undecided"`.
    pub fn name(self) -> &'static str {
        match self {
            HopfKind::Supercritical => "supercritical",
            HopfKind::Subcritical => "subcritical",
            HopfKind::Undecided => "undecided",
        }
    }
}

/// The first Lyapunov coefficient at a Hopf point, with what it was computed from.
#[derive(Clone, Debug, PartialEq)]
pub struct Lyapunov {
    /// $l_1$ (1/unit² of the reference coordinate: 1/m² for the railway models), normalised so
    /// that the reference coordinate's amplitude is $|z|$ (module docs)
    pub l1: f64,
    /// estimate of the absolute error of `l1`, from the Richardson tableau
    pub error: f64,
    /// the difference step of the returned estimate (reference-coordinate units)
    pub step: f64,
    /// angular frequency ω of the critical pair (rad/s)
    pub omega: f64,
    /// the real part of the critical eigenvalue at the point (1/s): how exactly it is a
    /// Hopf point
    pub sigma: f64,
    /// right eigenvector $q$ ($Jq = iωq$), scaled so that $q_{ref} = 1/2$
    pub q: Vec<C64>,
    /// left eigenvector $p$ ($J^{\mathsf T}p = −iωp$), with $\langle p, q\rangle = 1$
    pub p: Vec<C64>,
}

impl Lyapunov {
    /// The type from the sign of `l1` against its error estimate.
    pub fn kind(&self) -> HopfKind {
        if self.l1.abs() <= 3.0 * self.error || !self.l1.is_finite() {
            HopfKind::Undecided
        } else if self.l1 < 0.0 {
            HopfKind::Supercritical
        } else {
            HopfKind::Subcritical
        }
    }

    /// $\mathrm{Re}\langle p, M q\rangle$: the rate of change of the critical eigenvalue's
    /// real part when $J$ changes by $M$ per unit of a parameter (for $M = ∂J/∂V$: σ' in 1/m).
    pub fn eigenvalue_rate<const N: usize>(&self, m: &SMatrix<f64, N, N>) -> f64 {
        let mq: Vec<C64> = (0..N)
            .map(|r| (0..N).map(|c| self.q[c] * m[(r, c)]).sum())
            .collect();
        dot(&self.p, &mq).re
    }

    /// The leading-order squared amplitude of the reference coordinate on the cycles born at
    /// this point, at a parameter distance `dv` from it, when the critical real part changes
    /// at `rate` (σ', from [`Self::eigenvalue_rate`]): $−σ' Δ/(ω l_1)$; negative on the side
    /// without cycles.
    pub fn amplitude_squared(&self, rate: f64, dv: f64) -> f64 {
        -rate * dv / (self.omega * self.l1)
    }
}

/// Why $l_1$ could not be computed.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum LyapunovError {
    /// an option broke its rule
    #[error("first Lyapunov coefficient: {0}")]
    Options(String),
    /// the eigen-decomposition failed or gave no complex pair near iω
    #[error("first Lyapunov coefficient: no complex eigenvalue pair near {omega} rad/s at the equilibrium (eigen-decomposition of J)")]
    NoPair { omega: f64 },
    /// the reference coordinate does not move in the critical mode
    #[error("first Lyapunov coefficient: the reference state {reference} does not move in the critical mode (|q| = {modulus:e})")]
    Reference { reference: usize, modulus: f64 },
    /// $J$ or $2iωI − J$ is singular (a zero eigenvalue: zero-Hopf, or a resonance)
    #[error("first Lyapunov coefficient: {0} is singular at the Hopf point")]
    Singular(&'static str),
    /// a Jacobian was not finite at a difference step
    #[error("first Lyapunov coefficient: the Jacobian is not finite at step {step:e}")]
    NotFinite { step: f64 },
}

/// $\bar u^{\mathsf T} v$.
fn dot(u: &[C64], v: &[C64]) -> C64 {
    u.iter().zip(v).map(|(a, b)| a.conj() * b).sum()
}

/// $M v$ for a real matrix and a complex vector.
fn apply<const N: usize>(m: &SMatrix<f64, N, N>, v: &[C64]) -> Vec<C64> {
    (0..N)
        .map(|r| (0..N).map(|c| v[c] * m[(r, c)]).sum())
        .collect()
}

/// The critical eigenvectors at `speed`: $q$ with $q_{ref} = 1/2$, $p$ with $⟨p, q⟩ = 1$,
/// the eigenvalue $σ + iω$ nearest $i·$`omega`.
fn eigenvectors<const N: usize>(
    j: &SMatrix<f64, N, N>,
    speed: f64,
    omega: f64,
    reference: usize,
) -> Result<(Vec<C64>, Vec<C64>, C64), LyapunovError> {
    let near = |sp: super::Spectrum, target: f64| {
        sp.pairs.into_iter().filter(|p| p.im > 0.0).min_by(|a, b| {
            a.re.hypot(a.im - target)
                .total_cmp(&b.re.hypot(b.im - target))
        })
    };
    let right = spectrum_at(j, speed)
        .and_then(|s| near(s, omega))
        .ok_or(LyapunovError::NoPair { omega })?;
    let lambda = C64::new(right.re, right.im);
    // p̄ is the eigenvector of Jᵀ for +iω (Jᵀp = −iωp conjugated)
    let left = spectrum_at(&j.transpose(), speed)
        .and_then(|s| near(s, right.im))
        .ok_or(LyapunovError::NoPair { omega })?;
    let mut q: Vec<C64> = right.vector.iter().map(|z| C64::new(z.0, z.1)).collect();
    let qr = q.get(reference).copied().unwrap_or_default();
    let largest = q.iter().map(|z| z.norm()).fold(0.0, f64::max);
    if qr.norm().is_nan() || qr.norm() <= 1e-12 * largest {
        return Err(LyapunovError::Reference {
            reference,
            modulus: qr.norm(),
        });
    }
    let s = C64::new(0.5, 0.0) / qr;
    q.iter_mut().for_each(|z| *z *= s);
    // w = p̄ up to scale: normalise wᵀq = ⟨p, q⟩ = 1, then p = w̄
    let w: Vec<C64> = left.vector.iter().map(|z| C64::new(z.0, z.1)).collect();
    let wq: C64 = w.iter().zip(&q).map(|(a, b)| a * b).sum();
    if wq.norm().is_nan() || wq.norm() <= 0.0 {
        return Err(LyapunovError::NoPair { omega });
    }
    let p: Vec<C64> = w.iter().map(|z| (z / wq).conj()).collect();
    Ok((q, p, lambda))
}

/// $l_1$ of `field` at its equilibrium $x = 0$ at parameter `speed`, where $J$ has a complex
/// pair near $\pm i$`omega` on the imaginary axis (a located Hopf point).
pub fn first_lyapunov<const N: usize, F: VectorField<N>>(
    field: &F,
    speed: f64,
    omega: f64,
    opts: &LyapunovOptions,
) -> Result<Lyapunov, LyapunovError> {
    let at = Point::new(field, speed, omega, opts)?;
    let (l1, error, step) = richardson(|h| at.value(h), opts.initial_step, opts.halvings)?;
    Ok(Lyapunov {
        l1,
        error,
        step,
        omega: at.lambda.im,
        sigma: at.lambda.re,
        q: at.q,
        p: at.p,
    })
}

/// Everything at the Hopf point that does not depend on the difference step.
struct Point<'f, const N: usize, F> {
    field: &'f F,
    speed: f64,
    j0: SMatrix<f64, N, N>,
    lu: nalgebra::LU<f64, nalgebra::Dyn, nalgebra::Dyn>,
    two_iw: nalgebra::LU<C64, nalgebra::Dyn, nalgebra::Dyn>,
    q: Vec<C64>,
    p: Vec<C64>,
    lambda: C64,
}

impl<'f, const N: usize, F: VectorField<N>> Point<'f, N, F> {
    fn new(
        field: &'f F,
        speed: f64,
        omega: f64,
        opts: &LyapunovOptions,
    ) -> Result<Self, LyapunovError> {
        opts.validate()?;
        if opts.reference >= N {
            return Err(LyapunovError::Options(format!(
                "reference = {}: the model has {N} states",
                opts.reference
            )));
        }
        let j0 = field.jacobian(&SVector::zeros(), speed);
        if !j0.iter().all(|v| v.is_finite()) {
            return Err(LyapunovError::NotFinite { step: 0.0 });
        }
        let (q, p, lambda) = eigenvectors(&j0, speed, omega, opts.reference)?;
        let lu = DMatrix::<f64>::from_fn(N, N, |r, c| j0[(r, c)]).lu();
        if !lu.is_invertible() {
            return Err(LyapunovError::Singular("J"));
        }
        let two_iw = DMatrix::<C64>::from_fn(N, N, |r, c| {
            let d = if r == c {
                C64::new(0.0, 2.0 * lambda.im)
            } else {
                C64::new(0.0, 0.0)
            };
            d - C64::new(j0[(r, c)], 0.0)
        })
        .lu();
        if !two_iw.is_invertible() {
            return Err(LyapunovError::Singular("2iωI − J"));
        }
        Ok(Self {
            field,
            speed,
            j0,
            lu,
            two_iw,
            q,
            p,
            lambda,
        })
    }

    /// $DJ[d]$ and $D^2J[d,d]$ by central differences with step `h`.
    fn differences(
        &self,
        d: &SVector<f64, N>,
        h: f64,
    ) -> Result<(SMatrix<f64, N, N>, SMatrix<f64, N, N>), LyapunovError> {
        let plus = self.field.jacobian(&(d * h), self.speed);
        let minus = self.field.jacobian(&(d * -h), self.speed);
        if !plus.iter().chain(minus.iter()).all(|v| v.is_finite()) {
            return Err(LyapunovError::NotFinite { step: h });
        }
        Ok((
            (plus - minus) / (2.0 * h),
            (plus + minus - self.j0 * 2.0) / (h * h),
        ))
    }

    /// The formula with $B$ and $C$ from differences of step `h`.
    fn value(&self, h: f64) -> Result<f64, LyapunovError> {
        let q = &self.q;
        let a = SVector::<f64, N>::from_fn(|i, _| q[i].re);
        let b = SVector::<f64, N>::from_fn(|i, _| q[i].im);
        let (dja, d2a) = self.differences(&a, h)?;
        let (djb, d2b) = self.differences(&b, h)?;
        let (_, d2p) = self.differences(&(a + b), h)?;
        let (_, d2m) = self.differences(&(a - b), h)?;
        let i = C64::new(0.0, 1.0);
        // C(q, q, q̄) = D²J[q,q] q̄, D²J[q,q] = D²J[a,a] − D²J[b,b] + (i/2)(D²J[a+b] − D²J[a−b])
        let qbar: Vec<C64> = q.iter().map(|z| z.conj()).collect();
        let re_part = apply(&(d2a - d2b), &qbar);
        let im_part = apply(&((d2p - d2m) * 0.5), &qbar);
        let c_qqq: Vec<C64> = re_part
            .iter()
            .zip(&im_part)
            .map(|(r, m)| r + i * m)
            .collect();
        // B(q, w) = DJ[a] w + i DJ[b] w; B(q̄, w) = DJ[a] w − i DJ[b] w
        let b_with = |w: &[C64], sign: f64| -> Vec<C64> {
            let (x, y) = (apply(&dja, w), apply(&djb, w));
            x.iter().zip(&y).map(|(u, v)| u + i * v * sign).collect()
        };
        // B(q, q̄) is real (B is symmetric); its imaginary part is rounding
        let b_qqbar = b_with(&qbar, 1.0);
        let rhs = DVector::<f64>::from_fn(N, |k, _| b_qqbar[k].re);
        let h1 = self.lu.solve(&rhs).ok_or(LyapunovError::Singular("J"))?;
        let h1c: Vec<C64> = h1.iter().map(|v| C64::new(*v, 0.0)).collect();
        let h2 = self
            .two_iw
            .solve(&DVector::from_vec(b_with(q, 1.0)))
            .ok_or(LyapunovError::Singular("2iωI − J"))?;
        let term2 = b_with(&h1c, 1.0);
        let term3 = b_with(h2.as_slice(), -1.0);
        let total = dot(&self.p, &c_qqq) - dot(&self.p, &term2) * 2.0 + dot(&self.p, &term3);
        Ok(total.re / (2.0 * self.lambda.im))
    }
}

/// Ridders' extrapolation of $g(h) = g_0 + c_2h^2 + c_4h^4 + …$ to $h = 0$ over the steps
/// $h_0/2^k$: the tableau entry with the smallest error estimate, that estimate, and its
/// step. Stops once the error has grown to twice the best (rounding has taken over).
fn richardson(
    mut g: impl FnMut(f64) -> Result<f64, LyapunovError>,
    h0: f64,
    halvings: usize,
) -> Result<(f64, f64, f64), LyapunovError> {
    let mut prev: Vec<f64> = vec![g(h0)?];
    let mut best = (prev[0], f64::INFINITY, h0);
    for k in 1..=halvings {
        let h = h0 / f64::powi(2.0, k as i32);
        let mut row = vec![g(h)?];
        let mut factor = 1.0;
        for j in 1..=k {
            factor *= 4.0;
            let t = row[j - 1] + (row[j - 1] - prev[j - 1]) / (factor - 1.0);
            let err = (t - row[j - 1]).abs().max((t - prev[j - 1]).abs());
            if err < best.1 {
                best = (t, err, h);
            }
            row.push(t);
        }
        // the diagonal has stopped improving: higher orders only amplify rounding
        if (row[k] - prev[k - 1]).abs() >= 2.0 * best.1 {
            break;
        }
        prev = row;
    }
    Ok(best)
}

#[cfg(test)]
#[path = "lyapunov_tests.rs"]
mod tests;
