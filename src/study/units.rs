//! Physical quantities with units, as users write them in study files.
//!
//! A quantity is either a bare number, taken to be in SI units, or a string `"<number> <unit>"`
//! such as `"3.86e3 N/mm"`, `"700e6 kg mm^2"` or `"200 km/h"`. Each unit belongs to exactly one
//! [`Dimension`]; a unit of the wrong dimension is an error, never a silent reinterpretation.
//! Conversion to SI happens here and nowhere else.

use std::fmt;

/// The physical dimension a study key expects.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Dimension {
    /// m
    Length,
    /// kg
    Mass,
    /// kg m²
    Inertia,
    /// N
    Force,
    /// N/m
    Stiffness,
    /// N s/m
    Damping,
    /// N m (also the unit of the creep coefficient f23)
    ForceLength,
    /// N m² (the unit of the creep coefficient f33)
    ForceArea,
    /// Pa
    Pressure,
    /// m/s
    Speed,
    /// rad
    Angle,
    /// s
    Time,
    /// a pure number
    Dimensionless,
}

impl Dimension {
    /// The SI unit, as printed in messages and headers.
    pub fn si_unit(self) -> &'static str {
        match self {
            Dimension::Length => "m",
            Dimension::Mass => "kg",
            Dimension::Inertia => "kg m^2",
            Dimension::Force => "N",
            Dimension::Stiffness => "N/m",
            Dimension::Damping => "N s/m",
            Dimension::ForceLength => "N m",
            Dimension::ForceArea => "N m^2",
            Dimension::Pressure => "Pa",
            Dimension::Speed => "m/s",
            Dimension::Angle => "rad",
            Dimension::Time => "s",
            Dimension::Dimensionless => "",
        }
    }

    /// The units accepted for this dimension, with their factor to SI.
    fn units(self) -> &'static [(&'static str, f64)] {
        match self {
            Dimension::Length => &[("m", 1.0), ("mm", 1e-3), ("cm", 1e-2), ("km", 1e3)],
            Dimension::Mass => &[("kg", 1.0), ("t", 1e3), ("g", 1e-3)],
            Dimension::Inertia => &[("kg m^2", 1.0), ("kg mm^2", 1e-6), ("t m^2", 1e3)],
            Dimension::Force => &[("N", 1.0), ("kN", 1e3), ("MN", 1e6)],
            Dimension::Stiffness => &[
                ("N/m", 1.0),
                ("N/mm", 1e3),
                ("kN/m", 1e3),
                ("kN/mm", 1e6),
                ("MN/m", 1e6),
            ],
            Dimension::Damping => &[
                ("N s/m", 1.0),
                ("N s/mm", 1e3),
                ("kN s/m", 1e3),
                ("kN s/mm", 1e6),
                ("MN s/m", 1e6),
            ],
            Dimension::ForceLength => &[("N m", 1.0), ("N mm", 1e-3), ("kN m", 1e3)],
            Dimension::ForceArea => &[("N m^2", 1.0), ("N mm^2", 1e-6), ("kN m^2", 1e3)],
            Dimension::Pressure => &[
                ("Pa", 1.0),
                ("kPa", 1e3),
                ("MPa", 1e6),
                ("GPa", 1e9),
                ("N/mm^2", 1e6),
                ("N/m^2", 1.0),
            ],
            Dimension::Speed => &[("m/s", 1.0), ("km/h", 1.0 / 3.6), ("mph", 0.44704)],
            Dimension::Angle => &[
                ("rad", 1.0),
                ("mrad", 1e-3),
                ("deg", std::f64::consts::PI / 180.0),
            ],
            Dimension::Time => &[("s", 1.0), ("ms", 1e-3), ("min", 60.0)],
            Dimension::Dimensionless => &[("", 1.0)],
        }
    }

    /// What the dimension is called in messages.
    pub fn name(self) -> &'static str {
        match self {
            Dimension::Length => "length",
            Dimension::Mass => "mass",
            Dimension::Inertia => "moment of inertia",
            Dimension::Force => "force",
            Dimension::Stiffness => "stiffness",
            Dimension::Damping => "damping",
            Dimension::ForceLength => "force x length",
            Dimension::ForceArea => "force x area",
            Dimension::Pressure => "pressure",
            Dimension::Speed => "speed",
            Dimension::Angle => "angle",
            Dimension::Time => "time",
            Dimension::Dimensionless => "pure number",
        }
    }

    /// What a value of this dimension may be written as, for error messages.
    pub fn expectation(self) -> String {
        if matches!(self, Dimension::Dimensionless) {
            return format!("a {} without a unit (e.g. 0.3)", self.name());
        }
        format!(
            "a {} in SI ({}) or with one of the units {}",
            self.name(),
            self.si_unit(),
            self.accepted()
        )
    }

    /// The accepted units, for error messages.
    pub fn accepted(self) -> String {
        self.units()
            .iter()
            .map(|(u, _)| format!("'{u}'"))
            .collect::<Vec<_>>()
            .join(", ")
    }
}

impl fmt::Display for Dimension {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// A convenient display unit for a dimension: `(unit, factor)` with display = SI × factor
/// (reports of curves and trades, and their figures).
pub fn display_unit(dim: Dimension) -> (&'static str, f64) {
    match dim {
        Dimension::Stiffness => ("N/mm", 1e-3),
        Dimension::Damping => ("N s/mm", 1e-3),
        Dimension::Length => ("mm", 1e3),
        Dimension::Pressure => ("GPa", 1e-9),
        Dimension::Dimensionless => ("-", 1.0),
        d => (d.si_unit(), 1.0),
    }
}

/// Why a quantity string could not be read.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum UnitProblem {
    /// No number at the start.
    NoNumber,
    /// The unit is known, but of another dimension (e.g. `N/mm` for a damping).
    WrongDimension { unit: String, found: &'static str },
    /// The unit is not known at all.
    UnknownUnit { unit: String },
    /// The number is NaN or infinite.
    NotFinite,
    /// A string holding only a number where a unit is expected (write a plain number for SI).
    MissingUnit,
}

impl fmt::Display for UnitProblem {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            UnitProblem::NoNumber => f.write_str("it does not start with a number"),
            UnitProblem::WrongDimension { unit, found } => {
                write!(f, "'{unit}' is a unit of {found}")
            }
            UnitProblem::UnknownUnit { unit } => write!(f, "'{unit}' is not a known unit"),
            UnitProblem::NotFinite => f.write_str("it is not a finite number"),
            UnitProblem::MissingUnit => {
                f.write_str("it has no unit (write a plain number for SI, or add a unit)")
            }
        }
    }
}

/// Normalises spelling so that `N·s/m`, `N*s/m`, `Ns/m`, `kg·m²` and `N s / m` all match.
fn normalise(unit: &str) -> String {
    let mut u = unit
        .trim()
        .replace(['·', '*'], " ")
        .replace('²', "^2")
        .replace(" / ", "/")
        .replace("/ ", "/")
        .replace(" /", "/");
    while u.contains("  ") {
        u = u.replace("  ", " ");
    }
    // "Ns/m" and "Nm" are common in papers.
    match u.as_str() {
        "Ns/m" => "N s/m".into(),
        "Ns/mm" => "N s/mm".into(),
        "kNs/m" => "kN s/m".into(),
        "Nm" => "N m".into(),
        "Nmm" => "N mm".into(),
        "Nm^2" => "N m^2".into(),
        "Nmm^2" => "N mm^2".into(),
        "kgm^2" => "kg m^2".into(),
        "kgmm^2" => "kg mm^2".into(),
        "m2" => "m^2".into(),
        _ => u,
    }
}

fn lookup(dim: Dimension, unit: &str) -> Option<f64> {
    dim.units()
        .iter()
        .find(|(u, _)| *u == unit)
        .map(|&(_, factor)| factor)
}

const ALL: [Dimension; 13] = [
    Dimension::Length,
    Dimension::Mass,
    Dimension::Inertia,
    Dimension::Force,
    Dimension::Stiffness,
    Dimension::Damping,
    Dimension::ForceLength,
    Dimension::ForceArea,
    Dimension::Pressure,
    Dimension::Speed,
    Dimension::Angle,
    Dimension::Time,
    Dimension::Dimensionless,
];

/// Converts `"<number> <unit>"` to SI for the expected dimension.
///
/// ```
/// use critspeed::study::units::{parse_quantity, Dimension};
/// assert_eq!(parse_quantity("850 N/mm", Dimension::Stiffness), Ok(850e3));
/// assert!(parse_quantity("850 N/mm", Dimension::Damping).is_err());
/// ```
pub fn parse_quantity(text: &str, dim: Dimension) -> Result<f64, UnitProblem> {
    let text = text.trim();
    // The longest prefix that parses as a float is the number.
    let split = (1..=text.len())
        .rev()
        .filter(|&i| text.is_char_boundary(i))
        .find(|&i| text[..i].trim().parse::<f64>().is_ok())
        .ok_or(UnitProblem::NoNumber)?;
    let value: f64 = text[..split]
        .trim()
        .parse()
        .map_err(|_| UnitProblem::NoNumber)?;
    if !value.is_finite() {
        return Err(UnitProblem::NotFinite);
    }
    let unit = normalise(&text[split..]);
    if unit.is_empty() && dim != Dimension::Dimensionless {
        return Err(UnitProblem::MissingUnit);
    }
    if let Some(factor) = lookup(dim, &unit) {
        return Ok(value * factor);
    }
    match ALL.iter().find(|d| lookup(**d, &unit).is_some()) {
        Some(other) => Err(UnitProblem::WrongDimension {
            unit,
            found: other.name(),
        }),
        None => Err(UnitProblem::UnknownUnit { unit }),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: f64, b: f64) -> bool {
        (a - b).abs() <= 1e-12 * b.abs().max(1e-300)
    }

    #[test]
    fn every_unit_the_contract_names_converts() {
        let cases: &[(&str, Dimension, f64)] = &[
            ("742.9 mm", Dimension::Length, 0.7429),
            ("0.46 m", Dimension::Length, 0.46),
            ("1250 kg", Dimension::Mass, 1250.0),
            ("1.25 t", Dimension::Mass, 1250.0),
            ("700 kg m^2", Dimension::Inertia, 700.0),
            ("700e6 kg mm^2", Dimension::Inertia, 700.0),
            ("110000 N", Dimension::Force, 110_000.0),
            ("110 kN", Dimension::Force, 110_000.0),
            ("8.06 MN", Dimension::Force, 8.06e6),
            ("3.86e6 N/m", Dimension::Stiffness, 3.86e6),
            ("3.86e3 N/mm", Dimension::Stiffness, 3.86e6),
            ("3860 kN/m", Dimension::Stiffness, 3.86e6),
            ("3.86 MN/m", Dimension::Stiffness, 3.86e6),
            ("8000 N s/m", Dimension::Damping, 8000.0),
            ("8 N s/mm", Dimension::Damping, 8000.0),
            ("8 kN s/m", Dimension::Damping, 8000.0),
            ("2.2e4 N m", Dimension::ForceLength, 2.2e4),
            ("2.2e7 N mm", Dimension::ForceLength, 2.2e4),
            ("12.7 N m^2", Dimension::ForceArea, 12.7),
            ("1.27e7 N mm^2", Dimension::ForceArea, 12.7),
            ("8e10 Pa", Dimension::Pressure, 8e10),
            ("80e3 MPa", Dimension::Pressure, 8e10),
            ("210 GPa", Dimension::Pressure, 2.1e11),
            ("40 m/s", Dimension::Speed, 40.0),
            ("144 km/h", Dimension::Speed, 40.0),
            ("0.05 rad", Dimension::Angle, 0.05),
            ("50 mrad", Dimension::Angle, 0.05),
            ("180 deg", Dimension::Angle, std::f64::consts::PI),
        ];
        for &(text, dim, si) in cases {
            let got = parse_quantity(text, dim);
            assert!(
                matches!(got, Ok(v) if close(v, si)),
                "{text} as {dim}: {got:?}, expected {si}"
            );
        }
    }

    #[test]
    fn alternative_spellings() {
        for t in ["8 Ns/mm", "8 N·s/mm", "8 N*s/mm", "8 N s / mm", "8  N s/mm"] {
            assert_eq!(parse_quantity(t, Dimension::Damping), Ok(8000.0), "{t}");
        }
        assert_eq!(
            parse_quantity("700e6 kg·mm²", Dimension::Inertia),
            Ok(700.0)
        );
        assert_eq!(parse_quantity(" 5 ", Dimension::Dimensionless), Ok(5.0));
    }

    #[test]
    fn wrong_and_unknown_units_are_named() {
        assert_eq!(
            parse_quantity("850 N/mm", Dimension::Damping),
            Err(UnitProblem::WrongDimension {
                unit: "N/mm".into(),
                found: "stiffness"
            })
        );
        assert_eq!(
            parse_quantity("3 furlongs", Dimension::Length),
            Err(UnitProblem::UnknownUnit {
                unit: "furlongs".into()
            })
        );
        assert_eq!(
            parse_quantity("mm", Dimension::Length),
            Err(UnitProblem::NoNumber)
        );
        assert_eq!(
            parse_quantity("inf m", Dimension::Length),
            Err(UnitProblem::NotFinite)
        );
        // A bare number where a unit is needed is SI; a unit where none is expected is an error.
        assert_eq!(
            parse_quantity("0.7", Dimension::Length),
            Err(UnitProblem::MissingUnit)
        );
    }
}
