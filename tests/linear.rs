//! Linear stability: exact Jacobian, small-angle matrices, closed-form critical speed,
//! eigen-residuals and the Kalker/Shen relation (docs/model.md §5, §8, §9).

use approx::assert_relative_eq;
use critspeed::contact::creep::CreepLaw;
use critspeed::model::{Suspension, Wheelset};
use critspeed::reference::{
    cone_wheelset, hurwitz_critical_speed, seed_cone, SEED_CREEP, SEED_SUSPENSION, SEED_WHEELSET,
};
use critspeed::stability::{
    characteristic_polynomial, critical_speeds, spectrum_at, Direction, LinearOptions, LinearSystem,
};
use nalgebra::{Matrix4, Vector4};
use proptest::prelude::*;

const SHEN: CreepLaw = CreepLaw::Shen { friction: 0.3 };

fn central_difference_jacobian(w: &Wheelset, x: &Vector4<f64>, v: f64) -> Matrix4<f64> {
    let scale = [1e-3, 1e-3, 1e-2, 1e-2];
    let mut j = Matrix4::zeros();
    for k in 0..4 {
        let h = 1e-6 * scale[k];
        let mut xp = *x;
        let mut xm = *x;
        xp[k] += h;
        xm[k] -= h;
        let col = (w.rhs_vec(&xp, v) - w.rhs_vec(&xm, v)) / (2.0 * h);
        j.set_column(k, &col);
    }
    j
}

fn check_against_differences(w: &Wheelset, x: Vector4<f64>, v: f64) {
    let (exact, _) = w.jacobian(&x, v);
    let fd = central_difference_jacobian(w, &x, v);
    for c in 0..4 {
        let col_scale = exact.column(c).amax().max(1e-9);
        for r in 0..4 {
            let err = (exact[(r, c)] - fd[(r, c)]).abs();
            assert!(
                err <= 1e-6 * col_scale,
                "J[{r},{c}] exact {} vs differences {} at x={x:?}, V={v}",
                exact[(r, c)],
                fd[(r, c)]
            );
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]
    /// The dual-number Jacobian equals central differences of the same f, for both laws,
    /// at states away from the centre (where the Shen factor is saturating).
    #[test]
    fn exact_jacobian_matches_central_differences(
        y in -8e-3..8e-3f64, psi in -4e-3..4e-3f64,
        yd in -0.05..0.05f64, pd in -0.05..0.05f64, v in 5.0..150.0f64,
        shen in any::<bool>(),
    ) {
        let w = seed_cone(if shen { SHEN } else { CreepLaw::Kalker }).expect("seed cone");
        check_against_differences(&w, Vector4::new(y, psi, yd, pd), v);
    }

    /// Track symmetry (docs/model.md §9): f(−x) = −f(x).
    #[test]
    fn right_hand_side_is_odd(
        y in -8e-3..8e-3f64, psi in -4e-3..4e-3f64,
        yd in -0.05..0.05f64, pd in -0.05..0.05f64, v in 5.0..150.0f64,
    ) {
        let w = seed_cone(SHEN).expect("seed cone");
        let x = Vector4::new(y, psi, yd, pd);
        let a = w.rhs_vec(&x, v);
        let b = w.rhs_vec(&-x, v);
        for k in 0..4 {
            prop_assert!((a[k] + b[k]).abs() <= 1e-9 * a[k].abs().max(1e-6));
        }
    }
}

#[test]
fn jacobian_at_centre_matches_differences_for_both_laws() {
    for law in [CreepLaw::Kalker, SHEN] {
        let w = seed_cone(law).expect("seed cone");
        for v in [10.0, 40.0, 120.0] {
            check_against_differences(&w, Vector4::zeros(), v);
        }
    }
}

#[test]
fn jacobian_is_affine_in_inverse_speed() {
    for law in [CreepLaw::Kalker, SHEN] {
        let w = seed_cone(law).expect("seed cone");
        let sys = LinearSystem::at_centre(&w);
        for v in [3.7, 27.0, 99.9, 250.0] {
            let (direct, _) = w.jacobian(&Vector4::zeros(), v);
            let split = sys.jacobian(v);
            assert!(
                (direct - split).amax() <= 1e-12 * direct.amax(),
                "{law:?} V={v}"
            );
        }
    }
}

// docs/model.md §8's small-angle matrices against the exact Jacobian (error ∝ λ³) and the Klingel
// wavelength under rigid creep are asserted in tests/validation_sections/closed.rs, which
// also writes them into docs/VALIDATION.md.

fn undamped_gravity_free() -> (critspeed::model::WheelsetParams, Suspension) {
    let mut p = SEED_WHEELSET;
    p.axle_load = 0.0;
    let mut s = SEED_SUSPENSION;
    s.lateral_damping = 0.0;
    s.longitudinal_damping = 0.0;
    (p, s)
}

/// The independent check: cone, no spin, gravity or damping; the quartic's Hurwitz
/// condition in closed form (critspeed::reference) against the solver, to 1e-9.
#[test]
fn closed_form_hurwitz_critical_speed() {
    let (p, base) = undamped_gravity_free();
    for (kpx, lambda) in [(8.5e5, 0.05), (4e5, 0.05), (8.5e5, 0.15), (2e6, 0.1)] {
        let mut s = base;
        s.longitudinal_stiffness = kpx;
        let (vc, omega) = hurwitz_critical_speed(&p, &s, SEED_CREEP.f11, SEED_CREEP.f22, lambda)
            .expect("closed form has a solution");
        let w = cone_wheelset(p, s, SEED_CREEP, lambda, CreepLaw::Kalker, false).expect("cone");
        let sys = LinearSystem::at_centre(&w);
        let opts = LinearOptions {
            speed_range: (1.0, 2.0 * vc),
            ..LinearOptions::default()
        };
        let found = critical_speeds(&sys, CreepLaw::Kalker, &opts).expect("search runs");
        let c = found.critical().expect("a crossing exists");
        assert_relative_eq!(c.speed_m_s, vc, max_relative = 1e-9);
        assert_relative_eq!(
            c.frequency_hz,
            omega / (2.0 * std::f64::consts::PI),
            max_relative = 1e-9
        );
    }
}

/// At every located crossing the eigenvalues (faer, independent of the polynomial) have a
/// pair on the imaginary axis at the reported frequency, and the direction is right.
#[test]
fn crossings_agree_with_eigenvalues() {
    let mut s = SEED_SUSPENSION;
    s.lateral_damping = 0.0;
    s.longitudinal_damping = 0.0;
    for law in [CreepLaw::Kalker, SHEN] {
        let w = cone_wheelset(SEED_WHEELSET, s, SEED_CREEP, 0.05, law, true).expect("cone");
        let sys = LinearSystem::at_centre(&w);
        let opts = LinearOptions {
            speed_range: (1.0, 400.0),
            ..LinearOptions::default()
        };
        let found = critical_speeds(&sys, law, &opts).expect("search runs");
        assert!(!found.crossings.is_empty(), "{law:?}");
        for c in &found.crossings {
            let sp = spectrum_at(&sys.jacobian(c.speed_m_s), c.speed_m_s).expect("eig");
            let omega = 2.0 * std::f64::consts::PI * c.frequency_hz;
            let pair = sp
                .pairs
                .iter()
                .min_by(|a, b| (a.im - omega).abs().total_cmp(&(b.im - omega).abs()))
                .expect("four eigenvalues");
            assert!(
                pair.re.abs() <= 1e-9 * omega,
                "Re = {} at V = {}",
                pair.re,
                c.speed_m_s
            );
            assert_relative_eq!(pair.im, omega, max_relative = 1e-9);
            let re_at = |v: f64| {
                let sp = spectrum_at(&sys.jacobian(v), v).expect("eig");
                sp.pairs
                    .iter()
                    .min_by(|a, b| {
                        // nearest to iω in the complex plane: the two modes can have
                        // almost equal frequencies, so the real part must count too
                        a.re.hypot(a.im - omega)
                            .total_cmp(&b.re.hypot(b.im - omega))
                    })
                    .map(|p| p.re)
                    .expect("four eigenvalues")
            };
            let (before, after) = (re_at(c.speed_m_s * 0.999), re_at(c.speed_m_s * 1.001));
            match c.direction {
                Direction::Onset => assert!(
                    before < 0.0 && after > 0.0,
                    "{law:?} {c:?} {before} {after}"
                ),
                Direction::Recovery => assert!(before > 0.0 && after < 0.0),
            }
        }
    }
}

/// faer's eigenpairs satisfy J v = λ v to rounding (tolerance scaled by ε, n and |J|).
#[test]
fn eigen_residuals() {
    let w = seed_cone(SHEN).expect("seed cone");
    let sys = LinearSystem::at_centre(&w);
    for v in [2.0, 30.0, 180.0] {
        let j = sys.jacobian(v);
        let sp = spectrum_at(&j, v).expect("eig");
        for p in &sp.pairs {
            let mut res: f64 = 0.0;
            let mut norm: f64 = 0.0;
            for r in 0..4 {
                let (mut re, mut im) = (0.0, 0.0);
                for c in 0..4 {
                    re += j[(r, c)] * p.vector[c].0;
                    im += j[(r, c)] * p.vector[c].1;
                }
                re -= p.re * p.vector[r].0 - p.im * p.vector[r].1;
                im -= p.re * p.vector[r].1 + p.im * p.vector[r].0;
                res = res.max(re.hypot(im));
                norm = norm.max(p.vector[r].0.hypot(p.vector[r].1));
            }
            let tol = 100.0 * 4.0 * f64::EPSILON * j.amax() * norm;
            assert!(res <= tol, "V={v}: residual {res} > {tol}");
        }
        // the characteristic polynomial's roots are these eigenvalues
        let a = characteristic_polynomial(&j);
        for p in &sp.pairs {
            let s = nalgebra::Complex::new(p.re, p.im);
            let val = s.powi(4) + s.powi(3) * a[0] + s * s * a[1] + s * a[2] + a[3];
            let scale = s.norm().powi(4) + a[3].abs();
            assert!(val.norm() <= 1e-8 * scale, "V={v}: {}", val.norm());
        }
    }
}

/// docs/model.md §5: with spin creep switched off, the Shen model's Hopf speed equals Kalker's.
#[test]
fn without_spin_shen_hopf_equals_kalker() {
    let mut s = SEED_SUSPENSION;
    s.lateral_damping = 0.0;
    s.longitudinal_damping = 0.0;
    let opts = LinearOptions {
        speed_range: (1.0, 400.0),
        ..LinearOptions::default()
    };
    let mut speeds = Vec::new();
    for law in [CreepLaw::Kalker, SHEN] {
        let w = cone_wheelset(SEED_WHEELSET, s, SEED_CREEP, 0.05, law, false).expect("cone");
        let found = critical_speeds(&LinearSystem::at_centre(&w), law, &opts).expect("search runs");
        speeds.push(found.critical().expect("crossing").speed_m_s);
    }
    assert_relative_eq!(speeds[0], speeds[1], max_relative = 1e-9);
    // with spin the two differ (docs/model.md §5 note): the Shen Jacobian is not Kalker's
    let k =
        cone_wheelset(SEED_WHEELSET, s, SEED_CREEP, 0.05, CreepLaw::Kalker, true).expect("cone");
    let h = cone_wheelset(SEED_WHEELSET, s, SEED_CREEP, 0.05, SHEN, true).expect("cone");
    let vk = critical_speeds(&LinearSystem::at_centre(&k), CreepLaw::Kalker, &opts)
        .expect("search")
        .critical()
        .expect("crossing")
        .speed_m_s;
    let vh = critical_speeds(&LinearSystem::at_centre(&h), SHEN, &opts)
        .expect("search")
        .critical()
        .expect("crossing")
        .speed_m_s;
    assert!((vh - vk).abs() > 1e-3 * vk, "Kalker {vk} vs Shen {vh}");
}

#[test]
fn bad_options_are_rejected() {
    let w = seed_cone(CreepLaw::Kalker).expect("seed cone");
    let sys = LinearSystem::at_centre(&w);
    for range in [(0.0, 10.0), (10.0, 10.0), (20.0, 10.0), (1.0, f64::NAN)] {
        let opts = LinearOptions {
            speed_range: range,
            ..LinearOptions::default()
        };
        assert!(
            critical_speeds(&sys, CreepLaw::Kalker, &opts).is_err(),
            "{range:?}"
        );
    }
}

/// The structured (second-order) characteristic polynomial equals the general one.
#[test]
fn structured_and_general_characteristic_polynomials_agree() {
    let w = seed_cone(SHEN).expect("seed cone");
    let sys = LinearSystem::at_centre(&w);
    for v in [1.5, 40.0, 333.0] {
        let fast = sys.coefficients(v);
        let general = characteristic_polynomial(&sys.jacobian(v));
        for k in 0..4 {
            assert_relative_eq!(fast[k], general[k], max_relative = 1e-12);
        }
    }
}
