//! Switching surfaces, on the dead-band oscillator (the flange-contact caricature): located
//! crossing times, conservation, and the monodromy across kinks, all against its
//! piecewise-harmonic closed form.

use std::ops::ControlFlow;

use nalgebra::{Matrix2, Vector2};

use super::driver::run;
use super::models::DeadBand;
use super::tests::{opts, rel_err};
use super::*;

/// Runs the dead-band oscillator, returning the solution and the end times of the steps
/// that ended on a surface (|u| = c to 1e-9).
fn dead_band_run(field: &DeadBand, v0: f64, t_end: f64, o: &OdeOptions) -> (Solution<2>, Vec<f64>) {
    let mut on_surface = Vec::new();
    let x0 = Vector2::new(0.0, v0);
    let r = run(
        field,
        0.0,
        &x0,
        Matrix2::identity(),
        t_end,
        o,
        |_, _, trial| {
            if (trial.end.x[0].abs() - field.clearance).abs() < 1e-9 {
                on_surface.push(trial.end.t);
            }
            ControlFlow::Continue(())
        },
    )
    .expect("valid arguments");
    (r.sol, on_surface)
}

#[test]
fn dead_band_events_located_and_energy_conserved() {
    let field = DeadBand {
        k1: 1.0,
        k2: 50.0,
        clearance: 0.5,
    };
    let v0 = 1.0;
    let (t1, t2) = field
        .contact_times(v0)
        .expect("amplitude 1 > clearance 0.5");
    let half = 2.0 * t1 + t2;
    // 20 half periods, ending mid-way between the contacts of the last one.
    let t_end = 20.0 * half + 0.5 * t1;
    let o = opts(1e-12, 1e-14, true);
    let (sol, times) = dead_band_run(&field, v0, t_end, &o);
    assert_eq!(sol.stats.events, 40, "2 crossings per half period");
    assert_eq!(times.len(), 40);
    let e0 = field.energy(&Vector2::new(0.0, v0));
    assert!(
        (field.energy(&sol.x) - e0).abs() < 1e-10 * e0,
        "{}",
        field.energy(&sol.x) - e0
    );
    // The first event against the closed form asin(c/A)/√k1, then every later one.
    assert!((times[0] - t1).abs() < 1e-12 * t1, "{} vs {t1}", times[0]);
    for (i, t) in times.iter().enumerate() {
        let exact = (i / 2) as f64 * half + t1 + if i % 2 == 1 { t2 } else { 0.0 };
        assert!(
            (t - exact).abs() < 1e-10 * exact,
            "event {i}: {t} vs {exact}"
        );
    }
    // Over a period in contact the monodromy is area-preserving (Hamiltonian, det Φ = 1).
    let det = sol.monodromy.expect("monodromy requested").determinant();
    assert!((det - 1.0).abs() < 1e-9, "det {det}");
}

/// $e^{A\tau}$ for $A = [[0, 1], [-k, 0]]$.
pub(super) fn oscillator_exp(k: f64, tau: f64) -> Matrix2<f64> {
    let w = k.sqrt();
    let (s, c) = (w * tau).sin_cos();
    Matrix2::new(c, s / w, -w * s, c)
}

#[test]
fn dead_band_monodromy_is_product_of_segment_exponentials() {
    // f is continuous, so Φ needs no saltation at the kinks: over one period from u = 0 it is
    // the product of the exponentials of the Jacobian on each segment, with the closed-form
    // segment durations t1 (free), t2 (contact), 2 t1, t2, t1.
    let field = DeadBand {
        k1: 1.0,
        k2: 50.0,
        clearance: 0.5,
    };
    let (t1, t2) = field.contact_times(1.0).expect("contact");
    let (free, contact) = (
        |tau| oscillator_exp(1.0, tau),
        |tau| oscillator_exp(51.0, tau),
    );
    let one = free(t1) * contact(t2) * free(2.0 * t1) * contact(t2) * free(t1);
    let exact = one.pow(5);
    let x0 = Vector2::new(0.0, 1.0);
    let sol = integrate(
        &field,
        0.0,
        &x0,
        5.0 * (4.0 * t1 + 2.0 * t2),
        &opts(1e-12, 1e-14, true),
    )
    .expect("valid");
    let phi = sol.monodromy.expect("monodromy requested");
    assert!(rel_err(&phi, &exact) < 1e-9, "{}", rel_err(&phi, &exact));
    assert_eq!(sol.stats.events, 20);
    // The trivial Floquet multiplier: Φ f(x0) = f(x0) over whole periods.
    let f0 = field.rhs(&x0, 0.0);
    assert!((phi * f0 - f0).norm() < 1e-9 * f0.norm());
}

#[test]
fn event_restart_does_not_creep() {
    // Regression: a step ending exactly on the surface started the next one with the old
    // side's Jacobian (and the landing step's Φ error estimate saw the new side's), so the
    // controller crept across each kink with dozens of rejected steps.
    let field = DeadBand {
        k1: 1.0,
        k2: 50.0,
        clearance: 0.5,
    };
    let (t1, t2) = field.contact_times(1.0).expect("contact");
    for monodromy in [false, true] {
        let o = opts(1e-12, 1e-14, monodromy);
        let sol = integrate(
            &field,
            0.0,
            &Vector2::new(0.0, 1.0),
            10.0 * (4.0 * t1 + 2.0 * t2),
            &o,
        )
        .expect("valid");
        assert_eq!(sol.stats.events, 40);
        assert!(sol.stats.rejected < 3 * sol.stats.events, "{:?}", sol.stats);
    }
}

#[test]
fn dead_band_period_state_matches_closed_form() {
    // After whole periods the state is back at (0, v0) exactly; events keep it accurate.
    let field = DeadBand {
        k1: 1.0,
        k2: 50.0,
        clearance: 0.5,
    };
    let (t1, t2) = field.contact_times(1.0).expect("contact");
    let sol = integrate(
        &field,
        0.0,
        &Vector2::new(0.0, 1.0),
        10.0 * (4.0 * t1 + 2.0 * t2),
        &opts(1e-12, 1e-14, false),
    )
    .expect("piecewise-smooth problem");
    assert!((sol.x - Vector2::new(0.0, 1.0)).norm() < 1e-9, "{}", sol.x);
}

/// [`tangent_on_steps`] across the dead band's kinks, on 400 equal steps that do not stop at
/// them: over one period the tangents are the columns of the closed-form monodromy (the
/// product of the segment exponentials, as above) to 1e-7, and their differences in the
/// initial speed converge as the difference step shrinks from 1e-4 to 1e-7 (a step whose
/// stages changed side with the argument would make them jump by about h ΔJ / 6 per kink).
#[test]
fn fixed_step_tangents_are_exact_and_smooth_across_the_kinks() {
    let field = DeadBand {
        k1: 1.0,
        k2: 50.0,
        clearance: 0.5,
    };
    let (t1, t2) = field.contact_times(1.0).expect("contact");
    let period = 4.0 * t1 + 2.0 * t2;
    let (free, contact) = (
        |tau| oscillator_exp(1.0, tau),
        |tau| oscillator_exp(51.0, tau),
    );
    let exact = free(t1) * contact(t2) * free(2.0 * t1) * contact(t2) * free(t1);
    let taus: Vec<f64> = (1..=400).map(|i| f64::from(i) / 400.0).collect();
    let x0 = Vector2::new(0.0, 1.0);
    for j in 0..2 {
        let xi0 = Vector2::from_fn(|i, _| if i == j { 1.0 } else { 0.0 });
        let (x1, xi1) =
            tangent_on_steps(&field, 0.0, &x0, &xi0, (period, 0.0), &taus).expect("steps");
        assert!((x1 - x0).norm() < 1e-7, "the period closes: {x1}");
        let want = exact.column(j);
        assert!(
            (xi1 - want).norm() < 1e-7 * want.norm(),
            "column {j}: {xi1} against {want}"
        );
    }
    let tangent = |v0: f64| {
        let x = Vector2::new(0.0, v0);
        tangent_on_steps(
            &field,
            0.0,
            &x,
            &Vector2::new(1.0, 0.0),
            (period, 0.0),
            &taus,
        )
        .expect("steps")
        .1
    };
    let quotient = |d: f64| (tangent(1.0 + d) - tangent(1.0 - d)) / (2.0 * d);
    let steps = [1e-4, 1e-5, 1e-6, 1e-7];
    let q: Vec<Vector2<f64>> = steps.iter().map(|&d| quotient(d)).collect();
    for (k, w) in q.windows(2).enumerate() {
        assert!(
            (w[1] - w[0]).norm() < 1e-3 * w[0].norm(),
            "differences at {:e} and {:e}: {} and {}",
            steps[k],
            steps[k + 1],
            w[0],
            w[1]
        );
    }
}
