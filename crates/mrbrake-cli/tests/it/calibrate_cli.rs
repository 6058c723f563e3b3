//! `mrbrake calibrate` through the binary: known parameters come back from a rig log generated
//! by a perturbed design (within two standard errors and 2 %), a pair the static curve cannot
//! separate is reported as such, and bad logs and parameters are input errors (exit 2) that
//! name the flag or the file.

use crate::common;

use std::path::Path;

use common::{expect_input_error, json, mrbrake, path_str};

const SPEC: &str =
    concat!(env!("CARGO_MANIFEST_DIR"), "/../../examples/specs/thesis-bidirectional.toml");

/// The thesis spec with a 0.54 mm gap (+8 %), a fluid batch 15 % weaker and a gap 80 % full.
fn perturbed_spec(dir: &Path) -> std::path::PathBuf {
    let text = std::fs::read_to_string(SPEC).unwrap();
    let text = text.replacen("gap = \"0.5mm\"", "gap = \"0.54mm\"", 1);
    assert!(text.contains("gap = \"0.54mm\""), "the thesis spec's gap line moved");
    let path = dir.join("perturbed.toml");
    std::fs::write(
        &path,
        format!("{text}\n[fluid]\nyield_stress_scale = 0.85\nfill_fraction = 0.8\n"),
    )
    .unwrap();
    path
}

/// A characterisation log of `spec`'s brake model on the virtual rig (three repetitions, the
/// rig's sensor noise).
fn rig_log(spec: &Path, dir: &Path) -> std::path::PathBuf {
    let model = dir.join("model.json");
    let out = mrbrake(&[
        "analyze",
        path_str(spec),
        "--mesh",
        "coarse",
        "--points",
        "21",
        "--save-model",
        path_str(&model),
    ]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let config = String::from_utf8(mrbrake(&["rig", "config"]).stdout).unwrap();
    let config = config.replace("repetitions = 10", "repetitions = 3");
    let config_path = dir.join("rig.toml");
    std::fs::write(&config_path, config).unwrap();
    let logs = dir.join("logs");
    let out = mrbrake(&[
        "rig",
        "characterize",
        "--config",
        path_str(&config_path),
        "--brake-model",
        path_str(&model),
        "--out",
        path_str(&logs),
    ]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    logs.join("characterization.csv")
}

#[test]
#[cfg_attr(not(heavy_tests), ignore = "release only: tens of FEA analyses")]
fn known_parameters_come_back_and_an_unidentifiable_pair_is_named() {
    let dir = tempfile::tempdir().unwrap();
    let log = rig_log(&perturbed_spec(dir.path()), dir.path());
    let calibrated = dir.path().join("calibrated.toml");
    let fit = |set: &str, parameters: [&str; 2], extra: &[&str]| {
        let mut args = vec!["calibrate", SPEC, "--mesh", "coarse", "--log", path_str(&log)];
        args.extend(["--set", set, "--parameter", parameters[0], "--parameter", parameters[1]]);
        args.extend(extra);
        args.push("--json");
        json(&args)
    };
    let v = fit(
        "fluid.fill_fraction=0.8",
        ["fluid.yield_stress_scale=0.5..1.2", "drum.gap=0.4mm..0.7mm"],
        &["-o", path_str(&calibrated)],
    );
    for (k, truth) in [(0, 0.85), (1, 0.54e-3)] {
        let p = &v["parameters"][k];
        let (estimate, se) =
            (p["estimate"].as_f64().unwrap(), p["standard_error"].as_f64().unwrap());
        assert!((estimate - truth).abs() <= 0.02 * truth, "{}: {estimate} vs {truth}", p["name"]);
        assert!(
            (estimate - truth).abs() <= 2.0 * se,
            "{}: {estimate} ± {se} vs {truth}",
            p["name"]
        );
    }
    assert!(v["unidentifiable"].as_array().unwrap().is_empty(), "{}", v["unidentifiable"]);
    let before = v["residual_rms_before_Nm"].as_f64().unwrap();
    let after = v["residual_rms_after_Nm"].as_f64().unwrap();
    assert!(after < 0.1 * before, "residual {before} → {after} N·m");
    // The calibrated spec is a spec every command reads, with the estimates in it.
    let again = json(&["analyze", path_str(&calibrated), "--mesh", "coarse", "--json"]);
    let text = std::fs::read_to_string(&calibrated).unwrap();
    assert!(text.contains("# calibrated:") && text.contains("fill_fraction = 0.8"), "{text}");
    let torque = again["torque"]["at_max_current_Nm"].as_f64().unwrap();
    let fitted = v["calibrated"]["torque_at_max_current_Nm"].as_f64().unwrap();
    assert!((torque - fitted).abs() < 1e-9 * fitted, "{torque} vs {fitted}");

    // The yield stress and the wetted share scale the static torque alike.
    let v = fit(
        "drum.gap=0.54mm",
        ["fluid.yield_stress_scale=0.5..1.2", "fluid.fill_fraction=0.5..1"],
        &[],
    );
    let groups = v["unidentifiable"].as_array().unwrap();
    let named = |name: &str| groups.iter().flat_map(|g| g.as_array().unwrap()).any(|n| n == name);
    assert!(named("fluid.yield_stress_scale") && named("fluid.fill_fraction"), "{groups:?}");
}

fn run(a: &[String]) -> Vec<&str> {
    a.iter().map(String::as_str).collect()
}

#[test]
fn bad_logs_and_parameters_are_input_errors() {
    let dir = tempfile::tempdir().unwrap();
    let write = |name: &str, text: &str| {
        let path = dir.path().join(name);
        std::fs::write(&path, text).unwrap();
        path
    };
    // One ramp up, never down: no loop.
    let mut ramp = String::from("time_s,current_A,torque_Nm\n");
    for k in 0..2000 {
        ramp.push_str(&format!("{},{},{}\n", k as f64 * 1e-3, k as f64 * 1e-3, k as f64 * 2e-3));
    }
    let no_reversal = write("ramp.csv", &ramp);
    let args = |log: &Path| -> Vec<String> {
        ["calibrate", "--log", path_str(log), "--parameter", "fluid.yield_stress_scale"]
            .map(String::from)
            .to_vec()
    };
    expect_input_error(&run(&args(&no_reversal)), &["ramp.csv"]);
    let other = write("other.csv", "t,i,tau\n0,0,0\n0.001,0.5,1\n");
    expect_input_error(&run(&args(&other)), &["other.csv", "time_s"]);
    // Loops up to 1 A only, for a 2 A brake.
    let mut short = String::from("time_s,current_A,torque_Nm\n");
    let mut t = 0.0;
    for _ in 0..3 {
        for k in (0..=1000).chain((0..1000).rev()) {
            short.push_str(&format!("{t},{},{}\n", k as f64 * 1e-3, k as f64 * 3e-3));
            t += 1e-3;
        }
    }
    let short = write("short.csv", &short);
    expect_input_error(&run(&args(&short)), &["short.csv", "maximum current"]);
    let log = no_reversal.clone();
    let with = |parameter: &str| -> Vec<String> {
        ["calibrate", "--log", path_str(&log), "--parameter", parameter].map(String::from).to_vec()
    };
    expect_input_error(&run(&with("coil.turns")), &["--parameter", "whole-number"]);
    expect_input_error(&run(&with("materials.fluid")), &["materials.fluid"]);
    expect_input_error(&run(&with("drum.nothing")), &["drum.nothing"]);
    expect_input_error(&run(&with("drum.gap=0.8mm..0.4mm")), &["--parameter", "LOW < HIGH"]);
    expect_input_error(&run(&with("drag.seal_torque")), &["--parameter", "give bounds"]);
    expect_input_error(
        &run(&["calibrate", "--log", path_str(&log), "--parameter", "drum.gap", "--points", "2"]
            .map(String::from)),
        &["--points"],
    );
}

/// The rig's prototype log and frequency response (the thesis brake's measured lag, thesis (5.5)).
fn prototype_data(dir: &Path) -> (std::path::PathBuf, std::path::PathBuf) {
    let (char_dir, freq_dir) = (dir.join("char"), dir.join("freq"));
    for (protocol, out) in [("characterize", &char_dir), ("freqresp", &freq_dir)] {
        let o = mrbrake(&["rig", protocol, "--out", path_str(out)]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    }
    let o = mrbrake(&["freqresp", path_str(&freq_dir.join("manifest.csv"))]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    (char_dir.join("characterization.csv"), freq_dir.join("frd.csv"))
}

#[test]
#[cfg_attr(not(heavy_tests), ignore = "release only: frequency responses of a brake")]
fn a_frequency_response_is_fitted_with_the_loop() {
    let dir = tempfile::tempdir().unwrap();
    let (log, frd) = prototype_data(dir.path());
    let plot = dir.path().join("calibration.svg");
    let v = json(&[
        "calibrate",
        "--mesh",
        "coarse",
        "--log",
        path_str(&log),
        "--frd",
        path_str(&frd),
        "--parameter",
        "steel.conductivity_S_per_m=1MS/m..30MS/m",
        "--max-evaluations",
        "12",
        "--plot",
        path_str(&plot),
        "--json",
    ]);
    let f = &v["frequency_response"];
    let (before, after) = (f["rms_before"].as_f64().unwrap(), f["rms_after"].as_f64().unwrap());
    assert!(after <= before, "the response's misfit grew: {before} → {after}");
    // A more conductive steel lags more (eddy currents): the fit raises it towards the
    // prototype's slower response.
    let sigma = v["parameters"][0]["estimate"].as_f64().unwrap();
    assert!(sigma > v["parameters"][0]["start"].as_f64().unwrap(), "{sigma}");
    let measured = f["bandwidth_measured_rad_s"].as_f64().unwrap();
    assert!((measured - 63.0).abs() < 5.0, "the rig's prototype: {measured} rad/s");
    assert_eq!(
        f["measured"].as_array().unwrap().len(),
        f["predicted_after"].as_array().unwrap().len()
    );
    assert!(std::fs::metadata(&plot).unwrap().len() > 1000);
}

#[test]
fn a_bad_frequency_response_file_is_an_input_error() {
    let dir = tempfile::tempdir().unwrap();
    let mut log = String::from("time_s,current_A,torque_Nm\n");
    let mut t = 0.0;
    for _ in 0..3 {
        for k in (0..=2000).chain((0..2000).rev()) {
            log.push_str(&format!("{t},{},{}\n", k as f64 * 1e-3, k as f64 * 2e-3));
            t += 1e-3;
        }
    }
    let log_path = dir.path().join("loop.csv");
    std::fs::write(&log_path, log).unwrap();
    let frd = dir.path().join("bad-frd.csv");
    std::fs::write(&frd, "w,gain\n1,2\n").unwrap();
    expect_input_error(
        &[
            "calibrate",
            "--log",
            path_str(&log_path),
            "--frd",
            path_str(&frd),
            "--parameter",
            "drum.gap",
        ],
        &["bad-frd.csv"],
    );
}
