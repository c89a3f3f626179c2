//! The feasible intervals of a curve trade, their ends, the best design and its verification
//! (the definitions are in [`super::curve`]).

use super::curve::{binding, locate, margin, row_of, OnCurves, Sample, VnlSource, END_TOL, NUDGE};
use super::select::infeasibility;
use super::table::Row;
use super::{ResultKind, Sense, Target};
use crate::curve::SpecialKind;
use crate::sweep::PointRecord;

/// One end of a feasible interval.
#[derive(Clone, Debug, PartialEq)]
pub struct End {
    /// key value (SI)
    pub x: f64,
    /// how it was found, in words with the numbers
    pub how: String,
    /// the curves' estimate alone (linear interpolation of the constraint margin between the
    /// two samples), when both samples have one
    pub curve_estimate: Option<f64>,
    /// evaluations of the one-point computation spent on it
    pub evaluations: usize,
}

/// A run of feasible key values.
#[derive(Clone, Debug, PartialEq)]
pub struct Interval {
    /// lower end
    pub from: End,
    /// upper end
    pub to: End,
    /// what changes inside: V_NL's jumps, double Hopf points
    pub notes: Vec<String>,
}

/// The best design on the intervals.
#[derive(Clone, Debug, PartialEq)]
pub struct Best {
    /// key value (SI)
    pub x: f64,
    /// the interval it ends
    pub interval: usize,
    /// the curves' results there
    pub predicted: Row,
}

/// The verification's relative difference between the curves' V_NL and the one-point
/// computation's above which the disagreement is settled by simulation.
pub const DIFFER: f64 = 1e-3;

/// The best design recomputed by the one-point computation of a sweep.
#[derive(Clone, Debug, PartialEq)]
pub struct Verification {
    /// the key value computed (SI): the best moved into its interval
    pub x: f64,
    /// by how much and why, in words
    pub nudge: String,
    /// the curves' results at `x`
    pub predicted: Row,
    /// the one-point computation's results at `x`
    pub computed: Row,
    /// whether the computed results meet every constraint
    pub feasible: bool,
    /// why not (empty when feasible)
    pub reason: String,
    /// the computed results' smallest relative constraint margin
    pub margin: f64,
    /// where the curves' V_NL is lower than the one-point computation's: the fold cycles
    /// simulated ([`super::settle`]); feasibility and margin use its V_NL
    pub settlement: Option<super::settle::Settlement>,
    /// where that settled V_NL is below its bound: the best design moved inward to where the
    /// settled V_NL meets it
    pub settled: Option<SettledEnd>,
}

/// Everything a curve trade gives.
#[derive(Clone, Debug, PartialEq)]
pub struct CurveTrade {
    /// the samples and why each is infeasible (`None`: feasible)
    pub samples: Vec<(Sample, Option<String>)>,
    /// the feasible intervals, increasing in the key
    pub intervals: Vec<Interval>,
    /// the best design
    pub best: Option<Best>,
    /// its verification
    pub verification: Option<Verification>,
}

/// The two one-point computations a curve trade calls: the results the trade reads at a key
/// value, V_NL left out (`linear`, cheap, for the ends), and all of them (`whole`, for the
/// verification).
pub struct PointAt<'a> {
    /// V_L and V_H (as read) at a key value
    pub linear: &'a dyn Fn(f64) -> PointRecord,
    /// every result read, V_NL by the whole diagram
    pub whole: &'a dyn Fn(f64) -> PointRecord,
    /// the settlement at a key value, given the curves' V_NL and the one-point computation's
    /// ([`super::settle::settle`] on the curves' fold cycles there)
    pub settle: &'a dyn Fn(f64, f64, Option<f64>) -> super::settle::Settlement,
}

fn describe_binding(on: &OnCurves, row: &Row, x: f64) -> String {
    let plan = on.plan;
    let Some(i) = binding(plan, row) else {
        return "no constraint".into();
    };
    let c = &plan.constraints[i];
    match &c.target {
        Target::Axis { key, .. } => format!("the bound of {} ({})", key, c.text),
        Target::Result(ResultKind::NonlinearCriticalSpeed) => match on.vnl(x).1 {
            VnlSource::Between { a, va, b, vb } => format!(
                "{}: V_NL by linear interpolation between its points at {} = {a} ({va:.4} m/s) and {b} ({vb:.4} m/s)",
                c.text, on.axis.key
            ),
            VnlSource::OnCurves { curves, a, va, b, vb } => {
                let list: Vec<String> = curves.iter().map(|i| format!("{i}")).collect();
                format!(
                    "{}: V_NL along curve {} (linear interpolation between its adjacent points), between the V_NL points at {} = {a} ({va:.4} m/s) and {b} ({vb:.4} m/s)",
                    c.text,
                    list.join(" and "),
                    on.axis.key
                )
            }
            VnlSource::Point => format!("{}: at a V_NL point of the curves", c.text),
            _ => format!("{}: V_NL not known past this value", c.text),
        },
        Target::Result(r) => format!(
            "{}: located on the {} curve by the Illinois method on the first onset of the study rewritten at each key value (the sweep's linear analysis, which the curve's point there equals)",
            c.text,
            if *r == ResultKind::KalkerCriticalSpeed { "V_L" } else { "V_H" }
        ),
    }
}

/// The end between sample `good` (feasible) and `bad` (infeasible).
fn end(
    on: &OnCurves,
    truth: &dyn Fn(f64) -> Row,
    good: &(Sample, Option<String>),
    bad: &(Sample, Option<String>),
) -> End {
    let ax = on.axis;
    let (pg, pb) = (ax.p(good.0.x), ax.p(bad.0.x));
    let (mg, mb) = (margin(on.plan, &good.0.row), margin(on.plan, &bad.0.row));
    let curve_estimate = (mg.is_finite() && mb.is_finite() && mg != mb)
        .then(|| ax.x(pg + mg / (mg - mb) * (pb - pg)));
    let f = |p: f64| margin(on.plan, &truth(ax.x(p)));
    let (fg, fb) = (f(pg), f(pb));
    let tol = END_TOL * (ax.p(ax.range.1) - ax.p(ax.range.0)).abs();
    let (p, n) = if fg >= 0.0 && fb < 0.0 {
        locate(&f, (pg, fg), (pb, fb), tol)
    } else {
        // the one-point computation disagrees with the curves' samples about this bracket:
        // keep the feasible sample, and say so
        (pg, 0)
    };
    let x = ax.x(p);
    let row = truth(x);
    // past a sample without a value (a failure, V_NL unknown) the end is where the values stop
    let set_by = if mb == f64::NEG_INFINITY {
        "the last key value where every result the trade reads is known (bisection)".to_string()
    } else {
        describe_binding(on, &row, x)
    };
    let mut how = format!(
        "{set_by}; bracketed by the curve samples at {} = {} and {}",
        ax.key,
        super::curve_report::key_text(on.plan, good.0.x),
        super::curve_report::key_text(on.plan, bad.0.x)
    );
    if !(fg >= 0.0 && fb < 0.0) {
        how += &format!(
            "; the one-point computation does not confirm the bracket (margins {fg:.3e} and {fb:.3e}): the feasible sample is given"
        );
    }
    if let Some(why) = &bad.1 {
        how += &format!("; beyond it: {why}");
    }
    End {
        x,
        how,
        curve_estimate,
        evaluations: n + 3,
    }
}

fn range_end(x: f64) -> End {
    End {
        x,
        how: "the end of the sweep axis' range".into(),
        curve_estimate: Some(x),
        evaluations: 0,
    }
}

/// The notes of the curves about what changes between `from` and `to`.
fn interval_notes(on: &OnCurves, from: f64, to: f64) -> Vec<String> {
    let ax = on.axis;
    let inside = |x: f64| ax.p(from) <= ax.p(x) && ax.p(x) <= ax.p(to);
    let mut out = Vec::new();
    let reads_vnl = on
        .plan
        .read_results()
        .contains(&ResultKind::NonlinearCriticalSpeed);
    if reads_vnl {
        let mut known = on.report.nonlinear_critical_speed.clone();
        known.sort_by(|a, b| ax.p(a.0).total_cmp(&ax.p(b.0)));
        for w in known.windows(2) {
            // the curve report's own wording of the note
            let show = |v: f64| crate::curve::spec::show(&ax.key, on.report.dimension, v);
            let prefix = format!(
                "V_NL changes curve between {} and {}:",
                show(w[0].0),
                show(w[1].0)
            );
            let overlaps = ax.p(w[0].0) < ax.p(to) && ax.p(w[1].0) > ax.p(from);
            if overlaps {
                out.extend(
                    on.report
                        .notes
                        .iter()
                        .filter(|n| n.starts_with(&prefix))
                        .cloned(),
                );
            }
        }
    }
    for s in &on.report.special_points {
        if s.kind == SpecialKind::DoubleHopf && inside(s.parameter) {
            out.push(format!(
                "double Hopf point at {}, {:.3} m/s: two modes are critical there, the critical speed may change mode (a kink)",
                crate::curve::spec::show(&ax.key, on.report.dimension, s.parameter),
                s.speed_m_s
            ));
        }
    }
    out
}

/// The intervals, the best design and its verification.
pub fn run(on: &OnCurves, points: &PointAt) -> CurveTrade {
    let key = &on.axis.key;
    let reads_vnl = on
        .plan
        .read_results()
        .contains(&ResultKind::NonlinearCriticalSpeed);
    let truth = |x: f64| {
        let mut rec = (points.linear)(x);
        if reads_vnl {
            let (v, source) = on.vnl(x);
            rec.nonlinear_m_s = v;
            if let (None, VnlSource::Unknown(why)) = (v, source) {
                rec.failures.push(format!("nonlinear: {why}"));
            }
        }
        row_of(key, x, &rec)
    };
    let samples: Vec<(Sample, Option<String>)> = on
        .sample_values()
        .into_iter()
        .map(|x| {
            let s = on.sample(x);
            let why = infeasibility(on.plan, &s.row);
            (s, why)
        })
        .collect();
    let mut intervals = Vec::new();
    let mut i = 0;
    while i < samples.len() {
        if samples[i].1.is_some() {
            i += 1;
            continue;
        }
        let mut j = i;
        while j + 1 < samples.len() && samples[j + 1].1.is_none() {
            j += 1;
        }
        let from = match i {
            0 => range_end(samples[0].0.x),
            _ => end(on, &truth, &samples[i], &samples[i - 1]),
        };
        let to = if j + 1 == samples.len() {
            range_end(samples[j].0.x)
        } else {
            end(on, &truth, &samples[j], &samples[j + 1])
        };
        let notes = interval_notes(on, from.x, to.x);
        intervals.push(Interval { from, to, notes });
        i = j + 1;
    }
    let best = best(on, &intervals);
    let verification = best
        .as_ref()
        .map(|b| verify(on, points, &intervals[b.interval], b));
    CurveTrade {
        samples,
        intervals,
        best,
        verification,
    }
}

fn best(on: &OnCurves, intervals: &[Interval]) -> Option<Best> {
    let (interval, x) = match on.plan.objective.sense {
        Sense::Minimize => intervals.first().map(|i| (0, i.from.x))?,
        Sense::Maximize => intervals.last().map(|i| (intervals.len() - 1, i.to.x))?,
    };
    Some(Best {
        x,
        interval,
        predicted: on.sample(x).row,
    })
}

fn verify(on: &OnCurves, points: &PointAt, interval: &Interval, b: &Best) -> Verification {
    let ax = on.axis;
    let at_range_end = interval_end_is_range(interval, b.x, on.plan.objective.sense);
    let width = (ax.p(interval.to.x) - ax.p(interval.from.x)).abs();
    let step = if at_range_end {
        0.0
    } else {
        (NUDGE * ax.span_p()).min(0.5 * width)
    };
    let inward = match on.plan.objective.sense {
        Sense::Minimize => 1.0,
        Sense::Maximize => -1.0,
    };
    let x = ax.x(ax.p(b.x) + inward * step);
    let nudge = if at_range_end {
        "none: the best value is an end of the sweep axis' range, not a constraint's bound".into()
    } else {
        format!(
            "moved into the interval by {step:.3e} of the {} axis ({} of its span, at most half the interval), since at the end itself a speed equals its bound",
            if ax.log { "ln-key" } else { "key" },
            NUDGE
        )
    };
    let computed = row_of(&ax.key, x, &(points.whole)(x));
    let predicted = on.sample(x).row;
    let vnl = ResultKind::NonlinearCriticalSpeed;
    let one_point = computed.result(vnl);
    let settlement = settle_if_lower(on, points, x, &predicted, one_point);
    let judged = judged_row(&computed, settlement.as_ref());
    let reason = infeasibility(on.plan, &judged);
    let feasible = reason.is_none();
    let lower_by_one_point = matches!(
        (one_point, predicted.result(vnl)),
        (Some(c), Some(p)) if c < p * (1.0 - DIFFER)
    );
    // a judged V_NL below the bound: the interval's end moves inward to where it meets it, by
    // simulation where the settlement lowered V_NL, by one-point computations where the
    // one-point computation itself was the lower
    let settled = if feasible || !on.plan.read_results().contains(&vnl) {
        None
    } else if settlement
        .as_ref()
        .and_then(|st| st.nonlinear_m_s)
        .is_some_and(|v| one_point.is_none_or(|o| v < o))
    {
        let judge = |x: f64| {
            let curves = on
                .sample(x)
                .row
                .result(vnl)
                .or(one_point)
                .unwrap_or(f64::NAN);
            let st = (points.settle)(x, curves, one_point);
            let mut row = computed.clone();
            row.axes = vec![(ax.key.clone(), x)];
            let row = judged_row(&row, Some(&st));
            Judged {
                margin: margin(on.plan, &row),
                nonlinear_m_s: row.result(vnl),
                settlement: Some(st),
                computed: None,
            }
        };
        Some(settled_end(
            on,
            interval,
            x,
            margin(on.plan, &judged),
            Inward::Simulation,
            &judge,
        ))
    } else if lower_by_one_point {
        let judge = |x: f64| {
            let row = row_of(&ax.key, x, &(points.whole)(x));
            let st = settle_if_lower(on, points, x, &on.sample(x).row, row.result(vnl));
            let j = judged_row(&row, st.as_ref());
            Judged {
                margin: margin(on.plan, &j),
                nonlinear_m_s: j.result(vnl),
                settlement: st,
                computed: Some(row),
            }
        };
        Some(settled_end(
            on,
            interval,
            x,
            margin(on.plan, &judged),
            Inward::OnePoint,
            &judge,
        ))
    } else {
        None
    };
    Verification {
        x,
        nudge,
        predicted,
        margin: margin(on.plan, &judged),
        feasible,
        reason: reason.unwrap_or_default(),
        computed,
        settlement,
        settled,
    }
}

/// Where the curves' V_NL at `x` is lower than the one-point computation's (beyond
/// [`DIFFER`]), the disagreement settled by simulating the curves' fold cycles there.
fn settle_if_lower(
    on: &OnCurves,
    points: &PointAt,
    x: f64,
    predicted: &Row,
    one_point: Option<f64>,
) -> Option<super::settle::Settlement> {
    let vnl = ResultKind::NonlinearCriticalSpeed;
    match predicted.result(vnl) {
        Some(p)
            if on.plan.read_results().contains(&vnl)
                && one_point.is_none_or(|c| c > p * (1.0 + DIFFER)) =>
        {
            Some((points.settle)(x, p, one_point))
        }
        _ => None,
    }
}

/// The one-point computation's row with V_NL replaced by the settlement's, where there is one.
fn judged_row(computed: &Row, settlement: Option<&super::settle::Settlement>) -> Row {
    let mut judged = computed.clone();
    let vnl = ResultKind::NonlinearCriticalSpeed;
    if let (Some(v), Some(i)) = (
        settlement.and_then(|s| s.nonlinear_m_s),
        ResultKind::ALL.iter().position(|k| *k == vnl),
    ) {
        judged.results[i] = Some(v);
    }
    judged
}

/// How the best design was moved inward.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Inward {
    /// the curves' fold cycles simulated at each key value ([`super::settle`]), the
    /// verification's one-point V_NL taken to hold nearby: the curves' V_NL was the lower one
    Simulation,
    /// the sweep's one-point computation (the whole diagram and, where the sweep uses it, the
    /// attractor search) at each key value: its V_NL was the lower one, below the bound
    OnePoint,
}

impl Inward {
    /// For JSON: `"simulation"` or `"one-point"`.
    pub fn name(self) -> &'static str {
        match self {
            Inward::Simulation => "simulation",
            Inward::OnePoint => "one-point",
        }
    }
}

/// The best design moved inward to where its judged V_NL (settled by simulation, or by the
/// one-point computation where that is the lower) meets its bound.
#[derive(Clone, Debug, PartialEq)]
pub struct SettledEnd {
    /// the key value (SI), on the feasible side; `None` when the judged V_NL stays below its
    /// bound across the interval
    pub x: Option<f64>,
    /// how each key value on the way was judged
    pub by: Inward,
    /// the judged V_NL there (m/s)
    pub nonlinear_m_s: Option<f64>,
    /// the settlement there (by [`Inward::Simulation`], or where the curves were lower there)
    pub settlement: Option<super::settle::Settlement>,
    /// the one-point computation's results there (by [`Inward::OnePoint`])
    pub computed: Option<Row>,
    /// that design's smallest relative constraint margin
    pub margin: f64,
    /// key values judged (settlements, or one-point computations)
    pub evaluations: usize,
    /// how it was found, in words
    pub how: String,
}

/// Relative to the key axis' span: the first step inward from an infeasible verification, and
/// the width to which the settled end is located.
pub const SETTLED_STEP: f64 = 5e-3;
/// See [`SETTLED_STEP`].
pub const SETTLED_TOL: f64 = 5e-4;

/// A design judged at one key value on the way inward ([`settled_end`]).
struct Judged {
    margin: f64,
    nonlinear_m_s: Option<f64>,
    settlement: Option<super::settle::Settlement>,
    computed: Option<Row>,
}

/// Where the judged V_NL meets the bound, inward from the infeasible `x0` (margin `m0`), each
/// key value judged by `judge` (simulation of the curves' fold cycles, or one-point
/// computations, as `by` says): steps of [`SETTLED_STEP`] of the axis span, doubling, to a
/// feasible value (at most to the interval's other end), then the Illinois method to
/// [`SETTLED_TOL`] of the span.
fn settled_end(
    on: &OnCurves,
    interval: &Interval,
    x0: f64,
    m0: f64,
    by: Inward,
    judge: &dyn Fn(f64) -> Judged,
) -> SettledEnd {
    let ax = on.axis;
    let inward = match on.plan.objective.sense {
        Sense::Minimize => 1.0,
        Sense::Maximize => -1.0,
    };
    let far = match on.plan.objective.sense {
        Sense::Minimize => interval.to.x,
        Sense::Maximize => interval.from.x,
    };
    let (p0, p_far) = (ax.p(x0), ax.p(far));
    let done = std::cell::RefCell::new(Vec::<(f64, Judged)>::new());
    let f = |p: f64| {
        let j = judge(ax.x(p));
        let m = j.margin;
        done.borrow_mut().push((p, j));
        m
    };
    let what = match by {
        Inward::Simulation => "settlements",
        Inward::OnePoint => "one-point computations",
    };
    let judged_v = match by {
        Inward::Simulation => "settled V_NL",
        Inward::OnePoint => "one-point computation's V_NL",
    };
    let mut step = SETTLED_STEP * ax.span_p();
    let mut bad = (p0, m0);
    let mut good = None;
    loop {
        let p = (p0 + inward * step).clamp(p0.min(p_far), p0.max(p_far));
        let m = f(p);
        if m >= 0.0 {
            good = Some((p, m));
            break;
        }
        bad = (p, m);
        if p == p_far {
            break;
        }
        step *= 2.0;
    }
    let Some(good) = good else {
        let mut list = done.into_inner();
        let n = list.len();
        let last = list.pop().map(|d| d.1);
        return SettledEnd {
            x: None,
            by,
            nonlinear_m_s: last.as_ref().and_then(|j| j.nonlinear_m_s),
            settlement: last.as_ref().and_then(|j| j.settlement.clone()),
            computed: last.and_then(|j| j.computed),
            margin: bad.1,
            evaluations: n,
            how: format!(
                "the {judged_v} stays below its bound from {x0:e} to the interval's other end {far:e} ({n} {what}): no design of this interval is confirmed feasible"
            ),
        };
    };
    let (p, _) = locate(&f, good, bad, SETTLED_TOL * ax.span_p());
    let list = done.into_inner();
    let n = list.len();
    // the infeasible value judged nearest the feasible end: the bracket's other side
    let beyond = list
        .iter()
        .filter(|d| d.1.margin < 0.0)
        .map(|d| d.0)
        .chain(std::iter::once(p0))
        .min_by(|a, b| (a - p).abs().total_cmp(&(b - p).abs()))
        .unwrap_or(bad.0);
    let there = list.into_iter().rev().find(|d| d.0 == p).map(|d| d.1);
    SettledEnd {
        x: Some(ax.x(p)),
        by,
        nonlinear_m_s: there.as_ref().and_then(|j| j.nonlinear_m_s),
        margin: there.as_ref().map_or(f64::NAN, |j| j.margin),
        settlement: there.as_ref().and_then(|j| j.settlement.clone()),
        computed: there.and_then(|j| j.computed),
        evaluations: n,
        how: format!(
            "the {judged_v} meets its bound between {:e} and {:e} ({n} {what}: steps inward from the verification's value, then the Illinois method to {SETTLED_TOL} of the {} axis span); the feasible side is given",
            ax.x(p),
            ax.x(beyond),
            if ax.log { "ln-key" } else { "key" }
        ),
    }
}

fn interval_end_is_range(i: &Interval, x: f64, sense: Sense) -> bool {
    let e = match sense {
        Sense::Minimize => &i.from,
        Sense::Maximize => &i.to,
    };
    e.x == x && e.evaluations == 0 && e.how.starts_with("the end of the sweep axis")
}
