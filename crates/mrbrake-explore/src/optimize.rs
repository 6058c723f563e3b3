//! Optimisation of a brake design: an [`OptimizationProblem`] solved by NSGA-II or pattern search,
//! every evaluation analysed by the FEA through the results store.
//!
//! Brief overview: [`StudyProblem`] adapts a problem file to [`mrbrake_optim::Problem`]: a vector
//! of variable values becomes a [`crate::Design`], each batch (one NSGA-II generation, one
//! pattern-search poll) goes through the [`Runner`] (parallel, stored, never recomputed), and each
//! record becomes an [`Evaluation`]: the objectives (maximised ones negated) and the total normalised
//! constraint violation ([`crate::problem::Constraint::violation`]); infeasible or failed designs get
//! an infinite violation so that every evaluated design beats them (Deb's feasibility rules).
//! Because the algorithms are seeded and deterministic, re-running an interrupted optimisation on
//! the same store replays the same designs: stored ones are read back, the rest are computed.
//! [`run`] returns every evaluated design, the feasible Pareto front and the reference design.
//!
//! The caller's [`Observer`] sees an [`OptimizeProgress`] after every stored evaluation; a
//! [`Flow::Stop`] ends the optimisation once the designs in flight
//! are stored, and [`run`] returns what was evaluated until then with
//! [`OptimizationResult::stopped`] set (running it again on the same store resumes it).

use mrbrake_observe::{Flow, Observer, Silent};
use mrbrake_optim::pareto::{Evaluation, pareto_front};
use mrbrake_optim::space::Bounds;
use mrbrake_optim::{Problem, RunError, nsga2, pattern_search};
use mrbrake_store::{Record, Status, Store};

use crate::design::DesignSpace;
use crate::problem::{Algorithm, Goal, OptimizationProblem};
use crate::runner::{Progress, RunSummary, Runner};
use crate::variable::Quantity;
use crate::{Design, ExploreError};

/// One evaluated design of an optimisation.
#[derive(Debug, Clone)]
pub struct Evaluated {
    /// The stored record (variables, metrics, spec).
    pub record: Record,
    /// What the optimiser saw.
    pub evaluation: Evaluation,
}

/// An optimisation's outcome.
#[derive(Debug, Clone)]
pub struct OptimizationResult {
    /// Every distinct design evaluated, in the order first asked for.
    pub evaluated: Vec<Evaluated>,
    /// Indices into `evaluated` of the feasible Pareto front (sorted by the first objective); for
    /// one objective, the best feasible design.
    pub front: Vec<usize>,
    /// The base spec evaluated as the reference design (when the problem asks for it).
    pub reference: Option<Evaluated>,
    /// Batches run, and the summed run statistics.
    pub batches: usize,
    /// Designs asked for by the algorithm (repeats included).
    pub requested: usize,
    /// Sum of all batches' run summaries (computed, reused, timings).
    pub totals: RunSummary,
    /// The design variables (for display).
    pub variables: Vec<crate::variable::Variable>,
    /// NSGA-II generations or pattern-search iterations run.
    pub iterations: usize,
    /// Pattern search: whether the step fell below its minimum (converged) rather than the
    /// evaluation budget running out. `None` for NSGA-II, which runs its generations.
    pub converged: Option<bool>,
    /// True when the observer stopped the optimisation: `evaluated` holds the designs stored
    /// until then, `iterations` the generations or polls completed.
    pub stopped: bool,
}

/// Which batch of an optimisation is being evaluated.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Stage {
    /// The base spec, evaluated as the reference design before the algorithm starts.
    Reference,
    /// NSGA-II generation `index` of `of` (0: the initial population).
    Generation {
        /// 0 for the initial population, then 1 to `of`.
        index: usize,
        /// Generations after the initial population.
        of: usize,
    },
    /// Pattern search: the start point (0), then poll `index`.
    Poll {
        /// 0 for the start point, then 1, 2, …
        index: usize,
    },
}

/// Where an optimisation stands, over the whole run, reported after every stored evaluation.
///
/// Why not the runner's [`Progress`]: the optimiser runs one batch per generation (or poll), and
/// a batch's progress restarts at zero, so its lines would read "0/N" at every generation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OptimizeProgress {
    /// The batch being evaluated.
    pub stage: Stage,
    /// Designs asked for so far that are done (computed, read back from the store or repeats
    /// within their batch); never decreases during a run.
    pub done: usize,
    /// Designs the run asks for: the reference design, plus population × (generations + 1) for
    /// NSGA-II or the evaluation budget for pattern search (which may converge sooner).
    pub total: usize,
    /// The counts of every batch so far summed (this batch's included); `elapsed_s` is the time
    /// spent in batches.
    pub run: Progress,
}

/// The [`mrbrake_optim::Problem`] of an optimisation problem file.
pub struct StudyProblem<'s, 'p> {
    problem: &'p OptimizationProblem,
    space: DesignSpace,
    bounds: Vec<Bounds>,
    runner: Runner<'s>,
    evaluated: Vec<Evaluated>,
    seen: std::collections::HashMap<String, usize>,
    batches: usize,
    requested: usize,
    totals: Option<RunSummary>,
    /// Batches the algorithm asked for (the reference design not counted).
    algorithm_batches: usize,
    observer: &'p mut dyn Observer<OptimizeProgress>,
}

impl<'s, 'p> StudyProblem<'s, 'p> {
    /// Sets up the problem: reads the base spec, resolves the variables and their bounds;
    /// `observer` sees the progress of every batch.
    pub fn new(
        problem: &'p OptimizationProblem,
        store: &'s mut Store,
        jobs: usize,
        observer: &'p mut dyn Observer<OptimizeProgress>,
    ) -> Result<Self, ExploreError> {
        let (space, bounds) = space_and_bounds(problem)?;
        Ok(Self {
            problem,
            space,
            bounds,
            runner: Runner::new(store, problem.settings.clone(), jobs),
            evaluated: Vec::new(),
            seen: Default::default(),
            batches: 0,
            requested: 0,
            totals: None,
            algorithm_batches: 0,
            observer,
        })
    }

    /// The design space (base spec and variables).
    pub fn space(&self) -> &DesignSpace {
        &self.space
    }

    /// What the optimiser sees of a record.
    pub fn evaluation_of(&self, record: &Record) -> Evaluation {
        let n = self.problem.objectives.len();
        if record.status != Status::Ok {
            // A design the cascade stopped at a violated constraint keeps its violation, so the
            // optimiser still sees how far from feasible it is (Deb's rules).
            return crate::metrics::stopped_evaluation(record, &self.problem.constraints, n)
                .unwrap_or_else(|| Evaluation::failed(n));
        }
        let metric = |name: &str| {
            record.metrics.iter().find(|(k, _)| k == name).map_or(f64::NAN, |(_, v)| *v)
        };
        let objectives: Vec<f64> = self
            .problem
            .objectives
            .iter()
            .map(|o| {
                let v = metric(&o.metric);
                let v = if v.is_finite() { v } else { f64::INFINITY };
                match o.goal {
                    Goal::Minimize => v,
                    Goal::Maximize => -v,
                }
            })
            .collect();
        let violation: f64 =
            self.problem.constraints.iter().map(|c| c.violation(metric(&c.metric))).sum();
        if objectives.iter().any(|v| !v.is_finite()) {
            return Evaluation::failed(n);
        }
        Evaluation::new(objectives, violation)
    }

    /// The base spec's value of every variable, clamped into its bounds (a start point).
    pub fn base_point(&self) -> Result<Vec<f64>, ExploreError> {
        let base = self.space.base_design()?;
        let spec = base.spec.map_err(|source| ExploreError::InvalidBase {
            what: "algorithm.start = \"base\"",
            source,
        })?;
        let table = serde_json::to_value(&spec)
            .map_err(|e| ExploreError::Internal(format!("cannot read the base spec: {e}")))?;
        let mut point = Vec::with_capacity(self.bounds.len());
        for (variable, bounds) in self.space.variables().iter().zip(&self.bounds) {
            let value = variable
                .field
                .path
                .split('.')
                .try_fold(&table, |t, part| t.get(part))
                .and_then(serde_json::Value::as_f64)
                .ok_or_else(|| {
                    ExploreError::Input(format!(
                        "algorithm.start = \"base\": the base spec has no value for {} (e.g. turns \
                         computed from the window); give it in the spec or start at the centre",
                        variable.field.path
                    ))
                })?;
            point.push(bounds.repair(value));
        }
        Ok(point)
    }

    /// Designs the whole run asks for (see [`OptimizeProgress::total`]).
    fn planned_designs(&self) -> usize {
        let algorithm = match self.problem.algorithm {
            Algorithm::Nsga2 { population, generations, .. } => population * (generations + 1),
            Algorithm::PatternSearch { max_evaluations, .. } => max_evaluations,
        };
        algorithm + usize::from(self.problem.reference)
    }

    /// The stage of the algorithm's next batch.
    fn next_algorithm_stage(&self) -> Stage {
        let index = self.algorithm_batches;
        match self.problem.algorithm {
            Algorithm::Nsga2 { generations, .. } => Stage::Generation { index, of: generations },
            Algorithm::PatternSearch { .. } => Stage::Poll { index },
        }
    }

    fn run_batch(&mut self, designs: &[Design], stage: Stage) -> Result<Vec<Record>, ExploreError> {
        // The batch's progress made cumulative: designs and counts of the earlier batches added.
        let done_before = self.requested;
        let before = self.totals.as_ref().map(|t| t.progress);
        let total = self.planned_designs().max(done_before + designs.len());
        let observer = &mut *self.observer;
        let mut relay = |p: &Progress| -> Flow {
            // Everything of the batch not waiting to be computed is done (reused, computed, or a
            // repeat of a design earlier in the batch).
            let waiting = p.to_compute - p.computed;
            let mut run = *p;
            if let Some(b) = &before {
                run.add(b);
            }
            let done = done_before + designs.len() - waiting;
            observer.observe(&OptimizeProgress { stage, done, total, run })
        };
        let outcome = self.runner.run(designs, &mut relay);
        self.batches += 1;
        self.requested += designs.len();
        let (records, summary) = match outcome {
            Ok(done) => done,
            Err(ExploreError::Stopped { progress }) => {
                if stage != Stage::Reference {
                    self.keep_stored(designs)?;
                }
                let summary = RunSummary { progress, evaluation_s: 0.0, store_s: 0.0 };
                self.add_totals(summary);
                return Err(ExploreError::Stopped { progress });
            }
            Err(e) => return Err(e),
        };
        self.add_totals(summary);
        Ok(records)
    }

    /// Adds a batch's run summary to the totals.
    fn add_totals(&mut self, summary: RunSummary) {
        self.totals = Some(match self.totals.take() {
            None => summary,
            Some(mut t) => {
                t.progress.add(&summary.progress);
                t.evaluation_s += summary.evaluation_s;
                t.store_s += summary.store_s;
                t
            }
        });
    }

    /// Keeps the designs of a stopped batch that are in the store (those finished before the
    /// stop) among the evaluated ones.
    fn keep_stored(&mut self, designs: &[Design]) -> Result<(), ExploreError> {
        for design in designs {
            if let Some(record) = crate::stored::read_record(self.runner.store(), &design.key)? {
                self.keep(record);
            }
        }
        Ok(())
    }

    /// Adds `record` to the evaluated designs (once per key) and returns what the optimiser sees.
    fn keep(&mut self, record: Record) -> Evaluation {
        let evaluation = self.evaluation_of(&record);
        if !self.seen.contains_key(&record.key) {
            self.seen.insert(record.key.clone(), self.evaluated.len());
            self.evaluated.push(Evaluated { record, evaluation: evaluation.clone() });
        }
        evaluation
    }
}

impl Problem for StudyProblem<'_, '_> {
    type Error = ExploreError;

    fn bounds(&self) -> &[Bounds] {
        &self.bounds
    }

    fn objectives(&self) -> usize {
        self.problem.objectives.len()
    }

    fn evaluate_batch(&mut self, xs: &[Vec<f64>]) -> Result<Vec<Evaluation>, ExploreError> {
        let designs: Vec<Design> =
            xs.iter().map(|x| self.space.design(x)).collect::<Result<_, _>>()?;
        let stage = self.next_algorithm_stage();
        self.algorithm_batches += 1;
        let records = self.run_batch(&designs, stage)?;
        Ok(records.into_iter().map(|record| self.keep(record)).collect())
    }
}

/// Checks everything about `problem` that can be checked without evaluating a design: the base
/// spec reads, every variable names a field of it once, and the bounds are valid. Call it before
/// creating a results store, so that a bad problem file leaves nothing behind.
pub fn check(problem: &OptimizationProblem) -> Result<(), ExploreError> {
    let (space, bounds) = space_and_bounds(problem)?;
    mrbrake_optim::space::validate_bounds(&bounds).map_err(ExploreError::Optim)?;
    crate::metrics::check_space(&space, &problem.path)
}

/// The design space of `problem` (base spec and resolved variables) and the optimiser's bounds.
fn space_and_bounds(
    problem: &OptimizationProblem,
) -> Result<(DesignSpace, Vec<Bounds>), ExploreError> {
    let spec_text = std::fs::read_to_string(&problem.spec_path).map_err(|e| {
        ExploreError::Input(format!(
            "{}: spec = '{}': cannot read it: {e}",
            problem.path.display(),
            problem.spec_path.display()
        ))
    })?;
    let names: Vec<String> = problem.variables.iter().map(|v| v.name.clone()).collect();
    let space = DesignSpace::new(
        &spec_text,
        &problem.spec_path.display().to_string(),
        &problem.overrides,
        &names,
        problem.settings.clone(),
    )
    .map_err(|e| match e {
        // A variable the spec cannot take (unknown, given twice) is the problem file's fault.
        ExploreError::Input(message)
            if !message.starts_with(&*problem.spec_path.to_string_lossy()) =>
        {
            ExploreError::Input(format!("{}: {message}", problem.path.display()))
        }
        other => other,
    })?;
    let bounds: Vec<Bounds> = space
        .variables()
        .iter()
        .zip(&problem.variables)
        .map(|(v, b)| match v.field.quantity {
            Quantity::Integer => Bounds::integer(b.min, b.max),
            _ => Bounds::continuous(b.min, b.max),
        })
        .collect();
    Ok((space, bounds))
}

fn run_error(e: RunError<ExploreError>) -> ExploreError {
    match e {
        RunError::Optim(e) => ExploreError::Optim(e),
        RunError::Problem(e) => e,
    }
}

/// The store of a problem file when none is given: `<problem file stem>.sqlite` in the current
/// folder.
pub fn default_store_path(problem_path: &std::path::Path) -> std::path::PathBuf {
    let stem = problem_path.file_stem().and_then(|s| s.to_str()).unwrap_or("optimize");
    std::path::PathBuf::from(format!("{stem}.sqlite"))
}

/// Opens the results store of `problem` (created if missing; an existing store only with
/// `resume`) and records the problem file's text in a new one. The problem is checked first
/// ([`check`]): a bad problem file leaves no store behind (the corrected command would otherwise
/// need `--resume`).
pub fn open_problem_store(
    problem: &OptimizationProblem,
    store_path: &std::path::Path,
    resume: bool,
) -> Result<Store, ExploreError> {
    check(problem)?;
    let problem_path = problem.path.as_path();
    let mut store = Store::open_or_create(store_path, resume)?;
    if store.meta("problem")?.is_none() {
        let text = std::fs::read_to_string(problem_path).unwrap_or_default();
        store.set_meta("problem", &text)?;
    }
    Ok(store)
}

/// Runs the optimisation of `problem` with results in `store`, `jobs` analyses at a time,
/// showing `observer` the progress after every stored evaluation (see the module docs for a
/// stop).
pub fn run(
    problem: &OptimizationProblem,
    store: &mut Store,
    jobs: usize,
    observer: &mut dyn Observer<OptimizeProgress>,
) -> Result<OptimizationResult, ExploreError> {
    let mut study = StudyProblem::new(problem, store, jobs, observer)?;
    let reference = if problem.reference {
        let base = study.space.base_design()?;
        match study.run_batch(std::slice::from_ref(&base), Stage::Reference) {
            Ok(mut records) => {
                let record = records.pop().ok_or_else(|| {
                    ExploreError::Internal("the reference design was not stored".into())
                })?;
                let evaluation = study.evaluation_of(&record);
                Ok(Some(Evaluated { record, evaluation }))
            }
            Err(e) => Err(e),
        }
    } else {
        Ok(None)
    };
    let (reference, algorithm) = match reference {
        Ok(reference) => (reference, run_algorithm(&mut study, problem)),
        Err(e) => (None, Err(e)),
    };
    let (iterations, converged, stopped) = match algorithm {
        Ok((iterations, converged)) => (iterations, converged, false),
        Err(ExploreError::Stopped { .. }) => {
            // The batches that finished: the start (initial population or start point) is not an
            // iteration, and the stopped batch did not finish.
            (study.algorithm_batches.saturating_sub(2), None, true)
        }
        Err(e) => return Err(e),
    };
    let evaluations: Vec<Evaluation> =
        study.evaluated.iter().map(|e| e.evaluation.clone()).collect();
    let front = if problem.objectives.len() == 1 {
        best_feasible(&evaluations).into_iter().collect()
    } else {
        pareto_front(&evaluations)
    };
    let totals = match study.totals.clone() {
        Some(totals) => totals,
        None => return Err(ExploreError::Internal("the optimiser evaluated no design".into())),
    };
    Ok(OptimizationResult {
        iterations,
        converged,
        stopped,
        variables: study.space.variables().to_vec(),
        evaluated: study.evaluated,
        front,
        reference,
        batches: study.batches,
        requested: study.requested,
        totals,
    })
}

/// Runs the problem's algorithm on `study`: the generations (NSGA-II) or polls (pattern search)
/// run, and whether a pattern search converged.
fn run_algorithm(
    study: &mut StudyProblem<'_, '_>,
    problem: &OptimizationProblem,
) -> Result<(usize, Option<bool>), ExploreError> {
    match problem.algorithm {
        Algorithm::Nsga2 { population, generations, seed } => {
            let options = nsga2::Nsga2Options {
                population,
                generations,
                seed,
                ..nsga2::Nsga2Options::default()
            };
            let result = nsga2::run(study, &options, &mut Silent).map_err(run_error)?;
            Ok((result.generations, None))
        }
        Algorithm::PatternSearch { max_evaluations, seed, random_poll, start_at_base } => {
            let start = if start_at_base { Some(study.base_point()?) } else { None };
            let options = pattern_search::PatternSearchOptions {
                max_evaluations,
                seed,
                start,
                poll: if random_poll {
                    pattern_search::PollDirections::RandomOrthogonal
                } else {
                    pattern_search::PollDirections::Compass
                },
                ..pattern_search::PatternSearchOptions::default()
            };
            let result = pattern_search::run(study, &options, &mut Silent).map_err(run_error)?;
            Ok((result.iterations, Some(result.converged)))
        }
    }
}

/// The feasible design with the smallest objective.
fn best_feasible(evaluations: &[Evaluation]) -> Option<usize> {
    evaluations
        .iter()
        .enumerate()
        .filter(|(_, e)| e.feasible())
        .min_by(|a, b| a.1.objectives[0].total_cmp(&b.1.objectives[0]))
        .map(|(i, _)| i)
}
