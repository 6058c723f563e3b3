//! The one error type of this crate, and [`RunError`], which lets a caller's model error pass
//! through a propagation or a calibration unchanged.

use std::fmt;

/// Errors of `mrbrake-uq`.
///
/// Input variants name the offending parameter, option or sample by its name in this crate's API
/// (`std_dev`, `truncation.lower`, `bootstrap`, …) and the allowed range; the front end adds the
/// file and key the value came from.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum UqError {
    /// A distribution parameter is outside its allowed range (negative spread, non-finite value,
    /// mode outside `[lower, upper]`, …).
    #[error("{law} distribution: parameter `{parameter}` = {value} is invalid: allowed {allowed}")]
    InvalidParameter {
        /// The law, e.g. `normal`.
        law: &'static str,
        /// The parameter's name, e.g. `std_dev`.
        parameter: &'static str,
        /// The given value.
        value: f64,
        /// The allowed range, in words.
        allowed: &'static str,
    },
    /// A truncation interval is malformed (`lower >= upper`, NaN) or holds no probability of the law.
    #[error("{law} distribution: truncation [{lower}, {upper}] is invalid: {reason}")]
    InvalidTruncation {
        /// The law being truncated.
        law: &'static str,
        /// The truncation's lower bound.
        lower: f64,
        /// The truncation's upper bound.
        upper: f64,
        /// Why it is rejected.
        reason: &'static str,
    },
    /// A probability outside `[0, 1]` (or NaN) was given to a quantile function.
    #[error("probability {value} is outside [0, 1]")]
    InvalidProbability {
        /// The given probability.
        value: f64,
    },
    /// An option is outside its allowed range.
    #[error("option `{name}` = {value} is invalid: allowed {allowed}")]
    InvalidOption {
        /// The option's name.
        name: &'static str,
        /// The given value (converted to `f64` for counts).
        value: f64,
        /// The allowed range, in words.
        allowed: &'static str,
    },
    /// A set of samples cannot be used: empty, ragged, non-finite, or of the wrong size.
    #[error("{what}: {reason}")]
    InvalidSamples {
        /// Which data, e.g. `outputs` or `unit points`.
        what: &'static str,
        /// What is wrong, naming the sample and column.
        reason: String,
    },
    /// A calibration parameter's bounds or start value are unusable.
    #[error("parameter {index}: {reason}")]
    InvalidCalibrationParameter {
        /// Zero-based index of the parameter.
        index: usize,
        /// What is wrong, with the values.
        reason: String,
    },
    /// A scrambled Sobol' sequence was asked for more dimensions or points than supported.
    #[error(transparent)]
    Sobol(#[from] mrbrake_optim::OptimError),
    /// Valid input, failed numerics: e.g. a residual that is not finite where it must be, or a
    /// singular-value decomposition that did not converge. `history` holds the cost after each
    /// accepted step so far (empty where there is none).
    #[error("{message}")]
    Numerical {
        /// What failed, with the values.
        message: String,
        /// The cost (½‖r‖²) after each accepted step before the failure.
        history: Vec<f64>,
    },
    /// A caller's model broke its contract (e.g. returned residual vectors of varying length).
    #[error("the model broke its contract: {0}")]
    ModelContract(String),
}

impl UqError {
    /// A numerical failure with its history.
    pub(crate) fn numerical(message: impl Into<String>, history: Vec<f64>) -> Self {
        Self::Numerical { message: message.into(), history }
    }

    /// Invalid samples, described.
    pub(crate) fn samples(what: &'static str, reason: impl Into<String>) -> Self {
        Self::InvalidSamples { what, reason: reason.into() }
    }
}

impl mrbrake_error::Kind for UqError {
    /// Input for bad parameters, options and samples; numerical for failed numerics; internal when
    /// a model broke its contract.
    fn kind(&self) -> mrbrake_error::ErrorKind {
        match self {
            Self::Sobol(error) => error.kind(),
            Self::Numerical { .. } => mrbrake_error::ErrorKind::Numerical,
            Self::ModelContract(_) => mrbrake_error::ErrorKind::Internal,
            _ => mrbrake_error::ErrorKind::Input,
        }
    }
}

/// The error of a run that calls the caller's model (a propagation, a calibration): either this
/// crate's own [`UqError`] or, unchanged, the error the model returned (an FEA failure, a store
/// write error, …).
#[derive(Debug)]
pub enum RunError<E> {
    /// The algorithm rejected its input or failed numerically.
    Uq(UqError),
    /// The model failed; its error is passed through unchanged.
    Model(E),
}

impl<E: mrbrake_error::Kind> mrbrake_error::Kind for RunError<E> {
    /// This crate's own kind, or the model error's kind, unchanged.
    fn kind(&self) -> mrbrake_error::ErrorKind {
        match self {
            Self::Uq(error) => error.kind(),
            Self::Model(error) => error.kind(),
        }
    }
}

impl<E> From<UqError> for RunError<E> {
    fn from(error: UqError) -> Self {
        Self::Uq(error)
    }
}

impl<E: fmt::Display> fmt::Display for RunError<E> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Uq(error) => error.fmt(f),
            Self::Model(error) => error.fmt(f),
        }
    }
}

/// Transparent: the message and the source chain are those of the wrapped error.
impl<E: std::error::Error + 'static> std::error::Error for RunError<E> {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            Self::Uq(error) => std::error::Error::source(error),
            Self::Model(error) => error.source(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use mrbrake_error::{ErrorKind, Kind};

    #[test]
    fn kinds() {
        let input = UqError::InvalidProbability { value: 2.0 };
        assert_eq!(input.kind(), ErrorKind::Input);
        assert_eq!(UqError::numerical("x", vec![1.0]).kind(), ErrorKind::Numerical);
        assert_eq!(UqError::ModelContract("y".into()).kind(), ErrorKind::Internal);
        let wrapped: RunError<UqError> = RunError::Model(UqError::numerical("fea", vec![]));
        assert_eq!(wrapped.kind(), ErrorKind::Numerical);
        assert_eq!(wrapped.to_string(), "fea");
    }
}
