//! Surrogate-assisted optimisation of a study (`[algorithm] kind = "surrogate"`): the optimiser
//! core [`mrbrake_optim::surrogate`] driven through the study's store, jobs and reports.
//!
//! Brief overview: [`run`] hands the core the study's [`crate::optimize::StudyProblem`] (every
//! batch analysed in parallel by the FEA and stored the moment each design completes) with
//!
//! * **the data so far**: every record of the store that is a design of this problem (same
//!   variables, inside the bounds, the same design key, so the same base spec, overrides and
//!   evaluation settings), in the store's order. A resumed run (`--resume`, or a run continued with
//!   a larger `--max-evaluations`) rebuilds its models from them and continues; a run killed with
//!   `kill -9` loses only the analyses in flight. They count towards the budget and the initial
//!   design;
//! * **each evaluation** as the core wants it: the objectives (maximised ones negated), the total
//!   normalised violation, and every constraint's signed normalised value `−margin`
//!   ([`crate::problem::Constraint::margin`], satisfied when `≤ 0`), so the models learn how far
//!   from each limit a design is, not only whether it breaks one. A design that could not be
//!   analysed or is not a valid brake is a failed evaluation: the core's feasibility classifier
//!   learns it, it is never a crash;
//! * **the batch** of `algorithm.batch` designs per iteration, by default as many as `--jobs`
//!   analyses run at once (one per core), so every core is busy;
//! * **the hypervolume's reference point** of the study ([`crate::hypervolume`]): the problem's, or
//!   the one an interrupted run recorded in the store, so that a resumed run's acquisition and its
//!   reports use the point the run started with.
//!
//! Every iteration becomes an [`IterationStatus`] (the batch, the evaluations, the hypervolume and
//! each model's leave-one-out error by the problem's metric names, the fit and acquisition times),
//! shown to the study's observer with the progress and kept in the [`SurrogateRun`] of the result.
//!
//! # Categorical variables
//!
//! The core handles categorical variables (an exchangeable kernel over the level index,
//! [`mrbrake_optim::surrogate::gp`]). A study has none yet: its variables are the spec's numeric
//! fields. [`optimiser_bounds`] is the one place a study variable becomes an optimiser variable;
//! a categorical variable (a material chosen from a list) adds an arm there returning
//! [`Bounds::categorical`] with its number of levels, and [`crate::DesignSpace::design`] writes
//! the level index `0, 1, …` it receives as the level's name. Nothing else changes: NSGA-II, the
//! surrogate and the store already carry categoricals as level indices.

use mrbrake_observe::Flow;
use mrbrake_optim::Problem as _;
use mrbrake_optim::space::Bounds;
use mrbrake_optim::surrogate::{
    self, EvaluatedDesign, IterationReport, ModelRole, StopReason, SurrogateOptions,
};

use crate::ExploreError;
use crate::optimize::StudyProblem;
use crate::problem::{OptimizationProblem, SurrogateSettings, VariableBounds};
use crate::variable::Variable;

/// The optimiser's bounds of one study variable (module docs: the hook of categorical variables).
pub fn optimiser_bounds(variable: &Variable, bounds: &VariableBounds) -> Bounds {
    variable.bounds(bounds.min, bounds.max)
}

/// One model's fit after an iteration.
#[derive(Debug, Clone, PartialEq)]
pub struct ModelQuality {
    /// What it models: `objective METRIC`, `constraint METRIC` or `feasibility classifier`.
    pub model: String,
    /// Its training designs.
    pub points: usize,
    /// Root-mean-square leave-one-out residual over the outputs' standard deviation: 0 is a
    /// perfect fit, about 1 no better than the mean.
    pub loo_error: f64,
}

/// What a surrogate iteration did, in the study's terms.
#[derive(Debug, Clone, PartialEq)]
pub struct IterationStatus {
    /// 0 for the initial design, then 1, 2, …
    pub iteration: usize,
    /// Designs evaluated in this iteration.
    pub batch: usize,
    /// Designs in the data after it (those of an earlier run included).
    pub evaluations: usize,
    /// The hypervolume of the evaluated feasible front (0 while none is feasible).
    pub hypervolume: f64,
    /// Each model's fit (none for the initial design or a fallback).
    pub models: Vec<ModelQuality>,
    /// Why the iteration's designs are space-filling instead (a model that could not be fitted).
    pub fallback: Option<String>,
    /// Wall time of the model fits (s).
    pub fit_s: f64,
    /// Wall time of the batch selection (s).
    pub acquisition_s: f64,
}

impl IterationStatus {
    fn of(report: &IterationReport, problem: &OptimizationProblem) -> Self {
        let name = |role: ModelRole| match role {
            ModelRole::Objective(j) => format!("objective {}", problem.objectives[j].metric),
            ModelRole::Constraint(k) => format!("constraint {}", problem.constraints[k].metric),
            ModelRole::Feasibility => "feasibility classifier".into(),
        };
        Self {
            iteration: report.iteration,
            batch: report.batch.len(),
            evaluations: report.evaluations,
            hypervolume: report.hypervolume,
            models: report
                .models
                .iter()
                .map(|m| ModelQuality {
                    model: name(m.role),
                    points: m.points,
                    loo_error: m.loo_error,
                })
                .collect(),
            fallback: report.fallback.as_ref().map(|f| {
                let role = name(f.role);
                format!("{role} model not fitted ({}): space-filling designs instead", f.reason)
            }),
            fit_s: report.fit_seconds,
            acquisition_s: report.acquisition_seconds,
        }
    }
}

/// A surrogate run's record: its settings as run, every iteration, and why it stopped.
#[derive(Debug, Clone, PartialEq)]
pub struct SurrogateRun {
    /// Designs of the store this run continued from.
    pub resumed_from: usize,
    /// Designs of the store left out of that data: they lack a metric the objectives or
    /// constraints need (`StudyProblem::stored_designs`).
    pub skipped_incomplete: usize,
    /// Designs per iteration.
    pub batch: usize,
    /// Designs of the initial plan (those of the store included).
    pub initial_size: usize,
    /// The budget.
    pub max_evaluations: usize,
    /// Every iteration of this run (0: the initial design).
    pub iterations: Vec<IterationStatus>,
    /// Why it stopped: `budget`, `stall`, `observer` or `exhausted`.
    pub stop: &'static str,
}

impl SurrogateRun {
    /// Total wall time of the model fits (s).
    pub fn fit_s(&self) -> f64 {
        self.iterations.iter().map(|i| i.fit_s).sum()
    }

    /// Total wall time of the batch selections (s).
    pub fn acquisition_s(&self) -> f64 {
        self.iterations.iter().map(|i| i.acquisition_s).sum()
    }
}

/// The core's options from the problem's settings: `batch` when the file gives none,
/// `reference` the study's hypervolume reference (if already known).
pub fn options(
    settings: &SurrogateSettings,
    batch: usize,
    reference: Option<Vec<f64>>,
) -> SurrogateOptions {
    SurrogateOptions {
        initial_size: settings.initial_size,
        batch: settings.batch.unwrap_or(batch).clamp(1, crate::problem::MAX_BATCH),
        max_evaluations: settings.max_evaluations,
        stall_iterations: settings.stall_iterations,
        stall_tolerance: settings.stall_tolerance,
        acquisition: settings.acquisition,
        reference,
        seed: settings.seed,
        ..SurrogateOptions::default()
    }
}

/// Runs the surrogate optimiser on `study` (module docs), showing `on_iteration` every
/// iteration's status; returns the iterations run after the initial design and the run's record.
pub fn run(
    study: &mut StudyProblem<'_, '_>,
    problem: &OptimizationProblem,
    settings: &SurrogateSettings,
    jobs: usize,
    on_iteration: &mut dyn FnMut(&IterationStatus) -> Flow,
) -> Result<(usize, SurrogateRun), ExploreError> {
    let previous: Vec<EvaluatedDesign> = study.stored_designs()?;
    let options = options(settings, resolved_jobs(jobs), study.hypervolume_reference());
    let mut iterations = Vec::new();
    let mut observer = |report: &IterationReport| {
        let status = IterationStatus::of(report, problem);
        let flow = on_iteration(&status);
        iterations.push(status);
        flow
    };
    let result = surrogate::run(study, &options, &previous, &mut observer)
        .map_err(crate::optimize::run_error)?;
    let stop = match result.stop {
        StopReason::Budget => "budget",
        StopReason::Stall => "stall",
        StopReason::Observer => "observer",
        StopReason::Exhausted => "exhausted",
    };
    let record = SurrogateRun {
        resumed_from: previous.len(),
        skipped_incomplete: study.skipped_incomplete(),
        batch: options.batch,
        initial_size: options.initial_design_size(study.bounds().len()),
        max_evaluations: options.max_evaluations,
        iterations,
        stop,
    };
    Ok((result.iterations, record))
}

/// The analyses run at once for `jobs` (0: one per core).
pub fn resolved_jobs(jobs: usize) -> usize {
    if jobs > 0 { jobs } else { std::thread::available_parallelism().map_or(1, usize::from) }
}
