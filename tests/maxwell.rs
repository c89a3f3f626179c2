//! Dampers on series stiffness (Maxwell elements, docs/model.md §13) against closed forms: the
//! characteristic polynomial of a wheelset whose yaw is held only by a Maxwell pair, written by
//! hand; the rigid damper as the limit k_s → ∞ with an error like 1/k_s; the Jacobian against
//! differences and the variational product; the vector field's symmetry f(−x) = −f(x); the
//! mode shape's strokes against the stroke equation's closed form.

use critspeed::contact::creep::CreepLaw;
use critspeed::model::{
    layouts, DamperSeries, PrimaryVertical, Secondary, Vehicle, VehicleSpec, STATE_SIZES,
};
use critspeed::reference::{
    cone_wheelset, REFERENCE_FRAME, REFERENCE_SECONDARY, SEED_CREEP, SEED_SUSPENSION, SEED_WHEELSET,
};
use critspeed::system::ode::VectorField;
use nalgebra::{Complex, DMatrix, SMatrix, SVector, Vector4};

/// The seed wheelset on a 0.15 cone with a soft lateral primary (as tests/vehicle.rs): it
/// hunts near 70 m/s.
fn hunting_wheelset(law: CreepLaw) -> critspeed::model::Wheelset {
    let mut s = SEED_SUSPENSION;
    s.lateral_stiffness = 3e5;
    cone_wheelset(SEED_WHEELSET, s, SEED_CREEP, 0.15, law, true).expect("table")
}

fn primary_series(series: DamperSeries) -> PrimaryVertical {
    PrimaryVertical {
        series,
        ..PrimaryVertical::default()
    }
}

/// The bogie of tests/vehicle.rs's reference data with its yaw dampers (166.669 kN s/m per
/// side at 1.5 m, DYTSI's secondary longitudinal damping) on bushes of `ks` (None: rigid).
fn bogie_with_yaw_dampers(ks: Option<f64>) -> Vehicle {
    let secondary = Secondary {
        longitudinal_damping: 0.0,
        yaw_damping: 1.66669e5,
        yaw_damper_half_spacing: 1.5,
        series: DamperSeries {
            yaw: ks,
            ..DamperSeries::RIGID
        },
        ..REFERENCE_SECONDARY
    };
    let spec = VehicleSpec::Bogie {
        frame: REFERENCE_FRAME,
        secondary,
    };
    layouts::build(
        &spec,
        hunting_wheelset(CreepLaw::Kalker),
        &PrimaryVertical::default(),
    )
    .expect("bogie")
}

fn v_l<const N: usize>(v: &Vehicle) -> f64 {
    common::v_l_in::<N>(v, (1.0, 300.0))
}

fn det(m: DMatrix<Complex<f64>>) -> Complex<f64> {
    m.lu().determinant()
}

/// A wheelset whose yaw is restrained only by its two longitudinal dampers c on bushes k_s
/// (no longitudinal spring). Eliminating each damper's stroke, z = k_s/(k_s + c s) Δ, the pair
/// acts on the yaw as the impedance e(s) = 2 d² k_s c s / (k_s + c s). With the rigid
/// wheelset's equations written out (docs/model.md §8, `Wheelset::jacobian`, not the element
/// assembly) as ẍ = A q + B q̇ without the longitudinal primary, the polynomial
/// P(s) = (k_s + c s) det(s² I − s B − A + diag(0, e(s)/I_z))
/// has degree 5 and equals c det(sI − J) for the assembled model's 5 × 5 Jacobian J (its two
/// strokes share one state; their difference decays at −k_s/c on its own and is not a
/// state). Checked at points of the complex plane around the hunting frequency, at three
/// speeds.
#[test]
fn a_yaw_held_only_by_a_maxwell_pair_has_the_polynomial_written_by_hand() {
    let (ks, c) = (2.0e6, 1.0e5);
    let mut hand = SEED_SUSPENSION;
    hand.lateral_stiffness = 3e5;
    hand.longitudinal_stiffness = 0.0;
    hand.longitudinal_damping = 0.0;
    let hand_ws = cone_wheelset(
        SEED_WHEELSET,
        hand,
        SEED_CREEP,
        0.15,
        CreepLaw::Kalker,
        true,
    )
    .expect("ws");
    let mut model_susp = hand;
    model_susp.longitudinal_damping = c;
    let ws = cone_wheelset(
        SEED_WHEELSET,
        model_susp,
        SEED_CREEP,
        0.15,
        CreepLaw::Kalker,
        true,
    )
    .expect("ws");
    let series = DamperSeries {
        longitudinal: Some(ks),
        ..DamperSeries::RIGID
    };
    let v = layouts::build(&VehicleSpec::Wheelset, ws, &primary_series(series)).expect("model");
    assert_eq!(v.states(), 5, "one stroke for the pair");
    assert_eq!(v.maxwell.len(), 1);
    assert_eq!(v.maxwell[0].dampers, 2);
    assert_eq!(v.maxwell[0].name, "primary, wheelset 1");
    let d2 = hand.half_spring_spacing.powi(2);
    let iz = SEED_WHEELSET.yaw_inertia;
    for speed in [20.0, 60.0, 120.0] {
        let (j4, _) = hand_ws.jacobian(&Vector4::zeros(), speed);
        let j: SMatrix<f64, 5, 5> = VectorField::<5>::jacobian(&v, &SVector::zeros(), speed);
        for s in [
            Complex::new(0.0, 12.0),
            Complex::new(-3.0, 25.0),
            Complex::new(2.0, 5.0),
            Complex::new(-40.0, 0.0),
            Complex::new(7.0, -60.0),
        ] {
            let e = s * (2.0 * d2 * ks * c) / (s * c + ks) / iz;
            // s² I − s B − A, rows (y, ψ), plus e(s)/I_z on the yaw
            let q = |r: usize, col: usize| {
                let id = if r == col {
                    s * s
                } else {
                    Complex::new(0.0, 0.0)
                };
                id - s * j4[(2 + r, 2 + col)] - j4[(2 + r, col)]
                    + if r == 1 && col == 1 { e } else { 0.0.into() }
            };
            let p = (s * c + ks) * (q(0, 0) * q(1, 1) - q(0, 1) * q(1, 0));
            let si_j = DMatrix::from_fn(5, 5, |r, col| {
                let id = if r == col { s } else { Complex::new(0.0, 0.0) };
                id - Complex::new(j[(r, col)], 0.0)
            });
            let chi = det(si_j) * c;
            let err = (chi - p).norm() / p.norm();
            assert!(
                err < 1e-9,
                "V = {speed} m/s, s = {s}: det form {chi} vs hand {p} (rel. {err:.2e})"
            );
        }
    }
}

/// docs/model.md §13: k_s → ∞ gives the rigid damper, with an error like 1/k_s (the element's
/// dynamic stiffness c²ω²/k_s). On the wheelset (longitudinal primary dampers) and on the bogie
/// (yaw dampers, 13 states), V_L's error falls tenfold per decade of k_s.
#[test]
fn stiff_bushes_tend_to_the_rigid_damper_like_one_over_ks() {
    let rigid_ws = layouts::single(hunting_wheelset(CreepLaw::Kalker)).expect("ws");
    let v0 = v_l::<4>(&rigid_ws);
    let errs: Vec<f64> = [1e7, 1e8, 1e9]
        .iter()
        .map(|&ks| {
            let series = DamperSeries {
                longitudinal: Some(ks),
                ..DamperSeries::RIGID
            };
            let w = layouts::build(
                &VehicleSpec::Wheelset,
                hunting_wheelset(CreepLaw::Kalker),
                &primary_series(series),
            )
            .expect("ws");
            (v_l::<5>(&w) - v0).abs()
        })
        .collect();
    for pair in errs.windows(2) {
        let ratio = pair[0] / pair[1];
        assert!(
            (7.0..14.0).contains(&ratio),
            "wheelset (V_L rigid {v0:.4} m/s): errors {errs:?}, ratio {ratio}"
        );
    }
    let b0 = v_l::<12>(&bogie_with_yaw_dampers(None));
    let errs: Vec<f64> = [1e8, 1e9, 1e10]
        .iter()
        .map(|&ks| (v_l::<13>(&bogie_with_yaw_dampers(Some(ks))) - b0).abs())
        .collect();
    for pair in errs.windows(2) {
        let ratio = pair[0] / pair[1];
        assert!(
            (7.0..14.0).contains(&ratio),
            "bogie (V_L rigid {b0:.4} m/s): errors {errs:?}, ratio {ratio}"
        );
    }
}

fn state(n: usize, seed: &[f64]) -> Vec<f64> {
    (0..n)
        .map(|i| 1e-3 * seed[i % seed.len()] * (1.0 + 0.1 * i as f64))
        .collect()
}

/// The exact Jacobian of a car with series-stiff yaw and lateral dampers (32 states) against
/// central differences of f; the variational product against J Φ; f(−x) = −f(x).
#[test]
fn the_car_with_strokes_has_a_consistent_jacobian_and_is_odd() {
    let secondary = Secondary {
        yaw_damping: 1.66669e5,
        series: DamperSeries {
            yaw: Some(5e6),
            lateral: Some(8e6),
            ..DamperSeries::RIGID
        },
        ..REFERENCE_SECONDARY
    };
    let spec = VehicleSpec::Car {
        frame: REFERENCE_FRAME,
        secondary,
        body: critspeed::reference::REFERENCE_CAR_BODY,
    };
    let ws = hunting_wheelset(CreepLaw::Shen { friction: 0.3 });
    let v = layouts::build(&spec, ws, &PrimaryVertical::default()).expect("car");
    assert_eq!(v.states(), 32);
    assert!(STATE_SIZES.contains(&32));
    let names: Vec<&str> = v.maxwell.iter().map(|m| m.name.as_str()).collect();
    assert_eq!(
        names,
        [
            "secondary, frame 1",
            "yaw damper, frame 1",
            "secondary, frame 2",
            "yaw damper, frame 2"
        ]
    );
    let n = v.states();
    let x = state(n, &[0.3, -0.8, 0.5, 0.9, -0.2, 0.7]);
    let speed = 55.0;
    let (mut f, mut jac) = (vec![0.0; n], vec![0.0; n * n]);
    v.rhs_jacobian_into(&x, speed, &mut f, &mut jac);
    common::assert_jacobian_is_central_differences(&v, &x, speed, &jac, (1e-7, 1e-5));
    common::assert_variational_is_the_dense_product::<32>(&v, &x, speed, &jac, &f);
    common::assert_odd(&v, &x, speed, &f);
}

/// Strokes beyond the compiled state sizes are refused with the dampers named, not run: a bogie
/// with series stiffness on its three secondary dampers and on both primary dampers of each
/// wheelset has 12 + 3 + 4 = 19 states.
#[test]
fn too_many_strokes_are_refused_by_name() {
    let secondary = Secondary {
        yaw_damping: 1.66669e5,
        series: DamperSeries {
            yaw: Some(5e6),
            lateral: Some(8e6),
            longitudinal: Some(8e6),
            ..DamperSeries::RIGID
        },
        ..REFERENCE_SECONDARY
    };
    let spec = VehicleSpec::Bogie {
        frame: REFERENCE_FRAME,
        secondary,
    };
    let primary = primary_series(DamperSeries {
        lateral: Some(8e6),
        longitudinal: Some(8e6),
        ..DamperSeries::RIGID
    });
    let err = layouts::build(&spec, hunting_wheelset(CreepLaw::Kalker), &primary)
        .expect_err("19 states are not compiled");
    let text = err.to_string();
    assert!(
        text.contains("7 damper stroke(s)")
            && text.contains("yaw damper, frame")
            && text.contains("19 states"),
        "{text}"
    );
}

mod common;

/// The DTU bogie with its yaw dampers on 10 MN/m bushes and a relief valve at 3 kN (20 kN s/m
/// beyond), loaded from a study written to a scratch folder `name`: 13 states.
fn blow_off_bogie(name: &str) -> (critspeed::study::Plan, Vehicle) {
    let dir = common::scratch(name);
    let path = common::dtu_bogie_with(
        &dir,
        "secondary",
        "yaw_damper_series_stiffness = \"10 MN/m\"\n\
         yaw_damper_force_velocity = { blow_off_force = \"3 kN\", slope_after = \"20 kN s/m\" }",
    );
    let plan = critspeed::study::load(&path).expect("study");
    let model = plan.model().expect("model");
    assert_eq!(model.states(), 13);
    assert!(model.maxwell[0].law.is_some());
    (plan, model)
}

fn kalker_speed(out: &std::process::Output) -> (f64, usize) {
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).expect("json");
    let speed = json["kalker"]["critical_speed_m_s"]
        .as_f64()
        .unwrap_or_else(|| panic!("no kalker speed in {json}"));
    let states = json["states"]
        .as_u64()
        .unwrap_or_else(|| panic!("no states in {json}"));
    (speed, states as usize)
}

/// How many strokes the first Kalker crossing's mode shape lists (`None`: no mode shape).
fn mode_dampers(out: &std::process::Output) -> Option<usize> {
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).expect("json");
    json["critical_speeds"][0]["mode_shape"]["dampers"]
        .as_array()
        .map(Vec::len)
}

/// Through the study file: `secondary.yaw_damper_series_stiffness` makes the DTU bogie's yaw
/// dampers Maxwell elements (13 states); nearly rigid bushes (1e10 N/m) give the rigid
/// damper's V_L to 1e-4, 5 MN/m moves it by more than 1 %; zero and negative values exit 2 naming the key.
#[test]
fn the_study_key_reaches_the_model_and_bad_values_are_refused() {
    let dir = common::scratch("maxwell-study");
    let run = |lines: &str| {
        let study = common::dtu_bogie_with(&dir, "secondary", lines);
        common::critspeed(&["linear", study.to_str().expect("utf-8"), "--json"], &dir)
    };
    let rigid = run("");
    assert_eq!(rigid.status.code(), Some(0), "{rigid:?}");
    let (v0, n0) = kalker_speed(&rigid);
    assert_eq!(n0, 12);
    assert_eq!(
        mode_dampers(&rigid),
        Some(0),
        "rigid dampers report no stroke"
    );
    let stiff = run("yaw_damper_series_stiffness = \"1e10 N/m\"");
    assert_eq!(stiff.status.code(), Some(0), "{stiff:?}");
    let (v1, n1) = kalker_speed(&stiff);
    assert_eq!(n1, 13);
    assert_eq!(
        mode_dampers(&stiff),
        Some(1),
        "one stroke for the yaw-damper pair"
    );
    assert!((v1 - v0).abs() <= 1e-4 * v0, "{v1} vs rigid {v0}");
    let soft = run("yaw_damper_series_stiffness = \"5 MN/m\"");
    let (v2, _) = kalker_speed(&soft);
    assert!((v2 - v0).abs() > 1e-2 * v0, "{v2} vs rigid {v0}");
    for bad in ["0", "\"-5 MN/m\""] {
        let out = run(&format!("yaw_damper_series_stiffness = {bad}"));
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{bad}: {err}");
        assert!(
            err.contains("secondary.yaw_damper_series_stiffness"),
            "{bad}: {err}"
        );
    }
}

/// The DTU bogie (studies/dtu-cooperrider-bogie.toml) with its yaw dampers on 10 MN/m bushes and
/// a relief valve at 3 kN (20 kN s/m beyond): the continued diagram's stable cycles, whose yaw
/// dampers blow off, are the attractors of long simulations. From each of two stable cycles'
/// start states, moved by 0.1 mm, 56 + 4 s of simulation settle on the cycle: the leading
/// wheelset's amplitude over the last 4 s (sampled every 10 µs) equals the cycle's to 1e-6
/// relative, and the
/// damper's force passes the blow-off (the nonlinear part is exercised). The two cycles are
/// the first and the last stable ones whose largest nontrivial multiplier is below 0.9.
#[test]
fn a_blow_off_damper_cycle_is_the_attractor_of_a_long_simulation() {
    use critspeed::bifurcation::analyse;
    use critspeed::system::ode::{OdeOptions, Tolerances};
    let (plan, model) = blow_off_bogie("maxwell-blow-off");
    let report = analyse(&plan.name, &model, &plan.bifurcation_options()).expect("analysis");
    // stable cycles that attract fast enough for 56 s (about 550 periods) to settle to 1e-6
    let stable: Vec<_> = report
        .cycles
        .iter()
        .filter(|c| c.stable && c.max_multiplier_abs < 0.9)
        .collect();
    assert!(stable.len() >= 2, "{} stable cycles", stable.len());
    let ode = OdeOptions {
        tol: Tolerances::new(1e-10, 1e-13).expect("tolerances"),
        ..OdeOptions::default()
    };
    let blow_off = 3000.0;
    for cycle in [stable[0], stable[stable.len() - 1]] {
        let mut x0 = cycle.x0.clone();
        x0[0] += 1e-4;
        let settle = critspeed::simulate::simulate(&model, cycle.speed_m_s, &x0, 56.0, 0.1, &ode)
            .expect("simulation");
        let last = settle.x.last().expect("samples").clone();
        // the last 4 s sampled every 10 µs: a sampled maximum is within (ω dt)²/8 ≈ 1e-8 of
        // the true one at 5 Hz
        let h = critspeed::simulate::simulate(&model, cycle.speed_m_s, &last, 4.0, 1e-5, &ode)
            .expect("simulation");
        let tail = 0;
        let amplitude = h.x.iter().map(|x| x[0].abs()).fold(0.0, f64::max);
        let rel = (amplitude - cycle.amplitude_y_m).abs() / cycle.amplitude_y_m;
        assert!(
            rel < 1e-6,
            "{} m/s: simulated {amplitude} m vs continued {} m ({rel:.1e})",
            cycle.speed_m_s,
            cycle.amplitude_y_m
        );
        let mx = &model.maxwell[0];
        let n = model.dofs();
        let peak_force = h.x[tail..]
            .iter()
            .map(|x| mx.force(&x[..n], x[2 * n]).abs())
            .fold(0.0, f64::max);
        assert!(
            peak_force > blow_off,
            "{peak_force} N: the valve never opens"
        );
    }
}

/// The same bogie with blow-off yaw dampers hunts far below every stable cycle of its continued
/// branch: the branch's lowest stable cycle lies near 130 m/s (a torus point), but the attractor
/// search, started from kicks, finds a slower cycle (about 5 Hz against the branch's 11 Hz) on
/// which the valves open, alive down to about 84 m/s. V_NL is the search's, and the report says
/// in words that the two methods disagree (`critspeed attractors` prints it). A plain 150 s simulation (sharing only the
/// right-hand side with the search) from the search's state at the death bracket's upper end
/// confirms both ends: hunting above 1 mm at the upper end, below 0.1 mm at the lower end.
#[test]
fn blow_off_dampers_hunt_below_the_continued_branch_and_the_report_says_so() {
    use critspeed::attractors::{search, AttractorOptions};
    use critspeed::bifurcation::analyse;
    const N: usize = 13;
    let (plan, model) = blow_off_bogie("maxwell-search");
    let bo = plan.bifurcation_options();
    let b = analyse(&plan.name, &model, &bo).expect("branch");
    let continued = b
        .cycles
        .iter()
        .filter(|c| c.stable)
        .map(|c| c.speed_m_s)
        .fold(f64::INFINITY, f64::min);
    let opts = AttractorOptions::new(
        bo.speed_range,
        b.hopf.map(|h| h.speed_m_s),
        bo.geometry_limit,
    );
    let r = search(&plan.name, &model, &opts, Some(&b)).expect("search");
    let (v_nl, _, _) = r.nonlinear_critical_speed.expect("an attractor");
    assert!(
        v_nl < continued - 20.0,
        "search {v_nl} m/s vs the branch's lowest stable cycle {continued} m/s"
    );
    let ((lo, hi), below, above) = common::excursions_across_death::<N>(&model, &r);
    assert!(above > 1e-3, "at {hi} m/s: {above} m after 150 s");
    assert!(below < 1e-4, "at {lo} m/s: {below} m after 150 s");
    // the joined report takes the search's V_NL and names the disagreement
    let mut joined = b.clone();
    critspeed::reconcile::combine(&mut joined, &r);
    assert_eq!(joined.nonlinear_critical_speed.map(|(v, _)| v), Some(v_nl));
    assert!(
        joined
            .notes
            .iter()
            .any(|n| n.starts_with("the continuation and the attractor search disagree")),
        "{:?}",
        joined.notes
    );
    eprintln!(
        "V_NL {v_nl} m/s by the search, lowest stable continued cycle {continued} m/s; \
         after 150 s: {below:.3e} m at {lo} m/s, {above:.3e} m at {hi} m/s"
    );
}

/// The passenger car (studies/passenger-car-s1002.toml: yaw dampers of 300 kN s/m per side, the
/// slope at zero of their curve, on 10 MN/m bushes): in the linear motion at an eigenvalue s
/// the stroke obeys (c s + k_s) z = k_s Δ, so on the imaginary axis (s = iω, ω from the
/// crossing's frequency) the share of the deflection the damper takes is
/// k_s/√(k_s² + c²ω²), whatever the rest of the vehicle does. Every crossing's mode shape in
/// `linear --json` (both creep laws) lists both frames' yaw-damper strokes with that share,
/// and the console prints them.
#[test]
fn the_mode_shape_gives_each_stroke_the_closed_form_share_of_its_deflection() {
    let (ks, c) = (10e6, 300e3);
    let dir = common::scratch("maxwell-mode");
    let study = common::root().join("studies/passenger-car-s1002.toml");
    let study = study.to_str().expect("utf-8");
    let out = common::critspeed(&["linear", study, "--json"], &dir);
    assert_eq!(out.status.code(), Some(0), "{out:?}");
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).expect("json");
    let mut checked = 0;
    for key in ["critical_speeds", "creep_law_hopf_speeds"] {
        for crossing in json[key].as_array().expect("crossings") {
            let omega = 2.0 * std::f64::consts::PI * crossing["frequency_hz"].as_f64().expect("f");
            let want = ks / (ks * ks + c * c * omega * omega).sqrt();
            let dampers = crossing["mode_shape"]["dampers"]
                .as_array()
                .expect("dampers");
            let names: Vec<&str> = dampers
                .iter()
                .filter_map(|d| d["damper"].as_str())
                .collect();
            assert_eq!(names, ["yaw damper, frame 1", "yaw damper, frame 2"]);
            for d in dampers {
                let share = d["deflection_share"].as_f64().expect("share");
                let err = (share - want).abs() / want;
                eprintln!(
                    "{key} {:.3} m/s, {:.4} Hz, {}: share {share:.9}, k_s/|c s + k_s| {want:.9} \
                     (rel. {err:.1e}), |z|/|y1| {:.4e}, phase {:.1} deg",
                    crossing["speed_m_s"].as_f64().expect("speed"),
                    omega / (2.0 * std::f64::consts::PI),
                    d["damper"],
                    d["stroke_per_y1"].as_f64().expect("stroke"),
                    d["stroke_phase_deg"].as_f64().expect("phase"),
                );
                assert!(err < 1e-9, "{d}: share {share} vs {want}");
                checked += 1;
            }
        }
    }
    assert!(checked >= 4, "{checked} strokes checked");
    let text = common::critspeed(&["linear", study], &dir);
    let text = String::from_utf8_lossy(&text.stdout);
    assert!(
        text.contains("strokes |z|/|y1|, phase, |z|/|deflection|: yaw damper, frame 1 "),
        "{text}"
    );
}

/// The share of a stroke at the bogie's crossing (critspeed::analysis::mode_shape), with the
/// crossing's frequency (Hz).
fn bogie_share(ks: f64) -> (f64, f64) {
    use critspeed::stability::{critical_speeds, LinearOptions, LinearSystem};
    let v = bogie_with_yaw_dampers(Some(ks));
    let sys = LinearSystem::<13>::at_centre(&v);
    let opts = LinearOptions {
        speed_range: (1.0, 300.0),
        ..LinearOptions::default()
    };
    let found = critical_speeds(&sys, v.creep_law(), &opts).expect("search runs");
    let c = found.critical().expect("an onset");
    let pair = c.eigenpair(&sys).expect("eigenpair");
    let m = critspeed::analysis::mode_shape(&v, &pair.vector).expect("mode shape");
    assert_eq!(m.dampers.len(), 1);
    assert_eq!(m.dampers[0].damper, "yaw damper, frame");
    (m.dampers[0].deflection_share, c.frequency_hz)
}

/// k_s → ∞: the damper takes the whole deflection. z/Δ = 1/(1 + c s/k_s) tends to 1 like
/// 1/k_s, its modulus (the reported share, s = iω) like 1/k_s²: 1 − share falls a hundredfold
/// per decade of k_s on the bogie's yaw dampers.
#[test]
fn stiff_bushes_leave_the_damper_the_whole_deflection() {
    let gaps: Vec<f64> = [1e8, 1e9, 1e10]
        .iter()
        .map(|&ks| {
            let (share, f) = bogie_share(ks);
            eprintln!("k_s {ks:.0e} N/m: share {share:.12} at {f:.4} Hz");
            1.0 - share
        })
        .collect();
    assert!(gaps.iter().all(|g| *g > 0.0), "{gaps:?}");
    for pair in gaps.windows(2) {
        let ratio = pair[0] / pair[1];
        assert!(
            (70.0..140.0).contains(&ratio),
            "1 − share {gaps:?}, ratio {ratio}"
        );
    }
}
