//! MR brake design: closed-form torque models of the thesis, coil and winding formulas, passivity
//! conditions, and (later) brake specifications, the geometry builder and studies.

pub mod analysis;
pub mod formula;
pub mod geo_export;
pub mod geometry;
pub mod mesh_build;
pub mod spec;
pub mod study;

/// Errors of this crate.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum DesignError {
    /// Invalid input (a field out of its allowed range), with a message naming the field.
    #[error("{0}")]
    Input(String),
    /// A numerical or internal failure (e.g. the mesher could not reach the requested size).
    #[error("{0}")]
    Numerical(String),
}

impl mrbrake_error::Kind for DesignError {
    /// Input for invalid fields, numerical for failures of the mesher or the solver.
    fn kind(&self) -> mrbrake_error::ErrorKind {
        match self {
            Self::Input(_) => mrbrake_error::ErrorKind::Input,
            Self::Numerical(_) => mrbrake_error::ErrorKind::Numerical,
        }
    }
}
