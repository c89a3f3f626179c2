//! VALIDATION.md sections of the tabulated geometry (docs/model.md §3 method 3): the DTU RSGEO table
//! as critspeed reads and interpolates it, and a single wheelset computed on it.

use std::fmt::Write as _;

use critspeed::bifurcation::analyse;
use critspeed::contact::creep::CreepLaw;
use critspeed::contact::geometry::Geometry;
use critspeed::contact::kalker::CreepCoefficients;
use critspeed::contact::table::{Column, ContactTable, CreepSource};
use critspeed::continuation::SpecialKind;
use critspeed::stability::{critical_speeds, LinearSystem};
use critspeed::study;

fn dtu_plan() -> study::Plan {
    study::load(&super::root().join("studies/dtu-rsgeo-wheelset.toml")).expect("DTU study")
}

/// Round trip of the DTU table through the reader, the splines and the contact table.
pub fn table_geometry_section(s: &mut String) {
    let plan = dtu_plan();
    let Geometry::Table(t) = &plan.contact.geometry else {
        panic!("the DTU study uses geometry = \"table\"");
    };
    let _ = writeln!(
        s,
        "## 5. The DTU table as critspeed's geometry (`geometry = \"table\"`)\n"
    );
    let _ = writeln!(s, "`studies/tables/dtu-rsgeo-1o40.csv` is the table of section 4 converted as its header states (copied columns unchanged; roll derived from the two contact points' heights for a rigid wheelset; contact angle to the track plane = DYTSI's angle to the axle + roll; recomputed from the source by `tests/table_geometry.rs`). Sampled on a contact grid whose nodes are the file's {} rows (0.5 mm), the tool returns the file's values; its node slopes (exact slopes of the not-a-knot C² spline) are compared with central differences of the data:\n", t.nodes().len());
    let mut spec = plan.table_spec();
    spec.half_width = t.half_width();
    spec.nodes = t.nodes().len();
    // the geometry columns only: constant creep coefficients (C33 from Kalker's table is not
    // defined where the flange contact's a/b exceeds 10)
    spec.creep = CreepSource::Given(CreepCoefficients {
        f11: 1e7,
        f22: 1e7,
        f23: 1e4,
        f33: 10.0,
    });
    let table = ContactTable::build(&plan.contact.geometry, &spec).expect("table");
    let nodes = t.nodes();
    let rows = table.rows();
    let _ = writeln!(s, "| column | largest \\|tool − data\\| at the nodes | largest \\|slope − central difference\\|, \\|y\\| ≤ 5 mm | same, \\|y\\| ≤ 7 mm | same, all interior nodes | largest \\|central difference\\|, \\|y\\| ≤ 5 mm |\n|---|---|---|---|---|---|");
    for (k, name, unit) in [(1, "r_R", "m"), (2, "δ_R", "rad"), (3, "φ", "rad")] {
        let mut at_nodes = 0.0f64;
        for (row, n) in rows.iter().zip(&nodes) {
            let tool = [0.0, row.point.radius, row.point.angle, row.point.roll][k];
            // the file's centre row is y = −5.2e-16 m: compare at the file's own y
            let exact = [
                0.0,
                t.point(n[0]).radius.re,
                t.point(n[0]).angle.re,
                t.point(n[0]).roll.re,
            ][k];
            at_nodes = at_nodes.max((tool - n[k]).abs()).max((exact - n[k]).abs());
        }
        let (mut inner, mut tread, mut all, mut big) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
        for i in 1..nodes.len() - 1 {
            let cd = (nodes[i + 1][k] - nodes[i - 1][k]) / (nodes[i + 1][0] - nodes[i - 1][0]);
            let p = t.point(nodes[i][0]);
            let slope = [0.0, p.radius.eps[0], p.angle.eps[0], p.roll.eps[0]][k];
            all = all.max((slope - cd).abs());
            if nodes[i][0].abs() <= 0.005 + 1e-12 {
                inner = inner.max((slope - cd).abs());
                big = big.max(cd.abs());
            }
            if nodes[i][0].abs() <= 0.007 + 1e-12 {
                tread = tread.max((slope - cd).abs());
            }
        }
        let _ = writeln!(
            s,
            "| {name} ({unit}) | {at_nodes:.1e} | {inner:.3e} {unit}/m | {tread:.3e} {unit}/m | {all:.3e} {unit}/m | {big:.3e} {unit}/m |"
        );
    }
    let c = t.point(0.0);
    let l0 = plan.wheelset.half_contact_distance;
    let _ = writeln!(s, "\nThe slopes differ most from central differences where the data bend sharply: from 7 mm the contact climbs the flange root (r_R rises by 14 mm and δ_R from 0.12 to 1.22 rad between 7 and 9 mm); the spline is exact for cubics, a central difference over 1 mm is not, and both only sample a 0.5 mm table there. At the centre: λ_e = dr_R/dy = {:.5}, δ_R = {:.6} rad, dδ_R/dy = {:.4} rad/m, dφ/dy = {:.5} rad/m, against λ_e/l0 = {:.5} rad/m for a cone on knife-edge rails (the rail contact heights change the roll).\n",
        c.radius.eps[0], c.angle.re, c.angle.eps[0], c.roll.eps[0], c.radius.eps[0] / l0);
}

/// The single wheelset on the DTU table: what critspeed computes, and the literature search.
pub fn dtu_wheelset_section(s: &mut String) {
    let plan = dtu_plan();
    let model = plan.model().expect("model");
    let _ = writeln!(
        s,
        "## 6. A single wheelset on the DTU table (no published comparison found)\n"
    );
    let _ = writeln!(s, "Sought: a published single suspended wheelset with stated parameters and critical speeds on this geometry — Knudsen, Feldberg & True (1992), *Bifurcations and chaos in a model of a rolling railway wheelset*, Phil. Trans. R. Soc. A 338, 455–469; Knudsen, Slivsgaard, Rose, True & Feldberg (1994), *Dynamics of a model of a railway wheelset*, Nonlinear Dynamics 6, 215–236; True's later single-wheelset papers. Only their citations (e.g. in True & Trzepacz, Solid Mechanics and its Applications 122) were found in the reference corpora, not their parameters or critical speeds; the Cooperrider numbers available are for a bogie. **No published number is compared here.**\n");
    let _ = writeln!(s, "`studies/dtu-rsgeo-wheelset.toml` (its header gives the source of every value; mass and yaw inertia are ASSUMED) computed as is:\n");
    let opts = plan.linear;
    let kalker = LinearSystem::<4>::at_centre(&model.with_law(CreepLaw::Kalker));
    let lin = critical_speeds(&kalker, CreepLaw::Kalker, &opts).expect("search");
    let vl = lin.critical().expect("V_L in range");
    let r = analyse(&plan.name, &model, &plan.bifurcation_options()).expect("continuation");
    let vh = r.hopf.expect("Hopf point");
    let _ = writeln!(s, "| quantity | critspeed |\n|---|---|");
    let _ = writeln!(
        s,
        "| linear (Kalker) critical speed V_L | {:.1} m/s, {:.2} Hz, wavelength {:.2} m |",
        vl.speed_m_s, vl.frequency_hz, vl.wavelength_m
    );
    let _ = writeln!(
        s,
        "| kinematic (Klingel) wavelength 2π√(r0 l0/λ_e) | {:.2} m |",
        model.klingel_wavelength()
    );
    let _ = writeln!(
        s,
        "| Shen Hopf speed V_H | {:.1} m/s ({}) |",
        vh.speed_m_s,
        r.hopf_type.map_or("?", |h| h.name())
    );
    for f in r.special.iter().filter(|p| p.kind == SpecialKind::Fold) {
        let _ = writeln!(
            s,
            "| fold of the cycle branch | {:.1} m/s at amplitude {:.2} mm |",
            f.speed_m_s,
            1e3 * f.amplitude_y_m
        );
    }
    if let Some((v, _)) = r.nonlinear_critical_speed {
        let _ = writeln!(s, "| V_NL as the tool reports it | {v:.1} m/s |");
    }
    let lowest = r
        .cycles
        .iter()
        .filter(|c| c.stable)
        .map(|c| c.speed_m_s)
        .fold(f64::INFINITY, f64::min);
    let _ = writeln!(
        s,
        "| lowest speed of a computed stable cycle | {lowest:.1} m/s |"
    );
    let _ = writeln!(s, "\nThe primary springs (1.823 and 3.646 MN/m per side, DYTSI's Cooperrider values) tie the wheelset to a fixed frame, so the hunting speed is far above the bogie's; the hunting wavelength at V_L is the kinematic one to {:.1} %. The branch is supercritical at V_H, folds back at the first fold and regains stability only in a sliver between the two close folds near 120.7 m/s, in the tread region where the table's contact angle is irregular; so the nonlinear critical speed (docs/model.md §9: the lowest speed at which a stable cycle exists) is the lower fold of that sliver, far below V_H; how much of it is physics and how much the table's irregular contact angle is open. Model differences a comparison would have to account for: DYTSI's wheelset has roll and vertical freedoms with elastic (penetration-based) normal forces and no spin moment M_z; critspeed uses quasi-static N = (W/2)/cos δ and Kalker's spin moment with C33 from Kalker's table.\n",
        100.0 * (vl.wavelength_m / model.klingel_wavelength() - 1.0));
}

/// δ_R and dδ_R/dy of the geometry at every y of `ys` (increasing), solved marching outwards
/// from the centre on each side as the contact table does.
fn angles(plan: &study::Plan, ys: &[f64]) -> Vec<(f64, f64)> {
    let (g, n) = (&plan.contact.geometry, plan.table_spec().nominal);
    let mid = ys.partition_point(|&y| y < 0.0);
    let mut out = vec![(f64::NAN, f64::NAN); ys.len()];
    let sides = [
        ((mid..ys.len()).collect::<Vec<_>>(), 0.0),
        ((0..mid).rev().collect(), -0.0),
    ];
    for (order, start) in sides {
        let (_, mut guess) = g.solve(n, start, None).expect("solves");
        for k in order {
            let (p, u) = g.solve(n, ys[k], Some(guess)).expect("solves");
            guess = u;
            out[k] = (p.angle.re, p.angle.eps[0]);
        }
    }
    out
}

/// The C² contact table between and at its nodes, on the three kinds of sampled geometry.
pub fn contact_table_section(s: &mut String) {
    let _ = writeln!(s, "### The contact table between its nodes\n");
    let _ = writeln!(s, "Every geometry is sampled once onto the contact table's uniform grid (`contact.table_points` nodes over ±`lateral_range`) with its value and exact slope at each node, and a second derivative: the spline's own for a tabulated file (r_R, δ_R, φ; the Hertz and creep columns derived from them by central differences of their exact slopes), central differences of the exact node slopes for the cone-on-arc and profile solves (error h² f''''/6). Between the nodes a quintic Hermite polynomial matches all three at both ends, so the table is C²: the integrator's error estimate stays valid along an orbit (with a C¹ table the second derivative jumps at every node, which on S1002 cost a third of the integrator's trial steps). Measured on δ_R, the column with the largest second derivative:\n");
    let _ = writeln!(s, "| geometry | nodes (spacing) | largest jump of d²δ_R/dy² across a node, relative | d²δ_R/dy² at the nodes against the geometry, relative | largest \\|δ_R error\\| at the cell midpoints | same with half the spacing |\n|---|---|---|---|---|---|");
    // (label, study, the |y| window compared); profiles are compared unsmoothed
    let tread = Some((1e-3, 4.5e-3));
    let cases = [
        ("cone-on-arc (seed-hunting)", "seed-hunting.toml", None),
        (
            "S1002/UIC60 1:40, unsmoothed (tread: \\|y\\| in [1, 4.5] mm)",
            "s1002-uic60.toml",
            tread,
        ),
        (
            "DTU RSGEO file (dtu-rsgeo-wheelset)",
            "dtu-rsgeo-wheelset.toml",
            None,
        ),
    ];
    for (label, file, window) in cases {
        let mut plan = study::load(&super::root().join("studies").join(file)).expect("study");
        if let Geometry::Profiles { smoothing, .. } = &mut plan.contact.geometry {
            *smoothing = 0.0;
        }
        let spec = plan.table_spec();
        let mut mid_errors = Vec::new();
        let mut row = (0.0f64, 0.0f64, 0, 0.0);
        for (i, count) in [spec.nodes, 2 * spec.nodes - 1].into_iter().enumerate() {
            let mut sp = spec;
            sp.nodes = count;
            let t = ContactTable::build(&plan.contact.geometry, &sp).expect("table");
            let nodes: Vec<(f64, f64)> = t.node_second_derivatives(Column::Angle);
            let h = nodes[1].0 - nodes[0].0;
            let inside = |y: f64| window.is_none_or(|(a, b)| (a..=b).contains(&y.abs()));
            let mids: Vec<f64> = nodes[..nodes.len() - 1]
                .iter()
                .map(|n| n.0 + 0.5 * h)
                .filter(|&y| inside(y))
                .collect();
            let exact: Vec<f64> = match &plan.contact.geometry {
                Geometry::Table(tab) => mids.iter().map(|&y| tab.point(y).angle.re).collect(),
                _ => angles(&plan, &mids).iter().map(|p| p.0).collect(),
            };
            let err = mids
                .iter()
                .zip(&exact)
                .map(|(&y, e)| (t.derivatives(Column::Angle, y)[0] - e).abs())
                .fold(0.0, f64::max);
            mid_errors.push(err);
            if i > 0 {
                continue;
            }
            let scale = nodes.iter().map(|n| n.1.abs()).fold(0.0, f64::max);
            let mut jump = 0.0f64;
            for &(y, _) in &nodes[1..nodes.len() - 1] {
                let e = 1e-9 * h;
                jump = jump.max(
                    (t.derivatives(Column::Angle, y - e)[2]
                        - t.derivatives(Column::Angle, y + e)[2])
                        .abs(),
                );
            }
            // the second derivative at the nodes against central differences of the geometry's
            // exact slopes over ±1 µm (for the file: the spline's own, exact by construction)
            let mut node_err = 0.0f64;
            if !matches!(plan.contact.geometry, Geometry::Table(_)) {
                for &(y, c) in nodes.iter().filter(|n| inside(n.0)).step_by(5) {
                    let side = angles(&plan, &[y - 1e-6, y + 1e-6]);
                    let fd = (side[1].1 - side[0].1) / 2e-6;
                    node_err = node_err.max((c - fd).abs() / scale);
                }
            }
            row = (jump / scale, node_err, count, h);
        }
        let node = if matches!(plan.contact.geometry, Geometry::Table(_)) {
            "exact (the spline's)".to_string()
        } else {
            format!("{:.1e}", row.1)
        };
        let _ = writeln!(
            s,
            "| {label} | {} ({:.1} µm) | {:.1e} | {node} | {:.2e} rad | {:.2e} rad |",
            row.2,
            row.3 * 1e6,
            row.0,
            mid_errors[0],
            mid_errors[1]
        );
    }
    let _ = writeln!(s, "\nRelative figures are against the column's largest second derivative at the nodes. The jumps are those of approaching each node from 1e-9 h on either side (rounding and the third derivative over that distance); a C¹ table's are of the order of the second derivative itself near S1002's contact jumps. Values and slopes at the nodes are the geometry's own (`tests/contact_table.rs` checks them to a few ulps). The cone-on-arc is nearly linear, so its midpoint error is rounding at any spacing. The profiles are natural cubic splines of their point lists, only C² themselves, so the midpoint error falls by 3 to 8 per halving of the spacing rather than 16. The file's spline is cubic between its rows, 0.5 mm apart: the table reproduces it to rounding wherever a cell holds no row, so the error sits in the cells that contain a row, and with 801 nodes over ±8 mm (20 µm) every row is a node and the table is the spline. Section 8's cone and cubic are reproduced exactly by any of these interpolants, so its last digits depend on the interpolation only through rounding.\n");
}
