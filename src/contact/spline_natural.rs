//! Natural C² cubic interpolating spline, evaluated generically (value, slope, curvature) so
//! that dual numbers carry exact derivatives through the rigid contact solve.
//!
//! On knots `x_0 < … < x_{n−1}` the second derivatives `m_i` solve the usual tridiagonal system
//! with `m_0 = m_{n−1} = 0` (natural ends). The spline and its first two derivatives are
//! continuous everywhere; the third derivative is piecewise constant. Beyond the end knots the
//! end cubic is continued (callers check that contacts lie inside the profile).

use crate::system::scalar::Scalar;

/// A natural cubic spline; per interval `S = a + b t + c t² + d t³`, `t = x − x_i`.
#[derive(Clone, Debug, PartialEq)]
pub struct Spline {
    x: Vec<f64>,
    coef: Vec<[f64; 4]>,
}

impl Spline {
    /// Interpolates `(x_i, y_i)`; `x` strictly increasing with at least 3 points (the caller
    /// validates the profile, so this is an invariant).
    pub fn natural(x: &[f64], y: &[f64]) -> Self {
        let n = x.len();
        assert!(n >= 3 && y.len() == n, "spline needs >= 3 matching points");
        let h: Vec<f64> = x.windows(2).map(|w| w[1] - w[0]).collect();
        // Thomas algorithm on the interior unknowns m_1 … m_{n−2}.
        let mut diag = vec![0.0; n];
        let mut rhs = vec![0.0; n];
        for i in 1..n - 1 {
            diag[i] = 2.0 * (h[i - 1] + h[i]);
            rhs[i] = 6.0 * ((y[i + 1] - y[i]) / h[i] - (y[i] - y[i - 1]) / h[i - 1]);
        }
        for i in 2..n - 1 {
            let w = h[i - 1] / diag[i - 1];
            diag[i] -= w * h[i - 1];
            rhs[i] -= w * rhs[i - 1];
        }
        let mut m = vec![0.0; n];
        for i in (1..n - 1).rev() {
            m[i] = (rhs[i] - h[i] * m[i + 1]) / diag[i];
        }
        let coef = (0..n - 1)
            .map(|i| {
                let hi = h[i];
                let b = (y[i + 1] - y[i]) / hi - hi * (2.0 * m[i] + m[i + 1]) / 6.0;
                [y[i], b, m[i] / 2.0, (m[i + 1] - m[i]) / (6.0 * hi)]
            })
            .collect();
        Self {
            x: x.to_vec(),
            coef,
        }
    }

    /// The knot range `(x_0, x_{n−1})`.
    pub fn range(&self) -> (f64, f64) {
        (self.x[0], self.x[self.x.len() - 1])
    }

    /// Interval index containing `x` (clamped to the end intervals).
    #[inline]
    fn interval(&self, x: f64) -> usize {
        let k = self.x.partition_point(|&k| k <= x);
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

    /// Value at `x`, with a search hint.
    #[inline]
    pub fn value_hint(&self, x: f64, hint: &mut usize) -> f64 {
        let i = self.interval_from(x, hint);
        let [a, b, c, d] = self.coef[i];
        let t = x - self.x[i];
        a + t * (b + t * (c + t * d))
    }

    /// Value, first and second derivative at `x`.
    #[inline]
    pub fn eval<T: Scalar>(&self, x: T) -> (T, T, T) {
        let i = self.interval(x.re());
        let [a, b, c, d] = self.coef[i];
        let t = x - self.x[i];
        let v = ((t * d + c) * t + b) * t + a;
        let d1 = (t * (3.0 * d) + 2.0 * c) * t + b;
        let d2 = t * (6.0 * d) + 2.0 * c;
        (v, d1, d2)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reproduces_a_line_and_is_c2() {
        let x: Vec<f64> = (0..7).map(|k| (k as f64).powf(1.3)).collect();
        let y: Vec<f64> = x.iter().map(|v| 2.0 - 0.5 * v).collect();
        let s = Spline::natural(&x, &y);
        for q in [0.1, 1.7, 4.3, 8.9] {
            let (v, d1, d2) = s.eval(q);
            assert!((v - (2.0 - 0.5 * q)).abs() < 1e-13 && (d1 + 0.5).abs() < 1e-13);
            assert!(d2.abs() < 1e-12);
        }
        // continuity of S, S', S'' across an interior knot of a curved interpolant
        let y2: Vec<f64> = x.iter().map(|v| v.sin()).collect();
        let s2 = Spline::natural(&x, &y2);
        let k = x[3];
        let (l, r) = (s2.eval(k - 1e-12), s2.eval(k + 1e-12));
        assert!((l.0 - r.0).abs() < 1e-10 && (l.1 - r.1).abs() < 1e-10);
        assert!((l.2 - r.2).abs() < 1e-9);
    }

    #[test]
    fn converges_on_a_circle() {
        // a 300 mm arc sampled every 0.5 mm: curvature to 1e-4 relative in the middle
        let r = 0.3;
        let x: Vec<f64> = (-60..=60).map(|k| k as f64 * 5e-4).collect();
        let y: Vec<f64> = x.iter().map(|v| (r * r - v * v).sqrt()).collect();
        let s = Spline::natural(&x, &y);
        let (_, d1, d2) = s.eval(0.0101);
        let kappa = -d2 / (1.0 + d1 * d1).powf(1.5);
        assert!((kappa * r - 1.0).abs() < 1e-4, "{kappa}");
        let mut hint = 0;
        assert!((s.value_hint(0.0101, &mut hint) - s.eval(0.0101).0).abs() < 1e-16);
    }
}
