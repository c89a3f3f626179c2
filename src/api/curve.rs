//! `critspeed curve`: a study with a `[curve]` section in, the curves out.

use anyhow::anyhow;

use super::files::Output;
use super::{compute, user, Cancel, Failure, Kind, Source};
use crate::curve::keyed::KeyedStudy;
use crate::curve::{CurveError, CurveKind, CurveReport, CurveSpec};
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
    let report = crate::curve::analyse_with_progress(&study.keyed, &study.spec, cancel, progress)
        .map_err(failure)?;
    if cancel.is_some_and(|c| c()) {
        return Err(compute(anyhow!("curve continuation cancelled")));
    }
    Ok(report)
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
