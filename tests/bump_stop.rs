//! Lateral bump stops (docs/model.md §13): the force law in closed form, the vector field's
//! symmetry f(−x) = −f(x) beyond the clearance, the exact Jacobian against central differences
//! (and the variational and tangent products against it), the linear analysis unchanged with a
//! note, a simulation whose steps land on the stops' switching surfaces, the hunting cycle of
//! the DTU bogie on a secondary stop against a long simulation, and bad keys refused by name.

mod common;

use critspeed::contact::creep::CreepLaw;
use critspeed::model::{
    layouts, BumpStop, PrimaryVertical, Secondary, StopLaw, StopSpec, StopTable, Vehicle,
    VehicleSpec,
};
use critspeed::reference::{
    cone_wheelset, REFERENCE_CAR_BODY, REFERENCE_FRAME, REFERENCE_SECONDARY, SEED_CREEP,
    SEED_SUSPENSION, SEED_WHEELSET,
};
use critspeed::stability::{critical_speeds, LinearOptions, LinearSystem};
use critspeed::system::ode::{OdeOptions, Tolerances};
use nalgebra::SVector;

/// The seed wheelset on a 0.15 cone with a soft lateral primary (as tests/vehicle.rs).
fn hunting_wheelset(law: CreepLaw) -> critspeed::model::Wheelset {
    let mut s = SEED_SUSPENSION;
    s.lateral_stiffness = 3e5;
    cone_wheelset(SEED_WHEELSET, s, SEED_CREEP, 0.15, law, true).expect("table")
}

/// A secondary stop of 3 mm at 2 MN/m, a progressive primary stop of 1 mm (1 MN/m up to 2 mm
/// of penetration, then 5 MN/m).
fn stops() -> (StopSpec, StopSpec) {
    let table = StopTable::from_points(&[(0.002, 2000.0), (0.004, 12000.0)]).expect("table");
    (
        StopSpec {
            clearance: 0.003,
            law: StopLaw::Linear(2e6),
        },
        StopSpec {
            clearance: 0.001,
            law: StopLaw::Table(table),
        },
    )
}

fn build(car: bool, with_stops: bool, law: CreepLaw) -> Vehicle {
    let (sec, prim) = stops();
    let secondary = Secondary {
        bump_stop: with_stops.then_some(sec),
        ..REFERENCE_SECONDARY
    };
    let pv = PrimaryVertical {
        bump_stop: with_stops.then_some(prim),
        ..PrimaryVertical::default()
    };
    let spec = if car {
        VehicleSpec::Car {
            frame: REFERENCE_FRAME,
            secondary,
            body: REFERENCE_CAR_BODY,
        }
    } else {
        VehicleSpec::Bogie {
            frame: REFERENCE_FRAME,
            secondary,
        }
    };
    layouts::build(&spec, hunting_wheelset(law), &pv).expect("vehicle")
}

/// (1) The law: nothing inside the clearance, −k_b(Δ − δ_b sign Δ) beyond it, odd; a table's
/// slope changes at its knee; the switching functions are zero on the edges and knees.
#[test]
fn the_force_law_is_a_dead_band_spring_and_odd() {
    let stop = BumpStop {
        name: "stop".into(),
        row: vec![(0, 1.0)],
        clearance: 0.02,
        law: StopLaw::Linear(3e6),
    };
    for d in [-0.02, -0.01, 0.0, 0.005, 0.019_999, 0.02] {
        assert_eq!(stop.force(d), (0.0, 0.0), "Δ = {d}");
    }
    for d in [0.021, 0.03, 0.1] {
        let (f, slope) = stop.force(d);
        let want = -3e6 * (d - 0.02);
        assert!(
            (f - want).abs() <= 1e-9 * want.abs(),
            "Δ = {d}: {f} vs {want}"
        );
        assert_eq!(slope, -3e6);
        let (g, _) = stop.force(-d);
        assert_eq!(g, -f, "odd at {d}");
    }
    assert_eq!(stop.switch(0, 0.02), 0.0);
    assert_eq!(stop.switch(1, -0.02), 0.0);
    let (_, prim) = stops();
    let table = BumpStop {
        law: prim.law,
        clearance: prim.clearance,
        ..stop
    };
    // 2 edges + 2 for the knee at 2 mm
    assert_eq!(table.switches(), 4);
    assert!(table.switch(2, 0.003).abs() < 1e-18);
    assert!(table.switch(3, -0.003).abs() < 1e-18);
    let (f, s) = table.force(0.002);
    assert!(
        (f + 1000.0).abs() < 1e-9 && (s + 1e6).abs() < 1e-6,
        "{f} {s}"
    );
    let (f, s) = table.force(-0.004);
    assert!(
        (f - 7000.0).abs() < 1e-9 && (s + 5e6).abs() < 1e-6,
        "{f} {s}"
    );
}

/// A state whose bodies sit beyond the stops' clearances (the frames far from the car body,
/// the wheelsets far from their frames) and away from every kink.
fn beyond(v: &Vehicle) -> Vec<f64> {
    let n = v.dofs();
    let mut x: Vec<f64> = (0..v.states())
        .map(|i| 1e-3 * (0.3 + 0.37 * ((i * 7) % 11) as f64) * if i % 3 == 0 { -1.0 } else { 1.0 })
        .collect();
    for (k, b) in v.bodies.iter().enumerate() {
        x[b.dof] = match b.kind {
            critspeed::model::BodyKind::Wheelset => 0.0063 * if k % 2 == 0 { 1.0 } else { -1.0 },
            critspeed::model::BodyKind::Frame => 0.0011 * if k % 2 == 0 { -1.0 } else { 1.0 },
            critspeed::model::BodyKind::CarBody => -0.0023,
        };
    }
    // every stop is engaged and no switching function is near zero
    let q = &x[..n];
    for s in &v.stops {
        let d = s.deflection(q);
        assert!(d.abs() > s.clearance, "{}: Δ = {d}", s.name);
        for k in 0..s.switches() {
            assert!(
                s.switch(k, d).abs() > 2e-4,
                "{} switch {k} at Δ = {d}",
                s.name
            );
        }
    }
    x
}

/// (1) f(−x) = −f(x) beyond the clearance; the exact Jacobian equals central differences; the
/// variational product J Φ and the tangent J ξ equal the dense Jacobian's.
#[test]
fn the_car_with_stops_is_odd_and_its_jacobian_is_exact() {
    let v = build(true, true, CreepLaw::Shen { friction: 0.3 });
    assert_eq!(v.states(), 28);
    assert_eq!(v.stops.len(), 6, "four primary stops and two secondary");
    // flange none: 2 per linear stop, 4 per table stop
    assert_eq!(v.switches(), 4 * 4 + 2 * 2);
    let n = v.states();
    let x = beyond(&v);
    let speed = 55.0;
    let (mut f, mut jac) = (vec![0.0; n], vec![0.0; n * n]);
    v.rhs_jacobian_into(&x, speed, &mut f, &mut jac);
    let mut f2 = vec![0.0; n];
    v.rhs_into(&x, speed, &mut f2);
    assert_eq!(f, f2);
    let worst = common::assert_jacobian_is_central_differences(&v, &x, speed, &jac, (1e-8, 1e-5));
    eprintln!("Jacobian vs central differences: worst relative {worst:.1e}");
    // the stops act: the Jacobian differs from the one without them
    let plain = build(true, false, CreepLaw::Shen { friction: 0.3 });
    let mut jac0 = vec![0.0; n * n];
    plain.jacobian_into(&x, speed, &mut jac0);
    let changed = jac.iter().zip(&jac0).filter(|(a, b)| a != b).count();
    assert!(changed >= 12, "{changed} entries changed by the stops");
    // J Φ from the sparse lower block, and J ξ
    common::assert_variational_is_the_dense_product::<28>(&v, &x, speed, &jac, &f);
    common::assert_odd(&v, &x, speed, &f);
    // the secondary stops' deflection is the secondary lateral spring's: frame to car body
    // with the lever arms (x_b ψ_c of the car body, its secondary height under roll)
    let sec = v
        .stops
        .iter()
        .find(|s| s.name == "secondary bump stop, frame 1")
        .expect("secondary stop");
    let frame = &v.bodies[4];
    let body = &v.bodies[6];
    let lb = REFERENCE_CAR_BODY.half_bogie_distance;
    let row = |j: usize| sec.row.iter().find(|r| r.0 == j).map_or(0.0, |r| r.1);
    assert_eq!(row(frame.dof), 1.0);
    assert_eq!(row(body.dof), -1.0);
    assert_eq!(row(body.dof + 1), -lb);
}

fn v_l<const N: usize>(v: &Vehicle) -> f64 {
    let opts = LinearOptions {
        speed_range: (1.0, 300.0),
        ..LinearOptions::default()
    };
    let sys = LinearSystem::<N>::at_centre(v);
    let found = critical_speeds(&sys, v.creep_law(), &opts).expect("search runs");
    found.critical().expect("an onset").speed_m_s
}

/// (2) Inside the clearance the stops give nothing: V_L of the bogie with stops is V_L without
/// them, and the linear report says that the analysis is the centred motion.
#[test]
fn the_linear_analysis_is_the_centred_motion_and_says_so() {
    let with = build(false, true, CreepLaw::Kalker);
    let without = build(false, false, CreepLaw::Kalker);
    let (a, b) = (v_l::<12>(&with), v_l::<12>(&without));
    eprintln!("bogie V_L with stops {a} m/s, without {b} m/s");
    assert!((a - b).abs() <= 1e-12 * b, "{a} vs {b}");
    let notes = critspeed::analysis::linearisation_notes(&with);
    assert_eq!(notes.len(), 2, "{notes:?}");
    assert!(
        notes.iter().any(|n| n.contains("secondary bump stops")
            && n.contains("centred motion inside the ±3 mm clearance")),
        "{notes:?}"
    );
    assert!(notes.iter().any(|n| n.contains("±1 mm")), "{notes:?}");
    assert!(critspeed::analysis::linearisation_notes(&without).is_empty());
}

/// (3) A simulation of the bogie released far beyond the secondary stop's clearance at a speed
/// below V_L: the integrator's steps end on the stops' switching surfaces (each crossing is
/// located: at a step end the switching value is zero to 1e-12 m, and no step begins and ends
/// strictly on opposite sides); the motion decays inside the clearance.
#[test]
fn a_simulation_lands_on_the_stops_switching_surfaces() {
    use critspeed::system::ode::{integrate_observed, step_times};
    let v = build(false, true, CreepLaw::Kalker);
    let n = v.dofs();
    let mut x0 = SVector::<f64, 12>::zeros();
    let frame = v.bodies[2].dof;
    x0[frame] = 0.008;
    x0[0] = 0.004;
    x0[v.bodies[1].dof] = 0.004;
    let ode = OdeOptions {
        tol: Tolerances::new(1e-10, 1e-13).expect("tolerances"),
        ..OdeOptions::default()
    };
    let speed = 20.0;
    let t_end = 3.0;
    let times = step_times(&v, speed, &x0, t_end, &ode).expect("steps");
    let mut states = vec![(0.0, x0)];
    let sol = integrate_observed(&v, speed, &x0, t_end, &ode, &times, &mut |t, x| {
        states.push((t, *x))
    })
    .expect("simulation");
    assert!(sol.stats.events >= 2, "{:?}", sol.stats);
    let m = v.switches();
    let (mut landed, mut worst) = (0, 0.0_f64);
    for w in states.windows(2) {
        let (a, b) = (&w[0].1, &w[1].1);
        for k in 0..m {
            let (ga, gb) = (v.switch(k, a.as_slice()), v.switch(k, b.as_slice()));
            assert!(
                !(ga > 1e-12 && gb < -1e-12 || ga < -1e-12 && gb > 1e-12),
                "switch {k} crossed inside the step to t = {}: {ga} -> {gb}",
                w[1].0
            );
            if gb.abs() <= 1e-12 {
                landed += 1;
                worst = worst.max(gb.abs());
            }
        }
    }
    eprintln!(
        "{} events located, {landed} step ends on a surface (worst |g| {worst:.1e} m)",
        sol.stats.events
    );
    assert!(landed >= 2, "{landed} step ends on a switching surface");
    // the stop pushed the frame back: it ends inside the clearance, at rest
    let stop = &v
        .stops
        .iter()
        .find(|s| s.name.starts_with("secondary"))
        .expect("stop");
    let end = stop.deflection(&sol.x.as_slice()[..n]);
    assert!(
        end.abs() < stop.clearance,
        "frame at {end} m after {t_end} s"
    );
    let peak = states
        .iter()
        .map(|(_, x)| stop.deflection(&x.as_slice()[..n]).abs())
        .fold(0.0, f64::max);
    assert!(peak <= 0.008 + 1e-9, "the frame went out to {peak} m");
}

/// (2, 5) Through the CLI: the keys reach the model (V_L unchanged, the note in the JSON), and
/// bad values exit 2 naming the key.
#[test]
fn the_keys_reach_the_model_and_bad_values_are_refused() {
    let dir = common::scratch("bump-stop-keys");
    let run = |section: &str, lines: &str| {
        let study = common::dtu_bogie_with(&dir, section, lines);
        common::critspeed(&["linear", study.to_str().expect("utf-8"), "--json"], &dir)
    };
    let speed = |out: &std::process::Output| {
        let json: serde_json::Value = serde_json::from_slice(&out.stdout).expect("json");
        let v = json["kalker"]["critical_speed_m_s"]
            .as_f64()
            .expect("speed");
        (v, json["notes"].clone())
    };
    let plain = run("secondary", "");
    assert_eq!(plain.status.code(), Some(0), "{plain:?}");
    let (v0, _) = speed(&plain);
    let stop = run(
        "secondary",
        "bump_stop_clearance = \"3 mm\"\nbump_stop_stiffness = \"2 MN/m\"",
    );
    assert_eq!(stop.status.code(), Some(0), "{stop:?}");
    let (v1, notes) = speed(&stop);
    assert!((v1 - v0).abs() <= 1e-12 * v0, "{v1} vs {v0}");
    assert!(
        notes.to_string().contains("inside the ±3 mm clearance"),
        "{notes}"
    );
    let bad = [
        ("secondary", "bump_stop_clearance = 0\nbump_stop_stiffness = 1e6", "secondary.bump_stop_clearance"),
        ("secondary", "bump_stop_clearance = \"3 mm\"\nbump_stop_stiffness = \"-1 MN/m\"", "secondary.bump_stop_stiffness"),
        ("secondary", "bump_stop_clearance = \"3 mm\"", "secondary.bump_stop_stiffness"),
        ("suspension", "bump_stop_stiffness = \"1 MN/m\"", "suspension.bump_stop_clearance"),
        (
            "suspension",
            "bump_stop_clearance = \"2 mm\"\nbump_stop_force_table = { points = [[\"1 mm\", \"5 kN\"], [\"2 mm\", \"4 kN\"]] }",
            "suspension.bump_stop_force_table.points",
        ),
        (
            "suspension",
            "bump_stop_clearance = \"2 mm\"\nbump_stop_force_table = { points = [[0, \"1 kN\"], [\"2 mm\", \"4 kN\"]] }",
            "suspension.bump_stop_force_table.points",
        ),
    ];
    for (section, lines, key) in bad {
        let out = run(section, lines);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{lines}: {err}");
        assert!(err.contains(key), "{lines}: {err}");
    }
    // the wheelset layout: a primary stop beyond the geometry's lateral range is refused
    let root = common::root();
    let seed = std::fs::read_to_string(root.join("studies/seed.toml")).expect("seed study");
    let text = seed.replace(
        "[suspension]",
        "[suspension]\nbump_stop_clearance = \"50 mm\"\nbump_stop_stiffness = \"5 MN/m\"",
    );
    let path = dir.join("seed.toml");
    std::fs::write(&path, text).expect("write");
    let out = common::critspeed(&["linear", path.to_str().expect("utf-8")], &dir);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(
        err.contains("suspension.bump_stop_clearance") && err.contains("lateral range"),
        "{err}"
    );
}

/// The frame's lateral amplitude (m) of a cycle of the DTU bogie (its third body).
fn frame_amplitude(c: &critspeed::bifurcation::CycleRow) -> f64 {
    c.body_amplitudes.get(2).map_or(f64::NAN, |b| b.0)
}

/// studies/flange-hysteresis.toml as it is (`stop` false), or with its flange replaced by a
/// primary bump stop of the same clearance and stiffness (on the wheelset layout the stop's
/// deflection is the wheelset's y, so the stop is the flange's law exactly, docs/model.md §6).
fn hysteresis(stop: bool, key_value: Option<f64>) -> critspeed::api::Source {
    let studies = common::root().join("studies");
    let text = std::fs::read_to_string(studies.join("flange-hysteresis.toml")).expect("study");
    let mut table: toml::Table = toml::from_str(&text).expect("toml");
    let section = |t: &mut toml::Table, name: &str| -> toml::Table {
        t.get(name)
            .and_then(|v| v.as_table())
            .cloned()
            .expect("section")
    };
    if stop {
        table.remove("flange");
        let mut s = section(&mut table, "suspension");
        s.insert("bump_stop_clearance".into(), toml::Value::Float(0.003));
        s.insert("bump_stop_stiffness".into(), toml::Value::Float(18.23e6));
        table.insert("suspension".into(), toml::Value::Table(s));
    }
    if let Some(k) = key_value {
        table.remove("curve");
        let mut s = section(&mut table, "suspension");
        s.insert("lateral_stiffness".into(), toml::Value::Float(k));
        table.insert("suspension".into(), toml::Value::Table(s));
    }
    critspeed::api::Source {
        text: toml::to_string(&table).expect("toml"),
        origin: format!("flange-hysteresis (stop {stop}, key {key_value:?})"),
        folder: Some(studies),
    }
}

/// The located folds (speed, amplitude) of a whole diagram.
fn folds(source: &critspeed::api::Source) -> Vec<(f64, f64)> {
    use critspeed::api::{self, Prepared};
    let prepared = Prepared::new(source.plan().expect("plan")).expect("model");
    let d = api::bifurcation(&prepared, Default::default()).expect("diagram");
    d.special
        .iter()
        .filter(|s| s.kind == critspeed::continuation::SpecialKind::Fold && s.located)
        .map(|s| (s.speed_m_s, s.amplitude_y_m))
        .collect()
}

/// A primary bump stop on the single wheelset with the flange's clearance and stiffness is the
/// flange: the flange-hysteresis wheelset's whole diagram has the same two folds (3.2 and 4.2
/// mm, cycles across the stop's edge), and the fold curves over the lateral stiffness (as
/// tests/curve.rs's flange_fold_curves_equal_whole_diagrams) are the flange's, point by
/// point; at two points of each stop fold curve the whole diagram of the rewritten study has
/// the same fold (1e-6 in speed, 1e-4 in amplitude).
#[test]
fn a_primary_stop_on_the_wheelset_is_the_flange_and_its_fold_curves_equal_diagrams() {
    use critspeed::api::curve::{curve, curve_study};
    use critspeed::curve::CurveKind;
    let (flange, stop) = (
        folds(&hysteresis(false, None)),
        folds(&hysteresis(true, None)),
    );
    eprintln!("folds with the flange {flange:?}, with the stop {stop:?}");
    assert_eq!(flange.len(), stop.len());
    assert!(stop.len() >= 2, "{stop:?}");
    for (a, b) in flange.iter().zip(&stop) {
        assert!((a.0 - b.0).abs() <= 1e-8 * a.0, "{a:?} vs {b:?}");
        assert!((a.1 - b.1).abs() <= 1e-6 * a.1, "{a:?} vs {b:?}");
    }
    let t = std::time::Instant::now();
    let curves = |stop: bool| {
        let study = curve_study(&hysteresis(stop, None)).expect("curve study");
        let r = curve(&study, None).expect("curves");
        let folds: Vec<_> = r
            .curves
            .into_iter()
            .filter(|c| c.kind == CurveKind::Fold)
            .collect();
        folds
    };
    let (fc, sc) = (curves(false), curves(true));
    eprintln!("fold curves in {:?}", t.elapsed());
    assert_eq!(fc.len(), 2, "the flange loop's two folds");
    assert_eq!(sc.len(), fc.len(), "the stop's fold curves");
    let mut worst = 0.0_f64;
    for (f, s) in fc.iter().zip(&sc) {
        for p in &s.points {
            // the flange curve's speed at this parameter, interpolated between its points
            let q = &f.points;
            let i = q
                .windows(2)
                .position(|w| {
                    let (lo, hi) = (
                        w[0].parameter.min(w[1].parameter),
                        w[0].parameter.max(w[1].parameter),
                    );
                    p.parameter >= lo && p.parameter <= hi
                })
                .expect("inside the flange curve's range");
            let (a, b) = (&q[i], &q[i + 1]);
            let u = if b.parameter == a.parameter {
                0.0
            } else {
                (p.parameter - a.parameter) / (b.parameter - a.parameter)
            };
            let v = a.speed_m_s + u * (b.speed_m_s - a.speed_m_s);
            let rel = (v - p.speed_m_s).abs() / v;
            worst = worst.max(rel);
            assert!(
                rel <= 1e-4,
                "{} at {}: {} vs flange {v}",
                s.label,
                p.parameter,
                p.speed_m_s
            );
        }
        for k in [s.points.len() / 3, 2 * s.points.len() / 3] {
            let p = &s.points[k];
            let d = folds(&hysteresis(true, Some(p.parameter)));
            let nearest = d
                .iter()
                .min_by(|x, y| {
                    (x.0 - p.speed_m_s)
                        .abs()
                        .total_cmp(&(y.0 - p.speed_m_s).abs())
                })
                .expect("a located fold");
            let (dv, da) = (
                (nearest.0 - p.speed_m_s).abs() / p.speed_m_s,
                (nearest.1 - p.amplitude_m).abs() / p.amplitude_m,
            );
            eprintln!(
                "{} at {} N/m: curve {} m/s, {} m; diagram {nearest:?} ({dv:.1e}, {da:.1e})",
                s.label, p.parameter, p.speed_m_s, p.amplitude_m
            );
            assert!(dv <= 1e-6 && da <= 1e-4, "{dv:.1e} {da:.1e}");
        }
    }
    eprintln!("stop fold curves vs the flange's (interpolated): worst {worst:.1e}");
}

/// (4) The DTU bogie (studies/dtu-cooperrider-bogie.toml) with a secondary stop of 2 mm at
/// 20 MN/m, frame to the track-fixed car body: the large cycles' frame amplitude (2.5 mm
/// without the stop) reaches it. The stop changes the diagram: V_NL moves from the no-stop
/// diagram's (the large stable cycles near 124 m/s become unstable) by more than 10 %, and V_L
/// does not move. A stable cycle that presses on the stop (frame amplitude beyond the
/// clearance by 0.1 mm or more, largest multiplier below 0.9) is the attractor of a long
/// simulation: from its start state moved by 0.1 mm, 56 + 4 s settle on it, and the leading
/// wheelset's amplitude over the last 4 s (sampled every 10 µs) equals the cycle's to 1e-6
/// relative, with the frame beyond the clearance.
#[test]
fn a_stop_cycle_of_the_dtu_bogie_is_the_attractor_of_a_long_simulation() {
    use critspeed::bifurcation::analyse;
    let dir = common::scratch("bump-stop-cycle");
    let diagram = |lines: &str| {
        let path = common::dtu_bogie_with(&dir, "secondary", lines);
        let plan = critspeed::study::load(&path).expect("study");
        let model = plan.model().expect("model");
        let report = analyse(&plan.name, &model, &plan.bifurcation_options()).expect("analysis");
        (model, report)
    };
    let (_, plain) = diagram("");
    let (model, stop) =
        diagram("bump_stop_clearance = \"2 mm\"\nbump_stop_stiffness = \"20 MN/m\"");
    assert_eq!((model.states(), model.stops.len()), (12, 1));
    let clearance = model.stops[0].clearance;
    let vnl = |r: &critspeed::bifurcation::BifurcationReport| {
        r.nonlinear_critical_speed.expect("a V_NL").0
    };
    let vl =
        |r: &critspeed::bifurcation::BifurcationReport| r.kalker_critical_speed_m_s.expect("a V_L");
    let frame_max = |r: &critspeed::bifurcation::BifurcationReport| {
        r.cycles.iter().map(frame_amplitude).fold(0.0, f64::max)
    };
    eprintln!(
        "V_L {} / {} m/s, V_NL without the stop {} m/s, with it {} m/s; largest frame amplitude {} / {} m",
        vl(&plain),
        vl(&stop),
        vnl(&plain),
        vnl(&stop),
        frame_max(&plain),
        frame_max(&stop)
    );
    assert!((vl(&plain) - vl(&stop)).abs() <= 1e-9 * vl(&plain));
    assert!(
        frame_max(&plain) > clearance,
        "the cycles never reach the stop"
    );
    assert!((vnl(&stop) - vnl(&plain)).abs() > 0.1 * vnl(&plain));
    let cycle = stop
        .cycles
        .iter()
        .filter(|c| c.stable && c.max_multiplier_abs < 0.9)
        .filter(|c| frame_amplitude(c) > clearance + 1e-4)
        .max_by(|a, b| frame_amplitude(a).total_cmp(&frame_amplitude(b)))
        .expect("a stable cycle on the stop");
    let ode = OdeOptions {
        tol: Tolerances::new(1e-10, 1e-13).expect("tolerances"),
        ..OdeOptions::default()
    };
    let mut x0 = cycle.x0.clone();
    x0[0] += 1e-4;
    let settle = critspeed::simulate::simulate(&model, cycle.speed_m_s, &x0, 56.0, 0.1, &ode)
        .expect("simulation");
    let last = settle.x.last().expect("samples").clone();
    let h = critspeed::simulate::simulate(&model, cycle.speed_m_s, &last, 4.0, 1e-5, &ode)
        .expect("simulation");
    let amplitude = h.x.iter().map(|x| x[0].abs()).fold(0.0, f64::max);
    let rel = (amplitude - cycle.amplitude_y_m).abs() / cycle.amplitude_y_m;
    let n = model.dofs();
    let frame_peak =
        h.x.iter()
            .map(|x| model.stops[0].deflection(&x[..n]).abs())
            .fold(0.0, f64::max);
    eprintln!(
        "{} m/s (largest multiplier {:.3}): simulated {amplitude} m vs continued {} m ({rel:.1e}); frame {frame_peak} m vs continued {} m",
        cycle.speed_m_s,
        cycle.max_multiplier_abs,
        cycle.amplitude_y_m,
        frame_amplitude(cycle)
    );
    assert!(rel < 1e-6, "{rel:.1e}");
    assert!(
        frame_peak > clearance,
        "the frame never reaches the stop: {frame_peak} m"
    );
}
