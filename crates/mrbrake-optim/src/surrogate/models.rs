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
//! as in the references above).

use std::collections::HashMap;
use std::fmt;

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

/// Hyper-parameters of the previous fit of each model, to start the next search from.
pub(crate) type WarmStarts = HashMap<ModelRole, Hyperparameters>;

impl Models {
    /// Fits every model to `data` (at most `max_training` designs, chosen by [`training_subset`]).
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
        let constraint_count = evaluations.iter().map(|e| e.constraints.len()).find(|&c| c > 0);
        let mut fits = Vec::new();
        let mut fit_one = |role: ModelRole, rows: Vec<(usize, f64)>| {
            let inputs: Vec<Vec<f64>> = rows.iter().map(|&(i, _)| features[i].clone()).collect();
            let outputs: Vec<f64> = rows.iter().map(|&(_, v)| v).collect();
            let fallback = |reason| Fallback { role, reason };
            let gp = GaussianProcess::fit(
                &inputs,
                &outputs,
                encoding.categorical(),
                settings,
                warm.get(&role),
            )
            .map_err(fallback)?;
            let loo_error = gp.loo_error();
            if !loo_error.is_finite() {
                return Err(fallback(FitFailure::Singular));
            }
            warm.insert(role, gp.hyperparameters().clone());
            fits.push(ModelFit {
                role,
                points: gp.len(),
                loo_error,
                hyperparameters: gp.hyperparameters().clone(),
            });
            Ok(gp)
        };
        let evaluated = |e: &Evaluation| e.objectives.iter().all(|v| v.is_finite());
        let objective_models = (0..objectives)
            .map(|j| {
                let rows = evaluations.iter().enumerate().filter(|(_, e)| evaluated(e));
                fit_one(ModelRole::Objective(j), rows.map(|(i, e)| (i, e.objectives[j])).collect())
            })
            .collect::<Result<Vec<_>, _>>()?;
        let constraint_models = (0..constraint_count.unwrap_or(0))
            .map(|k| {
                let rows = evaluations.iter().enumerate().filter_map(|(i, e)| {
                    let value = *e.constraints.get(k)?;
                    (e.constraints.len() == constraint_count.unwrap_or(0) && value.is_finite())
                        .then_some((i, value))
                });
                fit_one(ModelRole::Constraint(k), rows.collect())
            })
            .collect::<Result<Vec<_>, _>>()?;
        let labels: Vec<(usize, f64)> = evaluations
            .iter()
            .enumerate()
            .map(|(i, e)| {
                let bad = if constraint_count.is_some() {
                    !e.violation.is_finite() || e.constraints.is_empty() || !evaluated(e)
                } else {
                    !e.feasible()
                };
                (i, if bad { 1.0 } else { -1.0 })
            })
            .collect();
        let both = labels.iter().any(|l| l.1 > 0.0) && labels.iter().any(|l| l.1 < 0.0);
        let classifier = if both { Some(fit_one(ModelRole::Feasibility, labels)?) } else { None };
        let models =
            Self { objectives: objective_models, constraints: constraint_models, classifier };
        Ok((models, fits))
    }

    /// Every model's prediction at each candidate (features).
    pub fn predict(&self, points: &[Vec<f64>]) -> Vec<CandidatePrediction> {
        let objectives: Vec<Vec<Prediction>> =
            self.objectives.iter().map(|gp| gp.predict(points)).collect();
        let constraints: Vec<Vec<Prediction>> =
            self.constraints.iter().map(|gp| gp.predict(points)).collect();
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
