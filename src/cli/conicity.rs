//! `critspeed conicity`: EN 15302 equivalent conicity against amplitude.

use std::path::{Path, PathBuf};

use anyhow::anyhow;

use super::commands::{argument, compute, load, prepare, user, write_all};
use super::console::{self, statusln};
use super::Failure;
use crate::api::{self, files};
use crate::conicity::DeltaR;
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
            let p = prepare(load(study)?)?;
            (p.plan().name.clone(), api::delta_r(&p)?)
        }
        (None, None) => return Err(user(anyhow!("give a STUDY or --delta-r FILE"))),
    };
    let amplitudes: Vec<f64> = if a.amplitudes.is_empty() {
        api::default_amplitudes()
    } else {
        a.amplitudes
            .iter()
            .map(|s| argument("--amplitudes", s, Dimension::Length))
            .collect::<Result<_, _>>()?
    };
    let (results, skipped) = api::conicity(&table, &amplitudes, !a.amplitudes.is_empty())?;
    for s in skipped {
        statusln!("  {s}");
    }
    let dir = root.join(&name);
    std::fs::create_dir_all(&dir).map_err(compute)?;
    write_all(&dir, &files::conicity(&name, &results))?;
    if a.json {
        let text = serde_json::to_string_pretty(&api::conicity_json(&results)).map_err(compute)?;
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
