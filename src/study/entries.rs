//! The resolved plan as a list of (study key, value in SI): what `critspeed check` prints, and
//! what the plausibility check ([`super::plausible`]) walks. One place maps the plan's fields
//! back to the study's keys.

use std::fmt;

use super::units::Dimension::{self, *};
use super::Plan;
use crate::contact::creep::CreepLaw;
use crate::contact::geometry::Geometry;
use crate::contact::table::CreepSource;
use crate::model::{CarBodyParams, FrameParams, Secondary, VehicleSpec};
use crate::system::ode::Method;

/// A value of the plan as the study writes it.
#[derive(Clone, Debug, PartialEq)]
pub enum Shown {
    /// a quantity in SI
    Number(f64, Dimension),
    /// a `[min, max]` pair in SI
    Pair(f64, f64, Dimension),
    /// a count (nodes, points)
    Count(usize),
    /// a choice, a flag, a file or a note
    Text(String),
}

/// Plain decimals for ordinary magnitudes (`3860000`), the exponent form beyond them.
fn si(v: f64) -> String {
    if v == 0.0 || (1e-5..1e16).contains(&v.abs()) {
        format!("{v}")
    } else {
        format!("{v:e}")
    }
}

impl fmt::Display for Shown {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let unit = |d: &Dimension| match d.si_unit() {
            "" => String::new(),
            u => format!(" {u}"),
        };
        match self {
            Shown::Number(v, d) => write!(f, "{}{}", si(*v), unit(d)),
            Shown::Pair(a, b, d) => write!(f, "[{}, {}]{}", si(*a), si(*b), unit(d)),
            Shown::Count(n) => write!(f, "{n}"),
            Shown::Text(t) => f.write_str(t),
        }
    }
}

/// One key of the plan.
#[derive(Clone, Debug, PartialEq)]
pub struct Entry {
    /// dotted study key
    pub key: String,
    /// its resolved value
    pub shown: Shown,
}

impl Entry {
    /// The numbers of the entry with the key each is checked under (`key[0]`, `key[1]` for a
    /// pair).
    pub fn numbers(&self) -> Vec<(String, f64)> {
        match self.shown {
            Shown::Number(v, _) => vec![(self.key.clone(), v)],
            Shown::Pair(a, b, _) => vec![
                (format!("{}[0]", self.key), a),
                (format!("{}[1]", self.key), b),
            ],
            Shown::Count(n) => vec![(self.key.clone(), n as f64)],
            Shown::Text(_) => Vec::new(),
        }
    }
}

/// Collects entries under a section prefix.
struct Section<'a> {
    out: &'a mut Vec<Entry>,
    prefix: &'static str,
}

impl Section<'_> {
    fn put(&mut self, key: &str, shown: Shown) {
        self.out.push(Entry {
            key: format!("{}.{key}", self.prefix),
            shown,
        });
    }

    fn num(&mut self, key: &str, v: f64, d: Dimension) {
        self.put(key, Shown::Number(v, d));
    }

    fn text(&mut self, key: &str, t: impl Into<String>) {
        self.put(key, Shown::Text(t.into()));
    }

    /// mass, yaw and roll inertia of a body
    fn body(&mut self, mass: f64, yaw: f64, roll: Option<f64>) {
        self.num("mass", mass, Mass);
        self.num("yaw_inertia", yaw, Inertia);
        match roll {
            Some(r) => self.num("roll_inertia", r, Inertia),
            None => self.text("roll_inertia", "none (no roll state)"),
        }
    }

    /// the dampers' series stiffnesses (`yaw`: the secondary's yaw damper too)
    fn series(&mut self, d: &crate::model::DamperSeries, yaw: bool) {
        let mut one = |what: &str, k: Option<f64>| {
            let key = format!("{what}_damper_series_stiffness");
            match k {
                Some(k) => self.num(&key, k, Stiffness),
                None => self.text(&key, "none (damper rigidly attached)"),
            }
        };
        one("lateral", d.lateral);
        one("longitudinal", d.longitudinal);
        one("vertical", d.vertical);
        if yaw {
            one("yaw", d.yaw);
        }
    }

    /// the dampers' force–velocity curves, where given (`yaw`: the secondary's yaw damper too):
    /// a blow-off's two numbers under their sweep keys, a table's points as text
    fn curves(&mut self, c: &crate::model::DamperCurves, yaw: bool) {
        let mut one = |what: &str, g: Option<&crate::model::ForceVelocity>| {
            let Some(g) = g else { return };
            let key = format!("{what}_damper_force_velocity");
            match g.blow_off_form() {
                Some((force, after)) => {
                    self.num(&format!("{key}.blow_off_force"), force, Force);
                    self.num(&format!("{key}.slope_after"), after, Damping);
                }
                None => {
                    let (points, tail) = g.points();
                    let shown: Vec<String> = points
                        .iter()
                        .skip(1)
                        .map(|(v, f)| format!("[{} m/s, {} N]", si(*v), si(*f)))
                        .collect();
                    self.text(
                        &key,
                        format!("{}, then {} N s/m", shown.join(", "), si(tail)),
                    );
                }
            }
        };
        one("lateral", c.lateral.as_ref());
        one("longitudinal", c.longitudinal.as_ref());
        one("vertical", c.vertical.as_ref());
        if yaw {
            one("yaw", c.yaw.as_ref());
        }
    }

    /// the bump stop's keys
    fn bump_stop(&mut self, stop: Option<&crate::model::StopSpec>) {
        let Some(stop) = stop else {
            self.text("bump_stop_clearance", "none (no bump stop)");
            return;
        };
        self.num("bump_stop_clearance", stop.clearance, Length);
        self.num(
            "bump_stop_stiffness",
            stop.law.initial_stiffness(),
            Stiffness,
        );
        match &stop.law {
            crate::model::StopLaw::Linear(_) => self.text(
                "bump_stop_force_table",
                "none (linear beyond the clearance)",
            ),
            crate::model::StopLaw::Table(t) => {
                let points: Vec<String> = t
                    .points()
                    .iter()
                    .skip(1)
                    .map(|(p, g)| format!("[{} m, {} N]", si(*p), si(*g)))
                    .collect();
                self.text("bump_stop_force_table", points.join(", "))
            }
        }
    }

    /// the five keys the primary and the secondary share
    fn springs(&mut self, k: [f64; 4], spacing: f64) {
        self.num("lateral_stiffness", k[0], Stiffness);
        self.num("longitudinal_stiffness", k[1], Stiffness);
        self.num("lateral_damping", k[2], Damping);
        self.num("longitudinal_damping", k[3], Damping);
        self.num("half_spring_spacing", spacing, Length);
    }
}

/// Every key of the plan, in the study file's order, defaults filled.
pub fn entries(p: &Plan) -> Vec<Entry> {
    let mut out = Vec::new();
    let w = &p.wheelset;
    let mut s = Section {
        out: &mut out,
        prefix: "wheelset",
    };
    s.num("mass", w.mass, Mass);
    s.num("yaw_inertia", w.yaw_inertia, Inertia);
    s.num("axle_load", w.axle_load, Force);
    s.num("half_contact_distance", w.half_contact_distance, Length);
    s.num("rolling_radius", w.rolling_radius, Length);
    let u = &p.suspension;
    let mut s = Section {
        out: &mut out,
        prefix: "suspension",
    };
    s.springs(
        [
            u.lateral_stiffness,
            u.longitudinal_stiffness,
            u.lateral_damping,
            u.longitudinal_damping,
        ],
        u.half_spring_spacing,
    );
    s.num(
        "vertical_stiffness",
        p.primary_vertical.stiffness,
        Stiffness,
    );
    s.num("vertical_damping", p.primary_vertical.damping, Damping);
    s.num("height", p.primary_vertical.height, Length);
    s.series(&p.primary_vertical.series, false);
    s.curves(&p.primary_vertical.curves, false);
    s.bump_stop(p.primary_vertical.bump_stop.as_ref());
    vehicle(&mut out, &p.vehicle);
    contact(&mut out, p);
    let mut s = Section {
        out: &mut out,
        prefix: "flange",
    };
    match &p.flange {
        Some(f) => {
            s.num("clearance", f.clearance, Length);
            s.num("stiffness", f.stiffness, Stiffness);
        }
        None => s.out.push(Entry {
            key: "flange".into(),
            shown: Shown::Text("none".into()),
        }),
    }
    let mut s = Section {
        out: &mut out,
        prefix: "linear",
    };
    let (lo, hi) = p.linear.speed_range;
    s.put("speed_range", Shown::Pair(lo, hi, Speed));
    s.put("grid_points", Shown::Count(p.grid_points()));
    s.put("spectrum_points", Shown::Count(p.spectrum_points));
    if let Some(b) = &p.bifurcation {
        let mut s = Section {
            out: &mut out,
            prefix: "bifurcation",
        };
        s.put(
            "speed_range",
            Shown::Pair(b.speed_range.0, b.speed_range.1, Speed),
        );
        s.num("max_amplitude", b.max_amplitude, Length);
        s.num("rtol", b.rtol, Dimensionless);
        s.num("ds_max", b.ds_max, Dimensionless);
        s.put("max_points", Shown::Count(b.max_points));
        s.put("segments", Shown::Count(b.segments));
        s.text("switch", b.switch.to_string());
        s.put("max_branches", Shown::Count(b.max_branches));
        s.text("corrector", if b.chord { "chord" } else { "newton" });
        s.text(
            "integrator",
            match b.integrator {
                Method::DormandPrince5 => "dopri5",
                Method::DormandPrince8 => "dop853",
            },
        );
    }
    if let Some(a) = &p.attractors {
        let mut s = Section {
            out: &mut out,
            prefix: "attractors",
        };
        let o = a.options(
            p.bifurcation_options().speed_range,
            None,
            p.contact.analysis_limit(),
        );
        match a.speed_range {
            Some((lo, hi)) => s.put("speed_range", Shown::Pair(lo, hi, Speed)),
            None => s.text(
                "speed_range",
                "from 0.5 to 1.1 times the Hopf speed of the creep law (within the bifurcation range)",
            ),
        }
        s.put("speeds", Shown::Count(o.speeds));
        s.text(
            "amplitudes",
            o.amplitudes
                .iter()
                .map(|v| format!("{v} m"))
                .collect::<Vec<_>>()
                .join(", "),
        );
        s.num("settle", o.settle, Dimension::Time);
        s.num("bracket", o.bracket, Speed);
        s.num("descent_step", o.descent_step, Dimensionless);
        s.num("lowest", o.lowest, Speed);
        s.num("threshold", o.threshold, Length);
        s.num("rtol", o.rtol, Dimensionless);
        s.put("max_period", Shown::Count(o.max_period));
    }
    out
}

/// `vehicle.kind` and the `[bogie]`, `[secondary]`, `[carbody]` keys.
fn vehicle(out: &mut Vec<Entry>, v: &VehicleSpec) {
    let (kind, frame, sec, body): (_, Option<&FrameParams>, Option<&Secondary>, _) = match v {
        VehicleSpec::Wheelset => ("wheelset", None, None, None),
        VehicleSpec::Bogie { frame, secondary } => ("bogie", Some(frame), Some(secondary), None),
        VehicleSpec::Car {
            frame,
            secondary,
            body,
        } => ("car", Some(frame), Some(secondary), Some(body)),
    };
    out.push(Entry {
        key: "vehicle.kind".into(),
        shown: Shown::Text(kind.into()),
    });
    if let Some(f) = frame {
        let mut s = Section {
            out,
            prefix: "bogie",
        };
        s.body(f.mass, f.yaw_inertia, f.roll_inertia);
        s.num("half_wheelbase", f.half_wheelbase, Length);
    }
    if let Some(c) = sec {
        secondary(out, c);
    }
    if let Some(b) = body {
        carbody(out, b);
    }
}

fn secondary(out: &mut Vec<Entry>, c: &Secondary) {
    let mut s = Section {
        out,
        prefix: "secondary",
    };
    s.springs(
        [
            c.lateral_stiffness,
            c.longitudinal_stiffness,
            c.lateral_damping,
            c.longitudinal_damping,
        ],
        c.half_spring_spacing,
    );
    s.num("yaw_damping", c.yaw_damping, Damping);
    s.num("yaw_damper_half_spacing", c.yaw_damper_half_spacing, Length);
    s.num("vertical_stiffness", c.vertical_stiffness, Stiffness);
    s.num("vertical_damping", c.vertical_damping, Damping);
    s.num("vertical_half_spacing", c.vertical_half_spacing, Length);
    s.num("height", c.height, Length);
    s.series(&c.series, true);
    s.curves(&c.curves, true);
    s.bump_stop(c.bump_stop.as_ref());
}

fn carbody(out: &mut Vec<Entry>, b: &CarBodyParams) {
    let mut s = Section {
        out,
        prefix: "carbody",
    };
    s.body(b.mass, b.yaw_inertia, b.roll_inertia);
    s.num("half_bogie_distance", b.half_bogie_distance, Length);
    s.num("secondary_height", b.secondary_height, Length);
}

/// The `[contact]` keys.
fn contact(out: &mut Vec<Entry>, p: &Plan) {
    let c = &p.contact;
    let mut s = Section {
        out,
        prefix: "contact",
    };
    match &c.geometry {
        &Geometry::Cone { conicity } => {
            s.text("geometry", "cone");
            s.num("conicity", conicity, Dimensionless);
        }
        &Geometry::ConeOnArc {
            conicity,
            rail_head_radius,
            crown_offset,
        } => {
            s.text("geometry", "cone-on-arc");
            s.num("conicity", conicity, Dimensionless);
            s.num("rail_head_radius", rail_head_radius, Length);
            s.num("crown_offset", crown_offset, Length);
        }
        Geometry::Table(t) => {
            s.text("geometry", "table");
            s.text("geometry_table", t.source.clone());
        }
        Geometry::Profiles { pair, smoothing } => {
            s.text("geometry", "profiles");
            s.text("wheel_profile", pair.files.0.clone());
            s.text("rail_profile", pair.files.1.clone());
            s.num("track_gauge", pair.track.gauge, Length);
            s.num("gauge_depth", pair.track.gauge_depth, Length);
            s.text(
                "rail_inclination",
                format!(
                    "{} rad (applied to the rail file)",
                    si(pair.track.inclination)
                ),
            );
            s.num("profile_smoothing", *smoothing, Length);
        }
    }
    if let (Some(r), false) = (
        c.rail_head_radius,
        matches!(c.geometry, Geometry::ConeOnArc { .. }),
    ) {
        s.num("rail_head_radius", r, Length);
    }
    match c.creep_law {
        CreepLaw::Kalker => s.text("creep_law", "kalker"),
        CreepLaw::Shen { friction } => {
            s.text("creep_law", "shen");
            s.num("friction", friction, Dimensionless);
        }
    }
    s.text("spin", c.spin.to_string());
    s.num("young_modulus", c.elastic.young_modulus, Pressure);
    s.num("poisson_ratio", c.elastic.poisson_ratio, Dimensionless);
    s.num("shear_modulus", c.elastic.shear_modulus, Pressure);
    match c.creep {
        CreepSource::Given(k) => {
            s.num("creep_coefficients.f11", k.f11, Force);
            s.num("creep_coefficients.f22", k.f22, Force);
            s.num("creep_coefficients.f23", k.f23, ForceLength);
            s.num("creep_coefficients.f33", k.f33, ForceArea);
        }
        CreepSource::Hertz => s.text(
            "creep_coefficients",
            match &c.geometry {
                Geometry::Table(t) if t.has_kalker() => {
                    "from the geometry table's a, b and Kalker C at each contact state (C33 from Kalker's table unless tabulated)"
                }
                _ => "from the Hertz patch and Kalker's table at each contact state",
            },
        ),
    }
    s.num("lateral_range", c.lateral_range, Length);
    s.put("table_points", Shown::Count(c.table_points));
    s.text(
        "extrapolate",
        match (c.extrapolate, c.valid_half_width()) {
            (_, None) => format!(
                "{} (the cone's linear extension is exact: no range)",
                c.extrapolate.name()
            ),
            (e, Some(w)) => format!(
                "{} (the geometry is genuine within ±{w} m; analyses {} beyond it)",
                e.name(),
                match e {
                    crate::contact::table::Extrapolation::None => "stop",
                    crate::contact::table::Extrapolation::Linear => "extend it linearly",
                }
            ),
        },
    );
}
