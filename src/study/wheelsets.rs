//! `[[contact.wheelset]]`: wheelsets with their own contact geometry (docs/vehicles.md,
//! docs/model.md §11). Each entry names the wheelsets' positions (1-based, front to rear, as
//! the layouts number them) and any of `[contact]`'s geometry keys; every key it does not
//! give is `[contact]`'s. An entry that changes `geometry` inherits none of `[contact]`'s
//! geometry keys (they describe another kind of geometry).

use std::path::Path;

use super::schema::{ContactSection, WheelsetContactSection};
use super::{geometry_of, rule, StudyError};
use crate::contact::geometry::Geometry;
use crate::contact::table::CreepSource;
use crate::model::{VehicleSpec, WheelsetParams};

/// The contact geometry of some wheelsets of the vehicle.
#[derive(Clone, Debug, PartialEq)]
pub struct WheelsetGeometry {
    /// the wheelsets' positions, 1-based from the front
    pub positions: Vec<usize>,
    /// their geometry (left and right wheels mirror images, as for `[contact]`)
    pub geometry: Geometry,
}

/// The study's `[contact]` data the entries inherit and are checked against.
pub(super) struct Common<'a> {
    pub section: &'a ContactSection,
    pub wheelset: &'a WheelsetParams,
    pub rail_head_radius: Option<f64>,
    pub creep: CreepSource,
    pub lateral_range: f64,
    pub folder: Option<&'a Path>,
}

/// The `[[contact.wheelset]]` entries of `common.section`, validated (positions against the
/// layout later, [`check_positions`]).
pub(super) fn plan(common: &Common) -> Result<Vec<WheelsetGeometry>, StudyError> {
    common
        .section
        .wheelset
        .iter()
        .enumerate()
        .map(|(i, e)| entry(common, i, e))
        .collect()
}

fn entry(
    common: &Common,
    i: usize,
    e: &WheelsetContactSection,
) -> Result<WheelsetGeometry, StudyError> {
    let prefix = format!("contact.wheelset[{i}]");
    if e.positions.is_empty() {
        return Err(rule(
            &format!("{prefix}.positions"),
            "[]",
            "must name at least one wheelset (1-based, front to rear)",
        ));
    }
    let section = merged(common.section, e).ok_or_else(|| {
        rule(
            &prefix,
            format!("positions = {:?} and no geometry key", e.positions),
            "an entry must give geometry, conicity, crown_offset, geometry_table or a profile key",
        )
    })?;
    let geometry = geometry_of(
        &section,
        common.wheelset,
        common.rail_head_radius,
        common.folder,
    )
    .map_err(|err| rekey(err, &prefix, e))?;
    if let Geometry::Table(t) = &geometry {
        if common.lateral_range > t.half_width() {
            return Err(rule(
                &format!("{prefix}.geometry_table"),
                format!("{:?}", t.source),
                &format!(
                    "covers |y| <= {} m, less than contact.lateral_range = {} m",
                    t.half_width(),
                    common.lateral_range
                ),
            ));
        }
    }
    let patch = match &geometry {
        Geometry::Profiles { .. } => true,
        Geometry::Table(t) => t.has_semi_axes(),
        _ => common.rail_head_radius.is_some(),
    };
    if matches!(common.creep, CreepSource::Hertz) && !patch {
        return Err(StudyError::Missing {
            key: "contact.creep_coefficients".into(),
            why: format!(
                "{prefix} has geometry {:?}, from which the creep coefficients of [contact] \
                 (from the Hertz patch) cannot be computed",
                section.geometry
            ),
        });
    }
    Ok(WheelsetGeometry {
        positions: e.positions.clone(),
        geometry,
    })
}

/// `[contact]` with the entry's geometry keys; `None` if the entry gives none.
fn merged(c: &ContactSection, e: &WheelsetContactSection) -> Option<ContactSection> {
    let mut m = c.clone();
    m.wheelset = Vec::new();
    if e.geometry.as_ref().is_some_and(|g| *g != c.geometry) {
        // another kind of geometry: [contact]'s geometry keys describe the other one
        m.conicity = None;
        m.crown_offset = None;
        m.geometry_table = None;
        m.wheel_profile = None;
        m.rail_profile = None;
        m.wheel_profile_mirror = None;
        m.wheel_profile_z_up = None;
        m.rail_profile_mirror = None;
        m.rail_profile_z_up = None;
        m.rail_inclination = None;
        m.track_gauge = None;
        m.gauge_depth = None;
        m.profile_smoothing = None;
    }
    let mut given = false;
    macro_rules! take {
        ($($field:ident),*) => {
            $(if let Some(v) = &e.$field {
                m.$field = Some(v.clone());
                given = true;
            })*
        };
    }
    take!(
        conicity,
        crown_offset,
        geometry_table,
        wheel_profile,
        rail_profile,
        wheel_profile_mirror,
        wheel_profile_z_up,
        rail_profile_mirror,
        rail_profile_z_up,
        rail_inclination,
        track_gauge,
        gauge_depth,
        profile_smoothing
    );
    if let Some(g) = &e.geometry {
        m.geometry = g.clone();
        given = true;
    }
    given.then_some(m)
}

/// An error of `[contact]`'s geometry keys, named as the entry's keys (the rail head radius
/// stays `[contact]`'s: it is common to every wheelset).
fn rekey(err: StudyError, prefix: &str, e: &WheelsetContactSection) -> StudyError {
    let re = |key: String| match key.strip_prefix("contact.") {
        Some(rest) if !rest.starts_with("rail_head_radius") => format!("{prefix}.{rest}"),
        _ => key,
    };
    match err {
        StudyError::Unit {
            key,
            value,
            dim,
            problem,
        } => StudyError::Unit {
            key: re(key),
            value,
            dim,
            problem,
        },
        StudyError::Rule { key, value, rule } => StudyError::Rule {
            key: re(key),
            value,
            rule,
        },
        StudyError::Missing { key, why } => StudyError::Missing { key: re(key), why },
        StudyError::Profile { key, source } => StudyError::Profile {
            key: re(key),
            source,
        },
        StudyError::Choice {
            key,
            value,
            allowed,
        } => StudyError::Choice {
            key: re(key),
            value,
            allowed,
        },
        StudyError::Table(source) => rule(
            &format!("{prefix}.geometry_table"),
            format!("{:?}", e.geometry_table.as_deref().unwrap_or("")),
            &source.to_string(),
        ),
        other => other,
    }
}

/// The number of wheelsets of a layout.
pub(super) fn wheelset_count(spec: &VehicleSpec) -> usize {
    match spec {
        VehicleSpec::Wheelset => 1,
        VehicleSpec::Bogie { .. } => 2,
        VehicleSpec::Car { .. } => 4,
    }
}

/// Every position names one of the vehicle's `count` wheelsets, and no wheelset is named twice.
pub(super) fn check_positions(
    entries: &[WheelsetGeometry],
    count: usize,
) -> Result<(), StudyError> {
    let mut seen = vec![None; count];
    for (i, e) in entries.iter().enumerate() {
        for &p in &e.positions {
            let key = format!("contact.wheelset[{i}].positions");
            let Some(slot) = p.checked_sub(1).and_then(|k| seen.get_mut(k)) else {
                return Err(rule(
                    &key,
                    p,
                    &format!(
                        "must lie in [1, {count}]: the vehicle's wheelsets, numbered from the front"
                    ),
                ));
            };
            if let Some(first) = *slot {
                return Err(rule(
                    &key,
                    p,
                    &format!("wheelset {p} is already given in contact.wheelset[{first}]"),
                ));
            }
            *slot = Some(i);
        }
    }
    Ok(())
}
