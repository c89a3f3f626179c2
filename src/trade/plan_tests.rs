use super::*;

fn table(text: &str) -> Table {
    text.parse::<Table>().expect("test TOML parses")
}

fn plan(text: &str) -> Result<TradePlan, StudyError> {
    trade_plan(&table(text))
}

#[test]
fn factor_times_line_speed_in_si() {
    let p = plan(
        r#"minimize = "suspension.longitudinal_stiffness"
           constraints = [ { result = "nonlinear_critical_speed", at_least = "200 km/h", factor = 1.1 } ]"#,
    )
    .expect("valid");
    assert_eq!(p.objective.sense, Sense::Minimize);
    assert_eq!(p.objective.dim, Dimension::Stiffness);
    assert_eq!(p.pareto, ResultKind::NonlinearCriticalSpeed);
    let c = &p.constraints[0];
    // 1.1 × 200 km/h = 1.1 × 200 / 3.6 m/s
    let want = 1.1 * 200.0 / 3.6;
    assert!((c.at_least.expect("bound") - want).abs() < 1e-12 * want);
    assert_eq!(c.at_most, None);
    assert!(c.text.contains("1.1 × 200 km/h = 61.11 m/s"), "{}", c.text);
}

#[test]
fn axis_bounds_use_the_axis_units() {
    let p = plan(
        r#"maximize = "suspension.lateral_damping"
           pareto = "kalker_critical_speed"
           constraints = [ { axis = "suspension.longitudinal_stiffness", at_least = 100, at_most = "2 kN/mm" } ]"#,
    )
    .expect("valid");
    assert_eq!(p.objective.sense, Sense::Maximize);
    assert_eq!(p.pareto, ResultKind::KalkerCriticalSpeed);
    let c = &p.constraints[0];
    assert_eq!(c.at_least, Some(100.0));
    assert_eq!(c.at_most, Some(2e6));
}

#[test]
fn errors_name_key_value_and_rule() {
    let cases = [
        ("constraints = []", "trade.minimize is missing"),
        (
            r#"minimize = "suspension.lateral_stiffness"
               maximize = "suspension.lateral_stiffness""#,
            "exactly one",
        ),
        (
            r#"minimize = "suspension.stiffnes""#,
            "\"suspension.stiffnes\" is not one of",
        ),
        (
            r#"minimize = "contact.conicity"
            objective = 3"#,
            "trade.objective = 3: unknown key",
        ),
        (
            r#"minimize = "contact.conicity"
               constraints = [ { result = "critical_speed", at_least = 3 } ]"#,
            "trade.constraints[0].result = \"critical_speed\" is not one of",
        ),
        (
            r#"minimize = "contact.conicity"
               constraints = [ { result = "hopf_speed", at_least = "200 N/mm" } ]"#,
            "trade.constraints[0].at_least = \"200 N/mm\"",
        ),
        (
            r#"minimize = "contact.conicity"
               constraints = [ { result = "hopf_speed" } ]"#,
            "trade.constraints[0].at_least is missing",
        ),
        (
            r#"minimize = "contact.conicity"
               constraints = [ { result = "hopf_speed", at_least = 3, factor = -1 } ]"#,
            "trade.constraints[0].factor = -1: must be > 0",
        ),
        (
            r#"minimize = "contact.conicity"
               constraints = [ { result = "hopf_speed", at_least = 30, at_most = 20 } ]"#,
            "the range is empty",
        ),
        (
            r#"minimize = "contact.conicity"
               constraints = [ { result = "hopf_speed", axis = "contact.conicity", at_least = 3 } ]"#,
            "exactly one of result",
        ),
        (
            r#"minimize = "contact.conicity"
               constraints = [ { result = "hopf_speed", above = 3 } ]"#,
            "trade.constraints[0].above = 3: unknown key",
        ),
        (
            r#"minimize = "contact.conicity"
            pareto = "speed""#,
            "trade.pareto = \"speed\"",
        ),
    ];
    for (text, want) in cases {
        let e = plan(text).expect_err(text).to_string();
        assert!(e.contains(want), "{text}\n  gave: {e}\n  want: {want}");
    }
}
