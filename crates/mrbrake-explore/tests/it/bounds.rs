//! How a metric beyond the analysed range (`MetricValue::AtLeast` / `AtMost`) or not applicable
//! counts in an optimisation: one case per rule of `evaluation_for` and `Constraint::violation_of`,
//! on stored records (no analysis).

use std::path::Path;

use mrbrake_explore::optimize::evaluation_for;
use mrbrake_explore::problem::OptimizationProblem;
use mrbrake_store::{MetricValue, Record, Status};

/// Maximise the bandwidth, minimise the release time, release time at most 0.5 s and t63 of
/// direction 2 at most 10 ms.
fn problem() -> OptimizationProblem {
    let text = r#"
spec = "thesis.toml"
mesh = "coarse"
[[variable]]
name = "g"
min = "0.4mm"
max = "0.6mm"
[[constraint]]
metric = "release_time_s"
max = "0.5s"
[[constraint]]
metric = "t63_dir2_s"
max = "10ms"
[[objective]]
metric = "bandwidth_rad_s"
goal = "maximize"
[[objective]]
metric = "t63_s"
goal = "minimize"
[algorithm]
kind = "nsga2"
population = 4
generations = 0
"#;
    OptimizationProblem::from_toml_str(text, Path::new("bounds.toml")).unwrap()
}

fn record(bandwidth: MetricValue, t63: MetricValue, release: MetricValue) -> Record {
    Record {
        key: "a".repeat(64),
        status: Status::Ok,
        reason: None,
        variables: vec![("g".into(), 5e-4.into())],
        metrics: vec![
            ("bandwidth_rad_s".into(), bandwidth),
            ("t63_s".into(), t63),
            ("release_time_s".into(), release),
            ("t63_dir2_s".into(), MetricValue::NotApplicable),
        ],
        spec_toml: String::new(),
        eval_seconds: 1.0,
        solver_version: "test".into(),
        settings: Default::default(),
    }
}

use MetricValue::{AtLeast, AtMost, NotApplicable, Value};

#[test]
fn an_at_least_bound_of_a_maximised_objective_is_ranked_by_its_bound() {
    let e = evaluation_for(&problem(), &record(AtLeast(6283.0), Value(2e-3), Value(0.1)));
    assert!(e.feasible(), "{e:?}");
    assert!((e.objectives[0] + 6283.0).abs() < 1e-9, "negated bound: {e:?}");
    // A bound on the bad side of its objective cannot be ranked: the design counts as failed.
    let e = evaluation_for(&problem(), &record(AtMost(100.0), Value(2e-3), Value(0.1)));
    assert!(e.violation.is_infinite(), "{e:?}");
}

#[test]
fn an_at_most_bound_of_a_minimised_objective_is_ranked_by_its_bound() {
    let e = evaluation_for(&problem(), &record(Value(500.0), AtMost(1e-3), Value(0.1)));
    assert!(e.feasible() && (e.objectives[1] - 1e-3).abs() < 1e-15, "{e:?}");
    let e = evaluation_for(&problem(), &record(Value(500.0), AtLeast(0.02), Value(0.1)));
    assert!(e.violation.is_infinite(), "a slow step beyond the run cannot be ranked: {e:?}");
}

#[test]
fn a_bound_that_satisfies_a_constraint_satisfies_it_and_one_beyond_violates_it_finitely() {
    // Released within at most 0.2 s: satisfies `max = 0.5 s`.
    let e = evaluation_for(&problem(), &record(Value(500.0), Value(2e-3), AtMost(0.2)));
    assert!(e.feasible(), "{e:?}");
    // Not released within the run, at least 2 s: violates it by at least (2 − 0.5)/0.5 = 3,
    // a finite violation Deb's rules rank (closer designs are better).
    let e = evaluation_for(&problem(), &record(Value(500.0), Value(2e-3), AtLeast(2.0)));
    assert!((e.violation - 3.0).abs() < 1e-12, "{e:?}");
    // At least 0.2 s cannot decide `max = 0.5 s`: counted as not computed.
    let e = evaluation_for(&problem(), &record(Value(500.0), Value(2e-3), AtLeast(0.2)));
    assert!(e.violation.is_infinite(), "{e:?}");
}

#[test]
fn a_metric_that_does_not_apply_satisfies_its_constraint_but_is_no_objective() {
    // `t63_dir2_s` is not applicable in every record above and never violated its constraint.
    let e = evaluation_for(&problem(), &record(Value(500.0), Value(2e-3), Value(0.1)));
    assert!(e.feasible(), "{e:?}");
    let e = evaluation_for(&problem(), &record(NotApplicable, Value(2e-3), Value(0.1)));
    assert!(e.violation.is_infinite(), "{e:?}");
}
