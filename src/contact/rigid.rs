//! Rigid two-point contact of an arbitrary wheel profile pair on arbitrary rails (docs/model.md §3,
//! method 2, general profiles).
//!
//! Frames as in [`crate::contact::geometry`]: wheelset frame (ζ lateral from the wheelset
//! centre, w up from the axle), track frame (Y right, Z up). The right wheel's profile point
//! at outward offset u from its taping line is `(ζ, w) = (l0 + u, −(r0 + ρ(u)))`, the left
//! wheel's its mirror image; a roll φ and displacement (y, z) map it to
//! `(Y, Z) = (y + ζ cos φ − w sin φ, z + ζ sin φ + w cos φ)`. The right rail's surface is
//! `Z = H(v)` at `Y = Y_g + v` (v outward), the left rail its mirror image.
//!
//! For each y the solve finds (z, φ, u_R, u_L):
//! 1. for a trial φ, the minimum vertical gap on each side is found by a scan of the wheel
//!    every [`SCAN_STEP`] with parabolic refinement (global, so contact jumps are found);
//! 2. φ is adjusted by the secant method until both minimum gaps are equal (then z closes
//!    them);
//! 3. Newton on the four contact equations (zero gap, tangency, each side) polishes the point,
//!    and the implicit function theorem gives exact slopes d/dy.

use nalgebra::{Matrix4, Vector4};

use super::geometry::{ContactPoint, GeometryError, Nominal};
use super::placement::{rail_spline, wheel_spline};
use super::profile::{Points, ProfileError};
use super::spline::CubicSpline;
use crate::system::scalar::{Dual, Scalar};

/// Wheel sampling step of the global gap scan (m).
pub const SCAN_STEP: f64 = 2.5e-4;
/// Lateral step of the central differences where Newton cannot polish (m).
const FD_STEP: f64 = 1e-5;
/// Iterations of the bracket growth and of the regula falsi on φ.
const MAX_BRACKET: usize = 100;
/// Newton iterations of the polish.
const MAX_NEWTON: usize = 40;

/// Placement of the rail profiles.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Track {
    /// track gauge between the gauge points (m)
    pub gauge: f64,
    /// depth of the gauge point below the rail's highest point (m)
    pub gauge_depth: f64,
    /// rail inclination applied to the rail profile (rad); 0 when the file is already canted
    pub inclination: f64,
}

/// A wheel and rail profile pair ready for the rigid contact solve.
#[derive(Clone, Debug, PartialEq)]
pub struct ProfilePair {
    /// wheel radius increment ρ(u) = r − r0 (m) against the outward offset u (m)
    wheel: CubicSpline,
    /// rail height H(v) (m, 0 at the top) against the outward offset v (m)
    rail: CubicSpline,
    /// track Y of the right rail's v = 0 (m)
    rail_y: f64,
    /// wheel scan samples (u, ρ)
    scan: Vec<(f64, f64)>,
    /// where the profiles come from
    pub files: (String, String),
    /// the rail placement used
    pub track: Track,
}

impl ProfilePair {
    /// The wheel's running part, as outward offsets u from its taping line (m), and the right
    /// rail's running surface in track Y (m): where the two can touch.
    pub fn extents(&self) -> ((f64, f64), (f64, f64)) {
        let (vlo, vhi) = self.rail.range();
        (self.wheel.range(), (self.rail_y + vlo, self.rail_y + vhi))
    }

    /// Builds the pair from the wheel and rail points.
    pub fn new(wheel: &Points, mut rail: Points, track: Track) -> Result<Self, ProfileError> {
        let w = wheel_spline(wheel)?;
        let rail_file = rail.file.clone();
        rail.incline(track.inclination);
        let (rail, rail_y) = rail_spline(&rail, track)?;
        let (lo, hi) = w.range();
        let n = ((hi - lo) / SCAN_STEP).floor() as usize;
        let scan = (0..=n)
            .map(|k| {
                let u = lo + k as f64 * SCAN_STEP;
                (u, w.eval(u).0)
            })
            .collect();
        Ok(Self {
            wheel: w,
            rail,
            rail_y,
            scan,
            files: (wheel.file.clone(), rail_file),
            track,
        })
    }

    /// Four residuals (gap, tangency right; gap, tangency left) at `x = (z, φ, u_R, u_L)`.
    fn residual<T: Scalar>(&self, n: Nominal, x: [T; 4], y: T) -> [T; 4] {
        let (gr, tr) = self.side(n, 1.0, x[2], x[0], x[1], y);
        let (gl, tl) = self.side(n, -1.0, x[3], x[0], x[1], y);
        [gr, tr, gl, tl]
    }

    /// Vertical gap and tangency residual of side `s` at wheel offset `u`.
    fn side<T: Scalar>(&self, n: Nominal, s: f64, u: T, z: T, phi: T, y: T) -> (T, T) {
        let (rho, drho, _) = self.wheel.eval(u);
        let zeta = (u + n.half_contact_distance) * s;
        let w = -(rho + n.rolling_radius);
        let (sn, c) = (phi.sin(), phi.cos());
        let big_y = y + zeta * c - w * sn;
        let big_z = z + zeta * sn + w * c;
        let v = big_y * s - self.rail_y;
        let (h, dh, _) = self.rail.eval(v);
        let dy = c * s + drho * sn;
        let dz = sn * s - drho * c;
        (big_z - h, dz - dh * dy * s)
    }

    /// Minimum vertical gap of side `s` at z = 0 and roll φ: (gap, u at the minimum).
    fn min_gap(&self, n: Nominal, s: f64, phi: f64, y: f64) -> (f64, f64) {
        let (sn, c) = phi.sin_cos();
        let (l0, r0) = (n.half_contact_distance, n.rolling_radius);
        let (vlo, vhi) = self.rail.range();
        let mut hint = 0;
        let mut best = (f64::INFINITY, 0usize);
        let mut g = Vec::with_capacity(self.scan.len());
        for (k, &(u, rho)) in self.scan.iter().enumerate() {
            let zeta = (u + l0) * s;
            let w = -(rho + r0);
            let v = (y + zeta * c - w * sn) * s - self.rail_y;
            let gap = if v < vlo || v > vhi {
                f64::INFINITY
            } else {
                zeta * sn + w * c - self.rail.value_hint(v, &mut hint)
            };
            if gap < best.0 {
                best = (gap, k);
            }
            g.push(gap);
        }
        let k = best.1;
        if k == 0 || k + 1 >= g.len() || !g[k - 1].is_finite() || !g[k + 1].is_finite() {
            return (best.0, self.scan[k].0);
        }
        // parabola through the three samples around the minimum
        let (a, b, cc) = (g[k - 1], g[k], g[k + 1]);
        let den = a - 2.0 * b + cc;
        let t = if den > 0.0 { 0.5 * (a - cc) / den } else { 0.0 };
        let t = t.clamp(-1.0, 1.0);
        (b - 0.25 * (a - cc) * t, self.scan[k].0 + t * SCAN_STEP)
    }

    /// Solves the contact at `y` (m); `guess` is the previous (z, φ, u_R, u_L).
    pub fn solve(
        &self,
        n: Nominal,
        y: f64,
        guess: Option<[f64; 4]>,
    ) -> Result<(ContactPoint<Dual<1>>, [f64; 4]), GeometryError> {
        let x = self.coarse(n, y, guess.map_or(0.0, |g| g[1]))?;
        let x = match self.polish(n, y, x) {
            Ok(x) => x,
            Err(GeometryError::NoConvergence { .. }) => return self.fallback(n, y, x),
            Err(e) => return Err(e),
        };
        self.check_inside(y, &x)?;
        let (jac, _) = self.jacobian(n, x, y);
        let xd: [Dual<1>; 4] = std::array::from_fn(|k| Dual::cst(x[k]));
        let fy = self.residual(n, xd, Dual::var(y, 0));
        let rhs = Vector4::from_fn(|i, _| -fy[i].eps[0]);
        let dx = jac
            .lu()
            .solve(&rhs)
            .ok_or(GeometryError::Singular { y_m: y })?;
        let d = |k: usize| Dual {
            re: x[k],
            eps: [dx[k]],
        };
        Ok((self.point(n, d(1), d(2), Dual::var(y, 0)), x))
    }

    /// Where Newton on the tangency conditions cannot converge (the minimum gap sits on a
    /// corner of a profile, where no common tangent exists), the scanned minimum is kept and
    /// the slopes are central differences of the scan-based solve over ±[`FD_STEP`].
    fn fallback(
        &self,
        n: Nominal,
        y: f64,
        x: [f64; 4],
    ) -> Result<(ContactPoint<Dual<1>>, [f64; 4]), GeometryError> {
        self.check_inside(y, &x)?;
        let xp = self.coarse(n, y + FD_STEP, x[1])?;
        let xm = self.coarse(n, y - FD_STEP, x[1])?;
        let at = |x: [f64; 4], y: f64| self.point(n, x[1], x[2], y);
        let (p, pp, pm) = (at(x, y), at(xp, y + FD_STEP), at(xm, y - FD_STEP));
        let d = |v: f64, a: f64, b: f64| Dual {
            re: v,
            eps: [(a - b) / (2.0 * FD_STEP)],
        };
        let point = ContactPoint {
            radius: d(p.radius, pp.radius, pm.radius),
            angle: d(p.angle, pp.angle, pm.angle),
            roll: d(p.roll, pp.roll, pm.roll),
            wheel_offset: d(p.wheel_offset, pp.wheel_offset, pm.wheel_offset),
        };
        Ok((point, x))
    }

    /// The right wheel's contact point.
    fn point<T: Scalar>(&self, n: Nominal, phi: T, u: T, y: T) -> ContactPoint<T> {
        let (rho, _, _) = self.wheel.eval(u);
        let w = -(rho + n.rolling_radius);
        let zeta = u + n.half_contact_distance;
        let v = y + zeta * phi.cos() - w * phi.sin() - self.rail_y;
        let (_, dh, _) = self.rail.eval(v);
        ContactPoint {
            radius: rho + n.rolling_radius,
            angle: dh.atan(),
            roll: phi,
            wheel_offset: u,
        }
    }

    /// B = κ_wheel + κ_rail at the right contact (1/m), both positive when convex.
    pub fn curvature<T: Scalar>(&self, n: Nominal, phi: T, u: T, y: T) -> T {
        let (rho, drho, d2rho) = self.wheel.eval(u);
        let w = -(rho + n.rolling_radius);
        let zeta = u + n.half_contact_distance;
        let v = y + zeta * phi.cos() - w * phi.sin() - self.rail_y;
        let (_, dh, d2h) = self.rail.eval(v);
        let k = |d1: T, d2: T| {
            let q = (d1 * d1 + 1.0).sqrt();
            -d2 / (q * q * q)
        };
        k(drho, d2rho) + k(dh, d2h)
    }

    /// Steps 1–2: φ such that the two minimum gaps are equal. F(φ) = D_R − D_L increases
    /// with φ (about 2 l0), so a bracket is grown from the guess and closed by the Illinois
    /// variant of regula falsi (robust where F is only piecewise smooth: contact jumps).
    fn coarse(&self, n: Nominal, y: f64, phi0: f64) -> Result<[f64; 4], GeometryError> {
        let f = |phi: f64| {
            let (gr, ur) = self.min_gap(n, 1.0, phi, y);
            let (gl, ul) = self.min_gap(n, -1.0, phi, y);
            (gr - gl, [-gr, phi, ur, ul])
        };
        let fail = |residual: f64| GeometryError::NoConvergence {
            y_m: y,
            residual,
            iterations: MAX_BRACKET,
        };
        let (mut a, (mut fa, xa)) = (phi0, f(phi0));
        if !fa.is_finite() {
            return Err(fail(fa));
        }
        // the parabolic minima are accurate to ~1e-10 m; Newton polishes afterwards
        if fa.abs() < 1e-10 {
            return Ok(xa);
        }
        let mut delta = -fa / (2.0 * n.half_contact_distance);
        let (mut b, (mut fb, mut xb)) = (a + delta, f(a + delta));
        let mut k = 0;
        while fa * fb > 0.0 {
            k += 1;
            if k > MAX_BRACKET || !fb.is_finite() {
                return Err(fail(fb));
            }
            (a, fa) = (b, fb);
            delta *= 2.0;
            b = a + delta;
            (fb, xb) = f(b);
        }
        for _ in 0..MAX_BRACKET {
            if fb.abs() < 1e-10 || (b - a).abs() < 1e-14 {
                return Ok(xb);
            }
            let c = b - fb * (b - a) / (fb - fa);
            let (fc, xc) = f(c);
            if fc * fb < 0.0 {
                (a, fa) = (b, fb);
            } else {
                fa *= 0.5;
            }
            (b, fb, xb) = (c, fc, xc);
        }
        Err(fail(fb))
    }

    fn jacobian(&self, n: Nominal, x: [f64; 4], y: f64) -> (Matrix4<f64>, Vector4<f64>) {
        let xd: [Dual<4>; 4] = std::array::from_fn(|k| Dual::var(x[k], k));
        let r = self.residual(n, xd, Dual::cst(y));
        (
            Matrix4::from_fn(|i, j| r[i].eps[j]),
            Vector4::from_fn(|i, _| r[i].re),
        )
    }

    /// Step 3: Newton on the four contact equations.
    /// Steps are limited (|Δz| ≤ 1 mm, |Δφ| ≤ 1 mrad, |Δu| ≤ two scan steps) so that Newton
    /// stays at the minimum the global scan found (near a jump the other one is close).
    fn polish(&self, n: Nominal, y: f64, mut x: [f64; 4]) -> Result<[f64; 4], GeometryError> {
        let limit = [1e-3, 1e-3, 2.0 * SCAN_STEP, 2.0 * SCAN_STEP];
        for _ in 0..MAX_NEWTON {
            let (jac, f) = self.jacobian(n, x, y);
            let step = jac
                .lu()
                .solve(&f)
                .ok_or(GeometryError::Singular { y_m: y })?;
            let shrink = (0..4)
                .map(|k| limit[k] / step[k].abs())
                .fold(1.0f64, f64::min);
            for k in 0..4 {
                x[k] -= shrink * step[k];
            }
            if !step.amax().is_finite() {
                break;
            }
            if step.amax() <= 1e-14 * n.rolling_radius {
                return Ok(x);
            }
        }
        let (_, f) = self.jacobian(n, x, y);
        Err(GeometryError::NoConvergence {
            y_m: y,
            residual: f.amax(),
            iterations: MAX_NEWTON,
        })
    }

    /// The contact points must lie on the kept parts of both profiles.
    fn check_inside(&self, y: f64, x: &[f64; 4]) -> Result<(), GeometryError> {
        let (lo, hi) = self.wheel.range();
        for u in [x[2], x[3]] {
            if u <= lo || u >= hi {
                return Err(GeometryError::OffProfile {
                    y_m: y,
                    offset_m: u,
                    range_m: (lo, hi),
                });
            }
        }
        Ok(())
    }
}
