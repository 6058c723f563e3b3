//! The cascade skips what it should: a design violating a static constraint runs no dynamics or
//! heat analysis and is stored infeasible with the analyses it skipped; a design passing it runs
//! exactly the analyses its metrics need, each once. One test in this file: the analysis counts
//! are per process.

use std::path::Path;

use mrbrake_design::spec::default_spec;
use mrbrake_explore::evaluate::evaluate;
use mrbrake_explore::metrics::{Analysis, analysis_counts};
use mrbrake_explore::problem::OptimizationProblem;
use mrbrake_store::Status;

fn problem(torque_min: &str) -> OptimizationProblem {
    problem_with(torque_min, "")
}

/// The problem with `extra` constraints.
fn problem_with(torque_min: &str, extra: &str) -> OptimizationProblem {
    let text = format!(
        r#"
spec = "thesis.toml"
mesh = "coarse"
record = ["t63_s"]
[response]
duration = "20ms"
[[variable]]
name = "g"
min = "0.4mm"
max = "0.6mm"
[[constraint]]
metric = "torque_max_Nm"
min = "{torque_min}"
{extra}
[[objective]]
metric = "bandwidth_rad_s"
goal = "maximize"
[algorithm]
kind = "nsga2"
population = 4
generations = 0
"#
    );
    OptimizationProblem::from_toml_str(&text, Path::new("cascade.toml")).unwrap()
}

fn count(of: Analysis) -> usize {
    analysis_counts().into_iter().find(|(a, _)| *a == of).map_or(0, |(_, n)| n)
}

#[test]
fn the_cascade_skips_what_a_static_constraint_rules_out() {
    let spec = default_spec();
    let total = || analysis_counts().iter().map(|(_, n)| n).sum::<usize>();
    assert_eq!(total(), 0);
    // 100 N·m is far beyond the thesis brake: infeasible after the static analysis.
    let out = evaluate(&spec, &problem("100Nm").settings);
    assert_eq!(out.status, Status::Infeasible);
    let reason = out.reason.unwrap();
    assert!(reason.contains("torque_max_Nm") && reason.contains("skipped"), "{reason}");
    assert!(
        reason.contains("small-signal response") && reason.contains("step response"),
        "{reason}"
    );
    assert!(out.metrics.iter().any(|(n, _)| n == "torque_max_Nm"), "static metrics kept");
    assert_eq!(total(), 0, "no expensive analysis ran: {:?}", analysis_counts());
    // 0.1 N·m passes: the small-signal response (level 1) and direction 1's step up (level 2)
    // run once each, nothing else (no release, no direction 2, no heat).
    let out = evaluate(&spec, &problem("0.1Nm").settings);
    assert_eq!(out.status, Status::Ok, "{:?}", out.reason);
    assert_eq!((count(Analysis::Frequency), count(Analysis::StepUp1)), (1, 1));
    assert_eq!(total(), 2, "{:?}", analysis_counts());
    let names: Vec<&str> = out.metrics.iter().map(|(n, _)| n.as_str()).collect();
    assert!(names.contains(&"bandwidth_rad_s") && names.contains(&"t63_s"), "{names:?}");
    assert!(!names.contains(&"t63_fall_s") && !names.contains(&"coil_max_T_C"), "{names:?}");
    // A level-1 metric violating its constraint (a bandwidth below 1 mrad/s) stops the cascade
    // before level 2: the small-signal response runs again (another key), the step does not.
    let gated = problem_with("0.1Nm", "[[constraint]]\nmetric = \"bandwidth_rad_s\"\nmax = 1e-3\n");
    let out = evaluate(&spec, &gated.settings);
    assert_eq!(out.status, Status::Infeasible);
    let reason = out.reason.unwrap();
    assert!(
        reason.contains("bandwidth_rad_s") && reason.contains("skipped: step response"),
        "{reason}"
    );
    assert_eq!((count(Analysis::Frequency), count(Analysis::StepUp1)), (2, 1));
}
