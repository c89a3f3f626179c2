//! The integration loop (step, error test, switching surfaces, end time) and the public entry
//! points built on it; they differ only in what they do after each accepted step.

use std::ops::ControlFlow;

use nalgebra::{SMatrix, SVector};

use super::dopri::{Carried, Column, Controller, Point, Rk, Trial, FAC_MIN};
use super::events::{brent, land_on, Switches};
use super::{OdeError, OdeOptions, Solution, Stats, StopReason, Tolerances, VectorField};

/// The loop's result: the solution, the last step size (for [`OdeError::StepSizeTooSmall`]),
/// and whether the per-step hook ended the run.
pub(super) struct Run<const N: usize, C> {
    pub sol: Solution<N>,
    pub h: f64,
    pub hooked: bool,
    /// what the variational equations carried, at the final time
    pub carried: C,
}

/// Runs the generic function `$go` with the carried value the options ask for: the monodromy
/// matrix with `opts.monodromy`, else nothing (see [`Carried`]).
macro_rules! by_carried {
    ($opts:expr, $go:ident ( $($arg:expr),* $(,)? )) => {
        if $opts.monodromy {
            $go::<N, F, SMatrix<f64, N, N>>($($arg),*)
        } else {
            $go::<N, F, ()>($($arg),*)
        }
    };
}

/// All of the point finite: a NaN or infinity anywhere makes the sum non-finite (a sum of
/// finite entries could only overflow beyond 1e308, which is a blow-up too). Cheaper than
/// testing each entry.
fn finite<const N: usize, C: Carried<N>>(p: &Point<N, C>) -> bool {
    (p.x.sum() + p.f.sum() + p.phi.sum() + p.f_phi.sum()).is_finite()
}

fn check_interval(t_end: f64) -> Result<(), OdeError> {
    if t_end.is_finite() && t_end > 0.0 {
        Ok(())
    } else {
        Err(OdeError::BadInterval { t_end })
    }
}

/// Integrates from $t = 0$ to `t_end`, calling `hook(rk, start, trial)` after every accepted
/// step; a `Break(point)` ends the run at that point. Numerical failures end the run with a
/// [`StopReason`]; only invalid arguments are errors here.
/// `phi0` is the carried value at $t = 0$ (the identity for the monodromy matrix); it rides
/// along when `opts.monodromy` is set or it is a [`Column`].
pub(super) fn run<const N: usize, F, C, H>(
    field: &F,
    p: f64,
    x0: &SVector<f64, N>,
    phi0: C,
    t_end: f64,
    opts: &OdeOptions,
    mut hook: H,
) -> Result<Run<N, C>, OdeError>
where
    F: VectorField<N>,
    C: Carried<N>,
    H: FnMut(&mut Rk<'_, N, F>, &Point<N, C>, &Trial<N, C>) -> ControlFlow<Point<N, C>>,
{
    opts.validate()?;
    check_interval(t_end)?;
    if !x0.iter().all(|v| v.is_finite()) {
        return Err(OdeError::NonFinite { t: 0.0 });
    }
    let mut rk = Rk {
        field,
        p,
        variational: opts.monodromy || C::ALWAYS,
        tol: opts.tol,
        tol_phi: Tolerances {
            rtol: opts.tol.rtol * opts.monodromy_tol_factor,
            atol: opts.tol.atol * opts.monodromy_tol_factor,
        },
        rhs_evals: 0,
        method: opts.method,
    };
    let mut cur = rk.point(0.0, *x0, phi0);
    let mut switches = Switches::new(field, x0);
    let mut ctrl = Controller::new(opts.method);
    let mut stats = Stats::default();
    let mut h = match opts.h_initial {
        Some(h) => h,
        None => rk.initial_step(&cur, opts.h_max),
    }
    .min(opts.h_max);
    let (mut after_reject, mut non_finite, mut hooked) = (false, false, false);
    let mut h_first = f64::NAN;
    let stop = if !finite(&cur) {
        StopReason::NonFinite
    } else {
        loop {
            if cur.t >= t_end {
                break StopReason::Reached;
            }
            if stats.steps + stats.rejected >= opts.max_steps {
                break StopReason::MaxSteps;
            }
            // Below 16 ulps of t a step no longer changes t meaningfully.
            if h < 16.0 * f64::EPSILON * cur.t.abs().max(f64::EPSILON * t_end) {
                break if non_finite {
                    StopReason::NonFinite
                } else {
                    StopReason::StepTooSmall
                };
            }
            // Land on t_end exactly (not t + h, with its round-off); stretch the step by up
            // to 1% (within h_max) rather than leave a sliver of a last step.
            let rest = t_end - cur.t;
            let (h_try, target) = if cur.t + 1.01 * h >= t_end && rest <= opts.h_max {
                (rest, t_end)
            } else {
                (h, cur.t + h)
            };
            let mut trial = rk.step(&cur, h_try);
            trial.end.t = target;
            let shortened = switches.settle(&mut rk, &cur, &mut trial);
            non_finite = !(trial.err.is_finite() && finite(&trial.end));
            if non_finite || trial.err > 1.0 {
                // A non-finite result is often an overshoot into a region where the field
                // overflows: retried smaller like a failed error test.
                let fac = if non_finite {
                    FAC_MIN
                } else {
                    ctrl.rejected(trial.err)
                };
                (h, after_reject) = ((trial.end.t - cur.t) * fac, true);
                stats.rejected += 1;
                continue;
            }
            if stats.steps == 0 {
                h_first = trial.end.t - cur.t;
            }
            stats.steps += 1;
            stats.events += switches.commit(field, &trial.end.x);
            // A step shortened to a surface keeps the h of the step it was cut from: its
            // small error says nothing about the step after.
            if !shortened {
                let fac = ctrl.accepted(trial.err);
                h = h_try * if after_reject { fac.min(1.0) } else { fac };
            }
            h = h.min(opts.h_max);
            after_reject = false;
            if let ControlFlow::Break(end) = hook(&mut rk, &cur, &trial) {
                (cur, hooked) = (end, true);
                break StopReason::Reached;
            }
            cur = trial.end;
        }
    };
    stats.rhs_evals = rk.rhs_evals;
    let monodromy = if opts.monodromy {
        cur.phi.monodromy()
    } else {
        None
    };
    let sol = Solution {
        t: cur.t,
        x: cur.x,
        monodromy,
        stats,
        stop,
        h_first,
    };
    Ok(Run {
        sol,
        h,
        hooked,
        carried: cur.phi,
    })
}

/// A run that did not reach its end becomes the matching error.
fn checked<const N: usize, C>(run: Run<N, C>) -> Result<Solution<N>, OdeError> {
    let Run { sol, h, .. } = run;
    let t = sol.t;
    match sol.stop {
        StopReason::Reached => Ok(sol),
        StopReason::MaxSteps => Err(OdeError::MaxSteps {
            t,
            steps: sol.stats.steps + sol.stats.rejected,
        }),
        StopReason::StepTooSmall => Err(OdeError::StepSizeTooSmall { t, h }),
        StopReason::NonFinite => Err(OdeError::NonFinite { t }),
    }
}

/// Integrates $\dot x = f(x; p)$ from $x_0$ at $t = 0$ to `t_end > 0`. With
/// `opts.monodromy` also returns $\Phi(t_{end}) = \partial x(t_{end}) / \partial x_0$, from
/// $\dot\Phi = J(x(t))\,\Phi$, $\Phi(0) = I$. Failing to reach `t_end` is an error.
pub fn integrate<const N: usize, F: VectorField<N>>(
    f: &F,
    p: f64,
    x0: &SVector<f64, N>,
    t_end: f64,
    opts: &OdeOptions,
) -> Result<Solution<N>, OdeError> {
    fn go<const N: usize, F: VectorField<N>, C: Carried<N>>(
        f: &F,
        p: f64,
        x0: &SVector<f64, N>,
        t_end: f64,
        opts: &OdeOptions,
    ) -> Result<Solution<N>, OdeError> {
        let phi0 = C::identity();
        checked(run(f, p, x0, phi0, t_end, opts, |_, _, _| {
            ControlFlow::Continue(())
        })?)
    }
    by_carried!(opts, go(f, p, x0, t_end, opts))
}

/// Whether a carried tangent vector joins the step-size control of [`integrate_tangent`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TangentControl {
    /// $w$ is in the error test, as one column of $\Phi$: the steps resolve $w$ as well as
    /// $x$ (the variational solution to the tolerance).
    Checked,
    /// the steps are the state's alone and $w$ is carried on them: the trajectory is exactly
    /// [`integrate`]'s, and $w$ has the method's fifth order on that grid. What a Lyapunov
    /// exponent needs: it is a growth rate averaged over many returns, not a solution to a
    /// tolerance, and on the S1002 bogie's chaotic motions checking $w$ took about twice as
    /// many steps as the state needs.
    Free,
}

/// As [`integrate`], carrying one tangent vector instead of the monodromy matrix: returns the
/// solution and $w(t_{end}) = \Phi(t_{end})\,w_0$, from $\dot w = J(x(t))\,w$ with the
/// same stages as $x$ ([`TangentControl`] says whether $w$ joins the error test). It costs one
/// directional derivative per stage instead of a Jacobian and an $N \times N$ product:
/// what the largest Lyapunov exponent needs. `opts.monodromy` is ignored.
pub fn integrate_tangent<const N: usize, F: VectorField<N>>(
    f: &F,
    p: f64,
    x0: &SVector<f64, N>,
    w0: &SVector<f64, N>,
    t_end: f64,
    opts: &OdeOptions,
    control: TangentControl,
) -> Result<(Solution<N>, SVector<f64, N>), OdeError> {
    fn go<const N: usize, F: VectorField<N>, const CHECKED: bool>(
        f: &F,
        p: f64,
        x0: &SVector<f64, N>,
        w0: &SVector<f64, N>,
        t_end: f64,
        opts: &OdeOptions,
    ) -> Result<(Solution<N>, SVector<f64, N>), OdeError> {
        let opts = OdeOptions {
            monodromy: false,
            ..*opts
        };
        let w0: Column<N, CHECKED> = Column(*w0);
        let run = run(f, p, x0, w0, t_end, &opts, |_, _, _| {
            ControlFlow::Continue(())
        })?;
        let w = run.carried.0;
        Ok((checked(run)?, w))
    }
    match control {
        TangentControl::Checked => go::<N, F, true>(f, p, x0, w0, t_end, opts),
        TangentControl::Free => go::<N, F, false>(f, p, x0, w0, t_end, opts),
    }
}

/// As [`integrate`], but a numerical failure (step limit, vanishing step, NaN) is an outcome,
/// not an error: the last accepted state is returned with its [`StopReason`] (a wheelset that
/// runs away in a sweep is a result). Invalid arguments are still errors.
pub fn integrate_partial<const N: usize, F: VectorField<N>>(
    f: &F,
    p: f64,
    x0: &SVector<f64, N>,
    t_end: f64,
    opts: &OdeOptions,
) -> Result<Solution<N>, OdeError> {
    fn go<const N: usize, F: VectorField<N>, C: Carried<N>>(
        f: &F,
        p: f64,
        x0: &SVector<f64, N>,
        t_end: f64,
        opts: &OdeOptions,
    ) -> Result<Solution<N>, OdeError> {
        let phi0 = C::identity();
        Ok(run(f, p, x0, phi0, t_end, opts, |_, _, _| {
            ControlFlow::Continue(())
        })?
        .sol)
    }
    by_carried!(opts, go(f, p, x0, t_end, opts))
}

/// As [`integrate`], and also the largest $|x_k(t)|$ of each component over $[0, t_{end}]$,
/// located on each step's continuous extension (see `Dense::abs_max`): the amplitudes of a
/// periodic orbit come with the shooting integration instead of costing one more.
pub fn integrate_with_peaks<const N: usize, F: VectorField<N>>(
    f: &F,
    p: f64,
    x0: &SVector<f64, N>,
    t_end: f64,
    opts: &OdeOptions,
) -> Result<(Solution<N>, SVector<f64, N>), OdeError> {
    let (sol, high, low) = integrate_with_extremes(f, p, x0, t_end, opts)?;
    Ok((sol, high.abs().sup(&low.abs())))
}

/// As [`integrate`], and also the largest and smallest value of each component over
/// $[0, t_{end}]$, `(solution, max x_k, min x_k)`, located on each step's continuous extension
/// (see `Dense::extremes`).
pub fn integrate_with_extremes<const N: usize, F: VectorField<N>>(
    f: &F,
    p: f64,
    x0: &SVector<f64, N>,
    t_end: f64,
    opts: &OdeOptions,
) -> Result<(Solution<N>, SVector<f64, N>, SVector<f64, N>), OdeError> {
    fn go<const N: usize, F: VectorField<N>, C: Carried<N>>(
        f: &F,
        p: f64,
        x0: &SVector<f64, N>,
        t_end: f64,
        opts: &OdeOptions,
    ) -> Result<(Solution<N>, SVector<f64, N>, SVector<f64, N>), OdeError> {
        let (mut high, mut low) = (*x0, *x0);
        let run = run(f, p, x0, C::identity(), t_end, opts, |rk, start, trial| {
            let (h, l) = rk.extremes(start, trial);
            high = high.sup(&h);
            low = low.inf(&l);
            ControlFlow::Continue(())
        })?;
        Ok((checked(run)?, high, low))
    }
    by_carried!(opts, go(f, p, x0, t_end, opts))
}

/// As [`integrate`], calling `observer(t, &x)` at each sample time (sorted ascending, within
/// $[0, t_{end}]$; a sample at a step end gets that step's state, others the step's
/// 4th-order continuous extension, whose error is of the order of the local error the
/// tolerances control). On failure the samples before it have been delivered.
pub fn integrate_observed<const N: usize, F: VectorField<N>>(
    f: &F,
    p: f64,
    x0: &SVector<f64, N>,
    t_end: f64,
    opts: &OdeOptions,
    samples: &[f64],
    observer: &mut dyn FnMut(f64, &SVector<f64, N>),
) -> Result<Solution<N>, OdeError> {
    check_interval(t_end)?;
    let mut prev = 0.0;
    for &ts in samples {
        if ts.is_nan() || ts < prev || ts > t_end {
            let rule = "samples must be sorted ascending within [0, t_end]";
            return Err(OdeError::BadArgument {
                name: "sample time",
                value: ts,
                rule,
            });
        }
        prev = ts;
    }
    fn go<const N: usize, F: VectorField<N>, C: Carried<N>>(
        f: &F,
        p: f64,
        x0: &SVector<f64, N>,
        t_end: f64,
        opts: &OdeOptions,
        samples: &[f64],
        observer: &mut dyn FnMut(f64, &SVector<f64, N>),
    ) -> Result<Solution<N>, OdeError> {
        let mut next = 0;
        let run = run(f, p, x0, C::identity(), t_end, opts, |rk, start, trial| {
            let mut dense = None;
            while let Some(&ts) = samples.get(next).filter(|&&ts| ts <= trial.end.t) {
                if ts >= trial.end.t {
                    observer(ts, &trial.end.x);
                } else if ts <= start.t {
                    observer(ts, &start.x);
                } else {
                    observer(
                        ts,
                        &dense.get_or_insert_with(|| rk.dense(start, trial)).eval(ts),
                    );
                }
                next += 1;
            }
            ControlFlow::Continue(())
        })?;
        checked(run)
    }
    by_carried!(opts, go(f, p, x0, t_end, opts, samples, observer))
}

/// Integrates until the first upward crossing of the section $s(x) = 0$ ($s$ from negative to
/// non-negative) at a time after `min_time` (time units of the field), at most to `t_max`;
/// `Ok(None)` if there is none. The crossing is located like a switching surface: Brent's
/// method on the step's dense output gives a guess, then an Illinois iteration on re-taken
/// steps ends a genuine RK step on the section (a few ulps of $t$ past it), so the time is as
/// accurate as the integration itself rather than the 4th-order dense output.
///
/// The monodromy returned is $\Phi(t_c)$, the sensitivity of the flow at the fixed time $t_c$:
/// the projection $(I - f\,\nabla s^{\mathsf T}/(\nabla s\cdot f))\,\Phi$ that turns it
/// into the Jacobian of the Poincaré map is *not* applied (the shooting code owns it).
pub fn integrate_to_section<const N: usize, F: VectorField<N>>(
    f: &F,
    p: f64,
    x0: &SVector<f64, N>,
    t_max: f64,
    section: &dyn Fn(&SVector<f64, N>) -> f64,
    min_time: f64,
    opts: &OdeOptions,
) -> Result<Option<Solution<N>>, OdeError> {
    if !min_time.is_finite() || min_time < 0.0 {
        let rule = "must be finite and >= 0";
        return Err(OdeError::BadArgument {
            name: "min_time",
            value: min_time,
            rule,
        });
    }
    #[allow(clippy::too_many_arguments)]
    fn go<const N: usize, F: VectorField<N>, C: Carried<N>>(
        f: &F,
        p: f64,
        x0: &SVector<f64, N>,
        t_max: f64,
        section: &dyn Fn(&SVector<f64, N>) -> f64,
        min_time: f64,
        opts: &OdeOptions,
    ) -> Result<Option<Solution<N>>, OdeError> {
        let mut s_prev = section(x0);
        let run = run(f, p, x0, C::identity(), t_max, opts, |rk, start, trial| {
            let (s0, s1) = (s_prev, section(&trial.end.x));
            s_prev = s1;
            let t1 = trial.end.t;
            if t1 <= min_time || s1.is_nan() || s1 < 0.0 {
                return ControlFlow::Continue(());
            }
            let dense = rk.dense(start, trial);
            let (a, sa) = if start.t >= min_time {
                (start.t, s0)
            } else {
                (min_time, section(&dense.eval(min_time)))
            };
            if sa.is_nan() || sa >= 0.0 {
                return ControlFlow::Continue(());
            }
            if s1 <= 0.0 {
                return ControlFlow::Break(trial.end);
            }
            let tc = brent(
                &mut |t| section(&dense.eval(t)),
                a,
                t1,
                sa,
                s1,
                4.0 * f64::EPSILON * t1.abs(),
            );
            let (t0, h) = (start.t, t1 - start.t);
            ControlFlow::Break(land_on(rk, start, section, (a - t0, sa), (h, s1), tc - t0).end)
        })?;
        let hooked = run.hooked;
        Ok(hooked.then_some(checked(run)?))
    }
    by_carried!(opts, go(f, p, x0, t_max, section, min_time, opts))
}

/// One return of a trajectory to a Poincaré section ([`integrate_sections`]).
#[derive(Clone, Debug, PartialEq)]
pub struct Return<const N: usize> {
    /// time of the crossing
    pub t: f64,
    /// the state there (on the step's continuous extension)
    pub x: SVector<f64, N>,
    /// the largest value of each component since the previous return (or the start), over
    /// whole steps (the step of each crossing counts on both sides)
    pub high: SVector<f64, N>,
    /// the smallest value of each component over the same steps
    pub low: SVector<f64, N>,
}

/// Integrates $\dot x = f(x; p)$ from $x_0$ for at most `t_end`, calling `on_return` at every
/// crossing of the section $s(x) = 0$ in the direction of increasing $s$ (located by Brent's
/// method on the step's continuous extension), with the extremes of each component since the
/// previous crossing; `on_return` ends the run by returning `Break`. A numerical failure (step
/// limit, vanishing step, NaN) ends the run with its [`StopReason`] in the returned solution,
/// as in [`integrate_partial`]: a motion that blows up is an outcome. Invalid arguments are
/// errors.
pub fn integrate_sections<const N: usize, F: VectorField<N>>(
    f: &F,
    p: f64,
    x0: &SVector<f64, N>,
    t_end: f64,
    section: &dyn Fn(&SVector<f64, N>) -> f64,
    opts: &OdeOptions,
    on_return: &mut dyn FnMut(&Return<N>) -> ControlFlow<()>,
) -> Result<Solution<N>, OdeError> {
    fn go<const N: usize, F: VectorField<N>, C: Carried<N>>(
        f: &F,
        p: f64,
        x0: &SVector<f64, N>,
        t_end: f64,
        section: &dyn Fn(&SVector<f64, N>) -> f64,
        opts: &OdeOptions,
        on_return: &mut dyn FnMut(&Return<N>) -> ControlFlow<()>,
    ) -> Result<Solution<N>, OdeError> {
        let mut s_prev = section(x0);
        let (mut high, mut low) = (*x0, *x0);
        let run = run(f, p, x0, C::identity(), t_end, opts, |rk, start, trial| {
            let dense = rk.dense(start, trial);
            let (h, l) = dense.extremes();
            high = high.sup(&h);
            low = low.inf(&l);
            let (s0, s1) = (s_prev, section(&trial.end.x));
            s_prev = s1;
            if !(s0 < 0.0 && s1 >= 0.0) {
                return ControlFlow::Continue(());
            }
            let t1 = trial.end.t;
            let tc = brent(
                &mut |t| section(&dense.eval(t)),
                start.t,
                t1,
                s0,
                s1,
                4.0 * f64::EPSILON * t1.abs(),
            );
            let r = Return {
                t: tc,
                x: dense.eval(tc),
                high,
                low,
            };
            (high, low) = (h, l);
            match on_return(&r) {
                ControlFlow::Continue(()) => ControlFlow::Continue(()),
                ControlFlow::Break(()) => ControlFlow::Break(trial.end),
            }
        })?;
        Ok(run.sol)
    }
    by_carried!(opts, go(f, p, x0, t_end, section, opts, on_return))
}

/// As [`integrate`], returning the end times of the accepted steps (the last is `t_end`):
/// a step sequence for [`tangent_on_steps`].
pub fn step_times<const N: usize, F: VectorField<N>>(
    f: &F,
    p: f64,
    x0: &SVector<f64, N>,
    t_end: f64,
    opts: &OdeOptions,
) -> Result<Vec<f64>, OdeError> {
    fn go<const N: usize, F: VectorField<N>, C: Carried<N>>(
        f: &F,
        p: f64,
        x0: &SVector<f64, N>,
        t_end: f64,
        opts: &OdeOptions,
    ) -> Result<Vec<f64>, OdeError> {
        let mut times = Vec::new();
        checked(run(f, p, x0, C::identity(), t_end, opts, |_, _, trial| {
            times.push(trial.end.t);
            ControlFlow::Continue(())
        })?)?;
        Ok(times)
    }
    by_carried!(opts, go(f, p, x0, t_end, opts))
}

/// The flow and one tangent of the time-normalised system on a fixed step sequence: with
/// $x(τ)$, $τ ∈ [0, 1]$, $x' = H f(x; p)$ and $ξ' = H J(x)\,ξ + dH\, f(x; p)$ from
/// $x(0) = x_0$, $ξ(0) = ξ_0$, returns $(x(1), ξ(1))$: $ξ(1)$ is the derivative of the flow
/// map over the horizon $H$ in the direction $(ξ_0, dH)$ of (initial state, horizon).
///
/// `taus` are the step ends in $(0, 1]$, ascending, ending at 1 (e.g. [`step_times`] / H);
/// each step is one classical 4th-order Runge–Kutta step. Written here rather than taken from
/// the adaptive integrator because differences of this map at nearby arguments must use
/// the *same* steps: an error-controlled step sequence changes with the arguments and makes
/// such differences noisy (the "internal numerical differentiation" of shooting codes).
pub fn tangent_on_steps<const N: usize, F: VectorField<N>>(
    f: &F,
    p: f64,
    x0: &SVector<f64, N>,
    xi0: &SVector<f64, N>,
    (horizon, d_horizon): (f64, f64),
    taus: &[f64],
) -> Result<(SVector<f64, N>, SVector<f64, N>), OdeError> {
    check_interval(horizon)?;
    let sides = Sides::new(f, x0);
    let field = |x: &SVector<f64, N>, xi: &SVector<f64, N>, up: &[bool]| {
        let x = sides.onto(f, x, up);
        let (fx, jxi) = f.rhs_tangent(&x, p, xi);
        (fx * horizon, jxi * horizon + fx * d_horizon)
    };
    let rk4 = |x: &SVector<f64, N>, xi: &SVector<f64, N>, h: f64, up: &[bool]| {
        let (k1, l1) = field(x, xi, up);
        let (k2, l2) = field(&(x + k1 * (0.5 * h)), &(xi + l1 * (0.5 * h)), up);
        let (k3, l3) = field(&(x + k2 * (0.5 * h)), &(xi + l2 * (0.5 * h)), up);
        let (k4, l4) = field(&(x + k3 * h), &(xi + l3 * h), up);
        (
            x + (k1 + (k2 + k3) * 2.0 + k4) * (h / 6.0),
            xi + (l1 + (l2 + l3) * 2.0 + l4) * (h / 6.0),
        )
    };
    let (mut x, mut xi) = (*x0, *xi0);
    let mut up = sides.up.clone();
    let mut tau = 0.0;
    for &next in taus {
        let mut h = next - tau;
        if h.is_nan() || h <= 0.0 {
            continue;
        }
        // A step that crosses a switching surface is split where this trajectory crosses
        // it, and each part is taken on one side's field (the stages held on that side):
        // the map then moves smoothly with its arguments, as its differences need.
        // (at most two crossings of each surface in one step; the rest of a step with more
        // is taken on the last sides)
        let mut crossings = 0;
        loop {
            let (xe, xie) = rk4(&x, &xi, h, &up);
            let crossing = (crossings < 2 * up.len())
                .then(|| sides.first_crossing(f, &x, &xe, &up, |t| rk4(&x, &xi, t * h, &up).0))
                .flatten();
            let Some((k, theta)) = crossing else {
                (x, xi) = (xe, xie);
                break;
            };
            (x, xi) = rk4(&x, &xi, theta * h, &up);
            up[k] = !up[k];
            h *= 1.0 - theta;
            crossings += 1;
        }
        tau = next;
        if !(x.sum() + xi.sum()).is_finite() {
            return Err(OdeError::NonFinite { t: tau * horizon });
        }
    }
    Ok((x, xi))
}

/// The switching surfaces of a field as [`tangent_on_steps`] meets them: each surface's side
/// (`up`: its function positive) and the means to hold a stage on a side and to find where a
/// step crosses a surface.
struct Sides {
    /// the side of each surface at the start
    up: Vec<bool>,
}

impl Sides {
    /// How far (the switching function's units, state units for the flange) a stage that has
    /// strayed across a surface is put back on its side.
    const INSIDE: f64 = 1e-13;

    fn new<const N: usize, F: VectorField<N>>(f: &F, x0: &SVector<f64, N>) -> Self {
        Sides {
            up: (0..f.switch_count())
                .map(|k| f.switch_value(k, x0) > 0.0)
                .collect(),
        }
    }

    /// `x`, or, where it lies across a surface from the side `up` holds, `x` moved along the
    /// switching function's gradient (a difference: the functions are linear in the state, or
    /// nearly so over the stray) to just inside that side. The field is continuous across
    /// its surfaces, so the move changes f by the stray's order; what it keeps is the side's
    /// Jacobian, which jumps at the surface.
    fn onto<const N: usize, F: VectorField<N>>(
        &self,
        f: &F,
        x: &SVector<f64, N>,
        up: &[bool],
    ) -> SVector<f64, N> {
        let mut y = *x;
        for (k, &side) in up.iter().enumerate() {
            let g = f.switch_value(k, &y);
            let target = if side { Self::INSIDE } else { -Self::INSIDE };
            // strictly inside (a point on the surface belongs to whichever side the field's
            // own comparison gives it, which may not be this one)
            if (side && g > 0.0) || (!side && g < 0.0) {
                continue;
            }
            let grad = SVector::<f64, N>::from_fn(|i, _| {
                let d = 1e-6 * (1.0 + y[i].abs());
                let mut z = y;
                z[i] += d;
                (f.switch_value(k, &z) - g) / d
            });
            let norm = grad.norm_squared();
            if norm > 0.0 && norm.is_finite() {
                y += grad * ((target - g) / norm);
            }
        }
        y
    }

    /// The first surface the step from `x` to `xe` (taken on the sides `up`) crosses, and the
    /// step's fraction where it does: the root of the switching function along `along(t)`, the
    /// state after the fraction `t` of the step (Brent's method, as the integrator's events,
    /// to round-off).
    fn first_crossing<const N: usize, F: VectorField<N>>(
        &self,
        f: &F,
        x: &SVector<f64, N>,
        xe: &SVector<f64, N>,
        up: &[bool],
        along: impl Fn(f64) -> SVector<f64, N>,
    ) -> Option<(usize, f64)> {
        let mut first: Option<(usize, f64)> = None;
        for (k, &side) in up.iter().enumerate() {
            let (g0, g1) = (f.switch_value(k, x), f.switch_value(k, xe));
            if (g1 > 0.0) == side || !g1.is_finite() {
                continue;
            }
            // the start lies on `side` (else the crossing is at the start); the end across
            let t = if (g0 > 0.0) == side && g0 != 0.0 {
                let mut g = |t: f64| f.switch_value(k, &along(t));
                super::events::brent(&mut g, 0.0, 1.0, g0, g1, 4.0 * f64::EPSILON)
            } else {
                0.0
            };
            if first.is_none_or(|(_, tf)| t < tf) {
                first = Some((k, t));
            }
        }
        first
    }
}
