//! `critspeed sweep` and `critspeed merge`: parameter grids, resumable, sharded.

use std::io::IsTerminal as _;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

use anyhow::anyhow;

use super::commands::{compute, user};
use super::console::{results, status, statusln};
use super::Failure;
use crate::output;
use crate::sweep::{
    self, Computed, Outcome, PointRecord, Progress, Shard, SweepError, SweepOptions, SweepStudy,
};

/// `critspeed sweep` arguments.
#[derive(Debug, clap::Args)]
pub struct SweepArgs {
    /// Study file (TOML) with a `[sweep]` section.
    pub study: PathBuf,
    /// Worker threads (default: all cores).
    #[arg(long)]
    pub threads: Option<usize>,
    /// Compute only every N-th point from I (0 <= I < N), into its own records file.
    #[arg(long, conflicts_with = "shard_from_env")]
    pub shard: Option<String>,
    /// Take the shard from a Slurm job array. With --shards N: I = SLURM_ARRAY_TASK_ID (submit
    /// --array=0-(N-1); a resubmitted index keeps its shard). Without: I = (SLURM_ARRAY_TASK_ID
    /// - SLURM_ARRAY_TASK_MIN) / SLURM_ARRAY_TASK_STEP, N = SLURM_ARRAY_TASK_COUNT.
    #[arg(long)]
    pub shard_from_env: bool,
    /// The number of shards N of the whole sweep, beside --shard-from-env: the shard count then
    /// does not depend on how many tasks a submission holds.
    #[arg(long, requires = "shard_from_env")]
    pub shards: Option<usize>,
}

/// `critspeed merge` arguments.
#[derive(Debug, clap::Args)]
pub struct MergeArgs {
    /// Study file (TOML) the shards were computed from.
    pub study: PathBuf,
    /// Records files to join (default: every `sweep*.records.csv` in OUT/<study name>/).
    #[arg(long, num_args = 1..)]
    pub records: Vec<PathBuf>,
    /// Write sweep.csv even when points are missing (they are listed on stderr).
    #[arg(long)]
    pub partial: bool,
}

fn failure(e: SweepError) -> Failure {
    crate::api::sweep_failure(e)
}

pub(super) fn clock(d: f64) -> String {
    let s = d.max(0.0).round() as u64;
    format!("{}:{:02}:{:02}", s / 3600, s / 60 % 60, s % 60)
}

/// One progress line: points done, failures, elapsed, estimated remaining.
pub(super) fn progress_line(p: &Progress) -> String {
    let el = p.elapsed.as_secs_f64();
    let left = if p.done > 0 {
        el / p.done as f64 * (p.todo - p.done) as f64
    } else {
        f64::NAN
    };
    format!(
        "  {}/{} points ({} failed, {} above range), elapsed {}, remaining {}",
        p.done,
        p.todo,
        p.failed,
        p.above_range,
        clock(el),
        if left.is_finite() {
            clock(left)
        } else {
            "?".into()
        }
    )
}

/// Runs `critspeed sweep`.
pub fn run(args: &SweepArgs, root: &Path) -> Result<(), Failure> {
    if let Some((study, rows)) = compute_points(args, root)? {
        results(&summary(&study, &rows))?;
    }
    Ok(())
}

/// Runs (or resumes) the sweep; for the whole grid also writes sweep.csv and the figures and
/// returns the rows (`None` for a shard, whose records wait for `critspeed merge`).
pub(super) fn compute_points(
    args: &SweepArgs,
    root: &Path,
) -> Result<Option<(SweepStudy, Vec<PointRecord>)>, Failure> {
    let study = SweepStudy::load(&args.study).map_err(failure)?;
    super::commands::warn(&crate::api::sweep_warnings(&study));
    if args.threads == Some(0) {
        return Err(user(anyhow!("--threads 0: must be at least 1")));
    }
    let dir = super::commands::out_dir(root, &study.base)?;
    let shard = shard_of(
        (&args.shard, args.shard_from_env, args.shards),
        &dir,
        "sweep",
    )?;
    let records = dir.join(shard.records_file());
    let total = study.spec.len();
    let mine = shard.ids(total).len();
    if records.exists() {
        let r = sweep::read_records(&records).map_err(failure)?;
        if r.fingerprint != study.fingerprint {
            return Err(failure(SweepError::Fingerprint {
                path: records.display().to_string(),
                found: r.fingerprint,
                expected: study.fingerprint.clone(),
                points: r.points,
            }));
        }
        statusln!(
            "resuming: {} of {mine} points already in {}",
            r.rows.len(),
            records.display()
        );
    }
    statusln!(
        "sweep of '{}': {total} points, shard {}/{} computes {mine}, fingerprint {}",
        study.base.name,
        shard.index,
        shard.count,
        study.fingerprint
    );
    let tty = std::io::stderr().is_terminal();
    let last = AtomicU64::new(0);
    let report = |p: &Progress| {
        let ms = p.elapsed.as_millis() as u64;
        let period = if tty { 200 } else { 10_000 };
        let prev = last.load(Ordering::Relaxed);
        if p.done == p.todo || ms >= prev + period {
            last.store(ms, Ordering::Relaxed);
            if tty {
                status!("\r{}   ", progress_line(p));
            } else {
                statusln!("{}", progress_line(p));
            }
        }
    };
    let opts = SweepOptions {
        threads: args.threads,
        shard,
        records: Some(records.clone()),
    };
    let res = crate::api::sweep(&study, &opts, Some(&report), None)?;
    if tty && res.computed > 0 {
        statusln!();
    }
    let failed = res.rows.iter().filter(|r| !r.ok()).count();
    let above = res
        .rows
        .iter()
        .filter(|r| r.ok() && r.has_above_range())
        .count();
    statusln!(
        "{} points finished ({} this run, {} resumed), {failed} failed, {above} above range (no onset up to the top of the speed range); records in {}",
        res.rows.len(),
        res.computed,
        res.resumed,
        records.display()
    );
    if shard != Shard::ALL {
        statusln!(
            "shard {}/{} done; join the shards with `critspeed merge {}`",
            shard.index,
            shard.count,
            args.study.display()
        );
        return Ok(None);
    }
    finish(&study, &dir, &res.rows)?;
    Ok(Some((study, res.rows)))
}

/// The shard of `--shard I/N`, or `--shard-from-env [--shards N]`, or the whole design; `stem`
/// names the records files (`sweep`, `uncertainty`) whose shard counts must agree.
pub(super) fn shard_of(
    (shard, from_env, shards): (&Option<String>, bool, Option<usize>),
    dir: &Path,
    stem: &str,
) -> Result<Shard, Failure> {
    let env = |k: &str| std::env::var(k).ok();
    Ok(match (shard, from_env, shards) {
        (Some(s), _, _) => Shard::parse(s).map_err(failure)?,
        (None, true, Some(n)) => Shard::from_env_with_count(env, n).map_err(failure)?,
        (None, true, None) => {
            let s = Shard::from_env(env).map_err(failure)?;
            check_recorded_count(s, dir, stem)?;
            s
        }
        (None, false, _) => Shard::ALL,
    })
}

/// A shard count taken from the submission (SLURM_ARRAY_TASK_COUNT) must be the one the
/// folder's shard records were written with: a single array index resubmitted alone has
/// COUNT = 1 and would recompute the whole grid as shard 0/1.
fn check_recorded_count(shard: Shard, dir: &Path, stem: &str) -> Result<(), Failure> {
    let names: Vec<String> = std::fs::read_dir(dir)
        .map_err(compute)?
        .filter_map(|e| e.ok()?.file_name().into_string().ok())
        .collect();
    let counts = sweep::shard::recorded_counts_of(stem, names.iter().map(String::as_str));
    match counts.iter().find(|&&n| n != shard.count) {
        None => Ok(()),
        Some(&n) => Err(user(anyhow!(
            "SLURM_ARRAY_TASK_COUNT = {} makes this task shard {}/{}, but {} holds the records \
             of {n} shards ({stem}.shard-I-of-{n}.records.csv): the count comes from the \
             submission, so a resubmitted array index would not resume its shard; pass \
             --shards {n} beside --shard-from-env (the array index is then the shard index, \
             --array=0-{}), or move the old records away",
            shard.count,
            shard.index,
            shard.count,
            dir.display(),
            n - 1
        ))),
    }
}

/// Writes sweep.csv and the figures.
fn finish(study: &SweepStudy, dir: &Path, rows: &[PointRecord]) -> Result<(), Failure> {
    super::commands::write_all(dir, &crate::api::files::sweep(study, rows))
}

/// One result over the points: the range where found, the count above range, the count
/// without a Hopf point in range (V_NL), the rest.
fn result_line(rows: &[PointRecord], which: Computed) -> String {
    let (mut found, mut above, mut no_hopf, mut missing) = (Vec::new(), Vec::new(), 0, 0);
    for r in rows {
        match r.outcome(which) {
            Outcome::Found { speed_m_s, .. } => found.push(speed_m_s),
            Outcome::AboveRange { stable_up_to_m_s } => above.push(stable_up_to_m_s),
            Outcome::NoHopf => no_hopf += 1,
            Outcome::Missing => missing += 1,
        }
    }
    let span = |v: &[f64]| {
        let lo = v.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = v.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        (lo, hi)
    };
    let mut parts = Vec::new();
    if found.is_empty() {
        parts.push("not found at any point".to_string());
    } else {
        let (lo, hi) = span(&found);
        parts.push(format!("{lo:.3} .. {hi:.3} m/s at {} points", found.len()));
    }
    if !above.is_empty() {
        let (lo, _) = span(&above);
        parts.push(format!(
            "above range (no onset up to {lo:.3} m/s) at {} points",
            above.len()
        ));
    }
    if no_hopf > 0 {
        parts.push(format!(
            "not computed at {no_hopf} points: no Hopf point in range (the branch starts there)"
        ));
    }
    if missing > 0 {
        parts.push(format!("failed at {missing} points"));
    }
    parts.join("; ")
}

/// Point counts by status, and each result's range, with units.
fn summary(study: &SweepStudy, rows: &[PointRecord]) -> String {
    let failed = rows.iter().filter(|r| !r.ok()).count();
    let partly = rows
        .iter()
        .filter(|r| r.ok() && (r.has_above_range() || r.no_hopf))
        .count();
    let no_hopf = rows.iter().filter(|r| r.ok() && r.no_hopf).count();
    let mut s = format!(
        "sweep '{}': {} points: {} ok, {partly} above range, {failed} failed",
        study.base.name,
        rows.len(),
        rows.len() - failed - partly
    );
    if no_hopf > 0 {
        s += &format!(" (V_NL not computed at {no_hopf}: no Hopf point in range)");
    }
    s.push('\n');
    let c = study.spec.compute;
    for (on, which, name) in [
        (
            c.kalker,
            Computed::Kalker,
            "Kalker critical speed V_L:     ",
        ),
        (c.hopf, Computed::Hopf, "creep-law Hopf speed V_H:      "),
        (
            c.nonlinear,
            Computed::Nonlinear,
            "nonlinear critical speed V_NL: ",
        ),
    ] {
        if on {
            s += &format!("  {name} {}\n", result_line(rows, which));
            if which == Computed::Nonlinear {
                let how = crate::sweep::nonlinear_method(study.spec.attractors).1;
                s += &format!("    V_NL {how}\n");
            }
        }
    }
    s
}

/// The records files `critspeed merge` joins: `given`, or else every `STEM*.records.csv` in
/// `dir` (sorted); each is named on stderr. None is a user error.
pub(super) fn records_files(
    dir: &Path,
    stem: &str,
    given: &[PathBuf],
) -> Result<Vec<PathBuf>, Failure> {
    let files = if given.is_empty() {
        let mut f: Vec<PathBuf> = std::fs::read_dir(dir)
            .map_err(compute)?
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| {
                p.file_name()
                    .and_then(|n| n.to_str())
                    .is_some_and(|n| n.starts_with(stem) && n.ends_with(".records.csv"))
            })
            .collect();
        f.sort();
        f
    } else {
        given.to_vec()
    };
    if files.is_empty() {
        return Err(user(anyhow!(
            "no records files ({stem}*.records.csv) in {}",
            dir.display()
        )));
    }
    for f in &files {
        statusln!("reading {}", f.display());
    }
    Ok(files)
}

/// Runs `critspeed merge`.
pub fn merge(args: &MergeArgs, root: &Path) -> Result<(), Failure> {
    let study = match SweepStudy::load(&args.study) {
        // a study with [uncertainty] and no [sweep]: its evaluations' records
        Err(SweepError::NoSweep { .. }) if super::uncertainty::has_section(&args.study) => {
            return super::uncertainty::merge(args, root)
        }
        s => s.map_err(failure)?,
    };
    let dir = output::study_dir(root, &study.base.name).map_err(compute)?;
    let files = records_files(&dir, "sweep", &args.records)?;
    let m = sweep::merge(&study, &files).map_err(failure)?;
    let total = study.spec.len();
    if !m.missing.is_empty() {
        let list: Vec<String> = m.missing.iter().take(20).map(usize::to_string).collect();
        statusln!(
            "{} of {total} points missing: {}{}",
            m.missing.len(),
            list.join(", "),
            if m.missing.len() > 20 { ", ..." } else { "" }
        );
        if !args.partial {
            return Err(compute(anyhow!(
                "{} points missing; run the missing shards (or pass --partial)",
                m.missing.len()
            )));
        }
    } else {
        statusln!("all {total} points present in {} files", files.len());
    }
    finish(&study, &dir, &m.rows)?;
    results(&summary(&study, &m.rows))?;
    Ok(())
}
