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
    /// No ramp is compiled for this state size (4, 12, 14, 28 and 34 are).
    #[error("no ramp is compiled for {0} states (4, 12, 14, 28 and 34 are)")]
    States(usize),
    /// The integration failed.
    #[error("integration failed in the run from t = {t} s, V = {speed:.3} m/s: {source}")]
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

/// One peak of |y| of the leading wheelset in the ramp's history.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EnvelopePoint {
    /// time of the peak (s)
    pub t_s: f64,
    /// speed at the peak (m/s)
    pub speed_m_s: f64,
    /// peak lateral amplitude |y| of the leading wheelset (m)
    pub amplitude_m: f64,
}

/// How a ramp run ended.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum RampStop {
    /// The peak amplitude fell below the threshold for good: the run went on until it was
    /// below a tenth of it (and every wheelset's EN 14363 r.m.s. below its limit), or to
    /// `end_speed`.
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
    /// the larger of the last two peak amplitudes of the settle phase (m): the cycle's max|y|
    /// also when the cycle is asymmetric
    pub start_amplitude_m: f64,
    /// relative change of the cycle's amplitude (the larger of two successive peaks) over the
    /// last 10 % of the settle phase (–):
    /// ≈ 0 when the motion had settled on a cycle; clearly negative when it was still dying
    /// out (the start speed is below the nonlinear critical speed, or `settle` is too short)
    pub settle_drift_rel: f64,
    /// every peak of the leading wheelset's |y|, settle phase included
    pub envelope: Vec<EnvelopePoint>,
    /// the EN 14363 evaluation of the worst wheelset ([`worst_wheelset`]; the only one of a
    /// single wheelset): a copy of `en14363_wheelsets[en14363_worst]`; absent when there was
    /// no hunting at the start
    pub en14363: Option<En14363>,
    /// the EN 14363 evaluation of every wheelset, front to rear (empty when there was no
    /// hunting at the start)
    pub en14363_wheelsets: Vec<En14363>,
    /// index into `en14363_wheelsets` of the worst wheelset, on which the verdict is judged
    pub en14363_worst: Option<usize>,
    /// speed at which the worst wheelset's EN 14363 sliding r.m.s. dropped below the limit for
    /// good (m/s), when it was ever above it: below it every wheelset is below its limit
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

/// The streaming analysis of the history: peaks of the leading wheelset's y, every
/// wheelset's ΣY, and one EN 14363 filter and window per wheelset.
struct Pipeline<'a> {
    model: &'a Vehicle,
    /// the model's state count; the speed is the state after them
    states: usize,
    /// index of the leading wheelset's ẏ: its y is coordinate 0, so ẏ is state `dofs`
    ydot: usize,
    prev: Option<Sample>,
    envelope: Vec<EnvelopePoint>,
    /// (t, speed, distance, ΣY per wheelset) samples held until f0 is known
    pending: Vec<(f64, f64, f64, Vec<f64>)>,
    /// one stream per wheelset, front to rear, once f0 is known
    en: Option<Vec<EnStream>>,
}

impl<'a> Pipeline<'a> {
    fn new(model: &'a Vehicle) -> Self {
        Self {
            model,
            states: model.states(),
            ydot: model.dofs(),
            prev: None,
            envelope: Vec::new(),
            pending: Vec::new(),
            en: None,
        }
    }

    /// Takes the sample (t, x) with x the model's states followed by the speed.
    fn push(&mut self, t: f64, x: &[f64]) {
        let (xs, speed) = (&x[..self.states], x[self.states]);
        let distance = match self.prev {
            Some(p) => p.distance + 0.5 * (t - p.t) * (p.speed + speed),
            None => 0.0,
        };
        let cur = Sample {
            t,
            y: xs[0],
            ydot: xs[self.ydot],
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
        let sy = self.model.guiding_forces(xs, speed);
        match self.en.as_mut() {
            Some(streams) => {
                for (en, &f) in streams.iter_mut().zip(&sy) {
                    en.push(t, speed, distance, f);
                }
            }
            None => self.pending.push((t, speed, distance, sy)),
        }
    }

    fn last_amplitude(&self) -> f64 {
        self.envelope.last().map_or(0.0, |p| p.amplitude_m)
    }

    /// Whether every wheelset's last sliding r.m.s. is below its limit (true before the
    /// streams start).
    fn en_below_limit(&self) -> bool {
        self.en
            .as_ref()
            .is_none_or(|s| s.iter().all(EnStream::below_limit))
    }

    /// The larger of the last two peak amplitudes before time `t` (m; 0 if none): one maximum
    /// and one minimum of y, so that an asymmetric cycle (whose two sides differ: the DTU
    /// bogie's large cycle reaches 10.1 mm on one side and 5 mm on the other) is measured by
    /// its larger side whichever peak came last.
    fn cycle_amplitude_before(&self, t: f64) -> f64 {
        self.envelope
            .iter()
            .rev()
            .filter(|p| p.t_s < t)
            .take(2)
            .map(|p| p.amplitude_m)
            .fold(0.0, f64::max)
    }

    /// Measures f0 on the peaks after `t_from` (or on all of them), builds one EN 14363 stream
    /// per wheelset (the same f0 for all: the vehicle hunts at one frequency) and feeds them
    /// the ΣY samples held so far.
    fn start_en14363(&mut self, t_from: f64, dt: f64) {
        let f0 = self
            .frequency_after(t_from)
            .or_else(|| self.frequency_after(0.0));
        // Q0 = W/2: the study's axle load W is the whole vertical load on the axle's two
        // contacts (docs/model.md §2, §11), bogie and car body included
        let limit = en14363_limit(self.model.contact.params.axle_load / 2.0);
        let wheelsets = self.model.wheelset_dofs().len();
        let mut streams: Vec<EnStream> = (0..wheelsets)
            .map(|_| EnStream::new(f0, dt, limit))
            .collect();
        for (t, v, s, sy) in self.pending.drain(..) {
            for (en, &f) in streams.iter_mut().zip(&sy) {
                en.push(t, v, s, f);
            }
        }
        self.en = Some(streams);
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

    /// Every wheelset's evaluation, named after its body.
    fn finish_en14363(&mut self) -> Vec<En14363> {
        let names: Vec<String> = self
            .model
            .bodies
            .iter()
            .filter(|b| b.kind == crate::model::BodyKind::Wheelset)
            .map(|b| b.name.clone())
            .collect();
        self.en
            .take()
            .unwrap_or_default()
            .into_iter()
            .enumerate()
            .map(|(k, en)| {
                let name = names
                    .get(k)
                    .cloned()
                    .unwrap_or_else(|| format!("wheelset {}", k + 1));
                en.finish(k, name)
            })
            .collect()
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
    /// Integrates `field` (`M` = the model's states + 1) from `x` (at global time `t0`) for
    /// `duration` s, sampling every `dt`; after each chunk `stop` may end the phase. Returns
    /// the final state and time.
    fn run<const M: usize>(
        &mut self,
        field: &RampField<'_>,
        mut x: SVector<f64, M>,
        t0: f64,
        duration: f64,
        stop: &dyn Fn(&Pipeline<'_>) -> bool,
    ) -> Result<(SVector<f64, M>, f64), RampError> {
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
            let mut observe = |ts: f64, xs: &SVector<f64, M>| pipe.push(base + ts, xs.as_slice());
            let sol = integrate_observed(
                field,
                0.0,
                &x,
                n as f64 * dt,
                &self.ode,
                &local[..n],
                &mut observe,
            )
            .map_err(|e| RampError::Ode {
                t: base,
                speed: x[M - 1],
                source: e.shifted(base),
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

/// The ramp method on a model of any layout: settle at `start_speed` from the leading
/// wheelset displaced by $y_0$ (all else at rest), then decelerate at `rate` until the leading
/// wheelset's peak amplitude has fallen below `threshold` for good (below a tenth of it, with
/// every wheelset's EN 14363 r.m.s. below its limit) or `end_speed` is reached. See the module
/// docs for what the answer means and how it errs. A state size for which no ramp is compiled
/// is [`RampError::States`].
pub fn ramp(model: &Vehicle, opts: &RampOptions) -> Result<RampResult, RampError> {
    crate::with_states_plus_one!(model.states(), M => ramp_states::<M>(model, opts),
        _ => Err(RampError::States(model.states())))
}

/// [`ramp`] with the field's size `M` = the model's states + 1.
fn ramp_states<const M: usize>(
    model: &Vehicle,
    opts: &RampOptions,
) -> Result<RampResult, RampError> {
    if M != model.states() + 1 {
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
    let mut x0 = SVector::<f64, M>::zeros();
    x0[0] = opts.y0;
    x0[M - 1] = opts.start_speed;
    let settle = RampField { model, rate: 0.0 };
    let (x, t) = run.run(&settle, x0, 0.0, opts.settle, &|_| false)?;
    let start_amplitude_m = run.pipe.cycle_amplitude_before(f64::INFINITY);
    let earlier = run.pipe.cycle_amplitude_before(0.9 * opts.settle);
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
        en14363_wheelsets: Vec::new(),
        en14363_worst: None,
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
    let dead = |p: &Pipeline<'_>| p.last_amplitude() < quiet && p.en_below_limit();
    let (_, t) = run.run(&field, x, t, duration, &dead)?;
    (result.died_at_m_s, result.stop) = died_at(&run.pipe.envelope, opts.threshold);
    result.en14363_wheelsets = run.pipe.finish_en14363();
    result.envelope = run.pipe.envelope;
    result.en14363_worst = worst_wheelset(&result.en14363_wheelsets);
    result.en14363 = result
        .en14363_worst
        .and_then(|k| result.en14363_wheelsets.get(k).cloned());
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
