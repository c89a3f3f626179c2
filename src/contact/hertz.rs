//! TEMPORARY stub (replaced by the real module).
use crate::system::scalar::Scalar;
pub struct HertzPatch<T> {
    pub a: T,
    pub b: T,
}
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum HertzError {
    #[error("stub")]
    Stub,
}
pub fn hertz_patch<T: Scalar>(
    _n: T,
    _a: T,
    _b: T,
    _e: f64,
    _nu: f64,
) -> Result<HertzPatch<T>, HertzError> {
    Err(HertzError::Stub)
}
