//! `critspeed conicity`: EN 15302 equivalent conicity against amplitude.

use std::path::{Path, PathBuf};

use anyhow::anyhow;
use serde_json::json;

use super::commands::{argument, build, compute, load, user, write};
use super::console::{self, statusln};
use super::Failure;
use crate::conicity::{Conicity, DeltaR};
use crate::figures;
use crate::study::units::Dimension;

/// The conicity command's arguments, as typed.
#[derive(Debug, clap::Args)]
pub struct ConicityArgs {
    /// Study file (TOML): Δr = r_R − r_L from its contact geometry.
    #[arg(required_unless_present = "delta_r", conflicts_with = "delta_r")]
    pub study: Option<PathBuf>,
    /// A rolling-radius-difference table instead: CSV with header `y_mm,delta_r_mm`.
    #[arg(long)]
    pub delta_r: Option<PathBuf>,
    /// Amplitudes, comma-separated, with units: --amplitudes 1mm,2mm,3mm
    /// (default 0.5 mm to 10 mm by 0.5 mm, as far as the table reaches).
    #[arg(long, value_delimiter = ',')]
    pub amplitudes: Vec<String>,
    /// Print one JSON object {"amplitude_m": [...], "equivalent_conicity": [...]} on stdout.
    #[arg(long)]
    pub json: bool,
}

/// Runs `critspeed conicity`.
pub fn run(a: &ConicityArgs, root: &Path) -> Result<(), Failure> {
    let (name, table) = match (&a.study, &a.delta_r) {
        (_, Some(file)) => {
            let stem = file
                .file_stem()
                .map_or("delta_r".into(), |s| s.to_string_lossy().to_string());
            (stem, DeltaR::read(file).map_err(user)?)
        }
        (Some(study), None) => {
            let plan = load(study)?;
            let model = build(&plan)?;
            let pts = model.contact.table.rolling_radius_difference();
            (
                plan.name.clone(),
                DeltaR::new(pts, &plan.name).map_err(compute)?,
            )
        }
        (None, None) => return Err(user(anyhow!("give a STUDY or --delta-r FILE"))),
    };
    let amplitudes: Vec<f64> = if a.amplitudes.is_empty() {
        (1..=20).map(|k| k as f64 * 0.5e-3).collect()
    } else {
        a.amplitudes
            .iter()
            .map(|s| argument("--amplitudes", s, Dimension::Length))
            .collect::<Result<_, _>>()?
    };
    let mut results: Vec<Conicity> = Vec::new();
    for &amp in &amplitudes {
        match table.equivalent_conicity(amp) {
            Ok(c) => results.push(c),
            // explicit amplitudes must all work; the default list stops at the table's end
            Err(e) if !a.amplitudes.is_empty() => return Err(user(anyhow!(e))),
            Err(e) => statusln!("  {:.1} mm: {e}", amp * 1e3),
        }
    }
    if results.is_empty() {
        return Err(user(anyhow!("no amplitude fits the Δr table")));
    }
    let dir = root.join(&name);
    std::fs::create_dir_all(&dir).map_err(compute)?;
    let mut csv = String::from("amplitude_m,equivalent_conicity,turning_low_m,turning_high_m\n");
    for c in &results {
        csv.push_str(&format!(
            "{},{},{},{}\n",
            c.amplitude_m, c.conicity, c.turning_m.0, c.turning_m.1
        ));
    }
    write(&dir, "conicity.csv", csv.as_bytes())?;
    let svg = figures::conicity(&name, &results).map_err(|e| compute(anyhow!(e)))?;
    write(&dir, "conicity.svg", svg.as_bytes())?;
    if a.json {
        let j = json!({
            "amplitude_m": results.iter().map(|c| c.amplitude_m).collect::<Vec<_>>(),
            "equivalent_conicity": results.iter().map(|c| c.conicity).collect::<Vec<_>>(),
        });
        let text = serde_json::to_string_pretty(&j).map_err(compute)?;
        console::results(&format!("{text}\n"))?;
    } else {
        let mut text = format!(
            "\n'{name}': equivalent conicity (EN 15302, wavelength of the kinematic oscillation)\n"
        );
        text += &format!(
            "  centre (Δr = 0) at {:.4} mm\n",
            table.centre().map_err(user)? * 1e3
        );
        for c in &results {
            text += &format!(
                "  amplitude {:6.2} mm: {:.4}\n",
                c.amplitude_m * 1e3,
                c.conicity
            );
        }
        console::results(&text)?;
    }
    Ok(())
}
