//! Design variables: the numeric fields of a brake spec that a study may vary, addressed by their
//! TOML path (`drum.gap`, `coil.turns`) or by the thesis's symbol (`g`, `h`, `R0`, `N`).
//!
//! Brief overview: the variable fields are the spec's own numeric fields
//! ([`mrbrake_design::spec::numeric_fields`], listed beside each table's definition, each with its
//! [`Quantity`]); [`resolve`] turns a user's name into a [`Variable`] for a given base spec (a symbol such as `g` means `drum.gap` for a
//! drum brake and `disc.gap` for a disc brake); [`Variable::parse_value`] reads a value with its unit
//! (`0.5mm`) into SI; [`set_field`] writes an SI value into the spec's TOML table. Values are written
//! as bare SI numbers, which the spec reader accepts, so a design file is unambiguous.

use mrbrake_design::spec::numeric_fields;
pub use mrbrake_design::spec::{Quantity, SpecField};
use mrbrake_units::{Dimension, parse};

use crate::ExploreError;

/// The thesis's symbols (chapter 3 and 4.4.2) and the field each names in a drum and in a disc
/// brake: `(symbol, drum field, disc field)`. A test checks that every field is one of the spec's
/// [`numeric_fields`] and exists in the configurations it is named for.
pub const SYMBOLS: &[(&str, Option<&str>, Option<&str>)] = &[
    ("g", Some("drum.gap"), Some("disc.gap")),
    ("h", Some("drum.height"), None),
    ("d", Some("drum.cylinder_thickness"), Some("disc.thickness")),
    ("R0", Some("drum.r0"), None),
    ("R1", None, Some("disc.inner_radius")),
    ("R2", None, Some("disc.outer_radius")),
    ("n", Some("drum.rotating_cylinders"), Some("disc.count")),
    ("N", Some("coil.turns"), Some("coil.turns")),
    ("I", Some("coil.max_current"), Some("coil.max_current")),
    ("AWG", Some("coil.wire.awg"), Some("coil.wire.awg")),
];

/// A variable resolved against a base spec.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Variable {
    /// The field it sets.
    pub field: SpecField,
    /// The name the user gave (a path or a symbol), used in reports.
    pub name: String,
}

impl Variable {
    /// Reads a value: a quantity with its unit (`0.5mm`, `2A`) or a bare SI number; an integer field
    /// takes a whole number.
    pub fn parse_value(&self, text: &str) -> Result<f64, ExploreError> {
        let text = text.trim();
        let bad = |why: String| {
            ExploreError::Input(format!("variable '{}' ({}): {why}", self.name, self.field.path))
        };
        match self.field.quantity {
            Quantity::Length => parse(text, Dimension::Length).map_err(|e| bad(e.to_string())),
            Quantity::Current => parse(text, Dimension::Current).map_err(|e| bad(e.to_string())),
            Quantity::Integer => {
                let value: i64 = text.parse().map_err(|_| {
                    bad(format!("'{text}' is not a whole number (this field counts something)"))
                })?;
                if value < 0 {
                    return Err(bad(format!("{value} is negative")));
                }
                Ok(value as f64)
            }
        }
    }

    /// The value formatted for people: millimetres for lengths, amperes, whole numbers.
    pub fn display_value(&self, si: f64) -> String {
        match self.field.quantity {
            Quantity::Length => format!("{}mm", round_sig(si * 1e3, 5)),
            Quantity::Current => format!("{}A", round_sig(si, 5)),
            Quantity::Integer => format!("{}", si.round() as i64),
        }
    }
}

/// Rounds to `significant` digits, so that `0.5e-3 * 1e3` prints `0.5`, not `0.49999999999999994`,
/// and a sampled 15.0402109 mm prints 15.04 mm.
fn round_sig(x: f64, significant: i32) -> f64 {
    if x == 0.0 || !x.is_finite() {
        return x;
    }
    let digits = significant - x.abs().log10().ceil() as i32;
    let scale = 10f64.powi(digits);
    (x * scale).round() / scale
}

/// Resolves `name` (a spec field's TOML path, see [`numeric_fields`], or a thesis symbol of
/// [`SYMBOLS`]) for a base spec whose configuration uses drums (`is_drum`) or discs.
pub fn resolve(name: &str, is_drum: bool) -> Result<Variable, ExploreError> {
    let trimmed = name.trim();
    let variable = |field: &SpecField| Variable { field: *field, name: trimmed.to_string() };
    if let Some(field) = numeric_fields().find(|f| f.path == trimmed) {
        return Ok(variable(field));
    }
    if let Some(&(symbol, drum, disc)) = SYMBOLS.iter().find(|(s, _, _)| *s == trimmed) {
        let path = if is_drum { drum } else { disc };
        let field = path.and_then(|path| numeric_fields().find(|f| f.path == path)).ok_or_else(|| {
            ExploreError::Input(format!(
                "variable '{symbol}' has no meaning for a {} brake; name the field instead (one of: {})",
                if is_drum { "drum" } else { "disc" },
                field_list()
            ))
        })?;
        return Ok(variable(field));
    }
    Err(ExploreError::Input(format!(
        "unknown design variable '{trimmed}': use a spec field ({}) or a thesis symbol ({})",
        field_list(),
        SYMBOLS.iter().map(|s| s.0).collect::<Vec<_>>().join(", ")
    )))
}

fn field_list() -> String {
    numeric_fields().map(|f| f.path).collect::<Vec<_>>().join(", ")
}

/// Writes the SI value `si` of `field` into the spec table, creating missing tables (e.g. a
/// `[spacer]` the base spec left out).
pub fn set_field(spec: &mut toml::Table, field: &SpecField, si: f64) -> Result<(), ExploreError> {
    let value = match field.quantity {
        Quantity::Integer => {
            let rounded = si.round();
            if (si - rounded).abs() > 1e-9 || rounded < 0.0 {
                return Err(ExploreError::Input(format!(
                    "{}: {si} is not a non-negative whole number",
                    field.path
                )));
            }
            toml::Value::Integer(rounded as i64)
        }
        Quantity::Length | Quantity::Current => {
            if !si.is_finite() {
                return Err(ExploreError::Input(format!("{}: {si} is not finite", field.path)));
            }
            toml::Value::Float(si)
        }
    };
    set_path(spec, field.path, Some(value))
}

/// Sets (`Some`) or removes (`None`) the value at a dotted path.
pub fn set_path(
    spec: &mut toml::Table,
    path: &str,
    value: Option<toml::Value>,
) -> Result<(), ExploreError> {
    let mut parts: Vec<&str> = path.split('.').collect();
    let last = parts.pop().filter(|s| !s.is_empty()).ok_or_else(|| {
        ExploreError::Input(format!("'{path}' is not a dotted spec path such as drum.gap"))
    })?;
    let mut table = spec;
    for part in parts {
        let entry =
            table.entry(part.to_string()).or_insert_with(|| toml::Value::Table(toml::Table::new()));
        table = entry.as_table_mut().ok_or_else(|| {
            ExploreError::Input(format!("'{path}': '{part}' is a value, not a table"))
        })?;
    }
    match value {
        Some(v) => {
            table.insert(last.to_string(), v);
        }
        None => {
            table.remove(last);
        }
    }
    Ok(())
}

/// Applies a fixed override `PATH=VALUE` to a spec table: `VALUE` is a quantity with its unit for a
/// variable field, `fill` for `coil.turns` (remove the count, so the turns fill the window, (4.2),
/// (4.3)), or any TOML value for other fields (e.g. `materials.fluid="mrf-132dg"`).
pub fn apply_override(
    spec: &mut toml::Table,
    path: &str,
    text: &str,
    is_drum: bool,
) -> Result<(), ExploreError> {
    let text = text.trim();
    if let Ok(variable) = resolve(path, is_drum) {
        if variable.field.path == "coil.turns" && text.eq_ignore_ascii_case("fill") {
            return set_path(spec, "coil.turns", None);
        }
        let si = variable.parse_value(text)?;
        return set_field(spec, &variable.field, si);
    }
    let value: toml::Value = match toml::from_str::<toml::Table>(&format!("v = {text}")) {
        Ok(mut t) => t.remove("v").unwrap_or(toml::Value::String(text.to_string())),
        Err(_) => toml::Value::String(text.to_string()),
    };
    set_path(spec, path.trim(), Some(value))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn symbols_follow_the_configuration() {
        assert_eq!(resolve("g", true).unwrap().field.path, "drum.gap");
        assert_eq!(resolve("g", false).unwrap().field.path, "disc.gap");
        assert!(resolve("R0", false).is_err());
        let err = resolve("gapp", true).unwrap_err().to_string();
        assert!(err.contains("drum.gap"), "{err}");
    }

    #[test]
    fn values_parse_with_units_and_integers_stay_whole() {
        let g = resolve("drum.gap", true).unwrap();
        assert!((g.parse_value("0.75mm").unwrap() - 0.75e-3).abs() < 1e-15);
        assert!((g.parse_value("0.001").unwrap() - 1e-3).abs() < 1e-15);
        let n = resolve("N", true).unwrap();
        assert!((n.parse_value("450").unwrap() - 450.0).abs() < 1e-12);
        assert!(n.parse_value("450.5").is_err());
        assert_eq!(g.display_value(0.5e-3), "0.5mm");
    }

    #[test]
    fn set_field_creates_tables_and_writes_si() {
        let mut t = toml::Table::new();
        set_field(&mut t, &resolve("spacer.thickness", true).unwrap().field, 4e-3).unwrap();
        let v = t["spacer"]["thickness"].as_float().unwrap();
        assert!((v - 4e-3).abs() < 1e-18);
        set_field(&mut t, &resolve("N", true).unwrap().field, 300.0).unwrap();
        assert_eq!(t["coil"]["turns"].as_integer(), Some(300));
        apply_override(&mut t, "coil.turns", "fill", true).unwrap();
        assert!(t["coil"].get("turns").is_none());
        apply_override(&mut t, "materials.fluid", "\"mrf-132dg\"", true).unwrap();
        assert_eq!(t["materials"]["fluid"].as_str(), Some("mrf-132dg"));
    }
}
