//! Trade rules for results above the speed range (no onset up to v_max).

use super::*;
use crate::study::units::Dimension;
use crate::trade::table::read_sweep;
use crate::trade::{Objective, ResultKind};

const K: &str = "suspension.longitudinal_stiffness";
const TOP: f64 = 300.0;

/// A row with objective `k` and V_NL `v` (m/s), or above range (stable to 300 m/s) if `None`.
fn row(k: f64, v: Option<f64>) -> Row {
    Row {
        id: k.to_string(),
        axes: vec![(K.into(), k)],
        results: [None, None, v],
        status: if v.is_some() {
            "ok".into()
        } else {
            "above range: nonlinear".into()
        },
        above: [false, false, v.is_none()],
        stable_up_to_m_s: v.is_none().then_some(TOP),
    }
}

fn plan(at_least: Option<f64>, at_most: Option<f64>) -> TradePlan {
    TradePlan {
        objective: Objective {
            key: K.into(),
            sense: Sense::Minimize,
            dim: Dimension::Stiffness,
        },
        constraints: vec![Constraint {
            target: Target::Result(ResultKind::NonlinearCriticalSpeed),
            at_least,
            at_most,
            text: String::new(),
        }],
        pareto: ResultKind::NonlinearCriticalSpeed,
        method: crate::trade::Method::Grid,
    }
}

#[test]
fn at_least_is_met_iff_the_bound_is_within_the_range() {
    let rows = [row(1.0, None)];
    for (x, feasible) in [(55.0, true), (TOP, true), (330.0, false)] {
        let a = assess(&plan(Some(x), None), &rows);
        assert_eq!(a[0].feasible, feasible, "at_least {x}: {}", a[0].reason);
        if !feasible {
            assert!(
                a[0].reason
                    .contains("stable to 300 m/s (no onset in range)"),
                "{}",
                a[0].reason
            );
        }
    }
}

#[test]
fn at_most_is_never_met_above_range() {
    let rows = [row(1.0, None)];
    // V > 300 m/s: violated for a bound at or below 300, unknown above it
    for (x, word) in [(250.0, "> 250 m/s"), (TOP, "> 300 m/s"), (400.0, "unknown")] {
        let a = assess(&plan(None, Some(x)), &rows);
        assert!(!a[0].feasible);
        assert!(a[0].reason.contains(word), "{x}: {}", a[0].reason);
        assert!(a[0]
            .reason
            .contains("stable to 300 m/s (no onset in range)"));
    }
}

#[test]
fn front_and_best_use_v_capped_at_the_range_top() {
    // minimise k; V rises with k and the stiffest two are above range
    let rows = [
        row(1.0, Some(100.0)),
        row(2.0, Some(200.0)),
        row(3.0, None),
        row(4.0, None),
    ];
    let a = assess(&plan(Some(250.0), None), &rows);
    let best: Vec<bool> = a.iter().map(|x| x.best).collect();
    assert_eq!(best, [false, false, true, false]);
    // min(V, 300) = 100, 200, 300, 300: the fourth is dominated by the third
    let front: Vec<bool> = a.iter().map(|x| x.pareto).collect();
    assert_eq!(front, [true, true, true, false]);
    assert_eq!(
        a.iter().map(|x| x.feasible).collect::<Vec<_>>(),
        [false, false, true, true]
    );
}

#[test]
fn rows_read_the_status_and_the_range_top() {
    let csv = "point_id,suspension.longitudinal_stiffness_n_per_m,nonlinear_critical_speed_m_s,status,stable_up_to_m_s\n\
               0,1e5,80,ok,\n\
               1,1e6,,above range: kalker; nonlinear,300\n\
               2,1e7,,failed: nonlinear: x; above range: kalker,300\n";
    let t = read_sweep(csv, "t.csv").expect("csv");
    let rows = t.rows(&plan(Some(250.0), None)).expect("rows");
    assert!(rows[0].ok() && rows[1].ok() && !rows[2].ok());
    let top = ResultKind::NonlinearCriticalSpeed;
    assert_eq!(rows[1].above_range(top), Some(300.0));
    assert_eq!(rows[2].above_range(top), None);
    assert_eq!(
        rows[2].above_range(ResultKind::KalkerCriticalSpeed),
        Some(300.0)
    );
    assert_eq!(rows[0].capped(top), Some(80.0));
    let a = assess(&plan(Some(250.0), None), &rows);
    assert_eq!(
        a.iter().map(|x| x.feasible).collect::<Vec<_>>(),
        [false, true, false]
    );
}

/// A point whose V_NL is unknown (no Hopf point in range) but whose V_L was found.
fn nl_unknown(k: f64, v_l: f64) -> Row {
    Row {
        id: k.to_string(),
        axes: vec![(K.into(), k)],
        results: [Some(v_l), None, None],
        status: "failed: nonlinear: V_NL unknown: no Hopf point in range".into(),
        above: [false, false, false],
        stable_up_to_m_s: None,
    }
}

fn kalker_plan(at_least: f64) -> TradePlan {
    let mut p = plan(Some(at_least), None);
    p.constraints[0].target = Target::Result(ResultKind::KalkerCriticalSpeed);
    p.pareto = ResultKind::KalkerCriticalSpeed;
    p
}

#[test]
fn a_failure_on_a_result_the_trade_does_not_read_does_not_matter() {
    let rows = [nl_unknown(1.0, 120.0), nl_unknown(2.0, 80.0)];
    let a = assess(&kalker_plan(100.0), &rows);
    assert!(a[0].feasible && a[0].best && a[0].pareto, "{:?}", a[0]);
    assert!(
        !a[1].feasible && a[1].reason.contains("< 100"),
        "{:?}",
        a[1]
    );
    // the same rows, constrained on V_NL: infeasible with the failure as the reason
    let a = assess(&plan(Some(100.0), None), &rows);
    assert!(
        a.iter().all(|x| !x.feasible && !x.pareto && !x.best),
        "{a:?}"
    );
    assert!(a[0].reason.contains("V_NL unknown"), "{}", a[0].reason);
}

#[test]
fn a_point_with_every_result_failed_is_never_feasible_on_axis_constraints_alone() {
    let mut r = nl_unknown(1.0, 120.0);
    r.results = [None, None, None];
    r.status = "failed: invalid parameters: lateral_stiffness must be > 0".into();
    let mut p = plan(None, None);
    p.constraints[0].target = Target::Axis {
        key: K.into(),
        dim: Dimension::Stiffness,
    };
    p.constraints[0].at_most = Some(10.0);
    let a = assess(&p, &[r]);
    assert!(
        !a[0].feasible && a[0].reason.contains("invalid parameters"),
        "{:?}",
        a[0]
    );
}
