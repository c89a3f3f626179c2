//! The `geometry = "profiles"` keys of a study: profile files, their conventions, the track.

use std::path::Path;
use std::sync::Arc;

use super::schema::ContactSection;
use super::units::Dimension;
use super::{checked, rule, StudyError};
use crate::contact::geometry::Geometry;
use crate::contact::profile::{self, Orientation};
use crate::contact::rigid::{ProfilePair, Track};

/// The profile geometry of a study; `base` is the study file's folder.
pub(super) fn geometry(
    c: &ContactSection,
    base: &Path,
    has_rail_radius: bool,
    half_contact_distance: f64,
) -> Result<Geometry, StudyError> {
    if c.conicity.is_some() || has_rail_radius || c.crown_offset.is_some() {
        return Err(rule(
            "contact.conicity / rail_head_radius / crown_offset",
            "given",
            "geometry \"profiles\" takes its shape from the profile files",
        ));
    }
    let path = |key: &str, v: &Option<String>| {
        v.as_ref()
            .map(|p| base.join(p))
            .ok_or_else(|| StudyError::Missing {
                key: format!("contact.{key}"),
                why: "geometry \"profiles\" needs a wheel and a rail profile file".into(),
            })
    };
    let read = |key: &str, file: &Path, mirror: Option<bool>, z_up: Option<bool>| {
        let o = Orientation {
            mirror: mirror.unwrap_or(false),
            z_up: z_up.unwrap_or(false),
        };
        profile::read(file, o).map_err(|source| StudyError::Profile {
            key: format!("contact.{key}"),
            source,
        })
    };
    let wheel_file = path("wheel_profile", &c.wheel_profile)?;
    let rail_file = path("rail_profile", &c.rail_profile)?;
    let wheel = read(
        "wheel_profile",
        &wheel_file,
        c.wheel_profile_mirror,
        c.wheel_profile_z_up,
    )?;
    let rail = read(
        "rail_profile",
        &rail_file,
        c.rail_profile_mirror,
        c.rail_profile_z_up,
    )?;
    let length = |key: &str, q: &Option<super::schema::Quantity>, default: f64, lo, hi| {
        q.as_ref().map_or(Ok(default), |q| {
            checked(
                &format!("contact.{key}"),
                q,
                Dimension::Length,
                |v| v >= lo && v <= hi,
                &format!("must lie in [{lo}, {hi}] m"),
            )
        })
    };
    let track = Track {
        gauge: length("track_gauge", &c.track_gauge, 1.435, 0.6, 2.0)?,
        gauge_depth: length("gauge_depth", &c.gauge_depth, 0.014, 0.0, 0.04)?,
        inclination: inclination(c.rail_inclination.as_deref())?,
    };
    let smoothing = length("profile_smoothing", &c.profile_smoothing, 0.0, 0.0, 0.005)?;
    let pair = ProfilePair::new(&wheel, rail, track).map_err(|source| StudyError::Profile {
        key: "contact.wheel_profile / rail_profile".into(),
        source,
    })?;
    touching(&pair, half_contact_distance)?;
    Ok(Geometry::Profiles {
        pair: Arc::new(pair),
        smoothing,
    })
}

/// The wheels sit on the rails: at the centred position the wheel's running part, its taping
/// line at `half_contact_distance` from the track centre, overlaps the rail head placed by the
/// gauge. Where it does not, no contact exists and the contact solve cannot mean anything.
fn touching(pair: &ProfilePair, l0: f64) -> Result<(), StudyError> {
    let ((ulo, uhi), (ylo, yhi)) = pair.extents();
    let (wlo, whi) = (l0 + ulo, l0 + uhi);
    if wlo < yhi && whi > ylo {
        return Ok(());
    }
    Err(rule(
        "wheelset.half_contact_distance",
        format!("{l0} m"),
        &format!(
            "with contact.track_gauge = {} m the wheel's running part (Y = {wlo:.4} to {whi:.4} m, \
             taping line at half_contact_distance) does not reach the rail head (Y = {ylo:.4} to \
             {yhi:.4} m): the wheels cannot touch the rails",
            pair.track.gauge
        ),
    ))
}

/// "none" (the file is already in track axes) or a ratio "1:n" (rad, atan(1/n)).
fn inclination(text: Option<&str>) -> Result<f64, StudyError> {
    const KEY: &str = "contact.rail_inclination";
    let Some(t) = text else {
        return Err(StudyError::Missing {
            key: KEY.into(),
            why: "say \"none\" when the rail file is already canted, else e.g. \"1:40\"".into(),
        });
    };
    if t.trim() == "none" {
        return Ok(0.0);
    }
    let parts: Vec<&str> = t.split(':').map(str::trim).collect();
    match parts.as_slice() {
        [one, n] if *one == "1" => match n.parse::<f64>() {
            Ok(n) if (5.0..=1000.0).contains(&n) => Ok((1.0 / n).atan()),
            _ => Err(rule(KEY, t, "the ratio 1:n needs n in [5, 1000]")),
        },
        _ => Err(rule(KEY, t, "must be \"none\" or a ratio such as \"1:40\"")),
    }
}

/// The profile keys are refused for the cone geometries (a misplaced key is an error).
pub(super) fn only_for_profiles(c: &ContactSection) -> Result<(), StudyError> {
    let profile_keys = [
        ("wheel_profile", c.wheel_profile.is_some()),
        ("rail_profile", c.rail_profile.is_some()),
        ("wheel_profile_mirror", c.wheel_profile_mirror.is_some()),
        ("wheel_profile_z_up", c.wheel_profile_z_up.is_some()),
        ("rail_profile_mirror", c.rail_profile_mirror.is_some()),
        ("rail_profile_z_up", c.rail_profile_z_up.is_some()),
        ("rail_inclination", c.rail_inclination.is_some()),
        ("track_gauge", c.track_gauge.is_some()),
        ("gauge_depth", c.gauge_depth.is_some()),
        ("profile_smoothing", c.profile_smoothing.is_some()),
    ];
    match profile_keys
        .iter()
        .find(|k| k.1 && c.geometry != "profiles")
    {
        Some((key, _)) => Err(rule(
            &format!("contact.{key}"),
            "given",
            "only applies to geometry \"profiles\"",
        )),
        None => Ok(()),
    }
}
