//! `mrbrake analyze --hysteresis`: the JSON's `hysteresis` object (the contract: `loop` with
//! `current_A`, `rising_Nm`, `falling_Nm`; `remanent_torque_Nm`; `width_at_mid_current_Nm`;
//! `material_model`; `timings_s`), the remanent torque in the off-state breakdown, the text, and bad
//! loop options as input errors naming their flag.

use crate::common;

use common::{expect_input_error, json, mrbrake, number};

const QUICK: [&str; 8] =
    ["analyze", "--mesh", "coarse", "--points", "2", "--hysteresis", "--loop-points", "2"];

#[test]
fn the_loop_and_the_remanent_torque_are_reported() {
    let mut args = QUICK.to_vec();
    args.push("--json");
    let value = json(&args);
    let h = &value["hysteresis"];
    let branches = &h["loop"];
    let grid = branches["current_A"].as_array().expect("current_A");
    assert_eq!(grid.len(), 3);
    for key in ["rising_Nm", "falling_Nm", "initial_Nm", "bipolar_rising_Nm"] {
        assert_eq!(branches[key].as_array().map(Vec::len), Some(3), "{key}");
    }
    assert!(h["material_model"].as_str().is_some_and(|m| m.contains("energy-based")));
    assert!(number(&h["timings_s"], "total") > 0.0);
    let remanent = number(h, "remanent_torque_Nm");
    assert!(remanent > 0.0);
    assert!(number(h, "width_at_mid_current_Nm").is_finite());
    let off = &value["torque_off"];
    assert!((number(off, "remanent_Nm") - remanent).abs() < 1e-15);
    let terms: f64 = ["viscous_Nm", "seal_Nm", "bearing_Nm", "freewheel_Nm", "remanent_Nm"]
        .iter()
        .map(|k| number(off, k))
        .sum();
    assert!((number(off, "total_Nm") - terms).abs() <= 1e-12);
    assert!(off["sources"]["remanent"].as_str().is_some_and(|s| s.contains("hysteretic")));

    let text = mrbrake(&QUICK);
    assert!(text.status.success());
    let text = String::from_utf8_lossy(&text.stdout);
    assert!(text.contains("remanent torque at 0 A after the peak"), "{text}");
}

#[test]
fn bad_loop_options_are_input_errors_naming_the_flag() {
    expect_input_error(&["analyze", "--hysteresis", "--peak", "50A"], &["--peak"]);
    expect_input_error(&["analyze", "--hysteresis", "--peak", "-1A"], &["--peak"]);
    expect_input_error(&["analyze", "--hysteresis", "--peak", "1V"], &["--peak"]);
    expect_input_error(&["analyze", "--hysteresis", "--loop-points", "1"], &["--loop-points"]);
    expect_input_error(&["analyze", "--peak", "1A"], &["--hysteresis"]);
    expect_input_error(&["analyze", "--forc-levels", "4"], &["--hysteresis"]);
    let mut forc = QUICK.to_vec();
    forc.extend(["--save-model", "/dev/null", "--forc-levels", "1"]);
    expect_input_error(&forc, &["--forc-levels"]);
}

/// `--save-model` with `--hysteresis` writes the Preisach model of the design's FORCs (schema 3),
/// says how it was made, and the remanent torque leaves the constant friction (it is the model's
/// torque at 0 A).
#[test]
fn the_saved_model_carries_the_predicted_preisach_hysteresis() {
    let dir = tempfile::tempdir().expect("temporary directory");
    let path = dir.path().join("brake.json");
    let mut args = QUICK.to_vec();
    let path_text = path.display().to_string();
    args.extend(["--save-model", &path_text, "--forc-levels", "4", "--forc-steps", "1", "--json"]);
    let out = mrbrake(&args);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("brake model hysteresis: Preisach from 4 FORCs"), "{stderr}");
    let value: serde_json::Value = serde_json::from_slice(&out.stdout).expect("JSON");
    let forc = &value["forc"];
    assert_eq!(forc["levels"], 4);
    // Each chain (one per thread) walks 0 → I_max → 0 (8 steps), the FORCs 2k steps (20).
    let chains = forc["chains"].as_u64().expect("chains");
    assert!((1..=4).contains(&chains));
    assert_eq!(forc["solves"].as_u64(), Some(8 * chains + 20));
    assert!(number(&forc["timings_s"], "wall") > 0.0);
    assert!(number(forc, "wiping_out_defect_Nm") >= 0.0);
    let model: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
    assert_eq!(model["schema_version"], 3);
    let unit = &model["units"][0];
    let h = &unit["hysteresis"];
    assert_eq!(h["kind"], "preisach");
    assert_eq!(h["levels_A"].as_array().map(Vec::len), Some(5));
    assert_eq!(h["everett_Nm"][4].as_array().map(Vec::len), Some(5));
    // The remanent torque is the rising branch's start, not in the seal friction as well.
    assert!(h["rising_Nm"][0].as_f64().is_some_and(|t| t > 0.0), "{h}");
    assert!(number(&unit["off_state"], "seal_friction_Nm").abs() < 1e-12);
}
