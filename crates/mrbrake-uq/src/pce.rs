//! Polynomial-chaos expansion (PCE) of a model output in the inputs' CDF variables, fitted by
//! least squares, with the basis chosen by the leave-one-out error.
//!
//! # The expansion
//!
//! `Y ≈ Σ_α c_α Ψ_α(u)`, `Ψ_α(u) = Π_i P̃_{α_i}(2u_i − 1)`, where `u_i = F_i(x_i)` is input `i`'s CDF
//! value (the unit-cube point of [`crate::qmc`]) and `P̃_k = √(2k + 1) P_k` the Legendre polynomials
//! orthonormal for the uniform law on `[−1, 1]` (Bonnet's recurrence
//! `(k + 1) P_{k+1}(ξ) = (2k + 1) ξ P_k(ξ) − k P_{k−1}(ξ)`, Abramowitz & Stegun 1964, eq. 22.7.10).
//!
//! **Why Legendre in `u = F(x)`**: for independent inputs with continuous laws the `u_i` are
//! independent and uniform on `(0, 1)` whatever the laws — normal, log-normal, triangular, any of
//! them truncated — so one orthonormal family serves every marginal (an isoprobabilistic transform;
//! Soize & Ghanem, "Physical systems with random uncertainties: chaos representations with
//! arbitrary probability measure", SIAM J. Sci. Comput. 26(2), 395–410, 2004). The Wiener–Askey
//! alternative (Hermite for normals, Laguerre, Jacobi; Xiu & Karniadakis, SIAM J. Sci. Comput.
//! 24(2), 619–644, 2002) has no family for a truncated or triangular law. The price is that the
//! model seen through `F⁻¹` may be less polynomial (a normal input's quantile is steep near
//! `u = 0, 1`); the degree chosen by the leave-one-out error absorbs it, and the error is reported.
//!
//! # Fit and basis selection
//!
//! Coefficients by ordinary least squares on the samples (Berveiller, Sudret & Lemaire, Eur. J.
//! Comput. Mech. 15, 81–92, 2006): normal equations by Cholesky when well conditioned (the rule for
//! an orthonormal basis), else a rank-revealing thin SVD (singular values below `max(n, P) ε s_max`
//! dropped, giving the minimum-norm solution). Candidate bases: the
//! total-degree sets `{α : Σ α_i ≤ p}` and the hyperbolic sets `{α : (Σ α_i^q)^{1/q} ≤ p}`, `q < 1`
//! (Blatman & Sudret, "Adaptive sparse polynomial chaos expansion based on least angle
//! regression", J. Comput. Phys. 230, 2345–2367, 2011), which keep high univariate degrees
//! but few interactions, for `p = 1, 2, …` while the basis has at most `max_terms_ratio · n` terms
//! (a least-squares oversampling of at least 2, and enough distinct points left in a bootstrap
//! resample, which holds ~63 % of them). The basis with the smallest **leave-one-out error** wins:
//! `ε_LOO = (1/n) Σ_i ((y_i − ŷ_i)/(1 − h_i))² / Var[y]` with `h_i` the diagonal of the hat matrix
//! `Ψ(ΨᵀΨ)⁻¹Ψᵀ` (the closed form of the LOO residual for least squares; Blatman & Sudret,
//! "Efficient computation of global sensitivity indices using sparse polynomial chaos expansions",
//! Reliab. Eng. Syst. Saf. 95, 1216–1229, 2010). For each `q` the degree stops rising once the
//! LOO error has grown twice in a row (over-fitting: the stopping rule of Blatman & Sudret 2011).

use crate::UqError;
use faer::Mat;

/// Options of the basis selection.
#[derive(Debug, Clone, PartialEq)]
pub struct PceOptions {
    /// Highest total degree tried (1 to 30).
    pub max_degree: usize,
    /// The q-norms of the candidate bases, each in `(0, 1]` (1 = total degree).
    pub q_norms: Vec<f64>,
    /// Largest basis, as a fraction of the number of samples, in `(0, 1)`.
    pub max_terms_ratio: f64,
}

impl Default for PceOptions {
    /// Degrees up to 12, q-norms 1, 0.75 and 0.5, at most n/2 terms.
    fn default() -> Self {
        Self { max_degree: 12, q_norms: vec![1.0, 0.75, 0.5], max_terms_ratio: 0.5 }
    }
}

impl PceOptions {
    fn validate(&self) -> Result<(), UqError> {
        let bad = |name, value, allowed| Err(UqError::InvalidOption { name, value, allowed });
        if !(1..=30).contains(&self.max_degree) {
            return bad("max_degree", self.max_degree as f64, "1 to 30");
        }
        if self.q_norms.is_empty() {
            return bad("q_norms", 0.0, "at least one q-norm");
        }
        if let Some(&q) = self.q_norms.iter().find(|q| !(**q > 0.0 && **q <= 1.0)) {
            return bad("q_norms", q, "each in (0, 1]");
        }
        if !(self.max_terms_ratio > 0.0 && self.max_terms_ratio < 1.0) {
            return bad("max_terms_ratio", self.max_terms_ratio, "in (0, 1)");
        }
        Ok(())
    }
}

/// A fitted polynomial-chaos expansion (module docs).
#[derive(Debug, Clone, PartialEq)]
pub struct Pce {
    terms: Vec<Vec<u8>>,
    coefficients: Vec<f64>,
    degree: usize,
    q_norm: f64,
    loo_error: f64,
    samples: usize,
}

impl Pce {
    /// Fits the expansion of outputs `y` at unit-cube points `u` (`u[k]` = the CDF values of sample
    /// `k`'s inputs; all rows of one length, values in `[0, 1]`), choosing the basis by the
    /// leave-one-out error among the candidates of `options`.
    pub fn fit(u: &[Vec<f64>], y: &[f64], options: &PceOptions) -> Result<Self, UqError> {
        options.validate()?;
        let dimension = check_samples(u, y)?;
        let cap = ((options.max_terms_ratio * u.len() as f64).floor() as usize).max(1);
        if dimension + 1 > cap {
            return Err(UqError::samples(
                "unit points",
                format!(
                    "{} samples cannot fit even a degree-1 expansion of {dimension} inputs \
                     (it needs at least {} samples at max_terms_ratio {})",
                    u.len(),
                    ((dimension + 1) as f64 / options.max_terms_ratio).ceil(),
                    options.max_terms_ratio
                ),
            ));
        }
        if sample_variance(y) <= 0.0 {
            return Ok(Self::constant(dimension, y[0], u.len()));
        }
        let table = LegendreTable::new(u, options.max_degree);
        let mut best: Option<Pce> = None;
        for &q in &options.q_norms {
            let candidate = select_degree(&table, y, q, options.max_degree, cap)?;
            if best.as_ref().is_none_or(|b| candidate.loo_error < b.loo_error) {
                best = Some(candidate);
            }
        }
        best.ok_or_else(|| UqError::numerical("no candidate basis could be fitted", Vec::new()))
    }

    /// The expansion of a constant output: one term, no variance.
    fn constant(dimension: usize, value: f64, samples: usize) -> Self {
        Self {
            terms: vec![vec![0; dimension]],
            coefficients: vec![value],
            degree: 0,
            q_norm: 1.0,
            loo_error: 0.0,
            samples,
        }
    }

    /// The number of inputs.
    pub fn dimension(&self) -> usize {
        self.terms[0].len()
    }

    /// The multi-indices `α` of the basis (the first is the constant term).
    pub fn terms(&self) -> &[Vec<u8>] {
        &self.terms
    }

    /// The coefficients `c_α`, in the order of [`Pce::terms`].
    pub fn coefficients(&self) -> &[f64] {
        &self.coefficients
    }

    /// The selected degree `p`.
    pub fn degree(&self) -> usize {
        self.degree
    }

    /// The selected q-norm (1 = total degree).
    pub fn q_norm(&self) -> f64 {
        self.q_norm
    }

    /// The relative leave-one-out error `ε_LOO` of the selected basis (module docs).
    pub fn loo_error(&self) -> f64 {
        self.loo_error
    }

    /// The number of samples fitted.
    pub fn samples(&self) -> usize {
        self.samples
    }

    /// The expansion's mean, `c_0` (the basis is orthonormal).
    pub fn mean(&self) -> f64 {
        self.coefficients[0]
    }

    /// The expansion's variance, `Σ_{α≠0} c_α²`.
    pub fn variance(&self) -> f64 {
        self.coefficients[1..].iter().map(|c| c * c).sum()
    }

    /// The expansion at unit-cube point `u` (one CDF value per input).
    pub fn evaluate(&self, u: &[f64]) -> f64 {
        let table = LegendreTable::new(&[u.to_vec()], usize::from(self.max_order()));
        table.row(0, &self.terms).iter().zip(&self.coefficients).map(|(p, c)| p * c).sum()
    }

    /// The highest univariate degree of the basis.
    fn max_order(&self) -> u8 {
        self.terms.iter().flatten().copied().max().unwrap_or(0)
    }

    /// First-order and total Sobol' indices from the coefficients (Sudret 2008: with an
    /// orthonormal basis the partial variances are sums of squared coefficients):
    /// `S_i = Σ_{α ∈ A_i} c_α² / D` over the terms in input `i` alone, `S_Ti = Σ_{α_i > 0} c_α² / D`,
    /// `D = Σ_{α≠0} c_α²`. A constant expansion (`D = 0`) has all indices 0.
    pub fn sobol_indices(&self) -> (Vec<f64>, Vec<f64>) {
        sobol_from_coefficients(&self.terms, &self.coefficients)
    }

    /// Refits the coefficients of this expansion's basis to other samples (the bootstrap's
    /// replicates), keeping degree and q-norm; the LOO error is that of the new fit.
    pub fn refit(&self, u: &[Vec<f64>], y: &[f64]) -> Result<Self, UqError> {
        check_samples(u, y)?;
        let table = LegendreTable::new(u, usize::from(self.max_order()));
        let fit = fit_terms(&table, y, &self.terms)?;
        Ok(Self { coefficients: fit.coefficients, loo_error: fit.loo_error, ..self.clone() })
    }
}

/// Sobol' indices of an orthonormal expansion (see [`Pce::sobol_indices`]).
pub(crate) fn sobol_from_coefficients(terms: &[Vec<u8>], c: &[f64]) -> (Vec<f64>, Vec<f64>) {
    let dimension = terms.first().map_or(0, Vec::len);
    let mut first = vec![0.0; dimension];
    let mut total = vec![0.0; dimension];
    let mut variance = 0.0;
    for (alpha, coefficient) in terms.iter().zip(c) {
        let active: Vec<usize> = (0..dimension).filter(|&i| alpha[i] > 0).collect();
        if active.is_empty() {
            continue;
        }
        let share = coefficient * coefficient;
        variance += share;
        for &i in &active {
            total[i] += share;
        }
        if let [only] = active[..] {
            first[only] += share;
        }
    }
    if variance > 0.0 {
        first.iter_mut().chain(total.iter_mut()).for_each(|s| *s = (*s / variance).min(1.0));
    }
    (first, total)
}

/// For one q-norm, the basis of degree `1..=max_degree` with the smallest LOO error (module docs).
fn select_degree(
    table: &LegendreTable,
    y: &[f64],
    q: f64,
    max_degree: usize,
    cap: usize,
) -> Result<Pce, UqError> {
    let mut best: Option<Pce> = None;
    let (mut previous_terms, mut previous_loo, mut rises) = (0, f64::INFINITY, 0);
    for degree in 1..=max_degree {
        let Some(terms) = multi_indices(table.dimension, degree, q, cap) else {
            break;
        };
        if terms.len() == previous_terms {
            continue; // a hyperbolic set that did not grow
        }
        previous_terms = terms.len();
        let fit = fit_terms(table, y, &terms)?;
        let loo = fit.loo_error;
        if best.as_ref().is_none_or(|b| loo < b.loo_error) {
            best = Some(Pce {
                terms,
                coefficients: fit.coefficients,
                degree,
                q_norm: q,
                loo_error: loo,
                samples: y.len(),
            });
        }
        rises = if loo > previous_loo { rises + 1 } else { 0 };
        previous_loo = loo;
        if rises >= 2 {
            break;
        }
    }
    best.ok_or_else(|| UqError::numerical("no candidate basis fits the sample size", Vec::new()))
}

/// The multi-indices of `dimension` inputs with q-norm `(Σ α_i^q)^{1/q} ≤ degree`, graded by total
/// degree (the zero index first); `None` when there are more than `cap`.
pub(crate) fn multi_indices(
    dimension: usize,
    degree: usize,
    q: f64,
    cap: usize,
) -> Option<Vec<Vec<u8>>> {
    let budget = (degree as f64).powf(q) * (1.0 + 1e-12);
    let mut out = Vec::new();
    let mut current = vec![0u8; dimension];
    if !extend(&mut current, 0, 0.0, degree, q, budget, cap, &mut out) {
        return None;
    }
    out.sort_by_key(|alpha| (alpha.iter().map(|&a| usize::from(a)).sum::<usize>(), alpha.clone()));
    Some(out)
}

/// Depth-first enumeration for [`multi_indices`]: sets `current[i..]` in every admissible way given
/// the q-norm sum `used` of `current[..i]`; false once `cap` is exceeded.
fn extend(
    current: &mut Vec<u8>,
    i: usize,
    used: f64,
    degree: usize,
    q: f64,
    budget: f64,
    cap: usize,
    out: &mut Vec<Vec<u8>>,
) -> bool {
    if i == current.len() {
        out.push(current.clone());
        return out.len() <= cap;
    }
    for k in 0..=degree {
        let cost = used + (k as f64).powf(q);
        if k > 0 && cost > budget {
            break;
        }
        current[i] = k as u8;
        if !extend(current, i + 1, cost, degree, q, budget, cap, out) {
            return false;
        }
    }
    current[i] = 0;
    true
}

/// Orthonormal Legendre values `P̃_k(2u − 1)`, `k = 0..=max_degree`, per sample and input.
pub(crate) struct LegendreTable {
    dimension: usize,
    order: usize,
    /// `values[(k * dimension + i) * (order + 1) + degree]`.
    values: Vec<f64>,
}

impl LegendreTable {
    pub(crate) fn new(u: &[Vec<f64>], max_degree: usize) -> Self {
        let dimension = u.first().map_or(0, Vec::len);
        let order = max_degree;
        let mut values = Vec::with_capacity(u.len() * dimension * (order + 1));
        for row in u {
            for &ui in row {
                let xi = 2.0 * ui - 1.0;
                let (mut previous, mut current) = (0.0, 1.0);
                for k in 0..=order {
                    values.push(current * ((2 * k + 1) as f64).sqrt());
                    // Bonnet: P_{k+1} = ((2k + 1) ξ P_k − k P_{k−1}) / (k + 1).
                    let next =
                        ((2 * k + 1) as f64 * xi * current - k as f64 * previous) / (k + 1) as f64;
                    (previous, current) = (current, next);
                }
            }
        }
        Self { dimension, order, values }
    }

    /// The basis functions `Ψ_α` of `terms` at sample `k`.
    pub(crate) fn row(&self, k: usize, terms: &[Vec<u8>]) -> Vec<f64> {
        let stride = self.order + 1;
        let base = k * self.dimension * stride;
        terms
            .iter()
            .map(|alpha| {
                alpha
                    .iter()
                    .enumerate()
                    .filter(|(_, a)| **a > 0)
                    .map(|(i, &a)| self.values[base + i * stride + usize::from(a)])
                    .product()
            })
            .collect()
    }
}

/// A least-squares fit: coefficients and its relative LOO error.
pub(crate) struct Fit {
    pub(crate) coefficients: Vec<f64>,
    pub(crate) loo_error: f64,
}

/// Fits the coefficients of `terms` to `y` over all samples of `table` (module docs).
pub(crate) fn fit_terms(
    table: &LegendreTable,
    y: &[f64],
    terms: &[Vec<u8>],
) -> Result<Fit, UqError> {
    let rows: Vec<Vec<f64>> = (0..y.len()).map(|k| table.row(k, terms)).collect();
    let psi = Mat::from_fn(y.len(), terms.len(), |k, j| rows[k][j]);
    let (coefficients, leverage) = least_squares(&psi, y)?;
    let variance = sample_variance(y);
    let mut sum = 0.0;
    for (k, row) in rows.iter().enumerate() {
        let fitted: f64 = row.iter().zip(&coefficients).map(|(p, c)| p * c).sum();
        let denominator = 1.0 - leverage[k];
        if denominator <= 1e-12 {
            // The sample is interpolated: its LOO residual is unbounded.
            return Ok(Fit { coefficients, loo_error: f64::INFINITY });
        }
        sum += ((y[k] - fitted) / denominator).powi(2);
    }
    let loo_error = if variance > 0.0 { sum / y.len() as f64 / variance } else { 0.0 };
    Ok(Fit { coefficients, loo_error })
}

/// Least squares `min ‖Ψ c − y‖`; returns `c` and the hat matrix's diagonal `h_k`. The normal
/// equations `ΨᵀΨ c = Ψᵀy` by Cholesky serve when they are well conditioned, which an orthonormal
/// basis sampled by its own measure makes the rule (`ΨᵀΨ/n → I`; Cohen, Davenport & Leviathan, "On
/// the stability and accuracy of least squares approximations", Found. Comput. Math. 13, 819–834,
/// 2013): half the cost of a QR and a fraction of an SVD's, which the bootstrap's hundreds of refits
/// notice. Otherwise (a pivot below 10⁻⁶ of the largest, i.e. `cond(ΨᵀΨ) ≳ 10¹²`, or a failed
/// factorisation) the thin SVD takes over.
fn least_squares(psi: &Mat<f64>, y: &[f64]) -> Result<(Vec<f64>, Vec<f64>), UqError> {
    match normal_equations(psi, y) {
        Some(solution) => Ok(solution),
        None => svd_least_squares(psi, y),
    }
}

/// The normal-equation solution (see [`least_squares`]): `G = ΨᵀΨ = LLᵀ`, `W = L⁻¹Ψᵀ`,
/// `h_k = ‖W e_k‖²`, `c = L⁻ᵀ W y`; `None` when `G` is ill-conditioned.
fn normal_equations(psi: &Mat<f64>, y: &[f64]) -> Option<(Vec<f64>, Vec<f64>)> {
    let (n, p) = (psi.nrows(), psi.ncols());
    let gram = psi.transpose() * psi;
    let llt = gram.llt(faer::Side::Lower).ok()?;
    let l = llt.L();
    let pivots: Vec<f64> = (0..p).map(|k| l[(k, k)]).collect();
    let largest = pivots.iter().copied().fold(0.0, f64::max);
    if pivots.iter().any(|&d| d.is_nan() || d <= 1e-6 * largest) {
        return None;
    }
    let mut w = psi.transpose().to_owned();
    l.solve_lower_triangular_in_place(&mut w);
    let leverage = (0..n).map(|k| (0..p).map(|j| w[(j, k)] * w[(j, k)]).sum()).collect();
    let mut c = Mat::from_fn(p, 1, |j, _| (0..n).map(|k| w[(j, k)] * y[k]).sum::<f64>());
    l.transpose().solve_upper_triangular_in_place(&mut c);
    Some(((0..p).map(|j| c[(j, 0)]).collect(), leverage))
}

/// Least squares by thin SVD, singular values below `max(n, P) ε s_max` dropped (minimum-norm
/// solution); `h_k = Σ_j U_kj²` over the kept singular values.
fn svd_least_squares(psi: &Mat<f64>, y: &[f64]) -> Result<(Vec<f64>, Vec<f64>), UqError> {
    let (n, p) = (psi.nrows(), psi.ncols());
    // faer's only SVD failure is a non-converged iteration (its `Debug` says no more).
    let svd = psi.thin_svd().map_err(|_| {
        UqError::numerical(format!("the SVD of the {n}×{p} PCE design did not converge"), vec![])
    })?;
    let (u, s, v) = (svd.U(), svd.S().column_vector(), svd.V());
    let s_max = (0..s.nrows()).map(|j| s[j]).fold(0.0, f64::max);
    let tolerance = n.max(p) as f64 * f64::EPSILON * s_max;
    let mut coefficients = vec![0.0; p];
    let mut leverage = vec![0.0; n];
    for j in (0..s.nrows()).filter(|&j| s[j] > tolerance) {
        let projection: f64 = (0..n).map(|k| u[(k, j)] * y[k]).sum::<f64>() / s[j];
        for (i, c) in coefficients.iter_mut().enumerate() {
            *c += v[(i, j)] * projection;
        }
        for (k, h) in leverage.iter_mut().enumerate() {
            *h += u[(k, j)] * u[(k, j)];
        }
    }
    Ok((coefficients, leverage))
}

/// Sample variance (`n − 1`) of `y` (0 for fewer than two samples).
fn sample_variance(y: &[f64]) -> f64 {
    if y.len() < 2 {
        return 0.0;
    }
    let mean = y.iter().sum::<f64>() / y.len() as f64;
    y.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (y.len() - 1) as f64
}

/// Checks `u` (non-empty, rows of one length ≥ 1, values finite in `[0, 1]`) against `y` (one
/// finite output per row); returns the dimension.
pub(crate) fn check_samples(u: &[Vec<f64>], y: &[f64]) -> Result<usize, UqError> {
    let dimension = u.first().map_or(0, Vec::len);
    if u.is_empty() || dimension == 0 {
        return Err(UqError::samples("unit points", "no samples or no inputs"));
    }
    if y.len() != u.len() {
        return Err(UqError::samples(
            "outputs",
            format!("{} outputs for {} samples", y.len(), u.len()),
        ));
    }
    for (k, row) in u.iter().enumerate() {
        if row.len() != dimension {
            return Err(UqError::samples(
                "unit points",
                format!("sample {k} has {} inputs, sample 0 has {dimension}", row.len()),
            ));
        }
        if let Some(i) = row.iter().position(|x| !(0.0..=1.0).contains(x)) {
            return Err(UqError::samples(
                "unit points",
                format!("sample {k}, input {i} is {}, outside [0, 1]", row[i]),
            ));
        }
    }
    if let Some(k) = y.iter().position(|v| !v.is_finite()) {
        return Err(UqError::samples("outputs", format!("sample {k} is {}", y[k])));
    }
    Ok(dimension)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn multi_index_counts() {
        // Total degree p in d inputs: C(d + p, p) terms.
        assert_eq!(multi_indices(3, 2, 1.0, 1000).unwrap().len(), 10);
        assert_eq!(multi_indices(8, 2, 1.0, 1000).unwrap().len(), 45);
        assert_eq!(multi_indices(8, 3, 1.0, 1000).unwrap().len(), 165);
        assert!(multi_indices(8, 3, 1.0, 100).is_none());
        // q = 0.5, p = 3: univariate terms only (1 + 3·d).
        assert_eq!(multi_indices(8, 3, 0.5, 1000).unwrap().len(), 25);
        // q = 0.75, p = 3: univariate up to 3 plus every pair (1, 1).
        assert_eq!(multi_indices(8, 3, 0.75, 1000).unwrap().len(), 1 + 24 + 28);
        let terms = multi_indices(2, 2, 1.0, 100).unwrap();
        assert_eq!(terms[0], vec![0, 0]);
    }

    #[test]
    fn legendre_values_are_orthonormal_polynomials() {
        // P̃_2(ξ) = √5 (3ξ² − 1)/2 at u = 0.8 (ξ = 0.6).
        let table = LegendreTable::new(&[vec![0.8]], 3);
        let row = table.row(0, &[vec![0], vec![1], vec![2], vec![3]]);
        assert!((row[1] - 3f64.sqrt() * 0.6).abs() < 1e-15);
        assert!((row[2] - 5f64.sqrt() * (3.0 * 0.36 - 1.0) / 2.0).abs() < 1e-15);
        assert!((row[3] - 7f64.sqrt() * (5.0 * 0.216 - 3.0 * 0.6) / 2.0).abs() < 1e-15);
    }

    #[test]
    fn exact_polynomial_is_recovered_with_zero_loo() {
        let u: Vec<Vec<f64>> = crate::qmc::ScrambledSobol::new(2, 5).unwrap().points(64).unwrap();
        let y: Vec<f64> = u.iter().map(|p| 1.0 + 2.0 * p[0] + p[0] * p[1]).collect();
        let pce = Pce::fit(&u, &y, &PceOptions::default()).unwrap();
        assert!(pce.loo_error() < 1e-20, "{}", pce.loo_error());
        assert!((pce.evaluate(&[0.3, 0.9]) - (1.0 + 0.6 + 0.27)).abs() < 1e-12);
        // E[1 + 2u + uv] = 1 + 1 + 1/4.
        assert!((pce.mean() - 2.25).abs() < 1e-12);
    }

    #[test]
    fn rank_deficient_design_falls_back_to_the_svd() {
        // Two identical columns: the normal equations are singular; the SVD's minimum-norm
        // solution splits the coefficient evenly and the hat matrix keeps rank 1.
        let psi = Mat::from_fn(4, 2, |k, _| 1.0 + k as f64);
        let y = [2.0, 4.0, 6.0, 8.0];
        assert!(normal_equations(&psi, &y).is_none());
        let (c, h) = least_squares(&psi, &y).unwrap();
        assert!((c[0] - 1.0).abs() < 1e-12 && (c[1] - 1.0).abs() < 1e-12, "{c:?}");
        assert!((h.iter().sum::<f64>() - 1.0).abs() < 1e-12);
        // A well-conditioned design takes the normal equations, with the same answer as the SVD.
        let psi = Mat::from_fn(5, 2, |k, j| if j == 0 { 1.0 } else { k as f64 });
        let y = [1.0, 3.0, 2.0, 5.0, 4.0];
        let (c1, h1) = normal_equations(&psi, &y).unwrap();
        let (c2, h2) = svd_least_squares(&psi, &y).unwrap();
        assert!(c1.iter().zip(&c2).all(|(a, b)| (a - b).abs() < 1e-12));
        assert!(h1.iter().zip(&h2).all(|(a, b)| (a - b).abs() < 1e-12));
    }

    #[test]
    fn bad_samples_and_options() {
        let u = vec![vec![0.5, 0.5]; 4];
        assert!(Pce::fit(&u, &[1.0; 3], &PceOptions::default()).is_err());
        assert!(Pce::fit(&u, &[1.0, 2.0, 3.0, 4.0], &PceOptions::default()).is_err()); // too few
        let options = PceOptions { q_norms: vec![1.5], ..PceOptions::default() };
        assert!(Pce::fit(&u, &[1.0; 4], &options).is_err());
        let outside = vec![vec![0.5, 1.5]; 8];
        assert!(Pce::fit(&outside, &[1.0; 8], &PceOptions::default()).is_err());
        let constant = vec![vec![0.1, 0.2]; 8];
        let pce = Pce::fit(&constant, &[3.0; 8], &PceOptions::default()).unwrap();
        assert_eq!(pce.sobol_indices(), (vec![0.0; 2], vec![0.0; 2]));
        assert!((pce.mean() - 3.0).abs() < 1e-15 && pce.variance() < 1e-300);
    }
}
