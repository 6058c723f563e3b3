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

impl mrbrake_error::Kind for SimError {
    /// Input for bad configurations; identification errors keep their own kind.
    fn kind(&self) -> mrbrake_error::ErrorKind {
        match self {
            Self::Input(_) => mrbrake_error::ErrorKind::Input,
            Self::Sysid(e) => e.kind(),
        }
    }
}
