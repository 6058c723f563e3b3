//! Axisymmetric non-linear magnetostatics in the azimuthal vector potential A_phi.
//!
//! Brief overview:
//! - [`problem::Problem`]: a mesh (`mrbrake_fem::mesh::Mesh`), a [`problem::Region`] (material and
//!   source) per physical surface, boundary conditions per physical curve.
//! - [`solver::Solver`]: built once per problem on the FEM core (basis, constraints, assembly,
//!   symbolic Cholesky), then [`solver::Solver::solve`] runs the core's Newton–Raphson with line
//!   search; sources can be changed ([`solver::Solver::set_source`]) and the previous solution
//!   passed as a warm start, as a current sweep does. The weak form is [`form`] (an
//!   `mrbrake_fem::workflow::assemble::ElementForm`), the open boundary a constant boundary coupling. The element order is
//!   [`solver::SolverOptions::order`]: linear triangles ([`ElementOrder::P1`], the default) or
//!   quadratic 6-node triangles ([`ElementOrder::P2`]) on the same mesh, with about four times the
//!   unknowns and one order more accuracy where the field is smooth (A in L2 at O(h³), B at O(h²);
//!   the validation tests measure both).
//! - [`field::Solution`] with post-processing on the solver: B at points and along lines, region
//!   statistics, flux linkage, inductance, energy and co-energy; [`force`]: the axial force on a
//!   body by virtual work on the layer of elements around it, and the Lorentz force on a coil.
//! - [`material`]: the material library's magnetic law ([`material::Magnetic`], with the
//!   [`material::Reluctivity`] `ν(B²)` of its B-H curves) and an analytic test curve.
//! - [`problem_file`]: the TOML problem files of `mrbrake fem solve`.
//! - [`exact`]: closed-form reference fields (current loop with elliptic integrals, solenoids, thick
//!   coil on the axis, permeable sphere) used by the validation tests.
//!
//! ```
//! use std::sync::Arc;
//! use mrbrake_fem::mesh::structured::{SideTags, graded_lines, rectangle_mesh};
//! use mrbrake_magnetics::material::Magnetic;
//! use mrbrake_magnetics::problem::{Boundary, BoundaryCondition, Problem, Region, Source};
//! use mrbrake_magnetics::solver::{Solver, SolverOptions};
//!
//! // A coil (tag 2) in air (tag 1), A = 0 on the outer box (edge tag 12).
//! let r = graded_lines(0.0, 0.1, 20, 1.0);
//! let z = graded_lines(-0.1, 0.1, 40, 1.0);
//! let coil = |r: f64, z: f64| if (0.02..0.03).contains(&r) && z.abs() < 0.02 { 2 } else { 1 };
//! let mesh = rectangle_mesh(&r, &z, coil, SideTags { r_min: 10, r_max: 11, z_min: 12, z_max: 12 }).unwrap();
//! let problem = Problem {
//!     mesh: Arc::new(mesh),
//!     regions: vec![
//!         Region { tag: 1, material: Magnetic::air(), source: None },
//!         Region { tag: 2, material: Magnetic::air(), source: Some(Source::Coil { turns: 100.0, current_a: 1.0 }) },
//!     ],
//!     boundaries: vec![
//!         Boundary { tag: 11, condition: BoundaryCondition::Dirichlet },
//!         Boundary { tag: 12, condition: BoundaryCondition::Dirichlet },
//!     ],
//! };
//! let mut solver = Solver::new(problem, SolverOptions::default()).unwrap();
//! let solution = solver.solve(None).unwrap();
//! let centre = solver.b_at(&solution, [0.0, 0.0]).unwrap();
//! assert!(centre.b_z_t > 0.0);
//! ```

pub mod benchmark;
pub mod dynamics;
pub mod exact;
pub mod field;
pub mod force;
pub mod form;
pub mod hysteresis;
pub mod material;
pub mod open_boundary;
pub mod problem;
pub mod problem_file;
pub mod solver;

pub use field::Solution;
pub use mrbrake_fem::discretisation::dofs::ElementOrder;
pub use solver::{NewtonStep, Solver, SolverOptions};

/// Errors of this crate.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum MagneticsError {
    /// Invalid input: the file when known, the field (a problem-file key such as
    /// `region[2].source.turns`, or an argument such as `frequencies`), the value and what is
    /// allowed.
    #[error(transparent)]
    Input(Box<mrbrake_error::FieldError>),
    /// Every invalid field of a table at once (a problem file's `[transient]` step keys).
    #[error(transparent)]
    Fields(#[from] mrbrake_error::FieldErrors),
    /// An error of the mesh / finite-element layer (mesh file, invalid mesh, factorisation).
    #[error(transparent)]
    Fem(#[from] mrbrake_fem::FemError),
    /// An error of the material library (unknown name, bad B-H file).
    #[error(transparent)]
    Material(#[from] mrbrake_materials::MaterialError),
    /// Newton–Raphson failed; the residual history says how far it got.
    #[error(transparent)]
    NotConverged(#[from] mrbrake_fem::workflow::newton::NewtonError),
    /// Another numerical failure.
    #[error("{0}")]
    Numerical(String),
    /// A transient failed: its options, its step bound, or a step (which one, at what time, and
    /// why: Newton's residual history is the next error of the chain).
    #[error(transparent)]
    Time(#[from] mrbrake_fem::workflow::time::TimeError),
}

impl From<mrbrake_error::FieldError> for MagneticsError {
    fn from(error: mrbrake_error::FieldError) -> Self {
        Self::Input(Box::new(error))
    }
}

impl MagneticsError {
    /// An input error about `field` (the message says what is wrong and what is allowed).
    pub(crate) fn field(field: impl std::fmt::Display, message: impl Into<String>) -> Self {
        mrbrake_error::FieldError::new(field.to_string(), message).into()
    }

    /// An input error about `field` of the problem file `file` (`field` empty: the whole file).
    pub(crate) fn in_file(
        file: &str,
        field: impl std::fmt::Display,
        message: impl Into<String>,
    ) -> Self {
        mrbrake_error::FieldError::new(field.to_string(), message).in_file(file, None).into()
    }
}

impl mrbrake_error::Kind for MagneticsError {
    /// Input for bad problems; the wrapped mesh and material errors keep their own kind; Newton
    /// failures are numerical.
    fn kind(&self) -> mrbrake_error::ErrorKind {
        use mrbrake_error::ErrorKind;
        match self {
            Self::Input(_) | Self::Fields(_) => ErrorKind::Input,
            Self::Fem(e) => e.kind(),
            Self::Material(e) => e.kind(),
            Self::NotConverged { .. } | Self::Numerical(_) => ErrorKind::Numerical,
            Self::Time(e) => e.kind(),
        }
    }
}
