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
    /// the layout (`kind = "wheelset" | "bogie" | "car"`); absent: a single wheelset
    #[serde(default)]
    pub vehicle: Option<VehicleSection>,
    pub wheelset: WheelsetSection,
    pub suspension: SuspensionSection,
    /// the bogie frame (layouts "bogie" and "car")
    #[serde(default)]
    pub bogie: Option<BogieSection>,
    /// the secondary suspension (layouts "bogie" and "car")
    #[serde(default)]
    pub secondary: Option<SecondarySection>,
    /// the car body (layout "car")
    #[serde(default)]
    pub carbody: Option<CarbodySection>,
    pub contact: ContactSection,
    #[serde(default)]
    pub flange: Option<FlangeSection>,
    #[serde(default)]
    pub linear: Option<LinearSection>,
    #[serde(default)]
    pub bifurcation: Option<BifurcationSection>,
    /// the search for every attractor (`critspeed attractors`)
    #[serde(default)]
    pub attractors: Option<AttractorsSection>,
    /// parameter sweep (`critspeed sweep`)
    #[serde(default)]
    pub sweep: Option<SweepSection>,
    /// trade study (`critspeed trade`), kept raw here and parsed by that command
    #[serde(default)]
    pub trade: Option<toml::Table>,
    /// critical speeds as curves over a design key (`critspeed curve`)
    #[serde(default)]
    pub curve: Option<CurveSection>,
    /// critical speeds under uncertain parameters (`critspeed uncertainty`)
    #[serde(default)]
    pub uncertainty: Option<UncertaintySection>,
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

/// A per-side spring-and-damper section: the keys the primary (`[suspension]`) and the
/// secondary (`[secondary]`) share, then the section's own optional keys. One definition, so
/// that the two cannot drift apart; each struct still denies unknown keys.
macro_rules! springs_section {
    ($(#[$meta:meta])* $name:ident { $($(#[$fmeta:meta])* $field:ident: $ty:ty),* $(,)? }) => {
        $(#[$meta])*
        #[derive(Clone, Debug, Deserialize)]
        #[serde(deny_unknown_fields)]
        pub struct $name {
            /// lateral stiffness per side
            pub lateral_stiffness: Quantity,
            /// longitudinal stiffness per side
            pub longitudinal_stiffness: Quantity,
            /// lateral damping per side
            pub lateral_damping: Quantity,
            /// longitudinal damping per side
            pub longitudinal_damping: Quantity,
            /// half the lateral distance between the two sides' springs
            pub half_spring_spacing: Quantity,
            /// vertical stiffness per side (acts on a rolling body only)
            #[serde(default)]
            pub vertical_stiffness: Option<Quantity>,
            /// vertical damping per side
            #[serde(default)]
            pub vertical_damping: Option<Quantity>,
            /// height above the frame's centre of mass (frame roll only)
            #[serde(default)]
            pub height: Option<Quantity>,
            /// stiffness in series with the lateral damper (a Maxwell element)
            #[serde(default)]
            pub lateral_damper_series_stiffness: Option<Quantity>,
            /// stiffness in series with the longitudinal damper
            #[serde(default)]
            pub longitudinal_damper_series_stiffness: Option<Quantity>,
            /// stiffness in series with the vertical damper
            #[serde(default)]
            pub vertical_damper_series_stiffness: Option<Quantity>,
            /// the lateral damper's force–velocity characteristic (on series stiffness)
            #[serde(default)]
            pub lateral_damper_force_velocity: Option<ForceVelocitySection>,
            /// the longitudinal damper's force–velocity characteristic (on series stiffness)
            #[serde(default)]
            pub longitudinal_damper_force_velocity: Option<ForceVelocitySection>,
            /// the vertical damper's force–velocity characteristic (on series stiffness)
            #[serde(default)]
            pub vertical_damper_force_velocity: Option<ForceVelocitySection>,
            /// a lateral bump stop's free play each way (docs/model.md §13)
            #[serde(default)]
            pub bump_stop_clearance: Option<Quantity>,
            /// the bump stop's stiffness beyond its clearance
            #[serde(default)]
            pub bump_stop_stiffness: Option<Quantity>,
            /// a progressive bump stop: force against penetration beyond the clearance
            #[serde(default)]
            pub bump_stop_force_table: Option<BumpStopTableSection>,
            $(
                $(#[$fmeta])*
                #[serde(default)]
                pub $field: Option<$ty>,
            )*
        }

        impl $name {
            /// The keys every spring section has.
            pub fn springs(&self) -> Springs<'_> {
                Springs {
                    stiffness: [&self.lateral_stiffness, &self.longitudinal_stiffness],
                    damping: [&self.lateral_damping, &self.longitudinal_damping],
                    half_spring_spacing: &self.half_spring_spacing,
                    vertical: [self.vertical_stiffness.as_ref(), self.vertical_damping.as_ref()],
                    height: self.height.as_ref(),
                    series: [
                        self.lateral_damper_series_stiffness.as_ref(),
                        self.longitudinal_damper_series_stiffness.as_ref(),
                        self.vertical_damper_series_stiffness.as_ref(),
                    ],
                    force_velocity: [
                        self.lateral_damper_force_velocity.as_ref(),
                        self.longitudinal_damper_force_velocity.as_ref(),
                        self.vertical_damper_force_velocity.as_ref(),
                    ],
                    bump_stop: [
                        self.bump_stop_clearance.as_ref(),
                        self.bump_stop_stiffness.as_ref(),
                    ],
                    bump_stop_table: self.bump_stop_force_table.as_ref(),
                }
            }
        }
    };
}

/// The keys the primary and the secondary share, as written.
#[derive(Clone, Copy, Debug)]
pub struct Springs<'a> {
    /// lateral, longitudinal stiffness
    pub stiffness: [&'a Quantity; 2],
    /// lateral, longitudinal damping
    pub damping: [&'a Quantity; 2],
    /// half the spring spacing
    pub half_spring_spacing: &'a Quantity,
    /// vertical stiffness and damping, when given
    pub vertical: [Option<&'a Quantity>; 2],
    /// height, when given
    pub height: Option<&'a Quantity>,
    /// the stiffnesses in series with the lateral, longitudinal and vertical dampers, when given
    pub series: [Option<&'a Quantity>; 3],
    /// the force–velocity curves of the lateral, longitudinal and vertical dampers, when given
    pub force_velocity: [Option<&'a ForceVelocitySection>; 3],
    /// the bump stop's clearance and stiffness, when given
    pub bump_stop: [Option<&'a Quantity>; 2],
    /// the bump stop's progressive table, when given
    pub bump_stop_table: Option<&'a BumpStopTableSection>,
}

springs_section!(
    /// `[suspension]`: the primary, per side, wheelset to frame (to the track for a wheelset).
    SuspensionSection {}
);

springs_section!(
    /// `[secondary]`: per side, frame to car body (track-fixed for a bogie).
    SecondarySection {
        /// longitudinal yaw dampers per side
        yaw_damping: Quantity,
        /// stiffness in series with each yaw damper (its end bushes)
        yaw_damper_series_stiffness: Quantity,
        /// the yaw dampers' force–velocity characteristic
        yaw_damper_force_velocity: ForceVelocitySection,
        /// half the lateral distance between the yaw dampers
        yaw_damper_half_spacing: Quantity,
        /// half the lateral distance between the vertical springs
        vertical_half_spacing: Quantity,
    }
);

/// A damper's force–velocity characteristic: either `points` (velocity, force) for v > 0, or
/// the blow-off form `blow_off_force` and `slope_after` (the slope below the blow-off is the
/// section's damping key).
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ForceVelocitySection {
    /// `[[velocity, force], …]` for v > 0, odd-extended through zero
    #[serde(default)]
    pub points: Option<PointsTable>,
    /// the force at which the relief valve opens
    #[serde(default)]
    pub blow_off_force: Option<Quantity>,
    /// the slope beyond the blow-off
    #[serde(default)]
    pub slope_after: Option<Quantity>,
}

/// A progressive bump stop: `points = [[penetration, force], …]` beyond the clearance,
/// penetration > 0, odd-extended, through zero.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BumpStopTableSection {
    /// `[[penetration, force], …]`
    pub points: PointsTable,
}

/// A piecewise-linear odd table as written, `[[x, force], …]` for x > 0 (the origin implied):
/// a damper's force–velocity curve, a bump stop's force against penetration.
pub type PointsTable = Vec<[Quantity; 2]>;

/// `[vehicle]`: which layout the study describes.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct VehicleSection {
    /// "wheelset", "bogie" or "car"
    pub kind: String,
}

/// `[bogie]`: the frame.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BogieSection {
    pub mass: Quantity,
    pub yaw_inertia: Quantity,
    pub half_wheelbase: Quantity,
    /// adds the frame's roll
    #[serde(default)]
    pub roll_inertia: Option<Quantity>,
}

/// `[carbody]`: the car body (layout "car").
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CarbodySection {
    pub mass: Quantity,
    pub yaw_inertia: Quantity,
    pub half_bogie_distance: Quantity,
    /// adds the car body's roll
    #[serde(default)]
    pub roll_inertia: Option<Quantity>,
    /// height of the secondary above the car body's centre of mass (negative: below)
    #[serde(default)]
    pub secondary_height: Option<Quantity>,
}

#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ContactSection {
    /// "cone", "cone-on-arc", "table" or "profiles"
    pub geometry: String,
    /// cone slope λ: a number (0.05) or a ratio string ("1:20"); cone geometries only
    #[serde(default)]
    pub conicity: Option<Quantity>,
    /// geometry "table": the CSV file, relative to the study file's folder
    #[serde(default)]
    pub geometry_table: Option<String>,
    /// wheel profile point list (CSV), relative to the study file's folder ("profiles")
    #[serde(default)]
    pub wheel_profile: Option<String>,
    /// rail profile point list (CSV), relative to the study file's folder ("profiles")
    #[serde(default)]
    pub rail_profile: Option<String>,
    /// the wheel file's lateral axis points towards the flange (default false: outward)
    #[serde(default)]
    pub wheel_profile_mirror: Option<bool>,
    /// the wheel file's vertical axis points up (default false: down)
    #[serde(default)]
    pub wheel_profile_z_up: Option<bool>,
    /// the rail file's lateral axis points towards the gauge side (default false: outward)
    #[serde(default)]
    pub rail_profile_mirror: Option<bool>,
    /// the rail file's vertical axis points up (default false: down)
    #[serde(default)]
    pub rail_profile_z_up: Option<bool>,
    /// inclination applied to the rail profile: "1:20", "1:40" or "none"
    #[serde(default)]
    pub rail_inclination: Option<String>,
    /// track gauge between the gauge points ("profiles"; default 1435 mm)
    #[serde(default)]
    pub track_gauge: Option<Quantity>,
    /// depth of the gauge point below the rail top ("profiles"; default 14 mm)
    #[serde(default)]
    pub gauge_depth: Option<Quantity>,
    /// half-width of the smoothing of the tabulated profile geometry ("profiles"; default 0)
    #[serde(default)]
    pub profile_smoothing: Option<Quantity>,
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
    /// beyond the table's valid range: "none" (default: cut there) or "linear"
    #[serde(default)]
    pub extrapolate: Option<String>,
    #[serde(default)]
    pub creep_coefficients: Option<CreepCoefficientsSection>,
    /// `[[contact.wheelset]]`: wheelsets with their own contact geometry
    #[serde(default)]
    pub wheelset: Vec<WheelsetContactSection>,
}

/// One `[[contact.wheelset]]` entry: the wheelsets at `positions` (1-based, front to rear)
/// take these geometry keys instead of `[contact]`'s; every key not given is `[contact]`'s.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WheelsetContactSection {
    /// the wheelsets' positions, 1-based from the front
    pub positions: Vec<usize>,
    /// "cone", "cone-on-arc", "table" or "profiles" (default: `[contact]`'s)
    #[serde(default)]
    pub geometry: Option<String>,
    #[serde(default)]
    pub conicity: Option<Quantity>,
    #[serde(default)]
    pub crown_offset: Option<Quantity>,
    #[serde(default)]
    pub geometry_table: Option<String>,
    #[serde(default)]
    pub wheel_profile: Option<String>,
    #[serde(default)]
    pub rail_profile: Option<String>,
    #[serde(default)]
    pub wheel_profile_mirror: Option<bool>,
    #[serde(default)]
    pub wheel_profile_z_up: Option<bool>,
    #[serde(default)]
    pub rail_profile_mirror: Option<bool>,
    #[serde(default)]
    pub rail_profile_z_up: Option<bool>,
    #[serde(default)]
    pub rail_inclination: Option<String>,
    #[serde(default)]
    pub track_gauge: Option<Quantity>,
    #[serde(default)]
    pub gauge_depth: Option<Quantity>,
    #[serde(default)]
    pub profile_smoothing: Option<Quantity>,
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
    /// relative tolerance of the monodromy matrix (default: rtol)
    #[serde(default)]
    pub floquet_rtol: Option<f64>,
    #[serde(default)]
    pub ds_max: Option<f64>,
    #[serde(default)]
    pub max_points: Option<usize>,
    /// shooting segments of the half period (0: the default, 4, on any machine)
    #[serde(default)]
    pub segments: Option<usize>,
    /// switch onto asymmetric and doubled branches (default true)
    #[serde(default)]
    pub switch: Option<bool>,
    /// branches continued at most (default 8)
    #[serde(default)]
    pub max_branches: Option<usize>,
    /// the cycles' corrector: "newton" (default) or "chord"
    #[serde(default)]
    pub corrector: Option<String>,
    /// the shooting flows' Runge–Kutta pair: "dopri5" (default) or "dop853"
    #[serde(default)]
    pub integrator: Option<String>,
}

/// `[attractors]`: the search for every attractor over speed.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AttractorsSection {
    /// the grid's lowest and highest speed
    #[serde(default)]
    pub speed_range: Option<[Quantity; 2]>,
    /// grid speeds
    #[serde(default)]
    pub speeds: Option<usize>,
    /// kick amplitudes
    #[serde(default)]
    pub amplitudes: Option<Vec<Quantity>>,
    /// longest simulation of one motion
    #[serde(default)]
    pub settle: Option<Quantity>,
    /// width of the bracket of each attractor's death speed
    #[serde(default)]
    pub bracket: Option<Quantity>,
    /// largest descent step, relative to the speed
    #[serde(default)]
    pub descent_step: Option<f64>,
    /// the lowest speed a descent goes to
    #[serde(default)]
    pub lowest: Option<Quantity>,
    /// equilibrium threshold on every body's lateral excursion
    #[serde(default)]
    pub threshold: Option<Quantity>,
    /// integrator relative tolerance of the simulations
    #[serde(default)]
    pub rtol: Option<f64>,
    /// largest period (returns to the section) recognised as a cycle
    #[serde(default)]
    pub max_period: Option<usize>,
}

/// `[sweep]`: a grid over one or two numeric study keys.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SweepSection {
    /// one or two axes
    pub axes: Vec<SweepAxisSection>,
    /// results per point: any of "kalker", "hopf", "nonlinear" (default: kalker, hopf)
    #[serde(default)]
    pub compute: Option<Vec<String>>,
    /// speed the vehicle runs at, drawn as the stable/unstable boundary on the plots
    #[serde(default)]
    pub operating_speed: Option<Quantity>,
    /// V_NL by the full attractor search at every point instead of the fast form (continuation
    /// and descents; default false)
    #[serde(default)]
    pub attractors: Option<bool>,
}

/// One axis of a sweep.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SweepAxisSection {
    /// dotted study key, e.g. "suspension.lateral_stiffness"
    pub key: String,
    /// first value (any accepted unit of the key)
    pub from: Quantity,
    /// last value
    pub to: Quantity,
    /// number of values (at least 1)
    pub count: usize,
    /// "linear" (default) or "log"
    #[serde(default)]
    pub spacing: Option<String>,
}

/// `[curve]`: critical speeds as curves over one design key (`critspeed curve`).
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CurveSection {
    /// dotted study key, any sweepable one, e.g. "suspension.lateral_stiffness"
    pub key: String,
    /// one end of the key's range (any accepted unit of the key)
    pub from: Quantity,
    /// the other end
    pub to: Quantity,
    /// "linear" (default) or "log": the axis the curves are continued and drawn on
    #[serde(default)]
    pub spacing: Option<String>,
    /// what to continue: any of "hopf", "fold", "symmetry_breaking", "period_doubling",
    /// "torus" (default ["hopf", "fold"])
    #[serde(default)]
    pub curves: Option<Vec<String>>,
    /// speeds the curves may visit (default: the linear speed range)
    #[serde(default)]
    pub speed_range: Option<[Quantity; 2]>,
    /// most points on each side of a curve's start (default 400)
    #[serde(default)]
    pub max_points: Option<usize>,
    /// largest step, as a fraction of the plot's diagonal (default 0.02)
    #[serde(default)]
    pub max_step: Option<f64>,
    /// values of the key where Hopf points are searched to start curves from (default 5)
    #[serde(default)]
    pub seed_points: Option<usize>,
    /// values of the key at which the folds of cycles are located, ends included (default 12)
    #[serde(default)]
    pub fold_points: Option<usize>,
    /// integrator relative tolerance of the fold curves and their diagrams (default 1e-8)
    #[serde(default)]
    pub rtol: Option<f64>,
    /// also run the attractor search at every V_NL value of the key (default false)
    #[serde(default)]
    pub attractors: Option<bool>,
}

/// `[uncertainty]`: the critical speeds' distribution and Sobol indices over random parameters.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct UncertaintySection {
    /// base sample count N (the Sobol indices cost N (d + 2) evaluations); a power of two for
    /// "sobol"
    pub samples: usize,
    /// "sobol" (scrambled Sobol quasi-Monte Carlo, default) or "random" (Monte Carlo)
    #[serde(default)]
    pub method: Option<String>,
    /// seed of the scrambling or of the random numbers, and of the bootstrap (default 1)
    #[serde(default)]
    pub seed: Option<u32>,
    /// results per evaluation: any of "kalker", "hopf", "nonlinear" (default ["kalker"])
    #[serde(default)]
    pub compute: Option<Vec<String>>,
    /// first-order and total Sobol indices with bootstrap intervals (default true)
    #[serde(default)]
    pub indices: Option<bool>,
    /// speed whose probability of lying above each critical speed is reported
    #[serde(default)]
    pub operating_speed: Option<Quantity>,
    /// V_NL by the full attractor search at every evaluation instead of the fast form
    /// (continuation and descents; default false)
    #[serde(default)]
    pub attractors: Option<bool>,
    /// the uncertain parameters (at least one)
    #[serde(default)]
    pub parameter: Vec<UncertainParameterSection>,
}

/// One uncertain parameter of `[uncertainty]`.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct UncertainParameterSection {
    /// dotted study key, any sweepable one, e.g. "suspension.lateral_stiffness"
    pub key: String,
    /// "uniform" (from, to), "normal" (mean, std, optional from/to truncation), "lognormal"
    /// (median, factor) or "choice" (values, weights)
    pub distribution: String,
    /// lower end (uniform; truncation of normal), any accepted unit of the key
    #[serde(default)]
    pub from: Option<Quantity>,
    /// upper end (uniform; truncation of normal)
    #[serde(default)]
    pub to: Option<Quantity>,
    /// mean (normal)
    #[serde(default)]
    pub mean: Option<Quantity>,
    /// standard deviation (normal)
    #[serde(default)]
    pub std: Option<Quantity>,
    /// median (lognormal)
    #[serde(default)]
    pub median: Option<Quantity>,
    /// the ratio of the 84th percentile to the median, exp(σ) (lognormal; > 1)
    #[serde(default)]
    pub factor: Option<f64>,
    /// the values (choice)
    #[serde(default)]
    pub values: Option<Vec<Quantity>>,
    /// their relative weights (choice; default equal)
    #[serde(default)]
    pub weights: Option<Vec<f64>>,
}
