//! One side of a Hopf curve: steps from a start point towards larger or smaller $P$ until a
//! bound, the step limit or a failure, with the codimension-two points on the way.
//!
//! **Test functions** at every point, each with a sign change at its special point:
//! - $l_1$ (where its sign is decided, [`crate::stability::HopfKind`]): a **generalised Hopf
//!   (Bautin)** point, where the Hopf point turns from super- to subcritical;
//! - the largest real part among the other complex pairs: a **double Hopf** point, where a
//!   second pair reaches the axis;
//! - $\det J$: a **zero-Hopf** point, where a real eigenvalue passes through 0 (the critical
//!   pair contributes $ω^2 > 0$ to $\det J$, every other complex pair $|λ|^2 > 0$);
//! - $ω$ itself: a **Bogdanov–Takens** point, where the pair meets at 0 and the Hopf curve
//!   ends; the curve is stopped when $ω$ has fallen below [`BT_FRACTION`] of its largest value
//!   and the point is extrapolated from the last two ($ω^2$ linear in arclength).
//!
//! A sign change between two points is located by the Illinois variant of regula falsi on
//! the arclength from the first point (each evaluation a corrector at that arclength), to
//! [`LOCATE_TOL`] of the step; a point is *located* when that converged, else *bracketed*.

use nalgebra::{DVector, SMatrix};

use super::family::HopfFamily;
use super::hopf::{advance, correct, scaled, tangent, Constraint, HopfParams, State, MAX_TURN};
use super::{CurveError, CurveStop, SpecialKind};
use crate::stability::{eigenvalues, HopfKind, Lyapunov};

/// ω below this fraction of the largest ω on the curve: a Bogdanov–Takens point is near.
pub const BT_FRACTION: f64 = 1e-3;
/// Location tolerance on the arclength, relative to the step.
pub const LOCATE_TOL: f64 = 1e-10;

/// What is known at one point of the curve besides the state.
#[derive(Clone, Debug)]
pub struct Evaluated {
    /// $l_1$ at the point
    pub l1: Option<Lyapunov>,
    /// $dσ/dV$ of the critical pair (1/m): positive at an onset
    pub rate: Option<f64>,
    /// largest real part of the other eigenvalues (1/s); −∞ when there are none
    pub others: f64,
    /// the other complex eigenvalue (Im > 0) with the largest real part: (re 1/s, im rad/s)
    pub second: Option<(f64, f64)>,
    /// $\det J$
    pub det: f64,
}

/// A point of the curve with its evaluation.
#[derive(Clone, Debug)]
pub struct TracedPoint<const N: usize> {
    pub state: State<N>,
    pub eval: Evaluated,
}

/// A special point found on one side.
#[derive(Clone, Debug)]
pub struct Found<const N: usize> {
    pub kind: SpecialKind,
    pub state: State<N>,
    pub eval: Option<Evaluated>,
    pub located: bool,
}

/// One side of a curve.
#[derive(Clone, Debug)]
pub struct Half<const N: usize> {
    pub points: Vec<TracedPoint<N>>,
    pub special: Vec<Found<N>>,
    pub stop: CurveStop,
    /// Newton iterations of the accepted correctors
    pub newton: usize,
    /// rejected steps
    pub rejected: usize,
}

/// The evaluation of `s`: eigenvalues, $\det J$, $l_1$ and the crossing rate.
pub fn evaluate<const N: usize, F: HopfFamily<N>>(
    family: &F,
    s: &State<N>,
) -> Result<Evaluated, CurveError> {
    let j = family.jacobian(s.v, s.p)?;
    let ev = eigenvalues(&j).ok_or(CurveError::Corrector {
        speed_m_s: s.v,
        parameter: family.value(s.p),
    })?;
    // the critical pair: the eigenvalues nearest ±iω
    let dist = |z: &(f64, f64), w: f64| z.0.hypot(z.1 - w);
    let nearest =
        |w: f64| (0..ev.len()).min_by(|&x, &y| dist(&ev[x], w).total_cmp(&dist(&ev[y], w)));
    let (up, down) = (nearest(s.omega), nearest(-s.omega));
    let others = (0..ev.len()).filter(|k| Some(*k) != up && Some(*k) != down);
    let max_re = others
        .clone()
        .map(|k| ev[k].0)
        .fold(f64::NEG_INFINITY, f64::max);
    let second = others
        .clone()
        .map(|k| ev[k])
        .filter(|z| z.1 > 0.0)
        .max_by(|x, y| x.0.total_cmp(&y.0));
    let det = crate::stability::determinant(&j);
    let l1 = family.lyapunov(s.v, s.p, s.omega);
    let jv = family.jacobian_v(s.v, s.p)?;
    let rate = match &l1 {
        Some(l) => Some(l.eigenvalue_rate(&jv)),
        None => rate_by_eigenvalues(family, s)?,
    };
    Ok(Evaluated {
        l1,
        rate,
        others: max_re,
        second,
        det,
    })
}

/// $dσ/dV$ from eigenvalues $10^{-6}V$ either side (when $l_1$'s eigenvectors are missing).
fn rate_by_eigenvalues<const N: usize, F: HopfFamily<N>>(
    family: &F,
    s: &State<N>,
) -> Result<Option<f64>, CurveError> {
    let h = 1e-6 * s.v.abs().max(1e-6);
    let re = |v: f64| -> Result<Option<f64>, CurveError> {
        let ev = eigenvalues(&family.jacobian(v, s.p)?);
        Ok(ev.and_then(|ev| {
            ev.into_iter()
                .filter(|z| z.1 > 0.0)
                .min_by(|x, y| {
                    x.0.hypot(x.1 - s.omega)
                        .total_cmp(&y.0.hypot(y.1 - s.omega))
                })
                .map(|z| z.0)
        }))
    };
    Ok(match (re(s.v + h)?, re(s.v - h)?) {
        (Some(a), Some(b)) => Some((a - b) / (2.0 * h)),
        _ => None,
    })
}

/// The value of a special point's test function, when it is defined; for detection ($l_1$
/// only where its sign is decided) or, inside a bracket, for location (any $l_1$).
fn test_value(kind: SpecialKind, e: &Evaluated, detect: bool) -> Option<f64> {
    match kind {
        SpecialKind::Bautin => {
            e.l1.as_ref()
                .filter(|l| !detect || l.kind() != HopfKind::Undecided)
                .map(|l| l.l1)
        }
        SpecialKind::DoubleHopf => e.second.map(|z| z.0),
        SpecialKind::ZeroHopf => Some(e.det),
        SpecialKind::BogdanovTakens
        | SpecialKind::Cusp
        | SpecialKind::FoldFlip
        | SpecialKind::FoldSymmetryBreaking
        | SpecialKind::FoldTorus => None,
    }
}

/// Everything one side of the walk needs.
struct Walk<'a, const N: usize, F> {
    family: &'a F,
    params: &'a HopfParams,
    cancel: Option<&'a (dyn Fn() -> bool + Sync)>,
}

impl<const N: usize, F: HopfFamily<N>> Walk<'_, N, F> {
    /// The point at scaled arclength `s` from `from` along `t`.
    fn at(
        &self,
        from: &State<N>,
        t: &DVector<f64>,
        jp: &SMatrix<f64, N, N>,
        s: f64,
    ) -> Result<(State<N>, usize), CurveError> {
        let guess = advance(from, t, s);
        let c = Constraint::Arclength {
            tangent: scaled(t, self.params),
            at: (guess.v, guess.p),
        };
        correct(self.family, &guess, from, c, jp, self.params).map(|r| (r.0.normalised(), r.1))
    }

    /// Locates the root of `kind`'s test function between `from` (value `f0`) and the point at
    /// arclength `ds` (value `f1`).
    fn locate(
        &self,
        kind: SpecialKind,
        from: &State<N>,
        t: &DVector<f64>,
        jp: &SMatrix<f64, N, N>,
        (ds, f0, f1): (f64, f64, f64),
    ) -> Found<N> {
        let (mut a, mut fa, mut b, mut fb) = (0.0, f0, ds, f1);
        let mut side = 0i8;
        let mut best: Option<(State<N>, Evaluated)> = None;
        for _ in 0..60 {
            if (b - a).abs() <= LOCATE_TOL * ds {
                break;
            }
            let c = (a * fb - b * fa) / (fb - fa);
            let c = if c.is_finite() && c > a.min(b) && c < a.max(b) {
                c
            } else {
                0.5 * (a + b)
            };
            let Ok((s, _)) = self.at(from, t, jp, c) else {
                break;
            };
            let Ok(e) = evaluate(self.family, &s) else {
                break;
            };
            let Some(fc) = test_value(kind, &e, false) else {
                break;
            };
            best = Some((s, e));
            if fc == 0.0 {
                (a, b) = (c, c);
                break;
            }
            if fc.signum() == fb.signum() {
                (b, fb) = (c, fc);
                if side == -1 {
                    fa *= 0.5;
                }
                side = -1;
            } else {
                (a, fa) = (c, fc);
                if side == 1 {
                    fb *= 0.5;
                }
                side = 1;
            }
        }
        let located = (b - a).abs() <= LOCATE_TOL * ds;
        match best {
            Some((state, eval)) => Found {
                kind,
                state,
                eval: Some(eval),
                located,
            },
            None => Found {
                kind,
                state: advance(from, t, 0.5 * ds),
                eval: None,
                located: false,
            },
        }
    }

    /// Sign changes of the test functions between two neighbouring points, located.
    fn specials(
        &self,
        prev: &TracedPoint<N>,
        next: &TracedPoint<N>,
        t: &DVector<f64>,
        jp: &SMatrix<f64, N, N>,
        ds: f64,
    ) -> Vec<Found<N>> {
        let mut out = Vec::new();
        for kind in [
            SpecialKind::Bautin,
            SpecialKind::DoubleHopf,
            SpecialKind::ZeroHopf,
        ] {
            let (Some(f0), Some(f1)) = (
                test_value(kind, &prev.eval, true),
                test_value(kind, &next.eval, true),
            ) else {
                continue;
            };
            if f0.signum() != f1.signum() && f0 != 0.0 {
                out.push(self.locate(kind, &prev.state, t, jp, (ds, f0, f1)));
            }
        }
        out
    }
}

/// Where the step from `a` to `b` leaves the box: the constraint of the end point and the
/// stop, or `None` when `b` is inside.
fn exit<const N: usize>(
    a: &State<N>,
    b: &State<N>,
    params: &HopfParams,
) -> Option<(Constraint, f64)> {
    let (plo, phi) = params.param_range;
    let (vlo, vhi) = params.speed_range;
    let frac = |x0: f64, x1: f64, bound: f64| (bound - x0) / (x1 - x0);
    let mut out: Option<(Constraint, f64)> = None;
    let mut consider = |c: Constraint, f: f64| {
        if f.is_finite() && (0.0..=1.0).contains(&f) && out.is_none_or(|o| f < o.1) {
            out = Some((c, f));
        }
    };
    if b.p > phi {
        consider(Constraint::Parameter(phi), frac(a.p, b.p, phi));
    }
    if b.p < plo {
        consider(Constraint::Parameter(plo), frac(a.p, b.p, plo));
    }
    if b.v > vhi {
        consider(Constraint::Speed(vhi), frac(a.v, b.v, vhi));
    }
    if b.v < vlo {
        consider(Constraint::Speed(vlo), frac(a.v, b.v, vlo));
    }
    out
}

/// Walks one side from `start` (a Hopf point, its eigenvector in `a`, `b`), first along the
/// direction of `direction`·P.
pub fn walk<const N: usize, F: HopfFamily<N>>(
    family: &F,
    start: &State<N>,
    direction: f64,
    params: &HopfParams,
    cancel: Option<&(dyn Fn() -> bool + Sync)>,
) -> Result<Half<N>, CurveError> {
    let w = Walk {
        family,
        params,
        cancel,
    };
    let r0 = start.clone().normalised();
    let mut jp = family.jacobian_p(r0.v, r0.p)?;
    let (s0, _) = correct(family, &r0, &r0, Constraint::Parameter(r0.p), &jp, params)?;
    let s0 = s0.normalised();
    jp = family.jacobian_p(s0.v, s0.p)?;
    let first = TracedPoint {
        eval: evaluate(family, &s0)?,
        state: s0,
    };
    let mut half = Half {
        points: vec![first],
        special: Vec::new(),
        stop: CurveStop::MaxPoints,
        newton: 0,
        rejected: 0,
    };
    let Some(mut t) = tangent(family, &half.points[0].state, &jp, (0.0, direction), params)? else {
        half.stop = CurveStop::Failed {
            message: "the curve is tangent to the speed axis at its start".into(),
        };
        return Ok(half);
    };
    let mut ds = params.ds_initial;
    let mut omega_max = half.points[0].state.omega.abs();
    half.stop = loop {
        if half.points.len() > params.max_points {
            break CurveStop::MaxPoints;
        }
        if w.cancel.is_some_and(|c| c()) {
            break CurveStop::Cancelled;
        }
        match step(&w, &mut half, &mut t, &mut jp, &mut ds, &mut omega_max) {
            Ok(None) => continue,
            Ok(Some(stop)) => break stop,
            Err(e) => {
                break CurveStop::Failed {
                    message: e.to_string(),
                }
            }
        }
    };
    Ok(half)
}

/// One accepted or rejected step; `Some(stop)` ends the side.
fn step<const N: usize, F: HopfFamily<N>>(
    w: &Walk<'_, N, F>,
    half: &mut Half<N>,
    t: &mut DVector<f64>,
    jp: &mut SMatrix<f64, N, N>,
    ds: &mut f64,
    omega_max: &mut f64,
) -> Result<Option<CurveStop>, CurveError> {
    let params = w.params;
    let last = half
        .points
        .last()
        .map(|p| p.state.clone())
        .ok_or(CurveError::Corrector {
            speed_m_s: f64::NAN,
            parameter: f64::NAN,
        })?;
    let shrink = |ds: &mut f64| -> Option<CurveStop> {
        *ds *= 0.5;
        (*ds < params.ds_min).then_some(CurveStop::StepTooSmall {
            parameter: w.family.value(last.p),
            speed_m_s: last.v,
        })
    };
    // a predictor outside the box: end on the bound (or stop, when already there)
    let guess = advance(&last, t, *ds);
    if let Some((c, frac)) = exit(&last, &guess, params) {
        if frac * *ds <= 1e-12 {
            return Ok(Some(bound_stop(w, c)));
        }
        return finish(w, half, &last, &guess, c, jp, t, *ds).map(Some);
    }
    let next = match w.at(&last, t, jp, *ds) {
        Ok((s, iterations)) => {
            half.newton += iterations;
            s
        }
        // a corrector that failed, or wandered to a key value without a valid model
        Err(CurveError::Corrector { .. } | CurveError::Model { .. }) => {
            half.rejected += 1;
            return Ok(shrink(ds));
        }
        Err(e) => return Err(e),
    };
    if let Some((c, _)) = exit(&last, &next, params) {
        return finish(w, half, &last, &next, c, jp, t, *ds).map(Some);
    }
    let new_jp = w.family.jacobian_p(next.v, next.p)?;
    let prev_dir = scaled(t, params);
    let Some(nt) = tangent(w.family, &next, &new_jp, prev_dir, params)? else {
        half.rejected += 1;
        return Ok(shrink(ds));
    };
    let turn = {
        let (a, b) = (prev_dir, scaled(&nt, params));
        (a.0 * b.0 + a.1 * b.1).clamp(-1.0, 1.0).acos()
    };
    if turn > MAX_TURN && *ds > 4.0 * params.ds_min {
        half.rejected += 1;
        return Ok(shrink(ds));
    }
    let point = TracedPoint {
        eval: evaluate(w.family, &next)?,
        state: next,
    };
    let found = half
        .points
        .last()
        .map(|prev| w.specials(prev, &point, t, jp, *ds))
        .unwrap_or_default();
    half.special.extend(found);
    *omega_max = omega_max.max(point.state.omega.abs());
    let bt = point.state.omega.abs() < BT_FRACTION * *omega_max;
    // back within half a step of the start, after going some way: a closed curve
    let closed = half.points.len() > 3 && {
        let (sv, sp) = params.scales();
        let s0 = &half.points[0].state;
        let d = ((point.state.v - s0.v) / sv).hypot((point.state.p - s0.p) / sp);
        d < 0.5 * *ds
    };
    half.points.push(point);
    if closed {
        return Ok(Some(CurveStop::Closed));
    }
    *t = nt;
    *jp = new_jp;
    *ds = (*ds * 1.5).min(params.ds_max);
    if bt {
        return Ok(Some(bogdanov_takens(w, half)));
    }
    Ok(None)
}

/// The step from `last` left the box: the end point on the bound, with the specials between.
#[allow(clippy::too_many_arguments)]
fn finish<const N: usize, F: HopfFamily<N>>(
    w: &Walk<'_, N, F>,
    half: &mut Half<N>,
    last: &State<N>,
    next: &State<N>,
    c: Constraint,
    jp: &SMatrix<f64, N, N>,
    t: &DVector<f64>,
    ds: f64,
) -> Result<CurveStop, CurveError> {
    let frac = exit(last, next, w.params).map_or(1.0, |e| e.1);
    let guess = advance(last, t, frac * ds);
    let (end, _) = correct(w.family, &guess, last, c, jp, w.params)?;
    let end = end.normalised();
    let point = TracedPoint {
        eval: evaluate(w.family, &end)?,
        state: end,
    };
    if let Some(prev) = half.points.last() {
        let found = w.specials(prev, &point, t, jp, frac * ds);
        half.special.extend(found);
    }
    half.points.push(point);
    Ok(bound_stop(w, c))
}

/// The stop at the bound of constraint `c`.
fn bound_stop<const N: usize, F: HopfFamily<N>>(w: &Walk<'_, N, F>, c: Constraint) -> CurveStop {
    match c {
        Constraint::Parameter(p) => CurveStop::ParameterBound {
            parameter: w.family.value(p),
        },
        Constraint::Speed(v) => CurveStop::SpeedBound { speed_m_s: v },
        Constraint::Arclength { .. } => CurveStop::MaxPoints,
    }
}

/// ω has nearly vanished: the Bogdanov–Takens point by extrapolating $ω^2$ linearly from the
/// last two points.
fn bogdanov_takens<const N: usize, F: HopfFamily<N>>(
    w: &Walk<'_, N, F>,
    half: &mut Half<N>,
) -> CurveStop {
    let n = half.points.len();
    let (a, b) = (&half.points[n - 2].state, &half.points[n - 1].state);
    let (wa, wb) = (a.omega * a.omega, b.omega * b.omega);
    let f = if wa != wb { wa / (wa - wb) } else { 1.0 };
    let mut s = b.clone();
    s.v = a.v + f * (b.v - a.v);
    s.p = a.p + f * (b.p - a.p);
    s.omega = 0.0;
    let stop = CurveStop::BogdanovTakens {
        parameter: w.family.value(s.p),
        speed_m_s: s.v,
    };
    half.special.push(Found {
        kind: SpecialKind::BogdanovTakens,
        state: s,
        eval: None,
        located: false,
    });
    stop
}
