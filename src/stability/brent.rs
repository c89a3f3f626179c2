//! Brent's bracketing root finder (Brent 1973, *Algorithms for Minimization without
//! Derivatives*, ch. 4): inverse quadratic interpolation and secant steps, falling back to
//! bisection whenever they do not shrink the bracket fast enough. Written here because it is
//! thirty lines and the search calls it on a cheap scalar function in its inner loop.

/// A located root.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Root {
    /// the root
    pub x: f64,
    /// width of the final bracket
    pub bracket: f64,
    /// function evaluations
    pub evaluations: usize,
}

/// A root of `f` in `[a, b]`, where `f(a)` and `f(b)` differ in sign, to absolute `tol`.
pub fn root(mut f: impl FnMut(f64) -> f64, a: f64, b: f64, tol: f64, max_iter: usize) -> Root {
    let (mut a, mut b) = (a, b);
    let (mut fa, mut fb) = (f(a), f(b));
    let mut evaluations = 2;
    if fa == 0.0 {
        return Root {
            x: a,
            bracket: 0.0,
            evaluations,
        };
    }
    let (mut c, mut fc) = (a, fa);
    let (mut d, mut e) = (b - a, b - a);
    for _ in 0..max_iter {
        if fb == 0.0 {
            return Root {
                x: b,
                bracket: 0.0,
                evaluations,
            };
        }
        if fb.signum() == fc.signum() {
            (c, fc) = (a, fa);
            d = b - a;
            e = d;
        }
        if fc.abs() < fb.abs() {
            (a, fa) = (b, fb);
            (b, fb) = (c, fc);
            (c, fc) = (a, fa);
        }
        let tol1 = 2.0 * f64::EPSILON * b.abs() + 0.5 * tol;
        let m = 0.5 * (c - b);
        if m.abs() <= tol1 {
            return Root {
                x: b,
                bracket: (c - b).abs(),
                evaluations,
            };
        }
        if e.abs() >= tol1 && fa.abs() > fb.abs() {
            let s = fb / fa;
            let (mut p, mut q) = if a == c {
                (2.0 * m * s, 1.0 - s)
            } else {
                let q = fa / fc;
                let r = fb / fc;
                (
                    s * (2.0 * m * q * (q - r) - (b - a) * (r - 1.0)),
                    (q - 1.0) * (r - 1.0) * (s - 1.0),
                )
            };
            if p > 0.0 {
                q = -q;
            } else {
                p = -p;
            }
            if 2.0 * p < (3.0 * m * q - (tol1 * q).abs()).min((e * q).abs()) {
                e = d;
                d = p / q;
            } else {
                d = m;
                e = d;
            }
        } else {
            d = m;
            e = d;
        }
        (a, fa) = (b, fb);
        b += if d.abs() > tol1 { d } else { tol1.copysign(m) };
        fb = f(b);
        evaluations += 1;
    }
    Root {
        x: b,
        bracket: (c - b).abs(),
        evaluations,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_known_roots() {
        let r = root(|x| x * x - 2.0, 0.0, 2.0, 1e-15, 100);
        assert!((r.x - 2f64.sqrt()).abs() < 1e-14, "{r:?}");
        let r = root(|x| x.cos() - x, 0.0, 1.0, 1e-15, 100);
        assert!((r.x - 0.739_085_133_215_160_6).abs() < 1e-14);
        // a function that defeats interpolation still converges by bisection
        let r = root(|x| (x - 0.3).cbrt(), -1.0, 1.0, 1e-14, 200);
        assert!((r.x - 0.3).abs() < 1e-13, "{r:?}");
    }
}
