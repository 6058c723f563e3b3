//! `mrbrake analyze --hysteresis --demag` and `mrbrake haptic wall --remanence … --demag-release`:
//! the scan's JSON (`hysteresis.demagnetisation`) on a quick run, the haptic run with and without the
//! demagnetising release (lower free-motion torque with it), and bad input as exit 2 naming the flag.

use crate::common;

use common::{expect_input_error, json, number, path_str};

const QUICK: [&str; 9] = [
    "analyze",
    "--mesh",
    "coarse",
    "--points",
    "2",
    "--hysteresis",
    "--loop-points",
    "2",
    "--demag",
];

#[test]
#[cfg_attr(not(heavy_tests), ignore = "release only: ~250 non-linear solves of the thesis brake")]
fn the_scan_feeds_the_haptic_release() {
    let mut args = QUICK.to_vec();
    args.push("--json");
    let value = json(&args);
    let d = &value["hysteresis"]["demagnetisation"];
    let without = number(d, "remanent_torque_without_Nm");
    let chosen = &d["chosen_pulse"];
    assert_eq!(chosen["release"]["kind"], "reverse_pulse", "{chosen}");
    assert!(number(chosen, "remanent_torque_Nm") < without, "{d}");
    assert!(d["candidates"].as_array().is_some_and(|c| c.len() >= 8));
    assert!(d["model"].as_str().is_some_and(|m| m.contains("quasi-static")));

    let dir = tempfile::tempdir().expect("temporary directory");
    let file = dir.path().join("analysis.json");
    std::fs::write(&file, serde_json::to_string(&value).unwrap()).unwrap();
    let haptic = ["haptic", "wall", "--device", "conventional", "--json", "--remanence"];
    let mut with = haptic.to_vec();
    with.extend([path_str(&file), "--demag-release"]);
    let mut without_release = haptic.to_vec();
    without_release.push(path_str(&file));
    let (a, b) = (json(&with), json(&without_release));
    let drag = |v: &serde_json::Value| number(&v["drag_after_Nm"], "outward");
    assert!(drag(&a) < drag(&b), "{a}\n{b}");
    assert!(number(&a, "free_motion_torque_Nm") <= number(&b, "free_motion_torque_Nm") + 1e-9);
}

#[test]
fn bad_demag_input_is_exit_2_naming_the_flag() {
    expect_input_error(&["analyze", "--demag"], &["--hysteresis"]);
    let mut args = QUICK.to_vec();
    args.extend(["--demag-reverse-limit", "-1A"]);
    expect_input_error(&args, &["--demag-reverse-limit"]);
    let dir = tempfile::tempdir().expect("temporary directory");
    let file = dir.path().join("bad.json");
    std::fs::write(&file, r#"{"hysteresis": {"remanent_torque_Nm": 0.1}}"#).unwrap();
    let wall = ["haptic", "wall", "--device", "conventional", "--remanence", path_str(&file)];
    expect_input_error(&wall, &["--remanence", "peak_current_A"]);
    let mut release = wall.to_vec();
    release.push("--demag-release");
    std::fs::write(
        &file,
        r#"{"hysteresis": {"remanent_torque_Nm": 0.1, "peak_current_A": 2.0, "demagnetisation":
            {"reverse_limit_A": 2.0, "chosen_pulse": {"release": {"amplitude_A": -0.3},
             "remanence_fraction": 0.1}}}}"#,
    )
    .unwrap();
    expect_input_error(&release, &["amplitude_a"]);
    expect_input_error(
        &["haptic", "wall", "--device", "conventional", "--demag-release"],
        &["--remanence"],
    );
}
