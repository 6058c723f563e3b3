//! The finite-element workflow of a physics: constrain, assemble, solve.
//!
//! [`constraints`] (which DOFs are free: axis, prescribed and fixed boundaries, lifting),
//! [`assemble`] (`Assembly`: the free-DOF pattern and parallel element loops over the physics'
//! forms), [`boundary`] (edge integrals as constant couplings, boundary fluxes), [`newton`]
//! (`NewtonSolver` over the `NonlinearSystem` trait) and [`time`] (one integrator in time for
//! every physics: implicit Euler and variable-step BDF2, fixed or adaptive steps, over the
//! `TransientProblem` trait).

pub mod assemble;
pub mod boundary;
pub mod constraints;
pub mod newton;
pub mod time;
