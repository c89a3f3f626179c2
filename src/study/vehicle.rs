//! `[vehicle]`, `[bogie]`, `[secondary]`, `[carbody]` and the spring sections (`[suspension]`
//! and `[secondary]` share their keys and their reading): the layout of docs/model.md §11, in SI,
//! checked.

use super::schema::{ForceVelocitySection, PointsTable, Quantity, Springs, StudyFile};
use super::units::Dimension;
use super::{checked, non_negative, positive, rule, StudyError};
use crate::model::{
    CarBodyParams, DamperCurves, DamperSeries, ForceVelocity, FrameParams, PrimaryVertical,
    Secondary, StopLaw, StopSpec, StopTable, Suspension, VehicleSpec,
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

/// A table `points = [[x, force], …]` in SI, `key` naming it (`….points`): `x` of dimension
/// `dim`, forces in N, every value finite. The table's own rules are the model's
/// ([`ForceVelocity::from_points`], [`StopTable::from_points`]).
fn points_table(
    key: &str,
    points: &PointsTable,
    dim: Dimension,
) -> Result<Vec<(f64, f64)>, StudyError> {
    let finite = |v: f64| v.is_finite();
    let mut pts = Vec::with_capacity(points.len());
    for (i, [x, f]) in points.iter().enumerate() {
        let k = format!("{key}[{i}]");
        pts.push((
            checked(&k, x, dim, finite, "must be finite")?,
            checked(&k, f, Dimension::Force, finite, "must be finite")?,
        ));
    }
    Ok(pts)
}

/// The force–velocity curve of a damper (`key`, e.g. `secondary.yaw_damper_force_velocity`)
/// and the damping at zero (N s/m) it implies, from `fv` and the section's damping key
/// (`damping_key`, its value `given`): the blow-off form's first slope is `given` (required); a
/// table's forces are scaled so that its slope at zero is `given` when that is set (the table
/// gives the curve's shape, the damping key its size, so that it can be swept), and are taken
/// as written otherwise.
fn force_velocity(
    (key, damping_key): (&str, &str),
    fv: &ForceVelocitySection,
    given: Option<f64>,
) -> Result<(f64, ForceVelocity), StudyError> {
    use Dimension::*;
    let sub = |k: &str| format!("{key}.{k}");
    let bad = |k: &str, e: String| rule(&sub(k), "as given", &e);
    match (&fv.points, &fv.blow_off_force, &fv.slope_after) {
        (Some(points), None, None) => {
            let pts = points_table(&sub("points"), points, Speed)?;
            let g = ForceVelocity::from_points(&pts).map_err(|e| bad("points", e))?;
            match given {
                Some(c) if c > 0.0 => Ok((c, g.scaled(c / g.slope_at_zero()))),
                Some(c) => Err(rule(
                    damping_key,
                    format!("{c} N s/m"),
                    "must be positive with a force-velocity curve (it scales the curve)",
                )),
                None => Ok((g.slope_at_zero(), g)),
            }
        }
        (None, Some(force), Some(after)) => {
            let force = positive(&sub("blow_off_force"), force, Force)?;
            let after = positive(&sub("slope_after"), after, Damping)?;
            let c = given
                .filter(|c| *c > 0.0)
                .ok_or_else(|| StudyError::Missing {
                    key: damping_key.into(),
                    why: format!("{key}'s blow-off form takes its first slope from it (> 0)"),
                })?;
            let g = ForceVelocity::blow_off(c, force / c, after).map_err(|e| bad("", e))?;
            Ok((c, g))
        }
        _ => Err(rule(
            key,
            "as given",
            "give either points = [[velocity, force], ...] or both blow_off_force and slope_after",
        )),
    }
}

/// The damper `what` (`lateral`, `longitudinal`, `vertical`, `yaw`) of section `prefix` with its
/// force–velocity curve `fv` when given: its damping (`given`, or the curve's slope at zero) and
/// the curve, which needs the damper's series stiffness `series` (the curve acts on the stroke).
fn damper_curve(
    (prefix, what): (&str, &str),
    fv: Option<&ForceVelocitySection>,
    given: Option<f64>,
    series: Option<f64>,
) -> Result<(Option<f64>, Option<ForceVelocity>), StudyError> {
    let Some(fv) = fv else {
        return Ok((given, None));
    };
    let key = format!("{prefix}.{what}_damper_force_velocity");
    let damping_key = format!("{prefix}.{what}_damping");
    let (c, g) = force_velocity((&key, &damping_key), fv, given)?;
    if series.is_none() {
        return Err(StudyError::Missing {
            key: format!("{prefix}.{what}_damper_series_stiffness"),
            why: format!(
                "{key} acts on the damper's stroke, which needs the bushes' series stiffness (a \
                 rigidly attached nonlinear damper: give a stiff one, e.g. 1e9 N/m)"
            ),
        });
    }
    Ok((Some(c), Some(g)))
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
            let points = format!("{}.points", key("force_table"));
            let pts = points_table(&points, &t.points, Length)?;
            let table = StopTable::from_points(&pts).map_err(|e| rule(&points, "as given", &e))?;
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

/// A spring section's vertical stiffness and damping (default 0; a vertical curve's slope at
/// zero without the damping key), height (default 0), its dampers' series stiffnesses and
/// force–velocity curves, and its bump stop.
fn vertical(prefix: &str, s: Springs<'_>) -> Result<PrimaryVertical, StudyError> {
    use Dimension::*;
    let key = |k: &str| format!("{prefix}.{k}");
    let stiffness = opt(
        &key("vertical_stiffness"),
        s.vertical[0],
        Stiffness,
        non_negative,
    )?;
    let series = series(prefix, s, None)?;
    let [lateral, longitudinal, vertical] = s.force_velocity;
    // the lateral and longitudinal damping keys are required (read again here, as checked by
    // `springs`): the curves' first slope and scale
    let curve = |what: &str, fv, damping: &Quantity, ks| {
        let c = non_negative(&key(&format!("{what}_damping")), damping, Damping)?;
        damper_curve((prefix, what), fv, Some(c), ks).map(|(_, g)| g)
    };
    let damping = opt(
        &key("vertical_damping"),
        s.vertical[1],
        Damping,
        non_negative,
    )?;
    let (damping, vertical_curve) =
        damper_curve((prefix, "vertical"), vertical, damping, series.vertical)?;
    let curves = DamperCurves {
        lateral: curve("lateral", lateral, s.damping[0], series.lateral)?,
        longitudinal: curve(
            "longitudinal",
            longitudinal,
            s.damping[1],
            series.longitudinal,
        )?,
        vertical: vertical_curve,
        yaw: None,
    };
    Ok(PrimaryVertical {
        stiffness: stiffness.unwrap_or(0.0),
        damping: damping.unwrap_or(0.0),
        height: height(&key("height"), s.height)?,
        series,
        curves,
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
    let (yaw_damping, curve) = damper_curve(
        ("secondary", "yaw"),
        s.yaw_damper_force_velocity.as_ref(),
        yaw_damping,
        series.yaw,
    )?;
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
        curves: DamperCurves {
            yaw: curve,
            ..v.curves
        },
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
