//! `critspeed uncertainty`: the critical speeds' distribution and Sobol indices over the
//! study's `[uncertainty]` parameters; resumable and sharded like `critspeed sweep`, whose
//! records, shards and progress line it uses.

use std::io::IsTerminal as _;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

use anyhow::anyhow;

use super::commands::{compute, user};
use super::console::{results, status, statusln};
use super::sweep::{progress_line, records_files, shard_of, MergeArgs};
use super::Failure;
use crate::output;
use crate::sweep::{self, PointRecord, Progress, Shard, SweepOptions};
use crate::uncertainty::{self, QuantityReport, UncertaintyError, UncertaintyStudy};

/// `critspeed uncertainty` arguments.
#[derive(Debug, clap::Args)]
pub struct UncertaintyArgs {
    /// Study file (TOML) with an `[uncertainty]` section.
    pub study: PathBuf,
    /// Print uncertainty.json on stdout instead of the table.
    #[arg(long)]
    pub json: bool,
    /// Worker threads (default: all cores).
    #[arg(long)]
    pub threads: Option<usize>,
    /// Compute only every N-th evaluation from I (0 <= I < N), into its own records file.
    #[arg(long, conflicts_with = "shard_from_env")]
    pub shard: Option<String>,
    /// Take the shard from a Slurm job array (as `critspeed sweep --shard-from-env`).
    #[arg(long)]
    pub shard_from_env: bool,
    /// The number of shards N beside --shard-from-env: the array index is the shard index.
    #[arg(long, requires = "shard_from_env")]
    pub shards: Option<usize>,
}

fn failure(e: UncertaintyError) -> Failure {
    crate::api::uncertainty_failure(e)
}

/// Whether the study file at `path` has an `[uncertainty]` table (read leniently: any error
/// says no, and the caller's own parse reports it).
pub(super) fn has_section(path: &Path) -> bool {
    std::fs::read_to_string(path)
        .ok()
        .and_then(|t| toml::from_str::<toml::Table>(&t).ok())
        .is_some_and(|t| t.contains_key("uncertainty"))
}

/// Runs `critspeed uncertainty`.
pub fn run(args: &UncertaintyArgs, root: &Path) -> Result<(), Failure> {
    let study = UncertaintyStudy::load(&args.study).map_err(failure)?;
    super::commands::warn(&study.sweep.base.warnings);
    if args.threads == Some(0) {
        return Err(user(anyhow!("--threads 0: must be at least 1")));
    }
    let dir = super::commands::out_dir(root, &study.sweep.base)?;
    let shard = shard_of(
        (&args.shard, args.shard_from_env, args.shards),
        &dir,
        uncertainty::RECORDS_STEM,
    )?;
    let records = dir.join(shard.records_file_of(uncertainty::RECORDS_STEM));
    let total = study.len();
    let mine = shard.ids(total).len();
    if records.exists() {
        let r = sweep::read_records(&records).map_err(|e| failure(e.into()))?;
        statusln!(
            "resuming: {} of {mine} evaluations already in {}",
            r.rows.len(),
            records.display()
        );
    }
    let spec = &study.spec;
    statusln!(
        "uncertainty of '{}': {} parameters, N = {} ({}, seed {}), {total} evaluations{}, shard {}/{} computes {mine}, fingerprint {}",
        study.sweep.base.name,
        spec.parameters.len(),
        spec.samples,
        spec.method.name(),
        spec.seed,
        if spec.indices { " (N (d + 2), for the indices)" } else { "" },
        shard.index,
        shard.count,
        study.sweep.fingerprint
    );
    let tty = std::io::stderr().is_terminal();
    let last = AtomicU64::new(0);
    let report = |p: &Progress| {
        let ms = p.elapsed.as_millis() as u64;
        let period = if tty { 200 } else { 10_000 };
        if p.done == p.todo || ms >= last.load(Ordering::Relaxed) + period {
            last.store(ms, Ordering::Relaxed);
            let line = progress_line(p).replace(" points ", " evaluations ");
            if tty {
                status!("\r{line}   ");
            } else {
                statusln!("{line}");
            }
        }
    };
    let opts = SweepOptions {
        threads: args.threads,
        shard,
        records: Some(records.clone()),
    };
    let res = crate::api::uncertainty(&study, &opts, Some(&report), None)?;
    if tty && res.computed > 0 {
        statusln!();
    }
    statusln!(
        "{} evaluations finished ({} this run, {} resumed); records in {}",
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
        return Ok(());
    }
    finish(&study, &dir, &res.rows, args.json)
}

/// Writes uncertainty.json, uncertainty.csv and uncertainty.svg, and prints the results.
fn finish(
    study: &UncertaintyStudy,
    dir: &Path,
    rows: &[PointRecord],
    json: bool,
) -> Result<(), Failure> {
    let rep = uncertainty::report(study, rows);
    let out = crate::api::files::uncertainty(study, &rep, rows)?;
    super::commands::write_all(dir, &out)?;
    if json {
        let text = serde_json::to_string_pretty(&rep).map_err(compute)?;
        results(&format!("{text}\n"))
    } else {
        results(&table(&rep))
    }
}

fn speed_name(name: &str) -> &'static str {
    match name {
        "kalker" => "Kalker critical speed V_L",
        "hopf" => "creep-law Hopf speed V_H",
        _ => "nonlinear critical speed V_NL",
    }
}

fn quantity_lines(q: &QuantityReport, op: Option<f64>) -> String {
    let mut s = format!("  {}:", speed_name(&q.name));
    match (q.mean_m_s, q.std_m_s) {
        (Some(m), Some(sd)) => {
            let at = |k: &str| q.quantiles_m_s.get(k).copied().unwrap_or(f64::NAN);
            s += &format!(
                " mean {m:.3} m/s, std {sd:.3} m/s, 5 % {:.3} m/s, median {:.3} m/s, 95 % {:.3} m/s",
                at("0.05"),
                at("0.5"),
                at("0.95")
            );
        }
        _ => s += " no evaluation gave a speed",
    }
    s += &format!("; {} failed, {} above range", q.failed, q.above_range);
    if let (Some(p), Some(v)) = (q.probability_below_operating_speed, op) {
        s += &format!("; P(below {v:.3} m/s = {:.1} km/h) = {p:.4}", v * 3.6);
    }
    s.push('\n');
    if !q.indices.is_empty() {
        let mut ix: Vec<_> = q.indices.iter().collect();
        ix.sort_by(|a, b| b.total.total_cmp(&a.total));
        let w = ix.iter().map(|i| i.key.len()).max().unwrap_or(3).max(3);
        s += &format!(
            "    {:w$}  {:>26}  {:>26}\n",
            "key", "first order [95 %]", "total [95 %]"
        );
        for i in ix {
            s += &format!(
                "    {:w$}  {:>8.3} [{:>6.3}, {:>6.3}]  {:>8.3} [{:>6.3}, {:>6.3}]\n",
                i.key,
                i.first_order,
                i.first_order_ci[0],
                i.first_order_ci[1],
                i.total,
                i.total_ci[0],
                i.total_ci[1]
            );
        }
    }
    s
}

/// The results table: per speed its statistics (m/s) and indices, sorted by total index.
fn table(rep: &uncertainty::UncertaintyReport) -> String {
    let mut s = format!(
        "uncertainty '{}': {} evaluations (N = {}, {}, seed {})\n",
        rep.study, rep.samples, rep.base_samples, rep.method, rep.seed
    );
    for q in &rep.quantities {
        s += &quantity_lines(q, rep.operating_speed_m_s);
        if let (true, Some(search)) = (q.name == "nonlinear", rep.nonlinear_by_search) {
            s += &format!("    V_NL {}\n", crate::sweep::nonlinear_method(search).1);
        }
        for n in &q.notes {
            s += &format!("    note: {n}\n");
        }
    }
    s
}

/// `critspeed merge` of an uncertainty study: joins its records files and writes its results.
pub(super) fn merge(args: &MergeArgs, root: &Path) -> Result<(), Failure> {
    let study = UncertaintyStudy::load(&args.study).map_err(failure)?;
    let dir = output::study_dir(root, &study.sweep.base.name).map_err(compute)?;
    let stem = uncertainty::RECORDS_STEM;
    let files = records_files(&dir, stem, &args.records)?;
    let m = uncertainty::merge(&study, &files).map_err(failure)?;
    let total = study.len();
    if !m.missing.is_empty() {
        let list: Vec<String> = m.missing.iter().take(20).map(usize::to_string).collect();
        statusln!(
            "{} of {total} evaluations missing: {}{}",
            m.missing.len(),
            list.join(", "),
            if m.missing.len() > 20 { ", ..." } else { "" }
        );
        if !args.partial {
            return Err(compute(anyhow!(
                "{} evaluations missing; run the missing shards (or pass --partial: missing evaluations then count as failed)",
                m.missing.len()
            )));
        }
    } else {
        statusln!("all {total} evaluations present in {} files", files.len());
    }
    finish(&study, &dir, &m.rows, false)
}
