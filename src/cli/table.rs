//! Human-readable tables for the terminal. Every number carries its unit.

use std::fmt::Write as _;

use crate::analysis::{GeometryReport, LinearReport};
use crate::contact::creep::CreepLaw;
use crate::contact::geometry::Geometry;
use crate::contact::table::CreepSource;
use crate::stability::CriticalSpeeds;
use crate::study::Plan;

fn crossings(
    s: &mut String,
    label: &str,
    c: &CriticalSpeeds,
    modes: Option<&[Option<crate::analysis::ModeShape>]>,
    l1: &[Option<crate::stability::Lyapunov>],
) {
    if !c.stable_at_start {
        let _ = writeln!(
            s,
            "  {label:<22} already unstable at {:.3} m/s (the start of the range)",
            c.speed_range.0
        );
    }
    if c.crossings.is_empty() {
        let _ = writeln!(
            s,
            "  {label:<22} no crossing in [{}, {}] m/s",
            c.speed_range.0, c.speed_range.1
        );
    }
    for (k, x) in c.crossings.iter().enumerate() {
        let _ = write!(
            s,
            "  {label:<22} {:<9} {:>12.6} {:>9.2} {:>10.4} {:>10.3}",
            x.direction.name(),
            x.speed_m_s,
            x.speed_m_s * 3.6,
            x.frequency_hz,
            x.wavelength_m
        );
        // the Hopf type from the first Lyapunov coefficient (1/m², docs/model.md §12)
        if let Some(Some(l)) = l1.get(k) {
            let _ = write!(s, "  l1 {:+.3e} 1/m2 {}", l.l1, l.kind().name());
        }
        // vehicles: the mode and the body that leads it
        if let Some(Some(m)) = modes.and_then(|m| m.get(k)) {
            let _ = write!(s, "  {} ({} leads)", m.label, m.leading_body);
        }
        s.push('\n');
    }
    for v in &c.divergence_speeds_m_s {
        let _ = writeln!(
            s,
            "  {label:<22} a real eigenvalue crosses zero (divergence) at {v:.6} m/s"
        );
    }
}

/// The linear results.
pub fn linear(plan: &Plan, r: &LinearReport) -> String {
    let mut s = String::new();
    let (lo, hi) = r.kalker.speed_range;
    let _ = writeln!(
        s,
        "\nstudy '{}': linear stability of the centred motion, V in [{lo}, {hi}] m/s",
        plan.name
    );
    let _ = writeln!(
        s,
        "  effective conicity at the centre {:.5}, kinematic (Klingel) wavelength {:.3} m",
        r.centre_conicity, r.klingel_wavelength_m
    );
    let _ = writeln!(
        s,
        "  {:<22} {:<9} {:>12} {:>9} {:>10} {:>10}",
        "model", "crossing", "speed (m/s)", "(km/h)", "freq (Hz)", "wave (m)"
    );
    let vehicle = r.layout.1 > 4;
    if vehicle {
        let _ = writeln!(s, "  vehicle: {} ({} states)", r.layout.0, r.layout.1);
    }
    let kalker_modes = vehicle.then_some(&r.kalker_modes[..]);
    crossings(
        &mut s,
        "Kalker: linear V_L",
        &r.kalker,
        kalker_modes,
        &r.kalker_lyapunov,
    );
    if let Some(c) = &r.creep_law {
        let label = format!("{}: Hopf V_H", c.law.name());
        let modes = vehicle.then_some(&r.creep_law_modes[..]);
        crossings(&mut s, &label, c, modes, &r.creep_law_lyapunov);
    }
    // How far from instability the top of the range is, so "no crossing" has a measure.
    for (name, spectra) in [
        ("Kalker", &r.spectrum_kalker),
        ("creep law", &r.spectrum_creep_law),
    ] {
        if let Some(last) = spectra.last() {
            let _ = writeln!(
                s,
                "  least damping ratio at {:.1} m/s ({name}): {:.4}",
                last.speed_m_s,
                last.least_damping_ratio()
            );
        }
    }
    s
}

/// A summary of the geometry table.
pub fn geometry(g: &GeometryReport) -> String {
    let mut s = String::new();
    let n = g.rows.len();
    let (first, last) = (g.rows.first(), g.rows.last());
    if let (Some(a), Some(b)) = (first, last) {
        let _ = writeln!(
            s,
            "\nstudy '{}': contact geometry tabulated at {n} points, y in [{:.4}, {:.4}] mm",
            g.study,
            a.y * 1e3,
            b.y * 1e3
        );
    }
    let _ = writeln!(
        s,
        "  effective conicity at the centre (dr_R/dy) {:.6}",
        g.centre_conicity
    );
    if let Some(c) = g.rows.get(n / 2) {
        let _ = writeln!(
            s,
            "  centred: r_R = {:.6} mm, delta_R = {:.6} rad",
            c.point.radius * 1e3,
            c.point.angle
        );
        if let Some((a, b)) = c.semi_axes {
            let _ = writeln!(
                s,
                "  centred Hertz patch: a = {:.4} mm (rolling), b = {:.4} mm (lateral)",
                a * 1e3,
                b * 1e3
            );
        }
        let _ = writeln!(
            s,
            "  centred creep coefficients: f11 = {:.4e} N, f22 = {:.4e} N, f23 = {:.4e} N m, f33 = {:.4e} N m^2",
            c.creep.f11, c.creep.f22, c.creep.f23, c.creep.f33
        );
    }
    let _ = writeln!(s, "  {}", valid_range(g.valid_half_width_m, g.extrapolate));
    geometry_events(&mut s, g);
    s
}

/// Where the contact table is genuine geometry, and what the analyses do beyond it.
fn valid_range(
    half_width: Option<f64>,
    extrapolate: crate::contact::table::Extrapolation,
) -> String {
    match half_width {
        None => "valid range: every y (the linear extension beyond the table is exact)".into(),
        Some(w) => format!(
            "valid range: |y| <= {:.4} mm; beyond it the table is extended linearly (contact.extrapolate = \"{}\": {})",
            w * 1e3,
            extrapolate.name(),
            match extrapolate {
                crate::contact::table::Extrapolation::None => "results stop at the range",
                crate::contact::table::Extrapolation::Linear => "results beyond it are kept",
            }
        ),
    }
}

/// Contact-point jumps and Kalker-range clamps of a profile geometry.
fn geometry_events(s: &mut String, g: &GeometryReport) {
    for j in &g.jumps {
        let _ = writeln!(
            s,
            "  contact jump between y = {:.4} and {:.4} mm: wheel point {:.3} -> {:.3} mm, r_R {:.4} -> {:.4} mm",
            j.y_m.0 * 1e3,
            j.y_m.1 * 1e3,
            j.wheel_offset_m.0 * 1e3,
            j.wheel_offset_m.1 * 1e3,
            j.radius_m.0 * 1e3,
            j.radius_m.1 * 1e3
        );
    }
    if let (Some(a), Some(b)) = (g.clamped.first(), g.clamped.last()) {
        let _ = writeln!(
            s,
            "  lateral curvature held inside Kalker's a/b range [0.1, 10] at {} nodes (y from {:.4} to {:.4} mm)",
            g.clamped.len(),
            a * 1e3,
            b * 1e3
        );
    }
}

/// The resolved plan in SI.
pub fn plan(p: &Plan) -> String {
    let mut s = String::new();
    let w = &p.wheelset;
    let u = &p.suspension;
    let c = &p.contact;
    let _ = writeln!(s, "study '{}' is valid. Resolved plan (SI units):", p.name);
    if !p.description.is_empty() {
        let _ = writeln!(s, "  {}", p.description);
    }
    let mut line = |k: &str, v: String| {
        let _ = writeln!(s, "  {k:<36} {v}");
    };
    line("wheelset.mass", format!("{} kg", w.mass));
    line("wheelset.yaw_inertia", format!("{} kg m^2", w.yaw_inertia));
    line("wheelset.axle_load", format!("{} N", w.axle_load));
    line(
        "wheelset.half_contact_distance",
        format!("{} m", w.half_contact_distance),
    );
    line("wheelset.rolling_radius", format!("{} m", w.rolling_radius));
    line(
        "suspension.lateral_stiffness",
        format!("{} N/m", u.lateral_stiffness),
    );
    line(
        "suspension.longitudinal_stiffness",
        format!("{} N/m", u.longitudinal_stiffness),
    );
    line(
        "suspension.lateral_damping",
        format!("{} N s/m", u.lateral_damping),
    );
    line(
        "suspension.longitudinal_damping",
        format!("{} N s/m", u.longitudinal_damping),
    );
    line(
        "suspension.half_spring_spacing",
        format!("{} m", u.half_spring_spacing),
    );
    vehicle_lines(p, &mut line);
    match &c.geometry {
        &Geometry::Cone { conicity } => {
            line("contact.geometry", "cone".into());
            line("contact.conicity", format!("{conicity}"));
        }
        &Geometry::ConeOnArc {
            conicity,
            rail_head_radius,
            crown_offset,
        } => {
            line("contact.geometry", "cone-on-arc".into());
            line("contact.conicity", format!("{conicity}"));
            line("contact.rail_head_radius", format!("{rail_head_radius} m"));
            line("contact.crown_offset", format!("{crown_offset} m"));
        }
        Geometry::Table(t) => {
            line("contact.geometry", "table".into());
            line("contact.geometry_table", t.source.clone());
        }
        Geometry::Profiles { pair, smoothing } => {
            line("contact.geometry", "profiles".into());
            line("contact.wheel_profile", pair.files.0.clone());
            line("contact.rail_profile", pair.files.1.clone());
            line("contact.track_gauge", format!("{} m", pair.track.gauge));
            line(
                "contact.gauge_depth",
                format!("{} m", pair.track.gauge_depth),
            );
            line(
                "contact.rail_inclination",
                format!("{} rad (applied to the rail file)", pair.track.inclination),
            );
            line("contact.profile_smoothing", format!("{smoothing} m"));
        }
    }
    match c.creep_law {
        CreepLaw::Kalker => line("contact.creep_law", "kalker".into()),
        CreepLaw::Shen { friction } => {
            line("contact.creep_law", "shen".into());
            line("contact.friction", format!("{friction}"));
        }
    }
    line("contact.spin", format!("{}", c.spin));
    line(
        "contact.young_modulus",
        format!("{} Pa", c.elastic.young_modulus),
    );
    line(
        "contact.poisson_ratio",
        format!("{}", c.elastic.poisson_ratio),
    );
    line(
        "contact.shear_modulus",
        format!("{} Pa", c.elastic.shear_modulus),
    );
    match c.creep {
        CreepSource::Given(k) => line(
            "contact.creep_coefficients",
            format!(
                "f11 = {} N, f22 = {} N, f23 = {} N m, f33 = {} N m^2 (given)",
                k.f11, k.f22, k.f23, k.f33
            ),
        ),
        CreepSource::Hertz => line(
            "contact.creep_coefficients",
            match &c.geometry {
                Geometry::Table(t) if t.has_kalker() => {
                    "from the geometry table's a, b and Kalker C at each contact state (C33 from Kalker's table unless tabulated)".into()
                }
                _ => "from the Hertz patch and Kalker's table at each contact state".into(),
            },
        ),
    }
    line("contact.lateral_range", format!("{} m", c.lateral_range));
    line("contact.table_points", format!("{}", c.table_points));
    line("contact.extrapolate", c.extrapolate.name().into());
    match &p.flange {
        Some(f) => {
            line("flange.clearance", format!("{} m", f.clearance));
            line("flange.stiffness", format!("{} N/m", f.stiffness));
        }
        None => line("flange", "none".into()),
    }
    let (lo, hi) = p.linear.speed_range;
    line("linear.speed_range", format!("[{lo}, {hi}] m/s"));
    line("linear.grid_points", format!("{}", p.grid_points()));
    line("linear.spectrum_points", format!("{}", p.spectrum_points));
    s
}

/// The bifurcation results.
pub fn bifurcation(r: &crate::bifurcation::BifurcationReport) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "\nstudy '{}': hunting limit cycles ({} creep), V in [{}, {}] m/s",
        r.study,
        r.law.name(),
        r.speed_range.0,
        r.speed_range.1
    );
    let speed = |v: Option<f64>| {
        v.map_or("none in range".to_string(), |v| {
            format!("{v:.4} m/s ({:.1} km/h)", v * 3.6)
        })
    };
    let _ = writeln!(
        s,
        "  linear (Kalker) critical speed V_L     {}",
        speed(r.kalker_critical_speed_m_s)
    );
    let _ = writeln!(
        s,
        "  Hopf speed of the creep law V_H        {}{}",
        speed(r.hopf.map(|h| h.speed_m_s)),
        r.hopf_type
            .map_or(String::new(), |t| format!(", {}", t.name()))
    );
    if let Some(l) = &r.first_lyapunov {
        let _ = writeln!(
            s,
            "  first Lyapunov coefficient l1          {:+.4e} 1/m2 (error {:.1e}): {}",
            l.l1,
            l.error,
            l.kind().name()
        );
    }
    if let Some(note) = crate::output::hopf_type_note(r) {
        let _ = writeln!(s, "  note: {note}");
    }
    let how = r.nonlinear_sources.first().map_or(String::new(), |c| {
        format!(
            ", {} ({}{}, {})",
            c.what,
            c.method.name(),
            c.branch.map_or(String::new(), |b| format!(", branch {b}")),
            if c.located {
                "located"
            } else {
                "lowest computed, not located"
            }
        )
    });
    let _ = writeln!(
        s,
        "  nonlinear critical speed V_NL          {}{how}",
        speed(r.nonlinear_critical_speed.map(|v| v.0)),
    );
    for b in &r.branches {
        let origin = b
            .parent
            .and_then(|(p, k)| r.special.get(k).map(|sp| (p, sp)))
            .map_or("from the Hopf point".to_string(), |(p, sp)| {
                format!(
                    "from the {} point at {:.4} m/s of branch {p}",
                    sp.kind.name().replace('_', " "),
                    sp.speed_m_s
                )
            });
        let _ = writeln!(
            s,
            "  branch {} ({}): {} cycles {origin}; {}",
            b.id,
            b.kind.name(),
            b.cycles,
            b.stop_reason
        );
        for p in r.special.iter().filter(|p| p.branch == b.id) {
            let _ = writeln!(
                s,
                "    {:<36} {:.4} m/s at amplitude {:.3} mm ({})",
                p.kind.name(),
                p.speed_m_s,
                p.amplitude_y_m * 1e3,
                if p.located { "located" } else { "bracketed" }
            );
        }
    }
    for n in &r.notes {
        let _ = writeln!(s, "  note: {n}");
    }
    let worst = r
        .cycles
        .iter()
        .map(|c| c.trivial_multiplier_error)
        .fold(0.0, f64::max);
    let _ = writeln!(
        s,
        "  {} cycles on {} branches; largest |trivial multiplier - 1| = {worst:.1e}",
        r.cycles.len(),
        r.branches.len().max(1),
    );
    s
}

/// Summary of time simulations: amplitude early and late, and whether the motion grew.
pub fn simulate(study: &str, runs: &[crate::simulate::TimeHistory]) -> String {
    let mut s = format!("\nstudy '{study}': time simulation (lateral amplitude max|y|)\n");
    for h in runs {
        let n = h.x.len();
        let first = h.x[..n / 10 + 1]
            .iter()
            .map(|x| x[0].abs())
            .fold(0.0, f64::max);
        let last = h.final_amplitude(0.1);
        let verdict = if last > first * 1.05 {
            "grows (hunting)"
        } else if last < first * 0.95 {
            "decays"
        } else {
            "steady"
        };
        let _ = writeln!(
            s,
            "  V = {:8.3} m/s: first 10 % {:8.4} mm, last 10 % {:8.4} mm: {verdict}",
            h.speed_m_s,
            first * 1e3,
            last * 1e3
        );
    }
    s
}

/// The assembled model for `critspeed check`: the contact table's range and where it is
/// genuine, the bodies with their coordinates in state order, then every element with its
/// attachment points (SI).
pub fn vehicle(v: &crate::model::Vehicle) -> String {
    let mut s = String::new();
    let table = &v.contact.table;
    let _ = writeln!(
        s,
        "contact table: y in [-{0:.4}, {0:.4}] mm, {1}",
        table.half_width() * 1e3,
        table
            .valid_half_width()
            .map_or("genuine everywhere (exact linear extension)".into(), |w| {
                format!("genuine for |y| <= {:.4} mm", w * 1e3)
            })
    );
    let _ = writeln!(
        s,
        "vehicle: {} ({} states: the coordinates below, then their rates in the same order)",
        v.layout.name(),
        v.states()
    );
    let names = v.coordinate_names();
    for b in &v.bodies {
        let coords = &names[b.dof..b.dof + b.dofs()];
        let roll = b
            .roll_inertia
            .map_or(String::new(), |r| format!(", roll inertia {r} kg m^2"));
        let _ = writeln!(
            s,
            "  body {:<11} x = {:>7} m  mass {} kg, yaw inertia {} kg m^2{roll}; states {}..{}: {}",
            b.name,
            b.position_m,
            b.mass,
            b.yaw_inertia,
            b.dof,
            b.dof + b.dofs() - 1,
            coords.join(", ")
        );
    }
    let end = |a: &crate::model::Attachment| {
        let name = a
            .body
            .and_then(|i| v.bodies.get(i))
            .map_or("track", |b| b.name.as_str());
        let [x, y, z] = a.point;
        format!("{name} ({x}, {y}, {z}) m")
    };
    let _ = writeln!(
        s,
        "elements ({}; k in N/m and c in N s/m along x, y, z; points in each body's axes, z down):",
        v.elements.len()
    );
    for e in &v.elements {
        let _ = writeln!(
            s,
            "  {:<34} {} -> {}  k = {:?}  c = {:?}",
            e.name,
            end(&e.a),
            end(&e.b),
            e.stiffness,
            e.damping
        );
    }
    s
}

/// The plan's `[vehicle]`, primary vertical, `[bogie]`, `[secondary]` and `[carbody]` values.
fn vehicle_lines(p: &Plan, line: &mut impl FnMut(&str, String)) {
    use crate::model::VehicleSpec;
    let pv = &p.primary_vertical;
    let kind = match p.vehicle {
        VehicleSpec::Wheelset => "wheelset",
        VehicleSpec::Bogie { .. } => "bogie",
        VehicleSpec::Car { .. } => "car",
    };
    line("vehicle.kind", kind.into());
    line(
        "suspension.vertical_stiffness",
        format!("{} N/m", pv.stiffness),
    );
    line(
        "suspension.vertical_damping",
        format!("{} N s/m", pv.damping),
    );
    line("suspension.height", format!("{} m", pv.height));
    let (frame, sec, body) = match &p.vehicle {
        VehicleSpec::Wheelset => return,
        VehicleSpec::Bogie { frame, secondary } => (frame, secondary, None),
        VehicleSpec::Car {
            frame,
            secondary,
            body,
        } => (frame, secondary, Some(body)),
    };
    let roll = |r: Option<f64>| {
        r.map_or("none (no roll state)".to_string(), |r| {
            format!("{r} kg m^2")
        })
    };
    line("bogie.mass", format!("{} kg", frame.mass));
    line("bogie.yaw_inertia", format!("{} kg m^2", frame.yaw_inertia));
    line("bogie.roll_inertia", roll(frame.roll_inertia));
    line(
        "bogie.half_wheelbase",
        format!("{} m", frame.half_wheelbase),
    );
    line(
        "secondary.lateral_stiffness",
        format!("{} N/m", sec.lateral_stiffness),
    );
    line(
        "secondary.longitudinal_stiffness",
        format!("{} N/m", sec.longitudinal_stiffness),
    );
    line(
        "secondary.lateral_damping",
        format!("{} N s/m", sec.lateral_damping),
    );
    line(
        "secondary.longitudinal_damping",
        format!("{} N s/m", sec.longitudinal_damping),
    );
    line(
        "secondary.half_spring_spacing",
        format!("{} m", sec.half_spring_spacing),
    );
    line(
        "secondary.yaw_damping",
        format!("{} N s/m", sec.yaw_damping),
    );
    line(
        "secondary.yaw_damper_half_spacing",
        format!("{} m", sec.yaw_damper_half_spacing),
    );
    line(
        "secondary.vertical_stiffness",
        format!("{} N/m", sec.vertical_stiffness),
    );
    line(
        "secondary.vertical_damping",
        format!("{} N s/m", sec.vertical_damping),
    );
    line(
        "secondary.vertical_half_spacing",
        format!("{} m", sec.vertical_half_spacing),
    );
    line("secondary.height", format!("{} m", sec.height));
    if let Some(b) = body {
        line("carbody.mass", format!("{} kg", b.mass));
        line("carbody.yaw_inertia", format!("{} kg m^2", b.yaw_inertia));
        line("carbody.roll_inertia", roll(b.roll_inertia));
        line(
            "carbody.half_bogie_distance",
            format!("{} m", b.half_bogie_distance),
        );
        line(
            "carbody.secondary_height",
            format!("{} m", b.secondary_height),
        );
    }
}
