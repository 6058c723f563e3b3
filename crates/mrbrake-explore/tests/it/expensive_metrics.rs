//! The dynamics and heat metrics of a study equal the values of `mrbrake response` and `mrbrake
//! thermal` (the JSON the commands print: the serialised results of the same library calls) for
//! the same design and settings; bad input stops a study before any analysis.

use crate::common;

use std::path::Path;

use common::problem;
use mrbrake_design::response::{ResponseOptions, response};
use mrbrake_design::spec::default_spec;
use mrbrake_design::thermal::{ThermalOptions, analyze_thermal};
use mrbrake_explore::evaluate::evaluate;
use mrbrake_explore::problem::OptimizationProblem;
use mrbrake_store::{MetricValue, Status};
use serde_json::Value;

/// The metric's value; a bound beyond the analysed range (where the command's JSON has `null`)
/// reads as `inf`, as `json_number` reads that `null`.
fn metric(metrics: &[(String, MetricValue)], name: &str) -> f64 {
    metrics
        .iter()
        .find(|(n, _)| n == name)
        .map_or(f64::NAN, |(_, v)| v.value().unwrap_or(f64::INFINITY))
}

/// The command's JSON number, `null` read as the metric's `inf`.
fn json_number(value: &Value) -> f64 {
    value.as_f64().unwrap_or(f64::INFINITY)
}

fn assert_close(name: &str, study: f64, command: f64, rtol: f64) {
    let agree = if command.is_finite() {
        (study - command).abs() <= rtol * command.abs().max(1e-12)
    } else {
        study.is_infinite()
    };
    assert!(agree, "{name}: study {study} vs command {command}");
}

#[test]
#[cfg_attr(not(heavy_tests), ignore = "release only: two step responses per direction")]
fn dynamics_metrics_equal_the_response_command() {
    let record = r#""bandwidth_rad_s", "t63_s", "t90_s", "t63_dir2_s", "t90_dir2_s",
        "t63_fall_s", "t90_fall_s", "t63_fall_dir2_s", "t90_fall_dir2_s""#;
    let p = problem(record, "[response]\nduration = \"50ms\"\nbias = \"1.5A\"\n");
    let spec = default_spec();
    let outcome = evaluate(&spec, &p.settings);
    assert_eq!(outcome.status, Status::Ok, "{:?}", outcome.reason);
    // `mrbrake response --mesh coarse --duration 50ms --bias 1.5A --json`, then `--step 2A..0A`.
    let options = ResponseOptions {
        mesh: p.settings.mesh,
        duration_s: 0.05,
        bias_a: Some(1.5),
        ..ResponseOptions::default()
    };
    let up = serde_json::to_value(response(&spec, &options).unwrap()).unwrap();
    let max = spec.coil.max_current.a();
    let release = ResponseOptions { step_from_a: max, step_to_a: Some(0.0), ..options };
    let down = serde_json::to_value(response(&spec, &release).unwrap()).unwrap();
    let m = &outcome.metrics;
    assert_close(
        "bandwidth_rad_s",
        metric(m, "bandwidth_rad_s"),
        json_number(&up["bandwidth_rad_s"]),
        1e-9,
    );
    for (d, suffix) in [(0, ""), (1, "_dir2")] {
        for t in ["t63", "t90"] {
            let rise = metric(m, &format!("{t}{suffix}_s"));
            assert_close(t, rise, json_number(&up["step"][d][format!("{t}_s")]), 1e-9);
            let fall = metric(m, &format!("{t}_fall{suffix}_s"));
            assert_close(t, fall, json_number(&down["step"][d][format!("{t}_s")]), 1e-9);
        }
    }
    // The release is slower than nothing and the torque falls (the fall time is a real time).
    assert!(metric(m, "t63_fall_s") > 0.0 && metric(m, "t63_fall_s") < 0.05);
}

#[test]
#[cfg_attr(not(heavy_tests), ignore = "release only: a warm-up and a continuous-current search")]
fn heat_metrics_equal_the_thermal_command() {
    let record = r#""coil_max_T_C", "continuous_current_A", "max_duty_at_max_current",
        "time_to_limit_s", "continuous_torque_Nm""#;
    let p = problem(record, "[thermal]\ntime = \"30min\"\ndt = \"20s\"\ncurrent = \"2.5A\"\n");
    let spec = default_spec();
    let outcome = evaluate(&spec, &p.settings);
    assert_eq!(outcome.status, Status::Ok, "{:?}", outcome.reason);
    // `mrbrake thermal --mesh coarse --time 30min --dt 20s --current 2.5A --json`.
    let options = ThermalOptions {
        current_a: 2.5,
        time_s: 1800.0,
        dt_s: 20.0,
        mesh: p.settings.mesh,
        behaviour: true,
        ..ThermalOptions::default()
    };
    let run = serde_json::to_value(analyze_thermal(&spec, &options).unwrap()).unwrap();
    let m = &outcome.metrics;
    assert_close(
        "coil_max_T_C",
        metric(m, "coil_max_T_C"),
        json_number(&run["steady"]["coil_max_T_C"]),
        1e-9,
    );
    let current = json_number(&run["continuous_current_A"]);
    assert_close("continuous_current_A", metric(m, "continuous_current_A"), current, 1e-9);
    let duty = json_number(&run["max_duty_at_max_current"]);
    assert_close("max_duty_at_max_current", metric(m, "max_duty_at_max_current"), duty, 1e-9);
    let limit = json_number(&run["time_to_limit_s"]);
    assert_close("time_to_limit_s", metric(m, "time_to_limit_s"), limit, 1e-9);
    // `mrbrake thermal … --current <continuous_current_A> --duty 1 --json`: its hot torque with
    // a current drive (Newton's tolerance apart: the steady solve starts elsewhere).
    let held = ThermalOptions { current_a: current, duty: 1.0, ..options };
    let hot = serde_json::to_value(analyze_thermal(&spec, &held).unwrap()).unwrap();
    let torque = json_number(&hot["behaviour"]["torque_hot_current_drive_Nm"]);
    assert_close("continuous_torque_Nm", metric(m, "continuous_torque_Nm"), torque, 1e-6);
    assert!(torque > 0.0 && torque < metric(m, "torque_max_Nm") * 2.0, "{torque}");
}

/// A changed setting of an asked-for metric changes the design key; a static-only study's key
/// is that of before (no `study` part), whatever its `[thermal]` says; the metrics asked for are
/// not part of it (a study asking for a heat metric at the default settings has the static
/// study's keys, so `--resume` completes the stored designs).
#[test]
fn settings_of_asked_metrics_are_part_of_the_key() {
    use mrbrake_explore::design::design_key;
    let spec = default_spec();
    let key =
        |record: &str, extra: &str| design_key(&spec, &problem(record, extra).settings).unwrap();
    let plain = key("", "");
    assert_eq!(plain, key("", "[thermal]\nambient = \"40C\"\n"), "static-only: settings unused");
    assert_eq!(
        plain,
        design_key(
            &spec,
            &mrbrake_explore::EvaluationSettings {
                mesh: mrbrake_design::mesh_build::MeshLevel::Coarse,
                ..Default::default()
            }
        )
        .unwrap()
    );
    let heat = key("\"coil_max_T_C\"", "");
    assert_eq!(heat, plain, "default settings: the static study's key");
    assert_ne!(heat, key("\"coil_max_T_C\"", "[thermal]\nambient = \"40C\"\n"));
    // A dynamics setting does not touch a heat-only study's key.
    assert_eq!(heat, key("\"coil_max_T_C\"", "[response]\nduration = \"20ms\"\n"));
    assert_ne!(key("\"t63_s\"", ""), key("\"t63_s\"", "[response]\nduration = \"20ms\"\n"));
}

#[test]
fn bad_metrics_and_settings_name_the_file_and_key() {
    let text = |record: &str, extra: &str| {
        format!(
            "spec = \"s.toml\"\nrecord = [{record}]\n{extra}\n[[variable]]\nname = \"g\"\nmin = \
             \"0.4mm\"\nmax = \"0.6mm\"\n[[objective]]\nmetric = \"volume_m3\"\n[algorithm]\nkind \
             = \"nsga2\"\n"
        )
    };
    let read = |record: &str, extra: &str| {
        OptimizationProblem::from_toml_str(&text(record, extra), Path::new("p.toml"))
            .unwrap_err()
            .to_string()
    };
    let e = read("\"t64_s\"", "");
    assert!(e.contains("p.toml") && e.contains("record[0]") && e.contains("t64_s"), "{e}");
    let e = read("", "[thermal]\nh = \"windy\"\n");
    assert!(e.contains("p.toml") && e.contains("thermal.h"), "{e}");
    let e = read("", "[response]\nstep = \"2A..1A\"\n");
    assert!(e.contains("response.step"), "{e}");
    let e = read("", "[response]\ncolour = 1\n");
    assert!(e.contains("colour"), "{e}");
}

/// A dynamics metric on a flux path without a conductivity in the library stops the study
/// before any design, naming the file, the metric and the missing value; a given conductivity
/// lifts it.
#[test]
fn a_dynamics_metric_needs_the_flux_path_conductivity() {
    let dir = tempfile::tempdir().unwrap();
    let spec_text = mrbrake_design::spec::DEFAULT_SPEC_TOML
        .replace("flux_path = \"steel-1008\"", "flux_path = \"steel-1010-motorproto\"");
    assert_ne!(spec_text, mrbrake_design::spec::DEFAULT_SPEC_TOML);
    std::fs::write(dir.path().join("s.toml"), spec_text).unwrap();
    let problem_text = |extra: &str| {
        format!(
            "spec = \"s.toml\"\nrecord = [\"t63_fall_s\"]\n{extra}\n[[variable]]\nname = \
             \"g\"\nmin = \"0.4mm\"\nmax = \"0.6mm\"\n[[objective]]\nmetric = \
             \"volume_m3\"\n[algorithm]\nkind = \"nsga2\"\n"
        )
    };
    let path = dir.path().join("p.toml");
    std::fs::write(&path, problem_text("")).unwrap();
    let p = OptimizationProblem::from_path(&path).unwrap();
    let e = mrbrake_explore::optimize::check(&p).unwrap_err();
    let text = e.to_string();
    assert!(mrbrake_error::Kind::is_input_error(&e), "{text}");
    assert!(text.contains("p.toml") && text.contains("t63_fall_s"), "{text}");
    assert!(text.contains("conductivity") && text.contains("steel-1010-motorproto"), "{text}");
    std::fs::write(&path, problem_text("[response]\nconductivity = \"5MS/m\"\n")).unwrap();
    mrbrake_explore::optimize::check(&OptimizationProblem::from_path(&path).unwrap()).unwrap();
}
