//! Axisymmetric finite-element core: mesh, elements, quadrature, basis, assembly of user forms,
//! constraints, sparse solves and Newton. Knows no physics: magnetostatics, magnetodynamics and
//! heat are forms and post-processing on top of it (scikit-fem's mesh / element / basis /
//! assemble, fenris's operators and Newton).
//!
//! The workflow of a physics:
//! 1. a [`mesh::Mesh`] and an element order make a [`basis::Basis`] (with a quadrature rule and the
//!    axisymmetric `r` weight): basis values and gradients at every quadrature point;
//! 2. [`constraints::Constraints`] say which DOFs are free (the axis, Dirichlet boundaries);
//! 3. an [`assemble::Assembly`] builds the free-DOF sparsity pattern and assembles the caller's
//!    forms: per-element bilinear/linear forms ([`assemble::element_matrices`],
//!    [`assemble::element_vectors`]) and non-linear residual/Jacobian kernels
//!    ([`assemble::ElementForm`]), plus boundary integrals ([`boundary::edge_matrices`]);
//! 4. [`newton::NewtonSolver`] solves any [`newton::NonlinearSystem`] (an assembly with a form is
//!    one: [`newton::AssembledSystem`]) with a safeguarded line search and a preconditioned-CG
//!    tail; linear systems converge in one step. Complex (time-harmonic) systems go to
//!    [`lu::SparseLu`].
//!
//! Brief overview of the modules:
//! - [`mesh::Mesh`] holds the (r, z) nodes, the triangles with their physical (region) tags and the
//!   tagged boundary edges; [`structured`] generates simple graded meshes of blocks and half-discs;
//!   [`gmsh`] reads Gmsh MSH 2.2 / 4.1 ASCII files; [`vtu`] writes ParaView files.
//! - [`quadrature`] gives triangle and interval rules; [`element`] the affine triangle geometry
//!   (barycentric gradients) and the Lagrange bases [`element::ElementTriP1`] and
//!   [`element::ElementTriP2`] used by the forms; [`dofs::DofMap`] numbers their degrees of freedom
//!   (vertices, then one per edge for P2) and finds boundary and axis DOFs.
//! - [`pattern::SymmetricPattern`] is the sparsity pattern with a precomputed element scatter map, and
//!   [`cholesky::SparseCholesky`] the faer sparse Cholesky with the symbolic analysis done once;
//!   [`ordering`] gives it a nested-dissection elimination order for 2D meshes.
//! - [`locate::PointLocator`] finds the triangle containing a point (uniform bucket grid).
//! - [`basis`], [`constraints`], [`assemble`] (with the [`by_order!`] dispatch macro),
//!   [`boundary`], [`newton`], [`lu`]: the generic finite-element workflow above;
//!   [`low_rank`]: dense rank-one Jacobian terms (an eliminated circuit equation) applied with the
//!   sparse factor by the Woodbury formula; [`sweep`]: frequency sweeps of `(K + jωM) x = b` by an
//!   adaptive reduced basis of real shifted Cholesky solves.

pub mod assemble;
pub mod basis;
pub mod boundary;
pub mod cholesky;
pub mod constraints;
pub mod dofs;
pub mod element;
pub mod gmsh;
pub mod locate;
pub mod low_rank;
pub mod lu;
pub mod mesh;
pub mod mesher;
pub mod newton;
pub mod ordering;
pub mod pattern;
pub mod quadrature;
pub mod structured;
pub mod sweep;
pub mod vtu;

/// Errors of this crate.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum FemError {
    /// Invalid input (file, line, field) with a message naming what was expected.
    #[error("{0}")]
    Input(String),
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
    /// A numerical failure (e.g. a matrix that is not positive definite).
    #[error("{0}")]
    Numerical(String),
}

impl mrbrake_error::Kind for FemError {
    /// Bad files and fields are input errors; a mesh file that cannot be read takes the kind of its
    /// I/O error (a missing file is input); factorisation failures are numerical.
    fn kind(&self) -> mrbrake_error::ErrorKind {
        use mrbrake_error::{ErrorKind, Kind};
        match self {
            Self::Input(_) | Self::Parse { .. } => ErrorKind::Input,
            Self::Io { source, .. } => Kind::kind(source),
            Self::Numerical(_) => ErrorKind::Numerical,
        }
    }
}
