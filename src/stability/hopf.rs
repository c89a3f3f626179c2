//! Newton's method on the Hopf system: the speed $V$, frequency $ω$ and eigenvector $v$ at
//! which $J(V) = J_0 + J_1/V$ has the eigenvalue $iω$.
//!
//! The unknowns are $v ∈ \mathbb{C}^N$ and the reals $ω, V$; the equations are
//! $$(J(V) − iω I)\,v = 0,\qquad c^H v = 1,$$
//! the second fixing the eigenvector's scale and phase against the start vector $c$. A Newton
//! step solves $A\,δv + d\,δV − i v\,δω = −r$, $c^H δv = −g$ with $A = J − iωI$,
//! $d = J'(V) v = −J_1 v/V^2$ and the residuals $r, g$. Both reals enter through one complex
//! bordered matrix $M = \begin{pmatrix} A & d \\ c^H & 0 \end{pmatrix}$ of order $N + 1$: with
//! $M (x_1, s_1) = (−r, −g)$ and $M (x_2, s_2) = (i v, 0)$, the step is
//! $(δv, δV) = (x_1, s_1) + δω\,(x_2, s_2)$ with $δω$ chosen so that $δV$ is real,
//! $δω = −\mathrm{Im}\,s_1/\mathrm{Im}\,s_2$. One LU of $M$ per step (complex, on a buffer
//! allocated once per call): for the 28-state car a tenth of an eigenvalue decomposition.
//!
//! At the solution, with $w$ the left eigenvector, $s_2 = i/λ'(V)$ where
//! $λ' = w^H J' v / w^H v$ is the speed derivative of the crossing eigenvalue, so
//! $\mathrm{Im}\,s_2 = \mathrm{Re}\,λ'/|λ'|^2$: its sign is the direction of the crossing
//! (onset when positive) without a left eigenvector, and it vanishes only where the crossing
//! is not transversal (where the bordered system is singular and Newton is not used).
//!
//! The start vector is the eigenvector of the start eigenvalue $z_0$ at the start speed, by
//! two steps of inverse iteration with the shift $z_0$. Written here (a complex LU of a few
//! dozen lines): no crate offers a Hopf-point corrector for this affine-in-$1/V$ family.

use nalgebra::Complex;

use super::LinearSystem;

type C64 = Complex<f64>;

/// Newton steps allowed before giving up.
const MAX_STEPS: usize = 40;

/// A converged Hopf point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct HopfPoint {
    /// speed (m/s)
    pub speed: f64,
    /// angular frequency (rad/s), > 0
    pub omega: f64,
    /// size of the last Newton correction of the speed (m/s)
    pub last_step: f64,
    /// whether the real part of the crossing eigenvalue grows with the speed there
    pub onset: bool,
}

/// LU factorisation with partial pivoting, in place, of the row-major `m`×`m` matrix `a`;
/// `piv[k]` is the row exchanged with row k at step k. A zero pivot is replaced by
/// `tiny` (inverse iteration on an exactly singular shift) or, when `tiny` is 0, makes the
/// factorisation fail. `false` on failure or a non-finite entry.
fn lu(a: &mut [C64], m: usize, piv: &mut [usize], tiny: f64) -> bool {
    for k in 0..m {
        let mut p = k;
        let mut best = a[k * m + k].norm_sqr();
        for r in k + 1..m {
            let x = a[r * m + k].norm_sqr();
            if x > best {
                (p, best) = (r, x);
            }
        }
        if !best.is_finite() {
            return false;
        }
        piv[k] = p;
        if p != k {
            for c in 0..m {
                a.swap(k * m + c, p * m + c);
            }
        }
        if best == 0.0 {
            if tiny > 0.0 {
                a[k * m + k] = C64::new(tiny, 0.0);
            } else {
                return false;
            }
        }
        let inv = a[k * m + k].inv();
        let (upper, lower) = a.split_at_mut((k + 1) * m);
        let pivot_row = &upper[k * m..];
        for row in lower.chunks_exact_mut(m) {
            let f = row[k] * inv;
            row[k] = f;
            if f != C64::new(0.0, 0.0) {
                for (x, y) in row[k + 1..].iter_mut().zip(&pivot_row[k + 1..]) {
                    *x -= f * y;
                }
            }
        }
    }
    true
}

/// Solves $A x = b$ in place with the factors of [`lu`].
fn solve(a: &[C64], m: usize, piv: &[usize], b: &mut [C64]) {
    for (k, &p) in piv.iter().enumerate().take(m) {
        b.swap(k, p);
    }
    for r in 1..m {
        let s: C64 = a[r * m..r * m + r]
            .iter()
            .zip(&b[..r])
            .map(|(x, y)| x * y)
            .sum();
        b[r] -= s;
    }
    for r in (0..m).rev() {
        let s: C64 = a[r * m + r + 1..(r + 1) * m]
            .iter()
            .zip(&b[r + 1..m])
            .map(|(x, y)| x * y)
            .sum();
        b[r] = (b[r] - s) / a[r * m + r];
    }
}

/// The unit eigenvector of $J(V)$ for the eigenvalue nearest `z`, by two steps of inverse
/// iteration with the shift `z`; `None` if the LU fails or the result is not finite.
fn eigenvector<const N: usize>(sys: &LinearSystem<N>, v: f64, z: C64) -> Option<Vec<C64>> {
    let j = sys.jacobian(v);
    let scale = j.iter().fold(0.0_f64, |s, x| s.max(x.abs())).max(z.norm());
    let mut a = vec![C64::new(0.0, 0.0); N * N];
    for r in 0..N {
        for c in 0..N {
            a[r * N + c] = C64::new(j[(r, c)], 0.0);
        }
        a[r * N + r] -= z;
    }
    let mut piv = vec![0; N];
    if !lu(
        &mut a,
        N,
        &mut piv,
        f64::EPSILON * scale.max(f64::MIN_POSITIVE),
    ) {
        return None;
    }
    let mut x = vec![C64::new(1.0, 0.0); N];
    for _ in 0..2 {
        solve(&a, N, &piv, &mut x);
        let norm = x.iter().map(|y| y.norm_sqr()).sum::<f64>().sqrt();
        if !(norm > 0.0 && norm.is_finite()) {
            return None;
        }
        x.iter_mut().for_each(|y| *y /= norm);
    }
    Some(x)
}

/// Newton on the Hopf system from speed `v0` and the eigenvalue `z0` = (re, im), im > 0, of
/// $J(v_0)$ (its eigenvector by inverse iteration). `None` if it does not converge to
/// `rel_tol` in the speed (and 1e-9 in ω) within 40 steps, leaves the positive speeds, ends
/// at ω ≤ 0, or meets a singular bordered matrix (a non-transversal crossing).
pub(super) fn newton<const N: usize>(
    sys: &LinearSystem<N>,
    v0: f64,
    z0: (f64, f64),
    rel_tol: f64,
) -> Option<HopfPoint> {
    if !(v0 > 0.0 && z0.1 > 0.0 && z0.0.is_finite() && z0.1.is_finite()) {
        return None;
    }
    // as for the eigenvalues: SSE code after dirty upper register halves runs slower
    super::spectrum::clear_upper_halves();
    let mut vec = eigenvector(sys, v0, C64::new(z0.0, z0.1))?;
    let c: Vec<C64> = vec.iter().map(|y| y.conj()).collect();
    let m = N + 1;
    let (mut omega, mut v) = (z0.1, v0);
    let mut a = vec![C64::new(0.0, 0.0); m * m];
    let mut piv = vec![0; m];
    let (mut rhs1, mut rhs2) = (vec![C64::new(0.0, 0.0); m], vec![C64::new(0.0, 0.0); m]);
    let i_omega = |w: f64| C64::new(0.0, w);
    for _ in 0..MAX_STEPS {
        let j = sys.jacobian(v);
        let djdv = -1.0 / (v * v);
        for r in 0..N {
            let (mut jv, mut d) = (C64::new(0.0, 0.0), C64::new(0.0, 0.0));
            for col in 0..N {
                a[r * m + col] = C64::new(j[(r, col)], 0.0);
                jv += vec[col] * j[(r, col)];
                d += vec[col] * (sys.j1[(r, col)] * djdv);
            }
            a[r * m + r] -= i_omega(omega);
            a[r * m + N] = d;
            rhs1[r] = -(jv - i_omega(omega) * vec[r]);
            rhs2[r] = i_omega(1.0) * vec[r];
        }
        let mut g = C64::new(-1.0, 0.0);
        for col in 0..N {
            a[N * m + col] = c[col];
            g += c[col] * vec[col];
        }
        a[N * m + N] = C64::new(0.0, 0.0);
        rhs1[N] = -g;
        rhs2[N] = C64::new(0.0, 0.0);
        if !lu(&mut a, m, &mut piv, 0.0) {
            return None;
        }
        solve(&a, m, &piv, &mut rhs1);
        solve(&a, m, &piv, &mut rhs2);
        let (s1, s2) = (rhs1[N], rhs2[N]);
        if s2.im == 0.0 {
            return None;
        }
        let d_omega = -s1.im / s2.im;
        let dv_raw = s1.re + d_omega * s2.re;
        if !(d_omega.is_finite() && dv_raw.is_finite()) {
            return None;
        }
        for (k, y) in vec.iter_mut().enumerate() {
            *y += rhs1[k] + rhs2[k] * d_omega;
        }
        omega += d_omega;
        // a step may not cross V = 0 (the model is singular there)
        let dv = dv_raw.clamp(-0.5 * v, 0.5 * v);
        v += dv;
        if dv.abs() <= rel_tol * v && d_omega.abs() <= 1e-9 * omega.abs().max(1e-12) {
            return (omega > 0.0 && v > 0.0).then_some(HopfPoint {
                speed: v,
                omega,
                last_step: dv.abs(),
                onset: s2.im > 0.0,
            });
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::SMatrix;

    /// A 4-state system whose oscillating pair is $σ(V) ± iω$ with $σ = 1 − 100/V$ and ω = 3
    /// (a rotation block plus two stable real modes): the crossing is at V = 100 m/s, an
    /// onset, found from 80 m/s; and the mirrored system ($σ = 100/V − 1$) gives a recovery
    /// at the same speed.
    #[test]
    fn newton_finds_a_known_crossing_and_its_direction() {
        for sign in [1.0, -1.0] {
            let j0 = SMatrix::<f64, 4, 4>::from_row_slice(&[
                sign, 3.0, 0.5, 0.0, //
                -3.0, sign, 0.0, 0.2, //
                0.0, 0.0, -2.0, 0.0, //
                0.0, 0.0, 0.0, -5.0,
            ]);
            let mut j1 = SMatrix::<f64, 4, 4>::zeros();
            j1[(0, 0)] = -100.0 * sign;
            j1[(1, 1)] = -100.0 * sign;
            let sys = LinearSystem::new(j0, j1);
            let v0 = 80.0;
            let z0 = (sign * (1.0 - 100.0 / v0), 3.0);
            let h = newton(&sys, v0, z0, 1e-12).expect("converges");
            assert!((h.speed - 100.0).abs() < 1e-9, "{h:?}");
            assert!((h.omega - 3.0).abs() < 1e-9, "{h:?}");
            assert_eq!(h.onset, sign > 0.0, "{h:?}");
        }
    }
}
