//! Time integration of $\dot x = f(x; p)$ with the monodromy matrix and switching surfaces.
//!
//! **Method.** Dormand–Prince 5(4) (Dormand & Prince 1980; Hairer, Nørsett & Wanner, *Solving
//! ODEs I*, §II.5): 7 stages, FSAL (6 field evaluations a step), local extrapolation (the
//! 5th-order solution is propagated), Shampine's 4th-order continuous extension (§II.6) for
//! sampling, event and section location, and DOPRI5's PI step-size controller (§II.4). Error
//! norm: the RMS of $e_i / (\mathrm{atol} + \mathrm{rtol}\max(|x_{0,i}|, |x_{1,i}|))$.
//! [`OdeOptions::method`] may choose Dormand and Prince's 8(5,3) pair instead (Hairer's DOP853,
//! `dop853.rs`: 12 evaluations a step, a 7th-order continuous extension at 3 more, DOP853's
//! controller): fewer evaluations at tight tolerances on smooth fields, more where the
//! Jacobian jumps. Steps that land on a switching surface are the 5th-order pair's either way.
//!
//! **Monodromy.** With [`OdeOptions::monodromy`] the variational equations
//! $\dot\Phi = J(x(t))\,\Phi$, $\Phi(0) = I$, are integrated with the *same* stages as $x$
//! ($J$ evaluated at each stage's $x$): this is the exact derivative of the discrete flow, and
//! $\Phi$ is in the error test (the max of the state's scaled RMS norm and $\Phi$'s, each entry
//! of $\Phi$ relative to the largest entry of its column: a column is the response to one
//! initial perturbation, and needs to be accurate relative to its size), so
//! $\Phi(t) = \partial x(t)/\partial x_0$ is as accurate as $x$.
//!
//! **Switching surfaces.** A field may declare functions $g_k(x)$ across which it is not
//! smooth. No accepted step straddles one: a trial step that crosses is replaced by a
//! re-taken step ending on the surface (a few ulps of $t$ past it; located by Brent's method
//! on the dense output, then an Illinois iteration on re-taken steps), and integration
//! restarts on the other side, with the new side's Jacobian in the first stage (see
//! `events.rs`). The fields of this crate are *continuous* across their surfaces (the flange
//! spring with its dead band: only $J$ jumps), so the state needs no reset and $\Phi$ needs no
//! saltation matrix: the saltation matrix
//! $S = I + (f^+ - f^-)\,\nabla g^{\mathsf T} / (\nabla g \cdot f^-)$ is the identity when
//! $f^+ = f^-$. A field with a *discontinuous* $f$ would need $S$ applied at each crossing,
//! which this module does not do. A surface crossed twice within one step (a graze shorter
//! than a step) is not seen; bound the step with [`OdeOptions::h_max`] if that matters.
//!
//! **Why hand-written on fixed-size nalgebra types.** The wheelset has 4 states and parameter
//! sweeps take millions of steps: with `SVector`/`SMatrix` every stage lives on the stack,
//! the step loop never allocates, and the compiler unrolls the 4×4 products. General ODE
//! crates work on heap vectors and do not integrate the variational equations with shared
//! stages or stop steps on switching surfaces.

mod dop853;
mod dopri;
mod driver;
mod events;
pub mod models;
#[cfg(test)]
mod tests;
#[cfg(test)]
mod tests_dop853;
#[cfg(test)]
mod tests_events;

use nalgebra::{SMatrix, SVector};

pub use driver::{
    integrate, integrate_observed, integrate_partial, integrate_sections, integrate_tangent,
    integrate_to_section, integrate_with_extremes, integrate_with_peaks, step_times,
    tangent_on_steps, Return, TangentControl,
};

/// An autonomous vector field $\dot x = f(x; p)$ with its exact Jacobian.
pub trait VectorField<const N: usize>: Sync {
    /// $f(x; p)$; $p$ is a scalar parameter (the speed, m/s, for the wheelset).
    fn rhs(&self, x: &SVector<f64, N>, p: f64) -> SVector<f64, N>;
    /// The exact Jacobian $\partial f / \partial x$ at $(x; p)$.
    fn jacobian(&self, x: &SVector<f64, N>, p: f64) -> SMatrix<f64, N, N>;
    /// $f$ and $J$ together (what each stage of the variational equations needs). The default
    /// calls [`rhs`](Self::rhs) and [`jacobian`](Self::jacobian); a field whose Jacobian comes
    /// with its value (forward-mode dual numbers) overrides it to evaluate the model once.
    fn rhs_jacobian(&self, x: &SVector<f64, N>, p: f64) -> (SVector<f64, N>, SMatrix<f64, N, N>) {
        (self.rhs(x, p), self.jacobian(x, p))
    }
    /// $f$ and the variational field $J\,\Phi$ at $(x; p)$ (each stage of the variational
    /// equations). The default is [`rhs_jacobian`](Self::rhs_jacobian) and a dense product; a
    /// second-order system $x = (q, \dot q)$, whose Jacobian's upper half is $[0 \; I]$,
    /// overrides it to copy that half of the product (half the work of the dense one).
    fn rhs_variational(
        &self,
        x: &SVector<f64, N>,
        p: f64,
        phi: &SMatrix<f64, N, N>,
    ) -> (SVector<f64, N>, SMatrix<f64, N, N>) {
        let (f, j) = self.rhs_jacobian(x, p);
        (f, j * phi)
    }
    /// $f$ and the directional derivative $J\,\xi$ at $(x; p)$ (a tangent flow's stage).
    /// The default forms $J$ ([`rhs_jacobian`](Self::rhs_jacobian)); a field with
    /// forward-mode dual numbers overrides it to carry the one direction only.
    fn rhs_tangent(
        &self,
        x: &SVector<f64, N>,
        p: f64,
        xi: &SVector<f64, N>,
    ) -> (SVector<f64, N>, SVector<f64, N>) {
        let (f, j) = self.rhs_jacobian(x, p);
        (f, j * xi)
    }
    /// Number of switching functions (surfaces where $f$ is not smooth); default 0.
    fn switch_count(&self) -> usize {
        0
    }
    /// Value of switching function `k` at `x`; a sign change is a crossing. Only called for
    /// `k < switch_count()`. It must change sign exactly where `rhs` and `jacobian` change
    /// branch (write both from the same expression, e.g. `y.abs() - clearance` and
    /// `y.abs() > clearance`): a point strictly on one side must get that side's Jacobian.
    fn switch_value(&self, _k: usize, _x: &SVector<f64, N>) -> f64 {
        0.0
    }
}

/// Error tolerances of the step-size control.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Tolerances {
    /// Relative tolerance (dimensionless).
    pub rtol: f64,
    /// Absolute tolerance, in the state's own units, the same for every component (m, rad,
    /// m/s, rad/s for the wheelset) and for the dimensionless entries of $\Phi$.
    pub atol: f64,
}

impl Tolerances {
    /// Both finite and positive; `rtol >= 1e-14` because below that the error test asks for
    /// less than the round-off of one step (a few ulps) and step sizes collapse.
    pub fn new(rtol: f64, atol: f64) -> Result<Self, OdeError> {
        let ok = rtol.is_finite() && atol.is_finite() && rtol >= 1e-14 && atol > 0.0;
        if ok {
            Ok(Tolerances { rtol, atol })
        } else {
            Err(OdeError::BadTolerance { rtol, atol })
        }
    }
}

impl Default for Tolerances {
    /// rtol 1e-10 so that the monodromy matrix, and the Floquet multipliers from it, come out
    /// accurate to about 1e-9; atol 1e-12 (m for the wheelset) is 1e-9 of a 1 mm displacement,
    /// so the relative tolerance governs except near zero crossings of a component.
    fn default() -> Self {
        Tolerances {
            rtol: 1e-10,
            atol: 1e-12,
        }
    }
}

/// The explicit Runge–Kutta pair of an integration.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Method {
    /// Dormand–Prince 5(4), 6 evaluations a step, 4th-order continuous extension: the
    /// default, and the better choice at loose tolerances and on rough fields.
    #[default]
    DormandPrince5,
    /// Dormand–Prince 8(5,3) (Hairer's DOP853), 12 evaluations a step, 7th-order continuous
    /// extension at 3 more: fewer evaluations at tight tolerances on smooth fields.
    DormandPrince8,
}

/// Options of one integration; validated at the start of every call.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OdeOptions {
    /// Error tolerances. Default: rtol 1e-10, atol 1e-12 (see [`Tolerances::default`]).
    pub tol: Tolerances,
    /// First trial step (time units of the field: s for the wheelset). Default `None`: chosen
    /// from the field by HNW's starting-step algorithm (one extra evaluation).
    pub h_initial: Option<f64>,
    /// Largest step (time units of the field). Default $\infty$: accuracy alone decides; set it
    /// below the shortest excursion across a switching surface that must not be missed.
    pub h_max: f64,
    /// Largest number of trial steps (accepted plus rejected). Default 1 000 000: far above
    /// any sensible run (a 30 s wheelset simulation takes ~1e4–1e5 steps at the default
    /// tolerances), so it only stops runaway integrations.
    pub max_steps: usize,
    /// Also integrate $\dot\Phi = J\Phi$ and return $\Phi(t)$. Default false (it costs a
    /// Jacobian and an $N\times N$ product per stage).
    pub monodromy: bool,
    /// The tolerances of $\Phi$'s error test are the state's times this factor (≥ 1).
    /// Default 1: $\Phi$ is solved to the state's tolerance, and its columns join the step
    /// control. A larger factor lets the steps be the trajectory's where $\Phi$'s fast modes
    /// would shorten them: Newton's Jacobian and the Floquet multipliers lose digits (about
    /// `factor × rtol`), the trajectory keeps its own. See `[bifurcation] floquet_rtol`.
    pub monodromy_tol_factor: f64,
    /// The Runge–Kutta pair. Default [`Method::DormandPrince5`].
    pub method: Method,
}

impl Default for OdeOptions {
    fn default() -> Self {
        OdeOptions {
            tol: Tolerances::default(),
            h_initial: None,
            h_max: f64::INFINITY,
            max_steps: 1_000_000,
            monodromy: false,
            monodromy_tol_factor: 1.0,
            method: Method::DormandPrince5,
        }
    }
}

impl OdeOptions {
    /// Checks every field (they are public, so [`Tolerances::new`] may have been bypassed).
    pub fn validate(&self) -> Result<(), OdeError> {
        Tolerances::new(self.tol.rtol, self.tol.atol)?;
        if self.h_max.is_nan() || self.h_max <= 0.0 {
            return Err(OdeError::BadArgument {
                name: "h_max",
                value: self.h_max,
                rule: "must be > 0 (may be inf)",
            });
        }
        if let Some(h) = self.h_initial {
            if !(h.is_finite() && h > 0.0) {
                return Err(OdeError::BadArgument {
                    name: "h_initial",
                    value: h,
                    rule: "must be finite and > 0",
                });
            }
        }
        if !(self.monodromy_tol_factor.is_finite() && self.monodromy_tol_factor >= 1.0) {
            return Err(OdeError::BadArgument {
                name: "monodromy_tol_factor",
                value: self.monodromy_tol_factor,
                rule: "must be finite and >= 1",
            });
        }
        if self.max_steps == 0 {
            return Err(OdeError::BadArgument {
                name: "max_steps",
                value: 0.0,
                rule: "must be >= 1",
            });
        }
        Ok(())
    }
}

/// Why an integration stopped.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StopReason {
    /// The end time (or, for [`integrate_to_section`], the section) was reached.
    Reached,
    /// [`OdeOptions::max_steps`] trial steps were taken.
    MaxSteps,
    /// The step size fell below 16 ulps of $t$: a singularity or extreme stiffness.
    StepTooSmall,
    /// The state or the field became NaN or infinite and smaller steps did not help.
    NonFinite,
}

/// Work done by one integration.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Stats {
    /// Accepted steps (including steps shortened to end on a switching surface).
    pub steps: usize,
    /// Steps rejected by the error test (or for a non-finite result).
    pub rejected: usize,
    /// Evaluations of $f$ (each with one of $J$ when the monodromy is on).
    pub rhs_evals: usize,
    /// Switching-surface crossings located.
    pub events: usize,
}

/// The state at the final time.
#[derive(Clone, Debug, PartialEq)]
pub struct Solution<const N: usize> {
    /// Final time (the requested end time when `stop` is `Reached`, else the last accepted).
    pub t: f64,
    /// State at `t`.
    pub x: SVector<f64, N>,
    /// $\Phi(t) = \partial x(t)/\partial x_0$ when [`OdeOptions::monodromy`] is set.
    pub monodromy: Option<SMatrix<f64, N, N>>,
    pub stats: Stats,
    pub stop: StopReason,
    /// Size of the first accepted step (NaN if none): a good [`OdeOptions::h_initial`] for a
    /// later integration from nearly the same start (Newton iterations of a shooting method).
    pub h_first: f64,
}

impl OdeError {
    /// The same error with its time `t` moved by `t0`: for an integration run from a local
    /// time 0 that stands for `t0` in the caller's time.
    pub fn shifted(self, t0: f64) -> Self {
        match self {
            OdeError::StepSizeTooSmall { t, h } => OdeError::StepSizeTooSmall { t: t + t0, h },
            OdeError::NonFinite { t } => OdeError::NonFinite { t: t + t0 },
            OdeError::MaxSteps { t, steps } => OdeError::MaxSteps { t: t + t0, steps },
            other => other,
        }
    }
}

/// Why an integration could not be done; each variant carries the numbers to diagnose it.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum OdeError {
    #[error("invalid tolerances rtol = {rtol:e}, atol = {atol:e}: both must be finite and > 0, with rtol >= 1e-14")]
    BadTolerance { rtol: f64, atol: f64 },
    #[error("invalid end time t_end = {t_end}: it must be finite and > 0")]
    BadInterval { t_end: f64 },
    #[error("step size h = {h:e} too small at t = {t} (below 16 ulps of t): singular solution or extreme stiffness")]
    StepSizeTooSmall { t: f64, h: f64 },
    #[error("state or field not finite at t = {t}")]
    NonFinite { t: f64 },
    #[error("max_steps = {steps} trial steps taken, stopped at t = {t}: a stiff model (a mass or an inertia far too small, a stiffness far too large) or too tight a tolerance")]
    MaxSteps { t: f64, steps: usize },
    /// Any other option or argument outside its domain (`h_max`, `h_initial`, `max_steps`,
    /// sample times, a section's `min_time`).
    #[error("invalid {name} = {value}: {rule}")]
    BadArgument {
        name: &'static str,
        value: f64,
        rule: &'static str,
    },
}
