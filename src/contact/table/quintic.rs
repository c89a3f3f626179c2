//! C² interpolation of node data on a uniform grid: piecewise quintic Hermite.
//!
//! Each node $y_k = y_0 + k h$ carries a value $p_k$, a slope $m_k$ and a second derivative
//! $c_k$ per column. On $[y_k, y_{k+1}]$ the interpolant is the quintic with these six data at
//! its two ends; in $t = (y − y_k)/h$, with $Δ = p_{k+1} − p_k$, $M_j = m_j h$, $C_j = c_j h^2$,
//!
//! $$q(t) = p_k + M_k t + \tfrac{1}{2} C_k t^2 + a_3 t^3 + a_4 t^4 + a_5 t^5,$$
//! $$a_3 = 10Δ − 6M_k − 4M_{k+1} − \tfrac{3}{2}C_k + \tfrac{1}{2}C_{k+1},\quad
//!   a_4 = −15Δ + 8M_k + 7M_{k+1} + \tfrac{3}{2}C_k − C_{k+1},$$
//! $$a_5 = 6Δ − 3M_k − 3M_{k+1} − \tfrac{1}{2}C_k + \tfrac{1}{2}C_{k+1}.$$
//!
//! Value, slope and second derivative are continuous at every node (they are the node's data
//! from both sides), so the interpolant is C²; it reproduces polynomials up to degree five
//! when the node data are theirs. Each interval's quintic is stored in powers of
//! $d = y − y_k$ (so at $d = 0$ the node's value and slope come back exactly, not through a
//! division by h) and evaluated by Horner's rule: five multiply-adds for the value, four
//! more for the slope; the `f64` evaluation of the model discards the slope, and with
//! [`Quintic::eval`] inlined the compiler does not compute it.
//!
//! Beyond the grid the columns are extended linearly with the end node's value and slope:
//! C¹ there (the second derivative drops to zero). A quadratic term would keep C² but
//! continue the end node's curvature, which on real profiles is the flange's, without
//! bound; the extension is not genuine geometry either way (see
//! [`super::ContactTable::valid_half_width`]), and the linear one is the tamer guess.

/// Where `y` falls on the grid.
#[derive(Clone, Copy, Debug)]
pub(super) enum Locus {
    /// in interval `k`, at `d = y − y_k` (m)
    Inside { k: usize, d: f64 },
    /// below the first node by `d < 0` (or `y` is NaN)
    Below { d: f64 },
    /// above the last node by `d ≥ 0`
    Above { d: f64 },
}

/// The piecewise quintic of `C` columns on a uniform grid.
#[derive(Clone, Debug)]
pub(super) struct Quintic<const C: usize> {
    y0: f64,
    h: f64,
    /// per interval, per column: coefficients of $d^0 … d^5$
    coef: Vec<[[f64; 6]; C]>,
    /// value and slope of the last node, per column (the first node's are `coef[0]`)
    last: [(f64, f64); C],
}

impl<const C: usize> Quintic<C> {
    /// The interpolant of the node data (`value`, `slope`, `curvature` = second derivative,
    /// `[node][column]`, at least two nodes) on the grid `y0 + k h`.
    pub(super) fn new(
        (y0, h): (f64, f64),
        value: &[[f64; C]],
        slope: &[[f64; C]],
        curvature: &[[f64; C]],
    ) -> Self {
        let n = value.len();
        assert!(
            n >= 2 && slope.len() == n && curvature.len() == n,
            "node data of equal length, two nodes at least"
        );
        let coef = (0..n - 1)
            .map(|k| {
                std::array::from_fn(|c| {
                    let (p0, p1) = (value[k][c], value[k + 1][c]);
                    let (m0, m1) = (slope[k][c] * h, slope[k + 1][c] * h);
                    let (c0, c1) = (curvature[k][c] * h * h, curvature[k + 1][c] * h * h);
                    let dp = p1 - p0;
                    let a3 = 10.0 * dp - 6.0 * m0 - 4.0 * m1 - 1.5 * c0 + 0.5 * c1;
                    let a4 = -15.0 * dp + 8.0 * m0 + 7.0 * m1 + 1.5 * c0 - c1;
                    let a5 = 6.0 * dp - 3.0 * (m0 + m1) - 0.5 * (c0 - c1);
                    let (h2, h3) = (h * h, h * h * h);
                    [
                        p0,
                        slope[k][c],
                        0.5 * curvature[k][c],
                        a3 / h3,
                        a4 / (h3 * h),
                        a5 / (h3 * h2),
                    ]
                })
            })
            .collect();
        let last = std::array::from_fn(|c| (value[n - 1][c], slope[n - 1][c]));
        Self { y0, h, coef, last }
    }

    /// The interval of `y` (or the side it leaves the grid on).
    #[inline]
    pub(super) fn locate(&self, y: f64) -> Locus {
        let s = (y - self.y0) / self.h;
        if s.is_nan() || s < 0.0 {
            return Locus::Below { d: y - self.y0 };
        }
        let m = self.coef.len();
        if s >= m as f64 {
            return Locus::Above {
                d: y - (self.y0 + m as f64 * self.h),
            };
        }
        let k = (s as usize).min(m - 1);
        Locus::Inside {
            k,
            d: y - (self.y0 + k as f64 * self.h),
        }
    }

    /// Column `c`'s value and slope at a located `y`.
    #[inline(always)]
    pub(super) fn eval(&self, at: &Locus, c: usize) -> (f64, f64) {
        match *at {
            Locus::Inside { k, d } => {
                let [b0, b1, b2, b3, b4, b5] = self.coef[k][c];
                let v = b0 + d * (b1 + d * (b2 + d * (b3 + d * (b4 + d * b5))));
                let s = b1 + d * (2.0 * b2 + d * (3.0 * b3 + d * (4.0 * b4 + d * (5.0 * b5))));
                (v, s)
            }
            Locus::Below { d } => {
                let [b0, b1, ..] = self.coef[0][c];
                (b0 + b1 * d, b1)
            }
            Locus::Above { d } => {
                let (v, s) = self.last[c];
                (v + s * d, s)
            }
        }
    }

    /// Column `c`'s value, slope and second derivative at `y` (not on the hot path).
    pub(super) fn eval2(&self, y: f64, c: usize) -> [f64; 3] {
        match self.locate(y) {
            Locus::Inside { k, d } => self.interval(k, d, c),
            at => {
                let (v, s) = self.eval(&at, c);
                [v, s, 0.0]
            }
        }
    }

    /// Value, slope and second derivative of interval `k`'s quintic at `d = y − y_k`.
    fn interval(&self, k: usize, d: f64, c: usize) -> [f64; 3] {
        let [b0, b1, b2, b3, b4, b5] = self.coef[k][c];
        [
            b0 + d * (b1 + d * (b2 + d * (b3 + d * (b4 + d * b5)))),
            b1 + d * (2.0 * b2 + d * (3.0 * b3 + d * (4.0 * b4 + d * (5.0 * b5)))),
            2.0 * b2 + d * (6.0 * b3 + d * (12.0 * b4 + d * (20.0 * b5))),
        ]
    }
}

/// Second derivatives at the nodes from the exact node slopes: central differences
/// $(m_{k+1} − m_{k−1})/(2h)$ inside, the one-sided second-order formulas
/// $∓(3m_k − 4m_{k±1} + m_{k±2})/(2h)$ at the two ends. Exact when the slopes are a
/// quadratic in y (so cubic columns are reproduced to rounding); error
/// $h^2 f^{(4)}/6$ inside and $h^2 f^{(4)}/3$ at the ends otherwise. Needs three nodes.
pub(super) fn curvatures<const C: usize>(slope: &[[f64; C]], h: f64) -> Vec<[f64; C]> {
    let n = slope.len();
    assert!(n >= 3, "three nodes for the second differences");
    (0..n)
        .map(|k| {
            std::array::from_fn(|c| {
                let s = |j: usize| slope[j][c];
                if k == 0 {
                    (-3.0 * s(0) + 4.0 * s(1) - s(2)) / (2.0 * h)
                } else if k == n - 1 {
                    (3.0 * s(k) - 4.0 * s(k - 1) + s(k - 2)) / (2.0 * h)
                } else {
                    (s(k + 1) - s(k - 1)) / (2.0 * h)
                }
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn grid(n: usize, y0: f64, h: f64) -> Vec<f64> {
        (0..n).map(|k| y0 + k as f64 * h).collect()
    }

    /// A quintic polynomial with its exact node data is reproduced everywhere (value, slope,
    /// second derivative), to rounding.
    #[test]
    fn quintics_are_reproduced() {
        let p = |y: f64| {
            0.46 + 0.05 * y - 3.0 * y * y + 900.0 * y.powi(3) + 4e4 * y.powi(4) - 3e6 * y.powi(5)
        };
        let dp = |y: f64| 0.05 - 6.0 * y + 2700.0 * y * y + 1.6e5 * y.powi(3) - 1.5e7 * y.powi(4);
        let d2p = |y: f64| -6.0 + 5400.0 * y + 4.8e5 * y * y - 6e7 * y.powi(3);
        let (y0, h) = (-0.01, 1e-3);
        let ys = grid(21, y0, h);
        let q = Quintic::<1>::new(
            (y0, h),
            &ys.iter().map(|&y| [p(y)]).collect::<Vec<_>>(),
            &ys.iter().map(|&y| [dp(y)]).collect::<Vec<_>>(),
            &ys.iter().map(|&y| [d2p(y)]).collect::<Vec<_>>(),
        );
        for j in 0..=400 {
            let y = -0.00999 + 0.01998 * j as f64 / 400.0;
            let [v, s, c] = q.eval2(y, 0);
            assert!((v - p(y)).abs() < 1e-15, "{y}: {v} vs {}", p(y));
            assert!((s - dp(y)).abs() < 1e-11, "{y}: {s} vs {}", dp(y));
            assert!((c - d2p(y)).abs() < 1e-7 * d2p(y).abs().max(1.0), "{y}");
        }
    }

    /// Value, slope and second derivative from either side of a node are the node's: C² by
    /// construction, also for data that are not a polynomial's (here: scrambled values and
    /// slopes, the second derivatives from [`curvatures`]).
    #[test]
    fn interpolant_is_c2_at_nodes() {
        let (y0, h) = (-0.004, 5e-4);
        let n = 17;
        let f = |k: usize, a: f64| ((k * 37 + 11) % 17) as f64 * a;
        let value: Vec<[f64; 2]> = (0..n).map(|k| [f(k, 1e-4), f(k, -3e-3)]).collect();
        let slope: Vec<[f64; 2]> = (0..n).map(|k| [f(k + 3, 0.1), f(k + 5, 2.0)]).collect();
        let curv = curvatures(&slope, h);
        let q = Quintic::new((y0, h), &value, &slope, &curv);
        for k in 1..n - 1 {
            for c in 0..2 {
                let (left, right) = (q.interval(k - 1, h, c), q.interval(k, 0.0, c));
                let want = [value[k][c], slope[k][c], curv[k][c]];
                // rounding of sums of terms up to 180 (|Δp| + |m| h + |c| h²), divided by h^j
                let big =
                    |v: &[[f64; 2]], s: f64| v.iter().map(|r| r[c].abs() * s).fold(0.0, f64::max);
                let size = 180.0 * (2.0 * big(&value, 1.0) + big(&slope, h) + big(&curv, h * h));
                for j in 0..3 {
                    let tol = 4.0 * f64::EPSILON * size / h.powi(j as i32);
                    assert!((left[j] - want[j]).abs() < tol, "node {k} col {c} d{j}");
                    assert!((right[j] - want[j]).abs() < tol, "node {k} col {c} d{j}");
                }
            }
        }
    }

    /// A smooth function (sin) with exact values and slopes and second derivatives from
    /// [`curvatures`]: the error between the nodes falls like h⁴ (the O(h²) error of the
    /// second derivatives enters with the weight h²), and the error at the nodes of the second
    /// derivative like h².
    #[test]
    fn smooth_functions_converge_like_h4() {
        let l = 2e-3;
        let mut errors = Vec::new();
        for n in [21, 41, 81, 161] {
            let h = 0.02 / (n - 1) as f64;
            let ys = grid(n, -0.01, h);
            let value: Vec<[f64; 1]> = ys.iter().map(|&y| [(y / l).sin()]).collect();
            let slope: Vec<[f64; 1]> = ys.iter().map(|&y| [(y / l).cos() / l]).collect();
            let curv = curvatures(&slope, h);
            let q = Quintic::new((-0.01, h), &value, &slope, &curv);
            let mid = ys[..n - 1]
                .iter()
                .map(|&y| (q.eval2(y + 0.5 * h, 0)[0] - ((y + 0.5 * h) / l).sin()).abs())
                .fold(0.0, f64::max);
            let node = ys[1..n - 1]
                .iter()
                .zip(&curv[1..n - 1])
                .map(|(&y, c)| (c[0] + (y / l).sin() / (l * l)).abs() * l * l)
                .fold(0.0, f64::max);
            errors.push((mid, node));
        }
        for w in errors.windows(2) {
            let (value, second) = (w[0].0 / w[1].0, w[0].1 / w[1].1);
            assert!((13.0..19.0).contains(&value), "{errors:?}");
            assert!((3.5..4.5).contains(&second), "{errors:?}");
        }
    }

    /// Central differences of the slopes are exact for quadratic slopes (cubic columns).
    #[test]
    fn curvatures_are_exact_for_cubics() {
        let h = 2.5e-4;
        let ys = grid(9, -1e-3, h);
        let slope: Vec<[f64; 1]> = ys
            .iter()
            .map(|&y| [0.05 + 6.0 * y - 2700.0 * y * y])
            .collect();
        for (c, &y) in curvatures(&slope, h).iter().zip(&ys) {
            assert!((c[0] - (6.0 - 5400.0 * y)).abs() < 1e-9, "{y}");
        }
    }

    /// Beyond the grid: the end node's value and slope, continued linearly.
    #[test]
    fn linear_extension_beyond_the_ends() {
        let (y0, h) = (-1.0, 1.0);
        let value = [[1.0], [0.0], [2.0]];
        let slope = [[-1.0], [0.5], [3.0]];
        let q = Quintic::new((y0, h), &value, &slope, &curvatures(&slope, h));
        let close = |a: [f64; 3], b: [f64; 3]| (0..3).all(|j| (a[j] - b[j]).abs() < 1e-15);
        assert!(close(q.eval2(-3.0, 0), [3.0, -1.0, 0.0]));
        assert!(close(q.eval2(2.0, 0), [5.0, 3.0, 0.0]));
        let nan = q.eval(&q.locate(f64::NAN), 0);
        assert!(nan.0.is_nan() && (nan.1 + 1.0).abs() < 1e-15);
    }
}
