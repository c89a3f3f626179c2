//! Time simulation, the ramp method and the EN 14363 criterion, checked against truths that do
//! not come from the code under test: the continuation's cycles and Hopf point, the normal-form
//! law of slow passage through a Hopf point, closed-form filter and r.m.s. values, and the
//! force formulas of docs/model.md.

use std::f64::consts::{PI, SQRT_2};
use std::path::Path;
use std::sync::OnceLock;

use critspeed::bifurcation::{analyse, BifurcationOptions, BifurcationReport, CycleRow, HopfType};
use critspeed::contact::creep::CreepLaw;
use critspeed::model::{layouts::single, Vehicle};
use critspeed::reference::{cone_wheelset, SEED_CREEP, SEED_SUSPENSION, SEED_WHEELSET};
use critspeed::simulate::*;
use critspeed::study;
use critspeed::system::ode::{integrate_to_section, OdeOptions, Solution, Tolerances};
use nalgebra::SVector;

fn seed_hunting() -> Vehicle {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("studies/seed-hunting.toml");
    let plan = study::load(&path).expect("studies/seed-hunting.toml is valid");
    plan.model().expect("its contact table builds")
}

/// The continuation of seed-hunting up to 8 mm, shared by the tests of this binary.
fn branch() -> &'static BifurcationReport {
    static REPORT: OnceLock<BifurcationReport> = OnceLock::new();
    REPORT.get_or_init(|| {
        let mut opts = BifurcationOptions::new((1.0, 150.0));
        opts.max_amplitude = 0.008;
        analyse("seed-hunting", &seed_hunting(), &opts).expect("analysis runs")
    })
}

fn ode(rtol: f64) -> OdeOptions {
    OdeOptions {
        tol: Tolerances::new(rtol, rtol * 1e-3).expect("valid tolerances"),
        ..OdeOptions::default()
    }
}

/// The next maximum of y (ẏ from + to −) after `min_time`.
fn next_max(
    m: &Vehicle,
    v: f64,
    x: &SVector<f64, 4>,
    min_time: f64,
    o: &OdeOptions,
) -> Solution<4> {
    let section = |x: &SVector<f64, 4>| -x[2];
    integrate_to_section(m, v, x, 10.0, &section, min_time, o)
        .expect("integration succeeds")
        .expect("a maximum within 10 s")
}

fn cycle_near(speed: f64) -> CycleRow {
    let r = branch();
    r.cycles
        .iter()
        .min_by(|a, b| {
            (a.speed_m_s - speed)
                .abs()
                .total_cmp(&(b.speed_m_s - speed).abs())
        })
        .expect("the branch has cycles")
        .clone()
}

#[test]
fn simulation_settles_on_the_continued_cycle() {
    let m = seed_hunting();
    let row = cycle_near(75.0);
    let v = row.speed_m_s;
    let o = ode(1e-11);
    // 40 s ≈ 190 periods; the slowest nontrivial multiplier (≈ 0.88) leaves < 1e-9 of the start
    let hist = simulate(&m, v, &[0.005, 0.0, 0.0, 0.0], 40.0, 0.01, &o).expect("simulation runs");
    let last = hist.x.last().expect("samples");
    let a = next_max(&m, v, &SVector::<f64, 4>::from_column_slice(last), 1e-9, &o);
    let b = next_max(&m, v, &a.x, 0.5 * row.period_s, &o);
    let (amp, period) = (a.x[0], b.t);
    eprintln!(
        "V = {v:.6} m/s: simulation amplitude {:.10} mm period {:.10} s; continuation {:.10} mm {:.10} s; \
         rel. diff {:.1e} / {:.1e}",
        amp * 1e3,
        period,
        row.amplitude_y_m * 1e3,
        row.period_s,
        (amp / row.amplitude_y_m - 1.0).abs(),
        (period / row.period_s - 1.0).abs()
    );
    assert!(row.stable);
    assert!((amp / row.amplitude_y_m - 1.0).abs() < 1e-6);
    assert!((period / row.period_s - 1.0).abs() < 1e-6);
    assert!(
        (b.x[0] / amp - 1.0).abs() < 1e-9,
        "settled: successive maxima agree"
    );
}

#[test]
fn ramp_peaks_and_frequency_on_the_settled_cycle() {
    let m = seed_hunting();
    let row = cycle_near(75.0);
    let mut opts = RampOptions::new(row.speed_m_s, row.speed_m_s - 0.5);
    opts.settle = 40.0;
    opts.rtol = 1e-11;
    let r = ramp(&m, &opts).expect("ramp runs");
    let f0 = r
        .en14363
        .as_ref()
        .and_then(|e| e.f0_hz)
        .expect("f0 measured");
    eprintln!(
        "settled peak {:.10} mm (continuation {:.10}), f0 {:.8} Hz (1/T {:.8})",
        r.start_amplitude_m * 1e3,
        row.amplitude_y_m * 1e3,
        f0,
        1.0 / row.period_s
    );
    assert_eq!(r.quantity, RAMP_QUANTITY);
    assert!((r.start_amplitude_m / row.amplitude_y_m - 1.0).abs() < 1e-6);
    assert!(r.settle_drift_rel.abs() < 1e-6, "{}", r.settle_drift_rel);
    assert!((f0 * row.period_s - 1.0).abs() < 1e-5);
    assert!(
        matches!(r.stop, RampStop::StillHunting { .. }),
        "{:?}",
        r.stop
    );
}

#[test]
fn ramp_estimate_lags_below_the_hopf_speed_and_converges_like_sqrt_rate() {
    let m = seed_hunting();
    let report = branch();
    assert_eq!(report.hopf_type, Some(HopfType::Supercritical));
    let (v_nl, located) = report.nonlinear_critical_speed.expect("V_NL found");
    assert!(located);
    let mut opts = RampOptions::new(72.0, 40.0);
    // the quasi-static limit of the estimate: where the stable branch reaches the threshold
    let v_threshold = report
        .cycles
        .iter()
        .find(|c| c.amplitude_y_m >= opts.threshold)
        .map(|c| c.speed_m_s)
        .expect("branch passes the threshold");
    opts.rate = 5.0 / 3.6;
    let c = ramp_converged(&m, &opts, 10, 5e-3).expect("valid options");
    eprintln!("V_NL (continuation, supercritical Hopf) = {v_nl:.6} m/s; branch at threshold by {v_threshold:.6}");
    eprintln!("rate m/s²    died_at m/s  V_NL−died  change_rel  extrapolated  simulated s");
    for r in &c.rows {
        let d = r.died_at_m_s.unwrap_or(f64::NAN);
        eprintln!(
            "{:.6e}  {:.6}  {:9.6}  {:10.3e}  {:.6}  {:.0}",
            r.rate_m_s2,
            d,
            v_nl - d,
            r.change_rel.unwrap_or(f64::NAN),
            r.extrapolated_m_s.unwrap_or(f64::NAN),
            r.simulated_s
        );
    }
    eprintln!("stop {:?}, converged {:?}", c.stop, c.converged);
    assert_eq!(c.stop, ConvergenceStop::Converged);
    let died: Vec<f64> = c
        .rows
        .iter()
        .map(|r| r.died_at_m_s.expect("hunting died"))
        .collect();
    assert!(died.len() >= 6);
    for (k, d) in died.iter().enumerate() {
        // the lag keeps the hunting alive below V_NL; even the r → 0 limit is below v_threshold
        assert!(*d < v_nl && *d < v_threshold, "row {k}: {d}");
    }
    // slow passage through a Hopf point: lag ∝ √(rate · ln(a/threshold)), ratio ≈ 1/√2 per
    // halving (a little less from the logarithm)
    let gaps: Vec<f64> = died.iter().map(|d| v_nl - d).collect();
    for w in gaps.windows(2) {
        let ratio = w[1] / w[0];
        assert!((0.6..0.78).contains(&ratio), "gap ratio {ratio}");
    }
    let extrapolated = c
        .rows
        .last()
        .and_then(|r| r.extrapolated_m_s)
        .expect("two rows");
    assert!(
        (extrapolated - v_nl).abs() < 0.15,
        "extrapolated {extrapolated}"
    );
    // The bracket the ramp gives: its estimate from below, the √rate extrapolation (which the
    // logarithmic factor makes overshoot) from above. V_NL from the continuation lies inside
    // it for each of the last rows.
    for r in c.rows.iter().skip(3) {
        let (lo, hi) = (
            r.died_at_m_s.expect("hunting died"),
            r.extrapolated_m_s.expect("two rows"),
        );
        assert!(lo < v_nl && v_nl < hi, "V_NL {v_nl} outside [{lo}, {hi}]");
    }
}

#[test]
fn seed_hunting_never_reaches_the_en14363_limit() {
    let m = seed_hunting();
    let r = ramp(&m, &RampOptions::new(75.0, 40.0)).expect("ramp runs");
    let e = r.en14363.as_ref().expect("hunting at the start");
    eprintln!(
        "GENSYS rate: died at {:?} m/s; EN 14363: f0 {:?} Hz, max rms {:.1} N, limit {:.1} N, {:?}",
        r.died_at_m_s, e.f0_hz, e.max_rms_n, e.limit_n, e.verdict
    );
    assert_eq!(e.verdict, En14363Verdict::NeverExceeded);
    assert!(e.max_rms_n > 0.0 && e.max_rms_n < e.limit_n);
    assert_eq!(r.en14363_speed_m_s, None);
    // EN 14363's Q0 is the static wheel load, W/2 = 55 kN
    assert!((e.limit_n - en14363_limit(55e3)).abs() < 1e-9);
}

/// The filtered ΣY on the settled cycle: its r.m.s. is the fundamental's amplitude / √2 (the
/// filter passes f0 with gain ≈ 1 and removes the odd harmonics), up to the ripple of a window
/// that holds a non-integer number of periods.
#[test]
fn en14363_rms_on_the_cycle_is_the_fundamental() {
    let m = seed_hunting();
    let row = cycle_near(75.0);
    let v = row.speed_m_s;
    let o = ode(1e-10);
    let hist = simulate(&m, v, &[0.005, 0.0, 0.0, 0.0], 40.0, 0.01, &o).expect("simulation runs");
    let start = next_max(
        &m,
        v,
        &SVector::<f64, 4>::from_column_slice(hist.x.last().expect("samples")),
        1e-9,
        &o,
    );
    let n = 512;
    let one = simulate(
        &m,
        v,
        start.x.as_slice(),
        row.period_s,
        row.period_s / n as f64,
        &o,
    )
    .expect("runs");
    let (mut re, mut im) = (0.0, 0.0);
    for (k, x) in one.x.iter().take(n).enumerate() {
        let sy = sum_of_guiding_forces(&m, x, v);
        let phase = 2.0 * PI * k as f64 / n as f64;
        (re, im) = (re + sy * phase.cos(), im - sy * phase.sin());
    }
    let fundamental = 2.0 * re.hypot(im) / n as f64;
    let mut opts = RampOptions::new(v, v - 0.5);
    opts.settle = 40.0;
    let r = ramp(&m, &opts).expect("ramp runs");
    let e = r.en14363.as_ref().expect("evaluated");
    let settled: Vec<f64> = e
        .series
        .iter()
        .filter(|p| p.t_s > 20.0 && p.t_s <= 40.0)
        .map(|p| p.rms_n)
        .collect();
    let mean = settled.iter().sum::<f64>() / settled.len() as f64;
    let expected = fundamental / SQRT_2;
    eprintln!("ΣY fundamental {fundamental:.1} N: expected rms {expected:.1} N, sliding rms mean {mean:.1} N over {} reports", settled.len());
    assert!(settled.len() > 20);
    assert!((mean / expected - 1.0).abs() < 0.01);
    for s in &settled {
        assert!((s / expected - 1.0).abs() < 0.03, "{s}");
    }
}

#[test]
fn sum_of_guiding_forces_is_creep_plus_gravitational_force_on_the_cone() {
    // Kalker creep without spin on the closed-form cone (docs/model.md §3–5):
    // ΣY = −2 f22 (ẏ/V − ψ) − (W/2)(tan(λ + φ) − tan(λ − φ)), φ = λy/l0
    let lambda = 0.05;
    let m = single(
        cone_wheelset(
            SEED_WHEELSET,
            SEED_SUSPENSION,
            SEED_CREEP,
            lambda,
            CreepLaw::Kalker,
            false,
        )
        .expect("table builds"),
    )
    .expect("assembles");
    let p = SEED_WHEELSET;
    for (x, v) in [
        ([0.0, 0.0, 0.0, 0.0], 50.0),
        ([0.003, 0.001, -0.05, 0.02], 40.0),
        ([-0.006, -0.002, 0.1, -0.03], 80.0),
    ] {
        let phi = lambda * x[0] / p.half_contact_distance;
        let gravity = -(p.axle_load / 2.0) * ((lambda + phi).tan() - (lambda - phi).tan());
        let creep = -2.0 * SEED_CREEP.f22 * (x[2] / v - x[1]);
        let expected = creep + gravity;
        let got = sum_of_guiding_forces(&m, &x, v);
        assert!(
            (got - expected).abs() <= 1e-6 * expected.abs().max(1.0),
            "{got} vs {expected}"
        );
    }
}

/// Steady-state gain of the filter on a sine of frequency `f` (Hz), measured by filtering.
fn measured_gain(bp: &mut BandPass, f: f64, fs: f64) -> f64 {
    let n = (30.0 * fs) as usize;
    let out = bp.filter(
        &(0..n)
            .map(|k| (2.0 * PI * f * k as f64 / fs).sin())
            .collect::<Vec<_>>(),
    );
    out[n * 2 / 3..].iter().fold(0.0_f64, |a, v| a.max(v.abs()))
}

#[test]
fn en14363_band_pass_passes_f0_and_rejects_six_hertz_away() {
    let fs = 500.0;
    for f0 in [4.74, 8.0, 10.0] {
        let bp = BandPass::en14363(f0, fs).expect("valid band");
        let g0 = measured_gain(&mut bp.clone(), f0, fs);
        assert!((g0 - 1.0).abs() < 0.01, "f0 {f0}: gain {g0}");
        for f in [f0 - 6.0, f0 + 6.0].into_iter().filter(|f| *f > 0.0) {
            let g = measured_gain(&mut bp.clone(), f, fs);
            eprintln!("f0 {f0} Hz: gain {g0:.5} at f0, {g:.5} at {f} Hz");
            assert!(g < 0.1, "f0 {f0}, f {f}: gain {g}");
        }
        // the frequency response is the analog Butterworth magnitude at the pre-warped
        // frequency, −3 dB at the band edges
        let warp = |f: f64| 2.0 * fs * (PI * f / fs).tan();
        let (w1, w2) = (warp(f0 - 2.0), warp(f0 + 2.0));
        for f in [1.0, f0 - 2.0, f0, f0 + 2.0, f0 + 6.0, 40.0] {
            let w = warp(f);
            let x = (w * w - w1 * w2) / ((w2 - w1) * w);
            let exact = 1.0 / (1.0 + x.powi(8)).sqrt();
            assert!(
                (bp.gain(f, fs) - exact).abs() < 1e-9,
                "f {f}: {} vs {exact}",
                bp.gain(f, fs)
            );
        }
        assert!((bp.gain(f0 + 2.0, fs) - 0.5_f64.sqrt()).abs() < 1e-9);
    }
}

#[test]
fn sliding_rms_of_a_unit_sine_is_one_over_root_two() {
    // 100 m at 64 m/s = 1.5625 s = 8 periods of 5.12 Hz at 1024 samples per second: every
    // track position k/16 m is exact, so each window holds exactly 1600 samples
    let (v, f, fs) = (64.0, 5.12, 1024.0);
    let mut w = SlidingRms::new(100.0, 10.0).expect("valid window");
    let mut reports = Vec::new();
    for k in 0..20_000 {
        let t = k as f64 / fs;
        if let Some(r) = w.push(v * t, (2.0 * PI * f * t).sin()) {
            reports.push(r);
        }
    }
    assert!(reports.len() > 50);
    for r in &reports {
        assert!((r - 1.0 / SQRT_2).abs() < 1e-9, "{r}");
    }
    // a window holding 8.24 periods: r.m.s. within the ripple bound 1/(4π·8.24) of 1/√2
    let mut w = SlidingRms::new(103.0, 10.0).expect("valid window");
    for k in 0..20_000 {
        let t = k as f64 / fs;
        if let Some(r) = w.push(v * t, (2.0 * PI * f * t).sin()) {
            assert!((r * SQRT_2 - 1.0).abs() < 1.0 / (4.0 * PI * 8.24), "{r}");
        }
    }
}

#[test]
fn en14363_limit_for_a_55_kn_wheel() {
    // (10 + 2·55/3)/2 kN = 23.333 kN
    assert!((en14363_limit(55e3) - 23_333.333_333).abs() < 1e-3);
}

#[test]
fn en14363_verdict_interpolates_the_last_downward_crossing() {
    let point = |speed_m_s: f64, rms_n: f64| RmsPoint {
        t_s: 0.0,
        speed_m_s,
        rms_n,
    };
    // rms = 1000 (V − 60) N falls through 5000 N at V = 65 m/s, after an earlier dip
    let series: Vec<RmsPoint> = [75.0, 74.0, 71.0, 70.0, 69.0, 66.5, 64.5, 63.0]
        .iter()
        .map(|&v| {
            point(
                v,
                if v == 71.0 {
                    4000.0
                } else {
                    1000.0 * (v - 60.0)
                },
            )
        })
        .collect();
    match en14363_verdict(&series, 5000.0) {
        En14363Verdict::DroppedBelow { speed_m_s } => assert!((speed_m_s - 65.0).abs() < 1e-12),
        v => panic!("{v:?}"),
    }
    assert_eq!(en14363_verdict(&series, 1e5), En14363Verdict::NeverExceeded);
    assert_eq!(en14363_verdict(&series, 100.0), En14363Verdict::StillAbove);
}

#[test]
fn died_at_is_exact_for_an_exponential_envelope() {
    // a_k = 5 mm · e^{−0.1k} at V_k = 75 − 0.07k: below 0.1 mm at k* = 10 ln 50
    let env: Vec<EnvelopePoint> = (0..100)
        .map(|k| EnvelopePoint {
            t_s: 0.1 * k as f64,
            speed_m_s: 75.0 - 0.07 * k as f64,
            amplitude_m: 5e-3 * (-0.1 * k as f64).exp(),
        })
        .collect();
    let (v, stop) = died_at(&env, 1e-4);
    let expected = 75.0 - 0.07 * 10.0 * 50.0_f64.ln();
    assert_eq!(stop, RampStop::Died);
    assert!((v.expect("died") - expected).abs() < 1e-9);
    let (v, stop) = died_at(&env, 1e-9);
    assert_eq!(v, None);
    assert!(matches!(stop, RampStop::StillHunting { .. }));
}

#[test]
fn ramp_below_the_hopf_speed_finds_no_settled_hunting() {
    let m = seed_hunting();
    let r = ramp(&m, &RampOptions::new(60.0, 50.0)).expect("ramp runs");
    assert_eq!(r.died_at_m_s, None);
    assert!(
        matches!(r.stop, RampStop::NotHuntingAtStart { .. }),
        "{:?}",
        r.stop
    );
    assert!(r.en14363.is_none());
    // just below V_H the decay is slow: still above the threshold after the settle phase, but
    // the drift shows that the motion was dying, not settled on a cycle
    let r = ramp(&m, &RampOptions::new(70.0, 50.0)).expect("ramp runs");
    eprintln!(
        "start 70 m/s: peak {:.3e} m, drift {:.3}",
        r.start_amplitude_m, r.settle_drift_rel
    );
    assert!(r.start_amplitude_m > r.options.threshold);
    assert!(r.settle_drift_rel < -0.05, "{}", r.settle_drift_rel);
}

#[test]
fn bad_options_name_the_field() {
    let m = seed_hunting();
    let good = RampOptions::new(75.0, 40.0);
    assert_eq!(good.validate(), Ok(()));
    type Spoil = fn(&mut RampOptions);
    let cases: [(&str, Spoil); 9] = [
        ("start_speed", |o| o.start_speed = -1.0),
        ("end_speed", |o| o.end_speed = 80.0),
        ("end_speed", |o| o.end_speed = 0.0),
        ("rate", |o| o.rate = 0.0),
        ("y0", |o| o.y0 = 0.0),
        ("settle", |o| o.settle = f64::NAN),
        ("threshold", |o| o.threshold = -1e-4),
        ("rtol", |o| o.rtol = 1e-20),
        ("rate", |o| o.rate = f64::INFINITY),
    ];
    for (field, spoil) in cases {
        let mut o = good;
        spoil(&mut o);
        let err = ramp(&m, &o).expect_err("rejected");
        assert!(
            matches!(err, RampError::BadOption { field: f, .. } if f == field),
            "{err}"
        );
        assert!(err.to_string().contains(field), "{err}");
    }
    let err = ramp_converged(&m, &good, 3, 0.0).expect_err("rejected");
    assert!(err.to_string().contains("rel_tol"), "{err}");
    for (res, field) in [
        (BandPass::en14363(1.5, 500.0), "f0"),
        (BandPass::butterworth(4, 6.0, 300.0, 500.0), "f_high"),
        (BandPass::butterworth(0, 3.0, 7.0, 500.0), "order"),
        (BandPass::butterworth(4, 3.0, 7.0, -1.0), "sample rate"),
    ] {
        let err = res.expect_err("rejected");
        assert!(err.to_string().contains(field), "{err}");
    }
    for (res, field) in [
        (SlidingRms::new(0.0, 10.0), "window_m"),
        (SlidingRms::new(100.0, 0.0), "step_m"),
    ] {
        let err = res.expect_err("rejected");
        assert!(err.to_string().contains(field), "{err}");
    }
}

/// The printed verdict is the trend at the run's end, not the change since the start: on
/// seed-hunting at 100 m/s, above its V_NL, starts at 30 mm and at 10 mm end on the same
/// amplitude (to 1e-3: an attracting cycle between them, about 19 mm), the first shrinking onto
/// it (`sustained (hunting)`, where the last 10 % against the first gave `decays`), the second
/// growing onto it; at 50 m/s, below V_L, the motion dies to round-off (`decays (to rest)`,
/// whose last tenths of 1e-13 m no longer read as growth).
#[test]
fn the_simulation_verdict_is_the_trend_at_the_end() {
    let dir = std::env::temp_dir().join(format!("critspeed-verdict-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("scratch folder");
    let study = format!("{}/studies/seed-hunting.toml", env!("CARGO_MANIFEST_DIR"));
    // (the last tenth's amplitude in mm, the verdict)
    let run = |speed: &str, y0: &str| -> (f64, String) {
        let out = std::process::Command::new(env!("CARGO_BIN_EXE_critspeed"))
            .args(["simulate", &study, "--speed", speed, "--y0", y0, "--out"])
            .arg(&dir)
            .output()
            .expect("runs");
        assert_eq!(out.status.code(), Some(0), "{out:?}");
        let text = String::from_utf8_lossy(&out.stdout).into_owned();
        let line = text
            .lines()
            .find(|l| l.contains("last 10 %"))
            .expect("a verdict line");
        let (head, verdict) = line.rsplit_once(" mm: ").expect("amplitude and verdict");
        let last = head
            .rsplit("last 10 %")
            .next()
            .and_then(|v| v.trim().parse().ok())
            .expect("the last tenth's amplitude");
        (last, verdict.to_string())
    };
    let (above, verdict) = run("100", "30 mm");
    assert_eq!(verdict, "sustained (hunting)");
    let (below, verdict) = run("100", "10 mm");
    assert_eq!(verdict, "sustained (hunting)");
    assert!(
        (above - below).abs() <= 1e-3 * below && below > 10.0 && above < 30.0,
        "{above} mm vs {below} mm"
    );
    assert_eq!(run("50", "10 mm").1, "decays (to rest)");
}

/// `SimulateRequest::rtol` (`critspeed simulate --rtol`): the time history converges as the
/// tolerance tightens. seed-hunting from 5 mm at 75 m/s (it hunts there) for 3 s, against the
/// same run at rtol 1e-12: the largest deviation of y shrinks at each hundredfold tightening,
/// by at least a factor 10, and at the default (1e-9) lies below 1e-6 of the amplitude; the
/// default is exactly `rtol = 1e-9`. Outside [1e-12, 1e-4] the request is refused.
#[test]
fn simulate_rtol_converges_and_is_checked() {
    use critspeed::api::{self, Failure, Prepared, SimulateRequest};
    let plan =
        study::load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("studies/seed-hunting.toml"))
            .expect("studies/seed-hunting.toml is valid");
    let p = Prepared::new(plan).expect("model");
    let request = |rtol: Option<f64>| SimulateRequest {
        speeds: vec![75.0],
        y0: 5e-3,
        duration: 3.0,
        dt: 2e-3,
        from: None,
        kicks: vec![],
        rtol,
    };
    let run = |rtol: Option<f64>| -> Vec<f64> {
        let h = api::simulate(&p, &request(rtol), &|_| {}, None).expect("simulation");
        h[0].x.iter().map(|x| x[0]).collect()
    };
    let reference = run(Some(1e-12));
    let amplitude = reference.iter().fold(0.0_f64, |a, y| a.max(y.abs()));
    let error = |rtol: Option<f64>| {
        let y = run(rtol);
        assert_eq!(y.len(), reference.len());
        y.iter()
            .zip(&reference)
            .fold(0.0_f64, |a, (u, v)| a.max((u - v).abs()))
    };
    let errors: Vec<f64> = [1e-5, 1e-7, 1e-9].iter().map(|&r| error(Some(r))).collect();
    eprintln!("max deviation of y from rtol 1e-12 at rtol 1e-5, 1e-7, 1e-9: {errors:?} m (amplitude {amplitude} m)");
    for w in errors.windows(2) {
        assert!(w[1] < 0.1 * w[0], "errors {errors:?} m");
    }
    assert!(
        errors[2] < 1e-6 * amplitude,
        "errors {errors:?} m, amplitude {amplitude} m"
    );
    assert_eq!(run(None), run(Some(1e-9)), "the default is 1e-9");
    for bad in [0.0, 1e-13, 1e-3, f64::NAN, -1e-8] {
        match request(Some(bad)).validate() {
            Err(Failure::User(e)) => {
                let msg = format!("{e:#}");
                assert!(
                    msg.contains("rtol") && msg.contains("[1e-12, 1e-4]"),
                    "{msg}"
                );
            }
            other => panic!("rtol {bad}: {other:?}"),
        }
    }
}
