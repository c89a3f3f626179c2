//! Creep forces: Kalker's linear theory and the Shen–Hedrick–Elkins saturation (docs/model.md §5).

use crate::contact::kalker::CreepCoefficients;
use crate::system::scalar::Scalar;

/// Which creep law turns creepages into forces.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum CreepLaw {
    /// Kalker's linear theory, unbounded.
    Kalker,
    /// Kalker's forces scaled by the Shen–Hedrick–Elkins factor ε(β), friction μ (–).
    Shen {
        /// wheel–rail friction coefficient μ (–)
        friction: f64,
    },
}

impl CreepLaw {
    /// Short name as used in study files and outputs.
    pub fn name(&self) -> &'static str {
        match self {
            CreepLaw::Kalker => "kalker",
            CreepLaw::Shen { .. } => "shen",
        }
    }
}

/// Creepages of one wheel: longitudinal ξ_x (–), lateral ξ_y (–), spin ω (1/m).
#[derive(Clone, Copy, Debug)]
pub struct Creepage<T> {
    pub long: T,
    pub lat: T,
    pub spin: T,
}

/// Creep forces on one wheel: F_x, F_y (N) and the spin moment M_z (N m).
#[derive(Clone, Copy, Debug)]
pub struct CreepForce<T> {
    pub fx: T,
    pub fy: T,
    pub mz: T,
}

/// Kalker's linear law:
/// $F_x = −f_{11}ξ_x$, $F_y = −f_{22}ξ_y − f_{23}ω$, $M_z = f_{23}ξ_y − f_{33}ω$.
#[inline]
pub fn kalker<T: Scalar>(c: &CreepCoefficients<T>, s: &Creepage<T>) -> CreepForce<T> {
    CreepForce {
        fx: -(c.f11 * s.long),
        fy: -(c.f22 * s.lat) - c.f23 * s.spin,
        mz: c.f23 * s.lat - c.f33 * s.spin,
    }
}

/// The Shen–Hedrick–Elkins factor
/// $ε(β) = 1 − β/3 + β²/27$ for $β < 3$, $1/β$ for $β ≥ 3$ (C¹ at β = 3).
#[inline]
pub fn shen_factor<T: Scalar>(beta: T) -> T {
    if beta.re() < 3.0 {
        beta * beta * (1.0 / 27.0) - beta * (1.0 / 3.0) + 1.0
    } else {
        beta.recip()
    }
}

/// Scales Kalker's forces by ε(β), $β = \sqrt{F_x² + F_y²}/(μN)$; `mu_n` = μN (N).
#[inline]
pub fn shen<T: Scalar>(f: CreepForce<T>, mu_n: T) -> CreepForce<T> {
    let beta = T::hypot0(f.fx, f.fy) / mu_n;
    let eps = shen_factor(beta);
    CreepForce {
        fx: f.fx * eps,
        fy: f.fy * eps,
        mz: f.mz * eps,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::system::scalar::derivative;

    #[test]
    fn shen_factor_is_c1_at_three() {
        let (l, dl) = derivative(shen_factor, 3.0 - 1e-12);
        let (r, dr) = derivative(shen_factor, 3.0 + 1e-12);
        assert!(
            (l - r).abs() < 1e-11 && (dl - dr).abs() < 1e-10,
            "{l} {r} {dl} {dr}"
        );
        // value 1/3, slope −1/9 at β = 3 from both sides
        assert!((r - 1.0 / 3.0).abs() < 1e-11 && (dr + 1.0 / 9.0).abs() < 1e-10);
    }

    #[test]
    fn shen_resultant_is_johnson_vermeulen() {
        // |F| ε(β) = μN (β − β²/3 + β³/27) below saturation, and μN above.
        let mu_n = 1000.0;
        for beta in [0.1, 1.0, 2.5, 3.5, 10.0] {
            let f = CreepForce {
                fx: 0.6 * beta * mu_n,
                fy: 0.8 * beta * mu_n,
                mz: 1.0,
            };
            let s = shen(f, mu_n);
            let resultant = s.fx.hypot(s.fy);
            let expect = if beta < 3.0 {
                mu_n * (beta - beta * beta / 3.0 + beta.powi(3) / 27.0)
            } else {
                mu_n
            };
            assert!((resultant - expect).abs() < 1e-9 * mu_n, "β={beta}");
        }
    }
}
