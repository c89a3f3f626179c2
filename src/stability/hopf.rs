//! Newton's method on the Hopf system: the speed $V$, frequency $ω$ and eigenvector $v$ at
//! which $J(V) = J_0 + J_1/V$ has the eigenvalue $iω$.
//!
//! The equations are $J(V)v − iωv = 0$ ($N$ complex) and $\langle v_0, v\rangle = 1$ (one
//! complex: the eigenvector's scale and phase fixed against the start vector $v_0$), in the
//! unknowns $v$, $ω$ and $V$. Writing the eigenvalue's correction as a complex $δκ$, a Newton
//! step is one LU of the bordered complex matrix
//! $$M = \begin{pmatrix} J − iωI & −v \\ v_0^H & 0 \end{pmatrix}$$
//! (size $N + 1$, regular at a simple eigenvalue) and two solves: $M(x_0, κ_0) = −(F, g)$ for
//! the residuals at fixed speed, and $M(x_1, κ_1) = (−J'v, 0)$ for the speed's effect; the
//! speed step is the one that keeps the eigenvalue on the imaginary axis,
//! $δV = −\mathrm{Re}\,κ_0/\mathrm{Re}\,κ_1$. By the left eigenvector $w$ ($w^H(J − iωI) = 0$)
//! the second solve gives $κ_1 = w^H J' v / w^H v = dλ/dV$, so the crossing's direction
//! (the sign of $d\,\mathrm{Re}\,λ/dV$, transversality) comes with the last step for free,
//! without eigenvalues either side. At a transversal crossing of a simple pair Newton converges
//! quadratically; from the eigenvector of the pair predicted between two grid speeds it takes
//! 3–5 steps.
//!
//! Written here: the complex LU is a dozen lines (partial pivoting on a row-major buffer
//! allocated once per solve); nalgebra's general LU of the equivalent real $(2N + 2)$-square
//! system took about a third of the car's whole critical-speed search (perf, issue 30), and no
//! crate offers a Hopf-point corrector for this affine-in-$1/V$ family.

use nalgebra::Complex;

use super::LinearSystem;

type C64 = Complex<f64>;

/// A converged Hopf point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct HopfPoint {
    /// speed (m/s)
    pub speed: f64,
    /// angular frequency (rad/s), > 0
    pub omega: f64,
    /// size of the last Newton correction of the speed (m/s)
    pub last_step: f64,
    /// $d\,\mathrm{Re}\,λ/dV$ of the crossing eigenvalue (1/m): > 0 for an onset
    pub growth: f64,
}

/// LU with partial pivoting of an n×n complex matrix stored by rows.
struct ComplexLu {
    n: usize,
    a: Vec<C64>,
    perm: Vec<usize>,
}

impl ComplexLu {
    /// Factors `a` (row-major, n·n entries) in place; `None` if an entry is not finite or a
    /// column has no nonzero pivot, unless `singular_ok`: then such a pivot is set to ε times
    /// the largest entry (inverse iteration with a shift that is an eigenvalue to rounding
    /// wants exactly that nearly singular solve).
    fn new(n: usize, mut a: Vec<C64>, singular_ok: bool) -> Option<Self> {
        if a.len() != n * n || !a.iter().all(|z| z.re.is_finite() && z.im.is_finite()) {
            return None;
        }
        let largest = a.iter().map(|z| z.norm()).fold(0.0, f64::max);
        let mut perm: Vec<usize> = (0..n).collect();
        for k in 0..n {
            let p = (k..n)
                .max_by(|&i, &j| a[i * n + k].norm_sqr().total_cmp(&a[j * n + k].norm_sqr()))?;
            if a[p * n + k].norm_sqr() == 0.0 {
                if !(singular_ok && largest > 0.0) {
                    return None;
                }
                a[p * n + k] = C64::new(f64::EPSILON * largest, 0.0);
            }
            let pivot = a[p * n + k];
            if p != k {
                for c in 0..n {
                    a.swap(k * n + c, p * n + c);
                }
                perm.swap(k, p);
            }
            let inv = pivot.inv();
            let (top, rest) = a.split_at_mut((k + 1) * n);
            let row_k = &top[k * n + k + 1..(k + 1) * n];
            for row in rest.chunks_exact_mut(n) {
                let l = row[k] * inv;
                row[k] = l;
                if l.re != 0.0 || l.im != 0.0 {
                    for (x, y) in row[k + 1..].iter_mut().zip(row_k) {
                        *x -= l * y;
                    }
                }
            }
        }
        Some(Self { n, a, perm })
    }

    /// Solves $A x = b$.
    fn solve(&self, b: &[C64]) -> Vec<C64> {
        let n = self.n;
        let mut x: Vec<C64> = self.perm.iter().map(|&p| b[p]).collect();
        for i in 0..n {
            let s: C64 = (0..i).map(|j| self.a[i * n + j] * x[j]).sum();
            x[i] -= s;
        }
        for i in (0..n).rev() {
            let s: C64 = (i + 1..n).map(|j| self.a[i * n + j] * x[j]).sum();
            x[i] = (x[i] - s) / self.a[i * n + i];
        }
        x
    }
}

/// The right eigenvector of $J(V)$ for the eigenvalue nearest `shift`, by three steps of
/// inverse iteration with $J(V) − \mathrm{shift}\,I$ (one LU), scaled to unit 2-norm; `None`
/// if the matrix is exactly singular or a result is not finite. A shift within a fraction of
/// the distance to the other eigenvalues suffices (each step gains that fraction).
pub(super) fn eigenvector<const N: usize>(
    sys: &LinearSystem<N>,
    v: f64,
    shift: (f64, f64),
) -> Option<Vec<(f64, f64)>> {
    let j = sys.jacobian(v);
    let s = C64::new(shift.0, shift.1);
    let a: Vec<C64> = (0..N * N)
        .map(|k| {
            let (r, c) = (k / N, k % N);
            C64::new(j[(r, c)], 0.0) - if r == c { s } else { C64::new(0.0, 0.0) }
        })
        .collect();
    let lu = ComplexLu::new(N, a, true)?;
    // a start with no special relation to the modes (all components nonzero, varied phases)
    let mut x: Vec<C64> = (0..N)
        .map(|k| C64::new(1.0 + 0.37 * (k as f64).sin(), 0.5 * (1.3 * k as f64).cos()))
        .collect();
    for _ in 0..3 {
        x = lu.solve(&x);
        let norm = x.iter().map(|z| z.norm_sqr()).sum::<f64>().sqrt();
        if !(norm > 0.0 && norm.is_finite()) {
            return None;
        }
        x.iter_mut().for_each(|z| *z /= norm);
    }
    Some(x.iter().map(|z| (z.re, z.im)).collect())
}

/// Newton on the Hopf system from speed `v0`, eigenvalue frequency `omega0` and eigenvector
/// `vec0` ((re, im) per state). `None` if it does not converge to `rel_tol` within 40 steps,
/// leaves `bounds` (m/s; the search is local to a grid interval, and a start that wanders off
/// is not worth its LUs), leaves the positive speeds, or ends at ω ≤ 0.
pub(super) fn newton<const N: usize>(
    sys: &LinearSystem<N>,
    v0: f64,
    omega0: f64,
    vec0: &[(f64, f64)],
    rel_tol: f64,
    bounds: (f64, f64),
) -> Option<HopfPoint> {
    if vec0.len() != N || !(v0 > 0.0 && omega0 > 0.0) {
        return None;
    }
    let norm = vec0
        .iter()
        .map(|z| z.0 * z.0 + z.1 * z.1)
        .sum::<f64>()
        .sqrt();
    if !(norm > 0.0 && norm.is_finite()) {
        return None;
    }
    let start: Vec<C64> = vec0.iter().map(|z| C64::new(z.0, z.1) / norm).collect();
    let m = N + 1;
    let mut x = start.clone();
    let (mut omega, mut v) = (omega0, v0);
    let mut rhs0 = vec![C64::new(0.0, 0.0); m];
    let mut rhs1 = vec![C64::new(0.0, 0.0); m];
    for _ in 0..40 {
        let j = sys.jacobian(v);
        let dj = -1.0 / (v * v);
        let iw = C64::new(0.0, omega);
        let mut a = vec![C64::new(0.0, 0.0); m * m];
        for r in 0..N {
            let (mut jx, mut djx) = (C64::new(0.0, 0.0), C64::new(0.0, 0.0));
            for c in 0..N {
                jx += x[c] * j[(r, c)];
                djx += x[c] * (sys.j1[(r, c)] * dj);
                a[r * m + c] = C64::new(j[(r, c)], 0.0);
            }
            a[r * m + r] -= iw;
            a[r * m + N] = -x[r];
            a[N * m + r] = start[r].conj();
            rhs0[r] = -(jx - iw * x[r]);
            rhs1[r] = -djx;
        }
        let g: C64 = start.iter().zip(&x).map(|(s, y)| s.conj() * y).sum();
        rhs0[N] = -(g - 1.0);
        rhs1[N] = C64::new(0.0, 0.0);
        let lu = ComplexLu::new(m, a, false)?;
        let (s0, s1) = (lu.solve(&rhs0), lu.solve(&rhs1));
        let (k0, k1) = (s0[N], s1[N]);
        if !(k1.re != 0.0 && k1.re.is_finite() && k0.re.is_finite()) {
            return None;
        }
        // a step may not cross V = 0 (the model is singular there)
        let dv = (-k0.re / k1.re).clamp(-0.5 * v, 0.5 * v);
        let d_omega = (k0 + k1 * dv).im;
        for ((xi, a0), a1) in x.iter_mut().zip(&s0).zip(&s1) {
            *xi += a0 + a1 * dv;
        }
        omega += d_omega;
        v += dv;
        if !(v.is_finite() && omega.is_finite()) || v < bounds.0 || v > bounds.1 {
            return None;
        }
        if dv.abs() <= rel_tol * v && d_omega.abs() <= 1e-9 * omega.abs().max(1e-12) {
            return (omega > 0.0 && v > 0.0).then_some(HopfPoint {
                speed: v,
                omega,
                last_step: dv.abs(),
                growth: k1.re,
            });
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::SMatrix;

    /// A 4-state system whose pair crosses at a known speed: the damped oscillator
    /// ẍ + (c − d/V)ẋ + ω0²x = 0 written as J(V) = J0 + J1/V with J0 = [[0,1],[−ω0², −c]] and
    /// J1 = [[0,0],[0, d]]: eigenvalues −(c − d/V)/2 ± i·√(ω0² − (c − d/V)²/4), so the real
    /// part vanishes at V = d/c with ω = ω0; a second, decoupled oscillator stays damped.
    /// Newton from 20 % off finds V = d/c and ω = ω0, and dRe λ/dV = −d/(2V²) < 0 (a
    /// recovery: the negative damping d/V fades with speed).
    #[test]
    fn newton_finds_the_closed_form_crossing() {
        let (w0, c, d) = (3.0, 0.4, 20.0);
        let mut j0 = SMatrix::<f64, 4, 4>::zeros();
        let mut j1 = SMatrix::<f64, 4, 4>::zeros();
        j0[(0, 1)] = 1.0;
        j0[(1, 0)] = -w0 * w0;
        j0[(1, 1)] = -c;
        j1[(1, 1)] = d;
        j0[(2, 3)] = 1.0;
        j0[(3, 2)] = -7.0;
        j0[(3, 3)] = -1.0;
        let sys = LinearSystem::new(j0, j1);
        let v_true = d / c;
        let v_start = 1.2 * v_true;
        let shift = {
            let s = -(c - d / v_start) / 2.0;
            (s, (w0 * w0 - s * s).sqrt())
        };
        let vec = eigenvector(&sys, v_start, shift).expect("eigenvector");
        // it is an eigenvector: ‖(J − λI)v‖ ≈ 0
        let j = sys.jacobian(v_start);
        let lam = C64::new(shift.0, shift.1);
        let res: f64 = (0..4)
            .map(|r| {
                let jv: C64 = (0..4)
                    .map(|k| C64::new(vec[k].0, vec[k].1) * j[(r, k)])
                    .sum();
                (jv - lam * C64::new(vec[r].0, vec[r].1)).norm_sqr()
            })
            .sum::<f64>()
            .sqrt();
        assert!(res < 1e-12, "residual {res}");
        let h = newton(&sys, v_start, shift.1, &vec, 1e-13, (1.0, 1e3)).expect("converges");
        assert!((h.speed - v_true).abs() < 1e-11 * v_true, "{h:?}");
        assert!((h.omega - w0).abs() < 1e-10 * w0, "{h:?}");
        let growth = -d / (2.0 * v_true * v_true);
        assert!(
            (h.growth - growth).abs() < 1e-6 * growth.abs(),
            "{h:?} against {growth}"
        );
        // outside the bounds it gives up
        assert!(newton(&sys, v_start, shift.1, &vec, 1e-13, (1.0, 0.5 * v_true)).is_none());
    }

    /// The LU solves a random-ish complex system to rounding, checked by its residual.
    #[test]
    fn complex_lu_solves_to_rounding() {
        let n = 9;
        // entries from a 64-bit linear congruential generator, uniform in [−1, 1)
        let mut state: u64 = 12345;
        let mut uniform = move || {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            (state >> 11) as f64 / (1u64 << 52) as f64 - 1.0
        };
        let a: Vec<C64> = (0..n * n).map(|_| C64::new(uniform(), uniform())).collect();
        let b: Vec<C64> = (0..n).map(|k| C64::new(k as f64, 1.0)).collect();
        let lu = ComplexLu::new(n, a.clone(), false).expect("regular");
        let x = lu.solve(&b);
        for r in 0..n {
            let ax: C64 = (0..n).map(|c| a[r * n + c] * x[c]).sum();
            assert!((ax - b[r]).norm() < 1e-12, "row {r}: {ax} against {}", b[r]);
        }
        assert!(ComplexLu::new(2, vec![C64::new(0.0, 0.0); 4], false).is_none());
        assert!(ComplexLu::new(2, vec![C64::new(0.0, 0.0); 4], true).is_none());
    }
}
