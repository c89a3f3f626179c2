//! Section of `docs/VALIDATION.md`: the S1002/UIC60 1:40 rigid contact geometry against the
//! DTU RSGEO table (DTU DYTSI, LGPL, `input/RSGEO/1o40/RSGEO.dat`, subsampled every 0.5 mm;
//! r0 = 0.425 m, l0 = 0.75 m, rail inclination 1:40; profiles not named in that repository;
//! its wheel is shown to be S1002 in `dtu_wheel.rs`), and the equivalent conicity of S1002/UIC60 against the range quoted
//! in the literature.

use std::fmt::Write as _;

use critspeed::conicity::DeltaR;
use critspeed::study;

use super::{data_rows, reference, root};

/// The DTU table's wheelset on the S1002/UIC60 study's profiles, raw geometry (no smoothing).
fn dtu_study(gauge_mm: f64) -> String {
    let text = std::fs::read_to_string(root().join("studies/s1002-uic60.toml")).expect("study");
    text.lines()
        .map(|l| match l.split('=').next().map(str::trim) {
            Some("rolling_radius") => "rolling_radius = \"425 mm\"".to_string(),
            Some("axle_load") => "axle_load = \"133300 N\"".to_string(),
            Some("track_gauge") => format!("track_gauge = \"{gauge_mm} mm\""),
            Some("profile_smoothing") => "profile_smoothing = \"0 mm\"".to_string(),
            Some("lateral_range") => "lateral_range = \"17 mm\"".to_string(),
            Some("table_points") => "table_points = 1361".to_string(),
            _ => l.to_string(),
        })
        .collect::<Vec<_>>()
        .join("\n")
}

/// Differences to the DTU rows: (rows, rms Δr m, max |Δr| m, rms Δδ rad, tread rows,
/// rms relative a, rms relative b on the tread).
#[derive(Clone, Copy, Debug)]
pub struct Metrics {
    pub gauge_mm: f64,
    pub rows: usize,
    pub rms_radius_m: f64,
    pub max_radius_m: f64,
    pub rms_angle_rad: f64,
    pub tread_rows: usize,
    pub rms_a_rel: f64,
    pub rms_b_rel: f64,
}

/// The rigid-contact table of the DTU wheelset on S1002/UIC60 at `gauge_mm`.
pub fn dtu_table(gauge_mm: f64) -> critspeed::contact::table::ContactTable {
    let origin = root().join("studies/dtu.toml");
    let plan = study::parse(&dtu_study(gauge_mm), &origin.display().to_string()).expect("plan");
    plan.wheelset_model().expect("table").table
}

pub fn metrics(gauge_mm: f64) -> Metrics {
    let rows = dtu_table(gauge_mm).rows();
    let dtu = data_rows(&reference("dtu_rsgeo_1o40_subsampled.csv"));
    let (mut n, mut nt) = (0, 0);
    let (mut sr, mut mr, mut sd, mut sa, mut sb) = (0.0, 0.0f64, 0.0, 0.0, 0.0);
    for d in &dtu {
        // table nodes every 25 µm: the DTU rows (every 0.5 mm) are nodes
        let Some(r) = rows.iter().find(|r| (r.y - d[0]).abs() < 1e-9) else {
            continue;
        };
        n += 1;
        let dr = r.point.radius - d[6];
        (sr, mr) = (sr + dr * dr, mr.max(dr.abs()));
        sd += (r.point.angle - d[2]).powi(2);
        if let (Some((a, b)), true) = (r.semi_axes, d[2].abs() < 0.1) {
            nt += 1;
            sa += (a / d[3] - 1.0).powi(2);
            sb += (b / d[4] - 1.0).powi(2);
        }
    }
    let rms = |s: f64, k: usize| (s / k.max(1) as f64).sqrt();
    Metrics {
        gauge_mm,
        rows: n,
        rms_radius_m: rms(sr, n),
        max_radius_m: mr,
        rms_angle_rad: rms(sd, n),
        tread_rows: nt,
        rms_a_rel: rms(sa, nt),
        rms_b_rel: rms(sb, nt),
    }
}

/// The gauge (mm, 0.5 mm steps in [1435, 1445]) that best reproduces DTU's rolling radii.
pub fn best_fit() -> Metrics {
    (0..=20)
        .map(|k| metrics(1435.0 + 0.5 * k as f64))
        .min_by(|a, b| a.rms_radius_m.total_cmp(&b.rms_radius_m))
        .expect("non-empty scan")
}

/// EN 15302 equivalent conicity of the study (raw geometry) at amplitudes (m).
pub fn conicities(amplitudes: &[f64]) -> Vec<f64> {
    let origin = root().join("studies/s1002-uic60.toml");
    let text = std::fs::read_to_string(&origin).expect("study");
    let plan = study::parse(&text, &origin.display().to_string()).expect("plan");
    let pts = plan
        .wheelset_model()
        .expect("table")
        .table
        .rolling_radius_difference();
    let dr = DeltaR::new(pts, "s1002-uic60").expect("Δr");
    amplitudes
        .iter()
        .map(|&a| dr.equivalent_conicity(a).expect("amplitude fits").conicity)
        .collect()
}

/// EN 15302 case E1 from the reference profiles themselves: R-UIC519-A wheels on S-UIC519-A
/// rails (EN 15302 Annex D, as digitised in criogenox/A_WRCC), gauge 1435.16 mm, flange-back
/// spacing 1360 mm (taping lines 750 mm from the centre), 920 mm wheels. Conventions read off
/// the files: wheel lateral axis outward (flange back at −70 mm), z up; rail z up, its first
/// point (−32.5, −14.0) mm is the gauge point, 14 mm below the file's z = 0 and 14.48 mm below
/// the rail's highest point (the rail file is already inclined). Returns the table's Δr (m)
/// at the reference's y (m) and the EN 15302 conicities at `amplitudes`.
pub fn en15302_e1(amplitudes: &[f64]) -> (Vec<(f64, f64)>, Vec<f64>) {
    let dir = std::env::temp_dir().join(format!("critspeed-e1-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let all = reference("en15302_reference_profiles.csv");
    for name in ["RUIC519A", "SUIC519A"] {
        let mut t = format!("# {name} from en15302_reference_profiles.csv\ny_mm,z_mm\n");
        for l in all.lines().filter(|l| l.starts_with(&format!("{name},"))) {
            t.push_str(l.split_once(',').expect("profile,y,z").1);
            t.push('\n');
        }
        std::fs::write(dir.join(format!("{name}.csv")), t).expect("write profile");
    }
    let study = r#"name = "e1"
[wheelset]
mass = 1250
yaw_inertia = 700
axle_load = 110000
half_contact_distance = "750 mm"
rolling_radius = "460 mm"
[suspension]
lateral_stiffness = 3e5
longitudinal_stiffness = 8.5e5
lateral_damping = 8e3
longitudinal_damping = 1e5
half_spring_spacing = 0.9
[contact]
geometry = "profiles"
wheel_profile = "RUIC519A.csv"
wheel_profile_z_up = true
rail_profile = "SUIC519A.csv"
rail_profile_z_up = true
rail_inclination = "none"
track_gauge = "1435.16 mm"
gauge_depth = "14.48 mm"
lateral_range = "10 mm"
table_points = 801
"#;
    let origin = dir.join("e1.toml").display().to_string();
    let plan = study::parse(study, &origin).expect("E1 study");
    let dr = plan
        .wheelset_model()
        .expect("E1 table")
        .table
        .rolling_radius_difference();
    let _ = std::fs::remove_dir_all(&dir);
    let table = DeltaR::new(dr.clone(), "E1").expect("Δr");
    let c = amplitudes
        .iter()
        .map(|&a| {
            table
                .equivalent_conicity(a)
                .expect("amplitude fits")
                .conicity
        })
        .collect();
    (dr, c)
}

/// (rows, rms, max) of |Δr − Δr_ref| (m) over |y| ≤ `limit` (m), EN 15302 case E1.
pub fn e1_delta_r(dr: &[(f64, f64)], limit: f64) -> (usize, f64, f64) {
    let refs: Vec<(f64, f64)> = data_rows_tagged(&reference("en15302_delta_r_reference.csv"), "E1");
    let (mut n, mut s2, mut mx) = (0, 0.0, 0.0f64);
    for (y, r) in refs.iter().filter(|(y, _)| y.abs() <= limit) {
        if let Some((_, d)) = dr.iter().find(|(yy, _)| (yy - y).abs() < 1e-9) {
            n += 1;
            s2 += (d - r).powi(2);
            mx = mx.max((d - r).abs());
        }
    }
    (n, (s2 / n.max(1) as f64).sqrt(), mx)
}

/// Rows `case,y_mm,value_mm` of one case, in metres.
fn data_rows_tagged(text: &str, case: &str) -> Vec<(f64, f64)> {
    text.lines()
        .filter_map(|l| l.strip_prefix(&format!("{case},")))
        .filter_map(|l| {
            let (a, b) = l.split_once(',')?;
            Some((
                a.trim().parse::<f64>().ok()? * 1e-3,
                b.trim().parse::<f64>().ok()? * 1e-3,
            ))
        })
        .collect()
}

/// The reference E1 conicity and band at an amplitude (m): (ref, lower, upper).
fn e1_conicity_reference(amplitude: f64) -> (f64, f64, f64) {
    let text = reference("en15302_equivalent_conicity_reference.csv");
    let row = data_rows_tagged_full(&text, "E1")
        .into_iter()
        .find(|r| (r[0] * 1e-3 - amplitude).abs() < 1e-9)
        .expect("amplitude in the reference");
    (row[1], row[3], row[2])
}

fn data_rows_tagged_full(text: &str, case: &str) -> Vec<Vec<f64>> {
    text.lines()
        .filter_map(|l| l.strip_prefix(&format!("{case},")))
        .filter_map(|l| l.split(',').map(|v| v.trim().parse().ok()).collect())
        .collect()
}

pub fn section(s: &mut String) {
    let _ = writeln!(s, "## 7. Real profiles: S1002 / UIC60 1:40 (issue 5)\n");
    let _ = writeln!(s, "Rigid contact of the Manchester-benchmark S1002 wheel and UIC60 rail (1:40) point lists (`studies/profiles/`), raw geometry (no smoothing), r0 = 0.425 m, l0 = 0.75 m, against the DTU RSGEO table (section 4's file; its profiles are not named). With the nominal gauge 1435 mm the DTU functions look like ours shifted by about 2.5 mm in y (DTU's flange contact starts near y = 9 mm, ours near 6.3 mm): DTU's placement of wheel and rail (gauge, flange-back spacing or gauge-point height) is not stated, so the gauge is fitted (0.5 mm steps, least rms rolling-radius difference). Hertz semi-axes are compared on the tread rows only (|δ| < 0.1 rad: DTU's normal force at the flange is not W/(2 cos δ)).\n");
    let _ = writeln!(s, "| gauge (mm) | rows | rms Δr_R | max Δr_R | rms Δδ_R | tread rows | rms a (rel.) | rms b (rel.) |\n|---|---|---|---|---|---|---|---|");
    let fit = best_fit();
    for m in [metrics(1435.0), fit] {
        let _ = writeln!(
            s,
            "| {:.1} | {} | {:.3} mm | {:.3} mm | {:.4} rad | {} | {:.1} % | {:.1} % |",
            m.gauge_mm,
            m.rows,
            m.rms_radius_m * 1e3,
            m.max_radius_m * 1e3,
            m.rms_angle_rad,
            m.tread_rows,
            100.0 * m.rms_a_rel,
            100.0 * m.rms_b_rel
        );
    }
    let _ = writeln!(s, "\nThe largest radius differences sit at the contact jumps: the S1002/UIC60 solve has a jump near the centre and one at the flange root, where DTU's contact point moves quickly but continuously (its rail profile or its contact search differ slightly; its wheel is S1002, below).\n");
    super::dtu_wheel::section(s, fit.gauge_mm);
    let amps = [1e-3, 2e-3, 3e-3, 4e-3];
    let c = conicities(&amps);
    let _ = writeln!(s, "EN 15302 equivalent conicity of `studies/s1002-uic60.toml` (gauge 1435 mm, flange-back spacing 1360 mm, the study's table: smoothing half-width 0.1 mm):\n\n| amplitude | tan γe |\n|---|---|");
    for (a, c) in amps.iter().zip(&c) {
        let _ = writeln!(s, "| {:.0} mm | {c:.4} |", a * 1e3);
    }
    let _ = writeln!(s, "\nA range of 0.1 to 0.2 at 3 mm amplitude is often quoted for new S1002 on UIC60 1:40 at these dimensions; a search of the available documentation found no published table for this exact pair, so only that range is checked (test `s1002_uic60_conicity_is_in_the_quoted_range`, bounds 0.1 to 0.25). The high values at 1 to 2 mm come from the contact jump at y ≈ 0.21 mm (Δr steps by about 0.46 mm there).\n");
    en15302_part(s);
}

const E1_AMPLITUDES: [f64; 5] = [1e-3, 2e-3, 3e-3, 4e-3, 5e-3];

fn en15302_part(s: &mut String) {
    let (dr, c) = en15302_e1(&E1_AMPLITUDES);
    let _ = writeln!(s, "\n### EN 15302 case E1 from its reference profiles\n\nThe contact solver on the EN 15302 Annex D profiles themselves (R-UIC519-A wheels, S-UIC519-A rail, gauge 1435.16 mm, taping lines 750 mm from the centre; files as digitised by criogenox/A_WRCC, conventions as read off the files: see `tests/validation/profiles.rs`), against the standard's reference Δr(y) and equivalent conicity (section 3's files):\n");
    let _ = writeln!(
        s,
        "| range of y | rows | rms Δr difference | max |\n|---|---|---|---|"
    );
    for lim in [4e-3, 6e-3] {
        let (n, rms, mx) = e1_delta_r(&dr, lim);
        let _ = writeln!(
            s,
            "| ±{:.0} mm | {n} | {:.4} mm | {:.4} mm |",
            lim * 1e3,
            rms * 1e3,
            mx * 1e3
        );
    }
    let _ = writeln!(
        s,
        "\n| amplitude | tan γe (profiles) | reference | band |\n|---|---|---|---|"
    );
    for (a, c) in E1_AMPLITUDES.iter().zip(&c) {
        let (r, lo, hi) = e1_conicity_reference(*a);
        let _ = writeln!(
            s,
            "| {:.0} mm | {c:.4} | {r:.3} | [{lo:.3}, {hi:.3}] |",
            a * 1e3
        );
    }
    let _ = writeln!(s, "\nNear the flange (|y| > 5 mm) Δr grows steeply and small differences in the profiles' digitisation and in the gauge-point convention show up as larger Δr differences.");
}

#[test]
fn en15302_e1_from_the_reference_profiles() {
    // The standard's band is ±0.05 on tan γe; the solver must sit well inside it. Δr within
    // 0.1 mm for |y| ≤ 4 mm (the digitised profiles' resolution and the gauge-point reading
    // are the limits).
    let (dr, c) = en15302_e1(&E1_AMPLITUDES);
    let (n, rms, mx) = e1_delta_r(&dr, 4e-3);
    assert!(n >= 70 && rms < 0.05e-3 && mx < 0.1e-3, "{n} {rms} {mx}");
    for (a, c) in E1_AMPLITUDES.iter().zip(&c) {
        let (r, lo, hi) = e1_conicity_reference(*a);
        assert!(
            (lo..=hi).contains(c) && (c - r).abs() < 0.025,
            "{a}: {c} vs {r}"
        );
    }
}

#[test]
fn s1002_uic60_matches_the_dtu_table() {
    // Tolerances: one fitted placement parameter (the gauge); the remaining differences come
    // from the unnamed DTU profiles and its continuous contact where ours jumps (rows near the
    // jumps carry up to ~1.5 mm of radius difference, a handful of the 69 rows).
    let m = best_fit();
    assert!((1438.0..=1443.0).contains(&m.gauge_mm), "{m:?}");
    assert!(m.rows >= 60, "{m:?}");
    assert!(m.rms_radius_m < 0.35e-3, "{m:?}");
    assert!(m.rms_angle_rad < 0.03, "{m:?}");
    assert!(m.rms_a_rel < 0.15 && m.rms_b_rel < 0.35, "{m:?}");
}

#[test]
fn s1002_uic60_conicity_is_in_the_quoted_range() {
    let c = conicities(&[3e-3]);
    assert!((0.1..=0.25).contains(&c[0]), "{c:?}");
}
