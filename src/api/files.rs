//! The files each command writes, as `(file name, bytes)` in the order the CLI writes them,
//! and the one function that writes them.

use std::path::{Path, PathBuf};

use anyhow::{anyhow, Context};

use super::{compute, Failure};
use crate::analysis::{GeometryReport, LinearReport};
use crate::bifurcation::BifurcationReport;
use crate::conicity::Conicity;
use crate::figures;
use crate::output;
use crate::simulate::TimeHistory;
use crate::sweep::{PointRecord, SweepStudy};

/// A file's name and contents.
pub type File = (String, Vec<u8>);

fn json_text(v: &serde_json::Value) -> Result<String, Failure> {
    serde_json::to_string_pretty(v).map_err(compute)
}

fn plot(e: crate::plot::PlotError) -> Failure {
    compute(anyhow!(e))
}

/// `linear.json`, `spectrum.csv` and the linear figures.
pub fn linear(r: &LinearReport) -> Result<Vec<File>, Failure> {
    let mut f = vec![
        (
            "linear.json".into(),
            json_text(&output::linear_json(r))?.into_bytes(),
        ),
        ("spectrum.csv".into(), output::spectrum_csv(r).into_bytes()),
    ];
    for (name, svg) in figures::linear(r).map_err(plot)? {
        f.push((name, svg.into_bytes()));
    }
    Ok(f)
}

/// `bifurcation.json`, `branch.csv` and `bifurcation.svg`.
pub fn bifurcation(r: &BifurcationReport) -> Result<Vec<File>, Failure> {
    Ok(vec![
        (
            "bifurcation.json".into(),
            json_text(&output::bifurcation_json(r))?.into_bytes(),
        ),
        ("branch.csv".into(), output::branch_csv(r).into_bytes()),
        (
            "bifurcation.svg".into(),
            figures::bifurcation(r).map_err(plot)?.into_bytes(),
        ),
    ])
}

/// `attractors.json`, `attractors.csv` and `attractors.svg` (with the continuation `b` that
/// ran before the search).
pub fn attractors(
    r: &crate::attractors::AttractorReport,
    b: &BifurcationReport,
) -> Result<Vec<File>, Failure> {
    Ok(vec![
        (
            "attractors.json".into(),
            json_text(&output::attractors_json(r, b))?.into_bytes(),
        ),
        (
            "attractors.csv".into(),
            output::attractors_csv(r).into_bytes(),
        ),
        (
            "attractors.svg".into(),
            figures::attractors(r, b).map_err(plot)?.into_bytes(),
        ),
    ])
}

/// `simulate.csv` and `simulate.svg`.
pub fn simulate(study: &str, runs: &[TimeHistory]) -> Result<Vec<File>, Failure> {
    Ok(vec![
        (
            "simulate.csv".into(),
            output::simulate_csv(runs).into_bytes(),
        ),
        (
            "simulate.svg".into(),
            figures::simulate(study, runs).map_err(plot)?.into_bytes(),
        ),
    ])
}

/// `geometry.csv` and `geometry.svg`.
pub fn geometry(g: &GeometryReport) -> Result<Vec<File>, Failure> {
    Ok(vec![
        ("geometry.csv".into(), output::geometry_csv(g).into_bytes()),
        (
            "geometry.svg".into(),
            figures::geometry(g).map_err(plot)?.into_bytes(),
        ),
    ])
}

/// `sweep.csv` and the sweep's figures.
pub fn sweep(study: &SweepStudy, rows: &[PointRecord]) -> Result<Vec<File>, Failure> {
    let mut f = vec![(
        "sweep.csv".into(),
        crate::sweep::sweep_csv(&study.spec.axes, rows).into_bytes(),
    )];
    for (name, svg) in figures::sweep(&study.base.name, &study.spec, rows).map_err(plot)? {
        f.push((name, svg.into_bytes()));
    }
    Ok(f)
}

/// The text of `conicity.csv`.
pub fn conicity_csv(results: &[Conicity]) -> String {
    let mut csv = String::from("amplitude_m,equivalent_conicity,turning_low_m,turning_high_m\n");
    for c in results {
        csv.push_str(&format!(
            "{},{},{},{}\n",
            c.amplitude_m, c.conicity, c.turning_m.0, c.turning_m.1
        ));
    }
    csv
}

/// `conicity.csv` and `conicity.svg`.
pub fn conicity(name: &str, results: &[Conicity]) -> Result<Vec<File>, Failure> {
    Ok(vec![
        ("conicity.csv".into(), conicity_csv(results).into_bytes()),
        (
            "conicity.svg".into(),
            figures::conicity(name, results).map_err(plot)?.into_bytes(),
        ),
    ])
}

/// The folder `root/name`, created if needed.
pub fn folder(root: &Path, name: &str) -> Result<PathBuf, Failure> {
    output::study_dir(root, name)
        .with_context(|| format!("creating {}", root.join(name).display()))
        .map_err(compute)
}

/// Writes `files` into `dir`, calling `wrote` with each path written.
pub fn write(dir: &Path, files: &[File], wrote: &mut dyn FnMut(&Path)) -> Result<(), Failure> {
    for (name, bytes) in files {
        let path = output::write(dir, name, bytes)
            .with_context(|| format!("writing {}", dir.join(name).display()))
            .map_err(compute)?;
        wrote(&path);
    }
    Ok(())
}
