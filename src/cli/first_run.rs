//! `critspeed run` without a study: the first run. It shows what the tool is for: the seed
//! study as published (stable far beyond railway speeds), beside it the seed wheelset made to
//! hunt (`seed-hunting`) with its bifurcation diagram, and a summary of both against the seed
//! paper's 40 and 35 m/s.

use std::path::Path;

use anyhow::anyhow;

use super::commands::{bifurcation, build, compute, linear, prepare, run_study};
use super::console::{results, statusln};
use super::Failure;
use crate::bifurcation::BifurcationReport;
use crate::contact::creep::CreepLaw;
use crate::stability::{critical_speeds, CriticalSpeeds, LinearOptions, LinearSystem};
use crate::study::{self, Plan};

/// The seed paper's critical speeds (Anyakwo et al., `studies/seed.toml`; docs/model.md §10):
/// the linear one and the nonlinear one, both from 30 s simulations, in m/s.
pub const SEED_PAPER_LINEAR_M_S: f64 = 40.0;
/// See [`SEED_PAPER_LINEAR_M_S`].
pub const SEED_PAPER_NONLINEAR_M_S: f64 = 35.0;

/// Where the first run looks for the seed's own critical speeds, which lie far above the
/// study's [1, 300] m/s (m/s).
const SEED_SEARCH_M_S: (f64, f64) = (1.0, 4000.0);

/// The first run follows seed-hunting's cycles to this amplitude (m): far enough to show the
/// supercritical branch growing, and the whole run stays well under a second (to the default
/// 20 mm the diagram alone takes about 0.9 s).
pub const FIRST_RUN_MAX_AMPLITUDE_M: f64 = 0.010;

/// Runs both embedded studies and prints the summary.
pub fn run(root: &Path) -> Result<(), Failure> {
    statusln!(
        "no study given: the first run, on two embedded studies: the seed paper's wheelset \
         (studies/seed.toml) and the same wheelset made to hunt (studies/seed-hunting.toml)"
    );
    let seed = parse(study::DEFAULT_STUDY, "embedded seed study")?;
    run_study(root, seed.clone())?;
    let (seed_kalker, seed_law) = wide_search(&seed)?;

    let hunting = parse(study::HUNTING_STUDY, "embedded seed-hunting study")?;
    let mut shown = hunting.clone();
    shown.bifurcation = Some(crate::bifurcation::BifurcationOptions {
        max_amplitude: FIRST_RUN_MAX_AMPLITUDE_M,
        ..hunting.bifurcation_options()
    });
    let p = prepare(shown)?;
    let hunting_linear = linear(&p, root)?;
    let b = bifurcation(&p, root)?;
    results(&super::table::bifurcation(&b))?;
    let text = summary(
        &seed,
        (&seed_kalker, &seed_law),
        &hunting,
        hunting_linear.centre_conicity,
        &b,
        root,
    );
    results(&text)?;
    Ok(())
}

fn parse(text: &str, origin: &str) -> Result<Plan, Failure> {
    study::parse(text, origin).map_err(compute)
}

/// The seed's Kalker critical speed and its creep law's Hopf speed over [`SEED_SEARCH_M_S`].
fn wide_search(seed: &Plan) -> Result<(CriticalSpeeds, CriticalSpeeds), Failure> {
    let model = build(seed)?;
    let opts = LinearOptions {
        speed_range: SEED_SEARCH_M_S,
        ..seed.linear
    };
    let search = |law: CreepLaw| {
        let sys = LinearSystem::<4>::at_centre(&model.with_law(law));
        critical_speeds(&sys, law, &opts).map_err(|e| compute(anyhow!(e)))
    };
    Ok((search(CreepLaw::Kalker)?, search(model.creep_law())?))
}

/// "2951.2 m/s (10624 km/h)", or "none below 4000 m/s".
fn speed(s: &CriticalSpeeds) -> String {
    match s.critical() {
        Some(c) => format!("{:.1} m/s ({:.0} km/h)", c.speed_m_s, c.speed_m_s * 3.6),
        None => format!("none below {} m/s", s.speed_range.1),
    }
}

fn onset(s: Option<f64>) -> String {
    s.map_or("none in range".into(), |v| {
        format!("{v:.2} m/s ({:.0} km/h)", v * 3.6)
    })
}

fn summary(
    seed: &Plan,
    (seed_kalker, seed_law): (&CriticalSpeeds, &CriticalSpeeds),
    hunting: &Plan,
    hunting_conicity: f64,
    b: &BifurcationReport,
    root: &Path,
) -> String {
    let s = &seed.suspension;
    let yaw_damping = 2.0 * s.longitudinal_damping * s.half_spring_spacing.powi(2);
    let h = &hunting.suspension;
    let hopf = b.hopf.as_ref().map(|c| c.speed_m_s);
    let kind = match b.hopf_type {
        Some(crate::bifurcation::HopfType::Supercritical) => ", supercritical",
        Some(crate::bifurcation::HopfType::Subcritical) => ", subcritical",
        None => "",
    };
    let nl = b.nonlinear_critical_speed.map(|(v, _)| v);
    let law = seed_law.law.name();
    let (so, ho) = (root.join(&seed.name), root.join(&hunting.name));
    format!(
        "\nsummary of the first run\n\
         the seed paper's wheelset (studies/seed.toml), computed over [{lo}, {hi}] m/s:\n\
         \x20 linear (Kalker) critical speed V_L   paper {pl} m/s   critspeed {vl}\n\
         \x20 nonlinear critical speed V_NL        paper {pn} m/s   critspeed: {vh}\n\
         \x20 the paper's speeds come from 30 s simulations, not from its parameters: its yaw\n\
         \x20 damping 2 C_px d^2 = {yd:.3e} N m s keeps the centred motion stable far beyond\n\
         \x20 railway speeds (docs/model.md §10)\n\
         the same wheelset made to hunt (studies/seed-hunting.toml: lateral primary {ky:.0} N/mm\n\
         per side, a worn-wheel cone: effective conicity {lam:.3} at the centre):\n\
         \x20 V_L = {hl}, V_H = {hh}{kind}, V_NL = {hn}\n\
         pictures: {so}/geometry.svg, {so}/damping.svg, {so}/root_locus.svg,\n\
         \x20         {ho}/bifurcation.svg (cycles to {amp} mm), {ho}/damping.svg\n\
         next: critspeed run studies/flange-hysteresis.toml (folds and hysteresis); the user\n\
         guide is docs/README.md\n",
        lo = SEED_SEARCH_M_S.0,
        hi = SEED_SEARCH_M_S.1,
        pl = SEED_PAPER_LINEAR_M_S,
        pn = SEED_PAPER_NONLINEAR_M_S,
        vl = speed(seed_kalker),
        vh = match seed_law.critical() {
            Some(_) => format!("the {law} law's Hopf speed V_H = {}", speed(seed_law)),
            None => format!(
                "no Hopf point of the {law} law below {} m/s, where a hunting branch would start",
                seed_law.speed_range.1
            ),
        },
        yd = yaw_damping,
        ky = h.lateral_stiffness * 1e-3,
        lam = hunting_conicity,
        hl = onset(b.kalker_critical_speed_m_s),
        hh = onset(hopf),
        hn = onset(nl),
        so = so.display(),
        ho = ho.display(),
        amp = FIRST_RUN_MAX_AMPLITUDE_M * 1e3,
    )
}
