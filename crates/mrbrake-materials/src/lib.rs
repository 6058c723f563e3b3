//! Material library for mrbrake: B-H curves, MR-fluid yield stress, linear materials, copper wire.
//!
//! (Work in progress: see docs/ARCHITECTURE.md for the crate map.)

/// Errors of this crate.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum MaterialError {
    /// Invalid input (file, field, value) with a message naming what was expected.
    #[error("{0}")]
    Input(String),
}

impl MaterialError {
    /// True when the error comes from bad input (the CLI exits with code 2), false for numerical or
    /// internal failures (exit code 1).
    pub fn is_input_error(&self) -> bool {
        matches!(self, Self::Input(_))
    }
}
