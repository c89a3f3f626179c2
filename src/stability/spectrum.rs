//! Eigenvalues and eigenvectors of the centred-motion Jacobian at one speed.
//!
//! Uses faer's general (non-symmetric) eigen-decomposition, which gives right eigenvectors
//! too, so that callers and tests can check the defining identity $J v = λ v$.

use faer::Mat;
use nalgebra::SMatrix;

/// One eigenvalue with its right eigenvector.
#[derive(Clone, Debug, PartialEq)]
pub struct EigenPair {
    /// real part (1/s)
    pub re: f64,
    /// imaginary part (rad/s)
    pub im: f64,
    /// eigenvector, (re, im) per state component
    pub vector: Vec<(f64, f64)>,
}

impl EigenPair {
    /// Damping ratio $ζ = −\mathrm{Re}\,λ/|λ|$ (–); 1 for a zero eigenvalue's neighbourhood.
    pub fn damping_ratio(&self) -> f64 {
        let m = self.re.hypot(self.im);
        if m > 0.0 {
            -self.re / m
        } else {
            0.0
        }
    }
    /// Frequency $|\mathrm{Im}\,λ|/2π$ (Hz).
    pub fn frequency_hz(&self) -> f64 {
        self.im.abs() / (2.0 * std::f64::consts::PI)
    }
}

/// The spectrum at one speed, eigenvalues sorted by decreasing imaginary part then real part.
#[derive(Clone, Debug, PartialEq)]
pub struct Spectrum {
    /// speed (m/s)
    pub speed_m_s: f64,
    /// the eigenpairs, one per state
    pub pairs: Vec<EigenPair>,
}

impl Spectrum {
    /// The least damping ratio over the oscillatory modes (or all modes if none oscillates).
    pub fn least_damping_ratio(&self) -> f64 {
        let osc: Vec<f64> = self
            .pairs
            .iter()
            .filter(|p| p.im.abs() > 0.0)
            .map(EigenPair::damping_ratio)
            .collect();
        let all = if osc.is_empty() {
            self.pairs.iter().map(EigenPair::damping_ratio).collect()
        } else {
            osc
        };
        all.into_iter().fold(f64::INFINITY, f64::min)
    }
}

/// Eigen-decomposition of `j`; `None` if the QR iteration failed (or `j` is not finite).
pub fn spectrum_at<const N: usize>(j: &SMatrix<f64, N, N>, speed_m_s: f64) -> Option<Spectrum> {
    if !j.iter().all(|x| x.is_finite()) {
        return None;
    }
    let a = Mat::<f64>::from_fn(N, N, |r, c| j[(r, c)]);
    let evd = a.eigen();
    clear_upper_halves();
    let evd = evd.ok()?;
    let s = evd.S().column_vector();
    let u = evd.U();
    let mut pairs: Vec<EigenPair> = (0..N)
        .map(|k| EigenPair {
            re: s[k].re,
            im: s[k].im,
            vector: (0..N).map(|r| (u[(r, k)].re, u[(r, k)].im)).collect(),
        })
        .collect();
    pairs.sort_by(|p, q| q.im.total_cmp(&p.im).then(q.re.total_cmp(&p.re)));
    Some(Spectrum { speed_m_s, pairs })
}

/// Clears the upper halves of the AVX registers (`vzeroupper`) on x86-64 processors with AVX.
///
/// faer's eigenvector solve leaves them dirty; until they are cleared every non-VEX SSE
/// instruction after it (the code of this crate and nalgebra's) runs about 2.5 times slower on
/// some processors, from the false dependency on the upper halves. A no-op elsewhere.
#[inline]
pub(crate) fn clear_upper_halves() {
    #[cfg(target_arch = "x86_64")]
    {
        if std::arch::is_x86_feature_detected!("avx") {
            // SAFETY: the processor has AVX (checked above), and `vzeroupper` only zeroes bits
            // 128 and up of the vector registers, which hold no value live across this call.
            unsafe { std::arch::x86_64::_mm256_zeroupper() }
        }
    }
}

/// The eigenvalues of `j` as (re, im), without vectors; `None` if not finite or QR failed
/// (a stack routine for small fixed sizes first: balancing, Householder Hessenberg form and
/// Francis double-shift QR; nalgebra's Schur decomposition if it does not converge, then
/// faer's eigenvalues).
pub fn eigenvalues<const N: usize>(j: &SMatrix<f64, N, N>) -> Option<Vec<(f64, f64)>> {
    if !j.iter().all(|x| x.is_finite()) {
        return None;
    }
    // whatever ran before may have left the vector registers' upper halves dirty (faer does),
    // which makes the SSE code below run 2 to 3 times slower on some processors
    clear_upper_halves();
    // balancing, Householder Hessenberg and Francis QR on a stack copy, eigenvalues only:
    // about half the time of nalgebra's Schur form below on the car's 28-state Jacobian (46
    // against 94–110 µs a matrix, small_eigen's docs), and the scan's grid is its hot loop
    if let Some(ev) = super::small_eigen::eigenvalues(j) {
        if ev.iter().all(|z| z.0.is_finite() && z.1.is_finite()) {
            return Some(ev.to_vec());
        }
    }
    // then nalgebra's real Schur form, then faer's ([`eigenvalues_dense`])
    let d = nalgebra::DMatrix::<f64>::from_fn(N, N, |r, c| j[(r, c)]);
    let ev = eigenvalues_dense(&d)?;
    Some(ev.iter().map(|z| (z.re, z.im)).collect())
}

/// The eigenvalues of a dense square matrix of any size (a monodromy matrix), or `None` when it
/// has a non-finite entry or neither method converges: nalgebra's real Schur form with at most
/// 60 n QR sweeps, then faer's. nalgebra's own `complex_eigenvalues()` iterates without a
/// limit, and on one monodromy of the DTU bogie (a 7.5 mm cycle the attractor search refined,
/// entries from 1 down to 1e-71: `tests/data/monodromy_schur_hang.csv`) it never returned.
pub fn eigenvalues_dense(m: &nalgebra::DMatrix<f64>) -> Option<Vec<nalgebra::Complex<f64>>> {
    let n = m.nrows();
    if n != m.ncols() || !m.iter().all(|x| x.is_finite()) {
        return None;
    }
    // nalgebra's Schur form takes about half the time of faer's `eigenvalues` on the car's
    // 28-state Jacobian (measured 190 against 385 µs a matrix, loaded machine)
    if let Some(schur) = nalgebra::Schur::try_new(m.clone(), f64::EPSILON, 60 * n.max(1)) {
        let ev: Vec<nalgebra::Complex<f64>> = schur.complex_eigenvalues().iter().copied().collect();
        if ev.iter().all(|z| z.re.is_finite() && z.im.is_finite()) {
            return Some(ev);
        }
    }
    let a = Mat::<f64>::from_fn(n, n, |r, c| m[(r, c)]);
    let ev = a.eigenvalues();
    clear_upper_halves();
    let ev: Vec<nalgebra::Complex<f64>> = ev
        .ok()?
        .iter()
        .map(|z| nalgebra::Complex::new(z.re, z.im))
        .collect();
    ev.iter()
        .all(|z| z.re.is_finite() && z.im.is_finite())
        .then_some(ev)
}

/// $\det J$ by faer's LU (any size).
pub fn determinant<const N: usize>(j: &SMatrix<f64, N, N>) -> f64 {
    Mat::<f64>::from_fn(N, N, |r, c| j[(r, c)])
        .as_ref()
        .determinant()
}
