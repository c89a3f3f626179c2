//! Helpers shared by the integration tests (each test file uses only some of them).
#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// Runs the real binary with `args` in `cwd`.
pub fn critspeed(args: &[&str], cwd: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_critspeed"))
        .args(args)
        .current_dir(cwd)
        .output()
        .expect("the binary runs")
}

/// An empty scratch folder for one test, named after the test file, `name` and the process.
pub fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!(
        "critspeed-{}-{name}-{}",
        env!("CARGO_CRATE_NAME"),
        std::process::id()
    ));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("temp dir");
    dir
}

/// A geometry table: a comment line, `header`, then one row `row(y)` per y (m).
pub fn table_text(header: &str, ys: &[f64], row: impl Fn(f64) -> Vec<f64>) -> String {
    let mut s = format!("# test table\n{header}\n");
    for &y in ys {
        let cells: Vec<String> = row(y).iter().map(|v| format!("{v:e}")).collect();
        s += &cells.join(",");
        s.push('\n');
    }
    s
}

/// `n` points spread uniformly over [−half, half].
pub fn grid(n: usize, half: f64) -> Vec<f64> {
    (0..n)
        .map(|i| -half + 2.0 * half * i as f64 / (n - 1) as f64)
        .collect()
}

/// studies/dtu-cooperrider-bogie.toml with `lines` added to its `[section]`, its table named by
/// absolute path.
pub fn dtu_bogie_text(section: &str, lines: &str) -> String {
    let text =
        std::fs::read_to_string(root().join("studies/dtu-cooperrider-bogie.toml")).expect("study");
    let table = root().join("studies/tables/dtu-rsgeo-1o40.csv");
    text.replace(
        "\"tables/dtu-rsgeo-1o40.csv\"",
        &format!("{:?}", table.to_str().expect("utf-8")),
    )
    .replace(&format!("[{section}]"), &format!("[{section}]\n{lines}"))
}

/// [`dtu_bogie_text`] written to `dir/bogie.toml`.
pub fn dtu_bogie_with(dir: &Path, section: &str, lines: &str) -> PathBuf {
    let path = dir.join("bogie.toml");
    std::fs::write(&path, dtu_bogie_text(section, lines)).expect("write");
    path
}

/// The crate's folder.
pub fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// A published reference file from `tests/data/` (source and licence in `tests/data/README.md`).
pub fn reference(name: &str) -> String {
    let path = root().join("tests/data").join(name);
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// The lowest linear (Kalker or the model's law) critical speed V_L (m/s) of `model` over
/// `range` (m/s); panics naming the search's result when no onset lies in the range.
pub fn v_l_in<const N: usize>(model: &critspeed::model::Vehicle, range: (f64, f64)) -> f64 {
    use critspeed::stability::{critical_speeds, LinearOptions, LinearSystem};
    assert_eq!(model.states(), N, "the model's state size");
    let opts = LinearOptions {
        speed_range: range,
        ..LinearOptions::default()
    };
    let sys = LinearSystem::<N>::at_centre(model);
    let found = critical_speeds(&sys, model.creep_law(), &opts).expect("search runs");
    found
        .critical()
        .unwrap_or_else(|| panic!("no onset in range: {found:?}"))
        .speed_m_s
}

/// Every wheelset's largest lateral excursion (m) over the last 10 s of a plain 150 s
/// simulation of `model` at `speed` from `x0` (rtol 1e-8): hunting or not, by an integration
/// that shares nothing with the attractor search but the right-hand side.
pub fn excursion_after_150_s<const N: usize>(
    model: &critspeed::model::Vehicle,
    speed: f64,
    x0: &nalgebra::SVector<f64, N>,
) -> f64 {
    use critspeed::system::ode::{integrate, integrate_with_extremes, OdeOptions, Tolerances};
    let opts = OdeOptions {
        tol: Tolerances::new(1e-8, 1e-11).expect("valid"),
        ..OdeOptions::default()
    };
    let x = integrate(model, speed, x0, 140.0, &opts).expect("140 s").x;
    let (_, high, low) = integrate_with_extremes(model, speed, &x, 10.0, &opts).expect("10 s");
    model
        .wheelset_dofs()
        .iter()
        .map(|&d| high[d].abs().max(low[d].abs()))
        .fold(0.0, f64::max)
}

/// The death bracket [lo, hi] (m/s) of the attractor that sets the search's V_NL, and every
/// wheelset's largest excursion (m) after 150 s at lo and at hi ([`excursion_after_150_s`]),
/// both started from the attractor's state at hi (the last speed where the search saw it).
pub fn excursions_across_death<const N: usize>(
    model: &critspeed::model::Vehicle,
    report: &critspeed::attractors::AttractorReport,
) -> ((f64, f64), f64, f64) {
    let (_, bracket, id) = report.nonlinear_critical_speed.expect("an attractor");
    let (lo, hi) = bracket.expect("a bracket");
    let a = report
        .attractors
        .iter()
        .find(|a| a.id == id)
        .expect("V_NL's attractor");
    let alive = a.path.last().expect("a path");
    assert_eq!(alive.speed_m_s, hi);
    let x0 = nalgebra::SVector::<f64, N>::from_iterator(alive.state.iter().copied());
    (
        (lo, hi),
        excursion_after_150_s(model, lo, &x0),
        excursion_after_150_s(model, hi, &x0),
    )
}

/// The sparse variational product $JΦ$ of `model` at `x` equals the dense product of `jac`
/// (the exact Jacobian, column-major as `Vehicle::jacobian_into` writes it) with a fixed Φ, to
/// 1e-12 of each entry's largest term, and its f equals `f` bit for bit; the tangent product
/// $Jξ$ equals the dense one with a fixed ξ, to 1e-10 of each entry's largest term, its f `f`
/// to 1e-12.
pub fn assert_variational_is_the_dense_product<const N: usize>(
    model: &critspeed::model::Vehicle,
    x: &[f64],
    speed: f64,
    jac: &[f64],
    f: &[f64],
) {
    use critspeed::system::ode::VectorField;
    use nalgebra::{SMatrix, SVector};
    let xs = SVector::<f64, N>::from_column_slice(x);
    let phi = SMatrix::<f64, N, N>::from_fn(|r, c| ((r * 7 + c * 3) % 11) as f64 - 5.0);
    let (fv, jphi) = VectorField::<N>::rhs_variational(model, &xs, speed, &phi);
    let jm = SMatrix::<f64, N, N>::from_column_slice(jac);
    let dense = jm * phi;
    for r in 0..N {
        assert_eq!(fv[r], f[r], "f row {r}");
        for c in 0..N {
            let scale = (0..N).fold(1e-300_f64, |s, k| s.max((jm[(r, k)] * phi[(k, c)]).abs()));
            assert!(
                (jphi[(r, c)] - dense[(r, c)]).abs() <= 1e-12 * scale,
                "JΦ[{r}][{c}]: {} vs {}",
                jphi[(r, c)],
                dense[(r, c)]
            );
        }
    }
    let xi = SVector::<f64, N>::from_fn(|r, _| ((r * 7 + 9) % 11) as f64 - 5.0);
    let (ft, jxi) = VectorField::<N>::rhs_tangent(model, &xs, speed, &xi);
    let want = jm * xi;
    for r in 0..N {
        assert!(
            (ft[r] - f[r]).abs() <= 1e-12 * f[r].abs().max(1.0),
            "f row {r}"
        );
        let scale = (0..N).fold(1e-300_f64, |s, k| s.max((jm[(r, k)] * xi[k]).abs()));
        assert!(
            (jxi[r] - want[r]).abs() <= 1e-10 * scale,
            "Jξ[{r}]: {} vs {}",
            jxi[r],
            want[r]
        );
    }
}

/// The exact Jacobian `jac` of `model` at `x` (column-major, as `Vehicle::jacobian_into` writes
/// it) equals central differences of f with step `h`: each entry to `tol` of max(|J|, 1).
/// Returns the worst relative difference.
pub fn assert_jacobian_is_central_differences(
    model: &critspeed::model::Vehicle,
    x: &[f64],
    speed: f64,
    jac: &[f64],
    (h, tol): (f64, f64),
) -> f64 {
    let n = x.len();
    let mut worst = 0.0_f64;
    for c in 0..n {
        let (mut xp, mut xm) = (x.to_vec(), x.to_vec());
        xp[c] += h;
        xm[c] -= h;
        let (mut fp, mut fm) = (vec![0.0; n], vec![0.0; n]);
        model.rhs_into(&xp, speed, &mut fp);
        model.rhs_into(&xm, speed, &mut fm);
        for r in 0..n {
            let fd = (fp[r] - fm[r]) / (2.0 * h);
            let exact = jac[c * n + r];
            let err = (fd - exact).abs() / exact.abs().max(1.0);
            worst = worst.max(err);
            assert!(err <= tol, "J[{r}][{c}]: {exact} vs difference {fd}");
        }
    }
    worst
}

/// $f(−x) = −f(x)$ for `model` at `x` (whose f is `f`), to 1e-13 of the largest |f|.
pub fn assert_odd(model: &critspeed::model::Vehicle, x: &[f64], speed: f64, f: &[f64]) {
    let xm: Vec<f64> = x.iter().map(|a| -a).collect();
    let mut g = vec![0.0; f.len()];
    model.rhs_into(&xm, speed, &mut g);
    let scale = f.iter().fold(0.0_f64, |m, a| m.max(a.abs()));
    for (i, (a, b)) in f.iter().zip(&g).enumerate() {
        assert!((a + b).abs() <= 1e-13 * scale, "row {i}");
    }
}

/// Every `.svg` under `dir` (recursively), after asserting that no legend box in it hides a
/// data mark, a reference line's label or a text (`critspeed::plot::legend_clashes`, which
/// reads the SVG as drawn). Returns the files and how many legend boxes were checked.
pub fn assert_legends_free(dir: &Path) -> (Vec<PathBuf>, usize) {
    fn walk(dir: &Path, out: &mut Vec<PathBuf>) {
        for e in std::fs::read_dir(dir).expect("a folder").flatten() {
            let p = e.path();
            if p.is_dir() {
                walk(&p, out);
            } else if p.extension().is_some_and(|x| x == "svg") {
                out.push(p);
            }
        }
    }
    let mut files = Vec::new();
    walk(dir, &mut files);
    files.sort();
    let mut legends = 0;
    for f in &files {
        let svg = std::fs::read_to_string(f).expect("svg text");
        assert_legend_free(&svg, &f.display().to_string());
        legends += critspeed::plot::legend_count(&svg);
    }
    (files, legends)
}

/// Asserts that no legend box of `svg` (named `what` in the message) hides anything.
pub fn assert_legend_free(svg: &str, what: &str) {
    let clashes = critspeed::plot::legend_clashes(svg);
    assert!(
        clashes.is_empty(),
        "{what}: {} clash(es), first {:?}",
        clashes.len(),
        clashes.iter().take(3).collect::<Vec<_>>()
    );
}
