//! Design variables: the fields of a brake spec that a study may vary, addressed by their TOML
//! path (`drum.gap`, `coil.turns`, `materials.bobbin`) or by the thesis's symbol (`g`, `h`, `R0`,
//! `N`).
//!
//! Brief overview: a variable is a numeric field ([`mrbrake_design::spec::numeric_fields`], listed
//! beside each table's definition, each with its [`Quantity`]) or the material of a part role
//! ([`MATERIAL_FIELDS`]: a categorical variable whose levels are library materials that suit the
//! part). [`resolve`] turns a user's name into a [`Variable`] for a given base spec (a symbol such
//! as `g` means `drum.gap` for a drum brake and `disc.gap` for a disc brake); a categorical one
//! gets its levels with [`Variable::with_levels`], each checked against the library and the part
//! role. A variable's value is a number: SI for a numeric field ([`Variable::parse_value`] reads a
//! value with its unit, `0.5mm`), the level's index for a material, which is how the optimisers
//! of [`mrbrake_optim`] see it (`Bounds::categorical`). [`Variable::set`] writes a value into the
//! spec's TOML table, as a bare SI number (which the spec reader accepts, so a design file is
//! unambiguous) or the level's name; [`Variable::value`] is what a stored record keeps: the number,
//! or the level by name.
//!
//! Fixed changes to a base spec (`--set PATH=VALUE`, a problem file's `[set]`) are parsed by
//! [`parse_set`] and applied by [`apply_override`], the one reader of both.

use mrbrake_design::spec::{MATERIAL_FIELDS, MaterialField, numeric_fields};
pub use mrbrake_design::spec::{Quantity, SpecField};
use mrbrake_error::FieldError;
use mrbrake_optim::space::Bounds;
use mrbrake_store::VariableValue;
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

/// What a variable sets: a numeric field, or the material of a part role with its levels.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum VariableKind {
    /// A numeric field of the spec.
    Numeric(SpecField),
    /// The material of a part role: a categorical variable whose value is the index of one of
    /// `levels` (library names, in the user's order; empty until [`Variable::with_levels`]).
    Material {
        /// The material field.
        field: &'static MaterialField,
        /// The library materials the variable takes.
        levels: Vec<String>,
    },
}

/// A variable resolved against a base spec.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Variable {
    /// What it sets.
    pub kind: VariableKind,
    /// The name the user gave (a path or a symbol), used in reports.
    pub name: String,
}

impl Variable {
    /// The dotted spec path it sets (`drum.gap`, `materials.bobbin`).
    pub fn path(&self) -> &'static str {
        match &self.kind {
            VariableKind::Numeric(field) => field.path,
            VariableKind::Material { field, .. } => field.path,
        }
    }

    /// What a numeric variable holds (`None` for a material).
    pub fn quantity(&self) -> Option<Quantity> {
        match &self.kind {
            VariableKind::Numeric(field) => Some(field.quantity),
            VariableKind::Material { .. } => None,
        }
    }

    /// The levels of a categorical (material) variable; empty for a numeric one.
    pub fn levels(&self) -> &[String] {
        match &self.kind {
            VariableKind::Numeric(_) => &[],
            VariableKind::Material { levels, .. } => levels,
        }
    }

    /// True for a categorical (material) variable.
    pub fn is_categorical(&self) -> bool {
        matches!(self.kind, VariableKind::Material { .. })
    }

    /// This material variable with `levels`: each a library material that suits the part role
    /// ([`MaterialField::check_suits`]), none twice, at least one. An error names the variable, the
    /// level and the allowed materials; a numeric variable takes no levels.
    pub fn with_levels(mut self, levels: &[String]) -> Result<Self, ExploreError> {
        let name = self.name.clone();
        let bad = |why: String| ExploreError::input(&name, format!("variable: {why}"));
        let VariableKind::Material { field, levels: own } = &mut self.kind else {
            return Err(bad("a numeric field takes min and max, not a list of levels".into()));
        };
        if levels.is_empty() {
            let e = FieldError::new(&name, "variable: give at least one material")
                .with_allowed(allowed(field));
            return Err(e.into());
        }
        let mut names: Vec<String> = Vec::with_capacity(levels.len());
        for level in levels {
            field.check_suits(level)?;
            let level = level.trim().to_ascii_lowercase();
            if names.contains(&level) {
                return Err(bad(format!("the material '{level}' is listed twice")));
            }
            names.push(level);
        }
        *own = names;
        Ok(self)
    }

    /// Reads a value: a quantity with its unit (`0.5mm`, `2A`) or a bare SI number; an integer field
    /// takes a whole number; a material variable a level's name (its index is returned).
    pub fn parse_value(&self, text: &str) -> Result<f64, ExploreError> {
        let text = text.trim();
        let bad = |why: String| self.error(why);
        let field = match &self.kind {
            VariableKind::Numeric(field) => field,
            VariableKind::Material { levels, .. } => {
                let name = text.trim_matches('"').to_ascii_lowercase();
                return levels.iter().position(|l| *l == name).map(|i| i as f64).ok_or_else(|| {
                    bad(format!("'{text}' is not one of its materials: {}", levels.join(", ")))
                });
            }
        };
        match field.quantity {
            Quantity::Length => parse(text, Dimension::Length).map_err(|e| bad(e.to_string())),
            Quantity::Current => parse(text, Dimension::Current).map_err(|e| bad(e.to_string())),
            Quantity::Conductivity => {
                parse(text, Dimension::Conductivity).map_err(|e| bad(e.to_string()))
            }
            Quantity::Torque => parse(text, Dimension::Torque).map_err(|e| bad(e.to_string())),
            Quantity::Factor => text
                .parse::<f64>()
                .map_err(|_| bad(format!("'{text}' is not a number (this field is a factor)"))),
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

    /// The level of a material variable at index `x` (a whole number in range), as an error
    /// naming the variable otherwise.
    pub fn level(&self, x: f64) -> Result<&str, ExploreError> {
        let levels = self.levels();
        let index = x.round();
        if (x - index).abs() > 1e-9 || index < 0.0 || index as usize >= levels.len() {
            let e = FieldError::new(&self.name, "variable: not the index of one of its materials")
                .with_value(x)
                .with_allowed(format!("0 to {}", levels.len().saturating_sub(1)));
            return Err(e.into());
        }
        Ok(&levels[index as usize])
    }

    /// An input error about this variable (named as written) and the field it sets, saying `why`.
    fn error(&self, why: String) -> ExploreError {
        let message = if self.name == self.path() {
            format!("variable: {why}")
        } else {
            format!("variable ({}): {why}", self.path())
        };
        ExploreError::input(&self.name, message)
    }

    /// The value a stored record keeps: the number, or the material by name.
    pub fn value(&self, x: f64) -> Result<VariableValue, ExploreError> {
        Ok(match self.kind {
            VariableKind::Numeric(_) => VariableValue::Number(x),
            VariableKind::Material { .. } => VariableValue::Level(self.level(x)?.to_string()),
        })
    }

    /// This variable's value in a stored record as the optimisers see it: the number, or for a
    /// material the index of the level the record names (`None` when the record lacks the
    /// variable, or names a material that is not one of its levels). The inverse of
    /// [`Self::value`].
    pub fn x_in(&self, record: &mrbrake_store::Record) -> Option<f64> {
        match (&self.kind, record.variable_value(&self.name)?) {
            (VariableKind::Numeric(_), VariableValue::Number(x)) => Some(*x),
            (VariableKind::Material { levels, .. }, VariableValue::Level(name)) => {
                levels.iter().position(|level| level == name).map(|i| i as f64)
            }
            _ => None,
        }
    }

    /// Writes the value `x` (SI, or a level's index) into the spec table.
    pub fn set(&self, spec: &mut toml::Table, x: f64) -> Result<(), ExploreError> {
        match &self.kind {
            VariableKind::Numeric(field) => set_field(spec, field, x),
            VariableKind::Material { field, .. } => {
                set_path(spec, field.path, Some(toml::Value::String(self.level(x)?.to_string())))
            }
        }
    }

    /// The optimiser's bounds of the variable between `lower` and `upper` (SI): continuous,
    /// integer, or categorical over its levels (the bounds are then its levels' indices).
    pub fn bounds(&self, lower: f64, upper: f64) -> Bounds {
        match self.quantity() {
            Some(Quantity::Integer) => Bounds::integer(lower, upper),
            Some(
                Quantity::Length
                | Quantity::Current
                | Quantity::Factor
                | Quantity::Conductivity
                | Quantity::Torque,
            ) => Bounds::continuous(lower, upper),
            None => Bounds::categorical(self.levels().len()),
        }
    }

    /// The value formatted for people: millimetres for lengths, amperes, whole numbers, the
    /// material's name.
    pub fn display_value(&self, x: f64) -> String {
        match self.quantity() {
            Some(Quantity::Length) => format!("{}mm", round_sig(x * 1e3, 5)),
            Some(Quantity::Current) => format!("{}A", round_sig(x, 5)),
            Some(Quantity::Integer) => format!("{}", x.round() as i64),
            Some(Quantity::Factor) => format!("{}", round_sig(x, 5)),
            Some(Quantity::Conductivity) => format!("{}MS/m", round_sig(x * 1e-6, 5)),
            Some(Quantity::Torque) => format!("{}mNm", round_sig(x * 1e3, 5)),
            None => self.level(x).map_or_else(|_| format!("level {x}"), str::to_string),
        }
    }

    /// A stored value formatted for people (see [`Self::display_value`]).
    pub fn display(&self, value: &VariableValue) -> String {
        match value {
            VariableValue::Number(x) if !self.is_categorical() => self.display_value(*x),
            other => other.to_string(),
        }
    }
}

/// The library materials that suit a material field, for messages.
fn allowed(field: &MaterialField) -> String {
    field.suitable().join(", ")
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

/// Resolves `name` (a spec field's TOML path, see [`numeric_fields`] and [`MATERIAL_FIELDS`], or a
/// thesis symbol of [`SYMBOLS`]) for a base spec whose configuration uses drums (`is_drum`) or
/// discs. A material variable comes without levels ([`Variable::with_levels`] gives them).
pub fn resolve(name: &str, is_drum: bool) -> Result<Variable, ExploreError> {
    let trimmed = name.trim();
    let variable = |field: &SpecField| Variable {
        kind: VariableKind::Numeric(*field),
        name: trimmed.to_string(),
    };
    if let Some(field) = numeric_fields().find(|f| f.path == trimmed) {
        return Ok(variable(field));
    }
    if let Some(field) = MaterialField::at(trimmed) {
        let kind = VariableKind::Material { field, levels: Vec::new() };
        return Ok(Variable { kind, name: trimmed.to_string() });
    }
    if let Some(&(symbol, drum, disc)) = SYMBOLS.iter().find(|(s, _, _)| *s == trimmed) {
        let path = if is_drum { drum } else { disc };
        let field =
            path.and_then(|path| numeric_fields().find(|f| f.path == path)).ok_or_else(|| {
                let configuration = if is_drum { "drum" } else { "disc" };
                FieldError::new(
                    symbol,
                    format!(
                        "variable: no meaning for a {configuration} brake; name the field instead"
                    ),
                )
                .with_allowed(field_list())
            })?;
        return Ok(variable(field));
    }
    let e = FieldError::new(trimmed, "unknown design variable").with_allowed(format!(
        "a spec field ({}), a material ({}) or a thesis symbol ({})",
        field_list(),
        MATERIAL_FIELDS.iter().map(|f| f.path).collect::<Vec<_>>().join(", "),
        SYMBOLS.iter().map(|s| s.0).collect::<Vec<_>>().join(", ")
    ));
    Err(e.into())
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
                let e = FieldError::out_of_range(field.path, si, "a whole number >= 0");
                return Err(e.into());
            }
            toml::Value::Integer(rounded as i64)
        }
        Quantity::Length
        | Quantity::Current
        | Quantity::Factor
        | Quantity::Conductivity
        | Quantity::Torque => {
            if !si.is_finite() {
                return Err(FieldError::out_of_range(field.path, si, "finite").into());
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
    let last = parts
        .pop()
        .filter(|s| !s.is_empty())
        .ok_or_else(|| FieldError::new(path, "not a dotted spec path such as drum.gap"))?;
    let mut table = spec;
    for part in parts {
        let entry =
            table.entry(part.to_string()).or_insert_with(|| toml::Value::Table(toml::Table::new()));
        table = entry
            .as_table_mut()
            .ok_or_else(|| FieldError::new(path, format!("'{part}' is a value, not a table")))?;
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

/// Splits one fixed change `PATH=VALUE` (the `--set` of `mrbrake sweep` and `mrbrake optimize`,
/// the `set` of the Python package) into its path and value, both trimmed.
pub fn parse_set(text: &str) -> Result<(String, String), ExploreError> {
    let (path, value) = text.split_once('=').ok_or_else(|| {
        FieldError::new("set", "expected PATH=VALUE")
            .with_value(format!("'{text}'"))
            .with_allowed("e.g. coil.turns=fill or materials.bobbin=pom")
    })?;
    let path = path.trim();
    if !is_spec_path(path) {
        return Err(FieldError::new("set", "names no field of a brake spec")
            .with_value(format!("'{path}'"))
            .with_allowed(
                "a spec key (docs/reference/spec.md, e.g. drum.gap, coil.turns, \
                 materials.bobbin) or a design-variable symbol (R0, h, g, …)",
            )
            .into());
    }
    Ok((path.to_string(), value.trim().to_string()))
}

/// True when `path` is a key of the spec's schema (any configuration) or a variable's name
/// (an unknown `--set` path made every design of a study infeasible, with exit 0).
fn is_spec_path(path: &str) -> bool {
    if resolve(path, true).is_ok() || resolve(path, false).is_ok() {
        return true;
    }
    let mut schema = mrbrake_design::spec::schema();
    mrbrake_schema::node_mut(&mut schema, path).is_some()
}

/// [`parse_set`] of every argument, in order.
pub fn parse_sets(texts: &[String]) -> Result<Vec<(String, String)>, ExploreError> {
    texts.iter().map(|t| parse_set(t)).collect()
}

/// Applies a fixed override `PATH=VALUE` to a spec table: `VALUE` is a quantity with its unit for a
/// variable field, `fill` for `coil.turns` (remove the count, so the turns fill the window, (4.2),
/// (4.3)), a library material that suits the part for a material field (`materials.bobbin=pom`),
/// or any TOML value for other fields.
pub fn apply_override(
    spec: &mut toml::Table,
    path: &str,
    text: &str,
    is_drum: bool,
) -> Result<(), ExploreError> {
    let text = text.trim();
    if let Ok(variable) = resolve(path, is_drum) {
        if variable.path() == "coil.turns" && text.eq_ignore_ascii_case("fill") {
            return set_path(spec, "coil.turns", None);
        }
        if variable.is_categorical() {
            let variable = variable.with_levels(&[toml_text(text)])?;
            return variable.set(spec, 0.0);
        }
        let si = variable.parse_value(text)?;
        return variable.set(spec, si);
    }
    let value: toml::Value = match toml::from_str::<toml::Table>(&format!("v = {text}")) {
        Ok(mut t) => t.remove("v").unwrap_or(toml::Value::String(text.to_string())),
        Err(_) => toml::Value::String(text.to_string()),
    };
    set_path(spec, path.trim(), Some(value))
}

/// The text of a value written bare (`pom`) or as a TOML string (`"pom"`).
fn toml_text(text: &str) -> String {
    match toml::from_str::<toml::Table>(&format!("v = {text}")) {
        Ok(t) => t.get("v").and_then(toml::Value::as_str).unwrap_or(text).to_string(),
        Err(_) => text.to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn symbols_follow_the_configuration() {
        assert_eq!(resolve("g", true).unwrap().path(), "drum.gap");
        assert_eq!(resolve("g", false).unwrap().path(), "disc.gap");
        assert!(resolve("R0", false).is_err());
        let err = resolve("gapp", true).unwrap_err().to_string();
        assert!(err.contains("drum.gap") && err.contains("materials.bobbin"), "{err}");
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
        let spacer = resolve("spacer.thickness", true).unwrap();
        spacer.set(&mut t, 4e-3).unwrap();
        let v = t["spacer"]["thickness"].as_float().unwrap();
        assert!((v - 4e-3).abs() < 1e-18);
        resolve("N", true).unwrap().set(&mut t, 300.0).unwrap();
        assert_eq!(t["coil"]["turns"].as_integer(), Some(300));
        apply_override(&mut t, "coil.turns", "fill", true).unwrap();
        assert!(t["coil"].get("turns").is_none());
        apply_override(&mut t, "materials.fluid", "\"mrf-132dg\"", true).unwrap();
        assert_eq!(t["materials"]["fluid"].as_str(), Some("mrf-132dg"));
        apply_override(&mut t, "materials.bobbin", "POM", true).unwrap();
        assert_eq!(t["materials"]["bobbin"].as_str(), Some("pom"));
    }

    /// A material variable takes library materials that suit its part, by name; its value is a
    /// level's index, kept by name in the record.
    #[test]
    fn a_material_variable_takes_suitable_levels_by_name() {
        let names = |list: &[&str]| list.iter().map(|s| s.to_string()).collect::<Vec<_>>();
        let bobbin = resolve("materials.bobbin", true).unwrap();
        assert!(bobbin.is_categorical() && bobbin.levels().is_empty());
        let bobbin = bobbin.with_levels(&names(&["aluminium", "Stainless-304", "pom"])).unwrap();
        assert_eq!(bobbin.levels(), ["aluminium", "stainless-304", "pom"]);
        assert!((bobbin.parse_value("pom").unwrap() - 2.0).abs() < 1e-12);
        assert_eq!(bobbin.value(1.0).unwrap(), VariableValue::Level("stainless-304".into()));
        assert_eq!(bobbin.display_value(0.0), "aluminium");
        assert!(bobbin.value(3.0).is_err() && bobbin.value(0.5).is_err());
        assert_eq!(bobbin.bounds(0.0, 0.0), Bounds::categorical(3));
        let mut t = toml::Table::new();
        bobbin.set(&mut t, 2.0).unwrap();
        assert_eq!(t["materials"]["bobbin"].as_str(), Some("pom"));
        let refuse = |field: &str, list: &[&str]| {
            resolve(field, true).unwrap().with_levels(&names(list)).unwrap_err().to_string()
        };
        let e = refuse("materials.bobbin", &["steel-1008"]);
        assert!(e.contains("materials.bobbin") && e.contains("steel") && e.contains("pom"), "{e}");
        let e = refuse("materials.bobbin", &["unobtainium"]);
        assert!(e.contains("not in the material library") && e.contains("aluminium"), "{e}");
        let e = refuse("materials.fluid", &["mrf-122eg", "aluminium"]);
        assert!(e.contains("materials.fluid") && e.contains("mrf-132dg"), "{e}");
        assert!(refuse("materials.bobbin", &["pom", "POM"]).contains("twice"));
        assert!(refuse("materials.bobbin", &[]).contains("at least one"));
        assert!(resolve("g", true).unwrap().with_levels(&names(&["pom"])).is_err());
        let mut t = toml::Table::new();
        assert!(apply_override(&mut t, "materials.flux_path", "aluminium", true).is_err());
    }

    #[test]
    fn sets_split_at_the_first_equals_sign() {
        assert_eq!(parse_set(" coil.turns = fill ").unwrap(), ("coil.turns".into(), "fill".into()));
        assert_eq!(parse_set("name=b=c").unwrap().1, "b=c");
        assert!(parse_set("coil.turns").unwrap_err().to_string().contains("PATH=VALUE"));
        // Any spec key or variable symbol; nothing else.
        for known in ["R0=20mm", "coil.wire.awg=25", "materials.bobbin=pom", "drag.seal_torque=0.1"]
        {
            assert!(parse_set(known).is_ok(), "{known}");
        }
        assert!(parse_set("drum.gapp=1mm").unwrap_err().to_string().contains("'drum.gapp'"));
    }
}
