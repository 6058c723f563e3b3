//! The Gaussian processes of one iteration: one per objective, one per constraint, and a
//! feasibility classifier for what the constraint models cannot see.
//!
//! * Objective `j` is modelled on every design whose objectives are all finite (feasible or not:
//!   an infeasible design still shows how the objectives vary).
//! * Constraint `k` is modelled on the designs that report per-constraint values
//!   ([`Evaluation::constraints`], signed, satisfied when `<= 0`); the probability that a design
//!   satisfies it is `Φ(−μ_k / s_k)` (Schonlau, Welch & Jones 1998, "Global versus local search in
//!   constrained optimization of computer models", IMS Lecture Notes 34, 11–25; Gardner et al.
//!   2014, "Bayesian optimization with inequality constraints", ICML).
//! * The classifier learns the designs no constraint model describes: those that *failed* (no
//!   values at all), and, when the evaluator reports only a total violation, every infeasible design.
//!   It is a Gaussian process on labels −1 (good) / +1 (failed or infeasible), the least-squares
//!   classifier of Rasmussen & Williams (2006, Sec. 6.5), read as a probability by `Φ(−μ / s)`. It is
//!   fitted only when both labels occur. So a failed evaluation is an infeasible point the models
//!   learn from, never a crash.
//!
//! The probability of feasibility is the product over the models (constraints assumed independent,
//! as in the references above). A constraint whose value is the same, and satisfied, at every
//! design of the data (a limit no variable moves, e.g. the current against the wire's rating when
//! neither is a variable) has no model: its probability is 1. Every other model that cannot be
//! fitted makes the iteration fall back to space-filling designs.

use std::collections::HashMap;
use std::fmt;

use rayon::prelude::*;

use super::EvaluatedDesign;
use super::encoding::Encoding;
use super::gp::{FitFailure, FitSettings, GaussianProcess, Hyperparameters, Prediction};
use crate::pareto::{Evaluation, non_dominated_sort};

/// Which quantity a model describes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ModelRole {
    /// Objective `j` (0-based).
    Objective(usize),
    /// Constraint `k` (0-based, in the order of [`Evaluation::constraints`]).
    Constraint(usize),
    /// The classifier of failed (or, without constraint values, infeasible) designs.
    Feasibility,
}

impl fmt::Display for ModelRole {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Objective(j) => write!(f, "objective {}", j + 1),
            Self::Constraint(k) => write!(f, "constraint {}", k + 1),
            Self::Feasibility => write!(f, "feasibility classifier"),
        }
    }
}

/// How well one model fits its data.
#[derive(Debug, Clone, PartialEq)]
pub struct ModelFit {
    /// What it models.
    pub role: ModelRole,
    /// Training points.
    pub points: usize,
    /// Root-mean-square leave-one-out residual over the outputs' standard deviation (0 perfect,
    /// about 1 no better than the mean; [`GaussianProcess::loo_error`]).
    pub loo_error: f64,
    /// The fitted length scales and nugget.
    pub hyperparameters: Hyperparameters,
}

/// A model that could not be fitted: the iteration evaluates space-filling designs instead.
#[derive(Debug, Clone, PartialEq)]
pub struct Fallback {
    /// The model that failed.
    pub role: ModelRole,
    /// Why.
    pub reason: FitFailure,
}

impl fmt::Display for Fallback {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{} model not fitted ({}): space-filling designs instead", self.role, self.reason)
    }
}

/// Every model's prediction at one candidate, and the probability that it is feasible.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct CandidatePrediction {
    pub objectives: Vec<Prediction>,
    pub constraints: Vec<Prediction>,
    pub classifier: Option<Prediction>,
    pub feasibility: f64,
}

/// The fitted models of one iteration.
#[derive(Debug, Clone)]
pub(crate) struct Models {
    objectives: Vec<GaussianProcess>,
    constraints: Vec<GaussianProcess>,
    classifier: Option<GaussianProcess>,
}

/// Hyper-parameters of the previous fit of each model, with the training-set sizes of its last
/// cold (multi-start) search and of its last optimisation: what the next fit starts from.
#[derive(Debug, Clone, Default)]
pub(crate) struct WarmStarts {
    previous: HashMap<ModelRole, Previous>,
}

#[derive(Debug, Clone)]
struct Previous {
    hyper: Hyperparameters,
    cold_points: usize,
    optimised_points: usize,
}

/// How a model's hyper-parameters are found this iteration.
enum Start<'a> {
    /// Multi-start likelihood search (first fit, or the data grew by [`COLD_AGAIN`]).
    Cold,
    /// One local search from the previous optimum.
    Warm(&'a Hyperparameters),
    /// The previous optimum as it is (the data grew by less than `reoptimise_growth`).
    Kept(&'a Hyperparameters),
}

/// A model is searched cold again (multi-start) once its data has grown by this factor since the
/// last cold search, so an early local optimum is not kept for the whole run.
const COLD_AGAIN: f64 = 1.25;

impl WarmStarts {
    fn start(&self, role: ModelRole, points: usize, settings: &FitSettings) -> Start<'_> {
        let Some(previous) = self.previous.get(&role) else { return Start::Cold };
        let grown = |since: usize, factor: f64| points as f64 > factor * since as f64;
        if grown(previous.cold_points, COLD_AGAIN) {
            Start::Cold
        } else if grown(previous.optimised_points, 1.0 + settings.reoptimise_growth) {
            Start::Warm(&previous.hyper)
        } else {
            Start::Kept(&previous.hyper)
        }
    }

    /// Keeps a fit's hyper-parameters and the sizes at which they were searched.
    fn record(
        &mut self,
        role: ModelRole,
        hyper: &Hyperparameters,
        points: usize,
        settings: &FitSettings,
    ) {
        let previous = self.previous.get(&role);
        let (cold_points, optimised_points) = match self.start(role, points, settings) {
            Start::Cold => (points, points),
            Start::Warm(_) => (previous.map_or(points, |p| p.cold_points), points),
            Start::Kept(_) => {
                previous.map_or((points, points), |p| (p.cold_points, p.optimised_points))
            }
        };
        self.previous
            .insert(role, Previous { hyper: hyper.clone(), cold_points, optimised_points });
    }
}

impl Models {
    /// Fits every model to `data` (at most `max_training` designs, chosen by [`training_subset`]),
    /// the models in parallel (the cores are idle between batches).
    pub fn fit(
        data: &[EvaluatedDesign],
        objectives: usize,
        encoding: &Encoding,
        settings: &FitSettings,
        max_training: usize,
        warm: &mut WarmStarts,
    ) -> Result<(Self, Vec<ModelFit>), Fallback> {
        let chosen = training_subset(data, max_training);
        let features: Vec<Vec<f64>> = chosen.iter().map(|d| encoding.encode(&d.x)).collect();
        let evaluations: Vec<&Evaluation> = chosen.iter().map(|d| &d.evaluation).collect();
        let jobs = training_sets(&evaluations, objectives);
        let fitted: Vec<Result<(GaussianProcess, f64), Fallback>> = jobs
            .par_iter()
            .map(|(role, rows)| {
                let inputs: Vec<Vec<f64>> =
                    rows.iter().map(|&(i, _)| features[i].clone()).collect();
                let outputs: Vec<f64> = rows.iter().map(|&(_, v)| v).collect();
                let categorical = encoding.categorical();
                match warm.start(*role, rows.len(), settings) {
                    Start::Cold => {
                        GaussianProcess::fit(&inputs, &outputs, categorical, settings, None)
                    }
                    Start::Warm(h) => {
                        GaussianProcess::fit(&inputs, &outputs, categorical, settings, Some(h))
                    }
                    Start::Kept(h) => GaussianProcess::with_hyperparameters(
                        &inputs,
                        &outputs,
                        categorical,
                        h.clone(),
                    ),
                }
                .and_then(|gp| {
                    let loo = gp.loo_error();
                    if loo.is_finite() { Ok((gp, loo)) } else { Err(FitFailure::Singular) }
                })
                .map_err(|reason| Fallback { role: *role, reason })
            })
            .collect();
        let mut models = Self { objectives: Vec::new(), constraints: Vec::new(), classifier: None };
        let mut fits = Vec::with_capacity(jobs.len());
        for ((role, _), gp) in jobs.iter().zip(fitted) {
            let (gp, loo_error) = match gp {
                Err(fallback) if always_satisfied(&fallback) => continue,
                other => other?,
            };
            warm.record(*role, gp.hyperparameters(), gp.len(), settings);
            let hyperparameters = gp.hyperparameters().clone();
            fits.push(ModelFit { role: *role, points: gp.len(), loo_error, hyperparameters });
            match role {
                ModelRole::Objective(_) => models.objectives.push(gp),
                ModelRole::Constraint(_) => models.constraints.push(gp),
                ModelRole::Feasibility => models.classifier = Some(gp),
            }
        }
        Ok((models, fits))
    }

    /// Every model's prediction at each candidate (features), in parallel over blocks of
    /// candidates.
    pub fn predict(&self, points: &[Vec<f64>]) -> Vec<CandidatePrediction> {
        const BLOCK: usize = 128;
        points.par_chunks(BLOCK).flat_map_iter(|block| self.predict_block(block)).collect()
    }

    fn predict_block(&self, points: &[Vec<f64>]) -> Vec<CandidatePrediction> {
        let predict_all = |models: &[GaussianProcess]| -> Vec<Vec<Prediction>> {
            models.iter().map(|gp| gp.predict(points)).collect()
        };
        let objectives = predict_all(&self.objectives);
        let constraints = predict_all(&self.constraints);
        let classifier = self.classifier.as_ref().map(|gp| gp.predict(points));
        (0..points.len())
            .map(|c| {
                let constraints: Vec<Prediction> = constraints.iter().map(|p| p[c]).collect();
                let classifier = classifier.as_ref().map(|p| p[c]);
                let feasibility =
                    constraints.iter().chain(&classifier).map(probability_not_positive).product();
                CandidatePrediction {
                    objectives: objectives.iter().map(|p| p[c]).collect(),
                    constraints,
                    classifier,
                    feasibility,
                }
            })
            .collect()
    }

    /// The models conditioned on their own predicted means at `point` (kriging believer).
    pub fn with_fantasy(
        &self,
        point: &[f64],
        prediction: &CandidatePrediction,
    ) -> Result<Self, FitFailure> {
        let point = [point.to_vec()];
        let believe = |gp: &GaussianProcess, p: &Prediction| gp.with_fantasies(&point, &[p.mean]);
        Ok(Self {
            objectives: self
                .objectives
                .iter()
                .zip(&prediction.objectives)
                .map(|(g, p)| believe(g, p))
                .collect::<Result<_, _>>()?,
            constraints: self
                .constraints
                .iter()
                .zip(&prediction.constraints)
                .map(|(g, p)| believe(g, p))
                .collect::<Result<_, _>>()?,
            classifier: match (&self.classifier, &prediction.classifier) {
                (Some(g), Some(p)) => Some(believe(g, p)?),
                _ => None,
            },
        })
    }
}

/// True when `fallback` is a constraint whose every value in the data is the same and satisfied
/// (module docs): no model is needed, its probability of feasibility is 1.
fn always_satisfied(fallback: &Fallback) -> bool {
    matches!(
        (fallback.role, &fallback.reason),
        (ModelRole::Constraint(_), FitFailure::ConstantOutput { value, .. }) if *value <= 0.0
    )
}

/// Each model's training rows `(index into evaluations, output)`: objectives, constraints, then the
/// classifier's labels (only when both labels occur; module docs).
fn training_sets(
    evaluations: &[&Evaluation],
    objectives: usize,
) -> Vec<(ModelRole, Vec<(usize, f64)>)> {
    let evaluated = |e: &Evaluation| e.objectives.iter().all(|v| v.is_finite());
    let constraint_count = evaluations.iter().map(|e| e.constraints.len()).find(|&c| c > 0);
    let mut jobs = Vec::new();
    for j in 0..objectives {
        let rows = evaluations.iter().enumerate().filter(|(_, e)| evaluated(e));
        jobs.push((ModelRole::Objective(j), rows.map(|(i, e)| (i, e.objectives[j])).collect()));
    }
    let count = constraint_count.unwrap_or(0);
    for k in 0..count {
        let rows = evaluations.iter().enumerate().filter_map(|(i, e)| {
            let value = *e.constraints.get(k)?;
            (e.constraints.len() == count && value.is_finite()).then_some((i, value))
        });
        jobs.push((ModelRole::Constraint(k), rows.collect()));
    }
    let labels: Vec<(usize, f64)> = evaluations
        .iter()
        .enumerate()
        .map(|(i, e)| {
            let bad = if count > 0 {
                !e.violation.is_finite() || e.constraints.len() != count || !evaluated(e)
            } else {
                !e.feasible()
            };
            (i, if bad { 1.0 } else { -1.0 })
        })
        .collect();
    if labels.iter().any(|l| l.1 > 0.0) && labels.iter().any(|l| l.1 < 0.0) {
        jobs.push((ModelRole::Feasibility, labels));
    }
    jobs
}

/// `P(Y <= 0)` for `Y ~ N(μ, s²)`; a step when `s = 0`.
fn probability_not_positive(p: &Prediction) -> f64 {
    if p.sd > 0.0 {
        super::acquisition::normal_cdf(-p.mean / p.sd)
    } else if p.mean <= 0.0 {
        1.0
    } else {
        0.0
    }
}

/// The designs the models are trained on: all of them up to `max_training`; beyond, the best by
/// constrained non-dominated rank (Deb et al. 2002), ties in the last rank taken in evaluation
/// order — the region of the design space where the next designs will be chosen keeps its data.
pub(crate) fn training_subset(
    data: &[EvaluatedDesign],
    max_training: usize,
) -> Vec<&EvaluatedDesign> {
    if data.len() <= max_training {
        return data.iter().collect();
    }
    let evaluations: Vec<Evaluation> = data.iter().map(|d| d.evaluation.clone()).collect();
    let mut chosen: Vec<usize> =
        non_dominated_sort(&evaluations).into_iter().flatten().take(max_training).collect();
    chosen.sort_unstable();
    chosen.into_iter().map(|i| &data[i]).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::space::Bounds;

    /// A constraint satisfied by the same margin everywhere has no model; one violated everywhere
    /// by the same amount still falls back.
    #[test]
    fn a_constant_satisfied_constraint_needs_no_model() {
        let data = |margin: f64| -> Vec<EvaluatedDesign> {
            (0..8)
                .map(|i| {
                    let x = i as f64 / 7.0;
                    let evaluation = Evaluation::new(vec![x, (1.0 - x).powi(2)], margin.max(0.0))
                        .with_constraints(vec![0.3 - x, margin]);
                    EvaluatedDesign { x: vec![x], evaluation }
                })
                .collect()
        };
        let encoding = Encoding::new(&[Bounds::continuous(0.0, 1.0)]);
        let fit = |d: &[EvaluatedDesign]| {
            Models::fit(d, 2, &encoding, &FitSettings::default(), 300, &mut WarmStarts::default())
        };
        let (models, fits) = fit(&data(-0.05)).expect("the constant constraint is not a failure");
        assert_eq!(models.constraints.len(), 1);
        assert!(fits.iter().all(|f| f.role != ModelRole::Constraint(1)), "{fits:?}");
        // The modelled constraint `0.3 − x ≤ 0` is broken at x = 0.1 and met at x = 0.9.
        let predictions = models.predict(&[vec![0.1], vec![0.9]]);
        assert!(predictions[1].feasibility > predictions[0].feasibility, "{predictions:?}");
        let error = fit(&data(0.05)).unwrap_err();
        assert_eq!(error.role, ModelRole::Constraint(1));
    }
}
