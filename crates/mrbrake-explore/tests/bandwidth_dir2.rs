//! `bandwidth_dir2_rad_s`: the −3 dB bandwidth of direction 2 of a bidirectional brake, from the
//! small-signal response of direction 2's own coils and gaps
//! (`ResponseModel::frequency_response_of`), at the study's bias; not applicable to a brake with
//! one direction. On the thesis brake, whose units are mirror images, it equals direction 1's
//! within the discretisation (the mesh is not mirrored).

#[path = "it/common/mod.rs"]
mod common;

use std::sync::Arc;

use common::problem;
use mrbrake_design::mesh_build::mesh_spec;
use mrbrake_design::response::{ResponseModel, ResponseOptions};
use mrbrake_design::spec::{BrakeSpec, default_spec};
use mrbrake_explore::evaluate::{METRICS, evaluate};
use mrbrake_explore::metrics::{Analysis, analysis_counts};
use mrbrake_store::{MetricValue, Status};

fn value(metrics: &[(String, MetricValue)], name: &str) -> Option<MetricValue> {
    metrics.iter().find(|(n, _)| n == name).map(|(_, v)| *v)
}

#[test]
fn the_metric_is_listed_with_its_unit() {
    let info = METRICS.iter().find(|m| m.name == "bandwidth_dir2_rad_s").expect("listed");
    assert_eq!(info.unit, "rad/s");
}

#[test]
#[cfg_attr(not(heavy_tests), ignore = "release only: two frequency sweeps of the whole brake")]
fn direction_2_has_its_own_bandwidth_equal_to_direction_1_on_the_mirror_symmetric_brake() {
    let p = problem(r#""bandwidth_rad_s", "bandwidth_dir2_rad_s""#, "[response]\nbias = \"1A\"\n");
    let spec = default_spec();
    let outcome = evaluate(&spec, &p.settings);
    assert_eq!(outcome.status, Status::Ok, "{:?}", outcome.reason);
    let b1 = value(&outcome.metrics, "bandwidth_rad_s").and_then(|v| v.value()).unwrap();
    let b2 = value(&outcome.metrics, "bandwidth_dir2_rad_s").and_then(|v| v.value()).unwrap();
    println!(
        "thesis brake, coarse mesh, bias 1 A: bandwidth {b1:.3} rad/s (dir. 1), {b2:.3} rad/s (dir. 2)"
    );
    assert!((b2 - b1).abs() <= 0.02 * b1, "mirror images: {b1} vs {b2}");
    let runs = |of: Analysis| analysis_counts().into_iter().find(|(a, _)| *a == of).unwrap().1;
    assert_eq!((runs(Analysis::Frequency), runs(Analysis::Frequency2)), (1, 1));

    // The library's direction-2 response at the same settings gives the same figure.
    let options =
        ResponseOptions { mesh: p.settings.mesh, bias_a: Some(1.0), ..Default::default() };
    let geometry = spec.validate().unwrap().geometry;
    let mesh = Arc::new(mesh_spec(&spec, &geometry, options.mesh).unwrap());
    let model = ResponseModel::on_mesh(&spec, &options, geometry, mesh).unwrap();
    let (_, _, direct) = model.frequency_response_of(1, 1.0).unwrap();
    assert!((direct.unwrap() - b2).abs() <= 1e-9 * b2, "{direct:?} vs {b2}");
}

#[test]
#[cfg_attr(not(heavy_tests), ignore = "release only: a static analysis of a drum brake")]
fn a_brake_with_one_direction_has_no_direction_2_bandwidth() {
    let path =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/specs/drum.toml");
    let spec = BrakeSpec::from_path(&path).unwrap();
    let p = problem(r#""bandwidth_dir2_rad_s""#, "");
    let outcome = evaluate(&spec, &p.settings);
    assert_eq!(outcome.status, Status::Ok, "{:?}", outcome.reason);
    assert_eq!(value(&outcome.metrics, "bandwidth_dir2_rad_s"), Some(MetricValue::NotApplicable));
}
