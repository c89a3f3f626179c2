//! One step of Dormand and Prince's explicit Runge–Kutta method of order 8 with its 5th- and
//! 3rd-order error estimators and its 7th-order continuous extension ("DOP853"), on the same
//! augmented system $(x, \Phi)$ as the 5th-order method of [`super::dopri`].
//!
//! Coefficients: P. J. Prince & J. R. Dormand, "High order embedded Runge–Kutta formulae",
//! J. Comput. Appl. Math. 7 (1981) 67–75, as modified and published by E. Hairer and
//! G. Wanner with their code DOP853 (Hairer, Nørsett & Wanner, *Solving Ordinary Differential
//! Equations I*, 2nd ed., §II.10, and the dense output of §II.6). The numbers below are that
//! published table; the code around them is this crate's.
//!
//! **Why an 8th-order method.** The continuation solves every cycle at rtol 1e-10. There a
//! step of the 5th-order method is about $\mathrm{rtol}^{1/5}$ of the time scale and one of
//! the 8th-order method about $\mathrm{rtol}^{1/8}$: on the cone wheelset's branch the
//! 12 evaluations of a DOP853 step replace about four 6-evaluation steps (the counts are in
//! docs/performance.md).
//!
//! **The step.** 12 stages, the 12th at $c = 1$ but not the new point; the new point's $f$
//! (and $J\Phi$) is evaluated as a 13th stage, as the 5th-order method does (FSAL), so that
//! the next step starts from it. Error: Hairer's blend of the 5th-order estimate $e_5$ and
//! the 3rd-order one $e_3$, $\|e\| = \|e_5\|^2 / \sqrt{\|e_5\|^2 + 0.01\|e_3\|^2}$, each norm
//! the scaled RMS of [`super::dopri`] (for $\Phi$ column by column, as there).
//!
//! **Continuous extension.** Three more evaluations of $f$ (not of $J\Phi$) give a
//! polynomial of degree 7 in $\theta$; they are spent only when a caller asks for the step's
//! dense output. The partial sums of the stages that enter them are formed with the step and
//! kept in [`Trial`] (seven vectors), so that the stages themselves need not be kept.

use nalgebra::{SMatrix, SVector};

use super::dopri::{scaled_rms, Carried, Dense, Point, Rk, Trial};
use super::{Method, VectorField};

/// A sparse row of coefficients: `(stage index, coefficient)`, stages numbered from 0.
type Row = &'static [(usize, f64)];

// Stage coefficients a_ij (DOP853's table; i is the stage, 1-based as published).
const A21: f64 = 0.05260015195876773;
const A31: f64 = 0.0197250569845379;
const A32: f64 = 0.0591751709536137;
const A41: f64 = 0.02958758547680685;
const A43: f64 = 0.08876275643042054;
const A51: f64 = 0.2413651341592667;
const A53: f64 = -0.8845494793282861;
const A54: f64 = 0.924834003261792;
const A61: f64 = 0.037037037037037035;
const A64: f64 = 0.17082860872947386;
const A65: f64 = 0.12546768756682242;
const A71: f64 = 0.037109375;
const A74: f64 = 0.17025221101954405;
const A75: f64 = 0.06021653898045596;
const A76: f64 = -0.017578125;
const A81: f64 = 0.03709200011850479;
const A84: f64 = 0.17038392571223998;
const A85: f64 = 0.10726203044637328;
const A86: f64 = -0.015319437748624402;
const A87: f64 = 0.008273789163814023;
const A91: f64 = 0.6241109587160757;
const A94: f64 = -3.3608926294469414;
const A95: f64 = -0.868219346841726;
const A96: f64 = 27.59209969944671;
const A97: f64 = 20.154067550477894;
const A98: f64 = -43.48988418106996;
const A101: f64 = 0.47766253643826434;
const A104: f64 = -2.4881146199716677;
const A105: f64 = -0.590290826836843;
const A106: f64 = 21.230051448181193;
const A107: f64 = 15.279233632882423;
const A108: f64 = -33.28821096898486;
const A109: f64 = -0.020331201708508627;
const A111: f64 = -0.9371424300859873;
const A114: f64 = 5.186372428844064;
const A115: f64 = 1.0914373489967295;
const A116: f64 = -8.149787010746927;
const A117: f64 = -18.52006565999696;
const A118: f64 = 22.739487099350505;
const A119: f64 = 2.4936055526796523;
const A1110: f64 = -3.0467644718982196;
const A121: f64 = 2.273310147516538;
const A124: f64 = -10.53449546673725;
const A125: f64 = -2.0008720582248625;
const A126: f64 = -17.9589318631188;
const A127: f64 = 27.94888452941996;
const A128: f64 = -2.8589982771350235;
const A129: f64 = -8.87285693353063;
const A1210: f64 = 12.360567175794303;
const A1211: f64 = 0.6433927460157636;

// Weights of the 8th-order solution.
const B1: f64 = 0.054293734116568765;
const B6: f64 = 4.450312892752409;
const B7: f64 = 1.8915178993145003;
const B8: f64 = -5.801203960010585;
const B9: f64 = 0.3111643669578199;
const B10: f64 = -0.1521609496625161;
const B11: f64 = 0.20136540080403034;
const B12: f64 = 0.04471061572777259;
// Weights of the 3rd-order estimator.
const BHH1: f64 = 0.2440944881889764;
const BHH2: f64 = 0.7338466882816118;
const BHH3: f64 = 0.022058823529411766;
// The 5th-order error estimator e_i.
const ER1: f64 = 0.01312004499419488;
const ER6: f64 = -1.2251564463762044;
const ER7: f64 = -0.4957589496572502;
const ER8: f64 = 1.6643771824549864;
const ER9: f64 = -0.35032884874997366;
const ER10: f64 = 0.3341791187130175;
const ER11: f64 = 0.08192320648511571;
const ER12: f64 = -0.022355307863886294;

// The three extra stages of the continuous extension.
const A141: f64 = 0.056167502283047954;
const A147: f64 = 0.25350021021662483;
const A148: f64 = -0.2462390374708025;
const A149: f64 = -0.12419142326381637;
const A1410: f64 = 0.15329179827876568;
const A1411: f64 = 0.00820105229563469;
const A1412: f64 = 0.007567897660545699;
const A1413: f64 = -0.008298;
const A151: f64 = 0.03183464816350214;
const A156: f64 = 0.028300909672366776;
const A157: f64 = 0.053541988307438566;
const A158: f64 = -0.05492374857139099;
const A1511: f64 = -0.00010834732869724932;
const A1512: f64 = 0.0003825710908356584;
const A1513: f64 = -0.00034046500868740456;
const A1514: f64 = 0.1413124436746325;
const A161: f64 = -0.42889630158379194;
const A166: f64 = -4.697621415361164;
const A167: f64 = 7.683421196062599;
const A168: f64 = 4.06898981839711;
const A169: f64 = 0.3567271874552811;
const A1613: f64 = -0.0013990241651590145;
const A1614: f64 = 2.9475147891527724;
const A1615: f64 = -9.15095847217987;

// Dense-output coefficients d_ij, i = 4..7 (the 5th to 8th coefficient vectors).
const D: [[f64; 12]; 4] = [
    [
        -8.428938276109013,
        0.5667149535193777,
        -3.0689499459498917,
        2.38466765651207,
        2.117034582445028,
        -0.871391583777973,
        2.2404374302607883,
        0.6315787787694688,
        -0.08899033645133331,
        18.148505520854727,
        -9.194632392478356,
        -4.436036387594894,
    ],
    [
        10.427508642579134,
        242.28349177525817,
        165.20045171727028,
        -374.5467547226902,
        -22.113666853125306,
        7.733432668472264,
        -30.674084731089398,
        -9.332130526430229,
        15.697238121770845,
        -31.139403219565178,
        -9.35292435884448,
        35.81684148639408,
    ],
    [
        19.985053242002433,
        -387.0373087493518,
        -189.17813819516758,
        527.8081592054236,
        -11.57390253995963,
        6.8812326946963,
        -1.0006050966910838,
        0.7777137798053443,
        -2.778205752353508,
        -60.19669523126412,
        84.32040550667716,
        11.99229113618279,
    ],
    [
        -25.69393346270375,
        -154.18974869023643,
        -231.5293791760455,
        357.6391179106141,
        93.40532418362432,
        -37.45832313645163,
        104.0996495089623,
        29.8402934266605,
        -43.53345659001114,
        96.32455395918828,
        -39.17726167561544,
        -149.72683625798564,
    ],
];
/// The stages each row of [`D`] multiplies: 0, 5, …, 12, then the extra stages 14, 15, 16
/// (the last three entries of a row).
const D_STAGES: [usize; 9] = [0, 5, 6, 7, 8, 9, 10, 11, 12];

/// Stages 2 to 12: the nonzero $a_{ij}$ of each.
const STAGES: [Row; 11] = [
    &[(0, A21)],
    &[(0, A31), (1, A32)],
    &[(0, A41), (2, A43)],
    &[(0, A51), (2, A53), (3, A54)],
    &[(0, A61), (3, A64), (4, A65)],
    &[(0, A71), (3, A74), (4, A75), (5, A76)],
    &[(0, A81), (3, A84), (4, A85), (5, A86), (6, A87)],
    &[(0, A91), (3, A94), (4, A95), (5, A96), (6, A97), (7, A98)],
    &[
        (0, A101),
        (3, A104),
        (4, A105),
        (5, A106),
        (6, A107),
        (7, A108),
        (8, A109),
    ],
    &[
        (0, A111),
        (3, A114),
        (4, A115),
        (5, A116),
        (6, A117),
        (7, A118),
        (8, A119),
        (9, A1110),
    ],
    &[
        (0, A121),
        (3, A124),
        (4, A125),
        (5, A126),
        (6, A127),
        (7, A128),
        (8, A129),
        (9, A1210),
        (10, A1211),
    ],
];
const WEIGHTS: Row = &[
    (0, B1),
    (5, B6),
    (6, B7),
    (7, B8),
    (8, B9),
    (9, B10),
    (10, B11),
    (11, B12),
];
const ERR5: Row = &[
    (0, ER1),
    (5, ER6),
    (6, ER7),
    (7, ER8),
    (8, ER9),
    (9, ER10),
    (10, ER11),
    (11, ER12),
];
/// $b - \hat b^{(3)}$: the 8th-order increment less the 3rd-order one.
const ERR3: Row = &[
    (0, B1 - BHH1),
    (5, B6),
    (6, B7),
    (7, B8),
    (8, B9 - BHH2),
    (9, B10),
    (10, B11),
    (11, B12 - BHH3),
];
/// The known part of the extra stages' arguments (stage 13 is $f$ at the new point).
const STAGE14: Row = &[
    (0, A141),
    (6, A147),
    (7, A148),
    (8, A149),
    (9, A1410),
    (10, A1411),
    (11, A1412),
    (12, A1413),
];
const STAGE15: Row = &[
    (0, A151),
    (5, A156),
    (6, A157),
    (7, A158),
    (10, A1511),
    (11, A1512),
    (12, A1513),
];
const STAGE16: Row = &[
    (0, A161),
    (5, A166),
    (6, A167),
    (7, A168),
    (8, A169),
    (12, A1613),
];

/// Nodes $c_1, \dots, c_{12}$ (only the tests use them: the field is autonomous).
#[cfg(test)]
pub(super) const NODES: [f64; 12] = [
    0.0,
    0.05260015195876773,
    0.0789002279381516,
    0.1183503419072274,
    0.2816496580927726,
    1.0 / 3.0,
    0.25,
    4.0 / 13.0,
    0.6512820512820513,
    0.6,
    6.0 / 7.0,
    1.0,
];
#[cfg(test)]
pub(super) const TEST_STAGES: [Row; 11] = STAGES;
#[cfg(test)]
pub(super) const TEST_WEIGHTS: Row = WEIGHTS;

/// Number of stages a step keeps (12 and the new point's $f$).
const KEPT: usize = 13;

/// $s = y + h\sum_{(j, a)} a\,k_j$ over a sparse row, entry by entry (each entry's sum runs
/// over the terms in order, written once: see [`super::dopri`]'s `combine` for why).
#[inline(always)]
pub(super) fn sparse<const R: usize, const CC: usize>(
    y: &SMatrix<f64, R, CC>,
    h: f64,
    row: &[(usize, f64)],
    k: &[SMatrix<f64, R, CC>],
) -> SMatrix<f64, R, CC> {
    match row.len() {
        1 => sparse_n::<R, CC, 1>(y, h, row, k),
        2 => sparse_n::<R, CC, 2>(y, h, row, k),
        3 => sparse_n::<R, CC, 3>(y, h, row, k),
        4 => sparse_n::<R, CC, 4>(y, h, row, k),
        5 => sparse_n::<R, CC, 5>(y, h, row, k),
        6 => sparse_n::<R, CC, 6>(y, h, row, k),
        7 => sparse_n::<R, CC, 7>(y, h, row, k),
        8 => sparse_n::<R, CC, 8>(y, h, row, k),
        9 => sparse_n::<R, CC, 9>(y, h, row, k),
        // no row of the table is longer
        _ => {
            let mut s = *y;
            for &(j, a) in row {
                for (si, ki) in s.as_mut_slice().iter_mut().zip(k[j].as_slice()) {
                    *si += h * a * ki;
                }
            }
            s
        }
    }
}

#[inline(always)]
fn sparse_n<const R: usize, const CC: usize, const M: usize>(
    y: &SMatrix<f64, R, CC>,
    h: f64,
    row: &[(usize, f64)],
    k: &[SMatrix<f64, R, CC>],
) -> SMatrix<f64, R, CC> {
    let c: [f64; M] = std::array::from_fn(|j| h * row[j].1);
    let ks: [&[f64]; M] = std::array::from_fn(|j| k[row[j].0].as_slice());
    let mut s = *y;
    for (e, si) in s.as_mut_slice().iter_mut().enumerate() {
        let mut acc = *si;
        for j in 0..M {
            acc += c[j] * ks[j][e];
        }
        *si = acc;
    }
    s
}

/// Hairer's blend of the two estimators' scaled norms: $e_5^2/\sqrt{e_5^2 + 0.01\,e_3^2}$
/// (0 when $e_5 = 0$; a NaN stays a NaN and rejects the step).
fn blend(e5: f64, e3: f64) -> f64 {
    let d = e5 * e5 + 0.01 * e3 * e3;
    if d > 0.0 {
        e5 * e5 / d.sqrt()
    } else if d.is_nan() {
        f64::NAN
    } else {
        0.0
    }
}

impl<const N: usize, F: VectorField<N>> Rk<'_, N, F> {
    /// One DOP853 step of size `h` from `p0` (12 new evaluations: 11 stages and the new
    /// point). The error is the larger of the state's and $\Phi$'s blended norms.
    pub(super) fn step8<C: Carried<N>>(&mut self, p0: &Point<N, C>, h: f64) -> Trial<N, C> {
        let mut k = [SVector::<f64, N>::zeros(); KEPT];
        let mut kp = [C::zero(); KEPT];
        k[0] = p0.f;
        kp[0] = p0.f_phi;
        for (s, row) in STAGES.iter().enumerate() {
            let xs = sparse(&p0.x, h, row, &k);
            (k[s + 1], kp[s + 1]) = if self.variational {
                let phis = C::combine_sparse(&p0.phi, h, row, &kp);
                self.eval(&xs, &phis)
            } else {
                self.eval(&xs, &p0.phi)
            };
        }
        let x1 = sparse(&p0.x, h, WEIGHTS, &k);
        let phi1 = if self.variational {
            C::combine_sparse(&p0.phi, h, WEIGHTS, &kp)
        } else {
            p0.phi
        };
        (k[12], kp[12]) = self.eval(&x1, &phi1);
        let zero = SVector::<f64, N>::zeros();
        let e5 = scaled_rms(&sparse(&zero, h, ERR5, &k), &p0.x, &x1, &self.tol);
        let e3 = scaled_rms(&sparse(&zero, h, ERR3, &k), &p0.x, &x1, &self.tol);
        let mut err = blend(e5, e3);
        if self.variational {
            let z = C::zero();
            let tol = &self.tol_phi;
            let p5 = C::error(&C::combine_sparse(&z, h, ERR5, &kp), &p0.phi, &phi1, tol);
            let p3 = C::error(&C::combine_sparse(&z, h, ERR3, &kp), &p0.phi, &phi1, tol);
            err = err.max(blend(p5, p3));
        }
        // the known parts of the continuous extension's sums (unscaled by h)
        let mut kept = [zero; 7];
        kept[0] = sparse(&zero, 1.0, STAGE14, &k);
        kept[1] = sparse(&zero, 1.0, STAGE15, &k);
        kept[2] = sparse(&zero, 1.0, STAGE16, &k);
        for (i, d) in D.iter().enumerate() {
            let mut s = zero;
            for (&j, &dj) in D_STAGES.iter().zip(d.iter()) {
                s.axpy(dj, &k[j], 1.0);
            }
            kept[3 + i] = s;
        }
        let end = Point {
            t: p0.t + h,
            x: x1,
            phi: phi1,
            f: k[12],
            f_phi: kp[12],
        };
        Trial {
            end,
            err,
            k: kept,
            method: Method::DormandPrince8,
        }
    }

    /// The 7th-order continuous extension of a DOP853 step: three more evaluations of $f$.
    pub(super) fn dense8<C>(&mut self, p0: &Point<N, C>, trial: &Trial<N, C>) -> Dense<N> {
        let h = trial.end.t - p0.t;
        let kept = &trial.k;
        self.rhs_evals += 3;
        let k14 = self.field.rhs(&(p0.x + kept[0] * h), self.p);
        let k15 = self
            .field
            .rhs(&(p0.x + (kept[1] + k14 * A1514) * h), self.p);
        let k16 = self
            .field
            .rhs(&(p0.x + (kept[2] + k14 * A1614 + k15 * A1615) * h), self.p);
        let r1 = trial.end.x - p0.x;
        let r2 = p0.f * h - r1;
        let r3 = r1 - trial.end.f * h - r2;
        let tail = |i: usize| {
            let d = &D[i];
            (kept[3 + i] + k14 * d[9] + k15 * d[10] + k16 * d[11]) * h
        };
        Dense::degree7(
            p0.t,
            h,
            [p0.x, r1, r2, r3, tail(0), tail(1), tail(2), tail(3)],
        )
    }
}
