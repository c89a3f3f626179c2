use super::*;
use crate::study::keys::study_keys;

#[test]
fn every_row_is_a_study_key_once_with_plausible_inside_meaningful() {
    let keys = study_keys().expect("traced");
    let all: Vec<&Range> = ranges().collect();
    assert!(all.len() > 60, "{} rows", all.len());
    for (i, r) in all.iter().enumerate() {
        assert!(
            keys.iter().any(|k| k == r.key),
            "{} is not a study key",
            r.key
        );
        assert!(all[..i].iter().all(|o| o.key != r.key), "{} twice", r.key);
        let (p, m) = (r.plausible, r.meaningful);
        assert!(p.lo < p.hi && m.lo < m.hi, "{}: empty range", r.key);
        // the plausible range lies inside the meaningful one
        for end in [p.lo, p.hi] {
            assert!(
                m.contains(end),
                "{}: plausible end {end} outside {m:?}",
                r.key
            );
        }
        assert!(!r.why.is_empty());
    }
}

#[test]
fn every_sweepable_key_has_a_range() {
    for (key, dim) in crate::sweep::SWEEP_KEYS {
        let r = range(key).unwrap_or_else(|| panic!("{key} has no range"));
        assert_eq!(r.dim, *dim, "{key}");
    }
}

#[test]
fn bounds_and_numbers_read_as_written() {
    assert_eq!(Bounds::left_open(0.0, 2.0).show(""), "(0, 2]");
    assert_eq!(Bounds::closed(1e-3, 10.0).show("m"), "[0.001, 10] m");
    assert_eq!(Bounds::closed(0.0, 1e11).show("N/m"), "[0, 1e11] N/m");
    assert_eq!(si(1e300), "1e300");
    assert_eq!(si(-2.5e-300), "-2.5e-300");
    assert_eq!(si(3_860_000.0), "3860000");
    assert_eq!(si(1e9), "1e9");
    assert_eq!(si(0.3), "0.3");
    assert_eq!(si(2951.5), "2951.5");
    assert!(!Bounds::closed(0.0, 1.0).contains(f64::NAN));
    assert!(Bounds::left_open(0.0, 2.0).contains(2.0));
    assert!(!Bounds::left_open(0.0, 2.0).contains(0.0));
    assert!(!Bounds::open(0.0, 0.5).contains(0.5));
    assert_eq!(
        range("linear.speed_range[1]").map(|r| r.key),
        Some("linear.speed_range")
    );
}

#[test]
fn outside_the_meaningful_range_is_an_error_naming_key_value_and_range() {
    let e = meaningful("wheelset.rolling_radius", 1e300).expect_err("a 1e300 m wheel");
    let msg = e.to_string();
    for part in [
        "wheelset.rolling_radius",
        "1e300 m",
        "[0.02, 2] m",
        "[0.2, 0.7] m",
    ] {
        assert!(msg.contains(part), "{part} not in {msg}");
    }
    assert!(meaningful("wheelset.rolling_radius", 0.46).is_ok());
    assert!(meaningful("no.such.key", 1e300).is_ok());
    let w = plausible("contact.friction", 0.9).expect("outside [0.05, 0.6]");
    assert_eq!(
        w.to_string(),
        "contact.friction = 0.9 lies outside the plausible range [0.05, 0.6] \
         (wet or contaminated (0.05) to dry sanded rail (0.6)); computed as given"
    );
    assert!(plausible("contact.friction", 0.3).is_none());
}

/// The shipped studies describe real vehicles: no value of theirs, nor of their sweep axes,
/// lies outside its plausible range.
#[test]
fn the_shipped_studies_are_plausible() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("studies");
    let mut seen = 0;
    for e in std::fs::read_dir(&dir).expect("studies/") {
        let p = e.expect("entry").path();
        if p.extension().is_none_or(|x| x != "toml") {
            continue;
        }
        let plan = crate::study::load(&p).expect("valid");
        assert!(
            plan.warnings.is_empty(),
            "{}: {:?}",
            p.display(),
            plan.warnings
        );
        if let Ok(s) = crate::sweep::SweepStudy::load(&p) {
            let w = crate::api::sweep_warnings(&s);
            assert!(w.is_empty(), "{}: {w:?}", p.display());
        }
        seen += 1;
    }
    assert!(seen >= 14, "{seen} studies");
}

/// docs/studies.md and docs/vehicles.md show every range as the table holds it.
#[test]
fn the_docs_show_every_range() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let pages: String = ["docs/studies.md", "docs/vehicles.md"]
        .iter()
        .map(|p| std::fs::read_to_string(root.join(p)).expect("page"))
        .collect();
    for r in ranges() {
        let unit = match r.dim.si_unit() {
            "" => "–",
            u => u,
        };
        let row = format!(
            "| `{}` | {unit} | {} | {} | {} |",
            r.key,
            r.plausible.show(""),
            r.meaningful.show(""),
            r.why
        );
        assert!(pages.lines().any(|l| l == row), "not in the docs: {row}");
    }
}

/// A damper's blow-off is listed under its sweep keys, so its plausible range is warned on; a
/// table's points are listed as text and not checked against the blow-off's range.
#[test]
fn a_blow_off_outside_its_plausible_range_is_warned_on() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("studies");
    let text = std::fs::read_to_string(dir.join("passenger-car-s1002.toml")).expect("study");
    let shipped = "blow_off_force = \"3000 N\", slope_after = \"20 kN s/m\"";
    assert!(text.contains(shipped));
    let key = "secondary.yaw_damper_force_velocity";
    let plan = crate::study::parse_in(&text, "shipped", Some(&dir)).expect("valid");
    let listed = entries(&plan);
    let number = |k: &str| {
        listed
            .iter()
            .find(|e| e.key == k)
            .map(|e| e.shown.clone())
            .unwrap_or_else(|| panic!("{k} not listed"))
    };
    assert_eq!(
        number(&format!("{key}.blow_off_force")),
        crate::study::entries::Shown::Number(3000.0, Force)
    );
    assert_eq!(
        number(&format!("{key}.slope_after")),
        crate::study::entries::Shown::Number(2e4, Damping)
    );
    let low = text.replace(
        shipped,
        "blow_off_force = \"50 N\", slope_after = \"5 N s/m\"",
    );
    let plan = crate::study::parse_in(&low, "low", Some(&dir)).expect("valid");
    let keys: Vec<&str> = plan.warnings.iter().map(|w| w.key.as_str()).collect();
    assert_eq!(
        keys,
        [
            format!("{key}.blow_off_force"),
            format!("{key}.slope_after")
        ]
    );
    let table = text.replace(
        shipped,
        "points = [[\"0.01 m/s\", \"50 N\"], [\"0.1 m/s\", \"60 N\"]]",
    );
    let plan = crate::study::parse_in(&table, "table", Some(&dir)).expect("valid");
    assert!(plan.warnings.is_empty(), "{:?}", plan.warnings);
    let shown = entries(&plan)
        .into_iter()
        .find(|e| e.key == key)
        .map(|e| e.shown.to_string());
    // the table's forces are scaled to the study's yaw damping at zero
    let c = match number("secondary.yaw_damping") {
        crate::study::entries::Shown::Number(c, _) => c,
        other => panic!("{other:?}"),
    };
    let factor = c / (50.0 / 0.01);
    let expected = format!(
        "[0.01 m/s, {} N], [0.1 m/s, {} N], then {} N s/m",
        si(50.0 * factor),
        si(60.0 * factor),
        si((60.0 - 50.0) / (0.1 - 0.01) * factor)
    );
    assert_eq!(shown.as_deref(), Some(expected.as_str()));
}
