//! The search for every attractor over speed (docs/model.md §12): simulations from many initial states at
//! a descending sequence of speeds, each motion classified when it has settled, every attractor
//! found followed down in speed from its own state until it dies, and the speed where it dies
//! bracketed by bisection.
//!
//! It complements the continuation ([`crate::bifurcation`]), which sees only the branches of
//! cycles connected to the Hopf point through the points it switches at, and no tori or chaos;
//! the search sees every attractor that a stated set of initial states reaches, but no unstable
//! cycles and no folds. The nonlinear critical speed is the lowest over both
//! ([`crate::bifurcation::vnl`]).
//!
//! * [`classify`]: one motion at one speed.
//! * [`search`]: the grid of speeds and initial states, the basin fractions, the descents and
//!   the bisection.

pub mod classify;
pub mod search;

pub use search::{search, search_with_hooks, AttractorOptions, Seed, StartKind};

/// What a settled motion is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MotionKind {
    /// every body's lateral excursion below the threshold (or steadily decaying to it)
    Equilibrium,
    /// a stable symmetric cycle, x(t + T/2) = −x(t)
    SymmetricCycle,
    /// a stable asymmetric cycle of one return per period (one of a mirror pair)
    AsymmetricCycle,
    /// a stable cycle of k returns to the section per period (k ≥ 2: after period doublings)
    PeriodK(usize),
    /// recurrent, not periodic, largest Lyapunov exponent ≈ 0 (a torus)
    QuasiPeriodic,
    /// recurrent, largest Lyapunov exponent > 0
    Chaotic,
    /// a wheelset left the contact geometry's range (no verdict on extrapolated geometry)
    OutOfRange,
    /// the integration failed (a blow-up)
    Diverged,
    /// still drifting at the time limit (a slow transient)
    Unsettled,
}

impl MotionKind {
    /// As written in outputs.
    pub fn name(self) -> String {
        match self {
            MotionKind::Equilibrium => "equilibrium".into(),
            MotionKind::SymmetricCycle => "symmetric cycle".into(),
            MotionKind::AsymmetricCycle => "asymmetric cycle".into(),
            MotionKind::PeriodK(k) => format!("period-{k} cycle"),
            MotionKind::QuasiPeriodic => "quasi-periodic".into(),
            MotionKind::Chaotic => "chaotic".into(),
            MotionKind::OutOfRange => "out of the geometry's range".into(),
            MotionKind::Diverged => "diverged".into(),
            MotionKind::Unsettled => "unsettled".into(),
        }
    }

    /// A hunting attractor: a stable non-equilibrium motion (what V_NL is the lowest speed of).
    pub fn is_hunting(self) -> bool {
        matches!(
            self,
            MotionKind::SymmetricCycle
                | MotionKind::AsymmetricCycle
                | MotionKind::PeriodK(_)
                | MotionKind::QuasiPeriodic
                | MotionKind::Chaotic
        )
    }
}

/// One body's amplitudes over a motion.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BodyAmplitude {
    /// largest excursion to the right, max y (m)
    pub y_right_m: f64,
    /// largest excursion to the left, max −y (m)
    pub y_left_m: f64,
    /// yaw amplitude max |ψ| (rad)
    pub psi_rad: f64,
}

impl BodyAmplitude {
    /// max |y| (m).
    pub fn y_m(&self) -> f64 {
        self.y_right_m.max(self.y_left_m)
    }
}

/// A classified motion at one speed.
#[derive(Clone, Debug, PartialEq)]
pub struct Motion {
    /// what it is
    pub kind: MotionKind,
    /// speed (m/s)
    pub speed_m_s: f64,
    /// period of a cycle (s; the exact cycle's, from Newton)
    pub period_s: Option<f64>,
    /// every body's amplitudes, in body order (of the exact cycle for a cycle; of the last
    /// return interval otherwise)
    pub amplitudes: Vec<BodyAmplitude>,
    /// the largest lateral excursion of any wheelset (m)
    pub excursion_m: f64,
    /// largest modulus of the cycle's nontrivial Floquet multipliers
    pub max_multiplier: Option<f64>,
    /// largest Lyapunov exponent (1/s), for the motions that did not settle on a cycle
    pub lyapunov_per_s: Option<f64>,
    /// a state on the attractor (a cycle's start for a cycle), in the model's state order
    pub state: Vec<f64>,
    /// simulated time until the verdict (s)
    pub time_s: f64,
    /// how the verdict was reached, in words, where it needs saying
    pub note: String,
}

impl Motion {
    /// A verdict with no amplitudes.
    pub fn simple(kind: MotionKind, speed_m_s: f64, time_s: f64) -> Self {
        Motion {
            kind,
            speed_m_s,
            period_s: None,
            amplitudes: Vec::new(),
            excursion_m: 0.0,
            max_multiplier: None,
            lyapunov_per_s: None,
            state: Vec::new(),
            time_s,
            note: String::new(),
        }
    }

    /// The largest wheelset's max |y| (m): the hunting amplitude (on a car one bogie may hunt
    /// while the other is nearly still, so the leading wheelset's alone can mislead).
    pub fn amplitude_m(&self) -> f64 {
        self.excursion_m
    }
}

/// One attractor, found at one speed and followed down to where it dies.
#[derive(Clone, Debug, PartialEq)]
pub struct Attractor {
    /// its number in the report
    pub id: usize,
    /// what it is where it was found
    pub kind: MotionKind,
    /// the highest speed where it was found (m/s)
    pub found_at_m_s: f64,
    /// the motion at every speed of its descent, highest first
    pub path: Vec<Motion>,
    /// where it dies: (a speed where it no longer exists, the lowest where it does) (m/s);
    /// `None` when it still exists at the lowest speed searched
    pub dies_m_s: Option<(f64, f64)>,
    /// the bracket is open: below its lower end the motion had no verdict even after the
    /// extended simulation ([`search::UNSETTLED_EXTENSIONS`]), so the attractor may live lower
    pub open_below: bool,
    /// what the motion does below that, in words
    pub fate: String,
    /// the continuation's branch whose cycle it equals, where one does (id, and the cycle's
    /// relative differences in amplitude and period)
    pub branch: Option<(usize, f64, f64)>,
}

impl Attractor {
    /// The lowest speed where it exists (m/s).
    pub fn lowest_m_s(&self) -> f64 {
        self.dies_m_s
            .map(|d| d.1)
            .or_else(|| self.path.last().map(|m| m.speed_m_s))
            .unwrap_or(self.found_at_m_s)
    }
}

/// The verdict of the search on one seed ([`AttractorOptions::seeds`]): what its simulation
/// settled on and, where it hunts, the attractor it is and where that attractor dies.
#[derive(Clone, Debug, PartialEq)]
pub struct SeedCheck {
    /// where the seed comes from, in words
    pub source: String,
    /// the speed it was simulated at (m/s)
    pub speed_m_s: f64,
    /// the motion it settled on
    pub motion: Motion,
    /// the attractor it is (its id), when it hunts
    pub attractor: Option<usize>,
    /// that attractor's lowest speed (m/s)
    pub lowest_m_s: Option<f64>,
    /// and the bracket of its death (m/s), when it dies in the range searched
    pub dies_m_s: Option<(f64, f64)>,
    /// whether that bracket is open below ([`Attractor::open_below`])
    pub open_below: bool,
}

impl SeedCheck {
    /// Whether the seed hunts: a hunting attractor lives at its speed.
    pub fn confirmed(&self) -> bool {
        self.attractor.is_some()
    }
}

/// The share of the initial states at one speed that end on each outcome.
#[derive(Clone, Debug, PartialEq)]
pub struct Outcome {
    /// the attractor's id (`None` for the equilibrium and the non-attractors)
    pub attractor: Option<usize>,
    /// what it is
    pub kind: MotionKind,
    /// initial states ending there
    pub count: usize,
    /// count over the initial states at this speed (the basin fraction)
    pub fraction: f64,
    /// leading wheelset's amplitude (m; 0 for the equilibrium)
    pub amplitude_m: f64,
}

/// One speed of the grid.
#[derive(Clone, Debug, PartialEq)]
pub struct SpeedRow {
    /// speed (m/s)
    pub speed_m_s: f64,
    /// initial states simulated
    pub starts: usize,
    /// what they ended on
    pub outcomes: Vec<Outcome>,
    /// a speed added between the grid's below the lowest hunting speed known (the grid's
    /// spacing halved there), not one of the `speeds` of the grid
    pub refined: bool,
}

/// V_NL by the search: the lowest speed with a hunting attractor (m/s), the bracket of its
/// death (m/s: it no longer exists at the first, still does at the second) and its id.
pub type SearchVnl = (f64, Option<(f64, f64)>, usize);

/// Everything the search produces.
#[derive(Clone, Debug, PartialEq)]
pub struct AttractorReport {
    /// study name
    pub study: String,
    /// the bodies in state order
    pub body_names: Vec<String>,
    /// the options used
    pub options: AttractorOptions,
    /// the initial states at each speed: what each is
    pub starts: Vec<(StartKind, String)>,
    /// the grid, highest speed first
    pub speeds: Vec<SpeedRow>,
    /// every attractor found
    pub attractors: Vec<Attractor>,
    /// V_NL(search): the lowest speed with a hunting attractor (m/s), the bracket of its death
    /// (m/s) and the attractor's id
    pub nonlinear_critical_speed: Option<SearchVnl>,
    /// the verdict on each of [`AttractorOptions::seeds`], in their order
    pub seed_checks: Vec<SeedCheck>,
    /// notes in words (motions that left the geometry's range, that did not settle)
    pub notes: Vec<String>,
    /// simulations run
    pub simulations: usize,
}
