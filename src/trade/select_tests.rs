use super::*;
use crate::study::units::Dimension;
use crate::trade::{Objective, ResultKind};

const K: &str = "suspension.longitudinal_stiffness";
const C: &str = "suspension.lateral_damping";

fn row(k: f64, c: f64, v: Option<f64>, status: &str) -> Row {
    Row {
        id: String::new(),
        axes: vec![(K.into(), k), (C.into(), c)],
        results: [v.map(|v| v - 5.0), None, v],
        status: status.into(),
        above: [false; 3],
        stable_up_to_m_s: None,
    }
}

fn plan(sense: Sense, at_least: f64) -> TradePlan {
    TradePlan {
        objective: Objective {
            key: K.into(),
            sense,
            dim: Dimension::Stiffness,
        },
        constraints: vec![Constraint {
            target: Target::Result(ResultKind::NonlinearCriticalSpeed),
            at_least: Some(at_least),
            at_most: None,
            text: String::new(),
        }],
        pareto: ResultKind::NonlinearCriticalSpeed,
        method: crate::trade::Method::Grid,
    }
}

/// Deterministic pseudo-random numbers in [0, 1) (LCG; no dependency, reproducible).
fn lcg(seed: &mut u64) -> f64 {
    *seed = seed
        .wrapping_mul(6364136223846793005)
        .wrapping_add(1442695040888963407);
    (*seed >> 11) as f64 / (1u64 << 53) as f64
}

#[test]
fn monotone_trade_has_closed_form_best() {
    // V(k) = 40 + 10 ln(k / 100 kN/m) rises with k, so V >= 60 m/s <=> k >= 100 e² kN/m;
    // minimising k, the best is the first grid stiffness at or above that.
    let ks: Vec<f64> = (0..25).map(|i| 1e5 * 30f64.powf(i as f64 / 24.0)).collect();
    let v = |k: f64| 40.0 + 10.0 * (k / 1e5).ln();
    let mut rows: Vec<Row> = ks.iter().map(|&k| row(k, 0.0, Some(v(k)), "ok")).collect();
    // failed points lack the failed result (as a sweep writes them)
    rows[3].status = "failed: continuation".into();
    rows[3].results[2] = None;
    rows[4].status = "no cycle".into();
    rows[4].results[2] = None;
    rows[20].results[2] = None; // nonlinear speed not found
    let a = assess(&plan(Sense::Minimize, 60.0), &rows);
    let k_min = 1e5 * 2f64.exp();
    let want = ks
        .iter()
        .position(|&k| k >= k_min)
        .expect("grid reaches it");
    assert_eq!(a.iter().position(|x| x.best), Some(want));
    for (i, (x, &k)) in a.iter().zip(&ks).enumerate() {
        let expect = k >= k_min && ![3, 4, 20].contains(&i);
        assert_eq!(x.feasible, expect, "point {i}: {}", x.reason);
        // with V increasing in k every computed point is non-dominated
        assert_eq!(x.pareto, ![3, 4, 20].contains(&i), "point {i}");
    }
    assert_eq!(a[3].reason, "failed: continuation");
    assert_eq!(a[4].reason, "failed: no cycle");
    assert_eq!(a[20].reason, "nonlinear_critical_speed not available");
    assert!(
        a[0].reason
            .starts_with("nonlinear_critical_speed 40 m/s < 60 m/s"),
        "{}",
        a[0].reason
    );
}

#[test]
fn small_front_known_by_hand() {
    let pts = [
        (1.0, 10.0),
        (2.0, 5.0),
        (3.0, 20.0),
        (4.0, 20.0),
        (5.0, 30.0),
    ]
    .map(Some);
    let f = pareto_front(Sense::Minimize, &pts);
    assert_eq!(f, vec![true, false, true, false, true]);
    let g = pareto_front(Sense::Maximize, &pts);
    assert_eq!(g, vec![false, false, false, false, true]);
    let dup = [Some((1.0, 1.0)), Some((1.0, 1.0)), None];
    assert_eq!(pareto_front(Sense::Minimize, &dup), vec![true, true, false]);
}

#[test]
fn ties_go_to_higher_speed_then_first_row() {
    let c = [
        Some((2.0, Some(50.0))),
        Some((1.0, Some(40.0))),
        Some((1.0, Some(45.0))),
        Some((1.0, Some(45.0))),
    ];
    assert_eq!(best_index(Sense::Minimize, &c), Some(2));
    assert_eq!(best_index(Sense::Maximize, &c), Some(0));
    assert_eq!(best_index(Sense::Minimize, &[None, None]), None);
}

#[test]
fn pareto_and_best_identities_on_random_two_axis_data() {
    let mut seed = 7;
    for sense in [Sense::Minimize, Sense::Maximize] {
        let rows: Vec<Row> = (0..300)
            .map(|i| {
                let k = (1e5 * (1.0 + 29.0 * lcg(&mut seed))).round(); // repeats on purpose
                let c = 1e4 * lcg(&mut seed);
                let v = (30.0 + 60.0 * lcg(&mut seed)).round();
                // a failed point lacks its result, as a sweep writes it
                let failed = i % 17 == 0;
                let status = if failed {
                    "failed: no hopf point"
                } else {
                    "ok"
                };
                row(k, c, (i % 11 != 0 && !failed).then_some(v), status)
            })
            .collect();
        let p = plan(sense, 62.0);
        let a = assess(&p, &rows);
        let cand = |r: &Row| match (r.axis(K), r.result(ResultKind::NonlinearCriticalSpeed)) {
            (Some(x), Some(v)) => Some((x, v)),
            _ => None,
        };
        let pts: Vec<Option<(f64, f64)>> = rows.iter().map(cand).collect();
        for (i, pi) in pts.iter().enumerate() {
            let dominated = |b: (f64, f64)| pts.iter().flatten().any(|q| dominates(sense, *q, b));
            match (pi, a[i].pareto) {
                (Some(b), true) => assert!(!dominated(*b), "front point {i} is dominated"),
                (Some(b), false) => {
                    let by_front = pts
                        .iter()
                        .zip(&a)
                        .any(|(q, x)| x.pareto && q.is_some_and(|q| dominates(sense, q, *b)));
                    assert!(
                        by_front,
                        "non-front point {i} not dominated by a front point"
                    );
                }
                (None, pareto) => assert!(!pareto, "non-candidate {i} on the front"),
            }
        }
        // feasibility by the definition, best by brute force
        let feasible: Vec<usize> = (0..rows.len())
            .filter(|&i| pts[i].is_some_and(|(_, v)| v >= 62.0))
            .collect();
        assert_eq!(
            feasible,
            (0..rows.len())
                .filter(|&i| a[i].feasible)
                .collect::<Vec<_>>()
        );
        let b = a
            .iter()
            .position(|x| x.best)
            .expect("some point is feasible");
        assert_eq!(a.iter().filter(|x| x.best).count(), 1);
        assert!(a[b].feasible);
        let kb = rows[b].axis(K).expect("objective");
        for &i in &feasible {
            let k = rows[i].axis(K).expect("objective");
            assert!(no_worse(sense, kb, k), "point {i} beats the best");
        }
    }
}

#[test]
fn axis_constraints_bound_the_axis() {
    let mut p = plan(Sense::Minimize, 0.0);
    p.constraints.push(Constraint {
        target: Target::Axis {
            key: C.into(),
            dim: Dimension::Damping,
        },
        at_least: None,
        at_most: Some(5e3),
        text: String::new(),
    });
    let rows = [
        row(1e5, 6e3, Some(70.0), "ok"),
        row(2e5, 4e3, Some(70.0), "ok"),
    ];
    let a = assess(&p, &rows);
    assert!(
        !a[0].feasible
            && a[0]
                .reason
                .contains("suspension.lateral_damping 6000 N s/m > 5000 N s/m")
    );
    assert!(a[1].feasible && a[1].best);
}

proptest::proptest! {
    /// Small integer values force ties and duplicates, where dominance is easiest to get wrong.
    #[test]
    fn front_identities_hold(pts in proptest::collection::vec(
        proptest::option::weighted(0.9, (0u8..8, 0u8..8)), 0..40), maximize: bool) {
        let sense = if maximize { Sense::Maximize } else { Sense::Minimize };
        let pts: Vec<Option<(f64, f64)>> =
            pts.iter().map(|p| p.map(|(a, b)| (f64::from(a), f64::from(b)))).collect();
        let front = pareto_front(sense, &pts);
        for (i, p) in pts.iter().enumerate() {
            let Some(b) = p else {
                proptest::prop_assert!(!front[i]);
                continue;
            };
            let dominated = pts.iter().flatten().any(|a| dominates(sense, *a, *b));
            proptest::prop_assert_eq!(front[i], !dominated);
            if !front[i] {
                let by_front = pts.iter().zip(&front)
                    .any(|(a, f)| *f && a.is_some_and(|a| dominates(sense, a, *b)));
                proptest::prop_assert!(by_front, "point {} not dominated by the front", i);
            }
        }
        // the best objective among candidates is on the front's objective extreme
        let cands: Vec<Option<(f64, Option<f64>)>> = pts.iter().map(|p| p.map(|(x, v)| (x, Some(v)))).collect();
        if let Some(b) = best_index(sense, &cands) {
            proptest::prop_assert!(front[b], "best {} of the candidates is not on the front", b);
        }
    }
}
