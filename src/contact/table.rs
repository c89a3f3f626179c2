//! The contact state of the right wheel tabulated against `y` and interpolated C¹.
//!
//! Every geometry (closed form or rigid-contact solve) is sampled once on a uniform grid
//! `y_k = −Y + k·h` with its value **and exact slope** at each node; between nodes a cubic
//! Hermite interpolant is used, so values and first derivatives are continuous (docs/model.md §3
//! asks for at least C¹) and the slope at a node is the exact one. Cubic Hermite reproduces
//! polynomials up to degree three, so the closed-form cone is reproduced to rounding. Beyond
//! the tabulated range the state is extended linearly with the end slope (still C¹); the
//! range is chosen by the study so that the motion stays inside it.
//!
//! The same table carries the Hertz semi-axes and, when the study does not give them, the
//! creep coefficients at each contact state (docs/model.md §4–5: the normal force and the curvatures
//! change with `y`).

use crate::contact::geometry::{ContactPoint, Geometry, GeometryError, Nominal};
use crate::contact::hertz::{hertz_patch, HertzError};
use crate::contact::kalker::{creep_coefficients, CreepCoefficients, KalkerError};
use crate::contact::tabulated::TabulatedGeometry;
use crate::system::scalar::{Dual, Scalar};

/// Column indices of the table.
const RADIUS: usize = 0;
const ANGLE: usize = 1;
const ROLL: usize = 2;
const SEMI_A: usize = 3;
const SEMI_B: usize = 4;
const F11: usize = 5;
const COLUMNS: usize = 9;

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
    /// values and slopes, `[node][column]`
    value: Vec<[f64; COLUMNS]>,
    slope: Vec<[f64; COLUMNS]>,
    has_patch: bool,
    /// raw wheel contact offset at each node (m), NaN when not tracked
    offsets: Vec<f64>,
    /// contact-point jumps found while tabulating
    jumps: Vec<Jump>,
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

/// Where `y` falls in the table, with the Hermite weights.
#[derive(Clone, Copy, Debug)]
enum Basis {
    Inside { k: usize, w: [f64; 4], dw: [f64; 4] },
    Outside { node: usize, d: f64 },
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
    /// Samples `geometry` on the grid of `spec`.
    pub fn build(geometry: &Geometry, spec: &TableSpec) -> Result<Self, TableError> {
        if let Geometry::Profiles { pair, smoothing } = geometry {
            return super::profile_table::build(pair, *smoothing, spec);
        }
        let lateral = spec
            .rail_head_radius
            .or_else(|| geometry.rail_transverse_curvature().map(|k| 1.0 / k))
            .map(|r| Dual::cst(1.0 / r));
        let tabulated = match geometry {
            Geometry::Table(t) => Some(t.as_ref()),
            _ => None,
        };
        let n = spec.nodes.max(5) | 1;
        let half = (n - 1) / 2;
        let h = spec.half_width / half as f64;
        let nodes = march(half, h, |y, guess| {
            let (point, u) = geometry.solve(spec.nominal, y, guess)?;
            Ok::<_, TableError>((node_columns(point, tabulated, lateral, spec, y)?, u))
        })?;
        // the patch is there for every node or for none
        let has_patch = nodes.first().is_some_and(|c| c.1);
        Ok(Self {
            y0: -(half as f64) * h,
            h,
            value: nodes.iter().map(|c| c.0.map(|d| d.re)).collect(),
            slope: nodes.iter().map(|c| c.0.map(|d| d.eps[0])).collect(),
            has_patch,
            offsets: vec![f64::NAN; n],
            jumps: Vec::new(),
            clamped: Vec::new(),
        })
    }

    /// Assembles a table from node states (uniform grid from `y0` with step `h`): the
    /// geometry as duals (value, d/dy) and the lateral relative curvature B (1/m).
    pub(crate) fn assemble(
        spec: &TableSpec,
        (y0, h): (f64, f64),
        nodes: &[(ContactPoint<Dual<1>>, Dual<1>)],
        offsets: Vec<f64>,
        jumps: Vec<Jump>,
    ) -> Result<Self, TableError> {
        let mut value = Vec::with_capacity(nodes.len());
        let mut slope = Vec::with_capacity(nodes.len());
        let mut has_patch = false;
        for (k, &(p, b)) in nodes.iter().enumerate() {
            let (cols, patch) = node_columns(p, None, Some(b), spec, y0 + k as f64 * h)?;
            has_patch = patch;
            value.push(cols.map(|d| d.re));
            slope.push(cols.map(|d| d.eps[0]));
        }
        Ok(Self {
            y0,
            h,
            value,
            slope,
            has_patch,
            offsets,
            jumps,
            clamped: Vec::new(),
        })
    }

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

    /// The cell and cubic Hermite basis at `y` (value and d/dy weights for p0, m0, p1, m1),
    /// or the end node for the linear extension beyond the table.
    #[inline]
    fn basis(&self, y: f64) -> Basis {
        let n = self.value.len();
        let s = (y - self.y0) / self.h;
        if s.is_nan() || s < 0.0 {
            // below the table (or NaN): linear extension of the first node
            return Basis::Outside {
                node: 0,
                d: y - self.y0,
            };
        }
        if s >= (n - 1) as f64 {
            let d = y - (self.y0 + (n - 1) as f64 * self.h);
            return Basis::Outside { node: n - 1, d };
        }
        let k = (s as usize).min(n - 2);
        let t = s - k as f64;
        let (t2, t3) = (t * t, t * t * t);
        let h = self.h;
        Basis::Inside {
            k,
            w: [
                2.0 * t3 - 3.0 * t2 + 1.0,
                (t3 - 2.0 * t2 + t) * h,
                -2.0 * t3 + 3.0 * t2,
                (t3 - t2) * h,
            ],
            dw: [
                (6.0 * t2 - 6.0 * t) / h,
                3.0 * t2 - 4.0 * t + 1.0,
                (-6.0 * t2 + 6.0 * t) / h,
                3.0 * t2 - 2.0 * t,
            ],
        }
    }

    /// Column `c` (value, slope) with a precomputed basis. Always inlined: as a call (which
    /// `#[inline]` left it) it was a fifth of the cone branch's instructions, and inlined the
    /// slope the `f64` evaluation discards is not computed (bitwise the same results).
    #[inline(always)]
    fn apply(&self, b: &Basis, c: usize) -> (f64, f64) {
        match *b {
            Basis::Outside { node, d } => (
                self.value[node][c] + self.slope[node][c] * d,
                self.slope[node][c],
            ),
            Basis::Inside { k, w, dw } => {
                let (p0, p1) = (self.value[k][c], self.value[k + 1][c]);
                let (m0, m1) = (self.slope[k][c], self.slope[k + 1][c]);
                (
                    w[0] * p0 + w[1] * m0 + w[2] * p1 + w[3] * m1,
                    dw[0] * p0 + dw[1] * m0 + dw[2] * p1 + dw[3] * m1,
                )
            }
        }
    }

    #[inline]
    fn column<T: Scalar>(&self, b: &Basis, c: usize, y: T) -> T {
        let (v, d) = self.apply(b, c);
        y.lift(v, d)
    }

    /// The right wheel's state at displacement `y`.
    #[inline]
    pub fn right<T: Scalar>(&self, y: T) -> WheelState<T> {
        let b = self.basis(y.re());
        WheelState {
            radius: self.column(&b, RADIUS, y),
            angle: self.column(&b, ANGLE, y),
            creep: CreepCoefficients {
                f11: self.column(&b, F11, y),
                f22: self.column(&b, F11 + 1, y),
                f23: self.column(&b, F11 + 2, y),
                f33: self.column(&b, F11 + 3, y),
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
        let b = self.basis(y.re());
        self.column(&b, ROLL, y)
    }
}

/// The table columns at one node, as one-direction duals (value and d/dy).
/// `lateral` is B (1/m): 1/R_rail for a cone (straight transversally), or the profiles'
/// κ_wheel + κ_rail; `None`: no Hertz patch.
/// Solves the nodes $y_k = k h$, $k = −$`half` … `half`, marching outwards from the centre in
/// both directions with each solve seeded by the previous one's `G`, and returns them in the
/// order of y. The two directions are independent, so they run on two rayon threads (the same
/// nodes as in series, bitwise); an error of the positive side is reported first.
pub(super) fn march<T: Send, G, E: Send>(
    half: usize,
    h: f64,
    node: impl Fn(f64, Option<G>) -> Result<(T, G), E> + Sync,
) -> Result<Vec<T>, E> {
    let side = |dir: f64| -> Result<Vec<T>, E> {
        let mut guess = None;
        let mut out = Vec::with_capacity(half + 1);
        for k in 0..=half {
            let (t, g) = node(dir * k as f64 * h, guess)?;
            guess = Some(g);
            out.push(t);
        }
        Ok(out)
    };
    let (right, left) = rayon::join(|| side(1.0), || side(-1.0));
    let right = right?;
    // −half … 0 from the negative side (its y = −0 node, as the serial loop kept), then 1 … half
    Ok(left?
        .into_iter()
        .rev()
        .chain(right.into_iter().skip(1))
        .collect())
}

fn node_columns(
    p: ContactPoint<Dual<1>>,
    tabulated: Option<&TabulatedGeometry>,
    lateral: Option<Dual<1>>,
    spec: &TableSpec,
    y: f64,
) -> Result<([Dual<1>; COLUMNS], bool), TableError> {
    let zero = Dual::cst(0.0);
    // docs/model.md §4: N = (W/2)/cos δ
    let normal = p.angle.cos().recip() * (spec.axle_load / 2.0);
    if let Some((column, value)) = tabulated.and_then(|t| t.non_positive_at(y)) {
        return Err(TableError::NonPositive {
            table: tabulated.map_or_else(String::new, |t| t.source.clone()),
            y_m: y,
            column,
            value,
        });
    }
    let patch = match (tabulated.and_then(|t| t.semi_axes(y, normal)), lateral) {
        (Some(ab), _) => Some(ab),
        // A = 1/r (rolling), B as given
        (None, Some(lateral)) => {
            let patch = hertz_patch(
                normal,
                p.radius.recip(),
                lateral,
                spec.elastic.young_modulus,
                spec.elastic.poisson_ratio,
            )
            .map_err(|source| TableError::Hertz { y_m: y, source })?;
            Some((patch.a, patch.b))
        }
        (None, None) => None,
    };
    let creep = match (spec.creep, patch) {
        (CreepSource::Given(c), _) => CreepCoefficients {
            f11: Dual::cst(c.f11),
            f22: Dual::cst(c.f22),
            f23: Dual::cst(c.f23),
            f33: Dual::cst(c.f33),
        },
        (CreepSource::Hertz, Some((a, b))) => {
            let (g, nu) = (spec.elastic.shear_modulus, spec.elastic.poisson_ratio);
            // the table's own Kalker coefficients when it has them, else Kalker's table
            tabulated
                .and_then(|t| t.creep(y, a, b, g, nu))
                .unwrap_or_else(|| creep_coefficients(a, b, g, nu))
                .map_err(|source| TableError::Kalker { y_m: y, source })?
        }
        (CreepSource::Hertz, None) => return Err(TableError::NoCreepCoefficients),
    };
    let (a, b) = patch.unwrap_or((zero, zero));
    Ok((
        [
            p.radius, p.angle, p.roll, a, b, creep.f11, creep.f22, creep.f23, creep.f33,
        ],
        patch.is_some(),
    ))
}
