//! Settling a disagreement on V_NL by simulation.
//!
//! A curve trade reads V_NL from fold curves (the lowest fold where a stable cycle branch ends)
//! and verifies its best design with the one-point computation (the whole diagram at that key
//! value and the descents from its stable cycles). Where the curves give the lower V_NL, the
//! diagram may not reach the curves' fold (an isolated branch, or one behind a point the
//! continuation does not pass), or the curves' fold may bound no attractor. Neither method can
//! say which from its own results, so the fold's own motion is tested in the other method's
//! terms: each fold curve's cycle at the key value (the state of its nearest solved point) is
//! simulated at [`ABOVE_FOLD`] above and below the fold's speed by the attractor search
//! ([`crate::attractors::Seed`]); where it hunts, that attractor is followed down until it dies
//! (the search's descent and bracket), and V_NL is the lowest speed where a hunting motion is
//! confirmed; where it does not, the fold is refuted as V_NL at this key value, and said so.
//!
//! Near a fold of cycles the amplitude obeys the saddle-node normal form ȧ = μ − a²: on the
//! side where the two cycles exist (μ > 0) the fold's own cycle lies between the unstable one
//! (a = −√μ) and the stable one (a = +√μ), so a simulation started on it at that speed settles
//! on the stable cycle, when there is one. The other side is simulated too, since the curves
//! do not say on which side of the fold its cycles lie.

use std::fmt::Write as _;

use crate::attractors::{self, Seed, SeedCheck};
use crate::model::Vehicle;
use crate::study::Plan;

/// The seeds are simulated at the fold's speed times (1 ± this).
pub const ABOVE_FOLD: f64 = 0.02;

/// A fold curve's cycle at a key value.
#[derive(Clone, Debug, PartialEq)]
pub struct FoldCycle {
    /// the curve's index in the curve report
    pub curve: usize,
    /// its label ("fold (symmetric)")
    pub label: String,
    /// the fold's speed at the key value (m/s; interpolated between the curve's points)
    pub fold_m_s: f64,
    /// the key value of the point whose cycle state is used (the nearer of the two)
    pub parameter: f64,
    /// that point's cycle state (the model's state order, SI)
    pub state: Vec<f64>,
}

/// The verdict on one fold's cycle.
#[derive(Clone, Debug, PartialEq)]
pub struct Check {
    /// the curve's index
    pub curve: usize,
    /// its label
    pub label: String,
    /// the fold's speed on the curves (m/s)
    pub fold_m_s: f64,
    /// the simulations: above the fold's speed, then below it
    pub seeds: Vec<SeedCheck>,
}

impl Check {
    /// The lowest speed where a hunting motion started on this fold's cycle may live (m/s):
    /// the attractor's lowest speed, or, where its death bracket is open below (the motion at
    /// the lower end had no verdict), that lower end: the safe side.
    pub fn lowest_m_s(&self) -> Option<f64> {
        self.seeds
            .iter()
            .filter_map(|s| match (s.open_below, s.dies_m_s) {
                (true, Some((lo, _))) => Some(lo),
                _ => s.lowest_m_s,
            })
            .reduce(f64::min)
    }
}

/// The outcome of settling.
#[derive(Clone, Debug, PartialEq)]
pub struct Settlement {
    /// the other method's V_NL (m/s): the one-point computation's in a trade
    pub one_point_m_s: Option<f64>,
    /// the curves' V_NL at the key value (m/s)
    pub curves_m_s: f64,
    /// one check per fold curve below the one-point V_NL
    pub checks: Vec<Check>,
    /// V_NL after settling: the lowest speed where a hunting motion is confirmed (the
    /// one-point computation's or a fold cycle's attractor)
    pub nonlinear_m_s: Option<f64>,
    /// whether the curves' V_NL is confirmed: an attractor started on a fold's cycle lives
    /// down to within the search's bracket of the curves' V_NL (or lower)
    pub confirmed: bool,
    /// the verdict in words
    pub words: String,
    /// simulations run
    pub simulations: usize,
    /// the model's bodies in state order (the motions' amplitudes are in this order)
    pub bodies: Vec<String>,
}

/// Settles the curves' V_NL `curves_m_s` against another method's `one_point` (named `other`:
/// "the one-point computation", "the attractor search") at one key value, whose study plan
/// and model are `plan` and `model`, by simulating from the fold cycles `cycles` (those within
/// [`super::intervals::DIFFER`] of `one_point` or above it are left out: the other method has
/// their motion).
pub fn settle(
    plan: &Plan,
    model: &Vehicle,
    cycles: &[FoldCycle],
    curves_m_s: f64,
    one_point: Option<f64>,
    other: &str,
) -> Result<Settlement, String> {
    let below: Vec<&FoldCycle> = cycles
        .iter()
        .filter(|c| one_point.is_none_or(|v| c.fold_m_s < v * (1.0 - super::intervals::DIFFER)))
        .collect();
    let mut opts = plan.attractor_options(None).descents_only();
    for c in &below {
        for (sign, side) in [(1.0, "above"), (-1.0, "below")] {
            opts.seeds.push(Seed {
                speed_m_s: c.fold_m_s * (1.0 + sign * ABOVE_FOLD),
                state: c.state.clone(),
                source: format!(
                    "the cycle of curve {} ({}) at {:.3} m/s, {:.0} % {side} its speed",
                    c.curve,
                    c.label,
                    c.fold_m_s,
                    100.0 * ABOVE_FOLD
                ),
            });
        }
    }
    let mut report = attractors::search(&plan.name, model, &opts, None)?;
    let mut found = std::mem::take(&mut report.seed_checks).into_iter();
    let checks: Vec<Check> = below
        .iter()
        .map(|c| Check {
            curve: c.curve,
            label: c.label.clone(),
            fold_m_s: c.fold_m_s,
            seeds: found.by_ref().take(2).collect(),
        })
        .collect();
    let lowest = checks.iter().filter_map(Check::lowest_m_s).reduce(f64::min);
    let nonlinear_m_s = match (one_point, lowest) {
        (Some(a), Some(b)) => Some(a.min(b)),
        (a, b) => a.or(b),
    };
    let confirmed = lowest.is_some_and(|l| l <= curves_m_s + 2.0 * opts.bracket);
    let words = words(
        &checks,
        curves_m_s,
        one_point,
        nonlinear_m_s,
        confirmed,
        other,
    );
    Ok(Settlement {
        one_point_m_s: one_point,
        curves_m_s,
        checks,
        nonlinear_m_s,
        confirmed,
        words,
        simulations: report.simulations,
        bodies: report.body_names,
    })
}

/// [`settle`] on `keyed` rewritten at key value `x`; a study or model that cannot be built
/// there is an error in words.
pub fn settle_at(
    keyed: &crate::curve::keyed::KeyedStudy,
    x: f64,
    cycles: &[FoldCycle],
    curves_m_s: f64,
    one_point: Option<f64>,
    other: &str,
) -> Result<Settlement, String> {
    let plan = keyed.plan_at(x).map_err(|e| e.to_string())?;
    let model = keyed.model_at(x).map_err(|e| e.to_string())?;
    settle(&plan, &model, cycles, curves_m_s, one_point, other)
}

fn seed_words(s: &SeedCheck) -> String {
    let m = &s.motion;
    let mut w = format!("at {:.3} m/s: {}", s.speed_m_s, m.kind.name());
    if m.kind.is_hunting() {
        let _ = write!(w, " ({:.3} mm)", m.amplitude_m() * 1e3);
    }
    if !m.note.is_empty() {
        let _ = write!(w, " ({})", m.note);
    }
    match (s.lowest_m_s, s.dies_m_s) {
        (Some(_), Some((a, b))) => {
            let open = if s.open_below {
                " (open below: the motion at its lower end had no verdict, so it may live down to that end, which counts)"
            } else {
                ""
            };
            let _ = write!(w, ", an attractor that dies in [{a:.4}, {b:.4}] m/s{open}");
        }
        (Some(l), None) => {
            let _ = write!(w, ", an attractor that lives down to {l:.4} m/s");
        }
        _ => {}
    }
    w
}

fn words(
    checks: &[Check],
    curves: f64,
    one_point: Option<f64>,
    settled: Option<f64>,
    confirmed: bool,
    other: &str,
) -> String {
    let op = one_point.map_or("none".to_string(), |v| format!("{v:.3} m/s"));
    if checks.is_empty() {
        return format!(
            "no fold curve below {other}'s V_NL ({op}) passes this key value with a cycle to start from; the curves' {curves:.3} m/s is not tested"
        );
    }
    let mut w = String::new();
    for c in checks {
        let sims: Vec<String> = c.seeds.iter().map(seed_words).collect();
        let _ = write!(
            w,
            "curve {} ({}) at {:.3} m/s, simulated from its cycle {}; ",
            c.curve,
            c.label,
            c.fold_m_s,
            sims.join("; ")
        );
    }
    let v = settled.map_or("unknown".to_string(), |v| format!("{v:.3} m/s"));
    if confirmed {
        let _ = write!(
            w,
            "CONFIRMED: a hunting attractor lives down to the curves' V_NL ({curves:.3} m/s), which {other} ({op}) did not reach; V_NL = {v}"
        );
    } else if settled.is_some_and(|s| one_point.is_none_or(|o| s < o)) {
        let _ = write!(
            w,
            "PARTLY CONFIRMED: a hunting attractor lives below {other}'s V_NL ({op}) but not down to the curves' {curves:.3} m/s; V_NL = {v}"
        );
    } else {
        let _ = write!(
            w,
            "REFUTED: no motion started on the curves' fold cycles hunts below {other}'s V_NL ({op}), so the curves' {curves:.3} m/s bounds no attractor found here; V_NL = {v} ({other}'s)"
        );
    }
    w
}
