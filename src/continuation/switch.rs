//! Branch switching: the start and direction of the branch of cycles that a
//! symmetry-breaking or a period-doubling point opens.
//!
//! * **Symmetry breaking** on a branch of symmetric cycles (half-period shooting): the
//!   half-period map has a multiplier ν = −1 with eigenvector $v$. The cycle is also a solution
//!   of the full-period problem $φ_T(x_0) − x_0 = 0$, whose monodromy $Φ_T = (−Φ_{T/2})^2$ then
//!   has the double multiplier 1 (eigenvectors $f(x_0)$ and $v$): a pitchfork, whose new branch
//!   leaves along $(v, 0, 0)$ in $(x_0, T, p)$. Its cycles are asymmetric; $−v$ gives the mirror
//!   branch $−x(t + T/2)$, the same cycles seen in the mirror, so one direction is continued.
//! * **Period doubling** on a branch of full-period cycles: $Φ_T$ has μ = −1 with eigenvector
//!   $w$; the problem of period $2T$ has the double multiplier $μ^2 = 1$ and its new branch
//!   leaves along $(w, 0, 0)$ from $(x_0, 2T, p)$. $−w$ gives the same cycles shifted by T.
//!
//! The direction is made orthogonal to the flow $f(x_0)$ (a shift of phase, which the phase
//! condition removes anyway) and, in the scaled metric of the continuation, to the parent's
//! tangent, so that the first corrector's arclength plane cannot meet the parent branch near
//! the point. The eigenvector comes from inverse iteration on the shooting monodromy.

use nalgebra::{DMatrix, DVector, SMatrix};

use super::branch::{Rejoin, SpecialKind, SpecialPoint};
use super::orbit::{OrbitPoint, Shooting};
use crate::system::ode::VectorField;

/// Where a new branch starts and where it goes.
#[derive(Clone, Debug, PartialEq)]
pub struct Switch<const N: usize> {
    /// the first orbit (the parent's located orbit, with the period of the new problem: the
    /// same T for symmetry breaking, 2T for period doubling); full-period shooting
    pub start: OrbitPoint<N>,
    /// unit direction in the continuation's scaled units
    pub direction: DVector<f64>,
    /// how the new branch recognises its return to the parent
    pub rejoin: Rejoin,
    /// the critical multiplier found there (ν for symmetry breaking, μ for period doubling);
    /// −1 at an exactly located point
    pub multiplier: f64,
    /// the period factor of the new problem against the parent's (1 or 2)
    pub period_factor: usize,
}

/// Why no branch could be switched to.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum SwitchError {
    /// only symmetry breaking (on a symmetric branch) and period doubling (on a full-period
    /// branch) open new branches of cycles here
    #[error("no branch of cycles to switch to at a {kind} point of a {} branch", if *.symmetric { "symmetric" } else { "full-period" })]
    Kind { kind: &'static str, symmetric: bool },
    /// the shooting problem could not be integrated at the point
    #[error("the orbit at {param} could not be integrated: {message}")]
    Integration { param: f64, message: String },
    /// no real multiplier near −1 at the point (a badly located point)
    #[error("no real multiplier near -1 at {param} (nearest {nearest})")]
    NoMultiplier { param: f64, nearest: f64 },
    /// inverse iteration failed (singular or non-finite)
    #[error("the critical eigenvector at {param} could not be computed")]
    Eigenvector { param: f64 },
}

/// The branch that the special point `sp` of the branch of `shooting` opens. `scale`: the
/// continuation's scales of $(x_0, T, p)$ for the **new** problem; `parent_tangent`: the
/// parent's unit tangent at the point (scaled, in the parent's units: its T entry is
/// rescaled by the period factor here).
pub fn switch_at<const N: usize, F: VectorField<N>>(
    shooting: &Shooting<'_, N, F>,
    sp: &SpecialPoint<N>,
    scale: &[f64],
    parent_tangent: Option<&DVector<f64>>,
) -> Result<Switch<N>, SwitchError> {
    let (rejoin, period_factor) = match (sp.kind, shooting.symmetric) {
        (SpecialKind::SymmetryBreaking, true) => (Rejoin::Mirror, 1),
        (SpecialKind::PeriodDoubling, false) => (Rejoin::Shift, 2),
        (kind, symmetric) => {
            return Err(SwitchError::Kind {
                kind: kind.name(),
                symmetric,
            })
        }
    };
    let z = sp.orbit;
    let lin = shooting
        .linearise(&z)
        .map_err(|e| SwitchError::Integration {
            param: z.param,
            message: e.to_string(),
        })?;
    // the shooting map's monodromy: −Φ_{T/2} (symmetric) or Φ_T
    let sign = if shooting.symmetric { -1.0 } else { 1.0 };
    let a: SMatrix<f64, N, N> = lin.monodromy * sign;
    let lambda = real_eigenvalue_near(&a, -1.0).ok_or(SwitchError::NoMultiplier {
        param: z.param,
        nearest: f64::NAN,
    })?;
    if (lambda + 1.0).abs() > 0.2 {
        return Err(SwitchError::NoMultiplier {
            param: z.param,
            nearest: lambda,
        });
    }
    let v = inverse_iteration(&a, lambda).ok_or(SwitchError::Eigenvector { param: z.param })?;
    // no component along the flow (a phase shift)
    let f = shooting.field.rhs(&z.x0, z.param);
    let ff = f.dot(&f);
    let v = if ff > 0.0 {
        v - f * (v.dot(&f) / ff)
    } else {
        v
    };
    let s = |i: usize| scale.get(i).copied().unwrap_or(1.0);
    let mut d = DVector::from_fn(N + 2, |i, _| if i < N { v[i] / s(i) } else { 0.0 });
    if let Some(t) = parent_tangent.filter(|t| t.len() == N + 2) {
        let mut t = t.clone();
        t[N] /= period_factor as f64;
        let tt = t.dot(&t);
        if tt > 0.0 {
            d -= &t * (d.dot(&t) / tt);
        }
    }
    let n = d.norm();
    if !(n.is_finite() && n > 0.0) {
        return Err(SwitchError::Eigenvector { param: z.param });
    }
    Ok(Switch {
        start: OrbitPoint {
            period: z.period * period_factor as f64,
            ..z
        },
        direction: d / n,
        rejoin,
        multiplier: lambda,
        period_factor,
    })
}

/// The real eigenvalue of `a` nearest `target`, if `a` has a real one.
fn real_eigenvalue_near<const N: usize>(a: &SMatrix<f64, N, N>, target: f64) -> Option<f64> {
    let m = DMatrix::from_fn(N, N, |i, j| a[(i, j)]);
    let eig = crate::stability::eigenvalues_dense(&m)?;
    eig.iter()
        .filter(|v| v.im.abs() <= 1e-9 * v.norm().max(1e-300))
        .map(|v| v.re)
        .min_by(|x, y| (x - target).abs().total_cmp(&(y - target).abs()))
}

/// The eigenvector of `a` for its real eigenvalue `lambda`, by three steps of inverse iteration
/// with a shift a little off `lambda` (the shifted matrix is nearly singular by design: the
/// solve's error lies along the wanted vector).
fn inverse_iteration<const N: usize>(
    a: &SMatrix<f64, N, N>,
    lambda: f64,
) -> Option<nalgebra::SVector<f64, N>> {
    let shift = lambda + 1e-10 * lambda.abs().max(1.0);
    let lu = DMatrix::from_fn(N, N, |i, j| a[(i, j)] - if i == j { shift } else { 0.0 }).lu();
    // a start with a component along every eigenvector, in general
    let mut v = DVector::from_fn(N, |i, _| 1.0 + 0.1 * i as f64);
    for _ in 0..3 {
        let w = lu.solve(&v)?;
        let n = w.norm();
        if !(n.is_finite() && n > 0.0) {
            return None;
        }
        v = w / n;
    }
    let v = nalgebra::SVector::<f64, N>::from_fn(|i, _| v[i]);
    // the residual shows whether it converged
    let r = (a * v - v * lambda).norm();
    (r <= 1e-6 * a.norm().max(1.0)).then_some(v)
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Matrix3;

    #[test]
    fn inverse_iteration_finds_the_eigenvector_of_a_real_eigenvalue() {
        // eigenvalues -1, 0.5, 2 with known eigenvectors (columns of p)
        let p = Matrix3::new(1.0, 0.2, 0.0, 0.3, 1.0, 0.1, 0.0, 0.4, 1.0);
        let d = Matrix3::from_diagonal(&nalgebra::Vector3::new(-1.0, 0.5, 2.0));
        let a = p * d * p.try_inverse().expect("invertible");
        let lambda = real_eigenvalue_near(&a, -0.9).expect("a real eigenvalue");
        assert!((lambda + 1.0).abs() < 1e-12, "{lambda}");
        let v = inverse_iteration(&a, lambda).expect("converges");
        let e = p.column(0).normalize();
        assert!((v.dot(&e).abs() - 1.0).abs() < 1e-10, "{v} {e}");
    }
}
