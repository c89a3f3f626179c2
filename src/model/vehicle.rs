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

use super::Wheelset;
use crate::contact::creep::CreepLaw;
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
    /// wheel–rail contact shared by every wheelset: geometry table, creep law, spin, flange,
    /// axle load and nominal radius (its `suspension` is the primary, per side, which the
    /// elements already hold)
    pub contact: Wheelset,
    /// $y$ index of each wheelset, front to rear
    wheelset_dofs: Vec<usize>,
    /// generalised mass per coordinate (kg or kg m²)
    mass: Vec<f64>,
    /// $K$, row-major, dofs × dofs
    stiffness: Vec<f64>,
    /// $C$, row-major, dofs × dofs
    damping: Vec<f64>,
    /// the nonzero entries of $K$ and $C$ row by row, for $f$ (see [`Sparse`])
    sparse: [Sparse; 2],
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
}

impl Lower {
    fn new(
        n: usize,
        stiffness: &[f64],
        damping: &[f64],
        mass: &[f64],
        wheelsets: &[usize],
    ) -> Self {
        let mut lower = Lower {
            entries: Vec::new(),
            starts: vec![0],
            contact: Vec::with_capacity(n),
        };
        for i in 0..n {
            let row_contact = wheelsets
                .iter()
                .enumerate()
                .find_map(|(j, &w)| (i == w || i == w + 1).then_some((j, i - w)));
            lower.contact.push(row_contact);
            let contact_cols = row_contact.map(|(j, _)| {
                let w = wheelsets[j];
                [w, w + 1, n + w, n + w + 1]
            });
            for col in 0..2 * n {
                let base = if col < n {
                    -stiffness[i * n + col]
                } else {
                    -damping[i * n + col - n]
                };
                let contact = contact_cols.and_then(|c| c.iter().position(|&k| k == col));
                if base != 0.0 || contact.is_some() {
                    lower.entries.push(LowerEntry {
                        col,
                        base,
                        scaled: base / mass[i],
                        contact,
                    });
                }
            }
            lower.starts.push(lower.entries.len());
        }
        lower
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
            if !finite || values.clone().any(|v| !(v.is_finite() && *v >= 0.0)) {
                return Err(AssemblyError::BadElement {
                    name: e.name.clone(),
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
                for i in (0..n).filter(|&i| b[i] != 0.0) {
                    for j in (0..n).filter(|&j| b[j] != 0.0) {
                        stiffness[i * n + j] += k * b[i] * b[j];
                        damping[i * n + j] += c * b[i] * b[j];
                    }
                }
            }
        }
        let sparse = [Sparse::new(&stiffness, n), Sparse::new(&damping, n)];
        let lower = Lower::new(n, &stiffness, &damping, &mass, &wheelset_dofs);
        Ok(Self {
            layout,
            bodies,
            elements,
            contact,
            wheelset_dofs,
            mass,
            stiffness,
            damping,
            sparse,
            lower,
        })
    }

    /// Number of generalised coordinates (half the state size).
    pub fn dofs(&self) -> usize {
        self.mass.len()
    }

    /// Number of first-order states, $2 \times$ [`Self::dofs`].
    pub fn states(&self) -> usize {
        2 * self.mass.len()
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

    /// Contact forces of wheelset `w` (its $y$ index) at state `x`.
    #[inline]
    fn wheelset_state(&self, x: &[f64], w: usize) -> [f64; 4] {
        let n = self.dofs();
        [x[w], x[w + 1], x[n + w], x[n + w + 1]]
    }

    /// The velocities into the upper half of `out` and the elements' forces $−Kq − C\dot q$
    /// into the lower half (not yet divided by the masses).
    fn elements_into(&self, x: &[f64], out: &mut [f64]) {
        let n = self.dofs();
        let (q, qd) = x.split_at(n);
        let (vel, acc) = out.split_at_mut(n);
        vel.copy_from_slice(qd);
        let [k, c] = &self.sparse;
        for (i, a) in acc.iter_mut().enumerate() {
            *a = -k.row_dot(i, q) - c.row_dot(i, qd);
        }
    }

    /// $f(x; V)$ into `out`; both slices hold [`Self::states`] values.
    pub fn rhs_into(&self, x: &[f64], v: f64, out: &mut [f64]) {
        let n = self.dofs();
        self.elements_into(x, out);
        let acc = &mut out[n..];
        for &w in &self.wheelset_dofs {
            let (qy, qpsi) = self.contact.contact_forces(&self.wheelset_state(x, w), v);
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
        for &w in &self.wheelset_dofs {
            let (xw, dw) = (self.wheelset_state(x, w), self.wheelset_state(xi, w));
            let xd: [Dual<1>; 4] = std::array::from_fn(|k| Dual {
                re: xw[k],
                eps: [dw[k]],
            });
            let (qy, qpsi) = self.contact.contact_forces(&xd, v);
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
        let s = 2 * n;
        let at = |r: usize, c: usize| c * s + r;
        jac.fill(0.0);
        for i in 0..n {
            jac[at(i, n + i)] = 1.0;
            for j in 0..n {
                jac[at(n + i, j)] = -self.stiffness[i * n + j];
                jac[at(n + i, n + j)] = -self.damping[i * n + j];
            }
        }
        if let Some(out) = out.as_deref_mut() {
            self.elements_into(x, out);
        }
        for &w in &self.wheelset_dofs {
            let xw = self.wheelset_state(x, w);
            let xd: [Dual<4>; 4] = std::array::from_fn(|k| Dual::var(xw[k], k));
            let (qy, qpsi) = self.contact.contact_forces(&xd, v);
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
            for (a, m) in out[n..].iter_mut().zip(&self.mass) {
                *a /= m;
            }
        }
    }

    /// Effective conicity at the centre (–), of the common contact geometry.
    pub fn centre_conicity(&self) -> f64 {
        self.contact.centre_conicity()
    }

    /// Kinematic (Klingel) wavelength of one free wheelset (m), docs/model.md §9.
    pub fn klingel_wavelength(&self) -> f64 {
        self.contact.klingel_wavelength()
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

    /// Sum of guiding forces ΣY (N) of each wheelset at state `x` (EN 14363): the lateral
    /// contact force $Q_{c,y}$ (creep after the creep law, gravitational stiffness, flange).
    pub fn guiding_forces(&self, x: &[f64], v: f64) -> Vec<f64> {
        self.wheelset_dofs
            .iter()
            .map(|&w| self.contact.contact_forces(&self.wheelset_state(x, w), v).0)
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
        if N != self.states()
            || !N.is_multiple_of(2)
            || N <= 8
            || self.wheelset_dofs.len() > MAX_WHEELSETS
        {
            // (the single wheelset: the dense product, cheaper than gathering at this size;
            // a wrong N: NaN everywhere)
            let (f, j) = <Self as crate::system::ode::VectorField<N>>::rhs_jacobian(self, x, v);
            return (f, j * phi);
        }
        let n = N / 2;
        let xs = x.as_slice();
        // f as `rhs_into` forms it, and each wheelset's contact derivatives from the same
        // dual-number evaluation (its real part is the force that f gets)
        let mut f = SVector::<f64, N>::zeros();
        let out = f.as_mut_slice();
        self.elements_into(xs, out);
        let mut partials = [[[0.0; 4]; 2]; MAX_WHEELSETS];
        for (j, &w) in self.wheelset_dofs.iter().enumerate() {
            let xw = self.wheelset_state(xs, w);
            let xd: [Dual<4>; 4] = std::array::from_fn(|k| Dual::var(xw[k], k));
            let (qy, qpsi) = self.contact.contact_forces(&xd, v);
            out[n + w] += qy.re;
            out[n + w + 1] += qpsi.re;
            if let Some(p) = partials.get_mut(j) {
                *p = [qy.eps, qpsi.eps];
            }
        }
        for (a, m) in out[n..].iter_mut().zip(&self.mass) {
            *a /= m;
        }
        // the lower block's entries, row by row, as the dense Jacobian holds them
        let lower = &self.lower;
        let mut values = SMatrix::<f64, N, N>::zeros();
        let vals = values.as_mut_slice();
        for i in 0..n {
            let row = lower.starts[i]..lower.starts[i + 1];
            for (slot, e) in vals[row.clone()].iter_mut().zip(&lower.entries[row]) {
                *slot = match (e.contact, lower.contact[i]) {
                    (Some(k), Some((j, side))) => {
                        let d = partials.get(j).map_or(f64::NAN, |p| p[side][k]);
                        (e.base + d) / self.mass[i]
                    }
                    _ => e.scaled,
                };
            }
        }
        let mut out = SMatrix::<f64, N, N>::zeros();
        let ps = phi.as_slice();
        for (c, col) in out.as_mut_slice().chunks_exact_mut(N).enumerate() {
            let pc = &ps[c * N..(c + 1) * N];
            let (top, bottom) = col.split_at_mut(n);
            top.copy_from_slice(&pc[n..]);
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
        if self.contact.flange.is_some() {
            2 * self.wheelset_dofs.len()
        } else {
            0
        }
    }
    fn switch_value(&self, k: usize, x: &SVector<f64, N>) -> f64 {
        self.flange_switch(k, x.as_slice())
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
