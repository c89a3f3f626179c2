//! Branch switching on two problems whose bifurcations of cycles are known in closed form
//! (`critspeed::reference::switching`): a symmetric branch that breaks its symmetry at two
//! speeds, joined by a branch of asymmetric cycles, and a cycle that doubles its period at two
//! parameter values, joined by a branch of doubled cycles. Independent of any wheelset.

use critspeed::continuation::{
    switch_at, Branch, BranchStop, Continuation, ContinuationParams, OrbitPoint, Rejoin, Shooting,
    SpecialKind,
};
use critspeed::reference::switching::{PeriodDoublingForm, SymmetryBreakingForm};
use critspeed::system::ode::{OdeOptions, Tolerances, VectorField};
use nalgebra::{DVector, SVector};
use std::f64::consts::PI;

fn ode(rtol: f64) -> OdeOptions {
    OdeOptions {
        tol: Tolerances::new(rtol, rtol * 1e-2).expect("valid tolerances"),
        ..OdeOptions::default()
    }
}

fn peak0<const N: usize>(_: &OrbitPoint<N>, peaks: &SVector<f64, N>) -> f64 {
    peaks[0]
}

fn continuation<'a, const N: usize, F: VectorField<N>>(
    field: &'a F,
    range: (f64, f64),
    symmetric: bool,
    segments: usize,
    rejoin: Option<Rejoin>,
) -> Continuation<'a, N, F> {
    let mut params = ContinuationParams::new(range, 10.0, vec![1.0; N + 2]);
    params.ds_initial = 0.02;
    params.ds_max = 0.05;
    params.newton_tol = 1e-11;
    Continuation {
        shooting: Shooting {
            field,
            symmetric,
            ode: ode(1e-12),
            dp_rel: 1e-6,
            parallel: false,
            busy: None,
            segments,
        },
        params,
        amplitude: &peak0::<N>,
        progress: None,
        cancel: None,
        extent: None,
        rejoin,
    }
}

fn points_of<const N: usize>(b: &Branch<N>, kind: SpecialKind) -> Vec<f64> {
    b.special
        .iter()
        .filter(|s| s.kind == kind)
        .map(|s| s.orbit.param)
        .collect()
}

const SB: SymmetryBreakingForm = SymmetryBreakingForm {
    omega: 2.0 * PI,
    k: 4.0,
    c1: 0.3,
    c2: 0.7,
};

fn symmetric_branch() -> Branch<3> {
    let c = continuation(&SB, (-0.1, 1.0), true, 1, None);
    let start = OrbitPoint {
        x0: SVector::<f64, 3>::zeros(),
        period: 1.0,
        param: 0.0,
    };
    c.run(start, DVector::from_vec(vec![1.0, 0.0, 0.0, 0.0, 0.0]))
}

#[test]
fn symmetry_breaking_is_located_where_the_half_period_multiplier_is_minus_one() {
    let b = symmetric_branch();
    let sb = points_of(&b, SpecialKind::SymmetryBreaking);
    assert_eq!(sb.len(), 2, "{:?}", b.special);
    assert!((sb[0] - SB.c1).abs() < 1e-8, "{sb:?}");
    assert!((sb[1] - SB.c2).abs() < 1e-8, "{sb:?}");
    // no fold, period doubling or torus on the way
    assert_eq!(b.special.len(), 2, "{:?}", b.special);
    // the symmetric cycles are unstable exactly between the two points
    for p in &b.points {
        let mu = p.orbit.param;
        if (mu - SB.c1).abs() > 1e-3 && (mu - SB.c2).abs() > 1e-3 && mu > 1e-3 {
            assert_eq!(p.floquet.stable(), !(SB.c1..SB.c2).contains(&mu), "{mu}");
        }
    }
}

/// The asymmetric branch: r² = μ, z² = h(μ), period 1, multipliers 1, e^{−2μT}, e^{−2h(μ)T};
/// it ends where it meets the symmetric branch again, at μ = c₂; the other direction is the
/// mirror branch z = −√h.
#[test]
fn the_asymmetric_branch_is_the_closed_form_and_rejoins_at_the_second_point() {
    let b = symmetric_branch();
    let at = b
        .special
        .iter()
        .find(|s| s.kind == SpecialKind::SymmetryBreaking)
        .expect("a symmetry-breaking point");
    let parent = continuation(&SB, (-0.1, 1.0), true, 1, None);
    let scale = vec![1.0; 5];
    let tangent = b.points.get(at.after).map(|p| &p.tangent);
    let sw = switch_at(&parent.shooting, at, &scale, tangent).expect("switch");
    assert!((sw.multiplier + 1.0).abs() < 1e-6, "{}", sw.multiplier);
    assert_eq!(sw.rejoin, Rejoin::Mirror);
    let mut z_signs = Vec::new();
    for sign in [1.0, -1.0] {
        let child = continuation(&SB, (-0.1, 1.0), false, 2, Some(sw.rejoin));
        let branch = child.run(sw.start, &sw.direction * sign);
        assert!(branch.points.len() > 5, "{:?}", branch.stop);
        let z_sign = branch.points[0].orbit.x0[2].signum();
        for p in &branch.points {
            let (mu, x) = (p.orbit.param, p.orbit.x0);
            let h = SB.h(mu);
            assert!((x[0] * x[0] + x[1] * x[1] - mu).abs() < 1e-9, "r² at {mu}");
            assert!(
                (x[2] * x[2] - h).abs() < 1e-9,
                "z² {} against h {h} at {mu}",
                x[2] * x[2]
            );
            assert_eq!(x[2].signum(), z_sign, "one side of the mirror pair");
            assert!((p.orbit.period - 1.0).abs() < 1e-10);
            let mut got: Vec<f64> = p.floquet.multipliers.iter().map(|m| m.re).collect();
            let mut want = vec![1.0, (-2.0 * mu).exp(), (-2.0 * h).exp()];
            got.sort_by(f64::total_cmp);
            want.sort_by(f64::total_cmp);
            for (g, w) in got.iter().zip(&want) {
                assert!((g - w).abs() < 1e-7, "{got:?} {want:?} at {mu}");
            }
            assert!(p.floquet.stable());
        }
        match branch.stop {
            // a branch point of the full-period problem: see the doubled branch's test
            BranchStop::Rejoined { param } => assert!((param - SB.c2).abs() < 1e-5, "{param}"),
            other => panic!("the branch should rejoin at c2, stopped {other:?}"),
        }
        // the meeting point is the branch's only special point (its turning in μ there is
        // not reported as a fold of asymmetric cycles)
        assert_eq!(branch.special.len(), 1, "{:?}", branch.special);
        assert_eq!(branch.special[0].kind, SpecialKind::SymmetryBreaking);
        z_signs.push(z_sign);
    }
    // the two directions give the two cycles of the mirror pair
    assert_eq!(z_signs[0], -z_signs[1], "{z_signs:?}");
}

const PD: PeriodDoublingForm = PeriodDoublingForm {
    omega: 2.0 * PI,
    c: 0.6,
};

fn base_branch() -> Branch<4> {
    let c = continuation(&PD, (-0.3, 0.9), false, 2, None);
    let start = OrbitPoint {
        x0: SVector::<f64, 4>::new(1.0, 0.0, 0.0, 0.0),
        period: 1.0,
        param: -0.3,
    };
    c.run(start, DVector::from_vec(vec![0.0, 0.0, 0.0, 0.0, 0.0, 1.0]))
}

#[test]
fn period_doubling_is_located_where_a_multiplier_is_minus_one() {
    let b = base_branch();
    let pd = points_of(&b, SpecialKind::PeriodDoubling);
    assert_eq!(pd.len(), 2, "{:?}", b.special);
    assert!(pd[0].abs() < 1e-8, "{pd:?}");
    assert!((pd[1] - PD.c).abs() < 1e-8, "{pd:?}");
    assert_eq!(b.special.len(), 2, "{:?}", b.special);
}

/// The doubled branch: |w|² = h(σ) along the whole cycle, period 2T, multipliers 1, e^{−4T},
/// e^{−4h T}, e^{−2T}; it meets the base cycle again at σ = c.
#[test]
fn the_doubled_branch_is_the_closed_form_and_rejoins_at_the_second_point() {
    let b = base_branch();
    let at = b
        .special
        .iter()
        .find(|s| s.kind == SpecialKind::PeriodDoubling)
        .expect("a period-doubling point");
    let parent = continuation(&PD, (-0.3, 0.9), false, 2, None);
    let mut scale = vec![1.0; 6];
    scale[4] = 2.0;
    let tangent = b.points.get(at.after).map(|p| &p.tangent);
    let sw = switch_at(&parent.shooting, at, &scale, tangent).expect("switch");
    assert!((sw.multiplier + 1.0).abs() < 1e-6, "{}", sw.multiplier);
    assert_eq!((sw.rejoin, sw.period_factor), (Rejoin::Shift, 2));
    let child = continuation(&PD, (-0.3, 0.9), false, 4, Some(sw.rejoin));
    let branch = child.run(sw.start, sw.direction.clone());
    assert!(branch.points.len() > 5, "{:?}", branch.stop);
    for p in &branch.points {
        let (s, x) = (p.orbit.param, p.orbit.x0);
        let h = PD.h(s);
        assert!(
            (x[2] * x[2] + x[3] * x[3] - h).abs() < 1e-9,
            "|w|² against {h} at {s}"
        );
        assert!((p.orbit.period - 2.0).abs() < 1e-10);
        let mut got: Vec<f64> = p.floquet.multipliers.iter().map(|m| m.re).collect();
        let mut want = vec![1.0, (-4.0f64).exp(), (-4.0 * h).exp(), (-2.0f64).exp()];
        got.sort_by(f64::total_cmp);
        want.sort_by(f64::total_cmp);
        for (g, w) in got.iter().zip(&want) {
            assert!((g - w).abs() < 1e-7, "{got:?} {want:?} at {s}");
        }
    }
    match branch.stop {
        // the meeting point is a branch point of the doubled problem (singular correctors
        // there): its turning point is found to a few 1e-6, the parent's own point to 1e-8
        BranchStop::Rejoined { param } => assert!((param - PD.c).abs() < 1e-5, "{param}"),
        other => panic!("the branch should rejoin at c, stopped {other:?}"),
    }
    assert_eq!(branch.special.len(), 1, "{:?}", branch.special);
    assert_eq!(branch.special[0].kind, SpecialKind::PeriodDoubling);
}
