//! The ramp method: settle on a cycle, decrease the speed slowly, find where hunting dies
//! (see the module docs of [`crate::simulate`] for what the estimate means).

use super::en14363::EnStream;
use super::*;

// ---------------------------------------------------------------------------------------
// The ramp method
// ---------------------------------------------------------------------------------------

/// What [`RampResult`] estimates, for output.
pub const RAMP_QUANTITY: &str = "ramp (simulation) estimate of the nonlinear critical speed";

/// Why a ramp run, its options or the filter were rejected; each variant carries the numbers.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum RampError {
    /// An option outside its domain.
    #[error("invalid {field} = {value}: {rule}")]
    BadOption {
        /// the option's name
        field: &'static str,
        /// its value
        value: f64,
        /// the rule it breaks
        rule: &'static str,
    },
    /// The ramp method runs on the 4-state wheelset only (so far).
    #[error("the ramp method runs on the single wheelset (4 states); this model has {0} states")]
    States(usize),
    /// The integration failed.
    #[error("integration failed at t = {t} s, V = {speed} m/s: {source}")]
    Ode {
        /// time of the failing chunk's start (s)
        t: f64,
        /// speed there (m/s)
        speed: f64,
        /// the integrator's error
        source: OdeError,
    },
}

pub(super) fn bad(field: &'static str, value: f64, rule: &'static str) -> RampError {
    RampError::BadOption { field, value, rule }
}

/// Options of one ramp run. Plain fields; [`RampOptions::validate`] checks them (every
/// entry point calls it).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RampOptions {
    /// speed of the settle phase and of the ramp's start (m/s); must lie above the
    /// critical speed, on a stable cycle
    pub start_speed: f64,
    /// speed at which the ramp ends if the hunting has not died (m/s)
    pub end_speed: f64,
    /// deceleration (m/s²), positive
    pub rate: f64,
    /// initial lateral displacement y(0) (m) that kicks the motion onto the cycle
    pub y0: f64,
    /// time at constant `start_speed` before the ramp begins (s)
    pub settle: f64,
    /// lateral peak amplitude below which the hunting counts as died out (m)
    pub threshold: f64,
    /// integrator relative tolerance (–); atol = rtol × 1 mm, as in the bifurcation analysis
    pub rtol: f64,
}

impl RampOptions {
    /// The defaults for a ramp from `start_speed` down to `end_speed` (m/s):
    ///
    /// * `rate` 1.389 m/s²: the 5 km/h per s that GENSYS documents for its ramp; usually far
    ///   too fast for an accurate answer near a Hopf point (see the module docs), hence
    ///   [`ramp_converged`];
    /// * `y0` 5 mm: the seed's initial displacement, large enough to land in the basin of a
    ///   large cycle;
    /// * `settle` 20 s: about 100 periods of a 5 Hz hunting motion, ten time constants of a
    ///   cycle whose slowest Floquet multiplier is 0.9 (check
    ///   [`RampResult::settle_drift_rel`]);
    /// * `threshold` 0.1 mm: a hundred times below typical hunting amplitudes, well above the
    ///   integration error (atol = 1e-11 m);
    /// * `rtol` 1e-8: on `studies/seed-hunting.toml` 1e-6 or 1e-10 move the estimate by
    ///   under 3e-5 m/s, far below the rate's effect; 1e-6 is 2.3 times cheaper.
    pub fn new(start_speed: f64, end_speed: f64) -> Self {
        Self {
            start_speed,
            end_speed,
            rate: 5.0 / 3.6,
            y0: 0.005,
            settle: 20.0,
            threshold: 1e-4,
            rtol: 1e-8,
        }
    }

    /// Checks every field; the error names the field, its value and the rule.
    pub fn validate(&self) -> Result<(), RampError> {
        let pos = |v: f64| v.is_finite() && v > 0.0;
        if !pos(self.start_speed) {
            return Err(bad(
                "start_speed",
                self.start_speed,
                "must be finite and > 0 m/s",
            ));
        }
        if !(pos(self.end_speed) && self.end_speed < self.start_speed) {
            let rule = "must be finite, > 0 and below start_speed";
            return Err(bad("end_speed", self.end_speed, rule));
        }
        if !pos(self.rate) {
            return Err(bad(
                "rate",
                self.rate,
                "must be finite and > 0 m/s² (a deceleration)",
            ));
        }
        if !(self.y0.is_finite() && self.y0 != 0.0 && self.y0.abs() < 0.1) {
            let rule = "must be finite, nonzero (the centred motion never hunts) and below 0.1 m";
            return Err(bad("y0", self.y0, rule));
        }
        if !pos(self.settle) {
            let rule = "must be finite and > 0 s (the hunting frequency f0 is measured there)";
            return Err(bad("settle", self.settle, rule));
        }
        if !pos(self.threshold) {
            return Err(bad("threshold", self.threshold, "must be finite and > 0 m"));
        }
        if !(self.rtol.is_finite() && (1e-13..=1e-3).contains(&self.rtol)) {
            return Err(bad("rtol", self.rtol, "must lie in [1e-13, 1e-3]"));
        }
        Ok(())
    }
}

/// One peak of |y| in the ramp's history.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EnvelopePoint {
    /// time of the peak (s)
    pub t_s: f64,
    /// speed at the peak (m/s)
    pub speed_m_s: f64,
    /// peak lateral amplitude |y| (m)
    pub amplitude_m: f64,
}

/// How a ramp run ended.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum RampStop {
    /// The peak amplitude fell below the threshold for good: the run went on until it was
    /// below a tenth of it (and the EN 14363 r.m.s. below its limit), or to `end_speed`.
    Died,
    /// Still hunting at `end_speed`; `amplitude_m` is the last peak (m).
    StillHunting {
        /// last peak amplitude (m)
        amplitude_m: f64,
    },
    /// No hunting above the threshold after the settle phase: the start speed is not on a
    /// cycle reachable from `y0`; `amplitude_m` is the last peak (m), 0 if none.
    NotHuntingAtStart {
        /// last peak amplitude (m)
        amplitude_m: f64,
    },
}

/// Everything one ramp run produces.
#[derive(Clone, Debug, PartialEq)]
pub struct RampResult {
    /// what `died_at_m_s` estimates: [`RAMP_QUANTITY`]
    pub quantity: &'static str,
    /// speed at which the peak amplitude fell below the threshold for good (m/s); linear
    /// interpolation of ln(amplitude) between the two peaks around the crossing
    pub died_at_m_s: Option<f64>,
    /// how the run ended
    pub stop: RampStop,
    /// the options of the run
    pub options: RampOptions,
    /// sampling interval of the history (s)
    pub sample_interval_s: f64,
    /// the last peak amplitude of the settle phase (m)
    pub start_amplitude_m: f64,
    /// relative change of the peak amplitude over the last 10 % of the settle phase (–):
    /// ≈ 0 when the motion had settled on a cycle; clearly negative when it was still dying
    /// out (the start speed is below the nonlinear critical speed, or `settle` is too short)
    pub settle_drift_rel: f64,
    /// every peak of |y|, settle phase included
    pub envelope: Vec<EnvelopePoint>,
    /// the EN 14363 evaluation (absent when there was no hunting at the start)
    pub en14363: Option<En14363>,
    /// speed at which the EN 14363 sliding r.m.s. dropped below the limit for good (m/s),
    /// when it was ever above it
    pub en14363_speed_m_s: Option<f64>,
    /// simulated time, settle included (s)
    pub simulated_s: f64,
    /// accepted integration steps
    pub steps: usize,
    /// right-hand side evaluations by the integrator
    pub rhs_evals: usize,
}

/// Sampling interval (s): at least 50 samples per kinematic (Klingel) period $L_k/V$, the
/// shortest hunting period a wheelset of this conicity shows (suspension stiffness lowers the
/// frequency), and at most 2 ms.
pub fn sample_interval(model: &Vehicle, speed: f64) -> f64 {
    let lk = model.klingel_wavelength();
    let dt = lk / speed / 50.0;
    if dt.is_finite() && dt > 0.0 {
        dt.min(2e-3)
    } else {
        2e-3
    }
}

/// Options of the integrator for a ramp: atol = rtol × 1 mm.
fn ramp_ode(rtol: f64) -> Result<OdeOptions, RampError> {
    let tol = Tolerances::new(rtol, rtol * 1e-3)
        .map_err(|_| bad("rtol", rtol, "rejected by the integrator"))?;
    Ok(OdeOptions {
        tol,
        ..OdeOptions::default()
    })
}

/// One sample of the history, as the streaming analysis needs it.
#[derive(Clone, Copy, Debug)]
struct Sample {
    t: f64,
    y: f64,
    ydot: f64,
    speed: f64,
    distance: f64,
}

/// The extremum of y between two samples where ẏ changes sign: the cubic Hermite
/// interpolant of (y, ẏ) at both ends (error O(dt⁴)), its derivative's root by bisection.
fn refine_peak(a: &Sample, b: &Sample) -> EnvelopePoint {
    let h = b.t - a.t;
    let (y0, y1, v0, v1) = (a.y, b.y, a.ydot * h, b.ydot * h);
    // d/ds of the Hermite cubic on s ∈ [0, 1]
    let qa = 6.0 * y0 + 3.0 * v0 - 6.0 * y1 + 3.0 * v1;
    let qb = -6.0 * y0 - 4.0 * v0 + 6.0 * y1 - 2.0 * v1;
    let dp = |s: f64| (qa * s + qb) * s + v0;
    let (mut lo, mut hi) = (0.0_f64, 1.0_f64);
    let up = dp(0.0) > 0.0;
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if (dp(mid) > 0.0) == up {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let s = 0.5 * (lo + hi);
    let (s2, s3) = (s * s, s * s * s);
    let y = (2.0 * s3 - 3.0 * s2 + 1.0) * y0
        + (s3 - 2.0 * s2 + s) * v0
        + (-2.0 * s3 + 3.0 * s2) * y1
        + (s3 - s2) * v1;
    EnvelopePoint {
        t_s: a.t + s * h,
        speed_m_s: a.speed + s * (b.speed - a.speed),
        amplitude_m: y.abs(),
    }
}

/// The streaming analysis of the history: peaks, ΣY, and the EN 14363 filter and window.
struct Pipeline<'a> {
    model: &'a Vehicle,
    prev: Option<Sample>,
    envelope: Vec<EnvelopePoint>,
    /// ΣY samples (t, speed, distance, ΣY) held until f0 is known
    pending: Vec<(f64, f64, f64, f64)>,
    en: Option<EnStream>,
}

impl<'a> Pipeline<'a> {
    fn new(model: &'a Vehicle) -> Self {
        Self {
            model,
            prev: None,
            envelope: Vec::new(),
            pending: Vec::new(),
            en: None,
        }
    }

    fn push(&mut self, t: f64, x: &SVector<f64, 5>) {
        let speed = x[4];
        let distance = match self.prev {
            Some(p) => p.distance + 0.5 * (t - p.t) * (p.speed + speed),
            None => 0.0,
        };
        let cur = Sample {
            t,
            y: x[0],
            ydot: x[2],
            speed,
            distance,
        };
        if let Some(p) = self.prev {
            let crossed = (p.ydot > 0.0 && cur.ydot <= 0.0) || (p.ydot < 0.0 && cur.ydot >= 0.0);
            if crossed {
                self.envelope.push(refine_peak(&p, &cur));
            }
        }
        self.prev = Some(cur);
        let sy = sum_of_guiding_forces(self.model, &[x[0], x[1], x[2], x[3]], speed);
        match self.en.as_mut() {
            Some(en) => en.push(t, speed, distance, sy),
            None => self.pending.push((t, speed, distance, sy)),
        }
    }

    fn last_amplitude(&self) -> f64 {
        self.envelope.last().map_or(0.0, |p| p.amplitude_m)
    }

    /// The last peak amplitude before time `t` (m); 0 if none.
    fn amplitude_before(&self, t: f64) -> f64 {
        self.envelope
            .iter()
            .rev()
            .find(|p| p.t_s < t)
            .map_or(0.0, |p| p.amplitude_m)
    }

    /// Measures f0 on the peaks after `t_from` (or on all of them), builds the EN 14363
    /// stream and feeds it the ΣY samples held so far.
    fn start_en14363(&mut self, t_from: f64, dt: f64) {
        let f0 = self
            .frequency_after(t_from)
            .or_else(|| self.frequency_after(0.0));
        let limit = en14363_limit(self.model.contact.params.axle_load / 2.0);
        let mut en = EnStream::new(f0, dt, limit);
        for (t, v, s, sy) in self.pending.drain(..) {
            en.push(t, v, s, sy);
        }
        self.en = Some(en);
    }

    /// Hunting frequency (Hz) from the mean spacing of the peaks after `t_from` (each peak is
    /// half a period from the next); `None` with fewer than three peaks.
    fn frequency_after(&self, t_from: f64) -> Option<f64> {
        let peaks: Vec<f64> = self
            .envelope
            .iter()
            .filter(|p| p.t_s >= t_from)
            .map(|p| p.t_s)
            .collect();
        let (first, last) = (peaks.first()?, peaks.last()?);
        (peaks.len() >= 3 && last > first)
            .then(|| (peaks.len() - 1) as f64 / (2.0 * (last - first)))
    }
}

/// Runs the phases of a ramp: chunked integration (so that the sample times need not be held
/// for the whole run, and the run can stop early) feeding the streaming analysis.
struct Runner<'a> {
    dt: f64,
    ode: OdeOptions,
    pipe: Pipeline<'a>,
    steps: usize,
    rhs_evals: usize,
}

impl Runner<'_> {
    /// Integrates `field` from `x` (at global time `t0`) for `duration` s, sampling every
    /// `dt`; after each chunk `stop` may end the phase. Returns the final state and time.
    fn run(
        &mut self,
        field: &RampField<'_>,
        mut x: SVector<f64, 5>,
        t0: f64,
        duration: f64,
        stop: &dyn Fn(&Pipeline<'_>) -> bool,
    ) -> Result<(SVector<f64, 5>, f64), RampError> {
        // 2000 samples (4 s at 2 ms): a restart costs one starting-step choice, negligible
        const CHUNK_SAMPLES: usize = 2000;
        let dt = self.dt;
        let total = (duration / dt).floor() as usize;
        let local: Vec<f64> = (1..=CHUNK_SAMPLES.min(total))
            .map(|j| j as f64 * dt)
            .collect();
        let mut done = 0;
        while done < total {
            let n = CHUNK_SAMPLES.min(total - done);
            // sample times by index, not by accumulation
            let base = t0 + done as f64 * dt;
            let pipe = &mut self.pipe;
            let mut observe = |ts: f64, xs: &SVector<f64, 5>| pipe.push(base + ts, xs);
            let sol = integrate_observed(
                field,
                0.0,
                &x,
                n as f64 * dt,
                &self.ode,
                &local[..n],
                &mut observe,
            )
            .map_err(|source| RampError::Ode {
                t: base,
                speed: x[4],
                source,
            })?;
            x = sol.x;
            self.steps += sol.stats.steps;
            self.rhs_evals += sol.stats.rhs_evals;
            done += n;
            if stop(&self.pipe) {
                break;
            }
        }
        Ok((x, t0 + done as f64 * dt))
    }
}

/// The ramp method: settle at `start_speed` from $y(0) = y_0$, then decelerate at `rate`
/// until the peak amplitude has fallen below `threshold` for good (below a tenth of it) or
/// `end_speed` is reached. See the module docs for what the answer means and how it errs.
pub fn ramp(model: &Vehicle, opts: &RampOptions) -> Result<RampResult, RampError> {
    if model.states() != 4 {
        return Err(RampError::States(model.states()));
    }
    opts.validate()?;
    let dt = sample_interval(model, opts.start_speed);
    let mut run = Runner {
        dt,
        ode: ramp_ode(opts.rtol)?,
        pipe: Pipeline::new(model),
        steps: 0,
        rhs_evals: 0,
    };
    let x0 = SVector::<f64, 5>::new(opts.y0, 0.0, 0.0, 0.0, opts.start_speed);
    let settle = RampField { model, rate: 0.0 };
    let (x, t) = run.run(&settle, x0, 0.0, opts.settle, &|_| false)?;
    let start_amplitude_m = run.pipe.last_amplitude();
    let earlier = run.pipe.amplitude_before(0.9 * opts.settle);
    let mut result = RampResult {
        quantity: RAMP_QUANTITY,
        died_at_m_s: None,
        stop: RampStop::NotHuntingAtStart {
            amplitude_m: start_amplitude_m,
        },
        options: *opts,
        sample_interval_s: dt,
        start_amplitude_m,
        settle_drift_rel: (start_amplitude_m - earlier) / start_amplitude_m,
        envelope: Vec::new(),
        en14363: None,
        en14363_speed_m_s: None,
        simulated_s: t,
        steps: run.steps,
        rhs_evals: run.rhs_evals,
    };
    if start_amplitude_m < opts.threshold {
        result.envelope = run.pipe.envelope;
        return Ok(result);
    }
    run.pipe.start_en14363(0.5 * opts.settle, dt);
    let field = RampField {
        model,
        rate: opts.rate,
    };
    let duration = (opts.start_speed - opts.end_speed) / opts.rate;
    let quiet = opts.threshold / 10.0;
    let dead = |p: &Pipeline<'_>| {
        p.last_amplitude() < quiet && p.en.as_ref().is_none_or(EnStream::below_limit)
    };
    let (_, t) = run.run(&field, x, t, duration, &dead)?;
    (result.died_at_m_s, result.stop) = died_at(&run.pipe.envelope, opts.threshold);
    result.envelope = run.pipe.envelope;
    result.en14363 = run.pipe.en.map(EnStream::finish);
    result.en14363_speed_m_s = result.en14363.as_ref().and_then(|e| match e.verdict {
        En14363Verdict::DroppedBelow { speed_m_s } => Some(speed_m_s),
        _ => None,
    });
    (result.simulated_s, result.steps, result.rhs_evals) = (t, run.steps, run.rhs_evals);
    Ok(result)
}

/// The speed where the `envelope` falls below `threshold` (m) for good: after its last peak
/// at or above it, by linear interpolation of ln(amplitude) against speed between that peak
/// and the next (exact for an exponentially decaying amplitude at constant deceleration over
/// one half period). `StillHunting` if the last peak is at or above the threshold.
pub fn died_at(envelope: &[EnvelopePoint], threshold: f64) -> (Option<f64>, RampStop) {
    let Some(j) = envelope.iter().rposition(|p| p.amplitude_m >= threshold) else {
        let amplitude_m = envelope.last().map_or(0.0, |p| p.amplitude_m);
        return (None, RampStop::NotHuntingAtStart { amplitude_m });
    };
    let Some(next) = envelope.get(j + 1) else {
        let amplitude_m = envelope[j].amplitude_m;
        return (None, RampStop::StillHunting { amplitude_m });
    };
    let a = envelope[j];
    let frac = if next.amplitude_m > 0.0 {
        (a.amplitude_m / threshold).ln() / (a.amplitude_m / next.amplitude_m).ln()
    } else {
        0.0
    };
    let speed = a.speed_m_s + frac.clamp(0.0, 1.0) * (next.speed_m_s - a.speed_m_s);
    (Some(speed), RampStop::Died)
}

/// One row of [`RampConvergence`]: a ramp at one rate.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RampRow {
    /// deceleration (m/s²)
    pub rate_m_s2: f64,
    /// the ramp estimate (m/s)
    pub died_at_m_s: Option<f64>,
    /// relative change from the previous row's estimate
    pub change_rel: Option<f64>,
    /// Richardson extrapolation to rate 0 from this row and the previous one, assuming the
    /// lag is proportional to √rate (slow passage through a Hopf point, see the module docs):
    /// $V_k + (V_k − V_{k−1})/(\sqrt 2 − 1)$ (m/s). Indicative only: the logarithmic factor
    /// of the lag makes it overshoot slightly, and near a fold the exponent is 2/3, not 1/2.
    pub extrapolated_m_s: Option<f64>,
    /// the EN 14363 speed of that run (m/s)
    pub en14363_speed_m_s: Option<f64>,
    /// how the run ended
    pub stop: RampStop,
    /// simulated time (s)
    pub simulated_s: f64,
    /// right-hand side evaluations
    pub rhs_evals: usize,
}

/// Why [`ramp_converged`] stopped.
#[derive(Clone, Debug, PartialEq)]
pub enum ConvergenceStop {
    /// The last two estimates agree to the relative tolerance.
    Converged,
    /// `max_halvings` halvings did not reach the tolerance.
    MaxHalvings,
    /// A run ended without the hunting dying (see its row's `stop`): nothing to compare.
    NoEstimate,
    /// A run failed.
    Failed(RampError),
}

/// The ramp estimate as the rate is halved: the table that shows its convergence.
#[derive(Clone, Debug, PartialEq)]
pub struct RampConvergence {
    /// one row per rate, fastest first
    pub rows: Vec<RampRow>,
    /// why it stopped
    pub stop: ConvergenceStop,
    /// the last estimate (m/s), with the rate that gave it (m/s²), when converged
    pub converged: Option<(f64, f64)>,
}

/// Runs [`ramp`] at `opts.rate`, `opts.rate/2`, … (at most `max_halvings` halvings) until two
/// successive estimates agree to `rel_tol`. The estimate's lag behind the critical speed
/// shrinks only like √rate near a Hopf point, so successive differences shrink by about 0.7
/// a halving (the remaining lag is then ≈ 2.4 × the last difference: see
/// [`RampRow::extrapolated_m_s`]), and each halving doubles the simulated time.
///
/// Invalid options are an error; a run that fails is recorded as [`ConvergenceStop::Failed`]
/// with the rows before it.
pub fn ramp_converged(
    model: &Vehicle,
    opts: &RampOptions,
    max_halvings: usize,
    rel_tol: f64,
) -> Result<RampConvergence, RampError> {
    opts.validate()?;
    if !(rel_tol.is_finite() && rel_tol > 0.0) {
        return Err(bad("rel_tol", rel_tol, "must be finite and > 0"));
    }
    let mut rows: Vec<RampRow> = Vec::new();
    let mut o = *opts;
    for k in 0..=max_halvings {
        o.rate = opts.rate / f64::powi(2.0, k as i32);
        let r = match ramp(model, &o) {
            Ok(r) => r,
            Err(e) => {
                return Ok(RampConvergence {
                    rows,
                    stop: ConvergenceStop::Failed(e),
                    converged: None,
                })
            }
        };
        let prev = rows.last().and_then(|p| p.died_at_m_s);
        let change_rel = prev.zip(r.died_at_m_s).map(|(a, b)| ((b - a) / b).abs());
        let extrapolated_m_s = prev
            .zip(r.died_at_m_s)
            .map(|(a, b)| b + (b - a) / (std::f64::consts::SQRT_2 - 1.0));
        rows.push(RampRow {
            rate_m_s2: o.rate,
            died_at_m_s: r.died_at_m_s,
            change_rel,
            extrapolated_m_s,
            en14363_speed_m_s: r.en14363_speed_m_s,
            stop: r.stop,
            simulated_s: r.simulated_s,
            rhs_evals: r.rhs_evals,
        });
        let Some(v) = r.died_at_m_s else {
            return Ok(RampConvergence {
                rows,
                stop: ConvergenceStop::NoEstimate,
                converged: None,
            });
        };
        if change_rel.is_some_and(|c| c <= rel_tol) {
            let converged = Some((v, o.rate));
            return Ok(RampConvergence {
                rows,
                stop: ConvergenceStop::Converged,
                converged,
            });
        }
    }
    Ok(RampConvergence {
        rows,
        stop: ConvergenceStop::MaxHalvings,
        converged: None,
    })
}
