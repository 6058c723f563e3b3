//! Non-negative least squares on the normal equations (Lawson & Hanson's active-set algorithm).
//!
//! C. L. Lawson, R. J. Hanson, *Solving Least Squares Problems*, Prentice-Hall 1974, ch. 23,
//! algorithm NNLS. The problems here are small (at most [`super::MAX_TERMS`] unknowns) and
//! over-determined, so the algorithm works on `G = AᵀA` and `c = Aᵀb` (columns scaled to unit norm by
//! the caller, which keeps `G` well scaled); the passive subsystems are solved by Cholesky with a
//! tiny ridge `1e-13·max diag(G)` that only matters for exactly dependent columns.

/// Solves `min |A x − b|²` subject to `x ≥ 0` given `G = AᵀA` (row-major `n×n`) and `c = Aᵀb`.
pub(crate) fn nnls(g: &[f64], c: &[f64]) -> Vec<f64> {
    let n = c.len();
    let mut x = vec![0.0; n];
    let mut passive = vec![false; n];
    let scale = (0..n).map(|i| g[i * n + i]).fold(0.0, f64::max).max(f64::MIN_POSITIVE);
    let tolerance = 1e-12 * scale.max(c.iter().fold(0.0, |m, v| m.max(v.abs())));
    for _ in 0..3 * n + 3 {
        let w = gradient(g, c, &x);
        let entering = (0..n)
            .filter(|&j| !passive[j] && w[j] > tolerance)
            .max_by(|&a, &b| w[a].total_cmp(&w[b]));
        let Some(j) = entering else { break };
        passive[j] = true;
        for _ in 0..n + 1 {
            let z = solve_passive(g, c, &passive);
            if (0..n).all(|i| !passive[i] || z[i] > 0.0) {
                x = z;
                break;
            }
            // Step from x towards z until the first passive variable reaches zero.
            let alpha = (0..n)
                .filter(|&i| passive[i] && z[i] <= 0.0)
                .map(|i| x[i] / (x[i] - z[i]))
                .fold(1.0, f64::min);
            for i in 0..n {
                x[i] += alpha * (z[i] - x[i]);
                if passive[i] && x[i] <= 1e-15 * scale {
                    passive[i] = false;
                    x[i] = 0.0;
                }
            }
        }
    }
    x
}

/// `c − G x`: the negative gradient of `|Ax − b|²/2`.
fn gradient(g: &[f64], c: &[f64], x: &[f64]) -> Vec<f64> {
    let n = c.len();
    (0..n).map(|i| c[i] - (0..n).map(|j| g[i * n + j] * x[j]).sum::<f64>()).collect()
}

/// The unconstrained least-squares solution on the passive set (zero elsewhere).
fn solve_passive(g: &[f64], c: &[f64], passive: &[bool]) -> Vec<f64> {
    let n = c.len();
    let index: Vec<usize> = (0..n).filter(|&i| passive[i]).collect();
    let m = index.len();
    let mut sub = vec![0.0; m * m];
    for (a, &i) in index.iter().enumerate() {
        for (b, &j) in index.iter().enumerate() {
            sub[a * m + b] = g[i * n + j];
        }
    }
    let rhs: Vec<f64> = index.iter().map(|&i| c[i]).collect();
    let solution = solve_spd(&sub, &rhs);
    let mut z = vec![0.0; n];
    for (a, &i) in index.iter().enumerate() {
        z[i] = solution[a];
    }
    z
}

/// Solves `S y = r` for a symmetric positive semi-definite `S` (row-major `m×m`) by Cholesky with a
/// tiny ridge.
pub(crate) fn solve_spd(s: &[f64], r: &[f64]) -> Vec<f64> {
    let l = cholesky(s, r.len());
    let m = r.len();
    let mut y = r.to_vec();
    for i in 0..m {
        for k in 0..i {
            y[i] -= l[i * m + k] * y[k];
        }
        y[i] /= l[i * m + i];
    }
    for i in (0..m).rev() {
        for k in i + 1..m {
            y[i] -= l[k * m + i] * y[k];
        }
        y[i] /= l[i * m + i];
    }
    y
}

/// The lower Cholesky factor of `S + ridge I`.
fn cholesky(s: &[f64], m: usize) -> Vec<f64> {
    let ridge = 1e-13 * (0..m).map(|i| s[i * m + i]).fold(0.0, f64::max).max(f64::MIN_POSITIVE);
    let mut l = vec![0.0; m * m];
    for i in 0..m {
        for j in 0..=i {
            let mut sum = s[i * m + j] + if i == j { ridge } else { 0.0 };
            for k in 0..j {
                sum -= l[i * m + k] * l[j * m + k];
            }
            l[i * m + j] = if i == j { sum.max(ridge).sqrt() } else { sum / l[j * m + j] };
        }
    }
    l
}

#[cfg(test)]
mod tests {
    use super::*;

    fn normal_equations(a: &[Vec<f64>], b: &[f64]) -> (Vec<f64>, Vec<f64>) {
        let n = a[0].len();
        let mut g = vec![0.0; n * n];
        let mut c = vec![0.0; n];
        for (row, &bi) in a.iter().zip(b) {
            for i in 0..n {
                c[i] += row[i] * bi;
                for j in 0..n {
                    g[i * n + j] += row[i] * row[j];
                }
            }
        }
        (g, c)
    }

    #[test]
    fn recovers_a_positive_solution_and_clamps_a_negative_one() {
        let a = vec![vec![1.0, 0.0], vec![0.0, 1.0], vec![1.0, 1.0]];
        let (g, c) = normal_equations(&a, &[2.0, 3.0, 5.0]);
        let x = nnls(&g, &c);
        assert!((x[0] - 2.0).abs() < 1e-12 && (x[1] - 3.0).abs() < 1e-12, "{x:?}");
        // Unconstrained optimum (−1, 3): NNLS gives x0 = 0 and the best x1 then.
        let (g, c) = normal_equations(&a, &[-1.0, 3.0, 2.0]);
        let x = nnls(&g, &c);
        assert!(x[0].abs() < 1e-15 && (x[1] - 2.5).abs() < 1e-12, "{x:?}");
    }
}
