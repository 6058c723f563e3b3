//! The one error type of this crate, and the wrapper that lets an evaluator's own error pass through
//! an optimiser unchanged.

use std::fmt;

/// Errors of `mrbrake-optim`.
///
/// Every variant names the offending option, variable or design and the allowed range, so a caller can
/// print it as is.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum OptimError {
    /// A variable's bounds are unusable: a bound is not finite, `lower > upper`, or an integer
    /// variable's interval contains no integer.
    #[error("variable {index}: bounds [{lower}, {upper}] are invalid: {reason}")]
    InvalidBounds {
        /// Zero-based index of the variable.
        index: usize,
        /// The given lower bound.
        lower: f64,
        /// The given upper bound.
        upper: f64,
        /// Why the bounds are rejected.
        reason: &'static str,
    },
    /// The problem has no design variables.
    #[error("the problem has no design variables (at least 1 is required)")]
    NoVariables,
    /// The problem declares a number of objectives the method cannot handle.
    #[error("the problem declares {got} objective(s); {method} needs {allowed}")]
    ObjectiveCount {
        /// The optimiser asking.
        method: &'static str,
        /// Objectives declared by the problem.
        got: usize,
        /// The allowed count, in words.
        allowed: &'static str,
    },
    /// An option is outside its allowed range.
    #[error("option `{name}` = {value} is invalid: allowed {allowed}")]
    InvalidOption {
        /// The option's field name.
        name: &'static str,
        /// The given value (converted to `f64` for integer options).
        value: f64,
        /// The allowed range, in words.
        allowed: &'static str,
    },
    /// A named choice (an acquisition function, a sampling plan) is not one the method knows.
    #[error("option `{name}` = \"{value}\" is unknown: allowed {allowed}")]
    UnknownChoice {
        /// The option's field name.
        name: &'static str,
        /// The given value.
        value: String,
        /// The known values, in words.
        allowed: &'static str,
    },
    /// A design supplied by the caller (an initial design or a start point) is unusable.
    #[error("{which}: {reason}")]
    InvalidDesign {
        /// Which design, e.g. `initial design 2` or `start point`.
        which: String,
        /// What is wrong, naming the variable and its bounds.
        reason: String,
    },
    /// More Sobol' dimensions were requested than the built-in direction-number table holds.
    #[error(
        "a Sobol' sequence of dimension {requested} was requested; the built-in Joe-Kuo table supports 1 to {max}"
    )]
    SobolDimension {
        /// The requested dimension (number of variables).
        requested: usize,
        /// The largest supported dimension.
        max: usize,
    },
    /// More Sobol' points were requested than 32-bit direction numbers can generate.
    #[error("{requested} Sobol' points were requested; at most {max} can be generated")]
    SobolPoints {
        /// The requested number of points.
        requested: usize,
        /// The largest supported number of points.
        max: usize,
    },
    /// The evaluator returned a different number of evaluations than designs it was given.
    #[error("the evaluator returned {got} evaluations for a batch of {expected} designs")]
    WrongEvaluationCount {
        /// Designs in the batch.
        expected: usize,
        /// Evaluations returned.
        got: usize,
    },
    /// The evaluator returned an evaluation that breaks the [`crate::pareto::Evaluation`] contract
    /// (wrong number of objectives, NaN or negative violation, NaN objective of a feasible design).
    #[error("evaluation {index} of the batch is invalid: {reason}")]
    InvalidEvaluation {
        /// Position of the evaluation in its batch.
        index: usize,
        /// What is wrong.
        reason: String,
    },
}

impl mrbrake_error::Kind for OptimError {
    /// Input for bad bounds, options and designs; internal when the evaluator broke its contract.
    fn kind(&self) -> mrbrake_error::ErrorKind {
        match self {
            Self::WrongEvaluationCount { .. } | Self::InvalidEvaluation { .. } => {
                mrbrake_error::ErrorKind::Internal
            }
            _ => mrbrake_error::ErrorKind::Input,
        }
    }
}

/// The error of an optimisation run: either the optimiser's own [`OptimError`] or, unchanged, the
/// error the [`crate::Problem`] evaluator returned (an FEA failure, a store write error, ...).
#[derive(Debug)]
pub enum RunError<E> {
    /// The optimiser rejected its input or the evaluator broke its contract.
    Optim(OptimError),
    /// The evaluator failed; its error is passed through unchanged.
    Problem(E),
}

impl<E: mrbrake_error::Kind> mrbrake_error::Kind for RunError<E> {
    /// The optimiser's own kind, or the evaluator's error's kind, unchanged.
    fn kind(&self) -> mrbrake_error::ErrorKind {
        match self {
            Self::Optim(error) => error.kind(),
            Self::Problem(error) => error.kind(),
        }
    }
}

impl<E> From<OptimError> for RunError<E> {
    fn from(error: OptimError) -> Self {
        Self::Optim(error)
    }
}

impl<E: fmt::Display> fmt::Display for RunError<E> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Optim(error) => error.fmt(f),
            Self::Problem(error) => error.fmt(f),
        }
    }
}

/// Transparent: the message and the source chain are those of the wrapped error, so nothing is
/// printed twice in an `anyhow` `{:#}` chain.
impl<E: std::error::Error + 'static> std::error::Error for RunError<E> {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            Self::Optim(error) => std::error::Error::source(error),
            Self::Problem(error) => error.source(),
        }
    }
}
