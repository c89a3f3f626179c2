//! Periodic orbits and their continuation in a parameter. Knows nothing of wheels.
//!
//! * [`orbit`]: single shooting (full or symmetric half-period), Floquet multipliers.
//! * [`branch`]: pseudo-arclength continuation from a Hopf point, with fold, period-doubling,
//!   symmetry-breaking and torus points detected ([`special`]) and located.
//! * [`switch`]: the new branch at a symmetry-breaking or period-doubling point.

pub mod branch;
pub mod orbit;
pub mod special;
pub mod switch;

pub use branch::{
    Branch, BranchPoint, BranchStats, BranchStop, Continuation, ContinuationParams, Rejoin,
    SpecialKind, SpecialPoint,
};
pub use orbit::{Floquet, NewtonStop, OrbitPoint, PoolBusy, SegmentSeed, Shooting};
pub use switch::{switch_at, Switch, SwitchError};
