//! The models: the suspended wheelset's contact and equations of motion (docs/model.md §1–8), and
//! vehicles assembled from bodies, elements and wheelsets (docs/model.md §11, [`vehicle`],
//! [`layouts`]). Every analysis takes a [`Vehicle`]; the single wheelset is its 4-state layout.
//!
//! State $x = (y, ψ, \dot y, \dot ψ)$ (m, rad, m/s, rad/s), forward speed $V > 0$ (m/s).
//! The one right-hand side [`Wheelset::rhs`] serves every analysis; it is generic over
//! [`Scalar`] so that the exact Jacobian comes from the same code ([`Wheelset::jacobian`]).
//!
//! $$m\ddot y = F_{y,R} + F_{y,L} + F_N + F_f + F_s$$
//! $$I_z\ddot ψ = l_0 (F_{x,L} − F_{x,R}) + M_{z,R} + M_{z,L} + M_s$$

pub mod bump_stop;
pub mod damper;
pub mod layouts;
mod table;
#[cfg(test)]
mod tests;
pub mod vehicle;
mod wheelsets;

pub use bump_stop::{BumpStop, StopLaw, StopSpec, StopTable};
pub use damper::ForceVelocity;
pub use layouts::{
    CarBodyParams, DamperCurves, DamperSeries, FrameParams, PrimaryVertical, Secondary, VehicleSpec,
};
pub use vehicle::{Attachment, Body, BodyKind, Element, Layout, Maxwell, Vehicle};

use nalgebra::{Matrix4, Vector4};

use crate::contact::creep::{self, CreepForce, CreepLaw, Creepage};
use crate::contact::table::{ContactTable, WheelState};
use crate::system::scalar::{Dual, Scalar};

/// Rigid wheelset data.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WheelsetParams {
    /// wheelset mass m (kg)
    pub mass: f64,
    /// yaw moment of inertia I_z (kg m²)
    pub yaw_inertia: f64,
    /// axle load W, the vertical load on both contacts together (N)
    pub axle_load: f64,
    /// half the lateral distance between the nominal contact points l0 (m)
    pub half_contact_distance: f64,
    /// nominal rolling radius r0 (m)
    pub rolling_radius: f64,
}

/// Primary suspension, values per side (docs/model.md §7).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Suspension {
    /// lateral stiffness K_py (N/m)
    pub lateral_stiffness: f64,
    /// longitudinal stiffness K_px (N/m)
    pub longitudinal_stiffness: f64,
    /// lateral damping C_py (N s/m)
    pub lateral_damping: f64,
    /// longitudinal damping C_px (N s/m)
    pub longitudinal_damping: f64,
    /// half the lateral spacing of the longitudinal springs d (m)
    pub half_spring_spacing: f64,
}

/// Flange contact: a stiff spring beyond a dead band (docs/model.md §6).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Flange {
    /// flange clearance δ_f (m)
    pub clearance: f64,
    /// flange contact stiffness k_f (N/m)
    pub stiffness: f64,
}

/// The wheelset model: parameters, contact table and creep law.
#[derive(Clone, Debug)]
pub struct Wheelset {
    /// rigid wheelset data
    pub params: WheelsetParams,
    /// primary suspension
    pub suspension: Suspension,
    /// the study's creep law
    pub creep_law: CreepLaw,
    /// whether spin creepage acts (docs/model.md §5; `false` drops f23, f33)
    pub spin: bool,
    /// flange contact, if modelled
    pub flange: Option<Flange>,
    /// right-wheel contact state against y
    pub table: ContactTable,
}

/// Effective conicity at the centre of a contact geometry table, $λ_e = dr_R/dy(0)$ (–).
pub fn centre_conicity(table: &ContactTable) -> f64 {
    table.right(Dual::<1>::var(0.0, 0)).radius.eps[0]
}

/// Flange force $F_f$ (N) at displacement `y` (m); zero inside the dead band.
#[inline]
pub fn flange_force<T: Scalar>(flange: Option<&Flange>, y: T) -> T {
    match flange {
        Some(f) if y.re() > f.clearance => -((y - f.clearance) * f.stiffness),
        Some(f) if y.re() < -f.clearance => -((y + f.clearance) * f.stiffness),
        _ => T::cst(0.0),
    }
}

impl Wheelset {
    /// The same wheelset with another creep law (the linear analysis needs Kalker's too).
    pub fn with_law(&self, law: CreepLaw) -> Self {
        Self {
            creep_law: law,
            ..self.clone()
        }
    }

    /// Creep force on one wheel; `side` = +1 right, −1 left; `(sin δ, cos δ)` of its contact
    /// angle (computed once per wheel: the trigonometry was a sixth of the right-hand side).
    #[inline]
    fn wheel_force<T: Scalar>(
        &self,
        w: &WheelState<T>,
        (sin_angle, cos_angle): (T, T),
        side: f64,
        x: &[T; 4],
        v: f64,
    ) -> CreepForce<T> {
        let p = &self.params;
        let [_, psi, ydot, psidot] = *x;
        let inv_v = 1.0 / v;
        let s = Creepage {
            long: -(w.radius / p.rolling_radius) + 1.0
                - psidot * (side * p.half_contact_distance * inv_v),
            lat: ydot * inv_v - psi,
            spin: if self.spin {
                psidot * inv_v - sin_angle * (side / p.rolling_radius)
            } else {
                T::cst(0.0)
            },
        };
        let mut coeffs = w.creep;
        if !self.spin {
            coeffs.f23 = T::cst(0.0);
            coeffs.f33 = T::cst(0.0);
        }
        let f = creep::kalker(&coeffs, &s);
        match self.creep_law {
            CreepLaw::Kalker => f,
            CreepLaw::Shen { friction } => {
                // docs/model.md §4: N_i = (W/2)/cos δ_i
                let normal = cos_angle.recip() * (p.axle_load / 2.0);
                creep::shen(f, normal * friction)
            }
        }
    }

    /// The generalised contact forces on the wheelset, $(Q_y, Q_ψ)$ (N, N m): creep on both
    /// wheels (after the creep law), the gravitational stiffness $F_N$ and the flange force
    /// $F_f$ (docs/model.md §4–6), i.e. every term of §8 except the suspension. In a vehicle each
    /// wheelset carries exactly these forces in its own state (docs/model.md §11).
    #[inline]
    pub fn contact_forces<T: Scalar>(&self, x: &[T; 4], v: f64) -> (T, T) {
        self.contact_forces_on(&self.table, x, v)
    }

    /// [`Self::contact_forces`] on the contact geometry `table` instead of the wheelset's own:
    /// a vehicle whose wheelsets have their own profiles (docs/model.md §11) keeps one creep
    /// law, spin, flange and axle load and hands each wheelset its table.
    #[inline]
    pub fn contact_forces_on<T: Scalar>(&self, table: &ContactTable, x: &[T; 4], v: f64) -> (T, T) {
        let p = &self.params;
        let y = x[0];
        let right = table.right(y);
        let left = table.left(y);
        let (trig_r, trig_l) = (right.angle.sin_cos(), left.angle.sin_cos());
        let fr = self.wheel_force(&right, trig_r, 1.0, x, v);
        let fl = self.wheel_force(&left, trig_l, -1.0, x, v);
        // gravitational stiffness, docs/model.md §4: tan δ = sin δ / cos δ
        let (tan_r, tan_l) = (trig_r.0 / trig_r.1, trig_l.0 / trig_l.1);
        let f_n = -((tan_r - tan_l) * (p.axle_load / 2.0));
        let f_f = flange_force(self.flange.as_ref(), y);
        (
            fr.fy + fl.fy + f_n + f_f,
            (fl.fx - fr.fx) * p.half_contact_distance + fr.mz + fl.mz,
        )
    }

    /// The right-hand side $f(x; V)$ of $\dot x = f(x; V)$: docs/model.md §8 written out for the single
    /// wheelset on a track-fixed frame. [`crate::model::Vehicle`] assembles the same model
    /// from elements; this direct form is the reference it is tested against.
    #[inline]
    pub fn rhs<T: Scalar>(&self, x: &[T; 4], v: f64) -> [T; 4] {
        let p = &self.params;
        let s = &self.suspension;
        let [y, psi, ydot, psidot] = *x;
        let (q_y, q_psi) = self.contact_forces(x, v);
        let f_s = -(y * (2.0 * s.lateral_stiffness)) - ydot * (2.0 * s.lateral_damping);
        let d2 = s.half_spring_spacing * s.half_spring_spacing;
        let m_s = -(psi * (2.0 * s.longitudinal_stiffness * d2))
            - psidot * (2.0 * s.longitudinal_damping * d2);
        let yddot = (q_y + f_s) / p.mass;
        let psiddot = (q_psi + m_s) / p.yaw_inertia;
        [ydot, psidot, yddot, psiddot]
    }

    /// $f(x; V)$ on plain vectors.
    pub fn rhs_vec(&self, x: &Vector4<f64>, v: f64) -> Vector4<f64> {
        let r = self.rhs(&[x[0], x[1], x[2], x[3]], v);
        Vector4::new(r[0], r[1], r[2], r[3])
    }

    /// The exact Jacobian $∂f/∂x$ at `x` (forward-mode dual numbers) and $f$ itself.
    pub fn jacobian(&self, x: &Vector4<f64>, v: f64) -> (Matrix4<f64>, Vector4<f64>) {
        let xd: [Dual<4>; 4] = std::array::from_fn(|k| Dual::var(x[k], k));
        let r = self.rhs(&xd, v);
        (
            Matrix4::from_fn(|i, j| r[i].eps[j]),
            Vector4::from_fn(|i, _| r[i].re),
        )
    }

    /// Effective conicity at the centre, $λ_e = dr_R/dy(0)$ (–).
    pub fn centre_conicity(&self) -> f64 {
        centre_conicity(&self.table)
    }

    /// Kinematic (Klingel) wavelength $L_k = 2π\sqrt{r_0 l_0/λ_e}$ (m), docs/model.md §9.
    pub fn klingel_wavelength(&self) -> f64 {
        let p = &self.params;
        2.0 * std::f64::consts::PI
            * (p.rolling_radius * p.half_contact_distance / self.centre_conicity()).sqrt()
    }
}

/// The wheelset as a vector field for the integrator and the continuation; the parameter is
/// the speed V (m/s). The flange's dead-band edges are the switching surfaces, written with
/// the same comparisons as [`flange_force`] so that the sign changes exactly where the force
/// law switches branch.
impl crate::system::ode::VectorField<4> for Wheelset {
    fn rhs(&self, x: &Vector4<f64>, v: f64) -> Vector4<f64> {
        self.rhs_vec(x, v)
    }
    fn jacobian(&self, x: &Vector4<f64>, v: f64) -> Matrix4<f64> {
        Wheelset::jacobian(self, x, v).0
    }
    /// One dual-number evaluation gives both (the value is the duals' real part).
    fn rhs_jacobian(&self, x: &Vector4<f64>, v: f64) -> (Vector4<f64>, Matrix4<f64>) {
        let (j, f) = Wheelset::jacobian(self, x, v);
        (f, j)
    }
    fn switch_count(&self) -> usize {
        if self.flange.is_some() {
            2
        } else {
            0
        }
    }
    fn switch_value(&self, k: usize, x: &Vector4<f64>) -> f64 {
        let c = self.flange.map_or(0.0, |f| f.clearance);
        // k = 0: right flange (y > δ_f); k = 1: left flange (y < −δ_f)
        if k == 0 {
            x[0] - c
        } else {
            -x[0] - c
        }
    }
}

/// The state sizes the analyses are compiled for: the layouts' 4, 12 (14 with frame roll) and
/// 28 (34 with roll), and those with one or two damper strokes per bogie frame (docs/model.md
/// §13: a yaw-damper pair on series stiffness adds one stroke per frame; on the wheelset one or
/// two, for its primary dampers). [`Vehicle::assemble`] refuses any other size when dampers'
/// strokes make it, naming them.
pub const STATE_SIZES: [usize; 14] = [4, 5, 6, 12, 13, 14, 15, 16, 28, 30, 32, 34, 36, 38];

/// Runs `$body` with the const `$n` set to the state size `$states` of a vehicle (one of
/// [`STATE_SIZES`]): the analyses are generic over the state size, and this is where a run-time
/// size picks the compiled one. Any other size evaluates `$other`.
#[macro_export]
macro_rules! with_states {
    ($states:expr, $n:ident => $body:expr, _ => $other:expr) => {
        $crate::with_state_sizes!($states, 0, $n => $body, _ => $other)
    };
}

/// Runs `$body` with the const `$m` set to one more than the state size `$states` of a
/// vehicle (5 for 4, 13 for 12, …): the fields that carry the model's states and one more (the
/// ramp's speed, [`crate::simulate::RampField`]) pick their compiled size here, beside
/// [`with_states!`]. Any other size evaluates `$other`.
#[macro_export]
macro_rules! with_states_plus_one {
    ($states:expr, $m:ident => $body:expr, _ => $other:expr) => {
        $crate::with_state_sizes!($states, 1, $m => $body, _ => $other)
    };
}

/// The one list of the vehicles' state sizes behind [`with_states!`] and
/// [`with_states_plus_one!`] (the sizes of [`STATE_SIZES`]): `$n` is the size matched plus
/// `$extra`.
#[doc(hidden)]
#[macro_export]
macro_rules! with_state_sizes {
    ($states:expr, $extra:expr, $n:ident => $body:expr, _ => $other:expr) => {
        $crate::with_state_sizes!(@arms $states, $extra, $n, $body, $other;
            4 5 6 12 13 14 15 16 28 30 32 34 36 38)
    };
    (@arms $states:expr, $extra:expr, $n:ident, $body:expr, $other:expr; $($size:literal)*) => {
        match $states {
            $(
                $size => {
                    const $n: usize = $size + $extra;
                    $body
                }
            )*
            _ => $other,
        }
    };
}
