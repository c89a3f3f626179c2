//! The real program, run as a user runs it: outputs, JSON contract, exit codes.

mod common;
use common::{critspeed, scratch};

fn study(name: &str) -> String {
    format!("{}/studies/{name}", env!("CARGO_MANIFEST_DIR"))
}

#[test]
fn run_without_a_study_writes_the_seed_outputs() {
    let dir = scratch("run");
    let out = critspeed(&["run"], &dir);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    for f in [
        "linear.json",
        "spectrum.csv",
        "root_locus.svg",
        "damping.svg",
        "geometry.csv",
        "geometry.svg",
    ] {
        let p = dir.join("out/seed").join(f);
        let meta = std::fs::metadata(&p).unwrap_or_else(|_| panic!("{} written", p.display()));
        assert!(meta.len() > 100, "{} is not empty", p.display());
    }
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(stdout.contains("Kalker"), "{stdout}");
    for f in [
        "linear.json",
        "damping.svg",
        "bifurcation.svg",
        "branch.csv",
    ] {
        let p = dir.join("out/seed-hunting").join(f);
        assert!(p.is_file(), "{} written by the first run", p.display());
    }
}

fn json(out: &std::process::Output) -> serde_json::Value {
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).expect("JSON on stdout")
}

/// The first run's summary states what the single commands compute: the seed's V_L over
/// [1, 4000] m/s against the paper's 40 m/s, and seed-hunting's V_L, V_H and V_NL.
#[test]
fn first_run_summary_agrees_with_the_commands() {
    let dir = scratch("first-run");
    let out = critspeed(&["run"], &dir);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let summary = String::from_utf8_lossy(&out.stdout);
    let seed = std::fs::read_to_string(study("seed.toml")).expect("seed.toml");
    let wide = seed.replace("\"300 m/s\"]", "\"4000 m/s\"]");
    assert_ne!(wide, seed, "the seed study's range is [1, 300] m/s");
    std::fs::write(dir.join("wide.toml"), wide).expect("write");
    let lin = json(&critspeed(
        &["--out", "o", "linear", "wide.toml", "--json"],
        &dir,
    ));
    let v_l = lin["linear_critical_speed_m_s"]
        .as_f64()
        .expect("a V_L below 4000 m/s");
    assert!(v_l > 300.0, "{v_l}");
    assert!(
        summary.contains(&format!("paper 40 m/s   critspeed {v_l:.1} m/s")),
        "{summary}"
    );
    assert!(summary.contains("paper 35 m/s"), "{summary}");
    let b = json(&critspeed(
        &[
            "--out",
            "o",
            "bifurcation",
            &study("seed-hunting.toml"),
            "--json",
        ],
        &dir,
    ));
    let f = |k: &str| b[k].as_f64().unwrap_or_else(|| panic!("{k}"));
    let line = format!(
        "V_L = {:.2} m/s ({:.0} km/h), V_H = {:.2} m/s ({:.0} km/h), supercritical, V_NL = {:.2} m/s",
        f("kalker_critical_speed_m_s"),
        f("kalker_critical_speed_m_s") * 3.6,
        f("hopf_speed_m_s"),
        f("hopf_speed_m_s") * 3.6,
        f("nonlinear_critical_speed_m_s"),
    );
    assert!(summary.contains(&line), "{line}\n{summary}");
    assert!(
        summary.contains("out/seed-hunting/bifurcation.svg"),
        "{summary}"
    );
}

#[test]
fn linear_json_has_the_contract_keys() {
    let dir = scratch("json");
    let out = critspeed(&["linear", &study("seed.toml"), "--json"], &dir);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value =
        serde_json::from_slice(&out.stdout).expect("stdout is one JSON object");
    assert_eq!(v["study"], "seed");
    let range = v["speed_range_m_s"].as_array().expect("range array");
    assert_eq!(range.len(), 2);
    assert!(v["critical_speeds"].is_array() && v["creep_law_hopf_speeds"].is_array());
    for c in v["critical_speeds"].as_array().into_iter().flatten() {
        assert!(c["speed_m_s"].is_f64() && c["frequency_hz"].is_f64());
        assert!(c["direction"] == "onset" || c["direction"] == "recovery");
    }
    // the file written is the same object
    let file: serde_json::Value = serde_json::from_slice(
        &std::fs::read(dir.join("out/seed/linear.json")).expect("linear.json"),
    )
    .expect("valid JSON");
    assert_eq!(file, v);
}

#[test]
fn spectrum_csv_header_is_stable() {
    let dir = scratch("csv");
    let out = critspeed(&["linear", &study("seed.toml")], &dir);
    assert!(out.status.success());
    let text = std::fs::read_to_string(dir.join("out/seed/spectrum.csv")).expect("csv");
    let header = text.lines().next().expect("header");
    assert_eq!(
        header,
        "creep_law,speed_m_s,eig1_re_per_s,eig1_im_rad_per_s,eig1_damping_ratio,\
eig2_re_per_s,eig2_im_rad_per_s,eig2_damping_ratio,eig3_re_per_s,eig3_im_rad_per_s,\
eig3_damping_ratio,eig4_re_per_s,eig4_im_rad_per_s,eig4_damping_ratio,least_damping_ratio"
    );
    let cols = header.split(',').count();
    assert!(text.lines().skip(1).all(|l| l.split(',').count() == cols));
}

#[test]
fn user_errors_exit_2_without_panicking() {
    let dir = scratch("errors");
    let bad = dir.join("bad.toml");
    std::fs::write(&bad, "name = \"x\"\n").expect("write");
    for args in [
        vec!["linear", "/nonexistent.toml"],
        vec!["linear", bad.to_str().expect("utf-8 path")],
        vec!["frobnicate"],
        vec!["check"],
    ] {
        let out = critspeed(&args, &dir);
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!err.contains("panicked"), "{err}");
    }
}

#[test]
fn check_prints_the_plan_in_si() {
    let dir = scratch("check");
    let out = critspeed(&["check", &study("seed.toml")], &dir);
    assert!(out.status.success());
    let s = String::from_utf8_lossy(&out.stdout);
    assert!(
        s.contains("700 kg m^2") && s.contains("3860000 N/m") && s.contains("8000 N s/m"),
        "{s}"
    );
}

#[test]
fn bifurcation_json_and_branch_csv_contract() {
    let dir = scratch("bif");
    let out = critspeed(
        &["bifurcation", &study("flange-hysteresis.toml"), "--json"],
        &dir,
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).expect("one JSON object");
    for key in [
        "study",
        "kalker_critical_speed_m_s",
        "hopf_speed_m_s",
        "hopf_type",
        "nonlinear_critical_speed_m_s",
        "nonlinear_critical_speed_sources",
        "branches",
        "special_points",
        "stop_reason",
    ] {
        assert!(v.get(key).is_some(), "missing {key}");
    }
    assert_eq!(v["hopf_type"], "supercritical");
    assert_eq!(v["branches"][0]["kind"], "symmetric");
    let folds: Vec<&serde_json::Value> = v["special_points"]
        .as_array()
        .expect("array")
        .iter()
        .filter(|p| p["kind"] == "fold")
        .collect();
    assert_eq!(folds.len(), 2);
    assert!(folds
        .iter()
        .all(|f| f["located"] == true && f["speed_m_s"].is_f64()));
    let csv = std::fs::read_to_string(dir.join("out/flange-hysteresis/branch.csv")).expect("csv");
    let header = csv.lines().next().expect("header");
    assert_eq!(
        header,
        "branch,branch_kind,speed_m_s,amplitude_y_m,amplitude_y_right_m,amplitude_y_left_m,\
amplitude_psi_rad,period_s,frequency_hz,stable,max_multiplier_abs,trivial_multiplier_error,\
newton_iterations,y0_m,psi0_rad,ydot0_m_s,psidot0_rad_s,mu1_re,mu1_im,mu2_re,mu2_im,mu3_re,\
mu3_im,mu4_re,mu4_im"
    );
    let cols = header.split(',').count();
    assert!(csv.lines().skip(1).all(|l| l.split(',').count() == cols));
    assert!(dir.join("out/flange-hysteresis/bifurcation.svg").is_file());
}

/// A study with an `[attractors]` section: `bifurcation --json` runs the search too and prints
/// one JSON object (the search's summary table is left out), whose V_NL names both methods,
/// and writes the search's files beside the diagram's.
#[test]
fn bifurcation_json_with_an_attractors_section_is_one_object() {
    let dir = scratch("bif-attractors");
    let v = json(&critspeed(
        &[
            "bifurcation",
            &study("dtu-bogie-uncertainty-nonlinear.toml"),
            "--json",
        ],
        &dir,
    ));
    let sources = v["nonlinear_critical_speed_sources"]
        .as_array()
        .expect("sources");
    assert!(sources.len() >= 2, "{sources:?}");
    let text = serde_json::to_string(sources).expect("text");
    assert!(
        text.contains("continuation") && text.contains("search"),
        "{text}"
    );
    let out = dir.join("out/dtu-bogie-uncertainty-nonlinear");
    for f in [
        "bifurcation.json",
        "branch.csv",
        "attractors.json",
        "attractors.csv",
    ] {
        assert!(out.join(f).is_file(), "{f} written");
    }
}

#[test]
fn simulate_and_ramp_write_their_files() {
    let dir = scratch("sim");
    let out = critspeed(
        &[
            "simulate",
            &study("seed.toml"),
            "--speed",
            "10,30,40",
            "--duration",
            "5 s",
        ],
        &dir,
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let csv = std::fs::read_to_string(dir.join("out/seed/simulate.csv")).expect("csv");
    assert!(csv.starts_with("speed_m_s,time_s,y_m,psi_rad,ydot_m_s,psidot_rad_s\n"));
    // 3 speeds × (5 s / 2 ms + 1) samples
    assert_eq!(csv.lines().count(), 1 + 3 * 2501);
    let out = critspeed(&["ramp", &study("seed-hunting.toml"), "--json"], &dir);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).expect("JSON");
    assert!(v["quantity"].as_str().is_some_and(|q| q.contains("ramp")));
    assert!(v["died_at_m_s"].is_f64());
    // a bad unit is a user error
    let bad = critspeed(&["simulate", &study("seed.toml"), "--speed", "40 N"], &dir);
    assert_eq!(bad.status.code(), Some(2));
}

/// `critspeed ramp` on a bogie (it refused vehicles before): the start defaults to 1.05 V_H
/// from the vehicle's eigenvalue scan, `ramp.json` keeps the wheelset's keys and adds one EN
/// 14363 object per wheelset, `en14363.csv` one column per wheelset.
#[test]
fn ramp_on_a_bogie_reports_every_wheelset() {
    let dir = scratch("ramp-bogie");
    let bogie = study("dtu-cooperrider-bogie.toml");
    let out = critspeed(&["ramp", &bogie, "--settle", "5 s", "--json"], &dir);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).expect("JSON");
    // 1.05 × V_H = 1.05 × 216.16 m/s
    let start = v["start_speed_m_s"].as_f64().expect("start");
    assert!((start / 1.05 - 216.16).abs() < 0.01, "{start}");
    assert!(v["died_at_m_s"].is_f64());
    let en = &v["en14363"];
    for key in [
        "f0_hz",
        "limit_kn",
        "max_rms_kn",
        "verdict",
        "worst_wheelset",
    ] {
        assert!(!en[key].is_null(), "{key}: {en}");
    }
    let wheelsets = en["wheelsets"].as_array().expect("wheelsets");
    let names: Vec<&str> = wheelsets
        .iter()
        .filter_map(|w| w["name"].as_str())
        .collect();
    assert_eq!(names, ["wheelset 1", "wheelset 2"]);
    let csv = std::fs::read_to_string(dir.join("out/dtu-cooperrider-bogie/en14363.csv"))
        .expect("en14363.csv");
    assert!(csv.starts_with(
        "time_s,speed_m_s,sum_guiding_forces_rms_kn,limit_kn,rms_wheelset_1_kn,rms_wheelset_2_kn\n"
    ));
    assert!(csv.lines().count() > 10);
    assert!(csv.lines().skip(1).all(|l| l.split(',').count() == 6));
}

#[test]
fn conicity_json_contract_and_errors() {
    let dir = scratch("conicity");
    let table = dir.join("dr.csv");
    // a 1:10 cone: Δr = 2·0.1·y
    let mut text = String::from("y_mm,delta_r_mm\n");
    for i in -80..=80 {
        let y = i as f64 * 0.1;
        text.push_str(&format!("{y},{}\n", 0.2 * y));
    }
    std::fs::write(&table, text).expect("write");
    let t = table.to_str().expect("utf-8");
    let out = critspeed(
        &[
            "conicity",
            "--delta-r",
            t,
            "--amplitudes",
            "1mm,3mm",
            "--json",
        ],
        &dir,
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).expect("JSON");
    let lam: Vec<f64> = v["equivalent_conicity"]
        .as_array()
        .expect("array")
        .iter()
        .map(|x| x.as_f64().expect("number"))
        .collect();
    assert_eq!(v["amplitude_m"].as_array().map(Vec::len), Some(2));
    assert!(lam.iter().all(|l| (l - 0.1).abs() < 1e-9), "{lam:?}");
    assert!(dir.join("out/dr/conicity.csv").is_file() && dir.join("out/dr/conicity.svg").is_file());
    // beyond the table, and a malformed file: user errors naming the problem
    let far = critspeed(&["conicity", "--delta-r", t, "--amplitudes", "20mm"], &dir);
    assert_eq!(far.status.code(), Some(2));
    std::fs::write(&table, "y_mm,delta_r_mm\n0,0\n1,oops\n").expect("write");
    let bad = critspeed(&["conicity", "--delta-r", t], &dir);
    assert_eq!(bad.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&bad.stderr).contains("dr.csv:3"));
}

#[test]
fn geometry_of_a_profile_study_reports_jumps_and_offsets() {
    let dir = scratch("profiles");
    let out = critspeed(&["geometry", &study("s1002-uic60.toml")], &dir);
    assert_eq!(out.status.code(), Some(0), "{out:?}");
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("contact jump between y = "), "{text}");
    let csv = std::fs::read_to_string(dir.join("out/s1002-uic60/geometry.csv")).expect("csv");
    let header = csv.lines().next().expect("header");
    assert!(
        header.ends_with(",wheel_contact_offset_right_m"),
        "{header}"
    );
    // a malformed profile is a user error (exit 2) naming the file and line
    let bad = dir.join("bad.toml");
    let text = std::fs::read_to_string(study("s1002-uic60.toml")).expect("study");
    let text = text.replace("profiles/s1002.csv", "wheel.csv");
    std::fs::write(&bad, text).expect("write study");
    // 30 points 2 mm apart; the 6th (file line 7) goes backwards
    let pts: String = (0..30)
        .map(|k| format!("{},0\n", if k == 5 { 3 } else { 2 * k } as f64 - 30.0))
        .collect();
    std::fs::write(dir.join("wheel.csv"), format!("y_mm,z_mm\n{pts}")).expect("write wheel");
    let out = critspeed(&["geometry", bad.to_str().expect("utf-8")], &dir);
    assert_eq!(out.status.code(), Some(2), "{out:?}");
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("wheel.csv:7:") && err.contains("monotonic"),
        "{err}"
    );
}

/// Every key of `[attractors]` and the new `[bifurcation]` keys checked: a bad value exits 2
/// with a message naming the key, the value and the rule.
#[test]
fn bad_attractor_and_switching_keys_exit_2_naming_the_key() {
    let dir = scratch("attractor-keys");
    let base = std::fs::read_to_string(study("seed-hunting.toml")).expect("study");
    let cases = [
        (
            "[attractors]\nspeeds = 0\n",
            "attractors.speeds",
            "must lie in [1, 200]",
        ),
        (
            "[attractors]\nspeed_range = [\"50 m/s\", \"400 m/s\"]\n",
            "attractors.speed_range[1]",
            "inside the bifurcation speed range",
        ),
        (
            "[attractors]\nspeed_range = [\"90 m/s\", \"60 m/s\"]\n",
            "attractors.speed_range",
            "the maximum must exceed the minimum",
        ),
        (
            "[attractors]\namplitudes = [\"15 mm\"]\n",
            "attractors.amplitudes[0]",
            "must not exceed the contact geometry's range",
        ),
        (
            "[attractors]\namplitudes = []\n",
            "attractors.amplitudes",
            "1 to 20",
        ),
        (
            "[attractors]\nsettle = \"-1 s\"\n",
            "attractors.settle",
            "positive",
        ),
        (
            "[attractors]\nbracket = \"0 m/s\"\n",
            "attractors.bracket",
            "positive",
        ),
        (
            "[attractors]\ndescent_step = 0.9\n",
            "attractors.descent_step",
            "(0, 0.5]",
        ),
        (
            "[attractors]\nthreshold = \"9 mm\"\namplitudes = [\"2 mm\"]\n",
            "attractors.threshold",
            "below the smallest",
        ),
        (
            "[attractors]\nrtol = 1\n",
            "attractors.rtol",
            "[1e-12, 1e-4]",
        ),
        (
            "[attractors]\nmax_period = 0\n",
            "attractors.max_period",
            "[1, 64]",
        ),
        (
            "[attractors]\nlowest = \"0.5 m/s\"\n",
            "attractors.lowest",
            "inside the bifurcation speed range",
        ),
        ("[attractors]\nsettle = \"2 m\"\n", "attractors.settle", "s"),
        (
            "[bifurcation]\nmax_branches = 0\n",
            "bifurcation.max_branches",
            "[1, 1000]",
        ),
        ("[bifurcation]\nswitch = \"yes\"\n", "switch", "bool"),
    ];
    for (section, key, rule) in cases {
        let text = if base.contains("[bifurcation]\n") && section.starts_with("[bifurcation]") {
            base.replacen("[bifurcation]\n", section, 1)
        } else {
            format!("{base}\n{section}")
        };
        let path = dir.join("bad.toml");
        std::fs::write(&path, &text).expect("write");
        let out = critspeed(&["check", path.to_str().expect("utf-8")], &dir);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{key}: {err}");
        assert!(
            err.contains(key) && err.contains(rule),
            "{key} / {rule}: {err}"
        );
    }
}
