//! Drivers: run an analysis of a plan and return plain result structs.
//!
//! These are the only functions that know both the model and the analyses; what they
//! return is data that [`crate::output`] and [`crate::plot`] turn into files.

use rayon::prelude::*;

use crate::contact::creep::CreepLaw;
use crate::contact::table::Row;
use crate::model::Wheelset;
use crate::stability::{
    critical_speeds, spectrum_at, CriticalSpeeds, LinearError, LinearSystem, Spectrum,
};
use crate::study::Plan;

/// Everything the linear analysis of a study produces.
#[derive(Clone, Debug)]
pub struct LinearReport {
    /// study name
    pub study: String,
    /// crossings of the Kalker-creep model (the linear critical speed is the first onset)
    pub kalker: CriticalSpeeds,
    /// crossings of the study's creep law's own Jacobian (its Hopf speed), when not Kalker
    pub creep_law: Option<CriticalSpeeds>,
    /// effective conicity at the centre, dr_R/dy(0) (–)
    pub centre_conicity: f64,
    /// kinematic (Klingel) wavelength 2π√(r0 l0/λe) (m)
    pub klingel_wavelength_m: f64,
    /// spectra of the Kalker model on the spectrum grid
    pub spectrum_kalker: Vec<Spectrum>,
    /// spectra of the study's law on the same grid, when not Kalker
    pub spectrum_creep_law: Vec<Spectrum>,
}

impl LinearReport {
    /// Crossings of the study's creep law (Kalker's when the study uses Kalker).
    pub fn law_crossings(&self) -> &CriticalSpeeds {
        self.creep_law.as_ref().unwrap_or(&self.kalker)
    }
}

/// Spectra on `n` speeds spread uniformly over `range`, computed in parallel (order kept).
pub fn spectrum_grid(sys: &LinearSystem, range: (f64, f64), n: usize) -> Vec<Spectrum> {
    let n = n.max(2);
    (0..n)
        .into_par_iter()
        .filter_map(|i| {
            let v = range.0 + (range.1 - range.0) * i as f64 / (n - 1) as f64;
            spectrum_at(&sys.jacobian(v), v)
        })
        .collect()
}

/// The linear analysis: Kalker critical speeds, the creep law's Hopf speeds, spectra.
pub fn linear(plan: &Plan, model: &Wheelset) -> Result<LinearReport, LinearError> {
    let kalker_model = model.with_law(CreepLaw::Kalker);
    let ks = LinearSystem::at_centre(&kalker_model);
    let kalker = critical_speeds(&ks, CreepLaw::Kalker, &plan.linear)?;
    let range = plan.linear.speed_range;
    let spectrum_kalker = spectrum_grid(&ks, range, plan.spectrum_points);
    let (creep_law, spectrum_creep_law) = match model.creep_law {
        CreepLaw::Kalker => (None, Vec::new()),
        law => {
            let ls = LinearSystem::at_centre(model);
            (
                Some(critical_speeds(&ls, law, &plan.linear)?),
                spectrum_grid(&ls, range, plan.spectrum_points),
            )
        }
    };
    Ok(LinearReport {
        study: plan.name.clone(),
        kalker,
        creep_law,
        centre_conicity: model.centre_conicity(),
        klingel_wavelength_m: model.klingel_wavelength(),
        spectrum_kalker,
        spectrum_creep_law,
    })
}

/// The contact geometry table of a study.
#[derive(Clone, Debug)]
pub struct GeometryReport {
    /// study name
    pub study: String,
    /// table nodes, right wheel, increasing y (the grid is symmetric about 0)
    pub rows: Vec<Row>,
    /// effective conicity at the centre (–)
    pub centre_conicity: f64,
    /// contact-point jumps of the right wheel (profile geometries)
    pub jumps: Vec<crate::contact::table::Jump>,
    /// nodes (y, m) where the lateral curvature was held inside Kalker's a/b range
    pub clamped: Vec<f64>,
}

/// The geometry table of a model.
pub fn geometry(plan: &Plan, model: &Wheelset) -> GeometryReport {
    GeometryReport {
        study: plan.name.clone(),
        rows: model.table.rows(),
        centre_conicity: model.centre_conicity(),
        jumps: model.table.jumps().to_vec(),
        clamped: model.table.clamped.clone(),
    }
}
