//! Per-wheelset contact geometry (`[[contact.wheelset]]`, docs/model.md §11): each wheelset's
//! rows of f use its own table, the odd symmetry and the exact Jacobian survive, the same
//! geometry everywhere is the study without the array bit for bit, and bad entries exit 2.

mod common;
use common::{critspeed, root, scratch};

use critspeed::contact::creep::CreepLaw;
use critspeed::contact::geometry::Geometry;
use critspeed::contact::table::ContactTable;
use critspeed::model::Vehicle;
use critspeed::stability::{critical_speeds, LinearSystem};
use critspeed::study::Plan;
use critspeed::system::ode::VectorField;
use nalgebra::{SMatrix, SVector};

fn study_text(name: &str) -> String {
    std::fs::read_to_string(root().join("studies").join(name)).expect("study")
}

fn plan_of(text: &str) -> Plan {
    critspeed::study::parse_in(text, "test.toml", Some(&root().join("studies"))).expect("plan")
}

/// The DTU bogie with a cone of slope `lambda` and given creep coefficients as `[contact]`.
fn cone_bogie(lambda: f64) -> String {
    let text = study_text("dtu-cooperrider-bogie.toml");
    let (head, rest) = text.split_once("[contact]").expect("[contact]");
    let (_, tail) = rest.split_once("[linear]").expect("[linear]");
    format!(
        "{head}[contact]\ngeometry = \"cone\"\nconicity = {lambda}\ncreep_law = \"shen\"\n\
         friction = 0.15\nspin = true\n\n[contact.creep_coefficients]\nf11 = \"8.06e6 N\"\n\
         f22 = \"8.09e6 N\"\nf23 = \"2.2e7 N mm\"\nf33 = \"1.27e7 N mm^2\"\n\n[linear]{tail}"
    )
}

/// The cone bogie whose trailing wheelset (position 2) has slope `trailing`.
fn two_cones(leading: f64, trailing: f64) -> Plan {
    plan_of(&format!(
        "{}\n[[contact.wheelset]]\npositions = [2]\nconicity = {trailing}\n",
        cone_bogie(leading)
    ))
}

/// A deterministic pseudo-random number in [−1, 1).
fn uniform(seed: &mut u64) -> f64 {
    *seed = seed
        .wrapping_mul(6364136223846793005)
        .wrapping_add(1442695040888963407);
    ((*seed >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
}

/// A state of small displacements (mm, mrad) and rates.
fn random_state(model: &Vehicle, seed: &mut u64) -> Vec<f64> {
    (0..model.states()).map(|_| 4e-3 * uniform(seed)).collect()
}

fn rhs(model: &Vehicle, x: &[f64], v: f64) -> Vec<f64> {
    let mut out = vec![0.0; model.states()];
    model.rhs_into(x, v, &mut out);
    out
}

/// The Kalker-creep linear critical speed (m/s).
fn v_l(plan: &Plan, model: &Vehicle) -> f64 {
    let kalker = model.with_law(CreepLaw::Kalker);
    let found = critspeed::with_states!(model.states(), N => {
        critical_speeds(&LinearSystem::<N>::at_centre(&kalker), CreepLaw::Kalker, &plan.linear)
    }, _ => panic!("{} states", model.states()));
    found
        .expect("linear scan")
        .critical()
        .expect("a crossing")
        .speed_m_s
}

#[test]
fn the_same_geometry_at_every_position_is_the_study_without_the_array_bit_for_bit() {
    for (file, positions) in [
        ("dtu-cooperrider-bogie.toml", "[1, 2]"),
        ("dtu-cooperrider-car.toml", "[1, 2, 3, 4]"),
    ] {
        let text = study_text(file);
        let plain = plan_of(&text);
        let own = plan_of(&format!(
            "{text}\n[[contact.wheelset]]\npositions = {positions}\n\
             geometry_table = \"tables/dtu-rsgeo-1o40.csv\"\n"
        ));
        let (a, b) = (plain.model().expect("model"), own.model().expect("model"));
        assert!(b.wheelset_tables().iter().all(Option::is_some));
        let mut seed = 7;
        for _ in 0..20 {
            let x = random_state(&a, &mut seed);
            let (fa, fb) = (rhs(&a, &x, 40.0), rhs(&b, &x, 40.0));
            assert!(fa.iter().zip(&fb).all(|(p, q)| p.to_bits() == q.to_bits()));
        }
        if file.contains("bogie") {
            let (va, vb) = (v_l(&plain, &a), v_l(&own, &b));
            println!("{file}: V_L {va} m/s without the array, {vb} m/s with it");
            assert_eq!(va.to_bits(), vb.to_bits());
        }
    }
}

#[test]
fn two_cones_keep_the_odd_symmetry_and_the_exact_jacobian_and_each_row_uses_its_own_table() {
    let (la, lb) = (0.15, 0.3);
    let plan = two_cones(la, lb);
    let model = plan.model().expect("model");
    let uniform_model = plan_of(&cone_bogie(la)).model().expect("model");
    let c = model.wheelset_conicities();
    assert!(
        (c[0] - la).abs() < 1e-12 && (c[1] - lb).abs() < 1e-12,
        "{c:?}"
    );
    assert!(model.conicities_differ());
    let n = model.states();
    assert_eq!(n, 12);
    let dofs = model.dofs();
    let trailing = Wheelset2::new(&model, lb, &plan);
    let mut seed = 11;
    let mut worst = [0.0f64; 4];
    for _ in 0..30 {
        let x = random_state(&model, &mut seed);
        let v = 20.0 + 40.0 * (uniform(&mut seed) + 1.0);
        // f(−x) = −f(x)
        let f = rhs(&model, &x, v);
        let neg: Vec<f64> = x.iter().map(|e| -e).collect();
        let fm = rhs(&model, &neg, v);
        let scale = f.iter().fold(0.0f64, |m, e| m.max(e.abs()));
        for (p, q) in f.iter().zip(&fm) {
            worst[0] = worst[0].max((p + q).abs() / scale);
        }
        // the exact Jacobian against central differences (column-major)
        let mut jac = vec![0.0; n * n];
        model.jacobian_into(&x, v, &mut jac);
        for col in 0..n {
            let h = 1e-7;
            let (mut xp, mut xm) = (x.clone(), x.clone());
            xp[col] += h;
            xm[col] -= h;
            let (fp, fq) = (rhs(&model, &xp, v), rhs(&model, &xm, v));
            for row in 0..n {
                let fd = (fp[row] - fq[row]) / (2.0 * h);
                let exact = jac[col * n + row];
                worst[1] = worst[1].max((fd - exact).abs() / (1.0 + exact.abs()));
            }
        }
        // the tangent and variational products use the same tables: J ξ and J Φ
        let xi = random_state(&model, &mut seed);
        let (mut ft, mut d) = (vec![0.0; n], vec![0.0; n]);
        model.rhs_tangent_into(&x, v, &xi, &mut ft, &mut d);
        let xs = SVector::<f64, 12>::from_column_slice(&x);
        let j = SMatrix::<f64, 12, 12>::from_column_slice(&jac);
        let jxi = j * SVector::<f64, 12>::from_column_slice(&xi);
        let phi = SMatrix::<f64, 12, 12>::from_fn(|r, c| (r as f64 - c as f64).sin());
        let (fv, jphi) = VectorField::<12>::rhs_variational(&model, &xs, v, &phi);
        let jscale = j.amax().max(1.0);
        for i in 0..n {
            worst[3] = worst[3].max((d[i] - jxi[i]).abs() / jscale);
            worst[3] = worst[3].max((ft[i] - f[i]).abs() / scale);
            worst[3] = worst[3].max((fv[i] - f[i]).abs() / scale);
        }
        worst[3] = worst[3].max((jphi - j * phi).amax() / (jscale * n as f64));
        // only the trailing wheelset's rows differ from the uniform bogie's, by its own
        // table's contact forces less the common one's
        let fu = rhs(&uniform_model, &x, v);
        let w = model.wheelset_dofs()[1];
        for (i, (p, q)) in f.iter().zip(&fu).enumerate() {
            if i != dofs + w && i != dofs + w + 1 {
                assert_eq!(p.to_bits(), q.to_bits(), "row {i}");
            }
        }
        let xw = [x[w], x[w + 1], x[dofs + w], x[dofs + w + 1]];
        let own = trailing.own.contact_forces(&xw, v);
        let common = model.contact.contact_forces(&xw, v);
        let m = model.generalised_mass(w);
        let iz = model.generalised_mass(w + 1);
        let dy = (f[dofs + w] - fu[dofs + w]) * m;
        let dpsi = (f[dofs + w + 1] - fu[dofs + w + 1]) * iz;
        worst[2] = worst[2].max((dy - (own.0 - common.0)).abs() / (1.0 + own.0.abs()));
        worst[2] = worst[2].max((dpsi - (own.1 - common.1)).abs() / (1.0 + own.1.abs()));
        let direct = model.wheelset_forces(1, &xw, v);
        assert_eq!(direct.0.to_bits(), own.0.to_bits());
        assert_eq!(direct.1.to_bits(), own.1.to_bits());
        let guiding = model.guiding_forces(&x, v);
        assert_eq!(guiding[1].to_bits(), own.0.to_bits());
    }
    println!(
        "odd symmetry {:.2e}, Jacobian vs central differences {:.2e}, trailing rows {:.2e}, \
         tangent/variational {:.2e}",
        worst[0], worst[1], worst[2], worst[3]
    );
    assert!(worst[0] < 1e-14, "f(-x) + f(x): {:e}", worst[0]);
    assert!(worst[1] < 1e-5, "Jacobian: {:e}", worst[1]);
    assert!(worst[2] < 1e-9, "trailing rows: {:e}", worst[2]);
    assert!(
        worst[3] < 1e-13,
        "tangent and variational products: {:e}",
        worst[3]
    );
}

/// The single wheelset of the cone bogie with the trailing wheelset's own table.
struct Wheelset2 {
    own: critspeed::model::Wheelset,
}

impl Wheelset2 {
    fn new(model: &Vehicle, lambda: f64, plan: &Plan) -> Self {
        let table = ContactTable::build(&Geometry::Cone { conicity: lambda }, &plan.table_spec())
            .expect("table");
        Self {
            own: critspeed::model::Wheelset {
                table,
                ..model.contact.clone()
            },
        }
    }
}

#[test]
fn the_critical_speed_tends_to_the_uniform_bogies_as_the_trailing_conicity_tends_to_the_leading() {
    let la = 0.15;
    let base = plan_of(&cone_bogie(la));
    let v0 = v_l(&base, &base.model().expect("model"));
    let mut gaps = Vec::new();
    for eps in [1e-2, 1e-3, 1e-4] {
        let plan = two_cones(la, la + eps);
        gaps.push((v_l(&plan, &plan.model().expect("model")) - v0).abs());
    }
    let swapped = two_cones(0.3, la);
    let forward = two_cones(la, 0.3);
    println!(
        "V_L uniform {v0:.6} m/s; gaps at eps 1e-2, 1e-3, 1e-4: {gaps:?}; \
         (0.15, 0.3): {:.4} m/s, (0.3, 0.15): {:.4} m/s",
        v_l(&forward, &forward.model().expect("model")),
        v_l(&swapped, &swapped.model().expect("model"))
    );
    assert!(
        gaps[1] < gaps[0] / 5.0 && gaps[2] < gaps[1] / 5.0,
        "{gaps:?}"
    );
    assert!(gaps[2] < 1e-3 * v0, "{gaps:?}");
}

#[test]
fn bad_entries_exit_2_naming_the_key() {
    let dir = scratch("bad");
    let text = study_text("dtu-cooperrider-bogie.toml");
    let tables = dir.join("tables");
    std::fs::create_dir_all(&tables).expect("dir");
    std::fs::copy(
        root().join("studies/tables/dtu-rsgeo-1o40.csv"),
        tables.join("dtu-rsgeo-1o40.csv"),
    )
    .expect("copy");
    let table = "geometry_table = \"tables/dtu-rsgeo-1o40.csv\"";
    for (entry, expected) in [
        (
            format!("positions = [3]\n{table}"),
            "contact.wheelset[0].positions = 3",
        ),
        (
            format!("positions = [0]\n{table}"),
            "contact.wheelset[0].positions = 0",
        ),
        (
            format!("positions = [1]\n{table}\n[[contact.wheelset]]\npositions = [2, 1]\n{table}"),
            "contact.wheelset[1].positions = 1: wheelset 1 is already given",
        ),
        ("positions = [1]".into(), "contact.wheelset[0] = positions"),
        (
            format!("positions = []\n{table}"),
            "contact.wheelset[0].positions",
        ),
        (
            "positions = [1]\ngeometry_table = \"tables/missing.csv\"".into(),
            "contact.wheelset[0].geometry_table",
        ),
        (
            "positions = [2]\nconicity = 0.3".into(),
            "contact.wheelset[0].conicity",
        ),
        (
            "positions = [2]\ngeometry = \"cone\"\nconicity = 0.3".into(),
            "contact.creep_coefficients",
        ),
        (
            "positions = [2]\ngeometry = \"ellipse\"".into(),
            "contact.wheelset[0].geometry = \"ellipse\"",
        ),
    ] {
        let study = dir.join("bad.toml");
        std::fs::write(&study, format!("{text}\n[[contact.wheelset]]\n{entry}\n")).expect("write");
        let out = critspeed(&["check", study.to_str().expect("utf-8")], &dir);
        let err = String::from_utf8_lossy(&out.stderr).into_owned();
        assert_eq!(out.status.code(), Some(2), "{entry}: {err}");
        assert!(err.contains(expected), "{entry}: {err}");
    }
}

#[test]
fn a_sweep_over_a_contact_key_rebuilds_the_tables_and_a_wheelsets_own_key_stays() {
    use critspeed::sweep::{Spares, SweepStudy};
    let text = format!(
        "{}\n[[contact.wheelset]]\npositions = [2]\nconicity = 0.3\n\n[sweep]\naxes = [ \
         {{ key = \"contact.conicity\", from = 0.1, to = 0.2, count = 2 }}, \
         {{ key = \"contact.friction\", from = 0.1, to = 0.2, count = 2 }} ]\n",
        cone_bogie(0.15)
    );
    let s =
        SweepStudy::parse_in(&text, "sweep.toml", Some(&root().join("studies"))).expect("sweep");
    let spares = Spares::default();
    for (values, leading) in [([0.1, 0.1], 0.1), ([0.2, 0.2], 0.2), ([0.15, 0.2], 0.15)] {
        let plan = s.plan_with(&values).expect("plan");
        // the base study's tables are reused only where no geometry changed
        assert_eq!(s.reuses_table(&plan), leading == 0.15, "{values:?}");
        let model = s.model(&plan, &spares).expect("model");
        let c = model.wheelset_conicities();
        assert!(
            (c[0] - leading).abs() < 1e-12 && (c[1] - 0.3).abs() < 1e-12,
            "{values:?}: {c:?}"
        );
        let fresh = plan.model().expect("model");
        let mut seed = 3;
        let x = random_state(&model, &mut seed);
        let (a, b) = (rhs(&model, &x, 50.0), rhs(&fresh, &x, 50.0));
        assert!(
            a.iter().zip(&b).all(|(p, q)| p.to_bits() == q.to_bits()),
            "{values:?}"
        );
    }
}
