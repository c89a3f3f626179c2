//! Results to bytes (pure functions) and the one place that writes files.
//!
//! Numbers are written with Rust's shortest round-trip formatting, so a program reading the
//! CSV or JSON gets exactly the `f64` that was computed. Every CSV header carries its unit.

mod attractors;
mod curve;
mod plan;

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use serde_json::{json, Value};

use crate::analysis::{GeometryReport, LinearReport};
use crate::stability::{CriticalSpeeds, Crossing, Spectrum};

pub use attractors::{attractors_csv, attractors_json, seed_check_json, ATTRACTOR_KIND};
pub use curve::{curve_csv, curve_json, curve_key_column, CURVE_KIND};
pub use plan::plan_json;

/// What every linear output calls the speeds it reports.
pub const LINEAR_KIND: &str = "linear critical speed: Hopf bifurcation of the centred motion \
(a complex eigenvalue pair of the exact Jacobian crosses the imaginary axis)";

fn crossing_json(c: &Crossing) -> Value {
    json!({
        "speed_m_s": c.speed_m_s,
        "speed_km_h": c.speed_m_s * 3.6,
        "frequency_hz": c.frequency_hz,
        "wavelength_m": c.wavelength_m,
        "direction": c.direction.name(),
        "bracket_m_s": c.bracket_m_s,
    })
}

fn mode_json(m: &crate::analysis::ModeShape) -> Value {
    let bodies: Vec<Value> = m
        .bodies
        .iter()
        .map(|b| {
            json!({
                "body": b.body,
                "lateral": b.lateral,
                "yaw": b.yaw,
                "lateral_phase_deg": b.lateral_phase_deg,
                "yaw_phase_deg": b.yaw_phase_deg,
                "reach": b.reach,
            })
        })
        .collect();
    let dampers: Vec<Value> = m
        .dampers
        .iter()
        .map(|d| {
            json!({
                "damper": d.damper,
                "stroke_per_y1": d.stroke_per_y1,
                "stroke_phase_deg": d.stroke_phase_deg,
                "deflection_share": d.deflection_share,
            })
        })
        .collect();
    json!({
        "label": m.label,
        "leading_body": m.leading_body,
        "bodies": bodies,
        "dampers": dampers,
    })
}

/// The first Lyapunov coefficient's fields of a crossing (`null` where it was not computed):
/// $l_1$ in 1/m² (normalised to the leading wheelset's lateral amplitude), its error
/// estimate and the Hopf type it gives.
pub fn lyapunov_fields(l: Option<&crate::stability::Lyapunov>) -> [(&'static str, Value); 3] {
    [
        ("first_lyapunov_coefficient", json!(l.map(|l| l.l1))),
        (
            "first_lyapunov_coefficient_error",
            json!(l.map(|l| l.error)),
        ),
        ("hopf_type", json!(l.map(|l| l.kind().name()))),
    ]
}

/// The crossings, each with its mode shape when one was computed and its first Lyapunov
/// coefficient.
fn crossings_json(
    c: &CriticalSpeeds,
    modes: &[Option<crate::analysis::ModeShape>],
    l1: &[Option<crate::stability::Lyapunov>],
) -> Value {
    Value::Array(
        c.crossings
            .iter()
            .enumerate()
            .map(|(k, x)| {
                let mut v = crossing_json(x);
                if let Some(o) = v.as_object_mut() {
                    for (key, value) in lyapunov_fields(l1.get(k).and_then(Option::as_ref)) {
                        o.insert(key.into(), value);
                    }
                }
                if let (Some(Some(m)), Some(o)) = (modes.get(k), v.as_object_mut()) {
                    o.insert("mode".into(), Value::from(m.label));
                    o.insert("leading_body".into(), Value::from(m.leading_body.clone()));
                    o.insert("mode_shape".into(), mode_json(m));
                }
                v
            })
            .collect(),
    )
}

fn details_json(
    c: &CriticalSpeeds,
    modes: &[Option<crate::analysis::ModeShape>],
    l1: &[Option<crate::stability::Lyapunov>],
) -> Value {
    json!({
        "creep_law": c.law.name(),
        "stable_at_range_start": c.stable_at_start,
        "critical_speed_m_s": c.critical().map(|x| x.speed_m_s),
        "crossings": crossings_json(c, modes, l1),
        "divergence_speeds_m_s": c.divergence_speeds_m_s,
        "polynomial_evaluations": c.evaluations,
    })
}

/// The linear results as one JSON object (the `--json` contract and `linear.json`).
pub fn linear_json(r: &LinearReport) -> Value {
    let law = r.law_crossings();
    let law_modes = if r.creep_law.is_some() {
        &r.creep_law_modes
    } else {
        &r.kalker_modes
    };
    json!({
        "study": r.study,
        "kind": LINEAR_KIND,
        "layout": r.layout.0,
        "states": r.layout.1,
        "speed_range_m_s": [r.kalker.speed_range.0, r.kalker.speed_range.1],
        "creep_law": law.law.name(),
        "critical_speeds": crossings_json(&r.kalker, &r.kalker_modes, &r.kalker_lyapunov),
        "creep_law_hopf_speeds": crossings_json(law, law_modes, r.law_lyapunov()),
        "linear_critical_speed_m_s": r.kalker.critical().map(|c| c.speed_m_s),
        "creep_law_hopf_speed_m_s": law.critical().map(|c| c.speed_m_s),
        "centre_conicity": r.centre_conicity,
        "klingel_wavelength_m": r.klingel_wavelength_m,
        "wheelset_conicities": r.wheelset_conicities,
        "kalker": details_json(&r.kalker, &r.kalker_modes, &r.kalker_lyapunov),
        "creep_law_details": details_json(law, law_modes, r.law_lyapunov()),
        "notes": r.notes,
    })
}

/// `spectrum.csv`: one row per (creep law, speed), every eigenvalue (one per state) and its
/// damping ratio.
pub fn spectrum_csv(r: &LinearReport) -> String {
    let mut s = String::from("creep_law,speed_m_s");
    for k in 1..=r.layout.1 {
        let _ = write!(
            s,
            ",eig{k}_re_per_s,eig{k}_im_rad_per_s,eig{k}_damping_ratio"
        );
    }
    s.push_str(",least_damping_ratio\n");
    let mut rows = |law: &str, spectra: &[Spectrum]| {
        for sp in spectra {
            let _ = write!(s, "{law},{}", sp.speed_m_s);
            for p in &sp.pairs {
                let _ = write!(s, ",{},{},{}", p.re, p.im, p.damping_ratio());
            }
            let _ = writeln!(s, ",{}", sp.least_damping_ratio());
        }
    };
    rows("kalker", &r.spectrum_kalker);
    if let Some(c) = &r.creep_law {
        rows(c.law.name(), &r.spectrum_creep_law);
    }
    s
}

/// `geometry.csv`: the contact state against y (right wheel; left by symmetry).
pub fn geometry_csv(g: &GeometryReport) -> String {
    let mut s = String::from(
        "y_m,r_right_m,r_right_minus_r_left_m,delta_right_rad,delta_left_rad,roll_rad,\
hertz_a_right_m,hertz_b_right_m,f11_right_n,f22_right_n,f23_right_n_m,f33_right_n_m2,\
wheel_contact_offset_right_m\n",
    );
    let n = g.rows.len();
    for (k, row) in g.rows.iter().enumerate() {
        // The grid is symmetric, so the left wheel at y is the right wheel at −y: row n−1−k.
        let mirror = &g.rows[n - 1 - k];
        let (a, b) = row
            .semi_axes
            .map_or((String::new(), String::new()), |(a, b)| {
                (a.to_string(), b.to_string())
            });
        let _ = writeln!(
            s,
            "{},{},{},{},{},{},{a},{b},{},{},{},{},{}",
            row.y,
            row.point.radius,
            row.point.radius - mirror.point.radius,
            row.point.angle,
            mirror.point.angle,
            row.point.roll,
            row.creep.f11,
            row.creep.f22,
            row.creep.f23,
            row.creep.f33,
            if row.point.wheel_offset.is_nan() {
                String::new()
            } else {
                row.point.wheel_offset.to_string()
            },
        );
    }
    s
}

/// The output folder of a study, `<root>/<name>`, created if needed.
pub fn study_dir(root: &Path, name: &str) -> std::io::Result<PathBuf> {
    let dir = root.join(name);
    std::fs::create_dir_all(&dir)?;
    Ok(dir)
}

/// Writes `bytes` to `dir/file` and returns the path written.
pub fn write(dir: &Path, file: &str, bytes: &[u8]) -> std::io::Result<PathBuf> {
    let path = dir.join(file);
    std::fs::write(&path, bytes)?;
    Ok(path)
}

/// What the bifurcation outputs call the speeds they report.
pub const NONLINEAR_KIND: &str = "nonlinear critical speed: the lowest speed at which a stable \
hunting motion exists (every branch of cycles the continuation followed, with branch switching; \
and every attractor of the search where one ran)";

/// A V_NL candidate as JSON (the entries of `nonlinear_critical_speed_sources`).
pub fn vnl_candidate_json(c: &crate::bifurcation::VnlCandidate) -> Value {
    json!({
        "speed_m_s": c.speed_m_s,
        "located": c.located,
        "method": c.method.name(),
        "what": c.what,
        "branch": c.branch,
        "bracket_m_s": c.bracket_m_s.map(|(a, b)| [a, b]),
        "bracket_open": c.bracket_open,
    })
}

/// The bifurcation results as one JSON object (`--json` and `bifurcation.json`).
pub fn bifurcation_json(r: &crate::bifurcation::BifurcationReport) -> Value {
    let special: Vec<Value> = r
        .special
        .iter()
        .map(|s| {
            json!({
                "branch": s.branch,
                "kind": s.kind.name(),
                "speed_m_s": s.speed_m_s,
                "amplitude_y_m": s.amplitude_y_m,
                "located": s.located,
            })
        })
        .collect();
    let branches: Vec<Value> = r
        .branches
        .iter()
        .map(|b| {
            let cycles = r.cycles.iter().filter(|c| c.branch == b.id);
            let (lo, hi) = cycles.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), c| {
                (lo.min(c.speed_m_s), hi.max(c.speed_m_s))
            });
            let joined = b.parent.and_then(|(_, k)| r.special.get(k)).map(|s| {
                json!({
                    "kind": s.kind.name(),
                    "speed_m_s": s.speed_m_s,
                    "amplitude_y_m": s.amplitude_y_m,
                    "located": s.located,
                })
            });
            json!({
                "id": b.id,
                "kind": b.kind.name(),
                "parent": b.parent.map(|p| p.0),
                "joined_at": joined,
                "switch_multiplier": b.switch_multiplier,
                "mirror": matches!(b.kind, crate::bifurcation::BranchKind::Asymmetric)
                    .then_some("one of a mirror pair: the other is -x(t + T/2), the same cycles seen in the mirror"),
                "cycles": b.cycles,
                "speed_range_m_s": (b.cycles > 0).then_some([lo, hi]),
                "stop_reason": b.stop_reason,
                "segments": b.segments,
                "segments_doubled": b.segments_doubled.iter().map(|(v, m)| json!({
                    "after_speed_m_s": v,
                    "segments": m,
                })).collect::<Vec<_>>(),
            })
        })
        .collect();
    let worst_trivial = r
        .cycles
        .iter()
        .map(|c| c.trivial_multiplier_error)
        .fold(0.0, f64::max);
    json!({
        "study": r.study,
        "kind": NONLINEAR_KIND,
        "creep_law": r.law.name(),
        "speed_range_m_s": [r.speed_range.0, r.speed_range.1],
        "kalker_critical_speed_m_s": r.kalker_critical_speed_m_s,
        "hopf_speed_m_s": r.hopf.map(|h| h.speed_m_s),
        "hopf_frequency_hz": r.hopf.map(|h| h.frequency_hz),
        "hopf_type": r.hopf_type.map(|t| t.name()),
        "first_lyapunov_coefficient": r.first_lyapunov.as_ref().map(|l| l.l1),
        "first_lyapunov_coefficient_error": r.first_lyapunov.as_ref().map(|l| l.error),
        "hopf_type_from_l1": r.first_lyapunov.as_ref().map(|l| l.kind().name()),
        "hopf_type_note": hopf_type_note(r),
        "nonlinear_critical_speed_m_s": r.nonlinear_critical_speed.map(|v| v.0),
        "nonlinear_critical_speed_located": r.nonlinear_critical_speed.map(|v| v.1),
        "nonlinear_critical_speed_sources": r.nonlinear_sources.iter().map(vnl_candidate_json).collect::<Vec<_>>(),
        "branches": branches,
        "special_points": special,
        "stop_reason": r.stop_reason,
        "notes": r.notes,
        "cycles": r.cycles.len(),
        "max_trivial_multiplier_error": worst_trivial,
    })
}

/// In words, when the Hopf type from the branch's direction and the one from $l_1$ are not
/// the same (or $l_1$ does not decide it); `None` when they agree or either is missing.
pub fn hopf_type_note(r: &crate::bifurcation::BifurcationReport) -> Option<String> {
    use crate::bifurcation::HopfType;
    use crate::stability::HopfKind;
    let (branch, l) = (r.hopf_type?, r.first_lyapunov.as_ref()?);
    let same = matches!(
        (branch, l.kind()),
        (HopfType::Supercritical, HopfKind::Supercritical)
            | (HopfType::Subcritical, HopfKind::Subcritical)
    );
    (!same).then(|| {
        format!(
            "the branch leaves the Hopf point as a {} one, but l1 = {:.4e} 1/m^2 (error estimate {:.1e}) says {}{}",
            branch.name(),
            l.l1,
            l.error,
            l.kind().name(),
            if l.kind() == HopfKind::Undecided {
                ": its sign is not decided (near a Bautin point, or the contact table is not smooth at the difference steps)"
            } else {
                ": the branch direction is decided by its first cycles, l1 by the equilibrium's derivatives"
            }
        )
    })
}

/// `branch.csv`: one row per computed cycle, branch by branch. The wheelset's columns are
/// fixed; a vehicle's start state and multipliers have one column per state, followed by every
/// body's amplitudes (`amp_y_<body>_m`, `amp_psi_<body>_rad`).
pub fn branch_csv(r: &crate::bifurcation::BifurcationReport) -> String {
    let mut s = String::from(
        "branch,branch_kind,speed_m_s,amplitude_y_m,amplitude_y_right_m,amplitude_y_left_m,\
amplitude_psi_rad,period_s,frequency_hz,stable,max_multiplier_abs,trivial_multiplier_error,\
newton_iterations",
    );
    let states = r.state_names.len();
    if states == 4 {
        s.push_str(",y0_m,psi0_rad,ydot0_m_s,psidot0_rad_s");
    } else {
        for n in &r.state_names {
            let _ = write!(s, ",x0_{n}");
        }
    }
    for k in 1..=states {
        let _ = write!(s, ",mu{k}_re,mu{k}_im");
    }
    if states != 4 {
        for b in &r.body_names {
            let b = b.replace(' ', "_");
            let _ = write!(s, ",amp_y_{b}_m,amp_psi_{b}_rad");
        }
    }
    s.push('\n');
    for c in &r.cycles {
        let kind = r
            .branches
            .get(c.branch)
            .map_or_else(|| "symmetric".to_string(), |b| b.kind.name());
        let _ = write!(
            s,
            "{},{kind},{},{},{},{},{},{},{},{},{},{},{}",
            c.branch,
            c.speed_m_s,
            c.amplitude_y_m,
            c.amplitude_sides_y_m.0,
            c.amplitude_sides_y_m.1,
            c.amplitude_psi_rad,
            c.period_s,
            1.0 / c.period_s,
            c.stable,
            c.max_multiplier_abs,
            c.trivial_multiplier_error,
            c.newton_iterations,
        );
        for x in &c.x0 {
            let _ = write!(s, ",{x}");
        }
        for (re, im) in &c.multipliers {
            let _ = write!(s, ",{re},{im}");
        }
        for (y, psi) in &c.body_amplitudes {
            let _ = write!(s, ",{y},{psi}");
        }
        s.push('\n');
    }
    s
}

/// `simulate.csv`: the time histories, one block per speed, one column per state.
pub fn simulate_csv(runs: &[crate::simulate::TimeHistory]) -> String {
    let names = runs.first().map_or(&[][..], |h| &h.state_names[..]);
    let mut s = String::from("speed_m_s,time_s");
    for n in names {
        let _ = write!(s, ",{n}");
    }
    s.push('\n');
    for h in runs {
        for (t, x) in h.t.iter().zip(&h.x) {
            let _ = write!(s, "{},{t}", h.speed_m_s);
            for v in x {
                let _ = write!(s, ",{v}");
            }
            s.push('\n');
        }
    }
    s
}
