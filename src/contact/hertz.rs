//! The Hertz elliptic contact patch (docs/model.md §4), generic over [`Scalar`] so that exact
//! derivatives of the semi-axes propagate into the creep coefficients and the Jacobian.
//!
//! Two identical steel bodies (Young's modulus E in Pa, Poisson ratio ν) touch with normal
//! force N (N). The relative curvatures (1/m) are $A = 1/r_\text{wheel}$ in the rolling
//! direction and $B = 1/R_\text{rail} + 1/R_\text{wheel,transverse}$ laterally (a cone is
//! straight transversally: 0). With the eccentricity e and, for B > A, the major semi-axis a
//! along the rolling direction and $b = a\sqrt{1-e^2}$:
//!
//! * $B/A = \dfrac{E(e)/(1-e^2) - K(e)}{K(e) - E(e)}$
//! * $a^3 = 3 N (K(e) - E(e)) (1-ν^2) / (π e^2 E\,A/2)$
//!
//! For A > B the roles swap (b is the major axis, $a = b\sqrt{1-e^2}$, A ↔ B in both).
//!
//! Internally everything is written in the axis ratio $g = \text{minor}/\text{major} =
//! \sqrt{1-e^2}$ (the complementary modulus k') and $D = (K - E)/e^2$. Since
//! $E/(1-e^2) - K = e^2 (K - D)/g^2$ and $K - E = e^2 D$, the two formulas become
//! $B/A = (K - D)/(D g^2)$ and $a^3 = 6 N D (1-ν^2)/(π E A)$: no 0/0 at either end, and the
//! circle A = B (g = 1, e = 0) is an ordinary point. There D = π/4, so
//! $a^3 = 3N(1-ν^2)/(2EA) = 3 N R/(4E^*)$ with $R = 1/A = 2/(A+B)$ and
//! $E^* = E/(2(1-ν^2))$: Hertz's sphere, reached continuously (tested).
//!
//! Derivatives: the ratio equation is solved for g in `f64`; then ONE Newton step is taken
//! in the generic type at the converged root, $g_T = g^* + (ρ_T - ρ(g^*))/ρ'(g^*)$ with ρ'
//! exact from `Dual<1>`. Its value is g* (to rounding) and, by the implicit function
//! theorem, its derivative part is exactly $dg = dρ/ρ'(g^*)$: no derivative ever flows
//! through the iteration, and the iteration count cannot affect the derivatives.

use crate::system::scalar::{Dual, Scalar};
use std::f64::consts::PI;
use std::fmt;

/// Semi-axes of the Hertz contact ellipse (m): `a` in the rolling direction, `b` lateral.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HertzPatch<T> {
    /// semi-axis along the rolling direction (m)
    pub a: T,
    /// semi-axis along the lateral direction (m)
    pub b: T,
}

/// Why no Hertz patch could be computed. Every variant carries the offending values.
#[derive(Debug, Clone, PartialEq)]
pub enum HertzError {
    /// The normal force (N) is not a finite positive number.
    NonPositiveLoad { normal_force: f64 },
    /// A relative curvature (1/m) is not a finite positive number.
    NonPositiveCurvature { rolling: f64, lateral: f64 },
    /// E (Pa) is not finite positive, or ν is outside (−1, 0.5].
    InvalidMaterial {
        young_modulus: f64,
        poisson_ratio: f64,
    },
    /// The curvature ratio max(A,B)/min(A,B) could not be inverted for the eccentricity.
    NoConvergence { ratio: f64 },
    /// The semi-axes (m) overflowed or underflowed.
    NonFiniteSemiAxes { a: f64, b: f64 },
}

impl fmt::Display for HertzError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::NonPositiveLoad { normal_force } => {
                write!(f, "normal force {normal_force:e} N is not finite positive")
            }
            Self::NonPositiveCurvature { rolling, lateral } => write!(
                f,
                "relative curvatures A = {rolling:e} 1/m, B = {lateral:e} 1/m must be finite positive"
            ),
            Self::InvalidMaterial { young_modulus, poisson_ratio } => write!(
                f,
                "invalid material: E = {young_modulus:e} Pa, nu = {poisson_ratio} (need E > 0, -1 < nu <= 0.5)"
            ),
            Self::NoConvergence { ratio } => {
                write!(f, "no eccentricity found for curvature ratio {ratio:e}")
            }
            Self::NonFiniteSemiAxes { a, b } => {
                write!(f, "semi-axes a = {a:e} m, b = {b:e} m are not finite positive")
            }
        }
    }
}

impl std::error::Error for HertzError {}

/// AGM iteration cap: convergence is quadratic, ~6 steps for g ≥ 1e-3, ~10 for g ~ 1e-100.
const MAX_AGM: usize = 64;

/// K, E and D = (K − E)/m of the parameter m = k² = 1 − g², from g = k' ∈ (0, 1] and m.
///
/// AGM (Abramowitz & Stegun 17.6): a₀ = 1, b₀ = k', c₀ = k, a_{n+1} = (a+b)/2,
/// b_{n+1} = √(ab), c_{n+1} = c_n²/(4a_{n+1}) (the stable form of (a−b)/2);
/// K = π/(2a_∞), E = K (1 − Σ 2^{n−1} c_n²). Carrying q_n = c_n²/m, i.e.
/// q_{n+1} = m q_n²/(16 a_{n+1}²), gives D = K Σ 2^{n−1} q_n without dividing by m.
fn agm_kd<T: Scalar>(g: T, m: T) -> (T, T, T) {
    let (mut a, mut b) = (T::cst(1.0), g);
    let (mut q, mut s, mut w) = (T::cst(1.0), T::cst(0.5), 0.5);
    let mut extra = 1; // one more step after the value converged, for the derivative parts
    for _ in 0..MAX_AGM {
        let a_next = (a + b) * 0.5;
        b = (a * b).sqrt();
        a = a_next;
        q = m * q * q / (a * a * 16.0);
        w *= 2.0;
        s = s + q * w;
        if (a.re() - b.re()).abs() <= 4e-16 * a.re() && q.re() * w <= 1e-17 * s.re() {
            if extra == 0 {
                break;
            }
            extra -= 1;
        }
    }
    let k = a.recip() * (PI / 2.0);
    let d = k * s;
    (k, k - m * d, d)
}

/// Complete elliptic integrals (K(e), E(e)) of the first and second kind, modulus k = e
/// (parameter m = e²), by the AGM. Exact derivatives propagate through the arithmetic.
/// K(±1) = ∞, E(±1) = 1 (returned as constants); |e| > 1 or NaN gives NaN.
pub fn complete_elliptic<T: Scalar>(e: T) -> (T, T) {
    let m = e * e;
    let mr = m.re();
    if mr.is_nan() || mr > 1.0 {
        return (T::cst(f64::NAN), T::cst(f64::NAN));
    }
    if mr < 1.0 {
        let (k, ee, _) = agm_kd((T::cst(1.0) - m).sqrt(), m);
        return (k, ee);
    }
    (T::cst(f64::INFINITY), T::cst(1.0)) // |e| = 1
}

/// The curvature ratio ρ(g) = max(A,B)/min(A,B) = (K − D)/(D g²) and D, at axis ratio g.
fn ratio_of<T: Scalar>(g: T) -> (T, T) {
    let m = (T::cst(1.0) - g) * (g + 1.0); // 1 − g², accurate as g → 1
    let (k, _, d) = agm_kd(g, m);
    ((k - d) / (d * g * g), d)
}

/// Solve ρ(g) = rho ≥ 1 for g ∈ (0, 1] in f64: safeguarded Newton in u = ln g, where
/// ln ρ is nearly linear (slope → −2 as g → 0). ρ is decreasing in g and ρ(g) ≤ 1/g²
/// (because D ≥ K/2), so u = −½ ln ρ is an upper bracket.
fn solve_axis_ratio(rho: f64) -> Option<f64> {
    if !(rho.is_finite() && rho >= 1.0) {
        return None;
    }
    let target = rho.ln();
    if target <= 0.0 {
        return Some(1.0); // the circle
    }
    let phi = |u: f64| {
        let g = Dual::<1>::var(u, 0).lift(u.exp(), u.exp());
        let r = ratio_of(g).0;
        (r.re.ln() - target, r.eps[0] / r.re)
    };
    // Expand downwards until φ(lo) > 0 (ρ too large there); keep g² far above underflow.
    let (mut hi, mut step) = (-0.5 * target, 1.0);
    let mut lo = hi - step;
    loop {
        let f = phi(lo).0;
        if f > 0.0 {
            break;
        }
        if f.is_nan() || lo < -300.0 {
            return None;
        }
        hi = lo;
        step *= 2.0;
        lo -= step;
    }
    let mut u = (-2.0 / 3.0 * target).clamp(lo, hi); // b/a ≈ (A/B)^(2/3)
    for _ in 0..200 {
        let (f, df) = phi(u);
        if f > 0.0 {
            lo = u;
        } else if f < 0.0 {
            hi = u;
        } else if f.is_nan() {
            return None;
        } else {
            return Some(u.exp()); // exact root
        }
        let newton = u - f / df; // safeguard: bisect when Newton leaves the bracket
        let next = if newton > lo && newton < hi {
            newton
        } else {
            0.5 * (lo + hi)
        };
        if (next - u).abs() <= 1e-15 * (1.0 + u.abs()) || hi - lo <= 1e-15 * (1.0 + u.abs()) {
            return Some(next.exp());
        }
        u = next;
    }
    None
}

/// Cube root with exact derivative (d∛x/dx = 1/(3∛x²)).
fn cbrt<T: Scalar>(x: T) -> T {
    let c = x.re().cbrt();
    x.lift(c, 1.0 / (3.0 * c * c))
}

/// The Hertz patch of two identical elastic bodies (docs/model.md §4).
///
/// * `normal_force` N (N), `curv_rolling` A = 1/r_wheel (1/m),
///   `curv_lateral` B = 1/R_rail + 1/R_wheel,transverse (1/m), both > 0;
/// * `young_modulus` E (Pa), `poisson_ratio` ν.
///
/// Major semi-axis along the smaller curvature C_min = min(A, B):
/// `major³ = 6 N D(e) (1 − ν²)/(π E C_min)`, minor = major·√(1−e²) (module docs).
pub fn hertz_patch<T: Scalar>(
    normal_force: T,
    curv_rolling: T,
    curv_lateral: T,
    young_modulus: f64,
    poisson_ratio: f64,
) -> Result<HertzPatch<T>, HertzError> {
    let (n, ca, cb) = (normal_force.re(), curv_rolling.re(), curv_lateral.re());
    let pos = |x: f64| x.is_finite() && x > 0.0;
    if !pos(n) {
        return Err(HertzError::NonPositiveLoad { normal_force: n });
    }
    if !(pos(ca) && pos(cb)) {
        return Err(HertzError::NonPositiveCurvature {
            rolling: ca,
            lateral: cb,
        });
    }
    if !(pos(young_modulus) && poisson_ratio > -1.0 && poisson_ratio <= 0.5) {
        return Err(HertzError::InvalidMaterial {
            young_modulus,
            poisson_ratio,
        });
    }
    // Either branch at A == B gives the same value and first derivatives (the map is C¹ there).
    let lateral_major = ca > cb;
    let (rho, c_min) = if lateral_major {
        (curv_rolling / curv_lateral, curv_lateral)
    } else {
        (curv_lateral / curv_rolling, curv_rolling)
    };
    let no_conv = || HertzError::NoConvergence { ratio: rho.re() };
    let g_star = solve_axis_ratio(rho.re()).ok_or_else(no_conv)?;
    let r = ratio_of(Dual::<1>::var(g_star, 0)).0;
    if !(r.eps[0].is_finite() && r.eps[0] < 0.0) {
        return Err(no_conv());
    }
    // Implicit-function step (module docs): exact value and derivatives of g.
    let g = (rho - r.re) / r.eps[0] + g_star;
    let (_, d) = ratio_of(g);
    let scale = 6.0 * (1.0 - poisson_ratio * poisson_ratio) / (PI * young_modulus);
    let major = cbrt(normal_force * d * scale / c_min);
    let minor = major * g;
    let (a, b) = if lateral_major {
        (minor, major)
    } else {
        (major, minor)
    };
    if !(pos(a.re()) && pos(b.re())) {
        return Err(HertzError::NonFiniteSemiAxes {
            a: a.re(),
            b: b.re(),
        });
    }
    Ok(HertzPatch { a, b })
}

#[cfg(test)]
mod tests {
    use super::*;

    type TestResult = Result<(), Box<dyn std::error::Error>>;
    const E_STEEL: f64 = 210e9;
    const NU: f64 = 0.3;

    fn close(x: f64, y: f64, rel: f64) -> bool {
        (x - y).abs() <= rel * x.abs().max(y.abs())
    }

    fn patch(n: f64, ca: f64, cb: f64) -> Result<(f64, f64), HertzError> {
        hertz_patch(n, ca, cb, E_STEEL, NU).map(|p| (p.a, p.b))
    }

    #[test]
    fn elliptic_integrals_known_values_and_legendre_relation() {
        let (k0, e0) = complete_elliptic(0.0);
        assert!(close(k0, PI / 2.0, 1e-16) && close(e0, PI / 2.0, 1e-16));
        // K, E at k = sin 45° (m = 1/2): A&S table 17.1 / DLMF 19.6 lemniscatic values.
        let (k, e) = complete_elliptic(std::f64::consts::FRAC_1_SQRT_2);
        assert!(close(k, 1.854_074_677_301_371_9, 4e-16), "{k}");
        assert!(close(e, 1.350_643_881_047_675_5, 4e-16), "{e}");
        // Legendre's relation E K' + E' K − K K' = π/2 (primes: complementary modulus).
        for &m in &[1e-12, 0.09, 0.36, 0.81, 0.9801, 0.999_999] {
            let (k, e) = complete_elliptic(f64::sqrt(m));
            let (kc, ec) = complete_elliptic(f64::sqrt(1.0 - m));
            let legendre = e * kc + ec * k - k * kc;
            assert!(close(legendre, PI / 2.0, 1e-14), "m = {m}: {legendre}");
        }
        assert_eq!(complete_elliptic(1.0), (f64::INFINITY, 1.0));
        assert!(complete_elliptic(1.5).0.is_nan() && complete_elliptic(f64::NAN).1.is_nan());
    }

    #[test]
    fn elliptic_derivatives_are_exact() {
        for &k in &[0.0, 0.2, 0.7, 0.95, 0.999] {
            let (kd, ed) = complete_elliptic(Dual::<1>::var(k, 0));
            // Closed forms (DLMF 19.4.1): dK/dk = E/(k k'²) − K/k, dE/dk = (E − K)/k.
            let (dk, de) = if k == 0.0 {
                (0.0, 0.0)
            } else {
                (ed.re / (k * (1.0 - k * k)) - kd.re / k, (ed.re - kd.re) / k)
            };
            assert!(
                (kd.eps[0] - dk).abs() <= 1e-12 * dk.abs().max(1.0),
                "K' at {k}"
            );
            assert!(
                (ed.eps[0] - de).abs() <= 1e-12 * de.abs().max(1.0),
                "E' at {k}"
            );
            let h = 1e-6 * (1.0 - k);
            let fd = |i: usize| {
                let f = |x: f64| {
                    if i == 0 {
                        complete_elliptic(x).0
                    } else {
                        complete_elliptic(x).1
                    }
                };
                (f(k + h) - f(k - h)) / (2.0 * h)
            };
            assert!((kd.eps[0] - fd(0)).abs() <= 1e-6 * dk.abs().max(1.0));
            assert!((ed.eps[0] - fd(1)).abs() <= 1e-6 * de.abs().max(1.0));
        }
    }

    /// docs/model.md §4 check: the seed's contact (N = 55 kN, r = 0.46 m, R_rail = 79.37 mm, steel)
    /// against the seed paper's a = 7.0045 mm, b = 2.20245 mm.
    #[test]
    fn seed_patch_matches_model_check() -> TestResult {
        let (a, b) = patch(55_000.0, 1.0 / 0.46, 1.0 / 0.07937)?;
        let (da, db) = (a / 7.0045e-3 - 1.0, b / 2.20245e-3 - 1.0);
        println!(
            "seed patch: a = {:.5} mm ({:+.3} %), b = {:.5} mm ({:+.3} %)",
            a * 1e3,
            da * 1e2,
            b * 1e3,
            db * 1e2
        );
        assert!(da.abs() < 5e-3 && db.abs() < 5e-3);
        Ok(())
    }

    /// Against `tests/data/hertz_mn.csv` (m, n, e from K(e), E(e), computed with scipy).
    /// Conventions: the file writes the gap as A' x² + B' y² with A', B' HALF the summed
    /// curvatures, so A' = A/2, B' = B/2 here; θ = arccos((B−A)/(A+B)) is the same in both.
    /// Its semi-axes are m, n · L with L = [3N/(4E*(A'+B'))]^(1/3), 1/E* = 2(1−ν²)/E.
    /// θ < 90° ⇔ B > A: major m along x (rolling, our a); θ > 90° swaps (tested by mirroring).
    /// The table prints 5 decimals (e: 6), so the tolerance is half a unit of the last digit.
    #[test]
    fn reproduces_exact_hertz_m_n_table() -> TestResult {
        let path =
            crate::testutil::shared_reference("hertz_mn.csv").ok_or("hertz_mn.csv not found")?;
        let text = std::fs::read_to_string(path)?;
        let n_force = 1.0e4;
        let mut rows = 0;
        for line in text
            .lines()
            .filter(|l| !l.starts_with('#') && !l.starts_with("theta"))
        {
            let f: Vec<f64> = line
                .split(',')
                .take(5)
                .map(str::parse)
                .collect::<Result<_, _>>()?;
            let (theta, m_t, n_t, e_t) = (f[0].to_radians(), f[1], f[2], f[4]);
            let (ca, cb) = (1.0 - theta.cos(), 1.0 + theta.cos()); // A + B = 2 1/m, A' + B' = 1
            let e_star = E_STEEL / (2.0 * (1.0 - NU * NU));
            let l = (3.0 * n_force / (4.0 * e_star * (ca + cb) / 2.0)).cbrt();
            let (a, b) = patch(n_force, ca, cb)?;
            assert!(
                (a / l - m_t).abs() <= 5.01e-6 && (b / l - n_t).abs() <= 5.01e-6,
                "θ={theta}"
            );
            let ecc = (1.0 - (b / a).powi(2)).sqrt();
            assert!(
                (ecc - e_t).abs() <= 5.01e-7,
                "θ = {}: e = {ecc} vs {e_t}",
                f[0]
            );
            let (a2, b2) = patch(n_force, cb, ca)?; // θ → 180° − θ: major is now lateral
            assert!(close(a2, b, 1e-12) && close(b2, a, 1e-12));
            rows += 1;
        }
        assert!(rows >= 20, "only {rows} rows");
        Ok(())
    }

    fn check_derivatives(n: f64, ca: f64, cb: f64) -> TestResult {
        let x = [n, ca, cb];
        let v = |k: usize| Dual::<3>::var(x[k], k);
        let p = hertz_patch(v(0), v(1), v(2), E_STEEL, NU)?;
        for k in 0..3 {
            let h = 1e-6 * x[k];
            let (mut up, mut dn) = (x, x);
            up[k] += h;
            dn[k] -= h;
            let (pu, pd) = (patch(up[0], up[1], up[2])?, patch(dn[0], dn[1], dn[2])?);
            let (fa, fb) = ((pu.0 - pd.0) / (2.0 * h), (pu.1 - pd.1) / (2.0 * h));
            let tol = |d: f64, s: f64| 1e-6 * d.abs().max(s / x[k]);
            assert!(
                (p.a.eps[k] - fa).abs() <= tol(fa, p.a.re),
                "da/dx{k}: {} vs {fa}",
                p.a.eps[k]
            );
            assert!(
                (p.b.eps[k] - fb).abs() <= tol(fb, p.b.re),
                "db/dx{k}: {} vs {fb}",
                p.b.eps[k]
            );
        }
        Ok(())
    }

    #[test]
    fn derivatives_match_central_differences() -> TestResult {
        check_derivatives(55_000.0, 1.0 / 0.46, 1.0 / 0.07937)?; // B > A (seed)
        check_derivatives(40_000.0, 1.0 / 0.05, 1.0 / 0.30)?; // A > B (lateral major)
        check_derivatives(60_000.0, 2.0, 2.0)?; // circle: C¹ across A = B
        check_derivatives(1_000.0, 1.0, 5.0e4) // very elongated
    }

    #[test]
    fn semi_axes_scale_with_cube_root_of_load() -> TestResult {
        let (a, b) = patch(10_000.0, 2.0, 13.0)?;
        let (a8, b8) = patch(80_000.0, 2.0, 13.0)?;
        assert!(close(a8, 2.0 * a, 1e-14) && close(b8, 2.0 * b, 1e-14));
        // and with the inverse cube root of a common curvature scale
        let (a_s, b_s) = patch(10_000.0, 16.0, 104.0)?;
        assert!(close(a_s, 0.5 * a, 1e-14) && close(b_s, 0.5 * b, 1e-14));
        Ok(())
    }

    #[test]
    fn circle_limit_is_hertz_sphere_and_continuous() -> TestResult {
        let (n, c) = (30_000.0, 4.0);
        let e_star = E_STEEL / (2.0 * (1.0 - NU * NU));
        let r = (3.0 * n * (1.0 / c) / (4.0 * e_star)).cbrt(); // a³ = 3 N R/(4E*), R = 1/A
        let (a, b) = patch(n, c, c)?;
        assert!(close(a, r, 1e-15) && close(b, r, 1e-15));
        for eps in [1e-12, 1e-9, 1e-6] {
            for (ca, cb) in [(c, c * (1.0 + eps)), (c * (1.0 + eps), c)] {
                let (a1, b1) = patch(n, ca, cb)?;
                // first order: a, b move by O(eps) from the sphere
                assert!(close(a1, r, 2.0 * eps) && close(b1, r, 2.0 * eps), "{eps}");
            }
        }
        Ok(())
    }

    #[test]
    fn bad_inputs_are_errors_never_panics() {
        let ok = (1e4, 2.0, 12.0);
        for n in [0.0, -1.0, f64::NAN, f64::INFINITY] {
            let r = patch(n, ok.1, ok.2);
            assert!(matches!(r, Err(HertzError::NonPositiveLoad { .. })), "{n}");
        }
        for c in [0.0, -2.0, f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            assert!(matches!(
                patch(ok.0, c, ok.2),
                Err(HertzError::NonPositiveCurvature { .. })
            ));
            assert!(matches!(
                patch(ok.0, ok.1, c),
                Err(HertzError::NonPositiveCurvature { .. })
            ));
        }
        for (e, nu) in [
            (0.0, 0.3),
            (-1.0, 0.3),
            (f64::NAN, 0.3),
            (2e11, 0.6),
            (2e11, -1.0),
            (2e11, f64::NAN),
        ] {
            let r = hertz_patch(ok.0, ok.1, ok.2, e, nu);
            assert!(
                matches!(r, Err(HertzError::InvalidMaterial { .. })),
                "{e} {nu}"
            );
        }
        // Extremes: either a finite positive patch or an error, never a panic.
        let extremes = [
            1e-300,
            1e-100,
            1e-8,
            1.0,
            1e8,
            1e100,
            1e300,
            f64::MAX,
            f64::MIN_POSITIVE,
        ];
        for &n in &extremes {
            for &ca in &extremes {
                for &cb in &extremes {
                    if let Ok((a, b)) = patch(n, ca, cb) {
                        assert!(a.is_finite() && b.is_finite() && a > 0.0 && b > 0.0);
                    }
                }
            }
        }
        let err = HertzError::NoConvergence { ratio: 1e308 };
        assert!(err.to_string().contains("1e308"));
    }
}
