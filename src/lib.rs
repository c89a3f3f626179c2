//! # critspeed
//!
//! At what speed does a railway wheelset start to hunt, and how violently?
//!
//! The workflow, in the order the modules are used:
//!
//! 1. [`study`]: read a TOML study file (any accepted unit), validate it into an SI [`study::Plan`]
//!    ([`study::keys::study_keys`] lists every key the schema accepts).
//! 2. [`contact`]: the contact geometry (closed-form cone, or a cone on a circular rail head by
//!    the rigid two-point contact method), Hertz patch, Kalker creep coefficients, creep laws.
//! 3. [`model`]: the suspended wheelset's equations of motion $\dot x = f(x; V)$, one
//!    right-hand side for every analysis, with the exact Jacobian by dual numbers.
//! 4. [`stability`]: the spectrum of the centred motion at any speed and every crossing of
//!    the imaginary axis (the linear, Kalker, critical speed and the Hopf speed of the study's
//!    creep law).
//! 5. [`continuation`] (generic: periodic orbits by shooting, Floquet multipliers,
//!    pseudo-arclength continuation, special points) driven by [`bifurcation`] for the
//!    wheelset: the branch of hunting cycles from the Hopf point, folds, the nonlinear
//!    critical speed; [`attractors`] searches for every attractor by simulation, and
//!    [`reconcile`] joins both methods' V_NL. [`system::ode`] is the integrator
//!    (Dormand–Prince 5(4), variational equations, event location at the flange);
//!    [`simulate`] runs time histories and the ramp method.
//! 6. [`output`], [`figures`] and [`plot`]: results as JSON/CSV and SVG under `out/<study>/`.
//! 7. [`sweep`]: the critical speeds over a grid of one or two study keys (`[sweep]`), in
//!    parallel, resumable and sharded.
//! 8. [`trade`]: a study's `[trade]` over its sweep's results: the feasible designs, the best
//!    one and the Pareto front of critical speed against the objective
//!    ([`plot::heat_map_svg`] draws two-axis maps with contours).
//! 9. [`uncertainty`]: the critical speeds' distribution over random parameters
//!    (`[uncertainty]`) and their first-order and total Sobol indices, evaluated as a sweep.
//!
//! [`api`] is the front door over all of this that the command line and the Python package
//! (`python/`, docs/python.md) both call: a study (file, TOML text or JSON object) in, reports
//! and the bytes of their files out, with cancellation hooks for long analyses.
//! The command line ([`cli`]) is a thin layer over these steps; the user guide, `docs/README.md`,
//! describes the study files, commands and output files.
//!
//! [`reference`](mod@reference) holds problems with known answers (closed-form critical speed, the Hopf
//! normal form) that the tests and benches share.
//!
//! ```
//! use critspeed::study;
//! use critspeed::stability::{critical_speeds, LinearSystem};
//! use critspeed::contact::creep::CreepLaw;
//!
//! let plan = study::parse(study::DEFAULT_STUDY, "seed").unwrap();
//! let model = plan.model().unwrap().with_law(CreepLaw::Kalker);
//! let sys = LinearSystem::<4>::at_centre(&model);
//! let found = critical_speeds(&sys, CreepLaw::Kalker, &plan.linear).unwrap();
//! // The seed's dampers keep its wheelset stable far beyond railway speeds (docs/model.md §10).
//! assert!(found.critical().map_or(true, |c| c.speed_m_s > 150.0));
//! ```

pub mod analysis;
pub mod api;
pub mod attractors;
pub mod bifurcation;
pub mod cli;
pub mod conicity;
pub mod contact;
pub mod continuation;
pub mod curve;
pub mod figures;
pub mod model;
pub mod output;
pub mod plot;
pub mod reconcile;
pub mod reference;
pub mod simulate;
pub mod stability;
pub mod study;
pub mod sweep;
pub mod system;
#[cfg(test)]
mod testutil;
pub mod trade;
pub mod uncertainty;
