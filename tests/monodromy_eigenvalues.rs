//! The Floquet multipliers of a monodromy on which nalgebra's `complex_eigenvalues()` (a Schur
//! QR iteration without a sweep limit) never returned: the attractor search of one uncertainty
//! draw of the DTU bogie hung there for as long as it was left to run. critspeed's eigenvalues
//! of a dense matrix (`stability::eigenvalues_dense`) bound the sweeps and fall back on faer.
//! The matrix is `tests/data/monodromy_schur_hang.csv` (its header says where it came from).
//! The eigenvalues are checked by identities: their sum is the trace and their product the
//! determinant.

use std::sync::mpsc;
use std::time::Duration;

use critspeed::continuation::Floquet;
use nalgebra::{Complex, DMatrix, SMatrix};

const N: usize = 12;

fn matrix() -> DMatrix<f64> {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/data/monodromy_schur_hang.csv"
    );
    let text = std::fs::read_to_string(path).expect("tests/data/monodromy_schur_hang.csv");
    let rows: Vec<Vec<f64>> = text
        .lines()
        .filter(|l| !l.starts_with('#') && !l.trim().is_empty())
        .map(|l| {
            l.split(',')
                .map(|x| x.trim().parse::<f64>().expect("a number"))
                .collect()
        })
        .collect();
    assert_eq!(rows.len(), N);
    assert!(rows.iter().all(|r| r.len() == N));
    DMatrix::from_fn(N, N, |i, j| rows[i][j])
}

/// Runs `f` on another thread and waits at most a minute for it: a regression hangs no longer
/// than that.
fn within_a_minute<T: Send + 'static>(f: impl FnOnce() -> T + Send + 'static) -> T {
    let (tx, rx) = mpsc::channel();
    std::thread::spawn(move || {
        let _ = tx.send(f());
    });
    rx.recv_timeout(Duration::from_secs(60))
        .expect("returned within a minute")
}

#[test]
fn eigenvalues_of_the_monodromy_that_hung_return_and_satisfy_trace_and_determinant() {
    let m = matrix();
    let mm = m.clone();
    let ev =
        within_a_minute(move || critspeed::stability::eigenvalues_dense(&mm)).expect("eigenvalues");
    assert_eq!(ev.len(), N);
    let sum: Complex<f64> = ev.iter().sum();
    let trace = m.trace();
    assert!(
        (sum.re - trace).abs() <= 1e-12 * trace.abs().max(1.0) && sum.im.abs() <= 1e-12,
        "sum {sum} against trace {trace}"
    );
    let product: Complex<f64> = ev.iter().product();
    let det = m.clone().lu().determinant();
    assert!(
        (product.re - det).abs() <= 1e-10 * det.abs().max(1e-300)
            && product.im.abs() <= 1e-10 * det.abs(),
        "product {product} against determinant {det}"
    );
}

#[test]
fn floquet_multipliers_of_the_monodromy_that_hung_are_the_eigenvalues() {
    let m = matrix();
    // Floquet::from_monodromy negates the half-period matrix of a symmetric cycle itself: hand
    // it the matrix as stored, unnegated, as the plain (whole-period) form
    let phi = SMatrix::<f64, N, N>::from_fn(|i, j| m[(i, j)]);
    let f = within_a_minute(move || Floquet::from_monodromy(&phi, false));
    assert_eq!(f.multipliers.len(), N);
    assert!(f
        .multipliers
        .iter()
        .all(|z| z.re.is_finite() && z.im.is_finite()));
    let ev = critspeed::stability::eigenvalues_dense(&m).expect("eigenvalues");
    let mut a: Vec<f64> = f.multipliers.iter().map(|z| z.norm()).collect();
    let mut b: Vec<f64> = ev.iter().map(|z| z.norm()).collect();
    a.sort_by(f64::total_cmp);
    b.sort_by(f64::total_cmp);
    assert_eq!(a, b);
    // the multiplier nearest 1 is the trivial one, and the others' largest modulus is reported
    let others = f
        .multipliers
        .iter()
        .enumerate()
        .filter(|(k, _)| *k != f.trivial)
        .map(|(_, z)| z.norm())
        .fold(0.0, f64::max);
    assert_eq!(others, f.max_nontrivial);
}

#[test]
fn a_monodromy_with_a_non_finite_entry_has_no_multipliers_and_is_not_stable() {
    let mut phi = SMatrix::<f64, 4, 4>::identity() * 0.5;
    phi[(1, 2)] = f64::NAN;
    let f = Floquet::from_monodromy(&phi, false);
    assert!(!f.stable());
    assert!(
        critspeed::stability::eigenvalues_dense(&DMatrix::from_fn(4, 4, |i, j| phi[(i, j)]))
            .is_none()
    );
}
