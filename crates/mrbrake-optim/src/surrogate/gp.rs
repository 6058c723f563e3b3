//! Gaussian-process (Kriging) regression on the unit box, with maximum-likelihood hyper-parameters
//! and closed-form leave-one-out residuals.
//!
//! The model (ordinary Kriging; Sacks, Welch, Mitchell & Wynn 1989, "Design and analysis of computer
//! experiments", Statist. Sci. 4(4), 409–423; Rasmussen & Williams, *Gaussian Processes for Machine
//! Learning*, MIT Press 2006, hereafter R&W) of standardised outputs `y`:
//! `y(z) = β + σ² · Z(z)` with a constant mean `β`, a process variance `σ²`, and the correlation
//!
//! * `c(z, z') = (1 + √5 r + 5 r²/3) exp(−√5 r)` (Matérn ν = 5/2, R&W eq. 4.17) of the anisotropic
//!   distance `r² = Σ_k δ_k(z, z')² / ℓ_k²`, one length scale `ℓ_k` per feature;
//! * `δ_k = z_k − z'_k` for a continuous or integer feature, and `δ_k = [z_k ≠ z'_k]` (0 or 1) for a
//!   categorical one: the exchangeable ("compound symmetry") correlation of unordered levels
//!   (Qian, Wu & Wu 2008, "Gaussian process models for computer experiments with qualitative and
//!   quantitative factors", Technometrics 50(3), 383–396; Roustant et al. 2020, "Group kernels for
//!   Gaussian process metamodels with categorical inputs", SIAM/ASA JUQ 8(2), 775–806). It is the
//!   Matérn kernel of the one-hot encoding with one shared length scale, hence positive definite;
//!   every pair of distinct levels is equally correlated, which is all that can be said of levels
//!   without an order.
//! * a nugget `η` on the diagonal (`R = C + η I`): numerical noise of the evaluations (mesh
//!   changes with the geometry) and the conditioning of `R` (Andrianakis & Challenor 2012, "The
//!   effect of the nugget on Gaussian process emulators of computer models", CSDA 56(12)).
//!
//! Given the hyper-parameters `θ = (log ℓ_1, …, log ℓ_d, log η)`, the generalised-least-squares mean
//! `β̂ = 1ᵀR⁻¹y / 1ᵀR⁻¹1` and variance `σ̂² = (y − β̂1)ᵀR⁻¹(y − β̂1) / n` maximise the likelihood, which
//! leaves the concentrated log-likelihood (Jones, Schonlau & Welch 1998, "Efficient global
//! optimization of expensive black-box functions", J. Global Optim. 13, 455–492, eq. (4))
//! `ℓ(θ) = −½ (n log σ̂² + log|R|)` and, since `β̂` and `σ̂²` are stationary points (envelope
//! theorem), its gradient (R&W eq. 5.9 with `α = R⁻¹(y − β̂1)`):
//! `∂ℓ/∂θ_j = ½ Σ_ik (α_i α_k / σ̂² − [R⁻¹]_ik) ∂R_ik/∂θ_j`, with
//! `∂R_ik/∂log ℓ_j = (5/3)(1 + √5 r) exp(−√5 r) δ_j² / ℓ_j²` and `∂R/∂log η = η I`.
//! It is maximised by projected L-BFGS (`local.rs`): from the previous iteration's optimum
//! when given (warm start), else from a default start and points of a Sobol' sequence over the box.
//!
//! Prediction at `z` (R&W eqs. 2.25–2.26 with the estimated-mean term of universal Kriging,
//! Santner, Williams & Notz, *The Design and Analysis of Computer Experiments*, 2003, eq. 3.4.4):
//! `μ(z) = β̂ + kᵀα`, `s²(z) = σ̂² (1 − kᵀR⁻¹k + (1 − 1ᵀR⁻¹k)² / 1ᵀR⁻¹1)`, with `k` the correlations
//! to the training points — the variance of the noise-free response (the nugget is not added).
//!
//! Leave-one-out residuals without refitting (Dubrule 1983, "Cross validation of kriging in a
//! unique neighborhood", Math. Geol. 15(6), 687–699; R&W eq. 5.12 for a known mean): with
//! `Q = R⁻¹ − R⁻¹11ᵀR⁻¹ / 1ᵀR⁻¹1`, `y_i − μ_{−i}(z_i) = [Qy]_i / Q_ii = α_i / Q_ii`, where `μ_{−i}`
//! is the model refitted without point `i` at the same hyper-parameters (the mean re-estimated).

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::llt;
use faer::linalg::triangular_solve::solve_lower_triangular_in_place;
use faer::{Mat, Par};

use super::local::minimise_in_box;
use crate::sampling::sobol_unit;

/// Bounds of `log ℓ` (length scales 0.01 to 100 on the unit box: from a feature that changes the
/// response within 1 % of its range to one whose effect is nearly linear over it).
const LOG_LENGTH: (f64, f64) = (-4.605_170_185_988_091, 4.605_170_185_988_091);
/// Bounds of `log η` (nugget 1e-8 to 1 of the process variance).
const LOG_NUGGET: (f64, f64) = (-18.420_680_743_952_367, 0.0);
/// The default start: every length scale 0.5, nugget 1e-4.
const START: (f64, f64) = (-std::f64::consts::LN_2, -9.210_340_371_976_183);

/// Why a Gaussian process could not be fitted. The optimiser does not stop on it: it evaluates a
/// space-filling design instead that iteration and reports the reason.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum FitFailure {
    /// Fewer training points than the model needs.
    #[error("{points} training point(s), at least {required} needed")]
    TooFewPoints {
        /// Points given.
        points: usize,
        /// Points needed.
        required: usize,
    },
    /// Every training output is the same: nothing to model.
    #[error("all {points} outputs equal {value}")]
    ConstantOutput {
        /// Points given.
        points: usize,
        /// The common value.
        value: f64,
    },
    /// A training input or output is NaN or infinite.
    #[error("a training input or output is not finite")]
    NotFinite,
    /// The correlation matrix is not positive definite at any hyper-parameter start.
    #[error("the correlation matrix is singular at every hyper-parameter start")]
    Singular,
}

/// Length scales and nugget of a fitted model.
#[derive(Debug, Clone, PartialEq)]
pub struct Hyperparameters {
    /// One length scale per feature (unit box).
    pub length_scales: Vec<f64>,
    /// The nugget, relative to the process variance.
    pub nugget: f64,
}

impl Hyperparameters {
    fn to_log(&self) -> Vec<f64> {
        let mut p: Vec<f64> = self.length_scales.iter().map(|l| l.ln()).collect();
        p.push(self.nugget.ln());
        p
    }

    fn from_log(p: &[f64]) -> Self {
        let d = p.len() - 1;
        Self { length_scales: p[..d].iter().map(|v| v.exp()).collect(), nugget: p[d].exp() }
    }
}

/// How hard the likelihood is maximised.
#[derive(Debug, Clone, PartialEq)]
pub struct FitSettings {
    /// Starts besides the default one (Sobol' points over the box) when there is no warm start;
    /// a warm-started fit runs one local search from the warm start.
    pub restarts: usize,
    /// Quasi-Newton iterations per start.
    pub max_iterations: usize,
    /// Relative growth of a model's training set since its hyper-parameters were last optimised
    /// below which the optimiser keeps them and only refactors (`0` re-optimises every iteration;
    /// the likelihood changes little when a few designs join many). Default 0.05.
    pub reoptimise_growth: f64,
}

impl Default for FitSettings {
    fn default() -> Self {
        Self { restarts: 2, max_iterations: 60, reoptimise_growth: 0.05 }
    }
}

/// Mean and standard deviation of a prediction, in the output's units.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Prediction {
    /// Posterior mean.
    pub mean: f64,
    /// Posterior standard deviation of the noise-free response (≥ 0).
    pub sd: f64,
}

/// A fitted Gaussian process.
#[derive(Debug, Clone)]
pub struct GaussianProcess {
    inputs: Vec<Vec<f64>>,
    categorical: Vec<bool>,
    /// Standardised outputs.
    outputs: Vec<f64>,
    /// Output = `offset + scale ×` standardised output.
    offset: f64,
    scale: f64,
    hyper: Hyperparameters,
    /// `1 / ℓ_k²`.
    inverse_squared_lengths: Vec<f64>,
    /// Lower Cholesky factor `L` of `R`.
    factor: Mat<f64>,
    beta: f64,
    alpha: Vec<f64>,
    variance: f64,
    /// `L⁻¹1`.
    whitened_ones: Vec<f64>,
    /// `1ᵀR⁻¹1`.
    ones_precision: f64,
    log_likelihood: f64,
}

impl GaussianProcess {
    /// Fits a model to `outputs` at `inputs` (features on the unit box; `categorical[k]` marks a
    /// feature compared by equality), maximising the likelihood from `warm` if given, else from
    /// the default start and `settings.restarts` Sobol' starts.
    pub fn fit(
        inputs: &[Vec<f64>],
        outputs: &[f64],
        categorical: &[bool],
        settings: &FitSettings,
        warm: Option<&Hyperparameters>,
    ) -> Result<Self, FitFailure> {
        let (offset, scale) = standardisation(inputs, outputs, categorical.len())?;
        let y: Vec<f64> = outputs.iter().map(|v| (v - offset) / scale).collect();
        let pairs = PairDistances::new(inputs, categorical);
        let d = categorical.len();
        let mut lower = vec![LOG_LENGTH.0; d + 1];
        let mut upper = vec![LOG_LENGTH.1; d + 1];
        (lower[d], upper[d]) = LOG_NUGGET;
        let mut objective =
            |p: &[f64], gradient: bool| negative_log_likelihood(&pairs, &y, p, gradient);
        let mut search = |start: &[f64]| {
            minimise_in_box(&mut objective, start, &lower, &upper, settings.max_iterations)
        };
        // A warm start (the previous iteration's optimum, a few designs ago) is near the new
        // optimum: one local search suffices. Cold: the default start and the Sobol' restarts.
        let warm_best = warm.and_then(|h| search(&h.to_log()));
        let best = match warm_best {
            Some(best) => best,
            None => {
                let mut default = vec![START.0; d + 1];
                default[d] = START.1;
                // d + 1 <= 32 fits the Sobol' table; beyond, the default start only.
                let restarts = sobol_unit(settings.restarts, d + 1).unwrap_or_default();
                std::iter::once(default)
                    .chain(restarts.iter().map(|u| {
                        u.iter()
                            .zip(&lower)
                            .zip(&upper)
                            .map(|((u, l), h)| l + u * (h - l))
                            .collect()
                    }))
                    .filter_map(|start| search(&start))
                    .min_by(|a, b| a.value.total_cmp(&b.value))
                    .ok_or(FitFailure::Singular)?
            }
        };
        let hyper = Hyperparameters::from_log(&best.x);
        Self::build(inputs.to_vec(), categorical.to_vec(), y, (offset, scale), hyper)
    }

    /// The model of `outputs` at `inputs` with the given hyper-parameters (no likelihood search).
    pub fn with_hyperparameters(
        inputs: &[Vec<f64>],
        outputs: &[f64],
        categorical: &[bool],
        hyper: Hyperparameters,
    ) -> Result<Self, FitFailure> {
        let (offset, scale) = standardisation(inputs, outputs, categorical.len())?;
        let y = outputs.iter().map(|v| (v - offset) / scale).collect();
        Self::build(inputs.to_vec(), categorical.to_vec(), y, (offset, scale), hyper)
    }

    /// The same model, also conditioned on `values` (output units) at `points`, hyper-parameters
    /// and standardisation unchanged (the "kriging believer" of a batch: Ginsbourger, Le Riche &
    /// Carraro 2010, "Kriging is well-suited to parallelize optimization", Sec. 4.1).
    pub fn with_fantasies(&self, points: &[Vec<f64>], values: &[f64]) -> Result<Self, FitFailure> {
        let mut inputs = self.inputs.clone();
        inputs.extend_from_slice(points);
        let mut y = self.outputs.clone();
        y.extend(values.iter().map(|v| (v - self.offset) / self.scale));
        let categorical = self.categorical.clone();
        Self::build(inputs, categorical, y, (self.offset, self.scale), self.hyper.clone())
    }

    fn build(
        inputs: Vec<Vec<f64>>,
        categorical: Vec<bool>,
        outputs: Vec<f64>,
        (offset, scale): (f64, f64),
        hyper: Hyperparameters,
    ) -> Result<Self, FitFailure> {
        let inverse_squared_lengths: Vec<f64> =
            hyper.length_scales.iter().map(|l| 1.0 / (l * l)).collect();
        let pairs = PairDistances::new(&inputs, &categorical);
        let (matrix, _) = pairs.correlation(&inverse_squared_lengths, hyper.nugget);
        let factor = cholesky(matrix).ok_or(FitFailure::Singular)?;
        let fit = Concentrated::new(&factor, &outputs).ok_or(FitFailure::Singular)?;
        let whitened_ones = lower_solve(&factor, vec![1.0; inputs.len()]);
        let ones_precision = whitened_ones.iter().map(|w| w * w).sum();
        Ok(Self {
            inputs,
            categorical,
            outputs,
            offset,
            scale,
            hyper,
            inverse_squared_lengths,
            factor,
            beta: fit.beta,
            alpha: fit.alpha,
            variance: fit.variance,
            whitened_ones,
            ones_precision,
            log_likelihood: -fit.negative_log_likelihood,
        })
    }

    /// The fitted length scales and nugget.
    pub fn hyperparameters(&self) -> &Hyperparameters {
        &self.hyper
    }

    /// The concentrated log-likelihood at the fitted hyper-parameters (standardised outputs, without
    /// the constant `−n/2 (1 + log 2π)`).
    pub fn log_likelihood(&self) -> f64 {
        self.log_likelihood
    }

    /// Training points.
    pub fn len(&self) -> usize {
        self.inputs.len()
    }

    /// Never true for a fitted model (kept for the `len`/`is_empty` convention).
    pub fn is_empty(&self) -> bool {
        self.inputs.is_empty()
    }

    /// Mean and standard deviation at each point (features on the unit box).
    pub fn predict(&self, points: &[Vec<f64>]) -> Vec<Prediction> {
        let n = self.inputs.len();
        let d = self.categorical.len();
        // Features divided by their length scales once, so each pair costs a plain sum of squares.
        let scale = |z: &[f64]| -> Vec<f64> {
            z.iter()
                .zip(&self.inverse_squared_lengths)
                .zip(&self.categorical)
                .map(|((v, s), &c)| if c { *v } else { v * s.sqrt() })
                .collect()
        };
        let training: Vec<f64> = self.inputs.iter().flat_map(|z| scale(z)).collect();
        let mut cross = Mat::<f64>::zeros(n, points.len());
        for (c, point) in points.iter().enumerate() {
            let point = scale(point);
            for (i, input) in training.chunks_exact(d.max(1)).enumerate() {
                let mut r2 = 0.0;
                for k in 0..d {
                    let delta = input[k] - point[k];
                    r2 += if self.categorical[k] {
                        f64::from(u8::from(delta.abs() > 0.5)) * self.inverse_squared_lengths[k]
                    } else {
                        delta * delta
                    };
                }
                cross[(i, c)] = matern52(r2.sqrt());
            }
        }
        let means: Vec<f64> = (0..points.len())
            .map(|c| self.beta + (0..n).map(|i| cross[(i, c)] * self.alpha[i]).sum::<f64>())
            .collect();
        solve_lower_triangular_in_place(self.factor.as_ref(), cross.as_mut(), Par::Seq);
        means
            .iter()
            .enumerate()
            .map(|(c, &mean)| {
                let column = cross.col(c);
                let explained: f64 = (0..n).map(|i| column[i] * column[i]).sum();
                let ones: f64 = (0..n).map(|i| column[i] * self.whitened_ones[i]).sum();
                let variance =
                    self.variance * (1.0 - explained + (1.0 - ones).powi(2) / self.ones_precision);
                Prediction {
                    mean: self.offset + self.scale * mean,
                    sd: self.scale * variance.max(0.0).sqrt(),
                }
            })
            .collect()
    }

    /// Leave-one-out residuals `y_i − μ_{−i}(z_i)` in output units (Dubrule 1983; module docs).
    pub fn loo_residuals(&self) -> Vec<f64> {
        let n = self.inputs.len();
        let inverse = cholesky_inverse(&self.factor);
        let inverse_ones: Vec<f64> =
            (0..n).map(|i| (0..n).map(|k| inverse[(i, k)]).sum()).collect();
        (0..n)
            .map(|i| {
                let q = inverse[(i, i)] - inverse_ones[i].powi(2) / self.ones_precision;
                self.scale * self.alpha[i] / q
            })
            .collect()
    }

    /// Root-mean-square leave-one-out residual over the outputs' standard deviation: 0 for a
    /// perfect model, about 1 for one no better than the mean.
    pub fn loo_error(&self) -> f64 {
        let residuals = self.loo_residuals();
        let mse = residuals.iter().map(|r| r * r).sum::<f64>() / residuals.len() as f64;
        mse.sqrt() / self.scale
    }
}

/// Offset and scale that standardise `outputs`, after checking the data.
fn standardisation(
    inputs: &[Vec<f64>],
    outputs: &[f64],
    features: usize,
) -> Result<(f64, f64), FitFailure> {
    let n = outputs.len();
    if n < 2 || inputs.len() != n {
        return Err(FitFailure::TooFewPoints { points: n.min(inputs.len()), required: 2 });
    }
    let finite = |v: &f64| v.is_finite();
    if !outputs.iter().all(finite)
        || !inputs.iter().all(|z| z.len() == features && z.iter().all(finite))
    {
        return Err(FitFailure::NotFinite);
    }
    let mean = outputs.iter().sum::<f64>() / n as f64;
    let sd = (outputs.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / n as f64).sqrt();
    let varies = sd > 1e-12 * mean.abs() && sd >= f64::MIN_POSITIVE;
    if !varies {
        return Err(FitFailure::ConstantOutput { points: n, value: mean });
    }
    Ok((mean, sd))
}

/// The Matérn ν = 5/2 correlation at scaled distance `r` (R&W eq. 4.17).
fn matern52(r: f64) -> f64 {
    let s = 5f64.sqrt() * r;
    (1.0 + s + s * s / 3.0) * (-s).exp()
}

/// `−(1/r) dc/dr` of [`matern52`], so that `∂c/∂log ℓ_k = g(r) δ_k²/ℓ_k²`: `(5/3)(1 + √5 r) e^(−√5 r)`.
fn matern52_slope(r: f64) -> f64 {
    let s = 5f64.sqrt() * r;
    5.0 / 3.0 * (1.0 + s) * (-s).exp()
}

/// Per-feature differences `δ_k²` between two points: squared difference, or 0/1 for a categorical.
fn squared_differences(a: &[f64], b: &[f64], categorical: &[bool], out: &mut [f64]) {
    for (k, o) in out.iter_mut().enumerate() {
        let delta = a[k] - b[k];
        *o = if categorical[k] { f64::from(u8::from(delta.abs() > 0.5)) } else { delta * delta };
    }
}

/// The squared per-feature differences of every pair `i < k` of training points, computed once per
/// fit and reused at every likelihood evaluation.
struct PairDistances {
    n: usize,
    d: usize,
    /// `squared[p · d + k]` for pair `p` in row-major upper-triangle order.
    squared: Vec<f64>,
}

impl PairDistances {
    fn new(inputs: &[Vec<f64>], categorical: &[bool]) -> Self {
        let (n, d) = (inputs.len(), categorical.len());
        let mut squared = vec![0.0; n * n.saturating_sub(1) / 2 * d];
        let mut p = 0;
        for i in 0..n {
            for k in (i + 1)..n {
                squared_differences(&inputs[i], &inputs[k], categorical, &mut squared[p..p + d]);
                p += d;
            }
        }
        Self { n, d, squared }
    }

    /// `R = C + η I` and the scaled distance `r` of every pair.
    fn correlation(&self, inverse_squared_lengths: &[f64], nugget: f64) -> (Mat<f64>, Vec<f64>) {
        let mut matrix = Mat::<f64>::zeros(self.n, self.n);
        let mut distances = Vec::with_capacity(self.squared.len() / self.d.max(1));
        let mut pair = self.squared.chunks_exact(self.d.max(1));
        for i in 0..self.n {
            matrix[(i, i)] = 1.0 + nugget;
            for k in (i + 1)..self.n {
                let deltas = pair.next().unwrap_or(&[]);
                let r2: f64 = deltas.iter().zip(inverse_squared_lengths).map(|(d, s)| d * s).sum();
                let r = r2.sqrt();
                let c = matern52(r);
                matrix[(i, k)] = c;
                matrix[(k, i)] = c;
                distances.push(r);
            }
        }
        (matrix, distances)
    }
}

/// `β̂`, `α`, `σ̂²` and `−ℓ` for a factored correlation matrix.
struct Concentrated {
    beta: f64,
    alpha: Vec<f64>,
    variance: f64,
    negative_log_likelihood: f64,
}

impl Concentrated {
    fn new(factor: &Mat<f64>, y: &[f64]) -> Option<Self> {
        let n = y.len();
        let solved_y = cholesky_solve(factor, y.to_vec());
        let solved_ones = cholesky_solve(factor, vec![1.0; n]);
        let beta = solved_y.iter().sum::<f64>() / solved_ones.iter().sum::<f64>();
        let alpha: Vec<f64> =
            solved_y.iter().zip(&solved_ones).map(|(a, o)| a - beta * o).collect();
        let variance = y.iter().zip(&alpha).map(|(v, a)| (v - beta) * a).sum::<f64>() / n as f64;
        let log_det = 2.0 * (0..n).map(|i| factor[(i, i)].ln()).sum::<f64>();
        let negative_log_likelihood = 0.5 * (n as f64 * variance.ln() + log_det);
        (variance > 0.0 && negative_log_likelihood.is_finite() && beta.is_finite())
            .then_some(Self { beta, alpha, variance, negative_log_likelihood })
    }
}

/// `−ℓ(θ)` and, if `with_gradient`, its gradient (module docs; else an empty vector), or `None`
/// where `R` is not positive definite.
fn negative_log_likelihood(
    pairs: &PairDistances,
    y: &[f64],
    p: &[f64],
    with_gradient: bool,
) -> Option<(f64, Vec<f64>)> {
    let d = pairs.d;
    let inverse_squared_lengths: Vec<f64> = p[..d].iter().map(|l| (-2.0 * l).exp()).collect();
    let nugget = p[d].exp();
    let (matrix, distances) = pairs.correlation(&inverse_squared_lengths, nugget);
    let factor = cholesky(matrix)?;
    let fit = Concentrated::new(&factor, y)?;
    if !with_gradient {
        return Some((fit.negative_log_likelihood, Vec::new()));
    }
    let inverse = cholesky_inverse(&factor);
    // M = α αᵀ/σ̂² − R⁻¹; dℓ/dθ_j = ½ Σ M ∂R/∂θ_j (upper-triangle pairs counted twice).
    let weight = |i: usize, k: usize| fit.alpha[i] * fit.alpha[k] / fit.variance - inverse[(i, k)];
    let mut gradient = vec![0.0; d + 1];
    let mut pair = 0;
    for i in 0..pairs.n {
        for k in (i + 1)..pairs.n {
            let factor_ik = weight(i, k) * matern52_slope(distances[pair]);
            let deltas = &pairs.squared[pair * d..(pair + 1) * d];
            for j in 0..d {
                gradient[j] -= factor_ik * deltas[j] * inverse_squared_lengths[j];
            }
            pair += 1;
        }
    }
    gradient[d] = -0.5 * nugget * (0..pairs.n).map(|i| weight(i, i)).sum::<f64>();
    Some((fit.negative_log_likelihood, gradient))
}

/// The lower Cholesky factor of a symmetric matrix, or `None` if it is not positive definite.
fn cholesky(mut matrix: Mat<f64>) -> Option<Mat<f64>> {
    let n = matrix.nrows();
    let mut memory = MemBuffer::new(llt::factor::cholesky_in_place_scratch::<f64>(
        n,
        Par::Seq,
        Default::default(),
    ));
    let stack = MemStack::new(&mut memory);
    llt::factor::cholesky_in_place(
        matrix.as_mut(),
        Default::default(),
        Par::Seq,
        stack,
        Default::default(),
    )
    .ok()?;
    // Only the lower triangle holds the factor; clear the rest so `L` can be used as is.
    for k in 1..n {
        for i in 0..k {
            matrix[(i, k)] = 0.0;
        }
    }
    Some(matrix)
}

/// `L⁻¹ b`.
fn lower_solve(factor: &Mat<f64>, b: Vec<f64>) -> Vec<f64> {
    let mut rhs = Mat::<f64>::from_fn(b.len(), 1, |i, _| b[i]);
    solve_lower_triangular_in_place(factor.as_ref(), rhs.as_mut(), Par::Seq);
    (0..b.len()).map(|i| rhs[(i, 0)]).collect()
}

/// `R⁻¹ b` from `R = L Lᵀ`.
fn cholesky_solve(factor: &Mat<f64>, b: Vec<f64>) -> Vec<f64> {
    let mut rhs = Mat::<f64>::from_fn(b.len(), 1, |i, _| b[i]);
    let mut memory =
        MemBuffer::new(llt::solve::solve_in_place_scratch::<f64>(b.len(), 1, Par::Seq));
    llt::solve::solve_in_place(factor.as_ref(), rhs.as_mut(), Par::Seq, MemStack::new(&mut memory));
    (0..b.len()).map(|i| rhs[(i, 0)]).collect()
}

/// `R⁻¹` (both triangles) from `R = L Lᵀ`.
fn cholesky_inverse(factor: &Mat<f64>) -> Mat<f64> {
    let n = factor.nrows();
    let mut inverse = Mat::<f64>::zeros(n, n);
    let mut memory = MemBuffer::new(llt::inverse::inverse_scratch::<f64>(n, Par::Seq));
    llt::inverse::inverse(inverse.as_mut(), factor.as_ref(), Par::Seq, MemStack::new(&mut memory));
    for k in 1..n {
        for i in 0..k {
            inverse[(i, k)] = inverse[(k, i)];
        }
    }
    inverse
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::Rng;

    fn branin_like(z: &[f64]) -> f64 {
        (6.0 * z[0]).sin() + (z[1] - 0.3).powi(2) * 4.0 + 0.5 * z[0] * z[1]
    }

    fn data(n: usize, seed: u64) -> (Vec<Vec<f64>>, Vec<f64>) {
        let mut rng = Rng::new(seed);
        let inputs: Vec<Vec<f64>> = (0..n).map(|_| vec![rng.uniform(), rng.uniform()]).collect();
        let outputs = inputs.iter().map(|z| branin_like(z)).collect();
        (inputs, outputs)
    }

    #[test]
    fn interpolates_noiseless_data_and_predicts_between_points() {
        let (inputs, outputs) = data(30, 1);
        let gp =
            GaussianProcess::fit(&inputs, &outputs, &[false; 2], &FitSettings::default(), None)
                .unwrap();
        assert!(gp.hyperparameters().nugget < 1e-3, "{:?}", gp.hyperparameters());
        for (p, y) in gp.predict(&inputs).iter().zip(&outputs) {
            assert!((p.mean - y).abs() < 2e-3, "{} vs {y}", p.mean);
            assert!(p.sd < 0.05, "sd {} at a training point", p.sd);
        }
        let (test_inputs, test_outputs) = data(200, 2);
        let predictions = gp.predict(&test_inputs);
        let rmse =
            (predictions.iter().zip(&test_outputs).map(|(p, y)| (p.mean - y).powi(2)).sum::<f64>()
                / 200.0)
                .sqrt();
        assert!(rmse < 0.05, "test RMSE {rmse}");
        assert!(predictions.iter().all(|p| p.sd.is_finite() && p.sd >= 0.0));
    }

    #[test]
    fn loo_closed_form_equals_brute_force_refits() {
        let (inputs, outputs) = data(15, 3);
        let categorical = [false, false];
        let hyper = Hyperparameters { length_scales: vec![0.3, 0.6], nugget: 1e-3 };
        let gp =
            GaussianProcess::with_hyperparameters(&inputs, &outputs, &categorical, hyper.clone())
                .unwrap();
        for (i, residual) in gp.loo_residuals().iter().enumerate() {
            let mut rest_in = inputs.clone();
            let mut rest_out = outputs.clone();
            let held_in = rest_in.remove(i);
            let held_out = rest_out.remove(i);
            // Same hyper-parameters, same standardisation (the residual is in output units and the
            // standardisation is affine, so refitting in standardised units would give the same).
            let refit = GaussianProcess::build(
                rest_in,
                categorical.to_vec(),
                rest_out.iter().map(|v| (v - gp.offset) / gp.scale).collect(),
                (gp.offset, gp.scale),
                hyper.clone(),
            )
            .unwrap();
            let predicted = refit.predict(&[held_in])[0].mean;
            assert!((held_out - predicted - residual).abs() < 1e-9, "{i}: {residual}");
        }
    }

    #[test]
    fn likelihood_gradient_matches_finite_differences() {
        let (inputs, outputs) = data(20, 4);
        let mut inputs = inputs;
        // A categorical third feature with three levels.
        for (k, z) in inputs.iter_mut().enumerate() {
            z.push((k % 3) as f64);
        }
        let categorical = [false, false, true];
        let (offset, scale) = standardisation(&inputs, &outputs, 3).unwrap();
        let y: Vec<f64> = outputs.iter().map(|v| (v - offset) / scale).collect();
        let pairs = PairDistances::new(&inputs, &categorical);
        let p = [-1.0, 0.2, -0.5, -6.0];
        let (_, gradient) = negative_log_likelihood(&pairs, &y, &p, true).unwrap();
        for j in 0..p.len() {
            let h = 1e-6;
            let mut up = p;
            let mut down = p;
            up[j] += h;
            down[j] -= h;
            let fd = (negative_log_likelihood(&pairs, &y, &up, false).unwrap().0
                - negative_log_likelihood(&pairs, &y, &down, false).unwrap().0)
                / (2.0 * h);
            assert!(
                (fd - gradient[j]).abs() < 1e-5 * (1.0 + fd.abs()),
                "{j}: {fd} vs {}",
                gradient[j]
            );
        }
    }

    #[test]
    fn bad_data_is_a_fit_failure_not_a_panic() {
        let (inputs, _) = data(5, 5);
        let settings = FitSettings::default();
        let constant = GaussianProcess::fit(&inputs, &[2.0; 5], &[false; 2], &settings, None);
        assert!(matches!(constant, Err(FitFailure::ConstantOutput { points: 5, .. })));
        let nan = GaussianProcess::fit(
            &inputs,
            &[1.0, f64::NAN, 2.0, 3.0, 4.0],
            &[false; 2],
            &settings,
            None,
        );
        assert!(matches!(nan, Err(FitFailure::NotFinite)));
        let one = GaussianProcess::fit(&inputs[..1], &[1.0], &[false; 2], &settings, None);
        assert!(matches!(one, Err(FitFailure::TooFewPoints { .. })));
        // Duplicated inputs with different outputs: the nugget absorbs them.
        let twice = [vec![0.5, 0.5], vec![0.5, 0.5], vec![0.1, 0.9]];
        let gp =
            GaussianProcess::fit(&twice, &[1.0, 1.1, 3.0], &[false; 2], &settings, None).unwrap();
        assert!(gp.predict(&[vec![0.5, 0.5]])[0].mean.is_finite());
    }
}
