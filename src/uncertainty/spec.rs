//! The `[uncertainty]` section resolved: parameters with their distributions in SI, the
//! method, the sample count and what to compute. Every rule broken names the key, the value
//! and the rule.

use crate::study::schema::{Quantity, UncertainParameterSection, UncertaintySection};
use crate::study::units::Dimension;
use crate::study::{self};
use crate::sweep::spec::{is_file_key, key_dimension, Axis, Compute, Spacing, FILE_KEYS};
use crate::sweep::SWEEP_KEYS;

use super::sample::{Distribution, Method};
use super::UncertaintyError;

/// Most base samples of "sobol" (the `sobol_burley` sequence's length).
pub const MAX_SOBOL_SAMPLES: usize = 1 << 16;

/// One uncertain parameter.
#[derive(Clone, Debug, PartialEq)]
pub struct Parameter {
    /// dotted study key (a sweepable one)
    pub key: String,
    /// dimension of its values
    pub dim: Dimension,
    /// its distribution, SI; for a file key the values of its `choice` are the indices of
    /// `files` (0, 1, …)
    pub distribution: Distribution,
    /// for a file key (`contact.geometry_table`, `contact.wheel_profile`,
    /// `contact.rail_profile`): the files of its `choice`, as written (relative to the study
    /// file); empty for a numeric key
    pub files: Vec<String>,
}

/// A resolved `[uncertainty]` section.
#[derive(Clone, Debug, PartialEq)]
pub struct UncertaintySpec {
    /// base sample count N
    pub samples: usize,
    /// how the uniforms are drawn
    pub method: Method,
    /// seed of the sample design and of the bootstrap
    pub seed: u32,
    /// results per evaluation
    pub compute: Compute,
    /// whether the Sobol indices are estimated (N (d + 2) evaluations instead of N)
    pub indices: bool,
    /// operating speed (m/s), if given
    pub operating_speed: Option<f64>,
    /// V_NL by the full attractor search (`attractors = true`) instead of the fast form
    pub attractors: bool,
    /// the uncertain parameters, at least one
    pub parameters: Vec<Parameter>,
}

impl UncertaintySpec {
    /// Evaluations of the design: N (d + 2) with indices, N without.
    pub fn evaluations(&self) -> usize {
        if self.indices {
            self.samples * (self.parameters.len() + 2)
        } else {
            self.samples
        }
    }
}

pub(super) fn bad(
    key: impl Into<String>,
    value: impl std::fmt::Display,
    rule: impl Into<String>,
) -> UncertaintyError {
    UncertaintyError::Rule {
        key: key.into(),
        value: value.to_string(),
        rule: rule.into(),
    }
}

/// The text of a quantity as written, for messages.
pub(super) fn written(q: &Quantity) -> String {
    match q {
        Quantity::Number(v) => v.to_string(),
        Quantity::Text(t) => format!("{t:?}"),
    }
}

/// Resolves the section, without the study.
pub fn resolve(s: &UncertaintySection) -> Result<UncertaintySpec, UncertaintyError> {
    let method = match s.method.as_deref() {
        None | Some("sobol") => Method::Sobol,
        Some("random") => Method::Random,
        Some(other) => {
            return Err(bad(
                "uncertainty.method",
                format!("{other:?}"),
                "must be \"sobol\" or \"random\"",
            ))
        }
    };
    if s.samples < 2 {
        return Err(bad("uncertainty.samples", s.samples, "must be at least 2"));
    }
    if method == Method::Sobol && !s.samples.is_power_of_two() {
        return Err(bad(
            "uncertainty.samples",
            s.samples,
            format!(
                "must be a power of two for method \"sobol\" (a Sobol sequence is balanced only in blocks of 2^k points), e.g. {} or {}",
                s.samples.next_power_of_two() / 2,
                s.samples.next_power_of_two()
            ),
        ));
    }
    if method == Method::Sobol && s.samples > MAX_SOBOL_SAMPLES {
        return Err(bad(
            "uncertainty.samples",
            s.samples,
            format!("must be at most {MAX_SOBOL_SAMPLES} for method \"sobol\""),
        ));
    }
    if s.parameter.is_empty() {
        return Err(bad(
            "uncertainty.parameter",
            "[]",
            "needs at least one [[uncertainty.parameter]]",
        ));
    }
    if method == Method::Sobol && 2 * s.parameter.len() > sobol_burley::NUM_DIMENSIONS as usize {
        return Err(bad(
            "uncertainty.parameter",
            s.parameter.len(),
            format!(
                "at most {} parameters for method \"sobol\"",
                sobol_burley::NUM_DIMENSIONS / 2
            ),
        ));
    }
    let mut parameters: Vec<Parameter> = Vec::with_capacity(s.parameter.len());
    for (i, p) in s.parameter.iter().enumerate() {
        let par = parameter(i, p)?;
        if parameters.iter().any(|q| q.key == par.key) {
            return Err(bad(
                format!("uncertainty.parameter[{i}].key"),
                format!("{:?}", par.key),
                "is already an uncertain parameter",
            ));
        }
        parameters.push(par);
    }
    let operating_speed = s
        .operating_speed
        .as_ref()
        .map(|q| study::quantity("uncertainty.operating_speed", q, Dimension::Speed))
        .transpose()
        .map_err(|e| bad("uncertainty.operating_speed", "", e.to_string()))?;
    Ok(UncertaintySpec {
        samples: s.samples,
        method,
        seed: s.seed.unwrap_or(1),
        compute: compute(s.compute.as_deref())?,
        indices: s.indices.unwrap_or(true),
        operating_speed,
        // the full search by default: a probability of hunting must not rest on a V_NL that
        // misses an attractor (the fast form did on 10 of 32 draws of the DTU bogie,
        // docs/uncertainty.md)
        attractors: s.attractors.unwrap_or(true),
        parameters,
    })
}

fn compute(c: Option<&[String]>) -> Result<Compute, UncertaintyError> {
    let mut out = Compute {
        kalker: c.is_none(),
        hopf: false,
        nonlinear: false,
    };
    for (i, name) in c.unwrap_or_default().iter().enumerate() {
        match name.as_str() {
            "kalker" => out.kalker = true,
            "hopf" => out.hopf = true,
            "nonlinear" => out.nonlinear = true,
            other => {
                return Err(bad(
                    format!("uncertainty.compute[{i}]"),
                    format!("{other:?}"),
                    "is not one of \"kalker\", \"hopf\", \"nonlinear\"",
                ))
            }
        }
    }
    if !(out.kalker || out.hopf || out.nonlinear) {
        return Err(bad(
            "uncertainty.compute",
            "[]",
            "must name at least one result",
        ));
    }
    Ok(out)
}

/// One parameter: its key (sweepable), its distribution's values in SI and their rules.
fn parameter(i: usize, p: &UncertainParameterSection) -> Result<Parameter, UncertaintyError> {
    let at = |field: &str| format!("uncertainty.parameter[{i}].{field} ({})", p.key);
    if is_file_key(&p.key) {
        return super::choice::file_parameter(i, p);
    }
    let dim = key_dimension(&p.key).ok_or_else(|| {
        let accepted: Vec<&str> = SWEEP_KEYS.iter().map(|(k, _)| *k).collect();
        bad(
            format!("uncertainty.parameter[{i}].key"),
            format!("{:?}", p.key),
            format!(
                "is not a key that can vary; the numeric keys are: {}; the file keys (distribution \"choice\"): {}",
                accepted.join(", "),
                FILE_KEYS.join(", ")
            ),
        )
    })?;
    let value = |field: &str, q: &Option<Quantity>| -> Result<Option<f64>, UncertaintyError> {
        q.as_ref()
            .map(|q| {
                // a conicity's values lie in (0, 1) and may be written as ratios; its standard
                // deviation is a plain number, checked below by the distribution's own rule
                let v = if p.key == "contact.conicity" && field != "std" {
                    study::conicity(q)
                } else {
                    study::quantity(&p.key, q, dim)
                };
                v.map_err(|e| bad(at(field), written(q), e.to_string()))
            })
            .transpose()
    };
    let need = |field: &str, v: Option<f64>| {
        v.ok_or_else(|| {
            bad(
                at(field),
                "(missing)",
                format!("distribution {:?} needs {field}", p.distribution),
            )
        })
    };
    let unused = |fields: &[(&str, bool)]| -> Result<(), UncertaintyError> {
        match fields.iter().find(|(_, set)| *set) {
            Some((f, _)) => Err(bad(
                at(f),
                "(set)",
                format!("is not a parameter of distribution {:?}", p.distribution),
            )),
            None => Ok(()),
        }
    };
    let unit = dim.si_unit();
    let distribution = match p.distribution.as_str() {
        "uniform" => {
            unused(&[
                ("mean", p.mean.is_some()),
                ("std", p.std.is_some()),
                ("median", p.median.is_some()),
                ("factor", p.factor.is_some()),
                ("values", p.values.is_some()),
                ("weights", p.weights.is_some()),
            ])?;
            let from = need("from", value("from", &p.from)?)?;
            let to = need("to", value("to", &p.to)?)?;
            if from >= to {
                return Err(bad(
                    at("from"),
                    format!("{from} {unit} (to = {to} {unit})"),
                    "from must be below to",
                ));
            }
            Distribution::Uniform { from, to }
        }
        "normal" => {
            unused(&[
                ("median", p.median.is_some()),
                ("factor", p.factor.is_some()),
                ("values", p.values.is_some()),
                ("weights", p.weights.is_some()),
            ])?;
            let mean = need("mean", value("mean", &p.mean)?)?;
            let std = need("std", value("std", &p.std)?)?;
            if std <= 0.0 {
                return Err(bad(at("std"), format!("{std} {unit}"), "must be positive"));
            }
            let from = value("from", &p.from)?.unwrap_or(f64::NEG_INFINITY);
            let to = value("to", &p.to)?.unwrap_or(f64::INFINITY);
            if from >= to {
                return Err(bad(
                    at("from"),
                    format!("{from} {unit} (to = {to} {unit})"),
                    "from must be below to",
                ));
            }
            // a truncation far in a tail leaves no probability to sample from
            let (lo, hi) = (
                super::sample::normal_cdf((from - mean) / std),
                super::sample::normal_cdf((to - mean) / std),
            );
            if hi - lo < 1e-6 {
                return Err(bad(
                    at("from"),
                    format!("{from} .. {to} {unit}"),
                    "the truncation keeps less than 1e-6 of the normal's probability",
                ));
            }
            Distribution::Normal {
                mean,
                std,
                from,
                to,
            }
        }
        "lognormal" => {
            unused(&[
                ("from", p.from.is_some()),
                ("to", p.to.is_some()),
                ("mean", p.mean.is_some()),
                ("std", p.std.is_some()),
                ("values", p.values.is_some()),
                ("weights", p.weights.is_some()),
            ])?;
            let median = need("median", value("median", &p.median)?)?;
            if median <= 0.0 {
                return Err(bad(
                    at("median"),
                    format!("{median} {unit}"),
                    "must be positive",
                ));
            }
            let factor = need("factor", p.factor)?;
            if !(factor.is_finite() && factor > 1.0) {
                return Err(bad(
                    at("factor"),
                    factor,
                    "must be a number above 1 (exp σ)",
                ));
            }
            Distribution::Lognormal { median, factor }
        }
        "choice" => {
            unused(&[
                ("from", p.from.is_some()),
                ("to", p.to.is_some()),
                ("mean", p.mean.is_some()),
                ("std", p.std.is_some()),
                ("median", p.median.is_some()),
                ("factor", p.factor.is_some()),
            ])?;
            let list = p.values.as_deref().unwrap_or_default();
            if list.is_empty() {
                return Err(bad(
                    at("values"),
                    "[]",
                    "distribution \"choice\" needs values",
                ));
            }
            let values = list
                .iter()
                .enumerate()
                .map(|(k, q)| {
                    value(&format!("values[{k}]"), &Some(q.clone())).map(|v| v.unwrap_or(f64::NAN))
                })
                .collect::<Result<Vec<f64>, _>>()?;
            let weights = super::choice::weights(&at, p, values.len())?;
            Distribution::Choice { values, weights }
        }
        other => {
            return Err(bad(
                format!("uncertainty.parameter[{i}].distribution ({})", p.key),
                format!("{other:?}"),
                "is not one of \"uniform\", \"normal\", \"lognormal\", \"choice\"",
            ))
        }
    };
    Ok(Parameter {
        key: p.key.clone(),
        dim,
        distribution,
        files: Vec::new(),
    })
}

/// The sweep axes standing for the parameters: each with the smallest and largest value of its
/// column of `design` (checked, each alone, to give a valid study).
pub fn axes(spec: &UncertaintySpec, design: &[Vec<f64>]) -> Vec<Axis> {
    spec.parameters
        .iter()
        .enumerate()
        .map(|(k, p)| {
            if !p.files.is_empty() {
                // every file of the choice is checked, and the values index them
                return Axis {
                    key: p.key.clone(),
                    dim: p.dim,
                    spacing: Spacing::Linear,
                    values: (0..p.files.len()).map(|f| f as f64).collect(),
                    files: p.files.clone(),
                };
            }
            let lo = design.iter().map(|r| r[k]).fold(f64::INFINITY, f64::min);
            let hi = design
                .iter()
                .map(|r| r[k])
                .fold(f64::NEG_INFINITY, f64::max);
            Axis {
                key: p.key.clone(),
                dim: p.dim,
                spacing: Spacing::Linear,
                values: vec![lo, hi],
                files: Vec::new(),
            }
        })
        .collect()
}
