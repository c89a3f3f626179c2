//! The contact state of the right wheel tabulated against `y` and interpolated C².
//!
//! Every geometry (closed form, tabulated file or rigid contact of profiles) is sampled once
//! on a uniform grid `y_k = −Y + k·h` with, at each node, its value, its **exact slope** and a
//! second derivative; between nodes a quintic Hermite interpolant is used (module `quintic`),
//! so value, slope and second derivative are continuous. The Jacobian of the equations of
//! motion is then continuous along an orbit (with a C¹ table it jumps at every node, where the
//! integrator's error estimate is not valid: on S1002 a third of the trial steps then fail).
//! Values and slopes at the nodes are
//! exactly those of the sampled geometry. The second derivatives are exact where the source
//! has them (a tabulated file: its C² spline's; the closed-form cone: zero), else central
//! differences of the exact node slopes (error $h^2 f^{(4)}/6$; exact for cubics, so the cone
//! and any cubic column are reproduced to rounding). Beyond the tabulated range the state is
//! extended linearly with the end slope (C¹ there); where that extension is not the geometry
//! itself, [`ContactTable::valid_half_width`] says how far the table is genuine, and the
//! study's `contact.extrapolate` ([`Extrapolation`]) whether analyses may go beyond it.
//!
//! The same table carries the Hertz semi-axes and, when the study does not give them, the
//! creep coefficients at each contact state (docs/model.md §4–5: the normal force and the curvatures
//! change with `y`).

mod build;
mod quintic;

pub(super) use build::march;

use crate::contact::geometry::{ContactPoint, GeometryError, Nominal};
use crate::contact::hertz::HertzError;
use crate::contact::kalker::{CreepCoefficients, KalkerError};
use crate::system::scalar::Scalar;
use quintic::{Locus, Quintic};

/// Column indices of the table.
const RADIUS: usize = 0;
const ANGLE: usize = 1;
const ROLL: usize = 2;
const SEMI_A: usize = 3;
const SEMI_B: usize = 4;
const F11: usize = 5;
const COLUMNS: usize = 9;

/// A column of the contact table (the right wheel's contact state).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Column {
    /// rolling radius r_R (m)
    Radius,
    /// contact angle δ_R (rad)
    Angle,
    /// wheelset roll φ (rad)
    Roll,
    /// Hertz semi-axis a, rolling direction (m; 0 without a patch)
    SemiA,
    /// Hertz semi-axis b, lateral (m; 0 without a patch)
    SemiB,
    /// creep coefficient f11 (N)
    F11,
    /// creep coefficient f22 (N)
    F22,
    /// creep coefficient f23 (N m)
    F23,
    /// creep coefficient f33 (N m²)
    F33,
}

impl Column {
    /// Every column, in the table's order.
    pub const ALL: [Column; COLUMNS] = [
        Column::Radius,
        Column::Angle,
        Column::Roll,
        Column::SemiA,
        Column::SemiB,
        Column::F11,
        Column::F22,
        Column::F23,
        Column::F33,
    ];

    fn index(self) -> usize {
        self as usize
    }
}

/// What the analyses may do where the contact table is not genuine geometry (beyond
/// [`ContactTable::valid_half_width`]): the study key `contact.extrapolate`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Extrapolation {
    /// `"none"` (default): a branch, attractor or simulation that leaves the valid range is
    /// cut there and reported as such; no critical speed is derived from extrapolated
    /// geometry.
    #[default]
    None,
    /// `"linear"`: the table's linear extension beyond its range is used as if it were
    /// geometry; results that rely on it are kept (and must say so).
    Linear,
}

impl Extrapolation {
    /// The accepted study values, for messages.
    pub const ALLOWED: &'static str = "\"none\", \"linear\"";

    /// The study value.
    pub fn name(self) -> &'static str {
        match self {
            Extrapolation::None => "none",
            Extrapolation::Linear => "linear",
        }
    }

    /// The mode of a study value, `None` when it is not one of [`Self::ALLOWED`].
    pub fn parse(text: &str) -> Option<Self> {
        match text {
            "none" => Some(Extrapolation::None),
            "linear" => Some(Extrapolation::Linear),
            _ => None,
        }
    }
}

/// Elastic constants of wheel and rail steel (identical bodies).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Elastic {
    /// Young's modulus E (Pa)
    pub young_modulus: f64,
    /// Poisson's ratio ν (–)
    pub poisson_ratio: f64,
    /// shear modulus G (Pa)
    pub shear_modulus: f64,
}

/// Where the creep coefficients come from.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum CreepSource {
    /// Given by the study, constant (N, N, N m, N m²).
    Given(CreepCoefficients<f64>),
    /// From the Hertz patch and Kalker's table at each contact state.
    Hertz,
}

/// What the table needs besides the geometry.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TableSpec {
    /// nominal dimensions
    pub nominal: Nominal,
    /// axle load W (N)
    pub axle_load: f64,
    /// elastic constants (for the Hertz patch)
    pub elastic: Elastic,
    /// transverse radius of the rail head for the Hertz patch (m); `None`: no patch
    pub rail_head_radius: Option<f64>,
    /// creep coefficient source
    pub creep: CreepSource,
    /// half-width of the tabulated range (m)
    pub half_width: f64,
    /// number of nodes (odd, so that y = 0 is a node)
    pub nodes: usize,
}

/// A failure while building the table.
#[derive(Debug, thiserror::Error)]
pub enum TableError {
    #[error(transparent)]
    Geometry(#[from] GeometryError),
    #[error("Hertz patch at y = {y_m:.6e} m: {source}")]
    Hertz { y_m: f64, source: HertzError },
    #[error("creep coefficients at y = {y_m:.6e} m: {source}")]
    Kalker { y_m: f64, source: KalkerError },
    #[error("creep coefficients are needed: give [contact.creep_coefficients] or a rail head radius for the Hertz patch")]
    NoCreepCoefficients,
    #[error("geometry table {table}: at y = {y_m:.6e} m the interpolated column {column} is {value:e}, not positive (the spline undershoots between steep rows; use finer rows or a smaller lateral_range)")]
    NonPositive {
        table: String,
        y_m: f64,
        column: &'static str,
        value: f64,
    },
}

/// One node's full contact state, for output.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Row {
    /// lateral displacement (m)
    pub y: f64,
    /// right-wheel contact state
    pub point: ContactPoint<f64>,
    /// Hertz semi-axes a (rolling), b (lateral) of the right wheel (m), if computed
    pub semi_axes: Option<(f64, f64)>,
    /// creep coefficients of the right wheel
    pub creep: CreepCoefficients<f64>,
}

/// The tabulated right-wheel contact state.
#[derive(Clone, Debug)]
pub struct ContactTable {
    y0: f64,
    h: f64,
    /// node values and second derivatives, `[node][column]` (the slopes are in `interp`)
    value: Vec<[f64; COLUMNS]>,
    curvature: Vec<[f64; COLUMNS]>,
    /// the C² interpolant of the node data
    interp: Quintic<COLUMNS>,
    has_patch: bool,
    /// raw wheel contact offset at each node (m), NaN when not tracked
    offsets: Vec<f64>,
    /// contact-point jumps found while tabulating
    jumps: Vec<Jump>,
    /// half-width of the genuine geometry (m); `None`: the linear extension is exact
    valid: Option<f64>,
    /// nodes (y, m) where the lateral curvature B was held inside Kalker's a/b range
    pub clamped: Vec<f64>,
}

/// A discontinuity of the right wheel's contact point between two table nodes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Jump {
    /// the two nodes' lateral displacements (m)
    pub y_m: (f64, f64),
    /// the wheel contact point's outward offset from the taping line at each (m)
    pub wheel_offset_m: (f64, f64),
    /// the rolling radius at each (m)
    pub radius_m: (f64, f64),
}

/// The interpolated contact state of one wheel.
#[derive(Clone, Copy, Debug)]
pub struct WheelState<T> {
    /// rolling radius (m)
    pub radius: T,
    /// contact angle (rad), positive pushing the wheel towards the track centre
    pub angle: T,
    /// creep coefficients
    pub creep: CreepCoefficients<T>,
}

impl ContactTable {
    /// Contact-point jumps found while tabulating (profiles only).
    pub fn jumps(&self) -> &[Jump] {
        &self.jumps
    }

    /// The tabulated half-width (m).
    pub fn half_width(&self) -> f64 {
        -self.y0
    }

    /// Whether the Hertz semi-axes were computed.
    pub fn has_patch(&self) -> bool {
        self.has_patch
    }

    /// The rolling-radius difference r_R(y) − r_L(y) = r_R(y) − r_R(−y) (m) at every node,
    /// as (y m, Δr m): the nodes are symmetric about y = 0, so node k's mirror is node n−1−k.
    pub fn rolling_radius_difference(&self) -> Vec<(f64, f64)> {
        let n = self.value.len();
        (0..n)
            .map(|k| {
                let dr = self.value[k][RADIUS] - self.value[n - 1 - k][RADIUS];
                (self.y0 + k as f64 * self.h, dr)
            })
            .collect()
    }

    /// The nodes, for output.
    pub fn rows(&self) -> Vec<Row> {
        (0..self.value.len())
            .map(|k| {
                let v = &self.value[k];
                Row {
                    y: self.y0 + k as f64 * self.h,
                    point: ContactPoint {
                        radius: v[RADIUS],
                        angle: v[ANGLE],
                        roll: v[ROLL],
                        wheel_offset: self.offsets[k],
                    },
                    semi_axes: self.has_patch.then_some((v[SEMI_A], v[SEMI_B])),
                    creep: CreepCoefficients {
                        f11: v[F11],
                        f22: v[F11 + 1],
                        f23: v[F11 + 2],
                        f33: v[F11 + 3],
                    },
                }
            })
            .collect()
    }

    /// Column `c` at a located `y` as a scalar of `y`'s type (value and slope).
    #[inline(always)]
    fn column<T: Scalar>(&self, at: &Locus, c: usize, y: T) -> T {
        let (v, d) = self.interp.eval(at, c);
        y.lift(v, d)
    }

    /// The right wheel's state at displacement `y`.
    #[inline]
    pub fn right<T: Scalar>(&self, y: T) -> WheelState<T> {
        let at = self.interp.locate(y.re());
        WheelState {
            radius: self.column(&at, RADIUS, y),
            angle: self.column(&at, ANGLE, y),
            creep: CreepCoefficients {
                f11: self.column(&at, F11, y),
                f22: self.column(&at, F11 + 1, y),
                f23: self.column(&at, F11 + 2, y),
                f33: self.column(&at, F11 + 3, y),
            },
        }
    }

    /// The left wheel's state at displacement `y`, by the track symmetry.
    #[inline]
    pub fn left<T: Scalar>(&self, y: T) -> WheelState<T> {
        self.right(-y)
    }

    /// Roll angle φ(y) (rad).
    pub fn roll<T: Scalar>(&self, y: T) -> T {
        let at = self.interp.locate(y.re());
        self.column(&at, ROLL, y)
    }

    /// Column `column` at `y` (m): value, first and second derivative with respect to y (the
    /// interpolant's; zero second derivative on the linear extension).
    pub fn derivatives(&self, column: Column, y: f64) -> [f64; 3] {
        self.interp.eval2(y, column.index())
    }

    /// The second derivative of `column` at every node, as (y m, value): the data of the C²
    /// interpolant (exact, or central differences of the exact slopes; see the module docs).
    pub fn node_second_derivatives(&self, column: Column) -> Vec<(f64, f64)> {
        let c = column.index();
        (0..self.curvature.len())
            .map(|k| (self.y0 + k as f64 * self.h, self.curvature[k][c]))
            .collect()
    }

    /// The half-width (m) of the range of y where the table is genuine geometry: the
    /// geometry was computed there (a profile pair's rigid solve, a cone-on-arc solve) or
    /// read there (a tabulated file; the study's `lateral_range` never exceeds the file's
    /// range). Beyond it every column is extended linearly with its end slope, which is a
    /// guess. `None` where that extension is exact: the cone on knife-edge rails with given
    /// creep coefficients, whose every column is linear (r, δ, φ) or constant (f11 … f33).
    pub fn valid_half_width(&self) -> Option<f64> {
        self.valid
    }

    /// Whether `y` (m) lies where the table is genuine ([`Self::valid_half_width`]); NaN is
    /// not.
    pub fn is_valid_at(&self, y: f64) -> bool {
        self.valid.map_or(!y.is_nan(), |w| y.abs() <= w)
    }
}
