//! Reading a geometry table: the header's column names and units, the rows in SI, and the
//! errors that name the file and the line.

use crate::contact::spline::SplineError;

/// A malformed table. Every variant names the file and, where there is one, the line (1-based).
#[derive(Debug, thiserror::Error)]
pub enum TabulatedError {
    #[error("cannot read geometry table {path}: {source}")]
    Io {
        path: String,
        source: std::io::Error,
    },
    #[error("{path}: no header line (only comments or blank lines)")]
    NoHeader { path: String },
    #[error(
        "{path}:{line}: unknown column {column:?}; accepted names (units in the name): {accepted}"
    )]
    UnknownColumn {
        path: String,
        line: usize,
        column: String,
        accepted: &'static str,
    },
    #[error("{path}:{line}: column {column:?} repeats a quantity already given")]
    DuplicateColumn {
        path: String,
        line: usize,
        column: String,
    },
    #[error("{path}:{line}: missing column for {what}")]
    MissingColumn {
        path: String,
        line: usize,
        what: &'static str,
    },
    #[error("{path}:{line}: {found} fields, the header has {expected}")]
    FieldCount {
        path: String,
        line: usize,
        expected: usize,
        found: usize,
    },
    #[error("{path}:{line}: column {column}: {text:?} is not a finite number")]
    NotANumber {
        path: String,
        line: usize,
        column: String,
        text: String,
    },
    #[error("{path}:{line}: y = {y_m:e} m does not exceed the previous row's {previous_m:e} m (y must increase strictly)")]
    NotIncreasing {
        path: String,
        line: usize,
        y_m: f64,
        previous_m: f64,
    },
    #[error("{path}:{line}: column {column} = {value:e} (SI): {rule}")]
    Unphysical {
        path: String,
        line: usize,
        column: String,
        value: f64,
        rule: &'static str,
    },
    #[error("{path}: {what}")]
    Coverage { path: String, what: String },
    #[error("{path}: column {column}: {source}")]
    Spline {
        path: String,
        column: &'static str,
        source: SplineError,
    },
}

/// What a header column holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Quantity {
    Y,
    Radius,
    RadiusDelta,
    Angle,
    Roll,
    SemiA,
    SemiB,
    C11,
    C22,
    C23,
    C33,
    Normal,
}

const ACCEPTED: &str = "y_m, y_mm, r_m, r_mm, r_minus_r0_m, r_minus_r0_mm, delta_rad, delta_deg, \
roll_rad, roll_deg, a_m, a_mm, b_m, b_mm, c11, c22, c23, c33, normal_force_N, normal_force_kN";

/// Column name → (quantity, factor to SI).
fn column(name: &str) -> Option<(Quantity, f64)> {
    use Quantity::*;
    let deg = std::f64::consts::PI / 180.0;
    Some(match name {
        "y_m" => (Y, 1.0),
        "y_mm" => (Y, 1e-3),
        "r_m" => (Radius, 1.0),
        "r_mm" => (Radius, 1e-3),
        "r_minus_r0_m" => (RadiusDelta, 1.0),
        "r_minus_r0_mm" => (RadiusDelta, 1e-3),
        "delta_rad" => (Angle, 1.0),
        "delta_deg" => (Angle, deg),
        "roll_rad" => (Roll, 1.0),
        "roll_deg" => (Roll, deg),
        "a_m" => (SemiA, 1.0),
        "a_mm" => (SemiA, 1e-3),
        "b_m" => (SemiB, 1.0),
        "b_mm" => (SemiB, 1e-3),
        "c11" => (C11, 1.0),
        "c22" => (C22, 1.0),
        "c23" => (C23, 1.0),
        "c33" => (C33, 1.0),
        "normal_force_N" => (Normal, 1.0),
        "normal_force_kN" => (Normal, 1e3),
        _ => return None,
    })
}

/// The parsed columns in SI, by quantity.
pub(super) struct Columns {
    /// line of the header (1-based)
    pub(super) header_line: usize,
    names: Vec<String>,
    kinds: Vec<(Quantity, f64)>,
    data: Vec<Vec<f64>>,
}

impl Columns {
    pub(super) fn get(&self, q: Quantity) -> Option<&[f64]> {
        self.kinds
            .iter()
            .position(|k| k.0 == q)
            .map(|i| self.data[i].as_slice())
    }
}

fn parse_header(path: &str, line: usize, text: &str) -> Result<Columns, TabulatedError> {
    let names: Vec<String> = text.split(',').map(|s| s.trim().to_string()).collect();
    let mut kinds: Vec<(Quantity, f64)> = Vec::new();
    for name in &names {
        let kind = column(name).ok_or_else(|| TabulatedError::UnknownColumn {
            path: path.into(),
            line,
            column: name.clone(),
            accepted: ACCEPTED,
        })?;
        let same = |q: Quantity| matches!(q, Quantity::Radius | Quantity::RadiusDelta);
        if kinds
            .iter()
            .any(|k| k.0 == kind.0 || (same(k.0) && same(kind.0)))
        {
            return Err(TabulatedError::DuplicateColumn {
                path: path.into(),
                line,
                column: name.clone(),
            });
        }
        kinds.push(kind);
    }
    Ok(Columns {
        header_line: line,
        data: vec![Vec::new(); names.len()],
        names,
        kinds,
    })
}

/// Reads the header and the rows, converting to SI and checking y's order.
pub(super) fn read_columns(text: &str, path: &str) -> Result<Columns, TabulatedError> {
    let mut cols: Option<Columns> = None;
    let mut last_y: Option<f64> = None;
    for (k, raw) in text.lines().enumerate() {
        let line = k + 1;
        let l = raw.trim();
        if l.is_empty() || l.starts_with('#') {
            continue;
        }
        let Some(c) = cols.as_mut() else {
            cols = Some(parse_header(path, line, l)?);
            continue;
        };
        let fields: Vec<&str> = l.split(',').map(str::trim).collect();
        if fields.len() != c.names.len() {
            return Err(TabulatedError::FieldCount {
                path: path.into(),
                line,
                expected: c.names.len(),
                found: fields.len(),
            });
        }
        for (i, f) in fields.iter().enumerate() {
            let v = f
                .parse::<f64>()
                .ok()
                .filter(|v| v.is_finite())
                .ok_or_else(|| TabulatedError::NotANumber {
                    path: path.into(),
                    line,
                    column: c.names[i].clone(),
                    text: (*f).into(),
                })?;
            let si = v * c.kinds[i].1;
            check_physical(path, line, &c.names[i], c.kinds[i].0, si)?;
            if c.kinds[i].0 == Quantity::Y {
                if let Some(prev) = last_y.filter(|&p| si <= p) {
                    return Err(TabulatedError::NotIncreasing {
                        path: path.into(),
                        line,
                        y_m: si,
                        previous_m: prev,
                    });
                }
                last_y = Some(si);
            }
            c.data[i].push(si);
        }
    }
    cols.ok_or_else(|| TabulatedError::NoHeader { path: path.into() })
}

fn check_physical(
    path: &str,
    line: usize,
    name: &str,
    q: Quantity,
    v: f64,
) -> Result<(), TabulatedError> {
    use Quantity::*;
    let rule = match q {
        Radius | SemiA | SemiB | Normal | C11 | C22 if v <= 0.0 => "must be positive",
        C23 | C33 if v < 0.0 => "must not be negative",
        Angle | Roll if v.abs() >= std::f64::consts::FRAC_PI_2 => "must lie in (−π/2, π/2)",
        _ => return Ok(()),
    };
    Err(TabulatedError::Unphysical {
        path: path.into(),
        line,
        column: name.into(),
        value: v,
        rule,
    })
}
