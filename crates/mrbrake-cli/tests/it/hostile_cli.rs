//! Issue 18 through the binary: one bad design does not stop a study (and `--resume` does not
//! replay into it), hostile rig configurations and logs are input errors (exit 2) naming the file,
//! never aborts, panics or NaN answers.

use crate::common;

use std::path::Path;

use common::{expect_input_error, json, path_str};

const SPEC: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../../examples/specs/single-disc.toml");

/// A sweep whose plan holds a 1 µm end plate (too thin for any mesh; it used to exhaust memory)
/// next to the example's own 5 mm: the thin design is stored as infeasible with its reason, the
/// other is computed, and a resumed run computes nothing again. A 1 µm coil window (issue 18's
/// optimisation) is stored the same way (the wire no longer fits it).
#[test]
fn one_unmeshable_design_is_stored_with_its_reason_and_the_study_goes_on() {
    let dir = tempfile::tempdir().unwrap();
    let store = dir.path().join("s.sqlite");
    let args = [
        "sweep",
        SPEC,
        "--vary",
        "housing.end_plate_thickness=0.001mm,5mm",
        "--mesh",
        "coarse",
        "--store",
        path_str(&store),
        "--json",
    ];
    json(&args);
    let designs = json(&["export", path_str(&store), "--json"]);
    let designs = designs.as_array().unwrap();
    assert_eq!(designs.len(), 2, "{designs:?}");
    let thin = designs.iter().find(|d| d["status"] != "ok").expect("the thin design is stored");
    let reason = thin["reason"].as_str().unwrap_or_default();
    assert!(
        reason.contains("housing.end_plate_thickness") && reason.contains("too thin"),
        "{thin}"
    );
    assert!(designs.iter().any(|d| d["status"] == "ok"), "{designs:?}");
    let mut resume = args.to_vec();
    resume.push("--resume");
    let again = json(&resume);
    assert_eq!(again["summary"]["computed"].as_u64(), Some(0), "{again}");
    assert_eq!(again["summary"]["reused"].as_u64(), Some(2), "{again}");

    let window = dir.path().join("w.sqlite");
    json(&[
        "sweep",
        SPEC,
        "--vary",
        "coil.window_height=0.001mm",
        "--mesh",
        "coarse",
        "--store",
        path_str(&window),
        "--json",
    ]);
    let designs = json(&["export", path_str(&window), "--json"]);
    let reason = designs[0]["reason"].as_str().unwrap_or_default();
    assert!(designs[0]["status"] == "infeasible" && reason.contains("coil"), "{designs}");
}

fn write(dir: &Path, name: &str, text: &str) -> String {
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path_str(&path).to_string()
}

/// The rig configurations of the hostile run: each aborted (allocation) or panicked (exit 101).
#[test]
fn hostile_rig_configurations_are_input_errors() {
    let dir = tempfile::tempdir().unwrap();
    for (name, text, field) in [
        ("reps.toml", "[characterization]\nrepetitions = 1000000\n", "characterization"),
        ("pause.toml", "[characterization]\npause_s = 1e308\n", "characterization"),
        ("imax.toml", "[brake]\ncurrent_max_A = 2147483647\n", "characterization"),
        ("fs.toml", "[sensor]\nfull_scale_V = 1e308\n", "sensor.full_scale_V"),
        (
            "den.toml",
            "[brake]\ndynamics_denominator = [5e-324, 0.01702, 1.0]\n",
            "brake.dynamics_denominator",
        ),
        ("motor.toml", "[motor]\ndenominator = [2e-5, 0.000368, 1e307]\n", "motor.denominator"),
    ] {
        let config = write(dir.path(), name, text);
        let out = dir.path().join("out");
        expect_input_error(
            &["rig", "characterize", "--config", &config, "--out", path_str(&out)],
            &[name, field],
        );
    }
}
