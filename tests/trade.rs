//! `critspeed trade` end to end on a synthetic `sweep.csv` whose critical speeds come from the
//! library's linear analysis (independent of the trade code): the best design must be the
//! lowest swept stiffness whose linear critical speed meets the constraint.

use std::path::{Path, PathBuf};

use critspeed::{analysis, study};

mod common;
use common::{critspeed, scratch};

const STUDY: &str = "trade-longitudinal-stiffness.toml";
const LINE_SPEED: f64 = 200.0 / 3.6; // m/s

fn study_text() -> String {
    let path = format!("{}/studies/{STUDY}", env!("CARGO_MANIFEST_DIR"));
    std::fs::read_to_string(path).expect("the trade study is in studies/")
}

/// The study with its longitudinal stiffness set to `k` (N/m).
fn with_stiffness(text: &str, k: f64) -> String {
    let from = "longitudinal_stiffness = \"850 N/mm\"";
    assert!(text.contains(from));
    text.replace(from, &format!("longitudinal_stiffness = {k:e}"))
}

/// Linear (Kalker) critical speed of the study at stiffness `k`, by the library.
fn linear_speed(text: &str, k: f64) -> Option<f64> {
    let plan = study::parse(&with_stiffness(text, k), "trade test").expect("valid study");
    let model = plan.model().expect("model");
    let r = analysis::linear(&plan, &model).expect("linear analysis");
    r.kalker.critical().map(|c| c.speed_m_s)
}

/// The study's trade constrained on the linear speed (the synthetic sweep has no nonlinear).
fn kalker_study(dir: &Path) -> PathBuf {
    let text = study_text().replace(
        "result = \"nonlinear_critical_speed\"",
        "result = \"kalker_critical_speed\"",
    );
    let p = dir.join(STUDY);
    std::fs::write(&p, text).expect("write study");
    p
}

#[test]
fn best_is_the_lowest_stiffness_meeting_the_linear_constraint() {
    let dir = scratch("e2e");
    let text = study_text();
    // 9 log-spaced stiffnesses, 100..3000 N/mm, by index
    let ks: Vec<f64> = (0..9).map(|i| 1e5 * 30f64.powf(i as f64 / 8.0)).collect();
    let vs: Vec<Option<f64>> = ks.iter().map(|&k| linear_speed(&text, k)).collect();
    // point 2 failed on V_L (no value), as a sweep records it: infeasible; point 6 failed on
    // V_H only, which this trade does not read: it counts with its V_L
    let (failed, other) = (2, 6);
    let mut csv = String::from(
        "point_id,suspension.longitudinal_stiffness_n_per_m,kalker_critical_speed_m_s,\
         hopf_speed_m_s,nonlinear_critical_speed_m_s,status,extra_column_hz\n",
    );
    for (i, (k, v)) in ks.iter().zip(&vs).enumerate() {
        let v = match v {
            Some(v) if i != failed => v.to_string(),
            _ => String::new(),
        };
        let status = match i {
            _ if i == failed => "failed: kalker: no convergence; test",
            _ if i == other => "failed: hopf: no onset; test",
            _ => "ok",
        };
        csv.push_str(&format!("{i},{k},{v},,,{status},1.5\n"));
    }
    let out_dir = dir.join("out/trade-longitudinal-stiffness");
    std::fs::create_dir_all(&out_dir).expect("out dir");
    std::fs::write(out_dir.join("sweep.csv"), csv).expect("sweep.csv");
    let study = kalker_study(&dir);
    let out = critspeed(
        &["trade", "--from-csv", study.to_str().expect("utf-8")],
        &dir,
    );
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );

    let bound = 1.1 * LINE_SPEED;
    let feasible = |i: usize| i != failed && vs[i].is_some_and(|v| v >= bound);
    let best = (0..ks.len())
        .find(|&i| feasible(i))
        .expect("some stiffness is fast enough");
    assert!(
        best > 0,
        "the constraint should cut off the softest springs"
    );
    assert!(
        feasible(other),
        "point {other} exercises a failure the trade does not read"
    );
    let trade = std::fs::read_to_string(out_dir.join("trade.csv")).expect("trade.csv");
    let mut lines = trade.lines();
    let header = lines.next().expect("header");
    assert!(header.starts_with("point_id,suspension.longitudinal_stiffness_n_per_m,"));
    assert!(header.ends_with(",extra_column_hz,feasible,pareto,best,reason"));
    for (i, line) in lines.enumerate() {
        let f: Vec<&str> = line.split(',').collect();
        assert_eq!(
            f[7],
            feasible(i).to_string(),
            "feasible flag of point {i}: {line}"
        );
        assert_eq!(f[9], (i == best).to_string(), "best flag of point {i}");
        // V_L rises with the stiffness (checked below), so every computed point is on the front
        assert_eq!(
            f[8],
            (i != failed && vs[i].is_some()).to_string(),
            "pareto {i}"
        );
    }
    let speeds: Vec<f64> = vs.iter().flatten().copied().collect();
    assert!(
        speeds.windows(2).all(|w| w[1] > w[0]),
        "V_L rises with stiffness: {speeds:?}"
    );
    let k_best = format!("{:.1}", ks[best] / 1e3);
    assert!(stdout.contains(&format!("best: point {best}:")), "{stdout}");
    assert!(
        stdout.contains("feasible:") && stdout.contains("m/s"),
        "{stdout}"
    );
    assert!(
        stdout.contains(&k_best[..3]),
        "best stiffness {k_best} N/mm in {stdout}"
    );
    let svg = std::fs::read_to_string(out_dir.join("trade.svg")).expect("trade.svg");
    assert!(svg.contains("best design") && svg.contains("61.11 m/s"));
}

#[test]
fn missing_sweep_and_bad_trade_are_user_errors() {
    let dir = scratch("errors");
    let study = kalker_study(&dir);
    let out = critspeed(
        &["trade", "--from-csv", study.to_str().expect("utf-8")],
        &dir,
    );
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("sweep.csv") && err.contains("critspeed sweep"),
        "{err}"
    );

    let bad = dir.join("bad.toml");
    let text = study_text().replace("minimize = ", "minimise = ");
    std::fs::write(&bad, text).expect("write");
    let out = critspeed(&["trade", bad.to_str().expect("utf-8")], &dir);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("trade.minimise") && err.contains("unknown key"),
        "{err}"
    );
}

/// Without `--from-csv`, `trade` runs the sweep itself (here 9 Kalker points): its best design
/// is the lowest swept stiffness whose V_L, computed independently by the library, meets the
/// constraint; a second run resumes every point instead of recomputing.
#[test]
fn trade_runs_the_sweep_first() {
    let dir = scratch("runs-sweep");
    let text = std::fs::read_to_string(kalker_study(&dir)).expect("study");
    let text = text.replace("count = 25", "count = 9").replace(
        "compute = [\"kalker\", \"nonlinear\"]",
        "compute = [\"kalker\"]",
    );
    assert!(text.contains("count = 9") && text.contains("compute = [\"kalker\"]"));
    let study = dir.join("quick.toml");
    std::fs::write(&study, &text).expect("write study");
    let args = ["trade", study.to_str().expect("utf-8")];
    let out = critspeed(&args, &dir);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let ks: Vec<f64> = (0..9).map(|i| 1e5 * 30f64.powf(i as f64 / 8.0)).collect();
    let best = ks
        .iter()
        .position(|&k| linear_speed(&text, k).is_some_and(|v| v >= 1.1 * LINE_SPEED))
        .expect("some stiffness is fast enough");
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(stdout.contains(&format!("best: point {best}:")), "{stdout}");
    let again = critspeed(&args, &dir);
    let err = String::from_utf8_lossy(&again.stderr);
    assert!(
        again.status.success() && err.contains("resuming: 9 of 9"),
        "{err}"
    );
    assert_eq!(again.stdout, out.stdout);
}

/// `critspeed check` validates `[sweep]` and `[trade]` too (it used to pass a broken trade).
#[test]
fn check_validates_sweep_and_trade() {
    let dir = scratch("check");
    let good = dir.join("good.toml");
    std::fs::write(&good, study_text()).expect("write");
    let out = critspeed(&["check", good.to_str().expect("utf-8")], &dir);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(
        stdout.contains("[sweep] valid: 25 points") && stdout.contains("[trade] valid"),
        "{stdout}"
    );
    // a wheelset's sweep finds V_NL by the fast form unless it asks for the search
    assert!(
        stdout.contains("  V_NL by the continuation and the descents"),
        "{stdout}"
    );
    let bad = dir.join("bad.toml");
    std::fs::write(&bad, study_text().replace("minimize = ", "minimise = ")).expect("write");
    let out = critspeed(&["check", bad.to_str().expect("utf-8")], &dir);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(err.contains("trade.minimise"), "{err}");
}
