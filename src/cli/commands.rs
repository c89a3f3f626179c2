//! The commands: load, compute, write, print.

use std::path::{Path, PathBuf};

use anyhow::{anyhow, Context};

use super::console::{results, status, statusln};
use super::{table, Cli, Command, Failure};
use crate::analysis::{self, GeometryReport, LinearReport};
use crate::bifurcation::BifurcationReport;
use crate::figures;
use crate::model::Vehicle;
use crate::output;
use crate::study::units::{parse_quantity, Dimension};
use crate::study::{self, Plan};

pub(super) fn user<E: Into<anyhow::Error>>(e: E) -> Failure {
    Failure::User(e.into())
}

pub(super) fn compute<E: Into<anyhow::Error>>(e: E) -> Failure {
    Failure::Compute(e.into())
}

/// Runs the parsed command.
pub fn dispatch(cli: &Cli) -> Result<(), Failure> {
    match &cli.command {
        Command::Run { study } => run(&cli.out, study.as_deref()),
        Command::Linear { study, json } => {
            let plan = load(study)?;
            let model = build(&plan)?;
            let report = linear(&plan, &model, &cli.out)?;
            if *json {
                let text =
                    serde_json::to_string_pretty(&output::linear_json(&report)).map_err(compute)?;
                results(&format!("{text}\n"))?;
            } else {
                results(&table::linear(&plan, &report))?;
            }
            Ok(())
        }
        Command::Bifurcation { study, json } => {
            let plan = load(study)?;
            let model = build(&plan)?;
            let report = bifurcation(&plan, &model, &cli.out)?;
            if *json {
                let text = serde_json::to_string_pretty(&output::bifurcation_json(&report))
                    .map_err(compute)?;
                results(&format!("{text}\n"))?;
            } else {
                results(&table::bifurcation(&report))?;
            }
            Ok(())
        }
        Command::Simulate {
            study,
            speed,
            y0,
            duration,
            dt,
        } => {
            let plan = load(study)?;
            let speeds = speed
                .iter()
                .map(|v| argument("--speed", v, Dimension::Speed))
                .collect::<Result<Vec<_>, _>>()?;
            let y0 = argument("--y0", y0, Dimension::Length)?;
            let duration = argument("--duration", duration, Dimension::Time)?;
            let dt = argument("--dt", dt, Dimension::Time)?;
            if speeds.iter().any(|v| *v <= 0.0) || duration <= 0.0 || dt <= 0.0 || dt > duration {
                return Err(user(anyhow!(
                    "speeds and --duration must be positive and 0 < --dt <= --duration"
                )));
            }
            if duration / dt > 5e6 {
                return Err(user(anyhow!(
                    "--duration / --dt = {:.0} samples per speed; at most 5e6",
                    duration / dt
                )));
            }
            let model = build(&plan)?;
            simulate(&plan, &model, &cli.out, &speeds, y0, duration, dt)
        }
        Command::Ramp(args) => super::ramp::run(args, &cli.out),
        Command::Conicity(args) => super::conicity::run(args, &cli.out),
        Command::Sweep(args) => super::sweep::run(args, &cli.out),
        Command::Merge(args) => super::sweep::merge(args, &cli.out),
        Command::Trade(args) => super::trade::run(args, &cli.out),
        Command::Geometry { study } => {
            let plan = load(study)?;
            let model = build(&plan)?;
            let g = geometry(&plan, &model, &cli.out)?;
            results(&table::geometry(&g))?;
            Ok(())
        }
        Command::Check { study } => {
            let plan = load(study)?;
            let sections = super::trade::check_sections(study)?;
            let model = build(&plan)?;
            results(&format!(
                "{}{}{sections}",
                table::plan(&plan),
                table::vehicle(&model)
            ))?;
            Ok(())
        }
    }
}

pub(super) fn load(path: &Path) -> Result<Plan, Failure> {
    study::load(path).map_err(user)
}

pub(super) fn build(plan: &Plan) -> Result<Vehicle, Failure> {
    plan.model()
        .with_context(|| format!("building the contact geometry of study '{}'", plan.name))
        .map_err(compute)
}

pub(super) fn out_dir(root: &Path, plan: &Plan) -> Result<PathBuf, Failure> {
    output::study_dir(root, &plan.name)
        .with_context(|| format!("creating {}", root.join(&plan.name).display()))
        .map_err(compute)
}

pub(super) fn write(dir: &Path, file: &str, bytes: &[u8]) -> Result<(), Failure> {
    let path = output::write(dir, file, bytes)
        .with_context(|| format!("writing {}", dir.join(file).display()))
        .map_err(compute)?;
    statusln!("wrote {}", path.display());
    Ok(())
}

pub(super) fn linear(plan: &Plan, model: &Vehicle, root: &Path) -> Result<LinearReport, Failure> {
    let report = analysis::linear(plan, model)
        .context("linear stability analysis")
        .map_err(compute)?;
    let dir = out_dir(root, plan)?;
    let json = serde_json::to_string_pretty(&output::linear_json(&report)).map_err(compute)?;
    write(&dir, "linear.json", json.as_bytes())?;
    write(
        &dir,
        "spectrum.csv",
        output::spectrum_csv(&report).as_bytes(),
    )?;
    for (file, svg) in figures::linear(&report).map_err(|e| compute(anyhow!(e)))? {
        write(&dir, &file, svg.as_bytes())?;
    }
    Ok(report)
}

fn bifurcation(plan: &Plan, model: &Vehicle, root: &Path) -> Result<BifurcationReport, Failure> {
    bifurcation_with(plan, model, root, &plan.bifurcation_options())
}

/// The bifurcation diagram with the given options (the study's, or the first run's).
pub(super) fn bifurcation_with(
    plan: &Plan,
    model: &Vehicle,
    root: &Path,
    opts: &crate::bifurcation::BifurcationOptions,
) -> Result<BifurcationReport, Failure> {
    statusln!(
        "continuing the hunting cycles of '{}' over [{}, {}] m/s (up to {} cycles, amplitude {} mm)",
        plan.name,
        opts.speed_range.0,
        opts.speed_range.1,
        opts.max_points,
        opts.max_amplitude * 1e3
    );
    let started = std::time::Instant::now();
    let tty = std::io::IsTerminal::is_terminal(&std::io::stderr());
    let progress = |k: usize, v: f64, a: f64| {
        if tty && k.is_multiple_of(5) {
            status!(
                "\r  cycle {k:>4}: V = {v:8.3} m/s, amplitude {:7.3} mm   ",
                a * 1e3
            );
        } else if !tty && k.is_multiple_of(50) {
            statusln!(
                "  cycle {k:>4}: V = {v:8.3} m/s, amplitude {:7.3} mm",
                a * 1e3
            );
        }
    };
    let report =
        crate::bifurcation::analyse_with_progress(&plan.name, model, opts, Some(&progress))
            .map_err(|e| compute(anyhow!(e)))?;
    let clear = if tty { "\r" } else { "" };
    statusln!(
        "{clear}  {} cycles in {:.2} s{}",
        report.cycles.len(),
        started.elapsed().as_secs_f64(),
        if tty { " ".repeat(40) } else { String::new() }
    );
    let dir = out_dir(root, plan)?;
    let json = serde_json::to_string_pretty(&output::bifurcation_json(&report)).map_err(compute)?;
    write(&dir, "bifurcation.json", json.as_bytes())?;
    write(&dir, "branch.csv", output::branch_csv(&report).as_bytes())?;
    let svg = figures::bifurcation(&report).map_err(|e| compute(anyhow!(e)))?;
    write(&dir, "bifurcation.svg", svg.as_bytes())?;
    Ok(report)
}

/// A command-line quantity: a plain number (SI) or a number with a unit.
pub(super) fn argument(flag: &str, text: &str, dim: Dimension) -> Result<f64, Failure> {
    if let Ok(v) = text.trim().parse::<f64>() {
        if v.is_finite() {
            return Ok(v);
        }
    }
    parse_quantity(text, dim).map_err(|p| {
        user(anyhow!(
            "{flag} {text:?}: {p}; expected a {dim} in SI ({}) or with one of the units {}",
            dim.si_unit(),
            dim.accepted()
        ))
    })
}

fn simulate(
    plan: &Plan,
    model: &Vehicle,
    root: &Path,
    speeds: &[f64],
    y0: f64,
    duration: f64,
    dt: f64,
) -> Result<(), Failure> {
    let ode = crate::system::ode::OdeOptions {
        tol: crate::system::ode::Tolerances::new(1e-9, 1e-12).map_err(compute)?,
        ..Default::default()
    };
    let mut runs = Vec::new();
    for &v in speeds {
        statusln!(
            "simulating '{}' at {v} m/s for {duration} s from y(0) = {} mm",
            plan.name,
            y0 * 1e3
        );
        let h = crate::simulate::simulate(
            model,
            v,
            &crate::simulate::lateral_start(model, y0),
            duration,
            dt,
            &ode,
        )
        .with_context(|| format!("time simulation at {v} m/s"))
        .map_err(compute)?;
        runs.push(h);
    }
    let dir = out_dir(root, plan)?;
    write(&dir, "simulate.csv", output::simulate_csv(&runs).as_bytes())?;
    let svg = figures::simulate(&plan.name, &runs).map_err(|e| compute(anyhow!(e)))?;
    write(&dir, "simulate.svg", svg.as_bytes())?;
    results(&table::simulate(&plan.name, &runs))?;
    Ok(())
}

pub(super) fn geometry(
    plan: &Plan,
    model: &Vehicle,
    root: &Path,
) -> Result<GeometryReport, Failure> {
    let g = analysis::geometry(plan, model);
    let dir = out_dir(root, plan)?;
    write(&dir, "geometry.csv", output::geometry_csv(&g).as_bytes())?;
    let svg = figures::geometry(&g).map_err(|e| compute(anyhow!(e)))?;
    write(&dir, "geometry.svg", svg.as_bytes())?;
    Ok(g)
}

fn run(root: &Path, study: Option<&Path>) -> Result<(), Failure> {
    match study {
        Some(p) => run_study(root, &load(p)?).map(|_| ()),
        None => super::first_run::run(root),
    }
}

/// `critspeed run STUDY`: geometry, linear stability and, when the study has a
/// `[bifurcation]` section, the diagram; the tables on stdout.
pub(super) fn run_study(root: &Path, plan: &Plan) -> Result<LinearReport, Failure> {
    let model = build(plan)?;
    let g = geometry(plan, &model, root)?;
    results(&table::geometry(&g))?;
    let report = linear(plan, &model, root)?;
    results(&table::linear(plan, &report))?;
    if plan.bifurcation.is_some() {
        let b = bifurcation(plan, &model, root)?;
        results(&table::bifurcation(&b))?;
    }
    Ok(report)
}
