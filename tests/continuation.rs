//! Shooting, Floquet multipliers and continuation on the Hopf normal form, whose cycles,
//! periods, multipliers and fold are known in closed form (critspeed::reference), independent
//! of any wheelset.

use approx::assert_relative_eq;
use critspeed::continuation::{
    BranchStop, Continuation, ContinuationParams, OrbitPoint, Shooting, SpecialKind,
};
use critspeed::reference::HopfNormalForm;
use critspeed::system::ode::{OdeOptions, Tolerances};
use nalgebra::{DVector, SVector};
use std::f64::consts::PI;

fn ode(rtol: f64) -> OdeOptions {
    OdeOptions {
        tol: Tolerances::new(rtol, rtol * 1e-2).expect("valid tolerances"),
        ..OdeOptions::default()
    }
}

fn radius(o: &OrbitPoint<2>, _: &SVector<f64, 2>) -> f64 {
    o.x0.norm()
}

fn continuation<'a>(
    field: &'a HopfNormalForm,
    range: (f64, f64),
    max_amp: f64,
    symmetric: bool,
) -> Continuation<'a, 2, HopfNormalForm> {
    let mut params = ContinuationParams::new(range, max_amp, vec![1.0, 1.0, 1.0, 1.0]);
    params.ds_initial = 0.02;
    params.ds_max = 0.05;
    Continuation {
        shooting: Shooting {
            field,
            symmetric,
            ode: ode(1e-12),
            dp_rel: 1e-6,
            parallel: false,
        },
        params,
        amplitude: &radius,
        progress: None,
    }
}

fn from_hopf(field: &HopfNormalForm) -> (OrbitPoint<2>, DVector<f64>) {
    let start = OrbitPoint {
        x0: SVector::<f64, 2>::zeros(),
        period: 2.0 * PI / field.omega,
        param: 0.0,
    };
    (start, DVector::from_vec(vec![1.0, 0.0, 0.0, 0.0]))
}

#[test]
fn supercritical_branch_is_the_square_root() {
    let field = HopfNormalForm {
        omega: 2.0,
        a: -1.0,
        b: 0.0,
    };
    for symmetric in [true, false] {
        let c = continuation(&field, (-1.0, 1.0), 0.9, symmetric);
        let (start, dir) = from_hopf(&field);
        let branch = c.run(start, dir);
        assert!(branch.points.len() > 10, "{:?}", branch.stop);
        assert!(matches!(
            branch.stop,
            BranchStop::AmplitudeBound { .. } | BranchStop::ParamBound { .. }
        ));
        for p in &branch.points {
            let r2 = p.amplitude * p.amplitude;
            assert_relative_eq!(r2, p.orbit.param, max_relative = 1e-8, epsilon = 1e-12);
            assert_relative_eq!(p.orbit.period, PI, max_relative = 1e-9);
            // trivial multiplier 1 and the radial one exp(−2μT)
            assert!(
                p.floquet.trivial_error < 1e-8,
                "{}",
                p.floquet.trivial_error
            );
            assert_relative_eq!(
                p.floquet.max_nontrivial,
                field.radial_multiplier(r2),
                max_relative = 1e-6
            );
            assert!(p.floquet.stable());
        }
        assert!(branch.special.is_empty(), "{:?}", branch.special);
    }
}

#[test]
fn subcritical_fold_is_located() {
    let field = HopfNormalForm {
        omega: 2.0,
        a: 1.0,
        b: -1.0,
    };
    let c = continuation(&field, (-1.0, 1.0), 1.1, true);
    let (start, dir) = from_hopf(&field);
    let branch = c.run(start, dir);
    let folds: Vec<_> = branch
        .special
        .iter()
        .filter(|s| s.kind == SpecialKind::Fold)
        .collect();
    assert_eq!(folds.len(), 1, "{:?}", branch.special);
    let f = folds[0];
    assert!(f.located);
    assert_relative_eq!(f.orbit.param, -0.25, max_relative = 1e-7);
    assert_relative_eq!(f.amplitude * f.amplitude, 0.5, max_relative = 1e-3);
    // every cycle lies on μ = r⁴ − r², unstable below the fold amplitude, stable above
    for p in &branch.points {
        let r2 = p.amplitude * p.amplitude;
        assert_relative_eq!(p.orbit.param, r2 * r2 - r2, epsilon = 1e-8);
        if (r2 - 0.5).abs() > 0.02 {
            assert_eq!(p.floquet.stable(), r2 > 0.5, "r² = {r2}");
            assert_relative_eq!(
                p.floquet.max_nontrivial,
                field.radial_multiplier(r2),
                max_relative = 1e-5
            );
        }
    }
}

#[test]
fn results_converge_as_tolerances_tighten() {
    let field = HopfNormalForm {
        omega: 2.0,
        a: 1.0,
        b: -1.0,
    };
    let mut errors = Vec::new();
    for rtol in [1e-6, 1e-8, 1e-10] {
        let mut c = continuation(&field, (-1.0, 1.0), 1.1, true);
        c.shooting.ode = ode(rtol);
        c.shooting.dp_rel = rtol.sqrt();
        let (start, dir) = from_hopf(&field);
        let branch = c.run(start, dir);
        let fold = branch
            .special
            .iter()
            .find(|s| s.kind == SpecialKind::Fold)
            .expect("a fold");
        errors.push((fold.orbit.param + 0.25).abs());
    }
    assert!(errors[2] <= errors[0], "{errors:?}");
    assert!(errors[2] < 1e-8, "{errors:?}");
}
