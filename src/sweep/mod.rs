//! Parameter sweeps: the critical speeds over a grid of one or two study keys (`[sweep]`).
//!
//! Each point is the study with the axis keys set (through the same validation as a study
//! file), analysed independently: results do not depend on the thread count or the order.
//! Finished points are appended to a records file and flushed at once, so an interrupted
//! sweep resumes where it stopped; shards (`I/N`: every N-th point from I) write their own
//! records files, which [`merge`] joins. Every records file carries the study fingerprint.

pub mod point;
pub mod records;
pub mod shard;
pub mod spec;
pub mod study;

use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Mutex;
use std::time::{Duration, Instant};

use rayon::prelude::*;

pub use point::{Computed, Outcome, PointRecord};
pub use records::{read_csv, read_records, sweep_csv, SweepCsv};
pub use shard::Shard;
pub use spec::{nonlinear_method, Axis, Compute, Spacing, SweepSpec, SWEEP_KEYS};
pub use study::{Spares, SweepStudy};

/// Why a sweep could not run (failed points are not errors: they are recorded).
#[derive(Debug, thiserror::Error)]
pub enum SweepError {
    #[error(transparent)]
    Study(#[from] crate::study::StudyError),
    #[error("study {path} has no [sweep] section")]
    NoSweep { path: String },
    #[error("{axis}: key {key:?} cannot be swept; the numeric keys are: {accepted}")]
    Key {
        axis: String,
        key: String,
        accepted: String,
    },
    #[error("{axis}: {rule}")]
    Axis { axis: String, rule: String },
    #[error("building the contact geometry of the study: {0}")]
    Model(String),
    #[error("{text:?}: {rule}")]
    Shard { text: String, rule: String },
    #[error("{path}: {source}")]
    Io {
        path: String,
        source: std::io::Error,
    },
    #[error("{path} line {line}: {problem}")]
    Records {
        path: String,
        line: usize,
        problem: String,
    },
    #[error("{path} was written for another study definition (fingerprint {found}, this study {expected}, {points} points); delete it or use the study it came from")]
    Fingerprint {
        path: String,
        found: String,
        expected: String,
        points: usize,
    },
    #[error("{path} is a records file of an older critspeed (no stable_up_to_m_s column): there a point with no onset in the speed range was a failure, now it is 'above range'; move it away and run the sweep again (an old sweep.csv is still read)")]
    OldRecords { path: String },
    #[error("point {id} appears in {first} and {second} with different results")]
    Conflict {
        id: usize,
        first: String,
        second: String,
    },
    #[error("building the thread pool: {0}")]
    Threads(String),
    #[error("cancelled with {done} of {total} points finished (the records file keeps them)")]
    Cancelled { done: usize, total: usize },
}

impl SweepError {
    /// Whether the user can fix it in the input (study, arguments, foreign files): exit 2.
    pub fn is_user_error(&self) -> bool {
        !matches!(
            self,
            SweepError::Io { .. }
                | SweepError::Model(_)
                | SweepError::Threads(_)
                | SweepError::Cancelled { .. }
        )
    }
}

/// How to run a sweep.
#[derive(Clone, Debug)]
pub struct SweepOptions {
    /// worker threads; `None` = rayon's default (all cores)
    pub threads: Option<usize>,
    /// part of the grid to compute
    pub shard: Shard,
    /// records file to resume from and append to; `None` = in memory only
    pub records: Option<PathBuf>,
}

/// Progress of a running sweep, reported after each point.
#[derive(Clone, Copy, Debug)]
pub struct Progress {
    /// points finished in this run
    pub done: usize,
    /// of which failed
    pub failed: usize,
    /// of which had some result above the speed range (stable up to v_max) and none failed
    pub above_range: usize,
    /// points this run computes
    pub todo: usize,
    /// points found finished in the records file at the start
    pub resumed: usize,
    /// time since the start of the run
    pub elapsed: Duration,
}

/// What a sweep run produced.
#[derive(Clone, Debug)]
pub struct SweepResults {
    /// every finished point of the shard (resumed and new), sorted by id
    pub rows: Vec<PointRecord>,
    /// points taken from the records file
    pub resumed: usize,
    /// points computed by this run
    pub computed: usize,
    /// grid size
    pub total: usize,
}

/// Opens the records file for appending, returning the points already in it.
fn open_records(
    study: &SweepStudy,
    shard: Shard,
    path: &Path,
) -> Result<(std::fs::File, Vec<PointRecord>), SweepError> {
    let io = |source| SweepError::Io {
        path: path.display().to_string(),
        source,
    };
    if !path.exists() {
        let mut f = std::fs::File::create(path).map_err(io)?;
        let pre = records::preamble(
            &study.spec.axes,
            study.len(),
            &study.fingerprint,
            (shard.index, shard.count),
        );
        f.write_all(pre.as_bytes())
            .and_then(|_| f.flush())
            .map_err(io)?;
        return Ok((f, Vec::new()));
    }
    let r = read_records(path)?;
    check_fingerprint(study, path, &r)?;
    let f = std::fs::OpenOptions::new()
        .write(true)
        .open(path)
        .map_err(io)?;
    // drop a partial last line left by an interrupted write
    f.set_len(r.complete_len as u64).map_err(io)?;
    let mut f = f;
    std::io::Seek::seek(&mut f, std::io::SeekFrom::End(0)).map_err(io)?;
    Ok((f, r.rows))
}

fn check_fingerprint(
    study: &SweepStudy,
    path: &Path,
    r: &records::RecordsFile,
) -> Result<(), SweepError> {
    if r.fingerprint != study.fingerprint || r.points != study.len() {
        return Err(SweepError::Fingerprint {
            path: path.display().to_string(),
            found: r.fingerprint.clone(),
            expected: study.fingerprint.clone(),
            points: r.points,
        });
    }
    Ok(())
}

/// Runs (or resumes) the sweep of `study`: computes the shard's points not yet in the records
/// file, in parallel, appending each as it finishes. `progress` is called after each point.
pub fn run(
    study: &SweepStudy,
    opts: &SweepOptions,
    progress: Option<&(dyn Fn(&Progress) + Sync)>,
) -> Result<SweepResults, SweepError> {
    run_cancellable(study, opts, progress, None)
}

/// [`run`] with a cancellation hook, asked before each point: once it returns `true` no
/// further point starts, the points already finished stay in the records file (a later run
/// resumes from them) and the run returns [`SweepError::Cancelled`].
pub fn run_cancellable(
    study: &SweepStudy,
    opts: &SweepOptions,
    progress: Option<&(dyn Fn(&Progress) + Sync)>,
    cancel: Option<&(dyn Fn() -> bool + Sync)>,
) -> Result<SweepResults, SweepError> {
    let (file, mut have, todo) = resume(study, opts)?;
    let resumed = have.len();
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(opts.threads.unwrap_or(0))
        .build()
        .map_err(|e| SweepError::Threads(e.to_string()))?;
    let started = Instant::now();
    let sink = Mutex::new(Sink {
        file,
        rows: Vec::with_capacity(todo.len()),
        failed: 0,
        above_range: 0,
        err: None,
    });
    let spares = Spares::default();
    let cancelled = AtomicBool::new(false);
    pool.install(|| {
        todo.par_iter().for_each(|&id| {
            if cancelled.load(Ordering::Relaxed) || cancel.is_some_and(|c| c()) {
                cancelled.store(true, Ordering::Relaxed);
                return;
            }
            let rec = point::compute(study, id, &spares);
            let mut g = sink.lock().unwrap_or_else(|e| e.into_inner());
            g.add(rec);
            if let Some(p) = progress {
                p(&Progress {
                    done: g.rows.len(),
                    failed: g.failed,
                    above_range: g.above_range,
                    todo: todo.len(),
                    resumed,
                    elapsed: started.elapsed(),
                });
            }
        })
    });
    let sink = sink.into_inner().unwrap_or_else(|e| e.into_inner());
    if let (Some(e), Some(p)) = (sink.err, &opts.records) {
        return Err(SweepError::Io {
            path: p.display().to_string(),
            source: e,
        });
    }
    let computed = sink.rows.len();
    if cancelled.into_inner() {
        return Err(SweepError::Cancelled {
            done: have.len() + computed,
            total: study.len(),
        });
    }
    have.extend(sink.rows);
    have.sort_by_key(|r| r.id);
    Ok(SweepResults {
        rows: have,
        resumed,
        computed,
        total: study.len(),
    })
}

/// The records file opened for appending, the shard's finished points (sorted by id) and
/// the ids still to compute.
type Resume = (
    Option<std::io::BufWriter<std::fs::File>>,
    Vec<PointRecord>,
    Vec<usize>,
);

fn resume(study: &SweepStudy, opts: &SweepOptions) -> Result<Resume, SweepError> {
    let total = study.len();
    let (file, mut have) = match &opts.records {
        Some(p) => {
            let (f, rows) = open_records(study, opts.shard, p)?;
            (Some(std::io::BufWriter::new(f)), rows)
        }
        None => (None, Vec::new()),
    };
    have.retain(|r| r.id < total && r.id % opts.shard.count == opts.shard.index);
    have.sort_by_key(|r| r.id);
    have.dedup_by_key(|r| r.id);
    let done: std::collections::HashSet<usize> = have.iter().map(|r| r.id).collect();
    let todo = opts
        .shard
        .ids(total)
        .into_iter()
        .filter(|i| !done.contains(i))
        .collect();
    Ok((file, have, todo))
}

/// Where finished points go: appended to the records file (flushed) and kept.
struct Sink {
    file: Option<std::io::BufWriter<std::fs::File>>,
    rows: Vec<PointRecord>,
    failed: usize,
    above_range: usize,
    /// the first write error; later points are no longer written
    err: Option<std::io::Error>,
}

impl Sink {
    fn add(&mut self, rec: PointRecord) {
        if let (Some(f), None) = (self.file.as_mut(), self.err.as_ref()) {
            let line = records::row(&rec) + "\n";
            if let Err(e) = f.write_all(line.as_bytes()).and_then(|_| f.flush()) {
                self.err = Some(e);
            }
        }
        self.failed += usize::from(!rec.ok());
        self.above_range += usize::from(rec.ok() && rec.has_above_range());
        self.rows.push(rec);
    }
}

/// The result of merging records files.
#[derive(Clone, Debug)]
pub struct Merged {
    /// every point found, sorted by id
    pub rows: Vec<PointRecord>,
    /// ids of the grid found in no file
    pub missing: Vec<usize>,
}

/// Joins records files (shards, or a partial run) of `study`; refuses files of another study.
pub fn merge(study: &SweepStudy, files: &[PathBuf]) -> Result<Merged, SweepError> {
    let total = study.len();
    let mut by_id: Vec<Option<(PointRecord, usize)>> = vec![None; total];
    for (k, path) in files.iter().enumerate() {
        let r = read_records(path)?;
        check_fingerprint(study, path, &r)?;
        for rec in r.rows {
            let Some(slot) = by_id.get_mut(rec.id) else {
                return Err(SweepError::Records {
                    path: path.display().to_string(),
                    line: 0,
                    problem: format!("point_id {} is outside the grid of {total} points", rec.id),
                });
            };
            match slot {
                Some((old, from)) if records::row(old) != records::row(&rec) => {
                    return Err(SweepError::Conflict {
                        id: rec.id,
                        first: files[*from].display().to_string(),
                        second: path.display().to_string(),
                    })
                }
                Some(_) => {}
                None => *slot = Some((rec, k)),
            }
        }
    }
    let missing = (0..total).filter(|&i| by_id[i].is_none()).collect();
    let rows = by_id.into_iter().flatten().map(|(r, _)| r).collect();
    Ok(Merged { rows, missing })
}
