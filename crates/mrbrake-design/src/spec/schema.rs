//! The spec file's JSON Schema, in the conventions of `mrbrake_schema`: its structure and doc text
//! from the spec types themselves (their serde attributes and doc comments), the unit and allowed
//! range of every numeric field from [`numeric_fields`] (the bounds [`BrakeSpec::validate`]
//! checks), the material choices from the material library (the names and kinds the validation
//! accepts), and the tables each configuration needs
//! ([`ConfigurationKind::requires_table`], the rule the reader applies). Nothing here is a second
//! copy of a rule.
//!
//! [`BrakeSpec::validate`]: super::BrakeSpec::validate

use schemars::{JsonSchema, Schema, SchemaGenerator};
use serde_json::{Map, Value, json};

use mrbrake_materials::MaterialKind;
use mrbrake_schema::{annotate, generate, node_mut, order, quantity};
use mrbrake_units::Dimension;

use super::raw::RawSpec;
use super::{
    Coil, ConfigurationKind, Current, Disc, Drum, Envelope, FluidFactors, Housing, Length,
    MATERIAL_FIELDS, Materials, Model, OPTIONAL_TABLES, Shaft, Spacer, SteelFactors, Wire,
    numeric_fields,
};

/// The JSON Schema of a spec file.
pub fn schema() -> Value {
    let mut schema = generate::<RawSpec>();
    schema["$id"] = json!("https://mrbrake.invalid/schema/spec.json");
    schema["title"] = json!("mrbrake brake specification");
    schema["description"] = json!(
        "A brake design for `mrbrake analyze`, `report`, `response`, `thermal`, `sweep`, \
         `optimize` and `studio`. Lengths and currents are bare SI numbers (0.025 is 25 mm) or \
         strings with a unit (\"25mm\", \"500mA\")."
    );
    order::<Materials>(&mut schema, "materials");
    order::<Shaft>(&mut schema, "shaft");
    order::<Housing>(&mut schema, "housing");
    order::<Drum>(&mut schema, "drum");
    order::<Disc>(&mut schema, "disc");
    order::<Coil>(&mut schema, "coil");
    order::<Wire>(&mut schema, "coil.wire");
    order::<Spacer>(&mut schema, "spacer");
    order::<Envelope>(&mut schema, "envelope");
    order::<Model>(&mut schema, "model");
    order::<FluidFactors>(&mut schema, "fluid");
    order::<SteelFactors>(&mut schema, "steel");
    for field in numeric_fields() {
        if let Some(node) = node_mut(&mut schema, field.path) {
            annotate(node, field.quantity.unit(), field.bounds);
        }
    }
    for field in MATERIAL_FIELDS {
        if let Some(node) = node_mut(&mut schema, field.path) {
            node["enum"] = json!(library_names(field.required));
        }
    }
    schema["allOf"] = configuration_rules();
    schema
}

/// The library's names of `kind` (all names for `None`).
fn library_names(kind: Option<MaterialKind>) -> Vec<&'static str> {
    mrbrake_materials::library::names()
        .iter()
        .filter(|(_, k)| kind.is_none_or(|want| *k == want))
        .map(|(n, _)| *n)
        .collect()
}

/// The tables each configuration requires and forbids, as `if`/`then` rules.
fn configuration_rules() -> Value {
    let kinds = [
        ConfigurationKind::SingleDisc,
        ConfigurationKind::MultiDisc,
        ConfigurationKind::Drum,
        ConfigurationKind::MultiDrum,
        ConfigurationKind::Bidirectional,
    ];
    let rules = kinds.iter().map(|kind| {
        let (needed, forbidden): (Vec<&str>, Vec<&str>) =
            OPTIONAL_TABLES.iter().partition(|t| kind.requires_table(t));
        let absent: Map<String, Value> =
            forbidden.iter().map(|t| (t.to_string(), json!(false))).collect();
        json!({
            "if": { "properties": { "configuration": { "const": kind.name() } } },
            "then": { "required": needed, "properties": absent },
        })
    });
    Value::Array(rules.collect())
}

impl JsonSchema for Length {
    fn schema_name() -> std::borrow::Cow<'static, str> {
        "Length".into()
    }

    fn inline_schema() -> bool {
        true
    }

    /// A bare SI number or a string with a unit; the bounds are the field's ([`numeric_fields`]).
    fn json_schema(_: &mut SchemaGenerator) -> Schema {
        quantity(Dimension::Length, "25mm")
    }
}

impl JsonSchema for Current {
    fn schema_name() -> std::borrow::Cow<'static, str> {
        "Current".into()
    }

    fn inline_schema() -> bool {
        true
    }

    /// A bare SI number or a string with a unit; the bounds are the field's ([`numeric_fields`]).
    fn json_schema(_: &mut SchemaGenerator) -> Schema {
        quantity(Dimension::Current, "2A")
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spec::Quantity;

    /// Every key of `table` (a TOML table) is a property of `node`, recursively; returns the
    /// dotted paths checked.
    fn keys_in_schema(table: &toml::Table, node: &Value, prefix: &str, checked: &mut Vec<String>) {
        for (key, value) in table {
            let path = if prefix.is_empty() { key.clone() } else { format!("{prefix}.{key}") };
            let child = &node["properties"][key];
            assert!(child.is_object(), "{path} is not in the schema");
            if let toml::Value::Table(inner) = value {
                keys_in_schema(inner, child, &path, checked);
            }
            checked.push(path);
        }
    }

    #[test]
    fn every_key_of_every_example_spec_is_in_the_schema() {
        let schema = schema();
        let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/../../examples/specs");
        let mut specs = 0;
        for entry in std::fs::read_dir(dir).unwrap() {
            let path = entry.unwrap().path();
            if path.extension().is_some_and(|e| e == "toml") {
                let table: toml::Table =
                    toml::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
                let mut checked = Vec::new();
                keys_in_schema(&table, &schema, "", &mut checked);
                assert!(checked.len() > 20, "{}: {checked:?}", path.display());
                specs += 1;
            }
        }
        assert!(specs >= 5);
    }

    #[test]
    fn numeric_fields_carry_their_unit_and_the_validated_bounds() {
        let mut schema = schema();
        for field in numeric_fields() {
            let node = node_mut(&mut schema, field.path)
                .unwrap_or_else(|| panic!("{} is not in the schema", field.path));
            assert!(node["description"].as_str().is_some_and(|d| d.len() > 5), "{}", field.path);
            let number = node["anyOf"]
                .as_array()
                .and_then(|b| b.iter().find(|b| b["type"] == "number"))
                .unwrap_or(node);
            let low = number.get("exclusiveMinimum").or(number.get("minimum"));
            assert!(low.and_then(Value::as_f64).is_some(), "{}: {number}", field.path);
            // Whole numbers and factors are dimensionless: no `x-unit`.
            if !matches!(field.quantity, Quantity::Integer | Quantity::Factor) {
                assert_eq!(node["x-unit"], field.quantity.unit(), "{}", field.path);
            }
        }
        let gap = node_mut(&mut schema, "drum.gap").unwrap().clone();
        assert_eq!(gap["anyOf"][0]["exclusiveMinimum"], 0);
        assert_eq!(gap["anyOf"][0]["maximum"], 0.01, "a fluid gap is at most 10 mm: {gap}");
        let awg = node_mut(&mut schema, "coil.wire.awg").unwrap().clone();
        assert_eq!((awg["minimum"].clone(), awg["maximum"].clone()), (json!(18), json!(40)));
    }

    #[test]
    fn materials_defaults_order_and_configuration_rules() {
        let mut schema = schema();
        let fluid = node_mut(&mut schema, "materials.fluid").unwrap().clone();
        assert!(fluid["enum"].as_array().unwrap().contains(&json!("mrf-122eg")));
        assert!(!fluid["enum"].as_array().unwrap().contains(&json!("steel-1008")));
        let coil = node_mut(&mut schema, "materials.coil").unwrap().clone();
        assert_eq!(coil["default"], "copper");
        let turns = node_mut(&mut schema, "coil.turns").unwrap().clone();
        assert!(turns["description"].as_str().unwrap().contains("if absent"), "{turns}");
        assert_eq!(schema["allOf"].as_array().unwrap().len(), 5);
        assert_eq!(schema["x-order"][0], "name");
        assert_eq!(node_mut(&mut schema, "coil").unwrap()["x-order"][0], "placement");
        let r0 = node_mut(&mut schema, "drum.r0").unwrap().clone();
        assert!(r0["anyOf"][1]["pattern"].as_str().unwrap().contains("mm|um"), "{r0}");
    }
}
