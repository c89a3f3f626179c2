//! Time simulation of the wheelset at constant speed, and the ramp method.
//!
//! * [`simulate`]: the seed's experiment (its Figs. 10–11): start from y(0), integrate at a
//!   fixed speed, sample uniformly.
//! * [`ramp`]: the industrial ramp method (True 2013; GENSYS documents a 5 km/h per s
//!   deceleration): start on a large cycle above the critical speed and decrease the speed
//!   slowly in one long simulation until the hunting dies; the speed where the amplitude
//!   falls below a threshold brackets the nonlinear critical speed from above.
//! * The EN 14363 instability criterion on the ramp's time history: the sliding r.m.s. of the
//!   sum of guiding forces ΣY, band-pass filtered to f0 ± 2 Hz around the hunting frequency
//!   f0, over 100 m of track, against the limit (10 + 2Q0/3)/2 kN, Q0 the static wheel load in
//!   kN. (EN 14363, instability assessment quantity ΣY; the filter band and method as listed
//!   in the GENSYS summary of the EN 14363/UIC 518 assessment quantities. The standard's text
//!   itself was not available to this project; its clause numbers are not quoted.)

use nalgebra::{SMatrix, SVector};

use crate::model::Wheelset;
use crate::system::ode::{integrate_observed, OdeError, OdeOptions, VectorField};

/// A sampled time history at one speed.
#[derive(Clone, Debug, PartialEq)]
pub struct TimeHistory {
    /// speed (m/s)
    pub speed_m_s: f64,
    /// sample times (s)
    pub t: Vec<f64>,
    /// states (y m, ψ rad, ẏ m/s, ψ̇ rad/s)
    pub x: Vec<[f64; 4]>,
}

impl TimeHistory {
    /// Largest |y| over the last `fraction` of the run (m): the settled amplitude.
    pub fn final_amplitude(&self, fraction: f64) -> f64 {
        let start = ((1.0 - fraction.clamp(0.0, 1.0)) * self.t.len() as f64) as usize;
        self.x[start.min(self.x.len())..]
            .iter()
            .map(|x| x[0].abs())
            .fold(0.0, f64::max)
    }
}

/// Integrates at constant `speed` from `x0` for `duration` s, sampled every `dt` s.
pub fn simulate(
    model: &Wheelset,
    speed: f64,
    x0: [f64; 4],
    duration: f64,
    dt: f64,
    ode: &OdeOptions,
) -> Result<TimeHistory, OdeError> {
    let n = (duration / dt).floor() as usize;
    let samples: Vec<f64> = (0..=n).map(|i| i as f64 * dt).collect();
    let mut t = Vec::with_capacity(samples.len());
    let mut x = Vec::with_capacity(samples.len());
    let mut observe = |ti: f64, xi: &SVector<f64, 4>| {
        t.push(ti);
        x.push([xi[0], xi[1], xi[2], xi[3]]);
    };
    integrate_observed(
        model,
        speed,
        &SVector::from(x0),
        duration,
        ode,
        &samples,
        &mut observe,
    )?;
    Ok(TimeHistory {
        speed_m_s: speed,
        t,
        x,
    })
}

/// The wheelset with the speed as a fifth state decreasing at `rate` (m/s²).
pub struct RampField<'a> {
    /// the wheelset
    pub model: &'a Wheelset,
    /// deceleration (m/s²), positive
    pub rate: f64,
}

impl VectorField<5> for RampField<'_> {
    fn rhs(&self, x: &SVector<f64, 5>, _p: f64) -> SVector<f64, 5> {
        let v = x[4].max(1e-3);
        let f = self.model.rhs_vec(&x.fixed_rows::<4>(0).into_owned(), v);
        SVector::<f64, 5>::new(f[0], f[1], f[2], f[3], -self.rate)
    }
    fn jacobian(&self, x: &SVector<f64, 5>, p: f64) -> SMatrix<f64, 5, 5> {
        // The ramp needs no monodromy; this Jacobian (exact in x, differences in V) exists
        // for completeness of the contract.
        let v = x[4].max(1e-3);
        let xs = x.fixed_rows::<4>(0).into_owned();
        let (j, _) = self.model.jacobian(&xs, v);
        let h = 1e-6 * v;
        let mut xp = *x;
        xp[4] += h;
        let mut xm = *x;
        xm[4] -= h;
        let dv = (self.rhs(&xp, p) - self.rhs(&xm, p)) / (2.0 * h);
        let mut out = SMatrix::<f64, 5, 5>::zeros();
        out.fixed_view_mut::<4, 4>(0, 0).copy_from(&j);
        out.fixed_view_mut::<4, 1>(0, 4)
            .copy_from(&dv.fixed_rows::<4>(0));
        out
    }
    fn switch_count(&self) -> usize {
        self.model.switch_count()
    }
    fn switch_value(&self, k: usize, x: &SVector<f64, 5>) -> f64 {
        self.model
            .switch_value(k, &x.fixed_rows::<4>(0).into_owned())
    }
}
