//! CLI behaviour of `mrbrake formula`: the thesis numbers end to end, JSON fields, and bad input
//! (wrong unit, negative length, R2 < R1) giving a clear message and exit code 2.

use crate::common;

use common::{expect_input_error, json};

#[test]
fn single_disc_0958() {
    let v = json(&[
        "formula",
        "single-disc",
        "--r1",
        "22.5mm",
        "--r2",
        "27.5mm",
        "--tau-y",
        "24.315kPa",
        "--json",
    ]);
    let t = v["torque_Nm"].as_f64().unwrap();
    assert!((t - 0.958).abs() < 5e-4, "{t}");
    assert!((v["inputs"]["r1_m"].as_f64().unwrap() - 0.0225).abs() < 1e-12);
    assert!((v["inputs"]["tau_y_Pa"].as_f64().unwrap() - 24_315.0).abs() < 1e-9);
}

#[test]
fn single_disc_from_flux_density_uses_the_fluid_curve() {
    let v = json(&[
        "formula",
        "single-disc",
        "--r1",
        "22.5mm",
        "--r2",
        "27.5mm",
        "--b",
        "0.46T",
        "--json",
    ]);
    let tau = v["inputs"]["tau_y_Pa"].as_f64().unwrap();
    // The thesis reads 24.315 kPa at 0.46 T from the MRF-122EG curve; the library reproduces it within 3 %.
    assert!((tau - 24_315.0).abs() / 24_315.0 < 0.03, "{tau}");
}

#[test]
fn viscous_term_is_added_at_speed() {
    let v = json(&[
        "formula",
        "single-disc",
        "--r1",
        "10mm",
        "--r2",
        "30mm",
        "--tau-y",
        "0",
        "--eta",
        "0.1Pa.s",
        "--speed",
        "100rad/s",
        "--gap",
        "1mm",
        "--json",
    ]);
    // π η ω (R2⁴ − R1⁴) / g = π · 0.1 · 100 · (8.1e-7 − 1e-8) / 1e-3
    let expected = std::f64::consts::PI * 0.1 * 100.0 * (0.03f64.powi(4) - 0.01f64.powi(4)) / 1e-3;
    assert!((v["viscous_torque_Nm"].as_f64().unwrap() - expected).abs() < 1e-12);
}

#[test]
fn multi_drum_433() {
    let v = json(&[
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
        "--json",
    ]);
    let t = v["torque_Nm"].as_f64().unwrap();
    assert!((t - 4.33).abs() < 5e-3, "{t}");
}

#[test]
fn multi_disc_and_drum_print_torque() {
    let v = json(&[
        "formula",
        "multi-disc",
        "--discs",
        "5",
        "--r1",
        "4mm",
        "--r2",
        "24mm",
        "--tau-y",
        "6.3388kPa",
        "--json",
    ]);
    assert!((v["torque_Nm"].as_f64().unwrap() - 1.83).abs() < 5e-3);
    let v =
        json(&["formula", "drum", "--r", "25mm", "--h", "9mm", "--tau-y", "3.5517kPa", "--json"]);
    assert!((v["torque_Nm"].as_f64().unwrap() - 0.25).abs() < 5e-3);
}

#[test]
fn coil_fields_and_thesis_current_density() {
    let v = json(&[
        "formula",
        "coil",
        "--window-width",
        "6mm",
        "--window-height",
        "10mm",
        "--wire-diameter",
        "0.5mm",
        "--current",
        "2A",
        "--json",
    ]);
    for field in ["turns", "resistance_ohm", "current_density_A_per_mm2", "wire_length_m"] {
        assert!(v.get(field).is_some(), "missing {field}");
    }
    let j = v["current_density_A_per_mm2"].as_f64().unwrap();
    assert!((j - 4.62).abs() < 5e-3, "{j}");
    let v = json(&[
        "formula",
        "coil",
        "--window-width",
        "12mm",
        "--window-height",
        "12mm",
        "--awg",
        "24",
        "--json",
    ]);
    assert!(v["turns"].as_u64().unwrap() > 100);
}

#[test]
fn bad_input_exits_2_with_a_clear_message() {
    expect_input_error(
        &["formula", "single-disc", "--r1", "22.5kg", "--r2", "27.5mm", "--tau-y", "1kPa"],
        &["--r1", "kg", "mm"],
    );
    expect_input_error(
        &["formula", "single-disc", "--r1", "-3mm", "--r2", "27.5mm", "--tau-y", "1kPa"],
        &["--r1: inner disc radius", "got -0.003 m", ">= 0"],
    );
    expect_input_error(
        &["formula", "single-disc", "--r1", "30mm", "--r2", "27.5mm", "--tau-y", "1kPa"],
        &["r2", "r1"],
    );
    expect_input_error(
        &["formula", "single-disc", "--r1", "3mm", "--r2", "27.5mm"],
        &["tau_y or b", "yield stress"],
    );
    expect_input_error(
        &["formula", "drum", "--r", "25mm", "--h", "9mm", "--tau-y", "1kPa", "--speed", "10rad/s"],
        &["speed needs gap"],
    );
    // The library's rules, whether or not a speed uses the value (the CLI once took a
    // viscosity the Python binding refused).
    expect_input_error(
        &["formula", "drum", "--r", "25mm", "--h", "9mm", "--tau-y", "1kPa", "--eta=-0.1Pa.s"],
        &["--eta: viscosity", ">= 0"],
    );
    expect_input_error(
        &["formula", "drum", "--r", "25mm", "--h", "9mm", "--tau-y=-1kPa"],
        &["--tau-y: yield stress", ">= 0"],
    );
    expect_input_error(&["formula", "drum", "--r", "25mm", "--h", "9mm", "--b", "4T"], &["3 T"]);
    expect_input_error(
        &["formula", "coil", "--window-width", "6mm", "--window-height", "10mm", "--awg", "40"],
        &["40"],
    );
    expect_input_error(
        &[
            "formula",
            "single-disc",
            "--r1",
            "3mm",
            "--r2",
            "27.5mm",
            "--b",
            "0.4T",
            "--fluid",
            "honey",
        ],
        &["honey"],
    );
}
