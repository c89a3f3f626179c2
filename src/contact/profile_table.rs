//! Tabulating a profile pair: rigid solve at every node, jump detection, optional smoothing.
//!
//! Real profiles give geometry functions with contact-point jumps (tread to flange root),
//! where r, δ and the curvature are discontinuous in y. The table stores at each node the
//! solved values with their exact slopes (implicit function theorem), or, when the study asks
//! for smoothing of half-width w ≥ 1.5 h (h the node spacing), a local linear regression of
//! the sampled values: at node k, `c0 + c1 d` is fitted by weighted least squares to the nodes
//! within |d| ≤ w with Gaussian weights (σ = w/2); c0 is the node's value and c1 its slope.
//! Where the function is smooth this changes values by about σ² f''/2 and slopes by O(σ² f''');
//! across a jump it replaces the step by a monotone ramp of width ≈ 2w without overshoot
//! (a local quadratic fit was tried first: its undershoot before a step made the effective
//! conicity dip before the jump, a spurious fold in the limit-cycle branch).
//! The Hertz patch and creep coefficients are computed from the smoothed (r, δ, B). Kalker's
//! table covers 0.1 ≤ a/b ≤ 10 only; at flange contact (and where the profiles are nearly
//! conformal, B ≤ 0) B is held at the end of the matching range of B/A, and the nodes where
//! that happened are listed ([`ContactTable::clamped`]).

use std::sync::Arc;

use super::geometry::ContactPoint;
use super::hertz::complete_elliptic;
use super::rigid::ProfilePair;
use super::table::{ContactTable, Jump, TableError, TableSpec};
use crate::system::scalar::{Dual, Scalar};

/// A jump is reported when the wheel contact point moves by more than this between two
/// nodes (m) …
const JUMP_MIN: f64 = 5e-4;
/// … and by more than this many times the node spacing.
const JUMP_RATIO: f64 = 10.0;

/// Raw node state: radius, angle, roll, curvature B as duals, and the wheel offset.
type Raw = ([Dual<1>; 4], f64);

/// Builds the contact table of a profile pair.
pub(super) fn build(
    pair: &Arc<ProfilePair>,
    smoothing: f64,
    spec: &TableSpec,
) -> Result<ContactTable, TableError> {
    let n = spec.nodes.max(5) | 1;
    let half = (n - 1) / 2;
    let h = spec.half_width / half as f64;
    let raw: Vec<Raw> = super::table::march(half, h, |y, guess| {
        let (p, u) = pair.solve(spec.nominal, y, guess)?;
        let b = pair.curvature(spec.nominal, p.roll, p.wheel_offset, Dual::var(y, 0));
        Ok::<_, TableError>((([p.radius, p.angle, p.roll, b], p.wheel_offset.re), u))
    })?;
    let y0 = -(half as f64) * h;
    let jumps = find_jumps(&raw, y0, h);
    let cols = if smoothing >= 1.5 * h {
        smooth(&raw, h, smoothing)
    } else {
        raw.iter().map(|r| r.0).collect()
    };
    let cap = kalker_ratio_cap();
    let mut clamped = Vec::new();
    let nodes: Vec<(ContactPoint<Dual<1>>, Dual<1>)> = cols
        .iter()
        .zip(&raw)
        .enumerate()
        .map(|(k, (c, r))| {
            // Kalker's table covers a/b in [0.1, 10]: B/A is held inside the matching range
            let a = c[0].recip();
            let b = if c[3].re > cap * a.re {
                clamped.push(y0 + k as f64 * h);
                a * cap
            } else if c[3].re < a.re / cap {
                clamped.push(y0 + k as f64 * h);
                a / cap
            } else {
                c[3]
            };
            (
                ContactPoint {
                    radius: c[0],
                    angle: c[1],
                    roll: c[2],
                    wheel_offset: Dual::cst(r.1),
                },
                b,
            )
        })
        .collect();
    let offsets = raw.iter().map(|r| r.1).collect();
    let mut t = ContactTable::assemble(spec, (y0, h), &nodes, offsets, jumps)?;
    t.clamped = clamped;
    Ok(t)
}

/// The curvature ratio max(A,B)/min(A,B) at which the Hertz axis ratio is 1/9.9, just inside
/// Kalker's table: ρ = (E/(1−e²) − K)/(K − E) with 1 − e² = g².
fn kalker_ratio_cap() -> f64 {
    let g: f64 = 1.0 / 9.9;
    let (k, e) = complete_elliptic((1.0 - g * g).sqrt());
    (e / (g * g) - k) / (k - e)
}

/// Contact-point jumps between consecutive nodes.
fn find_jumps(raw: &[Raw], y0: f64, h: f64) -> Vec<Jump> {
    raw.windows(2)
        .enumerate()
        .filter(|(_, w)| {
            let du = (w[1].1 - w[0].1).abs();
            du > JUMP_MIN && du > JUMP_RATIO * h
        })
        .map(|(k, w)| Jump {
            y_m: (y0 + k as f64 * h, y0 + (k + 1) as f64 * h),
            wheel_offset_m: (w[0].1, w[1].1),
            radius_m: (w[0].0[0].re, w[1].0[0].re),
        })
        .collect()
}

/// Local linear regression with Gaussian weights (σ = w/2, window |d| ≤ w) of the four
/// columns' values: value Σωv/Σω, slope Σωdv/Σωd² (exact for a straight line; monotone data
/// stay monotone, so a step becomes a smooth ramp without overshoot).
fn smooth(raw: &[Raw], h: f64, width: f64) -> Vec<[Dual<1>; 4]> {
    let n = raw.len();
    let m = (width / h).floor() as usize;
    let sigma = 0.5 * width / h;
    (0..n)
        .map(|k| {
            let (lo, hi) = (k.saturating_sub(m), (k + m).min(n - 1));
            let (mut s0, mut s1, mut s2) = (0.0, 0.0, 0.0);
            let (mut t0, mut t1) = ([0.0; 4], [0.0; 4]);
            for (j, r) in raw.iter().enumerate().take(hi + 1).skip(lo) {
                let d = j as f64 - k as f64;
                let w = (-0.5 * (d / sigma).powi(2)).exp();
                (s0, s1, s2) = (s0 + w, s1 + w * d, s2 + w * d * d);
                for c in 0..4 {
                    t0[c] += w * r.0[c].re;
                    t1[c] += w * d * r.0[c].re;
                }
            }
            // weighted least squares line c0 + c1 d (s1 ≠ 0 only near the table ends)
            let det = s0 * s2 - s1 * s1;
            std::array::from_fn(|c| Dual {
                re: (s2 * t0[c] - s1 * t1[c]) / det,
                eps: [(s0 * t1[c] - s1 * t0[c]) / det / h],
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn raw_of(f: impl Fn(f64) -> f64, n: usize, h: f64) -> Vec<Raw> {
        (0..n)
            .map(|k| {
                let y = (k as f64 - (n / 2) as f64) * h;
                ([Dual::cst(f(y)); 4], 0.0)
            })
            .collect()
    }

    #[test]
    fn smoothing_keeps_lines_and_turns_steps_into_monotone_ramps() {
        let h = 25e-6;
        // a straight line: values and slopes exact, also at the table ends
        let line = smooth(&raw_of(|y| 0.46 + 0.2 * y, 41, h), h, 1e-4);
        for (k, c) in line.iter().enumerate() {
            let y = (k as f64 - 20.0) * h;
            assert!((c[0].re - (0.46 + 0.2 * y)).abs() < 1e-14, "{k}");
            assert!((c[0].eps[0] - 0.2).abs() < 1e-9, "{k}");
        }
        // a step of 0.46 mm: monotone, no overshoot, odd about the step, slope ≥ 0
        let step = smooth(
            &raw_of(|y| if y > 0.0 { 4.6e-4 } else { 0.0 }, 81, h),
            h,
            1e-4,
        );
        for w in step.windows(2) {
            assert!(w[1][0].re >= w[0][0].re - 1e-18);
        }
        for c in &step {
            assert!((-1e-18..=4.6e-4 + 1e-18).contains(&c[0].re) && c[0].eps[0] >= -1e-12);
        }
        // beyond the window (|d| > w = 4 nodes) the step is untouched
        assert!(step[30][0].re.abs() < 1e-18);
        assert!((step[50][0].re - 4.6e-4).abs() < 1e-18);
    }
}
