//! A trade on curves (`[trade] method = "curve"`): the critical speeds the trade reads as
//! functions of the one swept key, from [`crate::curve`], instead of the sweep's grid points.
//!
//! - **Samples.** The Hopf results (V_L from Kalker's curves, V_H from the creep law's) are the
//!   lowest onset on their curves at a key value (linear interpolation in the key's axis
//!   between adjacent curve points, as the curves' stable band; `curve.max_step` keeps them
//!   dense), "above range" where no curve with a stable side below crosses the value, failed
//!   where the centred motion is unstable at the bottom of the speed range. V_NL is the
//!   curves' `nonlinear_critical_speed` points (at the fold grid's key values) and, between
//!   two adjacent ones, the lowest of the curves they lie on (the fold curve where a stable
//!   cycle ends, a supercritical stretch of V_H), interpolated between that curve's adjacent
//!   points; where neither curve has a candidate, linear interpolation between the two V_NL
//!   points; unknown across a grid value where V_NL is unknown. Each sample is
//!   a [`Row`], assessed by the grid method's own rules ([`super::select::infeasibility`]).
//! - **Intervals.** The feasible runs of samples; each end strictly inside the key's range is
//!   located between its two samples by the Illinois method (bisection where a side has no
//!   value) on the smallest relative margin of the constraints, evaluated by `truth`: the
//!   sweep's own one-point computation of V_L and V_H at that key value (the Hopf curve's
//!   point there, exactly: not an interpolation) and V_NL's interpolation. An end is the
//!   feasible side of the last bracket, within [`END_TOL`] of the key's axis span.
//! - **Best design.** The lowest (minimize) or highest (maximize) feasible key value: the
//!   outer end of the first or last interval.
//! - **Verification.** The whole one-point computation (V_NL by the whole diagram, as a sweep
//!   point) at the best value moved into its interval by [`NUDGE`] of the axis span (an end is
//!   where a speed equals its bound, so the end itself would test rounding), compared with the
//!   curves' prediction there.

use crate::curve::{CurveKind, CurveReport, StableSide};
use crate::study::units::Dimension;
use crate::study::StudyError;
use crate::sweep::{Computed, PointRecord, Spacing, SweepSpec};

pub use super::margin::{binding, locate, margin};
use super::table::Row;
use super::{ResultKind, Sense, Target, TradePlan};

/// Ends are located to this fraction of the key's axis span (in ln key on a log axis).
pub const END_TOL: f64 = 1e-12;
/// The verification moves the best value this fraction of the axis span into its interval
/// (at most half the interval).
pub const NUDGE: f64 = 1e-4;

/// The one swept key of a curve trade.
#[derive(Clone, Debug, PartialEq)]
pub struct KeyAxis {
    /// the study key
    pub key: String,
    /// its dimension (SI unit)
    pub dim: Dimension,
    /// `from` and `to` of the sweep axis (SI), lower first
    pub range: (f64, f64),
    /// logarithmic axis
    pub log: bool,
}

impl KeyAxis {
    /// The axis coordinate of a key value: ln x on a log axis.
    pub fn p(&self, x: f64) -> f64 {
        if self.log {
            x.ln()
        } else {
            x
        }
    }

    /// The key value of an axis coordinate.
    pub fn x(&self, p: f64) -> f64 {
        if self.log {
            p.exp()
        } else {
            p
        }
    }

    /// The span of the axis coordinate over the range.
    pub fn span_p(&self) -> f64 {
        (self.p(self.range.1) - self.p(self.range.0)).abs()
    }
}

/// Where a V_NL value comes from.
#[derive(Clone, Debug, PartialEq)]
pub enum VnlSource {
    /// V_NL is not read by the trade
    NotRead,
    /// a point of the curves' V_NL
    Point,
    /// linear interpolation between V_NL points at key values `a` and `b` (m/s `va`, `vb`)
    Between { a: f64, va: f64, b: f64, vb: f64 },
    /// between the V_NL points at `a` and `b`, the lowest of the curves V_NL lies on there
    /// (indices into the report's curves), interpolated between their adjacent points: the
    /// folds where a stable cycle ends, the supercritical stretches of V_H
    OnCurves {
        curves: Vec<usize>,
        a: f64,
        va: f64,
        b: f64,
        vb: f64,
    },
    /// not known here, and why
    Unknown(String),
}

/// A key value with the results the curves give there.
#[derive(Clone, Debug, PartialEq)]
pub struct Sample {
    /// key value (SI)
    pub x: f64,
    /// the results as a sweep row (the key as its one axis)
    pub row: Row,
    /// where V_NL comes from
    pub vnl: VnlSource,
}

/// The curves' results at any key value.
pub struct OnCurves<'a> {
    /// the trade
    pub plan: &'a TradePlan,
    /// the key
    pub axis: &'a KeyAxis,
    /// the curves
    pub report: &'a CurveReport,
    /// V_NL's key values where it should be known (the fold grid and the diagram's own value)
    pub vnl_grid: Vec<f64>,
}

fn computed(r: ResultKind) -> Computed {
    match r {
        ResultKind::KalkerCriticalSpeed => Computed::Kalker,
        ResultKind::HopfSpeed => Computed::Hopf,
        ResultKind::NonlinearCriticalSpeed => Computed::Nonlinear,
    }
}

/// A point's record as a trade row (the key as its one axis).
pub fn row_of(key: &str, x: f64, rec: &PointRecord) -> Row {
    Row {
        id: format!("{x:e}"),
        axes: vec![(key.to_string(), x)],
        results: [rec.kalker_m_s, rec.hopf_m_s, rec.nonlinear_m_s],
        status: rec.status(),
        above: Computed::ALL.map(|c| rec.above_range.contains(&c)),
        stable_up_to_m_s: rec.stable_up_to_m_s,
    }
}

impl OnCurves<'_> {
    /// The label of the curves a Hopf result is read from (`V_H` falls back to `V_L` for a
    /// study on Kalker's law, which has only those).
    fn label(&self, r: ResultKind) -> &'static str {
        let has_vh = self.report.stable_regions.iter().any(|s| s.label == "V_H");
        match r {
            ResultKind::HopfSpeed if has_vh => "V_H",
            _ => "V_L",
        }
    }

    /// The lowest onset at `x` on the curves labelled `label`: `Some(v)`, or `None` when no
    /// curve with a stable side below crosses `x` (no onset in the speed range).
    pub fn onset(&self, label: &str, x: f64) -> Option<f64> {
        let curves = self
            .report
            .curves
            .iter()
            .filter(|c| c.kind == CurveKind::Hopf && c.label == label);
        crate::curve::lowest_onset(curves, |v| self.axis.p(v), self.axis.p(x))
    }

    /// Whether the centred motion is unstable at the bottom of the speed range near `x`: the
    /// nearest sample of the curves' stable band says so.
    fn unstable_at_bottom(&self, label: &str, x: f64) -> bool {
        let p = self.axis.p(x);
        let region = self.report.stable_regions.iter().find(|s| s.label == label);
        let nearest = region.and_then(|s| {
            s.top.iter().min_by(|a, b| {
                (self.axis.p(a.0) - p)
                    .abs()
                    .total_cmp(&(self.axis.p(b.0) - p).abs())
            })
        });
        nearest.is_some_and(|t| t.1.is_nan())
    }

    /// V_NL at `x` from the curves' points.
    pub fn vnl(&self, x: f64) -> (Option<f64>, VnlSource) {
        let p = self.axis.p(x);
        let mut known: Vec<(f64, f64)> = self.report.nonlinear_critical_speed.clone();
        known.sort_by(|a, b| self.axis.p(a.0).total_cmp(&self.axis.p(b.0)));
        let close =
            |a: f64, b: f64| (self.axis.p(a) - self.axis.p(b)).abs() <= 1e-12 * self.axis.span_p();
        if let Some(&(_, v)) = known.iter().find(|k| close(k.0, x)) {
            return (Some(v), VnlSource::Point);
        }
        let pair = known
            .windows(2)
            .find(|w| self.axis.p(w[0].0) < p && p < self.axis.p(w[1].0));
        let Some(w) = pair else {
            let why = "outside the key values where the curves give V_NL".to_string();
            return (None, VnlSource::Unknown(why));
        };
        let ((a, va), (b, vb)) = (w[0], w[1]);
        let gap = self.vnl_grid.iter().find(|g| {
            let q = self.axis.p(**g);
            self.axis.p(a) < q && q < self.axis.p(b) && !close(**g, a) && !close(**g, b)
        });
        if let Some(g) = gap {
            let why = format!(
                "V_NL is unknown at {} = {g} between its points at {a} and {b}",
                self.axis.key
            );
            return (None, VnlSource::Unknown(why));
        }
        let mut curves: Vec<usize> = [(a, va), (b, vb)]
            .iter()
            .filter_map(|&(k, v)| self.curve_through(k, v))
            .collect();
        curves.dedup();
        let on = curves
            .iter()
            .filter_map(|&i| self.on_curve(i, x))
            .reduce(f64::min);
        if let Some(v) = on {
            return (
                Some(v),
                VnlSource::OnCurves {
                    curves,
                    a,
                    va,
                    b,
                    vb,
                },
            );
        }
        let t = (p - self.axis.p(a)) / (self.axis.p(b) - self.axis.p(a));
        (
            Some(va + t * (vb - va)),
            VnlSource::Between { a, va, b, vb },
        )
    }

    /// The curve V_NL = `v` at key value `k` lies on: a fold curve with a stable-side point
    /// there, or a V_H curve whose supercritical onset is `v` there.
    fn curve_through(&self, k: f64, v: f64) -> Option<usize> {
        let close =
            |a: f64, b: f64| (self.axis.p(a) - self.axis.p(b)).abs() <= 1e-12 * self.axis.span_p();
        self.report.curves.iter().enumerate().find_map(|(i, c)| {
            let hit = match c.kind {
                CurveKind::Fold => c.points.iter().any(|q| {
                    close(q.parameter, k)
                        && q.stable_cycle == Some(true)
                        && (q.speed_m_s - v).abs() <= 1e-7 * v.abs()
                }),
                CurveKind::Hopf if c.label == "V_H" => self
                    .on_curve(i, k)
                    .is_some_and(|s| (s - v).abs() <= 1e-7 * v.abs()),
                _ => false,
            };
            hit.then_some(i)
        })
    }

    /// The cycles of the fold curves at `x`: every fold curve with a stable-side stretch
    /// spanning `x`, its fold's speed there (linear in the key's axis between its adjacent
    /// points) and the nearer point's cycle state, lowest speed first.
    pub fn fold_cycles(&self, x: f64) -> Vec<super::settle::FoldCycle> {
        let p = self.axis.p(x);
        let mut out: Vec<super::settle::FoldCycle> = Vec::new();
        for (i, c) in self.report.curves.iter().enumerate() {
            if c.kind != CurveKind::Fold {
                continue;
            }
            let best = c
                .points
                .windows(2)
                .filter(|w| w[0].stable_cycle == Some(true) && w[1].stable_cycle == Some(true))
                .filter_map(|w| {
                    let (a, b) = (self.axis.p(w[0].parameter), self.axis.p(w[1].parameter));
                    if !(a.min(b) <= p && p <= a.max(b)) {
                        return None;
                    }
                    let t = if a != b { (p - a) / (b - a) } else { 0.0 };
                    let near = if t < 0.5 { &w[0] } else { &w[1] };
                    let v = w[0].speed_m_s + t * (w[1].speed_m_s - w[0].speed_m_s);
                    (!near.cycle_state.is_empty()).then_some((v, near))
                })
                .min_by(|a, b| a.0.total_cmp(&b.0));
            if let Some((v, near)) = best {
                out.push(super::settle::FoldCycle {
                    curve: i,
                    label: c.label.to_string(),
                    fold_m_s: v,
                    parameter: near.parameter,
                    state: near.cycle_state.clone(),
                });
            }
        }
        out.sort_by(|a, b| a.fold_m_s.total_cmp(&b.fold_m_s));
        out
    }

    /// The lowest V_NL candidate of curve `i` at `x`: on a fold curve, its segments between
    /// two stable-side folds; on a V_H curve, its segments between two supercritical onsets.
    fn on_curve(&self, i: usize, x: f64) -> Option<f64> {
        let c = self.report.curves.get(i)?;
        let p = self.axis.p(x);
        let usable = |q: &crate::curve::CurvePoint| match c.kind {
            CurveKind::Fold => q.stable_cycle == Some(true),
            _ => {
                q.stable_side == StableSide::Below
                    && q.hopf_type == Some(crate::stability::HopfKind::Supercritical)
            }
        };
        c.points
            .windows(2)
            .filter(|w| usable(&w[0]) && usable(&w[1]))
            .filter_map(|w| {
                let (a, b) = (self.axis.p(w[0].parameter), self.axis.p(w[1].parameter));
                if !(a.min(b) <= p && p <= a.max(b)) {
                    return None;
                }
                let t = if a != b { (p - a) / (b - a) } else { 0.0 };
                Some(w[0].speed_m_s + t * (w[1].speed_m_s - w[0].speed_m_s))
            })
            .reduce(f64::min)
    }

    /// The results the trade reads at `x`, from the curves.
    pub fn sample(&self, x: f64) -> Sample {
        let v_max = self.report.speed_range.1;
        let v_min = self.report.speed_range.0;
        let mut rec = PointRecord::empty(0, vec![x]);
        let mut vnl = VnlSource::NotRead;
        for r in self.plan.read_results() {
            let c = computed(r);
            if r == ResultKind::NonlinearCriticalSpeed {
                let (v, source) = self.vnl(x);
                match (v, &source) {
                    (Some(v), _) => rec.nonlinear_m_s = Some(v),
                    (None, VnlSource::Unknown(why)) => {
                        rec.failures.push(format!("nonlinear: {why}"))
                    }
                    (None, _) => rec.failures.push("nonlinear: unknown".into()),
                }
                vnl = source;
                continue;
            }
            let label = self.label(r);
            if self.unstable_at_bottom(label, x) {
                rec.failures.push(format!(
                    "{}: the centred motion is already unstable at {v_min} m/s ({label} curves' stable band)",
                    c.name()
                ));
                continue;
            }
            match (self.onset(label, x), c) {
                (Some(v), Computed::Kalker) => rec.kalker_m_s = Some(v),
                (Some(v), _) => rec.hopf_m_s = Some(v),
                (None, _) => {
                    rec.above_range.push(c);
                    rec.stable_up_to_m_s = Some(v_max);
                }
            }
        }
        rec.above_range.sort();
        Sample {
            x,
            row: row_of(&self.axis.key, x, &rec),
            vnl,
        }
    }

    /// The sample key values: the curves' stable-band values and V_NL's key values inside the
    /// axis range, sorted along the axis.
    pub fn sample_values(&self) -> Vec<f64> {
        let (lo, hi) = self.axis.range;
        let band = self
            .report
            .stable_regions
            .iter()
            .flat_map(|s| s.top.iter().map(|t| t.0));
        let vnl = self.report.nonlinear_critical_speed.iter().map(|t| t.0);
        let mut xs: Vec<f64> = band
            .chain(vnl)
            .chain([lo, hi])
            .filter(|x| x.is_finite() && (lo..=hi).contains(x))
            .collect();
        xs.sort_by(|a, b| self.axis.p(*a).total_cmp(&self.axis.p(*b)));
        let tol = 1e-12 * self.axis.span_p();
        xs.dedup_by(|a, b| (self.axis.p(*a) - self.axis.p(*b)).abs() <= tol);
        xs
    }
}

/// The key values where the curves give V_NL: `fold_points` values evenly spaced on the key's
/// axis, the ends as written (the fold grid of [`crate::curve`]), and the study's own value
/// when it lies in the range.
pub fn fold_grid(spec: &crate::curve::CurveSpec, own: Option<f64>) -> Vec<f64> {
    let to_p = |v: f64| if spec.log { v.ln() } else { v };
    let from_p = |p: f64| if spec.log { p.exp() } else { p };
    let n = spec.fold_points.max(2);
    let (p0, p1) = (to_p(spec.range.0), to_p(spec.range.1));
    let mut out: Vec<f64> = (0..n)
        .map(|i| match i {
            0 => spec.range.0,
            _ if i + 1 == n => spec.range.1,
            _ => from_p(p0 + (p1 - p0) * i as f64 / (n - 1) as f64),
        })
        .collect();
    let (a, b) = (
        spec.range.0.min(spec.range.1),
        spec.range.0.max(spec.range.1),
    );
    out.extend(own.filter(|v| (a..=b).contains(v)));
    out
}

/// The sweep's one axis, checked against a curve trade: one axis with a range, the objective
/// and every axis constraint on its key. Errors name key, value and rule.
pub fn key_axis(spec: &SweepSpec, tp: &TradePlan) -> Result<KeyAxis, StudyError> {
    let axes = &spec.axes;
    let [axis] = axes.as_slice() else {
        let keys: Vec<&str> = axes.iter().map(|a| a.key.as_str()).collect();
        return Err(rule(
            "trade.method",
            "\"curve\"",
            format!(
                "needs a [sweep] with exactly one axis (the curves' key); this one has {}: {}",
                axes.len(),
                keys.join(", ")
            ),
        ));
    };
    if tp.objective.key != axis.key {
        let which = match tp.objective.sense {
            Sense::Minimize => "trade.minimize",
            Sense::Maximize => "trade.maximize",
        };
        return Err(rule(
            which,
            format!("{:?}", tp.objective.key),
            format!(
                "with method = \"curve\" the objective must be the sweep's axis key {:?}",
                axis.key
            ),
        ));
    }
    for (i, c) in tp.constraints.iter().enumerate() {
        if let Target::Axis { key, .. } = &c.target {
            if *key != axis.key {
                return Err(rule(
                    &format!("trade.constraints[{i}].axis"),
                    format!("{key:?}"),
                    format!(
                        "with method = \"curve\" an axis constraint must be on the sweep's axis key {:?}",
                        axis.key
                    ),
                ));
            }
        }
    }
    let (a, b) = match (axis.values.first(), axis.values.last()) {
        (Some(a), Some(b)) => (*a, *b),
        _ => return Err(rule("sweep.axes[0]", "[]", "has no values")),
    };
    if a == b {
        return Err(rule(
            "sweep.axes[0].count",
            axis.values.len(),
            "with method = \"curve\" the axis needs a range (from ≠ to, count ≥ 2)",
        ));
    }
    Ok(KeyAxis {
        key: axis.key.clone(),
        dim: axis.dim,
        range: (a.min(b), a.max(b)),
        log: axis.spacing == Spacing::Log,
    })
}

fn rule(key: &str, value: impl std::fmt::Display, rule: impl std::fmt::Display) -> StudyError {
    StudyError::Rule {
        key: key.into(),
        value: value.to_string(),
        rule: rule.to_string(),
    }
}
