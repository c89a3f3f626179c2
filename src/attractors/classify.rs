//! One motion at one speed: simulate from a start until it settles, then say what it settled
//! on (docs/model.md §12's attractor classes).
//!
//! The trajectory is cut by the Poincaré section $y_1 = 0$, $\dot y_1 > 0$ of the leading
//! wheelset ([`integrate_sections`]). After each return:
//!
//! * **equilibrium** when every body's lateral excursion (a wheelset's $y$, a frame's or car
//!   body's $y$ and the ends' $y ± aψ$) since the last return is below the threshold;
//! * **out of range** when a wheelset leaves the contact geometry's range (unless the study
//!   extrapolates);
//! * **periodic** when the section points repeat with some period k ≤ `max_period` (two
//!   successive returns k apart within 1e-3, scaled by each component's swing): the cycle
//!   is then solved exactly by Newton on the shooting problem (symmetric half-period form when
//!   the motion's sides agree, else k whole periods) and accepted when Newton converges to a
//!   **stable** cycle; its period, amplitudes and multipliers are the exact cycle's, not the
//!   simulation's;
//! * at the time limit, a motion that still has not settled is **decaying** (its amplitude fell
//!   to less than half over the second half of the run, steadily: the centred motion is the
//!   attractor, reached slowly), **quasi-periodic** or **chaotic** by the largest Lyapunov
//!   exponent from the variational equations along the orbit (chaotic when a perturbation grows
//!   by more than 1 % per mean return time), provided the section points recur (the motion
//!   comes back near where it was); else **unsettled** (a slow transient, e.g. through the
//!   bottleneck just below a fold of cycles).

use std::ops::ControlFlow;

use nalgebra::SVector;

use super::{BodyAmplitude, Motion, MotionKind};
use crate::bifurcation::solve_cycle;
use crate::model::{BodyKind, Vehicle};
use crate::system::ode::{
    integrate_sections, integrate_tangent, integrate_with_extremes, OdeOptions, Return, StopReason,
    TangentControl, Tolerances,
};

/// What the classification needs besides the model.
#[derive(Clone, Copy, Debug)]
pub struct Settle {
    /// the longest simulated time (s)
    pub max_time: f64,
    /// equilibrium threshold on every body's lateral excursion (m)
    pub threshold: f64,
    /// largest period, in section returns, recognised as periodic
    pub max_period: usize,
    /// the contact geometry's half-width (m), `None`: no limit
    pub geometry_limit: Option<f64>,
    /// integrator relative tolerance of the simulation
    pub rtol: f64,
    /// relative tolerance of the Newton-refined cycles
    pub cycle_rtol: f64,
}

/// Scaled distance between two section points: each component against its swing over the
/// last return (with a floor, so that a component at rest does not dominate).
fn distance<const N: usize>(
    a: &SVector<f64, N>,
    b: &SVector<f64, N>,
    swing: &SVector<f64, N>,
) -> f64 {
    (0..N)
        .map(|i| (a[i] - b[i]).abs() / swing[i].max(1e-9))
        .fold(0.0, f64::max)
}

/// Lateral excursion of every body over an interval with extremes `high`, `low`: |y| of its
/// centre and of its ends y ± arm·ψ (bounded by |y| + arm·|ψ|), and the wheelsets' |y| alone.
fn excursions<const N: usize>(
    model: &Vehicle,
    high: &SVector<f64, N>,
    low: &SVector<f64, N>,
) -> (f64, f64) {
    let (a, lb) = model.layout_arms();
    let l0 = model.contact.params.half_contact_distance;
    let mut all: f64 = 0.0;
    let mut wheelsets: f64 = 0.0;
    for b in &model.bodies {
        let y = high[b.dof].abs().max(low[b.dof].abs());
        let psi = high[b.dof + 1].abs().max(low[b.dof + 1].abs());
        let arm = match b.kind {
            BodyKind::Wheelset => l0,
            BodyKind::Frame => a,
            BodyKind::CarBody => lb,
        };
        all = all.max(y + arm * psi);
        if b.kind == BodyKind::Wheelset {
            wheelsets = wheelsets.max(y);
        }
    }
    (all, wheelsets)
}

/// Each body's amplitudes over an interval.
pub fn body_amplitudes<const N: usize>(
    model: &Vehicle,
    high: &SVector<f64, N>,
    low: &SVector<f64, N>,
) -> Vec<BodyAmplitude> {
    model
        .bodies
        .iter()
        .map(|b| BodyAmplitude {
            y_right_m: high[b.dof],
            y_left_m: -low[b.dof],
            psi_rad: high[b.dof + 1].abs().max(low[b.dof + 1].abs()),
        })
        .collect()
}

fn ode(rtol: f64) -> OdeOptions {
    OdeOptions {
        tol: Tolerances {
            rtol,
            atol: rtol * 1e-3,
        },
        ..OdeOptions::default()
    }
}

/// Classifies the motion of `model` at `speed` from `x0`.
pub fn classify<const N: usize>(
    model: &Vehicle,
    speed: f64,
    x0: &SVector<f64, N>,
    s: &Settle,
) -> Motion {
    let section = |x: &SVector<f64, N>| x[0];
    let mut returns: Vec<Return<N>> = Vec::new();
    let mut verdict: Option<Motion> = None;
    let mut newton_after = 0usize;
    let mut on_return = |r: &Return<N>| {
        returns.push(r.clone());
        let n = returns.len();
        let (all, wheelsets) = excursions(model, &r.high, &r.low);
        if all < s.threshold {
            verdict = Some(Motion::simple(MotionKind::Equilibrium, speed, r.t));
            return ControlFlow::Break(());
        }
        // out of range: three returns in a row beyond the geometry's range, not coming back
        // (a transient from a large kick may pass beyond it and return)
        if let Some(g) = s.geometry_limit {
            let beyond = |q: &Return<N>| excursions(model, &q.high, &q.low).1;
            if n >= 3 && returns[n - 3..].iter().all(|q| beyond(q) > g) {
                let (e0, e2) = (beyond(&returns[n - 3]), wheelsets);
                if e2 >= 0.99 * e0 || n >= 12 {
                    let mut m = Motion::simple(MotionKind::OutOfRange, speed, r.t);
                    m.excursion_m = wheelsets;
                    verdict = Some(m);
                    return ControlFlow::Break(());
                }
            }
        }
        // the first returns are the transient from the kick
        if n < 4 || n < newton_after {
            return ControlFlow::Continue(());
        }
        let swing = r.high - r.low;
        for k in 1..=s.max_period {
            if n < 2 * k + 2 {
                break;
            }
            let d1 = distance(&returns[n - 1].x, &returns[n - 1 - k].x, &swing);
            let d2 = distance(&returns[n - 2].x, &returns[n - 2 - k].x, &swing);
            if d1 < 1e-3 && d2 < 1e-3 {
                // the extremes over the last k returns: whether the sides agree
                let (mut hi, mut lo) = (returns[n - k].high, returns[n - k].low);
                for q in &returns[n - k + 1..n] {
                    hi = hi.sup(&q.high);
                    lo = lo.inf(&q.low);
                }
                let period = returns[n - 1].t - returns[n - 1 - k].t;
                if let Some(m) = refine(model, speed, &returns[n - 1].x, period, k, &hi, &lo, s) {
                    verdict = Some(Motion { time_s: r.t, ..m });
                    return ControlFlow::Break(());
                }
                // not (yet) a stable cycle: look again later
                newton_after = n + 10 + n / 2;
                break;
            }
        }
        ControlFlow::Continue(())
    };
    let end = integrate_sections(
        model,
        speed,
        x0,
        s.max_time,
        &section,
        &ode(s.rtol),
        &mut on_return,
    );
    if let Some(v) = verdict {
        return v;
    }
    let time = end.as_ref().map_or(0.0, |e| e.t);
    match end {
        Ok(e) if e.stop != StopReason::Reached => {
            let mut m = Motion::simple(MotionKind::Diverged, speed, time);
            m.note = format!("the integration stopped: {:?}", e.stop);
            return m;
        }
        Err(e) => {
            let mut m = Motion::simple(MotionKind::Diverged, speed, time);
            m.note = e.to_string();
            return m;
        }
        Ok(_) => {}
    }
    let (last_high, last_low) = returns.last().map_or((*x0, *x0), |r| (r.high, r.low));
    unsettled(model, speed, &returns, (&last_high, &last_low), s, time)
}

/// Newton on the cycle through section point `x` with period `period` (k returns); `Some` when
/// it converges to a stable cycle.
#[allow(clippy::too_many_arguments)]
fn refine<const N: usize>(
    model: &Vehicle,
    speed: f64,
    x: &SVector<f64, N>,
    period: f64,
    k: usize,
    hi: &SVector<f64, N>,
    lo: &SVector<f64, N>,
    s: &Settle,
) -> Option<Motion> {
    // returns that repeat after k > 1 may be a cycle of one return still converging along a
    // multiplier near a k-th root of unity (Newton over k periods would then find it, run k
    // times, and call it period k): the cycle of one return through x, when it is stable and
    // passes within 1 % of x, is the motion
    if k > 1 {
        if let Some(m) = refine(model, speed, x, period / k as f64, 1, hi, lo, s) {
            let close = m.state.len() == N
                && (0..N)
                    .map(|i| (m.state[i] - x[i]).powi(2))
                    .sum::<f64>()
                    .sqrt()
                    <= 0.01 * x.norm().max(1e-12);
            if close {
                return Some(m);
            }
        }
    }
    let x0: [f64; N] = std::array::from_fn(|i| x[i]);
    // the sides of a symmetric motion agree: then the half-period form (exact symmetry)
    let sides = (0..N)
        .map(|i| (hi[i] + lo[i]).abs() / (hi[i] - lo[i]).abs().max(1e-12))
        .fold(0.0, f64::max);
    let try_symmetric = k == 1 && sides < 1e-2;
    let solved = if try_symmetric {
        solve_cycle(model, speed, x0, period, s.cycle_rtol, true)
            .ok()
            .map(|c| (c, true))
            .or_else(|| {
                solve_cycle(model, speed, x0, period, s.cycle_rtol, false)
                    .ok()
                    .map(|c| (c, false))
            })
    } else {
        solve_cycle(model, speed, x0, period, s.cycle_rtol, false)
            .ok()
            .map(|c| (c, false))
    };
    let ((orbit, floquet, _), symmetric) = solved?;
    if !floquet.stable() || (orbit.period - period).abs() > 0.05 * period {
        return None;
    }
    // the exact cycle's extremes, over one whole period
    let (_, high, low) =
        integrate_with_extremes(model, speed, &orbit.x0, orbit.period, &ode(s.cycle_rtol)).ok()?;
    // a cycle solved without the symmetry may still be symmetric (its transient's sides
    // differed when Newton started): then its exact extremes are opposite, max = −min, in
    // every component that moves
    let opposite = (0..N).all(|i| {
        let swing = high[i] - low[i];
        swing <= 1e-12 || (high[i] + low[i]).abs() <= 1e-6 * swing
    });
    let symmetric = symmetric || (k == 1 && opposite);
    let kind = match (k, symmetric) {
        (1, true) => MotionKind::SymmetricCycle,
        (1, false) => MotionKind::AsymmetricCycle,
        (k, _) => MotionKind::PeriodK(k),
    };
    let (_, wheelsets) = excursions(model, &high, &low);
    Some(Motion {
        kind,
        speed_m_s: speed,
        period_s: Some(orbit.period),
        amplitudes: body_amplitudes(model, &high, &low),
        excursion_m: wheelsets,
        max_multiplier: Some(floquet.max_nontrivial),
        lyapunov_per_s: None,
        state: orbit.x0.iter().copied().collect(),
        time_s: 0.0,
        note: String::new(),
    })
}

/// The verdict on a motion that reached the time limit without settling.
fn unsettled<const N: usize>(
    model: &Vehicle,
    speed: f64,
    returns: &[Return<N>],
    last: (&SVector<f64, N>, &SVector<f64, N>),
    s: &Settle,
    time: f64,
) -> Motion {
    let n = returns.len();
    let amp = |r: &Return<N>| excursions(model, &r.high, &r.low).0;
    let state: Vec<f64> = returns
        .last()
        .map_or_else(Vec::new, |r| r.x.iter().copied().collect());
    if n < 8 {
        let mut m = Motion::simple(MotionKind::Unsettled, speed, time);
        m.note = format!("{n} returns to the section in {time:.1} s");
        m.state = state;
        return m;
    }
    let half = &returns[n / 2..];
    let a_mid = amp(&half[0]);
    let a_end = amp(&returns[n - 1]);
    let steady_decay = half
        .windows(2)
        .all(|w| amp(&w[1]) <= amp(&w[0]) * (1.0 + 1e-9));
    if steady_decay && a_end < 0.5 * a_mid {
        let mut m = Motion::simple(MotionKind::Equilibrium, speed, time);
        m.note = format!(
            "decaying: {:.3e} m after {time:.1} s, {:.3e} m half-way",
            a_end, a_mid
        );
        return m;
    }
    // recurrence: the last section point comes back near one of the second half's earlier
    // ones (a closed curve or a strange attractor), not a drift away
    let swing = last.0 - last.1;
    let steps: Vec<f64> = half
        .windows(2)
        .map(|w| distance(&w[1].x, &w[0].x, &swing))
        .collect();
    let typical = steps.iter().copied().fold(0.0, f64::max);
    let recurs = half[..half.len().saturating_sub(10)]
        .iter()
        .any(|r| distance(&r.x, &returns[n - 1].x, &swing) < 0.2 * typical.max(1e-6));
    // a slow drift (a cycle next to a fold, a bottleneck) changes its amplitude one way only
    let amps: Vec<f64> = half.iter().map(amp).collect();
    let monotone = amps.windows(2).all(|w| w[1] <= w[0]) || amps.windows(2).all(|w| w[1] >= w[0]);
    let recurs = recurs && !monotone;
    let mean_return = (returns[n - 1].t - half[0].t) / (half.len() - 1).max(1) as f64;
    // a motion that is not periodic: its amplitudes over the whole second half of the run
    let (mut hi, mut lo) = (half[0].high, half[0].low);
    for q in half {
        hi = hi.sup(&q.high);
        lo = lo.inf(&q.low);
    }
    let amplitudes = body_amplitudes(model, &hi, &lo);
    let (_, wheelsets) = excursions(model, &hi, &lo);
    if !recurs {
        let mut m = Motion::simple(MotionKind::Unsettled, speed, time);
        m.note = format!("still drifting after {time:.1} s ({n} returns)");
        m.state = state;
        m.amplitudes = amplitudes;
        m.excursion_m = wheelsets;
        return m;
    }
    let x = returns[n - 1].x;
    let lyap = largest_lyapunov(model, speed, &x, mean_return, 100, s.rtol);
    let kind = match lyap {
        Some(l) if l * mean_return > 0.01 => MotionKind::Chaotic,
        Some(_) => MotionKind::QuasiPeriodic,
        None => MotionKind::Unsettled,
    };
    Motion {
        kind,
        speed_m_s: speed,
        period_s: None,
        amplitudes,
        excursion_m: wheelsets,
        max_multiplier: None,
        lyapunov_per_s: lyap,
        state,
        time_s: time,
        note: format!("mean return time {mean_return:.4} s"),
    }
}

/// The largest Lyapunov exponent (1/time unit of the field) along the orbit from `x` at
/// parameter `p`: a tangent vector carried by the variational equations over `chunks`
/// intervals of length `tau`, renormalised after each (Benettin, Galgani, Giorgilli & Strelcyn,
/// Meccanica 15 (1980)); `None` if an integration fails. The tangent vector is integrated on
/// its own ([`integrate_tangent`]: one directional derivative per stage), not as the full
/// monodromy matrix times the vector: on the S1002 bogie's search the matrix made this
/// function 61 % of the whole run.
pub fn largest_lyapunov<const N: usize, F: crate::system::ode::VectorField<N>>(
    field: &F,
    p: f64,
    x: &SVector<f64, N>,
    tau: f64,
    chunks: usize,
    rtol: f64,
) -> Option<f64> {
    let opts = ode(rtol);
    let mut x = *x;
    let mut w = SVector::<f64, N>::from_element(1.0).normalize();
    let mut sum = 0.0;
    for _ in 0..chunks {
        let (sol, v) =
            integrate_tangent(field, p, &x, &w, tau, &opts, TangentControl::Free).ok()?;
        let n = v.norm();
        if !(n.is_finite() && n > 0.0) {
            return None;
        }
        sum += n.ln();
        w = v / n;
        x = sol.x;
    }
    Some(sum / (tau * chunks as f64))
}
