//! Eigenvalues (no vectors) of a small real matrix of a size known at compile time, on the
//! stack.
//!
//! **Why hand-written.** The eigenvalue scan of the critical speed (`eigen_scan`) and the
//! curve and diagram checks call [`eigenvalues`](super::eigenvalues) on 12- to 34-state
//! Jacobians tens to thousands of times: it is the scan's hot loop. nalgebra's Schur form and
//! faer's eigenvalues are general: they work on heap matrices of any size, and nalgebra also
//! accumulates the orthogonal Schur factor (about $25N^3$ flops against $10N^3$ for the
//! eigenvalues alone, G&VL §7.5.6). Here the matrix is a fixed-size stack array, nothing is
//! allocated, the transformations are applied only to the active block, and the loops run over
//! contiguous row slices. On the car's 28-state Jacobian (`studies/dtu-cooperrider-car.toml`,
//! Kalker) it takes 46 µs a matrix against 94–110 µs for nalgebra's Schur form
//! (`cargo bench --bench vehicle -- eigenvalues_car`, 2-core machine; the same ratio over 64
//! speeds from 1 to 300 m/s). Once a faer eigenvector solve of that size has run in the
//! process (`spectrum_at`), the upper halves of the vector registers are left dirty on that
//! machine and all (non-VEX) SSE code, this routine's and nalgebra's alike, runs 2 to 3 times
//! slower until something clears them: [`eigenvalues`](super::eigenvalues) clears them
//! (`vzeroupper`) before calling this routine (62–64 µs a matrix against 167–178 µs after
//! faer's solve, measured on the loaded 2-core machine).
//!
//! **The method**, step by step as in the references:
//!
//! 1. *Balancing* (Parlett & Reinsch, Handbook II/11 `balanc`, without its permutation step):
//!    row and column $i$ are scaled by $1/f$ and $f$, $f$ a power of 2 (so the scaling is
//!    exact), until the off-diagonal 1-norms of each row and column are within a factor 2;
//!    the Jacobians here mix m, rad, m/s and rad/s rows, and their entries span many decades.
//! 2. *Hessenberg form* by Householder reflections $P_k = I − v v^T/h$ (Golub & Van Loan,
//!    *Matrix Computations*, 4th ed., Algorithm 7.4.2; the Handbook's `orthes`).
//! 3. *Francis implicit double-shift QR* on the unreduced active block $H_{lo..hi}$ (G&VL
//!    Algorithms 7.5.1 and 7.5.2; the Handbook's `hqr`): a subdiagonal entry is set to zero
//!    when $|h_{k,k−1}| ≤ ε(|h_{k−1,k−1}| + |h_{kk}|)$; the two shifts are the eigenvalues
//!    of the trailing 2×2 block, replaced by `hqr`'s exceptional shifts after 10, 20, …
//!    sweeps without a deflation; the bulge starts where two consecutive subdiagonal entries
//!    are small (`hqr`); after $30N$ sweeps in all the routine gives up (`None`). Only the
//!    rows and columns of the active block are transformed (the eigenvalues do not depend on
//!    the rest).
//! 4. *Eigenvalues of the deflated 1×1 and 2×2 blocks*; a 2×2 block is brought to the
//!    standardised form $\begin{pmatrix} a & b \\ c & a \end{pmatrix}$ by a rotation
//!    (as LAPACK's `dlanv2` does), giving $a ± \sqrt{bc}$, real (with imaginary part exactly 0)
//!    or a complex pair (both $a + i\sqrt{|bc|}$ and $a − i\sqrt{|bc|}$ returned).

use nalgebra::SMatrix;

/// Sweeps per state allowed in all before the iteration is declared failed (`hqr`: 30 N).
const SWEEPS_PER_STATE: usize = 30;

/// Sweeps without a deflation after which (and every so many after that) an exceptional
/// shift is used (`hqr`: after 10 and 20).
const EXCEPTIONAL_AFTER: usize = 10;

/// Most balancing sweeps: the Parlett–Reinsch loop converges in a few; the cap only
/// guarantees termination.
const BALANCE_SWEEPS: usize = 100;

/// A row-major N×N array: row slices are contiguous for the reflections from either side.
type Rows<const N: usize> = [[f64; N]; N];

/// The N eigenvalues of `m` as (re, im), complex pairs as two entries of opposite imaginary
/// parts and real eigenvalues with an imaginary part of exactly 0; `None` if `m` has a
/// non-finite entry, the QR iteration did not converge in $30N$ sweeps, or a result is not
/// finite. The order is the order of the deflated blocks along the diagonal.
pub fn eigenvalues<const N: usize>(m: &SMatrix<f64, N, N>) -> Option<[(f64, f64); N]> {
    if !m.iter().all(|x| x.is_finite()) {
        return None;
    }
    let mut a: Rows<N> = std::array::from_fn(|r| std::array::from_fn(|c| m[(r, c)]));
    balance(&mut a);
    hessenberg(&mut a);
    let ev = hessenberg_eigenvalues(&mut a)?;
    ev.iter()
        .all(|z| z.0.is_finite() && z.1.is_finite())
        .then_some(ev)
}

/// Parlett–Reinsch balancing by powers of 2 (`balanc`'s scaling loop): $A ← D^{-1} A D$.
fn balance<const N: usize>(a: &mut Rows<N>) {
    const RADIX: f64 = 2.0;
    for _ in 0..BALANCE_SWEEPS {
        let mut converged = true;
        for i in 0..N {
            let column: [f64; N] = std::array::from_fn(|j| a[j][i]);
            let mut c = abs_sum(&column[..i]) + abs_sum(&column[i + 1..]);
            let r = abs_sum(&a[i][..i]) + abs_sum(&a[i][i + 1..]);
            if c == 0.0 || r == 0.0 {
                continue;
            }
            // f² ≈ r/c within a factor RADIX: then the scaled sums c f and r/f are balanced
            let total = c + r;
            let mut f = 1.0;
            while c < r / RADIX {
                f *= RADIX;
                c *= RADIX * RADIX;
            }
            while c >= r * RADIX {
                f /= RADIX;
                c /= RADIX * RADIX;
            }
            // scale only for a real gain (`balanc`'s 0.95), so the loop ends
            if (c + r) / f < 0.95 * total {
                converged = false;
                let g = 1.0 / f;
                a[i].iter_mut().for_each(|x| *x *= g);
                a.iter_mut().for_each(|row| row[i] *= f);
            }
        }
        if converged {
            return;
        }
    }
}

/// Reduction to upper Hessenberg form by Householder reflections (G&VL Algorithm 7.4.2):
/// for each column k, $P = I − v v^T/h$ maps $a_{k+1.., k}$ onto a multiple of $e_1$, and
/// $A ← P A P$. Entries below the subdiagonal are set to exact zeros.
fn hessenberg<const N: usize>(a: &mut Rows<N>) {
    let mut v = [0.0; N];
    let mut w = [0.0; N];
    for k in 0..N.saturating_sub(2) {
        let s = k + 1;
        // scaled by the 1-norm so that the squares neither overflow nor underflow
        let scale: f64 = a[s..].iter().map(|row| row[k].abs()).sum();
        if scale == 0.0 {
            continue;
        }
        let mut h = 0.0;
        for (vi, row) in v[s..].iter_mut().zip(&a[s..]) {
            *vi = row[k] / scale;
            h += *vi * *vi;
        }
        // v = x − g e₁ with g = −sign(x₀)‖x‖ (no cancellation); h = vᵀv/2 = ‖x‖² − g x₀
        let g = -h.sqrt().copysign(v[s]);
        h -= v[s] * g;
        v[s] -= g;
        // A ← P A P in two passes: wᵀ = vᵀA/h over rows s.., then row by row the left
        // update (rows s.., columns s..; column k is set below) and the right one (all rows)
        let inv_h = 1.0 / h;
        w[s..].fill(0.0);
        for (vi, row) in v[s..].iter().zip(&a[s..]) {
            for (wj, x) in w[s..].iter_mut().zip(&row[s..]) {
                *wj += vi * x;
            }
        }
        w[s..].iter_mut().for_each(|x| *x *= inv_h);
        for (i, row) in a.iter_mut().enumerate() {
            if i >= s {
                let vi = v[i];
                for (x, wj) in row[s..].iter_mut().zip(&w[s..]) {
                    *x -= vi * wj;
                }
            }
            let f = dot(&row[s..], &v[s..]) * inv_h;
            for (x, vj) in row[s..].iter_mut().zip(&v[s..]) {
                *x -= f * vj;
            }
        }
        a[s][k] = scale * g;
        a[s + 1..].iter_mut().for_each(|row| row[k] = 0.0);
    }
}

/// $\sum_i |x_i|$ in four interleaved partial sums (one serial chain of additions is bound
/// by their latency). The non-generic helpers here are `#[inline]`: their generic callers
/// are compiled in the crates that call [`eigenvalues`] (benches, the CLI), which could not
/// inline them otherwise.
#[inline]
fn abs_sum(x: &[f64]) -> f64 {
    let mut acc = [0.0; 4];
    let chunks = x.chunks_exact(4);
    let tail: f64 = chunks.remainder().iter().map(|a| a.abs()).sum();
    for a in chunks {
        for i in 0..4 {
            acc[i] += a[i].abs();
        }
    }
    (acc[0] + acc[2]) + (acc[1] + acc[3]) + tail
}

/// $x^T y$ in four interleaved partial sums: one serial chain of additions would bound the
/// Hessenberg reduction's speed by the addition latency.
#[inline]
fn dot(x: &[f64], y: &[f64]) -> f64 {
    let mut acc = [0.0; 4];
    let (xc, yc) = (x.chunks_exact(4), y.chunks_exact(4));
    let tail: f64 = xc
        .remainder()
        .iter()
        .zip(yc.remainder())
        .map(|(a, b)| a * b)
        .sum();
    for (a, b) in xc.zip(yc) {
        for i in 0..4 {
            acc[i] += a[i] * b[i];
        }
    }
    (acc[0] + acc[2]) + (acc[1] + acc[3]) + tail
}

/// The shift polynomial $q(λ) = (λ − x)(λ − y) − w$ of a double-shift sweep (`hqr`'s form:
/// the first column of $q(H)$ is then computed from differences $x − h_{mm}$, without the
/// cancellation of $λ^2 − sλ + t$ when the shifts are large).
#[derive(Clone, Copy)]
struct Shifts {
    x: f64,
    y: f64,
    w: f64,
}

/// Eigenvalues of an upper Hessenberg matrix by the Francis double-shift QR iteration
/// (G&VL Algorithm 7.5.2 without the Schur vectors; the Handbook's `hqr`). `h` is destroyed.
fn hessenberg_eigenvalues<const N: usize>(h: &mut Rows<N>) -> Option<[(f64, f64); N]> {
    let mut ev = [(0.0, 0.0); N];
    // the deflation test's scale where both neighbouring diagonal entries are zero
    let norm: f64 = (0..N)
        .map(|i| {
            h[i][i.saturating_sub(1)..]
                .iter()
                .map(|x| x.abs())
                .sum::<f64>()
        })
        .sum();
    let mut budget = SWEEPS_PER_STATE * N;
    let mut since_deflation = 0;
    let mut next_exceptional = EXCEPTIONAL_AFTER;
    // rows and columns end.. are done
    let mut end = N;
    while end > 0 {
        let hi = end - 1;
        let lo = split(h, hi, norm);
        if lo + 1 >= hi {
            if lo == hi {
                ev[hi] = (h[hi][hi], 0.0);
            } else {
                [ev[lo], ev[hi]] = block_eigenvalues(h[lo][lo], h[lo][hi], h[hi][lo], h[hi][hi]);
            }
            end = lo;
            since_deflation = 0;
            next_exceptional = EXCEPTIONAL_AFTER;
            continue;
        }
        if since_deflation >= next_exceptional {
            // `hqr`'s ad hoc shifts, from the size of the last two subdiagonal entries
            next_exceptional += EXCEPTIONAL_AFTER;
            let e = h[hi][hi - 1].abs() + h[hi - 1][hi - 2].abs();
            let x = h[hi][hi] + 0.75 * e;
            let w = -0.4375 * e * e;
            budget = budget.checked_sub(1)?;
            since_deflation += 1;
            francis_sweep(h, lo, hi, Shifts { x, y: x, w });
            continue;
        }
        budget = budget.checked_sub(1)?;
        since_deflation += 1;
        let shifts = Shifts {
            x: h[hi][hi],
            y: h[hi - 1][hi - 1],
            w: h[hi][hi - 1] * h[hi - 1][hi],
        };
        francis_sweep(h, lo, hi, shifts);
    }
    Some(ev)
}

/// The top `lo` of the unreduced block ending at `hi`: the largest index ≤ `hi` whose
/// subdiagonal entry is negligible against its diagonal neighbours (set to 0 there), or 0.
fn split<const N: usize>(h: &mut Rows<N>, hi: usize, norm: f64) -> usize {
    let mut l = hi;
    while l > 0 {
        let mut s = h[l - 1][l - 1].abs() + h[l][l].abs();
        if s == 0.0 {
            s = norm;
        }
        if h[l][l - 1].abs() <= f64::EPSILON * s {
            h[l][l - 1] = 0.0;
            break;
        }
        l -= 1;
    }
    l
}

/// The first column $(x, y, z)$ of $q(H)$ at row `m` (only its direction matters), from
/// the differences of `hqr`'s form and without divisions (this is evaluated at every row the
/// bulge could start from). It overflows only for entries beyond about $10^{100}$, and then
/// the sweep makes no reflection and the iteration gives up.
fn first_column<const N: usize>(h: &Rows<N>, m: usize, q: Shifts) -> (f64, f64, f64) {
    let z = h[m][m];
    let (r, s) = (q.x - z, q.y - z);
    let h21 = h[m + 1][m];
    (
        r * s - q.w + h[m][m + 1] * h21,
        h21 * (h[m + 1][m + 1] - z - r - s),
        h21 * h[m + 2][m + 1],
    )
}

/// One implicit double-shift sweep on the unreduced block `lo..=hi` (at least 3×3; G&VL
/// Algorithm 7.5.1): the bulge made by $q(H)e_1$ at the start row `m` is chased down by
/// 3×3 reflections $P_k$ on rows and columns k..k+2 and a last 2×2 one. Each $P_k$ is made
/// from column k−1 (from $q(H)e_1$ at k = m) and applied from the left to columns k..=hi and
/// from the right to rows lo..=k+3: the active block only.
fn francis_sweep<const N: usize>(h: &mut Rows<N>, lo: usize, hi: usize, shifts: Shifts) {
    let (m, (x, y, z)) = bulge_start(h, lo, hi, shifts);
    for k in m..hi {
        let three = k + 2 <= hi;
        let (p, q, r) = if k == m {
            (x, y, z)
        } else {
            (
                h[k][k - 1],
                h[k + 1][k - 1],
                if three { h[k + 2][k - 1] } else { 0.0 },
            )
        };
        let Some(refl) = Reflector::new(p, q, r, three) else {
            continue;
        };
        if k > m {
            // the reflection maps column k−1's bulge onto (β, 0, 0)
            h[k][k - 1] = refl.beta;
            h[k + 1][k - 1] = 0.0;
            if three {
                h[k + 2][k - 1] = 0.0;
            }
        } else if m > lo {
            // the reflection's (1,1) entry; its fill-in below is negligible (bulge_start)
            h[k][k - 1] *= 1.0 - refl.tau;
        }
        refl.left(h, k, hi);
        refl.right(&mut h[lo..=(k + 3).min(hi)], k);
    }
}

/// The row `m` where the bulge starts and the first column of $q(H)$ there (`hqr`): the
/// lowest row above which two consecutive subdiagonal entries have a negligible product, so
/// that the sweep leaves the block above alone; `lo` if there is none.
fn bulge_start<const N: usize>(
    h: &Rows<N>,
    lo: usize,
    hi: usize,
    shifts: Shifts,
) -> (usize, (f64, f64, f64)) {
    let mut m = hi - 2;
    loop {
        let (x, y, z) = first_column(h, m, shifts);
        if m == lo {
            return (m, (x, y, z));
        }
        // the fill-in h_{m,m−1}(y, z)/x of a start at m is negligible against the diagonal
        let u = h[m][m - 1].abs() * (y.abs() + z.abs());
        let v = x.abs() * (h[m - 1][m - 1].abs() + h[m][m].abs() + h[m + 1][m + 1].abs());
        if u <= f64::EPSILON * v {
            return (m, (x, y, z));
        }
        m -= 1;
    }
}

/// Below this sum of squares a reflection's vector is scaled first (then no square loses
/// more than ε relative to it by underflow).
const SAFE_SQUARES: f64 = f64::MIN_POSITIVE / f64::EPSILON;

/// A Householder reflection $I − τ u u^T$, $u = (1, u_1, u_2)$ ($u_2 = 0$ for a 2×2 one),
/// mapping $(p, q, r)$ to $(β, 0, 0)$ (the convention of LAPACK's `dlarfg`).
struct Reflector {
    u1: f64,
    u2: f64,
    tau: f64,
    beta: f64,
    /// 3×3 (else 2×2, acting on two rows and columns)
    three: bool,
}

impl Reflector {
    /// `None` when $q = r = 0$ (nothing to annihilate) or an entry is not finite (then the
    /// iteration stops deflating and gives up after its sweeps).
    #[inline]
    fn new(p: f64, q: f64, r: f64, three: bool) -> Option<Self> {
        if q == 0.0 && r == 0.0 {
            return None;
        }
        let squares = p * p + q * q + r * r;
        if squares.is_finite() && squares >= SAFE_SQUARES {
            return Some(Self::from_norm(p, q, r, squares.sqrt(), three));
        }
        // scaled by the 1-norm where the squares would overflow or underflow (rare: kept off
        // the common path, whose divisions and square root are the sweep's serial chain)
        let scale = p.abs() + q.abs() + r.abs();
        if !scale.is_finite() {
            return None;
        }
        let (p, q, r) = (p / scale, q / scale, r / scale);
        let mut refl = Self::from_norm(p, q, r, (p * p + q * q + r * r).sqrt(), three);
        refl.beta *= scale;
        Some(refl)
    }

    /// From $(p, q, r)$ and its 2-norm.
    #[inline]
    fn from_norm(p: f64, q: f64, r: f64, norm: f64, three: bool) -> Self {
        let beta = -norm.copysign(p);
        // p − β = p + sign(p)‖·‖: no cancellation
        let d = p - beta;
        let inv = 1.0 / d;
        Self {
            u1: q * inv,
            u2: r * inv,
            tau: -d / beta,
            beta,
            three,
        }
    }

    /// From the right on columns k..k+2 (or k..k+1) of `rows`.
    fn right<const N: usize>(&self, rows: &mut [[f64; N]], k: usize) {
        let (t0, t1, t2) = (self.tau, self.tau * self.u1, self.tau * self.u2);
        if self.three {
            for row in rows {
                let x = &mut row[k..k + 3];
                let s = t0 * x[0] + t1 * x[1] + t2 * x[2];
                x[0] -= s;
                x[1] -= s * self.u1;
                x[2] -= s * self.u2;
            }
        } else {
            for row in rows {
                let x = &mut row[k..k + 2];
                let s = t0 * x[0] + t1 * x[1];
                x[0] -= s;
                x[1] -= s * self.u1;
            }
        }
    }

    /// From the left on rows k, k+1 (and k+2), columns k..=hi.
    fn left<const N: usize>(&self, h: &mut Rows<N>, k: usize, hi: usize) {
        let (top, rest) = h.split_at_mut(k + 1);
        let (mid, bottom) = rest.split_at_mut(1);
        let a = &mut top[k][k..=hi];
        let b = &mut mid[0][k..=hi];
        if self.three {
            let c = &mut bottom[0][k..=hi];
            for ((a, b), c) in a.iter_mut().zip(b.iter_mut()).zip(c.iter_mut()) {
                let s = self.tau * (*a + self.u1 * *b + self.u2 * *c);
                *a -= s;
                *b -= s * self.u1;
                *c -= s * self.u2;
            }
        } else {
            for (a, b) in a.iter_mut().zip(b.iter_mut()) {
                let s = self.tau * (*a + self.u1 * *b);
                *a -= s;
                *b -= s * self.u1;
            }
        }
    }
}

/// The eigenvalues of $\begin{pmatrix} a & b \\ c & d \end{pmatrix}$, real ones with an
/// imaginary part of exactly 0, a complex pair as (re, +im), (re, −im).
///
/// Well separated real eigenvalues come from the root formula without cancellation; otherwise
/// a rotation $R^T A R$ makes the diagonal entries equal (the standardised form of LAPACK's
/// `dlanv2`), $\begin{pmatrix} a' & b' \\ c' & a' \end{pmatrix}$, whose eigenvalues are
/// $a' ± \sqrt{b'c'}$.
#[inline]
fn block_eigenvalues(a: f64, b: f64, c: f64, d: f64) -> [(f64, f64); 2] {
    if c == 0.0 || b == 0.0 {
        return [(a, 0.0), (d, 0.0)];
    }
    let p = 0.5 * (a - d);
    if p == 0.0 && b.signum() != c.signum() {
        // already standardised: a complex pair
        let im = b.abs().sqrt() * c.abs().sqrt();
        return [(a, im), (a, -im)];
    }
    // discriminant p² + bc, scaled
    let bc_max = b.abs().max(c.abs());
    let bc_min = b.abs().min(c.abs()) * b.signum() * c.signum();
    let scale = p.abs().max(bc_max);
    let z = p / scale * p + bc_max / scale * bc_min;
    if z >= 4.0 * f64::EPSILON * scale {
        // real and apart by more than about √ε of the block's size (`dlanv2` compares z itself
        // with 4ε; relative here): the larger root without cancellation, the other from the
        // product
        let z = p + (scale.sqrt() * z.sqrt()).copysign(p);
        return [(d + z, 0.0), (d - bc_max / z * bc_min, 0.0)];
    }
    // rotation by θ with tan 2θ = −2p/(b + c), cos 2θ ≥ 0: equal diagonal entries after it
    let sigma = b + c;
    let tau = sigma.hypot(2.0 * p);
    let cs = (0.5 * (1.0 + sigma.abs() / tau)).sqrt();
    let sn = -(p / (tau * cs)) * if sigma < 0.0 { -1.0 } else { 1.0 };
    let (cs2, sn2, csn) = (cs * cs, sn * sn, cs * sn);
    let a2 = a * cs2 + sigma * csn + d * sn2;
    let d2 = a * sn2 - sigma * csn + d * cs2;
    let b2 = b * cs2 - c * sn2 + (d - a) * csn;
    let c2 = c * cs2 - b * sn2 + (d - a) * csn;
    let mean = 0.5 * (a2 + d2);
    let root = b2.abs().sqrt() * c2.abs().sqrt();
    if b2 == 0.0 || c2 == 0.0 || b2.signum() == c2.signum() {
        [(mean + root, 0.0), (mean - root, 0.0)]
    } else {
        [(mean, root), (mean, -root)]
    }
}

#[cfg(test)]
#[path = "small_eigen_tests.rs"]
mod tests;
