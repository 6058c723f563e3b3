//! The brake model from the design to the hand, end to end: `analyze --save-model` → `rig
//! characterize --brake-model` → `characterize` recovers the predicted static curve; `rig freqresp
//! --brake-model` → `freqresp` → `tfest` recovers the dynamics the model drives; `haptic wall
//! --brake-model` reports the sticky-wall measures of the design. The shipped prototype files drive
//! the simulators exactly as their built-in defaults (identical output), and bad model files are
//! refused with exit code 2 naming the file and the field.

use crate::common;

use common::{expect_input_error, json, mrbrake, number, path_str};

use std::path::{Path, PathBuf};

/// A shipped example file.
fn example(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/brake-models").join(name)
}

/// Steady shaft speed of the default rig: 10.35 rad/(s·V) × 1 V ÷ 6 (belt), rad/s (rig config).
const RIG_SPEED_RAD_S: f64 = 10.35 / 6.0;

/// Ascending polynomial coefficients of `v[branch]["coefficients"]`.
fn coefficients(v: &serde_json::Value, branch: &str) -> Vec<f64> {
    v[branch]["coefficients"]
        .as_array()
        .expect("coefficients")
        .iter()
        .map(|c| c.as_f64().expect("number"))
        .collect()
}

fn eval(c: &[f64], x: f64) -> f64 {
    c.iter().rev().fold(0.0, |acc, v| acc * x + v)
}

/// The thesis design's predicted model recovered by the virtual rig's identification chain.
#[test]
#[cfg_attr(not(heavy_tests), ignore = "release only: a field analysis and two rig sessions")]
fn predicted_model_is_recovered_by_the_rig_and_drives_the_haptic_wall() {
    let dir = tempfile::tempdir().expect("temporary directory");
    let model = dir.path().join("brake.json");
    let analysis = json(&["analyze", "--json", "--save-model", path_str(&model)]);
    let saved: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&model).expect("model written")).unwrap();
    assert_eq!(saved["schema"], "mrbrake-brake-model");
    assert_eq!(saved["units"].as_array().map(Vec::len), Some(2), "bidirectional: two units");
    assert_eq!(saved["provenance"]["spec_sha256"].as_str().map(str::len), Some(64));
    let unit = &saved["units"][0];
    let currents: Vec<f64> =
        serde_json::from_value(unit["static_curve"]["current_A"].clone()).unwrap();
    let torques: Vec<f64> =
        serde_json::from_value(unit["static_curve"]["torque_Nm"].clone()).unwrap();
    let curve = analysis["torque_current_curve"].as_array().expect("curve");
    for (k, p) in curve.iter().enumerate() {
        assert!((number(p, "yield_torque_Nm") - torques[k]).abs() < 1e-12, "point {k}");
    }
    let viscous = number(&unit["off_state"], "viscous_Nm_s_per_rad");
    let off_state = number(&analysis["torque"], "off_state_Nm");
    assert!((viscous * number(&analysis, "speed_rad_s") - off_state).abs() < 1e-12);

    // The rig measures static + viscous at its shaft speed; characterize (order 7, the most the
    // controller holds) fits that.
    let char_dir = dir.path().join("char");
    let out = mrbrake(&[
        "rig",
        "characterize",
        "--out",
        path_str(&char_dir),
        "--brake-model",
        path_str(&model),
    ]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(String::from_utf8_lossy(&out.stderr).contains("no dynamics"));
    let log = char_dir.join("characterization.csv");
    let v = json(&["characterize", path_str(&log), "--order", "7", "--json"]);
    let span = torques[torques.len() - 1] - torques[0];
    let mut worst: f64 = 0.0;
    for branch in ["rising", "falling"] {
        let c = coefficients(&v, branch);
        for (i, t) in currents.iter().zip(&torques) {
            worst = worst.max((eval(&c, *i) - (t + viscous * RIG_SPEED_RAD_S)).abs());
        }
    }
    eprintln!(
        "static curve recovered within {worst:.4} N·m ({:.2} % of {span:.3} N·m)",
        100.0 * worst / span
    );
    assert!(worst < 0.02 * span, "worst {worst} N·m of a {span} N·m span");
    // The identified branches go into a copy of the model as its unit-1 hysteresis.
    let identified = dir.path().join("identified.json");
    std::fs::copy(&model, &identified).unwrap();
    let args =
        ["characterize", path_str(&log), "--order", "7", "--brake-model", path_str(&identified)];
    assert!(mrbrake(&args).status.success());
    let saved: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&identified).unwrap()).unwrap();
    assert_eq!(saved["units"][0]["hysteresis"]["kind"], "polynomial_branches");
    assert_eq!(saved["units"][0]["hysteresis"]["rising"], v["rising"]["coefficients"]);
    assert_eq!(saved["units"][1]["hysteresis"]["kind"], "none");
    let m = json(&[
        "haptic",
        "wall",
        "--device",
        "conventional",
        "--brake-model",
        path_str(&identified),
        "--json",
    ]);
    assert!(number(&m, "max_penetration_rad").is_finite());

    // The predicted dynamics, then the frequency-response session through the model's branches.
    let out = mrbrake(&["response", "--save-model", path_str(&model)]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let saved: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&model).unwrap()).unwrap();
    let predicted: Vec<f64> =
        serde_json::from_value(saved["units"][0]["dynamics"]["denominator"].clone())
            .expect("response --save-model added the dynamics");
    assert_eq!(predicted.len(), 3, "{predicted:?}");
    // The bidirectional brake's unit 2 is fitted to direction 2's own response.
    let source_2 = saved["units"][1]["dynamics"]["source"].as_str().unwrap();
    assert!(source_2.contains("response of direction 2"), "{source_2}");
    let assumed = saved["provenance"]["assumed"].to_string();
    assert!(!assumed.contains("unit 2's dynamics"), "{assumed}");
    let freq_dir = dir.path().join("freq");
    let out = mrbrake(&[
        "rig",
        "freqresp",
        "--out",
        path_str(&freq_dir),
        "--brake-model",
        path_str(&model),
    ]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(!String::from_utf8_lossy(&out.stderr).contains("no dynamics"));
    let f = json(&["freqresp", path_str(&freq_dir.join("manifest.csv")), "--json"]);
    let lowest = &f["points"][0];
    assert!(number(lowest, "magnitude_dB").abs() < 0.5, "{lowest}");
    let t = json(&[
        "tfest",
        path_str(&freq_dir.join("frd.csv")),
        "--poles",
        "2",
        "--delay",
        "0.5ms",
        "--json",
    ]);
    let fitted: Vec<f64> = serde_json::from_value(t["denominator"].clone()).unwrap();
    // Denominators are normalised to D(0) = 1: compare the s² and s coefficients.
    for k in 0..2 {
        let error = (fitted[k] - predicted[k]).abs() / predicted[k];
        eprintln!(
            "dynamics: s^{} coefficient {:.6e} vs predicted {:.6e} ({:.2} %)",
            2 - k,
            fitted[k],
            predicted[k],
            100.0 * error
        );
        assert!(error < 0.03, "{fitted:?} vs {predicted:?}");
    }

    // The hot coil.
    let out = mrbrake(&["thermal", "--save-model", path_str(&model)]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let saved: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&model).unwrap()).unwrap();
    let thermal = &saved["units"][1]["thermal"];
    assert!(
        number(thermal, "hot_resistance_ohm") > number(&analysis["coil"], "resistance_20C_ohm")
    );
    assert!(number(thermal, "continuous_current_A") > 0.0, "{thermal}");
    assert_eq!(saved["provenance"]["amended"].as_array().map(Vec::len), Some(2));

    // The haptic wall on the design: the conventional brake sticks on withdrawal, the
    // bidirectional one does not (thesis ch. 2, §4.3).
    let mut excess = Vec::new();
    for device in ["conventional", "bidirectional"] {
        let m = json(&[
            "haptic",
            "wall",
            "--device",
            device,
            "--brake-model",
            path_str(&model),
            "--json",
        ]);
        assert_eq!(m["device"], device);
        for field in ["max_penetration_rad", "outward_drag_Nm", "withdraw_energy_J"] {
            assert!(number(&m, field).is_finite(), "{field}: {m}");
        }
        excess.push(number(&m["withdraw_excess_torque_Nm"], "peak"));
    }
    eprintln!(
        "withdraw excess torque peak: conventional {:.3} N·m, bidirectional {:.3} N·m",
        excess[0], excess[1]
    );
    assert!(excess[1] < 0.1 * excess[0], "{excess:?}");
}

/// The shipped prototypes are the built-in brakes: same output as without the flag.
#[test]
#[cfg_attr(not(heavy_tests), ignore = "release only: two full rig sessions")]
fn shipped_prototypes_reproduce_the_default_outputs_exactly() {
    let proto = example("prototype.json");
    for device in ["conventional", "bidirectional"] {
        let default = mrbrake(&["haptic", "wall", "--device", device, "--json"]);
        let file = mrbrake(&[
            "haptic",
            "wall",
            "--device",
            device,
            "--json",
            "--brake-model",
            path_str(&proto),
        ]);
        assert!(default.status.success() && file.status.success());
        assert_eq!(default.stdout, file.stdout, "{device}");
        assert!(file.stderr.is_empty(), "{}", String::from_utf8_lossy(&file.stderr));
    }
    let dir = tempfile::tempdir().expect("temporary directory");
    let (a, b) = (dir.path().join("a"), dir.path().join("b"));
    let rig = example("rig-prototype.json");
    assert!(mrbrake(&["rig", "characterize", "--out", path_str(&a)]).status.success());
    let out =
        mrbrake(&["rig", "characterize", "--out", path_str(&b), "--brake-model", path_str(&rig)]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    for name in ["characterization.csv", "rig.toml"] {
        let read = |d: &Path| std::fs::read(d.join(name)).expect(name);
        assert!(read(&a) == read(&b), "{name} differs");
    }
}

/// A change that spoils a good model file.
type Mutation = dyn Fn(&mut serde_json::Value);

/// Writes `value` to `dir/name` and returns the path.
fn write(dir: &Path, name: &str, value: &serde_json::Value) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, serde_json::to_string_pretty(value).unwrap()).unwrap();
    path
}

#[test]
fn bad_model_files_are_refused_naming_the_file_and_the_field() {
    let dir = tempfile::tempdir().expect("temporary directory");
    let good: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(example("prototype.json")).unwrap()).unwrap();
    let cases: Vec<(&str, Box<Mutation>, &[&str])> = vec![
        (
            "foreign.json",
            Box::new(|v| v["schema"] = "mrbrake-inverse-model".into()),
            &["foreign schema", "schema"],
        ),
        (
            "old.json",
            Box::new(|v| v["schema_version"] = 0.into()),
            &["schema_version", "reads versions [1, 2, 3]"],
        ),
        (
            "missing.json",
            Box::new(|v| {
                v["units"][0].as_object_mut().unwrap().remove("off_state");
            }),
            &["units[0]", "off_state"],
        ),
        (
            "units.json",
            Box::new(|v| {
                let curve = v["units"][0]["static_curve"].as_object_mut().unwrap();
                let t = curve.remove("torque_Nm").unwrap();
                curve.insert("torque_mNm".into(), t);
            }),
            &["torque_mNm"],
        ),
        (
            "decreasing.json",
            Box::new(|v| v["units"][1]["static_curve"]["torque_Nm"][5] = 0.0.into()),
            &["units[1].static_curve.torque_Nm[5]", "must not decrease"],
        ),
        (
            "null.json",
            Box::new(|v| v["units"][0]["current_max_A"] = serde_json::Value::Null),
            &["units[0].current_max_A"],
        ),
        (
            "branch.json",
            Box::new(|v| v["units"][0]["hysteresis"]["rising"] = serde_json::json!([1.0, -1.0])),
            &["units[0].hysteresis"],
        ),
        (
            "range.json",
            Box::new(|v| v["units"][0]["off_state"]["seal_friction_Nm"] = (-0.1).into()),
            &["seal_friction_Nm", "outside"],
        ),
    ];
    for (name, mutate, needles) in cases {
        let mut v = good.clone();
        mutate(&mut v);
        let path = write(dir.path(), name, &v);
        let mut all = needles.to_vec();
        all.push(name);
        expect_input_error(
            &["haptic", "wall", "--device", "conventional", "--brake-model", path_str(&path)],
            &all,
        );
        expect_input_error(
            &[
                "rig",
                "characterize",
                "--out",
                path_str(&dir.path().join("o")),
                "--brake-model",
                path_str(&path),
            ],
            &all,
        );
    }
    // Not JSON at all (a NaN is not a JSON number).
    let nan = dir.path().join("nan.json");
    std::fs::write(&nan, r#"{"schema": "mrbrake-brake-model", "schema_version": 1, "x": NaN}"#)
        .unwrap();
    expect_input_error(
        &["haptic", "wall", "--device", "conventional", "--brake-model", path_str(&nan)],
        &["nan.json", "not JSON"],
    );
    expect_input_error(
        &["haptic", "wall", "--device", "motor", "--brake-model", "no/such/brake.json"],
        &["no/such/brake.json"],
    );
}
