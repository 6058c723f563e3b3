//! Sparse LU for the symmetric but not Hermitian systems of time-harmonic problems, and any scalar.
//!
//! A time-harmonic eddy-current system `(K + jωσM) x = f` is complex symmetric (`Aᵀ = A`, not
//! `Aᴴ = A`), so the Cholesky factorisation of [`crate::linalg::cholesky`] (real, symmetric positive
//! definite, with a hand-written supernodal solve) does not apply. Such systems go to faer's
//! generic sparse LU (`faer::sparse::linalg::solvers::Lu`, COLAMD ordering and partial pivoting,
//! generic over `T: ComplexField`, so the same code serves `f64` and `faer::c64` =
//! `num_complex::Complex<f64>`). The symbolic analysis is done once per pattern and reused by every
//! numeric factorisation (every frequency of a sweep).
//!
//! The caller gives the upper triangle of the symmetric matrix on a [`SymmetricPattern`] (as the
//! assembly produces it); the full pattern (both triangles, no conjugation) is built once here
//! with the position of every upper entry in it.

use faer::linalg::solvers::Solve;
use faer::sparse::linalg::solvers::{Lu, SymbolicLu};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMat};
use faer::traits::ComplexField;
use faer::{MatMut, c64};

use super::failure::{faer_words, lu_words};
use crate::FemError;
use crate::linalg::pattern::SymmetricPattern;

/// Sparse LU of symmetric matrices on one pattern, for any faer scalar (`f64`, [`c64`]).
pub struct SparseLu<T> {
    /// Full (both triangles) structure, sorted rows per column.
    structure: SymbolicSparseColMat<usize>,
    /// Positions in `values` of each upper-triangle entry of the pattern: `(upper, lower)`, equal
    /// on the diagonal.
    value_map: Vec<(usize, usize)>,
    symbolic: SymbolicLu<usize>,
    values: Vec<T>,
    lu: Option<Lu<usize, T>>,
}

impl<T> std::fmt::Debug for SparseLu<T> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("SparseLu")
            .field("n", &self.structure.nrows())
            .field("nnz", &self.values.len())
            .field("factorised", &self.lu.is_some())
            .finish_non_exhaustive()
    }
}

impl<T: ComplexField + Copy> SparseLu<T> {
    /// The symbolic analysis of the full matrix of `pattern` (upper triangle).
    pub fn new(pattern: &SymmetricPattern) -> Result<Self, FemError> {
        let n = pattern.n;
        // Column counts of the full matrix: each off-diagonal upper entry (i, j) also at (j, i).
        let mut count = vec![0usize; n];
        for j in 0..n {
            for &i in &pattern.row_idx[pattern.col_ptr[j]..pattern.col_ptr[j + 1]] {
                count[j] += 1;
                if i != j {
                    count[i] += 1;
                }
            }
        }
        let mut col_ptr = vec![0usize; n + 1];
        for j in 0..n {
            col_ptr[j + 1] = col_ptr[j] + count[j];
        }
        // Two passes keep the rows of every column sorted: the first puts each column's own upper
        // entries (rows <= j, sorted), the second the mirrors (j, i) of later columns' entries
        // (rows > i, visited in increasing j).
        let mut fill = col_ptr[..n].to_vec();
        let mut row_idx = vec![0usize; col_ptr[n]];
        let mut value_map = Vec::with_capacity(pattern.nnz());
        let mut upper_position = vec![0usize; pattern.nnz()];
        for j in 0..n {
            for p in pattern.col_ptr[j]..pattern.col_ptr[j + 1] {
                let i = pattern.row_idx[p];
                upper_position[p] = fill[j];
                row_idx[fill[j]] = i;
                fill[j] += 1;
            }
        }
        for j in 0..n {
            for p in pattern.col_ptr[j]..pattern.col_ptr[j + 1] {
                let i = pattern.row_idx[p];
                if i != j {
                    row_idx[fill[i]] = j;
                    value_map.push((upper_position[p], fill[i]));
                    fill[i] += 1;
                } else {
                    value_map.push((upper_position[p], upper_position[p]));
                }
            }
        }
        let structure = SymbolicSparseColMat::new_checked(n, n, col_ptr, None, row_idx);
        let symbolic = SymbolicLu::try_new(structure.as_ref()).map_err(|e| {
            FemError::Numerical(format!("symbolic LU analysis failed: {}", faer_words(&e)))
        })?;
        let nnz = structure.compute_nnz();
        Ok(Self {
            structure,
            value_map,
            symbolic,
            values: vec![faer::traits::math_utils::zero::<T>(); nnz],
            lu: None,
        })
    }

    /// Numeric factorisation of the symmetric matrix with upper-triangle `upper` (pattern order).
    pub fn factorize_symmetric(&mut self, upper: &[T]) -> Result<(), FemError> {
        self.lu = None;
        if upper.len() != self.value_map.len() {
            return Err(FemError::Numerical(format!(
                "{} matrix values given, the pattern has {}",
                upper.len(),
                self.value_map.len()
            )));
        }
        for (&(a, b), &value) in self.value_map.iter().zip(upper) {
            self.values[a] = value;
            self.values[b] = value;
        }
        let matrix = SparseColMatRef::new(self.structure.as_ref(), &self.values);
        let lu = Lu::try_new_with_symbolic(self.symbolic.clone(), matrix).map_err(|e| {
            FemError::Numerical(format!("sparse LU factorisation failed: {}", lu_words(&e)))
        })?;
        self.lu = Some(lu);
        Ok(())
    }

    /// Solves `A x = rhs` in place with the last factorisation.
    pub fn solve_in_place(&self, rhs: &mut [T]) -> Result<(), FemError> {
        let lu = self.lu.as_ref().ok_or_else(|| {
            FemError::Numerical("solve requested before a successful factorisation".into())
        })?;
        let n = self.structure.nrows();
        if rhs.len() != n {
            return Err(FemError::Numerical(format!(
                "right-hand side has {} entries, the matrix {n} rows",
                rhs.len()
            )));
        }
        lu.solve_in_place(MatMut::from_column_major_slice_mut(rhs, n, 1));
        Ok(())
    }
}

/// A complex symmetric sparse LU (the time-harmonic case).
pub type ComplexLu = SparseLu<c64>;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::structured::{SideTags, graded_lines, rectangle_mesh};

    /// A complex symmetric system `(K + jωM) x = b` on a mesh pattern: the residual of the
    /// solution is at round-off, and the real case matches the Cholesky solver.
    #[test]
    fn complex_symmetric_system_is_solved() {
        let r = graded_lines(0.0, 1.0, 6, 1.0);
        let z = graded_lines(0.0, 1.0, 5, 1.0);
        let sides = SideTags { r_min: 1, r_max: 2, z_min: 3, z_max: 4 };
        let mesh = rectangle_mesh(&r, &z, |_, _| 1, sides).unwrap();
        let dofs: Vec<usize> = mesh.triangles.iter().flatten().copied().collect();
        let n = mesh.nodes.len();
        let pattern = SymmetricPattern::new(n, 3, &dofs);
        // A diagonally dominant symmetric matrix with a complex diagonal shift.
        let mut upper = vec![c64::new(0.0, 0.0); pattern.nnz()];
        for j in 0..n {
            for p in pattern.col_ptr[j]..pattern.col_ptr[j + 1] {
                let i = pattern.row_idx[p];
                upper[p] = if i == j {
                    c64::new(10.0 + j as f64 * 0.1, 3.0)
                } else {
                    c64::new(-1.0 / (1.0 + (i + j) as f64), 0.5 / (1.0 + i as f64))
                };
            }
        }
        let b: Vec<c64> = (0..n).map(|k| c64::new(1.0 + k as f64, -(k as f64) * 0.3)).collect();
        let mut lu = ComplexLu::new(&pattern).unwrap();
        lu.factorize_symmetric(&upper).unwrap();
        let mut x = b.clone();
        lu.solve_in_place(&mut x).unwrap();
        // Residual A x − b with A symmetric from its upper triangle.
        let mut ax = vec![c64::new(0.0, 0.0); n];
        for j in 0..n {
            for p in pattern.col_ptr[j]..pattern.col_ptr[j + 1] {
                let i = pattern.row_idx[p];
                ax[i] += upper[p] * x[j];
                if i != j {
                    ax[j] += upper[p] * x[i];
                }
            }
        }
        let error: f64 = ax.iter().zip(&b).map(|(a, b)| (a - b).norm()).fold(0.0, f64::max);
        assert!(error < 1e-12, "residual {error}");

        // Real part only: the same answer as the Cholesky solver.
        let real: Vec<f64> = upper.iter().map(|v| v.re).collect();
        let mut real_lu = SparseLu::<f64>::new(&pattern).unwrap();
        real_lu.factorize_symmetric(&real).unwrap();
        let mut x_lu: Vec<f64> = b.iter().map(|v| v.re).collect();
        real_lu.solve_in_place(&mut x_lu).unwrap();
        let mut cholesky = crate::linalg::cholesky::SparseCholesky::new(&pattern, 1).unwrap();
        cholesky.factorize(&real).unwrap();
        let mut x_llt: Vec<f64> = b.iter().map(|v| v.re).collect();
        cholesky.solve_in_place(&mut x_llt).unwrap();
        for (a, b) in x_lu.iter().zip(&x_llt) {
            assert!((a - b).abs() < 1e-12 * b.abs().max(1.0), "{a} vs {b}");
        }
    }

    #[test]
    fn solve_before_factorisation_is_an_error() {
        let pattern = SymmetricPattern::new(3, 3, &[0, 1, 2]);
        let lu = SparseLu::<f64>::new(&pattern).unwrap();
        assert!(lu.solve_in_place(&mut [1.0, 2.0, 3.0]).is_err());
    }
}
