//! One sweep point: its plan, model and the requested critical speeds, or why it failed.
//!
//! Each requested result has one of four outcomes ([`Outcome`]): found (a speed and a
//! frequency), **above range** (the eigen-analysis ran and the centred motion is stable over the
//! whole speed range `[v_min, v_max]`: no onset, no divergence, so the critical speed exceeds
//! `v_max`), for V_NL **no Hopf point in range** (its branch starts at the Hopf point, and there
//! is none in the range: V_NL is not computed, and not bounded either, since a subcritical branch
//! born above `v_max` can fold back below it), or failed (with the reason). Above range and no
//! Hopf point in range say what happened; they are not failures.

use crate::bifurcation;
use crate::contact::creep::CreepLaw;
use crate::model::Vehicle;
use crate::stability::{critical_speeds, LinearOptions, LinearSystem};

use super::study::{Spares, SweepStudy};

/// A result a sweep point can compute.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Computed {
    /// the Kalker (linear) critical speed V_L
    Kalker,
    /// the Hopf speed V_H of the study's creep law
    Hopf,
    /// the nonlinear critical speed V_NL
    Nonlinear,
}

impl Computed {
    /// All results, in column order.
    pub const ALL: [Computed; 3] = [Computed::Kalker, Computed::Hopf, Computed::Nonlinear];

    /// The name used in `status` and `compute`: `kalker`, `hopf`, `nonlinear`.
    pub fn name(self) -> &'static str {
        match self {
            Computed::Kalker => "kalker",
            Computed::Hopf => "hopf",
            Computed::Nonlinear => "nonlinear",
        }
    }

    /// Parses [`Self::name`].
    pub fn from_name(s: &str) -> Option<Computed> {
        Computed::ALL.into_iter().find(|c| c.name() == s)
    }
}

/// What one point gives for one result.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Outcome {
    /// the critical speed (m/s) and, for the linear results, the hunting frequency (Hz)
    Found {
        /// speed (m/s)
        speed_m_s: f64,
        /// hunting frequency at that speed (Hz), when known
        frequency_hz: Option<f64>,
    },
    /// no onset in the speed range: stable at least up to `stable_up_to_m_s` (= v_max, m/s)
    AboveRange {
        /// top of the point's speed range (m/s); the critical speed exceeds it
        stable_up_to_m_s: f64,
    },
    /// V_NL only: no Hopf point of the creep law in the speed range, so no branch to follow
    NoHopf,
    /// not computed, or failed (the point's `failures` say why)
    Missing,
}

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
    /// why requested results are missing; empty = no result failed
    pub failures: Vec<String>,
    /// hunting frequency at the Kalker critical speed (Hz)
    pub kalker_frequency_hz: Option<f64>,
    /// hunting frequency at the Hopf speed (Hz)
    pub hopf_frequency_hz: Option<f64>,
    /// whether V_NL was located (a fold, a supercritical Hopf point, an attractor's closed death
    /// bracket) rather than the lowest stable cycle computed or an open bracket (an upper bound)
    pub nonlinear_located: Option<bool>,
    /// the results with no onset in the speed range (sorted, in [`Computed::ALL`] order)
    pub above_range: Vec<Computed>,
    /// top of the speed range (m/s) when some result is above range, else `None`
    pub stable_up_to_m_s: Option<f64>,
    /// V_NL was requested and not computed: no Hopf point of the creep law in the speed range
    pub no_hopf: bool,
}

impl PointRecord {
    /// A record of point `id` at `values` with no result yet.
    pub(crate) fn empty(id: usize, values: Vec<f64>) -> Self {
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
            above_range: Vec::new(),
            stable_up_to_m_s: None,
            no_hopf: false,
        }
    }

    /// Whether no requested result failed: each was found, is above range or (V_NL) has no
    /// Hopf point in range.
    pub fn ok(&self) -> bool {
        self.failures.is_empty()
    }

    /// Whether some result is above range (stable up to [`Self::stable_up_to_m_s`]).
    pub fn has_above_range(&self) -> bool {
        !self.above_range.is_empty()
    }

    /// The outcome of result `which`.
    pub fn outcome(&self, which: Computed) -> Outcome {
        let (speed, freq) = match which {
            Computed::Kalker => (self.kalker_m_s, self.kalker_frequency_hz),
            Computed::Hopf => (self.hopf_m_s, self.hopf_frequency_hz),
            Computed::Nonlinear => (self.nonlinear_m_s, None),
        };
        match (speed, self.stable_up_to_m_s) {
            (Some(speed_m_s), _) => Outcome::Found {
                speed_m_s,
                frequency_hz: freq,
            },
            (None, Some(v)) if self.above_range.contains(&which) => Outcome::AboveRange {
                stable_up_to_m_s: v,
            },
            (None, _) if which == Computed::Nonlinear && self.no_hopf => Outcome::NoHopf,
            _ => Outcome::Missing,
        }
    }

    /// The `status` column: `ok` (every requested result found), else its clauses in this
    /// order, joined by `; `: `failed: <reasons>` (some failed), `above range: <names>` (these
    /// had no onset in the speed range, e.g. `above range: kalker; hopf`), `no Hopf point in
    /// range: nonlinear` (V_NL not computed). No commas, quotes or line breaks, so the CSV stays
    /// plain.
    pub fn status(&self) -> String {
        let mut clauses = Vec::new();
        if !self.ok() {
            clauses.push(format!("{FAILED}{}", clean(&self.failures.join("; "))));
        }
        if !self.above_range.is_empty() {
            let names: Vec<&str> = self.above_range.iter().map(|c| c.name()).collect();
            clauses.push(format!("{ABOVE}{}", names.join("; ")));
        }
        if self.no_hopf {
            clauses.push(NO_HOPF.to_string());
        }
        if clauses.is_empty() {
            "ok".into()
        } else {
            clauses.join("; ")
        }
    }

    /// Sets `failures`, `above_range` and `no_hopf` from a `status` text written by
    /// [`Self::status`].
    pub fn set_status(&mut self, status: &str) -> Result<(), String> {
        let s = parse_status(status)?;
        self.failures = s.failures;
        self.above_range = s.above;
        self.no_hopf = s.no_hopf;
        Ok(())
    }
}

/// Prefix of the status of a point with results above range.
pub const ABOVE: &str = "above range: ";
/// Prefix of the status of a failed point.
pub const FAILED: &str = "failed: ";
/// The status clause of a point whose V_NL was not computed for want of a Hopf point.
pub const NO_HOPF: &str = "no Hopf point in range: nonlinear";

/// A `status` read back.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Status {
    /// why results failed (one text; empty: none failed)
    pub failures: Vec<String>,
    /// the results above range
    pub above: Vec<Computed>,
    /// V_NL not computed: no Hopf point in range
    pub no_hopf: bool,
}

fn clean(why: &str) -> String {
    why.chars()
        .map(|c| match c {
            ',' => ';',
            '"' => '\'',
            '\n' | '\r' => ' ',
            c => c,
        })
        .collect()
}

/// `kalker; hopf` → the results, or `None` when a name is not one.
fn names(list: &str) -> Option<Vec<Computed>> {
    let mut v = list
        .split(';')
        .map(|s| Computed::from_name(s.trim()))
        .collect::<Option<Vec<_>>>()?;
    v.sort_unstable();
    v.dedup();
    Some(v)
}

/// A `status` text, as [`PointRecord::status`] writes it, read back.
pub fn parse_status(status: &str) -> Result<Status, String> {
    let bad = || {
        format!(
            "status {status:?} is none of \"ok\", \"{ABOVE}<results>\", \"{FAILED}<reasons>\", \"{NO_HOPF}\""
        )
    };
    if status == "ok" {
        return Ok(Status::default());
    }
    // the last clause: V_NL without a Hopf point
    let (rest, no_hopf) = match status.strip_suffix(NO_HOPF) {
        Some("") => {
            return Ok(Status {
                no_hopf: true,
                ..Status::default()
            })
        }
        Some(r) => match r.strip_suffix("; ") {
            Some(r) => (r, true),
            None => (status, false),
        },
        None => (status, false),
    };
    if let Some(list) = rest.strip_prefix(ABOVE) {
        let above = names(list).ok_or_else(bad)?;
        return Ok(Status {
            failures: Vec::new(),
            above,
            no_hopf,
        });
    }
    let why = rest.strip_prefix(FAILED).ok_or_else(bad)?;
    // a failed point may end with the results that were above range
    let tail = format!("; {ABOVE}");
    if let Some(k) = why.rfind(&tail) {
        if let Some(above) = names(&why[k + tail.len()..]) {
            let failures = vec![why[..k].to_string()];
            return Ok(Status {
                failures,
                above,
                no_hopf,
            });
        }
    }
    Ok(Status {
        failures: vec![why.to_string()],
        above: Vec::new(),
        no_hopf,
    })
}

/// The linear analysis of one law at a point.
enum Onset {
    /// first onset: (speed m/s, frequency Hz)
    Found(f64, f64),
    /// stable over the whole range: no onset, no divergence
    AboveRange,
}

/// First onset of `model`'s own law, or stable through the range, or the reason.
fn onset(model: &Vehicle, opts: &LinearOptions, what: &str) -> Result<Onset, String> {
    let law = model.creep_law();
    let found = crate::with_states!(model.states(),
        N => critical_speeds(&LinearSystem::<N>::at_centre(model), law, opts),
        _ => Err(crate::stability::LinearError::States(model.states())))
    .map_err(|e| format!("{what}: {e}"))?;
    let (lo, hi) = opts.speed_range;
    if let Some(c) = found.critical() {
        return Ok(Onset::Found(c.speed_m_s, c.frequency_hz));
    }
    if !found.stable_at_start {
        return Err(format!(
            "{what}: the centred motion is already unstable at {lo} m/s (no onset in [{lo}, {hi}] m/s)"
        ));
    }
    if let Some(v) = found.divergence_speeds_m_s.first() {
        return Err(format!(
            "{what}: no onset of hunting in [{lo}, {hi}] m/s but a divergence (real eigenvalue) at {v} m/s"
        ));
    }
    Ok(Onset::AboveRange)
}

/// Computes point `id` of the sweep. Never fails: problems become the record's failures.
pub fn compute(study: &SweepStudy, id: usize, spares: &Spares) -> PointRecord {
    compute_at(study, id, study.values(id), spares)
}

/// Computes the study with its axis keys set to `values` (SI, in axis order), recorded as point
/// `id`. Never fails: problems become the record's failures.
pub fn compute_at(study: &SweepStudy, id: usize, values: Vec<f64>, spares: &Spares) -> PointRecord {
    let mut rec = PointRecord::empty(id, values);
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

/// Records a linear result: found, above range (stable up to v_max) or failed.
fn record(rec: &mut PointRecord, which: Computed, found: Result<Onset, String>, v_max: f64) {
    match found {
        Ok(Onset::Found(v, f)) => match which {
            Computed::Kalker => (rec.kalker_m_s, rec.kalker_frequency_hz) = (Some(v), Some(f)),
            _ => (rec.hopf_m_s, rec.hopf_frequency_hz) = (Some(v), Some(f)),
        },
        Ok(Onset::AboveRange) => {
            rec.above_range.push(which);
            rec.stable_up_to_m_s = Some(v_max);
        }
        Err(e) => rec.failures.push(e),
    }
}

fn fill(study: &SweepStudy, rec: &mut PointRecord, spares: &Spares) {
    let plan = match study.plan_with(&rec.values) {
        Ok(p) => p,
        Err(e) => return rec.failures.push(format!("invalid parameters: {e}")),
    };
    let mut model = match study.model(&plan, spares) {
        Ok(m) => m,
        Err(e) => return rec.failures.push(format!("contact geometry: {e}")),
    };
    let c = study.spec.compute;
    let v_max = plan.linear.speed_range.1;
    if c.kalker {
        // the Kalker model is the study's with the law swapped (no copy of the table)
        let law = std::mem::replace(&mut model.contact.creep_law, CreepLaw::Kalker);
        let found = onset(&model, &plan.linear, "kalker");
        model.contact.creep_law = law;
        record(rec, Computed::Kalker, found, v_max);
    }
    if c.hopf {
        let found = onset(&model, &plan.linear, "hopf");
        record(rec, Computed::Hopf, found, v_max);
    }
    if c.nonlinear {
        nonlinear(rec, &plan, &model, study.spec.attractors);
    }
    if study.reuses_table(&plan) {
        spares.put(model);
    }
}

/// V_NL by continuation from the Hopf point, with the descents or (`search`) the whole
/// attractor search beside it. With no Hopf point in the range V_NL is not computed (`no_hopf`,
/// not a failure) and stays unknown: V_H > v_max does not bound V_NL, since a subcritical branch
/// born above v_max can fold back below it, where a continuation confined to the range never
/// looks. A search that fails leaves V_NL missing, with the reason: the continuation's V_NL
/// alone is not the method the sweep promised.
fn nonlinear(rec: &mut PointRecord, plan: &crate::study::Plan, model: &Vehicle, search: bool) {
    // the points are the parallel work; each continuation runs serially (same results)
    let opts = bifurcation::BifurcationOptions {
        parallel: false,
        ..plan.bifurcation_options()
    };
    let r = bifurcation::analyse(&plan.name, model, &opts)
        .map_err(|e| e.to_string())
        .and_then(|r| with_search(plan, model, r, search));
    match r {
        Ok(r) => match (r.nonlinear_critical_speed, r.hopf) {
            (Some((v, located)), _) => {
                (rec.nonlinear_m_s, rec.nonlinear_located) = (Some(v), Some(located))
            }
            (None, None) => rec.no_hopf = true,
            (None, Some(_)) => rec.failures.push(format!(
                "nonlinear: no stable cycle found ({})",
                r.stop_reason
            )),
        },
        Err(e) => rec.failures.push(format!("nonlinear: {e}")),
    }
}

/// The sweep's V_NL is the analysis' (docs/model.md §9): with `search` (`attractors = true`,
/// the default for a bogie or a car) the whole attractor search of `critspeed attractors` with
/// the study's `[attractors]` settings; else its fast form, the continuation with branch
/// switching and the descent by simulation from each of its lowest stable cycles (followed
/// through any jump to another attractor until it dies), without the search's grid of initial
/// states. The lower of the continuation's and the simulations' V_NL.
fn with_search(
    plan: &crate::study::Plan,
    model: &Vehicle,
    mut r: bifurcation::BifurcationReport,
    search: bool,
) -> Result<bifurcation::BifurcationReport, String> {
    let mut opts = plan.attractor_options(r.hopf.map(|h| h.speed_m_s));
    if !search {
        opts = opts.descents_only();
    }
    opts.parallel = false;
    let what = if search {
        "attractor search"
    } else {
        "descents"
    };
    let s = crate::attractors::search(&plan.name, model, &opts, Some(&r))
        .map_err(|e| format!("{what}: {e}"))?;
    crate::reconcile::combine(&mut r, &s);
    Ok(r)
}

#[cfg(test)]
#[path = "point_tests.rs"]
mod tests;
