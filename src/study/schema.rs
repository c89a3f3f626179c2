//! The study file exactly as written (TOML), before units are converted or rules checked.
//!
//! Every struct denies unknown keys, so a misspelt key is an error that names it. Physical
//! quantities are [`Quantity`]: a plain number (SI) or a string with a unit.

use serde::Deserialize;

/// A number in SI units, or a string `"<number> <unit>"`.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(untagged)]
pub enum Quantity {
    /// SI value
    Number(f64),
    /// value with unit, e.g. `"850 N/mm"`
    Text(String),
}

/// The whole study file.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StudyFile {
    /// study name; results go to `out/<name>/`
    pub name: String,
    /// free text: where the parameters come from
    #[serde(default)]
    pub description: Option<String>,
    pub wheelset: WheelsetSection,
    pub suspension: SuspensionSection,
    pub contact: ContactSection,
    #[serde(default)]
    pub flange: Option<FlangeSection>,
    #[serde(default)]
    pub linear: Option<LinearSection>,
    #[serde(default)]
    pub bifurcation: Option<BifurcationSection>,
    #[serde(default)]
    pub sweep: Option<toml::Table>,
    #[serde(default)]
    pub trade: Option<toml::Table>,
}

#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WheelsetSection {
    pub mass: Quantity,
    pub yaw_inertia: Quantity,
    pub axle_load: Quantity,
    pub half_contact_distance: Quantity,
    pub rolling_radius: Quantity,
}

#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SuspensionSection {
    pub lateral_stiffness: Quantity,
    pub longitudinal_stiffness: Quantity,
    pub lateral_damping: Quantity,
    pub longitudinal_damping: Quantity,
    pub half_spring_spacing: Quantity,
}

#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ContactSection {
    /// "cone" or "cone-on-arc"
    pub geometry: String,
    /// cone slope λ: a number (0.05) or a ratio string ("1:20")
    pub conicity: Quantity,
    #[serde(default)]
    pub rail_head_radius: Option<Quantity>,
    #[serde(default)]
    pub crown_offset: Option<Quantity>,
    /// "kalker" or "shen"
    #[serde(default)]
    pub creep_law: Option<String>,
    #[serde(default)]
    pub friction: Option<Quantity>,
    #[serde(default)]
    pub spin: Option<bool>,
    #[serde(default)]
    pub young_modulus: Option<Quantity>,
    #[serde(default)]
    pub poisson_ratio: Option<Quantity>,
    #[serde(default)]
    pub shear_modulus: Option<Quantity>,
    /// half-width of the tabulated geometry
    #[serde(default)]
    pub lateral_range: Option<Quantity>,
    /// nodes of the geometry table
    #[serde(default)]
    pub table_points: Option<usize>,
    #[serde(default)]
    pub creep_coefficients: Option<CreepCoefficientsSection>,
}

#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CreepCoefficientsSection {
    pub f11: Quantity,
    pub f22: Quantity,
    pub f23: Quantity,
    pub f33: Quantity,
}

#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FlangeSection {
    pub clearance: Quantity,
    pub stiffness: Quantity,
}

#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LinearSection {
    #[serde(default)]
    pub speed_range: Option<[Quantity; 2]>,
    #[serde(default)]
    pub grid_points: Option<usize>,
    #[serde(default)]
    pub spectrum_points: Option<usize>,
}

#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BifurcationSection {
    #[serde(default)]
    pub speed_range: Option<[Quantity; 2]>,
    #[serde(default)]
    pub max_amplitude: Option<Quantity>,
    #[serde(default)]
    pub rtol: Option<f64>,
    #[serde(default)]
    pub ds_max: Option<f64>,
    #[serde(default)]
    pub max_points: Option<usize>,
}
