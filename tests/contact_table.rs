//! The C² contact table (`src/contact/table.rs`): continuity of the second derivative at every
//! node, node values and slopes equal to the sampled geometry's, cubics reproduced, the error
//! against the source geometry and its convergence with the node count; the valid range and
//! the `contact.extrapolate` key.

use critspeed::contact::geometry::{ContactPoint, Geometry};
use critspeed::contact::table::{Column, ContactTable, Extrapolation, TableSpec};
use critspeed::study::{self, Plan};
use critspeed::system::scalar::Dual;

mod common;
use common::{critspeed, root, scratch};

fn load(name: &str) -> Plan {
    study::load(&root().join("studies").join(name)).expect("study loads")
}

fn table(plan: &Plan) -> ContactTable {
    ContactTable::build(&plan.contact.geometry, &plan.table_spec()).expect("table")
}

/// The node abscissae of a table built from `spec` (odd count, symmetric).
fn nodes(spec: &TableSpec) -> Vec<f64> {
    let n = spec.nodes.max(5) | 1;
    let half = (n - 1) / 2;
    let h = spec.half_width / half as f64;
    (0..n).map(|k| (k as f64 - half as f64) * h).collect()
}

/// The geometry solved at every y of `ys` (increasing), marching outwards from the centre on
/// each side as the table does (each solve seeded by the previous one; the centre from the
/// negative side's solve at −0).
fn solve_all(g: &Geometry, spec: &TableSpec, ys: &[f64]) -> Vec<ContactPoint<Dual<1>>> {
    let mid = ys.partition_point(|&y| y < 0.0);
    let mut out = vec![None; ys.len()];
    let mut side = |order: Vec<usize>, start: f64| {
        let (_, mut guess) = g.solve(spec.nominal, start, None).expect("solves");
        for k in order {
            let (p, u) = g.solve(spec.nominal, ys[k], Some(guess)).expect("solves");
            guess = u;
            out[k] = Some(p);
        }
    };
    side((mid..ys.len()).filter(|&k| ys[k] != 0.0).collect(), 0.0);
    side((0..mid).rev().collect(), -0.0);
    if let Some(k) = ys.iter().position(|&y| y == 0.0) {
        out[k] = Some(g.solve(spec.nominal, -0.0, None).expect("solves").0);
    }
    out.into_iter()
        .map(|p| p.expect("every y solved"))
        .collect()
}

/// Second derivative of every column equal from both sides of every interior node and equal
/// to the node's datum, relative to the column's largest second derivative: the table is C².
fn assert_c2(t: &ContactTable, what: &str) {
    for col in Column::ALL {
        let data = t.node_second_derivatives(col);
        let scale = data.iter().map(|d| d.1.abs()).fold(0.0, f64::max);
        if scale == 0.0 {
            continue;
        }
        let h = data[1].0 - data[0].0;
        let mut worst = 0.0f64;
        for &(y, c) in &data[1..data.len() - 1] {
            // close enough that the third derivative (up to 4e13 rad/m³ on S1002's smoothed
            // jumps) moves the second by less than 1e-8 of the scale
            let eps = 1e-9 * h;
            let (below, above) = (t.derivatives(col, y - eps), t.derivatives(col, y + eps));
            worst = worst
                .max((below[2] - above[2]).abs())
                .max((t.derivatives(col, y)[2] - c).abs());
        }
        eprintln!("{what} {col:?}: largest second-derivative jump {worst:.1e}, scale {scale:.1e}");
        assert!(
            worst <= 1e-6 * scale,
            "{what} {col:?}: {worst:e} of {scale:e}"
        );
    }
}

#[test]
fn every_shipped_kind_of_table_is_c2_at_its_nodes() {
    for name in [
        "seed-hunting.toml",       // cone-on-arc
        "s1002-uic60.toml",        // profiles, smoothed
        "dtu-rsgeo-wheelset.toml", // tabulated file
    ] {
        assert_c2(&table(&load(name)), name);
    }
    // the raw profile table (no smoothing: steps at the contact jumps)
    let mut plan = load("s1002-uic60.toml");
    if let Geometry::Profiles { smoothing, .. } = &mut plan.contact.geometry {
        *smoothing = 0.0;
    }
    assert_c2(&table(&plan), "s1002-uic60 unsmoothed");
}

/// At the nodes the table returns the geometry's own values and exact slopes; its second
/// derivative (central differences of the exact node slopes) is compared with central
/// differences of the geometry's exact slopes over ±1 µm: the node error of the scheme,
/// bounded by h² f''''/6 (h = 50 µm here).
#[test]
fn node_values_and_slopes_are_the_geometry_and_second_derivatives_converge() {
    let plan = load("seed-hunting.toml");
    let spec = plan.table_spec();
    let t = table(&plan);
    let ys = nodes(&spec);
    let exact = solve_all(&plan.contact.geometry, &spec, &ys);
    let fd = 1e-6;
    let h = ys[1] - ys[0];
    let mut worst = [0.0f64; 3];
    let mut node_error = [0.0f64; 2];
    for (k, (&y, p)) in ys.iter().zip(&exact).enumerate() {
        for (j, (col, q)) in [
            (Column::Radius, p.radius),
            (Column::Angle, p.angle),
            (Column::Roll, p.roll),
        ]
        .into_iter()
        .enumerate()
        {
            let [v, s, c] = t.derivatives(col, y);
            // a node can be located at the end of the interval below it: rounding of that
            // interval's quintic (terms up to 200 |Δp|)
            let tol = 16.0 * f64::EPSILON * (q.re.abs() + 200.0 * q.eps[0].abs() * h);
            node_error[0] = node_error[0].max((v - q.re).abs() / tol);
            node_error[1] = node_error[1].max((s - q.eps[0]).abs() / (tol / h));
            assert!((v - q.re).abs() <= tol, "{col:?} {k}: {v} vs {}", q.re);
            assert!(
                (s - q.eps[0]).abs() <= tol / h,
                "{col:?} {k}: {s} vs {}",
                q.eps[0]
            );
            if k == 0 || k + 1 == ys.len() {
                continue;
            }
            let side = solve_all(&plan.contact.geometry, &spec, &[y - fd, y + fd]);
            let pick = |p: &ContactPoint<Dual<1>>| [p.radius, p.angle, p.roll][j].eps[0];
            let second = (pick(&side[1]) - pick(&side[0])) / (2.0 * fd);
            worst[j] = worst[j].max((c - second).abs() / second.abs().max(1e-3));
        }
    }
    eprintln!("node values and slopes: largest error {node_error:.2?} of the tolerance");
    eprintln!("cone-on-arc, 401 nodes: node error of the second derivative (relative) r {:.1e}, δ {:.1e}, φ {:.1e}", worst[0], worst[1], worst[2]);
    assert!(worst.iter().all(|&w| w < 1e-4), "{worst:?}");
}

/// The closed-form cone is linear in y: reproduced exactly by the table, between the nodes
/// and beyond them (its linear extension is exact, so the table is valid everywhere).
#[test]
fn the_cone_is_reproduced_and_valid_everywhere() {
    let plan = load("seed-hunting-cone.toml");
    let t = table(&plan);
    let Geometry::Cone { conicity } = plan.contact.geometry else {
        panic!("a cone study");
    };
    let (r0, l0) = (
        plan.wheelset.rolling_radius,
        plan.wheelset.half_contact_distance,
    );
    for k in 0..=300 {
        let y = -0.015 + 0.03 * k as f64 / 300.0;
        let [r, dr, d2r] = t.derivatives(Column::Radius, y);
        assert!((r - (r0 + conicity * y)).abs() < 1e-15, "{y}");
        assert!((dr - conicity).abs() < 1e-11 && d2r.abs() < 1e-6, "{y}");
        let [d, dd, _] = t.derivatives(Column::Angle, y);
        assert!((d - conicity * (1.0 + y / l0)).abs() < 1e-15, "{y}");
        assert!((dd - conicity / l0).abs() < 1e-11, "{y}");
    }
    assert_eq!(t.valid_half_width(), None);
    assert!(t.is_valid_at(0.5) && !t.is_valid_at(f64::NAN));
}

/// The interpolant's error between the nodes against the source geometry, at the cell
/// midpoints, and its convergence with the node count: S1002/UIC60 without smoothing, on the
/// tread between the contact jumps at 0.21 and 4.84 mm (|y| in [1, 4.5] mm).
#[test]
fn midpoint_error_converges_with_the_node_count() {
    let mut plan = load("s1002-uic60.toml");
    if let Geometry::Profiles { smoothing, .. } = &mut plan.contact.geometry {
        *smoothing = 0.0;
    }
    let mut errors = Vec::new();
    for count in [241, 481, 961, 1921] {
        let mut spec = plan.table_spec();
        spec.nodes = count;
        let t = ContactTable::build(&plan.contact.geometry, &spec).expect("table");
        let ys = nodes(&spec);
        let h = ys[1] - ys[0];
        let mids: Vec<f64> = ys[..ys.len() - 1]
            .iter()
            .map(|y| y + 0.5 * h)
            .filter(|y| (1e-3..=4.5e-3).contains(&y.abs()))
            .collect();
        let exact = solve_all(&plan.contact.geometry, &spec, &mids);
        let mut err = [0.0f64; 2];
        for (&y, p) in mids.iter().zip(&exact) {
            err[0] = err[0].max((t.derivatives(Column::Radius, y)[0] - p.radius.re).abs());
            err[1] = err[1].max((t.derivatives(Column::Angle, y)[0] - p.angle.re).abs());
        }
        eprintln!("S1002 tread, {count} nodes (h = {:.2} µm): largest midpoint error r_R {:.2e} m, δ_R {:.2e} rad", h * 1e6, err[0], err[1]);
        errors.push(err);
    }
    // the profiles are natural cubic splines of their points (C², not smoother), so the
    // geometry is not smooth enough for h⁴: measured 2.7 to 8 per halving
    for w in errors.windows(2) {
        let ratios = [w[0][0] / w[1][0], w[0][1] / w[1][1]];
        assert!(
            ratios.iter().all(|&r| r > 2.5),
            "{errors:?}: not converging"
        );
    }
}

#[test]
fn the_valid_range_is_the_tabulated_range() {
    for (name, want) in [
        ("seed-hunting.toml", 0.010),
        ("s1002-uic60.toml", 0.012),
        ("dtu-rsgeo-wheelset.toml", 0.008),
    ] {
        let t = table(&load(name));
        let w = t.valid_half_width().expect("not a knife-edge cone");
        assert!((w - want).abs() < 1e-15, "{name}: {w}");
        assert!(
            t.is_valid_at(want) && !t.is_valid_at(want * 1.001) && !t.is_valid_at(-want * 1.001)
        );
    }
}

#[test]
fn contact_extrapolate_is_validated() {
    let base = std::fs::read_to_string(root().join("studies/seed-hunting.toml")).expect("study");
    let with = |v: &str| base.replace("[contact]\n", &format!("[contact]\nextrapolate = {v:?}\n"));
    let parse = |text: &str| study::parse(text, "t.toml");
    assert_eq!(
        parse(&base).expect("default").contact.extrapolate,
        Extrapolation::None
    );
    assert_eq!(
        parse(&with("linear")).expect("linear").contact.extrapolate,
        Extrapolation::Linear
    );
    // an unknown value: exit 2, the message naming the key, the value and the allowed values
    let dir = scratch("extrapolate");
    std::fs::write(dir.join("bad.toml"), with("quadratic")).expect("write");
    let out = critspeed(&["check", "bad.toml"], &dir);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    for part in ["contact.extrapolate", "quadratic", "\"none\", \"linear\""] {
        assert!(err.contains(part), "{part} missing from {err}");
    }
    // `check` and `geometry` print the valid range
    std::fs::write(dir.join("ok.toml"), with("linear")).expect("write");
    let out = critspeed(&["check", "ok.toml"], &dir);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        text.contains("genuine for |y| <= 10.0000 mm") && text.contains("linear"),
        "{text}"
    );
    let out = critspeed(&["geometry", "ok.toml"], &dir);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("valid range: |y| <= 10.0000 mm"), "{text}");
    let _ = std::fs::remove_dir_all(&dir);
}
