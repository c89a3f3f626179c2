//! Folds of cycles followed over a design key (`critspeed curve`'s `"fold"` curves).
//!
//! Each located fold of the diagram at the key's first value is followed to the next value by
//! relocating it: the fold's cycle, moved back along its branch by a few steps of the fold's
//! own chord direction, starts a short pseudo-arclength continuation in speed of the model at
//! the new value, which crosses the fold and locates it with the diagram's own locator (the
//! sign change of dV/ds, docs/model.md §9). The arclength corrector leaves the speed free, so
//! the fold may move in speed between two values; when the relocation finds no fold, the step
//! in the key is halved (up to [`MAX_HALVINGS`] times) before the curve is ended, with the
//! interval where it was lost. A fold that disappears at a cusp (where it meets a second fold
//! and both vanish) ends its curve that way.
//!
//! This is natural continuation in the key (one relocation per value) rather than a continuation
//! of the extended fold system in (V, p) with a bordered monodromy: each point is the same
//! located fold that a whole diagram at that key value gives (to the locator's tolerance), at a
//! fraction of its cost, but a curve that turns back in the key (a fold of the fold curve, the
//! cusp's geometry) is not followed round the turn.

use nalgebra::DVector;

use super::driver::{Run, Setup};
use rayon::prelude::*;

use super::{BifurcationOptions, BranchKind};
use std::sync::atomic::Ordering::Relaxed;
use std::sync::atomic::{AtomicBool, AtomicU8};

use crate::continuation::branch::{pack, unpack};
use crate::continuation::{Branch, BranchPoint, BranchStop, OrbitPoint, SpecialKind};
use crate::model::Vehicle;

/// The most times a step in the key is halved before a fold curve is ended.
pub const MAX_HALVINGS: usize = 4;

/// Steps of the relocating continuation taken before the predicted fold.
const BACK_STEPS: usize = 3;

/// A located "fold" of smaller amplitude (m) is the Hopf point itself, where a run through
/// zero amplitude turns onto the mirror cycles: the fold curve has reached a generalised Hopf
/// point and ends.
const MIN_FOLD_AMPLITUDE: f64 = 2e-5;

/// The most cycles of one relocating run: it ends as soon as it has passed the fold.
const MAX_RELOCATION_POINTS: usize = 24;

/// A family of models over a design key.
pub struct FoldTracking<'a> {
    /// the key's values (SI) after the one the diagram was computed at, in order
    pub values: &'a [f64],
    /// the key's values (SI) before it, nearest first
    pub back: &'a [f64],
    /// the key's value of the diagram (SI)
    pub first: f64,
    /// the model at a key value
    pub model_at: &'a (dyn Fn(f64) -> Result<Vehicle, String> + Sync),
    /// `skip(speed m/s, amplitude m)`: a fold of the diagram not to follow (one a curve
    /// already passes through)
    pub skip: &'a (dyn Fn(f64, f64) -> bool + Sync),
}

/// One point of a followed fold.
#[derive(Clone, Debug, PartialEq)]
pub struct FoldTrackPoint {
    /// the key's value (SI)
    pub parameter: f64,
    /// the fold's speed (m/s)
    pub speed_m_s: f64,
    /// the cycle's period (s)
    pub period_s: f64,
    /// the leading wheelset's max |y| over the cycle (m)
    pub amplitude_m: f64,
    /// whether a stable cycle branch ends at the fold (the branch on one side of it is stable):
    /// such a fold is where a hunting motion disappears, a candidate for V_NL
    pub stable_side: bool,
    /// located to tolerance (else only bracketed)
    pub located: bool,
}

/// A fold of cycles of the diagram followed over the key.
#[derive(Clone, Debug, PartialEq)]
pub struct FoldTrack {
    /// the branch of the diagram it lies on (its id in `branch.csv`)
    pub branch: usize,
    /// that branch's kind
    pub branch_kind: BranchKind,
    /// the points in the order of the key's values (`back` reversed, the diagram's fold,
    /// `values`)
    pub points: Vec<FoldTrackPoint>,
    /// why each end stopped, in words: (the `back` end, the `values` end)
    pub stops: (String, String),
}

/// One side of a followed fold.
struct Side {
    points: Vec<FoldTrackPoint>,
    stop: String,
}

/// A fold being followed: where it is and the direction of its branch there.
#[derive(Clone)]
struct Front<const N: usize> {
    orbit: OrbitPoint<N>,
    /// the branch's unit chord through the fold (scaled coordinates), pointing the way the
    /// branch was traced
    direction: DVector<f64>,
    /// the arclength step of the relocating runs (scaled units)
    ds: f64,
    point: FoldTrackPoint,
    /// the fold before (key value, packed orbit): the secant that predicts the next one
    previous: Option<(f64, DVector<f64>)>,
    /// whether the speed rises towards the fold along the branch (a fold at a maximum of the
    /// speed), from either side
    rising: bool,
}

/// Follows every located fold of `runs` over `track`'s key values.
pub(super) fn follow<const N: usize>(
    setup: &Setup<'_, N>,
    runs: &[Run<N>],
    track: &FoldTracking<'_>,
) -> Vec<FoldTrack> {
    // the models at the grid's values, built once for every fold
    let build = |values: &[f64]| -> Vec<Result<Vehicle, String>> {
        values.iter().map(|&v| (track.model_at)(v)).collect()
    };
    let (fore_models, back_models) = (build(track.values), build(track.back));
    let mut jobs = Vec::new();
    for run in runs.iter() {
        for (k, sp) in run.branch.special.iter().enumerate() {
            if sp.kind != SpecialKind::Fold
                || !sp.located
                || sp.amplitude < MIN_FOLD_AMPLITUDE
                || (track.skip)(sp.orbit.param, sp.amplitude)
            {
                continue;
            }
            if let Some(front) = first_front(setup, run, k, track.first) {
                jobs.push((run, front));
            }
        }
    }
    // every side of every fold on its own rayon task, each with serial shooting: on the
    // 2-core machine the folds' relocations scale better than one relocation's segments
    jobs.into_par_iter()
        .map(|(run, front)| {
            let (back, fore) = rayon::join(
                || follow_one(setup, run, front.clone(), track, track.back, &back_models),
                || follow_one(setup, run, front.clone(), track, track.values, &fore_models),
            );
            let mut points: Vec<FoldTrackPoint> = back.points.into_iter().skip(1).rev().collect();
            points.extend(fore.points);
            FoldTrack {
                branch: out_id(runs, run),
                branch_kind: run.kind,
                points,
                stops: (back.stop, fore.stop),
            }
        })
        .collect()
}

/// The id of `run` among `runs` (its place, as in `branch.csv`).
fn out_id<const N: usize>(runs: &[Run<N>], run: &Run<N>) -> usize {
    runs.iter()
        .position(|r| std::ptr::eq(r, run))
        .unwrap_or_default()
}

/// The scaled unit chord from point `a` to point `b` of a branch, `None` if they coincide.
fn chord<const N: usize>(
    a: &OrbitPoint<N>,
    b: &OrbitPoint<N>,
    scale: &[f64],
) -> Option<DVector<f64>> {
    let d = pack(b) - pack(a);
    let d = DVector::from_fn(N + 2, |i, _| d[i] / scale.get(i).copied().unwrap_or(1.0));
    let n = d.norm();
    (n > 0.0 && n.is_finite()).then(|| d / n)
}

/// Whether a stable cycle lies next to the fold `k` of `branch`.
fn stable_side<const N: usize>(branch: &Branch<N>, after: usize) -> bool {
    [after, after + 1]
        .iter()
        .filter_map(|&i| branch.points.get(i))
        .any(|p| p.floquet.stable())
}

fn first_front<const N: usize>(
    setup: &Setup<'_, N>,
    run: &Run<N>,
    k: usize,
    parameter: f64,
) -> Option<Front<N>> {
    let sp = run.branch.special.get(k)?;
    let a = run.branch.points.get(sp.after)?;
    let b = run.branch.points.get(sp.after + 1)?;
    let scale = setup.params(run.period_factor).scale;
    let direction = chord(&a.orbit, &b.orbit, &scale)?;
    let step = (pack(&b.orbit) - pack(&a.orbit))
        .iter()
        .zip(scale.iter())
        .map(|(d, s)| (d / s).powi(2))
        .sum::<f64>()
        .sqrt();
    Some(Front {
        orbit: sp.orbit,
        direction,
        // half the branch's step at the fold, but at least 3 % of (1 mm + the amplitude) in
        // scaled units (1 mm of amplitude ≈ 1 unit): the branch's steps shrink at a fold, and a
        // window of a few such steps can miss where the fold has moved (on the DTU bogie a
        // 0.002 window missed the 0.86 mm fold 1 % of the key away)
        ds: (step / 2.0)
            .max(0.03 * (1.0 + sp.amplitude / 1e-3))
            .clamp(1e-3, 0.5),
        point: FoldTrackPoint {
            parameter,
            speed_m_s: sp.orbit.param,
            period_s: sp.orbit.period,
            amplitude_m: sp.amplitude,
            stable_side: stable_side(&run.branch, sp.after),
            located: sp.located,
        },
        previous: None,
        rising: a.tangent.get(N + 1).is_some_and(|v| *v > 0.0),
    })
}

/// One side: the fold of `front` relocated at each of `values` in turn.
fn follow_one<const N: usize>(
    setup: &Setup<'_, N>,
    run: &Run<N>,
    mut front: Front<N>,
    track: &FoldTracking<'_>,
    values: &[f64],
    models: &[Result<Vehicle, String>],
) -> Side {
    let mut points = vec![front.point.clone()];
    let mut stop = format!(
        "end of the key's range ({})",
        values.last().copied().unwrap_or(track.first)
    );
    let mut previous = track.first;
    'values: for (i, &target) in values.iter().enumerate() {
        if setup.cancel.is_some_and(|c| c()) {
            stop = "cancelled".into();
            break;
        }
        // the interval from `previous` to `target`, in pieces halved on failure
        let mut pieces = 1usize;
        let mut done = 0usize;
        while done < pieces {
            let at = previous + (target - previous) * (done + 1) as f64 / pieces as f64;
            let built;
            let model = if done + 1 == pieces {
                match models.get(i) {
                    Some(Ok(m)) => m,
                    Some(Err(e)) => {
                        stop = format!("no model at key value {target}: {e}");
                        break 'values;
                    }
                    None => break 'values,
                }
            } else {
                built = (track.model_at)(at);
                match &built {
                    Ok(m) => m,
                    Err(e) => {
                        stop = format!("no model at key value {at}: {e}");
                        break 'values;
                    }
                }
            };
            match relocate(setup, run, model, &front, at) {
                Ok(next) => {
                    front = next;
                    points.push(front.point.clone());
                    done += 1;
                }
                Err(_) if pieces < 1 << MAX_HALVINGS => {
                    // redo the rest of the interval in twice as many pieces
                    let from = points.last().map_or(previous, |p| p.parameter);
                    previous = from;
                    pieces = 2 * (pieces - done);
                    done = 0;
                }
                Err(why) => {
                    let from = points.last().map_or(previous, |p| p.parameter);
                    stop = format!(
                        "the fold was not found between key values {from} and {at} (last at {:.4} m/s, {:.3} mm; {why})",
                        front.point.speed_m_s,
                        front.point.amplitude_m * 1e3
                    );
                    break 'values;
                }
            }
        }
        previous = target;
    }
    Side { points, stop }
}

/// The fold of `front` at the key value `parameter` (model `model`), by a short continuation
/// through the window around the previous fold.
fn relocate<const N: usize>(
    setup: &Setup<'_, N>,
    run: &Run<N>,
    model: &Vehicle,
    front: &Front<N>,
    parameter: f64,
) -> Result<Front<N>, String> {
    let serial = BifurcationOptions {
        parallel: false,
        ..setup.opts.clone()
    };
    let here = Setup {
        model,
        opts: &serial,
        ode: setup.ode,
        params: setup.params.clone(),
        amplitude: setup.amplitude,
        extent: setup.extent,
        progress: None,
        cancel: setup.cancel,
    };
    let scale: Vec<f64> = here.params(run.period_factor).scale;
    let shift = |k: f64, d: &DVector<f64>| {
        DVector::from_fn(N + 2, |i, _| {
            k * front.ds * d[i] * scale.get(i).copied().unwrap_or(1.0)
        })
    };
    // the secant through the last two folds predicts where the fold lies at `parameter`
    let here_z = pack(&front.orbit);
    let centre = match &front.previous {
        Some((p, z)) if *p != front.point.parameter => {
            let t = (parameter - front.point.parameter) / (front.point.parameter - p);
            &here_z + (&here_z - z) * t
        }
        _ => here_z.clone(),
    };
    // From a few steps before the predicted fold, along the branch, until the speed stops
    // rising (or falling) towards it: the fold is then located. A run whose first cycle
    // already moves away from the fold started past it: it is run again the other way.
    let attempt = |direction: &DVector<f64>| -> (Branch<N>, bool) {
        let seen = AtomicU8::new(0); // 0: no cycle yet, 1: approaching, 2: done
        let past = AtomicBool::new(false);
        let progress = |p: &BranchPoint<N>| {
            let towards = p
                .tangent
                .get(N + 1)
                .is_some_and(|v| (*v > 0.0) == front.rising);
            match (seen.load(Relaxed), towards) {
                (0, true) => seen.store(1, Relaxed),
                (0, false) => {
                    past.store(true, Relaxed);
                    seen.store(2, Relaxed);
                }
                (1, false) => seen.store(2, Relaxed),
                _ => {}
            }
        };
        let stop = || seen.load(Relaxed) == 2 || setup.cancel.is_some_and(|c| c());
        let mut c = here.continuation(run.symmetric, run.segments, run.period_factor, None);
        c.params.ds_initial = front.ds;
        c.params.ds_max = front.ds;
        c.params.ds_min = front.ds * 1e-3;
        c.params.max_points = MAX_RELOCATION_POINTS;
        c.progress = Some(&progress);
        c.cancel = Some(&stop);
        let start = unpack::<N>(&(&centre + shift(-(BACK_STEPS as f64), direction)));
        let b = c.run(start, direction.clone());
        (b, past.load(Relaxed))
    };
    let (mut branch, past) = attempt(&front.direction);
    if past && !setup.cancel.is_some_and(|c| c()) {
        branch = attempt(&-&front.direction).0;
    }
    let distance = |o: &OrbitPoint<N>| -> f64 {
        let d = pack(o) - &centre;
        d.iter()
            .zip(scale.iter())
            .map(|(d, s)| (d / s).powi(2))
            .sum::<f64>()
            .sqrt()
    };
    if setup.cancel.is_some_and(|c| c()) {
        return Err("cancelled".into());
    }
    let sp = branch
        .special
        .iter()
        .filter(|s| s.kind == SpecialKind::Fold)
        .min_by(|a, b| distance(&a.orbit).total_cmp(&distance(&b.orbit)))
        .ok_or_else(|| missing(&branch))?;
    if sp.amplitude < MIN_FOLD_AMPLITUDE {
        return Err(format!(
            "the fold's amplitude falls to zero ({:.1} µm): it ends on the Hopf curve, at a generalised Hopf (Bautin) point",
            sp.amplitude * 1e6
        ));
    }
    let (Some(a), Some(b)) = (branch.points.get(sp.after), branch.points.get(sp.after + 1)) else {
        return Err(missing(&branch));
    };
    let mut direction = chord(&a.orbit, &b.orbit, &scale).ok_or_else(|| missing(&branch))?;
    if direction.dot(&front.direction) < 0.0 {
        direction = -direction;
    }
    Ok(Front {
        orbit: sp.orbit,
        direction,
        ds: front.ds,
        point: FoldTrackPoint {
            parameter,
            speed_m_s: sp.orbit.param,
            period_s: sp.orbit.period,
            amplitude_m: sp.amplitude,
            stable_side: stable_side(&branch, sp.after),
            located: sp.located,
        },
        previous: Some((front.point.parameter, here_z)),
        rising: front.rising,
    })
}

/// Why a relocating run found no fold, from how it ended.
fn missing<const N: usize>(branch: &Branch<N>) -> String {
    let how = match branch.stop {
        BranchStop::AmplitudeBound { amplitude } => format!(
            "the cycles there reach the amplitude bound ({:.3} mm)",
            amplitude * 1e3
        ),
        BranchStop::ParamBound { param } => {
            format!("the cycles there leave the speed range ({param:.3} m/s)")
        }
        BranchStop::StepTooSmall { param, newton } => {
            format!("no cycle could be corrected near {param:.3} m/s (Newton: {newton:?})")
        }
        _ => format!(
            "{} cycles around the last fold turn nowhere: the fold vanished (at a cusp with another fold, or at a generalised Hopf point where its amplitude falls to zero) or moved out of reach",
            branch.points.len()
        ),
    };
    format!("no fold: {how}")
}
