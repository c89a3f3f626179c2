//! The geometry table reader (docs/model.md §3 method 3): units converted from the header, malformed
//! files refused with file and line, study keys that do not fit a table refused.

use std::path::PathBuf;

use critspeed::contact::tabulated::TabulatedGeometry;
use critspeed::study;

mod common;
use common::{grid, table_text};

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn error_of(text: &str) -> String {
    match TabulatedGeometry::parse(text, "t.csv", 0.46) {
        Ok(_) => panic!("table should have been refused:\n{text}"),
        Err(e) => e.to_string(),
    }
}

#[test]
fn units_in_the_header_are_converted() {
    let ys = grid(21, 0.01);
    let si = table_text("y_m,r_m,delta_rad,roll_rad", &ys, |y| {
        vec![y, 0.46 + 0.05 * y, 0.05 + 0.07 * y, 0.07 * y]
    });
    let other = table_text("y_mm,r_minus_r0_mm,delta_deg,roll_deg", &ys, |y| {
        let deg = 180.0 / std::f64::consts::PI;
        vec![
            1e3 * y,
            1e3 * 0.05 * y,
            deg * (0.05 + 0.07 * y),
            deg * 0.07 * y,
        ]
    });
    let a = TabulatedGeometry::parse(&si, "si.csv", 0.46).expect("valid");
    let b = TabulatedGeometry::parse(&other, "mm.csv", 0.46).expect("valid");
    for y in [-0.0093, -0.002, 0.0, 0.0041, 0.0099] {
        let (p, q) = (a.point(y), b.point(y));
        for (u, v) in [(p.radius, q.radius), (p.angle, q.angle), (p.roll, q.roll)] {
            assert!((u.re - v.re).abs() < 1e-14, "{y}: {u:?} vs {v:?}");
            assert!((u.eps[0] - v.eps[0]).abs() < 1e-11, "{y}: {u:?} vs {v:?}");
        }
    }
}

#[test]
fn malformed_tables_are_refused_with_file_and_line() {
    let ok = "# c\ny_m,r_m,delta_rad,roll_rad\n-2e-3,0.46,0.05,0\n-1e-3,0.46,0.05,0\n\
              1e-3,0.46,0.05,0\n2e-3,0.46,0.05,0\n";
    assert!(TabulatedGeometry::parse(ok, "t.csv", 0.46).is_ok());
    // y not increasing: line 5
    let e = error_of(&ok.replace("\n1e-3,0.46", "\n-1e-3,0.46"));
    assert!(e.starts_with("t.csv:5:") && e.contains("increase"), "{e}");
    // a unit the reader does not know
    let e = error_of(&ok.replace("y_m,", "y_in,"));
    assert!(e.starts_with("t.csv:2:") && e.contains("\"y_in\""), "{e}");
    // missing roll
    let e = error_of(&ok.replace(",roll_rad", "").replace(",0\n", "\n"));
    assert!(e.starts_with("t.csv:2:") && e.contains("roll"), "{e}");
    // NaN and text
    let e = error_of(&ok.replace("-1e-3,0.46,0.05", "-1e-3,NaN,0.05"));
    assert!(e.starts_with("t.csv:4:") && e.contains("r_m"), "{e}");
    let e = error_of(&ok.replace("\n2e-3,0.46,0.05,0\n", "\n2e-3,0.46,0.05\n"));
    assert!(e.starts_with("t.csv:6:") && e.contains("3 fields"), "{e}");
    // unphysical: negative radius, angle beyond 90°
    let e = error_of(&ok.replace("\n1e-3,0.46,0.05", "\n1e-3,-0.46,0.05"));
    assert!(e.starts_with("t.csv:5:") && e.contains("positive"), "{e}");
    let e = error_of(
        &ok.replace("delta_rad", "delta_deg")
            .replace(",0.05,", ",95,"),
    );
    assert!(e.starts_with("t.csv:3:") && e.contains("π/2"), "{e}");
    // one side of y only
    let one_sided = "y_m,r_m,delta_rad,roll_rad\n0,0.46,0.05,0\n1e-3,0.46,0.05,0\n\
                     2e-3,0.46,0.05,0\n3e-3,0.46,0.05,0\n";
    assert!(error_of(one_sided).contains("both signs"));
    // a without b; C without a, b
    let e = error_of(
        &ok.replace("roll_rad", "roll_rad,a_m")
            .replace(",0\n", ",0,0.006\n"),
    );
    assert!(e.contains("semi-axis"), "{e}");
    // two radius columns
    let e = error_of(
        &ok.replace("roll_rad", "roll_rad,r_mm")
            .replace(",0\n", ",0,460\n"),
    );
    assert!(e.starts_with("t.csv:2:") && e.contains("r_mm"), "{e}");
}

/// Study keys that do not fit the table geometry are refused with the key and the rule.
#[test]
fn table_study_keys_are_checked() {
    let dtu =
        std::fs::read_to_string(root().join("studies/dtu-rsgeo-wheelset.toml")).expect("DTU study");
    let folder = root().join("studies");
    let err = |text: &str| {
        study::parse_in(text, "s.toml", Some(&folder))
            .map(|_| ())
            .unwrap_err()
            .to_string()
    };
    let e = err(&dtu.replace("lateral_range = \"8 mm\"", "lateral_range = \"20 mm\""));
    assert!(
        e.contains("contact.lateral_range") && e.contains("0.017"),
        "{e}"
    );
    let e = err(&dtu.replace(
        "\ngeometry = \"table\"\n",
        "\ngeometry = \"table\"\nconicity = 0.05\n",
    ));
    assert!(e.contains("contact.conicity") && e.contains("table"), "{e}");
    let e = err(&dtu.replace(
        "\ngeometry = \"table\"\n",
        "\ngeometry = \"cone\"\nconicity = 0.05\n",
    ));
    assert!(e.contains("contact.geometry_table"), "{e}");
    let e = err(&dtu.replace("geometry_table = \"tables/dtu-rsgeo-1o40.csv\"\n", ""));
    assert!(e.contains("contact.geometry_table is missing"), "{e}");
}
