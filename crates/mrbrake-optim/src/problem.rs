//! The [`Problem`] an optimiser works on: bounds, number of objectives, and a batch evaluator.
//!
//! Optimisers hand the evaluator whole batches (one NSGA-II generation, one pattern-search poll) so
//! the caller can run expensive FEA evaluations in parallel and serve repeated designs from a cache.

use std::convert::Infallible;

use crate::OptimError;
use crate::pareto::Evaluation;
use crate::space::Bounds;

/// A constrained, possibly multi-objective, minimisation problem over a box of continuous and
/// integer variables.
pub trait Problem {
    /// The evaluator's own error; optimisers return it unchanged in
    /// [`RunError::Problem`](crate::RunError::Problem).
    type Error;

    /// One entry per design variable.
    fn bounds(&self) -> &[Bounds];

    /// Number of objectives (all minimised).
    fn objectives(&self) -> usize;

    /// Evaluates a batch of designs (the caller runs it in parallel and may take stored results from
    /// a cache). Must return one [`Evaluation`] per design, in order. A design that cannot be
    /// evaluated (invalid geometry) is reported as an evaluation with infinite violation
    /// ([`Evaluation::failed`]), not as an error; an error aborts the optimisation.
    fn evaluate_batch(&mut self, xs: &[Vec<f64>]) -> Result<Vec<Evaluation>, Self::Error>;
}

/// A [`Problem`] from bounds and a function evaluating one design at a time, serially. Handy for
/// tests, examples and cheap analytic problems.
///
/// ```
/// use mrbrake_optim::{FnProblem, pareto::Evaluation, space::Bounds};
/// let sphere = FnProblem::new(vec![Bounds::continuous(-1.0, 1.0); 2], 1, |x: &[f64]| {
///     Evaluation::new(vec![x.iter().map(|v| v * v).sum()], 0.0)
/// });
/// # let _ = sphere;
/// ```
pub struct FnProblem<F> {
    bounds: Vec<Bounds>,
    objectives: usize,
    function: F,
    evaluations: usize,
}

impl<F: FnMut(&[f64]) -> Evaluation> FnProblem<F> {
    /// A problem over `bounds` with `objectives` objectives, evaluated by `function`.
    pub fn new(bounds: Vec<Bounds>, objectives: usize, function: F) -> Self {
        Self { bounds, objectives, function, evaluations: 0 }
    }

    /// How many designs have been evaluated so far.
    pub fn evaluations(&self) -> usize {
        self.evaluations
    }
}

impl<F: FnMut(&[f64]) -> Evaluation> Problem for FnProblem<F> {
    type Error = Infallible;

    fn bounds(&self) -> &[Bounds] {
        &self.bounds
    }

    fn objectives(&self) -> usize {
        self.objectives
    }

    fn evaluate_batch(&mut self, xs: &[Vec<f64>]) -> Result<Vec<Evaluation>, Infallible> {
        self.evaluations += xs.len();
        Ok(xs.iter().map(|x| (self.function)(x)).collect())
    }
}

/// Checks an evaluator's answer against the [`Problem::evaluate_batch`] contract: one evaluation per
/// design, `objectives` values each, violation not NaN and not negative, no NaN objective in a
/// feasible evaluation.
pub(crate) fn check_batch(
    expected: usize,
    objectives: usize,
    evaluations: &[Evaluation],
) -> Result<(), OptimError> {
    if evaluations.len() != expected {
        return Err(OptimError::WrongEvaluationCount { expected, got: evaluations.len() });
    }
    for (index, e) in evaluations.iter().enumerate() {
        let reject = |reason: String| OptimError::InvalidEvaluation { index, reason };
        if e.objectives.len() != objectives {
            return Err(reject(format!(
                "it has {} objective values, the problem declares {objectives}",
                e.objectives.len()
            )));
        }
        if e.violation.is_nan() || e.violation < 0.0 {
            return Err(reject(format!(
                "violation {} must be 0 (feasible), positive, or infinity (not evaluable)",
                e.violation
            )));
        }
        if e.feasible() && e.objectives.iter().any(|v| v.is_nan()) {
            return Err(reject(
                "a feasible evaluation has a NaN objective (report it as failed instead)".into(),
            ));
        }
    }
    Ok(())
}

/// Evaluates `xs` through `problem` and checks the answer (see [`check_batch`]).
pub(crate) fn evaluate_checked<P: Problem>(
    problem: &mut P,
    xs: &[Vec<f64>],
) -> Result<Vec<Evaluation>, crate::RunError<P::Error>> {
    let evaluations = problem.evaluate_batch(xs).map_err(crate::RunError::Problem)?;
    check_batch(xs.len(), problem.objectives(), &evaluations)?;
    Ok(evaluations)
}

#[cfg(test)]
mod tests {
    use super::*;
    use mrbrake_error::Kind as _;

    #[test]
    fn check_batch_rejects_contract_breaches() {
        let ok = Evaluation::new(vec![1.0, 2.0], 0.0);
        assert!(check_batch(1, 2, std::slice::from_ref(&ok)).is_ok());
        assert!(matches!(
            check_batch(2, 2, std::slice::from_ref(&ok)),
            Err(OptimError::WrongEvaluationCount { expected: 2, got: 1 })
        ));
        assert!(check_batch(1, 3, std::slice::from_ref(&ok)).is_err());
        assert!(check_batch(1, 2, &[Evaluation::new(vec![1.0, 2.0], f64::NAN)]).is_err());
        assert!(check_batch(1, 2, &[Evaluation::new(vec![1.0, 2.0], -1.0)]).is_err());
        assert!(check_batch(1, 2, &[Evaluation::new(vec![f64::NAN, 2.0], 0.0)]).is_err());
        assert!(check_batch(1, 2, &[Evaluation::failed(2)]).is_ok());
        let e = check_batch(1, 2, &[Evaluation::new(vec![1.0], 0.0)]).unwrap_err();
        assert!(!e.is_input_error());
    }
}
