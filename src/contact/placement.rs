//! Placing the profiles: the wheel's radius function about its taping line and the rail's
//! height function about its gauge point (see [`crate::contact::profile`] for the conventions).

use super::profile::{Points, ProfileError, MAX_SLOPE};
use super::rigid::Track;
use super::spline::CubicSpline;

/// ρ(u) = z_down(u) − z_down(0) over the running part of the wheel.
pub(super) fn wheel_spline(p: &Points) -> Result<CubicSpline, ProfileError> {
    let anchor = p.u.iter().position(|&u| u >= 0.0).filter(|&k| k > 0);
    let Some(anchor) = anchor else {
        return Err(p.shape_error(
            "the lateral range must contain 0 (the taping line, where the radius is r0)".into(),
        ));
    };
    let (lo, hi) = p.running_range(anchor);
    if hi - lo < 10 {
        return Err(p.shape_error(format!(
            "only {} points around the taping line have a slope below {}: too steep or too few",
            hi - lo + 1,
            MAX_SLOPE
        )));
    }
    let s0 = natural(p, "wheel", &p.u[lo..=hi], &p.z_down[lo..=hi])?;
    let z0 = s0.eval(0.0).0;
    let rho: Vec<f64> = p.z_down[lo..=hi].iter().map(|z| z - z0).collect();
    let flange = rho
        .iter()
        .zip(&p.u[lo..=hi])
        .filter(|(_, &u)| u < 0.0)
        .map(|(r, _)| *r)
        .fold(f64::NEG_INFINITY, f64::max);
    if flange < 0.01 {
        return Err(p.shape_error(format!(
            "no flange on the inner side (largest radius increment inside the taping line \
             {:.3} mm, expected > 10 mm): check wheel_profile_mirror and wheel_profile_z_up",
            flange * 1e3
        )));
    }
    natural(p, "wheel", &p.u[lo..=hi], &rho)
}

/// H(v) = −(z_down − z_top) over the running part; the right rail's v = 0 sits at `rail_y`.
pub(super) fn rail_spline(p: &Points, t: Track) -> Result<(CubicSpline, f64), ProfileError> {
    let top = (0..p.u.len())
        .min_by(|&a, &b| p.z_down[a].total_cmp(&p.z_down[b]))
        .expect("profiles have at least 10 points");
    let z_top = p.z_down[top];
    // gauge point: first crossing of z_top + depth inward from the top
    let target = z_top + t.gauge_depth;
    let mut gauge_u = None;
    for k in (1..=top).rev() {
        let (z1, z0) = (p.z_down[k], p.z_down[k - 1]);
        if z1 <= target && z0 >= target {
            gauge_u = Some(gauge_crossing(p, k, target));
            break;
        }
    }
    let Some(gauge_u) = gauge_u else {
        return Err(p.shape_error(format!(
            "the gauge side never reaches {:.1} mm below the top: cannot place the gauge point \
             (check rail_profile_mirror and rail_profile_z_up)",
            t.gauge_depth * 1e3
        )));
    };
    let (lo, hi) = p.running_range(top);
    if hi - lo < 10 {
        return Err(p.shape_error("fewer than 10 points on the running surface".into()));
    }
    let v: Vec<f64> = p.u[lo..=hi].iter().map(|u| u - gauge_u).collect();
    let h: Vec<f64> = p.z_down[lo..=hi].iter().map(|z| z_top - z).collect();
    Ok((natural(p, "rail", &v, &h)?, 0.5 * t.gauge))
}

/// The natural spline through the running part of profile `p` (`what`: wheel or rail); the
/// points were checked when read, so an error here names the profile and the spline's rule.
fn natural(p: &Points, what: &str, u: &[f64], z: &[f64]) -> Result<CubicSpline, ProfileError> {
    CubicSpline::natural(u, z)
        .map_err(|e| p.shape_error(format!("the {what} running surface cannot be splined: {e}")))
}

/// The lateral position where the profile between points k−1 and k reaches depth `target`:
/// cubic Lagrange interpolation of u as a function of z through the four points around the
/// crossing (the gauge face is steep, so u(z) is the well-conditioned direction), falling
/// back to the chord where z is not monotonic over those points.
fn gauge_crossing(p: &Points, k: usize, target: f64) -> f64 {
    let (z1, z0) = (p.z_down[k], p.z_down[k - 1]);
    let chord = p.u[k] + (target - z1) / (z0 - z1).max(f64::MIN_POSITIVE) * (p.u[k - 1] - p.u[k]);
    if k < 2 || k + 1 >= p.u.len() {
        return chord;
    }
    let idx = [k - 2, k - 1, k, k + 1];
    let z: Vec<f64> = idx.iter().map(|&i| p.z_down[i]).collect();
    if !z.windows(2).all(|w| w[1] < w[0]) {
        return chord;
    }
    let mut u = 0.0;
    for (a, &ia) in idx.iter().enumerate() {
        let mut l = 1.0;
        for (b, _) in idx.iter().enumerate() {
            if a != b {
                l *= (target - z[b]) / (z[a] - z[b]);
            }
        }
        u += l * p.u[ia];
    }
    u
}
