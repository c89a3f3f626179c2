//! The sample design: the parameters' distributions (inverse CDFs) and the Saltelli matrices
//! A, B and A_B^(i) drawn from scrambled Sobol points or seeded random numbers.
//!
//! Evaluation ids are block-major: with N base samples and d parameters, id `k·N + j` is row
//! `j` of block `k`, where block 0 is A, block 1 is B and block `2 + i` is A_B^(i) (A with
//! column `i` taken from B). Without indices only block A is evaluated.

/// A parameter's distribution, values in SI.
#[derive(Clone, Debug, PartialEq)]
pub enum Distribution {
    /// uniform on `[from, to]`
    Uniform {
        /// lower end
        from: f64,
        /// upper end (> from)
        to: f64,
    },
    /// normal, optionally truncated to `[from, to]`
    Normal {
        /// mean
        mean: f64,
        /// standard deviation (> 0)
        std: f64,
        /// truncation: lower end (`-inf` when none)
        from: f64,
        /// truncation: upper end (`inf` when none)
        to: f64,
    },
    /// lognormal: `median · factor^z`, z standard normal (`factor` = exp σ > 1)
    Lognormal {
        /// median (> 0)
        median: f64,
        /// the ratio of the 84th percentile to the median (> 1)
        factor: f64,
    },
    /// one of `values` with probabilities proportional to `weights`
    Choice {
        /// the values
        values: Vec<f64>,
        /// their weights (≥ 0, positive sum)
        weights: Vec<f64>,
    },
}

impl Distribution {
    /// The value at probability `u` (0 < u < 1): the inverse CDF.
    pub fn quantile(&self, u: f64) -> f64 {
        match self {
            Distribution::Uniform { from, to } => from + (to - from) * u,
            Distribution::Normal {
                mean,
                std,
                from,
                to,
            } => {
                // truncation: u is mapped into [F(from), F(to)]; F by erfc (relative error
                // below 1.2e-7), so the result is clamped to the interval as well
                let lo = normal_cdf((from - mean) / std);
                let hi = normal_cdf((to - mean) / std);
                let p = (lo + (hi - lo) * u).clamp(f64::MIN_POSITIVE, 1.0 - f64::EPSILON / 2.0);
                (mean + std * normal_quantile(p)).clamp(*from, *to)
            }
            Distribution::Lognormal { median, factor } => median * factor.powf(normal_quantile(u)),
            Distribution::Choice { values, weights } => {
                let total: f64 = weights.iter().sum();
                let mut acc = 0.0;
                for (v, w) in values.iter().zip(weights) {
                    acc += w;
                    if u * total < acc {
                        return *v;
                    }
                }
                // u·total reaches the sum only by rounding: the last value with a weight
                values
                    .iter()
                    .zip(weights)
                    .rev()
                    .find(|(_, w)| **w > 0.0)
                    .map_or(f64::NAN, |(v, _)| *v)
            }
        }
    }

    /// The distribution's name in the study file.
    pub fn name(&self) -> &'static str {
        match self {
            Distribution::Uniform { .. } => "uniform",
            Distribution::Normal { .. } => "normal",
            Distribution::Lognormal { .. } => "lognormal",
            Distribution::Choice { .. } => "choice",
        }
    }
}

/// The standard normal quantile Φ⁻¹(p), 0 < p < 1, by Wichura's algorithm AS 241 (PPND16,
/// Applied Statistics 37, 1988): rational approximations with relative error about 1e-16.
pub fn normal_quantile(p: f64) -> f64 {
    const A: [f64; 8] = [
        3.387_132_872_796_366_6,
        133.141_667_891_784_38,
        1_971.590_950_306_551_4,
        13_731.693_765_509_46,
        45_921.953_931_549_87,
        67_265.770_927_008_7,
        33_430.575_583_588_13,
        2_509.080_928_730_122_7,
    ];
    const B: [f64; 8] = [
        1.0,
        42.313_330_701_600_91,
        687.187_007_492_057_9,
        5_394.196_021_424_751,
        21_213.794_301_586_597,
        39_307.895_800_092_71,
        28_729.085_735_721_943,
        5_226.495_278_852_854,
    ];
    const C: [f64; 8] = [
        1.423_437_110_749_683_5,
        4.630_337_846_156_545,
        5.769_497_221_460_691,
        3.647_848_324_763_204_5,
        1.270_458_252_452_368_4,
        0.241_780_725_177_450_6,
        0.022_723_844_989_269_184,
        7.745_450_142_783_414e-4,
    ];
    const D: [f64; 8] = [
        1.0,
        2.053_191_626_637_759,
        1.676_384_830_183_803_8,
        0.689_767_334_985_1,
        0.148_103_976_427_480_08,
        0.015_198_666_563_616_457,
        5.475_938_084_995_345e-4,
        1.050_750_071_644_416_8e-9,
    ];
    const E: [f64; 8] = [
        6.657_904_643_501_103,
        5.463_784_911_164_114,
        1.784_826_539_917_291_3,
        0.296_560_571_828_504_9,
        0.026_532_189_526_576_124,
        0.001_242_660_947_388_078_4,
        2.711_555_568_743_487_6e-5,
        2.010_334_399_292_288e-7,
    ];
    const F: [f64; 8] = [
        1.0,
        0.599_832_206_555_888,
        0.136_929_880_922_735_8,
        0.014_875_361_290_850_615,
        7.868_691_311_456_133e-4,
        1.846_318_317_510_054_8e-5,
        1.421_511_758_316_446e-7,
        2.044_263_103_389_939_7e-15,
    ];
    let poly = |c: &[f64; 8], x: f64| c.iter().rev().fold(0.0, |acc, &k| acc * x + k);
    let q = p - 0.5;
    if q.abs() <= 0.425 {
        let r = 0.180_625 - q * q;
        return q * poly(&A, r) / poly(&B, r);
    }
    let r = if q < 0.0 { p } else { 1.0 - p };
    let r = (-r.ln()).sqrt();
    let x = if r <= 5.0 {
        let r = r - 1.6;
        poly(&C, r) / poly(&D, r)
    } else {
        let r = r - 5.0;
        poly(&E, r) / poly(&F, r)
    };
    if q < 0.0 {
        -x
    } else {
        x
    }
}

/// The standard normal CDF Φ(x) = erfc(−x/√2)/2, erfc by the Chebyshev fit of Numerical
/// Recipes' `erfcc` (fractional error below 1.2e-7 everywhere). Used only for the ends of a
/// truncated normal.
pub fn normal_cdf(x: f64) -> f64 {
    if x == f64::INFINITY {
        return 1.0;
    }
    if x == f64::NEG_INFINITY {
        return 0.0;
    }
    let z = -x / std::f64::consts::SQRT_2;
    let a = z.abs();
    let t = 1.0 / (1.0 + 0.5 * a);
    let k = [
        -1.265_512_23,
        1.000_023_68,
        0.374_091_96,
        0.096_784_18,
        -0.186_288_06,
        0.278_868_07,
        -1.135_203_98,
        1.488_515_87,
        -0.822_152_23,
        0.170_872_77,
    ];
    let poly = k.iter().rev().fold(0.0, |acc, &c| acc * t + c);
    let erfc = t * (-a * a + poly).exp();
    let erfc = if z >= 0.0 { erfc } else { 2.0 - erfc };
    0.5 * erfc
}

/// How the uniforms are drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Method {
    /// Owen-scrambled Sobol points (`sobol_burley`): N a power of two up to 2^16, 2d ≤ 256
    Sobol,
    /// independent uniforms from a counter-based generator (SplitMix64)
    Random,
}

impl Method {
    /// The name in the study file.
    pub fn name(self) -> &'static str {
        match self {
            Method::Sobol => "sobol",
            Method::Random => "random",
        }
    }
}

/// SplitMix64's finaliser (Steele, Lea and Flood 2014): a bijective 64-bit mix. Written here
/// rather than taken from a crate so that the samples, which a records file's fingerprint
/// stands for, cannot change with a dependency's version.
pub fn splitmix64(x: u64) -> u64 {
    let mut z = x.wrapping_add(0x9e37_79b9_7f4a_7c15);
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

/// A uniform in (0, 1) from 64 random bits: the top 53 bits, centred in their cell.
fn open_unit(bits: u64) -> f64 {
    ((bits >> 11) as f64 + 0.5) / (1u64 << 53) as f64
}

/// A sequence of uniforms in (0, 1) from a seed (SplitMix64's generator).
#[derive(Clone, Debug)]
pub struct Stream(u64);

impl Stream {
    /// The stream of `seed`.
    pub fn new(seed: u64) -> Self {
        Stream(splitmix64(seed ^ 0x5851_f42d_4c95_7f2d))
    }

    /// The next 64 bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        splitmix64(self.0)
    }

    /// A whole number in `0..n` (n ≥ 1), by Lemire's multiply (bias below n / 2^64).
    pub fn below(&mut self, n: usize) -> usize {
        ((u128::from(self.next_u64()) * n as u128) >> 64) as usize
    }
}

/// The uniform of base row `j`, dimension `dim` (0..2d: A's columns, then B's), in (0, 1).
pub fn uniform(method: Method, seed: u32, j: usize, dim: usize) -> f64 {
    match method {
        // sobol_burley returns k·2^-23 in [0, 1); half a cell moves it off 0 into (0, 1)
        Method::Sobol => {
            f64::from(sobol_burley::sample(j as u32, dim as u32, seed))
                + 0.5 / f64::from(1u32 << 23)
        }
        Method::Random => {
            let counter = (u64::from(seed) << 40) ^ ((j as u64) << 9) ^ dim as u64;
            open_unit(splitmix64(splitmix64(counter)))
        }
    }
}

/// The Saltelli design: `n` base rows of the `dists`, blocks A, B and (with `indices`) A_B^(i),
/// block-major; each row the parameter values in SI.
///
/// For [`Method::Sobol`] the caller keeps `n ≤ 2^16` and `2 · dists.len() ≤ 256` (the sequence's
/// length and dimensions; [`super::spec::resolve`] refuses other sections): beyond them
/// `sobol_burley` panics (dimensions) or repeats itself (indices).
pub fn design(
    dists: &[Distribution],
    method: Method,
    seed: u32,
    n: usize,
    indices: bool,
) -> Vec<Vec<f64>> {
    let d = dists.len();
    let row = |j: usize, offset: usize| -> Vec<f64> {
        dists
            .iter()
            .enumerate()
            .map(|(k, dist)| dist.quantile(uniform(method, seed, j, offset + k)))
            .collect()
    };
    let a: Vec<Vec<f64>> = (0..n).map(|j| row(j, 0)).collect();
    if !indices {
        return a;
    }
    let b: Vec<Vec<f64>> = (0..n).map(|j| row(j, d)).collect();
    let mut out = Vec::with_capacity(n * (d + 2));
    out.extend(a.iter().cloned());
    out.extend(b.iter().cloned());
    for i in 0..d {
        out.extend(a.iter().zip(&b).map(|(ra, rb)| {
            let mut r = ra.clone();
            r[i] = rb[i];
            r
        }));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn normal_quantiles_are_the_tabulated_ones() {
        for (p, z) in [
            (0.975, 1.959_963_984_540_054),
            (0.95, 1.644_853_626_951_472_2),
            (0.999, 3.090_232_306_167_813_5),
            (0.5, 0.0),
            (0.025, -1.959_963_984_540_054),
            (1e-10, -6.361_340_902_404_056),
        ] {
            let got = normal_quantile(p);
            assert!(
                (got - z).abs() <= 1e-12 * z.abs().max(1.0),
                "{p}: {got} vs {z}"
            );
        }
        // the CDF inverts it to its stated accuracy
        for z in [-3.0, -1.0, 0.3, 2.5] {
            let p = normal_cdf(z);
            assert!((normal_quantile(p) - z).abs() < 1e-6, "{z}");
        }
        assert!((normal_cdf(1.959_963_984_540_054) - 0.975).abs() < 1.2e-7);
    }

    #[test]
    fn lognormal_median_and_factor() {
        let d = Distribution::Lognormal {
            median: 2.0,
            factor: 1.5,
        };
        assert!((d.quantile(0.5) - 2.0).abs() < 1e-15);
        // the 84.13th percentile (z = 1) is median·factor; z = −1 is median/factor
        let p1 = 0.841_344_746_068_542_9;
        assert!((d.quantile(p1) - 3.0).abs() < 1e-9);
        assert!((d.quantile(1.0 - p1) - 2.0 / 1.5).abs() < 1e-9);
    }

    #[test]
    fn truncated_normal_stays_in_range_and_keeps_its_median() {
        let d = Distribution::Normal {
            mean: 10.0,
            std: 2.0,
            from: 9.0,
            to: 20.0,
        };
        for k in 0..=1000 {
            let u = (k as f64 + 0.5) / 1001.0;
            let x = d.quantile(u);
            assert!((9.0..=20.0).contains(&x), "{u}: {x}");
        }
        assert!((d.quantile(1e-300) - 9.0).abs() < 1e-5);
        // median of the truncation: Φ((m−10)/2) = (Φ(−0.5) + Φ(5))/2
        let lo = normal_cdf(-0.5);
        let hi = normal_cdf(5.0);
        let m = 10.0 + 2.0 * normal_quantile(0.5 * (lo + hi));
        assert!((d.quantile(0.5) - m).abs() < 1e-12);
        assert!(m > 10.0);
    }

    #[test]
    fn choice_follows_the_weights() {
        let d = Distribution::Choice {
            values: vec![1.0, 2.0, 3.0],
            weights: vec![1.0, 0.0, 3.0],
        };
        assert_eq!(d.quantile(0.2), 1.0);
        assert_eq!(d.quantile(0.26), 3.0);
        assert_eq!(d.quantile(1.0 - 1e-17), 3.0);
    }

    #[test]
    fn uniforms_avoid_0_and_1_and_the_design_shares_columns() {
        for m in [Method::Sobol, Method::Random] {
            for j in 0..64 {
                for dim in 0..6 {
                    let u = uniform(m, 3, j, dim);
                    assert!(u > 0.0 && u < 1.0, "{m:?} {j} {dim}: {u}");
                }
            }
        }
        let dists = vec![Distribution::Uniform { from: 0.0, to: 1.0 }; 3];
        let x = design(&dists, Method::Sobol, 1, 8, true);
        assert_eq!(x.len(), 8 * 5);
        let (a, b) = (&x[0..8], &x[8..16]);
        for i in 0..3 {
            for j in 0..8 {
                let ab = &x[(2 + i) * 8 + j];
                for k in 0..3 {
                    assert_eq!(ab[k], if k == i { b[j][k] } else { a[j][k] });
                }
            }
        }
        // a Sobol column of 8 points holds one point in each eighth of [0, 1]
        let mut cells: Vec<usize> = a.iter().map(|r| (r[1] * 8.0) as usize).collect();
        cells.sort_unstable();
        assert_eq!(cells, (0..8).collect::<Vec<_>>());
    }
}
