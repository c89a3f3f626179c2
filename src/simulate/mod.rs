//! Time simulation of a model of any layout (wheelset, bogie, car: docs/model.md §11) at constant
//! speed, the ramp method, and the EN 14363 instability criterion evaluated on the ramp's
//! time history.
//!
//! * [`simulate`]: the seed's experiment (its Figs. 10–11): start from the leading wheelset's
//!   y(0), integrate at a fixed speed, sample uniformly.
//! * [`ramp`]: the industrial ramp method (True 2013; GENSYS documents a 5 km/h per s
//!   deceleration): start on a large cycle above the critical speed, let it settle, then
//!   decrease the speed linearly in one long simulation ([`RampField`]: the model's states
//!   and the speed as one more, for every layout) until the hunting dies. The result is the
//!   **ramp (simulation) estimate of the nonlinear critical speed**: the speed at which the
//!   peak lateral amplitude of the **leading wheelset** (state 0, its rate at state
//!   [`Vehicle::dofs`]) falls below a threshold for good. [`ramp_converged`] halves the
//!   deceleration until two successive estimates agree.
//! * The EN 14363 instability criterion on the same history, **one stream per wheelset**
//!   ([`Vehicle::guiding_forces`], [`BandPass`], [`SlidingRms`], [`en14363_limit`],
//!   [`en14363_verdict`]), judged on the worst wheelset ([`worst_wheelset`]) and reported in
//!   [`RampResult::en14363`] (the worst) and [`RampResult::en14363_wheelsets`] (all).
//!
//! # What the ramp estimate is, and which way it errs
//!
//! The ramp estimate is *not* the nonlinear critical speed $V_{NL}$ of docs/model.md §9; it
//! approaches it as the deceleration $r \to 0$ and the threshold $\to 0$, and the two
//! limits err in opposite directions:
//!
//! * **Lag (rate).** The amplitude relaxes towards the cycle at the rate of the cycle's
//!   nontrivial Floquet exponent, and decays below the critical speed at the rate
//!   $\mathrm{Re}\,λ(V)$ of the centred motion's eigenvalue. Both go to zero at a Hopf point,
//!   so the motion lags behind the slowly decreasing speed and keeps hunting *below*
//!   $V_{NL}$. Near a supercritical Hopf point $V_H$ (where $V_{NL} = V_H$),
//!   $\mathrm{Re}\,λ ≈ σ'(V − V_H)$ and an amplitude $a_H$ at $V_H$ decays as
//!   $a_H \exp(−σ'(V_H − V)^2 / 2r)$: the hunting dies about
//!   $\sqrt{2r\ln(a_H/\text{threshold})/σ'}$ *below* $V_H$, a lag that shrinks only like
//!   $\sqrt r$ (slow passage through a Hopf bifurcation). Near the fold of a subcritical
//!   branch the same bottleneck delays the collapse (a lag of order $r^{2/3}$). So at a
//!   finite rate the ramp **under-estimates** $V_{NL}$; it is not a bracket from above.
//! * **Threshold.** A cycle whose amplitude is below the threshold counts as dead, so even
//!   at $r \to 0$ the estimate converges to the speed where the stable branch's amplitude
//!   equals the threshold: for a supercritical Hopf point slightly *above* $V_H$ (the
//!   branch grows like $\sqrt{V − V_H}$: for `studies/seed-hunting.toml` 0.1 mm is reached
//!   a few mm/s above $V_H$), for a subcritical one at the fold, whose amplitude is finite.
//!
//! Measured on `studies/seed-hunting.toml` (supercritical, $V_{NL} = V_H = 70.707$ m/s, start
//! 72 m/s, threshold 0.1 mm; `tests/simulate.rs` prints the table): at the GENSYS rate the
//! hunting dies at 59.7 m/s, 11 m/s too low; each halving of the rate multiplies the lag by
//! ≈ 0.68 (√½ and the logarithm); after 8 halvings (5.4e-3 m/s², 400 s simulated) the estimate
//! is 70.18 m/s, still 0.53 m/s low although successive estimates differ by only 0.36 %. A
//! successive-difference criterion therefore over-states the accuracy by a factor ≈ 3 here;
//! [`RampRow::extrapolated_m_s`] (Richardson in √rate) gives 70.78 m/s from the same two runs.
//! On `studies/flange-hysteresis.toml` (supercritical Hopf point at 77.77 m/s, folds near
//! 84 m/s), starting on the large flange-contact cycle, the ramp drops to the small-cycle
//! branch at the fold and dies below 77.77 m/s in the same way.
//!
//! Measured on `studies/dtu-cooperrider-bogie.toml` (12 states; `tests/ramp_vehicle.rs`): from
//! its small supercritical cycle (0.669 mm at 220 m/s) the hunting dies 3.96 m/s below
//! $V_H = 216.162$ m/s at 1 m/s² and 1.71 m/s below at 0.25 m/s² (ratio 0.43 for a quarter of
//! the rate: √¼ and the logarithm). From its large cycle at 226.97 m/s (1.05 $V_H$, the CLI's
//! default start: 10.09 mm on one side, 5.0 mm on the other, an asymmetric cycle that runs
//! partly on the linear extension of the 8 mm contact table) it dies at 120.72, 122.14,
//! 122.94 and 123.37 m/s at 1.389, 0.7, 0.35 and 0.175 m/s²: far below the 150.51 m/s fold
//! that the continuation (of the symmetric branch, to 7 mm) reports as $V_{NL}$, and not by
//! lag: a constant-speed simulation at 135 m/s from the ramp's state keeps hunting at 8.4 mm.
//!
//! # The EN 14363 instability criterion
//!
//! The assessment quantity is the sum of guiding forces ΣY on each wheelset: the lateral
//! wheel–rail forces, creep (after the Shen factor), the lateral resultant of the normal
//! forces and the flange force: every term of $m\ddot y$ in docs/model.md §8 except the suspension
//! force, i.e. for wheelset $k$ of a vehicle
//! $$ΣY_k = m\ddot y_k + (Kq + C\dot q)_{y_k}$$
//! (docs/model.md §11: every lateral force on it but the elements'), taken directly as its lateral
//! contact force ([`Vehicle::guiding_forces`]; [`sum_of_guiding_forces`] is the leading
//! wheelset's). Each wheelset's ΣY is band-pass filtered to $f_0 ± 2$ Hz around the hunting
//! frequency $f_0$ (one $f_0$ for the vehicle, measured on the leading wheelset), and its
//! sliding r.m.s. over 100 m of track is compared with $(ΣY)_{lim} = (10 + 2Q_0/3)/2$ kN,
//! $Q_0$ the static wheel load in kN ([`en14363_limit`]): $Q_0 = W/2$ with $W$ the study's
//! axle load, which docs/model.md §2 and §11 define as the whole vertical load on the axle's two
//! contacts (for a vehicle it already includes the bogie's and the car body's share: the
//! DTU studies give 133.3 kN, the load of their contact table), so the limit is the same for
//! every wheelset. The vehicle's verdict is that of its worst wheelset ([`worst_wheelset`]:
//! the one above its limit down to the lowest speed, else the largest r.m.s.); below the
//! reported EN 14363 speed every wheelset is below its limit. The ramp stops early only when
//! the leading wheelset's amplitude is below a tenth of the threshold **and** every
//! wheelset's r.m.s. is below its limit.
//!
//! Sources: EN 14363 (instability assessment quantity ΣY, sliding r.m.s., filter band
//! $f_0 ± 2$ Hz, 100 m window, limit $(10 + 2Q_0/3)/2$ kN), as summarised in the GENSYS
//! course notes on the UIC 518 / EN 14363 acceptance tests (gensys.se, "UIC518_tests"). The
//! standard's text was not available to this project: its clause numbers are not quoted,
//! and two details it may fix were chosen here and are stated as choices:
//!
//! * **Filter.** A Butterworth band-pass from a 4th-order low-pass prototype (as
//!   `butter(4, [f1, f2], 'bandpass')` in MATLAB/SciPy: 8 poles, four biquad sections,
//!   −3 dB exactly at $f_0 ± 2$ Hz), designed by the bilinear transform with pre-warped band
//!   edges and the low-pass-to-band-pass transformation $s \to (s^2 + Ω_0^2)/(Bs)$
//!   (Oppenheim & Schafer, *Discrete-Time Signal Processing*, 3rd ed., ch. 7; any DSP text
//!   has both steps). It runs **forward only** (causal, as an on-board measurement would),
//!   so that the cut-offs stay the specified −3 dB points (forward–backward filtering would
//!   square the magnitude and move them to −6 dB) and the history can be filtered as it is
//!   computed, without storing it. The price is the group delay at $f_0$, about
//!   $2 \cdot 2.61/(2π \cdot 4\,\text{Hz}) ≈ 0.2$ s: the r.m.s. lags the speed by $r$ times
//!   that (≈ 0.3 m/s at 1.389 m/s²).
//! * **Window step.** The sliding r.m.s. is reported every 10 m of track.
//! * **$f_0$** is measured, not assumed: the mean spacing of the peaks of y over the second
//!   half of the settle phase (the hunting frequency of the cycle at the start speed).
//!   The band is not re-centred during the ramp: when the ramp leaves the start cycle for
//!   another one (on `studies/flange-hysteresis.toml` f0 is 16.7 Hz on the flange-contact
//!   cycle, 12.2 Hz on the small cycle below the fold) the second is attenuated.
//!
//! A single wheelset of the seed's size produces small guiding forces: on
//! `studies/seed-hunting.toml` the r.m.s. is 3.4 kN on the 6.8 mm cycle at 75 m/s and 8.1 kN
//! on the 20 mm cycle at 103.6 m/s, far below the 23.3 kN limit, so the criterion never flags that wheelset (the verdict says so, with the
//! largest r.m.s. reached). Ramped from 1.05 $V_H$ at 1.389 m/s², the DTU bogie on its 10 mm
//! cycle reaches a sliding r.m.s. of 11.59 kN on the leading wheelset and 5.55 kN on the
//! trailing one, the DTU car 11.38, 5.24, 12.77 and 5.72 kN (wheelsets 1–4; wheelset 3, the
//! leading one of the rear bogie, is the worst), all below their 27.22 kN limit
//! ($Q_0$ = 66.66 kN): the DTU table's low conicity (0.029) keeps the guiding forces small.

use nalgebra::{Complex, SMatrix, SVector};

use crate::model::Vehicle;
use crate::system::ode::{integrate_observed, OdeError, OdeOptions, Tolerances, VectorField};

/// A sampled time history at one speed.
#[derive(Clone, Debug, PartialEq)]
pub struct TimeHistory {
    /// speed (m/s)
    pub speed_m_s: f64,
    /// sample times (s)
    pub t: Vec<f64>,
    /// states at each sample, in the model's state order (y m, ψ rad, ẏ m/s, ψ̇ rad/s for the
    /// wheelset; [`crate::bifurcation::state_names`] for a vehicle): the leading wheelset's y
    /// is always the first
    pub x: Vec<Vec<f64>>,
    /// the state components with their SI units
    pub state_names: Vec<String>,
}

/// Where one wheelset's coordinates are in a [`TimeHistory`]'s states.
#[derive(Debug, Clone, PartialEq)]
pub struct WheelsetColumns {
    /// index of its lateral displacement y (m)
    pub y: usize,
    /// index of its yaw ψ (rad)
    pub psi: usize,
    /// index of its lateral velocity ẏ (m/s)
    pub ydot: usize,
    /// its name ("wheelset 3") on a vehicle; `None` for a single wheelset
    pub name: Option<String>,
}

impl TimeHistory {
    /// The wheelset that hunts most over the second half of the run (largest |y|): where its
    /// y, ψ and ẏ are in the state, and its name (`None` for a single wheelset, whose y, ψ, ẏ
    /// are the first three states).
    pub fn largest_wheelset(&self) -> WheelsetColumns {
        let index = |name: &str| self.state_names.iter().position(|n| n == name);
        let half = &self.x[self.x.len() / 2..];
        let mut best: Option<(f64, WheelsetColumns)> = None;
        for (i, n) in self.state_names.iter().enumerate() {
            let Some(k) = n
                .strip_prefix("y_wheelset_")
                .and_then(|r| r.strip_suffix("_m"))
            else {
                continue;
            };
            let (Some(psi), Some(ydot)) = (
                index(&format!("psi_wheelset_{k}_rad")),
                index(&format!("ydot_wheelset_{k}_m_s")),
            ) else {
                continue;
            };
            let a = half
                .iter()
                .filter_map(|x| x.get(i))
                .fold(0.0, |m: f64, v| m.max(v.abs()));
            if best.as_ref().is_none_or(|(b, _)| a > *b) {
                let name = Some(format!("wheelset {k}"));
                best = Some((
                    a,
                    WheelsetColumns {
                        y: i,
                        psi,
                        ydot,
                        name,
                    },
                ));
            }
        }
        best.map_or(
            WheelsetColumns {
                y: 0,
                psi: 1,
                ydot: 2,
                name: None,
            },
            |(_, w)| w,
        )
    }

    /// Largest |y| of the leading wheelset over the last `fraction` of the run (m): the
    /// settled amplitude.
    pub fn final_amplitude(&self, fraction: f64) -> f64 {
        let start = ((1.0 - fraction.clamp(0.0, 1.0)) * self.t.len() as f64) as usize;
        self.x[start.min(self.x.len())..]
            .iter()
            .map(|x| x[0].abs())
            .fold(0.0, f64::max)
    }
}

/// Integrates at constant `speed` from `x0` (one value per state of `model`) for `duration`
/// s, sampled every `dt` s. A start state of another length is an error.
pub fn simulate(
    model: &Vehicle,
    speed: f64,
    x0: &[f64],
    duration: f64,
    dt: f64,
    ode: &OdeOptions,
) -> Result<TimeHistory, OdeError> {
    if x0.len() != model.states() {
        return Err(OdeError::BadArgument {
            name: "start state length",
            value: x0.len() as f64,
            rule: "must equal the model's number of states",
        });
    }
    crate::with_states!(model.states(), N => simulate_states::<N>(model, speed, x0, duration, dt, ode),
    _ => Err(OdeError::BadArgument {
        name: "number of states",
        value: model.states() as f64,
        rule: "no analysis is compiled for this size (4, 12, 14, 28, 34 are)",
    }))
}

/// The start state of a simulation: the leading wheelset displaced by `y0` (m), all else 0.
pub fn lateral_start(model: &Vehicle, y0: f64) -> Vec<f64> {
    let mut x = vec![0.0; model.states()];
    x[0] = y0;
    x
}

fn simulate_states<const N: usize>(
    model: &Vehicle,
    speed: f64,
    x0: &[f64],
    duration: f64,
    dt: f64,
    ode: &OdeOptions,
) -> Result<TimeHistory, OdeError> {
    let n = (duration / dt).floor() as usize;
    let samples: Vec<f64> = (0..=n).map(|i| i as f64 * dt).collect();
    let mut t = Vec::with_capacity(samples.len());
    let mut x = Vec::with_capacity(samples.len());
    let mut observe = |ti: f64, xi: &SVector<f64, N>| {
        t.push(ti);
        x.push(xi.iter().copied().collect());
    };
    integrate_observed(
        model,
        speed,
        &SVector::<f64, N>::from_fn(|i, _| x0[i]),
        duration,
        ode,
        &samples,
        &mut observe,
    )?;
    Ok(TimeHistory {
        speed_m_s: speed,
        t,
        x,
        state_names: crate::bifurcation::state_names(model),
    })
}

/// The model with the speed as one more state, decreasing at `rate` (m/s²): the field the
/// ramp integrates, for every layout. Its state is $(x, V)$ with $x$ the model's
/// [`Vehicle::states`] values in the model's order and $V$ last, so it has $M$ = states + 1
/// entries (5 for the wheelset, 13/15 for a bogie, 29/35 for a car; the analyses pick $M$ with
/// [`crate::with_states_plus_one`]):
/// $$\dot x = f(x; V),\qquad \dot V = −r.$$
/// Called with another $M$, every value is NaN (the integrator then reports a non-finite
/// state): never a panic.
pub struct RampField<'a> {
    /// the model (any layout)
    pub model: &'a Vehicle,
    /// deceleration r (m/s²), positive; 0 holds the speed (the settle phase)
    pub rate: f64,
}

impl RampField<'_> {
    /// Whether `M` fits the model (states + 1).
    fn fits(&self, m: usize) -> bool {
        m == self.model.states() + 1
    }
}

impl<const M: usize> VectorField<M> for RampField<'_> {
    fn rhs(&self, x: &SVector<f64, M>, _p: f64) -> SVector<f64, M> {
        let mut out = SVector::<f64, M>::from_element(f64::NAN);
        if !self.fits(M) {
            return out;
        }
        let n = M - 1;
        let v = x[n].max(1e-3);
        self.model
            .rhs_into(&x.as_slice()[..n], v, &mut out.as_mut_slice()[..n]);
        out[n] = -self.rate;
        out
    }
    fn jacobian(&self, x: &SVector<f64, M>, _p: f64) -> SMatrix<f64, M, M> {
        // The ramp needs no monodromy; this Jacobian (exact in x, central differences in V)
        // exists for completeness of the contract.
        let mut out = SMatrix::<f64, M, M>::from_element(f64::NAN);
        if !self.fits(M) {
            return out;
        }
        let n = M - 1;
        let xs = &x.as_slice()[..n];
        let v = x[n].max(1e-3);
        let mut j = vec![0.0; n * n];
        self.model.jacobian_into(xs, v, &mut j);
        out.fill(0.0);
        for c in 0..n {
            for r in 0..n {
                out[(r, c)] = j[c * n + r];
            }
        }
        let h = 1e-6 * v;
        let (mut fp, mut fm) = (vec![0.0; n], vec![0.0; n]);
        self.model.rhs_into(xs, (x[n] + h).max(1e-3), &mut fp);
        self.model.rhs_into(xs, (x[n] - h).max(1e-3), &mut fm);
        for r in 0..n {
            out[(r, n)] = (fp[r] - fm[r]) / (2.0 * h);
        }
        out
    }
    fn switch_count(&self) -> usize {
        // the vehicle's count does not depend on its const size
        VectorField::<4>::switch_count(self.model)
    }
    fn switch_value(&self, k: usize, x: &SVector<f64, M>) -> f64 {
        if !self.fits(M) {
            return f64::NAN;
        }
        self.model.switch(k, &x.as_slice()[..M - 1])
    }
}

mod en14363;
mod ramp;

pub use en14363::*;
pub use ramp::*;

#[cfg(test)]
mod largest_wheelset_tests {
    use super::TimeHistory;

    /// Two wheelsets, the second hunting at 4 mm and the first at 0.3 mm over the second half
    /// (the first larger at the start): the second is picked, with its own ψ and ẏ.
    #[test]
    fn the_wheelset_that_hunts_most_late_in_the_run_is_picked() {
        let names = [
            "y_wheelset_1_m",
            "psi_wheelset_1_rad",
            "y_wheelset_2_m",
            "psi_wheelset_2_rad",
            "ydot_wheelset_1_m_s",
            "psidot_wheelset_1_rad_s",
            "ydot_wheelset_2_m_s",
            "psidot_wheelset_2_rad_s",
        ];
        let t: Vec<f64> = (0..100).map(|k| f64::from(k) * 0.01).collect();
        let x: Vec<Vec<f64>> = t
            .iter()
            .map(|&t| {
                let first = if t < 0.5 { 9e-3 } else { 3e-4 };
                vec![first, 0.0, 4e-3 * (t * 30.0).sin(), 0.0, 0.0, 0.0, 0.1, 0.0]
            })
            .collect();
        let h = TimeHistory {
            speed_m_s: 100.0,
            t,
            x,
            state_names: names.iter().map(|s| s.to_string()).collect(),
        };
        let w = h.largest_wheelset();
        assert_eq!((w.y, w.psi, w.ydot), (2, 3, 6));
        assert_eq!(w.name.as_deref(), Some("wheelset 2"));
        let single = TimeHistory {
            state_names: vec!["y_m".into(), "psi_rad".into(), "ydot_m_s".into()],
            ..h
        };
        let w = single.largest_wheelset();
        assert_eq!((w.y, w.psi, w.ydot, w.name), (0, 1, 2, None));
    }
}
