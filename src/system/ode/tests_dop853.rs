//! The 8th-order pair against closed forms: its order conditions, exactness on polynomials,
//! its convergence order and its continuous extension's, the monodromy matrix against a
//! matrix exponential, switching surfaces on the dead-band oscillator, and peaks on the
//! dense output.

use nalgebra::{Matrix2, SMatrix, SVector, Vector2, Vector3};

use super::dop853::{NODES, TEST_STAGES, TEST_WEIGHTS};
use super::dopri::{Point, Rk};
use super::models::{DeadBand, Linear};
use super::tests::{rel_err, rot_decay};
use super::tests_events::oscillator_exp;
use super::*;

fn opts8(rtol: f64, atol: f64, monodromy: bool) -> OdeOptions {
    OdeOptions {
        tol: Tolerances { rtol, atol },
        monodromy,
        method: Method::DormandPrince8,
        ..OdeOptions::default()
    }
}

/// Row sums equal the nodes, and the weights integrate $c^{q-1}$ exactly for q = 1..8 (the
/// bushy-tree conditions up to order 8), and two conditions through a stage,
/// $\sum_{ij} b_i a_{ij} c_j = 1/6$ and $\sum_{ij} b_i c_i a_{ij} c_j = 1/8$: a mistyped
/// coefficient fails one of them.
#[test]
fn order_conditions_hold() {
    let a = |i: usize, j: usize| -> f64 {
        if i == 0 {
            return 0.0;
        }
        TEST_STAGES[i - 1]
            .iter()
            .find(|(k, _)| *k == j)
            .map_or(0.0, |(_, v)| *v)
    };
    let b = |i: usize| {
        TEST_WEIGHTS
            .iter()
            .find(|(k, _)| *k == i)
            .map_or(0.0, |(_, v)| *v)
    };
    for (i, c) in NODES.iter().enumerate() {
        let sum: f64 = (0..12).map(|j| a(i, j)).sum();
        assert!((sum - c).abs() < 1e-14, "row {i}: {sum} vs c = {c}");
    }
    for q in 1..=8 {
        let s: f64 = (0..12).map(|i| b(i) * NODES[i].powi(q - 1)).sum();
        assert!((s - 1.0 / q as f64).abs() < 1e-14, "q = {q}: {s}");
    }
    // Σ b_i a_ij c_j = 1/6 (order 3) and Σ b_i c_i a_ij c_j = 1/8 (order 4)
    let mut s3 = 0.0;
    let mut s4 = 0.0;
    for (i, ci) in NODES.iter().enumerate() {
        for (j, cj) in NODES.iter().enumerate() {
            s3 += b(i) * a(i, j) * cj;
            s4 += b(i) * ci * a(i, j) * cj;
        }
    }
    assert!((s3 - 1.0 / 6.0).abs() < 1e-14, "{s3}");
    assert!((s4 - 1.0 / 8.0).abs() < 1e-14, "{s4}");
}

/// $\dot x_0 = 1$, $\dot x_1 = 8x_0^7$, $\dot x_2 = 7x_0^6$: $x = (t, t^8, t^7)$.
struct Powers8;

impl VectorField<3> for Powers8 {
    fn rhs(&self, x: &Vector3<f64>, _p: f64) -> Vector3<f64> {
        Vector3::new(1.0, 8.0 * x[0].powi(7), 7.0 * x[0].powi(6))
    }
    fn jacobian(&self, x: &Vector3<f64>, _p: f64) -> SMatrix<f64, 3, 3> {
        let mut j = SMatrix::<f64, 3, 3>::zeros();
        j[(1, 0)] = 56.0 * x[0].powi(6);
        j[(2, 0)] = 42.0 * x[0].powi(5);
        j
    }
}

fn rk8<F: VectorField<N>, const N: usize>(field: &F) -> Rk<'_, N, F> {
    Rk {
        field,
        p: 0.0,
        variational: false,
        tol: Tolerances::default(),
        tol_phi: Tolerances::default(),
        rhs_evals: 0,
        method: Method::DormandPrince8,
    }
}

/// One step integrates a polynomial of degree 8 exactly (an 8th-order quadrature), the
/// continuous extension one of degree 7; 12 evaluations a step, 3 more for the extension.
#[test]
fn step_exact_to_degree_8_and_dense_output_to_degree_7() {
    let mut rk = rk8(&Powers8);
    let t0 = 0.3_f64;
    let p0: Point<3, ()> = rk.point(t0, Vector3::new(t0, t0.powi(8), t0.powi(7)), ());
    let trial = rk.step(&p0, 0.7);
    assert!((trial.end.x[1] - 1.0).abs() < 1e-14, "{}", trial.end.x[1]);
    assert!((trial.end.x[2] - 1.0).abs() < 1e-14, "{}", trial.end.x[2]);
    assert_eq!(rk.rhs_evals, 13, "1 at the start + 12 per step");
    let dense = rk.dense(&p0, &trial);
    assert_eq!(rk.rhs_evals, 16, "3 for the continuous extension");
    for th in [0.1, 0.37, 0.5, 0.9] {
        let t = t0 + 0.7 * th;
        let x = dense.eval(t);
        assert!((x[0] - t).abs() < 1e-15, "θ = {th}");
        assert!((x[2] - t.powi(7)).abs() < 1e-14, "θ = {th}: {}", x[2]);
    }
}

/// The harmonic oscillator with fixed steps: halving the step divides the global error by
/// about 2⁸ = 256 at the end, and the continuous extension's error at mid-step (local,
/// O(h⁸)) by about 2⁸ as well.
#[test]
fn convergence_orders_are_8_and_8() {
    let field = Linear {
        a: Matrix2::new(0.0, 1.0, -1.0, 0.0),
    };
    // x = (sin t, cos t)
    let exact = |t: f64| Vector2::new(t.sin(), t.cos());
    let run = |n: usize| {
        let mut rk = rk8(&field);
        let h = 4.0 / n as f64;
        let mut p: Point<2, ()> = rk.point(0.0, exact(0.0), ());
        let mut mid_err = 0.0f64;
        for _ in 0..n {
            let trial = rk.step(&p, h);
            // the extension's own error at mid-step: against the exact flow from the step's
            // start, e^{Aτ} x(t₀) with e^{Aτ} = [[cos τ, sin τ], [−sin τ, cos τ]]
            let (s, c) = (0.5 * h).sin_cos();
            let from_start = Matrix2::new(c, s, -s, c) * p.x;
            let mid = rk.dense(&p, &trial).eval(p.t + 0.5 * h);
            mid_err = mid_err.max((mid - from_start).norm());
            p = trial.end;
        }
        ((p.x - exact(4.0)).norm(), mid_err)
    };
    let (e1, m1) = run(8);
    let (e2, m2) = run(16);
    let (ratio, mid_ratio) = (e1 / e2, m1 / m2);
    println!("global {e1:e} -> {e2:e} ({ratio:.0}), mid-step {m1:e} -> {m2:e} ({mid_ratio:.0})");
    assert!(ratio > 150.0 && ratio < 450.0, "global error ratio {ratio}");
    assert!(mid_ratio > 100.0, "mid-step error ratio {mid_ratio}");
}

/// Φ with the 8th-order pair equals the closed-form exponential of a rotation with decay,
/// and the pair takes fewer evaluations than the 5th-order one at rtol 1e-11.
#[test]
fn monodromy_matches_exponential_with_fewer_evaluations() {
    let (a, w, t) = (-0.3, 2.0, 5.0);
    let field = Linear {
        a: Matrix2::new(a, -w, w, a),
    };
    let x0 = Vector2::new(1.0, 0.5);
    let sol = integrate(&field, 0.0, &x0, t, &opts8(1e-11, 1e-13, true)).expect("smooth");
    let exact = rot_decay(a, w, t);
    assert!(rel_err(&sol.x, &(exact * x0)) < 1e-10);
    let phi = sol.monodromy.expect("monodromy requested");
    assert!(rel_err(&phi, &exact) < 1e-10, "{}", rel_err(&phi, &exact));
    let five = OdeOptions {
        method: Method::DormandPrince5,
        ..opts8(1e-11, 1e-13, true)
    };
    let sol5 = integrate(&field, 0.0, &x0, t, &five).expect("smooth");
    println!(
        "evaluations: dop853 {}, dopri5 {}",
        sol.stats.rhs_evals, sol5.stats.rhs_evals
    );
    assert!(sol.stats.rhs_evals < sol5.stats.rhs_evals);
}

/// Switching surfaces with the 8th-order pair: the dead-band oscillator's contact times
/// against the closed form, and its monodromy over a period against the product of the
/// segment exponentials.
#[test]
fn dead_band_events_and_monodromy_with_dop853() {
    let field = DeadBand {
        k1: 1.0,
        k2: 50.0,
        clearance: 0.5,
    };
    let (t1, t2) = field.contact_times(1.0).expect("contact");
    let period = 4.0 * t1 + 2.0 * t2;
    let x0 = Vector2::new(0.0, 1.0);
    let sol = integrate(&field, 0.0, &x0, 5.0 * period, &opts8(1e-12, 1e-14, true))
        .expect("piecewise smooth");
    assert_eq!(sol.stats.events, 20);
    assert!((sol.x - x0).norm() < 1e-9, "{}", sol.x);
    let osc = oscillator_exp;
    let one = osc(1.0, t1) * osc(51.0, t2) * osc(1.0, 2.0 * t1) * osc(51.0, t2) * osc(1.0, t1);
    let phi = sol.monodromy.expect("monodromy requested");
    assert!(
        rel_err(&phi, &one.pow(5)) < 1e-9,
        "{}",
        rel_err(&phi, &one.pow(5))
    );
}

/// The extremes found on the 8th-order dense output (only in steps where a derivative
/// changes sign) equal the closed-form maxima of four undamped rotations.
#[test]
fn peaks_with_dop853_match_closed_form_maxima() {
    let freqs = [3.0, 0.7, 11.0, 0.21];
    let radii = [1e-3, 2.5, 0.4, 7.0];
    let mut a = SMatrix::<f64, 8, 8>::zeros();
    let mut x0 = SVector::<f64, 8>::zeros();
    for k in 0..4 {
        let w = freqs[k];
        a.fixed_view_mut::<2, 2>(2 * k, 2 * k)
            .copy_from(&Matrix2::new(0.0, -w, w, 0.0));
        x0[2 * k] = radii[k];
    }
    for rtol in [1e-8, 1e-11] {
        let t_end = 9.0;
        let (_, high, low) = integrate_with_extremes(
            &Linear { a },
            0.0,
            &x0,
            t_end,
            &opts8(rtol, rtol * 1e-3, false),
        )
        .expect("smooth");
        for k in 0..4 {
            // u = r cos ωt reaches ±r within 9 s for every ω here except 0.21 (no minimum)
            let (r, w) = (radii[k], freqs[k]);
            let lo = if w * t_end >= std::f64::consts::PI {
                -r
            } else {
                r * (w * t_end).cos()
            };
            assert!(
                (high[2 * k] - r).abs() < 10.0 * rtol * r,
                "k {k}: {}",
                high[2 * k]
            );
            assert!(
                (low[2 * k] - lo).abs() < 10.0 * rtol * r,
                "k {k}: {} vs {lo}",
                low[2 * k]
            );
        }
    }
}
