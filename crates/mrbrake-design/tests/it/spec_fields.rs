//! The list of numeric spec fields (`spec::numeric_fields`, beside each table's definition) matches
//! the spec itself: every number or absent option in the serialised spec of every configuration is
//! listed, every listed field exists in some configuration, and each is read from the file with
//! its listed quantity (a length with `mm`, a current with `A`, a whole number). The configuration
//! tables are checked too: a missing or superfluous one is an input error naming it and its line.

use std::collections::BTreeSet;

use mrbrake_design::spec::{BrakeSpec, ConfigurationKind, Quantity, numeric_fields};
use mrbrake_error::Kind as _;
use serde_json::Value;

const STRING_OPTIONS: &[&str] = &["materials.spacer"];

fn example_text(name: &str) -> String {
    let path =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/specs").join(name);
    std::fs::read_to_string(path).expect("example spec")
}

/// One spec text per configuration (the multi-drum one is the thesis brake without its spacer).
fn every_configuration() -> Vec<(ConfigurationKind, toml::Table)> {
    let table = |text: &str| -> toml::Table { toml::from_str(text).expect("TOML") };
    let mut multi_drum = table(&example_text("thesis-bidirectional.toml"));
    multi_drum.insert("configuration".into(), "multi-drum".into());
    multi_drum.remove("spacer");
    vec![
        (ConfigurationKind::SingleDisc, table(&example_text("single-disc.toml"))),
        (ConfigurationKind::MultiDisc, table(&example_text("multi-disc.toml"))),
        (ConfigurationKind::Drum, table(&example_text("drum.toml"))),
        (ConfigurationKind::MultiDrum, multi_drum),
        (
            ConfigurationKind::Bidirectional,
            with_factors(&example_text("thesis-bidirectional.toml")),
        ),
    ]
}

/// The thesis brake with every material factor away from its default and the `[drag]` fields a
/// study may vary given (a table at its defaults is not written, so its fields would not appear
/// in the serialised spec; the bearings' count, bore and load are not study fields and stay out).
fn with_factors(text: &str) -> toml::Table {
    let factors = "[fluid]\nyield_stress_scale = 0.9\nB_scale = 1.1\nfill_fraction = 0.8\n\
                   conductivity_S_per_m = 1.0\n[steel]\nB_scale = 0.95\n\
                   conductivity_S_per_m = 2e6\n[drag]\nseals_per_rotor = 2\n\
                   seal_torque = 0.01\nfreewheel_drag = 0.005\n";
    toml::from_str(&format!("{text}\n{factors}")).expect("TOML")
}

fn parse(table: &toml::Table) -> BrakeSpec {
    let text = toml::to_string(table).expect("writes");
    BrakeSpec::from_toml_str(&text, "test.toml").unwrap_or_else(|e| panic!("{e}\n{text}"))
}

/// The numeric leaves of a spec's JSON (numbers, and absent options below the top level; a
/// top-level `null` is another configuration's table), with whether the number is whole.
fn numeric_leaves(value: &Value, path: &str, out: &mut Vec<(String, Option<bool>)>) {
    match value {
        Value::Object(map) => {
            for (key, inner) in map {
                let child = if path.is_empty() { key.clone() } else { format!("{path}.{key}") };
                numeric_leaves(inner, &child, out);
            }
        }
        Value::Number(n) => out.push((path.to_string(), Some(n.is_u64() || n.is_i64()))),
        Value::Null if path.contains('.') && !STRING_OPTIONS.contains(&path) => {
            out.push((path.to_string(), None));
        }
        _ => {}
    }
}

fn leaves_of(spec: &BrakeSpec) -> Vec<(String, Option<bool>)> {
    let mut out = Vec::new();
    numeric_leaves(&serde_json::to_value(spec).expect("JSON"), "", &mut out);
    out
}

fn set(table: &mut toml::Table, path: &str, value: toml::Value) {
    let mut parts: Vec<&str> = path.split('.').collect();
    let last = parts.pop().expect("a path");
    let mut t = table;
    for part in parts {
        t = t
            .entry(part)
            .or_insert_with(|| toml::Value::Table(toml::Table::new()))
            .as_table_mut()
            .expect("a table");
    }
    t.insert(last.into(), value);
}

fn get<'v>(value: &'v Value, path: &str) -> Option<&'v Value> {
    path.split('.').try_fold(value, |v, part| v.get(part))
}

#[test]
fn the_numeric_field_list_is_the_spec_of_every_configuration() {
    let listed: BTreeSet<&str> = numeric_fields().map(|f| f.path).collect();
    assert_eq!(listed.len(), numeric_fields().count(), "a field is listed twice");
    let mut seen = BTreeSet::new();
    for (kind, table) in every_configuration() {
        let spec = parse(&table);
        assert_eq!(spec.configuration.kind(), kind);
        for (path, whole) in leaves_of(&spec) {
            let field = numeric_fields()
                .find(|f| f.path == path)
                .unwrap_or_else(|| panic!("{}: {path} is not in numeric_fields()", kind.name()));
            if let Some(whole) = whole {
                assert_eq!(whole, field.quantity == Quantity::Integer, "{path}: quantity");
            }
            seen.insert(field.path);
        }
    }
    let missing: Vec<_> = listed.difference(&seen).collect();
    assert!(missing.is_empty(), "listed but in no configuration's spec: {missing:?}");
}

#[test]
fn every_numeric_field_reads_its_quantity_with_units() {
    for (kind, table) in every_configuration() {
        for (path, _) in leaves_of(&parse(&table)) {
            let field = numeric_fields().find(|f| f.path == path).expect("listed");
            let (text, expected): (toml::Value, f64) = match field.quantity {
                Quantity::Length => ("12.5mm".into(), 0.0125),
                Quantity::Current => ("1500mA".into(), 1.5),
                Quantity::Integer => (toml::Value::Integer(3), 3.0),
                Quantity::Factor => (toml::Value::Float(0.75), 0.75),
                Quantity::Conductivity => (toml::Value::Float(2.5e6), 2.5e6),
                Quantity::Torque => ("20mNm".into(), 0.02),
            };
            let mut edited = table.clone();
            set(&mut edited, path.as_str(), text);
            let json = serde_json::to_value(parse(&edited)).expect("JSON");
            let got = get(&json, &path).and_then(Value::as_f64);
            assert_eq!(got, Some(expected), "{} {path}", kind.name());
        }
    }
}

#[test]
fn a_missing_or_superfluous_table_names_itself_and_its_line() {
    let text = example_text("thesis-bidirectional.toml");
    let multi_drum =
        text.replacen("configuration = \"bidirectional\"", "configuration = \"multi-drum\"", 1);
    let err = BrakeSpec::from_toml_str(&multi_drum, "m.toml").unwrap_err();
    assert!(err.is_input_error());
    let errors = err.field_errors().expect("field errors");
    assert_eq!(errors.len(), 1, "{err}");
    let e = &errors.errors()[0];
    let spacer_line = text.lines().position(|l| l.starts_with("[spacer]")).unwrap() + 1;
    assert_eq!(
        (e.field.as_str(), e.file.as_deref(), e.line),
        ("spacer", Some("m.toml"), Some(spacer_line))
    );
    assert!(e.message.contains("multi-drum") && e.message.contains("remove"), "{err}");

    let disc =
        text.replacen("configuration = \"bidirectional\"", "configuration = \"multi-disc\"", 1);
    let err = BrakeSpec::from_toml_str(&disc, "d.toml").unwrap_err();
    let fields: Vec<&str> =
        err.field_errors().unwrap().errors().iter().map(|e| e.field.as_str()).collect();
    assert_eq!(fields, ["drum", "disc", "spacer"], "{err}");
    let configuration_line = text.lines().position(|l| l.starts_with("configuration")).unwrap() + 1;
    let missing_disc = &err.field_errors().unwrap().errors()[1];
    assert_eq!(missing_disc.line, Some(configuration_line));
    assert!(err.to_string().contains("disc: required for configuration \"multi-disc\""), "{err}");

    // Validation errors are located too, and a generated spec's are not.
    let bad_gap = text.replacen("gap = \"0.5mm\"", "gap = \"-0.5mm\"", 1);
    let gap_line = bad_gap.lines().position(|l| l.starts_with("gap =")).unwrap() + 1;
    let err = BrakeSpec::from_toml_str(&bad_gap, "g.toml").unwrap().validate().unwrap_err();
    assert!(err.to_string().contains(&format!("g.toml:{gap_line}: drum.gap: ")), "{err}");
    let err = BrakeSpec::from_generated_toml(&bad_gap, "design").unwrap().validate().unwrap_err();
    assert!(err.to_string().contains("\n  drum.gap: "), "{err}");
}

#[test]
fn specs_serialise_in_the_files_flat_form() {
    let spec = mrbrake_design::spec::default_spec();
    let json = serde_json::to_value(&spec).unwrap();
    assert_eq!(json["configuration"], "bidirectional");
    assert!(json["disc"].is_null() && json["drum"].is_object() && json["spacer"].is_object());
    let back: BrakeSpec = serde_json::from_value(json).unwrap();
    assert_eq!(back, spec);
    let mut odd = serde_json::to_value(&spec).unwrap();
    odd["spacer"] = Value::Null;
    let err = serde_json::from_value::<BrakeSpec>(odd).unwrap_err().to_string();
    assert!(err.contains("spacer: required"), "{err}");
}
