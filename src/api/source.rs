//! Where a study comes from: a file, TOML text, or a TOML table with the same structure.

use std::path::{Path, PathBuf};

use anyhow::anyhow;

use super::{user, Failure};
use crate::study::schema::StudyFile;
use crate::study::{self, Plan, StudyError};
use crate::sweep::SweepStudy;
use crate::uncertainty::UncertaintyStudy;

/// A study's TOML text, the name its messages give it, and the folder its relative paths
/// (geometry tables, profiles) are taken from (`None`: the current directory).
#[derive(Clone, Debug)]
pub struct Source {
    /// TOML text
    pub text: String,
    /// named in error messages (the file's path, or e.g. "`<TOML text>`")
    pub origin: String,
    /// folder of relative paths
    pub folder: Option<PathBuf>,
}

impl Source {
    /// Reads a study file (an unreadable file is a user error naming the path).
    pub fn file(path: &Path) -> Result<Self, Failure> {
        let text = std::fs::read_to_string(path).map_err(|source| {
            user(StudyError::Io {
                path: path.display().to_string(),
                source,
            })
        })?;
        Ok(Self {
            text,
            origin: path.display().to_string(),
            folder: path.parent().map(Path::to_path_buf),
        })
    }

    /// Study text; relative paths in it are taken from the current directory.
    pub fn text(text: &str, origin: &str) -> Self {
        Self {
            text: text.to_string(),
            origin: origin.to_string(),
            folder: None,
        }
    }

    /// A study given as a TOML table with the study file's structure (a Python dict): numbers
    /// in SI or strings with units, exactly as in a file; relative paths in it are taken from
    /// the current directory.
    pub fn table(table: &toml::Table, origin: &str) -> Result<Self, Failure> {
        let text = toml::to_string(table)
            .map_err(|e| user(anyhow!("{origin}: cannot be written as TOML: {e}")))?;
        Ok(Self::text(&text, origin))
    }

    /// The validated plan.
    pub fn plan(&self) -> Result<Plan, Failure> {
        study::parse_in(&self.text, &self.origin, self.folder.as_deref()).map_err(user)
    }

    /// The study file as written (its raw `[sweep]` and `[trade]` tables with it).
    pub fn file_schema(&self) -> Result<StudyFile, Failure> {
        toml::from_str(&self.text).map_err(|e| {
            user(StudyError::Syntax {
                path: self.origin.clone(),
                message: e.to_string(),
            })
        })
    }

    /// The study with its `[sweep]` section.
    pub fn sweep_study(&self) -> Result<SweepStudy, Failure> {
        SweepStudy::parse_in(&self.text, &self.origin, self.folder.as_deref())
            .map_err(super::sweep_failure)
    }

    /// The study with its `[uncertainty]` section.
    pub fn uncertainty_study(&self) -> Result<UncertaintyStudy, Failure> {
        UncertaintyStudy::parse_in(&self.text, &self.origin, self.folder.as_deref())
            .map_err(super::uncertainty_failure)
    }
}
