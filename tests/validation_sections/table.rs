//! VALIDATION.md sections of the tabulated geometry (docs/model.md §3 method 3): the DTU RSGEO table
//! as critspeed reads and interpolates it, and a single wheelset computed on it.

use std::fmt::Write as _;

use critspeed::bifurcation::analyse;
use critspeed::contact::creep::CreepLaw;
use critspeed::contact::geometry::Geometry;
use critspeed::contact::kalker::CreepCoefficients;
use critspeed::contact::table::{ContactTable, CreepSource};
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
