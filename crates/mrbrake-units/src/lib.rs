//! Physical quantities written with unit suffixes, parsed to SI.
//!
//! Brief overview: [`Dimension`] names what a quantity measures; [`parse`] turns text such as
//! `22.5mm`, `0.46 T`, `24.315kPa`, `300rpm` or a bare SI number (`0.0225`) into an `f64` in SI units,
//! and [`UnitError`] says precisely what was wrong and which units are allowed.
//!
//! Everything inside mrbrake is SI; units exist only at the edges (command line, spec files).
//!
//! ```
//! use mrbrake_units::{parse, Dimension};
//! let r1 = parse("22.5mm", Dimension::Length).unwrap();
//! assert!((r1 - 0.0225).abs() < 1e-15);
//! let w = parse("60 rpm", Dimension::AngularVelocity).unwrap();
//! assert!((w - 2.0 * std::f64::consts::PI).abs() < 1e-12);
//! ```

use std::fmt;

/// What a quantity measures; each has an SI base unit and a list of accepted suffixes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum Dimension {
    /// Length, SI unit m.
    Length,
    /// Magnetic flux density, SI unit T.
    FluxDensity,
    /// Magnetic field strength, SI unit A/m.
    FieldStrength,
    /// Stress or pressure (yield stress), SI unit Pa.
    Stress,
    /// Electric current, SI unit A.
    Current,
    /// Angular velocity, SI unit rad/s.
    AngularVelocity,
    /// Dynamic viscosity, SI unit Pa·s.
    Viscosity,
    /// Torque, SI unit N·m.
    Torque,
    /// Temperature in degrees Celsius (the one non-SI internal unit: resistances are quoted at °C).
    TemperatureCelsius,
    /// Time, SI unit s.
    Time,
    /// A plain number without unit.
    Dimensionless,
}

impl Dimension {
    /// The accepted suffixes and their factor to SI.
    pub fn units(self) -> &'static [(&'static str, f64)] {
        use std::f64::consts::PI;
        match self {
            Dimension::Length => {
                &[("m", 1.0), ("cm", 1e-2), ("mm", 1e-3), ("um", 1e-6), ("µm", 1e-6)]
            }
            Dimension::FluxDensity => &[("T", 1.0), ("mT", 1e-3), ("G", 1e-4)],
            Dimension::FieldStrength => &[("A/m", 1.0), ("kA/m", 1e3), ("MA/m", 1e6)],
            Dimension::Stress => &[("Pa", 1.0), ("kPa", 1e3), ("MPa", 1e6)],
            Dimension::Current => &[("A", 1.0), ("mA", 1e-3)],
            Dimension::AngularVelocity => {
                &[("rad/s", 1.0), ("rpm", 2.0 * PI / 60.0), ("deg/s", PI / 180.0), ("Hz", 2.0 * PI)]
            }
            Dimension::Viscosity => &[
                ("Pa.s", 1.0),
                ("Pa*s", 1.0),
                ("Pa·s", 1.0),
                ("Pas", 1.0),
                ("mPa.s", 1e-3),
                ("cP", 1e-3),
            ],
            Dimension::Torque => &[("Nm", 1.0), ("N.m", 1.0), ("N·m", 1.0), ("mNm", 1e-3)],
            Dimension::TemperatureCelsius => &[("C", 1.0), ("°C", 1.0), ("degC", 1.0)],
            Dimension::Time => &[("s", 1.0), ("ms", 1e-3), ("us", 1e-6), ("min", 60.0)],
            Dimension::Dimensionless => &[],
        }
    }

    /// The SI unit a bare number is read in.
    pub fn si_unit(self) -> &'static str {
        match self {
            Dimension::Length => "m",
            Dimension::FluxDensity => "T",
            Dimension::FieldStrength => "A/m",
            Dimension::Stress => "Pa",
            Dimension::Current => "A",
            Dimension::AngularVelocity => "rad/s",
            Dimension::Viscosity => "Pa.s",
            Dimension::Torque => "Nm",
            Dimension::TemperatureCelsius => "°C",
            Dimension::Time => "s",
            Dimension::Dimensionless => "",
        }
    }

    /// A human name for messages ("a length").
    pub fn describe(self) -> &'static str {
        match self {
            Dimension::Length => "a length",
            Dimension::FluxDensity => "a flux density",
            Dimension::FieldStrength => "a field strength",
            Dimension::Stress => "a stress",
            Dimension::Current => "a current",
            Dimension::AngularVelocity => "an angular velocity",
            Dimension::Viscosity => "a dynamic viscosity",
            Dimension::Torque => "a torque",
            Dimension::TemperatureCelsius => "a temperature",
            Dimension::Time => "a time",
            Dimension::Dimensionless => "a plain number",
        }
    }

    fn allowed_list(self) -> String {
        let names: Vec<&str> = self.units().iter().map(|(u, _)| *u).collect();
        if names.is_empty() {
            "no unit".to_string()
        } else {
            format!("{} (or a bare number in {})", names.join(", "), self.si_unit())
        }
    }
}

/// Why a quantity could not be read.
#[derive(Debug, Clone, PartialEq, Eq)]
#[non_exhaustive]
pub enum UnitError {
    /// The text is empty.
    Empty {
        /// What was expected.
        expected: Dimension,
    },
    /// The text does not start with a finite number.
    NotANumber {
        /// The text given.
        text: String,
        /// What was expected.
        expected: Dimension,
    },
    /// The suffix is not a unit of the expected dimension.
    WrongUnit {
        /// The text given.
        text: String,
        /// The suffix found.
        unit: String,
        /// What was expected.
        expected: Dimension,
    },
}

impl fmt::Display for UnitError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            UnitError::Empty { expected } => {
                write!(
                    f,
                    "empty value: expected {} with unit {}",
                    expected.describe(),
                    expected.allowed_list()
                )
            }
            UnitError::NotANumber { text, expected } => write!(
                f,
                "'{text}' is not a finite number: expected {} such as 1.5{}, units {}",
                expected.describe(),
                expected.units().get(1).or(expected.units().first()).map_or("", |u| u.0),
                expected.allowed_list()
            ),
            UnitError::WrongUnit { text, unit, expected } => write!(
                f,
                "'{text}': '{unit}' is not a unit of {}; allowed units: {}",
                expected.describe(),
                expected.allowed_list()
            ),
        }
    }
}

impl std::error::Error for UnitError {}

impl mrbrake_error::Kind for UnitError {
    /// Every unit error is bad input.
    fn kind(&self) -> mrbrake_error::ErrorKind {
        mrbrake_error::ErrorKind::Input
    }
}

/// Parses `text` as a quantity of dimension `dim` and returns its value in SI units.
///
/// A bare number is taken as SI (`0.0225` is 0.0225 m for a length). Whitespace between the number and
/// the unit is allowed. Units are case-sensitive (`mT` is not `MT`), as in the SI.
pub fn parse(text: &str, dim: Dimension) -> Result<f64, UnitError> {
    let t = text.trim();
    if t.is_empty() {
        return Err(UnitError::Empty { expected: dim });
    }
    let split = number_prefix_len(t);
    let (num, unit) = t.split_at(split);
    let value: f64 = num
        .parse()
        .ok()
        .filter(|v: &f64| v.is_finite())
        .ok_or_else(|| UnitError::NotANumber { text: t.to_string(), expected: dim })?;
    let unit = unit.trim();
    if unit.is_empty() {
        return Ok(value);
    }
    dim.units().iter().find(|(u, _)| *u == unit).map(|(_, factor)| value * factor).ok_or_else(
        || UnitError::WrongUnit { text: t.to_string(), unit: unit.to_string(), expected: dim },
    )
}

/// Length of the leading numeric part (sign, digits, point, exponent) of `t`.
fn number_prefix_len(t: &str) -> usize {
    let b = t.as_bytes();
    let mut i = 0;
    if i < b.len() && (b[i] == b'+' || b[i] == b'-') {
        i += 1;
    }
    while i < b.len() && (b[i].is_ascii_digit() || b[i] == b'.') {
        i += 1;
    }
    // An exponent only counts when digits follow (so "2e" stays a number "2" with unit "e").
    if i < b.len() && (b[i] == b'e' || b[i] == b'E') {
        let mut j = i + 1;
        if j < b.len() && (b[j] == b'+' || b[j] == b'-') {
            j += 1;
        }
        if j < b.len() && b[j].is_ascii_digit() {
            while j < b.len() && b[j].is_ascii_digit() {
                j += 1;
            }
            i = j;
        }
    }
    i
}

/// Formats an SI value with the most readable unit of `dim` (for echoing inputs back to the user).
pub fn format_si(value: f64, dim: Dimension) -> String {
    format!("{value} {}", dim.si_unit())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: f64, b: f64) -> bool {
        (a - b).abs() <= 1e-12 * (1.0 + b.abs())
    }

    #[test]
    fn parses_suffixes_to_si() {
        assert!(close(parse("22.5mm", Dimension::Length).unwrap(), 0.0225));
        assert!(close(parse("500 um", Dimension::Length).unwrap(), 5e-4));
        assert!(close(parse("0.46T", Dimension::FluxDensity).unwrap(), 0.46));
        assert!(close(parse("460mT", Dimension::FluxDensity).unwrap(), 0.46));
        assert!(close(parse("24.315kPa", Dimension::Stress).unwrap(), 24315.0));
        assert!(close(parse("500mA", Dimension::Current).unwrap(), 0.5));
        assert!(close(parse("0.056Pa.s", Dimension::Viscosity).unwrap(), 0.056));
        assert!(close(parse("1e-3m", Dimension::Length).unwrap(), 1e-3));
        assert!(close(parse("2.5E3 Pa", Dimension::Stress).unwrap(), 2500.0));
    }

    #[test]
    fn bare_numbers_are_si() {
        assert!(close(parse("0.0225", Dimension::Length).unwrap(), 0.0225));
        assert!(close(parse("-3", Dimension::Current).unwrap(), -3.0));
    }

    #[test]
    fn wrong_unit_names_the_allowed_ones() {
        let e = parse("22.5kg", Dimension::Length).unwrap_err();
        let msg = e.to_string();
        assert!(matches!(e, UnitError::WrongUnit { .. }));
        assert!(msg.contains("kg") && msg.contains("mm") && msg.contains("a length"), "{msg}");
        assert!(parse("0.46", Dimension::Dimensionless).is_ok());
        assert!(matches!(parse("3mm", Dimension::Current), Err(UnitError::WrongUnit { .. })));
    }

    #[test]
    fn garbage_is_not_a_number() {
        assert!(matches!(parse("mm", Dimension::Length), Err(UnitError::NotANumber { .. })));
        assert!(matches!(parse("", Dimension::Length), Err(UnitError::Empty { .. })));
        assert!(matches!(parse("inf", Dimension::Length), Err(UnitError::NotANumber { .. })));
        assert!(matches!(parse("1..2mm", Dimension::Length), Err(UnitError::NotANumber { .. })));
    }
}
