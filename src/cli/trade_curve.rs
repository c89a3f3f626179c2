//! `critspeed trade STUDY` with `[trade] method = "curve"`: the trade on curves over the
//! sweep's one key ([`crate::trade::curve`]).

use std::path::Path;
use std::time::Instant;

use anyhow::anyhow;

use super::commands::{compute, out_dir, user, write, write_figure};
use super::console::{results, statusln};
use super::trade::TradeArgs;
use super::Failure;
use crate::curve::keyed::KeyedStudy;
use crate::curve::{CurveError, CurveKind, CurveReport};
use crate::study::schema::{CurveSection, Quantity, StudyFile};
use crate::study::Plan;
use crate::sweep::{Compute, Spares, SweepStudy};
use crate::trade::curve::{fold_grid, KeyAxis, OnCurves};
use crate::trade::intervals::{self, PointAt};
use crate::trade::settle::Settlement;
use crate::trade::{curve_report, ResultKind, TradePlan};

fn curve_failure(e: CurveError) -> Failure {
    if e.is_user_error() {
        user(e)
    } else {
        compute(e)
    }
}

/// The `[curve]` section to run: the study's own (its other settings) with the key, range,
/// spacing and curves of the trade; the speed range is the study's linear one, as a sweep
/// point's.
fn section(file: &StudyFile, axis: &KeyAxis, tp: &TradePlan) -> CurveSection {
    let reads = tp.read_results();
    let mut curves = vec![CurveKind::Hopf.name().to_string()];
    if reads.contains(&ResultKind::NonlinearCriticalSpeed) {
        // V_NL comes from the folds and the supercritical parts of the V_H curves
        curves.push(CurveKind::Fold.name().to_string());
    }
    let own = file.curve.clone();
    CurveSection {
        key: axis.key.clone(),
        from: Quantity::Number(axis.range.0),
        to: Quantity::Number(axis.range.1),
        spacing: Some(if axis.log { "log" } else { "linear" }.into()),
        curves: Some(curves),
        speed_range: None,
        max_points: own.as_ref().and_then(|c| c.max_points),
        max_step: own.as_ref().and_then(|c| c.max_step),
        seed_points: own.as_ref().and_then(|c| c.seed_points),
        fold_points: own.as_ref().and_then(|c| c.fold_points),
        rtol: own.as_ref().and_then(|c| c.rtol),
        // the trade verifies its best design with the sweep's one-point computation instead
        attractors: None,
    }
}

/// The results `tp` reads at key value `x`, by the sweep's one-point computation (V_NL only
/// when `nonlinear`).
fn point_at(
    study: &SweepStudy,
    tp: &TradePlan,
    x: f64,
    nonlinear: bool,
) -> crate::sweep::PointRecord {
    let reads = tp.read_results();
    let mut s = study.clone();
    s.spec.axes[0].values = vec![x];
    s.spec.compute = Compute {
        kalker: reads.contains(&ResultKind::KalkerCriticalSpeed),
        hopf: reads.contains(&ResultKind::HopfSpeed),
        nonlinear: nonlinear && reads.contains(&ResultKind::NonlinearCriticalSpeed),
    };
    crate::sweep::point::compute(&s, 0, &Spares::default())
}

/// The settlement at key value `x` ([`crate::trade::settle`]); a study or model that cannot be
/// built there becomes a settlement that says so (V_NL the one-point computation's).
fn settle_at(
    keyed: &KeyedStudy,
    on: &OnCurves,
    x: f64,
    curves_m_s: f64,
    one_point: Option<f64>,
) -> Settlement {
    let cycles = on.fold_cycles(x);
    let run = crate::trade::settle::settle_at(
        keyed,
        x,
        &cycles,
        curves_m_s,
        one_point,
        "the one-point computation",
    );
    run.unwrap_or_else(|e| Settlement {
        one_point_m_s: one_point,
        curves_m_s,
        checks: Vec::new(),
        nonlinear_m_s: one_point,
        confirmed: false,
        words: format!("not settled: {e}"),
        simulations: 0,
        bodies: Vec::new(),
    })
}

/// The curves of the trade.
fn curves(
    path: &Path,
    file: &StudyFile,
    axis: &KeyAxis,
    tp: &TradePlan,
) -> Result<(KeyedStudy, CurveReport, Vec<f64>), Failure> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| user(anyhow!("reading {}: {e}", path.display())))?;
    let keyed = KeyedStudy::new(&text, &path.display().to_string(), path.parent(), &axis.key)
        .map_err(curve_failure)?;
    let spec = crate::curve::resolve(&section(file, axis, tp), &keyed).map_err(curve_failure)?;
    let progress = |line: &str| statusln!("  {line}");
    let report = crate::curve::analyse_with_progress(&keyed, &spec, None, Some(&progress))
        .map_err(curve_failure)?;
    let grid = fold_grid(&spec, keyed.own_value());
    Ok((keyed, report, grid))
}

/// Runs the curve trade: writes trade.csv, trade.json and trade.svg, prints the summary (or
/// the JSON with `--json`).
pub(super) fn run(
    a: &TradeArgs,
    root: &Path,
    plan: &Plan,
    file: &StudyFile,
    tp: &TradePlan,
) -> Result<(), Failure> {
    if a.from_csv {
        return Err(user(anyhow!(
            "--from-csv: method = \"curve\" does not read sweep.csv (it computes curves over the sweep's key); drop --from-csv or use method = \"grid\""
        )));
    }
    let study = SweepStudy::load(&a.study).map_err(crate::api::sweep_failure)?;
    let axis = crate::trade::curve::key_axis(&study.spec, tp).map_err(user)?;
    let t0 = Instant::now();
    let (keyed, report, vnl_grid) = curves(&a.study, file, &axis, tp)?;
    statusln!(
        "curves over {}: {} curves in {:.2} s",
        axis.key,
        report.curves.len(),
        t0.elapsed().as_secs_f64()
    );
    let on = OnCurves {
        plan: tp,
        axis: &axis,
        report: &report,
        vnl_grid,
    };
    let linear = |x: f64| point_at(&study, tp, x, false);
    let whole = |x: f64| {
        statusln!("  one-point computation at {} = {x:e}", axis.key);
        let t = Instant::now();
        let r = point_at(&study, tp, x, true);
        let vnl = match (r.nonlinear_m_s, r.failures.is_empty()) {
            (Some(v), _) => format!("V_NL {v:.4} m/s"),
            (None, true) => "no V_NL".to_string(),
            (None, false) => format!("failed: {}", r.failures.join("; ")),
        };
        statusln!("  computed in {:.2} s: {vnl}", t.elapsed().as_secs_f64());
        r
    };
    let settle = |x: f64, curves_m_s: f64, one_point: Option<f64>| {
        statusln!(
            "  settling V_NL at {} = {x:e}: {curves_m_s:.3} m/s on the curves, {} by the one-point computation; simulating from the fold curves' cycles",
            axis.key,
            one_point.map_or("none".into(), |v| format!("{v:.3} m/s"))
        );
        let t = Instant::now();
        let s = settle_at(&keyed, &on, x, curves_m_s, one_point);
        statusln!(
            "  settled in {:.2} s: {}",
            t.elapsed().as_secs_f64(),
            s.words
        );
        s
    };
    let t1 = Instant::now();
    let trade = intervals::run(
        &on,
        &PointAt {
            linear: &linear,
            whole: &whole,
            settle: &settle,
        },
    );
    statusln!(
        "intervals, best design and its verification: {:.2} s",
        t1.elapsed().as_secs_f64()
    );
    let dir = out_dir(root, plan)?;
    write(
        &dir,
        "trade.csv",
        curve_report::csv(&axis, &trade).as_bytes(),
    )?;
    let mut j = curve_report::json(&plan.name, tp, &axis, &report, &trade);
    // how the verification's one-point V_NL was found (the sweep's method)
    let method = (tp
        .read_results()
        .contains(&ResultKind::NonlinearCriticalSpeed)
        && trade.verification.is_some())
    .then(|| crate::sweep::nonlinear_method(study.spec.attractors));
    if let (Some((name, _)), Some(v)) = (method, j.get_mut("verification")) {
        if let Some(o) = v.as_object_mut() {
            o.insert("nonlinear_method".into(), name.into());
        }
    }
    let text = serde_json::to_string_pretty(&j).map_err(compute)? + "\n";
    write(&dir, "trade.json", text.as_bytes())?;
    let fig = crate::figures::trade_curve(&plan.name, tp, &axis, &trade);
    write_figure(&dir, fig, "trade.csv and trade.json")?;
    if a.json {
        results(&text)?;
    } else {
        let mut text = curve_report::summary(&plan.name, tp, &axis, &report, &trade);
        if let Some((_, words)) = method {
            text.push_str(&format!("the verification's one-point V_NL: {words}\n"));
        }
        results(&text)?;
    }
    Ok(())
}
