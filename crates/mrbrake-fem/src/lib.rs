//! Axisymmetric finite-element core: mesh, elements, quadrature, basis, assembly of user forms,
//! constraints, sparse solves and Newton. Knows no physics: magnetostatics, magnetodynamics and
//! heat are forms and post-processing on top of it (scikit-fem's mesh / element / basis /
//! assemble, fenris's operators and Newton).
//!
//! The workflow of a physics:
//! 1. a [`mesh::Mesh`] and an element order make a [`discretisation::basis::Basis`] (with a
//!    quadrature rule and the axisymmetric `r` weight): basis values and gradients at every
//!    quadrature point;
//! 2. [`workflow::constraints::Constraints`] say which DOFs are free (the axis, Dirichlet
//!    boundaries);
//! 3. an [`workflow::assemble::Assembly`] builds the free-DOF sparsity pattern and assembles the
//!    caller's forms: per-element bilinear/linear forms ([`workflow::assemble::element_matrices`],
//!    [`workflow::assemble::element_vectors`]) and non-linear residual/Jacobian kernels
//!    ([`workflow::assemble::ElementForm`]), plus boundary integrals
//!    ([`workflow::boundary::edge_matrices`]);
//! 4. [`workflow::newton::NewtonSolver`] solves any [`workflow::newton::NonlinearSystem`] (an
//!    assembly with a form is one: [`workflow::newton::AssembledSystem`]) with a safeguarded line
//!    search and a preconditioned-CG tail; linear systems converge in one step. Complex
//!    (time-harmonic) systems go to [`linalg::lu::SparseLu`].
//!
//! The modules, in four groups:
//! - [`mesh`]: the [`mesh::Mesh`] (the (r, z) nodes, the triangles with their physical (region)
//!   tags and the tagged boundary edges); [`mesh::structured`] generates simple graded meshes of
//!   blocks and half-discs, [`mesh::mesher`] meshes a brake's cross-section, [`mesh::gmsh`] reads
//!   Gmsh MSH 2.2 / 4.1 ASCII files, [`mesh::vtu`] writes ParaView files and
//!   [`mesh::locate::PointLocator`] finds the triangle containing a point.
//! - [`discretisation`]: [`discretisation::quadrature`] gives triangle and interval rules;
//!   [`discretisation::element`] the affine triangle geometry and the Lagrange bases used by the
//!   forms; [`discretisation::dofs::DofMap`] numbers their degrees of freedom (vertices, then one
//!   per edge for P2); [`discretisation::basis`] ties them to a mesh and a weight.
//! - [`workflow`]: [`workflow::constraints`], [`workflow::assemble`] (with the [`by_order!`]
//!   dispatch macro), [`workflow::boundary`] and [`workflow::newton`]: the generic finite-element
//!   workflow above.
//! - [`linalg`]: [`linalg::pattern::SymmetricPattern`] is the sparsity pattern with a precomputed
//!   element scatter map, [`linalg::cholesky::SparseCholesky`] the faer sparse Cholesky with the
//!   symbolic analysis done once, [`linalg::ordering`] a nested-dissection elimination order for
//!   2D meshes; [`linalg::low_rank`]: dense rank-one Jacobian terms (an eliminated circuit
//!   equation) applied with the sparse factor by the Woodbury formula; [`linalg::lu`] complex
//!   symmetric systems; [`linalg::sweep`]: frequency sweeps of `(K + jωM) x = b` by an adaptive
//!   reduced basis of real shifted Cholesky solves.

pub mod discretisation;
pub mod linalg;
pub mod mesh;
pub mod workflow;

/// Errors of this crate.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum FemError {
    /// Invalid input: the file when known, the field (an argument such as `radii`, `seeds`,
    /// `nodes`, or a problem-file key such as `mesh`), the value and what is allowed.
    #[error(transparent)]
    Input(Box<mrbrake_error::FieldError>),
    /// A malformed mesh file: the file, the 1-based line number and what was expected there.
    #[error("{file}:{line}: {message}")]
    Parse {
        /// The file being read.
        file: String,
        /// 1-based line number (the last line for a truncated file).
        line: usize,
        /// What was wrong and what was expected.
        message: String,
    },
    /// A file could not be read or written.
    #[error("{path}: cannot read or write the file")]
    Io {
        /// The file.
        path: String,
        /// The underlying I/O error.
        source: std::io::Error,
    },
    /// A symmetric matrix that is not positive definite: the Cholesky factorisation met a pivot
    /// that is not positive.
    #[error(
        "the matrix is not positive definite: the Cholesky pivot of row {row} (of {rows}) is not \
         positive"
    )]
    NotPositiveDefinite {
        /// The row of the failing pivot, in the matrix's own numbering (a free DOF).
        row: usize,
        /// The matrix's order.
        rows: usize,
    },
    /// Another numerical failure (a singular dense system, memory for a factorisation, …).
    #[error("{0}")]
    Numerical(String),
}

impl From<mrbrake_error::FieldError> for FemError {
    fn from(error: mrbrake_error::FieldError) -> Self {
        Self::Input(Box::new(error))
    }
}

impl FemError {
    /// An input error about `field` (no value or range: the message says what is wrong).
    pub(crate) fn field(field: &str, message: impl Into<String>) -> Self {
        mrbrake_error::FieldError::new(field, message).into()
    }
}

impl mrbrake_error::Kind for FemError {
    /// Bad files and fields are input errors; a mesh file that cannot be read takes the kind of its
    /// I/O error (a missing file is input); factorisation failures are numerical.
    fn kind(&self) -> mrbrake_error::ErrorKind {
        use mrbrake_error::{ErrorKind, Kind};
        match self {
            Self::Input(_) | Self::Parse { .. } => ErrorKind::Input,
            Self::Io { source, .. } => Kind::kind(source),
            Self::NotPositiveDefinite { .. } | Self::Numerical(_) => ErrorKind::Numerical,
        }
    }
}
