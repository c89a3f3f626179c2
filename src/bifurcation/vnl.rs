//! The nonlinear critical speed V_NL (docs/model.md §9): the lowest speed at which any stable
//! non-equilibrium motion exists, over every branch the continuation followed and, where a
//! search ran, every attractor it found.
//!
//! From the continuation the candidates are: the supercritical Hopf point (its first cycles are
//! stable); every special point next to a stable cycle of its branch (a fold where the stable
//! part of a branch turns, a symmetry-breaking or period-doubling point where a branch's stable
//! part ends or a stable child begins: located points); and every stable cycle (only as low as
//! the lowest one computed). The lowest wins; ties go to a located point.
//!
//! Joining these with the attractor search's candidate is done above both analyses (the
//! crate's `reconcile` module), so that this module knows nothing of the search.

use super::{BifurcationReport, BranchKind, HopfType};

/// Which method found a candidate for V_NL.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum VnlMethod {
    /// the continuation of cycles with branch switching (`critspeed bifurcation`)
    Continuation,
    /// the search for attractors by simulation from many initial states, each attractor
    /// followed down in speed (`critspeed attractors`)
    AttractorSearch,
}

impl VnlMethod {
    /// As written in outputs.
    pub fn name(self) -> &'static str {
        match self {
            VnlMethod::Continuation => "continuation",
            VnlMethod::AttractorSearch => "attractor search",
        }
    }
}

/// One candidate for V_NL: a speed, what lies there and how it was found.
#[derive(Clone, Debug, PartialEq)]
pub struct VnlCandidate {
    /// speed (m/s)
    pub speed_m_s: f64,
    /// located to the method's tolerance (a located special point, the Hopf point, a search
    /// bracket), or only the lowest computed instance
    pub located: bool,
    /// how it was found
    pub method: VnlMethod,
    /// what it is, in words ("fold of asymmetric cycles", "stable symmetric cycle",
    /// "supercritical Hopf point", "asymmetric cycle", …)
    pub what: String,
    /// the continuation's branch id, when it lies on one
    pub branch: Option<usize>,
    /// the search's bracket (m/s): the attractor exists at the upper end and not at the lower
    pub bracket_m_s: Option<(f64, f64)>,
    /// the bracket is open: at its lower end the motion had no verdict (still drifting after
    /// the extended simulation), so the attractor may live lower and the speed is an upper
    /// bound of its death, not a bracket
    pub bracket_open: bool,
}

impl VnlCandidate {
    /// ", dies in [a, b] m/s" with `digits` decimals, and whether the bracket is open; empty
    /// without a bracket.
    pub fn bracket_words(&self, digits: usize) -> String {
        match self.bracket_m_s {
            None => String::new(),
            Some((a, b)) if self.bracket_open => format!(
                ", dies in [{a:.digits$}, {b:.digits$}] m/s, a bracket open at its lower end (no \
                 verdict there after the extended simulation: the attractor may live lower)"
            ),
            Some((a, b)) => format!(", dies in [{a:.digits$}, {b:.digits$}] m/s"),
        }
    }
}

/// Every candidate from the continuation.
pub fn continuation_candidates(r: &BifurcationReport) -> Vec<VnlCandidate> {
    let kind_of = |b: usize| r.branches.get(b).map_or(BranchKind::Symmetric, |x| x.kind);
    let mut out = Vec::new();
    if let (Some(HopfType::Supercritical), Some(h)) = (r.hopf_type, r.hopf) {
        if r.cycles.first().is_some_and(|c| c.stable && c.branch == 0) {
            out.push(VnlCandidate {
                speed_m_s: h.speed_m_s,
                located: true,
                method: VnlMethod::Continuation,
                what: "supercritical Hopf point".into(),
                branch: Some(0),
                bracket_m_s: None,
                bracket_open: false,
            });
        }
    }
    for s in &r.special {
        let stable_next = [s.after, s.after + 1]
            .iter()
            .filter_map(|&i| r.cycles.get(i))
            .any(|c| c.branch == s.branch && c.stable);
        if stable_next {
            out.push(VnlCandidate {
                speed_m_s: s.speed_m_s,
                located: s.located,
                method: VnlMethod::Continuation,
                what: format!(
                    "{} of {} cycles",
                    s.kind.name().replace('_', " "),
                    kind_of(s.branch).name()
                ),
                branch: Some(s.branch),
                bracket_m_s: None,
                bracket_open: false,
            });
        }
    }
    for c in r.cycles.iter().filter(|c| c.stable) {
        out.push(VnlCandidate {
            speed_m_s: c.speed_m_s,
            located: false,
            method: VnlMethod::Continuation,
            what: format!("stable {} cycle", kind_of(c.branch).name()),
            branch: Some(c.branch),
            bracket_m_s: None,
            bracket_open: false,
        });
    }
    out
}

/// The lowest candidate (a located one on a tie).
pub fn lowest(candidates: &[VnlCandidate]) -> Option<&VnlCandidate> {
    candidates.iter().min_by(|a, b| {
        a.speed_m_s
            .total_cmp(&b.speed_m_s)
            .then(b.located.cmp(&a.located))
    })
}

/// V_NL from the continuation alone, and its source.
pub fn from_continuation(r: &BifurcationReport) -> (Option<(f64, bool)>, Vec<VnlCandidate>) {
    let all = continuation_candidates(r);
    match lowest(&all) {
        Some(c) => (Some((c.speed_m_s, c.located)), vec![c.clone()]),
        None => (None, Vec::new()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bifurcation::{BranchRow, CycleRow, SpecialRow};
    use crate::contact::creep::CreepLaw;
    use crate::continuation::{BranchStats, SpecialKind};
    use crate::stability::{Crossing, Direction};

    fn cycle(branch: usize, speed_m_s: f64, stable: bool) -> CycleRow {
        CycleRow {
            branch,
            speed_m_s,
            amplitude_y_m: 1e-3,
            amplitude_sides_y_m: (1e-3, 1e-3),
            wheelset_amplitude_m: 1e-3,
            amplitude_psi_rad: 1e-3,
            period_s: 0.1,
            stable,
            max_multiplier_abs: if stable { 0.5 } else { 2.0 },
            trivial_multiplier_error: 0.0,
            newton_iterations: 2,
            x0: vec![0.0; 4],
            multipliers: vec![(1.0, 0.0); 4],
            body_amplitudes: Vec::new(),
        }
    }

    fn special(branch: usize, kind: SpecialKind, speed_m_s: f64, after: usize) -> SpecialRow {
        SpecialRow {
            branch,
            kind,
            speed_m_s,
            amplitude_y_m: 5e-3,
            wheelset_amplitude_m: 5e-3,
            located: true,
            after,
        }
    }

    fn branch(id: usize, kind: BranchKind) -> BranchRow {
        BranchRow {
            id,
            kind,
            parent: (id > 0).then_some((0, 0)),
            switch_multiplier: None,
            stop_reason: String::new(),
            cycles: 0,
            segments: 1,
            segments_doubled: Vec::new(),
        }
    }

    fn report(cycles: Vec<CycleRow>, special: Vec<SpecialRow>) -> BifurcationReport {
        BifurcationReport {
            study: "synthetic".into(),
            law: CreepLaw::Shen { friction: 0.3 },
            kalker_critical_speed_m_s: Some(100.0),
            hopf: Some(Crossing {
                speed_m_s: 100.0,
                frequency_hz: 5.0,
                wavelength_m: 20.0,
                direction: Direction::Onset,
                bracket_m_s: 1e-12,
            }),
            hopf_type: Some(HopfType::Supercritical),
            first_lyapunov: None,
            nonlinear_critical_speed: None,
            nonlinear_sources: Vec::new(),
            branches: vec![
                branch(0, BranchKind::Symmetric),
                branch(1, BranchKind::Asymmetric),
            ],
            cycles,
            special,
            stop_reason: String::new(),
            notes: Vec::new(),
            speed_range: (1.0, 200.0),
            layout: "wheelset",
            body_names: vec!["wheelset 1".into()],
            state_names: Vec::new(),
            stats: BranchStats::default(),
        }
    }

    /// A supercritical branch (stable from V_H = 100) that turns back at 110, comes down to a
    /// fold at 80 and is stable again above it: V_NL is the fold at 80 (docs/model.md §9), not the Hopf
    /// speed. Without the fold-back V_NL is V_H.
    #[test]
    fn the_lowest_stable_cycle_of_the_branch_sets_v_nl() {
        let mut r = report(
            vec![
                cycle(0, 100.5, true),
                cycle(0, 110.0, true),
                cycle(0, 95.0, false),
            ],
            vec![special(0, SpecialKind::Fold, 110.2, 1)],
        );
        let (v, src) = from_continuation(&r);
        assert!(
            v.is_some_and(|v| (v.0 - 100.0).abs() < 1e-12 && v.1),
            "{v:?}"
        );
        assert_eq!(src[0].what, "supercritical Hopf point");
        r.cycles.extend([
            cycle(0, 80.0, false),
            cycle(0, 80.5, true),
            cycle(0, 90.0, true),
        ]);
        r.special.push(special(0, SpecialKind::Fold, 79.9, 3));
        let (v, src) = from_continuation(&r);
        assert!(
            v.is_some_and(|(v, located)| (v - 79.9).abs() < 1e-12 && located),
            "{v:?}"
        );
        assert_eq!(src[0].what, "fold of symmetric cycles");
    }

    /// A fold between two unstable stretches says nothing about stable motion; a stable
    /// asymmetric branch below every symmetric cycle sets V_NL through its own fold.
    #[test]
    fn a_fold_of_unstable_cycles_does_not_count_and_other_branches_do() {
        let r = report(
            vec![
                cycle(0, 100.5, true),
                cycle(0, 90.0, false),
                cycle(0, 60.0, false),
                cycle(0, 70.0, false),
                cycle(1, 95.0, false),
                cycle(1, 72.0, true),
                cycle(1, 85.0, true),
            ],
            vec![
                special(0, SpecialKind::Fold, 59.0, 2),
                special(1, SpecialKind::Fold, 71.5, 4),
            ],
        );
        let (v, src) = from_continuation(&r);
        assert!(v.is_some_and(|(v, _)| (v - 71.5).abs() < 1e-12), "{v:?}");
        assert_eq!(src[0].what, "fold of asymmetric cycles");
        assert_eq!(src[0].branch, Some(1));
    }
}
