//! Trade studies over a sweep's results: which designs meet the constraints, the best one
//! for the objective, and the Pareto front of critical speed against the objective axis.
//!
//! The study's `[trade]` table is validated once into a [`TradePlan`] (SI units, see
//! [`plan::trade_plan`]); the sweep's `sweep.csv` is read by column name into [`Row`]s
//! ([`table::read_sweep`]); [`select::assess`] is a pure function from both to one
//! [`Assessment`] per row; [`table::trade_csv`] writes the result.
//!
//! Definitions (with *V* the Pareto result, by default the first constrained result):
//! - a point is **feasible** when every result the trade reads (the constrained results and
//!   *V*) was found or is above range ([`select::failed_for`] is false: a failure on a result
//!   the trade does not read does not count), its objective value is present, and every
//!   constraint's value is present and within its bounds. A result **above range** (no onset up to the top of the point's speed
//!   range v_max, column `stable_up_to_m_s`) is only known to exceed v_max: it meets
//!   `at_least X` iff X ≤ v_max; it never meets `at_most X` (violated for X ≤ v_max, unknown
//!   for X > v_max), and the reason says "stable to v_max m/s (no onset in range)";
//! - the front and the tie-break use *V* capped at the top of the speed range,
//!   min(*V*, v_max): the found value, or v_max for a point above range. That is known exactly
//!   for both kinds of point, so dominance is decided soundly: an above-range point dominates
//!   every found point with no better objective (their *V* ≤ v_max < its *V*), and of two
//!   above-range points the one with the better objective is kept (ties: both);
//! - point *a* **dominates** *b* when *a*'s objective is no worse and *a*'s capped *V* is no
//!   lower, and one of the two is strictly better. The **Pareto front** is the set of points
//!   not failed on a result the trade reads, with finite objective and capped *V* that no such point dominates —
//!   constraints are not applied to the front, so it shows the whole trade and the constraint
//!   line on the plot shows which part of it is feasible;
//! - the **best design** is the feasible point with the lowest (`minimize`) or highest
//!   (`maximize`) objective; ties (relative difference ≤ 1e-12) go to the higher capped *V*,
//!   then to the earlier row.

pub mod curve;
pub mod curve_report;
pub mod intervals;
pub mod margin;
pub mod plan;
pub mod report;
pub mod select;
pub mod settle;
pub mod table;

use crate::study::units::Dimension;

pub use plan::trade_plan;
pub use select::{assess, Assessment};
pub use table::{read_sweep, trade_csv, Row, SweepTable};

/// A result column of the sweep.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ResultKind {
    /// the linear (Kalker) critical speed (m/s)
    KalkerCriticalSpeed,
    /// the Hopf speed of the study's creep law (m/s)
    HopfSpeed,
    /// the nonlinear critical speed: the lowest speed with a hunting cycle (m/s)
    NonlinearCriticalSpeed,
}

impl ResultKind {
    /// All results, in column order.
    pub const ALL: [ResultKind; 3] = [
        ResultKind::KalkerCriticalSpeed,
        ResultKind::HopfSpeed,
        ResultKind::NonlinearCriticalSpeed,
    ];

    /// The name used in study files, e.g. `nonlinear_critical_speed`.
    pub fn name(self) -> &'static str {
        match self {
            ResultKind::KalkerCriticalSpeed => "kalker_critical_speed",
            ResultKind::HopfSpeed => "hopf_speed",
            ResultKind::NonlinearCriticalSpeed => "nonlinear_critical_speed",
        }
    }

    /// The sweep CSV column, with its unit: `nonlinear_critical_speed_m_s`.
    pub fn column(self) -> String {
        format!("{}_m_s", self.name())
    }

    /// Parse a study-file name.
    pub fn from_name(s: &str) -> Option<ResultKind> {
        ResultKind::ALL.into_iter().find(|r| r.name() == s)
    }
}

/// Whether the objective axis is to be made small or large.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Sense {
    /// lower is better
    Minimize,
    /// higher is better
    Maximize,
}

/// The objective: one swept study key.
#[derive(Clone, Debug, PartialEq)]
pub struct Objective {
    /// study key, e.g. `suspension.longitudinal_stiffness`
    pub key: String,
    /// minimise or maximise
    pub sense: Sense,
    /// the key's physical dimension (its SI unit is the CSV's)
    pub dim: Dimension,
}

/// What a constraint bounds.
#[derive(Clone, Debug, PartialEq)]
pub enum Target {
    /// a result column (a speed, m/s)
    Result(ResultKind),
    /// a swept study key, in the SI unit of its dimension
    Axis {
        /// study key
        key: String,
        /// its dimension
        dim: Dimension,
    },
}

/// One constraint, bounds in SI units with any factor already applied.
#[derive(Clone, Debug, PartialEq)]
pub struct Constraint {
    /// what is bounded
    pub target: Target,
    /// lower bound (SI), inclusive
    pub at_least: Option<f64>,
    /// upper bound (SI), inclusive
    pub at_most: Option<f64>,
    /// the constraint as written with its SI value, for labels, e.g.
    /// `nonlinear_critical_speed ≥ 1.1 × 50 m/s = 55 m/s`
    pub text: String,
}

/// How the trade is computed (`[trade] method`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Method {
    /// over the sweep's grid points (`sweep.csv`): the default
    Grid,
    /// on the critical speeds continued as curves over the sweep's one key
    /// ([`crate::curve`]): the feasible set as intervals of the key ([`curve`])
    Curve,
}

impl Method {
    /// `"grid"` or `"curve"`, as in study files.
    pub fn name(self) -> &'static str {
        match self {
            Method::Grid => "grid",
            Method::Curve => "curve",
        }
    }
}

/// A validated `[trade]` section.
#[derive(Clone, Debug, PartialEq)]
pub struct TradePlan {
    /// the objective axis
    pub objective: Objective,
    /// constraints (all must hold)
    pub constraints: Vec<Constraint>,
    /// the result plotted against the objective and used for the Pareto front
    pub pareto: ResultKind,
    /// over the grid (default) or on curves
    pub method: Method,
}

impl TradePlan {
    /// The results the trade reads: the constrained ones and the Pareto speed, each once, in
    /// [`ResultKind::ALL`] order.
    pub fn read_results(&self) -> Vec<ResultKind> {
        ResultKind::ALL
            .into_iter()
            .filter(|r| {
                *r == self.pareto
                    || self
                        .constraints
                        .iter()
                        .any(|c| c.target == Target::Result(*r))
            })
            .collect()
    }
}

/// A problem with the sweep table or its fit to the trade plan.
#[derive(Debug, thiserror::Error)]
pub enum TradeError {
    /// The CSV text is malformed.
    #[error("{file}, line {line}: {problem}")]
    Csv {
        /// file name
        file: String,
        /// 1-based line number
        line: usize,
        /// what is wrong, with the value
        problem: String,
    },
    /// A column the trade needs is not in the sweep table.
    #[error("{file} has no column for {what} (looked for {wanted}); its columns are: {columns}")]
    MissingColumn {
        /// file name
        file: String,
        /// what the column is for, e.g. `the objective suspension.longitudinal_stiffness`
        what: String,
        /// the column name or prefix looked for
        wanted: String,
        /// the header, comma-separated
        columns: String,
    },
}

/// The dimension of a swept study key, if it is one (the keys a sweep may vary,
/// [`crate::sweep::SWEEP_KEYS`]).
pub fn axis_dimension(key: &str) -> Option<Dimension> {
    crate::sweep::spec::key_dimension(key)
}

/// A convenient display unit for a dimension ([`crate::study::units::display_unit`]).
pub use crate::study::units::display_unit;
