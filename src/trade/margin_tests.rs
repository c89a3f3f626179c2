use super::*;
use crate::study::units::Dimension;
use crate::trade::{Constraint, Method, Objective, ResultKind, Sense};

fn plan(at_least: Option<f64>, at_most: Option<f64>) -> TradePlan {
    TradePlan {
        objective: Objective {
            key: "k".into(),
            sense: Sense::Minimize,
            dim: Dimension::Stiffness,
        },
        constraints: vec![Constraint {
            target: Target::Result(ResultKind::HopfSpeed),
            at_least,
            at_most,
            text: String::new(),
        }],
        pareto: ResultKind::HopfSpeed,
        method: Method::Curve,
    }
}

fn row(v: Option<f64>, status: &str, top: Option<f64>) -> Row {
    Row {
        id: "0".into(),
        axes: vec![("k".into(), 1.0)],
        results: [None, v, None],
        status: status.into(),
        above: [false, status.contains("above"), false],
        stable_up_to_m_s: top,
    }
}

#[test]
fn the_illinois_end_is_the_root_on_the_feasible_side() {
    // f = 2 − p: feasible below 2
    let f = |p: f64| 2.0 - p;
    let (p, n) = locate(&f, (0.0, f(0.0)), (3.0, f(3.0)), 1e-12);
    assert!((p - 2.0).abs() <= 1e-12 && p <= 2.0 + 1e-15, "{p}");
    assert!(n < 10, "{n} evaluations for a straight line");
    // a curved margin converges superlinearly too
    let g = |p: f64| (p * p * p) - 8.0;
    let (p, n) = locate(&g, (3.0, g(3.0)), (0.5, g(0.5)), 1e-12);
    assert!((p - 2.0).abs() <= 1e-11 && g(p) >= 0.0, "{p}");
    assert!(n < 40, "{n}");
    // no value on the infeasible side: bisection, still to the tolerance
    let h = |p: f64| if p < 1.3 { 1.0 } else { f64::NEG_INFINITY };
    let (p, _) = locate(&h, (0.0, 1.0), (2.0, f64::NEG_INFINITY), 1e-10);
    assert!((p - 1.3).abs() <= 1e-10 && p < 1.3, "{p}");
}

#[test]
fn the_margin_is_non_negative_exactly_when_the_row_is_feasible() {
    let p = plan(Some(50.0), None);
    for v in [10.0, 49.999, 50.0, 50.001, 200.0] {
        let r = row(Some(v), "ok", None);
        let m = margin(&p, &r);
        assert_eq!(
            m >= 0.0,
            super::super::select::infeasibility(&p, &r).is_none(),
            "{v}"
        );
        assert!(
            (m - (v - 50.0) / 50.0).abs() <= 1e-15 || m == 0.0,
            "{v}: {m}"
        );
    }
    // above range: v_max counts; an at_most fails
    let above = row(None, "above range: hopf", Some(300.0));
    assert!((margin(&p, &above) - 5.0).abs() < 1e-12);
    assert!(margin(&plan(None, Some(400.0)), &above) < 0.0);
    // failed: no value at all
    let failed = row(None, "failed: hopf: no convergence", None);
    assert_eq!(margin(&p, &failed), f64::NEG_INFINITY);
}
