//! A study with its sweep: the base plan and model, each point's validated plan, the
//! fingerprint, and reuse of the contact table between points.

use crate::contact::table::ContactTable;
use crate::model::Vehicle;
use crate::study::schema::{Quantity, StudyFile};
use crate::study::{self, Plan};

use super::spec::{resolve, SweepSpec, SWEEP_KEYS};
use super::SweepError;

/// A study with its sweep: the base plan and model, and the means to make each point's plan.
#[derive(Clone, Debug)]
pub struct SweepStudy {
    /// the study without the sweep applied
    pub base: Plan,
    /// the resolved sweep
    pub spec: SweepSpec,
    /// hash of the normalised plan and sweep definition (16 hex digits)
    pub fingerprint: String,
    /// the study's `[curve]` section, when it has one (the sweep's figure draws its curves
    /// when its key is the sweep's one axis)
    pub curve: Option<crate::study::schema::CurveSection>,
    table: toml::Table,
    base_model: Vehicle,
    /// folder that relative paths in the study are taken from
    folder: Option<std::path::PathBuf>,
    /// the study file's text and its name in messages
    text: String,
    origin: String,
}

/// Sets a dotted key in a TOML table, creating sub-tables as needed.
pub(crate) fn set_key(t: &mut toml::Table, key: &str, value: f64) {
    let mut parts: Vec<&str> = key.split('.').collect();
    let last = parts.pop().unwrap_or(key);
    let mut cur = t;
    for p in parts {
        let entry = cur
            .entry(p.to_string())
            .or_insert_with(|| toml::Value::Table(toml::Table::new()));
        if !entry.is_table() {
            *entry = toml::Value::Table(toml::Table::new());
        }
        cur = match entry {
            toml::Value::Table(t) => t,
            _ => unreachable!("made a table above"),
        };
    }
    cur.insert(last.to_string(), toml::Value::Float(value));
}

/// Replaces each sweepable quantity written with a unit by its SI number (the value the
/// study's own validation gives), so that the per-point plans do not parse units again.
pub(crate) fn normalise(t: &mut toml::Table) {
    for (key, dim) in SWEEP_KEYS {
        let mut cur = &mut *t;
        let mut parts = key.split('.').peekable();
        while let Some(p) = parts.next() {
            if parts.peek().is_none() {
                if let Some(toml::Value::String(text)) = cur.get(p) {
                    let q = Quantity::Text(text.clone());
                    let v = if *key == "contact.conicity" {
                        study::conicity(&q).ok()
                    } else {
                        study::quantity(key, &q, *dim).ok()
                    };
                    if let Some(v) = v {
                        cur.insert(p.to_string(), toml::Value::Float(v));
                    }
                }
                break;
            }
            match cur.get_mut(p) {
                Some(toml::Value::Table(next)) => cur = next,
                _ => break,
            }
        }
    }
}

/// FNV-1a 64-bit hash (stable across platforms and Rust versions).
fn fnv1a(text: &str) -> u64 {
    text.bytes().fold(0xcbf2_9ce4_8422_2325_u64, |h, b| {
        (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3)
    })
}

impl SweepStudy {
    /// Reads a study file with a `[sweep]` section.
    pub fn load(path: &std::path::Path) -> Result<Self, SweepError> {
        let text = std::fs::read_to_string(path).map_err(|source| {
            SweepError::Study(study::StudyError::Io {
                path: path.display().to_string(),
                source,
            })
        })?;
        Self::parse_in(&text, &path.display().to_string(), path.parent())
    }

    /// Parses study text with a `[sweep]` section; `origin` names it in messages; relative
    /// paths in it (geometry tables, profiles) are taken from `origin`'s folder (see
    /// [`study::parse`]).
    pub fn parse(text: &str, origin: &str) -> Result<Self, SweepError> {
        Self::parse_in(text, origin, std::path::Path::new(origin).parent())
    }

    /// As [`Self::parse`], with relative paths taken from `folder` (the study file's folder).
    pub fn parse_in(
        text: &str,
        origin: &str,
        folder: Option<&std::path::Path>,
    ) -> Result<Self, SweepError> {
        let syntax = |e: &dyn std::fmt::Display| {
            SweepError::Study(study::StudyError::Syntax {
                path: origin.to_string(),
                message: e.to_string(),
            })
        };
        let base = study::parse_in(text, origin, folder).map_err(SweepError::Study)?;
        let mut table: toml::Table = toml::from_str(text).map_err(|e| syntax(&e))?;
        let file: StudyFile = toml::from_str(text).map_err(|e| syntax(&e))?;
        let section = file.sweep.ok_or_else(|| SweepError::NoSweep {
            path: origin.to_string(),
        })?;
        let spec = resolve(&section)?;
        table.remove("sweep");
        table.remove("trade");
        normalise(&mut table);
        let base_model = base.model().map_err(|e| SweepError::Model(e.to_string()))?;
        let mut normal = base.clone();
        normal.description.clear();
        let fingerprint = format!(
            "{:016x}",
            fnv1a(&format!("{normal:?}|{:?}|{:?}", spec.axes, spec.compute))
        );
        let s = Self {
            base,
            spec,
            fingerprint,
            curve: file.curve,
            table,
            base_model,
            folder: folder.map(std::path::Path::to_path_buf),
            text: text.to_string(),
            origin: origin.to_string(),
        };
        s.check_axis_values()?;
        Ok(s)
    }

    /// The study file's text, its name in messages and the folder its relative paths are
    /// taken from.
    pub fn source(&self) -> (&str, &str, Option<&std::path::Path>) {
        (&self.text, &self.origin, self.folder.as_deref())
    }

    /// Every value of each axis alone must give a valid study (names the key otherwise).
    fn check_axis_values(&self) -> Result<(), SweepError> {
        for (i, a) in self.spec.axes.iter().enumerate() {
            for v in &a.values {
                let mut t = self.table.clone();
                set_key(&mut t, &a.key, *v);
                self.plan_of(t).map_err(|e| SweepError::Axis {
                    axis: format!("sweep.axes[{i}] ({})", a.key),
                    rule: format!(
                        "value {} gives an invalid study: {e}",
                        format!("{v} {}", a.dim.si_unit()).trim_end()
                    ),
                })?;
            }
        }
        Ok(())
    }

    fn plan_of(&self, t: toml::Table) -> Result<Plan, study::StudyError> {
        let file: StudyFile = toml::Value::Table(t)
            .try_into()
            .map_err(|e: toml::de::Error| study::StudyError::Syntax {
                path: self.base.name.clone(),
                message: e.to_string(),
            })?;
        study::plan(file, self.folder.as_deref())
    }

    /// The validated plan of point `id`: the study with each axis key set to its value.
    pub fn point_plan(&self, id: usize) -> Result<Plan, study::StudyError> {
        let mut t = self.table.clone();
        for (a, v) in self.spec.axes.iter().zip(self.spec.values(id)) {
            set_key(&mut t, &a.key, v);
        }
        self.plan_of(t)
    }

    /// Whether a plan's contact table is the base study's (it is a function of the geometry
    /// and the table specification only).
    pub fn reuses_table(&self, plan: &Plan) -> bool {
        plan.contact.geometry == self.base.contact.geometry
            && plan.table_spec() == self.base.table_spec()
    }

    /// The model of a point's plan. When [`Self::reuses_table`], the contact table of a spare
    /// model from `spares` (or a copy of the base model's) is reused: it is not rebuilt.
    pub fn model(&self, plan: &Plan, spares: &Spares) -> Result<Vehicle, study::ModelError> {
        let table = if self.reuses_table(plan) {
            spares.take().map_or_else(
                || self.base_model.contact.table.clone(),
                |m| m.contact.table,
            )
        } else {
            ContactTable::build(&plan.contact.geometry, &plan.table_spec())?
        };
        plan.model_with(table)
    }
}

/// Models with the base study's contact table, kept between points to save copying it.
#[derive(Debug, Default)]
pub struct Spares(std::sync::Mutex<Vec<Vehicle>>);

impl Spares {
    fn take(&self) -> Option<Vehicle> {
        self.0.lock().unwrap_or_else(|e| e.into_inner()).pop()
    }

    /// Returns a model whose table is the base study's.
    pub fn put(&self, m: Vehicle) {
        self.0.lock().unwrap_or_else(|e| e.into_inner()).push(m);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ratio_conicity_and_units_on_the_axis_are_si() {
        let text = crate::study::DEFAULT_STUDY.to_string()
            + "\n[sweep]\naxes = [ { key = \"contact.conicity\", from = \"1:40\", to = \"1:20\", count = 2 },\n\
               { key = \"flange.clearance\", from = \"5 mm\", to = \"10 mm\", count = 2 } ]\n";
        // the seed has no [flange]: clearance alone is not a valid flange
        let err = SweepStudy::parse(&text, "t").expect_err("no flange stiffness");
        assert!(err.to_string().contains("flange.clearance"), "{err}");
        let text = text.replace("flange.clearance", "suspension.half_spring_spacing");
        let s = SweepStudy::parse(&text, "t").expect("valid");
        assert_eq!(s.spec.axes[0].values, vec![1.0 / 40.0, 1.0 / 20.0]);
        assert_eq!(s.spec.axes[1].values, vec![5e-3, 10e-3]);
        let p = s.point_plan(3).expect("plan");
        assert_eq!(p.contact.geometry.conicity(), 0.05);
        assert_eq!(p.suspension.half_spring_spacing, 10e-3);
        // everything else is the study's
        assert_eq!(p.wheelset, s.base.wheelset);
    }
}
