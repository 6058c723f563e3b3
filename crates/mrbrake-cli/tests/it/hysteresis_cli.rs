//! CLI behaviour of the minor-loop chain on the virtual rig with the Preisach brake:
//! `rig minor-loops` → `characterize --operators --save-model` → `rig track --model`, and its bad
//! input (a log without minor loops, more operators than the controller holds, in a flag or in a
//! file) giving a clear message and exit code 2.

use crate::common;

use common::{expect_input_error, json, mrbrake, number, path_str};

#[test]
fn minor_loops_identify_an_operator_model_that_tracks() {
    let dir = tempfile::tempdir().expect("temporary directory");
    let config = dir.path().join("rig.toml");
    std::fs::write(&config, "[hysteresis]\nmodel = \"preisach\"\n").expect("config written");
    let loops = dir.path().join("loops");
    let out =
        mrbrake(&["rig", "minor-loops", "--config", path_str(&config), "--out", path_str(&loops)]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let manifest = std::fs::read_to_string(loops.join("manifest.csv")).expect("manifest");
    assert!(manifest.starts_with("ramp,part,start_s,end_s,from_A,to_A\n"));
    assert!(manifest.contains("forc_from_above") && manifest.contains("decaying_triangles"));

    let log = loops.join("minor_loops.csv");
    let model = dir.path().join("operators.json");
    let fit = json(&[
        "characterize",
        path_str(&log),
        "--operators",
        "12",
        "--save-model",
        path_str(&model),
        "--json",
    ]);
    let stats = &fit["operator_model"]["fit"];
    assert!(number(stats, "fit_percent") > 90.0, "{fit}");
    assert!(number(stats, "inner_reversals") >= 10.0, "{fit}");
    let saved: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&model).expect("model written")).unwrap();
    assert_eq!(saved["schema"], "mrbrake.operator-model");
    assert_eq!(saved["version"], 1);

    let track = dir.path().join("track");
    let scores = json(&[
        "rig",
        "track",
        "--config",
        path_str(&config),
        "--model",
        path_str(&model),
        "--out",
        path_str(&track),
        "--json",
    ]);
    let scores = scores["scores"].as_array().expect("scores");
    assert_eq!(scores.len(), 4);
    for s in scores {
        let p = number(s, "rmse_percent_of_range");
        assert!(p > 0.0 && p < 25.0, "{s}");
    }

    // Bad input: more operators than the controller holds, in the flag and in a file.
    expect_input_error(
        &["characterize", path_str(&log), "--operators", "40"],
        &["--operators: ", "got 40; allowed: 1..=32"],
    );
    let text = std::fs::read_to_string(&model).unwrap();
    let thresholds: Vec<String> = (0..33).map(|k| format!("{}", k as f64 * 0.01)).collect();
    let start = text.find("\"thresholds_A\"").unwrap();
    let end = start + text[start..].find(']').unwrap() + 1;
    let too_many =
        format!("{}\"thresholds_A\": [{}]{}", &text[..start], thresholds.join(","), &text[end..]);
    let bad = dir.path().join("too_many.json");
    std::fs::write(&bad, too_many).unwrap();
    expect_input_error(
        &["rig", "track", "--model", path_str(&bad), "--out", path_str(&track)],
        &["plays.thresholds_A", "invalid length 33", "1 to 32"],
    );
}

#[test]
fn a_log_without_minor_loops_is_refused() {
    let dir = tempfile::tempdir().expect("temporary directory");
    let log = dir.path().join("ramps.csv");
    let mut csv = String::from("time_s,current_A,torque_Nm\n");
    for rep in 0..3 {
        for k in 0..400 {
            let i = if k < 200 { k as f64 * 0.01 } else { (400 - k) as f64 * 0.01 };
            let t = (rep * 400 + k) as f64 * 1e-3;
            csv.push_str(&format!("{t},{i},{}\n", 0.15 + 1.8 * i));
        }
    }
    std::fs::write(&log, csv).unwrap();
    expect_input_error(
        &["characterize", path_str(&log), "--operators", "8"],
        &["got 0 reversal(s); allowed: >= 2 reversals", "rig minor-loops"],
    );
}
