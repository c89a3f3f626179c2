//! Shooting, Floquet multipliers and continuation on the Hopf normal form, whose cycles,
//! periods, multipliers and fold are known in closed form (critspeed::reference), independent
//! of any wheelset.

use approx::assert_relative_eq;
use critspeed::continuation::{
    BranchStop, Continuation, ContinuationParams, OrbitPoint, Shooting, SpecialKind,
};
use critspeed::reference::HopfNormalForm;
use critspeed::system::ode::{OdeOptions, Tolerances, VectorField};
use nalgebra::{DVector, SVector};
use std::f64::consts::PI;

fn ode(rtol: f64) -> OdeOptions {
    OdeOptions {
        tol: Tolerances::new(rtol, rtol * 1e-2).expect("valid tolerances"),
        ..OdeOptions::default()
    }
}

fn radius(o: &OrbitPoint<2>, _: &SVector<f64, 2>) -> f64 {
    o.x0.norm()
}

fn continuation<'a>(
    field: &'a HopfNormalForm,
    range: (f64, f64),
    max_amp: f64,
    symmetric: bool,
) -> Continuation<'a, 2, HopfNormalForm> {
    let mut params = ContinuationParams::new(range, max_amp, vec![1.0, 1.0, 1.0, 1.0]);
    params.ds_initial = 0.02;
    params.ds_max = 0.05;
    Continuation {
        shooting: Shooting {
            field,
            symmetric,
            ode: ode(1e-12),
            dp_rel: 1e-6,
            parallel: false,
            busy: None,
            segments: 1,
        },
        params,
        amplitude: &radius,
        progress: None,
        cancel: None,
        extent: None,
        rejoin: None,
    }
}

fn from_hopf(field: &HopfNormalForm) -> (OrbitPoint<2>, DVector<f64>) {
    let start = OrbitPoint {
        x0: SVector::<f64, 2>::zeros(),
        period: 2.0 * PI / field.omega,
        param: 0.0,
    };
    (start, DVector::from_vec(vec![1.0, 0.0, 0.0, 0.0]))
}

#[test]
fn supercritical_branch_is_the_square_root() {
    let field = HopfNormalForm {
        omega: 2.0,
        a: -1.0,
        b: 0.0,
    };
    for symmetric in [true, false] {
        let c = continuation(&field, (-1.0, 1.0), 0.9, symmetric);
        let (start, dir) = from_hopf(&field);
        let branch = c.run(start, dir);
        assert!(branch.points.len() > 10, "{:?}", branch.stop);
        assert!(matches!(
            branch.stop,
            BranchStop::AmplitudeBound { .. } | BranchStop::ParamBound { .. }
        ));
        for p in &branch.points {
            let r2 = p.amplitude * p.amplitude;
            assert_relative_eq!(r2, p.orbit.param, max_relative = 1e-8, epsilon = 1e-12);
            assert_relative_eq!(p.orbit.period, PI, max_relative = 1e-9);
            // trivial multiplier 1 and the radial one exp(−2μT)
            assert!(
                p.floquet.trivial_error < 1e-8,
                "{}",
                p.floquet.trivial_error
            );
            assert_relative_eq!(
                p.floquet.max_nontrivial,
                field.radial_multiplier(r2),
                max_relative = 1e-6
            );
            assert!(p.floquet.stable());
        }
        assert!(branch.special.is_empty(), "{:?}", branch.special);
    }
}

#[test]
fn subcritical_fold_is_located() {
    let field = HopfNormalForm {
        omega: 2.0,
        a: 1.0,
        b: -1.0,
    };
    let c = continuation(&field, (-1.0, 1.0), 1.1, true);
    let (start, dir) = from_hopf(&field);
    let branch = c.run(start, dir);
    let folds: Vec<_> = branch
        .special
        .iter()
        .filter(|s| s.kind == SpecialKind::Fold)
        .collect();
    assert_eq!(folds.len(), 1, "{:?}", branch.special);
    let f = folds[0];
    assert!(f.located);
    assert_relative_eq!(f.orbit.param, -0.25, max_relative = 1e-7);
    assert_relative_eq!(f.amplitude * f.amplitude, 0.5, max_relative = 1e-3);
    // every cycle lies on μ = r⁴ − r², unstable below the fold amplitude, stable above
    for p in &branch.points {
        let r2 = p.amplitude * p.amplitude;
        assert_relative_eq!(p.orbit.param, r2 * r2 - r2, epsilon = 1e-8);
        if (r2 - 0.5).abs() > 0.02 {
            assert_eq!(p.floquet.stable(), r2 > 0.5, "r² = {r2}");
            assert_relative_eq!(
                p.floquet.max_nontrivial,
                field.radial_multiplier(r2),
                max_relative = 1e-5
            );
        }
    }
}

#[test]
fn results_converge_as_tolerances_tighten() {
    let field = HopfNormalForm {
        omega: 2.0,
        a: 1.0,
        b: -1.0,
    };
    let mut errors = Vec::new();
    for rtol in [1e-6, 1e-8, 1e-10] {
        let mut c = continuation(&field, (-1.0, 1.0), 1.1, true);
        c.shooting.ode = ode(rtol);
        c.shooting.dp_rel = rtol.sqrt();
        let (start, dir) = from_hopf(&field);
        let branch = c.run(start, dir);
        let fold = branch
            .special
            .iter()
            .find(|s| s.kind == SpecialKind::Fold)
            .expect("a fold");
        errors.push((fold.orbit.param + 0.25).abs());
    }
    assert!(errors[2] <= errors[0], "{errors:?}");
    assert!(errors[2] < 1e-8, "{errors:?}");
}

#[test]
fn cancellation_hook_stops_after_the_points_it_allowed() {
    // The hook is asked before each step: allowing 5 asks gives exactly 5 points, the
    // same 5 an uncancelled run computes first, and the stop reason says why.
    let field = HopfNormalForm {
        omega: 2.0,
        a: -1.0,
        b: 0.0,
    };
    let asked = std::sync::atomic::AtomicUsize::new(0);
    let cancel = || asked.fetch_add(1, std::sync::atomic::Ordering::Relaxed) >= 5;
    let mut c = continuation(&field, (-1.0, 1.0), 0.9, true);
    let (start, dir) = from_hopf(&field);
    let full = c.run(start, dir.clone());
    c.cancel = Some(&cancel);
    let cut = c.run(start, dir);
    assert_eq!(cut.stop, BranchStop::Cancelled);
    assert_eq!(cut.points.len(), 5);
    assert!(full.points.len() > 5, "{:?}", full.stop);
    assert_eq!(cut.points[..], full.points[..5]);
}

/// The Hopf normal form in (x0, x1) plus N − 2 decoupled decaying states, $\dot x_k = −c_k x_k$:
/// its cycles are the normal form's (the other states zero), with the extra Floquet
/// multipliers $e^{−c_k T}$. An N-state field with known cycles and spectrum, for the shooting
/// at the sizes of the vehicle models (odd, so the cycles are symmetric).
struct Padded<const N: usize> {
    core: HopfNormalForm,
}

impl<const N: usize> Padded<N> {
    fn rate(k: usize) -> f64 {
        0.3 + 0.05 * k as f64
    }
}

impl<const N: usize> VectorField<N> for Padded<N> {
    fn rhs(&self, x: &SVector<f64, N>, mu: f64) -> SVector<f64, N> {
        let f = self.core.rhs(&SVector::<f64, 2>::new(x[0], x[1]), mu);
        SVector::from_fn(|k, _| if k < 2 { f[k] } else { -Self::rate(k) * x[k] })
    }
    fn jacobian(&self, x: &SVector<f64, N>, mu: f64) -> nalgebra::SMatrix<f64, N, N> {
        let j = self.core.jacobian(&SVector::<f64, 2>::new(x[0], x[1]), mu);
        nalgebra::SMatrix::from_fn(|r, c| match (r, c) {
            (r, c) if r < 2 && c < 2 => j[(r, c)],
            (r, c) if r == c => -Self::rate(r),
            _ => 0.0,
        })
    }
}

/// Multiple shooting (1, 2 and 3 segments, serial and on rayon) on 4-, 12- and 30-state
/// fields: every cycle on μ = r⁴ − r², the fold at μ = −1/4, the multipliers e^{−c_k T} of
/// the padding states; rayon changes no bit.
fn segments_case<const N: usize>() {
    let field = Padded::<N> {
        core: HopfNormalForm {
            omega: 2.0,
            a: 1.0,
            b: -1.0,
        },
    };
    let period = PI;
    for segments in [1, 2, 3] {
        let mut branches = Vec::new();
        for parallel in [false, true] {
            let mut params = ContinuationParams::new((-1.0, 1.0), 1.1, vec![1.0; N + 2]);
            params.ds_initial = 0.02;
            params.ds_max = 0.1;
            let c = Continuation {
                shooting: Shooting {
                    field: &field,
                    symmetric: true,
                    ode: ode(1e-11),
                    dp_rel: 1e-6,
                    parallel,
                    busy: None,
                    segments,
                },
                params,
                amplitude: &|_: &OrbitPoint<N>, peaks: &SVector<f64, N>| peaks[0],
                progress: None,
                cancel: None,
                extent: None,
                rejoin: None,
            };
            let start = OrbitPoint {
                x0: SVector::<f64, N>::zeros(),
                period,
                param: 0.0,
            };
            let dir = DVector::from_fn(N + 2, |i, _| if i == 0 { 1.0 } else { 0.0 });
            branches.push(c.run(start, dir));
        }
        assert_eq!(branches[0], branches[1], "N {N}, {segments} segments");
        let b = &branches[0];
        assert!(b.points.len() > 10, "{:?}", b.stop);
        for p in &b.points {
            let r2 = p.amplitude * p.amplitude;
            assert_relative_eq!(p.orbit.param, r2 * r2 - r2, epsilon = 1e-8);
            assert_relative_eq!(p.orbit.period, period, max_relative = 1e-9);
            assert!(
                p.floquet.trivial_error < 1e-8,
                "{}",
                p.floquet.trivial_error
            );
            for k in 2..N {
                let mu = (-Padded::<N>::rate(k) * period).exp();
                let found = p
                    .floquet
                    .multipliers
                    .iter()
                    .map(|m| (m.re - mu).abs() + m.im.abs())
                    .fold(f64::INFINITY, f64::min);
                assert!(found < 1e-8 * mu.max(1e-3), "N {N} k {k}: {found:e}");
            }
        }
        let folds: Vec<_> = b
            .special
            .iter()
            .filter(|s| s.kind == SpecialKind::Fold)
            .collect();
        assert_eq!(folds.len(), 1, "{:?}", b.special);
        assert_relative_eq!(folds[0].orbit.param, -0.25, max_relative = 1e-7);
    }
}

#[test]
fn multiple_shooting_on_4_12_and_30_states() {
    segments_case::<4>();
    segments_case::<12>();
    segments_case::<30>();
}

/// A branch stops as stiff only where both hold: many integrator steps per Newton iteration and
/// a mean step near the explicit integrator's stability bound 3.3/|λ|max at the centre. The
/// normal form's steps are set by accuracy (rtol 1e-12; |λ|max = |a μ ± iω| ≈ 2 at the centre,
/// a bound of about 1.6 s, far above its steps): with a limit of one step per iteration its
/// branch still runs to its amplitude bound.
#[test]
fn accuracy_limited_steps_do_not_stop_a_branch_as_stiff() {
    let field = HopfNormalForm {
        omega: 2.0,
        a: -1.0,
        b: 0.0,
    };
    let mut c = continuation(&field, (-1.0, 1.0), 0.9, true);
    c.params.max_steps_per_iteration = Some(1.0);
    let (start, dir) = from_hopf(&field);
    let branch = c.run(start, dir);
    assert!(
        matches!(
            branch.stop,
            BranchStop::AmplitudeBound { .. } | BranchStop::ParamBound { .. }
        ),
        "{:?}",
        branch.stop
    );
    assert!(branch.points.len() > 10, "{}", branch.points.len());
}

/// The chord corrector (a linearisation kept for the iterations after it, which integrate the
/// plain flows alone) and Newton (a linearisation at every iteration) find the same cycles:
/// both on μ = r⁴ − r² with the fold at μ = −1/4, in one and in three segments, and the chord
/// corrector takes fewer linearisations for them.
#[test]
fn chord_and_newton_correctors_find_the_same_closed_form_cycles() {
    let field = HopfNormalForm {
        omega: 2.0,
        a: 1.0,
        b: -1.0,
    };
    for segments in [1, 3] {
        let mut linearisations = Vec::new();
        for chord in [true, false] {
            let mut c = continuation(&field, (-1.0, 1.0), 1.1, true);
            c.shooting.segments = segments;
            c.params.chord = chord;
            let (start, dir) = from_hopf(&field);
            let b = c.run(start, dir);
            assert!(b.points.len() > 10, "{:?}", b.stop);
            for p in &b.points {
                let r2 = p.amplitude * p.amplitude;
                assert_relative_eq!(p.orbit.param, r2 * r2 - r2, epsilon = 1e-8);
                assert!(
                    p.floquet.trivial_error < 1e-8,
                    "{}",
                    p.floquet.trivial_error
                );
            }
            let fold = b
                .special
                .iter()
                .find(|s| s.kind == SpecialKind::Fold)
                .expect("a fold");
            assert_relative_eq!(fold.orbit.param, -0.25, max_relative = 1e-7);
            assert_eq!(b.stats.chord_iterations > 0, chord, "{:?}", b.stats);
            linearisations.push(b.stats.newton_iterations as f64 / b.points.len() as f64);
        }
        assert!(
            linearisations[0] < linearisations[1],
            "{segments} segments: linearisations per cycle {linearisations:?}"
        );
    }
}
