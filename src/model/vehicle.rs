//! A vehicle as an assembly: rigid bodies, linear spring–damper elements between points of
//! them (or of the track), and the wheel–rail contact of each wheelset (docs/model.md §11).
//!
//! **States.** Every body has a lateral displacement $y$ and a yaw $ψ$; a frame or car body
//! may also roll ($φ$). The generalised coordinates $q$ stack $(y, ψ[, φ])$ body after body in
//! [`Vehicle::bodies`] order, which is: the wheelsets from the front, then the bogie frames
//! from the front, then the car body. The state is $x = (q, \dot q)$; the first two
//! coordinates are always the leading wheelset's $y$ and $ψ$, so that $x_0$ is the quantity
//! the 4-state wheelset reports.
//!
//! **Elements.** A point $p$ of a body (its own axes, origin at the centre of mass) moves by
//! $u_x = −p_y ψ$, $u_y = y + p_x ψ + p_z φ$, $u_z = −p_y φ$, i.e. $u = B_p\,q$ with a 3-row
//! matrix $B_p$; the track does not move. An element between $p_A$ and $p_B$ with stiffnesses
//! $k$ and dampings $c$ along the track axes pushes $A$ with $F = −\mathrm{diag}(k)Δ −
//! \mathrm{diag}(c)\dot Δ$, $Δ = u_A − u_B = (B_A − B_B)\,q$, and by virtual work its
//! generalised forces are $Q = (B_A − B_B)^{\mathsf T} F$. Summed over the elements,
//! $$Q_{el} = −K q − C \dot q,\qquad K = \sum b^{\mathsf T}\mathrm{diag}(k)\,b,\quad
//! C = \sum b^{\mathsf T}\mathrm{diag}(c)\,b,$$
//! assembled once ([`Vehicle::assemble`]).
//!
//! **Equations of motion.** $M\ddot q = Q_{contact}(q, \dot q; V) + Q_{el}$, with $M$
//! diagonal (mass, yaw and roll inertia) and $Q_{contact}$ the forces of docs/model.md §4–6 on each
//! wheelset, a function of that wheelset's own $(y, ψ, \dot y, \dot ψ)$ only
//! ([`Wheelset::contact_forces`]). The exact Jacobian is therefore
//! $$J = \begin{pmatrix} 0 & I \\ M^{-1}(∂Q_c/∂q − K) & M^{-1}(∂Q_c/∂\dot q − C)\end{pmatrix}$$
//! with the contact blocks (2×4 per wheelset) from dual numbers.
//!
//! Neglected, as docs/model.md §11 allows: gravity acting on a rolled body, the lateral component of
//! vertical suspension forces under roll, bounce, pitch and longitudinal motion.

use nalgebra::{SMatrix, SVector};

use super::bump_stop::{BumpStop, StopSpec};
use super::{ForceVelocity, Wheelset};
use crate::contact::creep::CreepLaw;
use crate::contact::table::ContactTable;
use crate::system::scalar::Dual;

/// Which assembly a study describes (docs/model.md §11's three layouts).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Layout {
    /// one wheelset, primary suspension to a track-fixed frame: 4 states
    Wheelset,
    /// a frame on two wheelsets, secondary to a track-fixed car body: 12 states (14 with roll)
    Bogie,
    /// a car body on two bogies: 28 states (34 with frame and car-body roll)
    Car,
}

impl Layout {
    /// `"wheelset"`, `"bogie"` or `"car"` (the study file's words).
    pub fn name(self) -> &'static str {
        match self {
            Layout::Wheelset => "wheelset",
            Layout::Bogie => "bogie",
            Layout::Car => "car",
        }
    }
}

/// What a body is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BodyKind {
    /// a wheelset (carries wheel–rail contact; no roll state)
    Wheelset,
    /// a bogie frame
    Frame,
    /// the car body
    CarBody,
}

impl BodyKind {
    /// `"wheelset"`, `"frame"` or `"car body"`.
    pub fn name(self) -> &'static str {
        match self {
            BodyKind::Wheelset => "wheelset",
            BodyKind::Frame => "frame",
            BodyKind::CarBody => "car body",
        }
    }
}

/// A rigid body of the assembly.
#[derive(Clone, Debug, PartialEq)]
pub struct Body {
    /// name used in outputs, e.g. `"wheelset 1"`, `"frame 2"`, `"car body"`
    pub name: String,
    /// kind
    pub kind: BodyKind,
    /// mass (kg)
    pub mass: f64,
    /// yaw moment of inertia (kg m²)
    pub yaw_inertia: f64,
    /// roll moment of inertia (kg m²); `Some` adds the roll coordinate φ
    pub roll_inertia: Option<f64>,
    /// longitudinal position of its centre in the vehicle, +x forward (m); for output only
    pub position_m: f64,
    /// index of its $y$ in $q$ ($ψ$ follows, then $φ$ if it rolls)
    pub dof: usize,
}

impl Body {
    /// Number of generalised coordinates (2, or 3 with roll).
    pub fn dofs(&self) -> usize {
        2 + usize::from(self.roll_inertia.is_some())
    }
}

/// One end of an element: a point of a body (its own axes, m) or of the track.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Attachment {
    /// index into [`Vehicle::bodies`]; `None` is the track (or a track-fixed body)
    pub body: Option<usize>,
    /// $(p_x, p_y, p_z)$ in the body's axes: x forward, y right, z down (m)
    pub point: [f64; 3],
}

/// A linear spring–damper between two points, acting along the track axes.
#[derive(Clone, Debug, PartialEq)]
pub struct Element {
    /// name used by `critspeed check`, e.g. `"primary, wheelset 1, right"`
    pub name: String,
    /// the end that the force $F$ acts on
    pub a: Attachment,
    /// the other end (it gets $−F$)
    pub b: Attachment,
    /// stiffness along x, y, z (N/m)
    pub stiffness: [f64; 3],
    /// damping along x, y, z (N s/m)
    pub damping: [f64; 3],
    /// stiffness in series with the damper along x, y, z (N/m; a Maxwell element,
    /// docs/model.md §13); `None`: the damper is rigidly attached (the spring ∥ damper above)
    pub series_stiffness: [Option<f64>; 3],
    /// the damper's force–velocity characteristic along x, y, z (docs/model.md §13), for a
    /// damper on series stiffness; `None`: linear, its `damping`
    pub force_velocity: [Option<ForceVelocity>; 3],
    /// a lateral bump stop on this element's lateral deflection (docs/model.md §13): free play
    /// $±δ_b$, then the stop's law; `None`: no stop
    pub bump_stop: Option<StopSpec>,
}

/// The stroke of a damper on series stiffness (a Maxwell element, docs/model.md §13), one
/// state $z$: along its axis the deflection is $Δ = b\,q$, the bushes carry $F = k_s(Δ − z)$
/// and the damper $c\,\dot z = k_s(Δ − z)$.
///
/// Identical dampers on the same deflection up to its sign (the right and left damper of a
/// pair, keyed per side) share one stroke: on $z_L = ±z_R$ their forces add up exactly, and
/// the difference of their strokes decays on its own at the rate $k_s/c$ without acting on any
/// body (a stable eigenvalue $−k_s/c$ that is not a state). So a yaw-damper pair adds one state
/// per bogie, and [`Maxwell::stiffness`] and [`Maxwell::damping`] are the pair's sums.
#[derive(Clone, Debug, PartialEq)]
pub struct Maxwell {
    /// e.g. `"yaw damper, frame 1"` (the element's name without its side when a pair shares it)
    pub name: String,
    /// the deflection $Δ = b\,q$: `(coordinate, coefficient)` pairs (m per m or per rad)
    pub row: Vec<(usize, f64)>,
    /// series stiffness $k_s$, summed over the dampers sharing the stroke (N/m)
    pub stiffness: f64,
    /// damping $c$, summed over the dampers sharing the stroke (N s/m)
    pub damping: f64,
    /// how many dampers share the stroke (1, or 2 for a pair)
    pub dampers: usize,
    /// each damper's force–velocity characteristic; `None`: linear, $c/$dampers each
    pub law: Option<ForceVelocity>,
}

impl Maxwell {
    /// $k_s/c$ (1/s): the stroke's relaxation rate.
    pub fn rate(&self) -> f64 {
        self.stiffness / self.damping
    }

    /// The deflection $Δ = b\,q$ (m) at coordinates `q`.
    #[inline]
    pub fn deflection(&self, q: &[f64]) -> f64 {
        self.row.iter().fold(0.0, |s, &(j, b)| s + b * q[j])
    }

    /// The force in each damper's bushes, $k_s(Δ − z)$ (N), at coordinates `q` and stroke `z`.
    #[inline]
    pub fn force(&self, q: &[f64], z: f64) -> f64 {
        self.stiffness / self.dampers as f64 * (self.deflection(q) - z)
    }

    /// The stroke rate $\dot z$ (m/s) at `q` and `z`, and the factor by which the rate's
    /// linear form $(k_s/c)(b\,q − z)$ must be multiplied for its derivative: 1 for a linear
    /// damper, $c/g'(\dot z)$ on a force–velocity curve.
    #[inline]
    pub fn rate_at(&self, q: &[f64], z: f64) -> (f64, f64) {
        match &self.law {
            None => (self.rate() * (self.deflection(q) - z), 1.0),
            Some(g) => {
                let (v, inv_slope) = g.velocity_at(self.force(q, z));
                (v, inv_slope * self.damping / self.dampers as f64)
            }
        }
    }
}

/// The assembled vehicle: bodies, elements and the common wheel–rail contact.
#[derive(Clone, Debug)]
pub struct Vehicle {
    /// the layout it was built as
    pub layout: Layout,
    /// bodies in state order
    pub bodies: Vec<Body>,
    /// spring–damper elements
    pub elements: Vec<Element>,
    /// the strokes of the dampers on series stiffness, in state order after $\dot q$
    pub maxwell: Vec<Maxwell>,
    /// the lateral bump stops (docs/model.md §13), each on one lateral deflection
    pub stops: Vec<BumpStop>,
    /// wheel–rail contact shared by every wheelset: geometry table, creep law, spin, flange,
    /// axle load and nominal radius (its `suspension` is the primary, per side, which the
    /// elements already hold)
    pub contact: Wheelset,
    /// each wheelset's own contact geometry, front to rear (`None`, or beyond the list: the
    /// common `contact.table`); see [`Vehicle::with_wheelset_tables`]
    pub(super) wheelset_tables: Vec<Option<ContactTable>>,
    /// $y$ index of each wheelset, front to rear
    wheelset_dofs: Vec<usize>,
    /// generalised mass per coordinate (kg or kg m²)
    mass: Vec<f64>,
    /// $K$, row-major, dofs × dofs (the Maxwell elements' series stiffness $k_s b^{\mathsf T} b$
    /// included)
    stiffness: Vec<f64>,
    /// $C$, row-major, dofs × dofs
    damping: Vec<f64>,
    /// the nonzero entries of $K$ and $C$ row by row, for $f$ (see [`Sparse`])
    sparse: [Sparse; 2],
    /// the nonzero entries of $G$ (dofs × strokes, $G_{ik} = k_{s,k}\,b_{k,i}$): the strokes'
    /// generalised forces $G z$
    coupling: Sparse,
    /// the nonzero entries of the Jacobian's lower block, for $J\Phi$ (see [`Lower`])
    lower: Lower,
}

/// One entry of the Jacobian's lower block $M^{-1}(∂Q/∂x)$, row $n + i$: its column, the
/// elements' part $−K_{ik}$ (or $−C_{ik}$), that part divided by $m_i$, and, when the
/// wheelset of row $i$ has contact forces in this column, which of the four derivatives
/// $(y, ψ, \dot y, \dot ψ)$ of that wheelset's force (row's `contact` below) it is.
#[derive(Clone, Copy, Debug)]
struct LowerEntry {
    col: usize,
    base: f64,
    scaled: f64,
    contact: Option<usize>,
    /// this entry's bump-stop terms: `Lower::stop_terms[stops.0..stops.1]`
    stops: (usize, usize),
}

/// The sparsity of the Jacobian's lower block, known at assembly: the elements' nonzero
/// entries and the four contact columns of each wheelset row. [`Vehicle`]'s
/// `rhs_variational` forms $J\Phi$ from it: each entry is the value the dense Jacobian
/// holds (`((−K_{ik}) + ∂Q_c)/m_i`, the same operations), summed over the row in column
/// order as the dense product's nonzero terms, so $J\Phi$ is the same to the bit; but it
/// neither fills nor divides the dense $N × N$ Jacobian nor gathers its nonzeros at every
/// stage (two allocations and 392 divisions a stage on the car).
#[derive(Clone, Debug, Default)]
struct Lower {
    entries: Vec<LowerEntry>,
    /// row i is `entries[starts[i]..starts[i + 1]]`
    starts: Vec<usize>,
    /// per row: `(wheelset number, 0 for its lateral force row, 1 for its yaw moment row)`
    contact: Vec<Option<(usize, usize)>>,
    /// per row: the generalised mass it is divided by (1 for a stroke's row)
    divisors: Vec<f64>,
    /// `(stop, b_i b_j)`: entry $(i, j)$ of a bump stop's $b^{\mathsf T} F'(Δ)\,b$, in stop order
    stop_terms: Vec<(usize, f64)>,
}

impl Lower {
    /// From the dense lower block `block` (row-major, `rows` × `cols`: the $n$ acceleration
    /// rows, then one row per Maxwell stroke) and each row's divisor (its generalised mass; 1
    /// for a stroke).
    fn new(
        block: &[f64],
        cols: usize,
        divisors: &[f64],
        (n, wheelsets): (usize, &[usize]),
        stops: &[BumpStop],
    ) -> Self {
        let mut lower = Lower {
            entries: Vec::new(),
            starts: vec![0],
            contact: Vec::with_capacity(divisors.len()),
            divisors: divisors.to_vec(),
            stop_terms: Vec::new(),
        };
        for (i, (row, &divisor)) in block.chunks_exact(cols.max(1)).zip(divisors).enumerate() {
            let row_contact = wheelsets
                .iter()
                .enumerate()
                .find_map(|(j, &w)| (i == w || i == w + 1).then_some((j, i - w)));
            lower.contact.push(row_contact);
            let contact_cols = row_contact.map(|(j, _)| {
                let w = wheelsets[j];
                [w, w + 1, n + w, n + w + 1]
            });
            for (col, &base) in row.iter().enumerate() {
                let contact = contact_cols.and_then(|c| c.iter().position(|&k| k == col));
                let first = lower.stop_terms.len();
                for (k, stop) in stops.iter().enumerate() {
                    let coef = |j: usize| stop.row.iter().find(|r| r.0 == j).map(|r| r.1);
                    if let (Some(bi), Some(bj)) = (coef(i), coef(col)) {
                        lower.stop_terms.push((k, bi * bj));
                    }
                }
                let stop_range = (first, lower.stop_terms.len());
                if base != 0.0 || contact.is_some() || stop_range.1 > first {
                    lower.entries.push(LowerEntry {
                        col,
                        base,
                        scaled: base / divisor,
                        contact,
                        stops: stop_range,
                    });
                }
            }
            lower.starts.push(lower.entries.len());
        }
        lower
    }

    /// Number of rows: the accelerations, then the strokes.
    fn rows(&self) -> usize {
        self.divisors.len()
    }
}

/// The nonzero entries of a dofs × dofs matrix, row by row: `(column, value)` pairs, row `i`
/// being `entries[starts[i]..starts[i + 1]]`. Each body is joined to a few others, so on the
/// car about a third of $K$ and $C$ is nonzero: with the dense rows, the elements' forces
/// were 19 % of a simulation of the S1002 car. The sums run over the nonzero entries in the
/// dense rows' order, so $f$ is the same to the bit (a zero entry's product adds nothing).
#[derive(Clone, Debug, Default)]
struct Sparse {
    entries: Vec<(usize, f64)>,
    starts: Vec<usize>,
}

impl Sparse {
    fn new(dense: &[f64], n: usize) -> Self {
        let mut sparse = Sparse {
            entries: Vec::new(),
            starts: vec![0],
        };
        for row in dense.chunks_exact(n.max(1)) {
            let nonzero = row.iter().enumerate().filter(|(_, v)| **v != 0.0);
            sparse.entries.extend(nonzero.map(|(j, &v)| (j, v)));
            sparse.starts.push(sparse.entries.len());
        }
        sparse
    }

    /// Row `i` times `v`, summed from 0 in column order.
    #[inline(always)]
    fn row_dot(&self, i: usize, v: &[f64]) -> f64 {
        self.entries[self.starts[i]..self.starts[i + 1]]
            .iter()
            .fold(0.0, |s, &(j, a)| s + a * v[j])
    }
}

/// Why an assembly is not valid (a builder's error: the study layer checks values first).
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum AssemblyError {
    #[error("body '{name}': mass and inertias must be positive and finite")]
    BadBody { name: String },
    #[error("element '{name}' refers to body {body}, but there are {count} bodies")]
    NoSuchBody {
        name: String,
        body: usize,
        count: usize,
    },
    #[error(
        "element '{name}': stiffness, damping and points must be finite, k and c non-negative"
    )]
    BadElement { name: String },
    #[error("a vehicle needs at least one wheelset, listed before the other bodies")]
    NoWheelset,
    #[error("element '{name}': a force-velocity curve needs the damper's series stiffness")]
    CurveWithoutSeries { name: String },
    #[error(
        "{strokes} damper stroke(s) ({names}) give {states} states, not among the sizes the \
         analyses are compiled for, {sizes:?}: give series stiffness to fewer dampers (one or \
         two pairs per bogie frame)"
    )]
    UnsupportedStates {
        states: usize,
        strokes: usize,
        names: String,
        sizes: Vec<usize>,
    },
    #[error(
        "{given} wheelset contact geometries given, but the vehicle has {wheelsets} wheelsets"
    )]
    WheelsetTables { given: usize, wheelsets: usize },
}

/// Row of $B$ for one axis of an attachment's displacement, over `n` coordinates.
fn displacement_row(bodies: &[Body], at: &Attachment, axis: usize, n: usize) -> Vec<f64> {
    let mut row = vec![0.0; n];
    let Some(b) = at.body.and_then(|i| bodies.get(i)) else {
        return row;
    };
    let [px, py, pz] = at.point;
    let (y, psi, phi) = (b.dof, b.dof + 1, b.roll_inertia.map(|_| b.dof + 2));
    match axis {
        0 => row[psi] = -py,
        1 => {
            row[y] = 1.0;
            row[psi] = px;
            if let Some(f) = phi {
                row[f] = pz;
            }
        }
        _ => {
            if let Some(f) = phi {
                row[f] = -py;
            }
        }
    }
    row
}

/// Adds the stroke of a damper (series stiffness `ks`, damping `c`, deflection row `b` over the
/// coordinates) to `strokes`, or joins it to an identical damper's on the same deflection up to
/// its sign (see [`Maxwell`]).
fn add_stroke(
    strokes: &mut Vec<Maxwell>,
    name: &str,
    b: &[f64],
    (ks, c): (f64, f64),
    law: Option<&ForceVelocity>,
) {
    let row: Vec<(usize, f64)> = b
        .iter()
        .enumerate()
        .filter(|(_, v)| **v != 0.0)
        .map(|(j, &v)| (j, v))
        .collect();
    let same = |mx: &Maxwell| {
        let (per_k, per_c) = (
            mx.stiffness / mx.dampers as f64,
            mx.damping / mx.dampers as f64,
        );
        let equal = |sign: f64| {
            mx.row.len() == row.len()
                && mx
                    .row
                    .iter()
                    .zip(&row)
                    .all(|(p, r)| p.0 == r.0 && p.1 == sign * r.1)
        };
        per_k == ks && per_c == c && mx.law.as_ref() == law && (equal(1.0) || equal(-1.0))
    };
    if let Some(mx) = strokes.iter_mut().find(|mx| same(mx)) {
        if mx.dampers == 1 {
            if let Some((pair, _side)) = mx.name.rsplit_once(", ") {
                mx.name = pair.to_string();
            }
        }
        mx.stiffness += ks;
        mx.damping += c;
        mx.dampers += 1;
        return;
    }
    strokes.push(Maxwell {
        name: name.to_string(),
        row,
        stiffness: ks,
        damping: c,
        dampers: 1,
        law: law.cloned(),
    });
}

impl Vehicle {
    /// Numbers the bodies' coordinates, checks the data and assembles $M$, $K$, $C$.
    /// Bodies must list the wheelsets first (the leading one first).
    pub fn assemble(
        layout: Layout,
        mut bodies: Vec<Body>,
        elements: Vec<Element>,
        contact: Wheelset,
    ) -> Result<Self, AssemblyError> {
        let mut n = 0;
        let mut mass = Vec::new();
        for b in &mut bodies {
            let inertias = [Some(b.mass), Some(b.yaw_inertia), b.roll_inertia];
            if inertias
                .iter()
                .flatten()
                .any(|v| !(v.is_finite() && *v > 0.0))
            {
                return Err(AssemblyError::BadBody {
                    name: b.name.clone(),
                });
            }
            b.dof = n;
            n += b.dofs();
            mass.extend(inertias.iter().flatten());
        }
        let wheelset_dofs: Vec<usize> = bodies
            .iter()
            .take_while(|b| b.kind == BodyKind::Wheelset)
            .map(|b| b.dof)
            .collect();
        if wheelset_dofs.is_empty()
            || bodies
                .iter()
                .filter(|b| b.kind == BodyKind::Wheelset)
                .count()
                != wheelset_dofs.len()
        {
            return Err(AssemblyError::NoWheelset);
        }
        let mut stiffness = vec![0.0; n * n];
        let mut damping = vec![0.0; n * n];
        let mut maxwell: Vec<Maxwell> = Vec::new();
        let mut stops: Vec<BumpStop> = Vec::new();
        for e in &elements {
            for at in [&e.a, &e.b] {
                if let Some(i) = at.body.filter(|&i| i >= bodies.len()) {
                    return Err(AssemblyError::NoSuchBody {
                        name: e.name.clone(),
                        body: i,
                        count: bodies.len(),
                    });
                }
            }
            let finite = e.a.point.iter().chain(&e.b.point).all(|v| v.is_finite());
            let values = e.stiffness.iter().chain(&e.damping);
            let series_ok = e
                .series_stiffness
                .iter()
                .flatten()
                .all(|k| k.is_finite() && *k > 0.0);
            if !finite || !series_ok || values.clone().any(|v| !(v.is_finite() && *v >= 0.0)) {
                return Err(AssemblyError::BadElement {
                    name: e.name.clone(),
                });
            }
            if (0..3).any(|a| e.force_velocity[a].is_some() && e.series_stiffness[a].is_none()) {
                return Err(AssemblyError::CurveWithoutSeries {
                    name: e.name.clone(),
                });
            }
            if let Some(spec) = &e.bump_stop {
                let k = spec.law.initial_stiffness();
                let ok = |v: f64| v.is_finite() && v > 0.0;
                if !(ok(spec.clearance) && ok(k)) {
                    return Err(AssemblyError::BadElement {
                        name: e.name.clone(),
                    });
                }
                let ra = displacement_row(&bodies, &e.a, 1, n);
                let rb = displacement_row(&bodies, &e.b, 1, n);
                let row = ra.iter().zip(&rb).map(|(a, b)| a - b).enumerate();
                stops.push(BumpStop {
                    name: e.name.clone(),
                    row: row.filter(|(_, v)| *v != 0.0).collect(),
                    clearance: spec.clearance,
                    law: spec.law,
                });
            }
            for axis in 0..3 {
                let (k, c) = (e.stiffness[axis], e.damping[axis]);
                if k == 0.0 && c == 0.0 {
                    continue;
                }
                let ra = displacement_row(&bodies, &e.a, axis, n);
                let rb = displacement_row(&bodies, &e.b, axis, n);
                let b: Vec<f64> = ra.iter().zip(&rb).map(|(a, b)| a - b).collect();
                // a damper on series stiffness is a stroke state, not a term of C (a series
                // spring without a damper transmits nothing)
                let series = e.series_stiffness[axis].filter(|_| c > 0.0);
                let c_direct = if series.is_some() { 0.0 } else { c };
                for i in (0..n).filter(|&i| b[i] != 0.0) {
                    for j in (0..n).filter(|&j| b[j] != 0.0) {
                        stiffness[i * n + j] += k * b[i] * b[j];
                        damping[i * n + j] += c_direct * b[i] * b[j];
                    }
                }
                if let Some(ks) = series.filter(|_| b.iter().any(|v| *v != 0.0)) {
                    for i in (0..n).filter(|&i| b[i] != 0.0) {
                        for j in (0..n).filter(|&j| b[j] != 0.0) {
                            stiffness[i * n + j] += ks * b[i] * b[j];
                        }
                    }
                    let law = e.force_velocity[axis].as_ref();
                    add_stroke(&mut maxwell, &e.name, &b, (ks, c), law);
                }
            }
        }
        let m = maxwell.len();
        let s = 2 * n + m;
        let mut coupling = vec![0.0; n * m];
        for (k, mx) in maxwell.iter().enumerate() {
            for &(i, b) in &mx.row {
                coupling[i * m + k] = mx.stiffness * b;
            }
        }
        // the lower block of the Jacobian without the contact: −K, −C and G in the
        // accelerations' rows (before the masses), the strokes' rows after them
        let mut block = vec![0.0; (n + m) * s];
        for i in 0..n {
            let row = &mut block[i * s..(i + 1) * s];
            for j in 0..n {
                row[j] = -stiffness[i * n + j];
                row[n + j] = -damping[i * n + j];
            }
            for k in 0..m {
                row[2 * n + k] = coupling[i * m + k];
            }
        }
        for (k, mx) in maxwell.iter().enumerate() {
            let row = &mut block[(n + k) * s..(n + k + 1) * s];
            for &(j, b) in &mx.row {
                row[j] = mx.rate() * b;
            }
            row[2 * n + k] = -mx.rate();
        }
        // (an assembly without strokes keeps any size: the analyses refuse an uncompiled one
        // themselves; with strokes the refusal here can name the dampers)
        if m > 0 && !super::STATE_SIZES.contains(&s) {
            let names: Vec<&str> = maxwell.iter().map(|mx| mx.name.as_str()).collect();
            return Err(AssemblyError::UnsupportedStates {
                states: s,
                strokes: m,
                names: names.join("; "),
                sizes: super::STATE_SIZES.to_vec(),
            });
        }
        let divisors: Vec<f64> = mass.iter().copied().chain(vec![1.0; m]).collect();
        let sparse = [Sparse::new(&stiffness, n), Sparse::new(&damping, n)];
        let lower = Lower::new(&block, s, &divisors, (n, &wheelset_dofs), &stops);
        Ok(Self {
            layout,
            bodies,
            elements,
            maxwell,
            stops,
            contact,
            wheelset_tables: Vec::new(),
            wheelset_dofs,
            mass,
            stiffness,
            damping,
            sparse,
            coupling: Sparse::new(&coupling, m),
            lower,
        })
    }

    /// Number of generalised coordinates $q$.
    pub fn dofs(&self) -> usize {
        self.mass.len()
    }

    /// Number of first-order states: $2 \times$ [`Self::dofs`] for $(q, \dot q)$, and one per
    /// damper stroke ([`Self::maxwell`]).
    pub fn states(&self) -> usize {
        2 * self.mass.len() + self.maxwell.len()
    }

    /// $y$ index of each wheelset, front to rear.
    pub fn wheelset_dofs(&self) -> &[usize] {
        &self.wheelset_dofs
    }

    /// The generalised mass of coordinate `i` (kg or kg m²).
    pub fn generalised_mass(&self, i: usize) -> f64 {
        self.mass[i]
    }

    /// $K_{ij}$ of the assembled elements (N/m, N, N m/rad …).
    pub fn stiffness(&self, i: usize, j: usize) -> f64 {
        self.stiffness[i * self.dofs() + j]
    }

    /// $C_{ij}$ of the assembled elements.
    pub fn damping(&self, i: usize, j: usize) -> f64 {
        self.damping[i * self.dofs() + j]
    }

    /// The same vehicle with another creep law (the linear analysis needs Kalker's too).
    pub fn with_law(&self, law: CreepLaw) -> Self {
        let mut v = self.clone();
        v.contact.creep_law = law;
        v
    }

    /// The study's creep law.
    pub fn creep_law(&self) -> CreepLaw {
        self.contact.creep_law
    }

    /// Names of the coordinates in state order, e.g. `y_wheelset_1`, `psi_frame_1`.
    pub fn coordinate_names(&self) -> Vec<String> {
        let mut names = Vec::with_capacity(self.dofs());
        for b in &self.bodies {
            let tag = b.name.replace(' ', "_");
            names.push(format!("y_{tag}"));
            names.push(format!("psi_{tag}"));
            if b.roll_inertia.is_some() {
                names.push(format!("phi_{tag}"));
            }
        }
        names
    }

    /// Names of the damper strokes in state order, e.g. `z_yaw_damper_frame_1` (m).
    pub fn stroke_names(&self) -> Vec<String> {
        self.maxwell
            .iter()
            .map(|mx| format!("z_{}", mx.name.replace(", ", "_").replace(' ', "_")))
            .collect()
    }

    /// Contact forces of wheelset `w` (its $y$ index) at state `x`.
    #[inline]
    fn wheelset_state(&self, x: &[f64], w: usize) -> [f64; 4] {
        let n = self.dofs();
        [x[w], x[w + 1], x[n + w], x[n + w + 1]]
    }

    /// The velocities into the first $n$ values of `out`, the elements' forces
    /// $−Kq − C\dot q + Gz$ into the next $n$ (not yet divided by the masses), and the strokes'
    /// rates $\dot z = (k_s/c)(b\,q − z)$ into the rest.
    fn elements_into(&self, x: &[f64], out: &mut [f64]) {
        let n = self.dofs();
        let (q, rest) = x.split_at(n);
        let (qd, z) = rest.split_at(n.min(rest.len()));
        let (vel, rest) = out.split_at_mut(n);
        let (acc, zd) = rest.split_at_mut(n.min(rest.len()));
        vel.copy_from_slice(qd);
        let [k, c] = &self.sparse;
        for (i, a) in acc.iter_mut().enumerate() {
            *a = -k.row_dot(i, q) - c.row_dot(i, qd);
        }
        if self.maxwell.is_empty() {
            return;
        }
        for (i, a) in acc.iter_mut().enumerate() {
            *a += self.coupling.row_dot(i, z);
        }
        for ((d, mx), &zk) in zd.iter_mut().zip(&self.maxwell).zip(z) {
            *d = mx.rate_at(q, zk).0;
        }
    }

    /// Adds the bump stops' generalised forces $b^{\mathsf T} F(b\,q)$ at coordinates `q` to
    /// `acc` (before the masses).
    #[inline]
    fn stops_into(&self, q: &[f64], acc: &mut [f64]) {
        for stop in &self.stops {
            let (f, _) = stop.force(stop.deflection(q));
            for &(i, b) in &stop.row {
                acc[i] += b * f;
            }
        }
    }

    /// Adds the bump stops' part of $J\,ξ$, $b^{\mathsf T} F'(b\,q)\,b\,ξ_q$ at coordinates
    /// `q`, to `acc` (before the masses).
    fn stops_tangent_into(&self, q: &[f64], xi: &[f64], acc: &mut [f64]) {
        for stop in &self.stops {
            let (_, slope) = stop.force(stop.deflection(q));
            let d = slope * stop.deflection(xi);
            for &(i, b) in &stop.row {
                acc[i] += b * d;
            }
        }
    }

    /// Each stroke's derivative factor at state `x` ([`Maxwell::rate_at`]): 1 for a linear
    /// damper. `None` when every damper is linear (nothing to scale).
    fn stroke_factors(&self, x: &[f64]) -> Option<Vec<f64>> {
        if self.maxwell.iter().all(|mx| mx.law.is_none()) {
            return None;
        }
        let n = self.dofs();
        let (q, z) = (&x[..n], x.get(2 * n..).unwrap_or(&[]));
        Some(
            self.maxwell
                .iter()
                .zip(z)
                .map(|(mx, &zk)| mx.rate_at(q, zk).1)
                .collect(),
        )
    }

    /// $f(x; V)$ into `out`; both slices hold [`Self::states`] values.
    pub fn rhs_into(&self, x: &[f64], v: f64, out: &mut [f64]) {
        let n = self.dofs();
        self.elements_into(x, out);
        self.stops_into(&x[..n], &mut out[n..2 * n]);
        let acc = &mut out[n..2 * n];
        for (j, &w) in self.wheelset_dofs.iter().enumerate() {
            let (qy, qpsi) = self.wheelset_forces(j, &self.wheelset_state(x, w), v);
            // (a + b == b + a exactly: the same sum as docs/model.md §8 written out)
            acc[w] += qy;
            acc[w + 1] += qpsi;
        }
        for (a, m) in acc.iter_mut().zip(&self.mass) {
            *a /= m;
        }
    }

    /// The exact Jacobian $∂f/∂x$ into `jac`, **column-major** (as nalgebra stores it),
    /// states × states.
    pub fn jacobian_into(&self, x: &[f64], v: f64, jac: &mut [f64]) {
        self.evaluate(x, v, None, jac);
    }

    /// $f(x; V)$ into `out` and $∂f/∂x$ into `jac` (column-major) from one evaluation: the
    /// contact forces' dual numbers carry their values too, so the variational equations do
    /// not evaluate the contact model a second time for $f$ (on the 4-state wheelset that
    /// second evaluation was a third of a variational step).
    pub fn rhs_jacobian_into(&self, x: &[f64], v: f64, out: &mut [f64], jac: &mut [f64]) {
        self.evaluate(x, v, Some(out), jac);
    }

    /// $f(x; V)$ into `out` and the directional derivative $J\,\xi$ into `d`: the elements'
    /// linear map applied to ξ, and each wheelset's contact forces in one-direction dual
    /// numbers (a tangent flow needs no more than this; forming the whole Jacobian with four
    /// directions per wheelset cost twice as much).
    pub fn rhs_tangent_into(&self, x: &[f64], v: f64, xi: &[f64], out: &mut [f64], d: &mut [f64]) {
        let n = self.dofs();
        self.elements_into(x, out);
        self.elements_into(xi, d);
        self.stops_into(&x[..n], &mut out[n..2 * n]);
        self.stops_tangent_into(&x[..n], &xi[..n], &mut d[n..2 * n]);
        if let Some(factors) = self.stroke_factors(x) {
            // the strokes' rows of J ξ: the linear form at ξ times each stroke's factor at x
            let (q, z) = (&xi[..n], &xi[2 * n..]);
            for (k, (mx, fk)) in self.maxwell.iter().zip(&factors).enumerate() {
                d[2 * n + k] = mx.rate() * (mx.deflection(q) - z[k]) * fk;
            }
        }
        for (j, &w) in self.wheelset_dofs.iter().enumerate() {
            let (xw, dw) = (self.wheelset_state(x, w), self.wheelset_state(xi, w));
            let xd: [Dual<1>; 4] = std::array::from_fn(|k| Dual {
                re: xw[k],
                eps: [dw[k]],
            });
            let (qy, qpsi) = self.wheelset_forces(j, &xd, v);
            out[n + w] += qy.re;
            out[n + w + 1] += qpsi.re;
            d[n + w] += qy.eps[0];
            d[n + w + 1] += qpsi.eps[0];
        }
        for (i, m) in self.mass.iter().enumerate() {
            out[n + i] /= m;
            d[n + i] /= m;
        }
    }

    fn evaluate(&self, x: &[f64], v: f64, mut out: Option<&mut [f64]>, jac: &mut [f64]) {
        let n = self.dofs();
        let s = self.states();
        let at = |r: usize, c: usize| c * s + r;
        jac.fill(0.0);
        for i in 0..n {
            jac[at(i, n + i)] = 1.0;
        }
        // the lower block without the contact, as assembled (−K, −C, G; the strokes' rows)
        let lower = &self.lower;
        let factors = self.stroke_factors(x);
        for i in 0..lower.rows() {
            let factor = factors.as_ref().and_then(|f| f.get(i.wrapping_sub(n)));
            for e in &lower.entries[lower.starts[i]..lower.starts[i + 1]] {
                jac[at(n + i, e.col)] = factor.map_or(e.base, |f| e.base * f);
            }
        }
        // the bump stops' b^T F'(Δ) b, added entry by entry in stop order (as `Lower` sums it)
        for stop in &self.stops {
            let (_, slope) = stop.force(stop.deflection(&x[..n]));
            for &(i, bi) in &stop.row {
                for &(j, bj) in &stop.row {
                    jac[at(n + i, j)] += bi * bj * slope;
                }
            }
        }
        if let Some(out) = out.as_deref_mut() {
            self.elements_into(x, out);
            self.stops_into(&x[..n], &mut out[n..2 * n]);
        }
        for (j, &w) in self.wheelset_dofs.iter().enumerate() {
            let xw = self.wheelset_state(x, w);
            let xd: [Dual<4>; 4] = std::array::from_fn(|k| Dual::var(xw[k], k));
            let (qy, qpsi) = self.wheelset_forces(j, &xd, v);
            let cols = [w, w + 1, n + w, n + w + 1];
            for (row, d) in [(n + w, qy), (n + w + 1, qpsi)] {
                for (&c, e) in cols.iter().zip(d.eps) {
                    jac[at(row, c)] += e;
                }
            }
            if let Some(out) = out.as_deref_mut() {
                out[n + w] += qy.re;
                out[n + w + 1] += qpsi.re;
            }
        }
        for i in 0..n {
            for c in 0..s {
                jac[at(n + i, c)] /= self.mass[i];
            }
        }
        if let Some(out) = out {
            for (a, m) in out[n..2 * n].iter_mut().zip(&self.mass) {
                *a /= m;
            }
        }
    }

    /// Effective conicity at the centre (–) of the leading wheelset's contact geometry (the
    /// common one unless the wheelsets have their own, [`Self::wheelset_conicities`]).
    pub fn centre_conicity(&self) -> f64 {
        super::centre_conicity(self.wheelset_table(0))
    }

    /// Kinematic (Klingel) wavelength of one free wheelset (m), docs/model.md §9, at the
    /// leading wheelset's centre conicity ([`Self::centre_conicity`]).
    pub fn klingel_wavelength(&self) -> f64 {
        let p = &self.contact.params;
        2.0 * std::f64::consts::PI
            * (p.rolling_radius * p.half_contact_distance / self.centre_conicity()).sqrt()
    }

    /// Switching function `k` of the flange dead bands at state `x` (at least the wheelsets'
    /// coordinates; NaN if `k` or `x` is too short): wheelset `k/2`'s $y − δ_f$ for even `k`
    /// (right flange), $−y − δ_f$ for odd `k` (left), as the 4-state model. The vector fields
    /// of the vehicle and of the ramp ([`crate::simulate::RampField`]) both use it.
    pub fn flange_switch(&self, k: usize, x: &[f64]) -> f64 {
        let c = self.contact.flange.map_or(0.0, |f| f.clearance);
        let y = self
            .wheelset_dofs
            .get(k / 2)
            .and_then(|&w| x.get(w))
            .map_or(f64::NAN, |&y| y);
        if k.is_multiple_of(2) {
            y - c
        } else {
            -y - c
        }
    }

    /// Number of switching functions: the flange dead bands' ([`Self::flange_switch`]), then
    /// two per knee of each stroke's force–velocity curve, then each bump stop's
    /// ([`BumpStop::switches`]: two for its edges, two per knee of a table).
    pub fn switches(&self) -> usize {
        let flange = if self.contact.flange.is_some() {
            2 * self.wheelset_dofs.len()
        } else {
            0
        };
        let knees: usize = self
            .maxwell
            .iter()
            .map(|mx| mx.law.as_ref().map_or(0, |g| 2 * g.knee_forces().len()))
            .sum();
        let stops: usize = self.stops.iter().map(BumpStop::switches).sum();
        flange + knees + stops
    }

    /// Switching function `k` of [`Self::switches`] at state `x` (NaN if `k` or `x` is out of
    /// range): the flange's, then for each stroke on a curve and each knee $F_i$ of it,
    /// $F − F_i$ and $−F − F_i$ with $F = k_s(Δ − z)$ the force in each damper, written with the
    /// comparisons of [`ForceVelocity::velocity_at`] so that the sign changes exactly where
    /// the curve's segment does; then each bump stop's [`BumpStop::switch`] at its deflection.
    pub fn switch(&self, k: usize, x: &[f64]) -> f64 {
        let flange = if self.contact.flange.is_some() {
            2 * self.wheelset_dofs.len()
        } else {
            0
        };
        if k < flange {
            return self.flange_switch(k, x);
        }
        let n = self.dofs();
        let mut k = k - flange;
        for (j, mx) in self.maxwell.iter().enumerate() {
            let Some(g) = &mx.law else { continue };
            let knees = g.knee_forces();
            if k < 2 * knees.len() {
                let (Some(q), Some(&z)) = (x.get(..n), x.get(2 * n + j)) else {
                    return f64::NAN;
                };
                let f = mx.force(q, z);
                let fi = knees[k / 2];
                return if k.is_multiple_of(2) { f - fi } else { -f - fi };
            }
            k -= 2 * knees.len();
        }
        for stop in &self.stops {
            if k < stop.switches() {
                return match x.get(..n) {
                    Some(q) => stop.switch(k, stop.deflection(q)),
                    None => f64::NAN,
                };
            }
            k -= stop.switches();
        }
        f64::NAN
    }

    /// Sum of guiding forces ΣY (N) of each wheelset at state `x` (EN 14363): the lateral
    /// contact force $Q_{c,y}$ (creep after the creep law, gravitational stiffness, flange).
    pub fn guiding_forces(&self, x: &[f64], v: f64) -> Vec<f64> {
        self.wheelset_dofs
            .iter()
            .enumerate()
            .map(|(j, &w)| self.wheelset_forces(j, &self.wheelset_state(x, w), v).0)
            .collect()
    }
}

/// The vehicle as a vector field of `N` states. `N` must equal [`Vehicle::states`]; the
/// analyses choose it from the state size ([`crate::with_states`]). Called with another `N`,
/// every value is NaN, which the integrator reports as a non-finite state (never a panic).
/// The most wheelsets a vehicle has (the car's four): the variational field keeps their
/// contact derivatives on the stack.
const MAX_WHEELSETS: usize = 4;

impl<const N: usize> crate::system::ode::VectorField<N> for Vehicle {
    #[inline]
    fn rhs(&self, x: &SVector<f64, N>, v: f64) -> SVector<f64, N> {
        let mut out = SVector::<f64, N>::from_element(f64::NAN);
        if N == self.states() {
            self.rhs_into(x.as_slice(), v, out.as_mut_slice());
        }
        out
    }
    fn jacobian(&self, x: &SVector<f64, N>, v: f64) -> SMatrix<f64, N, N> {
        let mut jac = SMatrix::<f64, N, N>::from_element(f64::NAN);
        if N == self.states() {
            self.jacobian_into(x.as_slice(), v, jac.as_mut_slice());
        }
        jac
    }
    /// One evaluation of the contact model gives both ([`Vehicle::rhs_jacobian_into`]).
    fn rhs_jacobian(&self, x: &SVector<f64, N>, v: f64) -> (SVector<f64, N>, SMatrix<f64, N, N>) {
        let mut f = SVector::<f64, N>::from_element(f64::NAN);
        let mut jac = SMatrix::<f64, N, N>::from_element(f64::NAN);
        if N == self.states() {
            self.rhs_jacobian_into(x.as_slice(), v, f.as_mut_slice(), jac.as_mut_slice());
        }
        (f, jac)
    }
    /// One evaluation in one-direction dual numbers ([`Vehicle::rhs_tangent_into`]).
    fn rhs_tangent(
        &self,
        x: &SVector<f64, N>,
        v: f64,
        xi: &SVector<f64, N>,
    ) -> (SVector<f64, N>, SVector<f64, N>) {
        let mut f = SVector::<f64, N>::from_element(f64::NAN);
        let mut d = SVector::<f64, N>::from_element(f64::NAN);
        if N == self.states() {
            self.rhs_tangent_into(
                x.as_slice(),
                v,
                xi.as_slice(),
                f.as_mut_slice(),
                d.as_mut_slice(),
            );
        }
        (f, d)
    }
    /// $J\Phi$ with $J = \begin{pmatrix} 0 & I \\ J_q & J_{\dot q} \end{pmatrix}$: the upper
    /// half of the product is the lower half of $\Phi$ (exactly what the dense product gives);
    /// the lower half is the $n × 2n$ block times $\Phi$, over the block's nonzero entries only
    /// (each body is joined to a few others: on the car about a third of the block is nonzero).
    /// A NaN entry is kept, so it still reaches the integrator's finiteness test.
    fn rhs_variational(
        &self,
        x: &SVector<f64, N>,
        v: f64,
        phi: &SMatrix<f64, N, N>,
    ) -> (SVector<f64, N>, SMatrix<f64, N, N>) {
        if N != self.states() || N <= 8 || self.wheelset_dofs.len() > MAX_WHEELSETS {
            // (the single wheelset: the dense product, cheaper than gathering at this size;
            // a wrong N: NaN everywhere)
            let (f, j) = <Self as crate::system::ode::VectorField<N>>::rhs_jacobian(self, x, v);
            return (f, j * phi);
        }
        let n = self.dofs();
        let xs = x.as_slice();
        // f as `rhs_into` forms it, and each wheelset's contact derivatives from the same
        // dual-number evaluation (its real part is the force that f gets)
        let mut f = SVector::<f64, N>::zeros();
        let out = f.as_mut_slice();
        self.elements_into(xs, out);
        self.stops_into(&xs[..n], &mut out[n..2 * n]);
        let mut partials = [[[0.0; 4]; 2]; MAX_WHEELSETS];
        for (j, &w) in self.wheelset_dofs.iter().enumerate() {
            let xw = self.wheelset_state(xs, w);
            let xd: [Dual<4>; 4] = std::array::from_fn(|k| Dual::var(xw[k], k));
            let (qy, qpsi) = self.wheelset_forces(j, &xd, v);
            out[n + w] += qy.re;
            out[n + w + 1] += qpsi.re;
            if let Some(p) = partials.get_mut(j) {
                *p = [qy.eps, qpsi.eps];
            }
        }
        for (a, m) in out[n..2 * n].iter_mut().zip(&self.mass) {
            *a /= m;
        }
        // the lower block's entries, row by row, as the dense Jacobian holds them
        let lower = &self.lower;
        let factors = self.stroke_factors(xs);
        let slopes: Vec<f64> = self
            .stops
            .iter()
            .map(|s| s.force(s.deflection(&xs[..n])).1)
            .collect();
        let mut values = SMatrix::<f64, N, N>::zeros();
        let vals = values.as_mut_slice();
        for i in 0..lower.rows() {
            let row = lower.starts[i]..lower.starts[i + 1];
            let factor = factors.as_ref().and_then(|f| f.get(i.wrapping_sub(n)));
            for (slot, e) in vals[row.clone()].iter_mut().zip(&lower.entries[row]) {
                // (the dense Jacobian's order: −K, then each stop's term, then the contact)
                let terms = &lower.stop_terms[e.stops.0..e.stops.1];
                let base = terms.iter().fold(e.base, |a, &(k, c)| {
                    a + c * slopes.get(k).copied().unwrap_or(f64::NAN)
                });
                *slot = match (e.contact, lower.contact[i], factor) {
                    (Some(k), Some((j, side)), _) => {
                        let d = partials.get(j).map_or(f64::NAN, |p| p[side][k]);
                        (base + d) / lower.divisors[i]
                    }
                    (_, _, Some(f)) => e.scaled * f,
                    _ if terms.is_empty() => e.scaled,
                    _ => base / lower.divisors[i],
                };
            }
        }
        let mut out = SMatrix::<f64, N, N>::zeros();
        let ps = phi.as_slice();
        for (c, col) in out.as_mut_slice().chunks_exact_mut(N).enumerate() {
            let pc = &ps[c * N..(c + 1) * N];
            let (top, bottom) = col.split_at_mut(n);
            top.copy_from_slice(&pc[n..2 * n]);
            for (i, o) in bottom.iter_mut().enumerate() {
                let row = lower.starts[i]..lower.starts[i + 1];
                *o = lower.entries[row.clone()]
                    .iter()
                    .zip(&vals[row])
                    .fold(0.0, |s, (e, &a)| s + a * pc[e.col]);
            }
        }
        (f, out)
    }
    fn switch_count(&self) -> usize {
        self.switches()
    }
    fn switch_value(&self, k: usize, x: &SVector<f64, N>) -> f64 {
        self.switch(k, x.as_slice())
    }
}

impl Vehicle {
    /// The layout's lever arms (m): half the wheelbase a and half the bogie distance l_b
    /// (0 where the layout has none), read from the bodies' positions.
    pub fn layout_arms(&self) -> (f64, f64) {
        let frames: Vec<&Body> = self
            .bodies
            .iter()
            .filter(|b| b.kind == BodyKind::Frame)
            .collect();
        let lb = frames.first().map_or(0.0, |f| f.position_m.abs());
        let a = match (frames.first(), self.bodies.first()) {
            (Some(f), Some(w)) => (w.position_m - f.position_m).abs(),
            _ => 0.0,
        };
        (a, lb)
    }
}
