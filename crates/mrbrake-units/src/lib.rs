//! Physical quantities written with unit suffixes, parsed to SI.
//!
//! Brief overview: [`Dimension`] names what a quantity measures; [`parse`] turns text such as
//! `22.5mm`, `0.46 T`, `24.315kPa`, `300rpm` or a bare SI number (`0.0225`) into an `f64` in SI units;
//! [`unit_scale`] gives the SI factor of a unit named on its own (a problem file's
//! `length_unit = "mm"`), from the same table; and [`UnitError`] says precisely what was wrong and
//! which units are allowed.
//!
//! Everything inside mrbrake is SI; units exist only at the edges (command line, spec files).
//!
//! ```
//! use mrbrake_units::{parse, Dimension};
//! let r1 = parse("22.5mm", Dimension::Length).unwrap();
//! assert!((r1 - 0.0225).abs() < 1e-15);
//! let w = parse("60 rpm", Dimension::AngularVelocity).unwrap();
//! assert!((w - 2.0 * std::f64::consts::PI).abs() < 1e-12);
//! let metres_per_unit = mrbrake_units::unit_scale("mm", Dimension::Length).unwrap();
//! assert!((metres_per_unit - 1e-3).abs() < 1e-18);
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
    /// Rotational stiffness (a virtual wall's K), SI unit N·m/rad.
    RotationalStiffness,
    /// Rotational viscous damping (a virtual wall's B), SI unit N·m·s/rad.
    RotationalDamping,
    /// Electrical conductivity, SI unit S/m.
    Conductivity,
    /// Heat-transfer coefficient of a surface, SI unit W/(m²·K).
    HeatTransferCoefficient,
    /// Force (a bearing load), SI unit N.
    Force,
    /// A plain number without unit.
    Dimensionless,
}

impl Dimension {
    /// Every dimension, in declaration order.
    pub const ALL: [Dimension; 16] = [
        Dimension::Length,
        Dimension::FluxDensity,
        Dimension::FieldStrength,
        Dimension::Stress,
        Dimension::Current,
        Dimension::AngularVelocity,
        Dimension::Viscosity,
        Dimension::Torque,
        Dimension::TemperatureCelsius,
        Dimension::Time,
        Dimension::RotationalStiffness,
        Dimension::RotationalDamping,
        Dimension::Conductivity,
        Dimension::HeatTransferCoefficient,
        Dimension::Force,
        Dimension::Dimensionless,
    ];

    /// The dimension whose SI unit is spelled `unit` (any of its factor-1 spellings: `"N·m"` and
    /// `"Nm"` are a torque), or `None` (a derived or unknown unit such as `"A/mm²"`). For values
    /// whose SI unit is known as text, e.g. a study metric's, to read `"80mm"` with [`parse`].
    pub fn from_si_unit(unit: &str) -> Option<Dimension> {
        let unit = unit.trim();
        Self::ALL.into_iter().find(|dim| {
            dim.units().iter().any(|&(name, factor)| name == unit && (factor - 1.0).abs() < 1e-15)
        })
    }

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
            Dimension::Time => {
                &[("s", 1.0), ("ms", 1e-3), ("us", 1e-6), ("min", 60.0), ("h", 3600.0)]
            }
            Dimension::RotationalStiffness => &[
                ("N·m/rad", 1.0),
                ("Nm/rad", 1.0),
                ("N.m/rad", 1.0),
                ("mN·m/rad", 1e-3),
                ("mNm/rad", 1e-3),
            ],
            Dimension::RotationalDamping => &[
                ("N·m·s/rad", 1.0),
                ("Nms/rad", 1.0),
                ("N.m.s/rad", 1.0),
                ("mN·m·s/rad", 1e-3),
                ("mNms/rad", 1e-3),
            ],
            Dimension::Conductivity => &[("S/m", 1.0), ("MS/m", 1e6)],
            Dimension::HeatTransferCoefficient => &[
                ("W/(m²·K)", 1.0),
                ("W/(m²K)", 1.0),
                ("W/(m2K)", 1.0),
                ("W/m2K", 1.0),
                ("W/m²K", 1.0),
            ],
            Dimension::Force => &[("N", 1.0), ("kN", 1e3), ("mN", 1e-3)],
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
            Dimension::RotationalStiffness => "N·m/rad",
            Dimension::RotationalDamping => "N·m·s/rad",
            Dimension::Conductivity => "S/m",
            Dimension::HeatTransferCoefficient => "W/(m²·K)",
            Dimension::Force => "N",
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
            Dimension::RotationalStiffness => "a rotational stiffness",
            Dimension::RotationalDamping => "a rotational damping",
            Dimension::Conductivity => "an electrical conductivity",
            Dimension::HeatTransferCoefficient => "a heat-transfer coefficient",
            Dimension::Force => "a force",
            Dimension::Dimensionless => "a plain number",
        }
    }

    /// The accepted suffixes, comma-separated, with the bare-number rule of [`parse`].
    fn allowed_list(self) -> String {
        let names = self.unit_names();
        if names.is_empty() {
            "no unit".to_string()
        } else {
            format!("{names} (or a bare number in {})", self.si_unit())
        }
    }

    /// The accepted suffixes, comma-separated (empty for [`Dimension::Dimensionless`]).
    fn unit_names(self) -> String {
        self.units().iter().map(|(u, _)| *u).collect::<Vec<_>>().join(", ")
    }

    /// The SI factor of the unit called `unit`, if it is one of this dimension's.
    fn factor_of(self, unit: &str) -> Option<f64> {
        self.units().iter().find(|(u, _)| *u == unit).map(|(_, factor)| *factor)
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
    /// A unit named on its own (see [`unit_scale`]) is not a unit of the expected dimension.
    UnknownUnit {
        /// The name given.
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
            UnitError::UnknownUnit { unit, expected } => write!(
                f,
                "'{unit}' is not a unit of {}; allowed units: {}",
                expected.describe(),
                expected.unit_names()
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
    dim.factor_of(unit).map(|factor| value * factor).ok_or_else(|| UnitError::WrongUnit {
        text: t.to_string(),
        unit: unit.to_string(),
        expected: dim,
    })
}

/// The SI factor of the unit called `unit` (surrounding spaces ignored, case-sensitive): the
/// number of SI units in one `unit`, e.g. `unit_scale("mm", Dimension::Length)` is 1e-3 (metres
/// per millimetre). The units and factors are those [`parse`] accepts as suffixes, so a file's
/// `length_unit = "um"` and a value `"500um"` mean the same thing.
///
/// For a key that names a unit on its own, such as a problem file's `length_unit`; an unknown
/// name gives [`UnitError::UnknownUnit`], whose message lists the allowed units.
pub fn unit_scale(unit: &str, dim: Dimension) -> Result<f64, UnitError> {
    let name = unit.trim();
    dim.factor_of(name)
        .ok_or_else(|| UnitError::UnknownUnit { unit: name.to_string(), expected: dim })
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

/// Formats an SI value with the SI unit of `dim` (`0.0225 m`), for echoing inputs back to the user.
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

    /// Issue 19: a haptic wall's K and B, a conductivity and a film coefficient carry units too.
    #[test]
    fn wall_and_material_quantities_parse() {
        let k = Dimension::RotationalStiffness;
        assert!(close(parse("30N·m/rad", k).unwrap(), 30.0));
        assert!(close(parse("30 Nm/rad", k).unwrap(), 30.0));
        assert!(close(parse("500mNm/rad", k).unwrap(), 0.5));
        let b = Dimension::RotationalDamping;
        assert!(close(parse("0.02N·m·s/rad", b).unwrap(), 0.02));
        assert!(close(parse("-20mNms/rad", b).unwrap(), -0.02));
        assert!(close(parse("5.8MS/m", Dimension::Conductivity).unwrap(), 5.8e6));
        assert!(close(parse("10W/(m²·K)", Dimension::HeatTransferCoefficient).unwrap(), 10.0));
        assert!(close(parse("10 W/m2K", Dimension::HeatTransferCoefficient).unwrap(), 10.0));
        // A damping is not a stiffness.
        let e = parse("30Nms/rad", k).unwrap_err().to_string();
        assert!(e.contains("a rotational stiffness") && e.contains("Nm/rad"), "{e}");
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
    fn unit_scale_reads_the_suffix_table() {
        // Every suffix `parse` accepts has the same factor on its own, for every dimension.
        for dim in [Dimension::Length, Dimension::FluxDensity, Dimension::AngularVelocity] {
            for &(unit, factor) in dim.units() {
                assert!(close(unit_scale(unit, dim).unwrap(), factor), "{unit}");
                assert!(close(parse(&format!("2{unit}"), dim).unwrap(), 2.0 * factor), "{unit}");
            }
        }
        assert!(close(unit_scale(" mm ", Dimension::Length).unwrap(), 1e-3));
        assert!(close(unit_scale("µm", Dimension::Length).unwrap(), 1e-6));
    }

    #[test]
    fn si_unit_names_give_their_dimension() {
        for dim in Dimension::ALL {
            if dim != Dimension::Dimensionless {
                assert_eq!(Dimension::from_si_unit(dim.si_unit()), Some(dim), "{dim:?}");
            }
        }
        assert_eq!(Dimension::from_si_unit("N·m"), Some(Dimension::Torque));
        assert_eq!(Dimension::from_si_unit(" T "), Some(Dimension::FluxDensity));
        // A scaled unit is not an SI unit, and a derived unit has no dimension here.
        assert_eq!(Dimension::from_si_unit("mm"), None);
        assert_eq!(Dimension::from_si_unit("A/mm²"), None);
        assert_eq!(Dimension::from_si_unit(""), None);
    }

    #[test]
    fn unit_scale_names_the_allowed_units() {
        let e = unit_scale("inch", Dimension::Length).unwrap_err();
        assert_eq!(
            e,
            UnitError::UnknownUnit { unit: "inch".to_string(), expected: Dimension::Length }
        );
        assert_eq!(
            e.to_string(),
            "'inch' is not a unit of a length; allowed units: m, cm, mm, um, µm"
        );
        assert!(mrbrake_error::Kind::is_input_error(&e));
        // Case-sensitive, as in the SI: `MM` is not a length unit, and a number is not a unit.
        assert!(unit_scale("MM", Dimension::Length).is_err());
        assert!(unit_scale("1e-3", Dimension::Length).is_err());
        assert!(unit_scale("", Dimension::Length).is_err());
    }

    #[test]
    fn garbage_is_not_a_number() {
        assert!(matches!(parse("mm", Dimension::Length), Err(UnitError::NotANumber { .. })));
        assert!(matches!(parse("", Dimension::Length), Err(UnitError::Empty { .. })));
        assert!(matches!(parse("inf", Dimension::Length), Err(UnitError::NotANumber { .. })));
        assert!(matches!(parse("1..2mm", Dimension::Length), Err(UnitError::NotANumber { .. })));
    }
}
