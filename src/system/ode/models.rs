//! Reference problems whose answers are known in closed form, shared by the tests and the
//! bench (and available to the shooting code's tests).

use nalgebra::{SMatrix, SVector, Vector2};

use super::VectorField;

/// $\dot x = A x$: $x(t) = e^{At} x_0$, $\Phi(t) = e^{At}$. The parameter is unused.
#[derive(Clone, Copy, Debug)]
pub struct Linear<const N: usize> {
    pub a: SMatrix<f64, N, N>,
}

impl<const N: usize> VectorField<N> for Linear<N> {
    fn rhs(&self, x: &SVector<f64, N>, _p: f64) -> SVector<f64, N> {
        self.a * x
    }
    fn jacobian(&self, _x: &SVector<f64, N>, _p: f64) -> SMatrix<f64, N, N> {
        self.a
    }
}

/// The Stuart–Landau oscillator (Hopf normal form), parameter $p = \mu$:
/// $\dot x = \mu x - \omega y - x(x^2 + y^2)$, $\dot y = \omega x + \mu y - y(x^2 + y^2)$,
/// i.e. $\dot r = r(\mu - r^2)$, $\dot\theta = \omega$. For $\mu > 0$ it has a stable cycle of
/// radius $\sqrt\mu$ and period $T = 2\pi/\omega$, with Floquet multipliers $1$ (along the
/// flow) and $e^{-2\mu T}$ (radial).
#[derive(Clone, Copy, Debug)]
pub struct StuartLandau {
    /// Angular frequency $\omega$ (rad per time unit).
    pub omega: f64,
}

impl StuartLandau {
    /// $T = 2\pi/\omega$.
    pub fn period(&self) -> f64 {
        std::f64::consts::TAU / self.omega
    }
    /// Cycle radius $\sqrt\mu$.
    pub fn radius(&self, mu: f64) -> f64 {
        mu.sqrt()
    }
    /// The non-trivial Floquet multiplier $e^{-2\mu T}$.
    pub fn radial_multiplier(&self, mu: f64) -> f64 {
        (-2.0 * mu * self.period()).exp()
    }
}

impl VectorField<2> for StuartLandau {
    fn rhs(&self, x: &Vector2<f64>, mu: f64) -> Vector2<f64> {
        let (u, v, w) = (x[0], x[1], self.omega);
        let r2 = u * u + v * v;
        Vector2::new(mu * u - w * v - u * r2, w * u + mu * v - v * r2)
    }
    fn jacobian(&self, x: &Vector2<f64>, mu: f64) -> SMatrix<f64, 2, 2> {
        let (u, v, w) = (x[0], x[1], self.omega);
        let r2 = u * u + v * v;
        SMatrix::<f64, 2, 2>::new(
            mu - r2 - 2.0 * u * u,
            -w - 2.0 * u * v,
            w - 2.0 * u * v,
            mu - r2 - 2.0 * v * v,
        )
    }
}

/// A caricature of flange contact: $\ddot u = -F(u)$ with the dead-band spring
/// $F(u) = k_1 u + k_2 \max(0, |u| - c)\,\mathrm{sign}(u)$, state $(u, \dot u)$. $F$ is
/// continuous, its slope jumps at $|u| = c$: switching functions $u - c$ and $u + c$. The
/// energy $E = \tfrac12\dot u^2 + \tfrac12 k_1 u^2 + \tfrac12 k_2 \max(0, |u| - c)^2$ is
/// conserved. The parameter is unused.
#[derive(Clone, Copy, Debug)]
pub struct DeadBand {
    /// Stiffness inside the dead band (1/time²).
    pub k1: f64,
    /// Added stiffness in contact (1/time²).
    pub k2: f64,
    /// Half-width of the dead band $c$ (units of $u$).
    pub clearance: f64,
}

impl DeadBand {
    fn excess(&self, u: f64) -> f64 {
        (u.abs() - self.clearance).max(0.0)
    }

    /// $E(u, \dot u)$.
    pub fn energy(&self, x: &Vector2<f64>) -> f64 {
        let e = self.excess(x[0]);
        0.5 * (x[1] * x[1] + self.k1 * x[0] * x[0] + self.k2 * e * e)
    }

    /// For a start at $u = 0$ with speed $v_0 > 0$: the time to first contact
    /// $t_1 = \arcsin(c/A)/\omega_1$ ($\omega_1 = \sqrt{k_1}$, $A = v_0/\omega_1$) and the
    /// duration of one contact $t_2 = (\pi - 2\varphi)/\omega_2$, where in contact
    /// $u - u_e$ oscillates at $\omega_2 = \sqrt{k_1 + k_2}$ about $u_e = k_2 c/(k_1 + k_2)$,
    /// entering at $u_0 = c - u_e$ with speed $v_c = \omega_1\sqrt{A^2 - c^2}$ and phase
    /// $\varphi = \operatorname{atan2}(u_0\,\omega_2, v_c)$. `None` if $A \le c$ (no contact).
    /// The half period is $2t_1 + t_2$.
    pub fn contact_times(&self, v0: f64) -> Option<(f64, f64)> {
        let (w1, w2, c) = (self.k1.sqrt(), (self.k1 + self.k2).sqrt(), self.clearance);
        let amp = v0 / w1;
        if amp <= c {
            return None;
        }
        let t1 = (c / amp).asin() / w1;
        let vc = w1 * (amp * amp - c * c).sqrt();
        let u0 = c * self.k1 / (self.k1 + self.k2);
        let phi = (u0 * w2).atan2(vc);
        Some((t1, (std::f64::consts::PI - 2.0 * phi) / w2))
    }
}

impl VectorField<2> for DeadBand {
    fn rhs(&self, x: &Vector2<f64>, _p: f64) -> Vector2<f64> {
        let force = self.k1 * x[0] + self.k2 * self.excess(x[0]) * x[0].signum();
        Vector2::new(x[1], -force)
    }
    fn jacobian(&self, x: &Vector2<f64>, _p: f64) -> SMatrix<f64, 2, 2> {
        let k = if x[0].abs() > self.clearance {
            self.k1 + self.k2
        } else {
            self.k1
        };
        SMatrix::<f64, 2, 2>::new(0.0, 1.0, -k, 0.0)
    }
    fn switch_count(&self) -> usize {
        2
    }
    fn switch_value(&self, k: usize, x: &Vector2<f64>) -> f64 {
        if k == 0 {
            x[0] - self.clearance
        } else {
            x[0] + self.clearance
        }
    }
}
