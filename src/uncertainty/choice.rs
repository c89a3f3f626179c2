//! The `choice` distribution's own rules: its weights, and a choice among files for the file
//! keys ([`FILE_KEYS`](crate::sweep::spec::FILE_KEYS)), whose design values are the indices
//! of the files.

use crate::study::schema::{Quantity, UncertainParameterSection};
use crate::study::units::Dimension;

use super::sample::Distribution;
use super::spec::{bad, written, Parameter};
use super::UncertaintyError;

/// The weights of a `choice` of `n` values: given (one per value, finite, not negative, a
/// positive sum) or equal.
pub(super) fn weights(
    at: &dyn Fn(&str) -> String,
    p: &UncertainParameterSection,
    n: usize,
) -> Result<Vec<f64>, UncertaintyError> {
    let weights = p.weights.clone().unwrap_or_else(|| vec![1.0; n]);
    if weights.len() != n {
        return Err(bad(
            at("weights"),
            format!("{} weights", weights.len()),
            format!("needs one weight per value ({n})"),
        ));
    }
    if let Some(w) = weights.iter().find(|w| !(w.is_finite() && **w >= 0.0)) {
        return Err(bad(
            at("weights"),
            w,
            "weights must be finite and not negative",
        ));
    }
    let sum: f64 = weights.iter().sum();
    if sum <= 0.0 {
        return Err(bad(
            at("weights"),
            format!("sum {sum}"),
            "weights must sum to a positive number",
        ));
    }
    Ok(weights)
}

/// A file key ([`FILE_KEYS`](crate::sweep::spec::FILE_KEYS)): only `choice`, its values file
/// paths (strings). The design samples the index of a file (0, 1, …) like any `choice`: a
/// uniform u picks the first file whose cumulative weight exceeds u times the weights' sum.
pub(super) fn file_parameter(
    i: usize,
    p: &UncertainParameterSection,
) -> Result<Parameter, UncertaintyError> {
    let at = |field: &str| format!("uncertainty.parameter[{i}].{field} ({})", p.key);
    if p.distribution != "choice" {
        return Err(bad(
            format!("uncertainty.parameter[{i}].distribution ({})", p.key),
            format!("{:?}", p.distribution),
            "a file key takes only distribution \"choice\" (values: the files, weights)",
        ));
    }
    for (f, set) in [
        ("from", p.from.is_some()),
        ("to", p.to.is_some()),
        ("mean", p.mean.is_some()),
        ("std", p.std.is_some()),
        ("median", p.median.is_some()),
        ("factor", p.factor.is_some()),
    ] {
        if set {
            return Err(bad(
                at(f),
                "(set)",
                "is not a parameter of distribution \"choice\"",
            ));
        }
    }
    let list = p.values.as_deref().unwrap_or_default();
    if list.is_empty() {
        return Err(bad(
            at("values"),
            "[]",
            "distribution \"choice\" needs values",
        ));
    }
    let files = list
        .iter()
        .enumerate()
        .map(|(k, q)| match q {
            Quantity::Text(t) if !t.trim().is_empty() => Ok(t.clone()),
            q => Err(bad(
                at(&format!("values[{k}]")),
                written(q),
                "must be a file path (a string, relative to the study file)",
            )),
        })
        .collect::<Result<Vec<String>, _>>()?;
    if let Some(k) = (1..files.len()).find(|&k| files[..k].contains(&files[k])) {
        return Err(bad(
            at(&format!("values[{k}]")),
            format!("{:?}", files[k]),
            "is listed twice (give it a larger weight instead)",
        ));
    }
    let weights = weights(&at, p, files.len())?;
    Ok(Parameter {
        key: p.key.clone(),
        dim: Dimension::Dimensionless,
        distribution: Distribution::Choice {
            values: (0..files.len()).map(|k| k as f64).collect(),
            weights,
        },
        files,
    })
}
