//! The conventions every mrbrake input-format JSON Schema follows, so that the spec, the problem
//! files and the study problems read alike in an editor (taplo / Even Better TOML), in the
//! studio's form and in the reference pages (`docs/reference/`).
//!
//! Brief overview: each format's reader types derive `schemars::JsonSchema`, so a schema's
//! structure and doc text are the types' own serde attributes and doc comments; [`generate`] turns
//! such a type into its schema with the shared settings (draft-07, the dialect taplo reads; every
//! sub-schema inline, so each key's node is where the key is; no `null`, which TOML lacks: an
//! optional key is left out) and the keys in file order ([`field_order`], as `x-order`). A format
//! then adds what only it knows: units and bounds ([`annotate`], from the constants its validation
//! reads), choices, rules between keys.
//!
//! Extensions beyond JSON Schema, which validators ignore: `x-unit` (the SI unit of a numeric key,
//! which a bare number is read in), `x-units` (the unit suffixes a string quantity may carry),
//! `x-order` (the keys of an object in the order the file writes them).

use schemars::generate::SchemaSettings;
use schemars::{JsonSchema, Schema, json_schema};
use serde::Deserialize;
use serde_json::{Value, json};

use mrbrake_units::Dimension;

/// The range of values a numeric key accepts (SI): what a format's validation checks and its
/// schema publishes, from one definition.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Bounds {
    /// Lower end.
    pub min: f64,
    /// Whether the lower end itself is allowed.
    pub min_inclusive: bool,
    /// Upper end.
    pub max: f64,
    /// Whether the upper end itself is allowed.
    pub max_inclusive: bool,
}

impl Bounds {
    /// `[min, max]`.
    pub const fn closed(min: f64, max: f64) -> Self {
        Self { min, min_inclusive: true, max, max_inclusive: true }
    }

    /// `(min, max)`.
    pub const fn open(min: f64, max: f64) -> Self {
        Self { min, min_inclusive: false, max, max_inclusive: false }
    }

    /// `(min, max]`.
    pub const fn open_closed(min: f64, max: f64) -> Self {
        Self { min, min_inclusive: false, max, max_inclusive: true }
    }

    /// `[min, max)`.
    pub const fn closed_open(min: f64, max: f64) -> Self {
        Self { min, min_inclusive: true, max, max_inclusive: false }
    }

    /// `[min, ∞)` (the upper end `f64::MAX`, which a schema leaves out).
    pub const fn at_least(min: f64) -> Self {
        Self::closed(min, f64::MAX)
    }

    /// `(min, ∞)`.
    pub const fn above(min: f64) -> Self {
        Self::open_closed(min, f64::MAX)
    }

    /// True for a finite `value` within the bounds.
    pub fn contains(self, value: f64) -> bool {
        let above = if self.min_inclusive { value >= self.min } else { value > self.min };
        let below = if self.max_inclusive { value <= self.max } else { value < self.max };
        value.is_finite() && above && below
    }

    /// The bounds in interval notation with `unit` (`(0, 10] m`, `≥ 1`).
    pub fn describe(self, unit: &str) -> String {
        let unit = if unit.is_empty() { String::new() } else { format!(" {unit}") };
        let open = if self.min_inclusive { '[' } else { '(' };
        if self.max >= f64::MAX {
            let sign = if self.min_inclusive { "≥" } else { ">" };
            return format!("{sign} {}{unit}", self.min);
        }
        let close = if self.max_inclusive { ']' } else { ')' };
        format!("{open}{}, {}{close}{unit}", self.min, self.max)
    }
}

/// The schema of `T` with the shared settings: draft-07, inline, without `null`, with `x-order`
/// where [`field_order`] knows the order (the root; nested objects get theirs from [`order`]).
pub fn generate<T: JsonSchema + for<'de> Deserialize<'de>>() -> Value {
    let settings = SchemaSettings::draft07().with(|s| s.inline_subschemas = true);
    let mut schema = without_null(settings.into_generator().into_root_schema_for::<T>().to_value());
    order::<T>(&mut schema, "");
    schema
}

/// Records the key order of the struct `T` (`x-order`) on the object at `path` in `schema` (on
/// its items for an array of tables).
pub fn order<T: for<'de> Deserialize<'de>>(schema: &mut Value, path: &str) {
    let keys = field_order::<T>();
    if let Some(mut node) = node_mut(schema, path) {
        if node.get("items").is_some() {
            node = &mut node["items"];
        }
        node["x-order"] = json!(keys);
    }
}

/// The node of the dotted `path` (`coil.wire.awg`; `""` is `schema` itself) under the schema's
/// properties, stepping through an array's `items` (`region.material` is the material of every
/// `[[region]]`).
pub fn node_mut<'a>(schema: &'a mut Value, path: &str) -> Option<&'a mut Value> {
    if path.is_empty() {
        return Some(schema);
    }
    path.split('.').try_fold(schema, |node, key| {
        let node = if node.get("items").is_some() { node.get_mut("items")? } else { node };
        node.get_mut("properties")?.get_mut(key)
    })
}

/// Adds the SI `unit` (unless empty) and `bounds` to a numeric key's node (to the number branch of
/// a quantity that may also be a string with a unit).
pub fn annotate(node: &mut Value, unit: &str, bounds: Bounds) {
    if !unit.is_empty() {
        node["x-unit"] = json!(unit);
    }
    let number = match node.get_mut("anyOf").and_then(Value::as_array_mut) {
        Some(branches) => branches.iter_mut().find(|b| b["type"] != "string"),
        None => Some(node),
    };
    if let Some(number) = number {
        write_bounds(number, bounds);
    }
}

/// `minimum`/`exclusiveMinimum` and `maximum`/`exclusiveMaximum` of `bounds` (draft-07); an
/// unbounded upper end (`f64::MAX`) is left out.
pub fn write_bounds(node: &mut Value, bounds: Bounds) {
    let Some(object) = node.as_object_mut() else { return };
    for key in ["minimum", "exclusiveMinimum", "maximum", "exclusiveMaximum"] {
        object.remove(key);
    }
    let number = |x: f64| {
        let whole = x.fract() == 0.0 && x.abs() < 1e15;
        if whole { json!(x as i64) } else { json!(x) }
    };
    let low = if bounds.min_inclusive { "minimum" } else { "exclusiveMinimum" };
    object.insert(low.into(), number(bounds.min));
    if bounds.max < f64::MAX {
        let high = if bounds.max_inclusive { "maximum" } else { "exclusiveMaximum" };
        object.insert(high.into(), number(bounds.max));
    }
}

/// The keys of the struct `T` in declaration order (the file's order), as its serde derive lists
/// them to a deserializer (JSON objects have no order, so a schema gives it as `x-order`).
pub fn field_order<T: for<'de> Deserialize<'de>>() -> Vec<&'static str> {
    let mut fields = order_probe::Fields(Vec::new());
    let _ = T::deserialize(&mut fields);
    fields.0
}

/// A deserializer that only records the field list a struct asks for.
mod order_probe {
    /// The recorded keys.
    pub struct Fields(pub Vec<&'static str>);

    /// The one "error": the keys are recorded, nothing is deserialised.
    #[derive(Debug)]
    pub struct Recorded;

    impl std::fmt::Display for Recorded {
        fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
            f.write_str("fields recorded")
        }
    }

    impl std::error::Error for Recorded {}

    impl serde::de::Error for Recorded {
        fn custom<M: std::fmt::Display>(_: M) -> Self {
            Recorded
        }
    }

    impl<'de> serde::Deserializer<'de> for &mut Fields {
        type Error = Recorded;

        fn deserialize_any<V: serde::de::Visitor<'de>>(self, _: V) -> Result<V::Value, Recorded> {
            Err(Recorded)
        }

        fn deserialize_struct<V: serde::de::Visitor<'de>>(
            self,
            _: &'static str,
            fields: &'static [&'static str],
            _: V,
        ) -> Result<V::Value, Recorded> {
            self.0 = fields.to_vec();
            Err(Recorded)
        }

        serde::forward_to_deserialize_any! {
            bool i8 i16 i32 i64 i128 u8 u16 u32 u64 u128 f32 f64 char str string bytes byte_buf
            option unit unit_struct newtype_struct seq tuple tuple_struct map enum identifier
            ignored_any
        }
    }
}

/// `schema` as TOML reads it: no `null` (an optional key is left out, its default its absence):
/// `"default": null` goes (a default kept by [`choice`] comes back), so do the `null` of a `type`
/// or `enum` and a `{"type": "null"}` branch (an `anyOf` left with one branch becomes it).
pub fn without_null(mut schema: Value) -> Value {
    strip_null(&mut schema);
    schema
}

fn strip_null(node: &mut Value) {
    match node {
        Value::Object(object) => {
            if object.get("default").is_some_and(Value::is_null) {
                object.remove("default");
            }
            if let Some(kept) = object.remove(DEFAULT_KEPT) {
                object.insert("default".into(), kept);
            }
            if let Some(Value::Array(types)) = object.get_mut("type") {
                types.retain(|t| t != "null");
                if let [only] = types.as_slice() {
                    let only = only.clone();
                    object.insert("type".into(), only);
                }
            }
            if let Some(Value::Array(values)) = object.get_mut("enum") {
                values.retain(|v| !v.is_null());
            }
            if let Some(Value::Array(branches)) = object.get_mut("anyOf") {
                branches.retain(|b| b.get("type").is_none_or(|t| t != "null"));
                if branches.len() == 1 {
                    let Some(Value::Object(only)) = branches.pop() else { return };
                    object.remove("anyOf");
                    for (key, value) in only {
                        object.entry(key).or_insert(value);
                    }
                }
            }
            object.values_mut().for_each(strip_null);
        }
        Value::Array(items) => items.iter_mut().for_each(strip_null),
        _ => {}
    }
}

/// A quantity written as a bare SI number or as a string with one of `dimension`'s units (as
/// `mrbrake_units::parse` reads it), e.g. `example` = `"25mm"`.
pub fn quantity(dimension: Dimension, example: &str) -> Schema {
    let units: Vec<&str> = dimension.units().iter().map(|(u, _)| *u).collect();
    json_schema!({
        "anyOf": [
            { "type": "number" },
            { "type": "string", "pattern": quantity_pattern(&units), "examples": [example] },
        ],
        "x-unit": dimension.si_unit(),
        "x-units": units,
    })
}

/// The regular expression of a number with an optional unit from `units`.
fn quantity_pattern(units: &[&str]) -> String {
    let alternatives = units.iter().map(|u| regex_escape(u)).collect::<Vec<_>>().join("|");
    format!(r"^\s*[-+]?(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?\s*({alternatives})?\s*$")
}

/// `text` with the regular-expression metacharacters of unit names escaped.
fn regex_escape(text: &str) -> String {
    text.chars()
        .flat_map(|c| {
            let special = matches!(c, '.' | '/' | '(' | ')' | '[' | ']' | '+' | '*' | '?' | '^');
            special.then_some('\\').into_iter().chain(std::iter::once(c))
        })
        .collect()
}

/// One of `values` (a key whose text names a choice, e.g. `kind = "dirichlet"`), with `default`.
pub fn choice(values: &[&str], default: Option<&str>) -> Schema {
    let mut schema = json_schema!({ "type": "string", "enum": values });
    if let Some(default) = default {
        with_default(&mut schema, json!(default));
    }
    schema
}

/// The element order key of the problem files: 1 (linear triangles, the default) or 2.
pub fn element_order() -> Schema {
    let mut schema = json_schema!({ "type": "integer", "enum": [1, 2] });
    with_default(&mut schema, json!(1));
    schema
}

/// A key naming a unit of `dimension` on its own (a problem file's `length_unit`), default SI.
pub fn unit_choice(dimension: Dimension) -> Schema {
    let units: Vec<&str> = dimension.units().iter().map(|(u, _)| *u).collect();
    choice(&units, Some(dimension.si_unit()))
}

/// Sets the default of a key schema written by a `schema_with` function. The derive overwrites a
/// field's `default` with its serde default (`null` for an absent optional key) after the
/// function ran, so the value is kept as `x-default` too, which [`without_null`] restores.
fn with_default(schema: &mut Schema, value: Value) {
    schema.insert("default".into(), value.clone());
    schema.insert(DEFAULT_KEPT.into(), value);
}

/// Where [`with_default`] keeps a default until [`without_null`] has run.
const DEFAULT_KEPT: &str = "x-default";

#[cfg(test)]
mod tests {
    use super::*;

    /// A reader type of some format.
    #[derive(Deserialize, JsonSchema)]
    #[serde(deny_unknown_fields)]
    #[allow(dead_code)]
    struct Example {
        /// The zeta.
        zeta: f64,
        /// An optional alpha.
        #[serde(default)]
        alpha: Option<u32>,
        /// Items.
        #[serde(default)]
        item: Vec<Item>,
    }

    #[derive(Deserialize, JsonSchema)]
    #[allow(dead_code)]
    struct Item {
        /// A tag.
        tag: u32,
    }

    #[test]
    fn generated_schemas_are_inline_ordered_and_without_null() {
        let mut schema = generate::<Example>();
        assert_eq!(schema["$schema"], "http://json-schema.org/draft-07/schema#");
        assert_eq!(schema["x-order"], json!(["zeta", "alpha", "item"]));
        assert_eq!(schema["properties"]["alpha"]["type"], "integer");
        assert!(!serde_json::to_string(&schema).unwrap().contains("null"));
        assert_eq!(schema["required"], json!(["zeta"]));
        let tag = node_mut(&mut schema, "item.tag").expect("through the array's items");
        assert_eq!(tag["description"], "A tag.");
        annotate(tag, "", Bounds::at_least(1.0));
        assert_eq!(tag["minimum"], 1);
        assert!(tag.get("maximum").is_none());
    }

    #[test]
    fn bounds_contain_describe_and_write() {
        let b = Bounds::open_closed(0.0, 100.0);
        assert!(b.contains(100.0) && !b.contains(0.0) && !b.contains(f64::NAN));
        assert_eq!(b.describe("A"), "(0, 100] A");
        assert_eq!(Bounds::at_least(1.0).describe(""), "≥ 1");
        let mut node = json!({ "anyOf": [{ "type": "number" }, { "type": "string" }] });
        annotate(&mut node, "m", Bounds::open(0.0, 0.5));
        assert_eq!(node["anyOf"][0]["exclusiveMaximum"], 0.5);
        assert_eq!(node["x-unit"], "m");
    }

    #[test]
    fn quantity_strings_match_the_units_parse_reads() {
        let schema = quantity(Dimension::Current, "2A").to_value();
        let pattern = schema["anyOf"][1]["pattern"].as_str().unwrap();
        assert!(pattern.ends_with(r"\s*(A|mA)?\s*$"), "{pattern}");
        assert_eq!(schema["x-unit"], "A");
    }
}
