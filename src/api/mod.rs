//! The library's front door: a study in, results out. The command line (`src/cli`) and the
//! Python package (`python/`) both call these functions and nothing below them, so a result
//! printed by `critspeed linear --json` and one returned by `critspeed.linear()` come from the
//! same code path.
//!
//! The surface is kept small on purpose: a [`Source`] (file, TOML text or a TOML table) gives a
//! validated [`Plan`]; [`Prepared`] is a plan with its model built (the model type never
//! crosses this surface); each analysis returns its plain report, [`files`] turns a report into
//! the bytes of the files the CLI writes, and [`columns`] reads one of those CSV files back as
//! typed columns (how Python gets arrays identical to the CSV's).
//!
//! Long analyses accept a cancellation hook (`Fn() -> bool`), asked between continuation steps,
//! sweep points and simulated speeds; the CLI passes none.

mod columns;
pub mod curve;
pub mod files;
mod source;

use anyhow::{anyhow, Context};
use serde_json::{json, Value};

pub use crate::bifurcation::Hooks;
pub use columns::{columns, Column, Kind};
pub use source::Source;

/// Column types of the CSV files read back by [`columns`].
pub mod kinds {
    pub use super::columns::{ATTRACTORS, BRANCH, NUMBERS, SWEEP, UNCERTAINTY};
    pub use super::curve::CURVE;
}

use crate::analysis::{self, GeometryReport, LinearReport};
use crate::bifurcation::BifurcationReport;
use crate::conicity::{Conicity, DeltaR};
use crate::model::Vehicle;
use crate::simulate::TimeHistory;
use crate::study::units::{parse_quantity, Dimension};
use crate::study::Plan;
use crate::sweep::{Progress, SweepOptions, SweepResults, SweepStudy};

/// The library's version (the crate's), which the CLI's `--version` and Python's
/// `critspeed.__version__` report.
pub const VERSION: &str = env!("CARGO_PKG_VERSION");

/// A quantity given as an argument (`name` is the flag or keyword that names it in a
/// message): a plain number (SI) or a number with one of the units of `dim`.
pub fn quantity(name: &str, text: &str, dim: Dimension) -> Result<f64, Failure> {
    if let Ok(v) = text.trim().parse::<f64>() {
        if v.is_finite() {
            return Ok(v);
        }
    }
    parse_quantity(text, dim).map_err(|p| {
        user(anyhow!(
            "{name} {text:?}: {p}; expected a {dim} in SI ({}) or with one of the units {}",
            dim.si_unit(),
            dim.accepted()
        ))
    })
}

/// Why a call failed, and so which exit code the CLI gives and which exception Python raises.
#[derive(Debug)]
pub enum Failure {
    /// bad input (study, argument, foreign file): exit code 2, `critspeed.StudyError`
    User(anyhow::Error),
    /// a computation or output failure: exit code 1, `critspeed.ComputationError`
    Compute(anyhow::Error),
}

impl Failure {
    /// The message with its whole context chain, as the CLI prints it.
    pub fn message(&self) -> String {
        match self {
            Failure::User(e) | Failure::Compute(e) => chain(e),
        }
    }
}

/// An error and its causes joined by ": ", each cause once: many of the crate's errors already
/// quote their cause in their own message (`cannot read study file F: <the OS error>`), which
/// anyhow's `{:#}` would print a second time.
pub fn chain(e: &anyhow::Error) -> String {
    let mut s = e.to_string();
    for cause in e.chain().skip(1) {
        let c = cause.to_string();
        if !s.contains(&c) {
            s.push_str(": ");
            s.push_str(&c);
        }
    }
    s
}

pub(crate) fn user<E: Into<anyhow::Error>>(e: E) -> Failure {
    Failure::User(e.into())
}

pub(crate) fn compute<E: Into<anyhow::Error>>(e: E) -> Failure {
    Failure::Compute(e.into())
}

/// A cancellation hook: `true` asks the computation to stop at its next check.
pub type Cancel<'a> = Option<&'a (dyn Fn() -> bool + Sync)>;

/// A validated plan with its model built once, for any number of analyses.
pub struct Prepared {
    plan: Plan,
    model: Vehicle,
}

impl Prepared {
    /// Builds the model of `plan` (the contact geometry table: a computation, so a failure
    /// here is [`Failure::Compute`]).
    pub fn new(plan: Plan) -> Result<Self, Failure> {
        let model = plan
            .model()
            .with_context(|| format!("building the contact geometry of study '{}'", plan.name))
            .map_err(compute)?;
        Ok(Self { plan, model })
    }

    /// The plan.
    pub fn plan(&self) -> &Plan {
        &self.plan
    }
}

/// The linear analysis (Kalker critical speeds, the creep law's Hopf speeds, spectra).
pub fn linear(p: &Prepared) -> Result<LinearReport, Failure> {
    analysis::linear(&p.plan, &p.model)
        .context("linear stability analysis")
        .map_err(compute)
}

/// The branch of hunting cycles of the study's creep law (defaults when the study has no
/// `[bifurcation]` section). A cancelled run is a [`Failure::Compute`] saying so.
pub fn bifurcation(p: &Prepared, hooks: Hooks<'_>) -> Result<BifurcationReport, Failure> {
    let opts = p.plan.bifurcation_options();
    let report = crate::bifurcation::analyse_with_hooks(&p.plan.name, &p.model, &opts, hooks)
        .map_err(|e| compute(anyhow!(e)))?;
    if hooks.cancel.is_some_and(|c| c()) {
        return Err(compute(anyhow!(
            "bifurcation analysis {}",
            report.stop_reason
        )));
    }
    Ok(report)
}

/// The search for every attractor (`[attractors]`, or its defaults), after the continuation
/// with branch switching whose stable cycles it starts from and matches; the continuation's
/// report comes back with the one V_NL of both methods ([`crate::reconcile::combine`]).
/// `progress` gets a line of text per speed and per descent.
pub fn attractors(
    p: &Prepared,
    hooks: Hooks<'_>,
    progress: Option<&(dyn Fn(&str) + Sync)>,
) -> Result<(crate::attractors::AttractorReport, BifurcationReport), Failure> {
    let mut b = bifurcation(p, hooks)?;
    let r = search(p, &b, hooks.cancel, progress)?;
    crate::reconcile::combine(&mut b, &r);
    Ok((r, b))
}

/// The nonlinear analysis a study asks for, the one rule for every front end: the continuation
/// (`continuation`, run with the caller's hooks and progress), then, when the study has an
/// `[attractors]` section, the search for every attractor beside it, and the continuation's report
/// carries the one V_NL of both ([`crate::reconcile::combine`]). `progress` gets the search's
/// lines, headed by one naming the study.
pub fn nonlinear(
    p: &Prepared,
    continuation: impl FnOnce() -> Result<BifurcationReport, Failure>,
    cancel: Cancel<'_>,
    progress: Option<&(dyn Fn(&str) + Sync)>,
) -> Result<
    (
        BifurcationReport,
        Option<crate::attractors::AttractorReport>,
    ),
    Failure,
> {
    let mut b = continuation()?;
    if p.plan.attractors.is_none() {
        return Ok((b, None));
    }
    if let Some(f) = progress {
        f(&format!(
            "searching for the attractors of '{}'",
            p.plan.name
        ));
    }
    let r = search(p, &b, cancel, progress)?;
    crate::reconcile::combine(&mut b, &r);
    Ok((b, Some(r)))
}

/// The search alone, given the continuation's report `b` (its Hopf speed sets the default
/// grid, its stable cycles are starts).
pub fn search(
    p: &Prepared,
    b: &BifurcationReport,
    cancel: Cancel<'_>,
    progress: Option<&(dyn Fn(&str) + Sync)>,
) -> Result<crate::attractors::AttractorReport, Failure> {
    let opts = p.plan.attractor_options(b.hopf.map(|h| h.speed_m_s));
    let r = crate::attractors::search_with_hooks(
        &p.plan.name,
        &p.model,
        &opts,
        Some(b),
        progress,
        cancel,
    )
    .map_err(|e| compute(anyhow!(e)))?;
    if cancel.is_some_and(|c| c()) {
        return Err(compute(anyhow!("attractor search cancelled")));
    }
    Ok(r)
}

/// The contact geometry table.
pub fn geometry(p: &Prepared) -> GeometryReport {
    analysis::geometry(&p.plan, &p.model)
}

/// A time simulation request, in SI.
#[derive(Clone, Debug, PartialEq)]
pub struct SimulateRequest {
    /// constant speeds, one run each (m/s)
    pub speeds: Vec<f64>,
    /// initial lateral displacement y(0) (m)
    pub y0: f64,
    /// simulated time (s)
    pub duration: f64,
    /// output sample interval (s)
    pub dt: f64,
    /// start on a motion the attractor search found instead of y(0): each speed starts from
    /// the state of the attractor's path nearest that speed ([`attractor_start`])
    pub from: Option<AttractorStart>,
    /// displacements added to the start, `BODY.COORD=VALUE` (`"wheelset 3.y=6 mm"`,
    /// `"frame 2.psi=2 mrad"`; hyphens and underscores in the body's name read as spaces;
    /// coordinates `y`, `psi` (or `yaw`), `phi` (or `roll`) where the body rolls)
    pub kicks: Vec<String>,
    /// the integrator's relative tolerance, within [`SIMULATE_RTOL_RANGE`]; the absolute
    /// tolerance is a thousandth of it (m, rad, m/s, rad/s). `None`: [`SIMULATE_RTOL`]
    pub rtol: Option<f64>,
}

/// The time simulation's relative tolerance when none is given (docs/commands.md, "How exact
/// a time history is", measures what it and looser ones keep and cost).
pub const SIMULATE_RTOL: f64 = 1e-9;

/// The relative tolerances a time simulation accepts.
pub const SIMULATE_RTOL_RANGE: (f64, f64) = (1e-12, 1e-4);

/// A start on an attractor of `attractors.json`: its path's states by speed.
#[derive(Clone, Debug, PartialEq)]
pub struct AttractorStart {
    /// where it comes from, in words (`out/x/attractors.json: attractor 2`)
    pub source: String,
    /// (speed m/s, state in the model's order, SI) along the attractor's descent
    pub path: Vec<(f64, Vec<f64>)>,
}

impl AttractorStart {
    /// The path's state nearest `speed`, with its speed.
    pub fn nearest(&self, speed: f64) -> Option<&(f64, Vec<f64>)> {
        self.path
            .iter()
            .min_by(|a, b| (a.0 - speed).abs().total_cmp(&(b.0 - speed).abs()))
    }
}

/// Reads attractor `id` of an `attractors.json` (`critspeed attractors`' output): its path's
/// states by speed. `spec` is `PATH:ID`.
pub fn attractor_start(spec: &str) -> Result<AttractorStart, Failure> {
    let rule = "must be PATH:N, an attractors.json written by `critspeed attractors` and an attractor id in it";
    let (path, id) = spec
        .rsplit_once(':')
        .ok_or_else(|| user(anyhow!("--from {spec:?}: {rule}")))?;
    let id: u64 = id.trim().parse().map_err(|_| {
        user(anyhow!(
            "--from {spec:?}: {id:?} is not an attractor id; {rule}"
        ))
    })?;
    let text = std::fs::read_to_string(path)
        .map_err(|e| user(anyhow!("--from {spec:?}: reading {path}: {e}")))?;
    let j: Value = serde_json::from_str(&text)
        .map_err(|e| user(anyhow!("--from {spec:?}: {path} is not JSON ({e}); {rule}")))?;
    let list = j["attractors"].as_array().ok_or_else(|| {
        user(anyhow!(
            "--from {spec:?}: {path} has no \"attractors\" list; {rule}"
        ))
    })?;
    let ids: Vec<String> = list.iter().map(|a| a["id"].to_string()).collect();
    let a = list
        .iter()
        .find(|a| a["id"].as_u64() == Some(id))
        .ok_or_else(|| {
            user(anyhow!(
                "--from {spec:?}: no attractor {id} in {path} (its ids: {})",
                ids.join(", ")
            ))
        })?;
    let path_states: Vec<(f64, Vec<f64>)> = a["path"]
        .as_array()
        .into_iter()
        .flatten()
        .filter_map(|m| {
            let v = m["speed_m_s"].as_f64()?;
            let x: Option<Vec<f64>> = m["state"].as_array()?.iter().map(Value::as_f64).collect();
            x.filter(|x| !x.is_empty()).map(|x| (v, x))
        })
        .collect();
    if path_states.is_empty() {
        return Err(user(anyhow!(
            "--from {spec:?}: attractor {id} of {path} has no states (written by an older critspeed: run `critspeed attractors` again)"
        )));
    }
    Ok(AttractorStart {
        source: format!("{path}: attractor {id}"),
        path: path_states,
    })
}

/// The state index and value of a kick `BODY.COORD=VALUE` on `model`.
pub fn parse_kick(model: &Vehicle, kick: &str) -> Result<(usize, f64), Failure> {
    let bodies: Vec<&str> = model.bodies.iter().map(|b| b.name.as_str()).collect();
    let rule = format!(
        "must be BODY.COORD=VALUE with BODY one of {} (hyphens or underscores for spaces), COORD y, psi or phi, VALUE with a unit",
        bodies.join(", ")
    );
    let (target, value) = kick
        .split_once('=')
        .ok_or_else(|| user(anyhow!("--kick {kick:?}: {rule}")))?;
    let (body, coord) = target
        .trim()
        .rsplit_once('.')
        .ok_or_else(|| user(anyhow!("--kick {kick:?}: {rule}")))?;
    let norm = |s: &str| s.trim().replace(['-', '_'], " ").to_lowercase();
    let b = model
        .bodies
        .iter()
        .find(|b| norm(&b.name) == norm(body))
        .ok_or_else(|| user(anyhow!("--kick {kick:?}: no body {body:?}; {rule}")))?;
    let (offset, dim) = match coord.trim().to_lowercase().as_str() {
        "y" => (0, Dimension::Length),
        "psi" | "yaw" | "ψ" => (1, Dimension::Angle),
        "phi" | "roll" | "φ" if b.dofs() > 2 => (2, Dimension::Angle),
        _ => {
            return Err(user(anyhow!(
                "--kick {kick:?}: {coord:?} is not a coordinate of {} ({rule})",
                b.name
            )))
        }
    };
    let v =
        parse_quantity(value, dim).map_err(|e| user(anyhow!("--kick {kick:?}: {value:?}: {e}")))?;
    if !v.is_finite() {
        return Err(user(anyhow!("--kick {kick:?}: the value must be finite")));
    }
    Ok((b.dof + offset, v))
}

impl SimulateRequest {
    /// The rules: positive speeds and duration, 0 < dt <= duration, at most 5e6 samples, one
    /// start (y0 = 0 with `from`), and `rtol` within [`SIMULATE_RTOL_RANGE`].
    pub fn validate(&self) -> Result<(), Failure> {
        let SimulateRequest {
            speeds,
            y0,
            duration,
            dt,
            ..
        } = self;
        let finite = speeds
            .iter()
            .chain([y0, duration, dt])
            .all(|v| v.is_finite());
        if speeds.is_empty()
            || !finite
            || speeds.iter().any(|v| *v <= 0.0)
            || *duration <= 0.0
            || *dt <= 0.0
            || dt > duration
        {
            return Err(user(anyhow!(
                "speeds {speeds:?} m/s, y0 {y0} m, duration {duration} s, dt {dt} s: \
                 at least one speed, all speeds and the duration positive, 0 < dt <= duration"
            )));
        }
        if self.from.is_some() && *y0 != 0.0 {
            return Err(user(anyhow!(
                "--y0 and --from: give one start (--kick adds to either)"
            )));
        }
        if duration / dt > 5e6 {
            return Err(user(anyhow!(
                "duration / dt = {:.0} samples per speed; at most 5e6",
                duration / dt
            )));
        }
        if let Some(rtol) = self.rtol {
            let (lo, hi) = SIMULATE_RTOL_RANGE;
            if !(lo..=hi).contains(&rtol) {
                let shown = if rtol.is_finite() && rtol != 0.0 {
                    format!("{rtol:e}")
                } else {
                    rtol.to_string()
                };
                return Err(user(anyhow!(
                    "rtol {shown}: the integrator's relative tolerance must lie in [{lo:e}, {hi:e}]"
                )));
            }
        }
        Ok(())
    }

    /// The relative tolerance the runs use.
    pub fn rtol(&self) -> f64 {
        self.rtol.unwrap_or(SIMULATE_RTOL)
    }
}

/// Time histories at each speed of `req` (validated first); `cancel` is asked between speeds
/// and `before` is called with each speed before its run.
pub fn simulate(
    p: &Prepared,
    req: &SimulateRequest,
    before: &dyn Fn(f64),
    cancel: Cancel<'_>,
) -> Result<Vec<TimeHistory>, Failure> {
    req.validate()?;
    let ode = crate::system::ode::OdeOptions {
        // rtol / 1e3, not 1e-3 × rtol: at the default that is exactly 1e-12, the absolute
        // tolerance the simulation had before `rtol` was an option (the same histories to the bit)
        tol: crate::system::ode::Tolerances::new(req.rtol(), req.rtol() / 1e3).map_err(compute)?,
        ..Default::default()
    };
    let mut runs = Vec::new();
    for &v in &req.speeds {
        if cancel.is_some_and(|c| c()) {
            return Err(compute(anyhow!("time simulation cancelled before {v} m/s")));
        }
        before(v);
        let mut x0 = match &req.from {
            Some(from) => {
                let (_, x) = from
                    .nearest(v)
                    .ok_or_else(|| user(anyhow!("--from {}: no states", from.source)))?;
                if x.len() != p.model.states() {
                    return Err(user(anyhow!(
                        "--from {}: its states have {} values, the model of '{}' has {} states: the file is another study's",
                        from.source,
                        x.len(),
                        p.plan.name,
                        p.model.states()
                    )));
                }
                x.clone()
            }
            None => crate::simulate::lateral_start(&p.model, req.y0),
        };
        for k in &req.kicks {
            let (i, value) = parse_kick(&p.model, k)?;
            if let Some(x) = x0.get_mut(i) {
                *x += value;
            }
        }
        let h = crate::simulate::simulate(&p.model, v, &x0, req.duration, req.dt, &ode)
            .with_context(|| format!("time simulation at {v} m/s"))
            .map_err(compute)?;
        runs.push(h);
    }
    Ok(runs)
}

/// The Δr = r_R − r_L table of a study's contact geometry.
pub fn delta_r(p: &Prepared) -> Result<DeltaR, Failure> {
    DeltaR::new(
        p.model.contact.table.rolling_radius_difference(),
        &p.plan.name,
    )
    .map_err(compute)
}

/// The default amplitudes of the conicity command: 0.5 mm to 10 mm by 0.5 mm.
pub fn default_amplitudes() -> Vec<f64> {
    (1..=20).map(|k| k as f64 * 0.5e-3).collect()
}

/// EN 15302 equivalent conicity of `table` at each amplitude (m). With `explicit`, every
/// amplitude must fit (else a user error); otherwise those beyond the table are skipped and
/// their reasons returned beside the results.
pub fn conicity(
    table: &DeltaR,
    amplitudes: &[f64],
    explicit: bool,
) -> Result<(Vec<Conicity>, Vec<String>), Failure> {
    let (mut results, mut skipped) = (Vec::new(), Vec::new());
    for &amp in amplitudes {
        match table.equivalent_conicity(amp) {
            Ok(c) => results.push(c),
            Err(e) if explicit => return Err(user(anyhow!(e))),
            Err(e) => skipped.push(format!("{:.1} mm: {e}", amp * 1e3)),
        }
    }
    if results.is_empty() {
        return Err(user(anyhow!("no amplitude fits the Δr table")));
    }
    Ok((results, skipped))
}

/// The conicity results as the JSON object `conicity --json` prints.
pub fn conicity_json(results: &[Conicity]) -> Value {
    json!({
        "amplitude_m": results.iter().map(|c| c.amplitude_m).collect::<Vec<_>>(),
        "equivalent_conicity": results.iter().map(|c| c.conicity).collect::<Vec<_>>(),
    })
}

/// Runs (or resumes, when `opts.records` names a file) a sweep; failures are sorted into
/// user and computation failures as the CLI's exit codes are.
pub fn sweep(
    study: &SweepStudy,
    opts: &SweepOptions,
    progress: Option<&(dyn Fn(&Progress) + Sync)>,
    cancel: Cancel<'_>,
) -> Result<SweepResults, Failure> {
    if opts.threads == Some(0) {
        return Err(user(anyhow!("threads = 0: must be at least 1")));
    }
    crate::sweep::run_cancellable(study, opts, progress, cancel).map_err(sweep_failure)
}

pub(crate) fn sweep_failure(e: crate::sweep::SweepError) -> Failure {
    if e.is_user_error() {
        user(e)
    } else {
        compute(e)
    }
}

/// Runs (or resumes, when `opts.records` names a file) the evaluations of an uncertainty
/// study's design ([`crate::uncertainty::run`]); [`crate::uncertainty::report`] turns the rows
/// into `uncertainty.json`'s statistics and indices.
pub fn uncertainty(
    study: &crate::uncertainty::UncertaintyStudy,
    opts: &SweepOptions,
    progress: Option<&(dyn Fn(&Progress) + Sync)>,
    cancel: Cancel<'_>,
) -> Result<SweepResults, Failure> {
    if opts.threads == Some(0) {
        return Err(user(anyhow!("threads = 0: must be at least 1")));
    }
    crate::uncertainty::run(study, opts, progress, cancel).map_err(uncertainty_failure)
}

/// An uncertainty study's error as a user failure (exit 2, Python's `StudyError`) when the
/// input can fix it, else a computation failure.
pub(crate) fn uncertainty_failure(e: crate::uncertainty::UncertaintyError) -> Failure {
    if e.is_user_error() {
        user(e)
    } else {
        compute(e)
    }
}

/// The plausibility warnings of a study with a sweep: the base plan's, and one per axis whose
/// values leave the key's plausible range.
pub fn sweep_warnings(s: &SweepStudy) -> Vec<String> {
    let mut w: Vec<String> = s.base.warnings.iter().map(ToString::to_string).collect();
    for (i, a) in s.spec.axes.iter().enumerate() {
        let out: Vec<_> = a
            .values
            .iter()
            .filter_map(|v| crate::study::plausible::plausible(&a.key, *v))
            .collect();
        if let (Some(first), Some(last)) = (out.first(), out.last()) {
            let unit = match first.unit {
                "" => String::new(),
                u => format!(" {u}"),
            };
            w.push(format!(
                "sweep.axes[{i}] ({}): {} of {} values, {} to {}{unit}, lie outside the plausible range {} ({}); computed as given",
                a.key,
                out.len(),
                a.values.len(),
                crate::study::plausible::si(first.value),
                crate::study::plausible::si(last.value),
                first.plausible.show(first.unit),
                first.why
            ));
        }
    }
    w
}

/// What `check` found: the plan, and the `[sweep]`, `[trade]` and `[curve]` sections, validated.
pub struct Checked {
    /// the resolved plan
    pub plan: Plan,
    /// the study's sweep, when it has a `[sweep]` section (every axis value gives a valid study)
    pub sweep: Option<SweepStudy>,
    /// the `[sweep]`, `[trade]` and `[curve]` tables as written, when present
    pub sections: Vec<(String, toml::Value)>,
    /// values outside their plausible ranges (the plan's and the sweep axes')
    pub warnings: Vec<String>,
}

/// Validates a study with its `[sweep]`, `[trade]` and `[curve]` sections.
pub fn check(source: &Source) -> Result<Checked, Failure> {
    let plan = source.plan()?;
    let file = source.file_schema()?;
    let sweep = match file.sweep {
        Some(_) => Some(source.sweep_study()?),
        None => None,
    };
    if let Some(t) = &file.trade {
        let tp = crate::trade::trade_plan(t).map_err(user)?;
        if tp.method == crate::trade::Method::Curve {
            let spec = sweep.as_ref().map(|s| &s.spec).ok_or_else(|| {
                user(crate::study::StudyError::Rule {
                    key: "trade.method".into(),
                    value: "\"curve\"".into(),
                    rule: "needs a [sweep] with exactly one axis (the curves' key); the study has none".into(),
                })
            })?;
            crate::trade::curve::key_axis(spec, &tp).map_err(user)?;
        }
    }
    if file.curve.is_some() {
        curve::curve_study(source)?;
    }
    if let Some(u) = &file.uncertainty {
        crate::uncertainty::spec::resolve(u).map_err(user)?;
    }
    let raw: toml::Table = toml::from_str(&source.text).map_err(|e| {
        user(crate::study::StudyError::Syntax {
            path: source.origin.clone(),
            message: e.to_string(),
        })
    })?;
    let sections = ["sweep", "trade", "curve", "uncertainty"]
        .iter()
        .filter_map(|k| raw.get(*k).map(|v| (k.to_string(), v.clone())))
        .collect();
    let warnings = match &sweep {
        Some(s) => sweep_warnings(s),
        None => plan.warnings.iter().map(ToString::to_string).collect(),
    };
    Ok(Checked {
        plan,
        sweep,
        sections,
        warnings,
    })
}

/// The resolved plan in SI as JSON (what `critspeed check` prints as a table: the study file's
/// sections and keys, every quantity a number in SI, defaults filled), with the `[sweep]`,
/// `[trade]` and `[curve]` sections as written, and `warnings` (a list of messages) when a value
/// lies outside its plausible range. For the cone and cone-on-arc geometries the object without
/// `warnings` is itself a valid study that resolves to the same plan.
pub fn check_json(c: &Checked) -> Result<Value, Failure> {
    let mut v = crate::output::plan_json(&c.plan);
    if let Value::Object(m) = &mut v {
        for (k, t) in &c.sections {
            m.insert(k.clone(), serde_json::to_value(t).map_err(compute)?);
        }
        if !c.warnings.is_empty() {
            m.insert("warnings".into(), json!(c.warnings));
        }
    }
    Ok(v)
}
