//! `geometry = "table"` (docs/model.md §3, method 3): the interpolation (data reproduced at the nodes,
//! cubics exactly), the track symmetry, the exact Jacobian, a cone written as a table giving the
//! closed-form cone's critical speeds, and the DTU table's conversion. The reader's units and
//! errors are in `tests/table_reader.rs`.

use critspeed::contact::creep::CreepLaw;
use critspeed::contact::geometry::Geometry;
use critspeed::contact::tabulated::TabulatedGeometry;
use critspeed::stability::{critical_speeds, LinearOptions, LinearSystem};
use critspeed::study;
use critspeed::system::scalar::Dual;

mod common;
use common::{grid, reference, root, table_text};

#[test]
fn a_missing_file_names_the_path_and_the_key() {
    let text = study_text("geometry = \"table\"\ngeometry_table = \"no/such/file.csv\"");
    let e = study::parse(&text, "s.toml")
        .map(|_| ())
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("contact.geometry_table") && e.contains("no/such/file.csv"),
        "{e}"
    );
}

/// Cubic columns on an irregular grid: the splines reproduce them exactly everywhere.
#[test]
fn cubics_are_reproduced_exactly_between_irregular_nodes() {
    let ys: Vec<f64> = (0..17)
        .map(|i| -0.008 + 0.001 * i as f64 + 1e-4 * ((i * 7) % 5) as f64)
        .collect();
    let r = |y: f64| 0.46 + 0.05 * y + 3.0 * y * y - 900.0 * y * y * y;
    let dr = |y: f64| 0.05 + 6.0 * y - 2700.0 * y * y;
    let d = |y: f64| 0.04 + 2.0 * y + 40.0 * y * y + 5e3 * y * y * y;
    let dd = |y: f64| 2.0 + 80.0 * y + 1.5e4 * y * y;
    let text = table_text("y_m,r_m,delta_rad,roll_rad", &ys, |y| {
        vec![y, r(y), d(y), 0.1 * y]
    });
    let t = TabulatedGeometry::parse(&text, "cubic.csv", 0.46).expect("valid");
    for k in 0..=50 {
        let y = -0.0079 + 0.0158 * k as f64 / 50.0;
        let p = t.point(y);
        assert!((p.radius.re - r(y)).abs() < 1e-15, "{y}");
        assert!((p.radius.eps[0] - dr(y)).abs() < 1e-12, "{y}");
        assert!((p.angle.re - d(y)).abs() < 1e-14, "{y}");
        assert!((p.angle.eps[0] - dd(y)).abs() < 1e-11, "{y}");
    }
}

fn study_text(contact: &str) -> String {
    format!(
        r#"name = "t"
[wheelset]
mass = "1250 kg"
yaw_inertia = "700 kg m^2"
axle_load = "110000 N"
half_contact_distance = "742.9 mm"
rolling_radius = "460 mm"
[suspension]
lateral_stiffness = "300 N/mm"
longitudinal_stiffness = "850 N/mm"
lateral_damping = "8 N s/mm"
longitudinal_damping = "100 N s/mm"
half_spring_spacing = "900 mm"
[contact]
{contact}
creep_law = "shen"
lateral_range = "10 mm"
table_points = 201
[contact.creep_coefficients]
f11 = "8.06e6 N"
f22 = "8.09e6 N"
f23 = "2.2e4 N m"
f33 = "12.7 N m^2"
[linear]
speed_range = ["1 m/s", "150 m/s"]
"#
    )
}

fn critical(text: &str, law: CreepLaw) -> f64 {
    let plan = study::parse(text, "test").expect("study");
    let model = plan.wheelset_model().expect("model").with_law(law);
    let opts = LinearOptions {
        speed_range: (1.0, 150.0),
        ..LinearOptions::default()
    };
    critical_speeds(&LinearSystem::at_centre(&model), law, &opts)
        .expect("search")
        .critical()
        .expect("a crossing in range")
        .speed_m_s
}

/// The closed-form cone (docs/model.md §3 method 1) written as a table gives the same V_L and V_H.
#[test]
fn a_cone_written_as_a_table_gives_the_cone_critical_speeds() {
    let (lambda, l0, r0) = (0.15, 0.7429, 0.46);
    let ys = grid(41, 0.012);
    let text = table_text("y_m,r_minus_r0_m,delta_rad,roll_rad", &ys, |y| {
        vec![y, lambda * y, lambda + lambda * y / l0, lambda * y / l0]
    });
    let dir = std::env::temp_dir().join(format!("critspeed-cone-table-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let path = dir.join("cone.csv");
    std::fs::write(&path, text).expect("write table");
    let cone = study_text("geometry = \"cone\"\nconicity = 0.15");
    let table = study_text(&format!(
        "geometry = \"table\"\ngeometry_table = {:?}",
        path.display().to_string()
    ));
    let _ = r0;
    for law in [CreepLaw::Kalker, CreepLaw::Shen { friction: 0.3 }] {
        let (a, b) = (critical(&cone, law), critical(&table, law));
        eprintln!(
            "{law:?}: cone {a} m/s, table {b} m/s, relative {:.1e}",
            (a - b) / a
        );
        assert!(
            (a - b).abs() <= 1e-9 * a,
            "{law:?}: cone {a} m/s, table {b} m/s"
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

fn dtu_plan() -> study::Plan {
    study::load(&root().join("studies/dtu-rsgeo-wheelset.toml")).expect("DTU study loads")
}

/// Track symmetry (docs/model.md §3): the left wheel is the right wheel at −y, so f(−x) = −f(x).
#[test]
fn the_tabulated_wheelset_is_odd_symmetric() {
    let model = dtu_plan().wheelset_model().expect("model");
    for x in [
        [1e-3, 2e-4, 0.01, -0.003],
        [-5.5e-3, -1e-3, 0.2, 0.01],
        [7e-3, 0.0, -0.1, 0.02],
    ] {
        let f = model.rhs(&x, 40.0);
        let g = model.rhs(&x.map(|v| -v), 40.0);
        for k in 0..4 {
            assert!(
                (f[k] + g[k]).abs() <= 1e-12 * f[k].abs().max(1e-9),
                "{x:?}: {f:?} vs {g:?}"
            );
        }
    }
    // the right wheel's flange approaches its rail as y grows (docs/model.md §1, §3)
    let t = &model.table;
    let (centre, out) = (t.right(0.0), t.right(0.007));
    assert!(out.radius > centre.radius && out.angle > centre.angle);
    assert!(t.roll(Dual::<1>::var(0.004, 0)).re > 0.0);
}

/// The DTU table sampled on a contact grid whose nodes are the file's rows: the file's values
/// come back to rounding, and the node slopes are the spline's (compared with central
/// differences of the data, which agree to the data's second-difference size).
#[test]
fn the_dtu_table_is_reproduced_at_its_nodes() {
    let plan = dtu_plan();
    let Geometry::Table(t) = &plan.contact.geometry else {
        panic!("the DTU study uses a table geometry");
    };
    let mut spec = plan.table_spec();
    spec.half_width = 0.008;
    spec.nodes = 33; // 0.5 mm spacing, as the file
    let table = critspeed::contact::table::ContactTable::build(&plan.contact.geometry, &spec)
        .expect("table");
    let nodes = t.nodes();
    for row in table.rows() {
        let file = nodes
            .iter()
            .find(|n| (n[0] - row.y).abs() < 1e-9)
            .expect("grid node is a file row");
        // the file's centre row is y = −5.2e-16 m, not 0: allow slope × that offset
        let tol = |slope: f64| 1e-15 + slope.abs() * (row.y - file[0]).abs();
        let checks = [
            (row.point.radius, file[1], 0.1),
            (row.point.angle, file[2], 100.0),
            (row.point.roll, file[3], 1.0),
        ];
        for (got, want, slope) in checks {
            assert!(
                (got - want).abs() < tol(slope),
                "y = {}: {got} vs {want}",
                row.y
            );
        }
    }
}

fn rows(text: &str) -> Vec<Vec<f64>> {
    text.lines()
        .filter(|l| !l.starts_with('#') && !l.trim().is_empty())
        .skip(1)
        .map(|l| {
            l.split(',')
                .map(|s| s.trim().parse().expect("number"))
                .collect()
        })
        .collect()
}

/// `studies/tables/dtu-rsgeo-1o40.csv` is the DTU DYTSI table (source: DYTSI
/// input/RSGEO/1o40/RSGEO.dat, LGPL; subsampled copy in tests/data) converted
/// as its header says: copied columns unchanged, roll from the contact heights, δ = δ_axle + φ.
#[test]
fn the_committed_dtu_table_is_the_documented_conversion() {
    let src = rows(&reference("dtu_rsgeo_1o40_subsampled.csv"));
    let conv = rows(
        &std::fs::read_to_string(root().join("studies/tables/dtu-rsgeo-1o40.csv"))
            .expect("converted table"),
    );
    assert_eq!(src.len(), conv.len());
    let n = src.len();
    for i in 0..n {
        let (s, m, c) = (&src[i], &src[n - 1 - i], &conv[i]);
        // copied: y, r, a, b, C11, C22, C23, N
        for (k, j) in [
            (0, 0),
            (1, 6),
            (4, 3),
            (5, 4),
            (6, 7),
            (7, 8),
            (8, 9),
            (9, 1),
        ] {
            assert!((c[k] - s[j]).abs() <= 1e-15 * s[j].abs(), "row {i} col {k}");
        }
        let (a, b, h) = (s[5] + m[5], s[6] - m[6], s[10] - m[10]);
        let roll = b.atan2(a) + (h / a.hypot(b)).asin();
        // the rigid-wheelset relation the roll satisfies
        assert!((a * roll.sin() - b * roll.cos() - h).abs() < 1e-15);
        assert!(
            (c[3] - roll).abs() < 1e-15,
            "row {i}: roll {} vs {roll}",
            c[3]
        );
        assert!((c[2] - (s[2] + roll)).abs() < 1e-15, "row {i}: delta");
    }
}

/// No published critical speed was found for a single wheelset on this table (docs/VALIDATION.md
/// section 6), so the DTU study is checked against the one independent reference docs/model.md §9 gives:
/// with stiff primary springs the hunting wavelength at V_L is near Klingel's kinematic
/// wavelength 2π√(r0 l0/λ_e), λ_e = dr_R/dy(0) of the table.
#[test]
fn dtu_wheelset_hunts_at_the_kinematic_wavelength() {
    let plan = dtu_plan();
    let model = plan.wheelset_model().expect("model");
    let law = CreepLaw::Kalker;
    let sys = LinearSystem::at_centre(&model.with_law(law));
    let c = *critical_speeds(&sys, law, &plan.linear)
        .expect("search")
        .critical()
        .expect("V_L in range");
    let lk = 2.0 * std::f64::consts::PI * (0.4248829 * 0.75 / model.centre_conicity()).sqrt();
    assert!(
        (c.wavelength_m / lk - 1.0).abs() < 0.01,
        "{} m vs {lk} m",
        c.wavelength_m
    );
}

/// The exact Jacobian of the tabulated model (spline slopes through the Hermite contact table)
/// agrees with central differences of f; and with spin off, the Shen law's Hopf speed is the
/// Kalker critical speed (docs/model.md §5: no centred spin creep, so no pre-saturation).
#[test]
fn tabulated_model_jacobian_and_spin_free_identity() {
    let mut plan = dtu_plan();
    let model = plan.wheelset_model().expect("model");
    let h = [1e-7, 1e-7, 1e-6, 1e-6];
    for x in [[1e-3, 2e-4, 0.01, -0.003], [-4.3e-3, -1e-3, 0.2, 0.01]] {
        let xv = nalgebra::Vector4::from(x);
        let (jac, _) = model.jacobian(&xv, 60.0);
        for j in 0..4 {
            let mut p = xv;
            let mut m = xv;
            p[j] += h[j];
            m[j] -= h[j];
            let fd = (model.rhs_vec(&p, 60.0) - model.rhs_vec(&m, 60.0)) / (2.0 * h[j]);
            for i in 0..4 {
                let scale = jac.column(j).amax().max(1.0);
                assert!(
                    (jac[(i, j)] - fd[i]).abs() <= 1e-5 * scale,
                    "x = {x:?}, J[{i}][{j}] = {} vs {}",
                    jac[(i, j)],
                    fd[i]
                );
            }
        }
    }
    plan.contact.spin = false;
    let model = plan.wheelset_model().expect("model");
    let speed = |law| {
        let sys = LinearSystem::at_centre(&model.with_law(law));
        critical_speeds(&sys, law, &plan.linear)
            .expect("search")
            .critical()
            .expect("in range")
            .speed_m_s
    };
    let (k, s) = (
        speed(CreepLaw::Kalker),
        speed(CreepLaw::Shen { friction: 0.3 }),
    );
    assert!((k - s).abs() <= 1e-9 * k, "Kalker {k} m/s, Shen {s} m/s");
}

/// A spline through a step in the semi-axis b undershoots below zero between rows; the contact
/// table refuses it, naming the table, y and the column, instead of using a negative patch.
#[test]
fn an_undershooting_spline_is_refused() {
    let ys = grid(11, 0.01);
    let text = table_text("y_m,r_m,delta_rad,roll_rad,a_mm,b_mm", &ys, |y| {
        let b = if y <= 0.0 { 4.0 } else { 0.05 };
        vec![y, 0.46 + 0.05 * y, 0.05 + 0.07 * y, 0.07 * y, 6.0, b]
    });
    let dir = std::env::temp_dir().join(format!("critspeed-step-table-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let path = dir.join("step.csv");
    std::fs::write(&path, text).expect("write table");
    let study = study_text(&format!(
        "geometry = \"table\"\ngeometry_table = {:?}",
        path.display().to_string()
    ));
    let plan = study::parse(&study, "step").expect("study");
    let e = plan.wheelset_model().map(|_| ()).unwrap_err().to_string();
    let _ = std::fs::remove_dir_all(&dir);
    assert!(e.contains("step.csv") && e.contains("column b"), "{e}");
}
