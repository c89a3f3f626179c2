//! Every expected value here comes from a closed form or an independent computation
//! (matrix exponentials by similarity to a block-diagonal closed form, the Stuart–Landau
//! cycle, the dead-band oscillator's piecewise-harmonic solution), never from this
//! integrator's own output.

use nalgebra::{Matrix2, Matrix3, SMatrix, SVector, Vector1, Vector2, Vector3};

use super::dopri::{Dense, Rk, C, E, TABLEAU};
use super::models::{Linear, StuartLandau};
use super::*;

pub(super) fn opts(rtol: f64, atol: f64, monodromy: bool) -> OdeOptions {
    OdeOptions {
        tol: Tolerances { rtol, atol },
        monodromy,
        ..OdeOptions::default()
    }
}

pub(super) fn rel_err<const R: usize, const CC: usize>(
    a: &SMatrix<f64, R, CC>,
    b: &SMatrix<f64, R, CC>,
) -> f64 {
    (a - b).norm() / b.norm()
}

/// $e^{at} R(\omega t)$, the exponential of $[[a, -\omega], [\omega, a]]$.
pub(super) fn rot_decay(a: f64, w: f64, t: f64) -> Matrix2<f64> {
    let (s, c) = (w * t).sin_cos();
    Matrix2::new(c, -s, s, c) * (a * t).exp()
}

#[test]
fn linear_rotation_decay_matches_exponential() {
    let (a, w, t) = (-0.3, 2.0, 5.0);
    let field = Linear {
        a: Matrix2::new(a, -w, w, a),
    };
    let x0 = Vector2::new(1.0, 0.5);
    let sol =
        integrate(&field, 0.0, &x0, t, &opts(1e-11, 1e-13, true)).expect("smooth linear problem");
    let exact = rot_decay(a, w, t);
    assert!(rel_err(&sol.x, &(exact * x0)) < 1e-9);
    let phi = sol.monodromy.expect("monodromy requested");
    assert!(rel_err(&phi, &exact) < 1e-9, "{}", rel_err(&phi, &exact));
    assert_eq!(sol.stop, StopReason::Reached);
    assert!((sol.t - t).abs() < 1e-15);
}

/// A 3-state linear field A = S D S⁻¹, D = blockdiag([[a, −w], [w, a]], d), its end time t
/// and the closed form e^{At} = S e^{Dt} S⁻¹.
fn similar_3d() -> (Linear<3>, f64, Matrix3<f64>) {
    let (a, w, d, t) = (-0.2, 1.5, -0.7, 4.0);
    let dm = Matrix3::new(a, -w, 0.0, w, a, 0.0, 0.0, 0.0, d);
    let s = Matrix3::new(1.0, 2.0, 0.0, 0.0, 1.0, 1.0, 1.0, 0.0, 3.0); // det 5
    let s_inv = s.try_inverse().expect("det S = 5");
    let field = Linear { a: s * dm * s_inv };
    let mut exp_d = Matrix3::zeros();
    exp_d
        .fixed_view_mut::<2, 2>(0, 0)
        .copy_from(&rot_decay(a, w, t));
    exp_d[(2, 2)] = (d * t).exp();
    let exact = s * exp_d * s_inv;
    (field, t, exact)
}

#[test]
fn linear_3d_matches_exponential_by_similarity() {
    let (field, t, exact) = similar_3d();
    let x0 = Vector3::new(0.3, -1.0, 2.0);
    let sol =
        integrate(&field, 0.0, &x0, t, &opts(1e-11, 1e-13, true)).expect("smooth linear problem");
    assert!(rel_err(&sol.x, &(exact * x0)) < 1e-9);
    let phi = sol.monodromy.expect("monodromy requested");
    assert!(rel_err(&phi, &exact) < 1e-9, "{}", rel_err(&phi, &exact));
}

#[test]
fn linear_4d_two_oscillators() {
    // The wheelset's dimension: two decaying rotations, e^{At} = blockdiag of closed forms.
    let (a1, w1, a2, w2, t) = (-0.1, 3.0, 0.05, 0.7, 6.0);
    let mut a = SMatrix::<f64, 4, 4>::zeros();
    a.fixed_view_mut::<2, 2>(0, 0)
        .copy_from(&Matrix2::new(a1, -w1, w1, a1));
    a.fixed_view_mut::<2, 2>(2, 2)
        .copy_from(&Matrix2::new(a2, -w2, w2, a2));
    let mut exact = SMatrix::<f64, 4, 4>::zeros();
    exact
        .fixed_view_mut::<2, 2>(0, 0)
        .copy_from(&rot_decay(a1, w1, t));
    exact
        .fixed_view_mut::<2, 2>(2, 2)
        .copy_from(&rot_decay(a2, w2, t));
    let x0 = SVector::<f64, 4>::new(1e-3, 0.0, -2e-3, 5e-4);
    let sol = integrate(&Linear { a }, 0.0, &x0, t, &opts(1e-11, 1e-15, true)).expect("smooth");
    assert!(rel_err(&sol.x, &(exact * x0)) < 1e-9);
    let phi = sol.monodromy.expect("monodromy requested");
    assert!(rel_err(&phi, &exact) < 1e-9, "{}", rel_err(&phi, &exact));
}

#[test]
fn tangent_vector_matches_the_exponential() {
    // One tangent vector w(t) = e^{At} w0 (closed form as above).
    let (field, t, exact) = similar_3d();
    let x0 = Vector3::new(0.3, -1.0, 2.0);
    let w0 = Vector3::new(0.0, 1.0, -0.5);
    let (sol, wt) = integrate_tangent(
        &field,
        0.0,
        &x0,
        &w0,
        t,
        &opts(1e-11, 1e-13, true),
        TangentControl::Checked,
    )
    .expect("smooth linear problem");
    assert!(rel_err(&sol.x, &(exact * x0)) < 1e-9);
    assert!(
        rel_err(&wt, &(exact * w0)) < 1e-9,
        "{}",
        rel_err(&wt, &(exact * w0))
    );
    assert!(sol.monodromy.is_none(), "a tangent run returns no matrix");
    // and the run that carries nothing
    let plain = integrate(&field, 0.0, &x0, t, &opts(1e-11, 1e-13, false)).expect("smooth");
    assert!(rel_err(&plain.x, &(exact * x0)) < 1e-9);
    assert!(plain.monodromy.is_none());
    // w carried free of the error test: the steps are the plain run's, so its state is the
    // plain run's to the bit, and w, on those steps, still meets the closed form
    let (free, wf) = integrate_tangent(
        &field,
        0.0,
        &x0,
        &w0,
        t,
        &opts(1e-11, 1e-13, true),
        TangentControl::Free,
    )
    .expect("smooth linear problem");
    assert_eq!(free.x, plain.x);
    assert_eq!(free.stats, plain.stats);
    assert!(
        rel_err(&wf, &(exact * w0)) < 1e-9,
        "{}",
        rel_err(&wf, &(exact * w0))
    );
}

#[test]
fn stuart_landau_cycle_returns_with_floquet_multipliers() {
    let (sl, mu) = (StuartLandau { omega: 1.3 }, 0.8);
    let t = sl.period();
    let x0 = Vector2::new(sl.radius(mu), 0.0);
    let sol = integrate(&sl, mu, &x0, t, &opts(1e-11, 1e-13, true)).expect("smooth cycle");
    assert!((sol.x - x0).norm() < 1e-9, "{}", (sol.x - x0).norm());
    let m = sol.monodromy.expect("monodromy requested");
    // Eigenvalues of a 2×2 from its trace and determinant (both real here).
    let (tr, det) = (m.trace(), m.determinant());
    let disc = (tr * tr - 4.0 * det).max(0.0).sqrt();
    let (big, small) = ((tr + disc) / 2.0, (tr - disc) / 2.0);
    assert!((big - 1.0).abs() < 1e-8, "trivial multiplier {big}");
    assert!(
        (small - sl.radial_multiplier(mu)).abs() < 1e-8,
        "radial {small}"
    );
    // The trivial multiplier's eigenvector is the flow direction: Φ(T) f(x0) = f(x0).
    let f0 = sl.rhs(&x0, mu);
    assert!((m * f0 - f0).norm() < 1e-8 * f0.norm());
}

#[test]
fn global_error_scales_with_rtol() {
    let (a, w, t) = (-0.3, 2.0, 5.0);
    let field = Linear {
        a: Matrix2::new(a, -w, w, a),
    };
    let x0 = Vector2::new(1.0, 0.5);
    let exact = rot_decay(a, w, t) * x0;
    let errs: Vec<f64> = [1e-6, 1e-8, 1e-10]
        .iter()
        .map(|&rtol| {
            let sol =
                integrate(&field, 0.0, &x0, t, &opts(rtol, rtol * 1e-2, false)).expect("smooth");
            rel_err(&sol.x, &exact)
        })
        .collect();
    for (pair, rtol) in errs.windows(2).zip([1e-6, 1e-8]) {
        // Tolerance proportionality: two decades of rtol buy between one and four decades.
        let ratio = pair[0] / pair[1];
        assert!((10.0..1e4).contains(&ratio), "ratio {ratio} at {errs:?}");
        assert!(pair[0] < 100.0 * rtol, "error {} at rtol {rtol}", pair[0]);
    }
}

#[test]
fn observed_samples_follow_exact_solution() {
    let (a, w, t) = (-0.3, 2.0, 5.0);
    let field = Linear {
        a: Matrix2::new(a, -w, w, a),
    };
    let x0 = Vector2::new(1.0, 0.5);
    let samples: Vec<f64> = (0..=100).map(|i| i as f64 * t / 100.0).collect();
    let (mut seen, mut worst) = (Vec::new(), 0.0_f64);
    let o = opts(1e-10, 1e-12, false);
    integrate_observed(&field, 0.0, &x0, t, &o, &samples, &mut |ts, x| {
        seen.push(ts);
        worst = worst.max((x - rot_decay(a, w, ts) * x0).norm());
    })
    .expect("smooth");
    assert_eq!(seen, samples);
    // The continuous extension's own error is O(h^5), of the order of the local error the
    // controller keeps near rtol·|x|; so a sample errs by about the global error of the
    // neighbouring step ends (tolerance-proportional, ~rtol here), not by more: bound 10·rtol.
    assert!(worst < 1e-9, "{worst}");
}

#[test]
fn section_returns_after_one_period() {
    let (sl, mu) = (StuartLandau { omega: 1.3 }, 0.8);
    let x0 = Vector2::new(sl.radius(mu), 0.0);
    let section = |x: &Vector2<f64>| x[1];
    let o = opts(1e-11, 1e-13, true);
    let hit = integrate_to_section(&sl, mu, &x0, 3.0 * sl.period(), &section, 0.01, &o)
        .expect("smooth cycle");
    let sol = hit.expect("the cycle crosses y = 0 upward after one period");
    assert!(
        (sol.t - sl.period()).abs() < 1e-10 * sl.period(),
        "{} vs {}",
        sol.t,
        sl.period()
    );
    assert!((sol.x - x0).norm() < 1e-9);
    assert!(sol.monodromy.is_some());
    // No upward crossing before t_max.
    let none =
        integrate_to_section(&sl, mu, &x0, 0.9 * sl.period(), &section, 0.01, &o).expect("smooth");
    assert!(none.is_none());
}

/// $\dot x = x^2$, $x(0) = 1$: $x = 1/(1 - t)$, singular at $t = 1$.
struct BlowUp;
impl VectorField<1> for BlowUp {
    fn rhs(&self, x: &Vector1<f64>, _p: f64) -> Vector1<f64> {
        x.component_mul(x)
    }
    fn jacobian(&self, x: &Vector1<f64>, _p: f64) -> SMatrix<f64, 1, 1> {
        SMatrix::<f64, 1, 1>::new(2.0 * x[0])
    }
}

#[test]
fn bad_arguments_are_errors() {
    for (r, a) in [
        (0.0, 1e-12),
        (1e-15, 1e-12),
        (f64::NAN, 1e-12),
        (1e-8, -1.0),
        (1e-8, f64::INFINITY),
    ] {
        assert!(matches!(
            Tolerances::new(r, a),
            Err(OdeError::BadTolerance { .. })
        ));
    }
    let field = Linear {
        a: Matrix2::<f64>::identity(),
    };
    let x0 = Vector2::new(1.0, 0.0);
    let bad_tol = opts(0.0, 1e-12, false);
    assert!(matches!(
        integrate(&field, 0.0, &x0, 1.0, &bad_tol),
        Err(OdeError::BadTolerance { .. })
    ));
    for t_end in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        let r = integrate(&field, 0.0, &x0, t_end, &OdeOptions::default());
        assert!(matches!(r, Err(OdeError::BadInterval { .. })));
    }
    let nan = Vector2::new(f64::NAN, 0.0);
    assert!(matches!(
        integrate(&field, 0.0, &nan, 1.0, &OdeOptions::default()),
        Err(OdeError::NonFinite { .. })
    ));
    let bad_h = OdeOptions {
        h_max: f64::NAN,
        ..OdeOptions::default()
    };
    assert!(matches!(
        integrate(&field, 0.0, &x0, 1.0, &bad_h),
        Err(OdeError::BadArgument { .. })
    ));
    let mut obs = |_: f64, _: &Vector2<f64>| {};
    let unsorted = integrate_observed(
        &field,
        0.0,
        &x0,
        1.0,
        &OdeOptions::default(),
        &[0.5, 0.2],
        &mut obs,
    );
    assert!(matches!(unsorted, Err(OdeError::BadArgument { .. })));
    let few = OdeOptions {
        max_steps: 3,
        ..OdeOptions::default()
    };
    assert!(matches!(
        integrate(&field, 0.0, &x0, 10.0, &few),
        Err(OdeError::MaxSteps { .. })
    ));
}

#[test]
fn blow_up_is_an_error_not_a_panic() {
    let x0 = Vector1::new(1.0);
    let r = integrate(&BlowUp, 0.0, &x0, 2.0, &OdeOptions::default());
    assert!(
        matches!(
            r,
            Err(OdeError::StepSizeTooSmall { .. }
                | OdeError::NonFinite { .. }
                | OdeError::MaxSteps { .. })
        ),
        "{r:?}"
    );
    // As an outcome: stopped just short of the singularity, on the exact solution's track.
    let sol =
        integrate_partial(&BlowUp, 0.0, &x0, 2.0, &OdeOptions::default()).expect("valid arguments");
    assert_ne!(sol.stop, StopReason::Reached);
    assert!(sol.t < 1.0 && sol.t > 1.0 - 1e-6, "{}", sol.t);
}

#[test]
fn tableau_satisfies_order_conditions() {
    // b = last row of A; b̂ = b - e. Quadrature conditions Σ b c^{q-1} = 1/q (q ≤ 5), the
    // embedded ones (q ≤ 4), row sums = c, and the order-3 condition Σ b a c = 1/6.
    let b: Vec<f64> = TABLEAU[5].iter().copied().chain([0.0]).collect();
    let bh: Vec<f64> = b.iter().zip(E).map(|(bi, ei)| bi - ei).collect();
    let sum = |w: &[f64], q: i32| {
        w.iter()
            .zip(C)
            .map(|(wi, ci)| wi * ci.powi(q - 1))
            .sum::<f64>()
    };
    for q in 1..=5 {
        assert!((sum(&b, q) - 1.0 / q as f64).abs() < 1e-15, "b, q = {q}");
    }
    for q in 1..=4 {
        assert!((sum(&bh, q) - 1.0 / q as f64).abs() < 1e-15, "b̂, q = {q}");
    }
    assert!(
        (sum(&bh, 5) - 0.2).abs() > 1e-6,
        "the embedded method is only of order 4"
    );
    for (i, row) in TABLEAU.iter().enumerate() {
        assert!(
            (row.iter().sum::<f64>() - C[i + 1]).abs() < 1e-14,
            "row {i}"
        );
    }
    let bac: f64 = (1..7)
        .map(|i| b[i] * (0..i).map(|j| TABLEAU[i - 1][j] * C[j]).sum::<f64>())
        .sum();
    assert!((bac - 1.0 / 6.0).abs() < 1e-15);
}

/// $\dot u = 1$, $\dot v = 4u^3$, $\dot w = 5u^4$: $v = u^4$, $w = u^5$ from the origin.
struct Powers;
impl VectorField<3> for Powers {
    fn rhs(&self, x: &Vector3<f64>, _p: f64) -> Vector3<f64> {
        Vector3::new(1.0, 4.0 * x[0].powi(3), 5.0 * x[0].powi(4))
    }
    fn jacobian(&self, x: &Vector3<f64>, _p: f64) -> Matrix3<f64> {
        Matrix3::new(
            0.0,
            0.0,
            0.0,
            12.0 * x[0].powi(2),
            0.0,
            0.0,
            20.0 * x[0].powi(3),
            0.0,
            0.0,
        )
    }
}

#[test]
fn step_exact_to_degree_5_and_dense_output_to_degree_4() {
    // Quadrature with a 5th-order step and a 4th-order continuous extension.
    let mut rk = Rk {
        field: &Powers,
        p: 0.0,
        variational: false,
        tol: Tolerances::default(),
        tol_phi: Tolerances::default(),
        rhs_evals: 0,
        method: Method::DormandPrince5,
    };
    let p0 = rk.point(
        0.3,
        Vector3::new(0.3, 0.3_f64.powi(4), 0.3_f64.powi(5)),
        Matrix3::identity(),
    );
    let trial = rk.step(&p0, 0.7);
    let u1 = 1.0_f64;
    assert!((trial.end.x[2] - u1.powi(5)).abs() < 1e-14);
    let dense = Dense::new(&p0, &trial);
    for th in [0.1, 0.37, 0.5, 0.9] {
        let t = 0.3 + 0.7 * th;
        let x = dense.eval(t);
        assert!(
            (x[0] - t).abs() < 1e-15 && (x[1] - t.powi(4)).abs() < 1e-14,
            "θ = {th}"
        );
    }
    assert_eq!(rk.rhs_evals, 7, "1 at the start + 6 per step (FSAL)");
    let _: SVector<f64, 3> = trial.end.f; // FSAL: the 7th stage is f at the new point
}

/// Largest |r cos(ωt + φ)| over [0, t_end], in closed form: the end values and the interior
/// points where ωt + φ is a multiple of π (|u| = r there).
fn cosine_abs_max(r: f64, w: f64, phase: f64, t_end: f64) -> f64 {
    let u = |t: f64| (r * (w * t + phase).cos()).abs();
    let first = (phase / std::f64::consts::PI).floor() + 1.0;
    let t_first = (first * std::f64::consts::PI - phase) / w;
    let interior = if t_first > 0.0 && t_first < t_end {
        r
    } else {
        0.0
    };
    u(0.0).max(u(t_end)).max(interior)
}

/// The peaks located on the dense output of an 8-state linear system (four undamped
/// rotations of different frequencies, some with interior maxima, some without) equal the
/// closed-form maxima of the cosines; over all horizons and at two tolerances.
#[test]
fn peaks_on_dense_output_match_closed_form_maxima() {
    let freqs = [3.0, 0.7, 11.0, 0.21];
    let radii = [1e-3, 2.5, 0.4, 7.0];
    let phases: [f64; 4] = [0.3, 2.0, -1.1, 0.05];
    let mut a = SMatrix::<f64, 8, 8>::zeros();
    let mut x0 = SVector::<f64, 8>::zeros();
    for k in 0..4 {
        let w = freqs[k];
        a.fixed_view_mut::<2, 2>(2 * k, 2 * k)
            .copy_from(&Matrix2::new(0.0, -w, w, 0.0));
        // u = r cos(ωt + φ), v = r sin(ωt + φ)
        x0[2 * k] = radii[k] * phases[k].cos();
        x0[2 * k + 1] = radii[k] * phases[k].sin();
    }
    for (rtol, bound) in [(1e-8, 1e-7), (1e-11, 1e-10)] {
        for t_end in [0.4, 1.7, 9.0] {
            let (_, peaks) = integrate_with_peaks(
                &Linear { a },
                0.0,
                &x0,
                t_end,
                &opts(rtol, rtol * 1e-3, false),
            )
            .expect("smooth");
            for k in 0..4 {
                let (r, w, ph) = (radii[k], freqs[k], phases[k]);
                let u = cosine_abs_max(r, w, ph, t_end);
                let v = cosine_abs_max(r, w, ph - std::f64::consts::FRAC_PI_2, t_end);
                let (eu, ev) = ((peaks[2 * k] - u) / r, (peaks[2 * k + 1] - v) / r);
                assert!(
                    eu.abs() < bound && ev.abs() < bound,
                    "rtol {rtol} t {t_end} k {k}: {eu:e} {ev:e}"
                );
            }
        }
    }
}
