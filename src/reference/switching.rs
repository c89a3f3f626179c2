//! Two problems whose symmetry-breaking and period-doubling bifurcations of cycles, and the
//! branches that leave them, are known in closed form: the reference for branch switching
//! ([`crate::continuation::switch`]), independent of any wheelset.

use nalgebra::{SMatrix, SVector};

use crate::system::ode::VectorField;
use crate::system::scalar::{Dual, Scalar};

/// An odd field in $(x, y, z)$ with symmetric cycles that break their symmetry twice:
/// $$\dot x = (μ − r^2)x − ωy,\quad \dot y = ωx + (μ − r^2)y,\quad \dot z = h(r^2)\,z − z^3,$$
/// $r^2 = x^2 + y^2$, $h(s) = k\,(s − c_1)(c_2 − s)$, parameter μ. The Hopf point is μ = 0; the
/// symmetric cycles are $r^2 = μ$, $z = 0$, period $T = 2π/ω$, and the half-period map's
/// multiplier along z is $ν = −e^{h(μ)T/2}$: it passes −1 at $μ = c_1$ and $μ = c_2$ (symmetry
/// breaking). Between them the asymmetric cycles $r^2 = μ$, $z = ±\sqrt{h(μ)}$ exist (the mirror
/// pair), with multipliers $1$, $e^{−2μT}$ and $e^{−2h(μ)T}$: stable, while the symmetric
/// cycles there are unstable.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SymmetryBreakingForm {
    /// angular frequency ω (rad/s)
    pub omega: f64,
    /// scale k of h
    pub k: f64,
    /// the lower symmetry-breaking point c₁
    pub c1: f64,
    /// the upper symmetry-breaking point c₂
    pub c2: f64,
}

impl SymmetryBreakingForm {
    /// $h(s)$.
    pub fn h(&self, s: f64) -> f64 {
        self.k * (s - self.c1) * (self.c2 - s)
    }

    fn field<T: Scalar>(&self, x: &[T; 3], mu: f64) -> [T; 3] {
        let [a, b, z] = *x;
        let r2 = a * a + b * b;
        let g = -r2 + mu;
        let h = (r2 - self.c1) * (-r2 + self.c2) * self.k;
        [
            g * a - b * self.omega,
            a * self.omega + g * b,
            h * z - z * z * z,
        ]
    }
}

/// A field in $(x, y, u, v)$ whose one cycle doubles its period twice:
/// $\dot ζ = (1 + iω)ζ − |ζ|^2 ζ$ for $ζ = x + iy$ (the unit circle, period $T = 2π/ω$), and for
/// $w = u + iv$
/// $$\dot w = \tfrac{iω}{2} w + (h(σ) − |P w|^2)\,P w − Q w,\qquad P w = \tfrac12(w + \bar w\,ζ/|ζ|),\; Qw = w − Pw,$$
/// $h(σ) = σ(c − σ)$, parameter σ. $P$ projects on the axis $e^{iθ/2}$ that turns half a turn per
/// period ($ζ = e^{iθ}$), so on the cycle $w = 0$ the multipliers along $w$ are $−e^{h T}$ and
/// $−e^{−T}$: period doubling at $σ = 0$ and $σ = c$. Between them the cycles of period $2T$,
/// $w = \sqrt{h(σ)}\,e^{iθ/2}$, exist, with multipliers $1$, $e^{−4T}$ (radial), $e^{−4h T}$ and
/// $e^{−2T}$. The field is not odd.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PeriodDoublingForm {
    /// angular frequency ω (rad/s) of the base cycle
    pub omega: f64,
    /// the second period-doubling point c
    pub c: f64,
}

impl PeriodDoublingForm {
    /// $h(σ)$.
    pub fn h(&self, sigma: f64) -> f64 {
        sigma * (self.c - sigma)
    }

    fn field<T: Scalar>(&self, x: &[T; 4], sigma: f64) -> [T; 4] {
        let [a, b, u, v] = *x;
        let r2 = a * a + b * b;
        let g = -r2 + 1.0;
        let r = r2.sqrt();
        let (ca, cb) = (a / r, b / r);
        let p_re = (u + u * ca + v * cb) * 0.5;
        let p_im = (v + u * cb - v * ca) * 0.5;
        let (q_re, q_im) = (u - p_re, v - p_im);
        let s = -(p_re * p_re + p_im * p_im) + self.h(sigma);
        [
            g * a - b * self.omega,
            a * self.omega + g * b,
            -(v * (0.5 * self.omega)) + s * p_re - q_re,
            u * (0.5 * self.omega) + s * p_im - q_im,
        ]
    }
}

/// The exact Jacobian of a generic field by forward-mode dual numbers.
fn jacobian<const N: usize>(
    f: impl Fn(&[Dual<N>; N]) -> [Dual<N>; N],
    x: &SVector<f64, N>,
) -> SMatrix<f64, N, N> {
    let xd: [Dual<N>; N] = std::array::from_fn(|k| Dual::var(x[k], k));
    let r = f(&xd);
    SMatrix::from_fn(|i, j| r[i].eps[j])
}

impl VectorField<3> for SymmetryBreakingForm {
    fn rhs(&self, x: &SVector<f64, 3>, mu: f64) -> SVector<f64, 3> {
        SVector::from(self.field(&[x[0], x[1], x[2]], mu))
    }
    fn jacobian(&self, x: &SVector<f64, 3>, mu: f64) -> SMatrix<f64, 3, 3> {
        jacobian(|d| self.field(d, mu), x)
    }
}

impl VectorField<4> for PeriodDoublingForm {
    fn rhs(&self, x: &SVector<f64, 4>, sigma: f64) -> SVector<f64, 4> {
        SVector::from(self.field(&[x[0], x[1], x[2], x[3]], sigma))
    }
    fn jacobian(&self, x: &SVector<f64, 4>, sigma: f64) -> SMatrix<f64, 4, 4> {
        jacobian(|d| self.field(d, sigma), x)
    }
}
