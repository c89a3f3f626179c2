//! The bifurcation driver for one state size: the Hopf point, the symmetric branch from it, and
//! the branches switched to at its symmetry-breaking and period-doubling points, recursively.
//!
//! Every branch is a [`Continuation`] of the same model with the same tolerances; they differ
//! in the shooting problem (half period for the symmetric branch, the whole period for
//! asymmetric cycles, two or more periods after a doubling), in the number of shooting
//! segments (one piece of equal length per segment: 2m segments over a whole period where the
//! symmetric branch has m over its half) and in how they end: an asymmetric branch ends where
//! it meets the symmetric branch again (a second symmetry-breaking point, [`Rejoin::Mirror`]),
//! a doubled one where it meets its parent ([`Rejoin::Shift`]). The parent's point that a child
//! met is not switched at again (the child already is that branch).

use nalgebra::{DVector, SVector};

use super::fold_track::{FoldTrack, FoldTracking};
use super::{
    coordinate_shares_of, hopf_point, newton_tol, ode_options, state_names, stiffness_check,
    BifurcationOptions, BifurcationReport, BranchKind, BranchRow, CycleRow, Hooks, HopfType,
    SpecialRow,
};
use crate::contact::creep::CreepLaw;
use crate::continuation::{
    switch_at, Branch, BranchPoint, BranchStats, BranchStop, Continuation, ContinuationParams,
    OrbitPoint, Rejoin, Shooting, SpecialKind,
};
use crate::model::Vehicle;
use crate::stability::{critical_speeds, LinearOptions, LinearSystem};
use crate::system::ode::OdeOptions;

/// One continued branch and where it came from.
pub(super) struct Run<const N: usize> {
    pub(super) kind: BranchKind,
    /// (parent run, index of the parent's special point)
    parent: Option<(usize, usize)>,
    switch_multiplier: Option<f64>,
    pub(super) symmetric: bool,
    /// shooting period over the symmetric branch's period at the Hopf point (1, 2, 4, …)
    pub(super) period_factor: usize,
    pub(super) segments: usize,
    pub(super) branch: Branch<N>,
}

/// What every branch's continuation shares.
pub(super) struct Setup<'a, const N: usize> {
    pub(super) model: &'a Vehicle,
    pub(super) opts: &'a BifurcationOptions,
    pub(super) ode: OdeOptions,
    pub(super) params: ContinuationParams,
    pub(super) amplitude: &'a (dyn Fn(&OrbitPoint<N>, &SVector<f64, N>) -> f64 + Sync),
    pub(super) extent: &'a (dyn Fn(&SVector<f64, N>) -> f64 + Sync),
    pub(super) progress: Option<&'a (dyn Fn(&BranchPoint<N>) + Sync)>,
    pub(super) cancel: Option<&'a (dyn Fn() -> bool + Sync)>,
    /// a line of text when a branch starts or ends ([`Hooks::branches`])
    pub(super) say: Option<&'a (dyn Fn(&str) + Sync)>,
}

impl<const N: usize> Setup<'_, N> {
    fn say(&self, text: &str) {
        if let Some(f) = self.say {
            f(text);
        }
    }

    /// "branch `id` (kind): n cycles, stop reason", and where its segments were doubled.
    fn ended(&self, id: usize, run: &Run<N>) {
        let doubled: String = run
            .branch
            .refined
            .iter()
            .map(|(v, m)| format!("; shooting segments doubled to {m} after {v:.4} m/s"))
            .collect();
        self.say(&format!(
            "branch {id} ({} cycles): {} cycles, {}{doubled}",
            run.kind.name(),
            run.branch.points.len(),
            stop_reason(&run.branch, self.opts)
        ));
    }
}

impl<const N: usize> Setup<'_, N> {
    fn shooting(&self, symmetric: bool, segments: usize) -> Shooting<'_, N, Vehicle> {
        Shooting {
            field: self.model,
            symmetric,
            ode: self.ode,
            dp_rel: self.opts.rtol.sqrt(),
            parallel: self.opts.parallel,
            busy: self.opts.busy.clone(),
            segments,
        }
    }

    /// The continuation's scales with the period scaled by `period_factor`.
    pub(super) fn params(&self, period_factor: usize) -> ContinuationParams {
        let mut p = self.params.clone();
        p.scale[N] *= period_factor as f64;
        p
    }

    pub(super) fn continuation(
        &self,
        symmetric: bool,
        segments: usize,
        period_factor: usize,
        rejoin: Option<Rejoin>,
    ) -> Continuation<'_, N, Vehicle> {
        Continuation {
            shooting: self.shooting(symmetric, segments),
            params: self.params(period_factor),
            amplitude: self.amplitude,
            progress: self.progress,
            cancel: self.cancel,
            extent: Some(self.extent),
            rejoin,
        }
    }
}

pub(super) fn analyse_states<const N: usize>(
    study: &str,
    model: &Vehicle,
    opts: &BifurcationOptions,
    hooks: Hooks<'_>,
) -> Result<BifurcationReport, String> {
    analyse_and_track::<N>(study, model, opts, hooks, None).map(|(r, _)| r)
}

/// The diagram of `model` and, with `track`, its located folds of cycles followed over the
/// key values of `track` ([`super::fold_track`]).
pub(super) fn analyse_and_track<const N: usize>(
    study: &str,
    model: &Vehicle,
    opts: &BifurcationOptions,
    hooks: Hooks<'_>,
    track: Option<&FoldTracking<'_>>,
) -> Result<(BifurcationReport, Vec<FoldTrack>), String> {
    let Hooks {
        progress,
        cancel,
        branches: say,
    } = hooks;
    let ode = ode_options(opts.rtol, opts.floquet_rtol, opts.integrator)?;
    let kalker = model.with_law(CreepLaw::Kalker);
    let kalker_critical_speed_m_s = critical_speeds(
        &LinearSystem::<N>::at_centre(&kalker),
        CreepLaw::Kalker,
        &LinearOptions {
            speed_range: opts.speed_range,
            ..LinearOptions::default()
        },
    )
    .ok()
    .and_then(|c| c.critical().map(|x| x.speed_m_s));
    let mut report = BifurcationReport {
        study: study.to_string(),
        law: model.creep_law(),
        kalker_critical_speed_m_s,
        hopf: None,
        hopf_type: None,
        first_lyapunov: None,
        nonlinear_critical_speed: None,
        nonlinear_sources: Vec::new(),
        branches: Vec::new(),
        cycles: Vec::new(),
        special: Vec::new(),
        stop_reason: String::new(),
        notes: Vec::new(),
        speed_range: opts.speed_range,
        layout: model.layout.name(),
        body_names: model.bodies.iter().map(|b| b.name.clone()).collect(),
        state_names: state_names(model),
        stats: BranchStats::default(),
    };
    let Some((hopf, q)) = hopf_point::<N>(model, opts.speed_range) else {
        report.stop_reason = format!(
            "no Hopf point of the {} model in [{}, {}] m/s: the centred motion does not lose stability there",
            model.creep_law().name(),
            opts.speed_range.0,
            opts.speed_range.1
        );
        return Ok((report, Vec::new()));
    };
    report.hopf = Some(hopf);
    stiffness_check::<N>(model, hopf.speed_m_s, hopf.frequency_hz)?;
    let omega = 2.0 * std::f64::consts::PI * hopf.frequency_hz;
    report.first_lyapunov =
        crate::stability::first_lyapunov::<N, _>(model, hopf.speed_m_s, omega, &Default::default())
            .ok();
    let a_ref = 1e-3;
    // each coordinate scaled by its share of the Hopf eigenvector (the leading wheelset's y is
    // 1): 1 mm of lateral amplitude ≈ 1 m/s of speed in the arclength
    let shares = coordinate_shares_of(model, &q);
    // (a damper's stroke, beyond the velocities, is a length of the order of the motions: 1 mm)
    let n = model.dofs();
    let mut scale: Vec<f64> = (0..N)
        .map(|i| {
            let share = shares.get(i % n.max(1)).copied().unwrap_or(1.0);
            if i < n {
                a_ref * share
            } else if i < 2 * n {
                a_ref * omega * share
            } else {
                a_ref
            }
        })
        .collect();
    scale.extend([1.0 / hopf.frequency_hz, 1.0]);
    let mut params =
        ContinuationParams::new(opts.speed_range, opts.amplitude_bound(), scale.clone());
    params.ds_initial = 0.1;
    params.ds_max = opts.ds_max;
    params.max_points = opts.max_points;
    params.chord = opts.chord;
    // Newton cannot converge below the integration noise: tie its tolerance to rtol.
    params.newton_tol = newton_tol(opts.rtol, N);
    // a branch that runs into stiffness (low speeds) ends with its reason instead of
    // crawling for hours (the same bound as the refusal at the Hopf point)
    params.max_steps_per_iteration = Some(super::MAX_STIFF_STEPS_PER_PERIOD);
    // where Newton fails at every step size, finer shooting before giving up (4× at most)
    params.refinements = super::SEGMENT_REFINEMENTS;
    // max |y| of the leading wheelset over the cycle, located on the shooting integration's
    // dense output
    let amplitude = |_: &OrbitPoint<N>, peaks: &SVector<f64, N>| peaks[0];
    // the largest lateral excursion of any wheelset: what the contact geometry must cover
    let wheelsets = model.wheelset_dofs().to_vec();
    let extent = move |peaks: &SVector<f64, N>| {
        wheelsets
            .iter()
            .filter_map(|&d| peaks.get(d).copied())
            .fold(0.0, f64::max)
    };
    let counter = std::sync::atomic::AtomicUsize::new(0);
    let report_point = |p: &BranchPoint<N>| {
        if let Some(f) = progress {
            let k = counter.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
            f(k, p.orbit.param, p.amplitude);
        }
    };
    let setup = Setup {
        model,
        opts,
        ode,
        params,
        amplitude: &amplitude,
        extent: &extent,
        progress: Some(&report_point),
        cancel,
        say,
    };
    let m = opts.segment_count();
    let start = OrbitPoint {
        x0: SVector::zeros(),
        period: 1.0 / hopf.frequency_hz,
        param: hopf.speed_m_s,
    };
    let direction = DVector::from_fn(N + 2, |i, _| {
        if i < N {
            a_ref * q[i].re / scale[i]
        } else {
            0.0
        }
    });
    let root = setup.continuation(true, m, 1, None).run(start, direction);
    let mut runs = vec![Run {
        kind: BranchKind::Symmetric,
        parent: None,
        switch_multiplier: None,
        symmetric: true,
        period_factor: 1,
        segments: m,
        branch: root,
    }];
    setup.ended(0, &runs[0]);
    let mut notes = Vec::new();
    if opts.switch {
        switch_all(&setup, &mut runs, &mut notes);
    }
    fill(&mut report, &runs, model, opts);
    report.notes.extend(notes);
    let tracks = match track {
        Some(t) => {
            if let Some(ready) = t.ready {
                ready();
            }
            super::fold_track::follow(&setup, &runs, t)
        }
        None => Vec::new(),
    };
    Ok((report, tracks))
}

/// Whether two special points of one kind are the same point: speeds within 1e-5 relative
/// (or 1 mm/s) and amplitudes within 1e-3 relative (or 1 µm); the locator's tolerance is far
/// below both, distinct points of a branch far above.
fn same_point(a: (f64, f64), b: (f64, f64)) -> bool {
    (a.0 - b.0).abs() <= (1e-5 * a.0.abs()).max(1e-3)
        && (a.1 - b.1).abs() <= (1e-3 * a.1.abs()).max(1e-6)
}

/// Switches at every symmetry-breaking point of a symmetric branch and every period doubling
/// of a full-period one, breadth first, until `max_branches` branches exist.
fn switch_all<const N: usize>(
    setup: &Setup<'_, N>,
    runs: &mut Vec<Run<N>>,
    notes: &mut Vec<String>,
) {
    // the parents' points already met by a child that rejoined there
    let mut met: Vec<(usize, usize)> = Vec::new();
    let mut next = 0;
    while next < runs.len() {
        let candidates: Vec<usize> = {
            let r = &runs[next];
            let last = r.branch.special.len().saturating_sub(1);
            let rejoined = matches!(r.branch.stop, BranchStop::Rejoined { .. });
            r.branch
                .special
                .iter()
                .enumerate()
                .filter(|(k, sp)| {
                    let opens = match sp.kind {
                        SpecialKind::SymmetryBreaking => r.symmetric,
                        SpecialKind::PeriodDoubling => !r.symmetric,
                        _ => false,
                    };
                    // a rejoined child's last point is its parent's, not a new one
                    opens && !(rejoined && *k == last)
                })
                .map(|(k, _)| k)
                .collect()
        };
        for k in candidates {
            if met.contains(&(next, k)) {
                continue;
            }
            let (speed, kind) = {
                let sp = &runs[next].branch.special[k];
                (sp.orbit.param, sp.kind)
            };
            if runs.len() >= setup.opts.max_branches {
                notes.push(format!(
                    "the {} point at {speed:.4} m/s on branch {next} was not followed: max_branches = {} reached",
                    kind.name(),
                    setup.opts.max_branches
                ));
                continue;
            }
            if setup.cancel.is_some_and(|c| c()) {
                return;
            }
            setup.say(&format!(
                "branch {}: switching at the {} point at {speed:.4} m/s of branch {next}",
                runs.len(),
                kind.name().replace('_', " ")
            ));
            match switch_from(setup, runs, next, k) {
                Ok(child) => {
                    setup.ended(runs.len(), &child);
                    if let BranchStop::Rejoined { .. } = child.branch.stop {
                        if let Some(end) = child.branch.special.last() {
                            let at = (end.orbit.param, end.amplitude);
                            for (ri, r) in runs.iter().enumerate() {
                                for (si, sp) in r.branch.special.iter().enumerate() {
                                    let joinable = sp.kind == end.kind
                                        && r.symmetric
                                            == (end.kind == SpecialKind::SymmetryBreaking)
                                        && (ri, si) != (next, k);
                                    if joinable && same_point((sp.orbit.param, sp.amplitude), at) {
                                        met.push((ri, si));
                                    }
                                }
                            }
                        }
                    }
                    runs.push(child);
                }
                Err(e) => notes.push(format!(
                    "no branch switched to at the {} point at {speed:.4} m/s on branch {next}: {e}",
                    kind.name()
                )),
            }
        }
        next += 1;
    }
}

/// The child branch at special point `k` of run `parent`.
fn switch_from<const N: usize>(
    setup: &Setup<'_, N>,
    runs: &[Run<N>],
    parent: usize,
    k: usize,
) -> Result<Run<N>, String> {
    let p = &runs[parent];
    let sp = &p.branch.special[k];
    let (kind, factor) = match sp.kind {
        SpecialKind::SymmetryBreaking => (BranchKind::Asymmetric, 1),
        _ => (
            BranchKind::Period(match p.kind {
                BranchKind::Period(j) => 2 * j,
                _ => 2,
            }),
            2,
        ),
    };
    let period_factor = p.period_factor * factor;
    // a whole period in 2m pieces where the symmetric branch has m over its half: every
    // segment is as long as the symmetric branch's, and the middle one starts half-way
    let segments = if p.symmetric {
        2 * p.segments
    } else {
        2 * p.segments.max(1)
    };
    let sh = setup.shooting(p.symmetric, p.segments);
    let child_scale = setup.params(period_factor).scale;
    let tangent = p.branch.points.get(sp.after).map(|q| &q.tangent);
    let sw = switch_at(&sh, sp, &child_scale, tangent).map_err(|e| e.to_string())?;
    let branch = setup
        .continuation(false, segments, period_factor, Some(sw.rejoin))
        .run(sw.start, sw.direction);
    Ok(Run {
        kind,
        parent: Some((parent, k)),
        switch_multiplier: Some(sw.multiplier),
        symmetric: false,
        period_factor,
        segments,
        branch,
    })
}

fn stop_reason<const N: usize>(branch: &Branch<N>, opts: &BifurcationOptions) -> String {
    match branch.stop {
        BranchStop::ParamBound { param } => format!("speed bound reached ({param:.4} m/s)"),
        BranchStop::AmplitudeBound { amplitude } => match opts.geometry_limit {
            Some(g) if g <= opts.max_amplitude && amplitude > g => format!(
                "cut where a wheelset leaves the contact geometry's range ({:.3} mm > {:.3} mm)",
                amplitude * 1e3,
                g * 1e3
            ),
            _ => format!("amplitude bound reached ({:.3} mm)", amplitude * 1e3),
        },
        BranchStop::MaxPoints => format!("step limit reached ({} cycles)", branch.points.len()),
        BranchStop::StepTooSmall { param, newton } => {
            format!("step too small at {param:.4} m/s (Newton: {newton:?})")
        }
        BranchStop::Cancelled => format!("cancelled after {} cycles", branch.points.len()),
        BranchStop::Rejoined { param } => {
            format!("met the branch it was switched from again at {param:.4} m/s")
        }
        BranchStop::TooStiff {
            param,
            steps_per_iteration,
            mean_step,
            stability_bound,
        } => format!(
            "stopped at {param:.4} m/s as too stiff: a cycle there took {steps_per_iteration:.0} \
             integrator steps per Newton iteration (the limit is {:.0}), with a mean step of \
             {mean_step:.2e} s against the explicit integrator's stability bound of \
             {stability_bound:.2e} s there (3.3/|lambda|max of the centred motion: the creep \
             forces' rates grow as 1/V). Cycles beyond were not computed",
            super::MAX_STIFF_STEPS_PER_PERIOD
        ),
    }
}

/// The largest wheelset's max |y| over an orbit with component peaks `peaks`.
fn wheelset_amplitude<const N: usize>(
    model: &Vehicle,
    peaks: &SVector<f64, N>,
    leading: f64,
) -> f64 {
    model
        .wheelset_dofs()
        .iter()
        .filter_map(|&d| peaks.get(d).copied())
        .fold(leading, f64::max)
}

fn cycle_row<const N: usize>(branch: usize, p: &BranchPoint<N>, model: &Vehicle) -> CycleRow {
    CycleRow {
        branch,
        speed_m_s: p.orbit.param,
        amplitude_y_m: p.amplitude,
        amplitude_sides_y_m: (p.high[0], -p.low[0]),
        wheelset_amplitude_m: wheelset_amplitude(model, &p.peaks, p.amplitude),
        amplitude_psi_rad: p.peaks[1],
        period_s: p.orbit.period,
        stable: p.floquet.stable(),
        max_multiplier_abs: p.floquet.max_nontrivial,
        trivial_multiplier_error: p.floquet.trivial_error,
        newton_iterations: p.newton_iterations,
        x0: p.orbit.x0.iter().copied().collect(),
        multipliers: (0..N)
            .map(|k| {
                p.floquet
                    .multipliers
                    .get(k)
                    .map_or((f64::NAN, f64::NAN), |m| (m.re, m.im))
            })
            .collect(),
        // every body's max |y| and max |ψ|, located on the same dense output
        body_amplitudes: if N == 4 {
            Vec::new()
        } else {
            model
                .bodies
                .iter()
                .map(|b| (p.peaks[b.dof], p.peaks[b.dof + 1]))
                .collect()
        },
    }
}

fn fill<const N: usize>(
    report: &mut BifurcationReport,
    runs: &[Run<N>],
    model: &Vehicle,
    opts: &BifurcationOptions,
) {
    // index of each run's first special point in the report's list
    let mut first_special = Vec::with_capacity(runs.len());
    for (id, r) in runs.iter().enumerate() {
        first_special.push(report.special.len());
        let s = &r.branch.stats;
        let t = &mut report.stats;
        t.failed_steps += s.failed_steps;
        t.angle_rejections += s.angle_rejections;
        t.locate_corrections += s.locate_corrections;
        t.newton_iterations += s.newton_iterations;
        t.chord_iterations += s.chord_iterations;
        t.integrator_steps += s.integrator_steps;
        t.integrator_rejected += s.integrator_rejected;
        report
            .cycles
            .extend(r.branch.points.iter().map(|p| cycle_row(id, p, model)));
        let first_cycle = report.cycles.len() - r.branch.points.len();
        report
            .special
            .extend(r.branch.special.iter().map(|s| SpecialRow {
                branch: id,
                after: first_cycle + s.after,
                kind: s.kind,
                speed_m_s: s.orbit.param,
                amplitude_y_m: s.amplitude,
                wheelset_amplitude_m: wheelset_amplitude(model, &s.peaks, s.amplitude),
                located: s.located,
            }));
        report.branches.push(BranchRow {
            id,
            kind: r.kind,
            parent: r.parent.map(|(pr, k)| (pr, first_special[pr] + k)),
            switch_multiplier: r.switch_multiplier,
            stop_reason: stop_reason(&r.branch, opts),
            cycles: r.branch.points.len(),
            segments: r.segments,
            segments_doubled: r.branch.refined.clone(),
        });
    }
    report.stop_reason = report
        .branches
        .first()
        .map(|b| b.stop_reason.clone())
        .unwrap_or_default();
    let hopf_speed = report.hopf.map(|h| h.speed_m_s);
    report.hopf_type = match (
        hopf_speed,
        runs.first().and_then(|r| r.branch.points.first()),
    ) {
        (Some(v), Some(c)) if c.orbit.param < v => Some(HopfType::Subcritical),
        (Some(_), Some(_)) => Some(HopfType::Supercritical),
        _ => None,
    };
    let (vnl, sources) = super::vnl::from_continuation(report);
    report.nonlinear_critical_speed = vnl;
    report.nonlinear_sources = sources;
    for (id, r) in runs.iter().enumerate() {
        if let BranchStop::TooStiff { param, .. } = r.branch.stop {
            let last_stable = r.branch.points.last().is_some_and(|p| p.floquet.stable());
            report.notes.push(format!(
                "branch {id} was stopped at {param:.4} m/s as too stiff for the explicit \
                 integrator (its stop reason gives the figures); its cycles there are {}, so \
                 {}",
                if last_stable { "stable" } else { "unstable" },
                if last_stable {
                    "a hunting motion exists at that speed and V_NL may lie lower: the reported \
                     V_NL is an upper bound"
                } else {
                    "the branch beyond may still turn stable at lower speeds: V_NL is not \
                     proven below that speed"
                }
            ));
        }
    }
}
