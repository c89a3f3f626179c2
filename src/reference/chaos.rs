//! The Lorenz system, whose largest Lyapunov exponent is known: the reference for the
//! attractor search's chaos test ([`crate::attractors::classify::largest_lyapunov`]).

use nalgebra::{SMatrix, SVector};

use crate::system::ode::VectorField;

/// $\dot x = σ(y − x)$, $\dot y = x(ρ − z) − y$, $\dot z = xy − βz$ with parameter ρ. At
/// σ = 10, β = 8/3, ρ = 28 the largest Lyapunov exponent is 0.9056 (Sprott, *Chaos and
/// Time-Series Analysis*, Oxford 2003, Table A.1; 0.9056 ± 0.0003 by several authors). The
/// field is odd in (x, y) only, not in z: not a model of the wheelset's symmetry.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Lorenz {
    /// σ
    pub sigma: f64,
    /// β
    pub beta: f64,
}

impl VectorField<3> for Lorenz {
    fn rhs(&self, x: &SVector<f64, 3>, rho: f64) -> SVector<f64, 3> {
        SVector::<f64, 3>::new(
            self.sigma * (x[1] - x[0]),
            x[0] * (rho - x[2]) - x[1],
            x[0] * x[1] - self.beta * x[2],
        )
    }
    fn jacobian(&self, x: &SVector<f64, 3>, rho: f64) -> SMatrix<f64, 3, 3> {
        SMatrix::<f64, 3, 3>::new(
            -self.sigma,
            self.sigma,
            0.0,
            rho - x[2],
            -1.0,
            -x[0],
            x[1],
            x[0],
            -self.beta,
        )
    }
}
