//! "No onset of hunting in the speed range" is a result (stable up to v_max), not a failure.
//! The truth is independent of the sweep: the linear analysis of each point's own study on a
//! wide range [1, 1000] m/s gives V_L and V_H; a sweep whose range stops below them must say
//! "above range" with stable_up_to_m_s = v_max, and one whose range holds them must find them.

use std::path::Path;

use critspeed::sweep::{self, Computed, Outcome, Shard, SweepOptions, SweepStudy};
use critspeed::{analysis, study};

mod common;
use common::{critspeed, scratch};

/// Longitudinal stiffnesses of the two points (N/m): stiff enough for V_L in the hundreds.
const KS: [f64; 2] = [2e6, 4e6];

fn seed(name: &str, v_max: f64) -> String {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/studies/seed-hunting.toml");
    let text = std::fs::read_to_string(path).expect("studies/seed-hunting.toml");
    let range = "speed_range = [\"1 m/s\", \"150 m/s\"]";
    assert!(text.contains(range));
    text.replace("name = \"seed-hunting\"", &format!("name = \"{name}\""))
        .replace(
            range,
            &format!("speed_range = [\"1 m/s\", \"{v_max} m/s\"]"),
        )
}

/// The sweep study over `KS` with the range [1, v_max] m/s.
fn sweep_study(v_max: f64) -> String {
    seed("above", v_max)
        + "\n[sweep]\naxes = [ { key = \"suspension.longitudinal_stiffness\", from = 2e6, to = 4e6, count = 2 } ]\n\
           compute = [\"kalker\", \"hopf\"]\n"
}

/// (V_L, V_H) in m/s of the seed with stiffness `k` on [1, v_max], by the linear analysis of
/// the plain study (no sweep code involved).
fn linear(k: f64, v_max: f64) -> (Option<f64>, Option<f64>) {
    let line = "longitudinal_stiffness = \"850 N/mm\"";
    let text = seed("one", v_max);
    assert!(text.contains(line));
    let text = text.replace(line, &format!("longitudinal_stiffness = {k:e}"));
    let plan = study::parse(&text, "one point").expect("study");
    let model = plan.model().expect("model");
    let r = analysis::linear(&plan, &model).expect("linear analysis");
    let first = |c: &critspeed::stability::CriticalSpeeds| c.critical().map(|x| x.speed_m_s);
    (first(&r.kalker), first(r.law_crossings()))
}

fn run(v_max: f64) -> Vec<sweep::PointRecord> {
    let s = SweepStudy::parse(&sweep_study(v_max), "above").expect("study");
    let opts = SweepOptions {
        threads: Some(1),
        shard: Shard::ALL,
        records: None,
    };
    sweep::run(&s, &opts, None).expect("sweep").rows
}

/// The wide-range truth: every V_L and V_H of the two points.
fn truth() -> Vec<(f64, f64)> {
    KS.iter()
        .map(|&k| match linear(k, 1000.0) {
            (Some(l), Some(h)) => (l, h),
            other => panic!("k = {k} N/m: no onset below 1000 m/s: {other:?}"),
        })
        .collect()
}

#[test]
fn range_top_below_the_critical_speed_is_above_range() {
    let t = truth();
    let lowest = t.iter().map(|p| p.0.min(p.1)).fold(f64::INFINITY, f64::min);
    let v_max = (0.9 * lowest).round();
    assert!(v_max > 10.0, "{t:?}");
    eprintln!("(V_L, V_H) on [1, 1000] m/s: {t:?}; sweep range top {v_max} m/s");
    for r in run(v_max) {
        assert!(r.ok(), "{r:?}");
        assert_eq!(r.above_range, vec![Computed::Kalker, Computed::Hopf]);
        assert_eq!(r.stable_up_to_m_s, Some(v_max));
        assert_eq!(r.status(), "above range: kalker; hopf");
        assert_eq!(r.kalker_m_s, None);
        assert_eq!(
            r.outcome(Computed::Hopf),
            Outcome::AboveRange {
                stable_up_to_m_s: v_max
            }
        );
    }
}

#[test]
fn range_top_above_the_critical_speed_finds_it() {
    let t = truth();
    let highest = t.iter().map(|p| p.0.max(p.1)).fold(0.0, f64::max);
    let v_max = (1.1 * highest).round().min(1000.0);
    for (r, (l, h)) in run(v_max).iter().zip(&t) {
        assert_eq!(r.status(), "ok");
        assert_eq!(r.stable_up_to_m_s, None);
        // the same search on the same range: identical numbers
        let (ls, hs) = linear(r.values[0], v_max);
        assert_eq!((r.kalker_m_s, r.hopf_m_s), (ls, hs));
        // and the wide range finds the same speeds (each located to 1e-12 relative)
        for (got, want) in [(r.kalker_m_s, *l), (r.hopf_m_s, *h)] {
            let got = got.expect("found");
            assert!((got - want).abs() <= 1e-9 * want, "{got} vs {want}");
        }
    }
}

fn ok(out: &std::process::Output) -> String {
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stdout).into_owned()
}

fn write_study(dir: &Path, v_max: f64) {
    std::fs::write(dir.join("study.toml"), sweep_study(v_max)).expect("write");
}

#[test]
fn csv_plot_summary_and_shards_show_above_range() {
    let dir = scratch("cli");
    let t = truth();
    let v_max = (0.9 * t.iter().map(|p| p.0.min(p.1)).fold(f64::INFINITY, f64::min)).round();
    write_study(&dir, v_max);
    let stdout = ok(&critspeed(&["--out", "w", "sweep", "study.toml"], &dir));
    assert!(
        stdout.contains("2 points: 0 ok, 2 above range, 0 failed"),
        "{stdout}"
    );
    let csv = std::fs::read_to_string(dir.join("w/above/sweep.csv")).expect("sweep.csv");
    let head: Vec<&str> = csv.lines().next().expect("header").split(',').collect();
    let col = |name: &str| head.iter().position(|c| *c == name).expect(name);
    for line in csv.lines().skip(1) {
        let f: Vec<&str> = line.split(',').collect();
        assert_eq!(f[col("status")], "above range: kalker; hopf");
        assert_eq!(f[col("stable_up_to_m_s")].parse::<f64>(), Ok(v_max));
        assert_eq!(f[col("kalker_critical_speed_m_s")], "");
    }
    let svg = std::fs::read_to_string(dir.join("w/above/sweep.svg")).expect("sweep.svg");
    assert!(
        svg.contains(&format!("above range: no onset up to {v_max:.0} m/s")),
        "legend entry"
    );
    assert!(!svg.contains("failed point"));

    // shards joined give the same bytes
    for s in ["0/2", "1/2"] {
        ok(&critspeed(
            &["--out", "s", "sweep", "study.toml", "--shard", s],
            &dir,
        ));
    }
    ok(&critspeed(&["--out", "s", "merge", "study.toml"], &dir));
    let merged = std::fs::read_to_string(dir.join("s/above/sweep.csv")).expect("merged");
    assert_eq!(merged, csv);
}

#[test]
fn old_records_files_are_refused_by_name() {
    let dir = scratch("old");
    write_study(&dir, 100.0);
    let s = SweepStudy::load(&dir.join("study.toml")).expect("study");
    let old = format!(
        "# critspeed sweep records\n# fingerprint: {}\n# points: 2\n# shard: 0/1\n\
         point_id,suspension.longitudinal_stiffness_n_per_m,kalker_critical_speed_m_s,hopf_speed_m_s,\
         nonlinear_critical_speed_m_s,status,kalker_frequency_hz,hopf_frequency_hz,nonlinear_located\n\
         0,2000000,,,,failed: kalker: no onset of hunting between 1 and 100 m/s,,,\n",
        s.fingerprint
    );
    std::fs::create_dir_all(dir.join("o/above")).expect("dir");
    std::fs::write(dir.join("o/above/sweep.records.csv"), old).expect("write");
    let out = critspeed(&["--out", "o", "sweep", "study.toml"], &dir);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(
        err.contains("sweep.records.csv") && err.contains("older critspeed"),
        "{err}"
    );
    let out = critspeed(&["--out", "o", "merge", "study.toml"], &dir);
    assert_eq!(out.status.code(), Some(2));
}

#[test]
fn old_sweep_csv_is_still_read() {
    let dir = scratch("oldcsv");
    let old = "point_id,suspension.longitudinal_stiffness_n_per_m,kalker_critical_speed_m_s,hopf_speed_m_s,\
               nonlinear_critical_speed_m_s,status,kalker_frequency_hz,hopf_frequency_hz,nonlinear_located\n\
               0,2000000,120.5,,,ok,2.5,,\n\
               1,4000000,,,,failed: kalker: no onset of hunting between 1 and 100 m/s,,,\n";
    let p = dir.join("sweep.csv");
    std::fs::write(&p, old).expect("write");
    let csv = sweep::read_csv(&p).expect("format-1 sweep.csv");
    assert_eq!(csv.rows.len(), 2);
    assert_eq!(csv.rows[0].kalker_m_s, Some(120.5));
    // its meaning is kept: there no onset was a failure
    assert!(!csv.rows[1].ok() && csv.rows[1].above_range.is_empty());
}
