//! The small eigenvalue routine against independent truth: matrices built with known
//! eigenvalues ($S D S^{-1}$), companion matrices of polynomials with known roots, faer's
//! eigenvalues, and the shipped car's Jacobian.

use nalgebra::SMatrix;

use super::*;
use crate::contact::creep::CreepLaw;
use crate::stability::LinearSystem;

/// A deterministic pseudo-random sequence (Knuth's MMIX linear congruential generator).
struct Lcg(u64);

impl Lcg {
    /// The next value, uniform in [−1, 1).
    fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (self.0 >> 11) as f64 / (1u64 << 52) as f64 - 1.0
    }
}

/// A known eigenvalue structure: a real eigenvalue, or the pair a ± iω.
#[derive(Clone, Copy, Debug)]
enum Eig {
    Real(f64),
    Pair(f64, f64),
}

/// The eigenvalues of `spec` as (re, im), pairs as both conjugates.
fn listed(spec: &[Eig]) -> Vec<(f64, f64)> {
    spec.iter()
        .flat_map(|e| match *e {
            Eig::Real(x) => vec![(x, 0.0)],
            Eig::Pair(a, w) => vec![(a, w), (a, -w)],
        })
        .collect()
}

/// Block diagonal D of `spec` (2×2 blocks [[a, −ω], [ω, a]]), conjugated by the dense, well
/// conditioned $S = I + R/(2\sqrt N)$, R pseudo-random in [−1, 1): $A = S D S^{-1}$.
fn with_spectrum<const N: usize>(spec: &[Eig], seed: u64) -> SMatrix<f64, N, N> {
    let mut d = SMatrix::<f64, N, N>::zeros();
    let mut k = 0;
    for e in spec {
        match *e {
            Eig::Real(x) => {
                d[(k, k)] = x;
                k += 1;
            }
            Eig::Pair(a, w) => {
                d[(k, k)] = a;
                d[(k + 1, k + 1)] = a;
                d[(k, k + 1)] = -w;
                d[(k + 1, k)] = w;
                k += 2;
            }
        }
    }
    assert_eq!(k, N, "the spectrum has N eigenvalues");
    let mut g = Lcg(seed);
    let s = SMatrix::<f64, N, N>::from_fn(|r, c| {
        f64::from(u8::from(r == c)) + 0.5 * g.next() / (N as f64).sqrt()
    });
    let inv = s.try_inverse().expect("S is well conditioned");
    s * d * inv
}

/// A spectrum of n eigenvalues: about n/3 distinct complex pairs, the rest distinct reals.
fn spread(n: usize) -> Vec<Eig> {
    let pairs = n / 3;
    let mut spec: Vec<Eig> = (0..pairs)
        .map(|j| Eig::Pair(-2.0 + 0.37 * j as f64, 0.5 + 1.1 * j as f64))
        .collect();
    spec.extend((0..n - 2 * pairs).map(|j| Eig::Real(-3.0 + 0.53 * j as f64)));
    spec
}

/// Every `truth` eigenvalue matched by a distinct computed one within `tol` (greedy nearest).
fn assert_matches(computed: &[(f64, f64)], truth: &[(f64, f64)], tol: f64) {
    assert_eq!(computed.len(), truth.len());
    let mut used = vec![false; computed.len()];
    for t in truth {
        let dist = |z: &(f64, f64)| (z.0 - t.0).hypot(z.1 - t.1);
        let (k, d) = computed
            .iter()
            .enumerate()
            .filter(|(k, _)| !used[*k])
            .map(|(k, z)| (k, dist(z)))
            .min_by(|a, b| a.1.total_cmp(&b.1))
            .expect("as many computed as true eigenvalues");
        assert!(
            d <= tol,
            "eigenvalue {t:?}: nearest computed {:?} is {d:e} away (tolerance {tol:e})\n\
             computed {computed:?}",
            computed[k]
        );
        used[k] = true;
    }
}

/// Real eigenvalues have an imaginary part of exactly 0 and complex ones come in conjugate
/// pairs of the same real part (what the scan's counts rely on).
fn assert_structure(ev: &[(f64, f64)]) {
    for z in ev.iter().filter(|z| z.1.abs() > 0.0) {
        assert!(
            ev.iter()
                .any(|w| (w.0 - z.0).abs() <= 0.0 && (w.1 + z.1).abs() <= 0.0),
            "{z:?} has no conjugate in {ev:?}"
        );
    }
}

/// Our eigenvalues of `a`, checked for structure, as a list.
fn ours<const N: usize>(a: &SMatrix<f64, N, N>) -> Vec<(f64, f64)> {
    let ev = eigenvalues(a).expect("converges");
    assert_structure(&ev);
    ev.to_vec()
}

/// faer's eigenvalues of `a`.
fn faer_eigenvalues<const N: usize>(a: &SMatrix<f64, N, N>) -> Vec<(f64, f64)> {
    faer::Mat::<f64>::from_fn(N, N, |r, c| a[(r, c)])
        .eigenvalues()
        .expect("faer converges")
        .iter()
        .map(|z| (z.re, z.im))
        .collect()
}

fn known<const N: usize>(seed: u64) {
    let spec = spread(N);
    let a = with_spectrum::<N>(&spec, seed);
    assert_matches(&ours(&a), &listed(&spec), 1e-10 * a.norm());
}

#[test]
fn known_spectra_of_sizes_4_12_28_34() {
    known::<4>(1);
    known::<12>(2);
    known::<28>(3);
    known::<34>(4);
}

#[test]
fn badly_scaled_similarity_keeps_the_spectrum() {
    // T A T⁻¹ with T = diag(10^-3 … 10^3): the same eigenvalues, entries over 12 decades;
    // balancing brings the rows back (powers of 2, exactly)
    let spec = spread(28);
    let a = with_spectrum::<28>(&spec, 5);
    let t = |k: usize| 10f64.powi((k % 7) as i32 - 3);
    let scaled = SMatrix::<f64, 28, 28>::from_fn(|r, c| t(r) * a[(r, c)] / t(c));
    assert_matches(&ours(&scaled), &listed(&spec), 1e-10 * a.norm());
}

#[test]
fn zero_and_repeated_eigenvalues() {
    // exactly 0, a triple real 2, a double pair −1 ± 3i (all semisimple)
    let spec = [
        Eig::Real(0.0),
        Eig::Real(2.0),
        Eig::Real(2.0),
        Eig::Real(2.0),
        Eig::Pair(-1.0, 3.0),
        Eig::Pair(-1.0, 3.0),
        Eig::Real(-0.5),
        Eig::Pair(0.25, 0.75),
        Eig::Real(2.0),
    ];
    let a = with_spectrum::<12>(&spec, 6);
    assert_matches(&ours(&a), &listed(&spec), 1e-10 * a.norm());
}

#[test]
fn jordan_block_to_the_square_root_of_epsilon() {
    // a defective double eigenvalue 1.5 moves by O(√ε) under round-off
    let mut d = SMatrix::<f64, 4, 4>::from_diagonal(&nalgebra::Vector4::new(1.5, 1.5, -2.0, 0.5));
    d[(0, 1)] = 1.0;
    let mut g = Lcg(7);
    let s = SMatrix::<f64, 4, 4>::from_fn(|r, c| f64::from(u8::from(r == c)) + 0.25 * g.next());
    let a = s * d * s.try_inverse().expect("S is well conditioned");
    let truth = [(1.5, 0.0), (1.5, 0.0), (-2.0, 0.0), (0.5, 0.0)];
    assert_matches(&ours(&a), &truth, 1e-6);
}

#[test]
fn triangular_matrix_gives_its_diagonal_exactly() {
    let mut g = Lcg(8);
    let a = SMatrix::<f64, 14, 14>::from_fn(|r, c| if r <= c { g.next() } else { 0.0 });
    let truth: Vec<(f64, f64)> = (0..14).map(|k| (a[(k, k)], 0.0)).collect();
    assert_matches(&ours(&a), &truth, 0.0);
}

#[test]
fn two_by_two_blocks() {
    let m = |a, b, c, d| SMatrix::<f64, 2, 2>::new(a, b, c, d);
    let s6 = 6f64.sqrt();
    assert_matches(
        &ours(&m(1.0, 2.0, -3.0, 1.0)),
        &[(1.0, s6), (1.0, -s6)],
        1e-15,
    );
    assert_matches(
        &ours(&m(4.0, 1.0, 2.0, 3.0)),
        &[(5.0, 0.0), (2.0, 0.0)],
        1e-14,
    );
    // complex with unequal diagonal: (a−d)²/4 + bc = 1 − 5 < 0 → 2.5 ± 2i
    assert_matches(
        &ours(&m(3.5, -1.0, 5.0, 1.5)),
        &[(2.5, 2.0), (2.5, -2.0)],
        1e-14,
    );
    // a double real eigenvalue, not diagonalisable: 1 ± O(√ε)
    assert_matches(
        &ours(&m(2.0, 1.0, -1.0, 0.0)),
        &[(1.0, 0.0), (1.0, 0.0)],
        1e-7,
    );
}

/// The companion matrix of the monic polynomial with roots `roots` (complex ones as pairs).
fn companion<const N: usize>(roots: &[Eig]) -> SMatrix<f64, N, N> {
    // coefficients of Π (x − r) (real) and Π (x² − 2a x + a² + ω²), highest power first
    let mut c = vec![1.0];
    let mut times = |factor: &[f64]| {
        let mut out = vec![0.0; c.len() + factor.len() - 1];
        for (i, ci) in c.iter().enumerate() {
            for (j, fj) in factor.iter().enumerate() {
                out[i + j] += ci * fj;
            }
        }
        c = out;
    };
    for r in roots {
        match *r {
            Eig::Real(x) => times(&[1.0, -x]),
            Eig::Pair(a, w) => times(&[1.0, -2.0 * a, a * a + w * w]),
        }
    }
    // first row −c₁ … −c_N, ones on the subdiagonal
    SMatrix::<f64, N, N>::from_fn(|r, col| match r {
        0 => -c[col + 1],
        _ if col + 1 == r => 1.0,
        _ => 0.0,
    })
}

#[test]
fn companion_matrices_of_known_roots() {
    let reals: Vec<Eig> = (1..=6).map(|k| Eig::Real(k as f64)).collect();
    assert_matches(&ours(&companion::<6>(&reals)), &listed(&reals), 1e-9);
    let mixed = [
        Eig::Pair(0.0, 1.0),
        Eig::Pair(2.0, 3.0),
        Eig::Real(-1.0),
        Eig::Real(0.5),
        Eig::Pair(-0.1, 2.0),
    ];
    assert_matches(&ours(&companion::<8>(&mixed)), &listed(&mixed), 1e-10);
}

#[test]
fn roots_of_unity_need_the_exceptional_shifts() {
    // the companion of x¹² − 1 is a cyclic permutation: standard shifts make no progress
    let a = SMatrix::<f64, 12, 12>::from_fn(|r, c| {
        f64::from(u8::from(c + 1 == r || (r == 0 && c == 11)))
    });
    let truth: Vec<(f64, f64)> = (0..12)
        .map(|k| {
            let t = 2.0 * std::f64::consts::PI * k as f64 / 12.0;
            (t.cos(), t.sin())
        })
        .collect();
    assert_matches(&ours(&a), &truth, 1e-12);
}

fn agrees_with_faer<const N: usize>(seed: u64) {
    let mut g = Lcg(seed);
    let a = SMatrix::<f64, N, N>::from_fn(|_, _| g.next());
    assert_matches(&ours(&a), &faer_eigenvalues(&a), 1e-11 * a.norm());
}

#[test]
fn pseudo_random_matrices_agree_with_faer() {
    for seed in 10..15 {
        agrees_with_faer::<4>(seed);
        agrees_with_faer::<12>(seed);
        agrees_with_faer::<14>(seed);
        agrees_with_faer::<28>(seed);
        agrees_with_faer::<34>(seed);
    }
}

#[test]
fn non_finite_input_gives_none() {
    let mut a = SMatrix::<f64, 12, 12>::identity();
    a[(3, 7)] = f64::NAN;
    assert!(eigenvalues(&a).is_none());
    a[(3, 7)] = f64::INFINITY;
    assert!(eigenvalues(&a).is_none());
}

#[test]
fn car_jacobian_agrees_with_faer() {
    let path =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("studies/dtu-cooperrider-car.toml");
    let plan = crate::study::load(&path).expect("study");
    let model = plan.model().expect("model");
    let sys = LinearSystem::<28>::at_centre(&model.with_law(CreepLaw::Kalker));
    for v in [20.0, 60.0, 100.0, 160.0, 250.0] {
        let j = sys.jacobian(v);
        let ev = ours(&j);
        assert_matches(&ev, &faer_eigenvalues(&j), 1e-11 * j.norm());
        // and through the public function, which now tries this routine first
        let public = crate::stability::eigenvalues(&j).expect("eigenvalues");
        assert_matches(&public, &ev, 0.0);
    }
}
