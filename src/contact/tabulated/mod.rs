//! docs/model.md §3 method 3: a contact geometry read from a CSV table and interpolated C².
//!
//! # File format
//!
//! Lines starting with `#` are comments. The first other line is the header; each column
//! name carries its unit, and every column is converted to SI once, here:
//!
//! | quantity | accepted names | required |
//! |---|---|---|
//! | lateral displacement y of the wheelset (towards the tabulated wheel's rail) | `y_m`, `y_mm` | yes |
//! | rolling radius r_R, or r_R − r0 | `r_m`, `r_mm`, `r_minus_r0_m`, `r_minus_r0_mm` | one of them |
//! | contact angle δ_R to the **track** plane (docs/model.md §3: includes the roll) | `delta_rad`, `delta_deg` | yes |
//! | wheelset roll φ | `roll_rad`, `roll_deg` | yes |
//! | Hertz semi-axes a (rolling), b (lateral) | `a_m`/`a_mm` and `b_m`/`b_mm` | optional, both |
//! | Kalker's coefficients C11, C22, C23 (dimensionless) | `c11`, `c22`, `c23` | optional, all three |
//! | Kalker's C33 (dimensionless) | `c33` | optional (else Kalker's table at a/b) |
//! | normal force at which a, b were computed | `normal_force_N`, `normal_force_kN` | optional |
//!
//! The roll is required: it cannot be derived from the other columns exactly (for a cone on
//! knife-edge rails φ = (r_R − r_L)/(2 l0), but real profiles' contact points move up and down
//! the rail head, which changes φ; see `studies/tables/dtu-rsgeo-1o40.csv` for how it was
//! derived there from the contact heights). The equations of motion (docs/model.md §4–8) use δ_R,
//! which already contains φ; the roll column is carried for output.
//!
//! Rows must have strictly increasing y and cover both signs of y: the table is the **right**
//! wheel's (docs/model.md §1: y > 0 moves the wheelset towards the right rail, the right wheel's flange
//! approaches its rail, δ_R and r_R grow), and the left wheel is r_L(y) = r_R(−y),
//! δ_L(y) = δ_R(−y). A table given for the left wheel with y measured to the right is
//! converted by y → −y (reverse the rows); radii, angles and patch data keep their values, the
//! roll changes sign.
//!
//! # Interpolation
//!
//! Each column gets a not-a-knot cubic spline ([`CubicSpline`]): C², the data reproduced at the
//! nodes, cubics reproduced exactly, and exact slopes and second derivatives for the contact
//! table's C² sampling.
//! When the file gives a, b and the normal force N_file, the semi-axes are scaled to the
//! model's normal force N = (W/2)/cos δ (docs/model.md §4) by Hertz's $a ∝ N^{1/3}$ at fixed
//! curvatures, so the axle load of the study is respected.

use std::path::Path;

use crate::contact::geometry::ContactPoint;
use crate::contact::kalker::{kalker_c, CreepCoefficients, KalkerError};
use crate::contact::spline::CubicSpline;
use crate::system::scalar::{Dual, Scalar};

mod read;

pub use read::TabulatedError;
use read::{read_columns, Quantity};

/// A contact geometry tabulated against y, as splines (SI units).
#[derive(Clone, Debug, PartialEq)]
pub struct TabulatedGeometry {
    /// the file (or origin) the table came from, for messages
    pub source: String,
    radius: CubicSpline,
    angle: CubicSpline,
    roll: CubicSpline,
    semi_axes: Option<(CubicSpline, CubicSpline)>,
    kalker: Option<[CubicSpline; 3]>,
    c33: Option<CubicSpline>,
    normal_force: Option<CubicSpline>,
}

impl TabulatedGeometry {
    /// Reads a table file; `r0` (m) converts an `r_minus_r0` column.
    pub fn read(path: &Path, r0: f64) -> Result<Self, TabulatedError> {
        let name = path.display().to_string();
        let text = std::fs::read_to_string(path).map_err(|source| TabulatedError::Io {
            path: name.clone(),
            source,
        })?;
        Self::parse(&text, &name, r0)
    }

    /// Parses table text; `origin` names it in messages.
    pub fn parse(text: &str, origin: &str, r0: f64) -> Result<Self, TabulatedError> {
        let c = read_columns(text, origin)?;
        let missing = |what| TabulatedError::MissingColumn {
            path: origin.into(),
            line: c.header_line,
            what,
        };
        let y = c
            .get(Quantity::Y)
            .ok_or_else(|| missing("y (y_m or y_mm)"))?;
        let radius: Vec<f64> = match (c.get(Quantity::Radius), c.get(Quantity::RadiusDelta)) {
            (Some(r), _) => r.to_vec(),
            (None, Some(dr)) => dr.iter().map(|d| r0 + d).collect(),
            (None, None) => return Err(missing("the rolling radius (r_m, r_minus_r0_m, ...)")),
        };
        let angle = c
            .get(Quantity::Angle)
            .ok_or_else(|| missing("the contact angle (delta_rad or delta_deg)"))?;
        let roll = c
            .get(Quantity::Roll)
            .ok_or_else(|| missing("the roll (roll_rad or roll_deg)"))?;
        if y[0] >= 0.0 || y[y.len() - 1] <= 0.0 {
            return Err(TabulatedError::Coverage {
                path: origin.into(),
                what: format!(
                    "y runs from {:e} m to {:e} m; the table must cover both signs of y (the left wheel uses r_R(−y))",
                    y[0],
                    y[y.len() - 1]
                ),
            });
        }
        let spline = |column: &'static str, v: &[f64]| {
            CubicSpline::not_a_knot(y, v).map_err(|source| TabulatedError::Spline {
                path: origin.into(),
                column,
                source,
            })
        };
        let pair = |qa, qb, what| match (c.get(qa), c.get(qb)) {
            (Some(_), Some(_)) | (None, None) => Ok(()),
            _ => Err(missing(what)),
        };
        pair(
            Quantity::SemiA,
            Quantity::SemiB,
            "the other Hertz semi-axis (a and b go together)",
        )?;
        pair(
            Quantity::C11,
            Quantity::C22,
            "Kalker's C11, C22, C23 (all three go together)",
        )?;
        pair(
            Quantity::C22,
            Quantity::C23,
            "Kalker's C11, C22, C23 (all three go together)",
        )?;
        let kalker = match (
            c.get(Quantity::C11),
            c.get(Quantity::C22),
            c.get(Quantity::C23),
        ) {
            (Some(a), Some(b), Some(d)) => {
                Some([spline("c11", a)?, spline("c22", b)?, spline("c23", d)?])
            }
            _ => None,
        };
        let semi_axes = match (c.get(Quantity::SemiA), c.get(Quantity::SemiB)) {
            (Some(a), Some(b)) => Some((spline("a", a)?, spline("b", b)?)),
            _ => None,
        };
        if kalker.is_some() && semi_axes.is_none() {
            return Err(missing(
                "the Hertz semi-axes a, b (Kalker's C need them: f11 = G a b C11)",
            ));
        }
        Ok(Self {
            source: origin.into(),
            radius: spline("r", &radius)?,
            angle: spline("delta", angle)?,
            roll: spline("roll", roll)?,
            semi_axes,
            kalker,
            c33: c.get(Quantity::C33).map(|v| spline("c33", v)).transpose()?,
            normal_force: c
                .get(Quantity::Normal)
                .map(|v| spline("normal_force", v))
                .transpose()?,
        })
    }

    /// The tabulated y range (m).
    pub fn range(&self) -> (f64, f64) {
        self.radius.range()
    }

    /// Largest half-width Y (m) such that [−Y, Y] lies inside the table.
    pub fn half_width(&self) -> f64 {
        let (lo, hi) = self.range();
        (-lo).min(hi)
    }

    /// The file's rows: (y, r, δ, φ) in SI, for round-trip checks.
    pub fn nodes(&self) -> Vec<[f64; 4]> {
        let (y, r) = self.radius.knots();
        let d = self.angle.knots().1;
        let p = self.roll.knots().1;
        (0..y.len()).map(|i| [y[i], r[i], d[i], p[i]]).collect()
    }

    /// Whether the file gives the Hertz semi-axes.
    pub fn has_semi_axes(&self) -> bool {
        self.semi_axes.is_some()
    }

    /// Whether the file gives Kalker's C11, C22, C23.
    pub fn has_kalker(&self) -> bool {
        self.kalker.is_some()
    }

    /// The right wheel's contact point at `y` with exact spline slopes.
    pub fn point(&self, y: f64) -> ContactPoint<Dual<1>> {
        let d = |s: &CubicSpline| {
            let (re, eps, _) = s.eval(y);
            Dual { re, eps: [eps] }
        };
        ContactPoint {
            radius: d(&self.radius),
            angle: d(&self.angle),
            roll: d(&self.roll),
            // the contact point's position on the wheel is not tabulated
            wheel_offset: Dual::cst(f64::NAN),
        }
    }

    /// The splines' second derivatives of r_R, δ_R and φ at `y` (1/m, rad/m², rad/m²):
    /// exact data for the contact table's C² interpolant.
    pub fn second_derivatives(&self, y: f64) -> [f64; 3] {
        [&self.radius, &self.angle, &self.roll].map(|s| s.eval(y).2)
    }

    /// The first interpolated contact quantity at `y` that is not positive (a spline through
    /// positive data can undershoot between steep rows): its column name and value.
    pub fn non_positive_at(&self, y: f64) -> Option<(&'static str, f64)> {
        let mut cols: Vec<(&'static str, &CubicSpline, bool)> = Vec::new();
        if let Some((a, b)) = &self.semi_axes {
            cols.extend([("a", a, true), ("b", b, true)]);
        }
        if let Some([c11, c22, c23]) = &self.kalker {
            cols.extend([("c11", c11, true), ("c22", c22, true), ("c23", c23, false)]);
        }
        if let Some(c33) = &self.c33 {
            cols.push(("c33", c33, false));
        }
        if let Some(n) = &self.normal_force {
            cols.push(("normal_force", n, true));
        }
        cols.into_iter().find_map(|(name, s, strict)| {
            let v = s.eval(y).0;
            let bad = if strict { v <= 0.0 } else { v < 0.0 };
            bad.then_some((name, v))
        })
    }

    /// Hertz semi-axes (a, b) at `y` for the model's normal force `normal` (N), if tabulated.
    pub fn semi_axes(&self, y: f64, normal: Dual<1>) -> Option<(Dual<1>, Dual<1>)> {
        let (sa, sb) = self.semi_axes.as_ref()?;
        let d = |s: &CubicSpline| {
            let (re, eps, _) = s.eval(y);
            Dual { re, eps: [eps] }
        };
        let (a, b) = (d(sa), d(sb));
        Some(match &self.normal_force {
            // Hertz: a, b ∝ N^{1/3} at fixed curvatures
            Some(n) => {
                let ratio = normal / d(n);
                let scale = ratio.lift(ratio.re.cbrt(), ratio.re.cbrt() / (3.0 * ratio.re));
                (a * scale, b * scale)
            }
            None => (a, b),
        })
    }

    /// Creep coefficients from the tabulated Kalker C at `y` and the patch (a, b) (docs/model.md §5);
    /// C33 from Kalker's table at a/b when the file has none. `None`: no C in the file.
    pub fn creep(
        &self,
        y: f64,
        a: Dual<1>,
        b: Dual<1>,
        shear_modulus: f64,
        poisson_ratio: f64,
    ) -> Option<Result<CreepCoefficients<Dual<1>>, KalkerError>> {
        let [s11, s22, s23] = self.kalker.as_ref()?;
        let d = |s: &CubicSpline| {
            let (re, eps, _) = s.eval(y);
            Dual { re, eps: [eps] }
        };
        let c33 = match &self.c33 {
            Some(s) => d(s),
            None => match kalker_c(a / b, poisson_ratio) {
                Ok(c) => c[3],
                Err(e) => return Some(Err(e)),
            },
        };
        let ab = a * b;
        let gab = ab * shear_modulus;
        Some(Ok(CreepCoefficients {
            f11: gab * d(s11),
            f22: gab * d(s22),
            f23: gab * ab.sqrt() * d(s23),
            f33: gab * ab * c33,
        }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const TABLE: &str = "y_mm,r_mm,delta_rad,roll_rad,a_mm,b_mm,c11,c22,c23,normal_force_kN\n\
        -3,460,0.05,0,6,4,4.2,3.7,1.6,50\n-1,460,0.05,0,6,4,4.2,3.7,1.6,50\n\
        1,460,0.05,0,6,4,4.2,3.7,1.6,50\n3,460,0.05,0,6,4,4.2,3.7,1.6,50\n";

    /// Hertz: a, b ∝ N^{1/3}; eight times the file's load doubles the semi-axes, and
    /// f11 = G a b C11 follows (docs/model.md §5).
    #[test]
    fn semi_axes_follow_the_model_normal_force() {
        let t = TabulatedGeometry::parse(TABLE, "t.csv", 0.46).expect("valid");
        let n = Dual::<1>::var(8.0 * 50e3, 0);
        let (a, b) = t.semi_axes(0.0, n).expect("tabulated");
        assert!((a.re - 0.012).abs() < 1e-15 && (b.re - 0.008).abs() < 1e-15);
        // d a / d N = a / (3N)
        assert!((a.eps[0] - 0.012 / (3.0 * 4e5)).abs() < 1e-20);
        let f = t
            .creep(0.0, a, b, 8e10, 0.3)
            .expect("tabulated C")
            .expect("C33 from Kalker's table");
        assert!((f.f11.re - 8e10 * 0.012 * 0.008 * 4.2).abs() < 1e-6 * f.f11.re);
        assert!((f.f23.re - 8e10 * (0.012f64 * 0.008).powf(1.5) * 1.6).abs() < 1e-6 * f.f23.re);
    }
}
