//! `critspeed trade STUDY`: the study's `[trade]` over `out/<name>/sweep.csv`.

use std::path::{Path, PathBuf};

use anyhow::{anyhow, Context};

use super::commands::{load, out_dir, user, write};
use super::console::results;
use super::Failure;
use crate::study::schema::StudyFile;
use crate::trade::{self, report};

/// Arguments of `critspeed trade`.
#[derive(Debug, clap::Args)]
pub struct TradeArgs {
    /// Study file (TOML) with a `[trade]` section (and the `[sweep]` that produced sweep.csv).
    pub study: PathBuf,
    /// Print one JSON object on stdout instead of the summary.
    #[arg(long)]
    pub json: bool,
    /// Use the existing `OUT/<name>/sweep.csv` (e.g. written by `critspeed merge` from shards)
    /// instead of running or resuming the sweep first.
    #[arg(long)]
    pub from_csv: bool,
    /// Worker threads of the sweep (default: all cores).
    #[arg(long)]
    pub threads: Option<usize>,
}

/// The `[trade]` table of the study file, validated, with the file.
fn trade_plan(path: &Path) -> Result<(trade::TradePlan, StudyFile), Failure> {
    let (_, file) = study_file(path)?;
    let table = file.trade.clone().ok_or_else(|| {
        user(anyhow!(
            "study {} has no [trade] section (see docs/sweeps.md, \"Trade studies\")",
            path.display()
        ))
    })?;
    Ok((trade::trade_plan(&table).map_err(user)?, file))
}

/// Runs the trade: reads the sweep's CSV, writes trade.csv and trade.svg, prints the summary.
pub fn run(a: &TradeArgs, root: &Path) -> Result<(), Failure> {
    let plan = load(&a.study)?;
    let (tp, file) = trade_plan(&a.study)?;
    if tp.method == trade::Method::Curve {
        return super::trade_curve::run(a, root, &plan, &file, &tp);
    }
    if !a.from_csv {
        // Runs the sweep, or resumes it: points already in its records file are not recomputed.
        let args = super::sweep::SweepArgs {
            study: a.study.clone(),
            threads: a.threads,
            shard: None,
            shard_from_env: false,
            shards: None,
        };
        super::sweep::compute_points(&args, root)?;
    }
    let sweep = root.join(&plan.name).join("sweep.csv");
    let text = std::fs::read_to_string(&sweep).map_err(|e| {
        user(anyhow!(
            "{}: {e}; run `critspeed sweep {}` (or `critspeed merge` for shards) first, or drop --from-csv",
            sweep.display(),
            a.study.display()
        ))
    })?;
    let table = trade::read_sweep(&text, &sweep.display().to_string()).map_err(user)?;
    let rows = table.rows(&tp).map_err(user)?;
    let verdicts = trade::assess(&tp, &rows);
    let dir = out_dir(root, &plan)?;
    write(
        &dir,
        "trade.csv",
        trade::trade_csv(&table, &verdicts).as_bytes(),
    )?;
    let svg = crate::figures::Rendered {
        file: "trade.svg".into(),
        size: (900, 580),
        svg: crate::plot::trade_svg(&report::plot(&plan.name, &tp, &rows, &verdicts)),
    };
    super::commands::write_figure(&dir, svg, "trade.csv")?;
    if a.json {
        let j = report::json(&plan.name, &tp, &rows, &verdicts);
        let s = serde_json::to_string_pretty(&j).map_err(super::commands::compute)?;
        results(&format!("{s}\n"))?;
    } else {
        results(&report::summary(&plan.name, &tp, &rows, &verdicts))?;
    }
    Ok(())
}

/// The study file's text and its schema (the raw `[sweep]` and `[trade]` tables with it).
fn study_file(path: &Path) -> Result<(String, StudyFile), Failure> {
    let text = std::fs::read_to_string(path)
        .with_context(|| format!("reading {}", path.display()))
        .map_err(user)?;
    let file: StudyFile = toml::from_str(&text)
        .with_context(|| format!("study file {} is not valid", path.display()))
        .map_err(user)?;
    Ok((text, file))
}
