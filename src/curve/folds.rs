//! The fold curves and V_NL against the key: the diagrams at the study's own key value and at
//! a few values of the fold grid, their located folds of cycles continued over the key as
//! solutions of the fold system (`crate::bifurcation::fold_track`), and V_NL at each grid value
//! from the folds and the supercritical V_H.

use crate::bifurcation::fold_track::{
    FoldSpecial, FoldSpecialKind, FoldTrack, FoldTracking, TrackKind, TrackStop,
};
use crate::bifurcation::{self, BranchKind, Hooks};
use crate::contact::creep::CreepLaw;
use crate::continuation::PoolBusy;
use crate::stability::HopfKind;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Condvar, Mutex, MutexGuard, PoisonError};
use std::time::Instant;

use super::keyed::KeyedStudy;
use super::run::to_p;
use super::spec::CurveSpec;
use super::{
    Curve, CurveError, CurveKind, CurvePoint, CurveReport, CurveStop, SpecialKind, SpecialPoint,
    StableSide,
};

/// The key's value at `P` = `p`.
fn from_p(spec: &CurveSpec, p: f64) -> f64 {
    if spec.log {
        p.exp()
    } else {
        p
    }
}

/// `fold_points` key values evenly spaced on the key's axis from `from` to `to`, the ends
/// exactly as written.
fn values(spec: &CurveSpec) -> Vec<f64> {
    let n = spec.fold_points.max(2);
    let (p0, p1) = (to_p(spec, spec.range.0), to_p(spec, spec.range.1));
    (0..n)
        .map(|i| match i {
            0 => spec.range.0,
            _ if i + 1 == n => spec.range.1,
            _ => from_p(spec, p0 + (p1 - p0) * i as f64 / (n - 1) as f64),
        })
        .collect()
}

/// Where the diagram is computed: the study's own value of the key when it lies in the range
/// (where the study's diagram is known), else `from`; and the grid's values after it (towards
/// `to`) and before it (nearest first).
fn split(spec: &CurveSpec, own: Option<f64>, grid: &[f64]) -> (f64, Vec<f64>, Vec<f64>) {
    let (a, b) = (
        spec.range.0.min(spec.range.1),
        spec.range.0.max(spec.range.1),
    );
    let seed = own.filter(|v| (a..=b).contains(v)).unwrap_or(spec.range.0);
    let beyond = |v: f64| (v - seed) * (spec.range.1 - spec.range.0) > 0.0;
    let fore: Vec<f64> = grid.iter().copied().filter(|&v| beyond(v)).collect();
    let back: Vec<f64> = grid
        .iter()
        .rev()
        .copied()
        .filter(|&v| v != seed && !beyond(v))
        .collect();
    (seed, fore, back)
}

/// The curve kind and label of a track: a fold of cycles of the branch's kind, or a flip,
/// which is a symmetry-breaking point on a symmetric branch and a period doubling else.
fn kind_and_label(t: &FoldTrack) -> (CurveKind, &'static str) {
    match (t.kind, t.branch_kind) {
        (TrackKind::Fold, BranchKind::Symmetric) => (CurveKind::Fold, "fold (symmetric)"),
        (TrackKind::Fold, BranchKind::Asymmetric) => (CurveKind::Fold, "fold (asymmetric)"),
        (TrackKind::Fold, BranchKind::Period(_)) => (CurveKind::Fold, "fold (doubled)"),
        (TrackKind::Flip, BranchKind::Symmetric) => {
            (CurveKind::SymmetryBreaking, "symmetry breaking")
        }
        (TrackKind::Flip, BranchKind::Asymmetric) => {
            (CurveKind::PeriodDoubling, "period doubling (asymmetric)")
        }
        (TrackKind::Flip, BranchKind::Period(_)) => {
            (CurveKind::PeriodDoubling, "period doubling (doubled)")
        }
        (TrackKind::Torus, BranchKind::Symmetric) => (CurveKind::Torus, "torus (symmetric)"),
        (TrackKind::Torus, BranchKind::Asymmetric) => (CurveKind::Torus, "torus (asymmetric)"),
        (TrackKind::Torus, BranchKind::Period(_)) => (CurveKind::Torus, "torus (doubled)"),
    }
}

/// Whether a curve of kind `curve` continues points of the fold system's kind `track`.
fn continues(track: TrackKind, curve: CurveKind) -> bool {
    match track {
        TrackKind::Fold => curve == CurveKind::Fold,
        TrackKind::Flip => {
            matches!(
                curve,
                CurveKind::SymmetryBreaking | CurveKind::PeriodDoubling
            )
        }
        TrackKind::Torus => curve == CurveKind::Torus,
    }
}

fn label(t: &FoldTrack) -> &'static str {
    kind_and_label(t).1
}

/// Adds the fold curves of `study` to `report`, and V_NL against the key.
pub(super) fn fold_curves(
    study: &KeyedStudy,
    spec: &CurveSpec,
    cancel: Option<&(dyn Fn() -> bool + Sync)>,
    progress: Option<&(dyn Fn(&str) + Sync)>,
    report: &mut CurveReport,
) -> Result<(), CurveError> {
    let grid = values(spec);
    let own = study.own_value();
    let mut kinds = Vec::new();
    if spec.curves.contains(&CurveKind::Fold) {
        kinds.push(TrackKind::Fold);
    }
    if spec.curves.contains(&CurveKind::SymmetryBreaking)
        || spec.curves.contains(&CurveKind::PeriodDoubling)
    {
        kinds.push(TrackKind::Flip);
    }
    if spec.curves.contains(&CurveKind::Torus) {
        kinds.push(TrackKind::Torus);
    }
    // the diagrams: at the study's own value (else `from`), then at `seed_points` values of
    // the grid, each following only the folds no curve passes through yet
    let n = grid.len();
    let k = spec.seed_points.min(n).max(1);
    let mut seeds: Vec<Option<f64>> = vec![own];
    seeds.extend((0..k).map(|i| grid.get(i * (n - 1) / (k - 1).max(1)).copied()));
    let law = study
        .base
        .model()
        .map_or(crate::contact::creep::CreepLaw::Kalker, |m| m.creep_law());
    let start = report.curves.len();
    // the values every fold curve is solved at (user points): the grid and the first
    // diagram's value (the study's own), so that V_NL there sees every curve, whichever
    // diagram it was followed from
    let first_value = split(spec, own, &grid).0;
    let mut pins = grid.clone();
    if !pins.contains(&first_value) {
        pins.push(first_value);
        pins.sort_by(|a, b| ((a - b) * (spec.range.1 - spec.range.0)).total_cmp(&0.0));
    }
    // the distinct diagram values in order, each with the pinned values beyond and before it
    let mut jobs: Vec<(f64, Vec<f64>, Vec<f64>)> = Vec::new();
    for seed in seeds {
        let job = split(spec, seed, &pins);
        if !jobs.iter().any(|j| j.0 == job.0) {
            jobs.push(job);
        }
    }
    let first_seed = jobs.first().map(|j| j.0);
    let diagrams = Diagrams {
        study,
        spec,
        cancel,
        progress,
        kinds: &kinds,
        law,
        start,
        // Inside the pool (a caller that is itself a rayon job, whose blocking could starve
        // it) or with one thread: one diagram after the other.
        concurrent: rayon::current_thread_index().is_none() && rayon::current_num_threads() > 1,
        origin: Instant::now(),
        turns: Mutex::new(Turns {
            report,
            turn: 0,
            computed: vec![false; jobs.len()],
            diagrams: 0,
            error: None,
            broken: false,
        }),
        bell: Condvar::new(),
        following_now: PoolBusy::new(),
        failed: AtomicBool::new(false),
    };
    if diagrams.concurrent {
        let diagrams = &diagrams;
        std::thread::scope(|s| {
            for (k, j) in jobs.iter().enumerate() {
                s.spawn(move || diagrams.run(k, j));
            }
        });
    } else {
        for (k, j) in jobs.iter().enumerate() {
            diagrams.run(k, j);
        }
    }
    let Turns {
        report,
        diagrams,
        error,
        ..
    } = diagrams
        .turns
        .into_inner()
        .unwrap_or_else(PoisonError::into_inner);
    if let Some(e) = error {
        return Err(e);
    }
    let first = first_seed.unwrap_or(spec.range.0);
    for kind in [
        CurveKind::SymmetryBreaking,
        CurveKind::PeriodDoubling,
        CurveKind::Torus,
    ] {
        if spec.curves.contains(&kind) && !report.curves[start..].iter().any(|c| c.kind == kind) {
            report.notes.push(format!(
                "no \"{}\" curve: the diagrams at {diagrams} values of {} (the study's own and {k} of the fold grid) have no such point of a cycle branch to start one from",
                kind.name(),
                spec.key
            ));
        }
    }
    if !spec.curves.contains(&CurveKind::Fold) {
        return Ok(());
    }
    if !report.curves[start..]
        .iter()
        .any(|c| c.kind == CurveKind::Fold)
    {
        report.notes.push(format!(
            "no located fold of cycles in the diagrams at {diagrams} values of {} (the study's own and {k} of the fold grid): no fold curve",
            spec.key
        ));
    }
    let mut at_values = grid.clone();
    if !at_values.contains(&first) {
        at_values.push(first);
        at_values.sort_by(|a, b| ((a - b) * (spec.range.1 - spec.range.0)).total_cmp(&0.0));
    }
    cusps_where_curves_meet(spec, start, report);
    nonlinear_critical_speed(spec, &at_values, report);
    unfollowed_bautin_points(spec, first, report);
    Ok(())
}

/// The diagrams of one run and what they share.
///
/// The diagrams overlap: while one diagram's folds are followed (on the pool's threads, a
/// curve's two sides and its tangent flows in parallel, with idle time between), the next
/// diagrams are computed. The curves stay as they were one diagram at a time: a diagram's
/// folds are considered for curves only when every earlier diagram's curves are in the report
/// (`skip` reads them), and curves are added in diagram order.
///
/// A thread per diagram: the first diagram and every diagram's curves use the pool; the later
/// diagrams, one at a time, are integrated on their own thread while curves are followed and
/// on the pool while none are (`PoolBusy`).
struct Diagrams<'a, 'r> {
    study: &'a KeyedStudy,
    spec: &'a CurveSpec,
    cancel: Option<&'a (dyn Fn() -> bool + Sync)>,
    progress: Option<&'a (dyn Fn(&str) + Sync)>,
    /// what is followed from each diagram
    kinds: &'a [TrackKind],
    law: CreepLaw,
    /// where this run's curves start in the report
    start: usize,
    /// a thread per diagram (else one diagram after the other)
    concurrent: bool,
    /// when the run started (for the progress lines)
    origin: Instant,
    turns: Mutex<Turns<'r>>,
    /// rung when a diagram is computed or its curves are added
    bell: Condvar,
    /// up while a diagram's curves are followed
    following_now: PoolBusy,
    /// a diagram failed: the others stop
    failed: AtomicBool,
}

/// The diagram at `.0`, with the pinned key values beyond it (`.1`) and before it (`.2`).
type Job = (f64, Vec<f64>, Vec<f64>);

impl<'r> Diagrams<'_, 'r> {
    fn say(&self, line: &str) {
        if let Some(p) = self.progress {
            p(line)
        }
    }

    /// The shared state once `ok` holds of it (or a diagram's thread has panicked).
    fn wait_until(&self, ok: &dyn Fn(&Turns) -> bool) -> MutexGuard<'_, Turns<'r>> {
        let mut guard = self.turns.lock().unwrap_or_else(PoisonError::into_inner);
        while !guard.broken && !ok(&guard) {
            guard = self
                .bell
                .wait(guard)
                .unwrap_or_else(PoisonError::into_inner);
        }
        guard
    }

    /// Diagram `k` is computed (its folds may now be considered, the next diagram may start).
    fn computed(&self, k: usize) {
        let mut t = self.turns.lock().unwrap_or_else(PoisonError::into_inner);
        if let Some(c) = t.computed.get_mut(k) {
            *c = true;
        }
        drop(t);
        self.bell.notify_all();
    }

    /// Cancelled, or an earlier diagram failed.
    fn stopped(&self) -> bool {
        self.cancel.is_some_and(|c| c()) || self.failed.load(Ordering::Relaxed)
    }

    /// Diagram `k`: computed when its turn to be computed comes, its folds followed when
    /// every earlier diagram's curves are in, its curves (or its error) added then.
    fn run(&self, k: usize, job: &Job) {
        // a panic in this diagram's work must not leave the later ones waiting for its turn
        let _release = Release(|| {
            self.turns
                .lock()
                .unwrap_or_else(PoisonError::into_inner)
                .broken = true;
            self.bell.notify_all();
        });
        // one diagram at a time beside the curves: the second starts with the first, the
        // next one as soon as the one before it is computed
        drop(self.wait_until(&|t| k < 2 || t.computed.get(k - 1).copied().unwrap_or(true)));
        self.say(&format!(
            "  diagram at {}: computing (from {:.1} s)",
            self.spec.show(job.0),
            self.origin.elapsed().as_secs_f64()
        ));
        let following = Mutex::new(None::<Instant>);
        let outcome = self.compute(k, job, &following);
        self.following_now.set(false);
        self.computed(k);
        let mut t = self.wait_until(&|t| t.turn >= k);
        match outcome {
            Ok(Some(tracks)) => {
                let followed = following
                    .lock()
                    .unwrap_or_else(PoisonError::into_inner)
                    .map_or(0.0, |f| f.elapsed().as_secs_f64());
                self.say(&format!(
                    "  diagram at {}: {} new curves of cycles ({followed:.1} s following them)",
                    self.spec.show(job.0),
                    tracks.len(),
                ));
                t.diagrams += 1;
                add_tracks(self.spec, &tracks, self.law, job.0, t.report);
                t.report.stats.models_built += job.1.len() + job.2.len() + 1;
            }
            Ok(None) => {}
            Err(e) => {
                if t.error.is_none() {
                    t.error = Some(e);
                }
                self.failed.store(true, Ordering::Relaxed);
            }
        }
        t.turn = k + 1;
        drop(t);
        self.bell.notify_all();
    }

    /// Diagram `k`'s whole diagram and the curves followed from it (`None`: stopped before
    /// it started); `following` is set when the following starts.
    fn compute(
        &self,
        k: usize,
        (first, fore, back): &Job,
        following: &Mutex<Option<Instant>>,
    ) -> Result<Option<Vec<FoldTrack>>, CurveError> {
        let first = *first;
        let started = Instant::now();
        if self.stopped() {
            return Ok(None);
        }
        let model = self.study.model_at(first)?;
        let plan = self.study.plan_at(first).map_err(CurveError::Study)?;
        let mut opts = plan.bifurcation_options();
        opts.speed_range = self.spec.speed_range;
        opts.rtol = self.spec.rtol;
        if self.concurrent && k > 0 {
            // beside an earlier diagram's curves: integrated on this thread alone while
            // curves are followed, on the pool while none are (the same diagram: the same
            // segments either way)
            opts.segments = opts.segment_count();
            opts.busy = Some(self.following_now.clone());
        }
        let model_at = |v: f64| self.study.model_at(v).map_err(|e| e.to_string());
        let skip = |kind: TrackKind, symmetric: bool, speed: f64, _amplitude: f64| {
            self.skip(first, kind, symmetric, speed)
        };
        let done = |t: &FoldTrack, seconds: f64| self.followed(first, t, seconds);
        // the earlier diagrams' curves are in: this diagram's folds may be followed
        let ready = || {
            let took = started.elapsed().as_secs_f64();
            self.computed(k);
            drop(self.wait_until(&|t| t.turn >= k));
            self.say(&format!(
                "  diagram at {}: computed in {took:.1} s; following its points over the key (from {:.1} s)",
                self.spec.show(first),
                self.origin.elapsed().as_secs_f64()
            ));
            *following.lock().unwrap_or_else(PoisonError::into_inner) = Some(Instant::now());
            self.following_now.set(true);
        };
        let track = FoldTracking {
            values: fore,
            back,
            first,
            model_at: &model_at,
            kinds: self.kinds,
            skip: &skip,
            done: Some(&done),
            ready: Some(&ready),
        };
        let stopped = || self.stopped();
        let hooks = Hooks {
            progress: None,
            cancel: Some(&stopped),
            branches: None,
        };
        let (_diagram, tracks) = bifurcation::analyse_with_fold_tracks(
            &self.study.base.name,
            &model,
            &opts,
            hooks,
            &track,
        )
        .map_err(|message| CurveError::Model {
            parameter: first,
            message,
        })?;
        Ok(Some(tracks))
    }

    /// Whether the diagram at `first`'s point of `kind` (a cycle at `speed`) is not followed:
    /// a flip of a kind not asked for, or a point an earlier curve already passes through.
    fn skip(&self, first: f64, kind: TrackKind, symmetric: bool, speed: f64) -> bool {
        let spec = self.spec;
        let unasked = match (kind, symmetric) {
            (TrackKind::Flip, true) => !spec.curves.contains(&CurveKind::SymmetryBreaking),
            (TrackKind::Flip, false) => !spec.curves.contains(&CurveKind::PeriodDoubling),
            _ => false,
        };
        if unasked {
            return true;
        }
        let t = self.turns.lock().unwrap_or_else(PoisonError::into_inner);
        t.report.curves[self.start..]
            .iter()
            .filter(|c| continues(kind, c.kind))
            .any(|c| {
                c.points
                    .iter()
                    .any(|p| p.parameter == first && (p.speed_m_s - speed).abs() <= 1e-4 * speed)
            })
    }

    /// The progress line of a curve followed from the diagram at `first` in `seconds`.
    fn followed(&self, first: f64, t: &FoldTrack, seconds: f64) {
        let (lo, hi) = t
            .points
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |a, p| {
                (a.0.min(p.parameter), a.1.max(p.parameter))
            });
        if t.points.is_empty() {
            self.say(&format!(
                "    {} not followed: {} ({seconds:.1} s)",
                label(t),
                t.stops.0.describe()
            ));
            return;
        }
        let at = t.points.iter().find(|p| p.parameter == first);
        self.say(&format!(
            "    {} from {}: {} points over {} in [{}, {}] ({seconds:.1} s)",
            label(t),
            at.map_or("the diagram".into(), |p| format!(
                "{:.3} m/s, {:.3} mm",
                p.speed_m_s,
                p.amplitude_m * 1e3
            )),
            t.points.len(),
            self.spec.key,
            self.spec.quantity(lo),
            self.spec.quantity(hi),
        ))
    }
}

/// The diagrams' shared state while they overlap: the report their curves go to, whose
/// diagram's curves are added next, which diagrams are computed, how many ran and the first
/// error.
struct Turns<'r> {
    report: &'r mut CurveReport,
    turn: usize,
    computed: Vec<bool>,
    diagrams: usize,
    error: Option<CurveError>,
    /// a diagram's thread panicked: nobody waits any more (the panic is raised again when
    /// the threads are joined)
    broken: bool,
}

/// Calls its function when dropped during a panic's unwinding.
struct Release<F: Fn()>(F);

impl<F: Fn()> Drop for Release<F> {
    fn drop(&mut self) {
        if std::thread::panicking() {
            (self.0)();
        }
    }
}

/// Adds the curves of the diagram at `first` asked for by `spec` to `report` (a track that
/// could not be followed becomes a note).
fn add_tracks(
    spec: &CurveSpec,
    tracks: &[FoldTrack],
    law: crate::contact::creep::CreepLaw,
    first: f64,
    report: &mut CurveReport,
) {
    for t in tracks {
        if !spec.curves.contains(&kind_and_label(t).0) {
            // a period doubling when only symmetry breaking was asked, or the reverse
            continue;
        }
        if t.points.is_empty() {
            report.notes.push(format!(
                "a {} of the diagram at {} was not followed: {}",
                label(t),
                spec.show(first),
                t.stops.0.describe()
            ));
            continue;
        }
        let index = report.curves.len();
        for sp in &t.special {
            report.special_points.push(special_point(sp, index));
        }
        report.curves.push(curve(t, law, first));
    }
}

/// A cusp, fold–flip or fold–torus point of the fold curve `curve`.
fn special_point(sp: &FoldSpecial, curve: usize) -> SpecialPoint {
    SpecialPoint {
        kind: match sp.kind {
            FoldSpecialKind::Cusp => SpecialKind::Cusp,
            FoldSpecialKind::FoldFlip => SpecialKind::FoldFlip,
            FoldSpecialKind::FoldSymmetryBreaking => SpecialKind::FoldSymmetryBreaking,
            FoldSpecialKind::FoldTorus => SpecialKind::FoldTorus,
        },
        curve,
        other_curve: None,
        parameter: sp.parameter,
        speed_m_s: sp.speed_m_s,
        frequency_hz: 1.0 / sp.period_s,
        second_frequency_hz: None,
        located: sp.located,
    }
}

fn curve(t: &FoldTrack, law: crate::contact::creep::CreepLaw, first: f64) -> Curve {
    let points = t
        .points
        .iter()
        .map(|p| CurvePoint {
            parameter: p.parameter,
            speed_m_s: p.speed_m_s,
            frequency_hz: 1.0 / p.period_s,
            amplitude_m: p.amplitude_m,
            first_lyapunov_coefficient: None,
            first_lyapunov_error: None,
            hopf_type: None,
            stable_side: StableSide::Neither,
            // (a flip's other multipliers say nothing of a cycle ending there)
            stable_cycle: (t.kind == TrackKind::Fold).then_some(p.stable_side),
            torus_angle_rad: p.angle_rad,
            cycle_state: p.state.clone(),
        })
        .collect();
    let end = |stop: &TrackStop| match stop {
        TrackStop::Unsolved {
            parameter,
            speed_m_s,
            message,
        } => CurveStop::Unsolved {
            parameter: *parameter,
            speed_m_s: *speed_m_s,
            message: message.clone(),
        },
        TrackStop::Ended(message) => CurveStop::Lost {
            message: message.clone(),
        },
    };
    Curve {
        kind: kind_and_label(t).0,
        creep_law: law,
        label: label(t),
        points,
        stops: (end(&t.stops.0), end(&t.stops.1)),
        seed_parameter: first,
    }
}

/// The speed of `curve` at key value `value` (linear in `P` between its points) and the
/// nearer point, if the curve spans `value`.
fn at<'c>(spec: &CurveSpec, curve: &'c Curve, value: f64) -> Option<(f64, &'c CurvePoint)> {
    let x = to_p(spec, value);
    curve.points.windows(2).find_map(|w| {
        let (a, b) = (to_p(spec, w[0].parameter), to_p(spec, w[1].parameter));
        if !(a.min(b) <= x && x <= a.max(b)) {
            return None;
        }
        let t = if a != b { (x - a) / (b - a) } else { 0.0 };
        let near = if t < 0.5 { &w[0] } else { &w[1] };
        Some((w[0].speed_m_s + t * (w[1].speed_m_s - w[0].speed_m_s), near))
    })
}

/// V_NL at every key value of `values`: the lowest of the folds where a stable cycle branch
/// ends and, where the lowest onset of the V_H curves is supercritical, that onset (a stable
/// cycle is born there). Where the lowest onset is subcritical and no fold with a stable side
/// was followed, V_NL is unknown there (it lies below V_H, on a fold that was not followed)
/// and the values are listed in a note. Its jumps, where the lowest changes from one curve to
/// another, go to the notes.
fn nonlinear_critical_speed(spec: &CurveSpec, values: &[f64], report: &mut CurveReport) {
    let mut previous: Option<(f64, f64, String)> = None;
    let mut previous_curve: Option<usize> = None;
    let mut unknown = Vec::new();
    for &value in values {
        // the lowest onset of the study's own creep law at this value
        let onset = report
            .curves
            .iter()
            .enumerate()
            .filter(|(_, c)| c.kind == CurveKind::Hopf && c.label == "V_H")
            .filter_map(|(i, c)| {
                at(spec, c, value)
                    .filter(|(_, p)| p.stable_side == StableSide::Below)
                    .map(|(v, p)| (v, p.hopf_type, i))
            })
            .min_by(|a, b| a.0.total_cmp(&b.0));
        let mut best: Option<(f64, String)> = None;
        let mut best_curve = None;
        if let Some((v, Some(HopfKind::Supercritical), i)) = onset {
            best = Some((v, format!("curve {i} (V_H, supercritical)")));
            best_curve = Some(i);
        }
        for (i, c) in report.curves.iter().enumerate() {
            if c.kind != CurveKind::Fold {
                continue;
            }
            // a curve that turns (a cusp) passes a value twice: its lowest stable-side fold
            let fold = c
                .points
                .iter()
                .filter(|p| p.parameter == value && p.stable_cycle == Some(true))
                .min_by(|a, b| a.speed_m_s.total_cmp(&b.speed_m_s));
            if let Some(p) = fold {
                // two curves through the same fold (followed from two diagrams) are one: the
                // curve V_NL was on before keeps it
                let same = best.as_ref().is_some_and(|b| {
                    (p.speed_m_s - b.0).abs() <= 1e-7 * b.0 && previous_curve == Some(i)
                });
                if best.as_ref().is_none_or(|b| p.speed_m_s < b.0 - 1e-7 * b.0) || same {
                    best = Some((p.speed_m_s, format!("curve {i} ({})", c.label)));
                    best_curve = Some(i);
                }
            }
        }
        let Some((v, source)) = best else {
            if onset.is_some() {
                unknown.push(value);
            }
            continue;
        };
        if let Some((pv, pspeed, psource)) = &previous {
            // the new curve through the previous value's V_NL fold: the same fold, followed
            // from two diagrams (the previous curve ended early), not a change
            let same_fold = best_curve
                .and_then(|i| report.curves.get(i))
                .is_some_and(|c| {
                    c.points.iter().any(|p| {
                        p.parameter == *pv && (p.speed_m_s - pspeed).abs() <= 1e-7 * pspeed
                    })
                });
            if *psource != source && !same_fold {
                // where the previous curve turns back at a cusp inside the interval, or ends
                // there, V_NL jumps there
                let inside = |p: f64| (p - pv) * (value - p) > 0.0;
                let cusp = previous_curve.and_then(|i| {
                    report.special_points.iter().find(|s| {
                        s.kind == SpecialKind::Cusp && s.curve == i && inside(s.parameter)
                    })
                });
                let ends = match cusp {
                    Some(s) => format!(
                        " (that fold curve turns back at a cusp at {}, {:.3} m/s: the stable cycle it bounds exists only on one side)",
                        spec.show(s.parameter), s.speed_m_s
                    ),
                    None => previous_curve
                        .and_then(|i: usize| report.curves.get(i))
                        .and_then(|c| {
                            let last = c.points.iter().max_by(|a, b| {
                                ((a.parameter - b.parameter) * (spec.range.1 - spec.range.0))
                                    .total_cmp(&0.0)
                            })?;
                            inside(last.parameter).then(|| {
                                format!(
                                    " (that fold curve ends at {}, {:.3} m/s)",
                                    spec.show(last.parameter), last.speed_m_s
                                )
                            })
                        })
                        .unwrap_or_default(),
                };
                report.notes.push(format!(
                    "V_NL changes curve between {} and {}: from {pspeed:.3} m/s on {psource} to {v:.3} m/s on {source}{ends}",
                    spec.show(*pv),
                    spec.show(value)
                ));
            }
        }
        report.nonlinear_critical_speed.push((value, v));
        report
            .nonlinear_methods
            .push(super::VnlMethod::Continuation);
        previous = Some((value, v, source));
        previous_curve = best_curve;
    }
    report.nonlinear_unknown = unknown.clone();
    if !unknown.is_empty() {
        let list: Vec<String> = unknown.iter().map(|&v| spec.show(v)).collect();
        report.notes.push(format!(
            "V_NL unknown at {}: the lowest Hopf point there is subcritical (or of unknown type) and no fold with a stable side was followed there, so V_NL lies below V_H on a fold this run did not reach",
            list.join(", ")
        ));
    }
}

/// Cusps the fold system could not pass, bracketed between the ends of two fold curves.
///
/// Near a cusp of cycles the two folds it joins are nearly one: on the DTU bogie at
/// 274.8 kN s/m they are 0.007 m/s and 0.035 mm apart at 290.9 kN s/m. The fold curve turns
/// there within a sliver of the key, where the test function is flat along the null vector
/// (the cusp's condition) and its integration noise stops the corrector, so the curve
/// ends on either side of the turn. Two unsolved ends of fold curves of one kind at the same
/// key value, speed and amplitude (to 1e-3 of the key's span, 1e-4 and 1e-2 relative), both
/// curves lying on the same side of it and distinct where both are solved at a value of the
/// grid, are the two folds meeting: a cusp, listed as bracketed (its speed and key the ends'
/// means).
fn cusps_where_curves_meet(spec: &CurveSpec, start: usize, report: &mut CurveReport) {
    // (curve, end point, the key's direction into the curve on the P axis)
    let mut ends: Vec<(usize, &CurvePoint, f64)> = Vec::new();
    for (i, c) in report.curves.iter().enumerate().skip(start) {
        if c.kind != CurveKind::Fold || c.points.len() < 2 {
            continue;
        }
        let n = c.points.len();
        for (stop, end, next) in [
            (&c.stops.0, &c.points[0], &c.points[1]),
            (&c.stops.1, &c.points[n - 1], &c.points[n - 2]),
        ] {
            if matches!(stop, CurveStop::Unsolved { .. }) {
                let inward = to_p(spec, next.parameter) - to_p(spec, end.parameter);
                ends.push((i, end, inward.signum()));
            }
        }
    }
    let span = (to_p(spec, spec.range.1) - to_p(spec, spec.range.0)).abs();
    let close = |a: &CurvePoint, b: &CurvePoint| {
        (to_p(spec, a.parameter) - to_p(spec, b.parameter)).abs() <= 1e-3 * span
            && (a.speed_m_s - b.speed_m_s).abs() <= 1e-4 * a.speed_m_s.abs()
            && (a.amplitude_m - b.amplitude_m).abs() <= 1e-2 * a.amplitude_m.abs()
    };
    // two different folds: solved at a common grid value, at different cycles there
    let distinct = |a: &Curve, b: &Curve| {
        a.points.iter().any(|p| {
            b.points.iter().any(|q| {
                p.parameter == q.parameter
                    && ((p.speed_m_s - q.speed_m_s).abs() > 1e-6 * p.speed_m_s.abs()
                        || (p.amplitude_m - q.amplitude_m).abs() > 1e-4 * p.amplitude_m.abs())
            })
        })
    };
    let mut found = Vec::new();
    for (k, &(i, a, da)) in ends.iter().enumerate() {
        for &(j, b, db) in &ends[k + 1..] {
            let (ci, cj) = (&report.curves[i], &report.curves[j]);
            if i == j || ci.label != cj.label || da != db || !close(a, b) || !distinct(ci, cj) {
                continue;
            }
            found.push(SpecialPoint {
                kind: SpecialKind::Cusp,
                curve: i,
                other_curve: Some(j),
                parameter: 0.5 * (a.parameter + b.parameter),
                speed_m_s: 0.5 * (a.speed_m_s + b.speed_m_s),
                frequency_hz: 0.5 * (a.frequency_hz + b.frequency_hz),
                second_frequency_hz: None,
                located: false,
            });
        }
    }
    report.special_points.extend(found);
}

/// A note for each generalised Hopf point of a V_H curve that no fold curve reaches: a fold
/// of cycles is born there, and this run did not follow it (only the folds of the diagrams
/// computed are followed).
fn unfollowed_bautin_points(spec: &CurveSpec, first: f64, report: &mut CurveReport) {
    let span = (to_p(spec, spec.range.1) - to_p(spec, spec.range.0)).abs();
    let mut notes = Vec::new();
    for s in &report.special_points {
        if s.kind != SpecialKind::Bautin {
            continue;
        }
        let reached = report
            .curves
            .iter()
            .filter(|c| c.kind == CurveKind::Fold)
            .any(|c| {
                c.points.iter().any(|p| {
                    (to_p(spec, p.parameter) - to_p(spec, s.parameter)).abs() <= 0.05 * span
                        && (p.speed_m_s - s.speed_m_s).abs() <= 0.02 * s.speed_m_s
                })
            });
        if !reached {
            notes.push(format!(
                "a fold of cycles is born at the generalised Hopf point at {}, {:.3} m/s, and was not followed: no diagram computed (at {} and at curve.seed_points values of the fold grid) had it (more seed_points, or a study whose own {} lies there, follows it)",
                spec.show(s.parameter), s.speed_m_s, spec.show(first), spec.key
            ));
        }
    }
    report.notes.extend(notes);
}
