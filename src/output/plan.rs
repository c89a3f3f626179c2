//! The resolved plan as JSON: the study file's sections and keys, every quantity a number in
//! SI, defaults filled (`critspeed check` prints the same as a table; Python's `check()`
//! returns this object). For the cone and cone-on-arc geometries the object is itself a valid
//! study (a dict study given back to the library resolves to the same plan).

use serde_json::{json, Map, Value};

use crate::contact::creep::CreepLaw;
use crate::contact::geometry::Geometry;
use crate::contact::table::CreepSource;
use crate::study::Plan;

fn contact_json(p: &Plan) -> Value {
    let c = &p.contact;
    let mut m = Map::new();
    let mut put = |k: &str, v: Value| {
        m.insert(k.to_string(), v);
    };
    match &c.geometry {
        Geometry::Cone { conicity } => {
            put("geometry", json!("cone"));
            put("conicity", json!(conicity));
        }
        Geometry::ConeOnArc {
            conicity,
            crown_offset,
            ..
        } => {
            put("geometry", json!("cone-on-arc"));
            put("conicity", json!(conicity));
            put("crown_offset", json!(crown_offset));
        }
        Geometry::Table(t) => {
            put("geometry", json!("table"));
            put("geometry_table", json!(t.source));
        }
        Geometry::Profiles { pair, smoothing } => {
            put("geometry", json!("profiles"));
            put("wheel_profile", json!(pair.files.0));
            put("rail_profile", json!(pair.files.1));
            put("track_gauge", json!(pair.track.gauge));
            put("gauge_depth", json!(pair.track.gauge_depth));
            put("rail_inclination_rad", json!(pair.track.inclination));
            put("profile_smoothing", json!(smoothing));
        }
    }
    if let Some(r) = c.rail_head_radius {
        put("rail_head_radius", json!(r));
    }
    match c.creep_law {
        CreepLaw::Kalker => put("creep_law", json!("kalker")),
        CreepLaw::Shen { friction } => {
            put("creep_law", json!("shen"));
            put("friction", json!(friction));
        }
    }
    put("spin", json!(c.spin));
    put("young_modulus", json!(c.elastic.young_modulus));
    put("poisson_ratio", json!(c.elastic.poisson_ratio));
    put("shear_modulus", json!(c.elastic.shear_modulus));
    put("lateral_range", json!(c.lateral_range));
    put("table_points", json!(c.table_points));
    put("extrapolate", json!(c.extrapolate.name()));
    if let CreepSource::Given(k) = c.creep {
        put(
            "creep_coefficients",
            json!({"f11": k.f11, "f22": k.f22, "f23": k.f23, "f33": k.f33}),
        );
    }
    Value::Object(m)
}

/// The plan as one JSON object (see the module docs).
pub fn plan_json(p: &Plan) -> Value {
    let w = &p.wheelset;
    let s = &p.suspension;
    let mut v = json!({
        "name": p.name,
        "description": p.description,
        "wheelset": {
            "mass": w.mass,
            "yaw_inertia": w.yaw_inertia,
            "axle_load": w.axle_load,
            "half_contact_distance": w.half_contact_distance,
            "rolling_radius": w.rolling_radius,
        },
        "suspension": {
            "lateral_stiffness": s.lateral_stiffness,
            "longitudinal_stiffness": s.longitudinal_stiffness,
            "lateral_damping": s.lateral_damping,
            "longitudinal_damping": s.longitudinal_damping,
            "half_spring_spacing": s.half_spring_spacing,
        },
        "contact": contact_json(p),
        "linear": {
            "speed_range": [p.linear.speed_range.0, p.linear.speed_range.1],
            "grid_points": p.grid_points(),
            "spectrum_points": p.spectrum_points,
        },
    });
    if let Value::Object(m) = &mut v {
        if let Some(f) = &p.flange {
            m.insert(
                "flange".into(),
                json!({"clearance": f.clearance, "stiffness": f.stiffness}),
            );
        }
        if let Some(b) = &p.bifurcation {
            m.insert(
                "bifurcation".into(),
                json!({
                    "speed_range": [b.speed_range.0, b.speed_range.1],
                    "max_amplitude": b.max_amplitude,
                    "rtol": b.rtol,
                    "ds_max": b.ds_max,
                    "max_points": b.max_points,
                }),
            );
        }
    }
    v
}
