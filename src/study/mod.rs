//! Study files: read (schema), convert units once, check the physics, fill defaults (plan).
//!
//! The plan is entirely SI; nothing after it sees strings or millimetres. The file format is
//! `docs/studies.md`; [`keys::study_keys`] lists every key the schema accepts (the guide's
//! documentation test demands each be documented). [`DEFAULT_STUDY`] is the seed study and
//! [`HUNTING_STUDY`] the seed made to hunt, both embedded in the binary for the first run.

mod attractors;
pub mod entries;
pub mod keys;
pub mod plausible;
mod profiles;
pub mod schema;
mod tabulated;
pub mod units;
mod vehicle;
mod wheelsets;

use std::path::Path;

use crate::bifurcation::BifurcationOptions;
use crate::contact::creep::CreepLaw;
use crate::contact::geometry::{Geometry, Nominal};
use crate::contact::kalker::CreepCoefficients;
use crate::contact::table::{
    ContactTable, CreepSource, Elastic, Extrapolation, TableError, TableSpec,
};
use crate::model::{
    layouts, Flange, PrimaryVertical, Suspension, Vehicle, VehicleSpec, Wheelset, WheelsetParams,
};
use crate::stability::LinearOptions;
use crate::system::ode::Method;
pub use attractors::AttractorSettings;
use schema::{Quantity, StudyFile};
use units::{parse_quantity, Dimension, UnitProblem};
pub use wheelsets::WheelsetGeometry;

/// The seed study (docs/model.md §10), embedded so that `critspeed run` works with no file.
pub const DEFAULT_STUDY: &str = include_str!("../../studies/seed.toml");

/// The seed wheelset made to hunt near 70 m/s (`studies/seed-hunting.toml`), embedded for the
/// first run (`critspeed run` without a study).
pub const HUNTING_STUDY: &str = include_str!("../../studies/seed-hunting.toml");

/// A problem with a study file. Every variant names the key and the offending value.
#[derive(Debug, thiserror::Error)]
pub enum StudyError {
    #[error("cannot read study file {path}: {source}")]
    Io {
        path: String,
        source: std::io::Error,
    },
    #[error("study file {path} is not valid: {message}")]
    Syntax { path: String, message: String },
    #[error("{key} = {value:?}: {problem}; expected {}", .dim.expectation())]
    Unit {
        key: String,
        value: String,
        dim: Dimension,
        problem: UnitProblem,
    },
    #[error("{key} = {value}: {rule}")]
    Rule {
        key: String,
        value: String,
        rule: String,
    },
    #[error("{key} is missing: {why}")]
    Missing { key: String, why: String },
    #[error("contact.geometry_table: {0}")]
    Table(crate::contact::tabulated::TabulatedError),
    #[error("{key}: {source}")]
    Profile {
        key: String,
        source: crate::contact::profile::ProfileError,
    },
    #[error("{key} = {value:?} is not one of {allowed}")]
    Choice {
        key: String,
        value: String,
        allowed: &'static str,
    },
}

/// Contact settings in SI with defaults filled.
#[derive(Clone, Debug, PartialEq)]
pub struct ContactPlan {
    /// geometry
    pub geometry: Geometry,
    /// the study's creep law (default Shen–Hedrick–Elkins, μ = 0.3)
    pub creep_law: CreepLaw,
    /// spin creepage on (default true)
    pub spin: bool,
    /// elastic constants (defaults: E = 210 GPa, ν = 0.3, G = E/(2(1+ν)))
    pub elastic: Elastic,
    /// rail head radius for the Hertz patch (m), if known
    pub rail_head_radius: Option<f64>,
    /// creep coefficients, given or from Hertz + Kalker
    pub creep: CreepSource,
    /// half-width of the tabulated geometry (m)
    pub lateral_range: f64,
    /// geometry table nodes
    pub table_points: usize,
    /// what the analyses may do beyond the table's valid range (default: cut there)
    pub extrapolate: Extrapolation,
    /// wheelsets with their own geometry (`[[contact.wheelset]]`); the others have `geometry`
    pub wheelsets: Vec<WheelsetGeometry>,
}

impl ContactPlan {
    /// The half-width (m) of the lateral range where the contact geometry is genuine: the
    /// tabulated range of a table, a profile solve or a cone on a circular rail head, beyond
    /// which the table is extended linearly; `None` for the cone on knife-edge rails, whose
    /// linear extension is exact. This is the limit the analyses cut branches and attractors
    /// at ([`Self::analysis_limit`]).
    pub fn valid_half_width(&self) -> Option<f64> {
        let cones = std::iter::once(&self.geometry)
            .chain(self.wheelsets.iter().map(|w| &w.geometry))
            .all(|g| matches!(g, Geometry::Cone { .. }));
        (!cones).then_some(self.lateral_range)
    }

    /// The geometry of the wheelset at `position` (1-based, front to rear): its own, else
    /// `[contact]`'s.
    pub fn geometry_at(&self, position: usize) -> &Geometry {
        self.wheelsets
            .iter()
            .find(|w| w.positions.contains(&position))
            .map_or(&self.geometry, |w| &w.geometry)
    }

    /// The half-width (m) where the analyses cut a branch or an attractor: the valid range,
    /// unless the study asks for extrapolation (`contact.extrapolate = "linear"`).
    pub fn analysis_limit(&self) -> Option<f64> {
        match self.extrapolate {
            Extrapolation::Linear => None,
            Extrapolation::None => self.valid_half_width(),
        }
    }
}

/// A validated study: everything in SI, defaults filled.
#[derive(Clone, Debug, PartialEq)]
pub struct Plan {
    /// study name (also the output folder name)
    pub name: String,
    /// description
    pub description: String,
    /// wheelset
    pub wheelset: WheelsetParams,
    /// the primary suspension per side (docs/model.md §7), wheelset to frame (to the track for the
    /// wheelset layout)
    pub suspension: Suspension,
    /// the primary's vertical stiffness, damping and height (frame roll only)
    pub primary_vertical: PrimaryVertical,
    /// the layout and its bodies beyond the wheelsets (docs/model.md §11)
    pub vehicle: VehicleSpec,
    /// contact
    pub contact: ContactPlan,
    /// flange, if any
    pub flange: Option<Flange>,
    /// linear analysis options
    pub linear: LinearOptions,
    /// speeds of the spectrum output (root locus, damping plot)
    pub spectrum_points: usize,
    /// the `[bifurcation]` section, when the study has one
    pub bifurcation: Option<BifurcationOptions>,
    /// the `[attractors]` section, when the study has one
    pub attractors: Option<AttractorSettings>,
    /// values outside their plausible range ([`plausible`]): computed as given, and said
    pub warnings: Vec<plausible::Warning>,
}

/// Reads and validates a study file.
pub fn load(path: &Path) -> Result<Plan, StudyError> {
    let text = std::fs::read_to_string(path).map_err(|source| StudyError::Io {
        path: path.display().to_string(),
        source,
    })?;
    parse_in(&text, &path.display().to_string(), path.parent())
}

/// Parses and validates study text; `origin` names it in messages. Relative paths in the study
/// (geometry table, profiles) are taken from `origin`'s folder when `origin` is a file path,
/// else from the current directory.
pub fn parse(text: &str, origin: &str) -> Result<Plan, StudyError> {
    parse_in(text, origin, Path::new(origin).parent())
}

/// Parses and validates study text whose relative paths (the geometry table) are relative
/// to `folder` (the study file's folder; `None`: the current directory).
pub fn parse_in(text: &str, origin: &str, folder: Option<&Path>) -> Result<Plan, StudyError> {
    let file: StudyFile = toml::from_str(text).map_err(|e| StudyError::Syntax {
        path: origin.to_string(),
        message: e.to_string(),
    })?;
    plan(file, folder)
}

pub(crate) fn quantity(key: &str, q: &Quantity, dim: Dimension) -> Result<f64, StudyError> {
    let v = match q {
        Quantity::Number(v) => Ok(*v),
        Quantity::Text(t) => parse_quantity(t, dim),
    };
    let v = v.and_then(|v| {
        if v.is_finite() {
            Ok(v)
        } else {
            Err(UnitProblem::NotFinite)
        }
    });
    v.map_err(|problem| StudyError::Unit {
        key: key.to_string(),
        value: match q {
            Quantity::Number(v) => v.to_string(),
            Quantity::Text(t) => t.clone(),
        },
        dim,
        problem,
    })
}

/// A quantity that must satisfy `ok`, described by `rule`.
pub(crate) fn checked(
    key: &str,
    q: &Quantity,
    dim: Dimension,
    ok: impl Fn(f64) -> bool,
    rule: &str,
) -> Result<f64, StudyError> {
    let v = quantity(key, q, dim)?;
    if !ok(v) {
        return Err(StudyError::Rule {
            key: key.to_string(),
            value: format!("{} {}", plausible::si(v), dim.si_unit()),
            rule: rule.to_string(),
        });
    }
    plausible::meaningful(key, v)?;
    Ok(v)
}

pub(crate) fn positive(key: &str, q: &Quantity, dim: Dimension) -> Result<f64, StudyError> {
    checked(key, q, dim, |v| v > 0.0, "must be positive")
}

pub(crate) fn non_negative(key: &str, q: &Quantity, dim: Dimension) -> Result<f64, StudyError> {
    checked(key, q, dim, |v| v >= 0.0, "must not be negative")
}

/// A plain number (no unit) inside its key's meaningful range.
fn number(key: &str, v: f64) -> Result<f64, StudyError> {
    if !v.is_finite() {
        return Err(rule(key, v, "must be a finite number"));
    }
    plausible::meaningful(key, v).map(|()| v)
}

/// A count inside its key's meaningful range.
fn count(key: &str, n: usize) -> Result<usize, StudyError> {
    plausible::meaningful(key, n as f64).map(|()| n)
}

/// The cone slope: a number, or a ratio string such as "1:20" or "1/40".
pub(crate) fn conicity(q: &Quantity) -> Result<f64, StudyError> {
    const KEY: &str = "contact.conicity";
    let v = match q {
        Quantity::Text(t) if t.contains([':', '/']) => {
            let parts: Vec<&str> = t.split([':', '/']).map(str::trim).collect();
            let num = parts.first().and_then(|s| s.parse::<f64>().ok());
            let den = parts.get(1).and_then(|s| s.parse::<f64>().ok());
            match (num, den, parts.len()) {
                (Some(n), Some(d), 2) if d != 0.0 => n / d,
                _ => {
                    return Err(StudyError::Rule {
                        key: KEY.into(),
                        value: t.clone(),
                        rule: "a ratio must read like \"1:20\"".into(),
                    })
                }
            }
        }
        _ => quantity(KEY, q, Dimension::Dimensionless)?,
    };
    if v > 0.0 && v < 1.0 {
        Ok(v)
    } else {
        Err(StudyError::Rule {
            key: KEY.into(),
            value: plausible::si(v),
            rule: "the cone slope must lie in (0, 1)".into(),
        })
    }
}

pub(crate) fn plan(f: StudyFile, folder: Option<&Path>) -> Result<Plan, StudyError> {
    plan_with(f, folder, None)
}

/// [`plan`], with the contact plan `contact` taken as it is instead of built from the file's
/// `[contact]`, `[wheelset]` and `[flange]` sections: for a study that differs from the one
/// `contact` was built for only elsewhere (a design key's value), where building it again
/// would read and sample the same geometry.
pub(crate) fn plan_with(
    f: StudyFile,
    folder: Option<&Path>,
    contact: Option<&ContactPlan>,
) -> Result<Plan, StudyError> {
    if f.name.is_empty()
        || !f
            .name
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || "-_.".contains(c))
        || f.name.starts_with('.')
    {
        return Err(StudyError::Rule {
            key: "name".into(),
            value: format!("{:?}", f.name),
            rule: "must be a non-empty folder name of letters, digits, '-', '_' or '.'".into(),
        });
    }
    let w = &f.wheelset;
    let wheelset = WheelsetParams {
        mass: positive("wheelset.mass", &w.mass, Dimension::Mass)?,
        yaw_inertia: positive("wheelset.yaw_inertia", &w.yaw_inertia, Dimension::Inertia)?,
        axle_load: positive("wheelset.axle_load", &w.axle_load, Dimension::Force)?,
        half_contact_distance: positive(
            "wheelset.half_contact_distance",
            &w.half_contact_distance,
            Dimension::Length,
        )?,
        rolling_radius: positive(
            "wheelset.rolling_radius",
            &w.rolling_radius,
            Dimension::Length,
        )?,
    };
    let suspension = vehicle::springs("suspension", f.suspension.springs())?;
    let flange = match &f.flange {
        Some(fl) => Some(Flange {
            clearance: positive("flange.clearance", &fl.clearance, Dimension::Length)?,
            stiffness: positive("flange.stiffness", &fl.stiffness, Dimension::Stiffness)?,
        }),
        None => None,
    };
    let contact = match contact {
        Some(c) => c.clone(),
        None => contact_plan(&f.contact, &wheelset, flange.as_ref(), folder)?,
    };
    let vehicle = vehicle::spec(&f)?;
    wheelsets::check_positions(&contact.wheelsets, wheelsets::wheelset_count(&vehicle))?;
    let primary_vertical = vehicle::primary_vertical(&f)?;
    // the wheelset layout's primary stop limits the wheelset's own y, which the contact
    // geometry covers up to its lateral range; on a bogie or car the stop's deflection is the
    // wheelset's y relative to its frame, which has no such bound
    if let (VehicleSpec::Wheelset, Some(stop)) = (&vehicle, &primary_vertical.bump_stop) {
        if stop.clearance >= contact.lateral_range {
            return Err(rule(
                "suspension.bump_stop_clearance",
                format!("{} m", plausible::si(stop.clearance)),
                &format!(
                    "must be below the contact geometry's lateral range {} m: on the wheelset \
                     layout the stop limits the wheelset's y, and a stop beyond the range never \
                     acts inside it",
                    plausible::si(contact.lateral_range)
                ),
            ));
        }
    }
    let (linear, spectrum_points) = linear_plan(f.linear.as_ref())?;
    let bifurcation = f
        .bifurcation
        .as_ref()
        .map(|b| bifurcation_plan(b, linear.speed_range))
        .transpose()?
        .map(|b| BifurcationOptions {
            geometry_limit: contact.analysis_limit(),
            ..b
        });
    let bifurcation_range = bifurcation
        .as_ref()
        .map_or(linear.speed_range, |b| b.speed_range);
    let attractors = f
        .attractors
        .as_ref()
        .map(|a| attractors::plan(a, bifurcation_range, contact.analysis_limit()))
        .transpose()?;
    let mut plan = Plan {
        name: f.name,
        description: f.description.unwrap_or_default(),
        wheelset,
        suspension,
        primary_vertical,
        vehicle,
        contact,
        flange,
        linear,
        spectrum_points,
        bifurcation,
        attractors,
        warnings: Vec::new(),
    };
    plan.warnings = plausible::warnings(&plan);
    Ok(plan)
}

pub(crate) fn rule(key: &str, value: impl std::fmt::Display, rule: &str) -> StudyError {
    StudyError::Rule {
        key: key.into(),
        value: value.to_string(),
        rule: rule.into(),
    }
}

fn bifurcation_plan(
    b: &schema::BifurcationSection,
    linear_range: (f64, f64),
) -> Result<BifurcationOptions, StudyError> {
    let mut o = BifurcationOptions::new(linear_range);
    if let Some([lo, hi]) = &b.speed_range {
        let lo = positive("bifurcation.speed_range[0]", lo, Dimension::Speed)?;
        let hi = positive("bifurcation.speed_range[1]", hi, Dimension::Speed)?;
        if hi <= lo {
            return Err(rule(
                "bifurcation.speed_range",
                format!("[{lo}, {hi}] m/s"),
                "the maximum must exceed the minimum",
            ));
        }
        o.speed_range = (lo, hi);
    }
    if let Some(q) = &b.max_amplitude {
        o.max_amplitude = positive("bifurcation.max_amplitude", q, Dimension::Length)?;
    }
    if let Some(r) = b.rtol {
        o.rtol = number("bifurcation.rtol", r)?;
    }
    if let Some(f) = b.floquet_rtol {
        let f = number("bifurcation.floquet_rtol", f)?;
        if !(f >= o.rtol && f <= 1e-4) {
            return Err(rule(
                "bifurcation.floquet_rtol",
                f,
                &format!(
                    "must lie in [rtol, 1e-4] = [{:e}, 1e-4] (the monodromy matrix is solved at \
                     least as tightly as Newton needs, never tighter than the cycles)",
                    o.rtol
                ),
            ));
        }
        o.floquet_rtol = Some(f);
    }
    if let Some(d) = b.ds_max {
        o.ds_max = number("bifurcation.ds_max", d)?;
    }
    if let Some(n) = b.max_points {
        o.max_points = count("bifurcation.max_points", n)?;
    }
    if let Some(n) = b.segments {
        o.segments = count("bifurcation.segments", n)?;
    }
    if let Some(s) = b.switch {
        o.switch = s;
    }
    if let Some(n) = b.max_branches {
        if !(1..=1000).contains(&n) {
            return Err(rule(
                "bifurcation.max_branches",
                n,
                "must lie in [1, 1000] (1: the branch from the Hopf point alone)",
            ));
        }
        o.max_branches = n;
    }
    if let Some(c) = &b.corrector {
        o.chord = match c.as_str() {
            "newton" => false,
            "chord" => true,
            _ => {
                return Err(rule(
                    "bifurcation.corrector",
                    format!("{c:?}"),
                    "must be \"newton\" (a linearisation at every iteration) or \"chord\" (a linearisation kept over the iterations after it)",
                ))
            }
        };
    }
    if let Some(m) = &b.integrator {
        o.integrator = match m.as_str() {
            "dopri5" => Method::DormandPrince5,
            "dop853" => Method::DormandPrince8,
            _ => {
                return Err(rule(
                    "bifurcation.integrator",
                    format!("{m:?}"),
                    "must be \"dopri5\" (Dormand-Prince 5(4), for contact tables, profiles and flanges) or \"dop853\" (Dormand-Prince 8(5,3), for smooth fields)",
                ))
            }
        };
    }
    Ok(o)
}

fn contact_plan(
    c: &schema::ContactSection,
    w: &WheelsetParams,
    flange: Option<&Flange>,
    folder: Option<&Path>,
) -> Result<ContactPlan, StudyError> {
    let rail_head_radius = c
        .rail_head_radius
        .as_ref()
        .map(|q| positive("contact.rail_head_radius", q, Dimension::Length))
        .transpose()?;
    let geometry = geometry_of(c, w, rail_head_radius, folder)?;
    let friction = match &c.friction {
        Some(q) => positive("contact.friction", q, Dimension::Dimensionless)?,
        None => 0.3,
    };
    let creep_law = match c.creep_law.as_deref().unwrap_or("shen") {
        "kalker" => CreepLaw::Kalker,
        "shen" => CreepLaw::Shen { friction },
        other => {
            return Err(StudyError::Choice {
                key: "contact.creep_law".into(),
                value: other.into(),
                allowed: "\"kalker\", \"shen\"",
            })
        }
    };
    let young_modulus = match &c.young_modulus {
        Some(q) => positive("contact.young_modulus", q, Dimension::Pressure)?,
        None => 210e9,
    };
    let poisson_ratio = match &c.poisson_ratio {
        Some(q) => checked(
            "contact.poisson_ratio",
            q,
            Dimension::Dimensionless,
            |v| v > 0.0 && v < 0.5,
            "must lie in (0, 0.5)",
        )?,
        None => 0.3,
    };
    let shear_modulus = match &c.shear_modulus {
        Some(q) => positive("contact.shear_modulus", q, Dimension::Pressure)?,
        None => young_modulus / (2.0 * (1.0 + poisson_ratio)),
    };
    let creep = match &c.creep_coefficients {
        Some(cc) => CreepSource::Given(CreepCoefficients {
            f11: positive("contact.creep_coefficients.f11", &cc.f11, Dimension::Force)?,
            f22: positive("contact.creep_coefficients.f22", &cc.f22, Dimension::Force)?,
            f23: non_negative(
                "contact.creep_coefficients.f23",
                &cc.f23,
                Dimension::ForceLength,
            )?,
            f33: non_negative(
                "contact.creep_coefficients.f33",
                &cc.f33,
                Dimension::ForceArea,
            )?,
        }),
        None if rail_head_radius.is_some() || c.geometry == "profiles" => CreepSource::Hertz,
        None if matches!(&geometry, Geometry::Table(t) if t.has_semi_axes()) => CreepSource::Hertz,
        None => {
            let table = match &geometry {
                Geometry::Table(t) => format!(
                    " (contact.geometry_table = {:?} has no Hertz semi-axes a, b)",
                    t.source
                ),
                _ => String::new(),
            };
            return Err(StudyError::Missing {
                key: "contact.creep_coefficients".into(),
                why: format!("without a rail_head_radius (or Hertz semi-axes in the geometry table) they cannot be computed from the Hertz patch{table}"),
            });
        }
    };
    let default_range = match &geometry {
        Geometry::Table(t) => t.half_width(),
        _ => flange.map_or(0.010, |f| (1.5 * f.clearance).max(0.010)),
    };
    let lateral_range = match &c.lateral_range {
        Some(q) => checked(
            "contact.lateral_range",
            q,
            Dimension::Length,
            |v| v > 0.0 && v < 0.5 * w.half_contact_distance,
            "must lie in (0, half_contact_distance/2)",
        )?,
        None if default_range >= 0.5 * w.half_contact_distance => {
            return Err(rule(
                "contact.lateral_range",
                format!("{default_range} m (the default: 1.5 x flange.clearance, or the table's half-width)"),
                "must lie in (0, half_contact_distance/2): give contact.lateral_range",
            ))
        }
        None => default_range,
    };
    if let Geometry::Table(t) = &geometry {
        if lateral_range > t.half_width() {
            return Err(rule(
                "contact.lateral_range",
                format!("{lateral_range} m"),
                &format!(
                    "must not exceed the half-width {} m of the table contact.geometry_table ({} covers y from {} m to {} m)",
                    t.half_width(),
                    t.source,
                    t.range().0,
                    t.range().1
                ),
            ));
        }
    }
    let table_points = c
        .table_points
        .map_or(Ok(401), |n| count("contact.table_points", n))?;
    let extrapolate = match c.extrapolate.as_deref() {
        None => Extrapolation::default(),
        Some(text) => Extrapolation::parse(text).ok_or_else(|| StudyError::Choice {
            key: "contact.extrapolate".into(),
            value: text.into(),
            allowed: Extrapolation::ALLOWED,
        })?,
    };
    let wheelsets = wheelsets::plan(&wheelsets::Common {
        section: c,
        wheelset: w,
        rail_head_radius,
        creep,
        lateral_range,
        folder,
    })?;
    Ok(ContactPlan {
        wheelsets,
        geometry,
        creep_law,
        spin: c.spin.unwrap_or(true),
        elastic: Elastic {
            young_modulus,
            poisson_ratio,
            shear_modulus,
        },
        rail_head_radius,
        creep,
        lateral_range,
        table_points,
        extrapolate,
    })
}

/// The contact geometry a `[contact]` section describes (the geometry keys; a misplaced one is
/// an error).
fn geometry_of(
    c: &schema::ContactSection,
    w: &WheelsetParams,
    rail_head_radius: Option<f64>,
    folder: Option<&Path>,
) -> Result<Geometry, StudyError> {
    let cone_slope = || match &c.conicity {
        Some(q) => conicity(q),
        None => Err(StudyError::Missing {
            key: "contact.conicity".into(),
            why: format!("geometry {:?} needs the cone slope", c.geometry),
        }),
    };
    let geometry = match c.geometry.as_str() {
        "cone" => Geometry::Cone {
            conicity: cone_slope()?,
        },
        "table" => tabulated::geometry(c, w, folder)?,
        "profiles" => profiles::geometry(
            c,
            folder.unwrap_or(Path::new("")),
            rail_head_radius.is_some(),
            w.half_contact_distance,
        )?,
        "cone-on-arc" => {
            let lambda = cone_slope()?;
            let radius = rail_head_radius.ok_or_else(|| StudyError::Missing {
                key: "contact.rail_head_radius".into(),
                why: "geometry \"cone-on-arc\" needs the rail head radius".into(),
            })?;
            // Default: the offset at which the arc's slope under the nominal contact point
            // equals the cone's, so that the centred contact is at the nominal point.
            let tangent_offset = radius * lambda.atan().sin();
            let crown_offset = match &c.crown_offset {
                Some(q) => checked(
                    "contact.crown_offset",
                    q,
                    Dimension::Length,
                    |v| v >= 0.0 && v < 0.5 * radius,
                    "must lie in [0, rail_head_radius/2)",
                )?,
                None => tangent_offset,
            };
            Geometry::ConeOnArc {
                conicity: lambda,
                rail_head_radius: radius,
                crown_offset,
            }
        }
        other => {
            return Err(StudyError::Choice {
                key: "contact.geometry".into(),
                value: other.into(),
                allowed: "\"cone\", \"cone-on-arc\", \"table\", \"profiles\"",
            })
        }
    };
    if c.geometry != "table" && c.geometry_table.is_some() {
        return Err(rule(
            "contact.geometry_table",
            "given",
            "only applies to geometry \"table\"",
        ));
    }
    profiles::only_for_profiles(c)?;
    if c.geometry == "cone" && c.crown_offset.is_some() {
        return Err(StudyError::Rule {
            key: "contact.crown_offset".into(),
            value: "given".into(),
            rule: "only applies to geometry \"cone-on-arc\"".into(),
        });
    }
    Ok(geometry)
}

fn linear_plan(l: Option<&schema::LinearSection>) -> Result<(LinearOptions, usize), StudyError> {
    let mut opts = LinearOptions::default();
    let mut spectrum_points = 300;
    if let Some(l) = l {
        if let Some([a, b]) = &l.speed_range {
            let lo = positive("linear.speed_range[0]", a, Dimension::Speed)?;
            let hi = positive("linear.speed_range[1]", b, Dimension::Speed)?;
            if hi <= lo {
                return Err(StudyError::Rule {
                    key: "linear.speed_range".into(),
                    value: format!("[{lo}, {hi}] m/s"),
                    rule: "the maximum must exceed the minimum".into(),
                });
            }
            opts.speed_range = (lo, hi);
        }
        if let Some(n) = l.grid_points {
            opts.grid_points = Some(count("linear.grid_points", n)?);
        }
        if let Some(n) = l.spectrum_points {
            spectrum_points = count("linear.spectrum_points", n)?;
        }
    }
    Ok((opts, spectrum_points))
}

impl Plan {
    /// The linear scan's grid points: the study's `linear.grid_points`, or the default of the
    /// model's path (512 for the wheelset's quartic scan, 64 refined for a vehicle's
    /// eigenvalue scan).
    pub fn grid_points(&self) -> usize {
        self.linear
            .grid_points
            .unwrap_or(if matches!(self.vehicle, VehicleSpec::Wheelset) {
                crate::stability::QUARTIC_GRID_POINTS
            } else {
                crate::stability::EIGEN_GRID_POINTS
            })
    }

    /// The bifurcation options: the study's `[bifurcation]` section, or the defaults over the
    /// linear speed range (with the contact geometry's range as the amplitude bound).
    pub fn bifurcation_options(&self) -> BifurcationOptions {
        self.bifurcation
            .clone()
            .unwrap_or_else(|| BifurcationOptions {
                geometry_limit: self.contact.analysis_limit(),
                ..BifurcationOptions::new(self.linear.speed_range)
            })
    }

    /// The attractor search's options: the study's `[attractors]` section, or its defaults, over
    /// the bifurcation speed range and amplitude bound, its default grid around the Hopf speed
    /// `v_h` (when known). The one place the commands, the API, the sweep's V_NL and the trade's
    /// settlement take them from.
    pub fn attractor_options(&self, v_h: Option<f64>) -> crate::attractors::AttractorOptions {
        let bo = self.bifurcation_options();
        self.attractors
            .clone()
            .unwrap_or_default()
            .options(bo.speed_range, v_h, bo.geometry_limit)
    }

    /// The geometry table specification of this plan.
    pub fn table_spec(&self) -> TableSpec {
        TableSpec {
            nominal: Nominal {
                rolling_radius: self.wheelset.rolling_radius,
                half_contact_distance: self.wheelset.half_contact_distance,
            },
            axle_load: self.wheelset.axle_load,
            elastic: self.contact.elastic,
            rail_head_radius: self.contact.rail_head_radius,
            creep: self.contact.creep,
            half_width: self.contact.lateral_range,
            nodes: self.contact.table_points,
        }
    }

    /// The single wheelset of docs/model.md §1–8 (its contact and primary): the contact part of every
    /// wheelset of the vehicle. Tabulates the contact geometry.
    pub fn wheelset_model(&self) -> Result<Wheelset, TableError> {
        let table = ContactTable::build(&self.contact.geometry, &self.table_spec())?;
        Ok(self.wheelset_with(table))
    }

    /// [`Self::wheelset_model`] with an already tabulated geometry.
    pub fn wheelset_with(&self, table: ContactTable) -> Wheelset {
        Wheelset {
            params: self.wheelset,
            suspension: self.suspension,
            creep_law: self.contact.creep_law,
            spin: self.contact.spin,
            flange: self.flange,
            table,
        }
    }

    /// Builds the model: tabulates the contact geometry and assembles the vehicle.
    pub fn model(&self) -> Result<Vehicle, ModelError> {
        let table = ContactTable::build(&self.contact.geometry, &self.table_spec())?;
        self.model_with(table)
    }

    /// [`Self::model`] with an already tabulated common geometry; the wheelsets' own
    /// geometries (`[[contact.wheelset]]`) are tabulated here.
    pub fn model_with(&self, table: ContactTable) -> Result<Vehicle, ModelError> {
        self.model_with_tables(table, self.wheelset_tables()?)
    }

    /// The wheelsets' own contact tables, front to rear (`None`: the common geometry), each
    /// geometry tabulated once. Empty without `[[contact.wheelset]]`.
    pub fn wheelset_tables(&self) -> Result<Vec<Option<ContactTable>>, TableError> {
        let count = self
            .contact
            .wheelsets
            .iter()
            .flat_map(|w| w.positions.iter().copied())
            .max()
            .unwrap_or(0);
        let mut tables = vec![None; count];
        for w in &self.contact.wheelsets {
            let table = ContactTable::build(&w.geometry, &self.table_spec())?;
            for &p in &w.positions {
                if let Some(slot) = p.checked_sub(1).and_then(|k| tables.get_mut(k)) {
                    *slot = Some(table.clone());
                }
            }
        }
        Ok(tables)
    }

    /// [`Self::model`] with every table already built (sweeps reuse them): the common one and
    /// the wheelsets' own ([`Self::wheelset_tables`]).
    pub fn model_with_tables(
        &self,
        table: ContactTable,
        wheelset_tables: Vec<Option<ContactTable>>,
    ) -> Result<Vehicle, ModelError> {
        let vehicle = layouts::build(
            &self.vehicle,
            self.wheelset_with(table),
            &self.primary_vertical,
        )?;
        Ok(vehicle.with_wheelset_tables(wheelset_tables)?)
    }
}

/// Why a plan's model could not be built.
#[derive(Debug, thiserror::Error)]
pub enum ModelError {
    /// the contact geometry could not be tabulated
    #[error(transparent)]
    Table(#[from] TableError),
    /// the assembly was refused
    #[error(transparent)]
    Assembly(#[from] crate::model::vehicle::AssemblyError),
}
