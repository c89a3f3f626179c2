//! The mathematical contract shared by every analysis: scalars with exact derivatives.

pub mod scalar;
