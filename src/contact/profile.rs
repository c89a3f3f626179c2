//! Wheel and rail profiles read from point lists (CSV), checked, and put into the
//! contact frame used by the rigid contact solver ([`crate::contact::rigid`]).
//!
//! # File format
//!
//! Lines starting with `#` are comments (cite the profile's source there). The first other
//! line is the header `y_mm,z_mm` or `y_m,z_m`: it states the unit of both columns. Every
//! following line is one point `lateral,vertical`. The lateral coordinate must be strictly
//! monotonic (increasing or decreasing) and consecutive points at most 5 mm apart.
//!
//! # Conventions (what the study's keys mean)
//!
//! * By default the file's lateral axis points **outward** (towards the field side) and its
//!   vertical axis points **down** (towards the rail for a wheel, into the rail for a rail), as
//!   in the UIC60 file of the Manchester benchmark. `*_mirror = true` says the lateral axis
//!   points towards the flange / gauge side (the S1002 file of the benchmark); `*_z_up = true`
//!   says the vertical axis points up.
//! * Wheel: lateral 0 is the taping line (where the radius is the study's r0); the radius is
//!   `r0 + z_down(u) − z_down(0)`.
//! * Rail: placed by the track gauge, measured between the gauge points `gauge_depth` (14 mm)
//!   below the rail's highest point, after the rail inclination is applied.
//!
//! Only the part of each profile whose slope stays below 1:[`MAX_SLOPE`]⁻¹ (about 80°) on the
//! side of the running surface is kept: the vertical flange back and rail sides are never in
//! contact and cannot be written as a function of the lateral coordinate.

use std::path::Path;

/// Steepest slope |dz/dy| kept (–).
pub const MAX_SLOPE: f64 = 6.0;
/// Largest distance between consecutive points (m).
pub const MAX_GAP: f64 = 5e-3;
/// Plausible lateral extent of a wheel or rail profile (m).
pub const WIDTH_RANGE: (f64, f64) = (0.02, 0.3);

/// A malformed or implausible profile file.
#[derive(Debug, thiserror::Error)]
pub enum ProfileError {
    #[error("cannot read profile {file}: {source}")]
    Io {
        file: String,
        source: std::io::Error,
    },
    #[error("{file}:{line}: {problem}")]
    Line {
        file: String,
        line: usize,
        problem: String,
    },
    #[error("profile {file}: {problem}")]
    Shape { file: String, problem: String },
}

/// How to read one profile file.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct Orientation {
    /// the file's lateral axis points towards the flange / gauge side (inward)
    pub mirror: bool,
    /// the file's vertical axis points up
    pub z_up: bool,
}

/// Profile points in SI: `u` outward (m), strictly increasing; `z_down` (m); the file line of
/// each point.
#[derive(Clone, Debug, PartialEq)]
pub struct Points {
    /// file name, for messages
    pub file: String,
    /// lateral coordinate, outward (m)
    pub u: Vec<f64>,
    /// vertical coordinate, downward (m)
    pub z_down: Vec<f64>,
    /// 1-based line number of each point in the file
    pub line: Vec<usize>,
}

/// Reads a profile file.
pub fn read(path: &Path, o: Orientation) -> Result<Points, ProfileError> {
    let file = path.display().to_string();
    let text = std::fs::read_to_string(path).map_err(|source| ProfileError::Io {
        file: file.clone(),
        source,
    })?;
    parse(&text, &file, o)
}

fn line_err(file: &str, line: usize, problem: String) -> ProfileError {
    ProfileError::Line {
        file: file.to_string(),
        line,
        problem,
    }
}

/// Parses profile text; `file` names it in messages.
pub fn parse(text: &str, file: &str, o: Orientation) -> Result<Points, ProfileError> {
    let mut scale = None;
    let mut header_line = 0;
    let (mut raw, mut lines) = (Vec::new(), Vec::new());
    for (k, l) in text.lines().enumerate() {
        let (line, l) = (k + 1, l.trim());
        if l.is_empty() || l.starts_with('#') {
            continue;
        }
        if scale.is_none() {
            let h: Vec<String> = l
                .split(',')
                .map(|c| c.trim().to_ascii_lowercase())
                .collect();
            scale = Some(
                match (h.first().map(String::as_str), h.get(1).map(String::as_str)) {
                    (Some("y_mm"), Some("z_mm")) if h.len() == 2 => 1e-3,
                    (Some("y_m"), Some("z_m")) if h.len() == 2 => 1.0,
                    _ => {
                        return Err(line_err(
                            file,
                            line,
                            format!(
                            "header {l:?} must be `y_mm,z_mm` or `y_m,z_m` (it states the unit)"
                        ),
                        ))
                    }
                },
            );
            header_line = line;
            continue;
        }
        let cols: Vec<&str> = l.split(',').map(str::trim).collect();
        let parsed: Vec<Option<f64>> = cols.iter().map(|c| c.parse::<f64>().ok()).collect();
        match parsed.as_slice() {
            [Some(y), Some(z)] if y.is_finite() && z.is_finite() => raw.push((*y, *z)),
            _ => {
                return Err(line_err(
                    file,
                    line,
                    format!("{l:?} is not two finite numbers `lateral,vertical`"),
                ))
            }
        }
        lines.push(line);
    }
    let Some(scale) = scale else {
        return Err(ProfileError::Shape {
            file: file.into(),
            problem: "no header line `y_mm,z_mm` or `y_m,z_m`".into(),
        });
    };
    if raw.len() < 10 {
        return Err(ProfileError::Shape {
            file: file.into(),
            problem: format!("{} points; at least 10 are needed", raw.len()),
        });
    }
    check_shape(&raw, &lines, scale, header_line, file)?;
    let sy = if o.mirror { -scale } else { scale };
    let sz = if o.z_up { -scale } else { scale };
    let mut pts: Vec<(f64, f64, usize)> = raw
        .iter()
        .zip(&lines)
        .map(|(&(y, z), &line)| (y * sy, z * sz, line))
        .collect();
    if pts[0].0 > pts[1].0 {
        pts.reverse();
    }
    Ok(Points {
        file: file.into(),
        u: pts.iter().map(|p| p.0).collect(),
        z_down: pts.iter().map(|p| p.1).collect(),
        line: pts.iter().map(|p| p.2).collect(),
    })
}

/// Monotonic lateral coordinate, bounded gaps, a width plausible for the stated unit.
fn check_shape(
    raw: &[(f64, f64)],
    lines: &[usize],
    scale: f64,
    header_line: usize,
    file: &str,
) -> Result<(), ProfileError> {
    let unit = if scale == 1.0 { "m" } else { "mm" };
    let width = (raw[raw.len() - 1].0 - raw[0].0).abs() * scale;
    if !(WIDTH_RANGE.0..=WIDTH_RANGE.1).contains(&width) {
        return Err(line_err(
            file,
            header_line,
            format!(
                "the profile is {:.6} {unit} wide, implausible for a wheel or rail in {unit} \
                 (expected {} to {} mm): is the header's unit right?",
                width / scale,
                WIDTH_RANGE.0 * 1e3,
                WIDTH_RANGE.1 * 1e3
            ),
        ));
    }
    let dir = (raw[1].0 - raw[0].0).signum();
    for (k, w) in raw.windows(2).enumerate() {
        let d = w[1].0 - w[0].0;
        if d * dir <= 0.0 {
            return Err(line_err(
                file,
                lines[k + 1],
                format!(
                    "lateral coordinate {} {unit} does not continue the monotonic order of the \
                     previous point ({} {unit})",
                    w[1].0, w[0].0
                ),
            ));
        }
        let gap = (w[1].0 - w[0].0).hypot(w[1].1 - w[0].1) * scale;
        if gap > MAX_GAP {
            return Err(line_err(
                file,
                lines[k + 1],
                format!(
                    "{:.3} mm from the previous point; at most {} mm allowed",
                    gap * 1e3,
                    MAX_GAP * 1e3
                ),
            ));
        }
    }
    Ok(())
}

impl Points {
    /// Rotates the points by `angle` (rad) about the origin, turning the surface normal towards
    /// the track centre (the rail inclination): `(u, h) → (u cos θ − h sin θ, u sin θ + h cos θ)`
    /// with `h = −z_down` up.
    pub fn incline(&mut self, angle: f64) {
        let (s, c) = angle.sin_cos();
        for (u, z) in self.u.iter_mut().zip(self.z_down.iter_mut()) {
            let h = -*z;
            let (nu, nh) = (*u * c - h * s, *u * s + h * c);
            *u = nu;
            *z = -nh;
        }
    }

    /// The contiguous index range around `anchor` where the secant slope stays ≤ MAX_SLOPE.
    pub fn running_range(&self, anchor: usize) -> (usize, usize) {
        let steep = |k: usize| {
            let s = (self.z_down[k + 1] - self.z_down[k]) / (self.u[k + 1] - self.u[k]);
            s.abs() > MAX_SLOPE
        };
        let mut lo = anchor;
        while lo > 0 && !steep(lo - 1) {
            lo -= 1;
        }
        let mut hi = anchor;
        while hi + 1 < self.u.len() && !steep(hi) {
            hi += 1;
        }
        (lo, hi)
    }

    /// An error about this profile's shape.
    pub fn shape_error(&self, problem: String) -> ProfileError {
        ProfileError::Shape {
            file: self.file.clone(),
            problem,
        }
    }
}
