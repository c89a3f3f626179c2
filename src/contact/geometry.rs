//! Contact geometry as functions of the lateral displacement `y` (docs/model.md §3).
//!
//! Conventions (docs/model.md §1): `y` to the right, the roll `φ` positive when the right side is
//! raised, contact angles positive when the normal force pushes the wheel towards the track
//! centre. All functions are for the **right** wheel; the left wheel follows from the track
//! symmetry `r_L(y) = r_R(−y)`, `δ_L(y) = δ_R(−y)`, `φ(−y) = −φ(y)`.
//!
//! Two geometries:
//!
//! * [`Geometry::Cone`]: a cone of slope λ on knife-edge rails, in closed form:
//!   $r_R = r_0 + λy$, $φ = λy/l_0$, $δ_R = λ + φ$.
//! * [`Geometry::ConeOnArc`]: a cone on a circular rail head, solved by the rigid two-point
//!   contact method: for each `y`, the vertical position `z` and roll `φ` of the wheelset and
//!   the contact points on both wheels are the solution of four equations (zero gap and
//!   tangency on each side). The slopes with respect to `y` are obtained exactly by the
//!   implicit function theorem, `du/dy = −F_u⁻¹ F_y`, with `F_u` and `F_y` from dual numbers.

use std::sync::Arc;

use nalgebra::{Matrix4, Vector4};

use super::rigid::ProfilePair;
use crate::contact::tabulated::TabulatedGeometry;
use crate::system::scalar::{Dual, Scalar};

/// Wheel–rail contact geometry of a study, in SI units.
#[derive(Clone, Debug, PartialEq)]
pub enum Geometry {
    /// Cone of slope `conicity` (λ, –) on knife-edge rails.
    Cone {
        /// λ (–)
        conicity: f64,
    },
    /// Cone of slope λ on a circular rail head (docs/model.md §3, method 2; the seed's eqs. 11–14).
    ConeOnArc {
        /// λ (–)
        conicity: f64,
        /// radius of the rail head arc (m)
        rail_head_radius: f64,
        /// lateral offset of the rail crown outside the nominal contact point (m)
        crown_offset: f64,
    },
    /// A geometry tabulated in a file (docs/model.md §3, method 3), interpolated by C² splines.
    Table(Arc<TabulatedGeometry>),
    /// Two arbitrary profiles (wheel and rail point lists) in rigid contact (docs/model.md §3,
    /// method 2); see [`crate::contact::rigid`].
    Profiles {
        /// the placed profile pair
        pair: Arc<ProfilePair>,
        /// half-width of the local-regression smoothing of the tabulated functions (m); 0: none
        smoothing: f64,
    },
}

/// The right wheel's contact state at one lateral displacement.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactPoint<T> {
    /// rolling radius r_R (m)
    pub radius: T,
    /// contact angle δ_R (rad)
    pub angle: T,
    /// wheelset roll φ (rad)
    pub roll: T,
    /// lateral position of the contact point on the wheel, from the nominal point, outward (m);
    /// NaN for a tabulated geometry (not tabulated)
    pub wheel_offset: T,
}

/// Failure of the rigid contact solve.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum GeometryError {
    /// Newton did not converge at this displacement.
    #[error("rigid contact solve did not converge at y = {y_m:.6e} m (residual {residual:.3e} after {iterations} iterations)")]
    NoConvergence {
        y_m: f64,
        residual: f64,
        iterations: usize,
    },
    /// The contact point left the rail arc (the rail head is narrower than the motion).
    #[error("at y = {y_m:.6e} m the contact point lies {offset_m:.6e} m from the rail crown, beyond the rail head radius {radius_m:.6e} m")]
    OffRailHead {
        y_m: f64,
        offset_m: f64,
        radius_m: f64,
    },
    /// The contact point left the running part of the wheel profile.
    #[error("at y = {y_m:.6e} m the wheel contact point u = {offset_m:.6e} m leaves the wheel profile's running part [{:.6e}, {:.6e}] m", .range_m.0, .range_m.1)]
    OffProfile {
        y_m: f64,
        offset_m: f64,
        range_m: (f64, f64),
    },
    /// The Jacobian of the contact equations is singular.
    #[error("rigid contact equations are singular at y = {y_m:.6e} m")]
    Singular { y_m: f64 },
    /// The displacement lies outside a tabulated geometry's range.
    #[error("y = {y_m:.6e} m lies outside the geometry table {table} (y from {min_m:.6e} m to {max_m:.6e} m)")]
    OutsideTable {
        y_m: f64,
        table: String,
        min_m: f64,
        max_m: f64,
    },
}

/// Nominal wheelset dimensions the geometry needs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Nominal {
    /// nominal rolling radius r0 (m)
    pub rolling_radius: f64,
    /// half the distance between the nominal contact points l0 (m)
    pub half_contact_distance: f64,
}

impl Geometry {
    /// The cone slope λ; for a table, the slope dr_R/dy at y = 0; NaN for profiles, which
    /// have no single slope (their model's `centre_conicity` is the slope at the centre).
    pub fn conicity(&self) -> f64 {
        match self {
            Geometry::Cone { conicity } | Geometry::ConeOnArc { conicity, .. } => *conicity,
            Geometry::Table(t) => t.point(0.0).radius.eps[0],
            Geometry::Profiles { .. } => f64::NAN,
        }
    }

    /// Transverse curvature of the rail head at the contact (1/m); 0 for a knife edge.
    pub fn rail_transverse_curvature(&self) -> Option<f64> {
        match *self {
            Geometry::Cone { .. } | Geometry::Table(_) | Geometry::Profiles { .. } => None,
            Geometry::ConeOnArc {
                rail_head_radius, ..
            } => Some(1.0 / rail_head_radius),
        }
    }

    /// The right wheel's contact point at displacement `y` (m), with exact slopes `d/dy`.
    /// `guess` is the previous solution (z, φ, η_R, η_L) for continuation along `y`.
    pub fn solve(
        &self,
        nominal: Nominal,
        y: f64,
        guess: Option<[f64; 4]>,
    ) -> Result<(ContactPoint<Dual<1>>, [f64; 4]), GeometryError> {
        let yd = Dual::<1>::var(y, 0);
        match self {
            Geometry::Profiles { pair, .. } => pair.solve(nominal, y, guess),
            &Geometry::Cone { conicity } => Ok((cone(conicity, nominal, yd), [0.0; 4])),
            &Geometry::ConeOnArc {
                conicity,
                rail_head_radius,
                crown_offset,
            } => {
                let arc = ConeOnArc {
                    lambda: conicity,
                    radius: rail_head_radius,
                    crown: crown_offset,
                    nominal,
                };
                arc.solve(y, guess)
            }
            Geometry::Table(t) => {
                let (min_m, max_m) = t.range();
                if !(min_m..=max_m).contains(&y) {
                    return Err(GeometryError::OutsideTable {
                        y_m: y,
                        table: t.source.clone(),
                        min_m,
                        max_m,
                    });
                }
                Ok((t.point(y), [0.0; 4]))
            }
        }
    }
}

/// docs/model.md §3 method 1 (closed form).
fn cone<T: Scalar>(lambda: f64, n: Nominal, y: T) -> ContactPoint<T> {
    let roll = y * (lambda / n.half_contact_distance);
    ContactPoint {
        radius: y * lambda + n.rolling_radius,
        angle: roll + lambda,
        roll,
        wheel_offset: -y,
    }
}

/// A cone of slope λ on a circular rail head.
///
/// Wheelset frame: lateral ζ from the wheelset centre, vertical w upward from the axle. The
/// right wheel's profile point at offset η (outward from the nominal contact point) is
/// `(l0 + η, −(r0 − λη))`; the left wheel's is its mirror image. A roll φ and displacement
/// (y, z) map it to the track frame `(Y, Z) = (y + ζ cos φ − w sin φ, z + ζ sin φ + w cos φ)`.
/// The right rail head is the arc `Z = √(R² − (Y − Y_c)²) − R` with crown `Y_c = l0 + c`.
struct ConeOnArc {
    lambda: f64,
    radius: f64,
    crown: f64,
    nominal: Nominal,
}

impl ConeOnArc {
    /// Track-frame point of a wheel profile point; `side` = +1 right, −1 left.
    fn wheel_point<T: Scalar>(&self, side: f64, eta: T, z: T, phi: T, y: T) -> (T, T) {
        let zeta = (eta + self.nominal.half_contact_distance) * side;
        let w = -(eta * (-self.lambda) + self.nominal.rolling_radius);
        let (s, c) = (phi.sin(), phi.cos());
        (y + zeta * c - w * s, z + zeta * s + w * c)
    }

    /// Rail surface height and slope dZ/dY at track lateral position `big_y`.
    fn rail<T: Scalar>(&self, side: f64, big_y: T) -> (T, T) {
        let yc = (self.nominal.half_contact_distance + self.crown) * side;
        let d = big_y - yc;
        let root = (d * d * -1.0 + self.radius * self.radius).sqrt();
        (root - self.radius, -d / root)
    }

    /// The four contact conditions: gap and tangency on the right, then on the left.
    fn residual<T: Scalar>(&self, u: [T; 4], y: T) -> [T; 4] {
        let [z, phi, eta_r, eta_l] = u;
        let mut out = [T::cst(0.0); 4];
        for (k, (side, eta)) in [(1.0, eta_r), (-1.0, eta_l)].into_iter().enumerate() {
            let (big_y, big_z) = self.wheel_point(side, eta, z, phi, y);
            let (h, slope) = self.rail(side, big_y);
            out[2 * k] = big_z - h;
            // Tangency: the wheel curve's direction (dY, dZ)/dη is parallel to the rail's
            // (1, slope). The wheel profile direction in the wheelset frame is (side, λ).
            let (s, c) = (phi.sin(), phi.cos());
            let dy = c * side - s * self.lambda;
            let dz = s * side + c * self.lambda;
            out[2 * k + 1] = dz - slope * dy;
        }
        out
    }

    fn check_on_head(&self, y: f64, u: &[f64; 4]) -> Result<(), GeometryError> {
        for (side, eta) in [(1.0, u[2]), (-1.0, u[3])] {
            let (big_y, _) = self.wheel_point(side, eta, u[0], u[1], y);
            let offset = big_y - (self.nominal.half_contact_distance + self.crown) * side;
            if offset.abs() >= 0.9 * self.radius {
                return Err(GeometryError::OffRailHead {
                    y_m: y,
                    offset_m: offset,
                    radius_m: self.radius,
                });
            }
        }
        Ok(())
    }

    fn jacobian(&self, u: [f64; 4], y: f64) -> (Matrix4<f64>, Vector4<f64>) {
        let ud: [Dual<4>; 4] = std::array::from_fn(|k| Dual::var(u[k], k));
        let r = self.residual(ud, Dual::cst(y));
        let jac = Matrix4::from_fn(|i, j| r[i].eps[j]);
        (jac, Vector4::from_fn(|i, _| r[i].re))
    }

    fn solve(
        &self,
        y: f64,
        guess: Option<[f64; 4]>,
    ) -> Result<(ContactPoint<Dual<1>>, [f64; 4]), GeometryError> {
        let n = self.nominal;
        let c = self.crown;
        let centred_z = n.rolling_radius + (self.radius * self.radius - c * c).sqrt() - self.radius;
        let mut u = guess.unwrap_or([centred_z, 0.0, -y, y]);
        const MAX_ITER: usize = 50;
        let mut residual = f64::INFINITY;
        let mut converged = false;
        for _ in 0..MAX_ITER {
            let (jac, f) = self.jacobian(u, y);
            residual = f.amax();
            if !residual.is_finite() {
                break;
            }
            let Some(step) = jac.lu().solve(&f) else {
                return Err(GeometryError::Singular { y_m: y });
            };
            for k in 0..4 {
                u[k] -= step[k];
            }
            // Converged when the update is at rounding level of the lengths involved.
            if step.amax() <= 1e-15 * n.rolling_radius {
                converged = true;
                break;
            }
        }
        let (jac, f) = self.jacobian(u, y);
        if !converged && f.amax() > 1e-13 * n.rolling_radius {
            return Err(GeometryError::NoConvergence {
                y_m: y,
                residual: residual.min(f.amax()),
                iterations: MAX_ITER,
            });
        }
        self.check_on_head(y, &u)?;
        // Implicit function theorem: du/dy = −F_u⁻¹ F_y.
        let ud: [Dual<1>; 4] = std::array::from_fn(|k| Dual::cst(u[k]));
        let fy = self.residual(ud, Dual::var(y, 0));
        let rhs = Vector4::from_fn(|i, _| -fy[i].eps[0]);
        let du = jac
            .lu()
            .solve(&rhs)
            .ok_or(GeometryError::Singular { y_m: y })?;
        let [_, phi, eta_r, _] = std::array::from_fn::<_, 4, _>(|k| Dual {
            re: u[k],
            eps: [du[k]],
        });
        let yd = Dual::var(y, 0);
        let (big_y, _) = self.wheel_point(1.0, eta_r, Dual::cst(u[0]), phi, yd);
        let (_, slope) = self.rail(1.0, big_y);
        let point = ContactPoint {
            radius: eta_r * (-self.lambda) + n.rolling_radius,
            angle: slope.atan(),
            roll: phi,
            wheel_offset: eta_r,
        };
        Ok((point, u))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const SEED: Nominal = Nominal {
        rolling_radius: 0.46,
        half_contact_distance: 0.7429,
    };

    fn seed_arc() -> Geometry {
        Geometry::ConeOnArc {
            conicity: 0.05,
            rail_head_radius: 0.07937,
            crown_offset: 0.00396,
        }
    }

    /// Solves a sweep in y from the centre outwards, as the table builder does.
    fn sweep(g: &Geometry, ys: &[f64]) -> Vec<ContactPoint<Dual<1>>> {
        let mut guess = None;
        ys.iter()
            .map(|&y| {
                let (p, u) = g.solve(SEED, y, guess).expect("seed geometry solves");
                guess = Some(u);
                p
            })
            .collect()
    }

    #[test]
    fn arc_is_symmetric_and_centred() {
        let g = seed_arc();
        for y in [1e-3, 4e-3, 8e-3] {
            let p = sweep(&g, &[0.0, y / 2.0, y])[2];
            let m = sweep(&g, &[0.0, -y / 2.0, -y])[2];
            // roll is odd in y
            assert!((p.roll.re + m.roll.re).abs() < 1e-15, "{y}");
        }
        let c = sweep(&g, &[0.0])[0];
        assert!(c.roll.re.abs() < 1e-16);
        // centred contact angle: the arc's slope where it equals the cone's (atan λ up to the
        // 3.96 mm crown offset's rounding): |δ − atan 0.05| < 1e-4
        assert!((c.angle.re - 0.05f64.atan()).abs() < 1e-4, "{}", c.angle.re);
    }

    #[test]
    fn slopes_match_central_differences() {
        let g = seed_arc();
        for y0 in [0.0, 2.5e-3, -6e-3] {
            let h = 1e-6;
            let pts = sweep(&g, &[0.0, y0 - h, y0, y0 + h]);
            let (m, c, p) = (pts[1], pts[2], pts[3]);
            let fd = |a: f64, b: f64| (b - a) / (2.0 * h);
            let checks = [
                (c.radius.eps[0], fd(m.radius.re, p.radius.re)),
                (c.angle.eps[0], fd(m.angle.re, p.angle.re)),
                (c.roll.eps[0], fd(m.roll.re, p.roll.re)),
            ];
            for (exact, approx) in checks {
                assert!(
                    (exact - approx).abs() <= 1e-6 * exact.abs().max(1e-3),
                    "y0={y0}: {exact} vs {approx}"
                );
            }
        }
    }

    #[test]
    fn arc_conicity_is_a_little_above_the_cone_slope() {
        // docs/model.md §3: for the seed pair the solution is nearly linear in y, with an effective
        // conicity a few per cent above λ. Here: (r_R − r_L)/(2y) at y = 1 mm.
        let g = seed_arc();
        let y = 1e-3;
        let p = sweep(&g, &[0.0, y])[1];
        let m = sweep(&g, &[0.0, -y])[1];
        let lambda_e = (p.radius.re - m.radius.re) / (2.0 * y);
        assert!(lambda_e > 0.05 && lambda_e < 0.05 * 1.10, "λe = {lambda_e}");
    }

    #[test]
    fn cone_is_the_closed_form() {
        let g = Geometry::Cone { conicity: 0.05 };
        let (p, _) = g.solve(SEED, 3e-3, None).expect("closed form");
        assert!((p.radius.re - (0.46 + 0.05 * 3e-3)).abs() < 1e-16);
        assert!((p.roll.re - 0.05 * 3e-3 / 0.7429).abs() < 1e-18);
        assert!((p.angle.eps[0] - 0.05 / 0.7429).abs() < 1e-15);
    }

    #[test]
    fn contact_moves_across_the_wheel_with_the_wheelset() {
        // The rail contact stays near the crown, so the wheel contact point moves by about −y.
        let g = seed_arc();
        let p = sweep(&g, &[0.0, 2e-3, 4e-3])[2];
        let c = sweep(&g, &[0.0])[0];
        let moved = p.wheel_offset.re - c.wheel_offset.re;
        assert!((moved + 4e-3).abs() < 0.05 * 4e-3, "{moved}");
    }
}
