//! `critspeed curve`: a study with a `[curve]` section in, the curves out.

use anyhow::anyhow;

use super::files::Output;
use super::{compute, user, Cancel, Failure, Kind, Source};
use crate::curve::keyed::KeyedStudy;
use crate::curve::{CurveError, CurveKind, CurveReport, CurveSpec, SearchAt, VnlMethod};
use crate::study::schema::{CurveSection, Quantity};
use crate::sweep::{Spacing, SweepStudy};

/// The column types of `curve.csv` (numbers but these; `stable_cycle` is empty on Hopf curves).
pub const CURVE: &[(&str, Kind)] = &[
    ("kind", Kind::Text),
    ("creep_law", Kind::Text),
    ("label", Kind::Text),
    ("hopf_type", Kind::Text),
    ("stable_side", Kind::Text),
    ("stable_cycle", Kind::OptBool),
];

/// A study with its `[curve]` section resolved.
pub struct CurveStudy {
    /// the study at any value of the key
    pub keyed: KeyedStudy,
    /// the resolved section
    pub spec: CurveSpec,
}

fn failure(e: CurveError) -> Failure {
    if e.is_user_error() {
        user(e)
    } else {
        compute(e)
    }
}

/// The study of `source` with its `[curve]` section (a study without one is a user error).
pub fn curve_study(source: &Source) -> Result<CurveStudy, Failure> {
    let section = source.file_schema()?.curve.ok_or_else(|| {
        user(anyhow!(
            "{}: no [curve] section: `critspeed curve` needs one with key, from and to",
            source.origin
        ))
    })?;
    let keyed = KeyedStudy::new(
        &source.text,
        &source.origin,
        source.folder.as_deref(),
        &section.key,
    )
    .map_err(failure)?;
    let spec = crate::curve::resolve(&section, &keyed).map_err(failure)?;
    Ok(CurveStudy { keyed, spec })
}

/// The curves the study's `[curve]` section asks for; `cancel` is asked before every
/// continuation step (a cancelled run is a [`Failure::Compute`] saying so).
pub fn curve(study: &CurveStudy, cancel: Cancel<'_>) -> Result<CurveReport, Failure> {
    curve_with_progress(study, cancel, None)
}

/// [`curve`], calling `progress` with a line of text as each diagram and curve is done.
pub fn curve_with_progress(
    study: &CurveStudy,
    cancel: Cancel<'_>,
    progress: Option<&(dyn Fn(&str) + Sync)>,
) -> Result<CurveReport, Failure> {
    let mut report =
        crate::curve::analyse_with_progress(&study.keyed, &study.spec, cancel, progress)
            .map_err(failure)?;
    if study.spec.attractors {
        search_at_values(study, &mut report, cancel, progress);
    }
    if cancel.is_some_and(|c| c()) {
        return Err(compute(anyhow!("curve continuation cancelled")));
    }
    Ok(report)
}

/// Where the search's simulations left the contact geometry's range (no verdict there: the
/// motion is large, not absent), as a clause: from the lowest such speed.
fn left_range(a: &crate::attractors::AttractorReport) -> String {
    use crate::attractors::MotionKind;
    let lowest = a
        .speeds
        .iter()
        .filter(|row| {
            row.outcomes
                .iter()
                .any(|o| o.kind == MotionKind::OutOfRange && o.count > 0)
        })
        .map(|row| row.speed_m_s)
        .reduce(f64::min);
    match lowest {
        Some(v) => format!(
            "; but initial states left the contact geometry's range at {v:.2} m/s and above, where it gives no verdict: the motion there is large, not absent"
        ),
        None => String::new(),
    }
}

/// How the attractor search's V_NL compares with the continuation's.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Verdict {
    /// the continuation's value lies in the search's death bracket widened by its width
    Agree,
    /// the search finds hunting below that
    SearchLower,
    /// the search's lowest attractor dies above it
    SearchHigher,
}

/// The continuation's V_NL `v` against the search's lowest hunting speed `speed` and the
/// bracket its attractor dies in (m/s): they agree when `v` lies in the bracket widened on
/// each side by its width (at least 1e-9 relative), as `tests/attractors.rs` compares them.
fn judge(v: f64, speed: f64, bracket: Option<(f64, f64)>) -> Verdict {
    let (lo, hi) = bracket.unwrap_or((speed, speed));
    let width = (hi - lo).max(1e-9 * speed.abs());
    if v < lo - width {
        Verdict::SearchHigher
    } else if v > hi + width {
        Verdict::SearchLower
    } else {
        Verdict::Agree
    }
}

/// Where the search's V_NL `search` is above the continuation's `v` at key value `p`: the fold
/// curves' cycles there simulated and followed down ([`crate::trade::settle`]), in words. A
/// confirmed fold keeps the continuation's V_NL; an unconfirmed one keeps it too, as a
/// candidate the simulation did not confirm (the safe side), and says so.
fn settle_at(study: &CurveStudy, report: &CurveReport, p: f64, v: f64, search: f64) -> String {
    use crate::trade::settle::{settle_at, FoldCycle};
    let cycles: Vec<FoldCycle> = report
        .curves
        .iter()
        .enumerate()
        .filter(|(_, c)| c.kind == CurveKind::Fold)
        .flat_map(|(i, c)| {
            c.points
                .iter()
                .filter(|q| {
                    q.parameter == p && q.stable_cycle == Some(true) && !q.cycle_state.is_empty()
                })
                .map(move |q| FoldCycle {
                    curve: i,
                    label: c.label.to_string(),
                    fold_m_s: q.speed_m_s,
                    parameter: p,
                    state: q.cycle_state.clone(),
                })
        })
        .collect();
    let run = settle_at(
        &study.keyed,
        p,
        &cycles,
        v,
        Some(search),
        "the attractor search",
    );
    match run {
        Ok(st) if st.confirmed => format!(
            "settled by simulating the fold's cycle, the continuation's value stands: {}",
            st.words
        ),
        Ok(st) => format!(
            "simulating the folds' cycles does not confirm the continuation's value, which stands as an unconfirmed candidate (the safe side): {}",
            st.words
        ),
        Err(e) => format!(
            "the continuation's value stands, not settled by simulation ({e})"
        ),
    }
}

/// The attractor search (`critspeed attractors`: the study's `[attractors]` section or its
/// defaults) on the study rewritten at every V_NL value of `report`. Where it finds a hunting
/// attractor alive below the curves' V_NL (below its death bracket's lower end, by more than
/// the bracket's width), V_NL there becomes the search's and says so; every disagreement, and
/// every failed search, is a note in words; the agreements are counted in one.
fn search_at_values(
    study: &CurveStudy,
    report: &mut CurveReport,
    cancel: Cancel<'_>,
    progress: Option<&(dyn Fn(&str) + Sync)>,
) {
    let say = |line: &str| {
        if let Some(p) = progress {
            p(line)
        }
    };
    let spec = &study.spec;
    let along = |a: &f64, b: &f64| ((a - b) * (spec.range.1 - spec.range.0)).total_cmp(&0.0);
    // every value V_NL is given at, and those where the continuation could not give it
    let mut values: Vec<(f64, f64)> = report.nonlinear_critical_speed.clone();
    values.extend(report.nonlinear_unknown.iter().map(|&p| (p, f64::NAN)));
    values.sort_by(|a, b| along(&a.0, &b.0));
    let mut found_at: Vec<(f64, f64, VnlMethod)> = Vec::new();
    let mut agree = 0;
    for &(p, v) in &values {
        if cancel.is_some_and(|c| c()) {
            break;
        }
        let started = std::time::Instant::now();
        let found = study
            .keyed
            .plan_at(p)
            .map_err(|e| e.to_string())
            .and_then(|plan| super::Prepared::new(plan).map_err(|e| e.message()))
            .and_then(|prepared| {
                let hooks = super::Hooks {
                    progress: None,
                    cancel,
                    branches: None,
                };
                super::attractors(&prepared, hooks, None).map_err(|e| e.message())
            });
        let mut at = SearchAt {
            parameter: p,
            continuation_m_s: v,
            search_m_s: None,
            bracket_m_s: None,
            bracket_open: false,
            error: None,
        };
        let place = spec.show(p);
        let known = v.is_finite();
        let continuation = format!("the continuation's V_NL {v:.3} m/s");
        match found {
            Err(e) => {
                report
                    .notes
                    .push(format!("the attractor search at {place} failed: {e}"));
                at.error = Some(e);
            }
            Ok((a, _)) => match a.nonlinear_critical_speed {
                None if known => report.notes.push(format!(
                    "at {place} the attractor search found no hunting attractor in its speed range{}, against {continuation}: the continuation's value stands (a start the search's grid misses, or an attractor above its range)",
                    left_range(&a)
                )),
                None => report.notes.push(format!(
                    "at {place} neither the continuation nor the attractor search gives V_NL (the search found no hunting attractor in its speed range{})",
                    left_range(&a)
                )),
                Some((speed, bracket, id)) => {
                    at.search_m_s = Some(speed);
                    at.bracket_m_s = bracket;
                    at.bracket_open = a.attractors.iter().find(|x| x.id == id).is_some_and(|x| x.open_below);
                    let (lo, hi) = bracket.unwrap_or((speed, speed));
                    let open = if at.bracket_open {
                        ", a bracket open at its lower end: no verdict there, it may live lower"
                    } else {
                        ""
                    };
                    match (known, judge(v, speed, bracket)) {
                        (false, _) => {
                            report.notes.push(format!(
                                "at {place} the continuation gives no V_NL; the attractor search finds hunting down to {speed:.3} m/s (it dies in [{lo:.3}, {hi:.3}] m/s{open}): V_NL there is the search's"
                            ));
                            found_at.push((p, speed, VnlMethod::AttractorSearch));
                        }
                        (true, Verdict::SearchHigher) => {
                            // settled by simulating the folds' own cycles there
                            let settled = settle_at(study, report, p, v, speed);
                            report.notes.push(format!(
                                "at {place} the attractor search's lowest hunting attractor dies in [{lo:.3}, {hi:.3}] m/s{open}, above {continuation}: {settled}"
                            ));
                        }
                        (true, Verdict::SearchLower) => {
                            report.notes.push(format!(
                                "at {place} the attractor search finds hunting down to {speed:.3} m/s (it dies in [{lo:.3}, {hi:.3}] m/s{open}), below {continuation}: V_NL there is the search's (an attractor no followed fold bounds)"
                            ));
                            found_at.push((p, speed, VnlMethod::AttractorSearch));
                        }
                        (true, Verdict::Agree) => agree += 1,
                    }
                }
            },
        }
        say(&format!(
            "  attractor search at {place}: {} ({:.1} s)",
            match (at.search_m_s, &at.error) {
                (_, Some(_)) => "failed".to_string(),
                (Some(s), _) => format!("hunting down to {s:.3} m/s"),
                (None, _) => "no hunting attractor".to_string(),
            },
            started.elapsed().as_secs_f64()
        ));
        report.attractor_search.push(at);
    }
    // V_NL: the continuation's values, each replaced where the search found hunting lower,
    // and the search's where the continuation had none
    let mut merged: Vec<(f64, f64, VnlMethod)> = report
        .nonlinear_critical_speed
        .iter()
        .enumerate()
        .map(|(i, &(p, v))| {
            let m = report
                .nonlinear_methods
                .get(i)
                .copied()
                .unwrap_or(VnlMethod::Continuation);
            (p, v, m)
        })
        .collect();
    for (p, speed, method) in found_at {
        match merged.iter_mut().find(|e| e.0 == p) {
            Some(e) => *e = (p, speed, method),
            None => merged.push((p, speed, method)),
        }
    }
    merged.sort_by(|a, b| along(&a.0, &b.0));
    report.nonlinear_critical_speed = merged.iter().map(|e| (e.0, e.1)).collect();
    report.nonlinear_methods = merged.iter().map(|e| e.2).collect();
    let compared = report
        .attractor_search
        .iter()
        .filter(|a| a.continuation_m_s.is_finite())
        .count();
    report.notes.push(format!(
        "the attractor search agrees with the continuation's V_NL (within its death bracket, widened by its width) at {agree} of the {compared} values where both were computed"
    ));
}

/// `curve.json`, `curve.csv` and `curve.svg`.
pub fn files(r: &CurveReport) -> Result<Output, Failure> {
    let json = serde_json::to_string_pretty(&crate::output::curve_json(r)).map_err(compute)?;
    Ok(Output::default()
        .text("curve.json", json)
        .text("curve.csv", crate::output::curve_csv(r))
        .figure(crate::figures::curve(r), "curve.json and curve.csv"))
}

/// The curves a one-axis sweep's figure draws on top of its points: when the study's
/// `[curve]` section has the sweep's axis key, the section continued over the sweep's range
/// and spacing, with its `curves` when it names them and else only `"hopf"` (the folds cost
/// whole diagrams: drawn only when asked for). `None` for a two-axis sweep, a single-value
/// axis or another key; a failure is not the sweep's: it becomes the returned warning and
/// nothing is drawn.
pub fn sweep_curves(study: &SweepStudy) -> (Option<CurveReport>, Vec<String>) {
    let (Some(section), [axis]) = (&study.curve, study.spec.axes.as_slice()) else {
        return (None, Vec::new());
    };
    let (Some(&from), Some(&to)) = (axis.values.first(), axis.values.last()) else {
        return (None, Vec::new());
    };
    if section.key != axis.key || from == to {
        return (None, Vec::new());
    }
    let section = CurveSection {
        from: Quantity::Number(from),
        to: Quantity::Number(to),
        spacing: Some(match axis.spacing {
            Spacing::Log => "log".into(),
            Spacing::Linear => "linear".into(),
        }),
        curves: Some(
            section
                .curves
                .clone()
                .unwrap_or_else(|| vec![CurveKind::Hopf.name().into()]),
        ),
        ..section.clone()
    };
    let (text, origin, folder) = study.source();
    let report = KeyedStudy::new(text, origin, folder, &axis.key).and_then(|keyed| {
        let spec = crate::curve::resolve(&section, &keyed)?;
        crate::curve::analyse(&keyed, &spec, None)
    });
    match report {
        Ok(r) => (Some(r), Vec::new()),
        Err(e) => (
            None,
            vec![format!(
                "the [curve] section's curves over {} are not drawn on the sweep's figure: {e}",
                axis.key
            )],
        ),
    }
}

#[cfg(test)]
mod tests {
    use super::{judge, Verdict};

    #[test]
    fn the_search_and_the_continuation_agree_within_the_widened_bracket() {
        // bracket [89.28, 89.35]: width 0.07, so agreement on [89.21, 89.42]
        let b = Some((89.28, 89.35));
        assert_eq!(judge(89.34, 89.28, b), Verdict::Agree);
        assert_eq!(judge(89.41, 89.28, b), Verdict::Agree);
        assert_eq!(judge(89.22, 89.28, b), Verdict::Agree);
        assert_eq!(judge(89.43, 89.28, b), Verdict::SearchLower);
        assert_eq!(judge(124.15, 89.28, b), Verdict::SearchLower);
        assert_eq!(judge(89.20, 89.28, b), Verdict::SearchHigher);
        // without a bracket only (nearly) equal speeds agree
        assert_eq!(judge(50.0, 50.0, None), Verdict::Agree);
        assert_eq!(judge(50.001, 50.0, None), Verdict::SearchLower);
    }
}
