//! CLI behaviour of the identification chain, end to end on the virtual rig: `rig characterize` →
//! `characterize --save-model` → `rig freqresp --model` → `freqresp` → `tfest`, recovering the rig's
//! hysteresis figures and the poles of its brake dynamics; plus `tfest` on exact synthetic data and
//! bad input (a NaN torque in a log, more zeros than poles) giving a clear message and exit code 2.

use crate::common;

use common::{expect_input_error, json, mrbrake, number, path_str};

use std::path::Path;

/// Real poles (rad/s, positive) of `a s² + b s + 1`.
fn real_poles_of_quadratic(a: f64, b: f64) -> [f64; 2] {
    let root = (b * b - 4.0 * a).sqrt();
    [(b - root) / (2.0 * a), (b + root) / (2.0 * a)]
}

/// The `[re, im]` pairs of a `tfest` result's `poles`, as (re, im).
fn poles(v: &serde_json::Value) -> Vec<(f64, f64)> {
    v["poles"]
        .as_array()
        .expect("poles is an array")
        .iter()
        .map(|p| (p[0].as_f64().expect("re"), p[1].as_f64().expect("im")))
        .collect()
}

#[test]
fn rig_session_recovers_hysteresis_and_brake_dynamics() {
    let dir = tempfile::tempdir().expect("temporary directory");
    let char_dir = dir.path().join("characterization");
    let freq_dir = dir.path().join("frequency-response");
    let model = dir.path().join("model.json");

    // 1. The characterisation experiment (§5.3.1) on the default (thesis) rig.
    let out = mrbrake(&["rig", "characterize", "--out", path_str(&char_dir)]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let rig_toml = std::fs::read_to_string(char_dir.join("rig.toml")).expect("rig.toml written");
    // The pole references below come from this brake lag: 1 / (1.791e-5 s² + 0.01702 s + 1).
    assert!(
        rig_toml.contains("dynamics_denominator = [0.00001791, 0.01702, 1.0]"),
        "the default rig changed; update the references:\n{rig_toml}"
    );

    // 2. Hysteresis branches and the inverse model.
    let log = char_dir.join("characterization.csv");
    let v = json(&["characterize", path_str(&log), "--json", "--save-model", path_str(&model)]);
    assert_eq!(v["repetitions"].as_u64(), Some(10), "{v}");
    let off_state = number(&v, "off_state_torque_Nm");
    assert!((off_state - 0.15).abs() < 0.02, "off-state torque {off_state} N·m");
    let max_torque = number(&v, "max_torque_Nm");
    assert!((max_torque - 3.84).abs() < 0.05, "max torque {max_torque} N·m");
    for branch in ["rising", "falling"] {
        let coefficients = v[branch]["coefficients"].as_array().expect("coefficients");
        assert_eq!(coefficients.len(), 6, "order 5 by default: {}", v[branch]);
        assert!(coefficients.iter().all(|c| c.as_f64().is_some_and(f64::is_finite)));
    }
    let saved: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&model).expect("model written"))
            .expect("model is JSON");
    assert_eq!(saved["rising"]["coefficients"], v["rising"]["coefficients"]);
    assert_eq!(saved["falling"]["coefficients"], v["falling"]["coefficients"]);

    // 3. The frequency-response experiment (§5.3.2), shaped by the identified inverse model.
    let out =
        mrbrake(&["rig", "freqresp", "--out", path_str(&freq_dir), "--model", path_str(&model)]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let manifest = freq_dir.join("manifest.csv");
    let manifest_rows =
        std::fs::read_to_string(&manifest).expect("manifest written").lines().count() - 1;
    assert!(manifest_rows >= 20, "{manifest_rows} frequencies");

    // 4. Gain and phase per frequency.
    let v = json(&["freqresp", path_str(&manifest), "--json"]);
    let points = v["points"].as_array().expect("points");
    assert_eq!(points.len(), manifest_rows);
    // Well below the brake's first pole the inverse model makes the output track the input.
    let lowest = &points[0];
    assert!(number(lowest, "omega_rad_s") < 1.0);
    assert!(number(lowest, "magnitude_dB").abs() < 0.5, "{lowest}");
    assert!(number(lowest, "phase_deg").abs() < 2.0, "{lowest}");
    let frd = freq_dir.join("frd.csv");
    assert!(frd.is_file(), "frd.csv written beside the manifest");

    // 5. Two-pole fit with the half-sample zero-order-hold delay removed.
    let v = json(&["tfest", path_str(&frd), "--poles", "2", "--delay", "0.5ms", "--json"]);
    let fitted = poles(&v);
    assert_eq!(fitted.len(), 2);
    let mut fitted_rad_s: Vec<f64> = fitted
        .iter()
        .map(|&(re, im)| {
            assert!(im.abs() < 1e-9 && re < 0.0, "expected real stable poles: {fitted:?}");
            -re
        })
        .collect();
    fitted_rad_s.sort_by(f64::total_cmp);
    let reference = real_poles_of_quadratic(1.791e-5, 0.01702);
    assert!((reference[0] - 62.92).abs() < 0.01 && (reference[1] - 887.4).abs() < 0.1);
    for (fit, truth) in fitted_rad_s.iter().zip(reference) {
        assert!((fit - truth).abs() / truth < 0.03, "pole {fit} rad/s vs rig {truth} rad/s");
    }
    assert_eq!(v["stable"], true);
}

/// Writes the exact frequency response of 1 / ((1 + s/100)(1 + s/2000)) at 30 log-spaced points.
fn write_exact_frd(path: &Path) {
    let mut text = String::from("omega_rad_s,re,im\n");
    for k in 0..30 {
        let omega = 10f64.powf(4.0 * f64::from(k) / 29.0);
        // (1 + jω/p1)(1 + jω/p2) = (1 − ω²/(p1 p2)) + jω (1/p1 + 1/p2); G is its reciprocal.
        let (den_re, den_im) = (1.0 - omega * omega / (100.0 * 2000.0), omega * (0.01 + 0.0005));
        let norm = den_re * den_re + den_im * den_im;
        text.push_str(&format!("{omega},{},{}\n", den_re / norm, -den_im / norm));
    }
    std::fs::write(path, text).expect("FRD written");
}

#[test]
fn tfest_recovers_exact_poles_and_rejects_more_zeros_than_poles() {
    let dir = tempfile::tempdir().expect("temporary directory");
    let frd = dir.path().join("exact.csv");
    write_exact_frd(&frd);

    let v = json(&["tfest", path_str(&frd), "--poles", "2", "--json"]);
    let mut fitted: Vec<f64> = poles(&v).iter().map(|&(re, _)| -re).collect();
    fitted.sort_by(f64::total_cmp);
    assert!((fitted[0] - 100.0).abs() < 1e-3, "{fitted:?}");
    assert!((fitted[1] - 2000.0).abs() < 2e-2, "{fitted:?}");
    assert!((number(&v, "dc_gain") - 1.0).abs() < 1e-6, "{v}");

    expect_input_error(
        &["tfest", path_str(&frd), "--poles", "2", "--zeros", "3"],
        &["--zeros: got 3", "allowed: <= poles (2)"],
    );
    expect_input_error(&["tfest", path_str(&frd), "--poles", "0"], &["--poles: got 0", ">= 1"]);
    expect_input_error(&["tfest", path_str(&frd), "--poles", "2", "--delay", "0.5kg"], &["kg"]);
}

#[test]
fn characterize_rejects_a_nan_torque_naming_the_line() {
    let dir = tempfile::tempdir().expect("temporary directory");
    // A short ramp log, header on line 1; line 7 carries a NaN torque.
    let mut text = String::from("time_s,current_A,torque_Nm\n");
    for k in 0..60 {
        let current = 0.05 * f64::from(k);
        let torque = if k == 5 { "NaN".to_owned() } else { format!("{}", 0.15 + 1.8 * current) };
        text.push_str(&format!("{},{current},{torque}\n", 0.01 * f64::from(k)));
    }
    let log = dir.path().join("nan-log.csv");
    std::fs::write(&log, text).expect("log written");
    expect_input_error(&["characterize", path_str(&log)], &["nan-log.csv", "line 7", "torque_Nm"]);

    let missing = dir.path().join("missing.csv");
    expect_input_error(&["characterize", path_str(&missing)], &["missing.csv"]);
    // The order is the library's rule, checked before the log is read, named by the CLI's flag.
    let order = ["characterize", path_str(&missing), "--order", "13"];
    expect_input_error(&order, &["--order: got 13", "allowed: 1..=12"]);
    let out = dir.path().join("r.html");
    let report = ["report", "--log", path_str(&missing), "--fit-order", "0", "-o", path_str(&out)];
    expect_input_error(&report, &["--fit-order: got 0", "1..=12"]);
}
