//! TEMPORARY stub (replaced by the real module).
use crate::system::scalar::Scalar;
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CreepCoefficients<T> {
    pub f11: T,
    pub f22: T,
    pub f23: T,
    pub f33: T,
}
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum KalkerError {
    #[error("stub")]
    Stub,
}
pub fn creep_coefficients<T: Scalar>(
    _a: T,
    _b: T,
    _g: f64,
    _nu: f64,
) -> Result<CreepCoefficients<T>, KalkerError> {
    Err(KalkerError::Stub)
}
