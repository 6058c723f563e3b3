//! The surrogate optimiser's driver on small problems: budgets and batches, failed evaluations,
//! model-fit fallbacks, resuming from given designs, the observer's stop, mixed integer and
//! categorical variables, bad settings, determinism.

use mrbrake_error::Kind as _;
use mrbrake_observe::{Flow, Silent};
use mrbrake_optim::pareto::Evaluation;
use mrbrake_optim::space::Bounds;
use mrbrake_optim::surrogate::{
    self, EvaluatedDesign, IterationReport, ModelRole, StopReason, SurrogateOptions,
};
use mrbrake_optim::{FnProblem, RunError};

/// Two objectives on [0, 1]²: x and (1 + y)(1 − √x).
fn two_objectives(x: &[f64]) -> Evaluation {
    Evaluation::new(vec![x[0], (1.0 + x[1]) * (1.0 - x[0].sqrt())], 0.0)
}

fn unit_square() -> Vec<Bounds> {
    vec![Bounds::continuous(0.0, 1.0); 2]
}

fn options(max_evaluations: usize) -> SurrogateOptions {
    SurrogateOptions { max_evaluations, reference: Some(vec![1.1, 2.2]), ..Default::default() }
}

/// Every number the run hands back is finite and every design legal.
fn assert_clean(bounds: &[Bounds], designs: &[EvaluatedDesign]) {
    for d in designs {
        for (v, b) in d.x.iter().zip(bounds) {
            assert!(b.contains(*v), "{:?} outside {bounds:?}", d.x);
        }
    }
}

#[test]
fn batches_fill_the_budget_exactly_without_repeating_a_design() {
    let bounds = unit_square();
    let mut problem = FnProblem::new(bounds.clone(), 2, two_objectives);
    let settings = SurrogateOptions { batch: 3, initial_size: Some(8), ..options(24) };
    let mut sizes = Vec::new();
    let mut observer = |r: &IterationReport| {
        sizes.push(r.batch.len());
        assert!(r.hypervolume.is_finite() && r.hypervolume >= 0.0);
        assert!(r.models.iter().all(|m| m.loo_error.is_finite()));
        assert!(r.acquisition.iter().all(|a| a.is_finite() && *a >= 0.0));
        Flow::Continue
    };
    let result = surrogate::run(&mut problem, &settings, &[], &mut observer).unwrap();
    // 8 initial designs, then batches of 3 up to 23, and a last batch cut to 1.
    assert_eq!(sizes, vec![8, 3, 3, 3, 3, 3, 1]);
    assert_eq!(result.designs.len(), 24);
    assert_eq!(problem.evaluations(), 24);
    assert_eq!(result.stop, StopReason::Budget);
    for (i, a) in result.designs.iter().enumerate() {
        for b in &result.designs[..i] {
            assert!(a.x.iter().zip(&b.x).any(|(p, q)| (p - q).abs() > 1e-9), "repeated {:?}", a.x);
        }
    }
    assert_clean(&bounds, &result.designs);
    // The hypervolume never decreases and is reported with its reference point.
    assert!(result.trace.windows(2).all(|w| w[1].hypervolume >= w[0].hypervolume));
    assert_eq!(result.reference, Some(vec![1.1, 2.2]));
}

#[test]
fn the_same_seed_gives_the_same_run_and_another_seed_another() {
    let run = |seed| {
        let mut problem = FnProblem::new(unit_square(), 2, two_objectives);
        let settings = SurrogateOptions { seed, initial_size: Some(6), batch: 2, ..options(14) };
        surrogate::run(&mut problem, &settings, &[], &mut Silent).unwrap().designs
    };
    assert_eq!(run(3), run(3));
    assert_ne!(run(3), run(4));
}

#[test]
fn failed_evaluations_train_the_feasibility_model_and_never_stop_the_run() {
    // Designs with x > 0.6 cannot be evaluated (an invalid geometry): the failure classifier learns
    // the region, and the later designs avoid its interior.
    let bounds = unit_square();
    let mut problem = FnProblem::new(bounds.clone(), 2, |x: &[f64]| {
        if x[0] > 0.6 { Evaluation::failed(2) } else { two_objectives(x) }
    });
    let settings = SurrogateOptions { initial_size: Some(10), ..options(40) };
    let mut classifier_seen = false;
    let mut observer = |r: &IterationReport| {
        classifier_seen |= r.models.iter().any(|m| m.role == ModelRole::Feasibility);
        assert!(r.fallback.is_none(), "{:?}", r.fallback);
        Flow::Continue
    };
    let result = surrogate::run(&mut problem, &settings, &[], &mut observer).unwrap();
    assert!(classifier_seen);
    assert_eq!(result.designs.len(), 40);
    assert_clean(&bounds, &result.designs);
    // Failures cluster at the edge of the region (the front ends there); deep inside it, where a
    // uniform sample would put 30 % of the designs, few are proposed.
    let deep = result.designs[10..].iter().filter(|d| d.x[0] > 0.7).count();
    assert!(deep <= 3, "{deep} of 30 proposed designs deep in the failing region");
    assert!(result.front.iter().all(|&i| result.designs[i].evaluation.feasible()));
}

#[test]
fn a_model_that_cannot_be_fitted_falls_back_to_space_filling_designs_and_says_so() {
    // The second objective is the same everywhere: nothing to model.
    let bounds = unit_square();
    let mut problem =
        FnProblem::new(bounds.clone(), 2, |x: &[f64]| Evaluation::new(vec![x[0], 1.0], 0.0));
    let settings = SurrogateOptions { initial_size: Some(5), batch: 2, ..options(11) };
    let mut fallbacks = Vec::new();
    let mut observer = |r: &IterationReport| {
        if let Some(f) = &r.fallback {
            fallbacks.push((f.role, f.to_string(), r.batch.len()));
        }
        Flow::Continue
    };
    let result = surrogate::run(&mut problem, &settings, &[], &mut observer).unwrap();
    assert_eq!(fallbacks.len(), 3);
    let (role, message, size) = &fallbacks[0];
    assert_eq!(*role, ModelRole::Objective(1));
    assert!(message.contains("objective 2") && message.contains("space-filling"), "{message}");
    assert_eq!(*size, 2);
    assert_eq!(result.designs.len(), 11);
    assert_clean(&bounds, &result.designs);
}

#[test]
fn a_run_resumed_after_the_initial_design_repeats_the_uninterrupted_run() {
    let settings = SurrogateOptions { initial_size: Some(6), batch: 2, ..options(16) };
    let mut whole_problem = FnProblem::new(unit_square(), 2, two_objectives);
    let whole = surrogate::run(&mut whole_problem, &settings, &[], &mut Silent).unwrap();
    // Interrupted after the initial design, then resumed from the stored designs: nothing is
    // evaluated twice and the continuation is the same.
    let stored = whole.designs[..6].to_vec();
    let mut resumed_problem = FnProblem::new(unit_square(), 2, two_objectives);
    let resumed = surrogate::run(&mut resumed_problem, &settings, &stored, &mut Silent).unwrap();
    assert_eq!(resumed_problem.evaluations(), 10);
    assert_eq!(resumed.designs, whole.designs);
    // Interrupted half-way through the initial design (4 of its 6 designs stored, in another
    // order): only the 2 missing ones are evaluated before the iterations.
    let partial = vec![stored[3].clone(), stored[0].clone(), stored[5].clone(), stored[1].clone()];
    let mut first_batch = Vec::new();
    let mut observer = |r: &IterationReport| {
        if r.iteration == 0 {
            first_batch = r.batch.iter().map(|d| d.x.clone()).collect();
        }
        Flow::Continue
    };
    let mut problem = FnProblem::new(unit_square(), 2, two_objectives);
    let again = surrogate::run(&mut problem, &settings, &partial, &mut observer).unwrap();
    assert_eq!(first_batch, vec![stored[2].x.clone(), stored[4].x.clone()]);
    assert_eq!(again.designs.len(), 16);
    assert_eq!(problem.evaluations(), 12);
}

#[test]
fn the_observer_stops_the_run_after_the_iteration_it_saw() {
    let mut problem = FnProblem::new(unit_square(), 2, two_objectives);
    let settings = SurrogateOptions { initial_size: Some(6), ..options(50) };
    let mut observer = |r: &IterationReport| Flow::stop_if(r.iteration == 2);
    let result = surrogate::run(&mut problem, &settings, &[], &mut observer).unwrap();
    assert_eq!(result.stop, StopReason::Observer);
    assert_eq!(result.iterations, 2);
    assert_eq!(result.designs.len(), 8);
}

#[test]
fn the_hypervolume_stall_rule_stops_a_run_whose_front_is_found() {
    // One objective, a single minimum at a corner of the box: found quickly, then nothing improves.
    let mut problem =
        FnProblem::new(unit_square(), 1, |x: &[f64]| Evaluation::new(vec![x[0] + x[1]], 0.0));
    let settings = SurrogateOptions {
        initial_size: Some(5),
        stall_iterations: 4,
        max_evaluations: 200,
        ..Default::default()
    };
    let result = surrogate::run(&mut problem, &settings, &[], &mut Silent).unwrap();
    assert_eq!(result.stop, StopReason::Stall);
    assert!(result.designs.len() < 200);
    let best = &result.designs[result.front[0]];
    assert!(best.evaluation.objectives[0] < 0.02, "{best:?}");
    // The reference was fixed from the first feasible designs.
    assert_eq!(result.reference.as_ref().map(Vec::len), Some(1));
}

#[test]
fn mixed_integer_and_categorical_designs_are_legal_and_reach_the_optimum() {
    // A drum count 1..6, a material among 3 (the second is best) and a continuous variable.
    let bounds =
        vec![Bounds::continuous(0.0, 1.0), Bounds::integer(1.0, 6.0), Bounds::categorical(3)];
    let mut problem = FnProblem::new(bounds.clone(), 1, |x: &[f64]| {
        let material = [0.6, 0.0, 0.3][x[2] as usize];
        Evaluation::new(vec![(x[0] - 0.3).powi(2) + 0.1 * (x[1] - 4.0).powi(2) + material], 0.0)
    });
    let settings = SurrogateOptions { initial_size: Some(12), ..Default::default() };
    let settings = SurrogateOptions { max_evaluations: 40, stall_iterations: 0, ..settings };
    let result = surrogate::run(&mut problem, &settings, &[], &mut Silent).unwrap();
    assert_clean(&bounds, &result.designs);
    let best = &result.designs[result.front[0]];
    assert_eq!((best.x[1], best.x[2]), (4.0, 1.0), "{best:?}");
    assert!((best.x[0] - 0.3).abs() < 0.05, "{best:?}");
    // No integer/categorical design evaluated twice.
    for (i, a) in result.designs.iter().enumerate() {
        assert!(result.designs[..i].iter().all(|b| b.x != a.x), "repeated {:?}", a.x);
    }
}

#[test]
fn a_small_discrete_space_is_exhausted_not_evaluated_twice() {
    // Two integer variables with 2 and 3 levels: 6 designs in all, a budget of 30.
    let bounds = vec![Bounds::integer(0.0, 1.0), Bounds::integer(1.0, 3.0)];
    let mut problem = FnProblem::new(bounds, 2, |x: &[f64]| {
        Evaluation::new(vec![x[0] + x[1], (2.0 - x[0]) * (4.0 - x[1])], 0.0)
    });
    let settings =
        SurrogateOptions { max_evaluations: 30, stall_iterations: 0, ..Default::default() };
    let result = surrogate::run(&mut problem, &settings, &[], &mut Silent).unwrap();
    assert_eq!(result.stop, StopReason::Exhausted);
    assert_eq!(problem.evaluations(), 6);
    assert_eq!(result.designs.len(), 6);
}

#[test]
fn constraint_values_train_one_model_each_and_three_objectives_work() {
    let bounds = vec![Bounds::continuous(0.0, 1.0); 3];
    let mut problem = FnProblem::new(bounds.clone(), 3, |x: &[f64]| {
        let g = [0.2 - x[0] - x[1], x[2] - 0.9];
        let violation = g.iter().map(|v| v.max(0.0)).sum();
        Evaluation::new(vec![x[0], x[1], 1.0 - x[0] * x[1] + x[2]], violation)
            .with_constraints(g.to_vec())
    });
    let settings = SurrogateOptions {
        initial_size: Some(8),
        batch: 2,
        max_evaluations: 16,
        ..Default::default()
    };
    let mut roles = Vec::new();
    let mut observer = |r: &IterationReport| {
        if roles.is_empty() {
            roles = r.models.iter().map(|m| m.role).collect();
        }
        Flow::Continue
    };
    let result = surrogate::run(&mut problem, &settings, &[], &mut observer).unwrap();
    let expected: Vec<ModelRole> =
        (0..3).map(ModelRole::Objective).chain((0..2).map(ModelRole::Constraint)).collect();
    assert_eq!(roles, expected);
    assert_eq!(result.designs.len(), 16);
    assert!(result.hypervolume > 0.0 && result.hypervolume.is_finite());
    assert_eq!(result.reference.map(|r| r.len()), Some(3));
}

#[test]
fn bad_settings_and_previous_designs_are_input_errors_before_any_evaluation() {
    let mut problem = FnProblem::new(unit_square(), 2, two_objectives);
    let bad = [
        SurrogateOptions { batch: 0, ..Default::default() },
        SurrogateOptions { initial_size: Some(2), ..Default::default() },
        SurrogateOptions { reference: Some(vec![1.0, f64::NAN]), ..Default::default() },
    ];
    for settings in &bad {
        let error = surrogate::run(&mut problem, settings, &[], &mut Silent).unwrap_err();
        assert!(error.is_input_error(), "{error}");
    }
    let outside = [EvaluatedDesign { x: vec![2.0, 0.5], evaluation: two_objectives(&[1.0, 0.5]) }];
    let error = surrogate::run(&mut problem, &options(10), &outside, &mut Silent).unwrap_err();
    assert!(
        matches!(&error, RunError::Optim(_)) && error.to_string().contains("previous design 0"),
        "{error}"
    );
    let nan = [EvaluatedDesign {
        x: vec![0.5, 0.5],
        evaluation: Evaluation::new(vec![f64::NAN, 1.0], 0.0),
    }];
    assert!(surrogate::run(&mut problem, &options(10), &nan, &mut Silent).is_err());
    assert_eq!(problem.evaluations(), 0);
}
