//! CLI behaviour of `mrbrake materials`: list, show (text and JSON), and bad input (exit code 2).

use crate::common;

use common::{json, mrbrake};

#[test]
fn list_shows_every_required_material() {
    let out = mrbrake(&["materials", "list"]);
    assert!(out.status.success());
    let text = String::from_utf8_lossy(&out.stdout);
    for name in [
        "steel-1008",
        "steel-1020",
        "air",
        "aluminium",
        "stainless-304",
        "copper",
        "mrf-122eg",
        "mrf-140cg",
    ] {
        assert!(text.contains(name), "{name} missing from:\n{text}");
    }
    let v = json(&["materials", "list", "--json"]);
    let materials = v["materials"].as_array().unwrap();
    assert!(materials.len() >= 15);
    assert!(materials.iter().any(|m| m["name"] == "mrf-122eg" && m["kind"] == "mr-fluid"));
    assert_eq!(v["default_fluid"], "mrf-122eg");
}

#[test]
fn show_mrf122eg_json_has_the_thesis_points_and_provenance() {
    let v = json(&["materials", "show", "MRF-122EG", "--json", "--b", "0.46T,490mT"]);
    assert_eq!(v["name"], "mrf-122eg");
    assert_eq!(v["kind"], "mr-fluid");
    let at_b = v["fluid"]["tau_y_at_B"].as_array().unwrap();
    assert!((at_b[0]["tau_y_Pa"].as_f64().unwrap() - 24_315.0).abs() < 1e-6);
    assert!((at_b[1]["tau_y_Pa"].as_f64().unwrap() - 25_670.0).abs() < 1e-6);
    assert!((v["fluid"]["tau_y_ceiling_Pa"].as_f64().unwrap() - 35_000.0).abs() < 1e-9);
    let checks = v["fluid"]["reference_checks"].as_array().unwrap();
    assert_eq!(checks.len(), 14);
    assert!(checks.iter().all(|c| c["error_percent"].as_f64().unwrap().abs() <= 3.0));
    assert!(
        v["fluid"]["yield_stress"]["provenance"]["source"].as_str().unwrap().contains("thesis")
    );
    assert!(v["magnetic"]["bh_curve"]["points_H_A_per_m_B_T"].as_array().unwrap().len() > 10);
    assert!(v["provenance"]["trust"].is_string());
}

#[test]
fn show_steel_text_reports_derived_values() {
    let out = mrbrake(&["materials", "show", "steel-1008", "--no-points"]);
    assert!(out.status.success());
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("B(     1000 A/m)"), "{text}");
    assert!(text.contains("trust   medium-high"), "{text}");
    let v = json(&["materials", "show", "steel-1008", "--json", "--h", "5kA/m"]);
    let b = v["magnetic"]["bh_curve"]["B_at_H"][0]["B_T"].as_f64().unwrap();
    assert!((b - 1.69).abs() < 0.01, "{b}");
}

#[test]
fn unknown_name_is_an_input_error_listing_the_known_ones() {
    let out = mrbrake(&["materials", "show", "unobtainium"]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("unknown material `unobtainium`") && err.contains("mrf-122eg"), "{err}");
}

#[test]
fn wrong_unit_or_negative_value_is_an_input_error() {
    let out = mrbrake(&["materials", "show", "mrf-122eg", "--b", "0.4kPa"]);
    assert_eq!(out.status.code(), Some(2));
    let out = mrbrake(&["materials", "show", "mrf-122eg", "--b", "-0.1T"]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(err.contains("--b[0]: got -0.1 T; allowed: finite, >= 0 T"), "{err}");
}

#[test]
fn a_closed_pipe_ends_the_text_output_quietly() {
    use std::process::{Command, Stdio};
    let mut child = Command::new(env!("CARGO_BIN_EXE_mrbrake"))
        .args(["materials", "show", "steel-1008"])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // Close the reading end before the program writes: its first write meets a closed pipe.
    drop(child.stdout.take());
    let out = child.wait_with_output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!err.contains("panicked"), "{err}");
    assert_eq!(out.status.code(), Some(0), "{err}");
}
