//! The `[sweep]` section resolved: the sweepable keys, axes in SI, the grid, the point ids.

use crate::study;
use crate::study::schema::{Quantity, SweepAxisSection, SweepSection};
use crate::study::units::Dimension;

use super::SweepError;

/// The numeric study keys a sweep may vary, with the dimension of their values.
pub const SWEEP_KEYS: &[(&str, Dimension)] = &[
    ("wheelset.mass", Dimension::Mass),
    ("wheelset.yaw_inertia", Dimension::Inertia),
    ("wheelset.axle_load", Dimension::Force),
    ("wheelset.half_contact_distance", Dimension::Length),
    ("wheelset.rolling_radius", Dimension::Length),
    ("suspension.lateral_stiffness", Dimension::Stiffness),
    ("suspension.longitudinal_stiffness", Dimension::Stiffness),
    ("suspension.lateral_damping", Dimension::Damping),
    ("suspension.longitudinal_damping", Dimension::Damping),
    ("suspension.half_spring_spacing", Dimension::Length),
    ("suspension.vertical_stiffness", Dimension::Stiffness),
    ("suspension.vertical_damping", Dimension::Damping),
    ("suspension.height", Dimension::Length),
    (
        "suspension.lateral_damper_series_stiffness",
        Dimension::Stiffness,
    ),
    (
        "suspension.longitudinal_damper_series_stiffness",
        Dimension::Stiffness,
    ),
    (
        "suspension.vertical_damper_series_stiffness",
        Dimension::Stiffness,
    ),
    (
        "suspension.lateral_damper_force_velocity.blow_off_force",
        Dimension::Force,
    ),
    (
        "suspension.lateral_damper_force_velocity.slope_after",
        Dimension::Damping,
    ),
    (
        "suspension.longitudinal_damper_force_velocity.blow_off_force",
        Dimension::Force,
    ),
    (
        "suspension.longitudinal_damper_force_velocity.slope_after",
        Dimension::Damping,
    ),
    (
        "suspension.vertical_damper_force_velocity.blow_off_force",
        Dimension::Force,
    ),
    (
        "suspension.vertical_damper_force_velocity.slope_after",
        Dimension::Damping,
    ),
    ("suspension.bump_stop_clearance", Dimension::Length),
    ("suspension.bump_stop_stiffness", Dimension::Stiffness),
    ("bogie.mass", Dimension::Mass),
    ("bogie.yaw_inertia", Dimension::Inertia),
    ("bogie.roll_inertia", Dimension::Inertia),
    ("bogie.half_wheelbase", Dimension::Length),
    ("secondary.lateral_stiffness", Dimension::Stiffness),
    ("secondary.longitudinal_stiffness", Dimension::Stiffness),
    ("secondary.lateral_damping", Dimension::Damping),
    ("secondary.longitudinal_damping", Dimension::Damping),
    ("secondary.half_spring_spacing", Dimension::Length),
    ("secondary.yaw_damping", Dimension::Damping),
    ("secondary.yaw_damper_half_spacing", Dimension::Length),
    ("secondary.vertical_stiffness", Dimension::Stiffness),
    ("secondary.vertical_damping", Dimension::Damping),
    ("secondary.vertical_half_spacing", Dimension::Length),
    ("secondary.height", Dimension::Length),
    (
        "secondary.lateral_damper_series_stiffness",
        Dimension::Stiffness,
    ),
    (
        "secondary.longitudinal_damper_series_stiffness",
        Dimension::Stiffness,
    ),
    (
        "secondary.vertical_damper_series_stiffness",
        Dimension::Stiffness,
    ),
    (
        "secondary.yaw_damper_series_stiffness",
        Dimension::Stiffness,
    ),
    (
        "secondary.lateral_damper_force_velocity.blow_off_force",
        Dimension::Force,
    ),
    (
        "secondary.lateral_damper_force_velocity.slope_after",
        Dimension::Damping,
    ),
    (
        "secondary.longitudinal_damper_force_velocity.blow_off_force",
        Dimension::Force,
    ),
    (
        "secondary.longitudinal_damper_force_velocity.slope_after",
        Dimension::Damping,
    ),
    (
        "secondary.vertical_damper_force_velocity.blow_off_force",
        Dimension::Force,
    ),
    (
        "secondary.vertical_damper_force_velocity.slope_after",
        Dimension::Damping,
    ),
    (
        "secondary.yaw_damper_force_velocity.blow_off_force",
        Dimension::Force,
    ),
    (
        "secondary.yaw_damper_force_velocity.slope_after",
        Dimension::Damping,
    ),
    ("secondary.bump_stop_clearance", Dimension::Length),
    ("secondary.bump_stop_stiffness", Dimension::Stiffness),
    ("carbody.mass", Dimension::Mass),
    ("carbody.yaw_inertia", Dimension::Inertia),
    ("carbody.roll_inertia", Dimension::Inertia),
    ("carbody.half_bogie_distance", Dimension::Length),
    ("carbody.secondary_height", Dimension::Length),
    ("contact.conicity", Dimension::Dimensionless),
    ("contact.rail_head_radius", Dimension::Length),
    ("contact.crown_offset", Dimension::Length),
    ("contact.friction", Dimension::Dimensionless),
    ("contact.young_modulus", Dimension::Pressure),
    ("contact.poisson_ratio", Dimension::Dimensionless),
    ("contact.shear_modulus", Dimension::Pressure),
    ("contact.lateral_range", Dimension::Length),
    ("contact.track_gauge", Dimension::Length),
    ("contact.gauge_depth", Dimension::Length),
    ("contact.profile_smoothing", Dimension::Length),
    ("contact.creep_coefficients.f11", Dimension::Force),
    ("contact.creep_coefficients.f22", Dimension::Force),
    ("contact.creep_coefficients.f23", Dimension::ForceLength),
    ("contact.creep_coefficients.f33", Dimension::ForceArea),
    ("flange.clearance", Dimension::Length),
    ("flange.stiffness", Dimension::Stiffness),
];

/// The study keys whose value is a file (relative to the study file): an uncertainty study may
/// draw them from a `choice` of files; a grid sweep cannot vary them (they have no order).
pub const FILE_KEYS: &[&str] = &[
    "contact.geometry_table",
    "contact.wheel_profile",
    "contact.rail_profile",
];

/// Whether `key` takes a file ([`FILE_KEYS`]).
pub fn is_file_key(key: &str) -> bool {
    FILE_KEYS.contains(&key)
}

/// The dimension of a sweepable key, or `None` when the key cannot be swept.
pub fn key_dimension(key: &str) -> Option<Dimension> {
    SWEEP_KEYS.iter().find(|(k, _)| *k == key).map(|(_, d)| *d)
}

/// The SI unit as a column-name suffix: `N/m` → `_n_per_m`, `kg m^2` → `_kg_m2`, `""` → `""`.
pub fn unit_suffix(dim: Dimension) -> String {
    let u = dim.si_unit();
    if u.is_empty() {
        return String::new();
    }
    let s = u
        .to_ascii_lowercase()
        .replace('/', " per ")
        .replace('^', "")
        .split_whitespace()
        .collect::<Vec<_>>()
        .join("_");
    format!("_{s}")
}

/// Spacing of the values along an axis.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Spacing {
    /// `from + (to − from)·i/(n − 1)`
    Linear,
    /// `from·(to/from)^(i/(n − 1))`
    Log,
}

/// One resolved axis: its key and its values in SI.
#[derive(Clone, Debug, PartialEq)]
pub struct Axis {
    /// dotted study key
    pub key: String,
    /// dimension of the values
    pub dim: Dimension,
    /// spacing
    pub spacing: Spacing,
    /// the values, SI units of `dim`; for a file axis (`files` not empty) the indices of the
    /// files (0, 1, …)
    pub values: Vec<f64>,
    /// for a file key ([`FILE_KEYS`]): the files (as written in the study, relative to its
    /// folder) that the values index; empty for a numeric key
    pub files: Vec<String>,
}

impl Axis {
    /// The file that value `v` of a file axis stands for (`None` for a numeric axis or an index
    /// out of range).
    pub fn file(&self, v: f64) -> Option<&str> {
        if !(v.is_finite() && v >= 0.0) {
            return None;
        }
        // the values of a file axis are whole indices; round off any representation error
        self.files.get(v.round() as usize).map(String::as_str)
    }

    /// The CSV column name: key plus SI unit suffix.
    pub fn column(&self) -> String {
        format!("{}{}", self.key, unit_suffix(self.dim))
    }

    /// Axis label for plots, with the unit.
    pub fn label(&self) -> String {
        match self.dim.si_unit() {
            "" => format!("{} (–)", self.key),
            u => format!("{} ({u})", self.key),
        }
    }
}

/// Which results a sweep computes at each point.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Compute {
    /// Kalker (linear) critical speed V_L
    pub kalker: bool,
    /// Hopf speed of the study's creep law
    pub hopf: bool,
    /// nonlinear critical speed V_NL from the continuation (expensive)
    pub nonlinear: bool,
}

/// A resolved `[sweep]` section.
#[derive(Clone, Debug, PartialEq)]
pub struct SweepSpec {
    /// one or two axes; point id = i0 + n0·i1
    pub axes: Vec<Axis>,
    /// results computed
    pub compute: Compute,
    /// operating speed (m/s), if given
    pub operating_speed: Option<f64>,
    /// V_NL by the full attractor search (`attractors = true`, the default for a bogie or a
    /// car) instead of the fast form (continuation with branch switching and the descents, the
    /// default for a wheelset): [`search_by_default`]
    pub attractors: bool,
}

/// How a sweep point's or an uncertainty evaluation's V_NL is found: `"descents"` (the fast form)
/// or `"search"` (`attractors = true`), with the words the summaries print.
pub fn nonlinear_method(search: bool) -> (&'static str, &'static str) {
    if search {
        (
            "search",
            "by the continuation and the full attractor search at every point",
        )
    } else {
        (
            "descents",
            "by the continuation and the descents from its lowest stable cycles (the fast form: \
             an attractor that no continued branch leads to is missed; attractors = true runs \
             the full search, the default for a bogie or a car)",
        )
    }
}

impl SweepSpec {
    /// Number of grid points.
    pub fn len(&self) -> usize {
        self.axes.iter().map(|a| a.values.len()).product()
    }

    /// Whether the grid is empty (never, after validation).
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Axis values (SI) of point `id` (its grid index; the first axis varies fastest).
    pub fn values(&self, id: usize) -> Vec<f64> {
        let mut rest = id;
        self.axes
            .iter()
            .map(|a| {
                let n = a.values.len();
                let v = a.values[rest % n];
                rest /= n;
                v
            })
            .collect()
    }
}

/// Grid values by index (the last value is `to` exactly).
pub fn grid(from: f64, to: f64, count: usize, spacing: Spacing) -> Vec<f64> {
    (0..count)
        .map(|i| {
            if i + 1 == count && count > 1 {
                return to;
            }
            let t = if count > 1 {
                i as f64 / (count - 1) as f64
            } else {
                0.0
            };
            match spacing {
                Spacing::Linear => from + (to - from) * t,
                Spacing::Log => from * (to / from).powf(t),
            }
        })
        .collect()
}

fn axis_error(i: usize, key: &str, rule: String) -> SweepError {
    SweepError::Axis {
        axis: format!("sweep.axes[{i}] ({key})"),
        rule,
    }
}

fn axis_value(
    i: usize,
    a: &SweepAxisSection,
    end: &str,
    q: &Quantity,
    dim: Dimension,
) -> Result<f64, SweepError> {
    let name = format!("sweep.axes[{i}].{end} ({})", a.key);
    if a.key == "contact.conicity" {
        if let Quantity::Text(t) = q {
            if t.contains([':', '/']) {
                return study::conicity(q).map_err(|e| SweepError::Axis {
                    axis: name,
                    rule: e.to_string(),
                });
            }
        }
    }
    study::quantity(&name, q, dim).map_err(SweepError::Study)
}

fn resolve_axis(i: usize, a: &SweepAxisSection) -> Result<Axis, SweepError> {
    let dim = key_dimension(&a.key).ok_or_else(|| SweepError::Key {
        axis: format!("sweep.axes[{i}].key"),
        key: a.key.clone(),
        accepted: SWEEP_KEYS
            .iter()
            .map(|(k, _)| *k)
            .collect::<Vec<_>>()
            .join(", "),
    })?;
    let from = axis_value(i, a, "from", &a.from, dim)?;
    let to = axis_value(i, a, "to", &a.to, dim)?;
    if !(1..=1_000_000).contains(&a.count) {
        return Err(axis_error(
            i,
            &a.key,
            format!("count = {} must lie in [1, 1000000]", a.count),
        ));
    }
    let spacing = match a.spacing.as_deref().unwrap_or("linear") {
        "linear" | "lin" => Spacing::Linear,
        "log" => Spacing::Log,
        other => {
            return Err(axis_error(
                i,
                &a.key,
                format!("spacing = {other:?} is not one of \"linear\", \"log\""),
            ))
        }
    };
    // from and to are finite (checked by the unit parser)
    if spacing == Spacing::Log && from * to <= 0.0 {
        return Err(axis_error(
            i,
            &a.key,
            format!("log spacing needs from and to of the same sign and not zero (from = {from}, to = {to} {})", dim.si_unit()),
        ));
    }
    Ok(Axis {
        key: a.key.clone(),
        dim,
        spacing,
        values: grid(from, to, a.count, spacing),
        files: Vec::new(),
    })
}

fn resolve_compute(c: Option<&[String]>) -> Result<Compute, SweepError> {
    let Some(list) = c else {
        return Ok(Compute {
            kalker: true,
            hopf: true,
            nonlinear: false,
        });
    };
    let mut out = Compute {
        kalker: false,
        hopf: false,
        nonlinear: false,
    };
    for (i, name) in list.iter().enumerate() {
        match name.as_str() {
            "kalker" => out.kalker = true,
            "hopf" => out.hopf = true,
            "nonlinear" => out.nonlinear = true,
            other => {
                return Err(SweepError::Axis {
                    axis: format!("sweep.compute[{i}]"),
                    rule: format!("{other:?} is not one of \"kalker\", \"hopf\", \"nonlinear\""),
                })
            }
        }
    }
    if !(out.kalker || out.hopf || out.nonlinear) {
        return Err(SweepError::Axis {
            axis: "sweep.compute".into(),
            rule: "must name at least one result".into(),
        });
    }
    Ok(out)
}

/// Resolves the section (units, grid, compute list), without the study. `search_by_default`
/// is V_NL's method when the section has no `attractors` key: the study's vehicle decides it
/// ([`search_by_default`]).
pub fn resolve(s: &SweepSection, search_by_default: bool) -> Result<SweepSpec, SweepError> {
    if !(1..=2).contains(&s.axes.len()) {
        return Err(SweepError::Axis {
            axis: "sweep.axes".into(),
            rule: format!("has {} axes; a sweep has one or two", s.axes.len()),
        });
    }
    let axes = s
        .axes
        .iter()
        .enumerate()
        .map(|(i, a)| resolve_axis(i, a))
        .collect::<Result<Vec<_>, _>>()?;
    let points: usize = axes.iter().map(|a| a.values.len()).product();
    if points > 10_000_000 {
        return Err(SweepError::Axis {
            axis: "sweep.axes".into(),
            rule: format!("{points} grid points; at most 10000000"),
        });
    }
    if axes.len() == 2 && axes[0].key == axes[1].key {
        return Err(axis_error(
            1,
            &axes[1].key,
            "the two axes name the same key".into(),
        ));
    }
    let operating_speed = s
        .operating_speed
        .as_ref()
        .map(|q| study::quantity("sweep.operating_speed", q, Dimension::Speed))
        .transpose()
        .map_err(SweepError::Study)?;
    Ok(SweepSpec {
        axes,
        compute: resolve_compute(s.compute.as_deref())?,
        operating_speed,
        attractors: s.attractors.unwrap_or(search_by_default),
    })
}

/// Whether a sweep of this vehicle finds V_NL by the full attractor search when its
/// `[sweep]` has no `attractors` key: yes for a bogie or a car (`[vehicle] kind`), whose fast
/// form can miss an attractor that no continued branch leads to (on 10 of 32 draws of the DTU
/// bogie it gave a V_NL 18 to 125 m/s too high: docs/uncertainty.md), no for a single wheelset,
/// where the search gave the same V_NL as the fast form on every shipped sweep (200 points of
/// `seed-stiffness-map`, 12 of `conicity-wear`) at 22 times the cost.
pub fn search_by_default(vehicle: &crate::model::VehicleSpec) -> bool {
    !matches!(vehicle, crate::model::VehicleSpec::Wheelset)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grid_values_follow_the_closed_forms() {
        let lin = grid(1.0, 3.0, 5, Spacing::Linear);
        assert_eq!(lin, vec![1.0, 1.5, 2.0, 2.5, 3.0]);
        let log = grid(100.0, 10_000.0, 3, Spacing::Log);
        assert_eq!(log[0], 100.0);
        assert!((log[1] - 1000.0).abs() < 1e-9, "{log:?}");
        assert_eq!(log[2], 10_000.0);
        // ratio of neighbours is constant on a log axis
        let g = grid(0.02, 0.3, 7, Spacing::Log);
        let r: Vec<f64> = g.windows(2).map(|w| w[1] / w[0]).collect();
        assert!(r.iter().all(|q| (q - r[0]).abs() < 1e-12 * r[0]), "{r:?}");
        assert_eq!(grid(5.0, 9.0, 1, Spacing::Log), vec![5.0]);
    }

    #[test]
    fn column_suffixes_spell_the_si_unit() {
        let col = |key: &str| {
            let dim = key_dimension(key).expect("sweepable");
            format!("{key}{}", unit_suffix(dim))
        };
        assert_eq!(
            col("suspension.longitudinal_stiffness"),
            "suspension.longitudinal_stiffness_n_per_m"
        );
        assert_eq!(
            col("suspension.lateral_damping"),
            "suspension.lateral_damping_n_s_per_m"
        );
        assert_eq!(col("wheelset.yaw_inertia"), "wheelset.yaw_inertia_kg_m2");
        assert_eq!(col("flange.clearance"), "flange.clearance_m");
        assert_eq!(col("contact.conicity"), "contact.conicity");
        assert!(key_dimension("linear.speed_range").is_none());
    }

    #[test]
    fn point_ids_run_first_axis_fastest() {
        let axis = |key: &str, values: Vec<f64>| Axis {
            key: key.into(),
            dim: Dimension::Dimensionless,
            spacing: Spacing::Linear,
            values,
            files: Vec::new(),
        };
        let spec = SweepSpec {
            axes: vec![axis("a", vec![1.0, 2.0, 3.0]), axis("b", vec![10.0, 20.0])],
            compute: Compute {
                kalker: true,
                hopf: false,
                nonlinear: false,
            },
            operating_speed: None,
            attractors: false,
        };
        assert_eq!(spec.len(), 6);
        assert_eq!(spec.values(0), vec![1.0, 10.0]);
        assert_eq!(spec.values(2), vec![3.0, 10.0]);
        assert_eq!(spec.values(4), vec![2.0, 20.0]);
    }
}
