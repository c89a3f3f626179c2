//! Interpolating C² cubic spline with a choice of end conditions, evaluated generically
//! (value, slope, curvature) so that dual numbers carry exact derivatives.
//!
//! Through points $(x_i, v_i)$, $i = 0..n-1$, with strictly increasing $x_i$, the spline is
//! the piecewise cubic Hermite interpolant whose node slopes $s_i$ solve
//!
//! $$h_i s_{i-1} + 2(h_{i-1} + h_i) s_i + h_{i-1} s_{i+1} = 3(h_i Δ_{i-1} + h_{i-1} Δ_i)$$
//!
//! at the interior nodes ($h_i = x_{i+1} − x_i$, $Δ_i = (v_{i+1} − v_i)/h_i$): continuity of
//! the second derivative. The two missing equations are the [`EndCondition`]:
//!
//! * **natural** (zero curvature at both ends, n ≥ 3): $2 s_0 + s_1 = 3 Δ_0$ and
//!   $s_{n-2} + 2 s_{n-1} = 3 Δ_{n-2}$. The system is strictly diagonally dominant and is
//!   solved as it stands. Used for the wheel and rail profile curves.
//! * **not-a-knot** (de Boor: the third derivative is continuous at $x_1$ and $x_{n-2}$,
//!   n ≥ 4): every cubic polynomial is reproduced exactly, which natural ends would not do.
//!   These rows, $h_1 s_0 + (h_0 + h_1) s_1 = r_0$ and its mirror image, are not diagonally
//!   dominant; subtracting each from its neighbouring interior row eliminates $s_0$ and
//!   $s_{n-1}$ and leaves a strictly diagonally dominant system for $s_1 … s_{n-2}$, after
//!   which $s_0$ and $s_{n-1}$ follow from the end rows. Used for tabulated contact geometry.
//!
//! Both are solved by the same Thomas algorithm without pivoting. Each interval then stores
//! its cubic as $S = a + b t + c t^2 + d t^3$, $t = x − x_k$ (so the data and the node slopes
//! are reproduced exactly at the left end of every interval). Beyond the end knots the end
//! cubic is continued; callers check that they stay inside.

use crate::system::scalar::Scalar;

#[cfg(test)]
mod tests;

/// How the two equations missing at the ends of the slope system are closed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EndCondition {
    /// Zero second derivative at the first and last knot (needs at least 3 points).
    Natural,
    /// Third derivative continuous at the second and second-to-last knot; reproduces cubic
    /// polynomials exactly (needs at least 4 points).
    NotAKnot,
}

impl EndCondition {
    /// The fewest points the end condition can close.
    pub fn min_points(self) -> usize {
        match self {
            Self::Natural => 3,
            Self::NotAKnot => 4,
        }
    }
}

impl std::fmt::Display for EndCondition {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Self::Natural => "natural",
            Self::NotAKnot => "not-a-knot",
        })
    }
}

/// A C² cubic spline: knots, data values and the cubic of each interval.
#[derive(Clone, Debug, PartialEq)]
pub struct CubicSpline {
    x: Vec<f64>,
    v: Vec<f64>,
    /// per interval k: `[a, b, c, d]` of `a + b t + c t² + d t³`, `t = x − x_k`
    coef: Vec<[f64; 4]>,
    end: EndCondition,
}

/// Why a spline could not be built (the caller names the file and column).
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum SplineError {
    /// Fewer points than the end condition needs.
    #[error("{points} points; the {end} spline needs at least {}", end.min_points())]
    TooFewPoints { points: usize, end: EndCondition },
    /// The abscissae are not strictly increasing (index of the offending point).
    #[error("x[{index}] = {x:e} does not exceed the previous value {previous:e}")]
    NotIncreasing { index: usize, x: f64, previous: f64 },
    /// A value or abscissa is not finite.
    #[error("point {index} is not finite: ({x:e}, {v:e})")]
    NotFinite { index: usize, x: f64, v: f64 },
}

impl CubicSpline {
    /// The spline through `(x[i], v[i])` (the shorter slice sets the count) with end
    /// condition `end`.
    pub fn new(x: &[f64], v: &[f64], end: EndCondition) -> Result<Self, SplineError> {
        let n = x.len().min(v.len());
        if n < end.min_points() {
            return Err(SplineError::TooFewPoints { points: n, end });
        }
        for i in 0..n {
            if !(x[i].is_finite() && v[i].is_finite()) {
                return Err(SplineError::NotFinite {
                    index: i,
                    x: x[i],
                    v: v[i],
                });
            }
            if i > 0 && x[i] <= x[i - 1] {
                return Err(SplineError::NotIncreasing {
                    index: i,
                    x: x[i],
                    previous: x[i - 1],
                });
            }
        }
        let (x, v) = (x[..n].to_vec(), v[..n].to_vec());
        let s = slopes(&x, &v, end);
        let coef = (0..n - 1)
            .map(|k| {
                let h = x[k + 1] - x[k];
                let d = (v[k + 1] - v[k]) / h;
                let (s0, s1) = (s[k], s[k + 1]);
                [
                    v[k],
                    s0,
                    (3.0 * d - 2.0 * s0 - s1) / h,
                    (s0 + s1 - 2.0 * d) / (h * h),
                ]
            })
            .collect();
        Ok(Self { x, v, coef, end })
    }

    /// The not-a-knot spline through `(x[i], v[i])`.
    pub fn not_a_knot(x: &[f64], v: &[f64]) -> Result<Self, SplineError> {
        Self::new(x, v, EndCondition::NotAKnot)
    }

    /// The natural spline through `(x[i], v[i])`.
    pub fn natural(x: &[f64], v: &[f64]) -> Result<Self, SplineError> {
        Self::new(x, v, EndCondition::Natural)
    }

    /// The end condition the spline was built with.
    pub fn end_condition(&self) -> EndCondition {
        self.end
    }

    /// The first and last knot.
    pub fn range(&self) -> (f64, f64) {
        (self.x[0], self.x[self.x.len() - 1])
    }

    /// The knots and the data values.
    pub fn knots(&self) -> (&[f64], &[f64]) {
        (&self.x, &self.v)
    }

    /// Interval index containing `x` (clamped to the end intervals; NaN gives the first).
    #[inline]
    fn interval(&self, x: f64) -> usize {
        let k = self.x.partition_point(|&xi| xi <= x);
        k.saturating_sub(1).min(self.coef.len() - 1)
    }

    /// Interval index, walking from a hint (fast for monotone sweeps).
    #[inline]
    fn interval_from(&self, x: f64, hint: &mut usize) -> usize {
        let last = self.coef.len() - 1;
        let mut i = (*hint).min(last);
        while i > 0 && x < self.x[i] {
            i -= 1;
        }
        while i < last && x >= self.x[i + 1] {
            i += 1;
        }
        *hint = i;
        i
    }

    /// Value, first and second derivative at `x`.
    #[inline]
    pub fn eval<T: Scalar>(&self, x: T) -> (T, T, T) {
        self.eval_in(self.interval(x.re()), x)
    }

    /// Value at `x`, finding the interval by walking from `hint` (updated).
    #[inline]
    pub fn value_hint(&self, x: f64, hint: &mut usize) -> f64 {
        self.eval_in(self.interval_from(x, hint), x).0
    }

    /// Value, first and second derivative of interval `k`'s cubic at `x`.
    #[inline]
    fn eval_in<T: Scalar>(&self, k: usize, x: T) -> (T, T, T) {
        let [a, b, c, d] = self.coef[k];
        let t = x - self.x[k];
        let v = ((t * d + c) * t + b) * t + a;
        let d1 = (t * (3.0 * d) + 2.0 * c) * t + b;
        let d2 = t * (6.0 * d) + 2.0 * c;
        (v, d1, d2)
    }
}

/// Node slopes (see the module docs); `x` strictly increasing, `x.len() == v.len()` at least
/// `end.min_points()`.
fn slopes(x: &[f64], v: &[f64], end: EndCondition) -> Vec<f64> {
    let n = x.len();
    let h: Vec<f64> = x.windows(2).map(|w| w[1] - w[0]).collect();
    let d: Vec<f64> = (0..n - 1).map(|i| (v[i + 1] - v[i]) / h[i]).collect();
    // All n rows: lower a, diagonal b, upper c, right-hand side r.
    let mut a = vec![0.0; n];
    let mut b = vec![0.0; n];
    let mut c = vec![0.0; n];
    let mut r = vec![0.0; n];
    for i in 1..n - 1 {
        a[i] = h[i];
        b[i] = 2.0 * (h[i - 1] + h[i]);
        c[i] = h[i - 1];
        r[i] = 3.0 * (h[i] * d[i - 1] + h[i - 1] * d[i]);
    }
    match end {
        EndCondition::Natural => {
            (b[0], c[0], r[0]) = (2.0, 1.0, 3.0 * d[0]);
            (a[n - 1], b[n - 1], r[n - 1]) = (1.0, 2.0, 3.0 * d[n - 2]);
            thomas(&a, &b, &c, &r)
        }
        EndCondition::NotAKnot => {
            // not-a-knot row 0: h1 s0 + e0 s1 = r0; row n−1: e1 s_{n−2} + h_{n−3} s_{n−1} = rn
            let (e0, e1) = (h[0] + h[1], h[n - 3] + h[n - 2]);
            let r0 = ((h[0] + 2.0 * e0) * h[1] * d[0] + h[0] * h[0] * d[1]) / e0;
            let rn =
                (h[n - 2] * h[n - 2] * d[n - 3] + (2.0 * e1 + h[n - 2]) * h[n - 3] * d[n - 2]) / e1;
            // Row 1 minus row 0 removes s0; row n−2 minus row n−1 removes s_{n−1}.
            let m = n - 1;
            b[1] -= e0;
            r[1] -= r0;
            a[1] = 0.0;
            b[m - 1] -= e1;
            r[m - 1] -= rn;
            c[m - 1] = 0.0;
            let inner = thomas(&a[1..m], &b[1..m], &c[1..m], &r[1..m]);
            let mut s = vec![0.0; n];
            s[1..m].copy_from_slice(&inner);
            s[0] = (r0 - e0 * s[1]) / h[1];
            s[m] = (rn - e1 * s[m - 1]) / h[n - 3];
            s
        }
    }
}

/// Thomas algorithm for a diagonally dominant tridiagonal system (a: lower, b: diagonal,
/// c: upper, r: right-hand side; `a[0]` and the last `c` are not used).
fn thomas(a: &[f64], b: &[f64], c: &[f64], r: &[f64]) -> Vec<f64> {
    let m = b.len();
    let mut cp = vec![0.0; m];
    let mut rp = vec![0.0; m];
    cp[0] = c[0] / b[0];
    rp[0] = r[0] / b[0];
    for j in 1..m {
        let den = b[j] - a[j] * cp[j - 1];
        cp[j] = c[j] / den;
        rp[j] = (r[j] - a[j] * rp[j - 1]) / den;
    }
    let mut s = vec![0.0; m];
    s[m - 1] = rp[m - 1];
    for j in (0..m - 1).rev() {
        s[j] = rp[j] - cp[j] * s[j + 1];
    }
    s
}
