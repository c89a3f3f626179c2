//! The critical-speed search for any number of states: eigenvalues on a grid, then Brent's
//! method on the real part of the eigenvalue that crossed (module docs of [`super`]).

use super::spectrum::{determinant, eigenvalues};
use super::{brent, CriticalSpeeds, Crossing, Direction, LinearError, LinearOptions, LinearSystem};
use crate::contact::creep::CreepLaw;

/// The eigenvalue of `ev` (Im > 0) nearest to `target`.
fn nearest(ev: &[(f64, f64)], target: (f64, f64)) -> Option<(f64, f64)> {
    ev.iter().copied().filter(|z| z.1 > 0.0).min_by(|a, b| {
        let d = |z: &(f64, f64)| (z.0 - target.0).hypot(z.1 - target.1);
        d(a).total_cmp(&d(b))
    })
}

/// Complex eigenvalues (Im > 0) in the right half-plane.
fn unstable(ev: &[(f64, f64)]) -> usize {
    ev.iter().filter(|z| z.1 > 0.0 && z.0 > 0.0).count()
}

/// One end of a scan interval: speed, eigenvalues, unstable count.
#[derive(Clone)]
struct End {
    v: f64,
    ev: Vec<(f64, f64)>,
    count: usize,
}

struct Scan<'a, const N: usize> {
    sys: &'a LinearSystem<N>,
    opts: &'a LinearOptions,
    evaluations: usize,
    crossings: Vec<Crossing>,
}

impl<const N: usize> Scan<'_, N> {
    fn end(&mut self, v: f64) -> Result<End, LinearError> {
        self.evaluations += 1;
        let ev =
            eigenvalues(&self.sys.jacobian(v)).ok_or(LinearError::NotFinite { speed_m_s: v })?;
        Ok(End {
            v,
            count: unstable(&ev),
            ev,
        })
    }

    /// Splits `[lo, hi]` until each part holds a net change of one pair, then locates it.
    fn interval(&mut self, lo: &End, hi: &End, depth: usize) -> Result<(), LinearError> {
        let change = hi.count.abs_diff(lo.count);
        if change == 0 {
            return Ok(());
        }
        if change > 1 && depth < 40 && hi.v - lo.v > 1e-9 * hi.v {
            let mid = self.end(0.5 * (lo.v + hi.v))?;
            self.interval(lo, &mid, depth + 1)?;
            return self.interval(&mid, hi, depth + 1);
        }
        self.narrow(lo, hi)
    }

    /// One net crossing between `lo` and `hi`: bisect on the count of unstable pairs until the
    /// interval is 1e-6 V wide (there the crossing pair moves far less than its distance to any
    /// other, even for the near-double pairs of two alike bogies), then locate it.
    fn narrow(&mut self, lo: &End, hi: &End) -> Result<(), LinearError> {
        let (mut lo, mut hi) = (lo.clone(), hi.clone());
        while hi.v - lo.v > 1e-6 * hi.v {
            let mid = self.end(0.5 * (lo.v + hi.v))?;
            if mid.count == lo.count {
                lo = mid;
            } else if mid.count == hi.count {
                hi = mid;
            } else {
                // another pair moved too: split again
                self.interval(&lo, &mid, 0)?;
                return self.interval(&mid, &hi, 0);
            }
        }
        self.locate(&lo, &hi);
        Ok(())
    }

    /// One pair crossed between `lo` and `hi`: the pair (a, b), a on the old side of the axis
    /// at `lo` and b on the new side at `hi`, nearest each other; Brent's method on the real
    /// part of the eigenvalue nearest the straight path from a to b.
    fn locate(&mut self, lo: &End, hi: &End) {
        let onset = hi.count > lo.count;
        let old_side = |z: &(f64, f64)| z.1 > 0.0 && if onset { z.0 <= 0.0 } else { z.0 > 0.0 };
        let new_side = |z: &(f64, f64)| z.1 > 0.0 && if onset { z.0 > 0.0 } else { z.0 <= 0.0 };
        let dist = |a: &(f64, f64), b: &(f64, f64)| (a.0 - b.0).hypot(a.1 - b.1);
        let mut best: Option<((f64, f64), (f64, f64))> = None;
        for a in lo.ev.iter().filter(|z| old_side(z)) {
            for b in hi.ev.iter().filter(|z| new_side(z)) {
                if best.is_none_or(|(x, y)| dist(a, b) < dist(&x, &y)) {
                    best = Some((*a, *b));
                }
            }
        }
        let Some((a, b)) = best else {
            return;
        };
        let sys = self.sys;
        let path = |v: f64| {
            let t = (v - lo.v) / (hi.v - lo.v);
            (a.0 + t * (b.0 - a.0), a.1 + t * (b.1 - a.1))
        };
        let tracked = |v: f64| {
            eigenvalues(&sys.jacobian(v))
                .and_then(|ev| nearest(&ev, path(v)))
                .map_or((f64::NAN, f64::NAN), |z| z)
        };
        let mut count = 0;
        let root = brent::root(
            |v| {
                count += 1;
                tracked(v).0
            },
            lo.v,
            hi.v,
            self.opts.rel_tol * hi.v,
            200,
        );
        self.evaluations += count;
        // re-check by fresh eigenvalues: σ has opposite signs 1e-6 V below and above (far
        // enough that rounding in the eigenvalues cannot decide the sign)
        let z = tracked(root.x);
        let delta = 1e-6 * root.x;
        let side = |v: f64| {
            eigenvalues(&sys.jacobian(v))
                .and_then(|ev| nearest(&ev, (0.0, z.1)))
                .map_or(f64::NAN, |z| z.0)
        };
        let (below, above) = (side(root.x - delta), side(root.x + delta));
        self.evaluations += 3;
        if !root.x.is_finite()
            || !z.1.is_finite()
            || below.is_nan()
            || below.signum() == above.signum()
        {
            return;
        }
        let f_hz = z.1 / (2.0 * std::f64::consts::PI);
        self.crossings.push(Crossing {
            speed_m_s: root.x,
            frequency_hz: f_hz,
            wavelength_m: root.x / f_hz,
            direction: if onset {
                Direction::Onset
            } else {
                Direction::Recovery
            },
            bracket_m_s: root.bracket,
        });
    }
}

/// Every crossing of the imaginary axis by a complex pair, for any state size: the count of
/// unstable complex eigenvalues on the grid; an interval where it changes by more than one is
/// bisected until each part holds one crossing (two bogies give pairs crossing fractions of a
/// m/s apart), which is then located. Two crossings in opposite directions within one grid step
/// cancel in the count and are not seen (as in the quartic scan).
pub(super) fn eigen_scan<const N: usize>(
    sys: &LinearSystem<N>,
    law: CreepLaw,
    opts: &LinearOptions,
) -> Result<CriticalSpeeds, LinearError> {
    let (lo, hi) = opts.speed_range;
    let n = opts.grid_points;
    let speed = |i: usize| lo + (hi - lo) * (i as f64) / ((n - 1) as f64);
    let det = |v: f64| determinant(&sys.jacobian(v));
    let mut scan = Scan {
        sys,
        opts,
        evaluations: 0,
        crossings: Vec::new(),
    };
    let first = scan.end(lo)?;
    let stable_at_start = first.ev.iter().all(|z| z.0 < 0.0);
    let mut divergence = Vec::new();
    let (mut prev, mut d_prev) = (first, det(lo));
    for i in 1..n {
        let cur = scan.end(speed(i))?;
        let d = det(cur.v);
        scan.interval(&prev, &cur, 0)?;
        if d_prev.signum() != d.signum() && d_prev.is_finite() && d.is_finite() {
            let root = brent::root(det, prev.v, cur.v, opts.rel_tol * cur.v, 200);
            scan.evaluations += root.evaluations;
            divergence.push(root.x);
        }
        (prev, d_prev) = (cur, d);
    }
    let mut crossings = scan.crossings;
    crossings.sort_by(|a, b| a.speed_m_s.total_cmp(&b.speed_m_s));
    Ok(CriticalSpeeds {
        law,
        speed_range: (lo, hi),
        crossings,
        stable_at_start,
        divergence_speeds_m_s: divergence,
        evaluations: scan.evaluations,
    })
}
