//! Plausible and meaningful ranges of every numeric study key, in one table ([`ranges`]).
//!
//! - **Plausible**: the values of real railway vehicles, from light rail to heavy haul and high
//!   speed, with some margin. Outside it the study is still computed, and the plan carries a
//!   [`Warning`] naming the key, the value with its unit and the range (`critspeed` prints it
//!   on stderr, `check`'s JSON lists it, Python issues a `warnings.warn`).
//! - **Meaningful**: where the model can mean anything at all. Outside it (a 1e300 m wheel, a
//!   1e-300 kg wheelset) the study is refused before anything is computed: exit code 2, a
//!   message naming the key, the value and the rule. The bounds lie two to four orders of
//!   magnitude beyond the plausible ones (scaled roller-rig models, extreme parameter studies
//!   stay possible) and well inside what double precision resolves beside the other keys at
//!   their ordinary scale (a 1e19 N/m spring next to 1e7 N creep forces leaves nothing of the
//!   creep terms in an f64 Jacobian).
//!
//! A key without a row has no range. To give a new key one, add a row here (the docs list the
//! ranges beside the keys; `plausible::tests` checks that the pages show the table's numbers).

use std::fmt;

use super::entries::{entries, Entry};
use super::units::Dimension;
use super::{Plan, StudyError};

/// An interval with open or closed ends.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bounds {
    /// lower end
    pub lo: f64,
    /// upper end
    pub hi: f64,
    /// the lower end itself is excluded
    pub lo_open: bool,
    /// the upper end itself is excluded
    pub hi_open: bool,
}

impl Bounds {
    /// `[lo, hi]`
    pub const fn closed(lo: f64, hi: f64) -> Self {
        Self {
            lo,
            hi,
            lo_open: false,
            hi_open: false,
        }
    }

    /// `(lo, hi]`
    pub const fn left_open(lo: f64, hi: f64) -> Self {
        Self {
            lo,
            hi,
            lo_open: true,
            hi_open: false,
        }
    }

    /// `(lo, hi)`
    pub const fn open(lo: f64, hi: f64) -> Self {
        Self {
            lo,
            hi,
            lo_open: true,
            hi_open: true,
        }
    }

    /// Whether `v` lies inside (NaN never does).
    pub fn contains(&self, v: f64) -> bool {
        let above = if self.lo_open {
            v > self.lo
        } else {
            v >= self.lo
        };
        let below = if self.hi_open {
            v < self.hi
        } else {
            v <= self.hi
        };
        above && below
    }

    /// The interval with its unit, e.g. `[0.001, 10] m` or `(0, 2]`.
    pub fn show(&self, unit: &str) -> String {
        let (l, r) = (
            if self.lo_open { '(' } else { '[' },
            if self.hi_open { ')' } else { ']' },
        );
        let text = format!("{l}{}, {}{r}", si(self.lo), si(self.hi));
        if unit.is_empty() {
            text
        } else {
            format!("{text} {unit}")
        }
    }
}

/// A number as messages show it, exactly: the decimal form unless the exponent form is
/// shorter by two characters or more (`1e300`, not three hundred digits; `1e9`; `0.001`,
/// `3860000`, `2951.5`).
pub fn si(v: f64) -> String {
    let (plain, exp) = (format!("{v}"), format!("{v:e}"));
    if exp.len() + 1 < plain.len() {
        exp
    } else {
        plain
    }
}

/// The ranges of one key.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Range {
    /// dotted study key; an array key (`linear.speed_range`) covers each element
    pub key: &'static str,
    /// the dimension of its SI value
    pub dim: Dimension,
    /// values of real vehicles: outside, a warning
    pub plausible: Bounds,
    /// values the model can mean: outside, the study is refused
    pub meaningful: Bounds,
    /// what the plausible range covers (in messages and the docs)
    pub why: &'static str,
}

use Dimension::*;

const fn row(
    key: &'static str,
    dim: Dimension,
    plausible: (f64, f64),
    meaningful: Bounds,
    why: &'static str,
) -> Range {
    Range {
        key,
        dim,
        plausible: Bounds::closed(plausible.0, plausible.1),
        meaningful,
        why,
    }
}

const STIFFNESS: Bounds = Bounds::closed(0.0, 1e11);
const DAMPING: Bounds = Bounds::closed(0.0, 1e9);
/// a series stiffness is positive (absent is rigid); beyond 1e11 N/m it is rigid to f64
const SERIES: Bounds = Bounds::left_open(0.0, 1e11);
/// a damper's relief valve: the blow-off force (N) and the slope after it (N s/m), both positive
/// (a curve rises); beyond 1e8 N and 1e9 N s/m they swamp the creep forces
const BLOW_OFF: (f64, f64) = (100.0, 1e5);
const BLOW_OFF_BOUNDS: Bounds = Bounds::left_open(0.0, 1e8);
const BLOW_OFF_WHY: &str = "relief valves of hydraulic dampers, 0.1 to 100 kN";
const SLOPE_AFTER: (f64, f64) = (10.0, 2e6);
const SLOPE_AFTER_BOUNDS: Bounds = Bounds::left_open(0.0, 1e9);
const SLOPE_AFTER_WHY: &str = "dampers' slopes beyond their relief valves";
const SPACING: Bounds = Bounds::closed(1e-3, 20.0);
const HEIGHT: Bounds = Bounds::closed(-10.0, 10.0);
const SPEED: Bounds = Bounds::closed(1e-3, 1e5);

/// The rows of a spring section (`[suspension]`, `[secondary]`): the keys they share.
macro_rules! springs {
    ($p:literal, $what:literal) => {
        [
            row(
                concat!($p, ".lateral_stiffness"),
                Stiffness,
                (0.0, 1e8),
                STIFFNESS,
                concat!($what, " springs, from none to rigid guidance"),
            ),
            row(
                concat!($p, ".longitudinal_stiffness"),
                Stiffness,
                (0.0, 1e8),
                STIFFNESS,
                concat!($what, " springs, from none to rigid guidance"),
            ),
            row(
                concat!($p, ".lateral_damping"),
                Damping,
                (0.0, 2e6),
                DAMPING,
                concat!($what, " dampers"),
            ),
            row(
                concat!($p, ".longitudinal_damping"),
                Damping,
                (0.0, 2e6),
                DAMPING,
                concat!($what, " dampers"),
            ),
            row(
                concat!($p, ".half_spring_spacing"),
                Length,
                (0.3, 2.0),
                SPACING,
                concat!($what, " springs within the vehicle's width"),
            ),
            row(
                concat!($p, ".vertical_stiffness"),
                Stiffness,
                (0.0, 1e8),
                STIFFNESS,
                concat!($what, " vertical springs"),
            ),
            row(
                concat!($p, ".vertical_damping"),
                Damping,
                (0.0, 2e6),
                DAMPING,
                concat!($what, " vertical dampers"),
            ),
            row(
                concat!($p, ".height"),
                Length,
                (-1.5, 1.5),
                HEIGHT,
                "heights within a bogie frame",
            ),
            row(
                concat!($p, ".lateral_damper_series_stiffness"),
                Stiffness,
                (1e5, 1e9),
                SERIES,
                "rubber end bushes of dampers, soft to stiff",
            ),
            row(
                concat!($p, ".longitudinal_damper_series_stiffness"),
                Stiffness,
                (1e5, 1e9),
                SERIES,
                "rubber end bushes of dampers, soft to stiff",
            ),
            row(
                concat!($p, ".vertical_damper_series_stiffness"),
                Stiffness,
                (1e5, 1e9),
                SERIES,
                "rubber end bushes of dampers, soft to stiff",
            ),
            row(
                concat!($p, ".lateral_damper_force_velocity.blow_off_force"),
                Force,
                BLOW_OFF,
                BLOW_OFF_BOUNDS,
                BLOW_OFF_WHY,
            ),
            row(
                concat!($p, ".lateral_damper_force_velocity.slope_after"),
                Damping,
                SLOPE_AFTER,
                SLOPE_AFTER_BOUNDS,
                SLOPE_AFTER_WHY,
            ),
            row(
                concat!($p, ".longitudinal_damper_force_velocity.blow_off_force"),
                Force,
                BLOW_OFF,
                BLOW_OFF_BOUNDS,
                BLOW_OFF_WHY,
            ),
            row(
                concat!($p, ".longitudinal_damper_force_velocity.slope_after"),
                Damping,
                SLOPE_AFTER,
                SLOPE_AFTER_BOUNDS,
                SLOPE_AFTER_WHY,
            ),
            row(
                concat!($p, ".vertical_damper_force_velocity.blow_off_force"),
                Force,
                BLOW_OFF,
                BLOW_OFF_BOUNDS,
                BLOW_OFF_WHY,
            ),
            row(
                concat!($p, ".vertical_damper_force_velocity.slope_after"),
                Damping,
                SLOPE_AFTER,
                SLOPE_AFTER_BOUNDS,
                SLOPE_AFTER_WHY,
            ),
            row(
                concat!($p, ".bump_stop_clearance"),
                Length,
                (1e-3, 0.1),
                Bounds::left_open(0.0, 1.0),
                "lateral free play of primary (a few mm) and secondary (20-60 mm) stops",
            ),
            row(
                concat!($p, ".bump_stop_stiffness"),
                Stiffness,
                (1e5, 1e9),
                Bounds::left_open(0.0, 1e11),
                "rubber and steel lateral bump stops",
            ),
        ]
    };
}

/// The spring sections' rows, per side: the primary and the secondary share their keys.
#[rustfmt::skip]
const SPRINGS: [[Range; 19]; 2] = [springs!("suspension", "primary"), springs!("secondary", "secondary")];

/// Every range but the spring sections'. Why the numbers: see each `why`; stiffnesses end at
/// 1e11 N/m (a steel bar is about 1e9 N/m, a Hertz contact 1e9 N/m), dampings at 1e9 N s/m,
/// because beyond that they swamp the creep forces (about 1e7 N) beyond what an f64 Jacobian
/// resolves.
#[rustfmt::skip]
const OTHERS: &[Range] = &[
    // [wheelset]
    row("wheelset.mass", Mass, (300.0, 4000.0), Bounds::closed(0.1, 1e5),
        "wheelsets from light rail to motored locomotive axles"),
    row("wheelset.yaw_inertia", Inertia, (50.0, 4000.0), Bounds::closed(1e-4, 1e6),
        "railway wheelsets about the vertical axis"),
    row("wheelset.axle_load", Force, (2e4, 4.5e5), Bounds::closed(1.0, 1e7),
        "2 t (light rail) to 45 t (heavy haul) per axle"),
    row("wheelset.half_contact_distance", Length, (0.3, 1.0), Bounds::closed(0.01, 10.0),
        "half the contact-point distance of 600 mm to 1676 mm gauges"),
    // meaningful: scale models down to 1:20, the largest driving wheels (1.15 m) with margin
    row("wheelset.rolling_radius", Length, (0.2, 0.7), Bounds::closed(0.02, 2.0),
        "wheel diameters of 400 mm to 1400 mm"),
    // [bogie]
    row("bogie.mass", Mass, (300.0, 3e4), Bounds::closed(1.0, 1e6),
        "bogie frames, from light rail to locomotive frames with motors"),
    row("bogie.yaw_inertia", Inertia, (50.0, 1e5), Bounds::closed(1e-3, 1e8),
        "bogie frames about the vertical axis"),
    row("bogie.roll_inertia", Inertia, (50.0, 1e5), Bounds::closed(1e-3, 1e8),
        "bogie frames about the longitudinal axis"),
    row("bogie.half_wheelbase", Length, (0.5, 2.5), Bounds::closed(0.01, 50.0),
        "bogie wheelbases of 1 m to 5 m"),
    // [secondary]: its own keys (the shared ones are in SPRINGS)
    row("secondary.yaw_damping", Damping, (0.0, 1e7), DAMPING,
        "yaw dampers, up to the stiffest high-speed ones"),
    row("secondary.yaw_damper_series_stiffness", Stiffness, (1e6, 1e9), SERIES,
        "yaw dampers' end bushes (5 to 20 MN/m on high-speed cars)"),
    row("secondary.yaw_damper_force_velocity.blow_off_force", Force, BLOW_OFF,
        BLOW_OFF_BOUNDS, BLOW_OFF_WHY),
    row("secondary.yaw_damper_force_velocity.slope_after", Damping, SLOPE_AFTER,
        SLOPE_AFTER_BOUNDS, SLOPE_AFTER_WHY),
    row("secondary.yaw_damper_half_spacing", Length, (0.3, 2.0), SPACING,
        "yaw dampers within the vehicle's width"),
    row("secondary.vertical_half_spacing", Length, (0.3, 2.0), SPACING,
        "secondary springs within the vehicle's width"),
    // [carbody]
    row("carbody.mass", Mass, (3e3, 1.5e5), Bounds::closed(1.0, 1e7),
        "car bodies from light rail to loaded freight and locomotives"),
    row("carbody.yaw_inertia", Inertia, (1e4, 5e7), Bounds::closed(1.0, 1e11),
        "car bodies of 10 m to 30 m about the vertical axis"),
    row("carbody.roll_inertia", Inertia, (1e3, 5e6), Bounds::closed(1.0, 1e10),
        "car bodies about the longitudinal axis"),
    row("carbody.half_bogie_distance", Length, (1.5, 15.0), Bounds::closed(0.01, 500.0),
        "bogie centres 3 m to 30 m apart"),
    row("carbody.secondary_height", Length, (-2.5, 2.5), HEIGHT,
        "heights within a car body"),
    // [contact]
    row("contact.conicity", Dimensionless, (0.005, 0.5), Bounds::open(0.0, 1.0),
        "new to badly worn wheels"),
    row("contact.rail_head_radius", Length, (0.01, 1.0), Bounds::closed(1e-4, 100.0),
        "rail head crowns and gauge corners"),
    row("contact.crown_offset", Length, (0.0, 0.03), Bounds::closed(0.0, 10.0),
        "offsets within a rail head"),
    row("contact.friction", Dimensionless, (0.05, 0.6), Bounds::left_open(0.0, 2.0),
        "wet or contaminated (0.05) to dry sanded rail (0.6)"),
    row("contact.young_modulus", Pressure, (1e11, 3e11), Bounds::closed(1e6, 1e13),
        "wheel and rail steels"),
    row("contact.poisson_ratio", Dimensionless, (0.2, 0.35), Bounds::open(0.0, 0.5),
        "steels (0.27-0.30)"),
    row("contact.shear_modulus", Pressure, (5e10, 1.2e11), Bounds::closed(1e5, 1e13),
        "steels (about 80 GPa)"),
    row("contact.lateral_range", Length, (1e-3, 0.05), Bounds::closed(1e-5, 5.0),
        "the tread and the flange, up to flange contact"),
    row("contact.table_points", Dimensionless, (51.0, 20001.0), Bounds::closed(5.0, 100_001.0),
        "enough nodes for the C1 table, few enough to build it fast"),
    row("contact.track_gauge", Length, (0.75, 1.7), Bounds::closed(0.6, 2.0),
        "track gauges of 750 mm to 1676 mm"),
    row("contact.gauge_depth", Length, (0.005, 0.02), Bounds::closed(0.0, 0.04),
        "gauge points 5 mm to 20 mm below the rail top (14 mm in Europe)"),
    row("contact.profile_smoothing", Length, (0.0, 0.002), Bounds::closed(0.0, 0.005),
        "smoothing well below a millimetre-scale feature"),
    row("contact.creep_coefficients.f11", Force, (1e5, 5e7), Bounds::closed(1.0, 1e10),
        "Kalker's coefficients of railway contact patches"),
    row("contact.creep_coefficients.f22", Force, (1e5, 5e7), Bounds::closed(1.0, 1e10),
        "Kalker's coefficients of railway contact patches"),
    row("contact.creep_coefficients.f23", ForceLength, (0.0, 2e5), Bounds::closed(0.0, 1e8),
        "Kalker's coefficients of railway contact patches"),
    row("contact.creep_coefficients.f33", ForceArea, (0.0, 2e3), Bounds::closed(0.0, 1e6),
        "Kalker's coefficients of railway contact patches"),
    // [flange]
    row("flange.clearance", Length, (1e-3, 0.02), Bounds::closed(1e-5, 0.2),
        "flangeway clearances of new and worn wheels"),
    row("flange.stiffness", Stiffness, (1e6, 1e10), Bounds::closed(1.0, 1e12),
        "rail and flange contact stiffness"),
    // [linear], [bifurcation], [sweep]
    row("linear.speed_range", Speed, (0.1, 1000.0), SPEED,
        "railway speeds, scanned well beyond service speed"),
    row("linear.grid_points", Dimensionless, (16.0, 1e5), Bounds::closed(3.0, 1e6),
        "scan grids that resolve crossings without crawling"),
    row("linear.spectrum_points", Dimensionless, (10.0, 1e4), Bounds::closed(2.0, 1e5),
        "speeds in the spectra and plots"),
    row("bifurcation.speed_range", Speed, (0.1, 1000.0), SPEED,
        "railway speeds, scanned well beyond service speed"),
    row("bifurcation.max_amplitude", Length, (1e-4, 0.05), Bounds::closed(1e-7, 1.0),
        "hunting amplitudes up to flange contact"),
    row("bifurcation.rtol", Dimensionless, (1e-12, 1e-6), Bounds::closed(1e-13, 1e-4),
        "tolerances that locate folds"),
    row("bifurcation.floquet_rtol", Dimensionless, (1e-10, 1e-6), Bounds::closed(1e-13, 1e-4),
        "Floquet multipliers to 4 digits or better"),
    row("bifurcation.ds_max", Dimensionless, (0.01, 5.0), Bounds::left_open(0.0, 10.0),
        "steps that follow a branch"),
    row("bifurcation.max_points", Dimensionless, (10.0, 1e4), Bounds::closed(2.0, 1e5),
        "branches of tens to thousands of cycles"),
    row("bifurcation.segments", Dimensionless, (0.0, 32.0), Bounds::closed(0.0, 64.0),
        "shooting segments (0: the default, 4)"),
    row("sweep.operating_speed", Speed, (1.0, 200.0), SPEED,
        "service speeds up to 720 km/h"),
];

/// Every range: the spring sections', then the others.
pub fn ranges() -> impl Iterator<Item = &'static Range> {
    SPRINGS.iter().flatten().chain(OTHERS)
}

/// The row of `key` (an element `key[i]` uses the row of `key`).
pub fn range(key: &str) -> Option<&'static Range> {
    let base = key.split('[').next().unwrap_or(key);
    ranges().find(|r| r.key == base)
}

/// `Err` naming the key, the value and the meaningful range when `v` lies outside it.
pub fn meaningful(key: &str, v: f64) -> Result<(), StudyError> {
    match range(key) {
        Some(r) if !r.meaningful.contains(v) => Err(StudyError::Rule {
            key: key.to_string(),
            value: with_unit(v, r.dim),
            rule: format!(
                "must lie in {} for the model to mean anything (plausible: {}, {})",
                r.meaningful.show(r.dim.si_unit()),
                r.plausible.show(r.dim.si_unit()),
                r.why
            ),
        }),
        _ => Ok(()),
    }
}

/// A value outside its key's plausible range: the study is computed, and says so.
#[derive(Clone, Debug, PartialEq)]
pub struct Warning {
    /// dotted study key
    pub key: String,
    /// the value in SI
    pub value: f64,
    /// its SI unit ("" for a pure number)
    pub unit: &'static str,
    /// the plausible range
    pub plausible: Bounds,
    /// what the range covers
    pub why: &'static str,
}

impl fmt::Display for Warning {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let value = match self.unit {
            "" => si(self.value),
            u => format!("{} {u}", si(self.value)),
        };
        write!(
            f,
            "{} = {value} lies outside the plausible range {} ({}); computed as given",
            self.key,
            self.plausible.show(self.unit),
            self.why
        )
    }
}

/// The warning for `v` at `key`, when it lies outside the plausible range.
pub fn plausible(key: &str, v: f64) -> Option<Warning> {
    let r = range(key)?;
    (!r.plausible.contains(v)).then(|| Warning {
        key: key.to_string(),
        value: v,
        unit: r.dim.si_unit(),
        plausible: r.plausible,
        why: r.why,
    })
}

/// The warnings of a plan: every value of [`entries`] outside its plausible range.
pub fn warnings(p: &Plan) -> Vec<Warning> {
    entries(p)
        .iter()
        .flat_map(Entry::numbers)
        .filter_map(|(k, v)| plausible(&k, v))
        .collect()
}

fn with_unit(v: f64, dim: Dimension) -> String {
    match dim.si_unit() {
        "" => si(v),
        u => format!("{} {u}", si(v)),
    }
}

#[cfg(test)]
#[path = "plausible_tests.rs"]
mod tests;
