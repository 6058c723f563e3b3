//! Axisymmetric finite-element core: mesh, elements, quadrature, assembly, sparse solve.
//! Knows no magnetics: physics lives in the forms the caller assembles.
//!
//! Brief overview: a [`mesh::Mesh`] holds the (r, z) nodes, the triangles with their physical (region)
//! tags and the tagged boundary edges. (More modules are being written: see docs/ARCHITECTURE.md.)

pub mod mesh;

/// Errors of this crate.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum FemError {
    /// Invalid input (file, line, field) with a message naming what was expected.
    #[error("{0}")]
    Input(String),
}

impl FemError {
    /// True when the error comes from bad input (the CLI exits with code 2), false for numerical or
    /// internal failures (exit code 1).
    pub fn is_input_error(&self) -> bool {
        matches!(self, Self::Input(_))
    }
}
