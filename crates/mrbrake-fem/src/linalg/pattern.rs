//! Sparsity pattern of a symmetric finite-element matrix and the scatter map from element matrices.
//!
//! The pattern stores the upper triangle (row <= column) in compressed sparse column form with sorted
//! row indices. It is built once per mesh and degree-of-freedom numbering, in O(nnz log(degree)),
//! from the node-to-element incidence; [`SymmetricPattern::scatter`] then gives, for every element
//! and every local pair `(a, b)` with `a <= b`, the position in the value array, so assembling a new
//! matrix (every Newton iteration) is one pass of additions with no sorting or searching.

/// Marker for a constrained (eliminated) degree of freedom in an element's DOF list.
pub const CONSTRAINED: usize = usize::MAX;

/// Marker in the scatter map for a local pair that touches a constrained DOF.
pub const NO_ENTRY: u32 = u32::MAX;

/// Upper-triangular CSC pattern of a symmetric matrix plus the element scatter map.
#[derive(Debug, Clone)]
pub struct SymmetricPattern {
    /// Matrix dimension (number of free DOFs).
    pub n: usize,
    /// Column pointers, length `n + 1`.
    pub col_ptr: Vec<usize>,
    /// Row indices (sorted within each column, `row <= column`).
    pub row_idx: Vec<usize>,
    /// For element `e` with `k` DOFs, entries `e * k(k+1)/2 ..` hold the value position of each local
    /// pair `(a, b)`, `a <= b`, in row-major upper order, or [`NO_ENTRY`].
    pub scatter: Vec<u32>,
    /// DOFs per element.
    pub dofs_per_element: usize,
}

impl SymmetricPattern {
    /// Builds the pattern of an `n × n` matrix from the free-DOF lists of the elements (each of length
    /// `dofs_per_element`, [`CONSTRAINED`] for eliminated DOFs). Panics only if a DOF is `>= n` and not
    /// [`CONSTRAINED`] (a caller bug, not an input error).
    pub fn new(n: usize, dofs_per_element: usize, element_dofs: &[usize]) -> Self {
        let k = dofs_per_element;
        let n_elements = element_dofs.len() / k;
        // DOF -> elements incidence (CSR).
        let mut start = vec![0usize; n + 1];
        for &d in element_dofs {
            if d != CONSTRAINED {
                start[d + 1] += 1;
            }
        }
        for i in 0..n {
            start[i + 1] += start[i];
        }
        let mut fill = start.clone();
        let mut incident = vec![0usize; start[n]];
        for (e, dofs) in element_dofs.chunks_exact(k).enumerate() {
            for &d in dofs {
                if d != CONSTRAINED {
                    incident[fill[d]] = e;
                    fill[d] += 1;
                }
            }
        }
        // Column j holds rows i <= j that share an element with j.
        let mut col_ptr = Vec::with_capacity(n + 1);
        col_ptr.push(0);
        let mut row_idx = Vec::new();
        let mut marker = vec![usize::MAX; n];
        let mut column = Vec::new();
        for j in 0..n {
            column.clear();
            for &e in &incident[start[j]..start[j + 1]] {
                for &i in &element_dofs[e * k..(e + 1) * k] {
                    if i != CONSTRAINED && i <= j && marker[i] != j {
                        marker[i] = j;
                        column.push(i);
                    }
                }
            }
            column.sort_unstable();
            row_idx.extend_from_slice(&column);
            col_ptr.push(row_idx.len());
        }
        let pairs = k * (k + 1) / 2;
        let mut scatter = vec![NO_ENTRY; n_elements * pairs];
        for (e, dofs) in element_dofs.chunks_exact(k).enumerate() {
            let mut p = 0;
            for a in 0..k {
                for b in a..k {
                    let (da, db) = (dofs[a], dofs[b]);
                    if da != CONSTRAINED && db != CONSTRAINED {
                        let (row, col) = if da <= db { (da, db) } else { (db, da) };
                        let rows = &row_idx[col_ptr[col]..col_ptr[col + 1]];
                        let offset = rows
                            .binary_search(&row)
                            .expect("row was inserted into this column above");
                        scatter[e * pairs + p] = (col_ptr[col] + offset) as u32;
                    }
                    p += 1;
                }
            }
        }
        Self { n, col_ptr, row_idx, scatter, dofs_per_element: k }
    }

    /// Position in the value array of the entry `(a, b)` (either order), or `None` when the pattern
    /// has no such entry.
    pub fn position(&self, a: usize, b: usize) -> Option<usize> {
        let (row, col) = if a <= b { (a, b) } else { (b, a) };
        let range = *self.col_ptr.get(col)?..*self.col_ptr.get(col + 1)?;
        let start = range.start;
        self.row_idx[range].binary_search(&row).ok().map(|k| start + k)
    }

    /// Number of stored (upper-triangle) entries.
    pub fn nnz(&self) -> usize {
        self.row_idx.len()
    }

    /// Adds the upper parts of the element matrices (`k(k+1)/2` values per element, same pair order as
    /// the scatter map) into `values` (length [`Self::nnz`]), which is zeroed first.
    pub fn assemble(&self, element_upper: &[f64], values: &mut [f64]) {
        values.iter_mut().for_each(|v| *v = 0.0);
        for (&pos, &v) in self.scatter.iter().zip(element_upper) {
            if pos != NO_ENTRY {
                values[pos as usize] += v;
            }
        }
    }

    /// Adds the upper parts of the matrices of the listed `elements` only (`element_upper` holds
    /// `k(k+1)/2` values for *every* element, in the order of [`Self::assemble`]) into `values`,
    /// which is not zeroed: e.g. the elements whose matrix changed, on top of a stored sum of the
    /// constant ones.
    pub fn add_elements(&self, elements: &[usize], element_upper: &[f64], values: &mut [f64]) {
        let pairs = self.dofs_per_element * (self.dofs_per_element + 1) / 2;
        for &e in elements {
            let range = e * pairs..(e + 1) * pairs;
            for (&pos, &v) in self.scatter[range.clone()].iter().zip(&element_upper[range]) {
                if pos != NO_ENTRY {
                    values[pos as usize] += v;
                }
            }
        }
    }

    /// `y = A x` for the symmetric matrix whose upper triangle is `values`.
    pub fn symmetric_mul(&self, values: &[f64], x: &[f64], y: &mut [f64]) {
        y.iter_mut().for_each(|v| *v = 0.0);
        for j in 0..self.n {
            for p in self.col_ptr[j]..self.col_ptr[j + 1] {
                let i = self.row_idx[p];
                y[i] += values[p] * x[j];
                if i != j {
                    y[j] += values[p] * x[i];
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn two_triangles_pattern() {
        // Square 0-1-2-3 split along 0-2; node 3 constrained.
        let dofs = [0, 1, 2, 0, 2, CONSTRAINED];
        let p = SymmetricPattern::new(3, 3, &dofs);
        assert_eq!(p.col_ptr, vec![0, 1, 3, 6]);
        assert_eq!(p.row_idx, vec![0, 0, 1, 0, 1, 2]);
        // Element matrices of ones: diagonal 0 gets 2, (0,2) gets 2, (1,1) 1.
        let ones = vec![1.0; 12];
        let mut values = vec![0.0; p.nnz()];
        p.assemble(&ones, &mut values);
        assert_eq!(values, vec![2.0, 1.0, 1.0, 2.0, 1.0, 2.0]);
        // Adding element 1 alone on top of element 0 alone gives the same sum.
        let mut partial = vec![0.0; p.nnz()];
        p.add_elements(&[0], &ones, &mut partial);
        p.add_elements(&[1], &ones, &mut partial);
        assert_eq!(partial, values);
        let mut y = vec![0.0; 3];
        p.symmetric_mul(&values, &[1.0, 1.0, 1.0], &mut y);
        assert_eq!(y, vec![5.0, 3.0, 5.0]);
    }
}
