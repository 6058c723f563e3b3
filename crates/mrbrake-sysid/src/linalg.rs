//! Dense linear least squares by Householder QR (Golub & Van Loan, *Matrix Computations*, §5.3).
//!
//! The problems here are small and tall (a few thousand rows, at most a few dozen columns): polynomial
//! branch fits, sine fits, the Sanathanan–Koerner and Levenberg–Marquardt steps. Columns are scaled to
//! unit norm before the factorisation, so the rank test is relative to each column's own size and a
//! badly scaled but well-posed problem is not mistaken for a singular one.

use crate::SysidError;
use mrbrake_error::FieldError;

/// Column-major dense matrix with `rows × cols` entries.
#[derive(Debug, Clone)]
pub struct Matrix {
    rows: usize,
    cols: usize,
    data: Vec<f64>,
}

impl Matrix {
    /// A zero matrix.
    pub fn zeros(rows: usize, cols: usize) -> Self {
        Self { rows, cols, data: vec![0.0; rows * cols] }
    }

    /// Number of rows.
    pub fn rows(&self) -> usize {
        self.rows
    }

    /// Number of columns.
    pub fn cols(&self) -> usize {
        self.cols
    }

    /// Entry (r, c).
    pub fn get(&self, r: usize, c: usize) -> f64 {
        self.data[c * self.rows + r]
    }

    /// Sets entry (r, c).
    pub fn set(&mut self, r: usize, c: usize, value: f64) {
        self.data[c * self.rows + r] = value;
    }

    fn col(&self, c: usize) -> &[f64] {
        &self.data[c * self.rows..(c + 1) * self.rows]
    }
}

/// Solves `min ‖A x − b‖₂` by Householder QR with column equilibration.
///
/// Fails with [`SysidError::Numerical`] when A is (numerically) rank deficient: a pivot of the scaled
/// R below `1e-13` times the largest, or non-finite entries.
pub fn least_squares(a: &Matrix, b: &[f64]) -> Result<Vec<f64>, SysidError> {
    let (m, n) = (a.rows, a.cols);
    if b.len() != m {
        return Err(FieldError::new("b", "least squares: one right-hand side per row")
            .with_value(b.len())
            .with_allowed(format!("{m} (the rows)"))
            .into());
    }
    if m < n || n == 0 {
        return Err(FieldError::new("a", format!("least squares: {n} unknowns"))
            .with_value(format!("{m} equations"))
            .with_allowed(format!(">= {n} equations, >= 1 unknown"))
            .into());
    }
    if a.data.iter().chain(b).any(|v| !v.is_finite()) {
        return Err(SysidError::numerical(
            "least squares: non-finite entry in the matrix or data",
            vec![],
        ));
    }
    let mut q = a.clone();
    let mut rhs = b.to_vec();
    let scale = equilibrate_columns(&mut q)?;
    let diag = householder_triangularise(&mut q, &mut rhs);
    let max_diag = diag.iter().fold(0.0_f64, |acc, d| acc.max(d.abs()));
    if let Some(k) = diag.iter().position(|d| d.abs() <= 1e-13 * max_diag) {
        return Err(SysidError::numerical(
            format!(
                "least squares: the design matrix is rank deficient (column {k} depends on the others)"
            ),
            diag.iter().map(|d| d.abs()).collect(),
        ));
    }
    let y = back_substitute(&q, &diag, &rhs);
    Ok(y.iter().zip(&scale).map(|(yi, si)| yi * si).collect())
}

/// Scales every column of `q` to unit norm in place and returns the factors: x = S y with
/// S = diag(1/‖a_j‖). A zero column is a numerical error.
fn equilibrate_columns(q: &mut Matrix) -> Result<Vec<f64>, SysidError> {
    let m = q.rows;
    let mut scale = vec![1.0; q.cols];
    for j in 0..q.cols {
        let norm = q.col(j).iter().map(|v| v * v).sum::<f64>().sqrt();
        if norm <= 0.0 {
            return Err(SysidError::numerical(
                format!("least squares: column {j} of the design matrix is zero"),
                vec![],
            ));
        }
        scale[j] = 1.0 / norm;
        for v in &mut q.data[j * m..(j + 1) * m] {
            *v *= scale[j];
        }
    }
    Ok(scale)
}

/// Householder QR in place: applies the reflections to the columns of `q` and to `rhs` (which becomes
/// Qᵀ b), leaves R's strictly upper part in `q` and returns R's diagonal.
fn householder_triangularise(q: &mut Matrix, rhs: &mut [f64]) -> Vec<f64> {
    let (m, n) = (q.rows, q.cols);
    let mut diag = vec![0.0; n];
    for k in 0..n {
        let norm = q.data[k * m + k..(k + 1) * m].iter().map(|v| v * v).sum::<f64>().sqrt();
        let akk = q.data[k * m + k];
        let alpha = if akk > 0.0 { -norm } else { norm };
        diag[k] = alpha;
        // v = x − alpha e1, stored in place of the column below the diagonal.
        q.data[k * m + k] -= alpha;
        let vtv: f64 = q.data[k * m + k..(k + 1) * m].iter().map(|v| v * v).sum();
        if vtv <= f64::MIN_POSITIVE {
            continue;
        }
        let (head, tail) = q.data.split_at_mut((k + 1) * m);
        let v = &head[k * m + k..(k + 1) * m];
        for j in 0..n - k - 1 {
            reflect(v, vtv, &mut tail[j * m + k..(j + 1) * m]);
        }
        reflect(v, vtv, &mut rhs[k..]);
    }
    diag
}

/// Applies the reflection `I − 2 v vᵀ / (vᵀ v)` to `x`.
#[inline]
fn reflect(v: &[f64], vtv: f64, x: &mut [f64]) {
    let dot: f64 = v.iter().zip(x.iter()).map(|(a, b)| a * b).sum();
    let f = 2.0 * dot / vtv;
    for (c, vi) in x.iter_mut().zip(v) {
        *c -= f * vi;
    }
}

/// Solves R y = Qᵀ b by back substitution, R's strictly upper part stored in `q` above the
/// diagonal and its diagonal in `diag`.
fn back_substitute(q: &Matrix, diag: &[f64], rhs: &[f64]) -> Vec<f64> {
    let n = q.cols;
    let mut y = vec![0.0; n];
    for k in (0..n).rev() {
        let mut s = rhs[k];
        for j in k + 1..n {
            s -= q.get(k, j) * y[j];
        }
        y[k] = s / diag[k];
    }
    y
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exact_overdetermined_system_is_solved() {
        // y = 2 − 3 t + 0.5 t² sampled without noise.
        let t: Vec<f64> = (0..20).map(|i| i as f64 * 0.3).collect();
        let mut a = Matrix::zeros(t.len(), 3);
        let mut b = vec![0.0; t.len()];
        for (i, ti) in t.iter().enumerate() {
            a.set(i, 0, 1.0);
            a.set(i, 1, *ti);
            a.set(i, 2, ti * ti);
            b[i] = 2.0 - 3.0 * ti + 0.5 * ti * ti;
        }
        let x = least_squares(&a, &b).unwrap();
        assert!(
            (x[0] - 2.0).abs() < 1e-12 && (x[1] + 3.0).abs() < 1e-12 && (x[2] - 0.5).abs() < 1e-12
        );
    }

    #[test]
    fn least_squares_residual_is_orthogonal_to_columns() {
        let mut a = Matrix::zeros(5, 2);
        let b = [1.0, 3.0, 2.0, 5.0, 4.0];
        for i in 0..5 {
            a.set(i, 0, 1.0);
            a.set(i, 1, i as f64);
        }
        let x = least_squares(&a, &b).unwrap();
        for j in 0..2 {
            let dot: f64 = (0..5)
                .map(|i| a.get(i, j) * (b[i] - a.get(i, 0) * x[0] - a.get(i, 1) * x[1]))
                .sum();
            assert!(dot.abs() < 1e-12);
        }
    }

    #[test]
    fn rank_deficiency_is_reported() {
        let mut a = Matrix::zeros(4, 2);
        for i in 0..4 {
            a.set(i, 0, i as f64);
            a.set(i, 1, 2.0 * i as f64);
        }
        let err = least_squares(&a, &[0.0, 1.0, 2.0, 3.0]).unwrap_err();
        assert!(matches!(err, SysidError::Numerical { .. }));
    }
}
