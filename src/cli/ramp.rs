//! `critspeed ramp`: the ramp method and the EN 14363 criterion on its history.

use std::path::Path;

use anyhow::anyhow;
use serde_json::{json, Value};

use super::commands::{argument, build, compute, load, out_dir, user, write};
use super::console::{results, statusln};
use super::Failure;
use crate::contact::creep::CreepLaw;
use crate::figures;
use crate::simulate::{
    ramp, ramp_converged, En14363, En14363Verdict, RampConvergence, RampOptions, RampResult,
    RampStop, RAMP_QUANTITY,
};
use crate::stability::{critical_speeds, LinearError, LinearSystem};
use crate::study::units::Dimension;

/// The ramp command's arguments, as typed.
#[derive(Debug, clap::Args)]
pub struct RampArgs {
    /// Study file (TOML).
    pub study: std::path::PathBuf,
    /// Start (and settle) speed; default 1.05 × the creep law's Hopf speed.
    #[arg(long)]
    pub start: Option<String>,
    /// Speed at which the ramp gives up; default half the start speed.
    #[arg(long)]
    pub end: Option<String>,
    /// Speed lost per second, e.g. "5 km/h" (per s, the GENSYS rate) or a number in m/s².
    #[arg(long, default_value = "5 km/h")]
    pub rate: String,
    /// Initial lateral displacement that kicks the motion onto the cycle.
    #[arg(long, default_value = "5 mm")]
    pub y0: String,
    /// Time at the start speed before the ramp begins.
    #[arg(long, default_value = "20 s")]
    pub settle: String,
    /// Peak amplitude below which the hunting counts as died out.
    #[arg(long, default_value = "0.1 mm")]
    pub threshold: String,
    /// Halve the rate until two estimates agree to --rel-tol (at most --max-halvings).
    #[arg(long)]
    pub converge: bool,
    /// Relative agreement for --converge.
    #[arg(long, default_value_t = 1e-3)]
    pub rel_tol: f64,
    /// Most halvings for --converge.
    #[arg(long, default_value_t = 8)]
    pub max_halvings: usize,
    /// Print one JSON object on stdout instead of the table.
    #[arg(long)]
    pub json: bool,
}

fn stop_name(s: &RampStop) -> String {
    match s {
        RampStop::Died => "died".into(),
        RampStop::StillHunting { amplitude_m } => {
            format!(
                "still hunting at the end speed ({:.3} mm)",
                amplitude_m * 1e3
            )
        }
        RampStop::NotHuntingAtStart { amplitude_m } => format!(
            "not hunting at the start speed ({:.3} mm): start above the critical speed",
            amplitude_m * 1e3
        ),
    }
}

fn result_json(r: &RampResult) -> Value {
    json!({
        "quantity": RAMP_QUANTITY,
        "died_at_m_s": r.died_at_m_s,
        "stop": stop_name(&r.stop),
        "start_speed_m_s": r.options.start_speed,
        "rate_m_s2": r.options.rate,
        "threshold_m": r.options.threshold,
        "start_amplitude_m": r.start_amplitude_m,
        "settle_drift_rel": r.settle_drift_rel,
        "en14363": r.en14363.as_ref().map(|e| json!({
            "quantity": "EN 14363 instability criterion: speed where the sliding rms of the \
    sum of guiding forces (f0 ± 2 Hz, 100 m) drops below (10 + 2 Q0/3)/2 kN, judged on the \
    worst wheelset",
            "speed_m_s": r.en14363_speed_m_s,
            "f0_hz": e.f0_hz,
            "limit_kn": e.limit_n / 1e3,
            "max_rms_kn": e.max_rms_n / 1e3,
            "verdict": format!("{:?}", e.verdict),
            "worst_wheelset": e.wheelset + 1,
            "worst_wheelset_name": e.name,
            "wheelsets": r.en14363_wheelsets.iter().map(wheelset_json).collect::<Vec<_>>(),
        })),
        "simulated_s": r.simulated_s,
        "steps": r.steps,
    })
}

/// One wheelset's EN 14363 evaluation: `wheelset` counts from 1 at the front, as the body
/// names do.
fn wheelset_json(e: &En14363) -> Value {
    json!({
        "wheelset": e.wheelset + 1,
        "name": e.name,
        "max_rms_kn": e.max_rms_n / 1e3,
        "limit_kn": e.limit_n / 1e3,
        "verdict": format!("{:?}", e.verdict),
        "speed_m_s": match e.verdict {
            En14363Verdict::DroppedBelow { speed_m_s } => Some(speed_m_s),
            _ => None,
        },
    })
}

fn convergence_json(c: &RampConvergence) -> Value {
    Value::Array(
        c.rows
            .iter()
            .map(|r| {
                json!({
                    "rate_m_s2": r.rate_m_s2,
                    "died_at_m_s": r.died_at_m_s,
                    "change_rel": r.change_rel,
                    "extrapolated_m_s": r.extrapolated_m_s,
                    "en14363_speed_m_s": r.en14363_speed_m_s,
                    "stop": stop_name(&r.stop),
                    "simulated_s": r.simulated_s,
                })
            })
            .collect(),
    )
}

fn envelope_csv(r: &RampResult) -> String {
    let mut s = String::from("time_s,speed_m_s,amplitude_y_m\n");
    for p in &r.envelope {
        s.push_str(&format!("{},{},{}\n", p.t_s, p.speed_m_s, p.amplitude_m));
    }
    s
}

/// `en14363.csv`: the worst wheelset's sliding r.m.s. (`sum_guiding_forces_rms_kn`, the
/// single wheelset's own) and its limit, then one column per wheelset, front to rear
/// (`rms_wheelset_1_kn`, …). Every wheelset's stream reports at the same track positions.
fn en14363_csv(r: &RampResult) -> String {
    let mut s = String::from("time_s,speed_m_s,sum_guiding_forces_rms_kn,limit_kn");
    for e in &r.en14363_wheelsets {
        s.push_str(&format!(",rms_{}_kn", e.name.replace(' ', "_")));
    }
    s.push('\n');
    if let Some(e) = &r.en14363 {
        for (i, p) in e.series.iter().enumerate() {
            s.push_str(&format!(
                "{},{},{},{}",
                p.t_s,
                p.speed_m_s,
                p.rms_n / 1e3,
                e.limit_n / 1e3
            ));
            for w in &r.en14363_wheelsets {
                match w.series.get(i) {
                    Some(q) => s.push_str(&format!(",{}", q.rms_n / 1e3)),
                    None => s.push(','),
                }
            }
            s.push('\n');
        }
    }
    s
}

/// Runs `critspeed ramp`.
pub fn run(a: &RampArgs, root: &Path) -> Result<(), Failure> {
    let plan = load(&a.study)?;
    let model = build(&plan)?;
    let start = match &a.start {
        Some(s) => argument("--start", s, Dimension::Speed)?,
        None => {
            let found = crate::with_states!(model.states(), N => critical_speeds(
                    &LinearSystem::<N>::at_centre(&model), model.creep_law(), &plan.linear),
                _ => Err(LinearError::States(model.states())))
            .map_err(compute)?;
            let hopf = found.critical().map(|c| c.speed_m_s).ok_or_else(|| {
                user(anyhow!(
                    "the {} model has no Hopf point in [{}, {}] m/s: give --start",
                    model.creep_law().name(),
                    plan.linear.speed_range.0,
                    plan.linear.speed_range.1
                ))
            })?;
            1.05 * hopf
        }
    };
    let mut o = RampOptions::new(start, 0.5 * start);
    if let Some(e) = &a.end {
        o.end_speed = argument("--end", e, Dimension::Speed)?;
    }
    o.rate = argument("--rate", &a.rate, Dimension::Speed)?;
    o.y0 = argument("--y0", &a.y0, Dimension::Length)?;
    o.settle = argument("--settle", &a.settle, Dimension::Time)?;
    o.threshold = argument("--threshold", &a.threshold, Dimension::Length)?;
    o.validate().map_err(user)?;
    if model.creep_law() == CreepLaw::Kalker {
        statusln!("note: with Kalker's unbounded creep law no limit cycle exists; the ramp tells only growth or decay");
    }
    statusln!(
        "ramp '{}': settle {} s at {:.3} m/s, then -{:.4} m/s^2 to {:.3} m/s{}",
        plan.name,
        o.settle,
        o.start_speed,
        o.rate,
        o.end_speed,
        if a.converge {
            ", halving the rate until converged"
        } else {
            ""
        }
    );
    let started = std::time::Instant::now();
    let (result, conv) = if a.converge {
        let c = ramp_converged(&model, &o, a.max_halvings, a.rel_tol).map_err(compute)?;
        let last = c.rows.last().map_or(o.rate, |r| r.rate_m_s2);
        let r = ramp(&model, &RampOptions { rate: last, ..o }).map_err(compute)?;
        (r, Some(c))
    } else {
        (ramp(&model, &o).map_err(compute)?, None)
    };
    statusln!("  done in {:.1} s", started.elapsed().as_secs_f64());
    let mut j = result_json(&result);
    j["study"] = json!(plan.name);
    if let Some(c) = &conv {
        j["convergence"] = convergence_json(c);
        j["converged"] = json!(c
            .converged
            .map(|(v, rate)| json!({"died_at_m_s": v, "rate_m_s2": rate})));
    }
    let dir = out_dir(root, &plan)?;
    let text = serde_json::to_string_pretty(&j).map_err(compute)?;
    write(&dir, "ramp.json", text.as_bytes())?;
    write(&dir, "ramp.csv", envelope_csv(&result).as_bytes())?;
    write(&dir, "en14363.csv", en14363_csv(&result).as_bytes())?;
    super::commands::write_figure(
        &dir,
        figures::ramp(&plan.name, &result),
        "ramp.json, ramp.csv and en14363.csv",
    )?;
    if a.json {
        results(&format!("{text}\n"))?;
    } else {
        results(&table(
            &plan.name,
            &result,
            conv.as_ref(),
            plan.contact.analysis_limit(),
        ))?;
    }
    Ok(())
}

fn table(
    study: &str,
    r: &RampResult,
    conv: Option<&RampConvergence>,
    limit: Option<f64>,
) -> String {
    let mut s = format!("\nstudy '{study}': {RAMP_QUANTITY}\n");
    if let Some(c) = conv {
        s.push_str("  rate (m/s^2)   died at (m/s)   change   extrapolated (m/s)\n");
        for row in &c.rows {
            s.push_str(&format!(
                "  {:<14.6} {:<15} {:<8} {}\n",
                row.rate_m_s2,
                row.died_at_m_s.map_or("-".into(), |v| format!("{v:.4}")),
                row.change_rel.map_or("-".into(), |v| format!("{v:.1e}")),
                row.extrapolated_m_s
                    .map_or("-".into(), |v| format!("{v:.4}")),
            ));
        }
        s.push_str(&format!("  stopped: {:?}\n", c.stop));
    }
    s.push_str(&format!(
        "  start {:.3} m/s on a {:.3} mm cycle (settle drift {:+.1e}); rate {:.4} m/s^2\n",
        r.options.start_speed,
        r.start_amplitude_m * 1e3,
        r.settle_drift_rel,
        r.options.rate
    ));
    s.push_str(&format!(
        "  hunting died at {} ({})\n",
        r.died_at_m_s.map_or("-".into(), |v| format!("{v:.4} m/s")),
        stop_name(&r.stop)
    ));
    s.push_str(
        "  (the ramp under-estimates V_NL at any finite rate; the lag shrinks like sqrt(rate))\n",
    );
    // the simulation runs on whatever geometry the model has; say when it left the valid range
    let largest = r
        .envelope
        .iter()
        .map(|p| p.amplitude_m)
        .fold(r.start_amplitude_m, f64::max);
    if let Some(g) = limit.filter(|g| largest > *g) {
        s.push_str(&format!(
            "  note: the motion reached {:.3} mm, beyond the contact geometry's valid range {:.3} mm: \
outside it the contact geometry is extrapolated, so this estimate rests on extrapolated \
geometry (`critspeed attractors` gives no verdict there; contact.extrapolate = \"linear\" accepts it)\n",
            largest * 1e3,
            g * 1e3
        ));
    }
    if let Some(e) = &r.en14363 {
        s.push_str(&format!(
            "  EN 14363: f0 = {} Hz, max sliding rms {:.2} kN against the limit {:.2} kN: {:?}\n",
            e.f0_hz.map_or("-".into(), |f| format!("{f:.3}")),
            e.max_rms_n / 1e3,
            e.limit_n / 1e3,
            e.verdict
        ));
        if r.en14363_wheelsets.len() > 1 {
            s.push_str(&format!("    judged on {} (the worst wheelset)\n", e.name));
            for w in &r.en14363_wheelsets {
                s.push_str(&format!(
                    "    {:<12} max sliding rms {:.2} kN (limit {:.2} kN): {:?}\n",
                    w.name,
                    w.max_rms_n / 1e3,
                    w.limit_n / 1e3,
                    w.verdict
                ));
            }
        }
    }
    s
}
