//! Periodic orbits by single shooting, with the period and the parameter as unknowns.
//!
//! For a vector field $\dot x = f(x; p)$ with flow $φ_t(x; p)$ a periodic orbit through $x_0$
//! with period $T$ satisfies $φ_T(x_0) − x_0 = 0$. When the field is odd, $f(−x) = −f(x)$ (the
//! wheelset on tangent track, MODEL §9), the primary cycles are *symmetric*,
//! $x(t + T/2) = −x(t)$, and the half-period condition $φ_{T/2}(x_0) + x_0 = 0$ is used instead:
//! half the integration, and the symmetry is exact. Its multipliers $ν$ (eigenvalues of
//! $−Φ_{T/2}$) give the full Floquet multipliers $μ = ν^2$, and tell symmetry breaking
//! ($ν = −1$, $μ = 1$) from a fold ($ν = +1$).
//!
//! The phase is fixed by the Poincaré condition $⟨f(x_r), x_0 − x_r⟩ = 0$ through a reference
//! point $x_r$ (the previous orbit's start).

use nalgebra::{Complex, DMatrix, DVector, SMatrix, SVector};

use crate::system::ode::{integrate, integrate_with_peaks, OdeError, OdeOptions, VectorField};

/// The shooting problem: a vector field, whether to use the symmetric half-period form, and
/// the integrator options.
pub struct Shooting<'a, const N: usize, F: VectorField<N>> {
    /// the vector field
    pub field: &'a F,
    /// use $φ_{T/2}(x_0) + x_0 = 0$ (requires an odd field)
    pub symmetric: bool,
    /// integrator options (tolerances); the monodromy flag is set internally
    pub ode: OdeOptions,
    /// run the two independent integrations of each Newton step (flow with monodromy, and
    /// the parameter perturbation) on two rayon threads; the results are bitwise identical
    /// to the serial run because the two are pure and independent
    pub parallel: bool,
    /// relative step of the one-sided difference for ∂φ/∂p; about √rtol balances truncation
    /// against integration noise. Its error only affects the Newton rate and the predictor,
    /// never the converged orbits, nor the folds (where the (x0, T) block is singular).
    pub dp_rel: f64,
}

/// End state, monodromy (when asked for), integrator steps and the largest |x_k| over the
/// interval of one flow evaluation.
type Flowed<const N: usize> = (
    SVector<f64, N>,
    Option<SMatrix<f64, N, N>>,
    usize,
    SVector<f64, N>,
);

/// One point of an orbit computation: the start, period and parameter.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OrbitPoint<const N: usize> {
    /// start of the orbit on the phase section
    pub x0: SVector<f64, N>,
    /// period T
    pub period: f64,
    /// parameter p
    pub param: f64,
}

/// The residual and its Jacobian with respect to (x0, T, p), as an N × (N + 2) matrix.
pub struct Linearised<const N: usize> {
    /// $G(x_0, T, p)$
    pub residual: SVector<f64, N>,
    /// $[∂G/∂x_0 \;|\; ∂G/∂T \;|\; ∂G/∂p]$
    pub jacobian: DMatrix<f64>,
    /// the (half-period when symmetric) monodromy $Φ$
    pub monodromy: SMatrix<f64, N, N>,
    /// state at the end of the shooting interval
    pub end: SVector<f64, N>,
    /// integrator steps used
    pub steps: usize,
    /// the largest $|x_k|$ over the shooting interval, per component (located on the
    /// integrator's continuous extension); for a symmetric orbit the half period holds the
    /// maximum over the whole period
    pub peaks: SVector<f64, N>,
}

impl<'a, const N: usize, F: VectorField<N>> Shooting<'a, N, F> {
    fn horizon(&self, period: f64) -> f64 {
        if self.symmetric {
            0.5 * period
        } else {
            period
        }
    }

    fn flow(
        &self,
        x0: &SVector<f64, N>,
        period: f64,
        p: f64,
        monodromy: bool,
    ) -> Result<Flowed<N>, OdeError> {
        let opts = OdeOptions {
            monodromy,
            ..self.ode
        };
        if monodromy {
            let (s, peaks) = integrate_with_peaks(self.field, p, x0, self.horizon(period), &opts)?;
            Ok((s.x, s.monodromy, s.stats.steps, peaks))
        } else {
            let s = integrate(self.field, p, x0, self.horizon(period), &opts)?;
            Ok((s.x, s.monodromy, s.stats.steps, SVector::zeros()))
        }
    }

    fn residual_of(&self, x0: &SVector<f64, N>, end: &SVector<f64, N>) -> SVector<f64, N> {
        if self.symmetric {
            end + x0
        } else {
            end - x0
        }
    }

    /// The shooting residual and its Jacobian at `z`.
    pub fn linearise(&self, z: &OrbitPoint<N>) -> Result<Linearised<N>, OdeError> {
        // ∂φ/∂p by a one-sided difference: the integrator has no parameter sensitivities, and
        // one extra integration instead of two is worth the O(h) error in a Newton column
        // (it changes the convergence rate slightly, not the converged orbit).
        let h = self.dp_rel * z.param.abs().max(1.0);
        let main = || self.flow(&z.x0, z.period, z.param, true);
        let shifted = || self.flow(&z.x0, z.period, z.param + h, false);
        let (a, b) = if self.parallel {
            rayon::join(main, shifted)
        } else {
            (main(), shifted())
        };
        let (end, phi, steps, peaks) = a?;
        let (plus, _, _, _) = b?;
        let phi = phi.ok_or(OdeError::NonFinite { t: 0.0 })?;
        let residual = self.residual_of(&z.x0, &end);
        let sign = if self.symmetric { 1.0 } else { -1.0 };
        let d_x0 = phi + SMatrix::<f64, N, N>::identity() * sign;
        let d_t = self.field.rhs(&end, z.param) * (self.horizon(1.0));
        let d_p = (plus - end) / h;
        let mut jacobian = DMatrix::zeros(N, N + 2);
        jacobian.view_mut((0, 0), (N, N)).copy_from(&d_x0);
        jacobian.view_mut((0, N), (N, 1)).copy_from(&d_t);
        jacobian.view_mut((0, N + 1), (N, 1)).copy_from(&d_p);
        Ok(Linearised {
            residual,
            jacobian,
            monodromy: phi,
            end,
            steps,
            peaks,
        })
    }
}

/// Floquet multipliers of an orbit from its shooting monodromy.
#[derive(Clone, Debug, PartialEq)]
pub struct Floquet {
    /// the full-period multipliers μ, sorted by decreasing modulus
    pub multipliers: Vec<Complex<f64>>,
    /// for symmetric orbits the half-period multipliers ν (μ = ν²), same order
    pub half: Option<Vec<Complex<f64>>>,
    /// distance of the multiplier nearest to 1 from 1: the accuracy figure
    pub trivial_error: f64,
    /// largest modulus of the others (the orbit is stable when < 1)
    pub max_nontrivial: f64,
}

impl Floquet {
    /// Multipliers from the shooting monodromy (`symmetric`: $Φ_{T/2}$, else $Φ_T$).
    pub fn from_monodromy<const N: usize>(phi: &SMatrix<f64, N, N>, symmetric: bool) -> Self {
        let m = DMatrix::from_fn(
            N,
            N,
            |i, j| if symmetric { -phi[(i, j)] } else { phi[(i, j)] },
        );
        let mut eig: Vec<Complex<f64>> = m.complex_eigenvalues().iter().copied().collect();
        eig.sort_by(|a, b| b.norm().total_cmp(&a.norm()));
        let (mu, half) = if symmetric {
            // |ν²| keeps the order of |ν|, so μ stays sorted and paired with ν
            let mu: Vec<Complex<f64>> = eig.iter().map(|v| v * v).collect();
            (mu, Some(eig.clone()))
        } else {
            (eig.clone(), None)
        };
        // The trivial multiplier: ν (or μ) closest to +1.
        let trivial = eig
            .iter()
            .enumerate()
            .min_by(|a, b| (a.1 - 1.0).norm().total_cmp(&(b.1 - 1.0).norm()))
            .map(|(k, _)| k)
            .unwrap_or(0);
        let trivial_error = eig.get(trivial).map_or(f64::NAN, |v| (v - 1.0).norm());
        let max_nontrivial = mu
            .iter()
            .enumerate()
            .filter(|(k, _)| *k != trivial)
            .map(|(_, v)| v.norm())
            .fold(0.0, f64::max);
        Floquet {
            multipliers: mu,
            half,
            trivial_error,
            max_nontrivial,
        }
    }

    /// All nontrivial multipliers inside the unit circle.
    pub fn stable(&self) -> bool {
        self.max_nontrivial < 1.0
    }
}

/// Why a Newton correction stopped.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum NewtonStop {
    /// the scaled update fell below the tolerance
    Converged,
    /// the iteration limit was reached
    MaxIterations,
    /// the bordered Jacobian was singular
    Singular,
    /// the residual or update became NaN/inf, or the integrator failed
    Diverged,
}

/// Solves the dense (N+2)×(N+2) bordered system; `None` when singular.
pub fn solve_dense(a: DMatrix<f64>, b: DVector<f64>) -> Option<DVector<f64>> {
    let lu = a.lu();
    let x = lu.solve(&b)?;
    x.iter().all(|v| v.is_finite()).then_some(x)
}
