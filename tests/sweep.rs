//! Parameter sweeps: each point equals a single-point run of the same parameters; the CSV is
//! byte-identical whatever the thread count, after an interruption and resume, and when
//! joined from shards; bad axes are user errors that name the key.

use std::path::PathBuf;
use std::process::{Command, Output};

use critspeed::contact::creep::CreepLaw;
use critspeed::sweep::{self, Shard, SweepOptions, SweepStudy};
use critspeed::{analysis, bifurcation, study};

mod common;
use common::{critspeed, scratch};

fn base_text() -> String {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/studies/seed-hunting.toml");
    std::fs::read_to_string(path).expect("studies/seed-hunting.toml")
}

/// The seed-hunting study with `[bifurcation]` (cheap: cycles up to 1 mm) and `sweep`.
fn with_sweep(name: &str, sweep: &str) -> String {
    base_text().replace("name = \"seed-hunting\"", &format!("name = \"{name}\""))
        + "\n[bifurcation]\nmax_amplitude = \"1 mm\"\n\n[sweep]\n"
        + sweep
}

/// 2 axes, 3 × 3 points; conicity 0.03 has no Hopf point below 150 m/s (V_NL not computed).
const GRID: &str = r#"axes = [ { key = "contact.conicity", from = 0.03, to = 0.2, count = 3 },
         { key = "suspension.lateral_stiffness", from = "200 N/mm", to = "800 N/mm", count = 3, spacing = "log" } ]
compute = ["kalker", "hopf", "nonlinear"]
operating_speed = "200 km/h"
"#;

/// The study text with a key's line replaced by `key = value` (SI), as a user would edit it.
fn set_by_hand(text: &str, line_start: &str, value: f64) -> String {
    text.lines()
        .map(|l| {
            if l.trim_start().starts_with(line_start) {
                format!("{line_start} = {value:e}")
            } else {
                l.to_string()
            }
        })
        .collect::<Vec<_>>()
        .join("\n")
}

#[test]
fn sweep_points_equal_single_point_runs() {
    let text = with_sweep("sweep-points", GRID);
    let s = SweepStudy::parse(&text, "test").expect("study");
    let opts = SweepOptions {
        threads: Some(1),
        shard: Shard::ALL,
        records: None,
    };
    let res = sweep::run(&s, &opts, None).expect("sweep");
    assert_eq!(res.rows.len(), 9);
    let mut found = 0;
    for r in &res.rows {
        let (lam, k) = (r.values[0], r.values[1]);
        let one = set_by_hand(&set_by_hand(&text, "conicity", lam), "lateral_stiffness", k);
        let one = one.split("[sweep]").next().expect("text before [sweep]");
        let plan = study::parse(one, "one point").expect("plan");
        assert_eq!(plan.contact.geometry.conicity(), lam);
        assert_eq!(plan.suspension.lateral_stiffness, k);
        let model = plan.model().expect("model");
        let lin = analysis::linear(&plan, &model).expect("linear");
        assert_eq!(
            r.kalker_m_s,
            lin.kalker.critical().map(|c| c.speed_m_s),
            "{r:?}"
        );
        assert_eq!(
            r.hopf_m_s,
            lin.law_crossings().critical().map(|c| c.speed_m_s)
        );
        assert!(matches!(model.creep_law(), CreepLaw::Shen { .. }));
        let b =
            bifurcation::analyse(&plan.name, &model, &plan.bifurcation_options()).expect("branch");
        assert_eq!(r.nonlinear_m_s, b.nonlinear_critical_speed.map(|v| v.0));
        // V_NL is not computed exactly where the branch has no Hopf point to start from
        assert_eq!(r.no_hopf, b.hopf.is_none(), "{r:?}");
        let known = |v: Option<f64>, which| v.is_some() || r.above_range.contains(&which);
        assert_eq!(
            r.ok(),
            known(r.kalker_m_s, sweep::Computed::Kalker)
                && known(r.hopf_m_s, sweep::Computed::Hopf)
                && (r.nonlinear_m_s.is_some() || r.no_hopf)
        );
        let all = r.kalker_m_s.is_some() && r.hopf_m_s.is_some() && r.nonlinear_m_s.is_some();
        found += usize::from(all);
    }
    // the grid has both kinds of points
    assert!((4..9).contains(&found), "{found} points ok");
}

fn ok(out: &Output) {
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

fn read(p: PathBuf) -> Vec<u8> {
    std::fs::read(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

/// A study folder with the grid study written as study.toml.
fn grid_dir(name: &str) -> PathBuf {
    let dir = scratch(name);
    std::fs::write(dir.join("study.toml"), with_sweep("grid", GRID)).expect("write study");
    dir
}

#[test]
fn threads_resume_and_shards_give_the_same_bytes() {
    let dir = grid_dir("bytes");
    ok(&critspeed(
        &["--out", "t1", "sweep", "study.toml", "--threads", "1"],
        &dir,
    ));
    ok(&critspeed(
        &["--out", "t2", "sweep", "study.toml", "--threads", "2"],
        &dir,
    ));
    let whole = read(dir.join("t1/grid/sweep.csv"));
    assert_eq!(
        whole,
        read(dir.join("t2/grid/sweep.csv")),
        "--threads 1 vs 2"
    );
    let text = String::from_utf8(whole.clone()).expect("utf8");
    assert_eq!(text.lines().count(), 10);
    assert!(text.starts_with(
        "point_id,contact.conicity,suspension.lateral_stiffness_n_per_m,kalker_critical_speed_m_s,\
hopf_speed_m_s,nonlinear_critical_speed_m_s,status,"
    ));
    assert!(
        text.contains("; no Hopf point in range: nonlinear,"),
        "{text}"
    );
    assert!(dir.join("t1/grid/sweep_map_nonlinear.svg").is_file());

    // interrupted: keep 4 finished points and half of the fifth line, then run again
    let rec = String::from_utf8(read(dir.join("t2/grid/sweep.records.csv"))).expect("utf8");
    let lines: Vec<&str> = rec.lines().collect();
    let head = lines
        .iter()
        .take_while(|l| !l.starts_with(|c: char| c.is_ascii_digit()))
        .count();
    let kept = lines[..head + 4].join("\n") + "\n" + &lines[head + 4][..10];
    std::fs::create_dir_all(dir.join("r/grid")).expect("dir");
    std::fs::write(dir.join("r/grid/sweep.records.csv"), kept).expect("write");
    let out = critspeed(
        &["--out", "r", "sweep", "study.toml", "--threads", "2"],
        &dir,
    );
    ok(&out);
    assert!(String::from_utf8_lossy(&out.stderr).contains("resuming: 4 of 9 points"));
    assert_eq!(whole, read(dir.join("r/grid/sweep.csv")), "resumed");

    // shards 0/3 and 2/3, then merge reports the missing shard, then 1/3 and merge
    for s in ["0/3", "2/3"] {
        ok(&critspeed(
            &["--out", "s", "sweep", "study.toml", "--shard", s],
            &dir,
        ));
    }
    let partial = critspeed(&["--out", "s", "merge", "study.toml"], &dir);
    assert_eq!(partial.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&partial.stderr).contains("3 of 9 points missing: 1, 4, 7"));
    let out = Command::new(env!("CARGO_BIN_EXE_critspeed"))
        .args(["--out", "s", "sweep", "study.toml", "--shard-from-env"])
        .env("SLURM_ARRAY_TASK_ID", "2")
        .env("SLURM_ARRAY_TASK_MIN", "1")
        .env("SLURM_ARRAY_TASK_COUNT", "3")
        .current_dir(&dir)
        .output()
        .expect("runs");
    ok(&out);
    assert!(dir.join("s/grid/sweep.shard-1-of-3.records.csv").is_file());
    ok(&critspeed(&["--out", "s", "merge", "study.toml"], &dir));
    assert_eq!(whole, read(dir.join("s/grid/sweep.csv")), "merged shards");

    // sweep.csv reads back to the same rows
    let csv = sweep::read_csv(&dir.join("s/grid/sweep.csv")).expect("read");
    assert_eq!(csv.rows.len(), 9);
    assert_eq!(
        sweep::sweep_csv(
            &SweepStudy::load(&dir.join("study.toml"))
                .expect("study")
                .spec
                .axes,
            &csv.rows
        )
        .into_bytes(),
        whole
    );
}

/// Runs `critspeed --out s sweep study.toml ARGS` as Slurm array task `id` of a submission
/// `--array=MIN-MAX` with `count` tasks.
fn array_task(dir: &std::path::Path, args: &[&str], id: &str, min_max_count: [&str; 3]) -> Output {
    let [min, max, count] = min_max_count;
    Command::new(env!("CARGO_BIN_EXE_critspeed"))
        .args(["--out", "s", "sweep", "study.toml", "--shard-from-env"])
        .args(args)
        .env("SLURM_ARRAY_TASK_ID", id)
        .env("SLURM_ARRAY_TASK_MIN", min)
        .env("SLURM_ARRAY_TASK_MAX", max)
        .env("SLURM_ARRAY_TASK_STEP", "1")
        .env("SLURM_ARRAY_TASK_COUNT", count)
        .current_dir(dir)
        .output()
        .expect("runs")
}

/// The defect found under Slurm 22.05: after `scancel` of one task of a 2-task array,
/// `sbatch --array=1 job.sh` sets SLURM_ARRAY_TASK_COUNT = 1 and MIN = 1, so the resubmitted
/// task ran as shard 0/1 and recomputed the whole grid instead of its own missing points.
#[test]
fn resubmitted_array_index_ran_as_shard_0_of_1() {
    let dir = grid_dir("resubmit");
    ok(&critspeed(&["--out", "w", "sweep", "study.toml"], &dir));
    let whole = read(dir.join("w/grid/sweep.csv"));
    // the first submission, --array=0-1 with --shards 2
    for id in ["0", "1"] {
        ok(&array_task(&dir, &["--shards", "2"], id, ["0", "1", "2"]));
    }
    // task 1 (points 1, 3, 5, 7) was cancelled after its first point
    let rec_path = dir.join("s/grid/sweep.shard-1-of-2.records.csv");
    let rec = String::from_utf8(read(rec_path.clone())).expect("utf8");
    let lines: Vec<&str> = rec.lines().collect();
    let head = lines
        .iter()
        .take_while(|l| !l.starts_with(|c: char| c.is_ascii_digit()))
        .count();
    std::fs::write(&rec_path, lines[..head + 1].join("\n") + "\n").expect("write");

    // resubmitted as the README's script advises, without --shards: refused, nothing computed
    let refused = array_task(&dir, &[], "1", ["1", "1", "1"]);
    assert_eq!(refused.status.code(), Some(2));
    let err = String::from_utf8_lossy(&refused.stderr);
    assert!(
        err.contains("SLURM_ARRAY_TASK_COUNT = 1 makes this task shard 0/1")
            && err.contains("--shards 2"),
        "{err}"
    );
    assert!(!dir.join("s/grid/sweep.shard-0-of-1.records.csv").exists());

    // with --shards 2 the lone index 1 is shard 1/2 and computes only its 3 missing points
    let out = array_task(&dir, &["--shards", "2"], "1", ["1", "1", "1"]);
    ok(&out);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("resuming: 1 of 4 points"), "{err}");
    assert!(err.contains("shard 1/2 computes 4"), "{err}");
    assert!(
        err.contains("4 points finished (3 this run, 1 resumed)"),
        "{err}"
    );
    ok(&critspeed(&["--out", "s", "merge", "study.toml"], &dir));
    assert_eq!(
        whole,
        read(dir.join("s/grid/sweep.csv")),
        "merged after resubmission"
    );

    // an index beyond the shards is a user error naming the array to submit
    let out = array_task(&dir, &["--shards", "2"], "2", ["0", "2", "3"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("--array=0-1"));
}

#[test]
fn merge_refuses_another_studys_shard() {
    let dir = grid_dir("foreign");
    let other = with_sweep("grid", &GRID.replace("count = 3 }", "count = 2 }"));
    std::fs::write(dir.join("other.toml"), other).expect("write");
    ok(&critspeed(
        &["--out", "o", "sweep", "other.toml", "--shard", "0/4"],
        &dir,
    ));
    let out = critspeed(&["--out", "o", "merge", "study.toml"], &dir);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("sweep.shard-0-of-4.records.csv") && err.contains("another study"),
        "{err}"
    );
    // and a resume refuses it too
    std::fs::rename(
        dir.join("o/grid/sweep.shard-0-of-4.records.csv"),
        dir.join("o/grid/sweep.records.csv"),
    )
    .expect("mv");
    let out = critspeed(&["--out", "o", "sweep", "study.toml"], &dir);
    assert_eq!(out.status.code(), Some(2));
}

#[test]
fn bad_axis_key_or_unit_is_a_user_error_naming_it() {
    let dir = scratch("bad");
    let cases = [
        (
            GRID.replace("contact.conicity", "contact.conicty"),
            "contact.conicty",
        ),
        (
            GRID.replace("\"200 N/mm\"", "\"200 N s/mm\""),
            "suspension.lateral_stiffness",
        ),
        (
            GRID.replace("from = 0.03", "from = -0.03"),
            "contact.conicity",
        ),
        (
            GRID.replace(
                "count = 3, spacing = \"log\"",
                "count = 3, spacing = \"cubic\"",
            ),
            "cubic",
        ),
        (GRID.replace("\"nonlinear\"", "\"nonlinar\""), "nonlinar"),
    ];
    for (k, (sweep, name)) in cases.iter().enumerate() {
        let file = format!("bad{k}.toml");
        std::fs::write(dir.join(&file), with_sweep("bad", sweep)).expect("write");
        let out = critspeed(&["sweep", &file], &dir);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{err}");
        assert!(err.contains(name), "{name}: {err}");
    }
    std::fs::write(dir.join("good.toml"), with_sweep("good", GRID)).expect("write");
    let out = critspeed(&["sweep", "good.toml", "--shard", "3/3"], &dir);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("\"3/3\""));
}

/// studies/conicity-wear.toml: wear (a steeper cone) lowers the critical speed at every step,
/// for the Kalker model and the study's Shen law alike.
#[test]
fn higher_conicity_lowers_the_critical_speed() {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/studies/conicity-wear.toml");
    let text = std::fs::read_to_string(path).expect("study").replace(
        "\"kalker\", \"hopf\", \"nonlinear\"",
        "\"kalker\", \"hopf\"",
    );
    let s = SweepStudy::parse(&text, path).expect("study");
    let opts = SweepOptions {
        threads: Some(2),
        shard: Shard::ALL,
        records: None,
    };
    let rows = sweep::run(&s, &opts, None).expect("sweep").rows;
    for get in [
        |r: &sweep::PointRecord| r.kalker_m_s,
        |r: &sweep::PointRecord| r.hopf_m_s,
    ] {
        let v: Vec<f64> = rows.iter().filter_map(get).collect();
        assert!(v.len() >= 8, "{v:?}");
        assert!(v.windows(2).all(|w| w[1] < w[0]), "{v:?}");
    }
}

#[test]
fn studies_with_sweep_and_trade_sections_load_everywhere() {
    let text =
        with_sweep("both", GRID) + "\n[trade]\nanything = \"is parsed by critspeed trade\"\n";
    let plan = study::parse(&text, "both").expect("a study with [sweep] and [trade] loads");
    assert_eq!(plan.name, "both");
    let s = SweepStudy::parse(&text, "both").expect("sweep study");
    // [trade] does not change the fingerprint
    assert_eq!(
        s.fingerprint,
        SweepStudy::parse(&with_sweep("both", GRID), "b")
            .expect("s")
            .fingerprint
    );
    let err = SweepStudy::parse(&base_text(), "plain").expect_err("no [sweep]");
    assert!(err.to_string().contains("no [sweep] section"), "{err}");
}

#[test]
fn cancelled_sweep_keeps_its_points_and_resumes_to_the_same_csv() {
    // The hook is asked before each point; with one thread, allowing 4 asks computes exactly
    // 4 points, which the records file keeps; a second run computes the other 5 and the CSV
    // equals that of an uninterrupted run.
    let text = with_sweep("grid", GRID);
    let s = SweepStudy::parse(&text, "test").expect("study");
    let dir = scratch("cancel");
    let records = dir.join("sweep.records.csv");
    let opts = SweepOptions {
        threads: Some(1),
        shard: Shard::ALL,
        records: Some(records.clone()),
    };
    let asked = std::sync::atomic::AtomicUsize::new(0);
    let cancel = || asked.fetch_add(1, std::sync::atomic::Ordering::Relaxed) >= 4;
    match sweep::run_cancellable(&s, &opts, None, Some(&cancel)) {
        Err(sweep::SweepError::Cancelled { done, total }) => assert_eq!((done, total), (4, 9)),
        other => panic!("expected a cancellation, got {other:?}"),
    }
    let kept = sweep::read_records(&records).expect("records");
    assert_eq!(kept.rows.len(), 4);
    let resumed = sweep::run(&s, &opts, None).expect("resume");
    assert_eq!((resumed.resumed, resumed.computed), (4, 5));
    let whole = SweepOptions {
        records: None,
        ..opts
    };
    let fresh = sweep::run(&s, &whole, None).expect("sweep");
    assert_eq!(
        sweep::sweep_csv(&s.spec.axes, &resumed.rows),
        sweep::sweep_csv(&s.spec.axes, &fresh.rows)
    );
}

/// `attractors = true`: a sweep point's V_NL is the full attractor search's, equal to that of
/// `critspeed attractors` on the study at the point's values, and never above the fast form's
/// (continuation and descents), which misses attractors no continued branch leads to. The
/// point is a draw of `studies/dtu-bogie-uncertainty.toml` (evaluation 25 of N = 4) on which
/// the fast form gave 203.67 m/s against the search's 85.95 m/s when measured.
#[test]
fn a_sweep_point_with_attractors_takes_the_searchs_v_nl() {
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/studies");
    let path = format!("{dir}/dtu-cooperrider-bogie.toml");
    let mut text = std::fs::read_to_string(&path).expect("studies/dtu-cooperrider-bogie.toml");
    for (shipped, drawn) in [
        (
            "lateral_stiffness = \"1.823 MN/m\"",
            "lateral_stiffness = 2084839.7464096546",
        ),
        (
            "longitudinal_stiffness = \"3.646 MN/m\"",
            "longitudinal_stiffness = 3187148.364675045",
        ),
        (
            "lateral_stiffness = \"182.3 kN/m\"",
            "lateral_stiffness = 183993.1971603632",
        ),
        (
            "lateral_damping = \"29.2 kN s/m\"",
            "lateral_damping = 33119.708836078644",
        ),
        ("friction = 0.15", "friction = 0.1626127016544342"),
        (
            "yaw_damping = \"166.669 kN s/m\"",
            "yaw_damping = 160528.08887605072",
        ),
    ] {
        assert_eq!(text.matches(shipped).count(), 1, "{shipped}");
        text = text.replace(shipped, drawn);
    }
    let rate = 160528.08887605072;
    let with = |attractors: bool| {
        format!(
            "{text}\n[sweep]\naxes = [ {{ key = \"secondary.yaw_damping\", from = {rate}, to = {rate}, count = 1 }} ]\ncompute = [\"nonlinear\"]\nattractors = {attractors}\n"
        )
    };
    let opts = SweepOptions {
        threads: Some(1),
        shard: Shard::ALL,
        records: None,
    };
    let v_nl = |attractors: bool| {
        let s = SweepStudy::parse_in(
            &with(attractors),
            "draw 25",
            Some(std::path::Path::new(dir)),
        )
        .expect("study");
        assert_eq!(s.spec.attractors, attractors);
        let res = sweep::run(&s, &opts, None).expect("sweep");
        assert_eq!(res.rows.len(), 1);
        res.rows[0].nonlinear_m_s.expect("V_NL")
    };
    let (search, fast) = (v_nl(true), v_nl(false));
    // the study at the point's values: the sweep's one value is the study's own
    let plan = study::parse_in(&text, "draw 25", Some(std::path::Path::new(dir))).expect("plan");
    let prepared = critspeed::api::Prepared::new(plan).expect("model");
    let (_, b) = critspeed::api::attractors(&prepared, Default::default(), None).expect("search");
    let alone = b.nonlinear_critical_speed.expect("V_NL").0;
    assert_eq!(search, alone, "the sweep point's search and `attractors`");
    assert!(
        search <= fast,
        "search {search} m/s above the fast form's {fast} m/s"
    );
}

/// Without an `attractors` key a sweep of a bogie or a car finds V_NL by the full search and a
/// sweep of a wheelset by the fast form; the key overrides either; records of one method do not
/// resume into the other (their fingerprints differ), while a wheelset's fast-form fingerprint
/// is the same with or without the key.
#[test]
fn a_sweeps_vnl_method_defaults_by_vehicle_and_enters_the_fingerprint() {
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/studies");
    let parse = |file: &str, attractors: Option<bool>| {
        let text = std::fs::read_to_string(format!("{dir}/{file}")).expect("study");
        let key = attractors.map_or(String::new(), |a| format!("attractors = {a}\n"));
        let text = format!(
            "{text}\n[sweep]\naxes = [ {{ key = \"contact.friction\", from = 0.1, to = 0.2, count = 2 }} ]\ncompute = [\"nonlinear\"]\n{key}"
        );
        SweepStudy::parse_in(&text, file, Some(std::path::Path::new(dir))).expect(file)
    };
    for (file, search) in [
        ("seed-hunting.toml", false),
        ("dtu-cooperrider-bogie.toml", true),
        ("dtu-cooperrider-car.toml", true),
    ] {
        let default = parse(file, None);
        assert_eq!(default.spec.attractors, search, "{file}");
        let same = parse(file, Some(search));
        let other = parse(file, Some(!search));
        assert_eq!(other.spec.attractors, !search, "{file}");
        assert_eq!(default.fingerprint, same.fingerprint, "{file}");
        assert_ne!(default.fingerprint, other.fingerprint, "{file}");
    }
}
