//! Optimisation of a brake design: an [`OptimizationProblem`] solved by NSGA-II, the
//! surrogate-assisted optimiser ([`crate::surrogate`]) or pattern search, every evaluation analysed
//! by the FEA through the results store.
//!
//! Brief overview: [`StudyProblem`] adapts a problem file to [`mrbrake_optim::Problem`]: a vector
//! of variable values becomes a [`crate::Design`], each batch (one NSGA-II generation, one
//! surrogate iteration, one pattern-search poll) goes through the [`Runner`] (parallel, stored,
//! never recomputed), and each record becomes an [`Evaluation`]: the objectives (maximised ones
//! negated), the total normalised constraint violation ([`crate::problem::Constraint::violation`])
//! and each constraint's signed value (`−margin`, [`crate::problem::Constraint::margin`]);
//! infeasible or failed designs get an infinite violation so that every evaluated design beats them
//! (Deb's feasibility rules). Because NSGA-II and pattern search are seeded and deterministic,
//! re-running an interrupted optimisation on the same store replays the same designs: stored ones
//! are read back, the rest are computed; the surrogate continues from the stored designs instead.
//! [`run`] returns every evaluated design, the feasible Pareto front (the non-dominated set of the
//! *evaluated* designs), its hypervolume ([`crate::hypervolume`]), the reference design, and the
//! front's designs as they are written ([`crate::front`]: rounded to the manufacturing resolution
//! and evaluated again); [`crate::polish`] refines one front design by a pattern search started
//! at it.
//!
//! The caller's [`Observer`] sees an [`OptimizeProgress`] after every stored evaluation, and after
//! every surrogate iteration (with its [`IterationStatus`]); a [`Flow::Stop`] ends the
//! optimisation once the designs in flight are stored, and [`run`] returns what was evaluated until
//! then with [`OptimizationResult::stopped`] set (running it again on the same store resumes it).

use std::cell::{Cell, RefCell};

use mrbrake_observe::{Flow, Observer, Silent};
use mrbrake_optim::pareto::{Evaluation, pareto_front};
use mrbrake_optim::space::{Bounds, validate_design};
use mrbrake_optim::surrogate::EvaluatedDesign;
use mrbrake_optim::{Problem, RunError, nsga2, pattern_search};
use mrbrake_store::{MetricValue, Record, Status, Store};

use crate::design::DesignSpace;
use crate::front::FrontDesign;
use crate::hypervolume::{self, Hypervolume, ReferenceSource};
use crate::problem::{Algorithm, Goal, OptimizationProblem, Start};
use crate::runner::{Progress, RunSummary, Runner};
use crate::surrogate::{IterationStatus, SurrogateRun, optimiser_bounds};
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
    /// The hypervolume of `evaluated` with its reference point and its growth (`None` while no
    /// design is feasible).
    pub hypervolume: Option<Hypervolume>,
    /// A surrogate run's iterations (model fits, timings) and why it stopped.
    pub surrogate: Option<SurrogateRun>,
    /// The front's designs as written (`designs/front-NN.toml`), in the front's order: rounded to
    /// the manufacturing resolution and evaluated again (empty for a stopped run).
    pub front_designs: Vec<FrontDesign>,
    /// The polish of a front design ([`run_with`]), whose designs are among `evaluated`.
    pub polish: Option<crate::polish::Polished>,
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
    /// Surrogate: the initial design (0), then iteration `index`.
    Iteration {
        /// 0 for the initial design, then 1, 2, …
        index: usize,
    },
    /// The front's designs rounded to the manufacturing resolution, evaluated again.
    FrontDesigns,
}

/// Where an optimisation stands, over the whole run, reported after every stored evaluation.
///
/// Why not the runner's [`Progress`]: the optimiser runs one batch per generation (or poll), and
/// a batch's progress restarts at zero, so its lines would read "0/N" at every generation.
#[derive(Debug, Clone, PartialEq)]
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
    /// Set once per surrogate iteration, after its batch: the iteration's hypervolume and model
    /// fits (the counts above are those of the last stored evaluation).
    pub iteration: Option<IterationStatus>,
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
    /// Designs of the store read as the data of a continued (surrogate) run.
    preloaded: usize,
    /// Designs of the store left out of that data because they lack a metric the objectives or
    /// constraints need ([`Self::stored_designs`]).
    skipped_incomplete: usize,
    /// The hypervolume's reference point and where it comes from, once known.
    reference: Option<(Vec<f64>, ReferenceSource)>,
    /// Whether a reference point this study fixes is recorded in the store.
    records_reference: bool,
    observer: &'p mut dyn Observer<OptimizeProgress>,
}

impl<'s, 'p> StudyProblem<'s, 'p> {
    /// Sets up the problem: reads the base spec, resolves the variables and their bounds, and the
    /// hypervolume's reference point if the problem gives one or the store records one;
    /// `observer` sees the progress of every batch.
    pub fn new(
        problem: &'p OptimizationProblem,
        store: &'s mut Store,
        jobs: usize,
        observer: &'p mut dyn Observer<OptimizeProgress>,
    ) -> Result<Self, ExploreError> {
        let (space, bounds) = space_and_bounds(problem)?;
        let reference = match &problem.hypervolume_reference {
            Some(r) => Some((r.clone(), ReferenceSource::Problem)),
            None => hypervolume::stored_reference(store, &problem.objectives)?
                .map(|r| (r, ReferenceSource::Store)),
        };
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
            preloaded: 0,
            skipped_incomplete: 0,
            reference,
            records_reference: true,
            observer,
        })
    }

    /// The design space (base spec and variables).
    pub fn space(&self) -> &DesignSpace {
        &self.space
    }

    /// The problem.
    pub fn problem(&self) -> &OptimizationProblem {
        self.problem
    }

    /// What the optimiser sees of a record ([`evaluation_for`]).
    pub fn evaluation_of(&self, record: &Record) -> Evaluation {
        evaluation_for(self.problem, record)
    }

    /// This study no longer records the hypervolume's reference point in the store (a polish,
    /// whose derived objectives are not the study's).
    pub fn without_recording(mut self) -> Self {
        self.records_reference = false;
        self
    }

    /// The designs evaluated, in order, and the summed run statistics (`None`: nothing run).
    pub fn into_parts(self) -> (Vec<Evaluated>, Option<RunSummary>) {
        (self.evaluated, self.totals)
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
            // A material's value is its level's index (a material not among them: none).
            let value = if variable.is_categorical() {
                let material = spec.materials.in_use(variable.path());
                material.and_then(|name| variable.parse_value(name).ok())
            } else {
                let found = variable.path().split('.').try_fold(&table, |t, part| t.get(part));
                found.and_then(serde_json::Value::as_f64)
            };
            let value = value.ok_or_else(|| {
                let e = mrbrake_error::FieldError::new(
                    "algorithm.start",
                    format!(
                        "the base spec has no value for {} among the variable's (e.g. turns \
                         computed from the window, or a material not listed); give it in the spec \
                         or start at the centre",
                        variable.path()
                    ),
                )
                .with_value("\"base\"");
                ExploreError::from(e).in_file(&self.problem.path.display().to_string())
            })?;
            point.push(bounds.repair(value));
        }
        Ok(point)
    }

    /// The start point of a pattern search (`algorithm.start`): `None` for the centre.
    pub fn start_point(&self, start: &Start) -> Result<Option<Vec<f64>>, ExploreError> {
        match start {
            Start::Centre => Ok(None),
            Start::Base => self.base_point().map(Some),
            Start::Values(values) => Ok(Some(
                values
                    .iter()
                    .zip(&self.bounds)
                    .map(|(v, b)| {
                        let (lo, hi) = b.feasible_range();
                        b.repair(v.unwrap_or(0.5 * (lo + hi)))
                    })
                    .collect(),
            )),
        }
    }

    /// The stored designs of this problem's space as evaluated designs (the data a continued
    /// surrogate run starts from), each also counted as seen. A stored design that lacks a
    /// metric the objectives or constraints need (evaluated by a study that asked for less, or
    /// stopped at another study's gate) is no data: it is skipped and counted
    /// ([`Self::skipped_incomplete`]); one that lacks only metrics the problem records is used.
    pub fn stored_designs(&mut self) -> Result<Vec<EvaluatedDesign>, ExploreError> {
        let records = crate::stored::read_records(self.runner.store())?;
        let needed: Vec<&str> = self.needed_metrics();
        let mut designs = Vec::new();
        for record in records {
            let x: Option<Vec<f64>> =
                self.space.variables().iter().map(|v| v.x_in(&record)).collect();
            let Some(x) = x.filter(|x| !x.is_empty()) else { continue };
            if validate_design(&self.bounds, &x, "stored design").is_err()
                || self.seen.contains_key(&record.key)
                || self.space.design(&x)?.key != record.key
            {
                continue;
            }
            if self.space.settings().study.needs_completion(&record) {
                let usable = record.status == mrbrake_store::Status::Ok
                    && needed.iter().all(|m| record.metric_value(m).is_some());
                if !usable {
                    self.skipped_incomplete += 1;
                    continue;
                }
            }
            let evaluation = self.keep(record);
            designs.push(EvaluatedDesign { x, evaluation });
        }
        self.preloaded = designs.len();
        Ok(designs)
    }

    /// The metrics the objectives and constraints read.
    fn needed_metrics(&self) -> Vec<&'p str> {
        let objectives = self.problem.objectives.iter().map(|o| o.metric.as_str());
        objectives.chain(self.problem.constraints.iter().map(|c| c.metric.as_str())).collect()
    }

    /// Stored designs [`Self::stored_designs`] left out for lacking a needed metric.
    pub fn skipped_incomplete(&self) -> usize {
        self.skipped_incomplete
    }

    /// The hypervolume's reference point, once known (given, recorded, or fixed by this run).
    pub fn hypervolume_reference(&self) -> Option<Vec<f64>> {
        self.reference.as_ref().map(|(r, _)| r.clone())
    }

    /// The evaluations of the designs evaluated so far, in order.
    pub fn evaluations(&self) -> Vec<Evaluation> {
        self.evaluated.iter().map(|e| e.evaluation.clone()).collect()
    }

    /// Fixes the hypervolume's reference point by the rule of [`crate::hypervolume`] once a design
    /// is feasible, and records it in the store (a resumed run and the study report use it).
    fn fix_reference(&mut self) -> Result<(), ExploreError> {
        if self.reference.is_none() {
            let objectives = self.problem.objectives.len();
            if let Some(r) = hypervolume::reference_of(&self.evaluations(), objectives) {
                self.reference = Some((r, ReferenceSource::FirstFeasibleBatch));
            }
        }
        if let (Some((r, ReferenceSource::FirstFeasibleBatch)), true) =
            (&self.reference, self.records_reference)
        {
            let store = self.runner.store_mut();
            hypervolume::record_reference(store, &self.problem.objectives, r)?;
        }
        Ok(())
    }

    /// The hypervolume of the evaluated designs, in order.
    fn hypervolume(&self) -> Option<Hypervolume> {
        let (reference, source) = self.reference.clone()?;
        Some(Hypervolume::of(&self.evaluations(), reference, source))
    }

    /// Designs the whole run asks for (see [`OptimizeProgress::total`]).
    fn planned_designs(&self) -> usize {
        let algorithm = match &self.problem.algorithm {
            Algorithm::Nsga2 { population, generations, .. } => population * (generations + 1),
            Algorithm::Surrogate(s) => s.max_evaluations.saturating_sub(self.preloaded),
            Algorithm::PatternSearch { max_evaluations, .. } => *max_evaluations,
        };
        algorithm + usize::from(self.problem.reference)
    }

    /// The stage of the algorithm's next batch.
    fn next_algorithm_stage(&self) -> Stage {
        let index = self.algorithm_batches;
        match self.problem.algorithm {
            Algorithm::Nsga2 { generations, .. } => Stage::Generation { index, of: generations },
            Algorithm::Surrogate(_) => Stage::Iteration { index },
            Algorithm::PatternSearch { .. } => Stage::Poll { index },
        }
    }

    /// Evaluates `designs` as the batch `stage` through the runner, relaying its progress.
    pub(crate) fn run_batch(
        &mut self,
        designs: &[Design],
        stage: Stage,
    ) -> Result<Vec<Record>, ExploreError> {
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
            observer.observe(&OptimizeProgress { stage, done, total, run, iteration: None })
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
        let evaluations = records.into_iter().map(|record| self.keep(record)).collect();
        self.fix_reference()?;
        Ok(evaluations)
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
    let problem_file = problem.path.display().to_string();
    let spec_text = mrbrake_error::read::text(&problem.spec_path, mrbrake_error::read::SETTINGS)
        .map_err(|e| {
            let e = mrbrake_error::FieldError::new("spec", format!("cannot read it: {e}"))
                .with_value(format!("'{}'", problem.spec_path.display()));
            ExploreError::from(e).in_file(&problem_file)
        })?;
    let names: Vec<String> = problem.variables.iter().map(|v| v.name.clone()).collect();
    let mut space = DesignSpace::new(
        &spec_text,
        &problem.spec_path.display().to_string(),
        &problem.overrides,
        &names,
        problem.settings.clone(),
    )
    // A variable the spec cannot take (unknown, given twice) or a setting out of range is the
    // problem file's fault (a change the spec cannot take is already located in the spec).
    .map_err(|e| e.in_file(&problem_file))?;
    for (index, b) in problem.variables.iter().enumerate() {
        if !b.levels.is_empty() {
            space.set_levels(index, &b.levels)?;
        }
    }
    let bounds: Vec<Bounds> = space
        .variables()
        .iter()
        .zip(&problem.variables)
        .map(|(v, b)| optimiser_bounds(v, b))
        .collect();
    Ok((space, bounds))
}

/// An optimiser's error as the study's: its own set-up errors wrapped, the study's unchanged.
pub(crate) fn run_error(e: RunError<ExploreError>) -> ExploreError {
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
        let text = mrbrake_error::read::text(problem_path, mrbrake_error::read::SETTINGS)
            .unwrap_or_default();
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
    run_with(problem, store, jobs, None, observer)
}

/// [`run`], then, with `polish`, a pattern search from one of the front's designs
/// ([`crate::polish`]): its designs join the evaluated ones before the front, its hypervolume and
/// its written designs are made.
pub fn run_with(
    problem: &OptimizationProblem,
    store: &mut Store,
    jobs: usize,
    polish: Option<&crate::polish::PolishRequest>,
    observer: &mut dyn Observer<OptimizeProgress>,
) -> Result<OptimizationResult, ExploreError> {
    // One observer for the batches (through each study) and the surrogate's iterations: the
    // iteration's line carries the counts of the last stored evaluation.
    let outer = RefCell::new(observer);
    let last: RefCell<Option<OptimizeProgress>> = RefCell::new(None);
    let next_iteration = Cell::new(0);
    let mut relay = |p: &OptimizeProgress| {
        let mut p = p.clone();
        if let Stage::Iteration { .. } = p.stage {
            // The surrogate numbers its iterations; a resumed run may skip the initial design.
            p.stage = Stage::Iteration { index: next_iteration.get() };
        }
        let flow = outer.borrow_mut().observe(&p);
        *last.borrow_mut() = Some(p);
        flow
    };
    let mut on_iteration = |status: &IterationStatus| {
        next_iteration.set(status.iteration + 1);
        let mut p = last.borrow().clone().unwrap_or_else(|| idle_progress(Stage::Reference));
        p.stage = Stage::Iteration { index: status.iteration };
        p.iteration = Some(status.clone());
        outer.borrow_mut().observe(&p)
    };
    let mut result = run_algorithm_phase(problem, store, jobs, &mut relay, &mut on_iteration)?;
    if let (Some(request), false) = (polish, result.stopped) {
        let polished = crate::polish::run(problem, store, jobs, &result, request, &mut relay)?;
        crate::polish::merge(&mut result, polished);
    }
    finish(problem, store, jobs, result, &mut relay)
}

/// A progress with nothing done yet, at `stage`.
fn idle_progress(stage: Stage) -> OptimizeProgress {
    let run = Progress {
        to_compute: 0,
        computed: 0,
        completed: 0,
        reused: 0,
        infeasible: 0,
        failed: 0,
        elapsed_s: 0.0,
    };
    OptimizeProgress { stage, done: 0, total: 0, run, iteration: None }
}

/// The reference design and the algorithm on one study: everything of the result but the front,
/// the hypervolume and the written designs ([`finish`]).
fn run_algorithm_phase(
    problem: &OptimizationProblem,
    store: &mut Store,
    jobs: usize,
    relay: &mut dyn Observer<OptimizeProgress>,
    on_iteration: &mut dyn FnMut(&IterationStatus) -> Flow,
) -> Result<OptimizationResult, ExploreError> {
    let mut study = StudyProblem::new(problem, store, jobs, relay)?;
    let reference = if problem.reference { reference_design(&mut study) } else { Ok(None) };
    let (reference, algorithm) = match reference {
        Ok(reference) => (reference, run_algorithm(&mut study, problem, jobs, on_iteration)),
        Err(e) => (None, Err(e)),
    };
    let (iterations, converged, surrogate, stopped) = match algorithm {
        Ok(Ran { iterations, converged, surrogate }) => {
            let stopped = surrogate.as_ref().is_some_and(|s| s.stop == "observer");
            (iterations, converged, surrogate, stopped)
        }
        Err(ExploreError::Stopped { .. }) => {
            // The batches that finished: the start (initial population or start point) is not an
            // iteration, and the stopped batch did not finish.
            (study.algorithm_batches.saturating_sub(2), None, None, true)
        }
        Err(e) => return Err(e),
    };
    study.fix_reference()?;
    let hypervolume = study.hypervolume();
    let totals = match study.totals.clone() {
        Some(totals) => totals,
        None if !study.evaluated.is_empty() => RunSummary {
            progress: idle_progress(Stage::Reference).run,
            evaluation_s: 0.0,
            store_s: 0.0,
        },
        None => return Err(ExploreError::Internal("the optimiser evaluated no design".into())),
    };
    Ok(OptimizationResult {
        iterations,
        converged,
        stopped,
        variables: study.space.variables().to_vec(),
        evaluated: study.evaluated,
        front: Vec::new(),
        reference,
        batches: study.batches,
        requested: study.requested,
        totals,
        hypervolume,
        surrogate,
        front_designs: Vec::new(),
        polish: None,
    })
}

/// The base spec, evaluated as the reference design.
fn reference_design(study: &mut StudyProblem<'_, '_>) -> Result<Option<Evaluated>, ExploreError> {
    let base = study.space.base_design()?;
    let mut records = study.run_batch(std::slice::from_ref(&base), Stage::Reference)?;
    let record = records
        .pop()
        .ok_or_else(|| ExploreError::Internal("the reference design was not stored".into()))?;
    let evaluation = study.evaluation_of(&record);
    Ok(Some(Evaluated { record, evaluation }))
}

/// The front of the evaluated designs, their hypervolume (over every evaluated design, in order,
/// against the run's reference point) and, for a run that was not stopped, the written designs.
fn finish(
    problem: &OptimizationProblem,
    store: &mut Store,
    jobs: usize,
    mut result: OptimizationResult,
    relay: &mut dyn Observer<OptimizeProgress>,
) -> Result<OptimizationResult, ExploreError> {
    let evaluations: Vec<Evaluation> =
        result.evaluated.iter().map(|e| e.evaluation.clone()).collect();
    result.front = front_of(problem, &evaluations);
    if let Some(h) = &result.hypervolume {
        result.hypervolume = Some(Hypervolume::of(&evaluations, h.reference.clone(), h.source));
    }
    if !result.stopped {
        let mut study = StudyProblem::new(problem, store, jobs, relay)?;
        match crate::front::designs(&mut study, &result) {
            Ok(designs) => result.front_designs = designs,
            Err(ExploreError::Stopped { .. }) => result.stopped = true,
            Err(e) => return Err(e),
        }
    }
    Ok(result)
}

/// What an algorithm's run returns to [`run_algorithm_phase`].
struct Ran {
    iterations: usize,
    converged: Option<bool>,
    surrogate: Option<SurrogateRun>,
}

/// Runs the problem's algorithm on `study`: the generations (NSGA-II), iterations (surrogate) or
/// polls (pattern search) run, whether a pattern search converged, and a surrogate run's record.
fn run_algorithm(
    study: &mut StudyProblem<'_, '_>,
    problem: &OptimizationProblem,
    jobs: usize,
    on_iteration: &mut dyn FnMut(&IterationStatus) -> Flow,
) -> Result<Ran, ExploreError> {
    match &problem.algorithm {
        Algorithm::Nsga2 { population, generations, seed } => {
            let options = nsga2::Nsga2Options {
                population: *population,
                generations: *generations,
                seed: *seed,
                ..nsga2::Nsga2Options::default()
            };
            let result = nsga2::run(study, &options, &mut Silent).map_err(run_error)?;
            Ok(Ran { iterations: result.generations, converged: None, surrogate: None })
        }
        Algorithm::Surrogate(settings) => {
            let (iterations, record) =
                crate::surrogate::run(study, problem, settings, jobs, on_iteration)?;
            Ok(Ran { iterations, converged: None, surrogate: Some(record) })
        }
        Algorithm::PatternSearch { max_evaluations, seed, random_poll, start } => {
            let options = pattern_search::PatternSearchOptions {
                max_evaluations: *max_evaluations,
                seed: *seed,
                start: study.start_point(start)?,
                poll: if *random_poll {
                    pattern_search::PollDirections::RandomOrthogonal
                } else {
                    pattern_search::PollDirections::Compass
                },
                ..pattern_search::PatternSearchOptions::default()
            };
            let result = pattern_search::run(study, &options, &mut Silent).map_err(run_error)?;
            Ok(Ran {
                iterations: result.iterations,
                converged: Some(result.converged),
                surrogate: None,
            })
        }
    }
}

/// What the optimiser sees of a record of `problem`: the objectives (maximised ones negated), the
/// total violation and each constraint's signed value `−margin` (satisfied when `≤ 0`); a record
/// that is not `ok`, or lacks a metric, is a failed evaluation.
///
/// A metric beyond the analysed range (`mrbrake_store::MetricValue`) counts as follows. In a
/// constraint: [`crate::problem::Constraint::violation_of`] (a bound that already satisfies it
/// satisfies it, one that cannot decide it counts as not computed). As an objective: a bound on
/// the good side is ranked by its bound — `AtLeast(b)` of a maximised objective as `b`,
/// `AtMost(b)` of a minimised one as `b` (the design is at least that good); a bound on the bad
/// side, or a metric that does not apply, cannot be ranked and the design counts as failed.
pub fn evaluation_for(problem: &OptimizationProblem, record: &Record) -> Evaluation {
    let n = problem.objectives.len();
    if record.status != Status::Ok {
        // A design the cascade stopped at a violated constraint keeps its violation, so the
        // optimiser still sees how far from feasible it is (Deb's rules).
        return crate::metrics::stopped_evaluation(record, &problem.constraints, n)
            .unwrap_or_else(|| Evaluation::failed(n));
    }
    let metric = |name: &str| record.metric_value(name).unwrap_or(MetricValue::Value(f64::NAN));
    let objectives: Vec<f64> =
        problem.objectives.iter().map(|o| objective_value(o.goal, metric(&o.metric))).collect();
    let violation: f64 =
        problem.constraints.iter().map(|c| c.violation_of(metric(&c.metric))).sum();
    if objectives.iter().any(|v| !v.is_finite()) || !violation.is_finite() {
        return Evaluation::failed(n);
    }
    let signed: Vec<f64> =
        problem.constraints.iter().map(|c| -c.margin_of(metric(&c.metric))).collect();
    Evaluation::new(objectives, violation).with_constraints(signed)
}

/// An objective as the optimiser minimises it (maximised ones negated), by the rules of
/// [`evaluation_for`]; infinite when it cannot be ranked.
pub fn objective_value(goal: Goal, value: MetricValue) -> f64 {
    let ranked = match (goal, value) {
        (_, MetricValue::Value(v))
        | (Goal::Maximize, MetricValue::AtLeast(v))
        | (Goal::Minimize, MetricValue::AtMost(v)) => v,
        _ => f64::NAN,
    };
    let ranked = if ranked.is_finite() { ranked } else { f64::INFINITY };
    match goal {
        Goal::Minimize => ranked,
        Goal::Maximize => -ranked,
    }
}

/// The front of `evaluations` (indices): the feasible non-dominated set, or for one objective the
/// best feasible design.
pub fn front_of(problem: &OptimizationProblem, evaluations: &[Evaluation]) -> Vec<usize> {
    if problem.objectives.len() == 1 {
        best_feasible(evaluations).into_iter().collect()
    } else {
        pareto_front(evaluations)
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
