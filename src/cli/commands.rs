//! The commands: load, compute (through [`crate::api`]), write, print.

use std::path::{Path, PathBuf};

use super::console::{results, status, statusln};
use super::{table, Cli, Command, Failure};
use crate::analysis::{GeometryReport, LinearReport};
use crate::api::{self, files, Prepared, SimulateRequest, Source};
pub(super) use crate::api::{compute, user};
use crate::bifurcation::{BifurcationReport, Hooks};
use crate::output;
use crate::study::units::Dimension;
use crate::study::Plan;

/// Runs the parsed command.
pub fn dispatch(cli: &Cli) -> Result<(), Failure> {
    match &cli.command {
        Command::Run { study } => run(&cli.out, study.as_deref()),
        Command::Linear { study, json } => {
            let p = prepare(load(study)?)?;
            let report = linear(&p, &cli.out)?;
            if *json {
                let text =
                    serde_json::to_string_pretty(&output::linear_json(&report)).map_err(compute)?;
                results(&format!("{text}\n"))?;
            } else {
                results(&table::linear(p.plan(), &report))?;
            }
            Ok(())
        }
        Command::Bifurcation { study, json, .. } => {
            let p = prepare(load(study)?)?;
            let report = nonlinear(&p, &cli.out, !*json)?;
            if *json {
                let text = serde_json::to_string_pretty(&output::bifurcation_json(&report))
                    .map_err(compute)?;
                results(&format!("{text}\n"))?;
            } else {
                results(&table::bifurcation(&report))?;
            }
            Ok(())
        }
        Command::Attractors { study, json, .. } => {
            super::attractors::command(study, *json, &cli.out)
        }
        Command::Simulate {
            study,
            speed,
            y0,
            from,
            kick,
            duration,
            dt,
            rtol,
        } => {
            let plan = load(study)?;
            let y0 = match y0 {
                Some(y) => argument("--y0", y, Dimension::Length)?,
                None if from.is_some() || !kick.is_empty() => 0.0,
                None => 5e-3,
            };
            let req = SimulateRequest {
                speeds: speed
                    .iter()
                    .map(|v| argument("--speed", v, Dimension::Speed))
                    .collect::<Result<Vec<_>, _>>()?,
                y0,
                duration: argument("--duration", duration, Dimension::Time)?,
                dt: argument("--dt", dt, Dimension::Time)?,
                from: from
                    .as_deref()
                    .map(crate::api::attractor_start)
                    .transpose()?,
                kicks: kick.clone(),
                rtol: *rtol,
            };
            req.validate()?;
            simulate(&prepare(plan)?, &cli.out, &req)
        }
        Command::Ramp(args) => super::ramp::run(args, &cli.out),
        Command::Conicity(args) => super::conicity::run(args, &cli.out),
        Command::Sweep(args) => super::sweep::run(args, &cli.out),
        Command::Merge(args) => super::sweep::merge(args, &cli.out),
        Command::Uncertainty(args) => super::uncertainty::run(args, &cli.out),
        Command::Trade(args) => super::trade::run(args, &cli.out),
        Command::Curve(args) => super::curve::run(args, &cli.out),
        Command::Geometry { study } => {
            let p = prepare(load(study)?)?;
            let g = geometry(&p, &cli.out)?;
            results(&table::geometry(&g))?;
            Ok(())
        }
        Command::Check { study } => {
            let checked = api::check(&Source::file(study)?)?;
            warn(&checked.warnings);
            let mut sections = String::new();
            if let Some(s) = &checked.sweep {
                let keys: Vec<String> = s
                    .spec
                    .axes
                    .iter()
                    .map(|a| format!("{} ({} values)", a.key, a.values.len()))
                    .collect();
                sections += &format!(
                    "[sweep] valid: {} points over {}\n",
                    s.spec.len(),
                    keys.join(" x ")
                );
                if s.spec.compute.nonlinear {
                    // the method's default depends on the vehicle: say which one applies
                    let words = crate::sweep::nonlinear_method(s.spec.attractors).1;
                    sections += &format!("  V_NL {words}\n");
                }
            }
            if checked.sections.iter().any(|(k, _)| k == "trade") {
                sections += "[trade] valid\n";
            }
            if checked.sections.iter().any(|(k, _)| k == "curve") {
                sections += "[curve] valid\n";
            }
            let model = build(&checked.plan)?;
            results(&format!(
                "{}{}{sections}",
                table::plan(&checked.plan, &checked.warnings),
                table::vehicle(&model)
            ))?;
            Ok(())
        }
    }
}

/// The validated plan of a study file; its plausibility warnings go to stderr.
pub(super) fn load(path: &Path) -> Result<Plan, Failure> {
    let plan = Source::file(path)?.plan()?;
    warn(&plan.warnings);
    Ok(plan)
}

/// Each message on stderr as `warning: …`.
pub(super) fn warn<T: std::fmt::Display>(warnings: &[T]) {
    for w in warnings {
        statusln!("warning: {w}");
    }
}

pub(super) fn prepare(plan: Plan) -> Result<Prepared, Failure> {
    Prepared::new(plan)
}

/// The model itself, for the commands Python does not offer (ramp) and `check`'s listing of
/// the vehicle's bodies and elements.
pub(super) fn build(plan: &Plan) -> Result<crate::model::Vehicle, Failure> {
    use anyhow::Context as _;
    plan.model()
        .with_context(|| format!("building the contact geometry of study '{}'", plan.name))
        .map_err(compute)
}

pub(super) fn out_dir(root: &Path, plan: &Plan) -> Result<PathBuf, Failure> {
    files::folder(root, &plan.name)
}

/// Writes the files into `dir`, saying so on stderr, with a warning for each figure written as
/// a note.
pub(super) fn write_all(dir: &Path, out: &files::Output) -> Result<(), Failure> {
    files::write(dir, out, &mut |p| statusln!("wrote {}", p.display()))?;
    warn(&out.warnings);
    Ok(())
}

pub(super) fn write(dir: &Path, file: &str, bytes: &[u8]) -> Result<(), Failure> {
    write_all(
        dir,
        &files::Output {
            files: vec![(file.to_string(), bytes.to_vec())],
            warnings: Vec::new(),
        },
    )
}

/// Writes a figure, or the note in its place with a warning; `numbers` names the files that
/// hold its results.
pub(super) fn write_figure(
    dir: &Path,
    f: crate::figures::Rendered,
    numbers: &str,
) -> Result<(), Failure> {
    let file = f.file.clone();
    let (bytes, warning) = files::figure(f, numbers);
    write(dir, &file, &bytes)?;
    warn(&warning.into_iter().collect::<Vec<_>>());
    Ok(())
}

pub(super) fn linear(p: &Prepared, root: &Path) -> Result<LinearReport, Failure> {
    let report = api::linear(p)?;
    write_all(&out_dir(root, p.plan())?, &files::linear(&report)?)?;
    Ok(report)
}

/// The hooks of a command-line analysis: none (Ctrl-C ends the process).
pub(super) fn bifurcation_hooks() -> Hooks<'static> {
    Hooks::default()
}

pub(super) fn bifurcation(p: &Prepared, root: &Path) -> Result<BifurcationReport, Failure> {
    let report = continuation(p)?;
    write_all(&out_dir(root, p.plan())?, &files::bifurcation(&report)?)?;
    Ok(report)
}

/// The continuation with its progress on standard error, no files written.
pub(super) fn continuation(p: &Prepared) -> Result<BifurcationReport, Failure> {
    let plan = p.plan();
    let opts = plan.bifurcation_options();
    statusln!(
        "continuing the hunting cycles of '{}' over [{}, {}] m/s (up to {} cycles a branch, {} branches, amplitude {} mm)",
        plan.name,
        opts.speed_range.0,
        opts.speed_range.1,
        opts.max_points,
        if opts.switch { opts.max_branches } else { 1 },
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
    // a branch's end or a switch: on its own line (after the terminal's last cycle line)
    let branch_line = |text: &str| statusln!("{}  {text}", if tty { "\r" } else { "" });
    let hooks = Hooks {
        progress: Some(&progress),
        cancel: None,
        branches: Some(&branch_line),
    };
    let report = api::bifurcation(p, hooks)?;
    let clear = if tty { "\r" } else { "" };
    statusln!(
        "{clear}  {} cycles in {:.2} s{}",
        report.cycles.len(),
        started.elapsed().as_secs_f64(),
        if tty { " ".repeat(40) } else { String::new() }
    );
    Ok(report)
}

/// The nonlinear analysis the study asks for ([`api::nonlinear`]): the continuation and, when the
/// study has an `[attractors]` section, the attractor search (its files written, its summary
/// printed when `table`: never before `--json`'s object); the report carries the one V_NL of both.
pub(super) fn nonlinear(
    p: &Prepared,
    root: &Path,
    table: bool,
) -> Result<BifurcationReport, Failure> {
    let started = std::time::Instant::now();
    let progress = |line: &str| statusln!("{line}");
    let (b, search) = api::nonlinear(
        p,
        || continuation(p),
        bifurcation_hooks().cancel,
        Some(&progress),
    )?;
    let dir = out_dir(root, p.plan())?;
    write_all(&dir, &files::bifurcation(&b)?)?;
    if let Some(r) = &search {
        super::attractors::finished(r, started);
        write_all(&dir, &files::attractors(r, &b)?)?;
        if table {
            results(&super::attractors::table(r, &b))?;
        }
    }
    Ok(b)
}

/// A command-line quantity: a plain number (SI) or a number with a unit.
pub(super) fn argument(flag: &str, text: &str, dim: Dimension) -> Result<f64, Failure> {
    api::quantity(flag, text, dim)
}

fn simulate(p: &Prepared, root: &Path, req: &SimulateRequest) -> Result<(), Failure> {
    let name = &p.plan().name;
    let kicks = if req.kicks.is_empty() {
        String::new()
    } else {
        format!(" plus {}", req.kicks.join(", "))
    };
    let before = |v: f64| {
        let start = match req
            .from
            .as_ref()
            .and_then(|f| f.nearest(v).map(|n| (f, n.0)))
        {
            Some((f, at)) => format!("{}'s state at {at} m/s", f.source),
            None => format!("y(0) = {} mm", req.y0 * 1e3),
        };
        statusln!(
            "simulating '{name}' at {v} m/s for {} s from {start}{kicks} (rtol {:e})",
            req.duration,
            req.rtol()
        )
    };
    let runs = api::simulate(p, req, &before, None)?;
    write_all(&out_dir(root, p.plan())?, &files::simulate(name, &runs))?;
    results(&table::simulate(name, &runs))?;
    Ok(())
}

pub(super) fn geometry(p: &Prepared, root: &Path) -> Result<GeometryReport, Failure> {
    let g = api::geometry(p);
    write_all(&out_dir(root, p.plan())?, &files::geometry(&g))?;
    Ok(g)
}

fn run(root: &Path, study: Option<&Path>) -> Result<(), Failure> {
    match study {
        Some(p) => run_study(root, load(p)?).map(|_| ()),
        None => super::first_run::run(root),
    }
}

/// `critspeed run STUDY`: geometry, linear stability and, when the study has a
/// `[bifurcation]` section, the diagram; the tables on stdout.
pub(super) fn run_study(root: &Path, plan: Plan) -> Result<LinearReport, Failure> {
    let p = prepare(plan)?;
    let g = geometry(&p, root)?;
    results(&table::geometry(&g))?;
    let report = linear(&p, root)?;
    results(&table::linear(p.plan(), &report))?;
    if p.plan().bifurcation.is_some() {
        let b = nonlinear(&p, root, true)?;
        results(&table::bifurcation(&b))?;
    }
    Ok(report)
}
