//! EN 14363 instability criterion: ΣY, the band-pass filter, the sliding r.m.s. and the limit
//! (see the module docs of [`crate::simulate`] for the sources and the choices made).

use std::collections::VecDeque;

use super::ramp::bad;
use super::*;

// ---------------------------------------------------------------------------------------
// EN 14363: ΣY, the band-pass filter, the sliding r.m.s. and the limit
// ---------------------------------------------------------------------------------------

/// Sum of guiding forces ΣY (N) of the leading wheelset at state `x` (the model's states)
/// and speed `v` (m/s): every lateral wheel–rail force on it (creep after the creep law,
/// gravitational stiffness, flange), i.e. $m\ddot y − F_s$ of docs/model.md §8, taken directly as the
/// wheelset's lateral contact force ([`Vehicle::guiding_forces`] gives every wheelset's).
pub fn sum_of_guiding_forces(model: &Vehicle, x: &[f64], v: f64) -> f64 {
    model
        .guiding_forces(x, v)
        .first()
        .copied()
        .unwrap_or(f64::NAN)
}

/// The EN 14363 limit of the sliding r.m.s. of ΣY (N): $(10 + 2Q_0/3)/2$ kN with $Q_0$ the
/// static wheel load in kN; here `static_wheel_load` $Q_0$ in N.
pub fn en14363_limit(static_wheel_load: f64) -> f64 {
    (10e3 + 2.0 * static_wheel_load / 3.0) / 2.0
}

/// A biquad in transposed direct form II, $b_1 = 0$, $b_2 = −b_0$ (a band-pass section).
#[derive(Clone, Copy, Debug, PartialEq)]
struct Biquad {
    b0: f64,
    a1: f64,
    a2: f64,
    z1: f64,
    z2: f64,
}

impl Biquad {
    #[inline]
    fn step(&mut self, x: f64) -> f64 {
        let y = self.b0 * x + self.z1;
        self.z1 = -self.a1 * y + self.z2;
        self.z2 = -self.b0 * x - self.a2 * y;
        y
    }
}

/// A digital Butterworth band-pass filter, forward only (causal), as a cascade of biquads.
///
/// Design: the low-pass prototype of order $n$ has poles $p_k = e^{iπ(2k+n+1)/(2n)}$; the
/// band edges are pre-warped, $Ω_j = 2f_s\tan(πf_j/f_s)$, $Ω_0 = \sqrt{Ω_1Ω_2}$,
/// $B = Ω_2 − Ω_1$; the transformation $s \to (s^2 + Ω_0^2)/(Bs)$ turns each $p_k$ into the
/// roots of $s^2 − p_kBs + Ω_0^2$, grouped with their conjugates into real sections
/// $Bs/(s^2 + a_1s + a_0)$; the bilinear transform $s = 2f_s(1 − z^{-1})/(1 + z^{-1})$
/// maps each to a biquad with zeros at $z = ±1$. The result has the analog magnitude at the
/// pre-warped frequency: $|H| = 1/\sqrt{1 + ((Ω^2 − Ω_0^2)/(BΩ))^{2n}}$, −3 dB at $f_1$, $f_2$.
#[derive(Clone, Debug, PartialEq)]
pub struct BandPass {
    sections: Vec<Biquad>,
}

impl BandPass {
    /// Order-`order` prototype, pass band [`f_low`, `f_high`] Hz, sample rate `fs` Hz.
    pub fn butterworth(order: usize, f_low: f64, f_high: f64, fs: f64) -> Result<Self, RampError> {
        if !(1..=16).contains(&order) {
            return Err(bad("order", order as f64, "must lie in 1..=16"));
        }
        if !(fs.is_finite() && fs > 0.0) {
            return Err(bad("sample rate", fs, "must be finite and > 0 Hz"));
        }
        if !(f_low.is_finite() && f_low > 0.0) {
            return Err(bad("f_low", f_low, "must be finite and > 0 Hz"));
        }
        if !(f_high.is_finite() && f_high > f_low && f_high < 0.5 * fs) {
            return Err(bad(
                "f_high",
                f_high,
                "must lie between f_low and the Nyquist frequency",
            ));
        }
        let c = 2.0 * fs;
        let warp = |f: f64| c * (std::f64::consts::PI * f / fs).tan();
        let (w1, w2) = (warp(f_low), warp(f_high));
        let (w0sq, bw) = (w1 * w2, w2 - w1);
        let mut analog: Vec<(f64, f64)> = Vec::with_capacity(order); // (a1, a0)
        for k in 0..order {
            let theta = std::f64::consts::PI * (2 * k + order + 1) as f64 / (2 * order) as f64;
            let p = Complex::from_polar(1.0, theta);
            if p.im < -1e-12 {
                continue; // the conjugate of an upper pole, handled with it
            }
            if p.im.abs() <= 1e-12 {
                // real prototype pole −1: s² + Bs + Ω0²
                analog.push((bw, w0sq));
                continue;
            }
            let pb = p * bw;
            let disc = (pb * pb - 4.0 * w0sq).sqrt();
            for q in [(pb + disc) * 0.5, (pb - disc) * 0.5] {
                // q and its conjugate: s² − 2Re(q)s + |q|²
                analog.push((-2.0 * q.re, q.norm_sqr()));
            }
        }
        let sections = analog
            .into_iter()
            .map(|(a1, a0)| {
                let d0 = c * c + a1 * c + a0;
                Biquad {
                    b0: bw * c / d0,
                    a1: (2.0 * a0 - 2.0 * c * c) / d0,
                    a2: (c * c - a1 * c + a0) / d0,
                    z1: 0.0,
                    z2: 0.0,
                }
            })
            .collect();
        Ok(Self { sections })
    }

    /// The EN 14363 band $f_0 ± 2$ Hz, 4th-order prototype, at sample rate `fs` (Hz).
    pub fn en14363(f0: f64, fs: f64) -> Result<Self, RampError> {
        if !(f0.is_finite() && f0 > 2.0) {
            return Err(bad("f0", f0, "must exceed the 2 Hz half band"));
        }
        Self::butterworth(4, f0 - 2.0, f0 + 2.0, fs)
    }

    /// Filters one sample.
    pub fn step(&mut self, x: f64) -> f64 {
        self.sections.iter_mut().fold(x, |v, s| s.step(v))
    }

    /// Filters a whole signal (forward, from zero state).
    pub fn filter(&mut self, x: &[f64]) -> Vec<f64> {
        x.iter().map(|&v| self.step(v)).collect()
    }

    /// Magnitude of the frequency response at `f` Hz for sample rate `fs` Hz.
    pub fn gain(&self, f: f64, fs: f64) -> f64 {
        let z1 = Complex::from_polar(1.0, -2.0 * std::f64::consts::PI * f / fs);
        let z2 = z1 * z1;
        self.sections
            .iter()
            .map(|s| ((1.0 - z2) * s.b0 / (1.0 + z1 * s.a1 + z2 * s.a2)).norm())
            .product()
    }
}

/// Sliding r.m.s. over a window of track length, reported every `step` of track.
#[derive(Clone, Debug)]
pub struct SlidingRms {
    window_m: f64,
    step_m: f64,
    buf: VecDeque<(f64, f64)>,
    first: Option<f64>,
    next_report: f64,
}

impl SlidingRms {
    /// A window of `window_m` metres reported every `step_m` metres (EN 14363: 100 m; the
    /// step of 10 m is this crate's choice); both finite and > 0.
    pub fn new(window_m: f64, step_m: f64) -> Result<Self, RampError> {
        if !(window_m.is_finite() && window_m > 0.0) {
            return Err(bad("window_m", window_m, "must be finite and > 0 m"));
        }
        if !(step_m.is_finite() && step_m > 0.0) {
            return Err(bad("step_m", step_m, "must be finite and > 0 m"));
        }
        Ok(Self {
            window_m,
            step_m,
            buf: VecDeque::new(),
            first: None,
            next_report: f64::INFINITY,
        })
    }

    /// Adds the value `z` at track position `s` (m, increasing); returns the r.m.s. over the
    /// samples in $(s − \text{window}, s]$ when a report is due (the first once a whole window
    /// has been seen).
    pub fn push(&mut self, s: f64, z: f64) -> Option<f64> {
        let first = *self.first.get_or_insert(s);
        if self.next_report.is_infinite() {
            self.next_report = first + self.window_m;
        }
        self.buf.push_back((s, z * z));
        while self
            .buf
            .front()
            .is_some_and(|&(s0, _)| s0 <= s - self.window_m)
        {
            self.buf.pop_front();
        }
        if s + 1e-9 * self.step_m < self.next_report {
            return None;
        }
        while self.next_report <= s + 1e-9 * self.step_m {
            self.next_report += self.step_m;
        }
        let sum: f64 = self.buf.iter().map(|&(_, q)| q).sum();
        Some((sum / self.buf.len() as f64).sqrt())
    }
}

/// One point of the EN 14363 sliding r.m.s. series.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RmsPoint {
    /// time at the window's end (s)
    pub t_s: f64,
    /// speed at the window's end (m/s)
    pub speed_m_s: f64,
    /// sliding r.m.s. of the filtered ΣY (N)
    pub rms_n: f64,
}

/// The EN 14363 verdict on a ramp.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum En14363Verdict {
    /// The sliding r.m.s. never reached the limit.
    NeverExceeded,
    /// It was at or above the limit and dropped below it for good at `speed_m_s` (linear
    /// interpolation between the two reports around the crossing).
    DroppedBelow {
        /// speed (m/s)
        speed_m_s: f64,
    },
    /// Still at or above the limit at the end of the run.
    StillAbove,
    /// Not evaluated: no hunting frequency could be measured, or it is at most 2 Hz so that
    /// the band f0 ± 2 Hz would reach 0 Hz.
    NotEvaluated,
}

/// The EN 14363 evaluation of one wheelset over a ramp.
#[derive(Clone, Debug, PartialEq)]
pub struct En14363 {
    /// the wheelset's index, 0 for the leading one, front to rear
    /// ([`Vehicle::wheelset_dofs`] order)
    pub wheelset: usize,
    /// its body name, e.g. `"wheelset 2"` ([`Vehicle::bodies`])
    pub name: String,
    /// hunting frequency f0 (Hz), from the settle phase's peak spacing
    pub f0_hz: Option<f64>,
    /// the limit (ΣY)_lim (N)
    pub limit_n: f64,
    /// the largest sliding r.m.s. (N)
    pub max_rms_n: f64,
    /// the sliding r.m.s. every 10 m of track
    pub series: Vec<RmsPoint>,
    /// the verdict
    pub verdict: En14363Verdict,
}

/// The verdict on a sliding r.m.s. `series` against `limit` (N): the last report at or
/// above the limit, and the speed where the r.m.s. crosses it after that report (linear
/// interpolation between the two reports).
pub fn en14363_verdict(series: &[RmsPoint], limit: f64) -> En14363Verdict {
    let Some(j) = series.iter().rposition(|p| p.rms_n >= limit) else {
        return En14363Verdict::NeverExceeded;
    };
    let Some(b) = series.get(j + 1) else {
        return En14363Verdict::StillAbove;
    };
    let a = series[j];
    let frac = (a.rms_n - limit) / (a.rms_n - b.rms_n);
    let speed_m_s = a.speed_m_s + frac * (b.speed_m_s - a.speed_m_s);
    En14363Verdict::DroppedBelow { speed_m_s }
}

/// How severely one wheelset's evaluation fails the criterion, as a key that sorts from mild
/// to severe: first the verdict's class ([`En14363Verdict::StillAbove`] >
/// [`En14363Verdict::DroppedBelow`] > [`En14363Verdict::NeverExceeded`] >
/// [`En14363Verdict::NotEvaluated`]), then, between two that dropped below, the lower speed
/// (the r.m.s. stayed above the limit longest), then the larger `max_rms_n / limit_n`.
fn severity(e: &En14363) -> (u8, f64, f64) {
    let ratio = e.max_rms_n / e.limit_n;
    let ratio = if ratio.is_finite() { ratio } else { 0.0 };
    match e.verdict {
        En14363Verdict::StillAbove => (3, 0.0, ratio),
        En14363Verdict::DroppedBelow { speed_m_s } => (2, -speed_m_s, ratio),
        En14363Verdict::NeverExceeded => (1, 0.0, ratio),
        En14363Verdict::NotEvaluated => (0, 0.0, ratio),
    }
}

/// The worst wheelset of a vehicle's EN 14363 evaluations (index into `evals`), on which the
/// vehicle's verdict is judged: the one whose sliding r.m.s. **stays at or above its limit
/// down to the lowest speed** (still above at the end of the run beats any that dropped below;
/// between two that dropped below, the lower [`En14363Verdict::DroppedBelow`] speed), and
/// when none of them ever reached its limit (or two tie), the one with the **largest
/// max r.m.s. relative to its limit**; a remaining tie goes to the front-most wheelset.
/// `None` for an empty slice.
pub fn worst_wheelset(evals: &[En14363]) -> Option<usize> {
    let mut best: Option<(usize, (u8, f64, f64))> = None;
    for (i, e) in evals.iter().enumerate() {
        let key = severity(e);
        let worse = best.is_none_or(|(_, b)| {
            key.0
                .cmp(&b.0)
                .then(key.1.total_cmp(&b.1))
                .then(key.2.total_cmp(&b.2))
                .is_gt()
        });
        if worse {
            best = Some((i, key));
        }
    }
    best.map(|(i, _)| i)
}

/// The streaming EN 14363 evaluation: filter → sliding r.m.s. → series.
pub(super) struct EnStream {
    f0: Option<f64>,
    filter: Option<BandPass>,
    rms: Option<SlidingRms>,
    limit: f64,
    series: Vec<RmsPoint>,
}

impl EnStream {
    pub(super) fn new(f0: Option<f64>, dt: f64, limit: f64) -> Self {
        let filter = f0.and_then(|f| BandPass::en14363(f, 1.0 / dt).ok());
        Self {
            f0,
            filter,
            rms: SlidingRms::new(100.0, 10.0).ok(),
            limit,
            series: Vec::new(),
        }
    }

    pub(super) fn push(&mut self, t: f64, speed: f64, distance: f64, sy: f64) {
        let (Some(filter), Some(rms)) = (self.filter.as_mut(), self.rms.as_mut()) else {
            return;
        };
        if let Some(rms_n) = rms.push(distance, filter.step(sy)) {
            self.series.push(RmsPoint {
                t_s: t,
                speed_m_s: speed,
                rms_n,
            });
        }
    }

    pub(super) fn below_limit(&self) -> bool {
        self.series.last().is_none_or(|p| p.rms_n < self.limit)
    }

    pub(super) fn finish(self, wheelset: usize, name: String) -> En14363 {
        let max_rms_n = self.series.iter().map(|p| p.rms_n).fold(0.0, f64::max);
        let verdict = if self.filter.is_none() {
            En14363Verdict::NotEvaluated
        } else {
            en14363_verdict(&self.series, self.limit)
        };
        En14363 {
            wheelset,
            name,
            f0_hz: self.f0,
            limit_n: self.limit,
            max_rms_n,
            series: self.series,
            verdict,
        }
    }
}
