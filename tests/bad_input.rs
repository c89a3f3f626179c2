//! Bad and absurd input through the real program: values the model cannot mean are refused
//! before anything is computed (exit 2, the key named), implausible ones are computed with a
//! warning, and a figure with nothing to draw never fails a finished computation.
//!
//! The regression tests at the end are cases the property harness (`tests/fuzz.rs`) found.

mod common;
use common::{critspeed, root, scratch};

/// The seed study with `key = value` in place of its line.
fn seed_with(key: &str, value: &str) -> String {
    let text = std::fs::read_to_string(root().join("studies/seed.toml")).expect("seed");
    let mut found = false;
    let lines: Vec<String> = text
        .lines()
        .map(|l| {
            if l.starts_with(&format!("{key} =")) {
                found = true;
                format!("{key} = {value}")
            } else {
                l.to_string()
            }
        })
        .collect();
    assert!(found, "{key} not in the seed study");
    lines.join("\n") + "\n"
}

fn stderr(out: &std::process::Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

#[test]
fn absurd_magnitudes_exit_2_naming_the_key_before_anything_is_computed() {
    let dir = scratch("absurd");
    for (key, value, section) in [
        ("rolling_radius", "1e300", "wheelset"),
        ("mass", "1e19", "wheelset"),
        ("mass", "1e-300", "wheelset"),
        ("half_spring_spacing", "1e19", "suspension"),
        ("half_contact_distance", "1e19", "wheelset"),
        ("lateral_damping", "1e300", "suspension"),
        ("friction", "5", "contact"),
    ] {
        let study = dir.join("absurd.toml");
        std::fs::write(&study, seed_with(key, value)).expect("write");
        for cmd in ["check", "linear"] {
            let out = critspeed(&[cmd, study.to_str().expect("utf-8")], &dir);
            let err = stderr(&out);
            assert_eq!(out.status.code(), Some(2), "{cmd} {key} = {value}: {err}");
            assert!(
                err.contains(&format!("{section}.{key} = {value}")) && err.contains("must lie in"),
                "{err}"
            );
            assert!(!dir.join("out").exists(), "nothing written for {key}");
        }
    }
}

#[test]
fn implausible_values_are_computed_with_a_warning_naming_key_value_and_range() {
    let dir = scratch("implausible");
    let study = dir.join("implausible.toml");
    std::fs::write(&study, seed_with("poisson_ratio", "1e-300")).expect("write");
    let out = critspeed(&["check", study.to_str().expect("utf-8")], &dir);
    let err = stderr(&out);
    assert!(out.status.success(), "{err}");
    assert!(
        err.contains(
            "warning: contact.poisson_ratio = 1e-300 lies outside the plausible range [0.2, 0.35]"
        ),
        "{err}"
    );
    let s = String::from_utf8_lossy(&out.stdout);
    assert!(s.contains("1 value(s) outside the plausible ranges"), "{s}");
}

/// An overdamped wheelset (a 1e9 N s/m lateral damper, meaningful but implausible) has no
/// oscillatory eigenvalue at any speed: the root locus has nothing to draw. The computation
/// stands: exit 0, the numbers written, the figure a note saying why.
#[test]
fn a_figure_with_nothing_to_draw_is_a_note_and_the_run_succeeds() {
    let dir = scratch("note");
    let study = dir.join("overdamped.toml");
    std::fs::write(&study, seed_with("lateral_damping", "1e9")).expect("write");
    let out = critspeed(&["linear", study.to_str().expect("utf-8")], &dir);
    let err = stderr(&out);
    assert!(out.status.success(), "{err}");
    assert!(
        err.contains("warning: suspension.lateral_damping = 1e9 N s/m"),
        "{err}"
    );
    assert!(
        err.contains("warning: root_locus.svg has nothing to draw")
            && err.contains("the results are in linear.json and spectrum.csv"),
        "{err}"
    );
    let folder = dir.join("out/seed");
    // the reason is true: every eigenvalue in spectrum.csv is real
    let csv = std::fs::read_to_string(folder.join("spectrum.csv")).expect("spectrum.csv");
    let header: Vec<&str> = csv.lines().next().expect("header").split(',').collect();
    let im: Vec<usize> = (0..header.len())
        .filter(|&i| header[i].ends_with("_im_rad_per_s"))
        .collect();
    assert_eq!(im.len(), 4);
    let rows: Vec<Vec<f64>> = csv
        .lines()
        .skip(1)
        .map(|l| {
            l.split(',')
                .skip(1)
                .map(|c| c.parse().expect("number"))
                .collect()
        })
        .collect();
    assert!(rows.len() >= 300, "{} rows", rows.len());
    assert!(rows.iter().all(|r| im.iter().all(|&i| r[i - 1] == 0.0)));
    let locus = std::fs::read_to_string(folder.join("root_locus.svg")).expect("svg");
    assert!(locus.contains("root_locus.svg: nothing to draw") && locus.contains("no data points"));
    // the other figure is drawn, and linear.json holds the result
    let damping = std::fs::read_to_string(folder.join("damping.svg")).expect("svg");
    assert!(!damping.contains("nothing to draw") && damping.len() > 5000);
    let json: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(folder.join("linear.json")).expect("linear.json"),
    )
    .expect("JSON");
    assert!(json.get("linear_critical_speed_m_s").is_some());
}

/// A shipped study with each `(section, key, value)` set (the value as TOML), written into a
/// scratch folder beside copies of the shipped tables and profiles; `critspeed check` on it.
fn check_with(study: &str, changes: &[(&str, &str, &str)]) -> (Option<i32>, String) {
    run_with("check", study, changes)
}

/// As [`check_with`], for any command that takes a study.
fn run_with(command: &str, study: &str, changes: &[(&str, &str, &str)]) -> (Option<i32>, String) {
    let dir = scratch(&format!("regression-{command}-{study}"));
    let text = std::fs::read_to_string(root().join("studies").join(study)).expect("study");
    let mut t: toml::Table = toml::from_str(&text).expect("toml");
    for (section, key, value) in changes {
        let v: toml::Table = toml::from_str(&format!("v = {value}")).expect("value");
        let s = t
            .entry(section.to_string())
            .or_insert_with(|| toml::Value::Table(toml::Table::new()));
        s.as_table_mut()
            .expect("a section")
            .insert(key.to_string(), v["v"].clone());
    }
    for sub in ["tables", "profiles"] {
        std::fs::create_dir_all(dir.join(sub)).expect("dir");
        for e in std::fs::read_dir(root().join("studies").join(sub)).expect("studies") {
            let p = e.expect("entry").path();
            std::fs::copy(&p, dir.join(sub).join(p.file_name().expect("name"))).expect("copy");
        }
    }
    let path = dir.join(study);
    std::fs::write(&path, toml::to_string(&t).expect("toml")).expect("write");
    let out = critspeed(&[command, path.to_str().expect("utf-8")], &dir);
    (out.status.code(), stderr(&out))
}

#[test]
fn regression_a_geometry_table_without_semi_axes_names_the_table() {
    let (code, err) = check_with(
        "dtu-cooperrider-car.toml",
        &[("contact", "geometry_table", "\"tables/cubic-fold.csv\"")],
    );
    assert_eq!(code, Some(2), "{err}");
    assert!(
        err.contains("contact.creep_coefficients is missing")
            && err.contains("contact.geometry_table = \"")
            && err.contains("has no Hertz semi-axes"),
        "{err}"
    );
}

#[test]
fn regression_an_invalid_sweep_value_names_its_axis() {
    let text = std::fs::read_to_string(root().join("studies/conicity-wear.toml")).expect("study");
    let text = text.replace("from = \"1:40\"", "from = 1.0");
    let dir = scratch("sweep-axis");
    let path = dir.join("axis.toml");
    std::fs::write(&path, text).expect("write");
    let out = critspeed(&["check", path.to_str().expect("utf-8")], &dir);
    let err = stderr(&out);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(
        err.contains("sweep.axes[0] (contact.conicity): value 1 gives an invalid study"),
        "{err}"
    );
}

#[test]
fn regression_profiles_wheels_off_the_rails_exit_2_naming_the_distance_and_gauge() {
    for (key, value) in [
        ("half_contact_distance", "0.4"),
        ("half_contact_distance", "0.9"),
    ] {
        let (code, err) = check_with("s1002-uic60.toml", &[("wheelset", key, value)]);
        assert_eq!(code, Some(2), "{key} = {value}: {err}");
        assert!(
            err.contains("wheelset.half_contact_distance")
                && err.contains("contact.track_gauge = 1.435 m")
                && err.contains("the wheels cannot touch the rails"),
            "{err}"
        );
    }
    for gauge in ["0.6", "2.0"] {
        let (code, err) = check_with("s1002-uic60.toml", &[("contact", "track_gauge", gauge)]);
        assert_eq!(code, Some(2), "gauge {gauge}: {err}");
        assert!(err.contains("the wheels cannot touch the rails"), "{err}");
    }
}

#[test]
fn regression_a_centimetre_wheel_is_refused_not_failed() {
    let (code, err) = check_with(
        "flange-hysteresis.toml",
        &[("wheelset", "rolling_radius", "0.01")],
    );
    assert_eq!(code, Some(2), "{err}");
    assert!(
        err.contains("wheelset.rolling_radius = 0.01 m: must lie in [0.02, 2] m"),
        "{err}"
    );
}

#[test]
fn regression_a_default_lateral_range_beyond_half_the_contact_distance_is_named() {
    let (code, err) = check_with(
        "flange-hysteresis.toml",
        &[
            ("flange", "clearance", "0.19"),
            ("wheelset", "half_contact_distance", "0.5"),
        ],
    );
    assert_eq!(code, Some(2), "{err}");
    assert!(
        err.contains("contact.lateral_range = 0.285") && err.contains("flange.clearance"),
        "{err}"
    );
}

#[test]
fn regression_a_missing_section_names_the_layout_that_needs_it() {
    let (code, err) = check_with(
        "dtu-bogie-stability-map.toml",
        &[("vehicle", "kind", "\"car\"")],
    );
    assert_eq!(code, Some(2), "{err}");
    assert!(
        err.contains("carbody is missing: vehicle.kind = \"car\" needs its car body"),
        "{err}"
    );
}

/// `check`'s JSON lists the warnings, and has no `warnings` key without them (then it stays a
/// study).
#[test]
fn check_json_lists_the_warnings() {
    use critspeed::api::{check, check_json, Source};
    let json = |text: &str| {
        check_json(
            &check(&Source::text(text, "t"))
                .map_err(|e| e.message())
                .expect("valid"),
        )
        .map_err(|e| e.message())
        .expect("json")
    };
    let plain = json(&seed_with("mass", "\"1250 kg\""));
    assert!(plain.get("warnings").is_none());
    let heavy = json(&seed_with("mass", "\"5 t\""));
    let w = heavy["warnings"].as_array().expect("a list");
    assert_eq!(w.len(), 1);
    assert!(
        w[0].as_str().is_some_and(|m| m.starts_with(
            "wheelset.mass = 5000 kg lies outside the plausible range [300, 4000] kg"
        )),
        "{w:?}"
    );
}

/// Found by the hour-long fuzz run: a table narrower than the study's `lateral_range` is
/// refused naming both keys, so a user who changed only the table sees it named.
#[test]
fn regression_a_table_narrower_than_the_lateral_range_names_the_table() {
    let (code, err) = check_with(
        "cubic-fold.toml",
        &[("contact", "geometry_table", "\"tables/dtu-rsgeo-1o40.csv\"")],
    );
    assert_eq!(code, Some(2), "{err}");
    assert!(
        err.contains("contact.lateral_range") && err.contains("contact.geometry_table"),
        "{err}"
    );
}

/// Found by a long fuzz run: a car whose bogie frames weigh in at 0.016 kg m² of yaw inertia
/// has a mode of |λ| ≈ 5e7 1/s, which the explicit shooting integration would resolve with
/// about 1e6 steps per hunting period (it ran for hours). The continuation is refused at
/// once, with the figures, as a computation failure.
#[test]
fn regression_a_model_too_stiff_to_integrate_is_refused_with_its_figures() {
    let (code, err) = run_with(
        "bifurcation",
        "dtu-car-yaw-damper-trade.toml",
        &[
            ("bogie", "yaw_inertia", "0.015967663110290728"),
            ("bifurcation", "max_points", "6"),
        ],
    );
    assert_eq!(code, Some(1), "{err}");
    assert!(
        err.contains("too stiff to integrate") && err.contains("steps per cycle"),
        "{err}"
    );
}

/// An error that quotes its cause (here the operating system's) prints it once.
#[test]
fn an_unreadable_study_names_the_cause_once() {
    let dir = scratch("missing-study");
    let out = critspeed(&["check", "no-such-study.toml"], &dir);
    let err = stderr(&out);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert_eq!(err.matches("os error").count(), 1, "{err}");
}
