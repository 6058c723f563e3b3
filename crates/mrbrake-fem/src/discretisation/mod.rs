//! Discretisation: what turns a mesh into a finite-element space, with nothing about physics.
//!
//! [`quadrature`] (triangle and interval rules), [`element`] (the affine triangle geometry and the
//! Lagrange bases `ElementTriP1` / `ElementTriP2` behind the `TriangleBasis` trait), [`dofs`] (the
//! DOF map of order 1 or 2) and [`basis`] (`Basis`: mesh + order + quadrature + planar or
//! axisymmetric weight; per element and quadrature point the values, gradients, point and weight
//! a form needs).

pub mod basis;
pub mod dofs;
pub mod element;
pub mod quadrature;
