//! Practical identifiability of a least-squares estimate from its Jacobian: which parameters (or
//! combinations of them) the residuals cannot pin down, reported as groups, never as a failure or a
//! NaN.
//!
//! The Jacobian's columns are scaled to unit length, `J̃ = J D⁻¹`, `D = diag(‖J_j‖)`, which
//! removes the parameters' units (Brun, Reichert & Künsch, "Practical identifiability analysis of
//! large environmental simulation models", Water Resour. Res. 37(4), 1015–1030, 2001). Its
//! singular values `s_k` and right singular vectors `v_k` describe every direction of parameter
//! space: a direction with a small `s_k` changes the residuals little, and its **collinearity
//! index** `γ_k = 1/s_k` (Brun et al.'s index is that of the smallest; they call a set with `γ` above
//! 10–15 poorly identifiable) is reported as a **weak direction** with its loadings `v_k` when it exceeds the
//! threshold. A parameter takes part in a weak direction when its loading is at least 0.3 times
//! the direction's largest. A parameter the residuals do not depend on has a zero column and a
//! direction of its own with `s = 0`.
//!
//! The covariance structure is `(JᵀJ)⁻¹ = D⁻¹ V diag(1/s̃²) Vᵀ D⁻¹` with `s̃ = max(s, √ε)`: finite
//! for every direction, huge for an unidentifiable one, so the correlation of a pair that only
//! enters as a product comes out as ±1 rather than NaN. **Unidentifiable groups** are the connected
//! sets of parameters linked by `|ρ_ij|` above the correlation threshold or by a common weak
//! direction (a parameter alone in a weak direction is a group of one).

use crate::UqError;
use faer::Mat;
use serde::Serialize;

/// A weak direction of parameter space (module docs).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct WeakDirection {
    /// Singular value of the column-normalised Jacobian along it (collinearity index = 1/this).
    pub singular_value: f64,
    /// The direction in column-normalised coordinates (unit length, largest entry positive), one
    /// loading per parameter: moving the parameters by `loadings[j] / ‖J_j‖` each changes the
    /// residuals by only `singular_value`.
    pub loadings: Vec<f64>,
    /// The parameters that take part (loading ≥ 0.3 × the largest).
    pub parameters: Vec<usize>,
}

impl WeakDirection {
    /// The collinearity index `γ = 1/s` (infinite for an exactly null direction).
    pub fn collinearity_index(&self) -> f64 {
        1.0 / self.singular_value
    }
}

/// What the residuals can and cannot identify.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Identifiability {
    /// Singular values of the column-normalised Jacobian, largest first, one per parameter.
    pub singular_values: Vec<f64>,
    /// Directions whose collinearity index exceeds the threshold, weakest first.
    pub weak_directions: Vec<WeakDirection>,
    /// Groups of parameters (indices, ascending) that cannot be identified separately.
    pub unidentifiable: Vec<Vec<usize>>,
}

/// The identifiability of a Jacobian and its covariance structure.
pub(crate) struct Analysis {
    pub(crate) identifiability: Identifiability,
    /// Correlation matrix of the estimate.
    pub(crate) correlation: Vec<Vec<f64>>,
    /// `((JᵀJ)⁻¹)_jj`, infinite for a zero column; standard error = σ √ this.
    pub(crate) unit_variance: Vec<f64>,
}

/// Analyses the Jacobian `j` (residuals × parameters, in the parameters' units).
pub(crate) fn analyse(
    j: &Mat<f64>,
    correlation_threshold: f64,
    collinearity_threshold: f64,
) -> Result<Analysis, UqError> {
    let (m, p) = (j.nrows(), j.ncols());
    let norms: Vec<f64> =
        (0..p).map(|c| (0..m).map(|i| j[(i, c)].powi(2)).sum::<f64>().sqrt()).collect();
    let scaled = Mat::from_fn(m, p, |i, c| if norms[c] > 0.0 { j[(i, c)] / norms[c] } else { 0.0 });
    let svd = if m >= p { scaled.thin_svd() } else { scaled.svd() }.map_err(|_| {
        UqError::numerical("the SVD of the Jacobian did not converge".to_string(), vec![])
    })?;
    let (s_diag, v) = (svd.S().column_vector(), svd.V());
    let s: Vec<f64> = (0..p).map(|k| if k < s_diag.nrows() { s_diag[k] } else { 0.0 }).collect();
    let floor = f64::EPSILON.sqrt();
    let inverse: Vec<f64> = s.iter().map(|&sk| sk.max(floor).powi(-2)).collect();
    let k_matrix: Vec<Vec<f64>> = (0..p)
        .map(|a| (0..p).map(|b| (0..p).map(|k| v[(a, k)] * inverse[k] * v[(b, k)]).sum()).collect())
        .collect();
    let correlation: Vec<Vec<f64>> = (0..p)
        .map(|a| {
            (0..p)
                .map(|b| {
                    let rho = k_matrix[a][b] / (k_matrix[a][a] * k_matrix[b][b]).sqrt();
                    if a == b { 1.0 } else { rho.clamp(-1.0, 1.0) }
                })
                .collect()
        })
        .collect();
    let unit_variance = (0..p)
        .map(|c| if norms[c] > 0.0 { k_matrix[c][c] / norms[c].powi(2) } else { f64::INFINITY })
        .collect();
    let weak_directions: Vec<WeakDirection> = (0..p)
        .rev()
        .filter(|&k| s[k] * collinearity_threshold < 1.0)
        .map(|k| weak_direction(s[k], (0..p).map(|a| v[(a, k)]).collect()))
        .collect();
    let unidentifiable = groups(&correlation, &weak_directions, correlation_threshold);
    Ok(Analysis {
        identifiability: Identifiability { singular_values: s, weak_directions, unidentifiable },
        correlation,
        unit_variance,
    })
}

/// A weak direction with its sign fixed (largest loading positive) and its participants.
fn weak_direction(singular_value: f64, mut loadings: Vec<f64>) -> WeakDirection {
    let largest =
        loadings.iter().copied().fold(0.0, |a: f64, b| if b.abs() > a.abs() { b } else { a });
    if largest < 0.0 {
        loadings.iter_mut().for_each(|l| *l = -*l);
    }
    let parameters =
        (0..loadings.len()).filter(|&a| loadings[a].abs() >= 0.3 * largest.abs()).collect();
    WeakDirection { singular_value, loadings, parameters }
}

/// Connected groups of parameters linked by a high correlation or a common weak direction
/// (union–find), plus the parameters alone in a weak direction.
fn groups(correlation: &[Vec<f64>], weak: &[WeakDirection], threshold: f64) -> Vec<Vec<usize>> {
    let p = correlation.len();
    let mut parent: Vec<usize> = (0..p).collect();
    let mut flagged = vec![false; p];
    let mut links: Vec<(usize, usize)> = Vec::new();
    for a in 0..p {
        for b in a + 1..p {
            if correlation[a][b].abs() > threshold {
                links.push((a, b));
            }
        }
    }
    for direction in weak {
        links.extend(direction.parameters.windows(2).map(|pair| (pair[0], pair[1])));
        direction.parameters.iter().for_each(|&a| flagged[a] = true);
    }
    for (a, b) in links {
        let (ra, rb) = (root(&mut parent, a), root(&mut parent, b));
        parent[ra.max(rb)] = ra.min(rb);
        flagged[a] = true;
        flagged[b] = true;
    }
    let mut out: Vec<(usize, Vec<usize>)> = Vec::new();
    for a in (0..p).filter(|&a| flagged[a]) {
        let r = root(&mut parent, a);
        match out.iter_mut().find(|(group_root, _)| *group_root == r) {
            Some((_, group)) => group.push(a),
            None => out.push((r, vec![a])),
        }
    }
    out.into_iter().map(|(_, group)| group).collect()
}

/// The representative of `a`'s set (union–find with path halving).
fn root(parent: &mut [usize], mut a: usize) -> usize {
    while parent[a] != a {
        parent[a] = parent[parent[a]];
        a = parent[a];
    }
    a
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn product_pair_and_dead_parameter_are_reported() {
        // r = a·b·t + c·t² with a = 2, b = 3: columns b t and a t are parallel; d has no effect.
        let t: Vec<f64> = (1..=10).map(f64::from).collect();
        let j = Mat::from_fn(10, 4, |i, c| match c {
            0 => 3.0 * t[i],
            1 => 2.0 * t[i],
            2 => t[i] * t[i],
            _ => 0.0,
        });
        let a = analyse(&j, 0.95, 20.0).unwrap();
        let id = &a.identifiability;
        assert_eq!(id.unidentifiable, vec![vec![0, 1], vec![3]]);
        assert!((a.correlation[0][1] + 1.0).abs() < 1e-6, "{}", a.correlation[0][1]);
        assert!(a.unit_variance[3].is_infinite());
        assert!(a.correlation.iter().flatten().all(|x| x.is_finite()));
        assert_eq!(id.weak_directions.len(), 2);
    }

    #[test]
    fn well_posed_jacobian_has_no_groups() {
        let j = Mat::from_fn(6, 2, |i, c| if c == 0 { 1.0 } else { i as f64 });
        let a = analyse(&j, 0.95, 20.0).unwrap();
        assert!(a.identifiability.unidentifiable.is_empty());
        assert!(a.identifiability.weak_directions.is_empty());
        // Straight-line fit: Var(slope) = 1/Σ(t − t̄)² = 1/17.5.
        assert!((a.unit_variance[1] - 1.0 / 17.5).abs() < 1e-12);
    }
}
