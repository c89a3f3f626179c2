//! Equivalent conicity against EN 15302's benchmark (Annex E reference Δr functions, Annex F
//! tolerances), as transcribed by criogenox/B_ECC-Equivalent-Conicity-Calculation (MIT) in
//! `tests/data/en15302_*` (source in each file's header and in tests/data/README.md).

use critspeed::conicity::DeltaR;
use std::collections::BTreeMap;

mod common;
use common::reference;

fn rows(text: &str) -> Vec<Vec<String>> {
    text.lines()
        .filter(|l| !l.starts_with('#') && !l.trim().is_empty())
        .skip(1)
        .map(|l| l.split(',').map(|s| s.trim().to_string()).collect())
        .collect()
}

#[test]
fn en15302_benchmark_cases_within_the_standards_tolerance() {
    let mut cases: BTreeMap<String, Vec<(f64, f64)>> = BTreeMap::new();
    for r in rows(&reference("en15302_delta_r_reference.csv")) {
        let (y, d): (f64, f64) = (r[1].parse().expect("y"), r[2].parse().expect("dr"));
        cases
            .entry(r[0].clone())
            .or_default()
            .push((y * 1e-3, d * 1e-3));
    }
    let tables: BTreeMap<String, DeltaR> = cases
        .into_iter()
        .map(|(c, p)| (c.clone(), DeltaR::new(p, &c).expect("valid table")))
        .collect();
    let (mut inside, mut evaluated, mut skipped) = (0, 0, 0);
    let mut worst: f64 = 0.0;
    for r in rows(&reference("en15302_equivalent_conicity_reference.csv")) {
        let Some(table) = tables.get(&r[0]) else {
            continue;
        };
        let f = |k: usize| -> f64 { r[k].parse().expect("number") };
        let (amp_mm, reference, upper, lower) = (f(1), f(2), f(3), f(4));
        match table.equivalent_conicity(amp_mm * 1e-3) {
            Ok(c) => {
                evaluated += 1;
                worst = worst.max((c.conicity - reference).abs());
                assert!(
                    (lower..=upper).contains(&c.conicity),
                    "{} at {amp_mm} mm: {} outside [{lower}, {upper}] (reference {reference})",
                    r[0],
                    c.conicity
                );
                inside += 1;
            }
            Err(e) => {
                // only amplitudes whose swing leaves the tabulated y range may be skipped
                let (lo, hi) = table.range();
                let centre = table.centre().expect("a centre");
                let room = (hi - centre).min(centre - lo);
                assert!(
                    matches!(e, critspeed::conicity::ConicityError::OutOfRange { .. })
                        && amp_mm * 1e-3 > room - 2e-3,
                    "{} at {amp_mm} mm: {e}",
                    r[0]
                );
                skipped += 1;
            }
        }
    }
    eprintln!(
        "EN 15302: {inside}/{evaluated} inside the tolerance, largest |λe − reference| = {worst:.4}, {skipped} amplitudes beyond the Δr tables"
    );
    assert!(evaluated >= 200, "{evaluated} evaluated");
    assert!(skipped * 4 <= evaluated, "{skipped} skipped of {evaluated}");
}

/// Two independent routes agree: the EN 15302 conicity of the seed's cone-on-arc Δr (from the
/// rigid contact table) at small amplitude equals the slope dr_R/dy at the centre that the
/// linear analysis uses (exact, from dual numbers).
#[test]
fn seed_geometry_conicity_matches_the_linear_model() {
    let plan = critspeed::study::parse(critspeed::study::DEFAULT_STUDY, "seed").expect("seed");
    let model = plan.wheelset_model().expect("model");
    let dr = DeltaR::new(model.table.rolling_radius_difference(), "seed").expect("table");
    let c = dr.equivalent_conicity(1e-3).expect("fits");
    let lin = model.centre_conicity();
    assert!(
        (c.conicity - lin).abs() < 1e-4 * lin,
        "{} vs {lin}",
        c.conicity
    );
}
