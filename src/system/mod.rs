//! The mathematical contract shared by every analysis: scalars with exact derivatives, and
//! the ODE integrator with variational equations and event location.

pub mod ode;
pub mod scalar;
