//! The assembly against docs/model.md §1–8 written out, and its Jacobian against differences.

use proptest::prelude::*;

use super::*;
use crate::contact::creep::CreepLaw;
use crate::reference::{
    seed_cone, seed_vehicle, REFERENCE_CAR_BODY, REFERENCE_FRAME, REFERENCE_SECONDARY,
};

fn bogie(roll: bool) -> VehicleSpec {
    let mut frame = REFERENCE_FRAME;
    frame.roll_inertia = roll.then_some(6780.0);
    VehicleSpec::Bogie {
        frame,
        secondary: REFERENCE_SECONDARY,
    }
}

fn car(roll: bool) -> VehicleSpec {
    let mut frame = REFERENCE_FRAME;
    let mut body = REFERENCE_CAR_BODY;
    frame.roll_inertia = roll.then_some(6780.0);
    body.roll_inertia = roll.then_some(2.8e5);
    VehicleSpec::Car {
        frame,
        secondary: REFERENCE_SECONDARY,
        body,
    }
}

fn rel(a: f64, b: f64, scale: f64) -> f64 {
    (a - b).abs() / scale.max(f64::MIN_POSITIVE)
}

/// docs/model.md §11's check: the wheelset layout through the element assembly is §1–8 exactly.
#[test]
fn wheelset_layout_equals_the_direct_model() {
    for law in [CreepLaw::Kalker, CreepLaw::Shen { friction: 0.3 }] {
        let direct = seed_cone(law).expect("table");
        let v = seed_vehicle(&VehicleSpec::Wheelset, law, true).expect("vehicle");
        assert_eq!(v.states(), 4);
        // §7: K = diag(2K_py, 2K_px d²), C = diag(2C_py, 2C_px d²)
        let s = direct.suspension;
        let d2 = s.half_spring_spacing * s.half_spring_spacing;
        assert!(rel(v.stiffness(0, 0), 2.0 * s.lateral_stiffness, 1.0) == 0.0);
        assert!(
            rel(
                v.stiffness(1, 1),
                2.0 * s.longitudinal_stiffness * d2,
                v.stiffness(1, 1)
            ) < 1e-15
        );
        assert!(v.stiffness(0, 1) == 0.0 && v.damping(1, 0) == 0.0);
        let mut worst: f64 = 0.0;
        for k in 0..200 {
            let t = k as f64;
            let x = [
                4e-3 * (0.7 * t).sin(),
                3e-3 * (1.3 * t).cos(),
                0.2 * (0.4 * t).sin(),
                0.1 * (2.1 * t).cos(),
            ];
            let speed = 5.0 + t;
            let f0 = direct.rhs(&x, speed);
            let mut f1 = [0.0; 4];
            v.rhs_into(&x, speed, &mut f1);
            let scale = f0.iter().fold(0.0_f64, |m, a| m.max(a.abs()));
            let (j0, _) = direct.jacobian(&nalgebra::Vector4::from(x), speed);
            let mut j1 = [0.0; 16];
            v.jacobian_into(&x, speed, &mut j1);
            let jscale = j0.iter().fold(0.0_f64, |m, a| m.max(a.abs()));
            for i in 0..4 {
                worst = worst.max(rel(f0[i], f1[i], scale));
                for c in 0..4 {
                    worst = worst.max(rel(j0[(i, c)], j1[c * 4 + i], jscale));
                }
            }
        }
        assert!(
            worst < 1e-14,
            "{} law: largest relative difference {worst:e}",
            law.name()
        );
    }
}

fn state(n: usize, seed: &[f64]) -> Vec<f64> {
    (0..n)
        .map(|i| {
            let s = seed[i % seed.len()] * (1.0 + 0.37 * i as f64).sin();
            if i < n / 2 {
                5e-3 * s
            } else {
                0.05 * s
            }
        })
        .collect()
}

fn central_difference_error(v: &Vehicle, x: &[f64], speed: f64) -> f64 {
    let n = v.states();
    let mut jac = vec![0.0; n * n];
    v.jacobian_into(x, speed, &mut jac);
    let mut worst: f64 = 0.0;
    for c in 0..n {
        // steps as in tests/linear.rs: 1e-6 of 1 mm (1 mrad) or of 1 cm/s
        let h = 1e-6 * if c < n / 2 { 1e-3 } else { 1e-2 };
        let (mut xp, mut xm) = (x.to_vec(), x.to_vec());
        xp[c] += h;
        xm[c] -= h;
        let (mut fp, mut fm) = (vec![0.0; n], vec![0.0; n]);
        v.rhs_into(&xp, speed, &mut fp);
        v.rhs_into(&xm, speed, &mut fm);
        let col = &jac[c * n..(c + 1) * n];
        let col_scale = col.iter().fold(1e-9_f64, |m, a| m.max(a.abs()));
        for r in 0..n {
            let d = (fp[r] - fm[r]) / (2.0 * h);
            worst = worst.max((d - col[r]).abs() / col_scale);
        }
    }
    worst
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]
    /// The exact Jacobian of bogie and car (with and without roll, both creep laws) against
    /// central differences of f, relative to each column's largest entry (as tests/linear.rs
    /// does for the 4-state model).
    #[test]
    fn vehicle_jacobian_matches_central_differences(
        seed in prop::collection::vec(-1.0f64..1.0, 5),
        speed in 10.0f64..120.0,
        which in 0usize..8,
    ) {
        let spec = if which % 4 < 2 { bogie(which % 2 == 1) } else { car(which % 2 == 1) };
        let law = if which < 4 { CreepLaw::Kalker } else { CreepLaw::Shen { friction: 0.3 } };
        let v = seed_vehicle(&spec, law, true).expect("vehicle");
        let x = state(v.states(), &seed);
        let err = central_difference_error(&v, &x, speed);
        prop_assert!(err < 1e-6, "{} states: {err:e}", v.states());
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]
    /// The one-direction derivative J ξ (tangent flows) equals the exact Jacobian times ξ, and
    /// its f equals `rhs_into`, on every layout, both creep laws (the same dual-number
    /// arithmetic with one direction instead of four: agreement to rounding).
    #[test]
    fn tangent_equals_jacobian_times_direction(
        seed in prop::collection::vec(-1.0f64..1.0, 5),
        dir in prop::collection::vec(-1.0f64..1.0, 5),
        speed in 10.0f64..120.0,
        which in 0usize..10,
    ) {
        let spec = match which % 5 {
            0 => VehicleSpec::Wheelset,
            1 | 2 => bogie(which % 5 == 2),
            _ => car(which % 5 == 4),
        };
        let law = if which < 5 { CreepLaw::Kalker } else { CreepLaw::Shen { friction: 0.3 } };
        let v = seed_vehicle(&spec, law, true).expect("vehicle");
        let n = v.states();
        let (x, xi) = (state(n, &seed), state(n, &dir));
        let (mut f, mut d) = (vec![0.0; n], vec![0.0; n]);
        v.rhs_tangent_into(&x, speed, &xi, &mut f, &mut d);
        let (mut f0, mut jac) = (vec![0.0; n], vec![0.0; n * n]);
        v.rhs_jacobian_into(&x, speed, &mut f0, &mut jac);
        for r in 0..n {
            // (column-major) and the sum's scale: the largest term
            let terms: Vec<f64> = (0..n).map(|c| jac[c * n + r] * xi[c]).collect();
            let jxi: f64 = terms.iter().sum();
            let scale = terms.iter().fold(1e-300_f64, |m, t| m.max(t.abs()));
            prop_assert!((d[r] - jxi).abs() <= 1e-12 * scale, "{n} states, row {r}: {} vs {jxi}", d[r]);
            prop_assert!((f[r] - f0[r]).abs() <= 1e-13 * f0[r].abs().max(1e-300), "{n} states, f row {r}");
        }
    }
}

/// Tangent track is symmetric: f(−x) = −f(x) for every layout (docs/model.md §11).
#[test]
fn vehicle_field_is_odd() {
    for spec in [
        VehicleSpec::Wheelset,
        bogie(false),
        bogie(true),
        car(false),
        car(true),
    ] {
        let v = seed_vehicle(&spec, CreepLaw::Shen { friction: 0.3 }, true).expect("vehicle");
        let n = v.states();
        assert_eq!(n, spec.states());
        let x = state(n, &[0.3, -0.8, 0.5, 0.9, -0.2]);
        let xm: Vec<f64> = x.iter().map(|a| -a).collect();
        let (mut f, mut g) = (vec![0.0; n], vec![0.0; n]);
        v.rhs_into(&x, 50.0, &mut f);
        v.rhs_into(&xm, 50.0, &mut g);
        let scale = f.iter().fold(0.0_f64, |m, a| m.max(a.abs()));
        for i in 0..n {
            assert!(
                (f[i] + g[i]).abs() <= 1e-13 * scale,
                "{n} states, row {i}: {} vs {}",
                f[i],
                g[i]
            );
        }
    }
}

/// The element formulation of docs/model.md §11 gives the stiffness matrix a symmetric,
/// positive semi-definite form, and a frame that is displaced rigidly with its wheelsets
/// (same y, no yaw) stretches only the secondary.
#[test]
fn assembled_stiffness_is_symmetric_and_rigid_motion_loads_only_the_secondary() {
    let v = seed_vehicle(&car(true), CreepLaw::Kalker, true).expect("vehicle");
    let n = v.dofs();
    for i in 0..n {
        for j in 0..n {
            assert!(
                (v.stiffness(i, j) - v.stiffness(j, i)).abs()
                    <= 1e-9 * v.stiffness(i, i).abs().max(1.0)
            );
        }
    }
    // the whole car translated by 1 mm: no element is stretched
    let mut q = vec![0.0; n];
    for b in &v.bodies {
        q[b.dof] = 1e-3;
    }
    for i in 0..n {
        let f: f64 = (0..n).map(|j| v.stiffness(i, j) * q[j]).sum();
        assert!(f.abs() < 1e-9, "row {i}: {f}");
    }
    assert_eq!(v.coordinate_names().len(), n);
    assert_eq!(v.coordinate_names()[0], "y_wheelset_1");
}
