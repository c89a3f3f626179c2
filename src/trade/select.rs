//! Feasibility, the Pareto front and the best design: pure functions over rows.

use super::plan::fmt_si;
use super::table::Row;
use super::{Constraint, ResultKind, Sense, Target, TradePlan};

/// The verdict on one row of the sweep.
#[derive(Clone, Debug, PartialEq)]
pub struct Assessment {
    /// meets every constraint (and the point did not fail)
    pub feasible: bool,
    /// why not, `""` when feasible; several reasons are joined with `"; "`
    pub reason: String,
    /// on the Pareto front (see the module docs of [`crate::trade`])
    pub pareto: bool,
    /// the best design
    pub best: bool,
}

/// Whether objective `a` is at least as good as `b`.
fn no_worse(sense: Sense, a: f64, b: f64) -> bool {
    match sense {
        Sense::Minimize => a <= b,
        Sense::Maximize => a >= b,
    }
}

/// Whether `a = (objective, V)` dominates `b`: no worse in both, strictly better in one
/// (V is always maximised).
pub fn dominates(sense: Sense, a: (f64, f64), b: (f64, f64)) -> bool {
    no_worse(sense, a.0, b.0) && a.1 >= b.1 && (a.0 != b.0 || a.1 != b.1)
}

/// Non-dominated flags of `points` (`None` = not a candidate, never on the front).
pub fn pareto_front(sense: Sense, points: &[Option<(f64, f64)>]) -> Vec<bool> {
    points
        .iter()
        .map(|p| match p {
            Some(b) => !points.iter().flatten().any(|a| dominates(sense, *a, *b)),
            None => false,
        })
        .collect()
}

/// Index of the best candidate `(objective, V)`: the optimal objective; within a relative
/// 1e-12 of it, the highest V (a missing V counts as lowest), then the first index.
pub fn best_index(sense: Sense, candidates: &[Option<(f64, Option<f64>)>]) -> Option<usize> {
    let mut best: Option<(usize, f64, Option<f64>)> = None;
    for (i, c) in candidates.iter().enumerate() {
        let Some((obj, v)) = *c else { continue };
        let replace = match best {
            None => true,
            Some((_, bo, bv)) => {
                let tie = (obj - bo).abs() <= 1e-12 * obj.abs().max(bo.abs());
                if tie {
                    v.unwrap_or(f64::NEG_INFINITY) > bv.unwrap_or(f64::NEG_INFINITY)
                } else {
                    no_worse(sense, obj, bo)
                }
            }
        };
        if replace {
            best = Some((i, obj, v));
        }
    }
    best.map(|b| b.0)
}

fn value(row: &Row, t: &Target) -> Option<f64> {
    match t {
        Target::Result(r) => row.result(*r),
        Target::Axis { key, .. } => row.axis(key),
    }
}

/// A constraint on a result that is only known to exceed `top` (no onset up to the top of the
/// speed range): `at_least` holds when its bound is ≤ `top`; `at_most` never holds (violated
/// when its bound is ≤ `top`, unknown above it: infeasible either way).
fn check_above(name: &str, top: f64, c: &Constraint) -> Option<String> {
    let stable = format!("stable to {} m/s (no onset in range)", fmt_si(top));
    let low = c.at_least.filter(|lo| *lo > top).map(|lo| {
        format!(
            "{name} unknown: {stable}; cannot show ≥ {} m/s (widen the speed range)",
            fmt_si(lo)
        )
    });
    let high = c.at_most.map(|hi| {
        if hi <= top {
            format!(
                "{name} > {} m/s ({stable}) > {} m/s",
                fmt_si(top),
                fmt_si(hi)
            )
        } else {
            format!("{name} unknown: {stable}; cannot show ≤ {} m/s", fmt_si(hi))
        }
    });
    low.or(high)
}

fn check(row: &Row, c: &Constraint) -> Option<String> {
    let (name, unit) = match &c.target {
        Target::Result(r) => (r.name(), "m/s"),
        Target::Axis { key, dim } => (key.as_str(), dim.si_unit()),
    };
    let Some(v) = value(row, &c.target) else {
        if let Target::Result(r) = c.target {
            if let Some(top) = row.above_range(r) {
                return check_above(name, top, c);
            }
        }
        return Some(format!("{name} not available"));
    };
    let low = c.at_least.filter(|lo| v < *lo).map(|lo| ("<", lo));
    let high = c.at_most.filter(|hi| v > *hi).map(|hi| (">", hi));
    low.or(high)
        .map(|(op, b)| format!("{name} {} {unit} {op} {} {unit}", fmt_si(v), fmt_si(b)))
}

/// The results the trade reads: the constrained ones and the Pareto speed.
fn read_results(plan: &TradePlan) -> impl Iterator<Item = ResultKind> + '_ {
    let constrained = plan.constraints.iter().filter_map(|c| match c.target {
        Target::Result(r) => Some(r),
        Target::Axis { .. } => None,
    });
    constrained.chain(std::iter::once(plan.pareto))
}

/// Whether the point failed on a result the trade reads (neither found nor above range). A
/// failure elsewhere does not count: V_NL unknown does not matter to a trade on V_L alone.
pub fn failed_for(plan: &TradePlan, row: &Row) -> bool {
    !row.ok() && read_results(plan).any(|r| row.capped(r).is_none())
}

/// Why `row` is infeasible, or `None` when it is feasible.
pub fn infeasibility(plan: &TradePlan, row: &Row) -> Option<String> {
    if failed_for(plan, row) {
        let s = row.status.trim();
        return Some(if s.starts_with("failed") {
            s.to_string()
        } else {
            format!("failed: {s}")
        });
    }
    let mut why: Vec<String> = Vec::new();
    if row.axis(&plan.objective.key).is_none() {
        why.push(format!("{} not available", plan.objective.key));
    }
    why.extend(plan.constraints.iter().filter_map(|c| check(row, c)));
    (!why.is_empty()).then(|| why.join("; "))
}

/// Assess every row: feasibility with reasons, Pareto front, best design.
pub fn assess(plan: &TradePlan, rows: &[Row]) -> Vec<Assessment> {
    let sense = plan.objective.sense;
    let reasons: Vec<Option<String>> = rows.iter().map(|r| infeasibility(plan, r)).collect();
    let pts: Vec<Option<(f64, f64)>> = rows
        .iter()
        .map(|r| {
            match (
                !failed_for(plan, r),
                r.axis(&plan.objective.key),
                r.capped(plan.pareto),
            ) {
                (true, Some(x), Some(v)) => Some((x, v)),
                _ => None,
            }
        })
        .collect();
    let front = pareto_front(sense, &pts);
    let candidates: Vec<Option<(f64, Option<f64>)>> = rows
        .iter()
        .zip(&reasons)
        .map(|(r, why)| match (why, r.axis(&plan.objective.key)) {
            (None, Some(x)) => Some((x, r.capped(plan.pareto))),
            _ => None,
        })
        .collect();
    let best = best_index(sense, &candidates);
    reasons
        .into_iter()
        .zip(front)
        .enumerate()
        .map(|(i, (why, pareto))| Assessment {
            feasible: why.is_none(),
            reason: why.unwrap_or_default(),
            pareto,
            best: best == Some(i),
        })
        .collect()
}

#[cfg(test)]
#[path = "select_tests.rs"]
mod tests;

#[cfg(test)]
#[path = "above_tests.rs"]
mod above_tests;
