//! Equivalent conicity of a rolling-radius-difference function Δr(y), as EN 15302 defines it.
//!
//! The wheelset's kinematic (Klingel) motion with a nonlinear Δr is, in the distance x
//! travelled, $y'' = −Δr(y)/(2 r_0 e_0)$. It conserves $\tfrac12 y'^2 + u(y)/(r_0 e_0)$ with the
//! potential $u(y) = \tfrac12\int_{y_c}^{y} Δr\,ds$. An oscillation of amplitude ŷ runs between
//! turning points $y_- < y_+$ with $y_+ − y_- = 2ŷ$ and $u(y_-) = u(y_+)$; its wavelength is
//! $L = \sqrt{r_0 e_0}\,I$ with $I = 2\int_{y_-}^{y_+} dy/\sqrt{2(u(y_+) − u(y))}$, and the
//! equivalent conicity is the cone slope with the same wavelength, $L = 2π\sqrt{r_0 e_0/λ_e}$:
//! $$λ_e(ŷ) = (2π/I)^2,$$
//! independent of r0 and e0. This reproduces the reference values of EN 15302's benchmark
//! cases (`tests/conicity.rs`), including those with contact-point jumps and with unequal wheel
//! diameters, where the oscillation centre y_c (the zero of Δr) is off the track centre. The
//! simpler harmonic linearisation (first Fourier coefficient of Δr(ŷ sin θ)) agrees only where
//! Δr is smooth, so it is not used.
//!
//! Δr is interpolated linearly between its points (as given by the standard's tables), so u is
//! piecewise quadratic and evaluated exactly; the integral uses $y = c + ŷ\sin φ$, which removes
//! the turning-point singularities, and the midpoint rule in φ.

use std::path::Path;

/// A rolling-radius difference Δr = r_R − r_L against the lateral displacement y.
#[derive(Clone, Debug, PartialEq)]
pub struct DeltaR {
    /// lateral displacements (m), strictly increasing
    y: Vec<f64>,
    /// Δr at each (m)
    dr: Vec<f64>,
    /// u(y_k) = ½∫_{y_0}^{y_k} Δr ds (m²)
    u: Vec<f64>,
}

/// Why a Δr table or an amplitude was refused.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum ConicityError {
    #[error("{file}:{line}: {problem}")]
    Table {
        file: String,
        line: usize,
        problem: String,
    },
    #[error("the Δr table needs at least 3 points, it has {0}")]
    TooShort(usize),
    #[error(
        "Δr has no zero in the table (range {min_m:.6e} to {max_m:.6e} m): no centred oscillation"
    )]
    NoCentre { min_m: f64, max_m: f64 },
    #[error("amplitude {amplitude_m:.6e} m does not fit in the table's y range [{lo_m:.6e}, {hi_m:.6e}] m around the centre {centre_m:.6e} m")]
    OutOfRange {
        amplitude_m: f64,
        centre_m: f64,
        lo_m: f64,
        hi_m: f64,
    },
    #[error("amplitude {0:e} m must be positive and finite")]
    BadAmplitude(f64),
    #[error("at amplitude {amplitude_m:.6e} m the motion has no restoring turning points (Δr does not push back)")]
    NotOscillating { amplitude_m: f64 },
}

/// The equivalent conicity at one amplitude.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Conicity {
    /// amplitude ŷ = (y₊ − y₋)/2 (m)
    pub amplitude_m: f64,
    /// equivalent conicity λ_e = tan γ_e (–)
    pub conicity: f64,
    /// turning points y₋, y₊ (m)
    pub turning_m: (f64, f64),
}

impl DeltaR {
    /// From points (m); sorted by y, duplicates and non-finite values refused.
    pub fn new(mut points: Vec<(f64, f64)>, origin: &str) -> Result<Self, ConicityError> {
        if points.len() < 3 {
            return Err(ConicityError::TooShort(points.len()));
        }
        points.sort_by(|a, b| a.0.total_cmp(&b.0));
        for (k, w) in points.windows(2).enumerate() {
            if w[1].0 <= w[0].0 {
                return Err(ConicityError::Table {
                    file: origin.into(),
                    line: k + 2,
                    problem: format!("y = {} m appears twice", w[1].0),
                });
            }
        }
        let (y, dr): (Vec<f64>, Vec<f64>) = points.into_iter().unzip();
        let mut u = vec![0.0; y.len()];
        for k in 1..y.len() {
            u[k] = u[k - 1] + 0.25 * (dr[k] + dr[k - 1]) * (y[k] - y[k - 1]);
        }
        Ok(Self { y, dr, u })
    }

    /// Reads a CSV with a header `y_mm,delta_r_mm` (or `y_m,delta_r_m`); `#` lines are
    /// comments. Errors name the file and line.
    pub fn read(path: &Path) -> Result<Self, ConicityError> {
        let name = path.display().to_string();
        let text = std::fs::read_to_string(path).map_err(|e| ConicityError::Table {
            file: name.clone(),
            line: 0,
            problem: e.to_string(),
        })?;
        Self::parse(&text, &name)
    }

    /// Parses the CSV text of [`DeltaR::read`].
    pub fn parse(text: &str, origin: &str) -> Result<Self, ConicityError> {
        let err = |line: usize, problem: String| ConicityError::Table {
            file: origin.into(),
            line,
            problem,
        };
        let mut scale = None;
        let mut points = Vec::new();
        for (k, raw) in text.lines().enumerate() {
            let line = raw.trim();
            if line.is_empty() || line.starts_with('#') {
                continue;
            }
            let f: Vec<&str> = line.split(',').map(str::trim).collect();
            if scale.is_none() {
                scale = match f.as_slice() {
                    ["y_mm", "delta_r_mm"] => Some(1e-3),
                    ["y_m", "delta_r_m"] => Some(1.0),
                    _ => {
                        return Err(err(
                            k + 1,
                            format!(
                            "header {line:?}: expected \"y_mm,delta_r_mm\" or \"y_m,delta_r_m\""
                        ),
                        ))
                    }
                };
                continue;
            }
            let s = scale.unwrap_or(1.0);
            let [a, b] = f.as_slice() else {
                return Err(err(k + 1, format!("{line:?}: expected two numbers")));
            };
            let (Ok(y), Ok(d)) = (a.parse::<f64>(), b.parse::<f64>()) else {
                return Err(err(k + 1, format!("{line:?}: not two numbers")));
            };
            if !(y.is_finite() && d.is_finite()) {
                return Err(err(k + 1, format!("{line:?}: not finite")));
            }
            points.push((y * s, d * s));
        }
        Self::new(points, origin)
    }

    /// The y range (m).
    pub fn range(&self) -> (f64, f64) {
        (self.y[0], self.y[self.y.len() - 1])
    }

    fn segment(&self, y: f64) -> Option<usize> {
        let (lo, hi) = self.range();
        if !(lo..=hi).contains(&y) {
            return None;
        }
        let k = self.y.partition_point(|v| *v <= y);
        Some(k.clamp(1, self.y.len() - 1) - 1)
    }

    /// Δr(y) (m), linear between points.
    pub fn value(&self, y: f64) -> Option<f64> {
        let k = self.segment(y)?;
        let s = (self.dr[k + 1] - self.dr[k]) / (self.y[k + 1] - self.y[k]);
        Some(self.dr[k] + s * (y - self.y[k]))
    }

    /// u(y) = ½∫Δr (m²), exact for the piecewise-linear Δr.
    fn potential(&self, y: f64) -> Option<f64> {
        let k = self.segment(y)?;
        let t = y - self.y[k];
        let s = (self.dr[k + 1] - self.dr[k]) / (self.y[k + 1] - self.y[k]);
        Some(self.u[k] + 0.5 * (self.dr[k] * t + 0.5 * s * t * t))
    }

    /// The oscillation centre: the zero of Δr nearest to y = 0.
    pub fn centre(&self) -> Result<f64, ConicityError> {
        let mut best: Option<f64> = None;
        for k in 0..self.y.len() - 1 {
            let (a, b) = (self.dr[k], self.dr[k + 1]);
            if a == 0.0 || a.signum() != b.signum() {
                let z = if a == b {
                    self.y[k]
                } else {
                    self.y[k] + (self.y[k + 1] - self.y[k]) * a / (a - b)
                };
                if best.is_none_or(|c| z.abs() < c.abs()) {
                    best = Some(z);
                }
            }
        }
        let (lo, hi) = self
            .dr
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), d| {
                (l.min(*d), h.max(*d))
            });
        best.ok_or(ConicityError::NoCentre {
            min_m: lo,
            max_m: hi,
        })
    }

    /// Equivalent conicity at amplitude `amplitude` (m), EN 15302's definition (module docs).
    pub fn equivalent_conicity(&self, amplitude: f64) -> Result<Conicity, ConicityError> {
        if !(amplitude > 0.0 && amplitude.is_finite()) {
            return Err(ConicityError::BadAmplitude(amplitude));
        }
        let c = self.centre()?;
        let (lo, hi) = self.range();
        let out = ConicityError::OutOfRange {
            amplitude_m: amplitude,
            centre_m: c,
            lo_m: lo,
            hi_m: hi,
        };
        // Upper turning point a in [c, c + 2ŷ] with u(a) = u(a − 2ŷ), by bisection: the
        // difference is negative at a = c (u is least at the centre) and positive at c + 2ŷ.
        let (mut a0, mut a1) = (c.max(lo + 2.0 * amplitude), (c + 2.0 * amplitude).min(hi));
        if a0 > a1 {
            return Err(out);
        }
        let g = |a: f64| -> Option<f64> {
            Some(self.potential(a)? - self.potential(a - 2.0 * amplitude)?)
        };
        let (g0, g1) = (g(a0).ok_or(out.clone())?, g(a1).ok_or(out.clone())?);
        if g0 > 0.0 || g1 < 0.0 {
            return Err(if a0 > c || a1 < c + 2.0 * amplitude {
                out
            } else {
                ConicityError::NotOscillating {
                    amplitude_m: amplitude,
                }
            });
        }
        for _ in 0..200 {
            let m = 0.5 * (a0 + a1);
            if g(m).ok_or(out.clone())? < 0.0 {
                a0 = m;
            } else {
                a1 = m;
            }
        }
        let y_hi = 0.5 * (a0 + a1);
        let y_lo = y_hi - 2.0 * amplitude;
        let energy = self.potential(y_hi).ok_or(out.clone())?;
        let mid = 0.5 * (y_hi + y_lo);
        // I = 2∫ dy/√(2(E − u)), y = mid + ŷ sin φ
        const N: usize = 4000;
        let mut integral = 0.0;
        for i in 0..N {
            let phi =
                -std::f64::consts::FRAC_PI_2 + std::f64::consts::PI * (i as f64 + 0.5) / N as f64;
            let y = mid + amplitude * phi.sin();
            let w = energy - self.potential(y).ok_or(out.clone())?;
            if w <= 0.0 {
                // a flat or reversed potential inside the swing: no restoring force there
                return if w > -1e-18 {
                    Ok(Conicity {
                        amplitude_m: amplitude,
                        conicity: 0.0,
                        turning_m: (y_lo, y_hi),
                    })
                } else {
                    Err(ConicityError::NotOscillating {
                        amplitude_m: amplitude,
                    })
                };
            }
            integral += amplitude * phi.cos() / (2.0 * w).sqrt();
        }
        integral *= 2.0 * std::f64::consts::PI / N as f64;
        let k = 2.0 * std::f64::consts::PI / integral;
        Ok(Conicity {
            amplitude_m: amplitude,
            conicity: k * k,
            turning_m: (y_lo, y_hi),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_cone_has_its_slope_at_every_amplitude() {
        // Δr = 2λy exactly (linear points): the oscillation is harmonic, λe = λ.
        let pts = (-100..=100).map(|i| {
            let y = i as f64 * 1e-4;
            (y, 2.0 * 0.05 * y)
        });
        let d = DeltaR::new(pts.collect(), "cone").expect("valid");
        for a in [1e-3, 3e-3, 9e-3] {
            let c = d.equivalent_conicity(a).expect("fits");
            assert!((c.conicity - 0.05).abs() < 1e-9, "{a}: {}", c.conicity);
        }
    }

    #[test]
    fn an_offset_cone_oscillates_about_its_zero() {
        // unequal wheel radii shift Δr: the centre moves to Δr = 0, the conicity stays λ
        let pts = (-100..=100).map(|i| {
            let y = i as f64 * 1e-4;
            (y, 2.0 * 0.2 * y - 0.4e-3)
        });
        let d = DeltaR::new(pts.collect(), "cone").expect("valid");
        assert!((d.centre().expect("zero") - 1e-3).abs() < 1e-15);
        let c = d.equivalent_conicity(4e-3).expect("fits");
        assert!((c.conicity - 0.2).abs() < 1e-9);
        assert!((c.turning_m.0 + 3e-3).abs() < 1e-12 && (c.turning_m.1 - 5e-3).abs() < 1e-12);
    }

    #[test]
    fn bad_tables_name_the_line() {
        let e = DeltaR::parse("y_mm,delta_r_mm\n0,0\n1,x\n2,1\n", "t.csv").unwrap_err();
        assert!(e.to_string().contains("t.csv:3"), "{e}");
        let e = DeltaR::parse("y,dr\n0,0\n", "t.csv").unwrap_err();
        assert!(e.to_string().contains("header"), "{e}");
        let e = DeltaR::parse("y_mm,delta_r_mm\n0,0\n0,1\n1,2\n", "t.csv").unwrap_err();
        assert!(e.to_string().contains("twice"), "{e}");
        let d = DeltaR::parse("y_mm,delta_r_mm\n-1,-0.1\n0,0\n1,0.1\n", "t").expect("valid");
        assert!(matches!(
            d.equivalent_conicity(0.01),
            Err(ConicityError::OutOfRange { .. })
        ));
        assert!(matches!(
            d.equivalent_conicity(-1.0),
            Err(ConicityError::BadAmplitude(_))
        ));
    }
}
