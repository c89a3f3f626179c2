//! Drivers: run an analysis of a plan and return plain result structs.
//!
//! These are the only functions that know both the model and the analyses; what they
//! return is data that [`crate::output`] and [`crate::plot`] turn into files.

use rayon::prelude::*;

use crate::contact::creep::CreepLaw;
use crate::contact::table::Row;
use crate::model::{BodyKind, Vehicle};
use crate::stability::{
    critical_speeds, first_lyapunov, spectrum_at, CriticalSpeeds, Crossing, LinearError,
    LinearSystem, Lyapunov, LyapunovOptions, Spectrum,
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
    /// each wheelset's centre conicity, front to rear (–): they differ when the wheelsets have
    /// their own geometry (`[[contact.wheelset]]`); `centre_conicity` and the Klingel
    /// wavelength are then the leading wheelset's
    pub wheelset_conicities: Vec<f64>,
    /// spectra of the Kalker model on the spectrum grid
    pub spectrum_kalker: Vec<Spectrum>,
    /// spectra of the study's law on the same grid, when not Kalker
    pub spectrum_creep_law: Vec<Spectrum>,
    /// the layout's name ("wheelset", "bogie", "car") and its number of states
    pub layout: (&'static str, usize),
    /// mode shape at each Kalker crossing (same order as `kalker.crossings`)
    pub kalker_modes: Vec<Option<ModeShape>>,
    /// mode shape at each crossing of the study's law, when not Kalker
    pub creep_law_modes: Vec<Option<ModeShape>>,
    /// first Lyapunov coefficient at each Kalker crossing (same order as `kalker.crossings`;
    /// `None` where it could not be computed)
    pub kalker_lyapunov: Vec<Option<Lyapunov>>,
    /// first Lyapunov coefficient at each crossing of the study's law, when not Kalker
    pub creep_law_lyapunov: Vec<Option<Lyapunov>>,
    /// what the linearisation replaced: each damper on a force–velocity curve is linearised at
    /// its slope at zero (docs/model.md §13), one sentence per damper
    pub notes: Vec<String>,
}

/// One body's part of a mode shape.
#[derive(Clone, Debug, PartialEq)]
pub struct BodyMode {
    /// body name
    pub body: String,
    /// lateral amplitude |y| relative to the largest body's (–)
    pub lateral: f64,
    /// yaw amplitude |ψ| relative to the largest body's (–)
    pub yaw: f64,
    /// phase of y against the leading wheelset's y (degrees, −180…180)
    pub lateral_phase_deg: f64,
    /// phase of ψ against the leading wheelset's y (degrees)
    pub yaw_phase_deg: f64,
    /// largest lateral displacement of the body's ends (its centre, and the wheelsets or
    /// bogie centres it carries, y ± x ψ) relative to the largest of all bodies (–)
    pub reach: f64,
}

/// One damper stroke's part of a mode shape: a damper pair on series stiffness (a Maxwell
/// element, docs/model.md §13) with its stroke $z$ and its end-to-end deflection $Δ = b\,q$.
/// In the linear motion $(c\,s + k_s)\,z = k_s Δ$ at the eigenvalue $s$, so the share is
/// $k_s/|c\,s + k_s|$.
#[derive(Clone, Debug, PartialEq)]
pub struct DamperMode {
    /// the stroke's name, e.g. `"yaw damper, frame 1"` ([`crate::model::Maxwell::name`])
    pub damper: String,
    /// stroke amplitude |z| relative to the leading wheelset's lateral amplitude |y₁| (m/m)
    pub stroke_per_y1: f64,
    /// phase of z against the leading wheelset's y (degrees, −180…180)
    pub stroke_phase_deg: f64,
    /// |z|/|Δ|: the share of the end-to-end deflection the damper takes (–); 1 for rigid
    /// bushes, towards 0 when the bushes take all the motion (0 where Δ vanishes)
    pub deflection_share: f64,
}

/// The eigenvector of a crossing pair, body by body (docs/model.md §11, "Reported for a vehicle").
#[derive(Clone, Debug, PartialEq)]
pub struct ModeShape {
    /// each body in state order
    pub bodies: Vec<BodyMode>,
    /// each damper stroke in state order (empty without series stiffness)
    pub dampers: Vec<DamperMode>,
    /// the body whose lateral displacement (`reach`) is largest
    pub leading_body: String,
    /// "wheelset hunting", "bogie hunting" (a wheelset or frame leads) or "car-body hunting"
    pub label: &'static str,
}

/// A body's name, complex y and ψ amplitudes, reach and kind.
type RawMode = (
    String,
    nalgebra::Complex<f64>,
    nalgebra::Complex<f64>,
    f64,
    BodyKind,
);

/// The mode shape of the eigenvector `v` (one (re, im) per state) of `vehicle`.
pub fn mode_shape(vehicle: &Vehicle, v: &[(f64, f64)]) -> Option<ModeShape> {
    let c = |i: usize| v.get(i).map(|z| nalgebra::Complex::new(z.0, z.1));
    let reference = c(vehicle.wheelset_dofs()[0])?;
    let phase = |z: nalgebra::Complex<f64>| {
        let r = z / reference;
        if reference.norm() > 0.0 {
            r.arg().to_degrees()
        } else {
            0.0
        }
    };
    // how far each body reaches: its ends are where it carries the next bodies
    let (a, lb) = vehicle.layout_arms();
    let ends = |kind: BodyKind| match kind {
        BodyKind::Wheelset => 0.0,
        BodyKind::Frame => a,
        BodyKind::CarBody => lb,
    };
    let raw: Vec<RawMode> = vehicle
        .bodies
        .iter()
        .map(|b| {
            let (y, psi) = (c(b.dof)?, c(b.dof + 1)?);
            let arm = ends(b.kind);
            let reach = (y + psi * arm).norm().max((y - psi * arm).norm());
            Some((b.name.clone(), y, psi, reach, b.kind))
        })
        .collect::<Option<_>>()?;
    let max_y = raw.iter().map(|r| r.1.norm()).fold(0.0, f64::max);
    let max_psi = raw.iter().map(|r| r.2.norm()).fold(0.0, f64::max);
    let max_reach = raw.iter().map(|r| r.3).fold(0.0, f64::max);
    let lead = raw.iter().max_by(|a, b| a.3.total_cmp(&b.3))?;
    let label = match (vehicle.layout, lead.4) {
        (crate::model::Layout::Wheelset, _) => "wheelset hunting",
        (_, BodyKind::CarBody) => "car-body hunting",
        _ => "bogie hunting",
    };
    let rel = |a: f64, m: f64| if m > 0.0 { a / m } else { 0.0 };
    // the strokes follow (q, q̇): z_k is state 2n + k, its deflection Δ = b q
    let n = vehicle.dofs();
    let dampers = vehicle
        .maxwell
        .iter()
        .enumerate()
        .map(|(k, mx)| {
            let z = c(2 * n + k)?;
            let delta = mx
                .row
                .iter()
                .try_fold(nalgebra::Complex::new(0.0, 0.0), |d, &(j, b)| {
                    Some(d + c(j)? * b)
                })?;
            Some(DamperMode {
                damper: mx.name.clone(),
                stroke_per_y1: rel(z.norm(), reference.norm()),
                stroke_phase_deg: phase(z),
                deflection_share: rel(z.norm(), delta.norm()),
            })
        })
        .collect::<Option<_>>()?;
    Some(ModeShape {
        leading_body: lead.0.clone(),
        label,
        dampers,
        bodies: raw
            .iter()
            .map(|(name, y, psi, reach, _)| BodyMode {
                body: name.clone(),
                lateral: rel(y.norm(), max_y),
                yaw: rel(psi.norm(), max_psi),
                lateral_phase_deg: phase(*y),
                yaw_phase_deg: phase(*psi),
                reach: rel(*reach, max_reach),
            })
            .collect(),
    })
}

/// Mode shapes of every crossing: the eigenvector of the pair at the crossing's frequency.
fn modes<const N: usize>(
    vehicle: &Vehicle,
    sys: &LinearSystem<N>,
    found: &CriticalSpeeds,
) -> Vec<Option<ModeShape>> {
    found
        .crossings
        .iter()
        .map(|c: &Crossing| mode_shape(vehicle, &c.eigenpair(sys)?.vector))
        .collect()
}

/// The first Lyapunov coefficient of `model` (its own law) at every crossing: the Hopf type
/// from $l_1$ (docs/model.md §12, [`crate::stability::first_lyapunov`]).
pub fn lyapunovs<const N: usize>(model: &Vehicle, found: &CriticalSpeeds) -> Vec<Option<Lyapunov>> {
    found
        .crossings
        .iter()
        .map(|c| {
            let omega = 2.0 * std::f64::consts::PI * c.frequency_hz;
            first_lyapunov::<N, _>(model, c.speed_m_s, omega, &LyapunovOptions::default()).ok()
        })
        .collect()
}

impl LinearReport {
    /// Crossings of the study's creep law (Kalker's when the study uses Kalker).
    pub fn law_crossings(&self) -> &CriticalSpeeds {
        self.creep_law.as_ref().unwrap_or(&self.kalker)
    }

    /// The first Lyapunov coefficients at [`Self::law_crossings`].
    pub fn law_lyapunov(&self) -> &[Option<Lyapunov>] {
        if self.creep_law.is_some() {
            &self.creep_law_lyapunov
        } else {
            &self.kalker_lyapunov
        }
    }
}

/// Spectra on `n` speeds spread uniformly over `range`, computed in parallel (order kept).
pub fn spectrum_grid<const N: usize>(
    sys: &LinearSystem<N>,
    range: (f64, f64),
    n: usize,
) -> Vec<Spectrum> {
    let n = n.max(2);
    (0..n)
        .into_par_iter()
        .filter_map(|i| {
            let v = range.0 + (range.1 - range.0) * i as f64 / (n - 1) as f64;
            spectrum_at(&sys.jacobian(v), v)
        })
        .collect()
}

/// The linear analysis: Kalker critical speeds, the creep law's Hopf speeds, spectra and mode
/// shapes, for a vehicle of any layout: the quartic Hurwitz scan for the 4-state wheelset,
/// the eigenvalue scan for more states.
pub fn linear(plan: &Plan, model: &Vehicle) -> Result<LinearReport, LinearError> {
    crate::with_states!(model.states(), N => linear_states::<N>(plan, model),
        _ => Err(LinearError::States(model.states())))
}

/// [`linear`] for a vehicle of `N` states (`N` = [`Vehicle::states`]).
pub fn linear_states<const N: usize>(
    plan: &Plan,
    model: &Vehicle,
) -> Result<LinearReport, LinearError> {
    let kalker_model = model.with_law(CreepLaw::Kalker);
    let ks = LinearSystem::<N>::at_centre(&kalker_model);
    let kalker = critical_speeds(&ks, CreepLaw::Kalker, &plan.linear)?;
    let range = plan.linear.speed_range;
    let spectrum_kalker = spectrum_grid(&ks, range, plan.spectrum_points);
    let kalker_modes = modes(model, &ks, &kalker);
    let kalker_lyapunov = lyapunovs::<N>(&kalker_model, &kalker);
    let (creep_law, spectrum_creep_law, creep_law_modes, creep_law_lyapunov) =
        match model.creep_law() {
            CreepLaw::Kalker => (None, Vec::new(), Vec::new(), Vec::new()),
            law => {
                let ls = LinearSystem::<N>::at_centre(model);
                let found = critical_speeds(&ls, law, &plan.linear)?;
                let m = modes(model, &ls, &found);
                let l = lyapunovs::<N>(model, &found);
                (
                    Some(found),
                    spectrum_grid(&ls, range, plan.spectrum_points),
                    m,
                    l,
                )
            }
        };
    Ok(LinearReport {
        study: plan.name.clone(),
        kalker,
        creep_law,
        centre_conicity: model.centre_conicity(),
        klingel_wavelength_m: model.klingel_wavelength(),
        wheelset_conicities: model.wheelset_conicities(),
        spectrum_kalker,
        spectrum_creep_law,
        layout: (model.layout.name(), model.states()),
        kalker_modes,
        creep_law_modes,
        kalker_lyapunov,
        creep_law_lyapunov,
        notes: linearisation_notes(model)
            .into_iter()
            .chain(conicity_note(model))
            .collect(),
    })
}

/// When the wheelsets' centre conicities differ, one sentence saying so and which one the
/// single conicity and Klingel wavelength are.
pub fn conicity_note(model: &Vehicle) -> Option<String> {
    model.conicities_differ().then(|| {
        format!(
            "the wheelsets' centre conicities differ ({}); the centre conicity and Klingel \
             wavelength reported are the leading wheelset's",
            model.conicity_summary()
        )
    })
}

/// One sentence per damper whose force–velocity curve the linear analysis replaces by its
/// slope at zero, and one per kind of bump stop (primary, secondary), which gives nothing at
/// the centre: the linear analysis is the motion inside its clearance.
pub fn linearisation_notes(model: &Vehicle) -> Vec<String> {
    let mut notes: Vec<String> = model
        .maxwell
        .iter()
        .filter_map(|mx| {
            let g = mx.law.as_ref()?;
            Some(format!(
                "{}: the linear analysis uses the force-velocity curve's slope at zero, {} kN s/m per damper (the centred motion); the blow-off acts in the nonlinear analyses only",
                mx.name,
                g.slope_at_zero() / 1e3
            ))
        })
        .collect();
    let mut kinds: Vec<(&str, f64)> = Vec::new();
    for stop in &model.stops {
        let kind = stop.name.split(',').next().unwrap_or(&stop.name);
        if !kinds
            .iter()
            .any(|(k, c)| *k == kind && *c == stop.clearance)
        {
            kinds.push((kind, stop.clearance));
        }
    }
    for (kind, clearance) in kinds {
        notes.push(format!(
            "{kind}s: the linear analysis is the centred motion inside the ±{} mm clearance (the stops act in the nonlinear analyses only)",
            (clearance * 1e9).round() / 1e6
        ));
    }
    notes
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
    /// half-width of the range where the table is genuine geometry (m); `None`: everywhere
    pub valid_half_width_m: Option<f64>,
    /// the study's `contact.extrapolate`
    pub extrapolate: crate::contact::table::Extrapolation,
    /// the wheelsets' centre conicities grouped, when the wheelsets have geometries of their
    /// own that differ (`[[contact.wheelset]]`; the rest of the report is `[contact]`'s)
    pub wheelsets: Option<String>,
}

/// The geometry table of a model.
pub fn geometry(plan: &Plan, model: &Vehicle) -> GeometryReport {
    let table = &model.contact.table;
    GeometryReport {
        study: plan.name.clone(),
        rows: table.rows(),
        centre_conicity: crate::model::centre_conicity(table),
        jumps: table.jumps().to_vec(),
        clamped: table.clamped.clone(),
        valid_half_width_m: table.valid_half_width(),
        extrapolate: plan.contact.extrapolate,
        wheelsets: model.conicities_differ().then(|| model.conicity_summary()),
    }
}
