//! The `[trade]` table of a study file → [`TradePlan`] (SI units, checked once).
//!
//! ```toml
//! [trade]
//! minimize = "suspension.longitudinal_stiffness"   # or maximize = "..."
//! pareto = "nonlinear_critical_speed"              # optional; default: first constrained result
//! constraints = [
//!   { result = "nonlinear_critical_speed", at_least = "200 km/h", factor = 1.1 },
//!   { axis = "suspension.lateral_damping", at_most = "10 N s/mm" },
//! ]
//! ```
//! A constraint names exactly one `result` (`kalker_critical_speed`, `hopf_speed`,
//! `nonlinear_critical_speed`; bounds are speeds) or one swept `axis` key (bounds in that key's
//! units), and at least one of `at_least` / `at_most` (a number in SI or a string with a unit).
//! The optional `factor` (> 0, default 1) multiplies both bounds: "1.1 × the line speed".
//! `method = "grid"` (default: over the sweep's points) or `"curve"` (on curves over a
//! one-axis sweep's key, [`super::curve`]).

use toml::{Table, Value};

use super::{axis_dimension, Constraint, Method, Objective, ResultKind, Sense, Target, TradePlan};
use crate::study::units::{parse_quantity, Dimension};
use crate::study::StudyError;

/// The keys of a `[trade]` table and of one of its `constraints` (listed beside the schema,
/// in [`crate::study::keys`], which names every study key).
pub use crate::study::keys::{CONSTRAINT_KEYS, TRADE_KEYS};

const RESULTS: &str = "kalker_critical_speed, hopf_speed, nonlinear_critical_speed";
const AXES: &str =
    "a swept key such as suspension.longitudinal_stiffness (see docs/sweeps.md, \"Trade studies\")";

fn rule(key: &str, value: impl std::fmt::Display, rule: &str) -> StudyError {
    StudyError::Rule {
        key: key.to_string(),
        value: value.to_string(),
        rule: rule.to_string(),
    }
}

fn unknown_keys(t: &Table, key: &str, allowed: &[&str]) -> Result<(), StudyError> {
    match t.keys().find(|k| !allowed.contains(&k.as_str())) {
        Some(k) => Err(rule(
            &format!("{key}.{k}"),
            &t[k],
            &format!("unknown key; allowed: {}", allowed.join(", ")),
        )),
        None => Ok(()),
    }
}

fn string<'a>(t: &'a Table, key: &str, full: &str) -> Result<Option<&'a str>, StudyError> {
    match t.get(key) {
        None => Ok(None),
        Some(Value::String(s)) => Ok(Some(s)),
        Some(v) => Err(rule(full, v, "must be a string")),
    }
}

/// A quantity: a number (SI) or a string with a unit.
fn quantity(v: &Value, key: &str, dim: Dimension) -> Result<f64, StudyError> {
    let x = match v {
        Value::Integer(i) => *i as f64,
        Value::Float(f) => *f,
        Value::String(s) => parse_quantity(s, dim).map_err(|problem| StudyError::Unit {
            key: key.to_string(),
            value: s.clone(),
            dim,
            problem,
        })?,
        other => {
            return Err(rule(
                key,
                other,
                "must be a number (SI) or a string with a unit",
            ))
        }
    };
    if x.is_finite() {
        Ok(x)
    } else {
        Err(rule(key, x, "must be finite"))
    }
}

fn axis_key(key: &str, full: &str) -> Result<Dimension, StudyError> {
    axis_dimension(key).ok_or_else(|| StudyError::Choice {
        key: full.to_string(),
        value: key.to_string(),
        allowed: AXES,
    })
}

fn objective(t: &Table) -> Result<Objective, StudyError> {
    let min = string(t, "minimize", "trade.minimize")?;
    let max = string(t, "maximize", "trade.maximize")?;
    let (key, sense, full) = match (min, max) {
        (Some(k), None) => (k, Sense::Minimize, "trade.minimize"),
        (None, Some(k)) => (k, Sense::Maximize, "trade.maximize"),
        (Some(a), Some(b)) => {
            let both = format!("{a:?} and {b:?}");
            return Err(rule(
                "trade.minimize/maximize",
                both,
                "give exactly one of them",
            ));
        }
        (None, None) => {
            return Err(StudyError::Missing {
                key: "trade.minimize".into(),
                why: "a trade needs an objective: minimize = \"<key>\" or maximize = \"<key>\""
                    .into(),
            })
        }
    };
    let dim = axis_key(key, full)?;
    Ok(Objective {
        key: key.to_string(),
        sense,
        dim,
    })
}

fn target(t: &Table, key: &str) -> Result<(Target, Dimension), StudyError> {
    let result = string(t, "result", &format!("{key}.result"))?;
    let axis = string(t, "axis", &format!("{key}.axis"))?;
    match (result, axis) {
        (Some(r), None) => {
            let kind = ResultKind::from_name(r).ok_or_else(|| StudyError::Choice {
                key: format!("{key}.result"),
                value: r.to_string(),
                allowed: RESULTS,
            })?;
            Ok((Target::Result(kind), Dimension::Speed))
        }
        (None, Some(a)) => {
            let dim = axis_key(a, &format!("{key}.axis"))?;
            let key = a.to_string();
            Ok((Target::Axis { key, dim }, dim))
        }
        _ => Err(rule(
            key,
            Value::Table(t.clone()),
            "give exactly one of result = \"...\" or axis = \"...\"",
        )),
    }
}

fn constraint(v: &Value, key: &str) -> Result<Constraint, StudyError> {
    let t = v
        .as_table()
        .ok_or_else(|| rule(key, v, "must be a table { result = ..., at_least = ... }"))?;
    unknown_keys(t, key, CONSTRAINT_KEYS)?;
    let (target, dim) = target(t, key)?;
    let factor = match t.get("factor") {
        None => 1.0,
        Some(f) => quantity(f, &format!("{key}.factor"), Dimension::Dimensionless)?,
    };
    if factor <= 0.0 {
        return Err(rule(&format!("{key}.factor"), factor, "must be > 0"));
    }
    let bound = |name: &str| -> Result<Option<(f64, String)>, StudyError> {
        let Some(v) = t.get(name) else {
            return Ok(None);
        };
        let si = factor * quantity(v, &format!("{key}.{name}"), dim)?;
        let written = match v {
            Value::String(s) => s.clone(),
            other => format!("{other} {}", dim.si_unit()),
        };
        let shown = if factor == 1.0 {
            written
        } else {
            format!("{factor} × {written}")
        };
        Ok(Some((
            si,
            format!("{shown} = {} {}", fmt_si(si), dim.si_unit()),
        )))
    };
    let (lo, hi) = (bound("at_least")?, bound("at_most")?);
    if lo.is_none() && hi.is_none() {
        return Err(StudyError::Missing {
            key: format!("{key}.at_least"),
            why: "a constraint needs at_least and/or at_most".into(),
        });
    }
    if let (Some((a, _)), Some((b, _))) = (&lo, &hi) {
        if a > b {
            return Err(rule(
                key,
                format!("at_least {a} > at_most {b}"),
                "the range is empty",
            ));
        }
    }
    let name = match &target {
        Target::Result(r) => r.name().to_string(),
        Target::Axis { key, .. } => key.clone(),
    };
    let text = [
        lo.as_ref().map(|(_, s)| format!("{name} ≥ {s}")),
        hi.as_ref().map(|(_, s)| format!("{name} ≤ {s}")),
    ]
    .into_iter()
    .flatten()
    .collect::<Vec<_>>()
    .join(" and ");
    Ok(Constraint {
        target,
        at_least: lo.map(|b| b.0),
        at_most: hi.map(|b| b.0),
        text,
    })
}

/// Four significant digits, no trailing zeros.
pub(crate) fn fmt_si(v: f64) -> String {
    let a = v.abs();
    if a == 0.0 || (1e-3..1e6).contains(&a) {
        let d = (3 - a.max(1e-300).log10().floor() as i32).clamp(0, 8) as usize;
        let s = format!("{v:.d$}");
        if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            s
        }
    } else {
        format!("{v:.4e}")
    }
}

/// Validate a `[trade]` table into a plan. Errors name the key (`trade.constraints[0].at_least`),
/// the value and the rule.
pub fn trade_plan(t: &Table) -> Result<TradePlan, StudyError> {
    unknown_keys(t, "trade", TRADE_KEYS)?;
    let objective = objective(t)?;
    let constraints = match t.get("constraints") {
        None => Vec::new(),
        Some(Value::Array(a)) => a
            .iter()
            .enumerate()
            .map(|(i, v)| constraint(v, &format!("trade.constraints[{i}]")))
            .collect::<Result<Vec<_>, _>>()?,
        Some(v) => return Err(rule("trade.constraints", v, "must be an array of tables")),
    };
    let first_result = constraints.iter().find_map(|c| match c.target {
        Target::Result(r) => Some(r),
        Target::Axis { .. } => None,
    });
    let pareto = match string(t, "pareto", "trade.pareto")? {
        Some(p) => ResultKind::from_name(p).ok_or_else(|| StudyError::Choice {
            key: "trade.pareto".into(),
            value: p.to_string(),
            allowed: RESULTS,
        })?,
        None => first_result.unwrap_or(ResultKind::NonlinearCriticalSpeed),
    };
    let method = match string(t, "method", "trade.method")? {
        None | Some("grid") => Method::Grid,
        Some("curve") => Method::Curve,
        Some(other) => {
            return Err(StudyError::Choice {
                key: "trade.method".into(),
                value: other.to_string(),
                allowed: "\"grid\" (the sweep's points, the default), \"curve\" (a one-axis sweep's key on curves)",
            })
        }
    };
    Ok(TradePlan {
        objective,
        constraints,
        pareto,
        method,
    })
}

#[cfg(test)]
#[path = "plan_tests.rs"]
mod tests;
