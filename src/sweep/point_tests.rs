use super::*;

fn rec(failures: &[&str], above: &[Computed], top: Option<f64>) -> PointRecord {
    PointRecord {
        failures: failures.iter().map(|s| s.to_string()).collect(),
        above_range: above.to_vec(),
        stable_up_to_m_s: top,
        ..PointRecord::empty(0, vec![1.0])
    }
}

#[test]
fn status_names_above_range_and_failures_and_reads_back() {
    let cases = [
        (rec(&[], &[], None), "ok"),
        (
            rec(&[], &[Computed::Kalker, Computed::Hopf], Some(300.0)),
            "above range: kalker; hopf",
        ),
        (
            rec(&["nonlinear: no cycle, at all"], &[], None),
            "failed: nonlinear: no cycle; at all",
        ),
        (
            rec(&["nonlinear: x"], &[Computed::Hopf], Some(300.0)),
            "failed: nonlinear: x; above range: hopf",
        ),
        (
            PointRecord {
                no_hopf: true,
                ..rec(&[], &[Computed::Kalker, Computed::Hopf], Some(300.0))
            },
            "above range: kalker; hopf; no Hopf point in range: nonlinear",
        ),
        (
            PointRecord {
                no_hopf: true,
                ..rec(&[], &[], None)
            },
            "no Hopf point in range: nonlinear",
        ),
        (
            PointRecord {
                no_hopf: true,
                ..rec(&["kalker: y"], &[Computed::Hopf], Some(300.0))
            },
            "failed: kalker: y; above range: hopf; no Hopf point in range: nonlinear",
        ),
    ];
    for (r, want) in cases {
        assert_eq!(r.status(), want);
        let Status {
            failures,
            above,
            no_hopf,
        } = parse_status(want).expect("a sweep status");
        assert_eq!(above, r.above_range, "{want}");
        assert_eq!(failures.is_empty(), r.ok(), "{want}");
        assert_eq!(no_hopf, r.no_hopf, "{want}");
        let mut back = r.clone();
        back.set_status(want).expect("reads");
        assert_eq!(back.status(), want);
    }
    // the pre-`above range` reason stays a failure; unknown text is an error naming it
    let st = parse_status("failed: kalker: no onset of hunting between 1 and 300 m/s")
        .expect("format 1");
    assert_eq!((st.failures.len(), st.above.len()), (1, 0));
    // so does the V_NL reason written before `no Hopf point in range` was a status of its own
    let st = parse_status("failed: nonlinear: V_NL unknown: no Hopf point of the shen model in [1; 300] m/s; above range: hopf")
        .expect("format 2");
    assert_eq!(
        (st.failures.len(), st.above, st.no_hopf),
        (1, vec![Computed::Hopf], false)
    );
    let e = parse_status("above range: kalker; warp").expect_err("no such result");
    assert!(e.contains("warp"), "{e}");
    assert!(parse_status("fine").is_err());
}

#[test]
fn outcome_tells_found_above_and_missing_apart() {
    let mut r = rec(&["nonlinear: x"], &[Computed::Hopf], Some(250.0));
    r.kalker_m_s = Some(120.0);
    r.kalker_frequency_hz = Some(2.5);
    assert_eq!(
        r.outcome(Computed::Kalker),
        Outcome::Found {
            speed_m_s: 120.0,
            frequency_hz: Some(2.5)
        }
    );
    assert_eq!(
        r.outcome(Computed::Hopf),
        Outcome::AboveRange {
            stable_up_to_m_s: 250.0
        }
    );
    assert_eq!(r.outcome(Computed::Nonlinear), Outcome::Missing);
    assert!(!r.ok() && r.has_above_range());
    // V_NL without a Hopf point in range is said, not failed
    let r = PointRecord {
        no_hopf: true,
        ..rec(&[], &[Computed::Hopf], Some(250.0))
    };
    assert_eq!(r.outcome(Computed::Nonlinear), Outcome::NoHopf);
    assert!(r.ok());
}
