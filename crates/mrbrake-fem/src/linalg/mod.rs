//! Sparse linear algebra on finite-element patterns.
//!
//! [`pattern`] (the symmetric sparsity pattern and its element scatter map), [`ordering`] (nested
//! dissection), [`cholesky`] (faer's sparse LLᵀ, symbolic analysis once), [`low_rank`] (dense
//! rank-one Jacobian terms applied with the sparse factor by the Woodbury formula), [`lu`] (sparse
//! LU of complex symmetric systems) and [`sweep`] (frequency sweeps of `(K + jωM) x = b` by a
//! reduced basis of real shifted Cholesky solves); `failure` puts faer's errors into words.

pub mod cholesky;
mod failure;
pub mod low_rank;
pub mod lu;
pub mod ordering;
pub mod pattern;
pub mod sweep;
