//! The crate's error type: invalid configuration found when a controller or a model is built.
//!
//! The control step itself never fails: bad run-time input gives the safe output and a
//! [`crate::Fault`] flag instead of an error, because a real-time loop must always produce currents.

use core::fmt;

/// Errors raised while building a configuration (never during a control step).
#[derive(Debug, Clone, Copy, PartialEq)]
#[non_exhaustive]
pub enum ControlError {
    /// A configuration field is outside its allowed range.
    OutOfRange {
        /// The field's name, e.g. `"current_max_a"`.
        field: &'static str,
        /// The rejected value.
        value: f64,
        /// Smallest allowed value.
        min: f64,
        /// Largest allowed value.
        max: f64,
    },
    /// A branch polynomial is unusable (no coefficients, too many, or not finite).
    InvalidPolynomial {
        /// Which branch: `"rising"` or `"falling"`.
        branch: &'static str,
    },
    /// A branch decreases somewhere on the current range, so its inverse is not unique.
    NonMonotoneBranch {
        /// Which branch: `"rising"` or `"falling"`.
        branch: &'static str,
    },
    /// A list of an operator model is empty or longer than the controller's fixed capacity.
    Capacity {
        /// The list, e.g. `"plays"`.
        field: &'static str,
        /// How many entries the model has.
        count: usize,
        /// The capacity ([`crate::MAX_PLAYS`] or [`crate::MAX_SEGMENTS`]).
        limit: usize,
    },
    /// Two lists of an operator model that must be equally long are not.
    CountMismatch {
        /// The list, e.g. `"weights"`.
        field: &'static str,
        /// Its length.
        count: usize,
        /// The length it must have.
        expected: usize,
    },
    /// A list of an operator model is not strictly increasing and finite (thresholds must start at 0).
    NotIncreasing {
        /// The list, e.g. `"thresholds"`.
        field: &'static str,
        /// The first offending value.
        value: f64,
    },
}

impl mrbrake_error::Kind for ControlError {
    /// Every variant comes from bad configuration input.
    fn kind(&self) -> mrbrake_error::ErrorKind {
        mrbrake_error::ErrorKind::Input
    }
}

impl fmt::Display for ControlError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::OutOfRange { field, value, min, max } => {
                write!(f, "{field} = {value} is outside the allowed range [{min}, {max}]")
            }
            Self::InvalidPolynomial { branch } => write!(
                f,
                "the {branch} branch needs 1 to {} finite coefficients (ascending powers of current)",
                crate::polynomial::MAX_DEGREE + 1
            ),
            Self::NonMonotoneBranch { branch } => write!(
                f,
                "the {branch} branch decreases somewhere on the current range, so torque -> current is ambiguous"
            ),
            Self::Capacity { field, count, limit } => write!(
                f,
                "{field}: {count} entries, but the controller holds 1 to {limit} (fixed capacity)"
            ),
            Self::CountMismatch { field, count, expected } => {
                write!(
                    f,
                    "{field}: {count} entries, expected {expected} (one per threshold or knot)"
                )
            }
            Self::NotIncreasing { field, value } => write!(
                f,
                "{field}: must be finite and strictly increasing (thresholds starting at 0); {value} breaks it"
            ),
        }
    }
}

#[cfg(any(test, feature = "std"))]
impl std::error::Error for ControlError {}

/// Checks `min ≤ value ≤ max` with a finite value.
pub(crate) fn check_range(
    field: &'static str,
    value: f64,
    min: f64,
    max: f64,
) -> Result<f64, ControlError> {
    if value.is_finite() && value >= min && value <= max {
        Ok(value)
    } else {
        Err(ControlError::OutOfRange { field, value, min, max })
    }
}
