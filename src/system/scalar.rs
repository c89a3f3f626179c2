//! A minimal real-number trait and forward-mode dual numbers.
//!
//! Every model function (contact geometry, Hertz patch, creep laws, the equations of motion)
//! is written once, generic over [`Scalar`]. Evaluated on `f64` it gives values; evaluated on
//! [`Dual<N>`] it gives values *and* exact first derivatives with respect to `N` seeded
//! directions. That is how the exact Jacobian ∂f/∂x of docs/model.md §8 is obtained, and how the
//! contact-geometry tables get exact slopes at their nodes (so the interpolant is C¹ with
//! exact nodal derivatives).
//!
//! Written by hand rather than taken from a crate because the model needs two operations a
//! general AD crate does not offer directly: [`Scalar::lift`] (apply a function whose value
//! and slope are already known, e.g. a tabulated interpolant) and [`Scalar::hypot0`] (a norm
//! whose derivative at the origin is taken as zero, which is the correct limit for the
//! Shen–Hedrick–Elkins force `F·ε(|F|)`); and the fixed-size `[f64; N]` layout keeps the
//! 4-direction Jacobian on the stack.

use std::ops::{Add, Div, Mul, Neg, Sub};

/// The arithmetic the model needs. Implemented for `f64` and [`Dual<N>`].
pub trait Scalar:
    Copy
    + std::fmt::Debug
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
    + Add<f64, Output = Self>
    + Sub<f64, Output = Self>
    + Mul<f64, Output = Self>
    + Div<f64, Output = Self>
{
    /// A constant (zero derivative).
    fn cst(v: f64) -> Self;
    /// The value, without derivatives.
    fn re(self) -> f64;
    /// `g(self)` where `g(re) = value` and `g'(re) = slope` are known.
    fn lift(self, value: f64, slope: f64) -> Self;

    fn sqrt(self) -> Self {
        let s = self.re().sqrt();
        self.lift(s, 0.5 / s)
    }
    fn sin(self) -> Self {
        let v = self.re();
        self.lift(v.sin(), v.cos())
    }
    fn cos(self) -> Self {
        let v = self.re();
        self.lift(v.cos(), -v.sin())
    }
    /// `(sin, cos)` with one evaluation of both (the model needs both of each contact angle).
    fn sin_cos(self) -> (Self, Self) {
        let (s, c) = self.re().sin_cos();
        (self.lift(s, c), self.lift(c, -s))
    }
    fn tan(self) -> Self {
        let t = self.re().tan();
        self.lift(t, 1.0 + t * t)
    }
    fn atan(self) -> Self {
        let v = self.re();
        self.lift(v.atan(), 1.0 / (1.0 + v * v))
    }
    fn recip(self) -> Self {
        let v = self.re();
        self.lift(1.0 / v, -1.0 / (v * v))
    }
    /// `sqrt(a² + b²)`, with derivative zero at the origin (the limit of `F·|F|` there).
    fn hypot0(a: Self, b: Self) -> Self;
}

impl Scalar for f64 {
    #[inline]
    fn cst(v: f64) -> Self {
        v
    }
    #[inline]
    fn re(self) -> f64 {
        self
    }
    #[inline]
    fn lift(self, value: f64, _slope: f64) -> Self {
        value
    }
    #[inline]
    fn sqrt(self) -> Self {
        f64::sqrt(self)
    }
    #[inline]
    fn sin(self) -> Self {
        f64::sin(self)
    }
    #[inline]
    fn cos(self) -> Self {
        f64::cos(self)
    }
    #[inline]
    fn tan(self) -> Self {
        f64::tan(self)
    }
    #[inline]
    fn atan(self) -> Self {
        f64::atan(self)
    }
    #[inline]
    fn recip(self) -> Self {
        1.0 / self
    }
    #[inline]
    fn hypot0(a: Self, b: Self) -> Self {
        // not `f64::hypot`: libm's overflow-safe version cost 6 % of a continuation, and the
        // model's forces (below 1e9 N) are far from where a² + b² could overflow
        (a * a + b * b).sqrt()
    }
}

/// A dual number `re + Σ eps[k] ε_k` carrying `N` directional derivatives.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Dual<const N: usize> {
    /// Value.
    pub re: f64,
    /// Derivatives along the `N` seeded directions.
    pub eps: [f64; N],
}

impl<const N: usize> Dual<N> {
    /// The `k`-th independent variable with value `re` (derivative 1 along direction `k`).
    pub fn var(re: f64, k: usize) -> Self {
        let mut eps = [0.0; N];
        eps[k] = 1.0;
        Self { re, eps }
    }
    #[inline]
    fn map(self, value: f64, slope: f64) -> Self {
        let mut eps = self.eps;
        for e in &mut eps {
            *e *= slope;
        }
        Self { re: value, eps }
    }
}

impl<const N: usize> Scalar for Dual<N> {
    #[inline]
    fn cst(v: f64) -> Self {
        Self {
            re: v,
            eps: [0.0; N],
        }
    }
    #[inline]
    fn re(self) -> f64 {
        self.re
    }
    #[inline]
    fn lift(self, value: f64, slope: f64) -> Self {
        self.map(value, slope)
    }
    fn hypot0(a: Self, b: Self) -> Self {
        let h = f64::hypot0(a.re, b.re);
        if h == 0.0 {
            return Self::cst(0.0);
        }
        let mut eps = [0.0; N];
        for (k, e) in eps.iter_mut().enumerate() {
            *e = (a.re * a.eps[k] + b.re * b.eps[k]) / h;
        }
        Self { re: h, eps }
    }
}

impl<const N: usize> Add for Dual<N> {
    type Output = Self;
    #[inline]
    fn add(mut self, o: Self) -> Self {
        self.re += o.re;
        for k in 0..N {
            self.eps[k] += o.eps[k];
        }
        self
    }
}
impl<const N: usize> Sub for Dual<N> {
    type Output = Self;
    #[inline]
    fn sub(mut self, o: Self) -> Self {
        self.re -= o.re;
        for k in 0..N {
            self.eps[k] -= o.eps[k];
        }
        self
    }
}
impl<const N: usize> Mul for Dual<N> {
    type Output = Self;
    #[inline]
    fn mul(self, o: Self) -> Self {
        let mut eps = [0.0; N];
        for (k, e) in eps.iter_mut().enumerate() {
            *e = self.eps[k] * o.re + self.re * o.eps[k];
        }
        Self {
            re: self.re * o.re,
            eps,
        }
    }
}
impl<const N: usize> Div for Dual<N> {
    type Output = Self;
    #[inline]
    fn div(self, o: Self) -> Self {
        let inv = 1.0 / o.re;
        let q = self.re * inv;
        let mut eps = [0.0; N];
        for (k, e) in eps.iter_mut().enumerate() {
            *e = (self.eps[k] - q * o.eps[k]) * inv;
        }
        Self { re: q, eps }
    }
}
impl<const N: usize> Neg for Dual<N> {
    type Output = Self;
    #[inline]
    fn neg(self) -> Self {
        self.map(-self.re, -1.0)
    }
}
impl<const N: usize> Add<f64> for Dual<N> {
    type Output = Self;
    #[inline]
    fn add(mut self, o: f64) -> Self {
        self.re += o;
        self
    }
}
impl<const N: usize> Sub<f64> for Dual<N> {
    type Output = Self;
    #[inline]
    fn sub(mut self, o: f64) -> Self {
        self.re -= o;
        self
    }
}
impl<const N: usize> Mul<f64> for Dual<N> {
    type Output = Self;
    #[inline]
    fn mul(self, o: f64) -> Self {
        self.map(self.re * o, o)
    }
}
impl<const N: usize> Div<f64> for Dual<N> {
    type Output = Self;
    #[inline]
    fn div(self, o: f64) -> Self {
        self.map(self.re / o, 1.0 / o)
    }
}

/// Derivative of a scalar function of one variable, exactly, by a one-direction dual.
pub fn derivative(f: impl Fn(Dual<1>) -> Dual<1>, x: f64) -> (f64, f64) {
    let r = f(Dual::var(x, 0));
    (r.re, r.eps[0])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn chain_rule_matches_closed_form() {
        // g(x) = sin(x)·sqrt(x) / (1 + tan(x)) + atan(x)/x
        let g = |x: Dual<1>| (x.sin() * x.sqrt()) / (x.tan() + 1.0) + x.atan() / x;
        let x = 0.7_f64;
        let (v, d) = derivative(g, x);
        let gf = |x: f64| (x.sin() * x.sqrt()) / (1.0 + x.tan()) + x.atan() / x;
        assert!((v - gf(x)).abs() < 1e-15);
        let h = 1e-5;
        let fd = (gf(x + h) - gf(x - h)) / (2.0 * h);
        assert!((d - fd).abs() < 1e-9, "{d} vs {fd}");
    }

    #[test]
    fn hypot0_has_zero_slope_at_origin() {
        let a = Dual::<2>::var(0.0, 0);
        let b = Dual::<2>::var(0.0, 1);
        let h = Scalar::hypot0(a, b);
        assert_eq!(h.eps, [0.0, 0.0]);
        let a = Dual::<2>::var(3.0, 0);
        let b = Dual::<2>::var(4.0, 1);
        let h = Scalar::hypot0(a, b);
        assert!((h.re - 5.0).abs() < 1e-15);
        assert!((h.eps[0] - 0.6).abs() < 1e-15 && (h.eps[1] - 0.8).abs() < 1e-15);
    }
}
