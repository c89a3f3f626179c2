//! The rigid contact solver for point-list profiles (`geometry = "profiles"`): identities,
//! an independent brute-force gap check, the cone-on-arc cross-check, malformed files.
//!
//! Profiles: S1002 wheel and UIC60 rail (1:40) of the Manchester contact benchmark, as
//! distributed with E. Vollebregt's CONTACT (Apache-2.0), copied with their source lines into
//! `studies/profiles/`.

use std::path::PathBuf;

use critspeed::contact::geometry::{Geometry, Nominal};
use critspeed::contact::profile::{self, Orientation, Points, ProfileError};
use critspeed::contact::rigid::{ProfilePair, Track};

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

const NOMINAL: Nominal = Nominal {
    rolling_radius: 0.46,
    half_contact_distance: 0.75,
};

const TRACK: Track = Track {
    gauge: 1.435,
    gauge_depth: 0.014,
    inclination: 0.0,
};

fn s1002() -> Points {
    let o = Orientation {
        mirror: true,
        z_up: false,
    };
    profile::read(&root().join("studies/profiles/s1002.csv"), o).expect("S1002 file")
}

fn uic60() -> Points {
    profile::read(
        &root().join("studies/profiles/uic60_1in40.csv"),
        Orientation::default(),
    )
    .expect("UIC60 file")
}

fn pair() -> ProfilePair {
    ProfilePair::new(&s1002(), uic60(), TRACK).expect("S1002/UIC60 pair")
}

/// Solves outwards from the centre to `y` (the table's continuation).
fn solve_to(p: &ProfilePair, y: f64) -> [f64; 4] {
    let n = 40;
    let mut guess = None;
    for k in 0..=n {
        let (_, x) = p
            .solve(NOMINAL, y * k as f64 / n as f64, guess)
            .expect("contact solves");
        guess = Some(x);
    }
    guess.expect("at least one step")
}

#[test]
fn left_and_right_are_mirror_images() {
    // Track symmetry (docs/model.md §3): u_L(y) = u_R(−y) (so r_L(y) = r_R(−y)), φ(−y) = −φ(y).
    let p = pair();
    for y in [0.7e-3, 3e-3, 5.5e-3, 8e-3] {
        let a = solve_to(&p, y);
        let b = solve_to(&p, -y);
        assert!(
            (a[1] + b[1]).abs() < 1e-12,
            "roll at {y}: {} {}",
            a[1],
            b[1]
        );
        assert!(
            (a[3] - b[2]).abs() < 1e-9,
            "u_L({y}) = {} vs u_R(-y) = {}",
            a[3],
            b[2]
        );
        assert!((a[0] - b[0]).abs() < 1e-12, "height at ±{y}");
    }
}

/// Independent check: the wheel's own file points, placed by this test's own reading of the
/// conventions, against the rail's file points interpolated linearly. The rail head is convex,
/// so its chords lie below it: a negative gap would be a penetration. Tolerance 2 µm: this test
/// places the gauge point on the chord, the solver by a cubic through four points; the
/// difference (≤ 0.5 µm laterally) times the flange slope (≤ 3) bounds the vertical offset. The
/// minimum over the discrete wheel points (spacing ≤ 0.445 mm, so ≤ 0.223 mm from the true
/// contact) exceeds zero by at most d²(κ_w + κ_r)/2 plus the chord sag h²κ_r/8; with the
/// sharpest curvatures met (13 mm gauge corner, ~15 mm flange root) that is < 6 µm.
fn brute_force_gaps(x: [f64; 4], y: f64) -> [f64; 2] {
    let (wheel, rail) = (s1002(), uic60());
    // taping line radius: wheel z_down at u = 0, interpolated linearly
    let z0 = interp(&wheel.u, &wheel.z_down, 0.0);
    let top = rail.z_down.iter().cloned().fold(f64::INFINITY, f64::min);
    let itop = rail.z_down.iter().position(|&z| z == top).expect("top");
    let mut ug = f64::NAN;
    for k in (1..=itop).rev() {
        if rail.z_down[k - 1] >= top + 0.014 && rail.z_down[k] <= top + 0.014 {
            let f = (top + 0.014 - rail.z_down[k]) / (rail.z_down[k - 1] - rail.z_down[k]);
            ug = rail.u[k] + f * (rail.u[k - 1] - rail.u[k]);
            break;
        }
    }
    let (z, phi) = (x[0], x[1]);
    let mut out = [f64::INFINITY; 2];
    for (i, s) in [1.0, -1.0].into_iter().enumerate() {
        for (u, zd) in wheel.u.iter().zip(&wheel.z_down) {
            let zeta = s * (NOMINAL.half_contact_distance + u);
            let w = -(NOMINAL.rolling_radius + zd - z0);
            let big_y = y + zeta * phi.cos() - w * phi.sin();
            let big_z = z + zeta * phi.sin() + w * phi.cos();
            let v = s * big_y - 0.5 * TRACK.gauge + ug;
            if v < rail.u[0] || v > rail.u[rail.u.len() - 1] {
                continue;
            }
            let h = top - interp(&rail.u, &rail.z_down, v);
            out[i] = out[i].min(big_z - h);
        }
    }
    out
}

fn interp(x: &[f64], y: &[f64], at: f64) -> f64 {
    let k = x.partition_point(|&v| v <= at).clamp(1, x.len() - 1);
    let t = (at - x[k - 1]) / (x[k] - x[k - 1]);
    y[k - 1] + t * (y[k] - y[k - 1])
}

#[test]
fn solution_touches_without_penetration() {
    let p = pair();
    for y in [0.0, 1e-3, -2.5e-3, 4e-3, 7e-3, -9e-3] {
        let x = solve_to(&p, y);
        let g = brute_force_gaps(x, y);
        for gap in g {
            assert!(
                gap > -2e-6 && gap < 6e-6,
                "y = {y}: brute-force minimum gap {gap:e} m"
            );
        }
    }
}

/// A 1:20 cone (with a flange far inside, never touched) on the seed's 79.37 mm rail arc,
/// as point lists, against the closed-form-ish `Geometry::ConeOnArc` solve.
#[test]
fn cone_on_arc_profiles_reproduce_the_cone_on_arc_geometry() {
    let (lambda, radius, crown) = (0.05, 0.07937, 0.00396);
    let mut wheel = String::from("# test cone\ny_m,z_m\n");
    for k in -200..=160 {
        let u = k as f64 * 2.5e-4;
        // z down = radius increment: −λu on the tread, a steep rise (flange) inside −36 mm,
        // beyond the rail arc's edge, so never in contact
        let flange = if u < -0.036 { 2.5 * (-0.036 - u) } else { 0.0 };
        wheel.push_str(&format!("{u},{}\n", -lambda * u + flange));
    }
    let mut rail = String::from("# test arc\ny_m,z_m\n");
    for k in -120..=120 {
        let v = k as f64 * 2.5e-4;
        rail.push_str(&format!(
            "{v},{}\n",
            radius - (radius * radius - v * v).sqrt()
        ));
    }
    let o = Orientation::default();
    let w = profile::parse(&wheel, "cone", o).expect("cone points");
    let r = profile::parse(&rail, "arc", o).expect("arc points");
    // gauge point 5 mm below the crown, on the inner side; place the crown at l0 + crown
    let depth = 0.005;
    let vg = (radius * radius - (radius - depth).powi(2)).sqrt();
    let track = Track {
        gauge: 2.0 * (NOMINAL.half_contact_distance + crown - vg),
        gauge_depth: depth,
        inclination: 0.0,
    };
    let pair = ProfilePair::new(&w, r, track).expect("pair");
    let arc = Geometry::ConeOnArc {
        conicity: lambda,
        rail_head_radius: radius,
        crown_offset: crown,
    };
    let (mut g1, mut g2) = (None, None);
    for k in 0..=40 {
        let y = k as f64 * 2.5e-4;
        let (a, x1) = pair.solve(NOMINAL, y, g1).expect("profiles");
        let (b, x2) = arc.solve(NOMINAL, y, g2).expect("arc");
        (g1, g2) = (Some(x1), Some(x2));
        assert!(
            (a.radius.re - b.radius.re).abs() < 1e-10,
            "r at {y}: {} {} u {:?} {:?}",
            a.radius.re,
            b.radius.re,
            x1,
            x2
        );
        assert!((a.angle.re - b.angle.re).abs() < 1e-8, "δ at {y}");
        assert!((a.roll.re - b.roll.re).abs() < 1e-10, "φ at {y}");
        assert!(
            (a.radius.eps[0] - b.radius.eps[0]).abs() < 1e-6,
            "dr/dy at {y}"
        );
        assert!(
            (a.angle.eps[0] - b.angle.eps[0]).abs() < 1e-4,
            "dδ/dy at {y}"
        );
    }
}

fn parse_err(text: &str) -> String {
    match profile::parse(text, "bad.csv", Orientation::default()) {
        Err(e @ (ProfileError::Line { .. } | ProfileError::Shape { .. })) => e.to_string(),
        other => panic!("expected an error, got {other:?}"),
    }
}

fn line_profile(header: &str, scale: f64, swap_at: Option<usize>) -> String {
    let mut s = format!("# test\n{header}\n");
    for k in 0..40 {
        let k = match swap_at {
            Some(j) if k == j => k - 2,
            _ => k,
        };
        s.push_str(&format!("{},{}\n", (k as f64 - 20.0) * 2.0 * scale, 0.0));
    }
    s
}

#[test]
fn malformed_profiles_name_the_file_and_line() {
    // non-monotonic lateral coordinate on the 13th point: line 2 + 13 = 15
    let e = parse_err(&line_profile("y_mm,z_mm", 1.0, Some(12)));
    assert!(
        e.starts_with("bad.csv:15:") && e.contains("monotonic"),
        "{e}"
    );
    // a profile 0.078 wide in "mm" (a file in metres with the wrong header): header line 2
    let e = parse_err(&line_profile("y_mm,z_mm", 1e-3, None));
    assert!(
        e.starts_with("bad.csv:2:") && e.contains("implausible"),
        "{e}"
    );
    // gap larger than 5 mm between points
    let e = parse_err(&line_profile("y_mm,z_mm", 3.0, None));
    assert!(
        e.starts_with("bad.csv:4:") && e.contains("at most 5 mm"),
        "{e}"
    );
    // unknown header
    let e = parse_err("y,z\n1,2\n");
    assert!(e.starts_with("bad.csv:1:") && e.contains("header"), "{e}");
    // a number that is not one
    let mut t = line_profile("y_mm,z_mm", 1.0, None);
    t.push_str("4x,1\n");
    let e = parse_err(&t);
    assert!(e.starts_with("bad.csv:43:"), "{e}");
    // wheel file read with the wrong lateral convention: the flange appears outside
    let o = Orientation::default();
    let w = profile::read(&root().join("studies/profiles/s1002.csv"), o).expect("points");
    let e = ProfilePair::new(&w, uic60(), TRACK).expect_err("flange outside");
    assert!(e.to_string().contains("no flange"), "{e}");
}

#[test]
fn s1002_uic60_study_tabulates_with_jumps_reported() {
    let plan = critspeed::study::load(&root().join("studies/s1002-uic60.toml")).expect("study");
    let model = plan.model().expect("table");
    // S1002/UIC60 1:40 has contact-point jumps (tread to flange root); they are reported
    assert!(!model.contact.table.jumps().is_empty());
    for j in model.contact.table.jumps() {
        assert!((j.wheel_offset_m.0 - j.wheel_offset_m.1).abs() > 5e-4);
    }
}

#[test]
fn study_keys_are_checked() {
    let text = std::fs::read_to_string(root().join("studies/s1002-uic60.toml")).expect("study");
    let origin = root().join("studies/x.toml").display().to_string();
    // a profile key on a cone geometry
    let cone = text.replace(
        "geometry = \"profiles\"",
        "geometry = \"cone\"\nconicity = 0.05",
    );
    let e = critspeed::study::parse(&cone, &origin).expect_err("profile keys on a cone");
    assert!(
        e.to_string()
            .contains("only applies to geometry \"profiles\""),
        "{e}"
    );
    // the rail inclination must be stated
    let no_incl: String = text
        .lines()
        .filter(|l| !l.starts_with("rail_inclination"))
        .collect::<Vec<_>>()
        .join("\n");
    let e = critspeed::study::parse(&no_incl, &origin).expect_err("no inclination");
    assert!(e.to_string().contains("contact.rail_inclination"), "{e}");
    // a malformed profile named by the study: the error names the key, the file and the line
    let dir = std::env::temp_dir().join(format!("critspeed-profiles-{}", std::process::id()));
    std::fs::create_dir_all(dir.join("profiles")).expect("temp dir");
    std::fs::copy(
        root().join("studies/profiles/uic60_1in40.csv"),
        dir.join("profiles/uic60_1in40.csv"),
    )
    .expect("copy rail");
    let wheel = std::fs::read_to_string(root().join("studies/profiles/s1002.csv")).expect("s1002");
    let mut lines: Vec<&str> = wheel.lines().collect();
    lines.swap(10, 11); // breaks the monotonic order at file line 12
    std::fs::write(dir.join("profiles/s1002.csv"), lines.join("\n")).expect("write");
    let origin = dir.join("s.toml").display().to_string();
    let e = critspeed::study::parse(&text, &origin).expect_err("malformed wheel");
    let msg = e.to_string();
    assert!(
        msg.contains("contact.wheel_profile") && msg.contains("s1002.csv:12:"),
        "{msg}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}
