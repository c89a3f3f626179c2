//! Wheel–rail contact: geometry, Hertz patch, creep coefficients and creep laws (docs/model.md §3–6).

pub mod creep;
pub mod geometry;
pub mod hertz;
pub mod kalker;
mod placement;
pub mod profile;
mod profile_table;
pub mod rigid;
pub mod spline;
pub mod table;
pub mod tabulated;
