//! `mrbrake thermal`: bad input exits 2 naming the flag and the allowed range (before any solve);
//! the JSON carries the keys and a closed energy balance; the plots are written; the hot
//! brake is consistent (release only: with the magnetic analysis and natural convection).

use crate::common;

use common::{expect_input_error, json, number, path_str};

#[test]
fn bad_thermal_input_is_exit_code_2() {
    expect_input_error(&["thermal", "--duty", "1.5"], &["--duty", "(0, 1]"]);
    expect_input_error(&["thermal", "--duty", "0"], &["--duty", "(0, 1]"]);
    expect_input_error(&["thermal", "--h=-1"], &["--h", "(0, 1e5]"]);
    expect_input_error(&["thermal", "--h", "windy"], &["--h", "natural"]);
    expect_input_error(&["thermal", "--ambient=-300C"], &["--ambient", "-273.15"]);
    expect_input_error(&["thermal", "--ambient", "25K"], &["--ambient"]);
    expect_input_error(&["thermal", "--current", "0A"], &["--current", "(0, 100]"]);
    expect_input_error(&["thermal", "--insulation-class", "Z"], &["--insulation-class", "F"]);
    expect_input_error(
        &["thermal", "--insulation-class", "20C"],
        &["--insulation-class", "ambient"],
    );
    expect_input_error(&["thermal", "--time", "1s"], &["--time", "step"]);
    expect_input_error(&["thermal", "--dt", "0s"], &["--dt", "> 0"]);
    expect_input_error(&["thermal", "--period", "0s"], &["--period", "> 0"]);
    expect_input_error(&["thermal", "--speed=-1rad/s"], &["--speed", "[0, 1e4]"]);
    expect_input_error(&["thermal", "--mesh", "huge"], &["--mesh"]);
    expect_input_error(&["thermal", "--emissivity", "1.2"], &["--emissivity", "[0, 1]"]);
}

/// The thesis brake on the coarse mesh, a short warm-up: every key the issue names, the energy
/// balance closed, the hot spot in the coil, the rating consistent with the steady state.
#[test]
fn thermal_json_keys_and_plots() {
    let dir = tempfile::tempdir().unwrap();
    let plots = dir.path().join("plots");
    let v = json(&[
        "thermal",
        "--mesh",
        "coarse",
        "--time",
        "10min",
        "--dt",
        "60s",
        "--no-behaviour",
        "--json",
        "--plot-dir",
        path_str(&plots),
    ]);
    let steady = &v["steady"];
    for key in [
        "coil_max_T_C",
        "coil_mean_T_C",
        "fluid_mean_T_C",
        "fluid_max_T_C",
        "housing_max_T_C",
        "heat_W",
        "energy_balance_W",
    ] {
        number(steady, key);
    }
    let heat = number(steady, "heat_W");
    assert!(number(steady, "energy_balance_W").abs() < 1e-8 * heat, "{steady}");
    assert!(number(steady, "coil_max_T_C") >= number(steady, "fluid_max_T_C"));
    let rating = number(&v, "continuous_current_A");
    assert!((number(steady, "coil_max_T_C") > 155.0) == (rating < 2.0), "{v}");
    let duty = number(&v, "max_duty_at_max_current");
    assert!((duty - (rating / 2.0).powi(2).min(1.0)).abs() < 1e-9);
    assert!(v.get("time_to_limit_s").is_some(), "time_to_limit_s must be present (maybe null)");
    let time = v["warmup"]["time_s"].as_array().unwrap();
    let hot = v["warmup"]["coil_max_T_C"].as_array().unwrap();
    assert_eq!(time.len(), 11);
    assert_eq!(hot.len(), time.len());
    assert!(number(&v["timings_s"], "total") > 0.0);
    assert!(v["behaviour"].is_null());
    for name in ["temperature_map.svg", "warmup.svg"] {
        let text = std::fs::read_to_string(plots.join(name)).unwrap();
        assert!(text.starts_with("<svg"), "{name}");
    }
}

/// The default mesh with natural convection and the hot behaviour: h from the correlation in the
/// range of still air, the hot brake has a higher resistance, a thinner fluid and (voltage drive)
/// less current and torque; radiation (emissivity 0.9) cools it markedly; the text names every
/// part.
#[test]
#[cfg_attr(not(heavy_tests), ignore)]
fn thermal_natural_convection_and_hot_behaviour() {
    let v = json(&["thermal", "--h", "natural", "--time", "30min", "--json"]);
    let h = number(&v["cooling"], "h_W_per_m2_K");
    assert!((2.0..20.0).contains(&h), "natural-convection h = {h}");
    let b = &v["behaviour"];
    assert!(number(b, "coil_resistance_hot_ohm") > number(b, "coil_resistance_cold_ohm"));
    assert!(number(b, "off_state_torque_hot_Nm") < number(b, "off_state_torque_cold_Nm"));
    let drive = &b["voltage_drive"];
    assert!(number(drive, "current_hot_A") < 2.0);
    assert!(number(drive, "torque_hot_Nm") < number(b, "torque_cold_Nm"));
    let radiating = json(&[
        "thermal",
        "--h",
        "natural",
        "--emissivity",
        "0.9",
        "--no-behaviour",
        "--time",
        "10min",
        "--json",
    ]);
    let hot = |v: &serde_json::Value| number(&v["steady"], "coil_max_T_C");
    assert!(
        hot(&radiating) < hot(&v) - 20.0,
        "radiation cools: {} vs {}",
        hot(&radiating),
        hot(&v)
    );
    let out = common::mrbrake(&["thermal", "--h", "natural", "--time", "10min"]);
    let text = String::from_utf8_lossy(&out.stdout);
    for needle in ["natural convection", "continuous current", "voltage drive", "off-state torque"]
    {
        assert!(text.contains(needle), "text lacks '{needle}':\n{text}");
    }
}
