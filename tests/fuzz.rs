//! Bad input as a property: every shipped study, mutated (keys and sections deleted, values
//! replaced by NaN, ±inf, negatives, zero, huge and tiny magnitudes, wrong or missing units,
//! wrong types, unknown keys and sections, the wrong table or profile files, other choices),
//! goes through `check`, `linear`, `geometry` and (for one case in four, on a time budget)
//! `bifurcation` in the library, and one case in eight also through the real binary.
//!
//! The property: never a panic, an abort or a hang; every failure is a user error (exit 2)
//! or a computation failure (exit 1); a user error's message names a key the case touched;
//! the binary exits 0, 1 or 2, exactly as the library's outcome says, and names the key too.
//!
//! The run is bounded by time and by cases, whichever ends it first: `FUZZ_SECONDS` (default
//! 25) and `FUZZ_CASES` (default 100000). A long run, `FUZZ_SECONDS=3600 cargo test --release --test fuzz -- --nocapture`,
//! prints its statistics; a failing case is shrunk and its seed kept in
//! `proptest-regressions/fuzz.txt` (replayed first by every run), and becomes a named test in
//! `tests/bad_input.rs`.

#[path = "fuzz/mutate.rs"]
mod mutate;
#[path = "fuzz/run.rs"]
mod run;

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::{Duration, Instant};

use proptest::prelude::*;
use proptest::test_runner::{Config, FileFailurePersistence, TestCaseError, TestError, TestRunner};

use mutate::{apply, names_a_key, op, Op};
use run::{binary, in_process, End, Outcome};

/// A case: a shipped study, its mutations, and which extra runs it gets.
#[derive(Clone, Debug)]
struct Case {
    study: usize,
    ops: Vec<Op>,
    bifurcation: bool,
    binary: bool,
}

fn case() -> impl Strategy<Value = Case> {
    (
        any::<usize>(),
        prop::collection::vec(op(), 1..=3),
        prop::bool::weighted(0.25),
        prop::bool::weighted(0.125),
    )
        .prop_map(|(study, ops, bifurcation, binary)| Case {
            study,
            ops,
            bifurcation,
            binary,
        })
}

fn studies_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("studies")
}

/// The shipped studies, as TOML tables, sorted by name.
fn corpus() -> Vec<(String, toml::Table)> {
    let mut v: Vec<(String, toml::Table)> = std::fs::read_dir(studies_dir())
        .expect("studies/")
        .filter_map(|e| {
            let p = e.ok()?.path();
            (p.extension()? == "toml").then_some(())?;
            let text = std::fs::read_to_string(&p).ok()?;
            let t: toml::Table = toml::from_str(&text).ok()?;
            Some((p.file_name()?.to_string_lossy().into_owned(), t))
        })
        .collect();
    v.sort_by(|a, b| a.0.cmp(&b.0));
    v
}

/// The budget of a case before its mutations (which may undo it: the bifurcation's time
/// limit then bounds it): fewer spectrum speeds, and a short branch.
fn budget(t: &mut toml::Table, bifurcation: bool) {
    let mut set = |section: &str, key: &str, v: i64| {
        let s = t
            .entry(section)
            .or_insert_with(|| toml::Value::Table(toml::Table::new()));
        if let Some(s) = s.as_table_mut() {
            s.insert(key.into(), toml::Value::Integer(v));
        }
    };
    set("linear", "spectrum_points", 24);
    if bifurcation {
        set("bifurcation", "max_points", 6);
    }
}

/// How many cases ended how, per command, for the closing statistics.
#[derive(Default)]
struct Tally {
    cases: AtomicUsize,
    ends: [[AtomicUsize; 3]; 4],
    binary_runs: AtomicUsize,
}

impl Tally {
    fn add(&self, o: &Outcome) {
        self.cases.fetch_add(1, Ordering::Relaxed);
        for (i, e) in [&o.check, &o.linear, &o.geometry, &o.bifurcation]
            .iter()
            .enumerate()
        {
            if let Some(e) = e {
                self.ends[i][e.code() as usize].fetch_add(1, Ordering::Relaxed);
            }
        }
    }

    fn report(&self, seconds: f64) -> String {
        let n = |i: usize, c: usize| self.ends[i][c].load(Ordering::Relaxed);
        let mut s = format!(
            "fuzz: {} cases in {seconds:.0} s ({} through the binary); exit 0 / 1 / 2:",
            self.cases.load(Ordering::Relaxed),
            self.binary_runs.load(Ordering::Relaxed)
        );
        for (i, name) in ["check", "linear", "geometry", "bifurcation"]
            .iter()
            .enumerate()
        {
            s += &format!(" {name} {} / {} / {};", n(i, 0), n(i, 1), n(i, 2));
        }
        s
    }
}

const HANG: Duration = Duration::from_secs(120);

fn check_case(
    c: &Case,
    corpus: &[(String, toml::Table)],
    studies: &Path,
    tally: &Tally,
) -> Result<(), TestCaseError> {
    let (name, base) = &corpus[c.study % corpus.len()];
    let mut t = base.clone();
    budget(&mut t, c.bifurcation);
    let touched: Vec<String> = c.ops.iter().filter_map(|o| apply(&mut t, o)).collect();
    let Ok(text) = toml::to_string(&t) else {
        return Ok(()); // not a TOML document any more (e.g. an array of mixed tables)
    };
    let show = || format!("study {name}, touched {touched:?}:\n{text}");
    let budget = c.bifurcation.then_some(Duration::from_secs(3));
    let o = in_process(&text, &studies_dir(), budget, HANG)
        .map_err(|e| TestCaseError::fail(format!("{e}\n{}", show())))?;
    tally.add(&o);
    if std::env::var_os("FUZZ_LOG").is_some() {
        for e in [&o.check, &o.linear, &o.geometry, &o.bifurcation]
            .into_iter()
            .flatten()
        {
            if let End::Compute(m) = e {
                eprintln!("exit 1, {name}, touched {touched:?}: {m}");
            }
        }
    }
    for e in [&o.check, &o.linear, &o.geometry, &o.bifurcation]
        .into_iter()
        .flatten()
    {
        if let End::User(m) = e {
            prop_assert!(
                names_a_key(m, &touched),
                "exit-2 message names no touched key: {m}\n{}",
                show()
            );
        }
    }
    if c.binary {
        tally.binary_runs.fetch_add(1, Ordering::Relaxed);
        for (cmd, end) in [("check", &o.check), ("linear", &o.linear)] {
            let (code, err) = binary(cmd, &text, studies, HANG)
                .map_err(|e| TestCaseError::fail(format!("{e}\n{}", show())))?;
            let want = end.as_ref().map_or(0, End::code);
            prop_assert_eq!(code, want, "critspeed {}: {}\n{}", cmd, err, show());
            if code == 2 {
                prop_assert!(names_a_key(&err, &touched), "{}\n{}", err, show());
            }
        }
    }
    Ok(())
}

fn env(name: &str, default: u64) -> u64 {
    std::env::var(name)
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(default)
}

#[test]
fn mutated_studies_never_panic_hang_or_misreport() {
    let seconds = env("FUZZ_SECONDS", 25);
    let cases = env("FUZZ_CASES", 100_000) as u32;
    let corpus = corpus();
    assert!(corpus.len() >= 14, "{} studies", corpus.len());
    let studies = run::scratch_studies("property");
    let tally = Tally::default();
    let mut runner = TestRunner::new(Config {
        cases,
        max_shrink_iters: 500,
        max_global_rejects: 1,
        failure_persistence: Some(Box::new(FileFailurePersistence::Direct(
            "proptest-regressions/fuzz.txt",
        ))),
        source_file: Some(file!()),
        ..Config::default()
    });
    let start = Instant::now();
    let limit = Duration::from_secs(seconds);
    // when the time is spent, the next case is rejected, which ends the run (one reject allowed)
    let result = runner.run(&case(), |c| {
        if start.elapsed() > limit {
            return Err(TestCaseError::reject("the time budget is spent"));
        }
        check_case(&c, &corpus, &studies, &tally)
    });
    let report = tally.report(start.elapsed().as_secs_f64());
    eprintln!("{report}");
    let _ = std::fs::remove_dir_all(studies.parent().unwrap_or(&studies));
    match result {
        Ok(()) => {}
        Err(TestError::Abort(_)) if start.elapsed() > limit => {}
        Err(e) => panic!("{e}\n{report}"),
    }
    assert!(tally.cases.load(Ordering::Relaxed) >= 50, "{report}");
}

/// The mutations reach what they should: every kind of mutation applies to every study.
#[test]
fn every_mutation_applies_to_every_shipped_study() {
    use mutate::Bad;
    let ops = [
        Op::Delete {
            pick: 3,
            section: false,
        },
        Op::Delete {
            pick: 1,
            section: true,
        },
        Op::Set {
            pick: 5,
            bad: Bad::Nan,
        },
        Op::Set {
            pick: 7,
            bad: Bad::WrongUnit(0),
        },
        Op::Unknown {
            pick: 2,
            section: false,
        },
        Op::Unknown {
            pick: 0,
            section: true,
        },
        Op::File { pick: 4, to: 1 },
    ];
    for (name, base) in corpus() {
        for o in &ops {
            let mut t = base.clone();
            let key = apply(&mut t, o).unwrap_or_else(|| panic!("{name}: {o:?} applies"));
            assert_ne!(t, base, "{name}: {o:?} on {key} changed nothing");
        }
    }
    assert!(names_a_key(
        "missing field `mass`",
        &["wheelset.mass".into()]
    ));
    assert!(names_a_key(
        "linear.speed_range[0] = -1 m/s: must be positive",
        &["linear.speed_range[0]".into()]
    ));
    assert!(!names_a_key("something else", &["wheelset.mass".into()]));
}
