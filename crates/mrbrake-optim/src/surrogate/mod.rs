//! Surrogate-assisted (Bayesian) constrained multi-objective optimisation: far fewer evaluations
//! to a Pareto front than NSGA-II when each evaluation is a finite-element analysis.
//!
//! # Brief overview
//!
//! [`run`] minimises a [`Problem`]'s objectives under its constraints:
//!
//! 1. **Initial design**: a space-filling plan ([`InitialPlan`]: shifted Sobol' by default, or a
//!    Latin hypercube) of [`SurrogateOptions::initial_size`] designs (default 10 × variables, at
//!    least variables + 1), evaluated in one batch. Designs given to [`run`] (a resumed study's
//!    records) count towards it: only the plan's designs not among them are evaluated, as many as
//!    it takes to reach the plan's size.
//! 2. **Iterations**: fit one Gaussian process per objective, one per constraint and, where
//!    needed, a feasibility classifier ([`ModelRole`]); choose a **batch** of
//!    [`SurrogateOptions::batch`] designs (the study's parallelism) that maximise the expected
//!    hypervolume improvement times the probability of feasibility; evaluate them in one
//!    `evaluate_batch` call.
//! 3. **Stop** at the budget ([`SurrogateOptions::max_evaluations`], counting the given data), when
//!    the hypervolume has stalled ([`SurrogateOptions::stall_iterations`]), or when the observer
//!    asks. The front is the non-dominated set of the *evaluated* designs, never of predictions.
//!
//! Every iteration is reported to an [`Observer`] as an [`IterationReport`]: the iteration, the
//! batch and its evaluations, the number of evaluations, the hypervolume with its reference point,
//! each model's leave-one-out error, the fit and acquisition times, and the fallback taken if a
//! model could not be fitted.
//!
//! # Choices, and why
//!
//! **Gaussian processes** ([`gp`]): ordinary Kriging with a Matérn 5/2 anisotropic kernel, inputs
//! on the unit box, outputs standardised, length scales and nugget by maximum likelihood
//! (concentrated likelihood, analytic gradient, projected L-BFGS from the previous iteration's
//! optimum, a default start and Sobol' restarts). Matérn 5/2 rather than the squared exponential:
//! twice-differentiable sample paths suit physical responses, and its matrices are far better
//! conditioned (Stein 1999; Snoek, Larochelle & Adams 2012 make the same choice for Bayesian
//! optimisation).
//!
//! **Own implementation on faer rather than `egobox-gp`.** Compared on this machine (2 cores
//! shared with other builds, load about 4, so times are indicative; the comparison program lived
//! outside the workspace and is not kept), fitting Latin hypercubes of `n` points in 6 variables
//! and predicting mean and variance at 1 000 uniform points:
//!
//! | | `egobox-gp` 0.37.1 | own (`gp.rs` on faer) |
//! |---|---|---|
//! | crates added to the build | 38 (ndarray 0.16, linfa, linfa-linalg, linfa-pls, ndarray-stats/-rand/-npy/-einsum, sprs, pest, zip, ...) | none (faer is already the workspace's dense and sparse solver) |
//! | cold release build of the library and its tree | 3 min 14 s wall, 101 s CPU | — |
//! | licence | Apache-2.0 | the project's |
//! | hyper-parameters | COBYLA (no gradient), 10 starts in parallel, nugget fixed at 100 ε | analytic gradient, projected L-BFGS, nugget fitted, warm starts |
//! | mixed variables | in `egobox-ego` (more crates), not in the GP | exchangeable kernel for categoricals, relaxed integers |
//! | leave-one-out, batch conditioning | not provided; refit | closed form; [`GaussianProcess::with_fantasies`] |
//! | Hartmann-6, n = 50 / 100 / 200: fit time | 0.10 / 0.35 / 1.68 s | 0.019 / 0.034 / 0.21 s cold, 0.013 s warm at 200 |
//! | Hartmann-6: test error (RMSE / output sd) | 0.706 / 0.544 / 0.410 | 0.736 / 0.557 / 0.426 |
//! | ZDT1's f2 (6 variables): fit time | 0.04 / 0.22 / 1.14 s | 0.006 / 0.029 / 0.145 s |
//! | ZDT1's f2: test error | 0.020 / 0.0052 / 0.0029 | 0.020 / 0.0102 / 0.0047 |
//! | prediction, 1 000 points, n = 200 | 0.06–0.07 s | 0.004–0.007 s |
//!
//! `egobox-gp` is slightly more accurate on these functions (its separable product of
//! one-dimensional Matérn kernels and ten likelihood starts), at 6 to 10 times the fit time and
//! 10 times the prediction time; it brings a second linear-algebra stack and ~40 crates into a
//! workspace that already has faer, fixes the nugget (a finite-element response with mesh noise
//! needs it fitted), panics on some malformed inputs (theta dimensions), and leaves mixed variables,
//! leave-one-out and batch conditioning to the caller. The Kriging it implements is a few hundred
//! lines here once a Cholesky factorisation is at hand, so the project keeps its own.
//!
//! **Acquisition** (`acquisition.rs`): expected hypervolume improvement (EHVI; Emmerich, Giannakoglou
//! & Naujoks 2006) rather than ParEGO's random Chebyshev scalarisations (Knowles 2006). EHVI
//! rewards exactly what the study reports (the hypervolume of the evaluated front), needs no
//! scalarisation weights, treats concave and disconnected fronts alike (a Chebyshev scalarisation
//! covers them too, but one random direction per design spends evaluations on parts of the front
//! already known), and for the usual two objectives is exact and cheap (a sum over the front's
//! strips). With three or more objectives it is a Monte Carlo mean. Constraints multiply it by the
//! probability of feasibility; before any feasible design is known, that probability alone is
//! maximised. A batch is built by the kriging believer (`search.rs`); with batch 1 this is plain
//! sequential EHVI.
//!
//! **Mixed variables** (`encoding.rs`): an integer variable is *relaxed* — the GP sees its value on
//! the unit box as a continuous feature, which keeps the neighbouring counts correlated (a drum
//! count of 2 predicts 3 better than an independent model per level with a handful of points each)
//! — and every proposed design is rounded before it is scored, so the acquisition is maximised over
//! legal designs only; designs already evaluated score nothing (de-duplication). A categorical
//! variable (a material) enters the kernel through `[a ≠ b]` with one length scale: the exchangeable
//! kernel, the one-hot encoding with a shared length scale, which assumes nothing about an order
//! the levels do not have and costs one hyper-parameter however many levels there are (a full
//! level-by-level correlation matrix, Qian et al. 2008, needs data the initial design of a costly
//! study does not have).
//!
//! **Failures**: an evaluation that failed (infinite violation) trains the feasibility classifier,
//! not the objective models; a model that cannot be fitted (too few points, all outputs equal, a
//! singular kernel) makes that iteration evaluate the next designs of the space-filling sequence
//! instead and says so in [`IterationReport::fallback`]. No NaN leaves this module: predictions are
//! finite, designs are repaired onto the bounds, acquisition values are clamped to `[0, ∞)`.
//!
//! **Cost** (`benches/surrogate_overhead.rs`, 6 variables, 2 objectives + 1 constraint, batch 2;
//! same loaded machine): a fit costs `O(n³)` per likelihood evaluation (Cholesky factor and inverse
//! of the `n × n` correlation matrix), scoring a candidate `O(n²)`. To keep the overhead small:
//! the models are fitted in parallel, the likelihood search is warm-started from the previous
//! iteration (cold multi-start again when a model's data has grown by 25 %), and the
//! hyper-parameters are kept (only the factorisation redone) until the data has grown by
//! [`FitSettings::reoptimise_growth`] (5 %). Measured: a cold iteration (first of a run or of a
//! resumed run) 42 / 92 / 329 ms at 50 / 100 / 200 designs; a warm iteration 19 / 27 / 47 ms; a
//! whole study from its 60-design initial plan to 200 evaluations 3.2 s of overhead, against
//! 100 × `t_eval` of evaluations on two cores: 6 % of the wall time at `t_eval` = 0.5 s, 3 % at 1 s,
//! 1.6 % at 2 s. Beyond [`SurrogateOptions::max_training`] designs (300) each model is trained on
//! the best 300 by constrained non-dominated rank, which bounds the per-iteration cost of longer
//! studies at its 300-design value.
//!
//! # Resuming
//!
//! [`run`] takes the designs evaluated so far ([`EvaluatedDesign`]: a resumed study's stored
//! records) and continues from them: they count towards the budget and the initial design, train
//! the models, and are never evaluated again. Every random choice of an iteration is drawn from a
//! generator seeded by the seed and the number of designs in the data, so a run is a function of
//! its data and settings but for the hyper-parameter search, which a resumed run starts cold where
//! the uninterrupted run starts from the previous iteration's optimum. A run resumed right after its
//! initial design therefore repeats the uninterrupted run exactly
//! (`tests/it/surrogate_driver.rs`); resumed later, it continues from the same data with slightly
//! different models. The explore layer resumes by passing the stored records; nothing else needs
//! storing.
//!
//! # Example
//!
//! ```
//! use mrbrake_observe::Flow;
//! use mrbrake_optim::{FnProblem, pareto::Evaluation, space::Bounds};
//! use mrbrake_optim::surrogate::{self, IterationReport, SurrogateOptions};
//!
//! // Two objectives, x and (1 + y)(1 − √x), on [0, 1]²: the front is y = 0.
//! let mut problem = FnProblem::new(vec![Bounds::continuous(0.0, 1.0); 2], 2, |x: &[f64]| {
//!     Evaluation::new(vec![x[0], (1.0 + x[1]) * (1.0 - x[0].sqrt())], 0.0)
//! });
//! let options = SurrogateOptions {
//!     max_evaluations: 30,
//!     reference: Some(vec![1.1, 2.2]),
//!     ..Default::default()
//! };
//! let mut observer = |report: &IterationReport| {
//!     assert!(report.hypervolume.is_finite());
//!     Flow::Continue
//! };
//! let result = surrogate::run(&mut problem, &options, &[], &mut observer).unwrap();
//! assert_eq!(result.designs.len(), 30);
//! assert!(result.hypervolume > 0.0 && !result.front.is_empty());
//! ```

mod acquisition;
mod encoding;
pub mod gp;
mod local;
mod models;
mod search;
mod settings;

use std::time::Instant;

use mrbrake_observe::Observer;

pub use gp::{FitFailure, FitSettings, GaussianProcess, Hyperparameters, Prediction};
pub use models::{Fallback, ModelFit, ModelRole};
pub use settings::{Acquisition, InitialPlan, SurrogateOptions};

use crate::pareto::{Evaluation, hypervolume, non_dominated_sort, pareto_front};
use crate::problem::{check_batch, evaluate_checked};
use crate::rng::Rng;
use crate::sampling::{MAX_SOBOL_DIMENSION, latin_hypercube, sobol_unit};
use crate::space::{Bounds, validate_design};
use crate::{Problem, RunError};
use acquisition::Acquirer;
use encoding::Encoding;
use models::{Models, WarmStarts};

/// A design and its evaluation.
#[derive(Debug, Clone, PartialEq)]
pub struct EvaluatedDesign {
    /// The design variables.
    pub x: Vec<f64>,
    /// Its evaluation.
    pub evaluation: Evaluation,
}

/// What the observer sees after the initial design (iteration 0) and after every iteration.
#[derive(Debug, Clone, PartialEq)]
pub struct IterationReport {
    /// 0 for the initial design, then 1, 2, ...
    pub iteration: usize,
    /// The designs evaluated in this iteration, with their evaluations.
    pub batch: Vec<EvaluatedDesign>,
    /// Designs in the data after this iteration (the given ones included).
    pub evaluations: usize,
    /// Hypervolume of the evaluated feasible front below [`IterationReport::reference`] (0 while
    /// there is no reference or no feasible design).
    pub hypervolume: f64,
    /// The hypervolume's reference point, once fixed.
    pub reference: Option<Vec<f64>>,
    /// Each model's fit (empty for the initial design and for a fallback iteration).
    pub models: Vec<ModelFit>,
    /// The acquisition value of each batch member when it was chosen (empty when none was used).
    pub acquisition: Vec<f64>,
    /// Set when a model could not be fitted and the batch is space-filling instead.
    pub fallback: Option<Fallback>,
    /// Wall time of the model fits, in seconds.
    pub fit_seconds: f64,
    /// Wall time of the batch selection, in seconds.
    pub acquisition_seconds: f64,
}

/// Why a run stopped.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StopReason {
    /// [`SurrogateOptions::max_evaluations`] designs are in the data.
    Budget,
    /// The hypervolume stalled ([`SurrogateOptions::stall_iterations`]).
    Stall,
    /// The observer returned [`mrbrake_observe::Flow::Stop`].
    Observer,
    /// Every design the search could propose has been evaluated (a small discrete space).
    Exhausted,
}

/// The hypervolume after an iteration.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HypervolumePoint {
    /// The iteration (0 = initial design).
    pub iteration: usize,
    /// Designs in the data.
    pub evaluations: usize,
    /// The hypervolume (0 before the reference is fixed).
    pub hypervolume: f64,
}

/// The outcome of a surrogate-assisted run.
#[derive(Debug, Clone, PartialEq)]
pub struct SurrogateResult {
    /// Every design in the data, in order: the given ones, then those evaluated by this run.
    pub designs: Vec<EvaluatedDesign>,
    /// Indices into `designs` of the Pareto front of the evaluated designs
    /// ([`crate::pareto::pareto_front`]).
    pub front: Vec<usize>,
    /// The hypervolume's reference point (`None` if no feasible design was found).
    pub reference: Option<Vec<f64>>,
    /// The front's hypervolume.
    pub hypervolume: f64,
    /// The hypervolume after every iteration.
    pub trace: Vec<HypervolumePoint>,
    /// Iterations after the initial design.
    pub iterations: usize,
    /// Why the run stopped.
    pub stop: StopReason,
}

/// Runs the surrogate-assisted optimisation on `problem`, continuing from `previous` (designs
/// already evaluated, e.g. a resumed study's records), reporting every iteration to `observer`.
///
/// Errors: [`RunError::Optim`] for invalid options, bounds or previous designs, or an evaluator
/// that breaks the [`Problem::evaluate_batch`] contract; [`RunError::Problem`] with the evaluator's
/// own error, unchanged. A model that cannot be fitted is not an error (module docs).
pub fn run<P: Problem>(
    problem: &mut P,
    options: &SurrogateOptions,
    previous: &[EvaluatedDesign],
    observer: &mut impl Observer<IterationReport>,
) -> Result<SurrogateResult, RunError<P::Error>> {
    let bounds = problem.bounds().to_vec();
    let objectives = problem.objectives();
    options.validate(&bounds, objectives)?;
    for (k, design) in previous.iter().enumerate() {
        validate_design(&bounds, &design.x, &format!("previous design {k}"))?;
    }
    let evaluations: Vec<Evaluation> = previous.iter().map(|d| d.evaluation.clone()).collect();
    check_batch(previous.len(), objectives, &evaluations)?;
    let mut driver = Driver::new(bounds, objectives, options, previous.to_vec());

    let initial = driver.initial_design();
    let mut report = driver.evaluate(problem, 0, initial)?;
    let mut iteration = 0;
    let stop = loop {
        if observer.observe(&report).is_stop() {
            break StopReason::Observer;
        }
        if driver.data.len() >= options.max_evaluations {
            break StopReason::Budget;
        }
        if driver.stalled() {
            break StopReason::Stall;
        }
        iteration += 1;
        let batch = options.batch.min(options.max_evaluations - driver.data.len());
        let mut step = driver.propose(batch);
        // A small discrete space can run out of designs: never evaluate one twice.
        let fresh = driver.unseen(step.proposals.iter().map(|p| p.x.clone()).collect());
        step.proposals.retain(|p| fresh.contains(&p.x));
        step.proposals.dedup_by(|a, b| a.x == b.x);
        if step.proposals.is_empty() {
            iteration -= 1;
            break StopReason::Exhausted;
        }
        report = driver.evaluate(problem, iteration, fresh)?;
        report.acquisition = step.proposals.iter().map(|p| p.acquisition).collect();
        (report.models, report.fallback) = (step.models, step.fallback);
        (report.fit_seconds, report.acquisition_seconds) =
            (step.fit_seconds, step.acquisition_seconds);
    };
    Ok(driver.finish(iteration, stop))
}

/// The designs chosen by one iteration and how they were chosen.
struct Step {
    proposals: Vec<search::Proposal>,
    models: Vec<ModelFit>,
    fallback: Option<Fallback>,
    fit_seconds: f64,
    acquisition_seconds: f64,
}

/// The state of a run: its data, reference point, hypervolume trace and warm starts.
struct Driver<'o> {
    options: &'o SurrogateOptions,
    bounds: Vec<Bounds>,
    objectives: usize,
    encoding: Encoding,
    data: Vec<EvaluatedDesign>,
    reference: Option<Vec<f64>>,
    trace: Vec<HypervolumePoint>,
    warm: WarmStarts,
}

impl<'o> Driver<'o> {
    fn new(
        bounds: Vec<Bounds>,
        objectives: usize,
        options: &'o SurrogateOptions,
        data: Vec<EvaluatedDesign>,
    ) -> Self {
        let encoding = Encoding::new(&bounds);
        let reference = options.reference.clone();
        Self {
            options,
            bounds,
            objectives,
            encoding,
            data,
            reference,
            trace: Vec::new(),
            warm: WarmStarts::default(),
        }
    }

    /// The generator of the iteration that starts with `data.len()` designs (module docs).
    fn rng(&self) -> Rng {
        Rng::new(self.options.seed ^ (self.data.len() as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15))
    }

    /// The initial plan's designs not yet in the data, as many as it takes to bring the data to
    /// the plan's size (the given designs count towards it), cut to the budget.
    fn initial_design(&self) -> Vec<Vec<f64>> {
        let size = self.options.initial_design_size(self.bounds.len());
        if self.data.len() >= size {
            return Vec::new();
        }
        let plan = match self.options.initial_plan {
            InitialPlan::Sobol if self.bounds.len() <= MAX_SOBOL_DIMENSION => {
                self.sobol_designs(size)
            }
            _ => latin_hypercube(size, &self.bounds, &mut Rng::new(self.options.seed)),
        };
        let room = self.options.max_evaluations.min(size).saturating_sub(self.data.len());
        self.unseen(plan).into_iter().take(room).collect()
    }

    /// The first `count` points of the run's shifted Sobol' sequence, as designs.
    fn sobol_designs(&self, count: usize) -> Vec<Vec<f64>> {
        let mut rng = Rng::new(self.options.seed);
        let shift: Vec<f64> = self.bounds.iter().map(|_| rng.uniform()).collect();
        let unit = sobol_unit(count, self.bounds.len()).unwrap_or_default();
        unit.iter()
            .map(|u| {
                u.iter()
                    .zip(&shift)
                    .zip(&self.bounds)
                    .map(|((u, s), b)| b.from_unit((u + s).fract()))
                    .collect()
            })
            .collect()
    }

    /// `count` space-filling designs not yet in the data, for a fallback iteration: the Sobol'
    /// sequence continued (a Latin hypercube beyond 32 variables).
    fn space_filling(&self, count: usize) -> Vec<Vec<f64>> {
        let designs = if self.bounds.len() <= MAX_SOBOL_DIMENSION {
            let initial = self.options.initial_design_size(self.bounds.len());
            self.sobol_designs(initial + self.data.len() + count)
        } else {
            latin_hypercube(count, &self.bounds, &mut self.rng())
        };
        let mut chosen = self.unseen(designs);
        chosen.truncate(count);
        chosen
    }

    /// `designs` without those already in the data or repeated (bit-for-bit equal).
    fn unseen(&self, designs: Vec<Vec<f64>>) -> Vec<Vec<f64>> {
        let same = |a: &[f64], b: &[f64]| a.iter().zip(b).all(|(x, y)| x.total_cmp(y).is_eq());
        let mut out: Vec<Vec<f64>> = Vec::with_capacity(designs.len());
        for x in designs {
            if !self.data.iter().any(|d| same(&d.x, &x)) && !out.iter().any(|o| same(o, &x)) {
                out.push(x);
            }
        }
        out
    }

    /// Fits the models and chooses `batch` designs (or space-filling ones if a fit fails).
    fn propose(&mut self, batch: usize) -> Step {
        let started = Instant::now();
        let fitted = Models::fit(
            &self.data,
            self.objectives,
            &self.encoding,
            &self.options.fit,
            self.options.max_training,
            &mut self.warm,
        );
        let fit_seconds = started.elapsed().as_secs_f64();
        let started = Instant::now();
        let (models, fits) = match fitted {
            Ok(fitted) => fitted,
            Err(fallback) => {
                let proposals = self
                    .space_filling(batch)
                    .into_iter()
                    .map(|x| search::Proposal { x, acquisition: 0.0 })
                    .collect();
                let acquisition_seconds = started.elapsed().as_secs_f64();
                return Step {
                    proposals,
                    models: Vec::new(),
                    fallback: Some(fallback),
                    fit_seconds,
                    acquisition_seconds,
                };
            }
        };
        let evaluations = self.evaluations();
        let front: Vec<usize> = pareto_front(&evaluations);
        let front_objectives: Vec<Vec<f64>> =
            front.iter().map(|&i| evaluations[i].objectives.clone()).collect();
        let acquirer = Acquirer::new(
            &front_objectives,
            self.acquisition_reference(&front_objectives).as_deref(),
        );
        // Local candidates around the best designs under constrained domination: the front, or the
        // least-violating designs while none is feasible.
        let best = non_dominated_sort(&evaluations).into_iter().next().unwrap_or_default();
        let best_features: Vec<Vec<f64>> =
            best.iter().map(|&i| self.encoding.encode(&self.data[i].x)).collect();
        let evaluated: Vec<Vec<f64>> =
            self.data.iter().map(|d| self.encoding.encode(&d.x)).collect();
        let mut rng = self.rng();
        let proposals = search::propose_batch(
            models,
            acquirer,
            &self.encoding,
            &evaluated,
            &best_features,
            batch,
            self.options.candidates,
            &mut rng,
        );
        let acquisition_seconds = started.elapsed().as_secs_f64();
        Step { proposals, models: fits, fallback: None, fit_seconds, acquisition_seconds }
    }

    /// The reference point of the acquisition: the report's, widened where the current front
    /// reaches beyond it (so the front's designs always count), `None` while nothing is feasible.
    fn acquisition_reference(&self, front: &[Vec<f64>]) -> Option<Vec<f64>> {
        let reference = self.reference.as_ref()?;
        if front.is_empty() {
            return None;
        }
        let points: Vec<&[f64]> = front.iter().map(Vec::as_slice).collect();
        let beyond = beyond_worst(&points, self.objectives);
        Some(reference.iter().zip(beyond).map(|(r, b)| r.max(b)).collect())
    }

    /// Evaluates `designs` (in one batch), adds them to the data and reports the iteration.
    fn evaluate<P: Problem>(
        &mut self,
        problem: &mut P,
        iteration: usize,
        designs: Vec<Vec<f64>>,
    ) -> Result<IterationReport, RunError<P::Error>> {
        let evaluations =
            if designs.is_empty() { Vec::new() } else { evaluate_checked(problem, &designs)? };
        let batch: Vec<EvaluatedDesign> = designs
            .into_iter()
            .zip(evaluations)
            .map(|(x, evaluation)| EvaluatedDesign { x, evaluation })
            .collect();
        self.data.extend(batch.iter().cloned());
        self.fix_reference();
        let hypervolume = self.hypervolume();
        self.trace.push(HypervolumePoint { iteration, evaluations: self.data.len(), hypervolume });
        Ok(IterationReport {
            iteration,
            batch,
            evaluations: self.data.len(),
            hypervolume,
            reference: self.reference.clone(),
            models: Vec::new(),
            acquisition: Vec::new(),
            fallback: None,
            fit_seconds: 0.0,
            acquisition_seconds: 0.0,
        })
    }

    /// Fixes the reference point from the feasible designs, the first time there are any (option
    /// docs).
    fn fix_reference(&mut self) {
        if self.reference.is_some() {
            return;
        }
        let feasible: Vec<&[f64]> = self
            .data
            .iter()
            .filter(|d| {
                d.evaluation.feasible() && d.evaluation.objectives.iter().all(|v| v.is_finite())
            })
            .map(|d| d.evaluation.objectives.as_slice())
            .collect();
        if !feasible.is_empty() {
            self.reference = Some(beyond_worst(&feasible, self.objectives));
        }
    }

    /// The evaluations of the data, in order.
    fn evaluations(&self) -> Vec<Evaluation> {
        self.data.iter().map(|d| d.evaluation.clone()).collect()
    }

    /// The hypervolume of the evaluated front (0 without a reference).
    fn hypervolume(&self) -> f64 {
        let Some(reference) = &self.reference else { return 0.0 };
        let evaluations = self.evaluations();
        let points: Vec<Vec<f64>> =
            pareto_front(&evaluations).iter().map(|&i| evaluations[i].objectives.clone()).collect();
        hypervolume(&points, reference)
    }

    /// True when the hypervolume grew by at most the tolerance over the last `stall_iterations`
    /// iterations (never before a feasible design is known).
    fn stalled(&self) -> bool {
        let window = self.options.stall_iterations;
        if window == 0 || self.trace.len() <= window {
            return false;
        }
        let now = self.trace[self.trace.len() - 1].hypervolume;
        let then = self.trace[self.trace.len() - 1 - window].hypervolume;
        now > 0.0 && now - then <= self.options.stall_tolerance * now
    }

    fn finish(self, iterations: usize, stop: StopReason) -> SurrogateResult {
        let evaluations = self.evaluations();
        let front = pareto_front(&evaluations);
        let hypervolume = self.hypervolume();
        SurrogateResult {
            designs: self.data,
            front,
            reference: self.reference,
            hypervolume,
            trace: self.trace,
            iterations,
            stop,
        }
    }
}

/// In each objective, 10 % of the points' range beyond their worst value (a small positive width
/// when the range is degenerate): the reference-point rule of Ishibuchi et al. (2018), the default
/// of [`SurrogateOptions::reference`]. Public so that a study measures other algorithms' runs with
/// the same rule.
pub fn beyond_worst(points: &[&[f64]], objectives: usize) -> Vec<f64> {
    (0..objectives)
        .map(|j| {
            let worst = points.iter().map(|p| p[j]).fold(f64::NEG_INFINITY, f64::max);
            let best = points.iter().map(|p| p[j]).fold(f64::INFINITY, f64::min);
            worst + 0.1 * (worst - best).max((worst.abs() * 1e-3).max(1e-12))
        })
        .collect()
}
