//! The `[curve]` section resolved: the key and its range in SI, what to continue, and the
//! continuation's limits, each checked once with an error naming key, value and rule.

use crate::study::schema::{CurveSection, Quantity};
use crate::study::units::Dimension;
use crate::study::{self, Plan};
use crate::sweep::spec::{key_dimension, SWEEP_KEYS};

use super::keyed::KeyedStudy;
use super::{CurveError, CurveKind};

/// The fold curves' integrator tolerance unless `curve.rtol` says otherwise.
pub const DEFAULT_RTOL: f64 = 1e-8;

/// A resolved `[curve]` section.
#[derive(Clone, Debug, PartialEq)]
pub struct CurveSpec {
    /// the design key (a sweepable study key)
    pub key: String,
    /// its dimension
    pub dimension: Dimension,
    /// `from` and `to` (SI), as written (`from` may exceed `to`)
    pub range: (f64, f64),
    /// continue and draw in $\ln p$ (`spacing = "log"`)
    pub log: bool,
    /// what to continue, each once, in [`CurveKind::ALL`] order; default Hopf and Fold
    pub curves: Vec<CurveKind>,
    /// speeds the curves may visit (m/s); default the study's linear range
    pub speed_range: (f64, f64),
    /// most points on each side of a curve's start; default 400
    pub max_points: usize,
    /// largest step as a fraction of the plot box's diagonal (speed range × key range, each
    /// scaled to 1); default 0.02, so that a curve across the box has at least 50 points
    pub max_step: f64,
    /// key values, evenly spread over the range (in $\ln p$ when log), where the Hopf
    /// crossings are searched that curves start from; default 5 (both ends and three
    /// between: a curve that enters and leaves the box between two of them is missed)
    pub seed_points: usize,
    /// key values at which the folds of cycles are located, ends included
    pub fold_points: usize,
    /// the integrator's relative tolerance for the fold curves and the diagrams they start
    /// from; default 1e-8 (the bogie's V_NL curve moves by at most 3e-9 relative from 1e-10,
    /// at less than half the cost: docs/curves.md)
    pub rtol: f64,
    /// run the attractor search (`critspeed attractors`, the study's `[attractors]` section
    /// or its defaults) on the study rewritten at every V_NL value; default false
    pub attractors: bool,
}

impl CurveSpec {
    /// `key = value unit` for messages (e.g. `secondary.yaw_damping = 109.091 N s/mm`).
    pub fn show(&self, value: f64) -> String {
        show(&self.key, self.dimension, value)
    }

    /// `value unit`, the value in the key's display unit to 6 significant digits.
    pub fn quantity(&self, value: f64) -> String {
        quantity(self.dimension, value)
    }
}

/// `key = value unit`, as [`CurveSpec::show`] (the curve report's notes use it).
pub fn show(key: &str, dimension: Dimension, value: f64) -> String {
    format!("{key} = {}", quantity(dimension, value))
}

/// `value unit`, the value in the dimension's display unit to 6 significant digits.
pub fn quantity(dimension: Dimension, value: f64) -> String {
    let (unit, factor) = crate::study::units::display_unit(dimension);
    let v = value * factor;
    let digits = if v == 0.0 || !v.is_finite() {
        0
    } else {
        (5 - v.abs().log10().floor() as i32).clamp(0, 12) as usize
    };
    let text = if v != 0.0 && (v.abs() >= 1e7 || v.abs() < 1e-4) {
        format!("{v:.5e}")
    } else {
        format!("{v:.digits$}")
    };
    let unit = match unit {
        "-" | "" => String::new(),
        u => format!(" {u}"),
    };
    format!("{text}{unit}")
}

fn rule(key: &str, value: impl ToString, rule: impl ToString) -> CurveError {
    CurveError::Spec {
        key: key.to_string(),
        value: value.to_string(),
        rule: rule.to_string(),
    }
}

fn value(name: &str, key: &str, q: &Quantity, dim: Dimension) -> Result<f64, CurveError> {
    if key == "contact.conicity" {
        if let Quantity::Text(t) = q {
            if t.contains([':', '/']) {
                return study::conicity(q).map_err(CurveError::Study);
            }
        }
    }
    study::quantity(name, q, dim).map_err(CurveError::Study)
}

fn names(list: Option<&[String]>) -> Result<Vec<CurveKind>, CurveError> {
    let Some(list) = list else {
        return Ok(vec![CurveKind::Hopf, CurveKind::Fold]);
    };
    let accepted: Vec<String> = CurveKind::ALL
        .iter()
        .map(|k| format!("{:?}", k.name()))
        .collect();
    let mut out = Vec::new();
    for (i, n) in list.iter().enumerate() {
        let k = CurveKind::from_name(n).ok_or_else(|| {
            rule(
                &format!("curve.curves[{i}]"),
                format!("{n:?}"),
                format!("is not one of {}", accepted.join(", ")),
            )
        })?;
        out.push(k);
    }
    if out.is_empty() {
        return Err(rule("curve.curves", "[]", "must name at least one curve"));
    }
    out.sort();
    out.dedup();
    Ok(out)
}

fn bounded(
    key: &str,
    v: Option<usize>,
    default: usize,
    lo: usize,
    hi: usize,
) -> Result<usize, CurveError> {
    let n = v.unwrap_or(default);
    if (lo..=hi).contains(&n) {
        Ok(n)
    } else {
        Err(rule(key, n, format!("must lie in [{lo}, {hi}]")))
    }
}

/// Resolves `s` against the study: the key must be sweepable, `from` and `to` must differ and
/// each give a valid study (so the range lies inside the key's physical bounds), the log
/// axis needs positive ends.
pub fn resolve(s: &CurveSection, study: &KeyedStudy) -> Result<CurveSpec, CurveError> {
    let dim = key_dimension(&s.key).ok_or_else(|| {
        let accepted: Vec<&str> = SWEEP_KEYS.iter().map(|(k, _)| *k).collect();
        rule(
            "curve.key",
            format!("{:?}", s.key),
            format!(
                "is not a sweepable study key; accepted: {}",
                accepted.join(", ")
            ),
        )
    })?;
    let from = value("curve.from", &s.key, &s.from, dim)?;
    let to = value("curve.to", &s.key, &s.to, dim)?;
    let unit = dim.si_unit();
    if from == to {
        return Err(rule(
            "curve.to",
            format!("{to} {unit}"),
            format!("must differ from curve.from = {from} {unit}: a curve needs a range"),
        ));
    }
    let log = match s.spacing.as_deref().unwrap_or("linear") {
        "linear" | "lin" => false,
        "log" => true,
        other => {
            return Err(rule(
                "curve.spacing",
                format!("{other:?}"),
                "is not one of \"linear\", \"log\"",
            ))
        }
    };
    if log && !(from > 0.0 && to > 0.0) {
        return Err(rule(
            "curve.spacing",
            "\"log\"",
            format!("needs positive from and to (from = {from}, to = {to} {unit})"),
        ));
    }
    for (name, v) in [("curve.from", from), ("curve.to", to)] {
        study.plan_at(v).map_err(|e| {
            rule(
                &format!("{name} ({})", s.key),
                format!("{v} {unit}"),
                format!("gives an invalid study: {e}"),
            )
        })?;
    }
    Ok(CurveSpec {
        key: s.key.clone(),
        dimension: dim,
        range: (from, to),
        log,
        curves: names(s.curves.as_deref())?,
        speed_range: speed_range(s, &study.base)?,
        max_points: bounded("curve.max_points", s.max_points, 400, 2, 100_000)?,
        max_step: match s.max_step {
            None => 0.02,
            Some(d) if d > 0.0 && d <= 0.5 => d,
            Some(d) => return Err(rule("curve.max_step", d, "must lie in (0, 0.5]")),
        },
        seed_points: bounded("curve.seed_points", s.seed_points, 5, 2, 1000)?,
        fold_points: bounded("curve.fold_points", s.fold_points, 12, 2, 1000)?,
        rtol: match s.rtol {
            None => DEFAULT_RTOL,
            Some(r) if (1e-12..=1e-6).contains(&r) => r,
            Some(r) => return Err(rule("curve.rtol", r, "must lie in [1e-12, 1e-6]")),
        },
        attractors: s.attractors.unwrap_or(false),
    })
}

fn speed_range(s: &CurveSection, plan: &Plan) -> Result<(f64, f64), CurveError> {
    let Some([lo, hi]) = &s.speed_range else {
        return Ok(plan.linear.speed_range);
    };
    let lo =
        study::quantity("curve.speed_range[0]", lo, Dimension::Speed).map_err(CurveError::Study)?;
    let hi =
        study::quantity("curve.speed_range[1]", hi, Dimension::Speed).map_err(CurveError::Study)?;
    if !(lo > 0.0 && hi > lo) {
        return Err(rule(
            "curve.speed_range",
            format!("[{lo}, {hi}] m/s"),
            "must satisfy 0 < min < max",
        ));
    }
    Ok((lo, hi))
}
