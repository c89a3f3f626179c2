//! `critspeed simulate --from PATH:N` and `--kick BODY.COORD=VALUE`: the start they build,
//! checked against the continuation's cycle (an independent Newton solution) and the state
//! layout of the model; bad arguments exit 2 naming option, value and rule.

use std::path::Path;

use critspeed::bifurcation::{analyse, BifurcationOptions};
use critspeed::study;

mod common;
use common::{critspeed, root, scratch};

fn study_path(name: &str) -> String {
    root()
        .join("studies")
        .join(name)
        .to_str()
        .expect("utf-8")
        .to_string()
}

/// Asserts that a run succeeded, showing its stderr where it did not.
fn succeeded(out: &std::process::Output) {
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

/// The columns of a simulate.csv.
fn csv(path: &Path) -> (Vec<String>, Vec<Vec<f64>>) {
    let text = std::fs::read_to_string(path).expect("simulate.csv");
    let mut lines = text.lines();
    let head: Vec<String> = lines
        .next()
        .expect("a header")
        .split(',')
        .map(String::from)
        .collect();
    let rows = lines
        .map(|l| l.split(',').map(|v| v.parse().expect("a number")).collect())
        .collect();
    (head, rows)
}

/// A start on a continued cycle stays on it: seed-hunting's stable cycle nearest 75 m/s,
/// written as attractor 5 of an attractors.json, simulated with `--from` for three periods at
/// its speed: the leading wheelset's largest |y| over the last period equals the cycle's
/// amplitude (Newton's solution) to 1e-5, and the first sample is the cycle's state exactly.
#[test]
fn a_start_from_an_attractors_state_stays_on_that_cycle() {
    let dir = scratch("simulate_start_from");
    let plan = study::load(Path::new(&study_path("seed-hunting.toml"))).expect("study");
    let model = plan.model().expect("model");
    let mut opts = BifurcationOptions::new((1.0, 150.0));
    opts.max_amplitude = 0.008;
    let r = analyse("seed-hunting", &model, &opts).expect("analysis");
    let c = r
        .cycles
        .iter()
        .filter(|c| c.stable)
        .min_by(|a, b| {
            (a.speed_m_s - 75.0)
                .abs()
                .total_cmp(&(b.speed_m_s - 75.0).abs())
        })
        .expect("a stable cycle");
    let json = serde_json::json!({
        "attractors": [
            {"id": 5, "path": [
                {"speed_m_s": c.speed_m_s + 10.0, "state": [0.001, 0.0, 0.0, 0.0]},
                {"speed_m_s": c.speed_m_s, "state": c.x0},
            ]},
        ]
    });
    let file = dir.join("attractors.json");
    std::fs::write(&file, json.to_string()).expect("write");
    let from = format!("{}:5", file.display());
    let speed = format!("{}", c.speed_m_s);
    let duration = format!("{} s", 3.0 * c.period_s);
    let out = critspeed(
        &[
            "simulate",
            &study_path("seed-hunting.toml"),
            "--speed",
            &speed,
            "--from",
            &from,
            "--duration",
            &duration,
            "--dt",
            "0.02 ms",
            "--out",
            dir.to_str().expect("utf-8"),
        ],
        &dir,
    );
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(0), "{err}");
    assert!(err.contains("attractor 5's state"), "{err}");
    let (head, rows) = csv(&dir.join("seed-hunting/simulate.csv"));
    let y = head.iter().position(|h| h == "y_m").expect("y_m");
    let t = head.iter().position(|h| h == "time_s").expect("time_s");
    let first = &rows[0];
    for (k, x) in c.x0.iter().enumerate() {
        assert_eq!(first[y + k], *x, "state {k}");
    }
    let last_period = rows
        .iter()
        .filter(|r| r[t] >= 2.0 * c.period_s)
        .map(|r| r[y].abs())
        .fold(0.0, f64::max);
    let rel = (last_period - c.amplitude_y_m).abs() / c.amplitude_y_m;
    assert!(
        rel < 1e-5,
        "{last_period} against {} ({rel:e})",
        c.amplitude_y_m
    );
}

/// `--kick` adds each displacement to its body's coordinate and nothing else: on the DTU car,
/// wheelset 3's y and frame 2's ψ (ψ after y in each body's coordinates).
#[test]
fn kicks_displace_the_named_coordinates_only() {
    let dir = scratch("simulate_start_kick");
    let out = critspeed(
        &[
            "simulate",
            &study_path("dtu-cooperrider-car.toml"),
            "--speed",
            "100",
            "--kick",
            "wheelset-3.y=6mm",
            "--kick",
            "frame_2.psi=2 mrad",
            "--duration",
            "0.01 s",
            "--out",
            dir.to_str().expect("utf-8"),
        ],
        &dir,
    );
    succeeded(&out);
    let (head, rows) = csv(&dir.join("dtu-cooperrider-car/simulate.csv"));
    let first = &rows[0];
    for (h, v) in head.iter().zip(first) {
        let want = match h.as_str() {
            "speed_m_s" => 100.0,
            "y_wheelset_3_m" => 0.006,
            "psi_frame_2_rad" => 0.002,
            _ => 0.0,
        };
        assert!((v - want).abs() < 1e-15, "{h}: {v} against {want}");
    }
}

/// Bad starts exit 2 naming option, value and rule.
#[test]
fn bad_starts_are_refused_naming_option_value_and_rule() {
    let dir = scratch("simulate_start_bad");
    let file = dir.join("attractors.json");
    std::fs::write(
        &file,
        r#"{"attractors": [{"id": 1, "path": [{"speed_m_s": 50, "state": [0.001, 0, 0, 0]}]}]}"#,
    )
    .expect("write");
    let f = |id: &str| format!("{}:{id}", file.display());
    let car = study_path("dtu-cooperrider-car.toml");
    let wheelset = study_path("seed-hunting.toml");
    let cases: Vec<(Vec<String>, Vec<&str>)> = vec![
        (
            vec!["--from".into(), f("7")],
            vec!["--from", "no attractor 7", "its ids: 1"],
        ),
        (
            vec!["--from".into(), f("x")],
            vec!["--from", "\"x\" is not an attractor id"],
        ),
        (
            vec!["--from".into(), f("1"), "--y0".into(), "3 mm".into()],
            vec!["--y0 and --from"],
        ),
        (
            vec!["--kick".into(), "wheel-9.y=6mm".into()],
            vec!["--kick", "no body \"wheel-9\"", "wheelset 1"],
        ),
        (
            vec!["--kick".into(), "frame-1.z=6mm".into()],
            vec!["--kick", "\"z\" is not a coordinate of frame 1"],
        ),
        (
            vec!["--kick".into(), "frame-1.y=6 kg".into()],
            vec!["--kick", "6 kg"],
        ),
        (
            vec!["--rtol".into(), "1e-3".into()],
            vec!["rtol 1e-3", "must lie in [1e-12, 1e-4]"],
        ),
        (
            vec!["--rtol".into(), "loose".into()],
            vec!["--rtol", "'loose'"],
        ),
    ];
    for (extra, words) in cases {
        let mut args: Vec<String> = vec![
            "simulate".into(),
            car.clone(),
            "--speed".into(),
            "100".into(),
        ];
        args.extend(extra);
        args.extend(["--duration".into(), "0.01 s".into()]);
        let argv: Vec<&str> = args.iter().map(String::as_str).collect();
        let out = critspeed(&argv, &dir);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {err}");
        for w in words {
            assert!(err.contains(w), "{args:?}: {w:?} not in {err}");
        }
    }
    // the file's states have 4 values, the car 28 states
    let out = critspeed(
        &["simulate", &car, "--speed", "100", "--from", &f("1")],
        &dir,
    );
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(err.contains("the file is another study's"), "{err}");
    // and the wheelset starts from them
    let out = critspeed(
        &[
            "simulate",
            &wheelset,
            "--speed",
            "50",
            "--from",
            &f("1"),
            "--duration",
            "0.01 s",
            "--out",
            dir.to_str().expect("utf-8"),
        ],
        &dir,
    );
    succeeded(&out);
}
