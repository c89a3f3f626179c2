//! Newton's method on the Hopf system: the speed $V$, frequency $ω$ and eigenvector $v$ at
//! which $J(V) = J_0 + J_1/V$ has the eigenvalue $iω$.
//!
//! With $v = a + ib$ the real system of $2N + 2$ equations in $(a, b, ω, V)$ is
//! $$J a + ω b = 0,\quad J b − ω a = 0,\quad a_0·a + b_0·b = 1,\quad a_0·b − b_0·a = 0,$$
//! the last two fixing the eigenvector's scale and phase against the start vector
//! $v_0 = a_0 + i b_0$ ($\langle v_0, v\rangle = 1$). At a simple crossing with a nonzero
//! speed derivative of the real part (transversality) its Jacobian is regular, so Newton
//! converges quadratically from an eigenpair of a nearby speed. Each step is one LU of a
//! $(2N+2)$-square real matrix: for the 28-state car about a fiftieth of an eigenvalue
//! decomposition's cost, which is why the scan locates crossings this way instead of by a
//! bracketing method on eigenvalues. Written here (a dozen lines of assembly around
//! nalgebra's LU): no crate offers a Hopf-point corrector for this affine-in-$1/V$ family.

use nalgebra::{DMatrix, DVector};

use super::LinearSystem;

/// A converged Hopf point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct HopfPoint {
    /// speed (m/s)
    pub speed: f64,
    /// angular frequency (rad/s), > 0
    pub omega: f64,
    /// size of the last Newton correction of the speed (m/s)
    pub last_step: f64,
}

/// Newton on the Hopf system from speed `v0`, eigenvalue frequency `omega0` and eigenvector
/// `vec0` ((re, im) per state). `None` if it does not converge to `rel_tol` within 40 steps,
/// leaves the positive speeds, or ends at ω ≤ 0.
pub(super) fn newton<const N: usize>(
    sys: &LinearSystem<N>,
    v0: f64,
    omega0: f64,
    vec0: &[(f64, f64)],
    rel_tol: f64,
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
    let a0: Vec<f64> = vec0.iter().map(|z| z.0 / norm).collect();
    let b0: Vec<f64> = vec0.iter().map(|z| z.1 / norm).collect();
    let m = 2 * N + 2;
    let mut a = a0.clone();
    let mut b = b0.clone();
    let (mut omega, mut v) = (omega0, v0);
    let mut jac = DMatrix::<f64>::zeros(m, m);
    let mut res = DVector::<f64>::zeros(m);
    for _ in 0..40 {
        let j = sys.jacobian(v);
        let dj = sys.j1 * (-1.0 / (v * v));
        res.fill(0.0);
        jac.fill(0.0);
        for r in 0..N {
            let (mut ja, mut jb, mut dja, mut djb) = (0.0, 0.0, 0.0, 0.0);
            for c in 0..N {
                ja += j[(r, c)] * a[c];
                jb += j[(r, c)] * b[c];
                dja += dj[(r, c)] * a[c];
                djb += dj[(r, c)] * b[c];
                jac[(r, c)] = j[(r, c)];
                jac[(N + r, N + c)] = j[(r, c)];
            }
            res[r] = ja + omega * b[r];
            res[N + r] = jb - omega * a[r];
            jac[(r, N + r)] = omega;
            jac[(N + r, r)] = -omega;
            jac[(r, 2 * N)] = b[r];
            jac[(N + r, 2 * N)] = -a[r];
            jac[(r, 2 * N + 1)] = dja;
            jac[(N + r, 2 * N + 1)] = djb;
            jac[(2 * N, r)] = a0[r];
            jac[(2 * N, N + r)] = b0[r];
            jac[(2 * N + 1, r)] = -b0[r];
            jac[(2 * N + 1, N + r)] = a0[r];
        }
        let dot = |x: &[f64], y: &[f64]| x.iter().zip(y).map(|(p, q)| p * q).sum::<f64>();
        res[2 * N] = dot(&a0, &a) + dot(&b0, &b) - 1.0;
        res[2 * N + 1] = dot(&a0, &b) - dot(&b0, &a);
        let step = jac.clone().lu().solve(&res)?;
        if !step.iter().all(|s| s.is_finite()) {
            return None;
        }
        for k in 0..N {
            a[k] -= step[k];
            b[k] -= step[N + k];
        }
        omega -= step[2 * N];
        // a step may not cross V = 0 (the model is singular there)
        let dv = step[2 * N + 1].clamp(-0.5 * v, 0.5 * v);
        v -= dv;
        if dv.abs() <= rel_tol * v && step[2 * N].abs() <= 1e-9 * omega.abs().max(1e-12) {
            return (omega > 0.0 && v > 0.0).then_some(HopfPoint {
                speed: v,
                omega,
                last_step: dv.abs(),
            });
        }
    }
    None
}
