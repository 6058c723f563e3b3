//! Study variables are the spec's own fields: every numeric field of every configuration is
//! reachable as a variable (resolved by its path, written by `Variable::set`, read back by the spec
//! reader), and every variable name and thesis symbol names a real field of the configurations it
//! is meant for. The user-facing names stay as they were.

use mrbrake_design::spec::{BrakeSpec, ConfigurationKind, Quantity, numeric_fields};
use mrbrake_explore::variable::{SYMBOLS, resolve};
use serde_json::Value;

fn example_table(name: &str) -> toml::Table {
    let path =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/specs").join(name);
    toml::from_str(&std::fs::read_to_string(path).expect("example")).expect("TOML")
}

/// One spec table per configuration (the multi-drum one is the thesis brake without its spacer).
fn every_configuration() -> Vec<(ConfigurationKind, toml::Table)> {
    let mut multi_drum = example_table("thesis-bidirectional.toml");
    multi_drum.insert("configuration".into(), "multi-drum".into());
    multi_drum.remove("spacer");
    vec![
        (ConfigurationKind::SingleDisc, example_table("single-disc.toml")),
        (ConfigurationKind::MultiDisc, example_table("multi-disc.toml")),
        (ConfigurationKind::Drum, example_table("drum.toml")),
        (ConfigurationKind::MultiDrum, multi_drum),
        (
            ConfigurationKind::Bidirectional,
            with_factors(example_table("thesis-bidirectional.toml")),
        ),
    ]
}

/// The thesis brake with every material factor away from its default and the `[drag]` fields a
/// study may vary given (a `[fluid]`, `[steel]` or `[drag]` table at its defaults is not written,
/// so its fields would not appear in the spec's JSON).
fn with_factors(mut table: toml::Table) -> toml::Table {
    let factors: toml::Table = toml::from_str(
        "[fluid]\nyield_stress_scale = 0.9\nB_scale = 1.1\nfill_fraction = 0.8\n\
         conductivity_S_per_m = 1.0\n[steel]\nB_scale = 0.95\nconductivity_S_per_m = 2e6\n\
         [drag]\nseals_per_rotor = 2\nseal_torque = 0.01\nfreewheel_drag = 0.005\n",
    )
    .expect("TOML");
    table.extend(factors);
    table
}

fn json_of(table: &toml::Table) -> Value {
    let text = toml::to_string(table).expect("writes");
    let spec = BrakeSpec::from_toml_str(&text, "test.toml").unwrap_or_else(|e| panic!("{e}"));
    serde_json::to_value(spec).expect("JSON")
}

/// Paths of the numbers and absent options of a spec's JSON below the top level.
fn numeric_paths(value: &Value, path: &str, out: &mut Vec<String>) {
    match value {
        Value::Object(map) => {
            for (key, inner) in map {
                let child = if path.is_empty() { key.clone() } else { format!("{path}.{key}") };
                numeric_paths(inner, &child, out);
            }
        }
        Value::Number(_) => out.push(path.to_string()),
        Value::Null if path.contains('.') && path != "materials.spacer" => out.push(path.into()),
        _ => {}
    }
}

fn get<'v>(value: &'v Value, path: &str) -> Option<&'v Value> {
    path.split('.').try_fold(value, |v, part| v.get(part))
}

#[test]
fn every_numeric_field_of_every_configuration_is_a_variable() {
    for (kind, table) in every_configuration() {
        let mut paths = Vec::new();
        numeric_paths(&json_of(&table), "", &mut paths);
        assert!(paths.len() >= 20, "{}: only {} fields", kind.name(), paths.len());
        for path in paths {
            let variable = resolve(&path, kind.is_drum())
                .unwrap_or_else(|e| panic!("{}: {path} is not a variable: {e}", kind.name()));
            assert_eq!(variable.path(), path);
            let value = match variable.quantity().expect("a numeric field") {
                Quantity::Integer => 3.0,
                Quantity::Length | Quantity::Current | Quantity::Factor => 0.0125,
                Quantity::Conductivity => 2.5e6,
                Quantity::Torque => 0.02,
            };
            let mut edited = table.clone();
            variable.set(&mut edited, value).expect("set");
            let got = get(&json_of(&edited), &path).and_then(Value::as_f64);
            assert_eq!(got, Some(value), "{} {path}", kind.name());
        }
    }
}

#[test]
fn every_variable_and_symbol_names_a_field_of_its_configurations() {
    let configurations = every_configuration();
    let paths_of = |drum: bool| -> Vec<String> {
        let mut paths = Vec::new();
        for (kind, table) in &configurations {
            if kind.is_drum() == drum {
                numeric_paths(&json_of(table), "", &mut paths);
            }
        }
        paths
    };
    let (drum_paths, disc_paths) = (paths_of(true), paths_of(false));
    for field in numeric_fields() {
        assert!(
            drum_paths.iter().chain(&disc_paths).any(|p| p == field.path),
            "{} is in no configuration's spec",
            field.path
        );
    }
    for &(symbol, drum, disc) in SYMBOLS {
        for (is_drum, path, paths) in [(true, drum, &drum_paths), (false, disc, &disc_paths)] {
            match path {
                Some(path) => {
                    assert_eq!(resolve(symbol, is_drum).unwrap().path(), path, "{symbol}");
                    assert!(paths.iter().any(|p| p == path), "{symbol}: {path} is not a field");
                }
                None => assert!(resolve(symbol, is_drum).is_err(), "{symbol}"),
            }
        }
    }
}

#[test]
fn the_thesis_symbols_keep_their_names() {
    let resolved = |drum: bool| -> Vec<String> {
        ["g", "h", "d", "R0", "R1", "R2", "n", "N", "I", "AWG"]
            .iter()
            .map(|s| resolve(s, drum).map_or_else(|_| "-".to_string(), |v| v.path().into()))
            .collect()
    };
    assert_eq!(
        resolved(true),
        [
            "drum.gap",
            "drum.height",
            "drum.cylinder_thickness",
            "drum.r0",
            "-",
            "-",
            "drum.rotating_cylinders",
            "coil.turns",
            "coil.max_current",
            "coil.wire.awg"
        ]
    );
    assert_eq!(
        resolved(false),
        [
            "disc.gap",
            "-",
            "disc.thickness",
            "-",
            "disc.inner_radius",
            "disc.outer_radius",
            "disc.count",
            "coil.turns",
            "coil.max_current",
            "coil.wire.awg"
        ]
    );
    assert_eq!(SYMBOLS.len(), 10);
}
