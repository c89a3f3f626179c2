//! The critical-speed search for any number of states: eigenvalues on a grid, then Brent's
//! method on the real part of the eigenvalue that crossed (module docs of [`super`]).

use super::spectrum::{determinant, eigenvalues};
use super::{brent, CriticalSpeeds, Crossing, Direction, LinearError, LinearOptions, LinearSystem};
use crate::contact::creep::CreepLaw;

/// Eigenvalues in the upper half-plane (Im > 0): one per complex pair.
fn upper(ev: &[(f64, f64)]) -> Vec<(f64, f64)> {
    ev.iter().copied().filter(|z| z.1 > 0.0).collect()
}

/// The eigenvalue of `ev` (Im > 0) nearest to `target`.
fn nearest(ev: &[(f64, f64)], target: (f64, f64)) -> Option<(f64, f64)> {
    ev.iter().copied().filter(|z| z.1 > 0.0).min_by(|a, b| {
        let d = |z: &(f64, f64)| (z.0 - target.0).hypot(z.1 - target.1);
        d(a).total_cmp(&d(b))
    })
}

/// Every crossing of the imaginary axis by a complex pair, for any state size.
pub(super) fn eigen_scan<const N: usize>(
    sys: &LinearSystem<N>,
    law: CreepLaw,
    opts: &LinearOptions,
) -> Result<CriticalSpeeds, LinearError> {
    let (lo, hi) = opts.speed_range;
    let n = opts.grid_points;
    let speed = |i: usize| lo + (hi - lo) * (i as f64) / ((n - 1) as f64);
    let eig = |v: f64| eigenvalues(&sys.jacobian(v)).ok_or(LinearError::NotFinite { speed_m_s: v });
    let det = |v: f64| determinant(&sys.jacobian(v));
    let mut evaluations = 0;
    let first = eig(lo)?;
    evaluations += 1;
    let stable_at_start = first.iter().all(|z| z.0 < 0.0);
    let mut crossings = Vec::new();
    let mut divergence = Vec::new();
    let (mut v_prev, mut e_prev, mut d_prev) = (lo, first, det(lo));
    for i in 1..n {
        let v = speed(i);
        let e = eig(v)?;
        evaluations += 1;
        let d = det(v);
        // match each pair at v to its nearest at v_prev: a change of sign of Re is a crossing
        for b in upper(&e) {
            let Some(a) = nearest(&e_prev, b) else {
                continue;
            };
            if a.0.signum() == b.0.signum() {
                continue;
            }
            let target = std::cell::Cell::new(((a.1 + b.1) / 2.0, 0usize));
            let sigma = |s: f64| {
                let (w, k) = target.get();
                target.set((w, k + 1));
                eigenvalues(&sys.jacobian(s))
                    .and_then(|ev| nearest(&ev, (0.0, w)))
                    .map_or(f64::NAN, |z| z.0)
            };
            let root = brent::root(sigma, v_prev, v, opts.rel_tol * v, 200);
            evaluations += target.get().1;
            let at = eigenvalues(&sys.jacobian(root.x))
                .and_then(|ev| nearest(&ev, (0.0, target.get().0)));
            let Some(z) = at else {
                continue;
            };
            // re-check by fresh eigenvalues: σ has opposite signs 1e-6 V below and above (far
            // enough that rounding in the eigenvalues cannot decide the sign)
            let side = |s: f64| {
                eigenvalues(&sys.jacobian(s))
                    .and_then(|ev| nearest(&ev, (0.0, z.1)))
                    .map_or(f64::NAN, |z| z.0)
            };
            let delta = 1e-6 * root.x;
            let (below, above) = (side(root.x - delta), side(root.x + delta));
            evaluations += 2;
            if !root.x.is_finite() || below.signum() == above.signum() || below.is_nan() {
                continue;
            }
            let f_hz = z.1 / (2.0 * std::f64::consts::PI);
            crossings.push(Crossing {
                speed_m_s: root.x,
                frequency_hz: f_hz,
                wavelength_m: root.x / f_hz,
                direction: if b.0 > 0.0 {
                    Direction::Onset
                } else {
                    Direction::Recovery
                },
                bracket_m_s: root.bracket,
            });
        }
        if d_prev.signum() != d.signum() && d_prev.is_finite() && d.is_finite() {
            let root = brent::root(det, v_prev, v, opts.rel_tol * v, 200);
            evaluations += root.evaluations;
            divergence.push(root.x);
        }
        (v_prev, e_prev, d_prev) = (v, e, d);
    }
    crossings.sort_by(|a, b| a.speed_m_s.total_cmp(&b.speed_m_s));
    Ok(CriticalSpeeds {
        law,
        speed_range: (lo, hi),
        crossings,
        stable_at_start,
        divergence_speeds_m_s: divergence,
        evaluations,
    })
}
