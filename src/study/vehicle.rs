//! `[vehicle]`, `[bogie]`, `[secondary]`, `[carbody]` and the spring sections (`[suspension]`
//! and `[secondary]` share their keys and their reading): the layout of docs/model.md §11, in SI,
//! checked.

use super::schema::{ForceVelocitySection, Quantity, Springs, StudyFile};
use super::units::Dimension;
use super::{checked, non_negative, positive, rule, StudyError};
use crate::model::{
    CarBodyParams, DamperSeries, ForceVelocity, FrameParams, PrimaryVertical, Secondary, StopLaw,
    StopSpec, StopTable, Suspension, VehicleSpec,
};

fn opt(
    key: &str,
    q: Option<&Quantity>,
    dim: Dimension,
    f: fn(&str, &Quantity, Dimension) -> Result<f64, StudyError>,
) -> Result<Option<f64>, StudyError> {
    q.map(|q| f(key, q, dim)).transpose()
}

fn height(key: &str, q: Option<&Quantity>) -> Result<f64, StudyError> {
    let v = q.map(|q| {
        checked(
            key,
            q,
            Dimension::Length,
            |v| v.abs() <= 10.0,
            "must lie in [-10, 10] m",
        )
    });
    Ok(v.transpose()?.unwrap_or(0.0))
}

/// The five keys every spring section has (`prefix`: `suspension` or `secondary`).
pub(super) fn springs(prefix: &str, s: Springs<'_>) -> Result<Suspension, StudyError> {
    use Dimension::*;
    let key = |k: &str| format!("{prefix}.{k}");
    Ok(Suspension {
        lateral_stiffness: non_negative(&key("lateral_stiffness"), s.stiffness[0], Stiffness)?,
        longitudinal_stiffness: non_negative(
            &key("longitudinal_stiffness"),
            s.stiffness[1],
            Stiffness,
        )?,
        lateral_damping: non_negative(&key("lateral_damping"), s.damping[0], Damping)?,
        longitudinal_damping: non_negative(&key("longitudinal_damping"), s.damping[1], Damping)?,
        half_spring_spacing: positive(&key("half_spring_spacing"), s.half_spring_spacing, Length)?,
    })
}

/// A spring section's series stiffnesses of its lateral, longitudinal and vertical dampers
/// (absent: rigid), and `yaw` as given (the secondary's yaw dampers).
fn series(
    prefix: &str,
    s: Springs<'_>,
    yaw: Option<&Quantity>,
) -> Result<DamperSeries, StudyError> {
    let key = |k: &str| format!("{prefix}.{k}_damper_series_stiffness");
    let [lateral, longitudinal, vertical] = s.series;
    let get = |what: &str, q: Option<&Quantity>| opt(&key(what), q, Dimension::Stiffness, positive);
    Ok(DamperSeries {
        lateral: get("lateral", lateral)?,
        longitudinal: get("longitudinal", longitudinal)?,
        vertical: get("vertical", vertical)?,
        yaw: get("yaw", yaw)?,
    })
}

/// The yaw dampers' force–velocity curve and the damping at zero (N s/m) it implies, from
/// `fv` and the section's `secondary.yaw_damping` (`given`): the blow-off form's first slope is
/// `given` (required); a table's forces are scaled so that its slope at zero is `given` when
/// that is set (the table gives the curve's shape, the damping key its size, so that it can be
/// swept), and are taken as written otherwise.
fn force_velocity(
    fv: &ForceVelocitySection,
    given: Option<f64>,
) -> Result<(f64, ForceVelocity), StudyError> {
    use Dimension::*;
    const KEY: &str = "secondary.yaw_damper_force_velocity";
    let key = |k: &str| format!("{KEY}.{k}");
    let bad = |k: &str, e: String| rule(&key(k), "as given", &e);
    match (&fv.points, &fv.blow_off_force, &fv.slope_after) {
        (Some(points), None, None) => {
            let mut pts = Vec::with_capacity(points.len());
            for (i, [v, f]) in points.iter().enumerate() {
                let k = key(&format!("points[{i}]"));
                pts.push((
                    checked(&k, v, Speed, |v| v.is_finite(), "must be finite")?,
                    checked(&k, f, Force, |v| v.is_finite(), "must be finite")?,
                ));
            }
            let g = ForceVelocity::from_points(&pts).map_err(|e| bad("points", e))?;
            match given {
                Some(c) if c > 0.0 => Ok((c, g.scaled(c / g.slope_at_zero()))),
                Some(c) => Err(rule(
                    "secondary.yaw_damping",
                    format!("{c} N s/m"),
                    "must be positive with a force-velocity curve (it scales the curve)",
                )),
                None => Ok((g.slope_at_zero(), g)),
            }
        }
        (None, Some(force), Some(after)) => {
            let force = positive(&key("blow_off_force"), force, Force)?;
            let after = positive(&key("slope_after"), after, Damping)?;
            let c = given
                .filter(|c| *c > 0.0)
                .ok_or_else(|| StudyError::Missing {
                    key: "secondary.yaw_damping".into(),
                    why: format!("{KEY}'s blow-off form takes its first slope from it (> 0)"),
                })?;
            let g = ForceVelocity::blow_off(c, force / c, after).map_err(|e| bad("", e))?;
            Ok((c, g))
        }
        _ => Err(rule(
            KEY,
            "as given",
            "give either points = [[velocity, force], ...] or both blow_off_force and slope_after",
        )),
    }
}

/// A spring section's bump stop (docs/model.md §13), `prefix` naming it: `bump_stop_clearance`
/// with either `bump_stop_stiffness` or `bump_stop_force_table`, or neither. With both, the
/// table gives the stop's shape and the stiffness its size: the table's forces are scaled so
/// that its first slope is the stiffness (so that the stiffness can be swept, as the yaw
/// damper's curve is scaled by `secondary.yaw_damping`).
fn bump_stop(prefix: &str, s: Springs<'_>) -> Result<Option<StopSpec>, StudyError> {
    use Dimension::*;
    let key = |k: &str| format!("{prefix}.bump_stop_{k}");
    let [clearance, stiffness] = s.bump_stop;
    let clearance = opt(&key("clearance"), clearance, Length, positive)?;
    let stiffness = opt(&key("stiffness"), stiffness, Stiffness, positive)?;
    let table = match s.bump_stop_table {
        None => None,
        Some(t) => {
            let mut pts = Vec::with_capacity(t.points.len());
            for (i, [p, f]) in t.points.iter().enumerate() {
                let k = format!("{}.points[{i}]", key("force_table"));
                pts.push((
                    checked(&k, p, Length, |v| v.is_finite(), "must be finite")?,
                    checked(&k, f, Force, |v| v.is_finite(), "must be finite")?,
                ));
            }
            let table = StopTable::from_points(&pts)
                .map_err(|e| rule(&format!("{}.points", key("force_table")), "as given", &e))?;
            Some(table)
        }
    };
    let law = match (stiffness, table) {
        (_, Some(t)) => {
            let t = match stiffness {
                Some(k) => t.scaled(k / t.initial_stiffness()),
                None => t,
            };
            Some(StopLaw::Table(t))
        }
        (Some(k), None) => Some(StopLaw::Linear(k)),
        (None, None) => None,
    };
    match (clearance, law) {
        (Some(clearance), Some(law)) => Ok(Some(StopSpec { clearance, law })),
        (None, None) => Ok(None),
        (Some(_), None) => Err(StudyError::Missing {
            key: key("stiffness"),
            why: format!(
                "{} needs the stop's stiffness (or {})",
                key("clearance"),
                key("force_table")
            ),
        }),
        (None, Some(_)) => Err(StudyError::Missing {
            key: key("clearance"),
            why: format!(
                "a bump stop ({} or {}) needs its clearance, the free play each way",
                key("stiffness"),
                key("force_table")
            ),
        }),
    }
}

/// A spring section's vertical stiffness and damping (default 0) and height (default 0).
fn vertical(prefix: &str, s: Springs<'_>) -> Result<PrimaryVertical, StudyError> {
    use Dimension::*;
    let key = |k: &str| format!("{prefix}.{k}");
    Ok(PrimaryVertical {
        stiffness: opt(
            &key("vertical_stiffness"),
            s.vertical[0],
            Stiffness,
            non_negative,
        )?
        .unwrap_or(0.0),
        damping: opt(
            &key("vertical_damping"),
            s.vertical[1],
            Damping,
            non_negative,
        )?
        .unwrap_or(0.0),
        height: height(&key("height"), s.height)?,
        series: series(prefix, s, None)?,
        bump_stop: bump_stop(prefix, s)?,
    })
}

/// The primary's vertical stiffness, damping and height (`[suspension]`).
pub(super) fn primary_vertical(f: &StudyFile) -> Result<PrimaryVertical, StudyError> {
    vertical("suspension", f.suspension.springs())
}

/// A body's mass, yaw and (optional) roll inertia, `prefix` naming its section.
fn body(
    prefix: &str,
    mass: &Quantity,
    yaw: &Quantity,
    roll: Option<&Quantity>,
) -> Result<(f64, f64, Option<f64>), StudyError> {
    use Dimension::*;
    Ok((
        positive(&format!("{prefix}.mass"), mass, Mass)?,
        positive(&format!("{prefix}.yaw_inertia"), yaw, Inertia)?,
        opt(&format!("{prefix}.roll_inertia"), roll, Inertia, positive)?,
    ))
}

fn frame(f: &StudyFile) -> Result<FrameParams, StudyError> {
    let b = f.bogie.as_ref().ok_or_else(|| StudyError::Missing {
        key: "bogie".into(),
        why: format!(
            "{} needs its frame: mass, yaw_inertia, half_wheelbase",
            layout(f)
        ),
    })?;
    let (mass, yaw_inertia, roll_inertia) =
        body("bogie", &b.mass, &b.yaw_inertia, b.roll_inertia.as_ref())?;
    Ok(FrameParams {
        mass,
        yaw_inertia,
        roll_inertia,
        half_wheelbase: positive("bogie.half_wheelbase", &b.half_wheelbase, Dimension::Length)?,
    })
}

fn secondary(f: &StudyFile) -> Result<Secondary, StudyError> {
    let s = f.secondary.as_ref().ok_or_else(|| StudyError::Missing {
        key: "secondary".into(),
        why: format!("{} needs its secondary suspension", layout(f)),
    })?;
    use Dimension::*;
    let k = springs("secondary", s.springs())?;
    let v = vertical("secondary", s.springs())?;
    let spacing = k.half_spring_spacing;
    let yaw_damping = opt(
        "secondary.yaw_damping",
        s.yaw_damping.as_ref(),
        Damping,
        non_negative,
    )?;
    let yaw_spacing = opt(
        "secondary.yaw_damper_half_spacing",
        s.yaw_damper_half_spacing.as_ref(),
        Length,
        positive,
    )?;
    let series = series(
        "secondary",
        s.springs(),
        s.yaw_damper_series_stiffness.as_ref(),
    )?;
    let (yaw_damping, curve) = match &s.yaw_damper_force_velocity {
        None => (yaw_damping, None),
        Some(fv) => {
            let (c, g) = force_velocity(fv, yaw_damping)?;
            (Some(c), Some(g))
        }
    };
    if curve.is_some() && series.yaw.is_none() {
        return Err(StudyError::Missing {
            key: "secondary.yaw_damper_series_stiffness".into(),
            why: "secondary.yaw_damper_force_velocity acts on the damper's stroke, which needs \
                  the bushes' series stiffness (a rigidly attached nonlinear damper: give a \
                  stiff one, e.g. 1e9 N/m)"
                .into(),
        });
    }
    if yaw_damping.is_some_and(|c| c > 0.0) && yaw_spacing.is_none() {
        return Err(StudyError::Missing {
            key: "secondary.yaw_damper_half_spacing".into(),
            why: "secondary.yaw_damping needs the dampers' half spacing".into(),
        });
    }
    Ok(Secondary {
        lateral_stiffness: k.lateral_stiffness,
        longitudinal_stiffness: k.longitudinal_stiffness,
        lateral_damping: k.lateral_damping,
        longitudinal_damping: k.longitudinal_damping,
        half_spring_spacing: spacing,
        yaw_damping: yaw_damping.unwrap_or(0.0),
        yaw_damper_half_spacing: yaw_spacing.unwrap_or(spacing),
        vertical_stiffness: v.stiffness,
        vertical_damping: v.damping,
        vertical_half_spacing: opt(
            "secondary.vertical_half_spacing",
            s.vertical_half_spacing.as_ref(),
            Length,
            positive,
        )?
        .unwrap_or(spacing),
        height: v.height,
        series,
        yaw_damper_force_velocity: curve,
        bump_stop: v.bump_stop,
    })
}

fn carbody(f: &StudyFile, frame: &FrameParams) -> Result<CarBodyParams, StudyError> {
    let c = f.carbody.as_ref().ok_or_else(|| StudyError::Missing {
        key: "carbody".into(),
        why: format!(
            "{} needs its car body: mass, yaw_inertia, half_bogie_distance",
            layout(f)
        ),
    })?;
    let lb = positive(
        "carbody.half_bogie_distance",
        &c.half_bogie_distance,
        Dimension::Length,
    )?;
    if lb <= frame.half_wheelbase {
        return Err(rule(
            "carbody.half_bogie_distance",
            format!("{lb} m"),
            &format!(
                "must exceed bogie.half_wheelbase ({} m): the bogies would overlap",
                frame.half_wheelbase
            ),
        ));
    }
    let (mass, yaw_inertia, roll_inertia) =
        body("carbody", &c.mass, &c.yaw_inertia, c.roll_inertia.as_ref())?;
    Ok(CarBodyParams {
        mass,
        yaw_inertia,
        roll_inertia,
        half_bogie_distance: lb,
        secondary_height: height("carbody.secondary_height", c.secondary_height.as_ref())?,
    })
}

/// The layout as the study chooses it, for messages: `vehicle.kind = "car"`.
fn layout(f: &StudyFile) -> String {
    let kind = f.vehicle.as_ref().map_or("wheelset", |v| v.kind.as_str());
    format!("vehicle.kind = {kind:?}")
}

/// A section the layout does not use is an error that says so.
fn unused(f: &StudyFile, kind: &str, sections: &[(&str, bool)]) -> Result<(), StudyError> {
    match sections.iter().find(|(_, present)| *present) {
        Some((name, _)) => Err(rule(
            name,
            "given",
            &format!("the layout vehicle.kind = \"{kind}\" has no {name}; remove the section or choose another kind"),
        )),
        None => {
            let _ = f;
            Ok(())
        }
    }
}

/// The layout of the study.
pub(super) fn spec(f: &StudyFile) -> Result<VehicleSpec, StudyError> {
    let kind = f.vehicle.as_ref().map_or("wheelset", |v| v.kind.as_str());
    let has = |o: bool| o;
    match kind {
        "wheelset" => {
            unused(
                f,
                kind,
                &[
                    ("bogie", has(f.bogie.is_some())),
                    ("secondary", has(f.secondary.is_some())),
                    ("carbody", has(f.carbody.is_some())),
                ],
            )?;
            if f.suspension.height.is_some() {
                return Err(rule("suspension.height", "given", "only acts on a rolling bogie frame (vehicle.kind \"bogie\" or \"car\" with bogie.roll_inertia)"));
            }
            Ok(VehicleSpec::Wheelset)
        }
        "bogie" => {
            unused(f, kind, &[("carbody", f.carbody.is_some())])?;
            Ok(VehicleSpec::Bogie {
                frame: frame(f)?,
                secondary: secondary(f)?,
            })
        }
        "car" => {
            let fr = frame(f)?;
            let body = carbody(f, &fr)?;
            if fr.roll_inertia.is_some() != body.roll_inertia.is_some() {
                return Err(rule(
                    if fr.roll_inertia.is_some() { "carbody.roll_inertia" } else { "bogie.roll_inertia" },
                    "missing",
                    "a car rolls as a whole: give both bogie.roll_inertia and carbody.roll_inertia (34 states) or neither (28)",
                ));
            }
            Ok(VehicleSpec::Car {
                frame: fr,
                secondary: secondary(f)?,
                body,
            })
        }
        other => Err(StudyError::Choice {
            key: "vehicle.kind".into(),
            value: other.into(),
            allowed: "\"wheelset\", \"bogie\", \"car\"",
        }),
    }
}
