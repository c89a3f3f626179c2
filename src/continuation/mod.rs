//! Periodic orbits and their continuation in a parameter. Knows nothing of wheels.
//!
//! * [`orbit`]: single shooting (full or symmetric half-period), Floquet multipliers.
//! * [`branch`]: pseudo-arclength continuation from a Hopf point, with fold, period-doubling,
//!   symmetry-breaking and torus points detected and located.

pub mod branch;
pub mod orbit;

pub use branch::{
    Branch, BranchPoint, BranchStats, BranchStop, Continuation, ContinuationParams, SpecialKind,
    SpecialPoint,
};
pub use orbit::{Floquet, NewtonStop, OrbitPoint, SegmentSeed, Shooting};
