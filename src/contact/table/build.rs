//! Building the contact table: the node solves (marching outwards from the centre), the
//! columns at each node with exact slopes (geometry, Hertz patch, creep coefficients) and the
//! second derivatives of the C² interpolant.

use super::quintic::{curvatures, Quintic};
use super::{ContactTable, CreepSource, Jump, TableError, TableSpec, ANGLE, COLUMNS, RADIUS, ROLL};
use crate::contact::geometry::{ContactPoint, Geometry};
use crate::contact::hertz::hertz_patch;
use crate::contact::kalker::{creep_coefficients, CreepCoefficients};
use crate::contact::tabulated::TabulatedGeometry;
use crate::system::scalar::{Dual, Scalar};

impl ContactTable {
    /// Samples `geometry` on the grid of `spec`.
    pub fn build(geometry: &Geometry, spec: &TableSpec) -> Result<Self, TableError> {
        if let Geometry::Profiles { pair, smoothing } = geometry {
            return crate::contact::profile_table::build(pair, *smoothing, spec);
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
        let y0 = -(half as f64) * h;
        let nodes = march(half, h, |y, guess| {
            let (point, u) = geometry.solve(spec.nominal, y, guess)?;
            Ok::<_, TableError>((node_columns(point, tabulated, lateral, spec, y)?, u))
        })?;
        // the patch is there for every node or for none
        let has_patch = nodes.first().is_some_and(|c| c.1);
        let value: Vec<_> = nodes.iter().map(|c| c.0.map(|d| d.re)).collect();
        let slope: Vec<_> = nodes.iter().map(|c| c.0.map(|d| d.eps[0])).collect();
        let mut curvature = curvatures(&slope, h);
        if let Some(t) = tabulated {
            // the file's spline has exact second derivatives of the geometry columns
            for (k, c) in curvature.iter_mut().enumerate() {
                let [r, d, p] = t.second_derivatives(y0 + k as f64 * h);
                (c[RADIUS], c[ANGLE], c[ROLL]) = (r, d, p);
            }
        }
        // every column of the cone on knife-edge rails is linear or constant in y (unless the
        // creep coefficients come from the Hertz patch, whose normal force grows like 1/cos δ)
        let exact = matches!(geometry, Geometry::Cone { .. })
            && matches!(spec.creep, CreepSource::Given(_));
        Ok(Self::from_nodes(
            (y0, h),
            (value, slope, curvature),
            has_patch,
            (vec![f64::NAN; n], Vec::new()),
            (!exact).then_some(-y0),
        ))
    }

    /// Assembles a table from node states (uniform grid from `y0` with step `h`): the
    /// geometry as duals (value, d/dy) and the lateral relative curvature B (1/m); the table
    /// is genuine over the grid. The second derivatives are central differences of the
    /// slopes.
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
        let curvature = curvatures(&slope, h);
        Ok(Self::from_nodes(
            (y0, h),
            (value, slope, curvature),
            has_patch,
            (offsets, jumps),
            Some(-y0),
        ))
    }

    /// The table of the node data.
    fn from_nodes(
        (y0, h): (f64, f64),
        (value, slope, curvature): Nodes,
        has_patch: bool,
        (offsets, jumps): (Vec<f64>, Vec<Jump>),
        valid: Option<f64>,
    ) -> Self {
        let interp = Quintic::new((y0, h), &value, &slope, &curvature);
        Self {
            y0,
            h,
            value,
            curvature,
            interp,
            has_patch,
            offsets,
            jumps,
            valid,
            clamped: Vec::new(),
        }
    }
}

/// Values, slopes and second derivatives of the columns, `[node][column]`.
type Nodes = (
    Vec<[f64; COLUMNS]>,
    Vec<[f64; COLUMNS]>,
    Vec<[f64; COLUMNS]>,
);

/// The table columns at one node, as one-direction duals (value and d/dy).
/// `lateral` is B (1/m): 1/R_rail for a cone (straight transversally), or the profiles'
/// κ_wheel + κ_rail; `None`: no Hertz patch.
/// Solves the nodes $y_k = k h$, $k = −$`half` … `half`, marching outwards from the centre in
/// both directions with each solve seeded by the previous one's `G`, and returns them in the
/// order of y. The two directions are independent, so they run on two rayon threads (the same
/// nodes as in series, bitwise); an error of the positive side is reported first.
pub(in crate::contact) fn march<T: Send, G, E: Send>(
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
