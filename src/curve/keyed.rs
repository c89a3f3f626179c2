//! A study with one key set to any value: the plan and model at each value of the design key,
//! by the same rewrite a sweep point uses (the study's TOML with the key set, validated by the
//! study's own rules), reusing the contact table when the key does not change the geometry.

use std::path::{Path, PathBuf};

use crate::contact::table::{ContactTable, TableError};
use crate::model::Vehicle;
use crate::study::schema::StudyFile;
use crate::study::{self, Plan};
use crate::sweep::study::{normalise, set_key};

use super::CurveError;

/// A study whose design key can be set to any value.
#[derive(Clone, Debug)]
pub struct KeyedStudy {
    /// the study as written (the key at its own value)
    pub base: Plan,
    /// the dotted study key
    pub key: String,
    /// the study's TOML without `[sweep]`, `[trade]` and `[curve]`, quantities in SI
    table: toml::Table,
    /// the base study's model (its contact table is reused)
    base_model: Vehicle,
    folder: Option<PathBuf>,
}

impl KeyedStudy {
    /// The study `text` (its relative paths taken from `folder`) with `key` free. The key is
    /// not checked here (the `[curve]` section's resolution does that).
    pub fn new(
        text: &str,
        origin: &str,
        folder: Option<&Path>,
        key: &str,
    ) -> Result<Self, CurveError> {
        let base = study::parse_in(text, origin, folder).map_err(CurveError::Study)?;
        let mut table: toml::Table = toml::from_str(text).map_err(|e| {
            CurveError::Study(study::StudyError::Syntax {
                path: origin.to_string(),
                message: e.to_string(),
            })
        })?;
        for section in ["sweep", "trade", "curve"] {
            table.remove(section);
        }
        normalise(&mut table);
        let base_model = base.model().map_err(|e| CurveError::Model {
            parameter: f64::NAN,
            message: format!("the study as written: {e}"),
        })?;
        Ok(Self {
            base,
            key: key.to_string(),
            table,
            base_model,
            folder: folder.map(Path::to_path_buf),
        })
    }

    /// The key's value in the study as written (SI), if the study sets it.
    pub fn own_value(&self) -> Option<f64> {
        let mut cur = &self.table;
        let mut parts = self.key.split('.').peekable();
        while let Some(p) = parts.next() {
            match (cur.get(p)?, parts.peek()) {
                (toml::Value::Table(t), Some(_)) => cur = t,
                (toml::Value::Float(v), None) => return Some(*v),
                (toml::Value::Integer(v), None) => return Some(*v as f64),
                _ => return None,
            }
        }
        None
    }

    /// The validated plan with the key set to `value` (SI). When the key leaves the sections
    /// the contact plan is built from (`[contact]`, `[wheelset]`, `[flange]`) as written, the
    /// base study's contact plan is reused: reading and sampling the geometry again was a
    /// tenth of a bogie's fold-curve run, and profile geometries cost far more.
    pub fn plan_at(&self, value: f64) -> Result<Plan, study::StudyError> {
        let mut t = self.table.clone();
        set_key(&mut t, &self.key, value);
        let same_contact = ["contact", "wheelset", "flange"]
            .iter()
            .all(|s| t.get(*s) == self.table.get(*s));
        let file: StudyFile = toml::Value::Table(t)
            .try_into()
            .map_err(|e: toml::de::Error| study::StudyError::Syntax {
                path: self.base.name.clone(),
                message: e.to_string(),
            })?;
        let contact = same_contact.then_some(&self.base.contact);
        study::plan_with(file, self.folder.as_deref(), contact)
    }

    /// The model with the key set to `value`: the base study's contact table when the
    /// geometry and table specification are unchanged, else a new one.
    pub fn model_at(&self, value: f64) -> Result<Vehicle, CurveError> {
        let failed = |message: String| CurveError::Model {
            parameter: value,
            message,
        };
        let plan = self
            .plan_at(value)
            .map_err(|e| failed(format!("{} = {value}: {e}", self.key)))?;
        let (table, own) = if plan.contact.geometry == self.base.contact.geometry
            && plan.contact.wheelsets == self.base.contact.wheelsets
            && plan.table_spec() == self.base.table_spec()
        {
            (
                self.base_model.contact.table.clone(),
                self.base_model.wheelset_tables().to_vec(),
            )
        } else {
            let geometry = |e: TableError| failed(format!("contact geometry: {e}"));
            (
                ContactTable::build(&plan.contact.geometry, &plan.table_spec())
                    .map_err(geometry)?,
                plan.wheelset_tables().map_err(geometry)?,
            )
        };
        plan.model_with_tables(table, own)
            .map_err(|e| failed(format!("model: {e}")))
    }
}
