//! Force–velocity curves on every damper with series stiffness (docs/model.md §13), shown on the
//! DTU bogie's secondary lateral dampers: the exact Jacobian against central differences on
//! either side of the blow-off, the variational and tangent products against it, the field's
//! symmetry f(−x) = −f(x), a blow-off whose slope does not change giving the linear damper's
//! field, a table scaled by the damping key, the knees as switching surfaces, the linear
//! analysis on the slope at zero (with its note), a primary damper's curve, and bad input
//! refused by name.

mod common;

use critspeed::model::Vehicle;

/// The DTU bogie (studies/dtu-cooperrider-bogie.toml) with `secondary` added to its
/// `[secondary]` and `edit` applied to the whole text, written to a scratch folder `name`.
fn dtu_bogie(name: &str, secondary: &str, edit: impl Fn(String) -> String) -> std::path::PathBuf {
    let dir = common::scratch(name);
    let path = dir.join("bogie.toml");
    std::fs::write(&path, edit(common::dtu_bogie_text("secondary", secondary))).expect("write");
    path
}

fn model(name: &str, secondary: &str) -> Vehicle {
    let path = dtu_bogie(name, secondary, |t| t);
    let plan = critspeed::study::load(&path).expect("study");
    plan.model().expect("model")
}

/// The secondary lateral dampers (29.2 kN s/m per side in the study) on 8 MN/m bushes.
const SERIES: &str = "lateral_damper_series_stiffness = \"8 MN/m\"";
/// A relief valve at 1 kN, 5 kN s/m beyond.
const BLOW_OFF: &str =
    "lateral_damper_force_velocity = { blow_off_force = \"1 kN\", slope_after = \"5 kN s/m\" }";
const BLOW_OFF_FORCE: f64 = 1000.0;
const DAMPING: f64 = 29.2e3;

/// A state of `v` whose damper force in the stroke on a curve is `force` (N per damper); the
/// other states small and distinct.
fn state_with_force(v: &Vehicle, force: f64) -> (Vec<f64>, usize) {
    let n = v.dofs();
    let mut x: Vec<f64> = (0..v.states())
        .map(|i| 1e-3 * [0.3, -0.8, 0.5, 0.9, -0.2, 0.7][i % 6] * (1.0 + 0.1 * i as f64))
        .collect();
    let j = v
        .maxwell
        .iter()
        .position(|mx| mx.law.is_some())
        .expect("a stroke on a curve");
    let mx = &v.maxwell[j];
    let per_damper = mx.stiffness / mx.dampers as f64;
    x[2 * n + j] = mx.deflection(&x[..n]) - force / per_damper;
    assert!((mx.force(&x[..n], x[2 * n + j]) - force).abs() <= 1e-9 * force.abs());
    (x, j)
}

/// (a, b, c) On either side of the blow-off (0.4 and 3 times its force, both signs): the stroke
/// rate is g⁻¹(F) written out, the exact Jacobian equals central differences, the variational product J Φ and the tangent J ξ equal
/// the dense Jacobian's, and f(−x) = −f(x). The stroke's own entry ∂ż/∂z is −k_s/g'(ż) per
/// damper pair, g' the slope of the segment the force is on: 29.2 kN s/m below, 5 kN s/m above.
#[test]
fn the_blow_off_field_has_an_exact_jacobian_and_is_odd() {
    let v = model("fv-jacobian", &format!("{SERIES}\n{BLOW_OFF}"));
    assert_eq!(v.states(), 13);
    let n = v.dofs();
    let speed = 60.0;
    for (force, slope) in [
        (0.4 * BLOW_OFF_FORCE, DAMPING),
        (-0.4 * BLOW_OFF_FORCE, DAMPING),
        (3.0 * BLOW_OFF_FORCE, 5e3),
        (-3.0 * BLOW_OFF_FORCE, 5e3),
    ] {
        let (x, j) = state_with_force(&v, force);
        let (mut f, mut jac) = (vec![0.0; 13], vec![0.0; 13 * 13]);
        v.rhs_jacobian_into(&x, speed, &mut f, &mut jac);
        let worst =
            common::assert_jacobian_is_central_differences(&v, &x, speed, &jac, (1e-7, 1e-5));
        eprintln!("F = {force} N: Jacobian vs central differences, worst relative {worst:.1e}");
        let s = 2 * n + j;
        // the stroke rate is g⁻¹(F), written out: F/c below the knee, then F_b/c + (|F| − F_b)/c₂
        let a = force.abs();
        let rate = if a <= BLOW_OFF_FORCE {
            a / DAMPING
        } else {
            BLOW_OFF_FORCE / DAMPING + (a - BLOW_OFF_FORCE) / 5e3
        }
        .copysign(force);
        assert!(
            (f[s] - rate).abs() <= 1e-12 * rate.abs(),
            "F = {force} N: ż = {} against g⁻¹(F) = {rate}",
            f[s]
        );
        let ks = v.maxwell[j].stiffness / v.maxwell[j].dampers as f64;
        let want = -ks / slope;
        assert!(
            (jac[s * 13 + s] - want).abs() <= 1e-12 * want.abs(),
            "F = {force} N: ∂ż/∂z = {} against −k_s/g' = {want}",
            jac[s * 13 + s]
        );
        common::assert_variational_is_the_dense_product::<13>(&v, &x, speed, &jac, &f);
        common::assert_odd(&v, &x, speed, &f);
    }
}

/// (d) A blow-off whose slope after equals the slope before (the damping key) is the linear
/// damper: the field and its Jacobian equal those without a curve to 1e-12 of their largest
/// entry, below and above the knee.
#[test]
fn a_blow_off_without_a_change_of_slope_is_the_linear_damper() {
    let linear = model("fv-same-linear", SERIES);
    let same = model(
        "fv-same-curve",
        &format!(
            "{SERIES}\nlateral_damper_force_velocity = {{ blow_off_force = \"1 kN\", \
             slope_after = \"29.2 kN s/m\" }}"
        ),
    );
    assert_eq!(linear.states(), 13);
    assert!(linear.maxwell.iter().all(|mx| mx.law.is_none()));
    for force in [
        0.5 * BLOW_OFF_FORCE,
        -2.0 * BLOW_OFF_FORCE,
        7.0 * BLOW_OFF_FORCE,
    ] {
        let (x, _) = state_with_force(&same, force);
        let (mut f0, mut j0) = (vec![0.0; 13], vec![0.0; 13 * 13]);
        let (mut f1, mut j1) = (vec![0.0; 13], vec![0.0; 13 * 13]);
        linear.rhs_jacobian_into(&x, 70.0, &mut f0, &mut j0);
        same.rhs_jacobian_into(&x, 70.0, &mut f1, &mut j1);
        for (what, a, b) in [("f", &f0, &f1), ("J", &j0, &j1)] {
            let scale = a.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
            let worst = a
                .iter()
                .zip(b)
                .fold(0.0_f64, |m, (p, q)| m.max((p - q).abs()));
            eprintln!(
                "F = {force} N: {what} differs by {:.1e} of its largest entry",
                worst / scale
            );
            assert!(
                worst <= 1e-12 * scale,
                "F = {force} N: {what} differs by {worst:e} (largest {scale:e})"
            );
        }
    }
}

/// The curve reaches the model: the knee gives two switching functions, F − F_b and −F − F_b
/// (F the force per damper), which change sign at the blow-off force; a table is scaled so that its slope at zero is the damping
/// key (29.2 kN s/m: the table's 1 kN at 0.01 m/s becomes 292 N, its 2 kN at 0.1 m/s 584 N).
#[test]
fn the_knees_are_switching_surfaces_and_a_table_is_scaled_by_the_damping() {
    let linear = model("fv-switch-linear", SERIES);
    let v = model("fv-switch-curve", &format!("{SERIES}\n{BLOW_OFF}"));
    assert_eq!(v.switches(), linear.switches() + 2);
    let first = linear.switches();
    for force in [
        0.5 * BLOW_OFF_FORCE,
        1.5 * BLOW_OFF_FORCE,
        -1.5 * BLOW_OFF_FORCE,
    ] {
        let (x, _) = state_with_force(&v, force);
        let (up, down) = (v.switch(first, &x), v.switch(first + 1, &x));
        assert!((up - (force - BLOW_OFF_FORCE)).abs() <= 1e-9 * BLOW_OFF_FORCE);
        assert!((down - (-force - BLOW_OFF_FORCE)).abs() <= 1e-9 * BLOW_OFF_FORCE);
    }
    let table = model(
        "fv-table",
        &format!(
            "{SERIES}\nlateral_damper_force_velocity = \
             {{ points = [[\"0.01 m/s\", \"1 kN\"], [\"0.1 m/s\", \"2 kN\"]] }}"
        ),
    );
    assert_eq!(table.switches(), linear.switches() + 4);
    let g = table.maxwell.iter().find_map(|mx| mx.law).expect("a curve");
    let tail = (584.0 - 292.0) / 0.09;
    for (vel, want) in [
        (0.005, 146.0),
        (0.01, 292.0),
        (-0.1, -584.0),
        (0.3, 584.0 + tail * 0.2),
    ] {
        let got = g.force_at(vel);
        assert!(
            (got - want).abs() <= 1e-9 * want.abs(),
            "g({vel}) = {got}, not {want}"
        );
    }
    assert!((g.slope_at_zero() - DAMPING).abs() <= 1e-9 * DAMPING);
}

fn kalker(out: &std::process::Output) -> (f64, String) {
    assert_eq!(out.status.code(), Some(0), "{out:?}");
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).expect("json");
    let v = json["kalker"]["critical_speed_m_s"]
        .as_f64()
        .expect("speed");
    (v, json["notes"].to_string())
}

/// Through the CLI: the linear analysis sees the slope at zero (V_L as with the linear damper on
/// the same bushes, to 1e-9) and its note says so; a primary damper's curve (the primary lateral
/// dampers on 10 MN/m with a table) gives each wheelset's stroke its curve.
#[test]
fn the_linear_analysis_uses_the_slope_at_zero_and_says_so() {
    let run = |name: &str, lines: &str| {
        let path = dtu_bogie(name, lines, |t| t);
        let dir = path.parent().expect("folder").to_path_buf();
        common::critspeed(&["linear", path.to_str().expect("utf-8"), "--json"], &dir)
    };
    let (v0, _) = kalker(&run("fv-cli-linear", SERIES));
    let (v1, notes) = kalker(&run("fv-cli-curve", &format!("{SERIES}\n{BLOW_OFF}")));
    assert!((v1 - v0).abs() <= 1e-9 * v0, "{v1} vs {v0}");
    assert!(
        notes.contains("secondary, frame: the linear analysis uses the force-velocity curve's slope at zero, 29.2 kN s/m per damper"),
        "{notes}"
    );
    let primary = dtu_bogie("fv-primary", "", |t| {
        t.replace(
            "lateral_damping = 0\n",
            "lateral_damping = \"10 kN s/m\"\nlateral_damper_series_stiffness = \"10 MN/m\"\n\
             lateral_damper_force_velocity = { points = [[\"0.02 m/s\", \"1 kN\"], [\"0.2 m/s\", \"3 kN\"]] }\n",
        )
    });
    let v = critspeed::study::load(&primary)
        .expect("study")
        .model()
        .expect("model");
    assert_eq!(v.states(), 14);
    let curves: Vec<(&str, f64)> = v
        .maxwell
        .iter()
        .filter_map(|mx| Some((mx.name.as_str(), mx.law?.slope_at_zero())))
        .collect();
    assert_eq!(curves.len(), 2, "{curves:?}");
    for (name, slope) in curves {
        assert!(name.starts_with("primary, wheelset"), "{name}");
        assert!((slope - 1e4).abs() <= 1e-9 * 1e4, "{name}: {slope}");
    }
}

type Edit = fn(String) -> String;

/// Bad input exits 2 naming the key, the value and the rule: a curve without its series
/// stiffness, a falling table, a table not through zero, a blow-off without its first slope
/// (the lateral damping 0; the vertical damping absent), and a table on a damper of zero damping.
#[test]
fn bad_curves_are_refused_by_name() {
    let blow_off = format!("{SERIES}\n{BLOW_OFF}");
    // (scratch folder, lines added to [secondary], an edit of the whole text, the message's parts)
    type Case<'a> = (&'a str, &'a str, Edit, &'a [&'a str]);
    let cases: [Case; 6] = [
        (
            "fv-bad-series",
            BLOW_OFF,
            |t| t,
            &[
                "secondary.lateral_damper_series_stiffness is missing",
                "secondary.lateral_damper_force_velocity acts on the damper's stroke",
            ],
        ),
        (
            "fv-bad-monotone",
            "lateral_damper_series_stiffness = \"8 MN/m\"\nlateral_damper_force_velocity = \
             { points = [[\"0.01 m/s\", \"1 kN\"], [\"0.1 m/s\", \"0.5 kN\"]] }",
            |t| t,
            &[
                "secondary.lateral_damper_force_velocity.points = as given",
                "must be monotone: the force 500 N at 0.1 m/s is not above 1000 N at 0.01 m/s",
            ],
        ),
        (
            "fv-bad-zero",
            "lateral_damper_series_stiffness = \"8 MN/m\"\nlateral_damper_force_velocity = \
             { points = [[0, \"1 kN\"], [\"0.1 m/s\", \"2 kN\"]] }",
            |t| t,
            &[
                "secondary.lateral_damper_force_velocity.points = as given",
                "the curve must pass through zero",
            ],
        ),
        (
            "fv-bad-blow-off",
            &blow_off,
            |t| t.replace("lateral_damping = \"29.2 kN s/m\"", "lateral_damping = 0"),
            &[
                "secondary.lateral_damping is missing",
                "blow-off form takes its first slope from it",
            ],
        ),
        (
            "fv-bad-vertical",
            "vertical_damper_series_stiffness = \"8 MN/m\"\nvertical_damper_force_velocity = \
             { blow_off_force = \"1 kN\", slope_after = \"5 kN s/m\" }",
            |t| t.replace("vertical_damping = \"20 kN s/m\"\n", ""),
            &[
                "secondary.vertical_damping is missing",
                "secondary.vertical_damper_force_velocity's blow-off form",
            ],
        ),
        (
            "fv-bad-scale",
            "lateral_damper_series_stiffness = \"8 MN/m\"\nlateral_damper_force_velocity = \
             { points = [[\"0.1 m/s\", \"2 kN\"]] }",
            |t| t.replace("lateral_damping = \"29.2 kN s/m\"", "lateral_damping = 0"),
            &[
                "secondary.lateral_damping = 0 N s/m",
                "must be positive with a force-velocity curve",
            ],
        ),
    ];
    for (name, lines, edit, wants) in cases {
        let path = dtu_bogie(name, lines, edit);
        let dir = path.parent().expect("folder").to_path_buf();
        let out = common::critspeed(&["linear", path.to_str().expect("utf-8")], &dir);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{name}: {err}");
        for want in wants {
            assert!(err.contains(want), "{name}: {want:?} not in {err}");
        }
    }
}

/// The secondary lateral dampers' curve of `plan` (the bogie's).
fn lateral_curve(plan: &critspeed::study::Plan) -> Option<critspeed::model::ForceVelocity> {
    match &plan.vehicle {
        critspeed::model::VehicleSpec::Bogie { secondary, .. } => secondary.curves.lateral,
        _ => None,
    }
}

/// The blow-off's two numbers are sweep keys (and so `[curve]` and uncertainty keys): each point
/// of a sweep over `secondary.lateral_damper_force_velocity.blow_off_force` carries its force
/// into the model (the knee at the swept force, the slope after it as given) and, since the
/// linear analysis uses the slope at zero, every point's V_L is the study's to 1e-12; a sweep
/// over `slope_after` sets the tail. On a table curve the blow-off key is refused by name.
#[test]
fn the_blow_off_is_swept_into_the_model() {
    use critspeed::sweep::SweepStudy;
    let sweep = |name: &str, curve: &str, axis: &str| {
        let path = dtu_bogie(name, &format!("{SERIES}\n{curve}"), |t| {
            format!("{t}\n[sweep]\naxes = [ {axis} ]\ncompute = [\"kalker\"]\n")
        });
        SweepStudy::load(&path)
    };
    let study = sweep(
        "fv-sweep-force",
        BLOW_OFF,
        "{ key = \"secondary.lateral_damper_force_velocity.blow_off_force\", from = \"0.5 kN\", \
         to = \"4 kN\", count = 3 }",
    )
    .expect("sweep study");
    let v_l = |plan: &critspeed::study::Plan| {
        let r = critspeed::analysis::linear(plan, &plan.model().expect("model")).expect("linear");
        r.kalker.critical().expect("V_L").speed_m_s
    };
    let v0 = v_l(&study.base);
    for (id, force) in [500.0, 2250.0, 4000.0].into_iter().enumerate() {
        let plan = study.point_plan(id).expect("point plan");
        let g = lateral_curve(&plan).expect("the point's curve");
        assert_eq!(g.knee_forces(), &[force], "point {id}");
        let (_, tail) = g.points();
        assert!((tail - 5e3).abs() <= 1e-9 * 5e3, "point {id}: {tail}");
        assert!((g.slope_at_zero() - DAMPING).abs() <= 1e-9 * DAMPING);
        let v = v_l(&plan);
        assert!((v - v0).abs() <= 1e-12 * v0, "point {id}: {v} vs {v0}");
    }
    let study = sweep(
        "fv-sweep-slope",
        BLOW_OFF,
        "{ key = \"secondary.lateral_damper_force_velocity.slope_after\", from = \"1 kN s/m\", \
         to = \"9 kN s/m\", count = 2 }",
    )
    .expect("sweep study");
    for (id, after) in [1e3, 9e3].into_iter().enumerate() {
        let plan = study.point_plan(id).expect("point plan");
        let (_, tail) = lateral_curve(&plan).expect("curve").points();
        assert!((tail - after).abs() <= 1e-9 * after, "point {id}: {tail}");
    }
    let table = "lateral_damper_force_velocity = { points = [[\"0.02 m/s\", \"1 kN\"]] }";
    let err = match sweep(
        "fv-sweep-table",
        table,
        "{ key = \"secondary.lateral_damper_force_velocity.blow_off_force\", from = \"1 kN\", \
         to = \"2 kN\", count = 2 }",
    ) {
        // refused when the sweep is read (its axis ends are validated), else at the point
        Ok(s) => s
            .point_plan(0)
            .map(|_| ())
            .expect_err("a blow-off key on a table")
            .to_string(),
        Err(e) => e.to_string(),
    };
    assert!(err.contains("give either points"), "{err}");
    assert!(
        err.contains("secondary.lateral_damper_force_velocity"),
        "{err}"
    );
}
