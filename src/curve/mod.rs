//! Critical speeds as curves over a design key (`critspeed curve`, study section `[curve]`):
//! the special points of the speed diagram continued in a second parameter, with the
//! codimension-two points where the answer changes character (docs/model.md §12).
//!
//! One driver per [`CurveKind`]. **Hopf curves** ([`hopf`], [`trace`]): the linear (Kalker)
//! critical speed $V_L(p)$ and the creep law's Hopf speed $V_H(p)$ as solution curves of
//! $J(V, p)v = iωv$, continued by pseudo-arclength from every Hopf crossing found at a few
//! values of the key ([`CurveSpec::seed_points`]), with the first Lyapunov coefficient and
//! the Hopf type at every point, and the generalised Hopf (Bautin), double Hopf, zero-Hopf
//! and Bogdanov–Takens points located on them. **Fold curves** (`crate::bifurcation::fold_track`):
//! every located fold of cycles of the diagrams at the study's own key value and at a few grid
//! values, continued over the key as solutions of the minimally augmented fold system
//! (bordered shooting Jacobian), with cusps, fold–flip, fold–torus and fold–symmetry-breaking
//! points located on them and the fold solved at each of [`CurveSpec::fold_points`] key values;
//! V_NL against the key from them and the supercritical parts of the V_H curves, with its
//! jumps. The same system with another test matrix continues the diagrams' symmetry-breaking
//! and period-doubling points (Φ ∓ I singular) and, with the angle θ as one more unknown, their
//! torus points (σΦ − e^{iθ}I singular, complex).
//!
//! Data flow: [`keyed::KeyedStudy`] (the study at any value of the key) → a
//! [`family::HopfFamily`] per creep law → the continuation → [`CurveReport`] (plain data for
//! `crate::output` and `crate::figures`).

pub mod family;
mod folds;
pub mod hopf;
pub mod keyed;
mod run;
pub mod spec;
#[cfg(test)]
mod tests;
pub mod trace;

pub use run::{analyse, analyse_with_progress, lowest_onset};
pub use spec::{resolve, CurveSpec};

use crate::contact::creep::CreepLaw;
use crate::stability::HopfKind;
use crate::study::units::Dimension;

/// What a curve continues (the `[curve] curves` names are the contract).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum CurveKind {
    /// Hopf points of the centred motion: $V_L$ (Kalker) and the creep law's $V_H$
    Hopf,
    /// folds of cycles of the study's diagram (V_NL among them)
    Fold,
    /// symmetry-breaking (pitchfork) bifurcations of cycles
    SymmetryBreaking,
    /// period doublings of cycles
    PeriodDoubling,
    /// torus (Neimark–Sacker) bifurcations of cycles
    Torus,
}

impl CurveKind {
    /// Every kind, in output order.
    pub const ALL: [CurveKind; 5] = [
        CurveKind::Hopf,
        CurveKind::Fold,
        CurveKind::SymmetryBreaking,
        CurveKind::PeriodDoubling,
        CurveKind::Torus,
    ];

    /// The study file's and the outputs' name.
    pub fn name(self) -> &'static str {
        match self {
            CurveKind::Hopf => "hopf",
            CurveKind::Fold => "fold",
            CurveKind::SymmetryBreaking => "symmetry_breaking",
            CurveKind::PeriodDoubling => "period_doubling",
            CurveKind::Torus => "torus",
        }
    }

    /// Parses [`Self::name`].
    pub fn from_name(s: &str) -> Option<CurveKind> {
        CurveKind::ALL.into_iter().find(|k| k.name() == s)
    }
}

/// A codimension-two point on a curve.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SpecialKind {
    /// generalised Hopf: $l_1$ changes sign, the Hopf point turns from super- to subcritical
    /// and a curve of folds of cycles starts
    Bautin,
    /// a second complex pair on the imaginary axis: two modes set in together
    DoubleHopf,
    /// a real eigenvalue through zero on the Hopf curve
    ZeroHopf,
    /// the pair meets at zero frequency and the Hopf curve ends
    BogdanovTakens,
    /// a fold curve of cycles turns in the key: two folds meet and vanish (cusp of cycles)
    Cusp,
    /// a real multiplier passes −1 on a fold of cycles (fold–flip)
    FoldFlip,
    /// a half-period multiplier of a symmetric cycle passes −1 on its fold: the fold meets a
    /// symmetry-breaking point
    FoldSymmetryBreaking,
    /// a complex pair passes the unit circle on a fold of cycles (fold–Neimark–Sacker)
    FoldTorus,
}

impl SpecialKind {
    /// `"bautin"`, `"double_hopf"`, `"zero_hopf"`, `"bogdanov_takens"`, `"cusp"`,
    /// `"fold_flip"`, `"fold_symmetry_breaking"`, `"fold_torus"`.
    pub fn name(self) -> &'static str {
        match self {
            SpecialKind::Bautin => "bautin",
            SpecialKind::DoubleHopf => "double_hopf",
            SpecialKind::ZeroHopf => "zero_hopf",
            SpecialKind::BogdanovTakens => "bogdanov_takens",
            SpecialKind::Cusp => "cusp",
            SpecialKind::FoldFlip => "fold_flip",
            SpecialKind::FoldSymmetryBreaking => "fold_symmetry_breaking",
            SpecialKind::FoldTorus => "fold_torus",
        }
    }

    /// What a reader of a design report calls it, with the field's abbreviation: legends
    /// and summary lines use these words.
    pub fn words(self) -> &'static str {
        match self {
            SpecialKind::Bautin => "generalised Hopf (GH)",
            SpecialKind::DoubleHopf => "double Hopf (HH)",
            SpecialKind::ZeroHopf => "zero-Hopf (ZH)",
            SpecialKind::BogdanovTakens => "Bogdanov–Takens (BT)",
            SpecialKind::Cusp => "cusp of folds (CPC)",
            SpecialKind::FoldFlip => "fold–flip (LPPD)",
            SpecialKind::FoldSymmetryBreaking => "fold–symmetry breaking (LPSB)",
            SpecialKind::FoldTorus => "fold–torus (LPNS)",
        }
    }

    /// The field's abbreviation: `GH`, `HH`, `ZH`, `BT`, `CPC`, `LPPD`, `LPSB`, `LPNS`
    /// (`curve.json`'s `label`).
    pub fn label(self) -> &'static str {
        match self {
            SpecialKind::Bautin => "GH",
            SpecialKind::DoubleHopf => "HH",
            SpecialKind::ZeroHopf => "ZH",
            SpecialKind::BogdanovTakens => "BT",
            SpecialKind::Cusp => "CPC",
            SpecialKind::FoldFlip => "LPPD",
            SpecialKind::FoldSymmetryBreaking => "LPSB",
            SpecialKind::FoldTorus => "LPNS",
        }
    }
}

/// Why one end of a curve stopped.
#[derive(Clone, Debug, PartialEq)]
pub enum CurveStop {
    /// reached `from` or `to` (the key's value there, SI)
    ParameterBound { parameter: f64 },
    /// reached the end of the speed range (m/s)
    SpeedBound { speed_m_s: f64 },
    /// the step limit (`max_points`) on this side
    MaxPoints,
    /// the corrector failed at the smallest step
    StepTooSmall { parameter: f64, speed_m_s: f64 },
    /// the frequency fell to zero: the curve ends at a Bogdanov–Takens point
    BogdanovTakens { parameter: f64, speed_m_s: f64 },
    /// the curve came back to its start: a closed curve inside the box
    Closed,
    /// the cancellation hook asked to stop
    Cancelled,
    /// a model could not be built or evaluated
    Failed { message: String },
    /// no fold (flip, torus point) of cycles could be solved beyond the last point at the
    /// smallest step: that point's key value (SI) and speed, and why, in words
    Unsolved {
        parameter: f64,
        speed_m_s: f64,
        message: String,
    },
    /// a curve of cycles ended otherwise (a bound, a limit, a codimension-two point), in words
    Lost { message: String },
}

impl CurveStop {
    /// In words, with the numbers.
    pub fn describe(&self) -> String {
        match self {
            CurveStop::ParameterBound { parameter } => {
                format!("end of the key's range ({parameter})")
            }
            CurveStop::SpeedBound { speed_m_s } => {
                format!("end of the speed range ({speed_m_s} m/s)")
            }
            CurveStop::MaxPoints => "step limit (max_points)".into(),
            CurveStop::StepTooSmall {
                parameter,
                speed_m_s,
            } => format!("step too small at key value {parameter}, {speed_m_s} m/s"),
            CurveStop::BogdanovTakens {
                parameter,
                speed_m_s,
            } => format!(
                "the frequency falls to zero near key value {parameter}, {speed_m_s} m/s (Bogdanov-Takens)"
            ),
            CurveStop::Closed => "the curve closed on itself".into(),
            CurveStop::Cancelled => "cancelled".into(),
            CurveStop::Failed { message } => format!("failed: {message}"),
            CurveStop::Unsolved { message, .. } | CurveStop::Lost { message } => message.clone(),
        }
    }
}

/// On which side of a Hopf point (in speed) the centred motion is stable.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StableSide {
    /// stable just below the point's speed (an onset)
    Below,
    /// stable just above it (a recovery)
    Above,
    /// unstable on both sides (another mode is unstable there)
    Neither,
}

impl StableSide {
    /// `"below"`, `"above"`, `"neither"`.
    pub fn name(self) -> &'static str {
        match self {
            StableSide::Below => "below",
            StableSide::Above => "above",
            StableSide::Neither => "neither",
        }
    }
}

/// One point of a curve.
#[derive(Clone, Debug, PartialEq)]
pub struct CurvePoint {
    /// the key's value (SI unit of the key)
    pub parameter: f64,
    /// speed (m/s)
    pub speed_m_s: f64,
    /// frequency (Hz)
    pub frequency_hz: f64,
    /// cycle amplitude (m): 0 on a Hopf curve
    pub amplitude_m: f64,
    /// first Lyapunov coefficient (1/m², docs/model.md §12), when computed
    pub first_lyapunov_coefficient: Option<f64>,
    /// its error estimate (1/m²)
    pub first_lyapunov_error: Option<f64>,
    /// the Hopf type from $l_1$
    pub hopf_type: Option<HopfKind>,
    /// where the centred motion is stable (Hopf curves; `Neither` on fold curves)
    pub stable_side: StableSide,
    /// on a fold curve: whether a stable cycle branch ends at the fold (a hunting motion
    /// disappears there, so the fold can be V_NL); `None` on Hopf curves
    pub stable_cycle: Option<bool>,
    /// on a torus curve: the angle θ (rad) of the shooting map's multipliers e^{±iθ} on the
    /// unit circle (the torus's rotation number is θ/2π); `None` elsewhere
    pub torus_angle_rad: Option<f64>,
    /// on a fold, flip or torus curve: the cycle's state at its section (the model's state
    /// order, SI), where a simulation or the attractor search can start on the curve's motion;
    /// empty on Hopf curves
    pub cycle_state: Vec<f64>,
}

/// One continued curve.
#[derive(Clone, Debug, PartialEq)]
pub struct Curve {
    /// what it continues
    pub kind: CurveKind,
    /// the creep law of its model
    pub creep_law: CreepLaw,
    /// the speed it is: `"V_L"` (Kalker) or `"V_H"` (the creep law's Hopf speed)
    pub label: &'static str,
    /// points in order along the curve
    pub points: Vec<CurvePoint>,
    /// why each end stopped: (first point's end, last point's end)
    pub stops: (CurveStop, CurveStop),
    /// the key's value where it was found (SI)
    pub seed_parameter: f64,
}

/// A codimension-two point.
#[derive(Clone, Debug, PartialEq)]
pub struct SpecialPoint {
    /// what it is
    pub kind: SpecialKind,
    /// index of its curve in [`CurveReport::curves`]
    pub curve: usize,
    /// the other curve through the point (a double Hopf point lies on the curves of both
    /// pairs; a bracketed cusp joins the ends of two fold curves), when that curve was
    /// continued too
    pub other_curve: Option<usize>,
    /// key value (SI)
    pub parameter: f64,
    /// speed (m/s)
    pub speed_m_s: f64,
    /// frequency of the continued pair (Hz)
    pub frequency_hz: f64,
    /// the second pair's frequency at a double Hopf point (Hz)
    pub second_frequency_hz: Option<f64>,
    /// located to tolerance (true) or only bracketed/extrapolated
    pub located: bool,
}

/// Where the centred motion is stable, for one creep law: at each key value of a grid, the
/// top of the stable band of speeds that starts at the bottom of the speed range.
#[derive(Clone, Debug, PartialEq)]
pub struct StableRegion {
    /// the creep law
    pub creep_law: CreepLaw,
    /// `"V_L"` or `"V_H"`, as its curves
    pub label: &'static str,
    /// (key value SI, top speed m/s): the lowest onset on the law's curves at that value, the
    /// top of the speed range when there is none, NaN when the centred motion is already
    /// unstable at the bottom of the speed range
    pub top: Vec<(f64, f64)>,
}

/// Solver statistics of a run.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct CurveStats {
    /// models built (the main cost)
    pub models_built: usize,
    /// Newton iterations of accepted correctors
    pub newton_iterations: usize,
    /// rejected steps
    pub rejected_steps: usize,
}

/// Everything `critspeed curve` computes.
#[derive(Clone, Debug, PartialEq)]
pub struct CurveReport {
    /// study name
    pub study: String,
    /// the design key
    pub key: String,
    /// its dimension (unit)
    pub dimension: Dimension,
    /// the key's range (SI), as asked
    pub range: (f64, f64),
    /// whether the key's axis is logarithmic
    pub log: bool,
    /// speed range (m/s)
    pub speed_range: (f64, f64),
    /// the curves
    pub curves: Vec<Curve>,
    /// codimension-two points on them
    pub special_points: Vec<SpecialPoint>,
    /// the stable region of each creep law (for the plot's shading)
    pub stable_regions: Vec<StableRegion>,
    /// V_NL against the key: (key value, m/s) at the fold curves' key values: the lowest fold
    /// where a stable cycle branch ends, and V_H where the Hopf point is supercritical
    pub nonlinear_critical_speed: Vec<(f64, f64)>,
    /// the fold grid's key values where the continuation gives no V_NL (the lowest Hopf point
    /// subcritical and no stable-side fold followed there), in the key's order
    pub nonlinear_unknown: Vec<f64>,
    /// how V_NL was found at each value of `nonlinear_critical_speed`, in its order: by the
    /// continuation (the curves), or by the attractor search where that found hunting lower
    pub nonlinear_methods: Vec<VnlMethod>,
    /// the attractor search at each V_NL value (`curve.attractors = true`; else empty)
    pub attractor_search: Vec<SearchAt>,
    /// what was asked for and could not be computed, and why
    pub notes: Vec<String>,
    /// solver statistics
    pub stats: CurveStats,
}

/// How a value of V_NL against the key was found: by the continuation (here the fold curves,
/// or the supercritical V_H) or by the attractor search (the same two methods, and names, as
/// in `critspeed bifurcation` and `critspeed attractors`).
pub use crate::bifurcation::vnl::VnlMethod;

/// The attractor search of the study rewritten at one V_NL value of the key.
#[derive(Clone, Debug, PartialEq)]
pub struct SearchAt {
    /// the key's value (SI)
    pub parameter: f64,
    /// V_NL there from the curves (m/s; NaN where they give none)
    pub continuation_m_s: f64,
    /// the lowest speed at which the search found a hunting attractor (m/s), if any
    pub search_m_s: Option<f64>,
    /// the speeds between which that attractor dies (m/s)
    pub bracket_m_s: Option<(f64, f64)>,
    /// the bracket is open at its lower end (no verdict there: the attractor may live lower)
    pub bracket_open: bool,
    /// why the search failed, when it did
    pub error: Option<String>,
}

/// Why the curves could not be computed.
#[derive(Debug, thiserror::Error)]
pub enum CurveError {
    /// a `[curve]` value broke its rule (a user error)
    #[error("{key} = {value}: {rule}")]
    Spec {
        key: String,
        value: String,
        rule: String,
    },
    /// the study itself is invalid (a user error)
    #[error(transparent)]
    Study(crate::study::StudyError),
    /// a model could not be built at a key value
    #[error("at key value {parameter}: {message}")]
    Model { parameter: f64, message: String },
    /// Newton's method on the Hopf system did not converge
    #[error("the Hopf point could not be corrected near {speed_m_s} m/s, key value {parameter}")]
    Corrector { speed_m_s: f64, parameter: f64 },
    /// nothing to continue
    #[error("{0}")]
    Nothing(String),
}

impl CurveError {
    /// Whether the error is the user's (exit code 2) rather than the computation's.
    pub fn is_user_error(&self) -> bool {
        matches!(self, CurveError::Spec { .. } | CurveError::Study(_))
    }
}
