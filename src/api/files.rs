//! The files each command writes, as `(file name, bytes)` in the order the CLI writes them,
//! and the one function that writes them.

use std::path::{Path, PathBuf};

use anyhow::Context;

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

/// The files of a command, and what is wrong with them: figures that could not be drawn are
/// written as a note saying why (the numbers files hold the results), and said here.
#[derive(Debug, Default)]
pub struct Output {
    /// `(file name, bytes)` in the order the CLI writes them
    pub files: Vec<File>,
    /// one message per figure written as a note, naming the file, the reason and the numbers
    pub warnings: Vec<String>,
}

impl Output {
    pub(crate) fn text(mut self, name: &str, text: String) -> Self {
        self.files.push((name.into(), text.into_bytes()));
        self
    }

    /// A figure, or the note in its place; `numbers` names the files that hold its results.
    pub(crate) fn figure(mut self, f: figures::Rendered, numbers: &str) -> Self {
        let d = crate::plot::drawing(&f.file, f.svg, numbers, f.size);
        if let Some(why) = d.empty {
            self.warnings.push(format!(
                "{} has nothing to draw ({why}); written as a note, the results are in {numbers}",
                f.file
            ));
        }
        self.files.push((f.file, d.svg.into_bytes()));
        self
    }

    fn figures(self, fs: Vec<figures::Rendered>, numbers: &str) -> Self {
        fs.into_iter().fold(self, |o, f| o.figure(f, numbers))
    }
}

/// A figure written where a command writes its own files (`ramp.svg`, `trade.svg`): its bytes
/// and, when it is a note, the warning.
pub fn figure(f: figures::Rendered, numbers: &str) -> (Vec<u8>, Option<String>) {
    let mut o = Output::default().figure(f, numbers);
    (
        o.files.pop().map(|f| f.1).unwrap_or_default(),
        o.warnings.pop(),
    )
}

fn json_text(v: &serde_json::Value) -> Result<String, Failure> {
    serde_json::to_string_pretty(v).map_err(compute)
}

/// `linear.json`, `spectrum.csv` and the linear figures.
pub fn linear(r: &LinearReport) -> Result<Output, Failure> {
    Ok(Output::default()
        .text("linear.json", json_text(&output::linear_json(r))?)
        .text("spectrum.csv", output::spectrum_csv(r))
        .figures(figures::linear(r), "linear.json and spectrum.csv"))
}

/// `bifurcation.json`, `branch.csv` and `bifurcation.svg`.
pub fn bifurcation(r: &BifurcationReport) -> Result<Output, Failure> {
    Ok(Output::default()
        .text("bifurcation.json", json_text(&output::bifurcation_json(r))?)
        .text("branch.csv", output::branch_csv(r))
        .figure(figures::bifurcation(r), "bifurcation.json and branch.csv"))
}

/// `attractors.json`, `attractors.csv` and `attractors.svg` (with the continuation `b` that
/// ran before the search).
pub fn attractors(
    r: &crate::attractors::AttractorReport,
    b: &BifurcationReport,
) -> Result<Output, Failure> {
    Ok(Output::default()
        .text(
            "attractors.json",
            json_text(&output::attractors_json(r, b))?,
        )
        .text("attractors.csv", output::attractors_csv(r))
        .figure(
            figures::attractors(r, b),
            "attractors.json and attractors.csv",
        ))
}

/// `simulate.csv` and `simulate.svg`.
pub fn simulate(study: &str, runs: &[TimeHistory]) -> Output {
    Output::default()
        .text("simulate.csv", output::simulate_csv(runs))
        .figure(figures::simulate(study, runs), "simulate.csv")
}

/// `geometry.csv` and `geometry.svg`.
pub fn geometry(g: &GeometryReport) -> Output {
    Output::default()
        .text("geometry.csv", output::geometry_csv(g))
        .figure(figures::geometry(g), "geometry.csv")
}

/// `sweep.csv` and the sweep's figures; a one-axis sweep's figure with the curves of the
/// study's `[curve]` section when its key is the axis' ([`super::curve::sweep_curves`]).
pub fn sweep(study: &SweepStudy, rows: &[PointRecord]) -> Output {
    let (curves, warnings) = super::curve::sweep_curves(study);
    let mut out = Output::default()
        .text("sweep.csv", crate::sweep::sweep_csv(&study.spec.axes, rows))
        .figures(
            figures::sweep_with_curves(&study.base.name, &study.spec, rows, curves.as_ref()),
            "sweep.csv",
        );
    out.warnings.extend(warnings);
    out
}

/// `uncertainty.json`, `uncertainty.csv` and the figure of an uncertainty study's results.
pub fn uncertainty(
    study: &crate::uncertainty::UncertaintyStudy,
    report: &crate::uncertainty::UncertaintyReport,
    rows: &[PointRecord],
) -> Result<Output, Failure> {
    let json = serde_json::to_string_pretty(report).map_err(compute)? + "\n";
    Ok(Output::default()
        .text("uncertainty.json", json)
        .text(
            "uncertainty.csv",
            crate::uncertainty::uncertainty_csv(study, rows),
        )
        .figure(figures::uncertainty(report), "uncertainty.csv"))
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
pub fn conicity(name: &str, results: &[Conicity]) -> Output {
    Output::default()
        .text("conicity.csv", conicity_csv(results))
        .figure(figures::conicity(name, results), "conicity.csv")
}

/// The folder `root/name`, created if needed.
pub fn folder(root: &Path, name: &str) -> Result<PathBuf, Failure> {
    output::study_dir(root, name)
        .with_context(|| format!("creating {}", root.join(name).display()))
        .map_err(compute)
}

/// Writes the files into `dir`, calling `wrote` with each path written.
pub fn write(dir: &Path, out: &Output, wrote: &mut dyn FnMut(&Path)) -> Result<(), Failure> {
    for (name, bytes) in &out.files {
        let path = output::write(dir, name, bytes)
            .with_context(|| format!("writing {}", dir.join(name).display()))
            .map_err(compute)?;
        wrote(&path);
    }
    Ok(())
}
