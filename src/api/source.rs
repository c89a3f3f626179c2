//! Where a study comes from: a file, TOML text, or a JSON object with the same structure.

use std::path::{Path, PathBuf};

use anyhow::anyhow;
use serde_json::Value;

use super::{user, Failure};
use crate::study::schema::StudyFile;
use crate::study::{self, Plan, StudyError};
use crate::sweep::SweepStudy;

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

    /// A JSON object with the study file's structure (a Python dict): numbers in SI or strings
    /// with units, exactly as in a file. `null` is refused, naming its key.
    pub fn json(value: &Value, origin: &str) -> Result<Self, Failure> {
        let table = match to_toml(value, "")? {
            toml::Value::Table(t) => t,
            _ => return Err(user(anyhow!("{origin}: a study must be a table (a dict)"))),
        };
        let text = toml::to_string(&table)
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
}

/// JSON to TOML; the key path names a `null` (TOML has none) or a number JSON cannot hold.
fn to_toml(v: &Value, key: &str) -> Result<toml::Value, Failure> {
    let at = |k: &str| {
        if key.is_empty() {
            k.to_string()
        } else {
            format!("{key}.{k}")
        }
    };
    Ok(match v {
        Value::Null => {
            return Err(user(anyhow!(
            "{key} = None: a study value must be a number, a string, a boolean, a list or a table"
        )))
        }
        Value::Bool(b) => toml::Value::Boolean(*b),
        Value::Number(n) => match (n.as_i64(), n.as_f64()) {
            (Some(i), _) => toml::Value::Integer(i),
            (None, Some(f)) => toml::Value::Float(f),
            (None, None) => return Err(user(anyhow!("{key} = {n}: not a number TOML can hold"))),
        },
        Value::String(s) => toml::Value::String(s.clone()),
        Value::Array(a) => toml::Value::Array(
            a.iter()
                .enumerate()
                .map(|(i, x)| to_toml(x, &format!("{key}[{i}]")))
                .collect::<Result<_, _>>()?,
        ),
        Value::Object(m) => toml::Value::Table(
            m.iter()
                .map(|(k, x)| Ok((k.clone(), to_toml(x, &at(k))?)))
                .collect::<Result<_, Failure>>()?,
        ),
    })
}
