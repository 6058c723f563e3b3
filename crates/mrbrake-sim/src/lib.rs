//! Plant models, virtual test rig and haptic simulation.
//!
//! (Work in progress: see docs/ARCHITECTURE.md for the crate map.)

pub mod haptic;
pub mod lti;
pub mod rig;

/// Errors of this crate.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum SimError {
    /// Invalid input (file, field, value) with a message naming what was expected.
    #[error("{0}")]
    Input(String),
    /// An identification step inside a simulation (inverse model, log parsing) failed.
    #[error(transparent)]
    Sysid(#[from] mrbrake_sysid::SysidError),
}

impl SimError {
    /// True when the error comes from bad input (the CLI exits with code 2), false for numerical or
    /// internal failures (exit code 1).
    pub fn is_input_error(&self) -> bool {
        matches!(self, Self::Input(_)) || matches!(self, Self::Sysid(e) if e.is_input_error())
    }
}
