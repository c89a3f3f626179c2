//! A study with its sweep: the base plan and model, each point's validated plan, the
//! fingerprint, and reuse of the contact table between points.

use crate::contact::table::ContactTable;
use crate::model::Vehicle;
use crate::study::schema::{Quantity, StudyFile};
use crate::study::{self, Plan};

use super::spec::{resolve, search_by_default, Axis, SweepSpec, SWEEP_KEYS};
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
    /// explicit points (each the axis values in SI, in axis order) in place of the grid of
    /// `spec` (an uncertainty study's sample design); `None` = the grid
    design: Option<std::sync::Arc<[Vec<f64>]>>,
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
    set_value(t, key, toml::Value::Float(value));
}

/// Sets a dotted key to any TOML value, creating sub-tables as needed.
fn set_value(t: &mut toml::Table, key: &str, value: toml::Value) {
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
    cur.insert(last.to_string(), value);
}

/// Sets an axis's key to value `v`: the SI number, or for a file axis the file it indexes.
fn set_axis(t: &mut toml::Table, axis: &Axis, v: f64) -> Result<(), study::StudyError> {
    if axis.files.is_empty() {
        set_key(t, &axis.key, v);
        return Ok(());
    }
    let file = axis.file(v).ok_or_else(|| study::StudyError::Rule {
        key: axis.key.clone(),
        value: v.to_string(),
        rule: format!(
            "is not the index of one of its {} files (a records file of another design?)",
            axis.files.len()
        ),
    })?;
    set_value(t, &axis.key, toml::Value::String(file.to_string()));
    Ok(())
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

fn syntax(origin: &str, e: &dyn std::fmt::Display) -> SweepError {
    SweepError::Study(study::StudyError::Syntax {
        path: origin.to_string(),
        message: e.to_string(),
    })
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
        let spec = |file: &StudyFile, base: &Plan| {
            let section = file.sweep.as_ref().ok_or_else(|| SweepError::NoSweep {
                path: origin.to_string(),
            })?;
            resolve(section, search_by_default(&base.vehicle))
        };
        let s = Self::build(text, origin, folder, spec, None)?;
        s.check_axis_values()?;
        Ok(s)
    }

    /// A study evaluated at explicit points rather than the grid of a `[sweep]` section: point
    /// `id` sets the keys of `axes` (whose `values` are not a grid here; they are only
    /// checked, each alone, to give a valid study) to `design[id]`. `tag` describes how the
    /// design was made and enters the fingerprint, so records of another design are refused.
    pub fn with_design(
        text: &str,
        origin: &str,
        folder: Option<&std::path::Path>,
        spec: SweepSpec,
        design: Vec<Vec<f64>>,
        tag: &str,
    ) -> Result<Self, SweepError> {
        let mut s = Self::build(text, origin, folder, |_, _| Ok(spec), Some(tag))?;
        s.check_axis_values()?;
        s.design = Some(design.into());
        Ok(s)
    }

    /// The study, its table without the analysis sections, the base model and the fingerprint
    /// (of the sweep's axes, compute and V_NL method, and `tag` when given); `spec` makes the
    /// axes from the study file and its plan once the study itself is valid.
    fn build(
        text: &str,
        origin: &str,
        folder: Option<&std::path::Path>,
        spec: impl FnOnce(&StudyFile, &Plan) -> Result<SweepSpec, SweepError>,
        tag: Option<&str>,
    ) -> Result<Self, SweepError> {
        let base = study::parse_in(text, origin, folder).map_err(SweepError::Study)?;
        let mut table: toml::Table = toml::from_str(text).map_err(|e| syntax(origin, &e))?;
        let file: StudyFile = toml::from_str(text).map_err(|e| syntax(origin, &e))?;
        let spec = spec(&file, &base)?;
        table.remove("sweep");
        table.remove("trade");
        table.remove("uncertainty");
        normalise(&mut table);
        let base_model = base.model().map_err(|e| SweepError::Model(e.to_string()))?;
        let mut normal = base.clone();
        normal.description.clear();
        // the method enters only when it is the search, so records of fast-form sweeps written
        // before the key existed still resume
        let mut print = format!("{normal:?}|{:?}|{:?}", spec.axes, spec.compute);
        if spec.attractors && spec.compute.nonlinear {
            print.push_str("|search");
        }
        if let Some(t) = tag {
            print = format!("{print}|{t}");
        }
        Ok(Self {
            base,
            spec,
            fingerprint: format!("{:016x}", fnv1a(&print)),
            curve: file.curve,
            design: None,
            table,
            base_model,
            folder: folder.map(std::path::Path::to_path_buf),
            text: text.to_string(),
            origin: origin.to_string(),
        })
    }

    /// Number of points: the design's rows, or the grid's size.
    pub fn len(&self) -> usize {
        self.design
            .as_ref()
            .map_or_else(|| self.spec.len(), |d| d.len())
    }

    /// Whether there is no point (never, after validation).
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Axis values (SI, in axis order) of point `id`: the design's row, or the grid point's.
    pub fn values(&self, id: usize) -> Vec<f64> {
        match &self.design {
            Some(d) => d.get(id).cloned().unwrap_or_default(),
            None => self.spec.values(id),
        }
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
                let shown = match a.file(*v) {
                    Some(f) => format!("{f:?}"),
                    None => format!("{v} {}", a.dim.si_unit()).trim_end().to_string(),
                };
                set_axis(&mut t, a, *v)
                    .and_then(|()| self.plan_of(t))
                    .map_err(|e| SweepError::Axis {
                        axis: format!("sweep.axes[{i}] ({})", a.key),
                        rule: format!("value {shown} gives an invalid study: {e}"),
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
        self.plan_with(&self.values(id))
    }

    /// The validated plan with each axis key set to `values` (SI, in axis order).
    pub fn plan_with(&self, values: &[f64]) -> Result<Plan, study::StudyError> {
        let mut t = self.table.clone();
        for (a, v) in self.spec.axes.iter().zip(values) {
            set_axis(&mut t, a, *v)?;
        }
        self.plan_of(t)
    }

    /// The validated plan of the study with each `(key, value)` set (SI values of sweepable
    /// keys, see [`super::SWEEP_KEYS`]).
    pub fn point_plan_at(&self, values: &[(&str, f64)]) -> Result<Plan, study::StudyError> {
        let mut t = self.table.clone();
        for (k, v) in values {
            set_key(&mut t, k, *v);
        }
        self.plan_of(t)
    }

    /// Whether a plan's contact tables are the base study's (they are a function of the
    /// geometries, the wheelsets' own included, and the table specification only).
    pub fn reuses_table(&self, plan: &Plan) -> bool {
        plan.contact.geometry == self.base.contact.geometry
            && plan.contact.wheelsets == self.base.contact.wheelsets
            && plan.table_spec() == self.base.table_spec()
    }

    /// The model of a point's plan. When [`Self::reuses_table`], the contact tables of a spare
    /// model from `spares` (or copies of the base model's) are reused: they are not rebuilt.
    /// Otherwise every table is built again, the wheelsets' own too.
    pub fn model(&self, plan: &Plan, spares: &Spares) -> Result<Vehicle, study::ModelError> {
        if !self.reuses_table(plan) {
            let table = ContactTable::build(&plan.contact.geometry, &plan.table_spec())?;
            return plan.model_with(table);
        }
        let (table, own) = spares.take().map_or_else(
            || {
                (
                    self.base_model.contact.table.clone(),
                    self.base_model.wheelset_tables().to_vec(),
                )
            },
            |m| {
                let own = m.wheelset_tables().to_vec();
                (m.contact.table, own)
            },
        );
        plan.model_with_tables(table, own)
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
