//! Critical speeds under uncertainty (`[uncertainty]`, `critspeed uncertainty`): the
//! distribution of V_L, V_H and V_NL over random parameters, and which parameters decide it
//! (first-order and total Sobol indices with bootstrap intervals).
//!
//! The parameters' values come from a Saltelli design ([`sample::design`]): matrices A and B of
//! N rows (scrambled Sobol points or seeded random numbers mapped through each distribution's
//! inverse CDF) and, for the indices, A_B^(i) for each of the d parameters: N (d + 2)
//! evaluations. The design is evaluated by the sweep's machinery: a [`SweepStudy`] whose points
//! are the design's rows ([`SweepStudy::with_design`]), so each evaluation is a sweep point
//! ([`crate::sweep::point::compute`]), and the records file, resume after a kill, shards and
//! [`crate::sweep::merge`] are the sweep's. [`report`] turns the finished rows into the
//! statistics and indices ([`estimate`]).

mod choice;
pub mod estimate;
pub mod report;
pub mod sample;
pub mod spec;

use crate::study::schema::StudyFile;
use crate::study::{self};
use crate::sweep::{self, Progress, SweepError, SweepOptions, SweepResults, SweepSpec, SweepStudy};

pub use report::{report, uncertainty_csv, QuantityReport, UncertaintyReport};
pub use spec::{Parameter, UncertaintySpec};

/// The stem of an uncertainty study's records files (`uncertainty.records.csv`,
/// `uncertainty.shard-I-of-N.records.csv`).
pub const RECORDS_STEM: &str = "uncertainty";

/// Why an uncertainty study could not run (failed evaluations are not errors: they are
/// recorded and reported).
#[derive(Debug, thiserror::Error)]
pub enum UncertaintyError {
    /// the study, its evaluation, records or shards
    #[error(transparent)]
    Sweep(#[from] SweepError),
    /// the study has no `[uncertainty]` section
    #[error("study {path} has no [uncertainty] section")]
    NoSection {
        /// the study's name in messages
        path: String,
    },
    /// a value of `[uncertainty]` breaks a rule
    #[error("{key} = {value}: {rule}")]
    Rule {
        /// the key, e.g. `uncertainty.parameter[0].std (suspension.lateral_stiffness)`
        key: String,
        /// the value as given or in SI
        value: String,
        /// the rule it breaks
        rule: String,
    },
}

impl UncertaintyError {
    /// Whether the user can fix it in the input (study, arguments, foreign files): exit 2.
    pub fn is_user_error(&self) -> bool {
        match self {
            UncertaintyError::Sweep(e) => e.is_user_error(),
            _ => true,
        }
    }
}

/// A study with its `[uncertainty]` section and the design's evaluations as a sweep.
#[derive(Clone, Debug)]
pub struct UncertaintyStudy {
    /// the resolved section
    pub spec: UncertaintySpec,
    /// the study evaluated at the design's rows (point id = evaluation id)
    pub sweep: SweepStudy,
}

impl UncertaintyStudy {
    /// Reads a study file with an `[uncertainty]` section.
    pub fn load(path: &std::path::Path) -> Result<Self, UncertaintyError> {
        let text = std::fs::read_to_string(path).map_err(|source| {
            SweepError::Study(study::StudyError::Io {
                path: path.display().to_string(),
                source,
            })
        })?;
        Self::parse_in(&text, &path.display().to_string(), path.parent())
    }

    /// Parses study text with an `[uncertainty]` section; relative paths in it are taken from
    /// `folder`.
    pub fn parse_in(
        text: &str,
        origin: &str,
        folder: Option<&std::path::Path>,
    ) -> Result<Self, UncertaintyError> {
        // the study itself first, so that its own errors come before the section's
        study::parse_in(text, origin, folder).map_err(SweepError::Study)?;
        let file: StudyFile = toml::from_str(text).map_err(|e| {
            SweepError::Study(study::StudyError::Syntax {
                path: origin.to_string(),
                message: e.to_string(),
            })
        })?;
        let section = file
            .uncertainty
            .ok_or_else(|| UncertaintyError::NoSection {
                path: origin.to_string(),
            })?;
        let spec = spec::resolve(&section)?;
        let dists: Vec<sample::Distribution> = spec
            .parameters
            .iter()
            .map(|p| p.distribution.clone())
            .collect();
        let design = sample::design(&dists, spec.method, spec.seed, spec.samples, spec.indices);
        let sweep_spec = SweepSpec {
            axes: spec::axes(&spec, &design),
            compute: spec.compute,
            operating_speed: spec.operating_speed,
            attractors: spec.attractors,
        };
        let tag = format!("uncertainty {spec:?}");
        let sweep = SweepStudy::with_design(text, origin, folder, sweep_spec, design, &tag)
            .map_err(|e| match e {
                // the extremes of a parameter's samples, each alone, give an invalid study
                SweepError::Axis { axis, rule } => UncertaintyError::Rule {
                    key: axis.replacen("sweep.axes", "uncertainty.parameter", 1),
                    value: "its sampled range".into(),
                    rule: rule.replacen("value", "the sampled value", 1),
                },
                e => e.into(),
            })?;
        Ok(Self { spec, sweep })
    }

    /// Evaluations of the design.
    pub fn len(&self) -> usize {
        self.sweep.len()
    }

    /// Whether the design is empty (never, after validation).
    pub fn is_empty(&self) -> bool {
        self.sweep.is_empty()
    }
}

/// Runs (or resumes) the evaluations of the design: the sweep's [`sweep::run_cancellable`] over
/// the design's rows (records, resume, shards and threads as there).
pub fn run(
    study: &UncertaintyStudy,
    opts: &SweepOptions,
    progress: Option<&(dyn Fn(&Progress) + Sync)>,
    cancel: Option<&(dyn Fn() -> bool + Sync)>,
) -> Result<SweepResults, UncertaintyError> {
    Ok(sweep::run_cancellable(
        &study.sweep,
        opts,
        progress,
        cancel,
    )?)
}

/// Joins records files (shards, or a partial run) of `study`: [`sweep::merge`].
pub fn merge(
    study: &UncertaintyStudy,
    files: &[std::path::PathBuf],
) -> Result<sweep::Merged, UncertaintyError> {
    Ok(sweep::merge(&study.sweep, files)?)
}
