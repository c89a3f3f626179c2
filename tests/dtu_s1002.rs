//! The DTU Cooperrider bogie and car on S1002 / UIC60 1:40 by the profile contact solve
//! (`studies/dtu-cooperrider-{bogie,car}-s1002.toml`): they load, their linear critical speeds
//! are eigenpairs on the imaginary axis, the vehicle is odd-symmetric, and the contact moves
//! onto the flange beyond the flange clearance given by the profiles' standard dimensions.

use critspeed::analysis;
use critspeed::contact::creep::CreepLaw;
use critspeed::stability::{spectrum_at, LinearSystem};
use critspeed::study;

mod common;
use common::root;

fn load(name: &str) -> study::Plan {
    study::load(&root().join("studies").join(name)).expect("study loads")
}

/// Each Kalker crossing of the linear solve: J v = λ v at the crossing speed to 1e-12 of ‖J‖
/// and Re λ ≈ 0 (to 1e-7 of the frequency).
#[test]
fn linear_critical_speeds_are_eigenpairs_on_the_axis() {
    for (name, states) in [
        ("dtu-cooperrider-bogie-s1002.toml", 12),
        ("dtu-cooperrider-car-s1002.toml", 28),
    ] {
        let plan = load(name);
        let model = plan.model().expect("model");
        assert_eq!(model.states(), states, "{name}");
        let r = analysis::linear(&plan, &model).expect("linear");
        assert!(!r.kalker.crossings.is_empty(), "{name}: no V_L in range");
        let kalker = model.with_law(CreepLaw::Kalker);
        for c in &r.kalker.crossings {
            let omega = 2.0 * std::f64::consts::PI * c.frequency_hz;
            let res = critspeed::with_states!(states, N => {
                let jm = LinearSystem::<N>::at_centre(&kalker).jacobian(c.speed_m_s);
                let sp = spectrum_at(&jm, c.speed_m_s).expect("spectrum");
                let p = sp
                    .pairs
                    .iter()
                    .min_by(|a, b| a.re.hypot(a.im - omega).total_cmp(&b.re.hypot(b.im - omega)))
                    .expect("a pair");
                let norm = jm.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
                let mut worst = 0.0_f64;
                for i in 0..N {
                    let (mut re, mut im) = (0.0, 0.0);
                    for k in 0..N {
                        re += jm[(i, k)] * p.vector[k].0;
                        im += jm[(i, k)] * p.vector[k].1;
                    }
                    re -= p.re * p.vector[i].0 - p.im * p.vector[i].1;
                    im -= p.re * p.vector[i].1 + p.im * p.vector[i].0;
                    worst = worst.max(re.hypot(im));
                }
                (worst / norm, p.re, p.im)
            }, _ => panic!("{states} states"));
            eprintln!(
                "{name}: V_L {:.6} m/s ({:?}), {:.4} Hz: residual {:.1e}, Re λ {:.1e}",
                c.speed_m_s, c.direction, c.frequency_hz, res.0, res.1
            );
            assert!(res.0 < 1e-12, "{name}: residual {}", res.0);
            assert!(res.1.abs() < 1e-7 * res.2, "{name}: Re λ = {}", res.1);
        }
    }
}

/// Track symmetry (docs/model.md §3): the table's nodes are symmetric about y = 0 and the left
/// wheel is the right one at −y, so the wheelset's field is odd, f(−x) = −f(x), also on the
/// flange.
#[test]
fn the_geometry_table_is_symmetric() {
    let plan = load("dtu-cooperrider-bogie-s1002.toml");
    let wheelset = plan.wheelset_model().expect("model");
    let rows = wheelset.table.rows();
    let n = rows.len();
    for k in 0..n {
        assert!((rows[k].y + rows[n - 1 - k].y).abs() < 1e-15, "node {k}");
    }
    for x in [
        [1e-3, 2e-4, 0.01, -0.003],
        [-5.5e-3, -1e-3, 0.2, 0.01],
        [7e-3, 1e-4, -0.1, 0.02],
        [-1.1e-2, 0.0, 0.3, -0.05],
    ] {
        let f = wheelset.rhs(&x, 40.0);
        let g = wheelset.rhs(&x.map(|v| -v), 40.0);
        for k in 0..4 {
            assert!(
                (f[k] + g[k]).abs() <= 1e-12 * f[k].abs().max(1e-9),
                "{x:?}: {f:?} vs {g:?}"
            );
        }
    }
}

/// S1002's flange thickness is 32.5 mm at 10 mm below the running circle (EN 13715), so with
/// the taping line 70 mm from the flange back the flange face lies 37.5 mm inboard of the taping
/// line there; on 1435 mm gauge with 1360 mm flange-back spacing the wheelset's front-to-front
/// width is 1425 mm: a nominal flange clearance of 5 mm per side. The rigid solve must keep the
/// right wheel's contact off the flange up to that clearance and put it on the flange face
/// (30 to 50 mm inboard of the taping line, r_R at least 10 mm above r0: the flange is 28 mm
/// high) from 1.5 mm beyond it to the table's end at 12 mm.
#[test]
fn the_contact_is_on_the_flange_beyond_the_flange_clearance() {
    let plan = load("dtu-cooperrider-bogie-s1002.toml");
    let file = std::fs::read_to_string(root().join("studies/profiles/s1002.csv")).expect("file");
    // the profile file itself: the flange face at 10 mm depth, 37.5 mm from the taping line
    let face = file
        .lines()
        .filter_map(|l| {
            let mut it = l.split(',').map(|s| s.trim().parse::<f64>());
            Some((it.next()?.ok()?, it.next()?.ok()?))
        })
        .filter(|&(y, z)| y > 20.0 && (z - 10.0).abs() < 0.5)
        .map(|(y, _)| y)
        .fold(f64::NAN, f64::max);
    assert!((face - 37.5).abs() < 0.3, "flange face at {face} mm");
    let model = plan.wheelset_model().expect("model");
    let r0 = plan.wheelset.rolling_radius;
    let clearance = 0.5 * (1.435 - (1.360 + 2.0 * 0.0325));
    for row in model.table.rows() {
        let (y, u, r) = (row.y, row.point.wheel_offset, row.point.radius);
        if y.abs() <= clearance {
            assert!(u > -0.030, "y = {y}: contact at {u} m, on the flange");
        } else if y > clearance + 1.5e-3 {
            assert!(
                (-0.050..=-0.030).contains(&u) && r > r0 + 0.010,
                "y = {y}: contact at {u} m, r {r} m: not on the flange"
            );
        }
    }
}
