//! VALIDATION.md, section 2 (continued): the knife-edge cone limits of docs/model.md §8 and the
//! kinematic (Klingel) wavelength of docs/model.md §9.

use std::fmt::Write as _;

use critspeed::contact::creep::CreepLaw;
use critspeed::model::Suspension;
use critspeed::reference::{
    cone_wheelset, small_angle_matrices, SEED_CREEP, SEED_SUSPENSION, SEED_WHEELSET,
};
use critspeed::stability::{spectrum_at, LinearSystem};
use nalgebra::{Matrix2, Matrix4, Vector4};

/// The first-order system matrix of M q̈ + C q̇ + K q = 0.
fn first_order(m: &Matrix2<f64>, c: &Matrix2<f64>, k: &Matrix2<f64>) -> Matrix4<f64> {
    let minv = m.try_inverse().expect("M is diagonal and positive");
    let (a, b) = (-minv * k, -minv * c);
    let mut j = Matrix4::zeros();
    j[(0, 2)] = 1.0;
    j[(1, 3)] = 1.0;
    j.fixed_view_mut::<2, 2>(2, 0).copy_from(&a);
    j.fixed_view_mut::<2, 2>(2, 2).copy_from(&b);
    j
}

/// docs/model.md §8: the exact Jacobian of the cone on knife-edge rails against the small-angle
/// matrices; the difference is O(λ²) relative to the λ-proportional entries, so halving λ
/// divides it (relative to the whole matrix) by about eight.
pub fn knife_edge_section(s: &mut String) {
    let _ = writeln!(s, "Cone on knife-edge rails (seed wheelset and creep coefficients, spin on, V = 50 m/s): the exact Jacobian at the centre against docs/model.md §8's small-angle matrices M, C, K. The difference comes only from cos δ, tan δ and sin δ, so it must vanish like λ³ relative to the whole matrix (λ² relative to the λ-proportional entries):\n");
    let _ = writeln!(
        s,
        "| λ | max abs(J_exact − J_small-angle) / max abs(J_exact) | ratio to the previous λ |\n|---|---|---|"
    );
    let mut prev: Option<f64> = None;
    for lambda in [0.04, 0.02, 0.01] {
        let w = cone_wheelset(
            SEED_WHEELSET,
            SEED_SUSPENSION,
            SEED_CREEP,
            lambda,
            CreepLaw::Kalker,
            true,
        )
        .expect("cone");
        let v = 50.0;
        let (m, c, k) = small_angle_matrices(&w, &SEED_CREEP, lambda, v);
        let (exact, _) = w.jacobian(&Vector4::zeros(), v);
        let err = (exact - first_order(&m, &c, &k)).amax() / exact.amax();
        assert!(err < 10.0 * lambda * lambda, "λ={lambda}: {err}");
        let ratio = prev.map(|p| p / err);
        if let Some(r) = ratio {
            assert!((3.9..8.5).contains(&r), "ratio {r}");
        }
        let shown = ratio.map_or("–".to_string(), |r| format!("{r:.2}"));
        let _ = writeln!(s, "| {lambda} | {err:.2e} | {shown} |");
        prev = Some(err);
    }
    let _ = writeln!(s);
}

/// docs/model.md §9: with rigid creep (f11 = f22 = 1e13 N) and no suspension, gravity or spin, the
/// hunting wavelength V/f of the kinematic mode is Klingel's 2π√(r0 l0/λ).
pub fn klingel_section(s: &mut String) {
    let _ = writeln!(s, "Kinematic (Klingel) wavelength: cone on knife-edge rails, rigid creep (f11 = f22 = 1e13 N), no suspension, no gravitational stiffness, no spin. The slow oscillatory eigenvalue pair's wavelength V/f against 2π√(r0 l0/λ):\n");
    let _ = writeln!(
        s,
        "| λ | V (m/s) | V/f (m) | 2π√(r0 l0/λ) (m) | relative difference |\n|---|---|---|---|---|"
    );
    let free = Suspension {
        lateral_stiffness: 0.0,
        longitudinal_stiffness: 0.0,
        lateral_damping: 0.0,
        longitudinal_damping: 0.0,
        half_spring_spacing: SEED_SUSPENSION.half_spring_spacing,
    };
    let mut p = SEED_WHEELSET;
    p.axle_load = 0.0;
    let mut rigid = SEED_CREEP;
    rigid.f11 = 1e13;
    rigid.f22 = 1e13;
    for lambda in [0.05, 0.15] {
        let w = cone_wheelset(p, free, rigid, lambda, CreepLaw::Kalker, false).expect("cone");
        let sys = LinearSystem::at_centre(&w);
        let closed = 2.0
            * std::f64::consts::PI
            * (p.rolling_radius * p.half_contact_distance / lambda).sqrt();
        for v in [10.0, 30.0] {
            let sp = spectrum_at(&sys.jacobian(v), v).expect("eigenvalues");
            let f = sp
                .pairs
                .iter()
                .filter(|e| e.im > 0.0)
                .map(|e| e.frequency_hz())
                .fold(f64::INFINITY, f64::min);
            let rel = ((v / f - closed) / closed).abs();
            assert!(rel < 1e-4, "λ={lambda} V={v}: {rel}");
            let _ = writeln!(
                s,
                "| {lambda} | {v} | {:.4} | {closed:.4} | {rel:.1e} |",
                v / f
            );
        }
    }
    let _ = writeln!(s);
}
