//! One fuzz case through the library (in process, panics caught, a watchdog against hangs)
//! and, for a sample, through the real binary.

use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::sync::mpsc;
use std::time::{Duration, Instant};

use critspeed::api::{self, files, Failure, Hooks, Prepared, Source};

/// How a call ended: the exit code the command line gives it, and the message.
#[derive(Clone, Debug, PartialEq)]
pub enum End {
    Ok,
    /// exit 2
    User(String),
    /// exit 1
    Compute(String),
}

impl End {
    fn of<T>(r: &Result<T, Failure>) -> End {
        match r {
            Ok(_) => End::Ok,
            Err(f @ Failure::User(_)) => End::User(f.message()),
            Err(f @ Failure::Compute(_)) => End::Compute(f.message()),
        }
    }

    /// The command line's exit code for this end.
    pub fn code(&self) -> i32 {
        match self {
            End::Ok => 0,
            End::Compute(_) => 1,
            End::User(_) => 2,
        }
    }
}

/// What the library did with a case, command by command (`None`: not reached).
#[derive(Clone, Debug, Default)]
pub struct Outcome {
    /// `api::check`, then the model build (`critspeed check` builds it too)
    pub check: Option<End>,
    /// `critspeed linear`: plan, model, analysis, its files
    pub linear: Option<End>,
    /// `critspeed geometry`
    pub geometry: Option<End>,
    /// `critspeed bifurcation` with a bounded budget
    pub bifurcation: Option<End>,
}

/// The first of a chain of steps that did not end well.
fn first_bad(steps: &[End]) -> End {
    steps
        .iter()
        .find(|e| **e != End::Ok)
        .cloned()
        .unwrap_or(End::Ok)
}

/// Runs the case's commands through the library. `budget`: the bifurcation's time limit
/// (`None`: not run).
fn library(src: &Source, budget: Option<Duration>) -> Outcome {
    let mut o = Outcome::default();
    let checked = api::check(src);
    let check = End::of(&checked);
    let plan = src.plan();
    let plan_end = End::of(&plan);
    let prepared = plan.ok().map(Prepared::new);
    let model_end = prepared.as_ref().map_or(End::Ok, End::of);
    o.check = Some(first_bad(&[check, model_end.clone()]));
    let Some(Ok(p)) = prepared else {
        o.linear = Some(first_bad(&[plan_end.clone(), model_end.clone()]));
        o.geometry = o.linear.clone();
        return o;
    };
    let linear = api::linear(&p);
    let linear_files = linear.as_ref().map(files::linear);
    o.linear = Some(first_bad(&[
        End::of(&linear),
        linear_files.map_or(End::Ok, |f| End::of(&f)),
    ]));
    let g = api::geometry(&p);
    let _ = files::geometry(&g);
    o.geometry = Some(End::Ok);
    if let Some(limit) = budget {
        let start = Instant::now();
        let cancel = move || start.elapsed() > limit;
        let hooks = Hooks {
            progress: None,
            cancel: Some(&cancel),
            branches: None,
        };
        let r = api::bifurcation(&p, hooks);
        let f = r.as_ref().map(files::bifurcation);
        o.bifurcation = Some(first_bad(&[
            End::of(&r),
            f.map_or(End::Ok, |f| End::of(&f)),
        ]));
    }
    o
}

/// The case through the library on a worker thread: `Err` with the panic's message, or
/// "hang" when it takes longer than `hang`.
pub fn in_process(
    text: &str,
    folder: &Path,
    budget: Option<Duration>,
    hang: Duration,
) -> Result<Outcome, String> {
    let src = Source {
        text: text.to_string(),
        origin: "fuzz.toml".into(),
        folder: Some(folder.to_path_buf()),
    };
    let (tx, rx) = mpsc::channel();
    std::thread::spawn(move || {
        let r = catch_unwind(AssertUnwindSafe(|| library(&src, budget)));
        let _ = tx.send(r.map_err(|e| {
            e.downcast_ref::<String>()
                .cloned()
                .or_else(|| e.downcast_ref::<&str>().map(|s| s.to_string()))
                .unwrap_or_else(|| "a panic without a message".into())
        }));
    });
    match rx.recv_timeout(hang) {
        Ok(r) => r.map_err(|m| format!("panicked: {m}")),
        Err(_) => Err(format!("hang: no end after {} s", hang.as_secs())),
    }
}

/// A scratch copy of the studies' folder (tables, profiles, the seed) where mutated studies
/// are written for the binary, so that their relative paths resolve as in `studies/`.
pub fn scratch_studies(name: &str) -> PathBuf {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let dir = std::env::temp_dir().join(format!("critspeed-fuzz-{name}-{}", std::process::id()));
    let studies = dir.join("studies");
    let _ = std::fs::remove_dir_all(&dir);
    for sub in ["tables", "profiles"] {
        std::fs::create_dir_all(studies.join(sub)).expect("scratch dir");
        for e in std::fs::read_dir(root.join("studies").join(sub)).expect("studies") {
            let p = e.expect("entry").path();
            let to = studies.join(sub).join(p.file_name().expect("name"));
            std::fs::copy(&p, to).expect("copy");
        }
    }
    std::fs::copy(root.join("studies/seed.toml"), studies.join("seed.toml")).expect("copy");
    studies
}

/// `critspeed <cmd> <study>` on the text written into `studies`: the exit code (`Err` for a
/// signal, a hang or a panic message) and stderr.
pub fn binary(
    cmd: &str,
    text: &str,
    studies: &Path,
    hang: Duration,
) -> Result<(i32, String), String> {
    let study = studies.join("fuzz.toml");
    std::fs::write(&study, text).map_err(|e| e.to_string())?;
    let mut child = Command::new(env!("CARGO_BIN_EXE_critspeed"))
        .args(["--out", "out", cmd])
        .arg(&study)
        .current_dir(studies)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .map_err(|e| e.to_string())?;
    // stderr is read while the program runs, so that a long message cannot block it
    let reader = child.stderr.take().map(|mut e| {
        std::thread::spawn(move || {
            let mut s = String::new();
            let _ = std::io::Read::read_to_string(&mut e, &mut s);
            s
        })
    });
    let start = Instant::now();
    let status = loop {
        match child.try_wait().map_err(|e| e.to_string())? {
            Some(s) => break s,
            None if start.elapsed() > hang => {
                let _ = child.kill();
                let _ = child.wait();
                return Err(format!(
                    "critspeed {cmd}: hang, killed after {} s",
                    hang.as_secs()
                ));
            }
            None => std::thread::sleep(Duration::from_millis(5)),
        }
    };
    let err = reader.and_then(|r| r.join().ok()).unwrap_or_default();
    match status.code() {
        Some(c) if !err.contains("panicked") => Ok((c, err)),
        Some(_) => Err(format!("critspeed {cmd} panicked: {err}")),
        None => Err(format!(
            "critspeed {cmd} ended by a signal ({status}): {err}"
        )),
    }
}
