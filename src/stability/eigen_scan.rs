//! The critical-speed search for any number of states: eigenvalues on a grid, then Brent's
//! method on the real part of the eigenvalue that crossed (module docs of [`super`]).

use super::spectrum::{determinant, eigenvalues};
use super::{
    brent, hopf, CriticalSpeeds, Crossing, Direction, LinearError, LinearOptions, LinearSystem,
};
use crate::contact::creep::CreepLaw;

/// The eigenvalue of `ev` (Im > 0) nearest to `target` (by squared distances, here and below:
/// the same neighbours without the cost of `hypot`).
fn nearest(ev: &[(f64, f64)], target: (f64, f64)) -> Option<(f64, f64)> {
    ev.iter().copied().filter(|z| z.1 > 0.0).min_by(|a, b| {
        let d = |z: &(f64, f64)| (z.0 - target.0).powi(2) + (z.1 - target.1).powi(2);
        d(a).total_cmp(&d(b))
    })
}

/// Complex eigenvalues (Im > 0) in the right half-plane.
fn unstable(ev: &[(f64, f64)]) -> usize {
    ev.iter().filter(|z| z.1 > 0.0 && z.0 > 0.0).count()
}

/// The largest real part of the complex eigenvalues (Im > 0); −∞ if there are none.
fn top(ev: &[(f64, f64)]) -> f64 {
    ev.iter()
        .filter(|z| z.1 > 0.0)
        .map(|z| z.0)
        .fold(f64::NEG_INFINITY, f64::max)
}

/// The complex eigenvalues (Im > 0) of either end that are unstable there and whose nearest
/// complex eigenvalue at the other end is stable: pairs that crossed the axis between the
/// ends even when another pair crossing the other way leaves the unstable count unchanged.
fn exchanged(lo: &End, hi: &End) -> usize {
    let dist = |a: &(f64, f64), b: &(f64, f64)| (a.0 - b.0).powi(2) + (a.1 - b.1).powi(2);
    let one_way = |from: &End, to: &End| {
        from.ev
            .iter()
            .filter(|z| z.1 > 0.0 && z.0 > 0.0)
            .filter(|z| {
                to.ev
                    .iter()
                    .filter(|w| w.1 > 0.0)
                    .min_by(|a, b| dist(a, z).total_cmp(&dist(b, z)))
                    .is_some_and(|w| w.0 <= 0.0)
            })
            .count()
    };
    one_way(lo, hi) + one_way(hi, lo)
}

/// The sign of det J from its eigenvalues: the product of the real ones' signs (a complex
/// pair contributes |λ|² > 0), so the grid needs no LU of its own to see a real eigenvalue
/// cross zero.
fn det_sign(ev: &[(f64, f64)]) -> f64 {
    ev.iter()
        .filter(|z| z.1 == 0.0)
        .map(|z| if z.0 < 0.0 { -1.0 } else { 1.0 })
        .product()
}

/// One end of a scan interval: speed, eigenvalues, unstable count, least damped real part,
/// sign of det J.
#[derive(Clone)]
struct End {
    v: f64,
    ev: Vec<(f64, f64)>,
    count: usize,
    top: f64,
    det_sign: f64,
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
            top: top(&ev),
            det_sign: det_sign(&ev),
            ev,
        })
    }

    /// The crossings between `lo` and `hi` by Newton on the Hopf system ([`hopf::newton`]):
    /// one run for each complex eigenvalue (Im > 0) of either end whose nearest complex
    /// eigenvalue at the other end lies on the other side of the axis, started from the end
    /// where that pair is nearer the axis (its eigenvalue there, eigenvector by inverse
    /// iteration). Each root's direction is the sign of the real part's speed derivative
    /// there, which the last Newton step gives. `false` (nothing recorded) unless the roots in
    /// `[lo, hi]` add up to the change of the unstable count and there are roots: then the
    /// caller falls back to bisection. `exchanged` ([`exchanged`]) pairs crossed both ways.
    fn by_newton(&mut self, lo: &End, hi: &End, exchanged: usize) -> bool {
        let change = hi.count as i64 - lo.count as i64;
        let sys = self.sys;
        // (eigenvalue at lo, eigenvalue at hi) of each pair that changed side
        let mut pairs: Vec<((f64, f64), (f64, f64))> = Vec::new();
        for (from, to, from_lo) in [(lo, hi, true), (hi, lo, false)] {
            for z in from.ev.iter().filter(|z| z.1 > 0.0) {
                let Some(w) = nearest(&to.ev, *z) else {
                    continue;
                };
                if (z.0 > 0.0) == (w.0 > 0.0) {
                    continue;
                }
                let pair = if from_lo { (*z, w) } else { (w, *z) };
                if !pairs.contains(&pair) {
                    pairs.push(pair);
                }
            }
        }
        if pairs.len() < (change.unsigned_abs() as usize).max(exchanged) {
            return false;
        }
        let tol = self.opts.rel_tol.max(1e-14);
        let mut found: Vec<Crossing> = Vec::new();
        for (a, b) in pairs {
            let (v0, z0) = if a.0.abs() <= b.0.abs() {
                (lo.v, a)
            } else {
                (hi.v, b)
            };
            let Some(h) = hopf::newton(sys, v0, z0, tol) else {
                continue;
            };
            let f_hz = h.omega / (2.0 * std::f64::consts::PI);
            let seen = found.iter().any(|c| {
                (c.speed_m_s - h.speed).abs() <= 1e-9 * h.speed
                    && (c.frequency_hz - f_hz).abs() <= 1e-6 * f_hz
            });
            if seen || h.speed < lo.v || h.speed > hi.v {
                continue;
            }
            found.push(Crossing::new(h.speed, h.omega, h.onset, 2.0 * h.last_step));
        }
        let net: i64 = found
            .iter()
            .map(|c| match c.direction {
                Direction::Onset => 1,
                Direction::Recovery => -1,
            })
            .sum();
        if net != change || found.is_empty() {
            return false;
        }
        self.crossings.extend(found);
        true
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
        let dist = |a: &(f64, f64), b: &(f64, f64)| (a.0 - b.0).powi(2) + (a.1 - b.1).powi(2);
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
        self.crossings
            .push(Crossing::new(root.x, z.1, onset, root.bracket));
    }
}

/// The grid of the eigenvalue scan when the study does not set `grid_points`: 64 speeds, of
/// which the scan visits those `stride` allows (every one wherever an eigenvalue
/// approaches the axis), refined by `refine_turns` where the least damped pair turns near the
/// axis. On every shipped study and on a 7×7 bogie stability map it finds the crossings the
/// 512-point grid finds (`tests/vehicle.rs`).
pub const EIGEN_GRID_POINTS: usize = 64;

/// Most grid steps of [`EIGEN_GRID_POINTS`] one step of the scan may span.
const MAX_STRIDE: usize = 8;

/// The fraction of its distance to the imaginary axis that an eigenvalue may be predicted to
/// cover in one step of the scan.
const APPROACH: f64 = 0.5;

/// How many grid steps of `h` (m/s) the scan may take after `cur`, given the end `prev`
/// before it: each eigenvalue of `cur`, with the speed derivative of its real part estimated
/// from its nearest eigenvalue at `prev`, may be predicted to move toward the axis by at most
/// [`APPROACH`] of its distance from it; at least 1, at most `cap`. A pair moving away from
/// the axis, or along it, sets no limit: the steps stay short only where some eigenvalue
/// comes near the axis, which is where the 64-point grid is needed.
fn stride(prev: &End, cur: &End, h: f64, cap: usize) -> usize {
    let dv = cur.v - prev.v;
    let dist = |a: &(f64, f64), b: &(f64, f64)| (a.0 - b.0).powi(2) + (a.1 - b.1).powi(2);
    let mut steps = cap as f64;
    // the eigenvalues with Im < 0 mirror those with Im > 0
    for z in cur.ev.iter().filter(|z| z.1 >= 0.0) {
        let Some(p) = prev
            .ev
            .iter()
            .min_by(|a, b| dist(a, z).total_cmp(&dist(b, z)))
        else {
            return 1;
        };
        let slope = (z.0 - p.0) / dv;
        let toward = if z.0 > 0.0 {
            -slope
        } else if z.0 < 0.0 {
            slope
        } else {
            slope.abs()
        };
        if toward > 0.0 {
            steps = steps.min(APPROACH * z.0.abs() / (toward * h));
        }
    }
    if steps.is_finite() && steps >= 1.0 {
        (steps as usize).min(cap)
    } else {
        1
    }
}

/// Subdivisions of an interval flagged by [`refine_turns`].
const TURN_SUBDIVISIONS: usize = 8;

/// Speeds inside the grid intervals where an onset and a recovery could cancel in the count:
/// wherever the parabola through the least damped real part at three successive grid speeds
/// (same unstable count at all three) has its maximum between them and above zero, both
/// intervals are split into [`TURN_SUBDIVISIONS`] parts. A pair that dips into the right
/// half-plane and out again within one grid step shows as such a turn.
fn refine_turns(ends: &[End]) -> Vec<f64> {
    let mut flagged = vec![false; ends.len().saturating_sub(1)];
    for (i, w) in ends.windows(3).enumerate() {
        let (a, b, c) = (&w[0], &w[1], &w[2]);
        if a.count != b.count
            || b.count != c.count
            || !(a.top.is_finite() && b.top.is_finite() && c.top.is_finite())
        {
            continue;
        }
        // the parabola through (v, top) at the three speeds
        let (h1, h2) = (b.v - a.v, c.v - b.v);
        let d1 = (b.top - a.top) / h1;
        let d2 = (c.top - b.top) / h2;
        let curv = (d2 - d1) / (h1 + h2); // half the second derivative
        if curv >= 0.0 {
            continue;
        }
        // slope at b: d1 + curv·h1; vertex where the slope vanishes
        let slope_b = d1 + curv * h1;
        let vertex = b.v - slope_b / (2.0 * curv);
        if !(a.v..=c.v).contains(&vertex) {
            continue;
        }
        let peak = b.top + slope_b * (vertex - b.v) + curv * (vertex - b.v).powi(2);
        if peak > 0.0 {
            flagged[i] = true;
            flagged[i + 1] = true;
        }
    }
    let mut extra = Vec::new();
    for (i, f) in flagged.iter().enumerate() {
        if *f {
            let (lo, hi) = (ends[i].v, ends[i + 1].v);
            extra.extend(
                (1..TURN_SUBDIVISIONS)
                    .map(|k| lo + (hi - lo) * k as f64 / TURN_SUBDIVISIONS as f64),
            );
        }
    }
    extra
}

/// Every crossing of the imaginary axis by a complex pair, for any state size: the count of
/// unstable complex eigenvalues on the grid (on the default grid only at the speeds [`stride`]
/// allows, refined where the least damped pair turns near the axis, [`refine_turns`]; a
/// study's `grid_points` are all visited). Where the count changes between two speeds the
/// crossings are located by Newton on the Hopf system ([`hopf::newton`]); should their directions not
/// account for the change, the interval is bisected on the count until each part holds one
/// crossing (two bogies give pairs crossing fractions of a m/s apart), which is then located
/// by Brent's method on the tracked eigenvalue. Two crossings in opposite directions within one
/// grid step that the turn test misses cancel in the count and are not seen (as in the quartic
/// scan).
pub(super) fn eigen_scan<const N: usize>(
    sys: &LinearSystem<N>,
    law: CreepLaw,
    opts: &LinearOptions,
) -> Result<CriticalSpeeds, LinearError> {
    let (lo, hi) = opts.speed_range;
    let (n, speed) = super::grid(opts, EIGEN_GRID_POINTS);
    let det = |v: f64| determinant(&sys.jacobian(v));
    let mut scan = Scan {
        sys,
        opts,
        evaluations: 0,
        crossings: Vec::new(),
    };
    let mut ends = if opts.grid_points.is_some() {
        (0..n)
            .map(|i| scan.end(speed(i)))
            .collect::<Result<Vec<End>, LinearError>>()?
    } else {
        // the default grid, stepping over the grid speeds where no eigenvalue nears the axis
        let h = speed(1) - speed(0);
        let mut ends = vec![scan.end(speed(0))?];
        let (mut i, mut k) = (0, 1);
        while i + 1 < n {
            let j = (i + k).min(n - 1);
            let e = scan.end(speed(j))?;
            let cap = (2 * k).min(MAX_STRIDE);
            k = ends.last().map_or(1, |prev| stride(prev, &e, h, cap));
            ends.push(e);
            i = j;
        }
        ends
    };
    let extra = refine_turns(&ends);
    if !extra.is_empty() {
        for v in extra {
            ends.push(scan.end(v)?);
        }
        ends.sort_by(|a, b| a.v.total_cmp(&b.v));
    }
    let stable_at_start = ends[0].ev.iter().all(|z| z.0 < 0.0);
    let mut divergence = Vec::new();
    for w in ends.windows(2) {
        let (prev, cur) = (&w[0], &w[1]);
        let swapped = exchanged(prev, cur);
        if (prev.count != cur.count || swapped > 0) && !scan.by_newton(prev, cur, swapped) {
            scan.interval(prev, cur, 0)?;
        }
        if prev.det_sign != cur.det_sign {
            let root = brent::root(det, prev.v, cur.v, opts.rel_tol * cur.v, 200);
            scan.evaluations += root.evaluations;
            divergence.push(root.x);
        }
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

#[cfg(test)]
mod tests {
    use super::*;

    fn end(v: f64, top: f64) -> End {
        End {
            v,
            ev: Vec::new(),
            count: 0,
            top,
            det_sign: 1.0,
        }
    }

    /// σ(V) = 0.5 − (V − 5)² sampled at 4, 5.8 and 6.5 is negative at all three, but its
    /// maximum (0.5 at V = 5, exact for a parabola) is not: both intervals are subdivided.
    /// Shifted down by 1 the turn stays in the left half-plane and nothing is added.
    #[test]
    fn a_turn_above_the_axis_between_grid_speeds_is_refined() {
        let s = |v: f64| 0.5 - (v - 5.0) * (v - 5.0);
        let ends: Vec<End> = [4.0, 5.8, 6.5].iter().map(|&v| end(v, s(v))).collect();
        assert!(ends.iter().all(|e| e.top < 0.0));
        let extra = refine_turns(&ends);
        assert_eq!(extra.len(), 2 * (TURN_SUBDIVISIONS - 1));
        assert!(extra.iter().all(|v| (4.0..6.5).contains(v)));
        let below: Vec<End> = [4.0, 5.8, 6.5]
            .iter()
            .map(|&v| end(v, s(v) - 1.0))
            .collect();
        assert!(refine_turns(&below).is_empty());
    }

    /// A pair 1 1/s left of the axis that moved 1 1/s toward it over the last 1 m/s may take
    /// 0.5 m/s (five steps of 0.1 m/s); moving away from the axis, or along it, it sets no
    /// limit (the cap); ahead of the axis by less than one step's predicted move, one step.
    #[test]
    fn stride_keeps_each_eigenvalue_half_its_distance_from_the_axis() {
        let at = |v: f64, ev: Vec<(f64, f64)>| End {
            v,
            ev,
            count: 0,
            top: 0.0,
            det_sign: 1.0,
        };
        let prev = at(10.0, vec![(-2.0, 1.0), (-2.0, -1.0), (-50.0, 0.0)]);
        let toward = at(11.0, vec![(-1.0, 1.0), (-1.0, -1.0), (-50.0, 0.0)]);
        assert_eq!(stride(&prev, &toward, 0.1, 8), 5);
        let away = at(11.0, vec![(-3.0, 1.5), (-3.0, -1.5), (-50.0, 0.0)]);
        assert_eq!(stride(&prev, &away, 0.1, 8), 8);
        let close = at(11.0, vec![(-0.01, 1.0), (-0.01, -1.0), (-50.0, 0.0)]);
        assert_eq!(stride(&prev, &close, 0.1, 8), 1);
    }

    /// The sign of det J read from the eigenvalues equals the sign of the LU determinant, on
    /// 6×6 matrices with one, two or no negative real eigenvalues and complex pairs.
    #[test]
    fn determinant_sign_from_eigenvalues_matches_lu() {
        use nalgebra::SMatrix;
        let (mut signs, mut compared) = ([0usize; 2], 0);
        for k in 0..40 {
            let j = SMatrix::<f64, 6, 6>::from_fn(|r, c| {
                ((r * 7 + c * 3 + k * 11) as f64 * 0.37 + (r * c) as f64).sin()
                    + if r == c { 0.1 * k as f64 - 2.0 } else { 0.0 }
            });
            let ev = eigenvalues(&j).expect("eigenvalues");
            let det = determinant(&j);
            if det.abs() < 1e-6 {
                continue; // too near singular for either sign to mean anything
            }
            assert_eq!(det_sign(&ev), det.signum(), "matrix {k}: det {det}, {ev:?}");
            signs[usize::from(det > 0.0)] += 1;
            compared += 1;
        }
        assert!(
            compared >= 30 && signs[0] > 0 && signs[1] > 0,
            "{compared} {signs:?}"
        );
    }
}
