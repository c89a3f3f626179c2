//! No legend hides data: every figure the shipped studies write, read back as SVG.
//!
//! Each study in `studies/` is run as a user runs it (the binary, the study as shipped) with
//! the commands whose figures it has: `run` (geometry, linear spectra, the diagram), `sweep`
//! and `trade` where it has those sections, `curve` where the curve is cheap, `conicity`,
//! `simulate` and `ramp` on one wheelset and one vehicle. Every `.svg` written is read back
//! by `critspeed::plot::legend_clashes`, which looks at the drawn elements (not at the
//! geometry the placement used): no legend box may cover a data mark, a reference line, a
//! reference line's label or another text.
//!
//! The costly figures are checked where their results are computed anyway: the S1002 bogie's
//! attractors (tests/attractors.rs, the numbering test), the DTU car's yaw-damper trade with
//! its curves and diagrams (tests/trade_curve.rs, the settlement test).

mod common;

use common::{assert_legend_free, assert_legends_free, critspeed, root, scratch};
use std::path::Path;

/// Runs `args` (then the study's path) into `dir/out`, asserting success.
fn run(dir: &Path, args: &[&str], study: &str) {
    let path = root().join("studies").join(format!("{study}.toml"));
    let mut all = vec!["--out", "out"];
    all.extend_from_slice(args);
    all.push(path.to_str().expect("utf-8 path"));
    let out = critspeed(&all, dir);
    assert!(
        out.status.success(),
        "{study} {args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
}

/// The sections a shipped study has, from its text.
fn sections(study: &str) -> String {
    std::fs::read_to_string(root().join("studies").join(format!("{study}.toml")))
        .expect("study text")
}

/// Every shipped study but the whole cars with diagrams (their own tests below) and the
/// passenger car's V_NL map (nine diagrams and searches of that car: about 40 min on two cores,
/// docs/vehicles.md; its heat map is drawn by the same code as the trade study's).
fn small_studies() -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(root().join("studies"))
        .expect("studies/")
        .flatten()
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .filter_map(|p| Some(p.file_stem()?.to_str()?.to_string()))
        .filter(|n| {
            !n.starts_with("dtu-cooperrider-car")
                && n != "dtu-car-yaw-damper-trade"
                && n != "passenger-car-s1002"
                && n != "passenger-car-yaw-damper-vnl"
        })
        .collect();
    names.sort();
    names
}

#[test]
fn every_figure_of_the_wheelset_and_bogie_studies_leaves_the_data_free() {
    let dir = scratch("small");
    let studies = small_studies();
    assert!(studies.len() >= 15, "{studies:?}");
    for s in &studies {
        let text = sections(s);
        run(&dir, &["run"], s);
        if text.contains("[sweep]") {
            run(&dir, &["sweep"], s);
            if text.contains("[trade]") {
                run(&dir, &["trade"], s);
            }
        }
        // the cheap curves; the DTU bogie's and the period-doubling flange's are tests/curve.rs's
        if text.contains("[curve]") && ["cubic-fold", "flange-hysteresis"].contains(&s.as_str()) {
            run(&dir, &["curve"], s);
        }
        if !text.contains("[vehicle]") {
            run(&dir, &["conicity"], s);
        }
    }
    run(
        &dir,
        &["simulate", "--speed", "60,120", "--duration", "3 s"],
        "s1002-uic60",
    );
    run(&dir, &["ramp"], "seed-hunting-cone");
    let (files, legends) = assert_legends_free(&dir.join("out"));
    // every study drew its figures, and legends were there to check
    assert!(files.len() >= 3 * studies.len(), "{}", files.len());
    assert!(
        legends >= studies.len(),
        "{legends} legends in {} files",
        files.len()
    );
}

#[test]
fn every_figure_of_the_dtu_car_on_its_table_leaves_the_data_free() {
    let dir = scratch("car");
    run(&dir, &["run"], "dtu-cooperrider-car");
    run(
        &dir,
        &["simulate", "--speed", "100", "--duration", "2 s"],
        "dtu-cooperrider-car",
    );
    let (files, legends) = assert_legends_free(&dir.join("out"));
    assert!(files.len() >= 4 && legends >= 2, "{files:?} {legends}");
}

#[test]
fn every_figure_of_the_s1002_car_leaves_the_data_free() {
    let dir = scratch("car-s1002");
    run(&dir, &["run"], "dtu-cooperrider-car-s1002");
    let (files, legends) = assert_legends_free(&dir.join("out"));
    assert!(files.len() >= 4 && legends >= 2, "{files:?} {legends}");
}

/// The passenger car (36 states: its yaw dampers' strokes) draws its linear figures and its
/// curves over the yaw-damper rate with the data free. Its whole diagram is not drawn here: one
/// continuation of this car takes over 20 minutes (docs/vehicles.md).
#[test]
fn every_linear_and_curve_figure_of_the_passenger_car_leaves_the_data_free() {
    let dir = scratch("passenger-car");
    run(&dir, &["linear"], "passenger-car-s1002");
    run(&dir, &["curve"], "passenger-car-s1002");
    let (files, legends) = assert_legends_free(&dir.join("out"));
    assert!(files.len() >= 3 && legends >= 2, "{files:?} {legends}");
}

/// The pictures the manual shows never hide data either.
#[test]
fn the_manuals_pictures_leave_the_data_free() {
    let (files, legends) = assert_legends_free(&root().join("docs/images"));
    assert!(files.len() >= 8 && legends >= 5, "{files:?} {legends}");
}

/// The checker itself sees a legend over data: a figure whose every place inside the plot is
/// covered, drawn with its legend forced inside by hand-written SVG, is caught.
#[test]
fn the_check_catches_a_legend_over_a_line() {
    let svg = r##"<svg><polyline fill="none" stroke="#0072B2" points="0,50 500,50"/><rect x="10" y="10" width="200" height="100" opacity="0.9" fill="#FFFFFF" stroke="none"/></svg>"##;
    assert_eq!(critspeed::plot::legend_clashes(svg).len(), 1);
    let free = svg.replace("0,50 500,50", "0,150 500,150");
    assert_legend_free(&free, "a line below the legend");
}
