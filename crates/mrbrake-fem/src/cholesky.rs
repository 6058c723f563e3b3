//! Sparse Cholesky factorisation (faer) with the symbolic analysis done once per pattern.
//!
//! The symbolic step (fill-reducing ordering, elimination tree, supernode partition) depends only
//! on the [`SymmetricPattern`]; the ordering is faer's AMD or one given by the caller (e.g. the
//! geometric nested dissection of [`crate::ordering`]); it is computed in [`SparseCholesky::new`] and shared (`Arc`) by every
//! later numeric factorisation: all Newton iterations and all solves on the same mesh. The numeric
//! factor and its workspace are allocated once and overwritten.

use std::sync::Arc;

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::perm::PermRef;
use faer::sparse::linalg::cholesky::SymmetricOrdering;
use faer::sparse::linalg::cholesky::{SymbolicCholesky, factorize_symbolic_cholesky};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMat};
use faer::{Conj, MatMut, Par, Side};

use crate::FemError;
use crate::pattern::SymmetricPattern;

/// Reusable sparse `L Lᵀ` factorisation for matrices sharing one symmetric pattern.
pub struct SparseCholesky {
    structure: SymbolicSparseColMat<usize>,
    symbolic: Arc<SymbolicCholesky<usize>>,
    l_values: Vec<f64>,
    factor_workspace: MemBuffer,
    solve_workspace: MemBuffer,
    factorised: bool,
    parallelism: Par,
}

impl std::fmt::Debug for SparseCholesky {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("SparseCholesky")
            .field("n", &self.structure.nrows())
            .field("factor_nnz", &self.l_values.len())
            .field("factorised", &self.factorised)
            .finish_non_exhaustive()
    }
}

impl SparseCholesky {
    /// Symbolic analysis of `pattern` (upper triangle) with the AMD ordering. `threads = 0` uses
    /// rayon's global pool size.
    pub fn new(pattern: &SymmetricPattern, threads: usize) -> Result<Self, FemError> {
        Self::with_order(pattern, threads, None)
    }

    /// Symbolic analysis with the elimination order `order` (`order[k]` = the row eliminated k-th,
    /// a permutation of `0..n`), or AMD when `None`. A list that is not a permutation is an error.
    pub fn with_order(
        pattern: &SymmetricPattern,
        threads: usize,
        order: Option<&[usize]>,
    ) -> Result<Self, FemError> {
        let inverse = match order {
            Some(order) => Some(inverse_permutation(order, pattern.n)?),
            None => None,
        };
        let ordering = match (order, &inverse) {
            (Some(forward), Some(inverse)) => {
                SymmetricOrdering::Custom(PermRef::new_checked(forward, inverse, pattern.n))
            }
            _ => SymmetricOrdering::Amd,
        };
        let structure = SymbolicSparseColMat::new_checked(
            pattern.n,
            pattern.n,
            pattern.col_ptr.clone(),
            None,
            pattern.row_idx.clone(),
        );
        let symbolic = factorize_symbolic_cholesky(
            structure.as_ref(),
            Side::Upper,
            ordering,
            Default::default(),
        )
        .map_err(|e| FemError::Numerical(format!("symbolic Cholesky analysis failed: {e:?}")))?;
        let parallelism = if threads == 1 { Par::Seq } else { Par::rayon(threads) };
        let factor_req =
            symbolic.factorize_numeric_llt_scratch::<f64>(parallelism, Default::default());
        let solve_req = symbolic.solve_in_place_scratch::<f64>(1, parallelism);
        let l_values = vec![0.0; symbolic.len_val()];
        Ok(Self {
            structure,
            symbolic: Arc::new(symbolic),
            l_values,
            factor_workspace: MemBuffer::try_new(factor_req).map_err(|_| {
                FemError::Numerical("out of memory for the Cholesky workspace".into())
            })?,
            solve_workspace: MemBuffer::try_new(solve_req).map_err(|_| {
                FemError::Numerical("out of memory for the Cholesky workspace".into())
            })?,
            factorised: false,
            parallelism,
        })
    }

    /// Number of stored values in the factor `L` (a measure of fill-in).
    pub fn factor_nnz(&self) -> usize {
        self.l_values.len()
    }

    /// Numeric factorisation of the matrix with upper-triangle `values` (pattern order). Fails with
    /// [`FemError::Numerical`] when the matrix is not numerically positive definite.
    pub fn factorize(&mut self, values: &[f64]) -> Result<(), FemError> {
        self.factorised = false;
        let matrix = SparseColMatRef::new(self.structure.as_ref(), values);
        self.symbolic
            .factorize_numeric_llt(
                &mut self.l_values,
                matrix,
                Side::Upper,
                Default::default(),
                self.parallelism,
                MemStack::new(&mut self.factor_workspace),
                Default::default(),
            )
            .map_err(|e| {
                FemError::Numerical(format!("sparse Cholesky factorisation failed: {e:?}"))
            })?;
        self.factorised = true;
        Ok(())
    }

    /// Solves `A x = rhs` in place with the last factorisation.
    pub fn solve_in_place(&mut self, rhs: &mut [f64]) -> Result<(), FemError> {
        if !self.factorised {
            return Err(FemError::Numerical(
                "solve requested before a successful factorisation".into(),
            ));
        }
        if rhs.len() != self.structure.nrows() {
            return Err(FemError::Numerical(format!(
                "right-hand side has {} entries, the matrix {} rows",
                rhs.len(),
                self.structure.nrows()
            )));
        }
        let n = rhs.len();
        let llt = faer::sparse::linalg::cholesky::LltRef::new(&self.symbolic, &self.l_values);
        let rhs_mat = MatMut::from_column_major_slice_mut(rhs, n, 1);
        llt.solve_in_place_with_conj(
            Conj::No,
            rhs_mat,
            self.parallelism,
            MemStack::new(&mut self.solve_workspace),
        );
        Ok(())
    }
}

/// `inverse[order[k]] = k`, checking that `order` is a permutation of `0..n`.
fn inverse_permutation(order: &[usize], n: usize) -> Result<Vec<usize>, FemError> {
    let not_a_permutation =
        || FemError::Numerical(format!("elimination order is not a permutation of 0..{n}"));
    if order.len() != n {
        return Err(not_a_permutation());
    }
    let mut inverse = vec![usize::MAX; n];
    for (k, &v) in order.iter().enumerate() {
        if v >= n || inverse[v] != usize::MAX {
            return Err(not_a_permutation());
        }
        inverse[v] = k;
    }
    Ok(inverse)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::pattern::SymmetricPattern;

    #[test]
    fn solves_a_1d_laplacian() {
        // Chain of 2-node "elements" with stiffness [1 -1; -1 1], first node constrained.
        let n = 50;
        let mut dofs = Vec::new();
        dofs.extend([crate::pattern::CONSTRAINED, 0]);
        for i in 0..n - 1 {
            dofs.extend([i, i + 1]);
        }
        let pattern = SymmetricPattern::new(n, 2, &dofs);
        let element_upper: Vec<f64> = (0..n).flat_map(|_| [1.0, -1.0, 1.0]).collect();
        let mut values = vec![0.0; pattern.nnz()];
        pattern.assemble(&element_upper, &mut values);
        let mut chol = SparseCholesky::new(&pattern, 1).unwrap();
        chol.factorize(&values).unwrap();
        let mut rhs = vec![0.0; n];
        rhs[n - 1] = 1.0; // unit end load: x_i = i + 1
        chol.solve_in_place(&mut rhs).unwrap();
        for (i, x) in rhs.iter().enumerate() {
            assert!((x - (i + 1) as f64).abs() < 1e-10);
        }
        // Reuse: scale the matrix by 2, the solution halves.
        values.iter_mut().for_each(|v| *v *= 2.0);
        chol.factorize(&values).unwrap();
        let mut rhs = vec![0.0; n];
        rhs[n - 1] = 1.0;
        chol.solve_in_place(&mut rhs).unwrap();
        assert!((rhs[n - 1] - n as f64 / 2.0).abs() < 1e-10);
    }

    #[test]
    fn custom_order_gives_the_same_solution_and_bad_orders_are_errors() {
        let n = 30;
        let mut dofs = vec![crate::pattern::CONSTRAINED, 0];
        for i in 0..n - 1 {
            dofs.extend([i, i + 1]);
        }
        let pattern = SymmetricPattern::new(n, 2, &dofs);
        let element_upper: Vec<f64> = (0..n).flat_map(|_| [1.0, -1.0, 1.0]).collect();
        let mut values = vec![0.0; pattern.nnz()];
        pattern.assemble(&element_upper, &mut values);
        let reversed: Vec<usize> = (0..n).rev().collect();
        let mut chol = SparseCholesky::with_order(&pattern, 1, Some(&reversed)).unwrap();
        chol.factorize(&values).unwrap();
        let mut rhs = vec![0.0; n];
        rhs[n - 1] = 1.0;
        chol.solve_in_place(&mut rhs).unwrap();
        for (i, x) in rhs.iter().enumerate() {
            assert!((x - (i + 1) as f64).abs() < 1e-10);
        }
        let mut repeated = reversed.clone();
        repeated[0] = repeated[1];
        assert!(SparseCholesky::with_order(&pattern, 1, Some(&repeated)).is_err());
        assert!(SparseCholesky::with_order(&pattern, 1, Some(&reversed[1..])).is_err());
    }

    #[test]
    fn indefinite_matrix_is_an_error() {
        let pattern = SymmetricPattern::new(1, 1, &[0]);
        let mut chol = SparseCholesky::new(&pattern, 1).unwrap();
        assert!(chol.factorize(&[-1.0]).is_err());
    }
}
