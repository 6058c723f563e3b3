//! The naming convention of docs/CONVENTIONS.md, checked on every command's `--json` output and on
//! the results store's metric names: snake_case words, then the unit after the last word, written
//! as SI symbols with their case (`torque_Nm`, `mean_B_T`, `h_W_per_m2_K`); dimensionless keys
//! have no unit. Each command runs with cheap settings (coarse mesh, few points, a short step
//! response).

use crate::common;

use common::{json, mrbrake, path_str};
use serde_json::Value;

/// Unit symbols a key may end with (before an optional power 2 or 3).
/// `C` is the degree Celsius, `ohm` the ohm, `percent` %, `min` the minute; `Nm` is N·m.
const UNIT_SYMBOLS: &[&str] = &[
    "m", "g", "s", "A", "K", "C", "N", "Nm", "Pa", "J", "W", "V", "ohm", "S", "Wb", "T", "H", "Hz",
    "rad", "deg", "dB", "percent", "min",
];

/// Prefixed unit symbols a key may end with (a closed list: `nm` would read as nanometre where a
/// miscased N·m is meant).
const PREFIXED_SYMBOLS: &[&str] =
    &["mm", "cm", "um", "kg", "kPa", "MPa", "mT", "kA", "mA", "ms", "kHz", "mH"];

/// Quantity symbols written with their case among the words (`mean_B_T`, `H_A_per_m`,
/// `coil_max_T_C`, `resistance_20C_ohm`).
const SYMBOL_WORDS: &[&str] = &["B", "H", "T", "20C"];

/// Keys that are not quantity names, with why (docs/CONVENTIONS.md, "Exceptions").
const ALLOWED_KEYS: &[(&str, &str)] = &[(
    "points_H_A_per_m_B_T",
    "a table of (H, B) pairs names its two columns with their units, in order",
)];

/// Objects whose keys are names the user chose, not quantity names: the design variables of a
/// study (spec paths or thesis symbols such as `R0`, `housing.outer_radius`).
const USER_NAMED_OBJECTS: &[&str] = &["variables"];

fn is_unit_symbol(token: &str) -> bool {
    let base = token.trim_end_matches(['2', '3']);
    UNIT_SYMBOLS.contains(&base) || PREFIXED_SYMBOLS.contains(&base)
}

/// True when `tokens` is a unit: `U(_U)*`, `U(_U)*_per_U(_U)*`, `per_U(_U)*` (a count per unit) or
/// `rad_s` (rad/s, the spelling the issues fixed for angular speeds).
fn is_unit(tokens: &[&str]) -> bool {
    if tokens == ["rad", "s"] {
        return true;
    }
    let factors = |t: &[&str]| !t.is_empty() && t.iter().all(|t| is_unit_symbol(t));
    match tokens.iter().position(|t| *t == "per") {
        Some(0) => factors(&tokens[1..]),
        Some(k) => factors(&tokens[..k]) && factors(&tokens[k + 1..]),
        None => factors(tokens),
    }
}

/// Checks one key against the convention; the error says what is wrong.
fn check_key(key: &str) -> Result<(), String> {
    if ALLOWED_KEYS.iter().any(|(allowed, _)| *allowed == key) {
        return Ok(());
    }
    let tokens: Vec<&str> = key.split('_').collect();
    // The longest unit suffix that leaves at least one word.
    let words_end = (1..tokens.len()).find(|&k| is_unit(&tokens[k..])).unwrap_or(tokens.len());
    let words = &tokens[..words_end];
    for word in words {
        let lower =
            !word.is_empty() && word.chars().all(|c| c.is_ascii_lowercase() || c.is_ascii_digit());
        if !lower && !SYMBOL_WORDS.contains(word) {
            return Err(format!("word '{word}' is not lower-case snake_case"));
        }
    }
    // No unit, or only a `per_…` rate: the last word must not be a unit in the wrong case
    // (`power_w`, `stiffness_nm_per_rad`).
    if words_end == tokens.len() || tokens[words_end] == "per" {
        let last = words[words.len() - 1];
        if last.len() <= 2 && UNIT_SYMBOLS.iter().any(|u| u.to_ascii_lowercase() == last) {
            return Err(format!("ends in '{last}': write the unit in its SI case"));
        }
        if words.contains(&"per") {
            return Err("a unit quotient with a unit not written in its SI case".into());
        }
    }
    Ok(())
}

/// Every key of `value` that breaks the convention, as `path: reason`.
fn violations(value: &Value, path: &str, out: &mut Vec<String>) {
    match value {
        Value::Object(map) => {
            for (key, child) in map {
                if let Err(reason) = check_key(key) {
                    out.push(format!("{path}.{key}: {reason}"));
                }
                if !USER_NAMED_OBJECTS.contains(&key.as_str()) {
                    violations(child, &format!("{path}.{key}"), out);
                }
            }
        }
        Value::Array(items) => {
            items.iter().for_each(|item| violations(item, &format!("{path}[]"), out))
        }
        _ => {}
    }
}

/// Runs `mrbrake ARGS… --json` and asserts that every key of its output follows the convention.
fn assert_conventional(args: &[&str]) -> Value {
    let mut with_json = args.to_vec();
    with_json.push("--json");
    let value = json(&with_json);
    let mut found = Vec::new();
    violations(&value, "", &mut found);
    assert!(
        found.is_empty(),
        "mrbrake {}: keys break docs/CONVENTIONS.md:\n{}",
        args.join(" "),
        found.join("\n")
    );
    value
}

#[test]
fn the_rule_accepts_the_contract_keys_and_refuses_miscased_units() {
    for good in [
        "torque_Nm",
        "mean_B_T",
        "B_z_T",
        "flux_linkage_Wb",
        "omega_rad_s",
        "magnitude_dB",
        "phase_deg",
        "t63_s",
        "time_s",
        "current_A",
        "impedance_ohm",
        "eddy_loss_W",
        "timings_s",
        "total",
        "displayed_stiffness_Nm_per_rad",
        "h_W_per_m2_K",
        "viscous_Nm_s_per_rad",
        "current_density_A_per_mm2",
        "tau_y_kPa",
        "coil_max_T_C",
        "resistance_20C_ohm",
        "rotor_inertia_kg_m2",
        "evaluations_per_min",
        "dynamic_range",
        "q90_B_T",
        "r_m",
    ] {
        assert_eq!(check_key(good), Ok(()), "{good}");
    }
    for bad in [
        "torque_max_nm",
        "mean_b_fluid_t",
        "power_w",
        "max_b_t",
        "displayed_stiffness_nm_per_rad",
        "temperature_c",
        "max_current_a",
        "tau_y_pa",
        "Torque_Nm",
    ] {
        assert!(check_key(bad).is_err(), "{bad} should break the rule");
    }
}

#[test]
fn store_metric_names_follow_the_convention() {
    for metric in mrbrake::explore::evaluate::METRICS {
        assert_eq!(check_key(metric.name), Ok(()), "metric {}", metric.name);
    }
    // A study keeping curves stores each point as a metric of its own.
    let curve_point = mrbrake::explore::evaluate::torque_curve_metric(3);
    assert_eq!(check_key(&curve_point), Ok(()), "metric {curve_point}");
    for (old, new) in mrbrake::explore::evaluate::LEGACY_METRIC_NAMES {
        assert!(check_key(old).is_err(), "legacy name {old} follows the rule: why renamed?");
        assert!(mrbrake::explore::evaluate::metric_info(new).is_some(), "{old} → {new}: no metric");
    }
}

#[test]
fn design_commands_follow_the_convention() {
    let dir = tempfile::tempdir().expect("temporary directory");
    let geo = dir.path().join("brake.geo");
    assert_conventional(&["analyze", "--mesh", "coarse", "--points", "3"]);
    assert_conventional(&[
        "analyze",
        "../../examples/specs/single-disc.toml",
        "--mesh",
        "coarse",
        "--points",
        "2",
    ]);
    assert_conventional(&["export-geo", "-o", path_str(&geo)]);
    assert_conventional(&["study", "thesis-tables", "--mesh", "coarse"]);
    assert_conventional(&["thermal", "--mesh", "coarse"]);
}

/// Coarse mesh and a 5 ms step: about 8 s in a debug build.
#[test]
fn response_follows_the_convention() {
    assert_conventional(&["response", "--mesh", "coarse", "--duration", "5ms"]);
}

#[test]
fn formulas_and_materials_follow_the_convention() {
    let radii = ["--r1", "22.5mm", "--r2", "27.5mm", "--tau-y", "24.315kPa"];
    assert_conventional(&[&["formula", "single-disc"][..], &radii].concat());
    let multi = [
        &["formula", "multi-disc", "--discs", "3", "--gap", "1mm", "--speed", "60rpm"][..],
        &radii,
    ];
    assert_conventional(&multi.concat());
    assert_conventional(&["formula", "drum", "--r", "25mm", "--h", "9mm", "--tau-y", "3.5517kPa"]);
    assert_conventional(&[
        "formula",
        "multi-drum",
        "--r0",
        "25mm",
        "--h",
        "9mm",
        "--d",
        "1mm",
        "--g",
        "0.5mm",
        "--surfaces",
        "4",
        "--tau-y",
        "25.67kPa",
    ]);
    assert_conventional(&[
        "formula",
        "coil",
        "--window-width",
        "10mm",
        "--window-height",
        "14.4mm",
        "--wire-diameter",
        "0.5mm",
        "--current",
        "2A",
    ]);
    assert_conventional(&["materials", "list"]);
    assert_conventional(&["materials", "show", "MRF-122EG", "--b", "0.46T", "--h", "5kA/m"]);
    assert_conventional(&["materials", "show", "steel-1008", "--h", "5kA/m"]);
}

#[test]
fn fem_solves_follow_the_convention() {
    for problem in [
        "potcore.toml",
        "potcore-heat.toml",
        "potcore-warmup.toml",
        "eddy-cylinder/eddy-cylinder.toml",
    ] {
        assert_conventional(&["fem", "solve", &format!("../../examples/fem/{problem}")]);
    }
}

#[test]
fn haptic_commands_follow_the_convention() {
    for device in ["conventional", "bidirectional", "motor"] {
        assert_conventional(&["haptic", "wall", "--device", device]);
    }
    assert_conventional(&["haptic", "zwidth", "--points", "3"]);
}

#[test]
fn rig_and_identification_follow_the_convention() {
    let dir = tempfile::tempdir().expect("temporary directory");
    let (char_dir, freq_dir) = (dir.path().join("char"), dir.path().join("fr"));
    let model = dir.path().join("model.json");
    assert_conventional(&["rig", "characterize", "--out", path_str(&char_dir)]);
    let log = char_dir.join("characterization.csv");
    assert_conventional(&["characterize", path_str(&log), "--save-model", path_str(&model)]);
    assert_conventional(&[
        "rig",
        "freqresp",
        "--out",
        path_str(&freq_dir),
        "--model",
        path_str(&model),
    ]);
    assert_conventional(&["freqresp", path_str(&freq_dir.join("manifest.csv"))]);
    assert_conventional(&["tfest", path_str(&freq_dir.join("frd.csv")), "--poles", "2"]);

    // The minor-loop chain: its rig log, the operator model fitted to it, and tracking with it.
    let preisach = dir.path().join("preisach.toml");
    std::fs::write(&preisach, "[hysteresis]\nmodel = \"preisach\"\n").expect("config written");
    let config = path_str(&preisach);
    let (loops_dir, track_dir) = (dir.path().join("loops"), dir.path().join("track"));
    let operators = dir.path().join("operators.json");
    assert_conventional(&["rig", "minor-loops", "--config", config, "--out", path_str(&loops_dir)]);
    let loops = loops_dir.join("minor_loops.csv");
    let operators_model = path_str(&operators);
    let fit =
        ["characterize", path_str(&loops), "--operators", "8", "--save-model", operators_model];
    assert_conventional(&fit);
    let track_out = path_str(&track_dir);
    let track =
        ["rig", "track", "--config", config, "--out", track_out, "--model", operators_model];
    assert_conventional(&track);
}

#[test]
fn studies_and_the_store_follow_the_convention() {
    let dir = tempfile::tempdir().expect("temporary directory");
    let store = dir.path().join("sweep.sqlite");
    let sweep =
        ["sweep", "--vary", "g=0.4mm,0.5mm", "--mesh", "coarse", "--store", path_str(&store)];
    assert_conventional(&sweep);
    let exported = assert_conventional(&["export", path_str(&store)]);
    assert!(exported[0]["metrics"]["torque_max_Nm"].is_number(), "{exported}");
    // Every row carries the evaluation settings it was computed with (merged stores may differ).
    let settings = &exported[0]["settings"];
    assert_eq!(settings["mesh_level"], "coarse", "{exported}");
    assert_eq!(settings["element_order"], 1, "{exported}");
    assert!(settings["speed_rad_s"].as_f64().is_some_and(|w| w > 0.0), "{exported}");
    let csv = dir.path().join("sweep.csv");
    assert!(mrbrake(&["export", path_str(&store), "--csv", path_str(&csv)]).status.success());
    let header = std::fs::read_to_string(&csv).expect("CSV written");
    let header = header.lines().next().expect("a header");
    for setting in ["mesh_level", "element_order", "speed_rad_s"] {
        assert!(header.split(',').any(|column| column == setting), "{setting}: {header}");
    }

    let problem = dir.path().join("problem.toml");
    let spec =
        std::fs::canonicalize("../../examples/specs/thesis-bidirectional.toml").expect("spec");
    let text = format!(
        "spec = {:?}\nmesh = \"coarse\"\n[[variable]]\nname = \"h\"\nmin = \"8mm\"\nmax = \"10mm\"\n\
         [[constraint]]\nmetric = \"torque_max_Nm\"\nmin = \"1Nm\"\n\
         [[objective]]\nmetric = \"rotor_inertia_kg_m2\"\n[[objective]]\nmetric = \"volume_m3\"\n\
         [algorithm]\nkind = \"nsga2\"\npopulation = 4\ngenerations = 1\nseed = 1\n",
        path_str(&spec)
    );
    std::fs::write(&problem, text).expect("problem written");
    let opt_store = dir.path().join("opt.sqlite");
    let nsga2 =
        assert_conventional(&["optimize", path_str(&problem), "--store", path_str(&opt_store)]);
    assert!(nsga2["hypervolume"]["value"].is_number(), "{nsga2}");
    // The surrogate's report: the hypervolume with its reference point and growth, every
    // iteration's model fits, the written front designs.
    let surrogate = dir.path().join("surrogate.toml");
    let text = std::fs::read_to_string(&problem).expect("problem");
    let text = text.replace(
        "kind = \"nsga2\"\npopulation = 4\ngenerations = 1\n",
        "kind = \"surrogate\"\nmax_evaluations = 6\ninitial_size = 3\nbatch = 1\n",
    );
    std::fs::write(&surrogate, text).expect("surrogate problem written");
    let s_store = dir.path().join("surrogate.sqlite");
    let v = assert_conventional(&["optimize", path_str(&surrogate), "--store", path_str(&s_store)]);
    for key in ["hypervolume", "surrogate", "front_designs"] {
        assert!(!v[key].is_null(), "{key}: {v}");
    }
    assert!(v["hypervolume"]["reference"]["volume_m3"].is_number(), "{v}");
    assert!(v["surrogate"]["iterations"][1]["models"][0]["loo_error"].is_number(), "{v}");
    // The text of --list-metrics names the same metrics.
    let listed = mrbrake(&["optimize", "--list-metrics"]);
    assert!(String::from_utf8_lossy(&listed.stdout).contains("torque_max_Nm"));
}
