//! The constraint margin of a trade row and the Illinois method that locates where it
//! changes sign: the two pieces a curve trade's interval ends are found with.

use super::select::infeasibility;
use super::table::Row;
use super::{Target, TradePlan};

/// The smallest relative margin of the constraints on `row` (≥ 0 iff feasible): at_least X
/// gives (V − X)/|X|, at_most X gives (X − V)/|X|; a result above range counts as v_max
/// (and fails every at_most); −∞ when a value the trade reads is missing or failed.
pub fn margin(plan: &TradePlan, row: &Row) -> f64 {
    if infeasibility(plan, row).is_none() {
        // feasible: the margin is ≥ 0 by the same rules
        return raw_margin(plan, row).max(0.0);
    }
    let m = raw_margin(plan, row);
    if m < 0.0 {
        m
    } else {
        // infeasible for want of a value (a failure), not by a bound
        f64::NEG_INFINITY
    }
}

fn raw_margin(plan: &TradePlan, row: &Row) -> f64 {
    let mut m = f64::INFINITY;
    for c in &plan.constraints {
        let v = match &c.target {
            Target::Result(r) => match (row.result(*r), row.above_range(*r)) {
                (Some(v), _) => Some(v),
                (None, Some(top)) => {
                    if c.at_most.is_some() {
                        return -1.0;
                    }
                    Some(top)
                }
                (None, None) => None,
            },
            Target::Axis { key, .. } => row.axis(key),
        };
        let Some(v) = v else {
            return f64::NEG_INFINITY;
        };
        let rel = |d: f64, b: f64| d / b.abs().max(f64::MIN_POSITIVE);
        if let Some(lo) = c.at_least {
            m = m.min(rel(v - lo, lo));
        }
        if let Some(hi) = c.at_most {
            m = m.min(rel(hi - v, hi));
        }
    }
    m
}

/// The constraint whose margin is smallest at `row` (the one an end is set by).
pub fn binding(plan: &TradePlan, row: &Row) -> Option<usize> {
    let single = |c: &super::Constraint| {
        let p = TradePlan {
            constraints: vec![c.clone()],
            ..plan.clone()
        };
        raw_margin(&p, row).abs()
    };
    (0..plan.constraints.len())
        .min_by(|&a, &b| single(&plan.constraints[a]).total_cmp(&single(&plan.constraints[b])))
}

/// The Illinois method on `f` (≥ 0: feasible) between axis coordinates `good` (f ≥ 0) and
/// `bad` (f < 0), bisecting where a side's value is not finite; returns the feasible side of
/// the last bracket, within `tol` of the end, and the number of evaluations.
pub fn locate(f: &dyn Fn(f64) -> f64, good: (f64, f64), bad: (f64, f64), tol: f64) -> (f64, usize) {
    let ((mut a, mut fa), (mut b, mut fb)) = (good, bad);
    // which side the previous step replaced (true: the feasible one)
    let mut last_good: Option<bool> = None;
    let mut n = 0;
    while (b - a).abs() > tol && n < 200 {
        let secant = fa.is_finite() && fb.is_finite() && fa != fb;
        let mut x = if secant {
            (a * fb - b * fa) / (fb - fa)
        } else {
            0.5 * (a + b)
        };
        if !(x > a.min(b) && x < a.max(b)) {
            x = 0.5 * (a + b);
        }
        let fx = f(x);
        n += 1;
        let good_side = fx >= 0.0;
        // Illinois: the side kept twice has its value halved
        if last_good == Some(good_side) {
            if good_side {
                fb *= 0.5;
            } else {
                fa *= 0.5;
            }
        }
        if good_side {
            (a, fa) = (x, fx);
        } else {
            (b, fb) = (x, fx);
        }
        last_good = Some(good_side);
        if fx == 0.0 {
            break;
        }
    }
    (a, n)
}

#[cfg(test)]
#[path = "margin_tests.rs"]
mod tests;
