//! Which multipliers cross the unit circle between two orbits of a branch, and the test
//! functions that locate each kind of crossing.
//!
//! Between consecutive orbits the nontrivial multipliers of the shooting map (ν of the
//! half-period map $x \mapsto −φ_{T/2}(x)$ on a symmetric branch, μ of $φ_T$ otherwise) are
//! counted by where they lie outside the unit circle: real and below −1, real and above +1,
//! or in a complex pair. A change of the count below −1 by an odd number is one real
//! multiplier through −1: **symmetry breaking** on a symmetric branch (ν = −1, hence μ = ν² = 1
//! without a fold: a pitchfork of the full-period problem, whose new cycles are not symmetric),
//! **period doubling** elsewhere (μ = −1). A change of the complex count with the real counts
//! unchanged is a complex pair through the circle: a **torus** (Neimark–Sacker) point. Two real
//! multipliers that meet and leave the real axis change both counts and are not a
//! bifurcation. Folds are found from the tangent (dp/ds changes sign), not here.
//!
//! On a symmetric branch a real μ through −1 would need ν = ±i, a complex pair of the half-period
//! map: period doubling of a symmetric cycle is not generic (Swift & Wiesenfeld, Phys. Rev. Lett.
//! 52, 705 (1984)); symmetry breaking comes first, and the doubling happens on the asymmetric
//! branch.
//!
//! Location (Illinois on the arclength, `branch.rs`) needs a continuous function with a sign
//! change: $\prod_i (1 + ν_i)$ (a complex pair contributes $|1 + ν|^2 > 0$, the trivial ν = 1
//! contributes 2), so only a real multiplier through −1 changes its sign; for a torus the
//! signed distance $|μ| − 1$ of the complex multiplier nearest the circle.

use nalgebra::Complex;

use super::{Floquet, SpecialKind};

/// A multiplier is taken as real when its imaginary part is below this fraction of its
/// modulus (the eigenvalue solver returns exact zeros for real eigenvalues of a real Schur
/// form; pairs that are about to meet on the axis have imaginary parts far above this).
const REAL: f64 = 1e-9;

/// Nontrivial multipliers outside the unit circle, by kind.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Census {
    /// real, below −1
    pub negative: usize,
    /// real, above +1
    pub positive: usize,
    /// in complex pairs (counted singly)
    pub complex: usize,
}

fn is_real(m: &Complex<f64>) -> bool {
    m.im.abs() <= REAL * m.norm()
}

/// The census of the shooting map's nontrivial multipliers (ν on a symmetric branch).
pub fn census(f: &Floquet) -> Census {
    let mut c = Census {
        negative: 0,
        positive: 0,
        complex: 0,
    };
    for (k, m) in f.shooting_multipliers().iter().enumerate() {
        if k == f.trivial || m.norm() <= 1.0 {
            continue;
        }
        if !is_real(m) {
            c.complex += 1;
        } else if m.re < 0.0 {
            c.negative += 1;
        } else {
            c.positive += 1;
        }
    }
    c
}

/// The crossings between two orbits of a branch (`symmetric`: the branch's orbits are
/// symmetric and the multipliers are the half-period map's), in a fixed order.
pub fn crossings(a: &Floquet, b: &Floquet, symmetric: bool) -> Vec<SpecialKind> {
    let (ca, cb) = (census(a), census(b));
    let mut out = Vec::new();
    if (ca.negative + cb.negative) % 2 == 1 {
        out.push(if symmetric {
            SpecialKind::SymmetryBreaking
        } else {
            SpecialKind::PeriodDoubling
        });
    }
    if ca.complex != cb.complex && ca.negative + ca.positive == cb.negative + cb.positive {
        out.push(SpecialKind::Torus);
    }
    out
}

/// The test function of a crossing kind, evaluated on an orbit's multipliers: it changes sign
/// where the crossing happens (NaN for a fold, which is located on the tangent).
pub fn test_value(kind: SpecialKind, f: &Floquet) -> f64 {
    let m = f.shooting_multipliers();
    match kind {
        SpecialKind::SymmetryBreaking | SpecialKind::PeriodDoubling => {
            m.iter()
                .fold(Complex::new(1.0, 0.0), |acc, v| acc * (v + 1.0))
                .re
        }
        SpecialKind::Torus => m
            .iter()
            .filter(|v| !is_real(v))
            .map(|v| v.norm() - 1.0)
            .min_by(|a, b| a.abs().total_cmp(&b.abs()))
            .unwrap_or(f64::NAN),
        SpecialKind::Fold => f64::NAN,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn floquet(mult: &[(f64, f64)], symmetric: bool) -> Floquet {
        let m: Vec<Complex<f64>> = mult.iter().map(|&(r, i)| Complex::new(r, i)).collect();
        let trivial = m
            .iter()
            .enumerate()
            .min_by(|a, b| (a.1 - 1.0).norm().total_cmp(&(b.1 - 1.0).norm()))
            .map_or(0, |k| k.0);
        let max_nontrivial = m
            .iter()
            .enumerate()
            .filter(|(k, _)| *k != trivial)
            .map(|(_, v)| v.norm())
            .fold(0.0, f64::max);
        Floquet {
            multipliers: m
                .iter()
                .map(|v| if symmetric { v * v } else { *v })
                .collect(),
            half: symmetric.then(|| m.clone()),
            trivial_error: 0.0,
            max_nontrivial,
            trivial,
        }
    }

    #[test]
    fn a_real_multiplier_through_minus_one_is_symmetry_breaking_or_doubling() {
        for symmetric in [true, false] {
            let a = floquet(
                &[(1.0, 0.0), (-0.9, 0.0), (0.1, 0.2), (0.1, -0.2)],
                symmetric,
            );
            let b = floquet(
                &[(1.0, 0.0), (-1.1, 0.0), (0.1, 0.2), (0.1, -0.2)],
                symmetric,
            );
            let kind = if symmetric {
                SpecialKind::SymmetryBreaking
            } else {
                SpecialKind::PeriodDoubling
            };
            assert_eq!(crossings(&a, &b, symmetric), vec![kind]);
            let (ga, gb) = (test_value(kind, &a), test_value(kind, &b));
            assert!(ga * gb < 0.0, "{ga} {gb}");
        }
    }

    #[test]
    fn a_complex_pair_through_the_circle_is_a_torus_and_a_collision_is_nothing() {
        let a = floquet(&[(1.0, 0.0), (0.5, 0.8), (0.5, -0.8), (0.2, 0.0)], false);
        let b = floquet(&[(1.0, 0.0), (0.6, 0.9), (0.6, -0.9), (0.2, 0.0)], false);
        assert_eq!(crossings(&a, &b, false), vec![SpecialKind::Torus]);
        let (ga, gb) = (
            test_value(SpecialKind::Torus, &a),
            test_value(SpecialKind::Torus, &b),
        );
        assert!(ga < 0.0 && gb > 0.0, "{ga} {gb}");
        // two real multipliers below −1 meet and become a complex pair outside: no crossing
        let c = floquet(&[(1.0, 0.0), (-1.5, 0.0), (-1.4, 0.0), (0.2, 0.0)], false);
        let d = floquet(
            &[(1.0, 0.0), (-1.45, 0.1), (-1.45, -0.1), (0.2, 0.0)],
            false,
        );
        assert!(crossings(&c, &d, false).is_empty());
        // a multiplier through +1 (a fold) is not reported here
        let e = floquet(&[(1.0, 0.0), (0.9, 0.0), (0.2, 0.0)], false);
        let f = floquet(&[(1.0, 0.0), (1.1, 0.0), (0.2, 0.0)], false);
        assert!(crossings(&e, &f, false).is_empty());
    }
}
