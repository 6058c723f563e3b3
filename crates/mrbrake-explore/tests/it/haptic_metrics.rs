//! The haptic metrics of a study equal `mrbrake haptic wall --brake-model m.json --json` where
//! `m.json` is what `mrbrake analyze --save-model` (and, for predicted dynamics, `mrbrake response
//! --save-model`) write for the same design and settings: the same library calls as the commands,
//! the model through its JSON text as through the file. A `[haptic]` table without a haptic
//! metric leaves the design keys of a static study as they were.

use crate::common;

use std::path::Path;

use common::{problem, problem_text};
use mrbrake_design::analysis::{AnalysisOptions, AnalysisRequest};
use mrbrake_design::response::{ResponseOptions, response};
use mrbrake_design::spec::default_spec;
use mrbrake_device::brake_model::{add_dynamics, from_analysis};
use mrbrake_explore::design::analysis_identity;
use mrbrake_explore::evaluate::evaluate;
use mrbrake_explore::problem::OptimizationProblem;
use mrbrake_sim::brake_model::BrakeModel;
use mrbrake_sim::brake_model::apply::apply_to_haptic;
use mrbrake_sim::haptic::{DeviceKind, HapticConfig, Scenario, simulate};
use mrbrake_store::{MetricValue, Status};
use serde_json::Value;

const HAPTIC: &str = r#""withdraw_excess_torque_Nm", "release_time_s",
    "displayed_stiffness_Nm_per_rad", "free_motion_torque_Nm""#;

/// The metric's value; a bound beyond the analysed range (where the command's JSON has `null`)
/// reads as `inf`, as the wall's `null`.
fn metric(metrics: &[(String, MetricValue)], name: &str) -> f64 {
    metrics
        .iter()
        .find(|(n, _)| n == name)
        .map_or(f64::NAN, |(_, v)| v.value().unwrap_or(f64::INFINITY))
}

/// `haptic wall --device D --scenario S --stiffness K --brake-model <model> --json`.
fn wall_json(model: &BrakeModel, device: DeviceKind, scenario: Scenario, k: f64) -> Value {
    let model = BrakeModel::from_json("m.json", &model.to_json()).unwrap();
    let mut config = HapticConfig::new(device, scenario);
    config.wall_stiffness_nm_per_rad = k;
    apply_to_haptic(&model, &mut config).unwrap();
    serde_json::to_value(simulate(&config, false).unwrap().metrics).unwrap()
}

fn assert_equal_to_wall(metrics: &[(String, MetricValue)], wall: &Value) {
    let pairs = [
        ("withdraw_excess_torque_Nm", &wall["withdraw_excess_torque_Nm"]["peak"]),
        ("release_time_s", &wall["release_time_s"]),
        ("displayed_stiffness_Nm_per_rad", &wall["displayed_stiffness_Nm_per_rad"]),
        ("free_motion_torque_Nm", &wall["free_motion_torque_Nm"]),
    ];
    for (name, command) in pairs {
        let command = command.as_f64().unwrap_or(f64::INFINITY);
        let study = metric(metrics, name);
        let agree = if command.is_finite() {
            (study - command).abs() <= 1e-9 * command.abs().max(1e-12)
        } else {
            study.is_infinite()
        };
        assert!(agree, "{name}: study {study} vs haptic wall {command}");
    }
}

/// The static curve and rotor inertia of `analyze --mesh coarse --points 5 --save-model`.
fn analysed_model(seal_friction_nm: f64) -> BrakeModel {
    let spec = default_spec();
    let options = AnalysisOptions {
        mesh: mrbrake_design::mesh_build::MeshLevel::Coarse,
        points: 5,
        seal_friction_nm,
        ..AnalysisOptions::default()
    };
    let analysis = AnalysisRequest::of(&spec).options(options).run().unwrap();
    let identity = analysis_identity(&spec, &options).unwrap();
    from_analysis(&analysis, &options, Some(identity), "test").unwrap()
}

#[test]
#[cfg_attr(not(heavy_tests), ignore = "release only: a 5-point sweep and a haptic run")]
fn haptic_metrics_equal_the_wall_command_with_the_thesis_lags() {
    let extra = "[haptic]\npoints = 5\ndynamics = \"thesis\"\n\
                 device = \"conventional\"\nstiffness = \"40N·m/rad\"\n";
    let mut p = problem(HAPTIC, extra);
    // `sweep --seal-friction 0.05Nm` / `analyze --seal-friction 0.05Nm`.
    p.settings.seal_friction_nm = 0.05;
    let outcome = evaluate(&default_spec(), &p.settings);
    assert_eq!(outcome.status, Status::Ok, "{:?}", outcome.reason);
    let model = analysed_model(0.05);
    assert!(model.units.iter().all(|u| u.rotor_inertia_kg_m2.is_some_and(|j| j > 0.0)));
    let wall = wall_json(&model, DeviceKind::Conventional, Scenario::PressWithdraw, 40.0);
    assert_equal_to_wall(&outcome.metrics, &wall);
    // The seal friction is felt in free motion: at least it, plus the bearing's 5 mN·m.
    assert!(metric(&outcome.metrics, "free_motion_torque_Nm") >= 0.05 + 0.005 - 1e-12);
    // Without predicted dynamics the study ran no small-signal response.
    assert!(!outcome.metrics.iter().any(|(n, _)| n == "bandwidth_rad_s"));
}

#[test]
#[cfg_attr(not(heavy_tests), ignore = "release only: a sweep, the response and a haptic run")]
fn haptic_metrics_equal_the_wall_command_with_the_predicted_lag() {
    let extra = "[response]\nduration = \"20ms\"\n[haptic]\npoints = 5\n";
    let p = problem(HAPTIC, extra);
    let spec = default_spec();
    let outcome = evaluate(&spec, &p.settings);
    assert_eq!(outcome.status, Status::Ok, "{:?}", outcome.reason);
    let mut model = analysed_model(0.0);
    // `mrbrake response --mesh coarse --duration 20ms --save-model m.json`.
    let options =
        ResponseOptions { mesh: p.settings.mesh, duration_s: 0.02, ..ResponseOptions::default() };
    add_dynamics(&mut model, &response(&spec, &options).unwrap(), "test").unwrap();
    let wall = wall_json(&model, DeviceKind::Bidirectional, Scenario::PressWithdraw, 30.0);
    assert_equal_to_wall(&outcome.metrics, &wall);
}

#[test]
fn a_haptic_table_alone_leaves_static_keys_and_asks_for_the_analyses_it_needs() {
    let plain = problem("", "");
    let with_table = problem("", "[haptic]\nscenario = \"slide-hold\"\n");
    assert_eq!(plain.settings.canonical(), with_table.settings.canonical());
    let asked = problem(r#""free_motion_torque_Nm""#, "[haptic]\nscenario = \"slide-hold\"\n");
    let key = asked.settings.canonical();
    assert_eq!(key["study"]["haptic"]["scenario"], "slide-hold", "{key}");
    let analyses = asked.settings.study.analyses();
    use mrbrake_explore::metrics::Analysis;
    assert!(analyses.contains(&Analysis::Haptic) && analyses.contains(&Analysis::Frequency));
    let thesis = problem(r#""free_motion_torque_Nm""#, "[haptic]\ndynamics = \"thesis\"\n");
    assert!(!thesis.settings.study.analyses().contains(&Analysis::Frequency));
    let text = problem_text("", "[haptic]\nscenario = \"juggle\"\n");
    let e = OptimizationProblem::from_toml_str(&text, Path::new("bad.toml")).unwrap_err();
    let e = e.to_string();
    assert!(e.contains("bad.toml") && e.contains("haptic.scenario"), "{e}");
}
