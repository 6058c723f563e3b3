//! Polishing a front design: a pattern search started at it (`mrbrake optimize --polish N`).
//!
//! Brief overview: a global optimiser (NSGA-II, the surrogate) leaves each front design where its
//! last generation or iteration put it, not at the local optimum nearby. [`run`] takes front design
//! `N` (numbered as in `designs/front-NN.toml`) and runs a compass pattern search
//! ([`mrbrake_optim::pattern_search`]) started at it, on a derived single-objective problem:
//!
//! * the objective to improve ([`PolishRequest::objective`], default the problem's first);
//! * the problem's constraints, plus every *other* objective bounded by the design's own value
//!   (a minimised one from above, a maximised one from below), so the polished design is never
//!   worse than the front design in any objective: it dominates it or equals it;
//! * a first step of [`INITIAL_STEP_FRACTION`] of each variable's range (the search is local), down
//!   to the default minimum step, within [`PolishRequest::max_evaluations`] designs.
//!
//! Every design of the polish goes through the same store and joins the run's evaluated designs,
//! so the front, its hypervolume and the written designs are those of all evaluated designs
//! ([`crate::optimize::run_with`]); re-running the command replays the polish from the store.

use mrbrake_observe::{Observer, Silent};
use mrbrake_optim::pattern_search::{self, PatternSearchOptions, PollDirections};

use crate::ExploreError;
use crate::optimize::{Evaluated, OptimizationResult, OptimizeProgress, StudyProblem, front_of};
use crate::problem::{Algorithm, Constraint, Goal, OptimizationProblem, Start};

/// The first step of a polish, as a fraction of each variable's range.
pub const INITIAL_STEP_FRACTION: f64 = 0.05;

/// The default budget of a polish (designs).
pub const DEFAULT_POLISH_EVALUATIONS: usize = 60;

/// Which front design to polish, for which objective, with how many designs.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct PolishRequest {
    /// The front design, from 1 (as in `front-NN.toml`).
    pub design: usize,
    /// The metric of the objective to improve; `None`: the first objective.
    pub objective: Option<String>,
    /// The most designs the pattern search evaluates, the start included.
    pub max_evaluations: usize,
}

impl PolishRequest {
    /// Checks the request's ranges before any design is evaluated (a front design numbered from
    /// 1, at least one evaluation); the errors name `polish` and `polish_evaluations`.
    pub fn check(&self) -> Result<(), ExploreError> {
        if self.design == 0 {
            let e = mrbrake_error::FieldError::new("polish", "front designs are numbered from 1")
                .with_value(0)
                .with_allowed(">= 1");
            return Err(e.into());
        }
        if self.max_evaluations == 0 || self.max_evaluations > crate::problem::MAX_EVALUATIONS {
            let allowed = format!("1 to {}", crate::problem::MAX_EVALUATIONS);
            let e = mrbrake_error::FieldError::out_of_range(
                "polish_evaluations",
                self.max_evaluations,
                allowed,
            );
            return Err(e.into());
        }
        Ok(())
    }
}

/// A polish's outcome.
#[derive(Debug, Clone)]
pub struct Polished {
    /// The front design polished (from 1).
    pub design: usize,
    /// The objective improved (its metric).
    pub objective: String,
    /// The front design the search started at.
    pub start: Evaluated,
    /// The best design the search found under the derived constraints (the start if none is
    /// better), with its evaluation under the original problem.
    pub best: Evaluated,
    /// Every design of the polish, in order, with its evaluation under the original problem.
    pub evaluated: Vec<Evaluated>,
    /// What the polish computed and read back.
    pub totals: Option<crate::RunSummary>,
    /// Pattern-search iterations.
    pub iterations: usize,
    /// Whether the step fell below its minimum (rather than the budget running out).
    pub converged: bool,
}

/// Polishes front design `request.design` of `result` (module docs), its designs through `store`.
pub fn run(
    problem: &OptimizationProblem,
    store: &mut mrbrake_store::Store,
    jobs: usize,
    result: &OptimizationResult,
    request: &PolishRequest,
    observer: &mut dyn Observer<OptimizeProgress>,
) -> Result<Polished, ExploreError> {
    request.check()?;
    if let Some(material) = problem.variables.iter().find(|v| !v.levels.is_empty()) {
        return Err(ExploreError::input(
            "polish",
            format!(
                "steps each variable along an order, and the materials of '{}' ({}) have none; \
                 polish with the material fixed (optimize --set {}=…)",
                material.name,
                material.levels.join(", "),
                material.name
            ),
        ));
    }
    let evaluations: Vec<_> = result.evaluated.iter().map(|e| e.evaluation.clone()).collect();
    let front = front_of(problem, &evaluations);
    let index =
        request.design.checked_sub(1).and_then(|k| front.get(k)).copied().ok_or_else(|| {
            let e = mrbrake_error::FieldError::new(
                "polish",
                format!("the front has {} design(s)", front.len()),
            )
            .with_value(request.design)
            .with_allowed(format!("1 to {}", front.len()));
            ExploreError::from(e)
        })?;
    let start = result.evaluated[index].clone();
    let (derived, objective) = derived_problem(problem, &start, request)?;
    let mut study = StudyProblem::new(&derived, store, jobs, observer)?.without_recording();
    let options = PatternSearchOptions {
        initial_step_fraction: INITIAL_STEP_FRACTION,
        max_evaluations: request.max_evaluations,
        start: study.start_point(&start_of(&derived))?,
        poll: PollDirections::Compass,
        ..PatternSearchOptions::default()
    };
    let outcome = pattern_search::run(&mut study, &options, &mut Silent)
        .map_err(crate::optimize::run_error)?;
    let (designs, totals) = study.into_parts();
    let evaluated: Vec<Evaluated> = designs
        .into_iter()
        .map(|e| {
            let evaluation = crate::optimize::evaluation_for(problem, &e.record);
            Evaluated { record: e.record, evaluation }
        })
        .collect();
    let same_x = |e: &&Evaluated| {
        e.record.variables.len() == outcome.best_x.len()
            && e.record
                .variables
                .iter()
                .zip(&outcome.best_x)
                .all(|(v, x)| v.1.as_number().is_some_and(|v| v.total_cmp(x).is_eq()))
    };
    let best = if outcome.best.feasible() {
        evaluated.iter().find(same_x).cloned().unwrap_or_else(|| start.clone())
    } else {
        start.clone()
    };
    Ok(Polished {
        design: request.design,
        objective,
        start,
        best,
        evaluated,
        totals,
        iterations: outcome.iterations,
        converged: outcome.converged,
    })
}

/// The single-objective problem of a polish and the objective's metric.
fn derived_problem(
    problem: &OptimizationProblem,
    start: &Evaluated,
    request: &PolishRequest,
) -> Result<(OptimizationProblem, String), ExploreError> {
    let k = match &request.objective {
        None => 0,
        Some(metric) => {
            problem.objectives.iter().position(|o| o.metric == metric.trim()).ok_or_else(|| {
                let names: Vec<&str> =
                    problem.objectives.iter().map(|o| o.metric.as_str()).collect();
                let e = mrbrake_error::FieldError::new(
                    "polish_objective",
                    "not an objective of the problem",
                )
                .with_value(metric)
                .with_allowed(names.join(", "));
                ExploreError::from(e)
            })?
        }
    };
    let mut derived = problem.clone();
    derived.objectives = vec![problem.objectives[k].clone()];
    for (_, o) in problem.objectives.iter().enumerate().filter(|(j, _)| *j != k) {
        let value = start.record.metric(&o.metric).ok_or_else(|| {
            ExploreError::Internal(format!("front design without metric {}", o.metric))
        })?;
        let (min, max) = match o.goal {
            Goal::Minimize => (None, Some(value)),
            Goal::Maximize => (Some(value), None),
        };
        derived.constraints.push(Constraint { metric: o.metric.clone(), min, max });
    }
    let x: Vec<Option<f64>> =
        problem.variables.iter().map(|v| start.record.variable(&v.name)).collect();
    derived.reference = false;
    derived.hypervolume_reference = None;
    derived.algorithm = Algorithm::PatternSearch {
        max_evaluations: request.max_evaluations,
        seed: 1,
        random_poll: false,
        start: Start::Values(x),
    };
    Ok((derived, problem.objectives[k].metric.clone()))
}

fn start_of(problem: &OptimizationProblem) -> Start {
    match &problem.algorithm {
        Algorithm::PatternSearch { start, .. } => start.clone(),
        _ => Start::Centre,
    }
}

/// Adds a polish's designs to the run's evaluated designs (each once) and its counts to the run's.
pub fn merge(result: &mut OptimizationResult, polished: Polished) {
    for e in &polished.evaluated {
        if !result.evaluated.iter().any(|r| r.record.key == e.record.key) {
            result.evaluated.push(e.clone());
        }
    }
    if let Some(t) = &polished.totals {
        result.totals.progress.add(&t.progress);
        result.totals.evaluation_s += t.evaluation_s;
        result.totals.store_s += t.store_s;
        result.batches += 1;
    }
    result.polish = Some(polished);
}
