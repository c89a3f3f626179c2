//! Human-readable tables for the terminal. Every number carries its unit.

use std::fmt::Write as _;

use crate::analysis::{GeometryReport, LinearReport};
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
        let mode = modes.and_then(|m| m.get(k)).and_then(Option::as_ref);
        if let Some(m) = mode {
            let _ = write!(s, "  {} ({} leads)", m.label, m.leading_body);
        }
        s.push('\n');
        // dampers on series stiffness: each stroke against y1 and its share of the deflection
        if let Some(m) = mode.filter(|m| !m.dampers.is_empty()) {
            s.push_str("    strokes |z|/|y1|, phase, |z|/|deflection|:");
            for (i, d) in m.dampers.iter().enumerate() {
                let sep = if i == 0 { " " } else { "; " };
                let _ = write!(
                    s,
                    "{sep}{} {:.4} m/m {:+.1} deg {:.4}",
                    d.damper, d.stroke_per_y1, d.stroke_phase_deg, d.deflection_share
                );
            }
            s.push('\n');
        }
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
    for note in &r.notes {
        let _ = writeln!(s, "  note: {note}");
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
    if let Some(w) = &g.wheelsets {
        let _ = writeln!(
            s,
            "  the wheelsets' own geometries: {w} (this table is [contact]'s)"
        );
    }
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

/// The resolved plan in SI, one key a line (and how many values lie outside their plausible
/// ranges: the warnings themselves go to stderr).
pub fn plan(p: &Plan, warnings: &[String]) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "study '{}' is valid. Resolved plan (SI units):", p.name);
    if !p.description.is_empty() {
        let _ = writeln!(s, "  {}", p.description);
    }
    for e in crate::study::entries::entries(p) {
        let _ = writeln!(s, "  {:<36} {}", e.key, e.shown);
    }
    if !warnings.is_empty() {
        let _ = writeln!(
            s,
            "{} value(s) outside the plausible ranges: see the warnings on stderr",
            warnings.len()
        );
    }
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
    // a branch stopped as too stiff (driver's stop reason) leaves the speeds below unexplored
    let stiff_stop = r
        .branches
        .iter()
        .filter(|b| b.stop_reason.contains("as too stiff"))
        .filter_map(|b| r.cycles.iter().rfind(|c| c.branch == b.id))
        .map(|c| c.speed_m_s)
        .fold(None, |m: Option<f64>, v| Some(m.map_or(v, |m| m.max(v))));
    let vnl = match (r.nonlinear_critical_speed, stiff_stop) {
        (None, Some(v)) => format!(
            "none found above {v:.4} m/s (a branch was stopped there as too stiff; see the note)"
        ),
        (vnl, _) => speed(vnl.map(|v| v.0)),
    };
    let _ = writeln!(s, "  nonlinear critical speed V_NL          {vnl}{how}");
    let searched = r
        .nonlinear_sources
        .iter()
        .any(|c| c.method == crate::bifurcation::VnlMethod::AttractorSearch)
        || r.notes.iter().any(|n| n.contains("attractor search"));
    if !searched {
        let _ = writeln!(
            s,
            "    from the continuation alone: no attractor search ran (`critspeed attractors STUDY`, or an [attractors] section, adds it)"
        );
    }
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
            // the amplitude the diagram plots: the largest wheelset's max |y| (the leading
            // wheelset's beside it where they differ, on a bogie or a car)
            let leading = if (p.wheelset_amplitude_m - p.amplitude_y_m).abs() > 5e-7 {
                format!(
                    " (largest wheelset; leading wheelset {:.3} mm)",
                    p.amplitude_y_m * 1e3
                )
            } else {
                String::new()
            };
            let _ = writeln!(
                s,
                "    {:<36} {:.4} m/s at amplitude {:.3} mm{leading} ({})",
                p.kind.name(),
                p.speed_m_s,
                p.wheelset_amplitude_m * 1e3,
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
        "  {} cycles on {} branch{}; largest |trivial multiplier - 1| = {worst:.1e}",
        r.cycles.len(),
        r.branches.len().max(1),
        if r.branches.len() > 1 { "es" } else { "" },
    );
    s
}

/// Below this amplitude (m) a motion is at rest: its trend there is round-off, not hunting.
const SUSTAINED_M: f64 = 1e-6;

/// Summary of time simulations: amplitude early and late, and the motion's trend at the end of
/// the run (the last tenth against the tenth before it).
pub fn simulate(study: &str, runs: &[crate::simulate::TimeHistory]) -> String {
    let mut s = format!(
        "\nstudy '{study}': time simulation (lateral amplitude: the largest wheelset's max|y|)\n"
    );
    for h in runs {
        // the wheelsets' lateral coordinates: `y_m` of a single wheelset, `y_wheelset_k_m` of a
        // vehicle (the amplitude the diagrams plot)
        let ys: Vec<usize> = h
            .state_names
            .iter()
            .enumerate()
            .filter(|(_, n)| *n == "y_m" || n.starts_with("y_wheelset"))
            .map(|(i, _)| i)
            .collect();
        let ys = if ys.is_empty() { vec![0] } else { ys };
        let amplitude = |rows: &[Vec<f64>]| {
            rows.iter()
                .flat_map(|x| ys.iter().filter_map(|&i| x.get(i)))
                .fold(0.0, |m: f64, v| m.max(v.abs()))
        };
        let n = h.x.len();
        let tenth = n / 10 + 1;
        let first = amplitude(&h.x[..tenth.min(n)]);
        let last = amplitude(&h.x[n.saturating_sub(tenth)..]);
        let before = amplitude(&h.x[n.saturating_sub(2 * tenth)..n.saturating_sub(tenth)]);
        // the trend at the run's end (the last tenth against the one before it), not against
        // the start: a motion kicked above its cycle shrinks onto it and hunts on
        let verdict = if last < SUSTAINED_M {
            if first >= SUSTAINED_M {
                "decays (to rest)"
            } else {
                "at rest"
            }
        } else if last > before * 1.05 {
            "grows (hunting)"
        } else if last < before * 0.95 {
            "decays"
        } else {
            "sustained (hunting)"
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
    if v.wheelset_tables().iter().any(Option::is_some) {
        let _ = writeln!(
            s,
            "wheelsets with their own contact geometry ([[contact.wheelset]]), centre conicities: {}",
            v.conicity_summary()
        );
    }
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
        if let Some(stop) = &e.bump_stop {
            let law = match stop.law {
                crate::model::StopLaw::Linear(_) => "linear",
                crate::model::StopLaw::Table(_) => "progressive table",
            };
            let _ = writeln!(
                s,
                "  {:<34} {} -> {}  lateral bump stop: clearance {} m, stiffness {} N/m ({law})",
                e.name,
                end(&e.a),
                end(&e.b),
                stop.clearance,
                stop.law.initial_stiffness()
            );
            continue;
        }
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
