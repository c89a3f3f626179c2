//! Study files: units converted once, physics checked, errors that name key, value and rule.

use critspeed::contact::geometry::Geometry;
use critspeed::contact::table::CreepSource;
use critspeed::study::{self, StudyError, DEFAULT_STUDY};

fn with(replace: &str, by: &str) -> String {
    assert!(
        DEFAULT_STUDY.contains(replace),
        "seed study has {replace:?}"
    );
    DEFAULT_STUDY.replacen(replace, by, 1)
}

fn error_of(text: &str) -> String {
    match study::parse(text, "test") {
        Ok(_) => panic!("study should have been refused"),
        Err(e) => e.to_string(),
    }
}

/// The seed study is docs/model.md §10's table, exactly, in SI.
#[test]
fn seed_study_is_model_section_10() {
    let p = study::parse(DEFAULT_STUDY, "seed").expect("seed study is valid");
    let close = |a: f64, b: f64| (a - b).abs() <= 1e-12 * b.abs();
    let w = p.wheelset;
    assert!(close(w.mass, 1250.0) && close(w.yaw_inertia, 700.0) && close(w.axle_load, 110_000.0));
    assert!(close(w.half_contact_distance, 0.7429) && close(w.rolling_radius, 0.46));
    let s = p.suspension;
    assert!(close(s.lateral_stiffness, 3.86e6) && close(s.longitudinal_stiffness, 8.5e5));
    assert!(close(s.lateral_damping, 8e3) && close(s.longitudinal_damping, 1e5));
    assert!(close(s.half_spring_spacing, 0.9));
    match p.contact.geometry {
        Geometry::ConeOnArc {
            conicity,
            rail_head_radius,
            crown_offset,
        } => {
            assert!(close(conicity, 0.05) && close(rail_head_radius, 0.07937));
            assert!(close(crown_offset, 0.00396));
        }
        g => panic!("seed geometry is cone-on-arc, got {g:?}"),
    }
    match p.contact.creep {
        CreepSource::Given(c) => {
            assert!(close(c.f11, 8.06e6) && close(c.f22, 8.09e6));
            assert!(close(c.f23, 2.2e4) && close(c.f33, 12.7));
        }
        CreepSource::Hertz => panic!("the seed gives its creep coefficients"),
    }
    assert!(close(p.contact.elastic.shear_modulus, 8e10));
    assert!(close(p.contact.elastic.young_modulus, 2.1e11));
}

#[test]
fn every_shipped_study_is_valid() {
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/studies");
    let mut n = 0;
    for entry in std::fs::read_dir(dir).expect("studies/ exists") {
        let path = entry.expect("readable entry").path();
        if path.extension().is_some_and(|e| e == "toml") {
            let plan = study::load(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
            plan.model()
                .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
            n += 1;
        }
    }
    assert!(n >= 2, "at least the seed and one hunting study");
}

#[test]
fn invalid_physics_is_refused_with_key_value_and_rule() {
    let cases = [
        (
            with("mass = \"1250 kg\"", "mass = \"-1250 kg\""),
            "wheelset.mass",
            "-1250 kg",
            "positive",
        ),
        (
            with("conicity = \"1:20\"", "conicity = 0"),
            "contact.conicity",
            "0",
            "(0, 1)",
        ),
        (
            with("conicity = \"1:20\"", "conicity = -0.05"),
            "contact.conicity",
            "-0.05",
            "(0, 1)",
        ),
        (
            with(
                "speed_range = [\"1 m/s\", \"300 m/s\"]",
                "speed_range = [\"50 m/s\", \"50 m/s\"]",
            ),
            "linear.speed_range",
            "[50, 50] m/s",
            "exceed",
        ),
        (
            with("poisson_ratio = 0.3", "poisson_ratio = 0.7"),
            "contact.poisson_ratio",
            "0.7",
            "(0, 0.5)",
        ),
        (
            with(
                "lateral_damping = \"8 N s/mm\"",
                "lateral_damping = \"-8 N s/mm\"",
            ),
            "suspension.lateral_damping",
            "-8000 N s/m",
            "negative",
        ),
    ];
    for (text, key, value, rule) in cases {
        let msg = error_of(&text);
        assert!(
            msg.contains(key) && msg.contains(value) && msg.contains(rule),
            "{msg}"
        );
    }
}

#[test]
fn wrong_units_name_the_key_the_value_and_what_was_expected() {
    let msg = error_of(&with(
        "lateral_damping = \"8 N s/mm\"",
        "lateral_damping = \"8 N/mm\"",
    ));
    assert!(msg.contains("suspension.lateral_damping"), "{msg}");
    assert!(
        msg.contains("8 N/mm") && msg.contains("stiffness") && msg.contains("N s/m"),
        "{msg}"
    );
    let msg = error_of(&with(
        "rolling_radius = \"460 mm\"",
        "rolling_radius = \"460 parsecs\"",
    ));
    assert!(
        msg.contains("wheelset.rolling_radius") && msg.contains("parsecs"),
        "{msg}"
    );
}

#[test]
fn unknown_keys_and_choices_are_errors() {
    let msg = error_of(&with("mass = \"1250 kg\"", "mass = \"1250 kg\"\nmas = 3"));
    assert!(msg.contains("mas"), "{msg}");
    let msg = error_of(&with("creep_law = \"shen\"", "creep_law = \"polach\""));
    assert!(
        msg.contains("contact.creep_law") && msg.contains("polach"),
        "{msg}"
    );
    let msg = error_of(&with("geometry = \"cone-on-arc\"", "geometry = \"wedge\""));
    assert!(
        msg.contains("contact.geometry") && msg.contains("wedge") && msg.contains("\"profiles\""),
        "{msg}"
    );
}

#[test]
fn plain_numbers_are_si_and_ratios_are_accepted() {
    let a = study::parse(
        &with("rolling_radius = \"460 mm\"", "rolling_radius = 0.46"),
        "t",
    )
    .expect("valid");
    let b = study::parse(DEFAULT_STUDY, "t").expect("valid");
    assert_eq!(a.wheelset, b.wheelset);
    let c = study::parse(&with("conicity = \"1:20\"", "conicity = 0.05"), "t").expect("valid");
    assert_eq!(c.contact.geometry, b.contact.geometry);
}

#[test]
fn missing_files_and_syntax_errors() {
    let e = study::load(std::path::Path::new("/nonexistent/study.toml"));
    assert!(matches!(e, Err(StudyError::Io { .. })));
    let msg = error_of("name = \"x\"\n[wheelset\n");
    assert!(msg.contains("not valid"), "{msg}");
}

/// Regression: a unit on a pure-number key used to print "expected a pure number in SI () or
/// with one of the units ''".
#[test]
fn a_unit_on_a_pure_number_is_named_as_such() {
    let e = error_of(&with("friction = 0.3", "friction = \"0.3 N\""));
    assert!(
        e.contains("contact.friction") && e.contains("pure number without a unit"),
        "{e}"
    );
    assert!(!e.contains("SI ()"), "{e}");
}

/// `[bifurcation] segments`: 0 (one per thread) to 64; more is refused naming key and value.
#[test]
fn bifurcation_segments_are_checked() {
    let text = format!("{DEFAULT_STUDY}\n[bifurcation]\nsegments = 2\n");
    let p = study::parse(&text, "test").expect("valid");
    assert_eq!(p.bifurcation_options().segments, 2);
    let e = error_of(&format!("{DEFAULT_STUDY}\n[bifurcation]\nsegments = 65\n"));
    assert!(
        e.contains("bifurcation.segments") && e.contains("65"),
        "{e}"
    );
}
