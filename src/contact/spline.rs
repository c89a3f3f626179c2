//! Interpolating cubic spline with the not-a-knot end condition (C², exact for cubics).
//!
//! Through points $(x_i, v_i)$, $i = 0..n-1$, with strictly increasing $x_i$ (n ≥ 4), the
//! spline is the piecewise cubic Hermite interpolant whose node slopes $s_i$ solve
//!
//! $$h_i s_{i-1} + 2(h_{i-1} + h_i) s_i + h_{i-1} s_{i+1} = 3(h_i Δ_{i-1} + h_{i-1} Δ_i)$$
//!
//! at the interior nodes ($h_i = x_{i+1} − x_i$, $Δ_i = (v_{i+1} − v_i)/h_i$): continuity of
//! the second derivative. The two missing equations are de Boor's *not-a-knot* conditions
//! (the third derivative is continuous at $x_1$ and $x_{n-2}$), under which every cubic
//! polynomial is reproduced exactly; natural end conditions (zero curvature) would not.
//!
//! The not-a-knot rows are not diagonally dominant. Subtracting each from its neighbouring
//! interior row eliminates $s_0$ and $s_{n-1}$ and leaves a strictly diagonally dominant
//! tridiagonal system for $s_1 … s_{n-2}$, solved by the Thomas algorithm without pivoting;
//! $s_0$ and $s_{n-1}$ then follow from the not-a-knot rows.

/// A cubic spline: knots, values and exact slopes at the knots (Hermite form).
#[derive(Clone, Debug, PartialEq)]
pub struct CubicSpline {
    x: Vec<f64>,
    v: Vec<f64>,
    s: Vec<f64>,
}

/// Why a spline could not be built (the caller names the file and column).
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum SplineError {
    /// Fewer than four points.
    #[error("{points} points; the not-a-knot spline needs at least 4")]
    TooFewPoints { points: usize },
    /// The abscissae are not strictly increasing (index of the offending point).
    #[error("x[{index}] = {x:e} does not exceed the previous value {previous:e}")]
    NotIncreasing { index: usize, x: f64, previous: f64 },
    /// A value or abscissa is not finite.
    #[error("point {index} is not finite: ({x:e}, {v:e})")]
    NotFinite { index: usize, x: f64, v: f64 },
}

impl CubicSpline {
    /// The not-a-knot spline through `(x[i], v[i])`.
    pub fn new(x: &[f64], v: &[f64]) -> Result<Self, SplineError> {
        let n = x.len().min(v.len());
        if n < 4 {
            return Err(SplineError::TooFewPoints { points: n });
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
        let s = not_a_knot_slopes(&x, &v);
        Ok(Self { x, v, s })
    }

    /// The first and last knot.
    pub fn range(&self) -> (f64, f64) {
        (self.x[0], self.x[self.x.len() - 1])
    }

    /// The knots and the data values.
    pub fn knots(&self) -> (&[f64], &[f64]) {
        (&self.x, &self.v)
    }

    /// Value and first derivative at `t`; beyond the knots the end cubic is continued.
    pub fn eval(&self, t: f64) -> (f64, f64) {
        let n = self.x.len();
        let k = self.x.partition_point(|&xi| xi <= t).clamp(1, n - 1) - 1;
        let h = self.x[k + 1] - self.x[k];
        let u = (t - self.x[k]) / h;
        let (u2, u3) = (u * u, u * u * u);
        let (p0, p1) = (self.v[k], self.v[k + 1]);
        let (m0, m1) = (self.s[k] * h, self.s[k + 1] * h);
        let value = (2.0 * u3 - 3.0 * u2 + 1.0) * p0
            + (u3 - 2.0 * u2 + u) * m0
            + (3.0 * u2 - 2.0 * u3) * p1
            + (u3 - u2) * m1;
        let slope = ((6.0 * u2 - 6.0 * u) * (p0 - p1)
            + (3.0 * u2 - 4.0 * u + 1.0) * m0
            + (3.0 * u2 - 2.0 * u) * m1)
            / h;
        (value, slope)
    }
}

/// Node slopes of the not-a-knot spline (see the module docs); `x` strictly increasing,
/// `x.len() == v.len() >= 4`.
fn not_a_knot_slopes(x: &[f64], v: &[f64]) -> Vec<f64> {
    let n = x.len();
    let h: Vec<f64> = x.windows(2).map(|w| w[1] - w[0]).collect();
    let d: Vec<f64> = (0..n - 1).map(|i| (v[i + 1] - v[i]) / h[i]).collect();
    // Full rows: not-a-knot row 0: h1 s0 + (h0+h1) s1 = r0; interior rows as in the docs;
    // not-a-knot row n−1: (h_{n−3}+h_{n−2}) s_{n−2} + h_{n−3} s_{n−1} = r_{n−1}.
    let (e0, e1) = (h[0] + h[1], h[n - 3] + h[n - 2]);
    let r0 = ((h[0] + 2.0 * e0) * h[1] * d[0] + h[0] * h[0] * d[1]) / e0;
    let rn = (h[n - 2] * h[n - 2] * d[n - 3] + (2.0 * e1 + h[n - 2]) * h[n - 3] * d[n - 2]) / e1;
    let interior = |i: usize| 3.0 * (h[i] * d[i - 1] + h[i - 1] * d[i]);
    // Reduced system for s_1 … s_{n−2} (m unknowns): lower a, diagonal b, upper c, rhs r.
    let m = n - 2;
    let mut a = vec![0.0; m];
    let mut b = vec![0.0; m];
    let mut c = vec![0.0; m];
    let mut r = vec![0.0; m];
    for j in 0..m {
        let i = j + 1;
        a[j] = h[i];
        b[j] = 2.0 * (h[i - 1] + h[i]);
        c[j] = h[i - 1];
        r[j] = interior(i);
    }
    // Row 1 minus row 0 removes s0; row n−2 minus row n−1 removes s_{n−1}.
    b[0] -= e0;
    r[0] -= r0;
    a[0] = 0.0;
    b[m - 1] -= e1;
    r[m - 1] -= rn;
    c[m - 1] = 0.0;
    let s_inner = thomas(&a, &b, &c, &r);
    let mut s = vec![0.0; n];
    s[1..n - 1].copy_from_slice(&s_inner);
    s[0] = (r0 - e0 * s[1]) / h[1];
    s[n - 1] = (rn - e1 * s[n - 2]) / h[n - 3];
    s
}

/// Thomas algorithm for a diagonally dominant tridiagonal system (a: lower, b: diagonal,
/// c: upper, r: right-hand side).
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

#[cfg(test)]
mod tests {
    use super::*;

    fn cubic(t: f64) -> (f64, f64) {
        (
            0.3 - 2.0 * t + 5.0 * t * t - 7.0 * t * t * t,
            -2.0 + 10.0 * t - 21.0 * t * t,
        )
    }

    /// Irregular knots, 4 to 9 of them.
    fn knots(n: usize) -> Vec<f64> {
        (0..n)
            .map(|i| -1.0 + 0.3 * i as f64 + 0.05 * ((i * i) % 3) as f64)
            .collect()
    }

    #[test]
    fn reproduces_a_cubic_exactly() {
        for n in 4..10 {
            let x = knots(n);
            let v: Vec<f64> = x.iter().map(|&t| cubic(t).0).collect();
            let sp = CubicSpline::new(&x, &v).expect("valid knots");
            for k in 0..=40 {
                let t = x[0] + (x[n - 1] - x[0]) * k as f64 / 40.0;
                let (val, der) = sp.eval(t);
                let (ev, ed) = cubic(t);
                assert!((val - ev).abs() < 1e-12, "n={n} t={t}: {val} vs {ev}");
                assert!((der - ed).abs() < 1e-11, "n={n} t={t}: {der} vs {ed}");
            }
        }
    }

    #[test]
    fn interpolates_and_is_c2() {
        let x = knots(9);
        let v: Vec<f64> = x.iter().map(|&t| (3.0 * t).sin()).collect();
        let sp = CubicSpline::new(&x, &v).expect("valid knots");
        for (xi, vi) in x.iter().zip(&v) {
            assert!((sp.eval(*xi).0 - vi).abs() < 1e-15);
        }
        // second derivative continuous at interior knots: compare one-sided differences
        let eps = 1e-6;
        for &xi in &x[1..8] {
            let left = (sp.eval(xi - eps).1 - sp.eval(xi - 2.0 * eps).1) / eps;
            let right = (sp.eval(xi + 2.0 * eps).1 - sp.eval(xi + eps).1) / eps;
            assert!((left - right).abs() < 1e-3 * left.abs().max(1.0), "{xi}");
        }
    }

    #[test]
    fn rejects_bad_input() {
        assert_eq!(
            CubicSpline::new(&[0.0, 1.0, 2.0], &[0.0; 3]),
            Err(SplineError::TooFewPoints { points: 3 })
        );
        assert!(matches!(
            CubicSpline::new(&[0.0, 1.0, 1.0, 2.0], &[0.0; 4]),
            Err(SplineError::NotIncreasing { index: 2, .. })
        ));
        assert!(matches!(
            CubicSpline::new(&[0.0, 1.0, 2.0, 3.0], &[0.0, f64::NAN, 0.0, 0.0]),
            Err(SplineError::NotFinite { index: 1, .. })
        ));
    }
}
