//! Reference problems with known answers, shared by tests, benches and doctests.
//!
//! * [`seed_cone`]: the seed wheelset (docs/model.md §10) on the closed-form cone, with the seed's
//!   creep coefficients, built without a study file.
//! * [`small_angle_matrices`]: docs/model.md §8's M, C, K for the cone.
//! * [`hurwitz_critical_speed`]: for the cone **without spin, gravity or damping** the
//!   quartic's Hurwitz condition gives the critical speed in closed form (derived below).
//!
//! With $u = 1/V$, $c_1 = αu$, $c_2 = βu$ ($α = 2f_{22}$, $β = 2f_{11}l_0^2$),
//! $k_{11} = 2K_{py}$, $k_{22} = 2K_{px}d^2$, $k_{12} = −2f_{22}$, $k_{21} = 2f_{11}l_0λ/r_0$,
//! $\det(Ms^2 + Cs + K)/(mI_z) = s^4 + pu\,s^3 + (r + σu^2)s^2 + qu\,s + w$ with
//! $p = (mβ + I_zα)/(mI_z)$, $q = (αk_{22} + βk_{11})/(mI_z)$, $r = (mk_{22} + I_zk_{11})/(mI_z)$,
//! $σ = αβ/(mI_z)$, $w = (k_{11}k_{22} − k_{12}k_{21})/(mI_z)$. Then
//! $Δ_3 = u^2(pqr + pqσu^2 − q^2 − p^2w) = 0$ gives
//! $$V_c = \sqrt{\frac{pqσ}{q^2 + p^2 w − pqr}},\qquad ω_c^2 = q/p.$$

pub mod chaos;
pub mod switching;

use nalgebra::Matrix2;

use crate::contact::creep::CreepLaw;
use crate::contact::geometry::{Geometry, Nominal};
use crate::contact::kalker::CreepCoefficients;
use crate::contact::table::{ContactTable, CreepSource, Elastic, TableError, TableSpec};
use crate::model::{Suspension, Wheelset, WheelsetParams};

/// The seed's wheelset data (docs/model.md §10, SI).
pub const SEED_WHEELSET: WheelsetParams = WheelsetParams {
    mass: 1250.0,
    yaw_inertia: 700.0,
    axle_load: 110_000.0,
    half_contact_distance: 0.7429,
    rolling_radius: 0.46,
};

/// The seed's suspension (docs/model.md §10, SI, per side).
pub const SEED_SUSPENSION: Suspension = Suspension {
    lateral_stiffness: 3.86e6,
    longitudinal_stiffness: 8.5e5,
    lateral_damping: 8e3,
    longitudinal_damping: 1e5,
    half_spring_spacing: 0.9,
};

/// The seed's creep coefficients (N, N, N m, N m²).
pub const SEED_CREEP: CreepCoefficients<f64> = CreepCoefficients {
    f11: 8.06e6,
    f22: 8.09e6,
    f23: 2.2e4,
    f33: 12.7,
};

/// A wheelset on the closed-form cone of slope `lambda` with constant creep coefficients.
pub fn cone_wheelset(
    params: WheelsetParams,
    suspension: Suspension,
    creep: CreepCoefficients<f64>,
    lambda: f64,
    law: CreepLaw,
    spin: bool,
) -> Result<Wheelset, TableError> {
    let spec = TableSpec {
        nominal: Nominal {
            rolling_radius: params.rolling_radius,
            half_contact_distance: params.half_contact_distance,
        },
        axle_load: params.axle_load,
        elastic: Elastic {
            young_modulus: 210e9,
            poisson_ratio: 0.3,
            shear_modulus: 80e9,
        },
        rail_head_radius: None,
        creep: CreepSource::Given(creep),
        half_width: 0.01,
        nodes: 201,
    };
    let table = ContactTable::build(&Geometry::Cone { conicity: lambda }, &spec)?;
    Ok(Wheelset {
        params,
        suspension,
        creep_law: law,
        spin,
        flange: None,
        table,
    })
}

/// The seed wheelset on the 1:20 cone (docs/model.md §10 parameters, Kalker creep, spin on).
pub fn seed_cone(law: CreepLaw) -> Result<Wheelset, TableError> {
    cone_wheelset(SEED_WHEELSET, SEED_SUSPENSION, SEED_CREEP, 0.05, law, true)
}

/// docs/model.md §8's small-angle matrices (M, C, K) at speed `v` for the cone of slope `lambda`.
pub fn small_angle_matrices(
    w: &Wheelset,
    creep: &CreepCoefficients<f64>,
    lambda: f64,
    v: f64,
) -> (Matrix2<f64>, Matrix2<f64>, Matrix2<f64>) {
    let p = &w.params;
    let s = &w.suspension;
    let (f11, f22) = (creep.f11, creep.f22);
    let (f23, f33) = if w.spin {
        (creep.f23, creep.f33)
    } else {
        (0.0, 0.0)
    };
    let (l0, r0, d2) = (
        p.half_contact_distance,
        p.rolling_radius,
        s.half_spring_spacing * s.half_spring_spacing,
    );
    let m = Matrix2::new(p.mass, 0.0, 0.0, p.yaw_inertia);
    let c = Matrix2::new(
        2.0 * f22 / v + 2.0 * s.lateral_damping,
        2.0 * f23 / v,
        -2.0 * f23 / v,
        2.0 * f11 * l0 * l0 / v + 2.0 * f33 / v + 2.0 * s.longitudinal_damping * d2,
    );
    let k = Matrix2::new(
        2.0 * s.lateral_stiffness + p.axle_load * lambda / l0 - 2.0 * f23 * lambda / (r0 * l0),
        -2.0 * f22,
        2.0 * f11 * l0 * lambda / r0 - 2.0 * f33 * lambda / (r0 * l0),
        2.0 * s.longitudinal_stiffness * d2 + 2.0 * f23,
    );
    (m, c, k)
}

/// Closed-form critical speed (m/s) and frequency (rad/s) of the cone without spin, gravity
/// or damping; `None` when the formula has no real positive solution.
pub fn hurwitz_critical_speed(
    p: &WheelsetParams,
    s: &Suspension,
    f11: f64,
    f22: f64,
    lambda: f64,
) -> Option<(f64, f64)> {
    let (m, iz) = (p.mass, p.yaw_inertia);
    let (l0, r0) = (p.half_contact_distance, p.rolling_radius);
    let alpha = 2.0 * f22;
    let beta = 2.0 * f11 * l0 * l0;
    let k11 = 2.0 * s.lateral_stiffness;
    let k22 = 2.0 * s.longitudinal_stiffness * s.half_spring_spacing * s.half_spring_spacing;
    let k12 = -2.0 * f22;
    let k21 = 2.0 * f11 * l0 * lambda / r0;
    let mi = m * iz;
    let pp = (m * beta + iz * alpha) / mi;
    let q = (alpha * k22 + beta * k11) / mi;
    let r = (m * k22 + iz * k11) / mi;
    let sigma = alpha * beta / mi;
    let w = (k11 * k22 - k12 * k21) / mi;
    let den = q * q + pp * pp * w - pp * q * r;
    let v2 = pp * q * sigma / den;
    (den > 0.0 && v2 > 0.0).then(|| (v2.sqrt(), (q / pp).sqrt()))
}

/// The Hopf normal form (Stuart–Landau oscillator) in Cartesian coordinates, parameter μ:
/// $\dot r = r(μ + a r^2 + b r^4)$, $\dot θ = ω$. With `a = −1, b = 0` (supercritical) the
/// cycles are $r = \sqrt{μ}$; with `a = 1, b = −1` (subcritical) they are $μ = r^4 − r^2$, with
/// a fold at $μ = −1/4$, $r^2 = 1/2$. The period is $2π/ω$ and the radial multiplier is
/// $\exp(T\, r\, ∂_r[μ + a r^2 + b r^4])$. The field is odd, so its cycles are symmetric.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HopfNormalForm {
    /// angular frequency ω (rad/s)
    pub omega: f64,
    /// cubic coefficient a
    pub a: f64,
    /// quintic coefficient b
    pub b: f64,
}

impl HopfNormalForm {
    /// The radial growth rate $g(r^2) = μ + a r^2 + b r^4$.
    fn g(&self, mu: f64, r2: f64) -> f64 {
        mu + self.a * r2 + self.b * r2 * r2
    }
    /// Radial Floquet multiplier of the cycle of radius² `r2`: $\exp(T\,2r^2 g'(r^2))$.
    pub fn radial_multiplier(&self, r2: f64) -> f64 {
        let t = 2.0 * std::f64::consts::PI / self.omega;
        (t * 2.0 * r2 * (self.a + 2.0 * self.b * r2)).exp()
    }
}

impl crate::system::ode::VectorField<2> for HopfNormalForm {
    fn rhs(&self, x: &nalgebra::SVector<f64, 2>, mu: f64) -> nalgebra::SVector<f64, 2> {
        let r2 = x[0] * x[0] + x[1] * x[1];
        let g = self.g(mu, r2);
        nalgebra::SVector::<f64, 2>::new(g * x[0] - self.omega * x[1], self.omega * x[0] + g * x[1])
    }
    fn jacobian(&self, x: &nalgebra::SVector<f64, 2>, mu: f64) -> nalgebra::SMatrix<f64, 2, 2> {
        let r2 = x[0] * x[0] + x[1] * x[1];
        let g = self.g(mu, r2);
        let dg = self.a + 2.0 * self.b * r2; // dg/d(r²)
        nalgebra::SMatrix::<f64, 2, 2>::new(
            g + 2.0 * dg * x[0] * x[0],
            -self.omega + 2.0 * dg * x[0] * x[1],
            self.omega + 2.0 * dg * x[0] * x[1],
            g + 2.0 * dg * x[1] * x[1],
        )
    }
}

/// A bogie frame in the range of the DTU Cooperrider vehicle
/// (DTU DYTSI, `docs/data/dytsi_cooperrider_vehicle.md`: frame 2918.9 kg, 6780 kg m²,
/// half wheelbase 1.074 m), for tests and benches.
pub const REFERENCE_FRAME: crate::model::FrameParams = crate::model::FrameParams {
    mass: 2918.9,
    yaw_inertia: 6780.0,
    roll_inertia: None,
    half_wheelbase: 1.074,
};

/// A secondary suspension per side from the same sheet (k4, D2 lateral; k6, D6 longitudinal
/// at ±1.5 m; the vertical k5, D1 at ±0.68 m; heights from the frame centre 0.6584 m).
pub const REFERENCE_SECONDARY: crate::model::Secondary = crate::model::Secondary {
    lateral_stiffness: 1.823e5,
    longitudinal_stiffness: 9.0335e5,
    lateral_damping: 2.92e4,
    longitudinal_damping: 1.66669e5,
    half_spring_spacing: 1.5,
    yaw_damping: 0.0,
    yaw_damper_half_spacing: 1.5,
    vertical_stiffness: 3.333e5,
    vertical_damping: 2.0e4,
    vertical_half_spacing: 0.68,
    height: 0.6584,
    series: crate::model::DamperSeries::RIGID,
    curves: crate::model::DamperCurves::LINEAR,
    bump_stop: None,
};

/// The car body of the same sheet (44388 kg; the yaw inertia 5.6e6 kg m² of the sheet's
/// older model, not the 5.0e5 placeholder; roll 2.8e5 kg m²), secondary 0.9 m below its centre.
pub const REFERENCE_CAR_BODY: crate::model::CarBodyParams = crate::model::CarBodyParams {
    mass: 44388.0,
    yaw_inertia: 5.6e6,
    roll_inertia: None,
    half_bogie_distance: 7.5,
    secondary_height: -0.9,
};

/// The seed wheelset (on the 1:20 cone, seed creep coefficients) in a vehicle of `spec`.
pub fn seed_vehicle(
    spec: &crate::model::VehicleSpec,
    law: CreepLaw,
    spin: bool,
) -> Result<crate::model::Vehicle, String> {
    let ws = cone_wheelset(SEED_WHEELSET, SEED_SUSPENSION, SEED_CREEP, 0.05, law, spin)
        .map_err(|e| e.to_string())?;
    crate::model::layouts::build(spec, ws, &crate::model::PrimaryVertical::default())
        .map_err(|e| e.to_string())
}
