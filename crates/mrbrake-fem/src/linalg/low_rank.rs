//! Symmetric low-rank terms of a Jacobian, solved with the factor of its sparse part.
//!
//! Some systems have a Jacobian `K + Σ_k w_k c_k c_kᵀ`: a sparse, symmetric positive-definite `K`
//! plus a few dense rank-one terms with weights `w_k > 0` (e.g. a circuit equation eliminated into
//! the field equations: the coil current depends on the flux linkage `cᵀu`, which couples every
//! DOF of the winding with every other). The dense terms are never assembled: with the Cholesky
//! factor of `K`, the Sherman–Morrison–Woodbury formula (Golub & Van Loan, *Matrix
//! Computations*, 4th ed., §2.1.4, eq. 2.1.4)
//!
//! `(K + C W Cᵀ)⁻¹ b = x − Z S⁻¹ Cᵀ x`, with `x = K⁻¹ b`, `Z = K⁻¹ C`, `S = W⁻¹ + Cᵀ Z`,
//!
//! costs `k` extra triangular solves per factorisation (for `Z`) and a `k × k` dense solve per
//! right-hand side. `S` is symmetric positive definite when `K` is and `W > 0`, so the sum stays
//! the Jacobian of a convex energy and the Newton line search is unchanged (its slope gains
//! `Σ_k w_k (c_k · δ)²`).

use crate::FemError;

/// One term `w c cᵀ` of a Jacobian (`c` on the free DOFs).
#[derive(Debug, Clone, PartialEq)]
pub struct LowRankTerm {
    /// The vector `c`, one value per free DOF.
    pub vector: Vec<f64>,
    /// The weight `w` (> 0).
    pub weight: f64,
}

/// The Woodbury data of a set of terms for the current factor of `K`.
#[derive(Debug, Default, Clone)]
pub(crate) struct Woodbury {
    terms: Vec<LowRankTerm>,
    /// `z_k = K⁻¹ c_k`.
    z: Vec<Vec<f64>>,
    /// `S = W⁻¹ + Cᵀ Z`, row-major `k × k`.
    capacitance: Vec<f64>,
}

impl Woodbury {
    /// Replaces the terms (the factor data must then be refreshed).
    pub(crate) fn set_terms(&mut self, terms: &[LowRankTerm]) -> Result<(), FemError> {
        if let Some(t) = terms.iter().find(|t| !(t.weight > 0.0 && t.weight.is_finite())) {
            return Err(FemError::Numerical(format!(
                "a low-rank Jacobian term has weight {} (must be finite and > 0)",
                t.weight
            )));
        }
        self.terms = terms.to_vec();
        self.z.clear();
        self.capacitance.clear();
        Ok(())
    }

    /// True when there are no terms.
    pub(crate) fn is_empty(&self) -> bool {
        self.terms.is_empty()
    }

    /// Recomputes `Z` and `S` after a new factorisation of `K`; `solve` applies `K⁻¹` in place.
    pub(crate) fn refresh(
        &mut self,
        mut solve: impl FnMut(&mut [f64]) -> Result<(), FemError>,
    ) -> Result<(), FemError> {
        let k = self.terms.len();
        self.z = Vec::with_capacity(k);
        for term in &self.terms {
            let mut z = term.vector.clone();
            solve(&mut z)?;
            self.z.push(z);
        }
        self.capacitance = vec![0.0; k * k];
        for a in 0..k {
            for b in 0..k {
                self.capacitance[a * k + b] = dot(&self.terms[a].vector, &self.z[b]);
            }
            self.capacitance[a * k + a] += 1.0 / self.terms[a].weight;
        }
        Ok(())
    }

    /// Turns `x = K⁻¹ b` into `(K + C W Cᵀ)⁻¹ b` in place.
    pub(crate) fn correct(&self, x: &mut [f64]) -> Result<(), FemError> {
        let k = self.terms.len();
        if k == 0 {
            return Ok(());
        }
        let mut y: Vec<f64> = self.terms.iter().map(|t| dot(&t.vector, x)).collect();
        solve_dense(self.capacitance.clone(), &mut y)?;
        for (z, y) in self.z.iter().zip(&y) {
            for (xi, zi) in x.iter_mut().zip(z) {
                *xi -= y * zi;
            }
        }
        Ok(())
    }

    /// `Σ_k w_k (c_k · δ)²`: the terms' part of the curvature `δᵀ J δ`.
    pub(crate) fn curvature(&self, delta: &[f64]) -> f64 {
        self.terms.iter().map(|t| t.weight * dot(&t.vector, delta).powi(2)).sum()
    }
}

/// Solves the small dense system `a y = b` in place (Gaussian elimination with partial pivoting;
/// `a` row-major `n × n`).
fn solve_dense(mut a: Vec<f64>, b: &mut [f64]) -> Result<(), FemError> {
    let n = b.len();
    for col in 0..n {
        let pivot = (col..n)
            .max_by(|&i, &j| a[i * n + col].abs().total_cmp(&a[j * n + col].abs()))
            .unwrap_or(col);
        let magnitude = a[pivot * n + col].abs();
        if magnitude.is_nan() || magnitude <= 0.0 {
            return Err(FemError::Numerical("singular Woodbury capacitance matrix".into()));
        }
        if pivot != col {
            for j in 0..n {
                a.swap(col * n + j, pivot * n + j);
            }
            b.swap(col, pivot);
        }
        for row in col + 1..n {
            let factor = a[row * n + col] / a[col * n + col];
            for j in col..n {
                a[row * n + j] -= factor * a[col * n + j];
            }
            b[row] -= factor * b[col];
        }
    }
    for row in (0..n).rev() {
        let tail: f64 = (row + 1..n).map(|j| a[row * n + j] * b[j]).sum();
        b[row] = (b[row] - tail) / a[row * n + row];
    }
    Ok(())
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A diagonal `K` plus two rank-one terms: the corrected solve satisfies the full system.
    #[test]
    fn woodbury_solves_the_updated_system() {
        let k_diag = [2.0, 3.0, 5.0, 7.0];
        let terms = vec![
            LowRankTerm { vector: vec![1.0, 0.5, 0.0, -1.0], weight: 4.0 },
            LowRankTerm { vector: vec![0.0, 1.0, 2.0, 0.25], weight: 0.5 },
        ];
        let mut w = Woodbury::default();
        w.set_terms(&terms).unwrap();
        w.refresh(|v| {
            v.iter_mut().zip(&k_diag).for_each(|(x, d)| *x /= d);
            Ok(())
        })
        .unwrap();
        let b = [1.0, -2.0, 0.5, 3.0];
        let mut x: Vec<f64> = b.iter().zip(&k_diag).map(|(b, d)| b / d).collect();
        w.correct(&mut x).unwrap();
        for i in 0..4 {
            let mut ax = k_diag[i] * x[i];
            for t in &terms {
                ax += t.weight * t.vector[i] * dot(&t.vector, &x);
            }
            assert!((ax - b[i]).abs() < 1e-12, "row {i}: {ax} vs {}", b[i]);
        }
        let curvature = w.curvature(&x);
        let expected: f64 = terms.iter().map(|t| t.weight * dot(&t.vector, &x).powi(2)).sum();
        assert!((curvature - expected).abs() < 1e-14);
    }

    #[test]
    fn non_positive_weights_are_refused() {
        let mut w = Woodbury::default();
        let term = LowRankTerm { vector: vec![1.0], weight: 0.0 };
        assert!(w.set_terms(&[term]).is_err());
    }
}
