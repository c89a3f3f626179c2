//! The finished evaluations as results: per computed speed its statistics, failures,
//! censored (above range) count and Sobol indices (`uncertainty.json`), and one CSV row per
//! evaluation (`uncertainty.csv`).

use std::collections::BTreeMap;
use std::fmt::Write as _;

use serde::Serialize;

use crate::sweep::{Computed, Outcome, PointRecord};

use super::estimate::{self, Saltelli, QUANTILES, RESAMPLES};
use super::{UncertaintySpec, UncertaintyStudy};

/// The CSV columns of the speeds, in [`Computed::ALL`] order (empty where not computed,
/// failed or above range).
pub const SPEED_COLUMNS: [&str; 3] = [
    "kalker_critical_speed_m_s",
    "hopf_speed_m_s",
    "nonlinear_critical_speed_m_s",
];

/// One parameter's indices for one speed.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct IndexReport {
    /// the parameter's study key
    pub key: String,
    /// first-order Sobol index S_i
    pub first_order: f64,
    /// its 95 % bootstrap interval [low, high]
    pub first_order_ci: [f64; 2],
    /// total Sobol index S_T,i
    pub total: f64,
    /// its 95 % bootstrap interval [low, high]
    pub total_ci: [f64; 2],
}

/// A failed evaluation, named.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct FailureReport {
    /// evaluation id (row of `uncertainty.csv`)
    pub evaluation: usize,
    /// why
    pub reason: String,
}

/// The results for one computed speed.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct QuantityReport {
    /// "kalker", "hopf" or "nonlinear"
    pub name: String,
    /// mean of the speed (m/s) over the evaluations of A and B (A alone without indices)
    pub mean_m_s: Option<f64>,
    /// standard deviation (n − 1) over the same evaluations (m/s)
    pub std_m_s: Option<f64>,
    /// quantiles "0.05", "0.5", "0.95" (m/s; type 7)
    pub quantiles_m_s: BTreeMap<String, f64>,
    /// evaluations (of all blocks) where this speed failed or was not computed
    pub failed: usize,
    /// the failed evaluations and why (the first 50)
    pub failures: Vec<FailureReport>,
    /// evaluations (of all blocks) with no onset up to the top of the speed range
    pub above_range: usize,
    /// the fraction of the statistics' evaluations whose speed lies below the operating speed
    #[serde(skip_serializing_if = "Option::is_none")]
    pub probability_below_operating_speed: Option<f64>,
    /// first-order and total indices per parameter (empty without indices)
    pub indices: Vec<IndexReport>,
    /// how failures and above-range results were handled
    pub notes: Vec<String>,
    /// the speeds the statistics are computed on (m/s; above-range ones censored), in
    /// evaluation order; not written to the JSON (uncertainty.csv holds them)
    #[serde(skip)]
    pub values_m_s: Vec<f64>,
}

/// A parameter as reported.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ParameterReport {
    /// study key
    pub key: String,
    /// distribution name
    pub distribution: String,
    /// its values' SI unit
    pub unit: String,
    /// for a choice among files: the files, in the order their indices count (not written
    /// for a numeric parameter)
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub files: Vec<String>,
}

/// `uncertainty.json`.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct UncertaintyReport {
    /// the study's name
    pub study: String,
    /// evaluations run
    pub samples: usize,
    /// the base sample count N
    pub base_samples: usize,
    /// "sobol" or "random"
    pub method: String,
    /// seed of the design and the bootstrap
    pub seed: u32,
    /// the operating speed (m/s), when set
    #[serde(skip_serializing_if = "Option::is_none")]
    pub operating_speed_m_s: Option<f64>,
    /// how V_NL was found, when computed: by the full attractor search (`true`, `attractors =
    /// true`) or by the fast form (`false`); in the JSON `nonlinear_method`, "search" or
    /// "descents" ([`crate::sweep::nonlinear_method`])
    #[serde(
        rename = "nonlinear_method",
        skip_serializing_if = "Option::is_none",
        serialize_with = "method_name"
    )]
    pub nonlinear_by_search: Option<bool>,
    /// the uncertain parameters
    pub parameters: Vec<ParameterReport>,
    /// one entry per computed speed
    pub quantities: Vec<QuantityReport>,
}

/// `nonlinear_method`'s name in the JSON (only called when set).
fn method_name<S: serde::Serializer>(search: &Option<bool>, s: S) -> Result<S::Ok, S::Error> {
    s.serialize_str(crate::sweep::nonlinear_method(search.unwrap_or(false)).0)
}

/// One evaluation's value of one speed.
#[derive(Clone, Debug, PartialEq)]
pub enum Value {
    /// the speed (m/s)
    Found(f64),
    /// no onset up to this top of the speed range (m/s)
    Censored(f64),
    /// failed or not computed, and why
    Failed(String),
}

fn value(rec: Option<&PointRecord>, which: Computed) -> Value {
    let Some(rec) = rec else {
        return Value::Failed("not evaluated (missing from the records)".into());
    };
    match rec.outcome(which) {
        Outcome::Found { speed_m_s, .. } => Value::Found(speed_m_s),
        Outcome::AboveRange { stable_up_to_m_s } => Value::Censored(stable_up_to_m_s),
        Outcome::NoHopf => {
            Value::Failed("no Hopf point in the speed range: V_NL not computed".into())
        }
        Outcome::Missing => Value::Failed(if rec.failures.is_empty() {
            "not computed".into()
        } else {
            rec.failures.join("; ")
        }),
    }
}

fn computed(study: &UncertaintyStudy) -> Vec<Computed> {
    let c = study.spec.compute;
    Computed::ALL
        .into_iter()
        .filter(|w| match w {
            Computed::Kalker => c.kalker,
            Computed::Hopf => c.hopf,
            Computed::Nonlinear => c.nonlinear,
        })
        .collect()
}

/// The report of the finished evaluations `rows` (any order; missing ones count as failed).
pub fn report(study: &UncertaintyStudy, rows: &[PointRecord]) -> UncertaintyReport {
    let total = study.len();
    let mut by_id: Vec<Option<&PointRecord>> = vec![None; total];
    for r in rows {
        if let Some(slot) = by_id.get_mut(r.id) {
            *slot = Some(r);
        }
    }
    let spec = &study.spec;
    UncertaintyReport {
        study: study.sweep.base.name.clone(),
        samples: rows.len(),
        base_samples: spec.samples,
        method: spec.method.name().into(),
        seed: spec.seed,
        operating_speed_m_s: spec.operating_speed,
        nonlinear_by_search: spec.compute.nonlinear.then_some(spec.attractors),
        parameters: spec
            .parameters
            .iter()
            .map(|p| ParameterReport {
                key: p.key.clone(),
                distribution: p.distribution.name().into(),
                unit: p.dim.si_unit().into(),
                files: p.files.clone(),
            })
            .collect(),
        quantities: computed(study)
            .into_iter()
            .map(|w| {
                let values: Vec<Value> = by_id.iter().map(|r| value(*r, w)).collect();
                let mut q = quantity(spec, w.name(), &values);
                if w == Computed::Nonlinear {
                    q.notes.extend(unlocated_note(&by_id));
                }
                q
            })
            .collect(),
    }
}

/// A note counting the evaluations whose V_NL is not a located point (`nonlinear_located =
/// false`): the lowest stable cycle computed, or an attractor whose death bracket the search
/// left open. Hunting may exist below such a V_NL, so it is an upper bound.
fn unlocated_note(by_id: &[Option<&PointRecord>]) -> Option<String> {
    let mut found = 0;
    let mut unlocated = Vec::new();
    for r in by_id.iter().flatten().filter(|r| r.nonlinear_m_s.is_some()) {
        found += 1;
        if r.nonlinear_located == Some(false) {
            unlocated.push(r.id);
        }
    }
    (!unlocated.is_empty()).then(|| {
        let ids: Vec<String> = unlocated.iter().take(20).map(usize::to_string).collect();
        format!(
            "{} of the {found} evaluations with a V_NL have it unlocated (evaluations {}{}): the lowest stable cycle computed, or an attractor whose death bracket is open (no verdict below it). Hunting may exist lower there, so their V_NL is an upper bound, the statistics and quantiles of V_NL may lie too high and the probability below the operating speed too low; `critspeed attractors` of such an evaluation's parameters says why",
            unlocated.len(),
            ids.join(", "),
            if unlocated.len() > 20 { ", …" } else { "" }
        )
    })
}

/// The report of one speed named `name` from its values at every evaluation of `spec`'s design
/// (indexed by evaluation id, block-major as in [`super::sample`]).
pub fn quantity(spec: &UncertaintySpec, name: &str, values: &[Value]) -> QuantityReport {
    let n = spec.samples;
    let number = |v: &Value| match v {
        Value::Found(x) | Value::Censored(x) => Some(*x),
        Value::Failed(_) => None,
    };
    // statistics over A and B (independent samples of the inputs; A_B rows repeat their parts)
    let stat_rows = if spec.indices { 2 * n } else { n };
    let stat: Vec<f64> = values[..stat_rows.min(values.len())]
        .iter()
        .filter_map(number)
        .collect();
    let summary = estimate::summary(&stat);
    let mut failures = Vec::new();
    let (mut failed, mut above, mut top) = (0, 0, f64::NAN);
    for (id, v) in values.iter().enumerate() {
        match v {
            Value::Failed(why) => {
                failed += 1;
                if failures.len() < 50 {
                    failures.push(FailureReport {
                        evaluation: id,
                        reason: why.clone(),
                    });
                }
            }
            Value::Censored(v) => {
                above += 1;
                top = *v;
            }
            Value::Found(_) => {}
        }
    }
    let mut notes = Vec::new();
    let stat_failed = stat_rows.min(values.len()) - stat.len();
    notes.push(format!(
        "statistics over the {} evaluations of {} that did not fail ({stat_failed} failed and are left out)",
        stat.len(),
        if spec.indices { "blocks A and B" } else { "block A" }
    ));
    if failed > 0 {
        notes.push(format!(
            "{failed} evaluations failed (listed in failures, the first 50); a base row with a failure in any of its blocks is left out of the indices"
        ));
    }
    if above > 0 {
        notes.push(format!(
            "{above} evaluations had no onset up to the top of the speed range ({top} m/s): they enter the statistics and indices censored at that speed, so the mean and the quantiles are lower bounds of the true ones (a quantile below {top} m/s is exact), the probability below the operating speed is exact when the operating speed is at most {top} m/s and an upper bound otherwise, and the indices are those of min(speed, {top} m/s); widen [linear] speed_range to remove the censoring"
        ));
    }
    let probability_below_operating_speed = spec.operating_speed.and_then(|op| {
        (!stat.is_empty())
            .then(|| stat.iter().filter(|v| **v < op).count() as f64 / stat.len() as f64)
    });
    let indices = if spec.indices {
        indices(spec, values, number, &mut notes)
    } else {
        Vec::new()
    };
    QuantityReport {
        name: name.into(),
        mean_m_s: summary.as_ref().map(|s| s.mean),
        std_m_s: summary.as_ref().map(|s| s.std),
        quantiles_m_s: summary
            .map(|s| {
                QUANTILES
                    .iter()
                    .zip(s.quantiles)
                    .map(|(p, q)| (p.to_string(), q))
                    .collect()
            })
            .unwrap_or_default(),
        failed,
        failures,
        above_range: above,
        probability_below_operating_speed,
        indices,
        notes,
        values_m_s: stat,
    }
}

/// The indices over the base rows whose every block has a number.
fn indices(
    spec: &UncertaintySpec,
    values: &[Value],
    number: impl Fn(&Value) -> Option<f64>,
    notes: &mut Vec<String>,
) -> Vec<IndexReport> {
    let (n, d) = (spec.samples, spec.parameters.len());
    let mut s = Saltelli {
        a: Vec::new(),
        b: Vec::new(),
        ab: vec![Vec::new(); d],
    };
    let mut dropped = 0;
    for j in 0..n {
        let row: Option<Vec<f64>> = (0..d + 2)
            .map(|k| values.get(k * n + j).and_then(&number))
            .collect();
        let Some(row) = row else {
            dropped += 1;
            continue;
        };
        s.a.push(row[0]);
        s.b.push(row[1]);
        for (i, ab) in s.ab.iter_mut().enumerate() {
            ab.push(row[2 + i]);
        }
    }
    if dropped > 0 {
        notes.push(format!(
            "indices over {} of {n} base rows: {dropped} rows with a failed evaluation in A, B or some A_B^(i) are left out",
            n - dropped
        ));
    }
    match estimate::indices(&s, RESAMPLES, u64::from(spec.seed)) {
        Some(ix) => spec
            .parameters
            .iter()
            .zip(ix)
            .map(|(p, x)| IndexReport {
                key: p.key.clone(),
                first_order: x.first_order,
                first_order_ci: x.first_order_ci,
                total: x.total,
                total_ci: x.total_ci,
            })
            .collect(),
        None => {
            notes.push(
                "no indices: fewer than two complete base rows, or the speed does not vary".into(),
            );
            Vec::new()
        }
    }
}

/// The design block of evaluation `id`: "A", "B" or "AB<i>" (i from 1).
fn block(study: &UncertaintyStudy, id: usize) -> String {
    match id / study.spec.samples {
        0 => "A".into(),
        1 => "B".into(),
        k => format!("AB{}", k - 1),
    }
}

/// `uncertainty.csv`: one row per evaluation, sorted by id: `evaluation_id`, `block`, a column
/// per parameter key (SI), the speeds ([`SPEED_COLUMNS`]), `status` and `stable_up_to_m_s`.
pub fn uncertainty_csv(study: &UncertaintyStudy, rows: &[PointRecord]) -> String {
    let mut sorted: Vec<&PointRecord> = rows.iter().collect();
    sorted.sort_by_key(|r| r.id);
    let mut s = String::from("evaluation_id,block");
    for p in &study.spec.parameters {
        s.push(',');
        s.push_str(&p.key);
    }
    for c in SPEED_COLUMNS.iter().chain(&["status", "stable_up_to_m_s"]) {
        s.push(',');
        s.push_str(c);
    }
    s.push('\n');
    let opt = |v: Option<f64>| v.map_or(String::new(), |x| x.to_string());
    for r in sorted {
        let _ = write!(s, "{},{}", r.id, block(study, r.id));
        for (v, p) in r.values.iter().zip(&study.spec.parameters) {
            // a choice among files: the file itself (quoted when CSV needs it)
            match p.files.get(v.round() as usize) {
                Some(f) if f.contains([',', '"', '\n']) => {
                    let _ = write!(s, ",\"{}\"", f.replace('"', "\"\""));
                }
                Some(f) => {
                    let _ = write!(s, ",{f}");
                }
                None => {
                    let _ = write!(s, ",{v}");
                }
            }
        }
        let _ = writeln!(
            s,
            ",{},{},{},{},{}",
            opt(r.kalker_m_s),
            opt(r.hopf_m_s),
            opt(r.nonlinear_m_s),
            r.status(),
            opt(r.stable_up_to_m_s)
        );
    }
    s
}
