//! Tests of the unified spline against independent truth: polynomials, a hand-solved natural
//! spline, the defining end conditions, C² continuity, finite differences and dual numbers.

use super::*;
use crate::system::scalar::Dual;

fn cubic(t: f64) -> (f64, f64, f64) {
    (
        0.3 - 2.0 * t + 5.0 * t * t - 7.0 * t * t * t,
        -2.0 + 10.0 * t - 21.0 * t * t,
        10.0 - 42.0 * t,
    )
}

/// Irregular knots, 4 to 9 of them.
fn knots(n: usize) -> Vec<f64> {
    (0..n)
        .map(|i| -1.0 + 0.3 * i as f64 + 0.05 * ((i * i) % 3) as f64)
        .collect()
}

fn both(x: &[f64], v: &[f64]) -> [CubicSpline; 2] {
    [EndCondition::Natural, EndCondition::NotAKnot]
        .map(|end| CubicSpline::new(x, v, end).expect("valid knots"))
}

#[test]
fn not_a_knot_reproduces_a_cubic_exactly() {
    for n in 4..10 {
        let x = knots(n);
        let v: Vec<f64> = x.iter().map(|&t| cubic(t).0).collect();
        let sp = CubicSpline::not_a_knot(&x, &v).expect("valid knots");
        // inside and 0.2 beyond each end (the end cubic is continued)
        for k in 0..=48 {
            let t = x[0] - 0.2 + (x[n - 1] - x[0] + 0.4) * k as f64 / 48.0;
            let (val, d1, d2) = sp.eval(t);
            let (ev, ed1, ed2) = cubic(t);
            assert!((val - ev).abs() < 1e-12, "n={n} t={t}: {val} vs {ev}");
            assert!((d1 - ed1).abs() < 1e-11, "n={n} t={t}: {d1} vs {ed1}");
            assert!((d2 - ed2).abs() < 1e-10, "n={n} t={t}: {d2} vs {ed2}");
        }
    }
}

#[test]
fn not_a_knot_third_derivative_is_continuous_at_the_second_knots() {
    let x = knots(9);
    let v: Vec<f64> = x.iter().map(|&t| (3.0 * t).sin()).collect();
    let sp = CubicSpline::not_a_knot(&x, &v).expect("valid knots");
    // S''' = 6 d per interval: intervals 0 and 1 (and the last two) are one cubic
    let d = |k: usize| sp.coef[k][3];
    let last = sp.coef.len() - 1;
    assert!(
        (d(0) - d(1)).abs() < 1e-12 * d(0).abs().max(1.0),
        "{} {}",
        d(0),
        d(1)
    );
    let (p, q) = (d(last - 1), d(last));
    assert!((p - q).abs() < 1e-12 * p.abs().max(1.0), "{p} {q}");
    // and not at the interior knots in general (the condition is not vacuous)
    assert!((d(2) - d(3)).abs() > 1e-3);
}

#[test]
fn natural_ends_have_zero_curvature() {
    for n in 3..10 {
        let x: Vec<f64> = (0..n).map(|k| (k as f64).powf(1.3) * 0.01).collect();
        let v: Vec<f64> = x.iter().map(|&t| (40.0 * t).exp() + t * t).collect();
        let sp = CubicSpline::natural(&x, &v).expect("valid knots");
        let scale = v.iter().fold(0.0f64, |m, y| m.max(y.abs())) / (x[1] - x[0]).powi(2);
        let (_, _, c0) = sp.eval(x[0]);
        let (_, _, c1) = sp.eval(x[n - 1]);
        assert!(c0.abs() < 1e-12 * scale, "n={n}: S''(x0) = {c0}");
        assert!(c1.abs() < 1e-12 * scale, "n={n}: S''(xn) = {c1}");
    }
}

/// Through (0, 0), (1, 1), (2, 0) with natural ends, by hand: the curvature at x = 1 solves
/// 2(h0 + h1) m1 = 6(Δ1 − Δ0), so m1 = −3, and on [0, 1] S = 1.5 t − 0.5 t³ (symmetric about 1).
#[test]
fn natural_matches_a_hand_solved_case() {
    let sp = CubicSpline::natural(&[0.0, 1.0, 2.0], &[0.0, 1.0, 0.0]).expect("valid knots");
    for t in [0.0, 0.25, 0.5, 1.0, 1.5, 2.0] {
        let u = if t <= 1.0 { t } else { 2.0 - t };
        let sign = if t <= 1.0 { 1.0 } else { -1.0 };
        let (v, d1, d2) = sp.eval(t);
        assert!(
            (v - (1.5 * u - 0.5 * u * u * u)).abs() < 1e-15,
            "t={t}: {v}"
        );
        assert!(
            (d1 - sign * (1.5 - 1.5 * u * u)).abs() < 1e-15,
            "t={t}: {d1}"
        );
        assert!((d2 + 3.0 * u).abs() < 1e-14, "t={t}: {d2}");
    }
}

#[test]
fn natural_reproduces_a_line() {
    let x: Vec<f64> = (0..7).map(|k| (k as f64).powf(1.3)).collect();
    let y: Vec<f64> = x.iter().map(|v| 2.0 - 0.5 * v).collect();
    let s = CubicSpline::natural(&x, &y).expect("valid knots");
    for q in [-0.5, 0.1, 1.7, 4.3, 8.9, 10.0] {
        let (v, d1, d2) = s.eval(q);
        assert!((v - (2.0 - 0.5 * q)).abs() < 1e-13 && (d1 + 0.5).abs() < 1e-13);
        assert!(d2.abs() < 1e-12);
    }
}

#[test]
fn interpolates_at_every_knot() {
    let x = knots(9);
    let v: Vec<f64> = x.iter().map(|&t| (3.0 * t).sin()).collect();
    for sp in both(&x, &v) {
        for (xi, vi) in x.iter().zip(&v) {
            let got = sp.eval(*xi).0;
            assert!(
                (got - vi).abs() < 4.0 * f64::EPSILON,
                "{:?} at {xi}: {got} vs {vi}",
                sp.end
            );
        }
        assert_eq!(sp.knots().1, &v[..]);
        assert_eq!(sp.range(), (x[0], x[8]));
    }
}

/// Each interval's cubic, evaluated at its right end, meets the next one's at its left end in
/// value, slope and curvature (C²), for both end conditions.
#[test]
fn is_c2_at_interior_knots() {
    let x = knots(9);
    let v: Vec<f64> = x.iter().map(|&t| (3.0 * t).sin() + t * t * t).collect();
    for sp in both(&x, &v) {
        for (k, &xk) in x.iter().enumerate().take(x.len() - 1).skip(1) {
            let left = sp.eval_in(k - 1, xk);
            let right = sp.eval_in(k, xk);
            let pairs = [(left.0, right.0), (left.1, right.1), (left.2, right.2)];
            for (j, (l, r)) in pairs.into_iter().enumerate() {
                assert!(
                    (l - r).abs() < 1e-12 * l.abs().max(1.0),
                    "{:?} knot {k} derivative {j}: {l} vs {r}",
                    sp.end
                );
            }
        }
    }
}

/// Slope and curvature against central differences of the value and the slope (error
/// O(ε²·S''') and O(ε²·S'''') = O(ε²) with a piecewise-constant S''' away from knots).
#[test]
fn derivatives_match_finite_differences_and_dual_numbers() {
    let x = knots(9);
    let v: Vec<f64> = x.iter().map(|&t| (2.0 * t).cos()).collect();
    let eps = 1e-6;
    for sp in both(&x, &v) {
        for k in 0..40 {
            // midpoints-ish, never within eps of a knot
            let t = x[0] + 0.013 + (x[8] - x[0] - 0.03) * k as f64 / 40.0;
            if x.iter().any(|&xi| (xi - t).abs() < 2.0 * eps) {
                continue;
            }
            let (_, d1, d2) = sp.eval(t);
            let fd1 = (sp.eval(t + eps).0 - sp.eval(t - eps).0) / (2.0 * eps);
            let fd2 = (sp.eval(t + eps).1 - sp.eval(t - eps).1) / (2.0 * eps);
            assert!((d1 - fd1).abs() < 1e-8, "{:?} t={t}: {d1} vs {fd1}", sp.end);
            assert!((d2 - fd2).abs() < 1e-7, "{:?} t={t}: {d2} vs {fd2}", sp.end);
            let (dv, dd1, _) = sp.eval(Dual::<1>::var(t, 0));
            assert!((dv.eps[0] - d1).abs() < 1e-14 * d1.abs().max(1.0));
            assert!((dd1.eps[0] - d2).abs() < 1e-13 * d2.abs().max(1.0));
        }
    }
}

#[test]
fn natural_converges_on_a_circle() {
    // a 300 mm arc sampled every 0.5 mm: curvature to 1e-4 relative in the middle
    let r = 0.3;
    let x: Vec<f64> = (-60..=60).map(|k| k as f64 * 5e-4).collect();
    let y: Vec<f64> = x.iter().map(|v| (r * r - v * v).sqrt()).collect();
    let s = CubicSpline::natural(&x, &y).expect("valid knots");
    let (_, d1, d2) = s.eval(0.0101);
    let kappa = -d2 / (1.0 + d1 * d1).powf(1.5);
    assert!((kappa * r - 1.0).abs() < 1e-4, "{kappa}");
}

#[test]
fn value_hint_agrees_with_eval_in_any_order() {
    let x = knots(9);
    let v: Vec<f64> = x.iter().map(|&t| (3.0 * t).sin()).collect();
    let sp = CubicSpline::natural(&x, &v).expect("valid knots");
    let mut hint = 0;
    for t in [-1.5, 0.3, -0.2, 1.4, 1.41, 2.0, -0.9, x[4], f64::NAN] {
        let (a, b) = (sp.value_hint(t, &mut hint), sp.eval(t).0);
        assert!(
            (a - b).abs() < 1e-16 || (a.is_nan() && b.is_nan()),
            "{t}: {a} vs {b}"
        );
    }
}

#[test]
fn rejects_bad_input() {
    assert_eq!(
        CubicSpline::not_a_knot(&[0.0, 1.0, 2.0], &[0.0; 3]),
        Err(SplineError::TooFewPoints {
            points: 3,
            end: EndCondition::NotAKnot
        })
    );
    let two = CubicSpline::natural(&[0.0, 1.0], &[0.0; 2]);
    assert_eq!(
        two.map_err(|e| e.to_string()),
        Err("2 points; the natural spline needs at least 3".to_string())
    );
    assert!(CubicSpline::natural(&[0.0, 1.0, 2.0], &[0.0; 3]).is_ok());
    assert!(matches!(
        CubicSpline::not_a_knot(&[0.0, 1.0, 1.0, 2.0], &[0.0; 4]),
        Err(SplineError::NotIncreasing { index: 2, .. })
    ));
    assert!(matches!(
        CubicSpline::natural(&[0.0, 1.0, 2.0, 3.0], &[0.0, f64::NAN, 0.0, 0.0]),
        Err(SplineError::NotFinite { index: 1, .. })
    ));
}

/// Random irregular knots (gaps 0.05–1) and data: both end conditions interpolate, are C² at
/// every interior knot, natural ends have zero curvature, and not-a-knot reproduces a random
/// cubic through the same knots.
mod random {
    use super::*;
    use proptest::prelude::*;

    fn knots_and_values() -> impl Strategy<Value = (Vec<f64>, Vec<f64>)> {
        (4usize..24).prop_flat_map(|n| {
            (
                proptest::collection::vec(0.05f64..1.0, n - 1),
                proptest::collection::vec(-2.0f64..2.0, n),
            )
                .prop_map(|(gaps, v)| {
                    let mut x = vec![-1.0];
                    for g in gaps {
                        x.push(x[x.len() - 1] + g);
                    }
                    (x, v)
                })
        })
    }

    proptest! {
        #[test]
        fn interpolating_c2_and_end_conditions((x, v) in knots_and_values(),
                                               p in proptest::array::uniform4(-3.0f64..3.0)) {
            let n = x.len();
            for sp in both(&x, &v) {
                let tol = 1e-9 * sp.coef.iter().flatten().fold(1.0f64, |m, c| m.max(c.abs()));
                for (k, (&xk, &vk)) in x.iter().zip(&v).enumerate() {
                    prop_assert!((sp.eval(xk).0 - vk).abs() < 1e-12);
                    if k > 0 && k + 1 < n {
                        let (l, r) = (sp.eval_in(k - 1, xk), sp.eval_in(k, xk));
                        prop_assert!((l.0 - r.0).abs() < tol && (l.1 - r.1).abs() < tol);
                        prop_assert!((l.2 - r.2).abs() < tol, "{:?} knot {k}: {} vs {}", sp.end, l.2, r.2);
                    }
                }
                if sp.end == EndCondition::Natural {
                    prop_assert!(sp.eval(x[0]).2.abs() < tol);
                    prop_assert!(sp.eval(x[n - 1]).2.abs() < tol);
                }
            }
            let f = |t: f64| p[0] + t * (p[1] + t * (p[2] + t * p[3]));
            let w: Vec<f64> = x.iter().map(|&t| f(t)).collect();
            let sp = CubicSpline::not_a_knot(&x, &w).expect("valid knots");
            let scale = 1.0 + p.iter().map(|c| c.abs()).sum::<f64>() * x[n - 1].abs().max(1.0).powi(3);
            for k in 0..=50 {
                let t = x[0] + (x[n - 1] - x[0]) * k as f64 / 50.0;
                prop_assert!((sp.eval(t).0 - f(t)).abs() < 1e-10 * scale, "t={t}");
            }
        }
    }
}
