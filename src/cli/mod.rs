//! The command line: clap definitions, and the commands as functions returning a [`Failure`].
//!
//! Exit codes: 0 success, 2 user error (bad file, bad argument), 1 computation failure.
//!
//! Output goes through the `console` module only: `print!`/`eprint!` panic on a closed stream, and
//! clippy refuses them here.

#![deny(clippy::print_stdout, clippy::print_stderr)]

mod attractors;
mod commands;
mod conicity;
mod console;
mod curve;
mod first_run;
mod ramp;
mod sweep;
mod table;
mod trade;
mod trade_curve;
mod uncertainty;

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Parser, Subcommand};

use console::statusln;

/// critspeed: the speed at which a railway wheelset starts to hunt.
#[derive(Debug, Parser)]
#[command(version, about, long_about = None)]
pub struct Cli {
    /// Folder for results; each study writes to `OUT/<study name>/`.
    #[arg(long, global = true, default_value = "out")]
    pub out: PathBuf,
    #[command(subcommand)]
    pub command: Command,
}

#[derive(Debug, Subcommand)]
pub enum Command {
    /// Everything the study asks for (geometry, linear stability, and the bifurcation
    /// diagram when the study has a `[bifurcation]` section). Without STUDY, the first run:
    /// the embedded seed study and the seed made to hunt (seed-hunting) with its diagram.
    Run {
        /// Study file (TOML); omit for the embedded seed study.
        study: Option<PathBuf>,
    },
    /// Linear (Kalker) critical speeds and the creep law's Hopf speeds, with spectra.
    Linear {
        /// Study file (TOML).
        study: PathBuf,
        /// Print one JSON object on stdout instead of the table.
        #[arg(long)]
        json: bool,
    },
    /// The branch of hunting limit cycles from the Hopf point of the study's creep law:
    /// stability (Floquet multipliers), folds, the nonlinear critical speed, the diagram.
    Bifurcation {
        /// Study file (TOML).
        study: PathBuf,
        /// Print one JSON object on stdout instead of the table.
        #[arg(long)]
        json: bool,
        /// Worker threads (default: all cores); the results are the same on any count.
        #[arg(long)]
        threads: Option<usize>,
    },
    /// Every hunting attractor: simulations from many initial states over a descending
    /// sequence of speeds, each attractor followed down until it dies, with the continuation
    /// (branch switching) beside it; the one V_NL of both (attractors.json, .csv, .svg).
    Attractors {
        /// Study file (TOML).
        study: PathBuf,
        /// Print one JSON object on stdout instead of the table.
        #[arg(long)]
        json: bool,
        /// Worker threads (default: all cores); the results are the same on any count.
        #[arg(long)]
        threads: Option<usize>,
    },
    /// Time simulation at one or more constant speeds from an initial lateral displacement
    /// (the seed's Figs. 10-11): time-history CSV and SVG (y, yaw, phase portrait).
    Simulate {
        /// Study file (TOML).
        study: PathBuf,
        /// Speed(s), comma-separated or repeated, with a unit or in m/s: --speed 10,30,40
        #[arg(long, value_delimiter = ',', required = true)]
        speed: Vec<String>,
        /// Initial lateral displacement y(0) of the first body (default 5 mm; 0 with --from
        /// or --kick).
        #[arg(long)]
        y0: Option<String>,
        /// Start on an attractor the search found: PATH:N, attractor N of an attractors.json
        /// (each speed starts from the state of its path nearest that speed).
        #[arg(long)]
        from: Option<String>,
        /// Add a displacement to the start: BODY.COORD=VALUE, e.g. "wheelset-3.y=6mm" or
        /// "frame-2.psi=2mrad"; repeat for several.
        #[arg(long)]
        kick: Vec<String>,
        /// Simulated time.
        #[arg(long, default_value = "30 s")]
        duration: String,
        /// Output sample interval.
        #[arg(long, default_value = "2 ms")]
        dt: String,
        /// The integrator's relative tolerance, in [1e-12, 1e-4] (absolute: a thousandth of
        /// it); default 1e-9. Looser is faster and less exact (docs/commands.md says how much).
        #[arg(long)]
        rtol: Option<f64>,
    },
    /// The ramp method (simulation): settle on a hunting cycle, decrease the speed slowly,
    /// report where the hunting dies; with the EN 14363 criterion on the same history.
    Ramp(ramp::RampArgs),
    /// EN 15302 equivalent conicity against amplitude, for a study's geometry or a Δr table.
    Conicity(conicity::ConicityArgs),
    /// The contact geometry table (rolling radii, contact angles, roll, Hertz patch, creep
    /// coefficients against lateral displacement) as CSV and SVG.
    Geometry {
        /// Study file (TOML).
        study: PathBuf,
    },
    /// Parameter sweep: the critical speeds over the study's `[sweep]` grid, in parallel,
    /// resumable, optionally one shard: `out/<name>/sweep.csv` and plots.
    Sweep(sweep::SweepArgs),
    /// Critical speeds as curves over the study's `[curve]` key: the Hopf speeds V_L and V_H
    /// continued in (speed, key), with the first Lyapunov coefficient, the folds of cycles and
    /// V_NL (symmetry breaking, period doubling and torus when asked), and the codimension-two
    /// points (curve.csv, curve.json, curve.svg).
    Curve(curve::CurveArgs),
    /// Join the records files of a sharded sweep into sweep.csv, or of a sharded uncertainty
    /// study into its results (refuses other studies' files).
    Merge(sweep::MergeArgs),
    /// Critical speeds under uncertainty: the distribution of the speeds over the study's
    /// `[uncertainty]` parameters and their first-order and total Sobol indices, in parallel,
    /// resumable, optionally one shard (uncertainty.json, uncertainty.csv, uncertainty.svg).
    Uncertainty(uncertainty::UncertaintyArgs),
    /// The study's `[trade]` over its sweep (`out/<name>/sweep.csv`): the feasible set, the best
    /// design and the Pareto front of critical speed against the objective (trade.csv,
    /// trade.svg); with `method = "curve"`, on the curves over the sweep's one key: feasible
    /// intervals and the best design verified by a whole diagram (also trade.json).
    Trade(trade::TradeArgs),
    /// Validate a study and print the resolved plan in SI units.
    Check {
        /// Study file (TOML).
        study: PathBuf,
    },
}

pub use crate::api::Failure;

/// The `--threads` of a command that runs on rayon's pool (the sweeps build their own).
fn threads(c: &Command) -> Option<usize> {
    match c {
        Command::Bifurcation { threads, .. } | Command::Attractors { threads, .. } => *threads,
        Command::Curve(a) => a.threads,
        _ => None,
    }
}

/// A pool of `n` worker threads, or the user error of `--threads 0`.
fn pool(n: usize) -> Result<rayon::ThreadPool, Failure> {
    if n == 0 {
        return Err(Failure::User(anyhow::anyhow!(
            "--threads 0: must be at least 1"
        )));
    }
    rayon::ThreadPoolBuilder::new()
        .num_threads(n)
        .build()
        .map_err(|e| Failure::Compute(anyhow::anyhow!("cannot start {n} threads: {e}")))
}

/// Parses the arguments, runs the command and maps the outcome to an exit code.
pub fn main() -> ExitCode {
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => {
            // clap prints help/version to stdout (exit 0) and usage errors to stderr (exit 2)
            let _ = e.print();
            return if e.use_stderr() {
                ExitCode::from(2)
            } else {
                ExitCode::SUCCESS
            };
        }
    };
    let run = || commands::dispatch(&cli);
    let outcome = match threads(&cli.command) {
        None => run(),
        Some(n) => pool(n).and_then(|p| p.install(run)),
    };
    match outcome {
        Ok(()) => ExitCode::SUCCESS,
        Err(f @ Failure::User(_)) => {
            statusln!("error: {}", f.message());
            ExitCode::from(2)
        }
        Err(f @ Failure::Compute(_)) => {
            statusln!("computation failed: {}", f.message());
            ExitCode::from(1)
        }
    }
}
