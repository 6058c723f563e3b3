//! The quick variant of `examples/optimize/haptic-compact.toml` (the example's variables,
//! constraints and objectives on the coarse mesh, a 3-point haptic static curve, 20 ms step
//! responses and a population of 4 without generations): the example parses, its metrics are
//! computed through the whole cascade, and every stored design says what it is.

use std::path::PathBuf;
use std::time::Instant;

use mrbrake_explore::optimize;
use mrbrake_explore::problem::OptimizationProblem;
use mrbrake_observe::Silent;
use mrbrake_store::{Status, Store};

fn example() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../examples/optimize/haptic-compact.toml")
}

/// The example's text with the quick variant's overrides.
fn quick_text() -> String {
    let text = std::fs::read_to_string(example()).unwrap();
    let replaced = text
        .replace("mesh = \"default\"", "mesh = \"coarse\"\nreference = false")
        .replace("dynamics = \"predicted\"", "dynamics = \"predicted\"\npoints = 3")
        .replace("population = 24", "population = 4")
        .replace("generations = 12", "generations = 0");
    assert_ne!(replaced, text);
    replaced + "\n[response]\nduration = \"20ms\"\n"
}

#[test]
fn the_full_example_parses_and_asks_for_every_level() {
    let problem = OptimizationProblem::from_path(&example()).unwrap();
    let asked = problem.settings.study.requested();
    for metric in ["continuous_torque_Nm", "bandwidth_rad_s", "release_time_s"] {
        assert!(asked.contains(&metric), "{asked:?}");
    }
    assert_eq!(problem.variables.len(), 5);
    assert_eq!(problem.objectives.len(), 2);
}

#[test]
#[cfg_attr(not(heavy_tests), ignore = "release only: four designs through the whole cascade")]
fn the_quick_example_runs_through_the_cascade() {
    let problem = OptimizationProblem::from_toml_str(&quick_text(), &example()).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let mut store = Store::open_or_create(&dir.path().join("h.sqlite"), false).unwrap();
    let start = Instant::now();
    let result = optimize::run(&problem, &mut store, 1, &mut Silent).unwrap();
    eprintln!("{} designs in {:.1} s", result.evaluated.len(), start.elapsed().as_secs_f64());
    assert_eq!(result.evaluated.len(), 4);
    for e in &result.evaluated {
        let r = &e.record;
        match r.status {
            Status::Ok => {
                for m in ["continuous_torque_Nm", "bandwidth_rad_s", "release_time_s"] {
                    assert!(r.metric_value(m).is_some(), "{m} missing: {:?}", r.metrics);
                }
                let felt = r.metric("free_motion_torque_Nm").unwrap();
                assert!(felt > 0.0 && felt.is_finite(), "{felt}");
            }
            _ => assert!(r.reason.is_some(), "{r:?}"),
        }
    }
    for &i in &result.front {
        assert!(result.evaluated[i].evaluation.feasible());
    }
}
