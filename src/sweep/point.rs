//! One sweep point: its plan, model and the requested critical speeds, or why it failed.

use crate::bifurcation;
use crate::contact::creep::CreepLaw;
use crate::model::Wheelset;
use crate::stability::{critical_speeds, LinearOptions, LinearSystem};

use super::study::{Spares, SweepStudy};

/// The result of one grid point.
#[derive(Clone, Debug, PartialEq)]
pub struct PointRecord {
    /// grid index (first axis fastest)
    pub id: usize,
    /// axis values in SI units, in axis order
    pub values: Vec<f64>,
    /// Kalker (linear) critical speed: first onset (m/s), when computed and found
    pub kalker_m_s: Option<f64>,
    /// Hopf speed of the study's creep law: first onset (m/s)
    pub hopf_m_s: Option<f64>,
    /// nonlinear critical speed V_NL (m/s)
    pub nonlinear_m_s: Option<f64>,
    /// why requested results are missing; empty = the point is ok
    pub failures: Vec<String>,
    /// hunting frequency at the Kalker critical speed (Hz)
    pub kalker_frequency_hz: Option<f64>,
    /// hunting frequency at the Hopf speed (Hz)
    pub hopf_frequency_hz: Option<f64>,
    /// whether V_NL was located (fold or supercritical Hopf) rather than the lowest stable cycle
    pub nonlinear_located: Option<bool>,
}

impl PointRecord {
    fn empty(id: usize, values: Vec<f64>) -> Self {
        Self {
            id,
            values,
            kalker_m_s: None,
            hopf_m_s: None,
            nonlinear_m_s: None,
            failures: Vec::new(),
            kalker_frequency_hz: None,
            hopf_frequency_hz: None,
            nonlinear_located: None,
        }
    }

    /// Whether every requested result was found.
    pub fn ok(&self) -> bool {
        self.failures.is_empty()
    }

    /// `ok`, or `failed: <reasons>` (no commas, quotes or line breaks, so the CSV stays plain).
    pub fn status(&self) -> String {
        if self.ok() {
            "ok".into()
        } else {
            let why = self.failures.join("; ");
            let clean: String = why
                .chars()
                .map(|c| match c {
                    ',' => ';',
                    '"' => '\'',
                    '\n' | '\r' => ' ',
                    c => c,
                })
                .collect();
            format!("failed: {clean}")
        }
    }
}

/// First onset of `model`'s own law: (speed m/s, frequency Hz), or the reason.
fn onset(model: &Wheelset, opts: &LinearOptions, what: &str) -> Result<(f64, f64), String> {
    let law = model.creep_law;
    let found = critical_speeds(&LinearSystem::at_centre(model), law, opts)
        .map_err(|e| format!("{what}: {e}"))?;
    found
        .critical()
        .map(|c| (c.speed_m_s, c.frequency_hz))
        .ok_or_else(|| {
            format!(
                "{what}: no onset of hunting between {} and {} m/s",
                opts.speed_range.0, opts.speed_range.1
            )
        })
}

/// Computes point `id` of the sweep. Never fails: problems become the record's failures.
pub fn compute(study: &SweepStudy, id: usize, spares: &Spares) -> PointRecord {
    let mut rec = PointRecord::empty(id, study.spec.values(id));
    let run = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        fill(study, &mut rec, spares)
    }));
    if let Err(e) = run {
        let msg = e
            .downcast_ref::<&str>()
            .map(|s| s.to_string())
            .or_else(|| e.downcast_ref::<String>().cloned())
            .unwrap_or_else(|| "unknown".into());
        rec.failures.push(format!("internal error (panic): {msg}"));
    }
    rec
}

fn fill(study: &SweepStudy, rec: &mut PointRecord, spares: &Spares) {
    let plan = match study.point_plan(rec.id) {
        Ok(p) => p,
        Err(e) => return rec.failures.push(format!("invalid parameters: {e}")),
    };
    let mut model = match study.model(&plan, spares) {
        Ok(m) => m,
        Err(e) => return rec.failures.push(format!("contact geometry: {e}")),
    };
    let c = study.spec.compute;
    if c.kalker {
        // the Kalker model is the study's with the law swapped (no copy of the table)
        let law = std::mem::replace(&mut model.creep_law, CreepLaw::Kalker);
        let found = onset(&model, &plan.linear, "kalker");
        model.creep_law = law;
        match found {
            Ok((v, f)) => (rec.kalker_m_s, rec.kalker_frequency_hz) = (Some(v), Some(f)),
            Err(e) => rec.failures.push(e),
        }
    }
    if c.hopf {
        match onset(&model, &plan.linear, "hopf") {
            Ok((v, f)) => (rec.hopf_m_s, rec.hopf_frequency_hz) = (Some(v), Some(f)),
            Err(e) => rec.failures.push(e),
        }
    }
    if c.nonlinear {
        // the points are the parallel work; each continuation runs serially (same results)
        let opts = bifurcation::BifurcationOptions {
            parallel: false,
            ..plan.bifurcation_options()
        };
        match bifurcation::analyse(&plan.name, &model, &opts) {
            Ok(r) => match r.nonlinear_critical_speed {
                Some((v, located)) => {
                    (rec.nonlinear_m_s, rec.nonlinear_located) = (Some(v), Some(located))
                }
                None => rec.failures.push(format!(
                    "nonlinear: no stable cycle found ({})",
                    r.stop_reason
                )),
            },
            Err(e) => rec.failures.push(format!("nonlinear: {e}")),
        }
    }
    if study.reuses_table(&plan) {
        spares.put(model);
    }
}
