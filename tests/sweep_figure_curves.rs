//! A one-axis sweep's figure draws the curves of the study's `[curve]` section when its key is
//! the sweep's axis: through `critspeed sweep` and through `critspeed merge` of shards; a
//! sweep without such a section (or with another key, or a two-axis map) is drawn as before.

use std::path::{Path, PathBuf};

mod common;
use common::{critspeed, root, scratch};

/// `studies/seed-stiffness-map.toml` with `sweep` in place of its `[sweep]` and `curve` in
/// place of its `[curve]` section (empty: none).
fn study(sweep: &str, curve: &str) -> String {
    let text =
        std::fs::read_to_string(root().join("studies/seed-stiffness-map.toml")).expect("study");
    let a = text.find("[sweep]").expect("[sweep]");
    let b = text.find("[curve]").expect("[curve]");
    assert!(a < b, "[sweep] comes before [curve]");
    format!("{}{sweep}\n{curve}\n", &text[..a])
}

const ONE_AXIS: &str = "[sweep]\naxes = [ { key = \"suspension.lateral_stiffness\", from = \"100 N/mm\", to = \"3000 N/mm\", count = 6, spacing = \"log\" } ]\ncompute = [\"kalker\", \"hopf\"]\n";
const LATERAL: &str = "[curve]\nkey = \"suspension.lateral_stiffness\"\nfrom = \"100 N/mm\"\nto = \"3000 N/mm\"\nspacing = \"log\"\n";

fn run(dir: &Path, name: &str, text: &str, args: &[&str]) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, text).expect("write study");
    let mut all: Vec<&str> = args.to_vec();
    all.push(path.to_str().expect("utf-8"));
    let out = critspeed(&all, dir);
    assert!(
        out.status.success(),
        "{:?}: {}",
        args,
        String::from_utf8_lossy(&out.stderr)
    );
    dir.join("out/seed-stiffness-map")
}

fn svg(dir: &Path, file: &str) -> String {
    std::fs::read_to_string(dir.join(file)).expect("figure")
}

#[test]
fn the_line_plot_draws_the_hopf_curves_of_a_matching_curve_section() {
    let dir = scratch("match");
    let out = run(&dir, "s.toml", &study(ONE_AXIS, LATERAL), &["sweep"]);
    let s = svg(&out, "sweep.svg");
    assert!(s.contains("V_L(curve)"), "no V_L curve");
    assert!(s.contains("V_H(curve)"), "no V_H curve");
    // the folds are drawn only when the section asks for them
    assert!(!s.contains("V_NL(curve)"));
    // the grid's points are still there
    assert!(s.contains("Kalker critical speed V_L"));
}

#[test]
fn without_a_matching_curve_section_the_figure_is_unchanged() {
    let dir = scratch("nomatch");
    let other = LATERAL.replace("lateral_stiffness", "longitudinal_stiffness");
    let a = svg(
        &run(&dir, "a.toml", &study(ONE_AXIS, ""), &["sweep"]),
        "sweep.svg",
    );
    std::fs::remove_dir_all(dir.join("out")).expect("clean");
    let b = svg(
        &run(&dir, "b.toml", &study(ONE_AXIS, &other), &["sweep"]),
        "sweep.svg",
    );
    assert!(!a.contains("(curve)"));
    assert_eq!(a, b, "a [curve] on another key changed sweep.svg");
    // a map over both keys draws no curves either
    let two = ONE_AXIS.replace(
        "spacing = \"log\" } ]",
        "spacing = \"log\" },\n  { key = \"suspension.longitudinal_stiffness\", from = \"500 N/mm\", to = \"2000 N/mm\", count = 3 } ]",
    );
    std::fs::remove_dir_all(dir.join("out")).expect("clean");
    let out = run(&dir, "c.toml", &study(&two, LATERAL), &["sweep"]);
    let map = svg(&out, "sweep_map_kalker.svg");
    assert!(!map.contains("(curve)"));
}

#[test]
fn merged_shards_draw_the_curves_too() {
    let dir = scratch("merge");
    let text = study(ONE_AXIS, LATERAL);
    run(&dir, "s.toml", &text, &["sweep", "--shard", "0/2"]);
    run(&dir, "s.toml", &text, &["sweep", "--shard", "1/2"]);
    let out = run(&dir, "s.toml", &text, &["merge"]);
    let s = svg(&out, "sweep.svg");
    assert!(s.contains("V_L(curve)") && s.contains("V_H(curve)"));
}

#[test]
fn folds_are_drawn_when_the_curve_section_asks_for_them() {
    let dir = scratch("folds");
    let table = root().join("studies/tables/cubic-fold.csv");
    let text = std::fs::read_to_string(root().join("studies/cubic-fold.toml"))
        .expect("study")
        .replace(
            "\"tables/cubic-fold.csv\"",
            &format!("{:?}", table.to_str().expect("utf-8")),
        )
        .replace("to = 0.6", "to = 0.4\ncurves = [\"hopf\", \"fold\"]")
        + "\n[sweep]\naxes = [ { key = \"contact.friction\", from = 0.15, to = 0.4, count = 3 } ]\ncompute = [\"hopf\"]\n";
    let path = dir.join("cubic.toml");
    std::fs::write(&path, text).expect("write");
    let out = critspeed(&["sweep", path.to_str().expect("utf-8")], &dir);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let s = svg(&dir.join("out/cubic-fold"), "sweep.svg");
    assert!(s.contains("V_NL(curve)") && s.contains("V_H(curve)"));
}
