//! Calibration: bounded non-linear least squares `min ½‖r(θ)‖²`, `lower ≤ θ ≤ upper`, on a residual
//! function supplied by the caller (e.g. measured minus predicted torque at each current, the FEA
//! in the loop), with standard errors, the correlation matrix and the unidentifiable parameter
//! groups of the estimate.
//!
//! # Algorithm
//!
//! **Levenberg–Marquardt** (Levenberg 1944; Marquardt, SIAM J. Appl. Math. 11, 431–441, 1963) as in
//! Madsen, Nielsen & Tingleff, *Methods for Non-Linear Least Squares Problems*, 2nd ed., IMM DTU
//! 2004, ch. 3: the step solves `(JᵀJ + μI) h = −Jᵀr`, its gain ratio
//! `ρ = (F(θ) − F(θ + h)) / (L(0) − L(h))` against the linear model `L` decides acceptance, and the
//! damping follows Nielsen's update (`μ ← μ max(1/3, 1 − (2ρ − 1)³)` after a success,
//! `μ ← μν, ν ← 2ν` after a failure; H. B. Nielsen, "Damping parameter in Marquardt's method",
//! IMM-REP-1999-05, DTU, 1999), starting from `μ₀ = 10⁻³ max diag(JᵀJ)`.
//!
//! It works in the **normalised coordinates** `z = (θ − lower)/(upper − lower) ∈ [0, 1]ᵖ`: the
//! bounds make every parameter's scale explicit, so the identity damping `μI` treats a gap in
//! metres and a yield-stress factor alike.
//!
//! **Bounds by projection** (a projected Levenberg–Marquardt method: Kanzow, Yamashita & Fukushima,
//! "Levenberg–Marquardt methods with strong local convergence properties for solving nonlinear
//! equations with convex constraints", J. Comput. Appl. Math. 172, 375–397, 2004): the trial point is
//! the projection `clamp(z + h, 0, 1)`, and a parameter on a bound whose gradient pushes outward is
//! held there for the step (removed from the linear system, as in an active-set method). The gain
//! ratio uses the projected step. Projection rather than a transformation (`θ = lower + (upper −
//! lower) sin²φ` and the like) because (1) a transformation's Jacobian vanishes at the bounds, so a
//! parameter that belongs on a bound is approached ever more slowly and its covariance is
//! ill-defined there, while projection reaches the bound and reports it ([`Calibration::at_bound`]);
//! (2) the covariance `σ²(JᵀJ)⁻¹` is then in the parameters' own units, with no change of variables.
//!
//! **Finite-difference Jacobian**, one column per parameter evaluated in parallel (rayon): forward
//! differences (central on request) with the step `relative_step · max(|θ_j|, upper_j − lower_j)`
//! (at most half the range), taken backwards when a forward step would leave the bounds (the model
//! may be undefined outside).
//! The Jacobian is recomputed after every accepted step and once more at the final estimate.
//!
//! **Stopping** (the tests of MINPACK's `lmder`, Moré, Garbow & Hillstrom, *User Guide for MINPACK-1*,
//! ANL-80-74, 1980): the residual is orthogonal to every free Jacobian column to within
//! `gradient_tolerance` (cosine), the relative cost reduction of an accepted step is below
//! `cost_tolerance`, or the step is below `step_tolerance` (normalised units); otherwise the
//! iteration or evaluation budget ends it, which is reported, not an error.
//!
//! # Statistics
//!
//! At the estimate, `Cov(θ) = σ² (JᵀJ)⁻¹` (Bates & Watts, *Nonlinear Regression Analysis and Its
//! Applications*, 1988, ch. 2: the linear-approximation inference), `σ` the given measurement noise or the residual
//! estimate `s² = ‖r‖² / (m − p)`; standard errors are its diagonal's roots, the correlation matrix
//! its normalisation. Near-singular `JᵀJ` is handled by [`crate::identifiability`]: the inverse is
//! taken through the SVD of the column-normalised Jacobian with singular values floored at
//! `√ε` (an unidentifiable direction gets a huge, finite variance and correlations of ±1), and the
//! unidentifiable groups are reported instead of a failure or a NaN.

use crate::identifiability::{Identifiability, analyse};
use crate::{RunError, UqError};
use faer::Mat;
use faer::linalg::solvers::SolveLstsq;
use rayon::prelude::*;
use serde::Serialize;

/// One parameter to calibrate: its start value and bounds (SI).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Parameter {
    /// Start value, within the bounds.
    pub start: f64,
    /// Lower bound (finite).
    pub lower: f64,
    /// Upper bound (finite, greater than `lower`).
    pub upper: f64,
}

/// Options of [`calibrate`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CalibrationOptions {
    /// Most iterations (accepted or rejected steps).
    pub max_iterations: usize,
    /// Most residual evaluations (Jacobian columns included).
    pub max_evaluations: usize,
    /// Finite-difference step relative to `max(|θ_j|, upper_j − lower_j)`, in `(0, 0.1]`.
    pub relative_step: f64,
    /// Central instead of forward differences (twice the evaluations per Jacobian).
    pub central_differences: bool,
    /// The measurement noise (standard deviation of one residual); `None` estimates it from the
    /// residuals at the estimate (then more residuals than parameters are needed).
    pub noise: Option<f64>,
    /// `|ρ_ij|` above which two parameters are reported unidentifiable together, in `(0, 1)`.
    pub correlation_threshold: f64,
    /// Collinearity index (Brun et al. 2001) above which a direction is reported unidentifiable, > 1.
    pub collinearity_threshold: f64,
    /// Orthogonality (cosine) of residual and Jacobian columns that ends the iteration.
    pub gradient_tolerance: f64,
    /// Relative cost reduction of an accepted step that ends the iteration.
    pub cost_tolerance: f64,
    /// Step length (normalised coordinates) that ends the iteration.
    pub step_tolerance: f64,
}

impl Default for CalibrationOptions {
    fn default() -> Self {
        Self {
            max_iterations: 100,
            max_evaluations: 1000,
            relative_step: 1e-3,
            central_differences: false,
            noise: None,
            correlation_threshold: 0.95,
            collinearity_threshold: 20.0,
            gradient_tolerance: 1e-8,
            cost_tolerance: 1e-10,
            step_tolerance: 1e-9,
        }
    }
}

/// Why the iteration stopped.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Termination {
    /// The residual is orthogonal to the free Jacobian columns (first-order optimality).
    Gradient,
    /// An accepted step reduced the cost by less than `cost_tolerance` (relative).
    Cost,
    /// The step became shorter than `step_tolerance`.
    Step,
    /// No damping, however large, reduced the cost.
    Stalled,
    /// The iteration budget ran out.
    MaxIterations,
    /// The evaluation budget ran out.
    MaxEvaluations,
}

impl Termination {
    /// True for the convergence tests (gradient, cost, step).
    pub fn converged(self) -> bool {
        matches!(self, Self::Gradient | Self::Cost | Self::Step)
    }
}

/// The result of a calibration (module docs).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Calibration {
    /// The estimate, one value per parameter (SI).
    pub estimate: Vec<f64>,
    /// Standard errors `σ √((JᵀJ)⁻¹)_jj` (infinite for a parameter the residuals do not depend on).
    pub standard_error: Vec<f64>,
    /// Correlation matrix of the estimate, in parameter order.
    pub correlation: Vec<Vec<f64>>,
    /// True for a parameter that ended on one of its bounds (its standard error then describes
    /// the interior only).
    pub at_bound: Vec<bool>,
    /// The residuals at the estimate.
    pub residuals: Vec<f64>,
    /// RMS of the residuals at the start.
    pub residual_rms_before: f64,
    /// RMS of the residuals at the estimate.
    pub residual_rms_after: f64,
    /// The noise σ used for the standard errors.
    pub noise: f64,
    /// True when σ was estimated from the residuals (`‖r‖² / (m − p)`).
    pub noise_estimated: bool,
    /// Residual evaluations, Jacobian columns included.
    pub evaluations: usize,
    /// Iterations (accepted and rejected steps).
    pub iterations: usize,
    /// Why the iteration stopped.
    pub termination: Termination,
    /// The cost `½‖r‖²` at the start and after each accepted step.
    pub cost_history: Vec<f64>,
    /// Singular values, weak directions and unidentifiable groups.
    pub identifiability: Identifiability,
}

/// Calibrates `parameters` so that `residual(θ)` is least in the sense of least squares, within
/// the bounds (module docs). `residual` must return vectors of one length, may be called from
/// several threads at once, and its errors are passed through unchanged as [`RunError::Model`];
/// a non-finite residual at a trial point only rejects that step.
///
/// ```
/// use mrbrake_uq::calibration::{calibrate, CalibrationOptions, Parameter};
/// // Fit y = a exp(b t) to exact data a = 2, b = −0.5.
/// let t: Vec<f64> = (0..20).map(|k| 0.25 * k as f64).collect();
/// let y: Vec<f64> = t.iter().map(|t| 2.0 * (-0.5 * t).exp()).collect();
/// let residual = |p: &[f64]| -> Result<Vec<f64>, std::convert::Infallible> {
///     Ok(t.iter().zip(&y).map(|(t, y)| p[0] * (p[1] * t).exp() - y).collect())
/// };
/// let parameters = [
///     Parameter { start: 1.0, lower: 0.1, upper: 10.0 },
///     Parameter { start: -1.0, lower: -5.0, upper: 0.0 },
/// ];
/// let fit = calibrate(residual, &parameters, &CalibrationOptions::default()).unwrap();
/// assert!((fit.estimate[0] - 2.0).abs() < 1e-6 && (fit.estimate[1] + 0.5).abs() < 1e-6);
/// assert!(fit.termination.converged());
/// ```
pub fn calibrate<F, E>(
    residual: F,
    parameters: &[Parameter],
    options: &CalibrationOptions,
) -> Result<Calibration, RunError<E>>
where
    F: Fn(&[f64]) -> Result<Vec<f64>, E> + Sync,
    E: Send,
{
    validate(parameters, options)?;
    let mut problem = Problem { residual: &residual, parameters, options, evaluations: 0, m: 0 };
    let start: Vec<f64> =
        parameters.iter().map(|p| (p.start - p.lower) / (p.upper - p.lower)).collect();
    let r0 = problem.evaluate(&start)?.ok_or_else(|| {
        UqError::numerical("the residual at the start point is not finite", Vec::new())
    })?;
    problem.m = r0.len();
    if r0.is_empty() {
        return Err(UqError::ModelContract("the residual vector is empty".into()).into());
    }
    if options.noise.is_none() && r0.len() <= parameters.len() {
        return Err(UqError::InvalidOption {
            name: "noise",
            value: f64::NAN,
            allowed: "a given noise when there are no more residuals than parameters",
        }
        .into());
    }
    let rms_before = rms(&r0);
    let state = problem.iterate(start, r0)?;
    problem.finish(state, rms_before)
}

/// Checks bounds, start values and options.
fn validate(parameters: &[Parameter], options: &CalibrationOptions) -> Result<(), UqError> {
    if parameters.is_empty() {
        return Err(UqError::InvalidOption {
            name: "parameters",
            value: 0.0,
            allowed: "at least one",
        });
    }
    for (index, p) in parameters.iter().enumerate() {
        let reason = if !(p.lower.is_finite() && p.upper.is_finite()) {
            "bounds must be finite"
        } else if p.lower >= p.upper {
            "`lower` must be below `upper`"
        } else if !(p.lower..=p.upper).contains(&p.start) {
            "the start value must lie within the bounds"
        } else {
            continue;
        };
        return Err(UqError::InvalidCalibrationParameter {
            index,
            reason: format!("{reason} (start {}, bounds [{}, {}])", p.start, p.lower, p.upper),
        });
    }
    let bad = |name, value, allowed| Err(UqError::InvalidOption { name, value, allowed });
    let o = options;
    if !(o.relative_step > 0.0 && o.relative_step <= 0.1) {
        return bad("relative_step", o.relative_step, "in (0, 0.1]");
    }
    if let Some(noise) = o.noise.filter(|n| !(n.is_finite() && *n > 0.0)) {
        return bad("noise", noise, "positive and finite");
    }
    if !(o.correlation_threshold > 0.0 && o.correlation_threshold < 1.0) {
        return bad("correlation_threshold", o.correlation_threshold, "in (0, 1)");
    }
    if !(o.collinearity_threshold > 1.0 && o.collinearity_threshold.is_finite()) {
        return bad("collinearity_threshold", o.collinearity_threshold, "finite and above 1");
    }
    for (name, value) in [
        ("gradient_tolerance", o.gradient_tolerance),
        ("cost_tolerance", o.cost_tolerance),
        ("step_tolerance", o.step_tolerance),
    ] {
        if !(value.is_finite() && value >= 0.0) {
            return bad(name, value, "finite and non-negative");
        }
    }
    Ok(())
}

/// RMS of a residual vector.
fn rms(r: &[f64]) -> f64 {
    (r.iter().map(|x| x * x).sum::<f64>() / r.len() as f64).sqrt()
}

/// The cost `½‖r‖²`.
fn cost(r: &[f64]) -> f64 {
    0.5 * r.iter().map(|x| x * x).sum::<f64>()
}

/// The caller's residual with its parameters, options and evaluation count.
struct Problem<'a, F> {
    residual: &'a F,
    parameters: &'a [Parameter],
    options: &'a CalibrationOptions,
    evaluations: usize,
    /// The residual length (set by the first evaluation).
    m: usize,
}

/// The iteration's state: normalised point, residual, its Jacobian (when current), damping.
struct State {
    z: Vec<f64>,
    r: Vec<f64>,
    jacobian: Option<Mat<f64>>,
    iterations: usize,
    termination: Termination,
    history: Vec<f64>,
}

impl<F, E> Problem<'_, F>
where
    F: Fn(&[f64]) -> Result<Vec<f64>, E> + Sync,
    E: Send,
{
    /// θ of the normalised point `z`.
    fn theta(&self, z: &[f64]) -> Vec<f64> {
        z.iter().zip(self.parameters).map(|(z, p)| p.lower + z * (p.upper - p.lower)).collect()
    }

    /// Checks one residual vector: `None` if not finite, a contract error if of the wrong length.
    fn check(&self, r: Vec<f64>) -> Result<Option<Vec<f64>>, UqError> {
        if self.m > 0 && r.len() != self.m {
            return Err(UqError::ModelContract(format!(
                "the residual has {} entries, the first had {}",
                r.len(),
                self.m
            )));
        }
        Ok(r.iter().all(|x| x.is_finite()).then_some(r))
    }

    /// The residual at normalised point `z` (`None` when not finite).
    fn evaluate(&mut self, z: &[f64]) -> Result<Option<Vec<f64>>, RunError<E>> {
        self.evaluations += 1;
        let r = (self.residual)(&self.theta(z)).map_err(RunError::Model)?;
        Ok(self.check(r)?)
    }

    /// The finite-difference Jacobian `∂r/∂z` at `z` (residual `r`), columns in parallel (module
    /// docs). A non-finite column is a numerical error naming the parameter.
    fn jacobian(&mut self, z: &[f64], r: &[f64]) -> Result<Mat<f64>, RunError<E>> {
        let theta = self.theta(z);
        let mut points = Vec::new(); // (column, θ_j shifted, signed step in z)
        for (j, p) in self.parameters.iter().enumerate() {
            let range = p.upper - p.lower;
            // At most half the range, so that one side always stays within the bounds.
            let h = (self.options.relative_step * theta[j].abs().max(range)).min(0.5 * range);
            let forward = theta[j] + h <= p.upper;
            let backward = theta[j] - h >= p.lower;
            if self.options.central_differences && forward && backward {
                points.push((j, theta[j] + h, h / range));
                points.push((j, theta[j] - h, -h / range));
            } else {
                let step = if forward { h } else { -h };
                points.push((j, theta[j] + step, step / range));
            }
        }
        self.evaluations += points.len();
        let outputs: Vec<Vec<f64>> = points
            .par_iter()
            .map(|&(j, value, _)| {
                let mut shifted = theta.clone();
                shifted[j] = value;
                (self.residual)(&shifted)
            })
            .collect::<Result<_, E>>()
            .map_err(RunError::Model)?;
        let mut jacobian = Mat::zeros(self.m, self.parameters.len());
        let central = |j: usize| points.iter().filter(|q| q.0 == j).count() == 2;
        for ((j, _, dz), output) in points.iter().zip(outputs) {
            let Some(shifted) = self.check(output)? else {
                return Err(UqError::numerical(
                    format!("the residual is not finite at parameter {j}'s finite-difference step"),
                    Vec::new(),
                )
                .into());
            };
            // Forward/backward: (r(z + dz) − r)/dz; central: the two halves (r± − r)/(2 dz) sum
            // to (r+ − r−)/(2h).
            let divisor = if central(*j) { 2.0 * dz } else { *dz };
            for i in 0..self.m {
                jacobian[(i, *j)] += (shifted[i] - r[i]) / divisor;
            }
        }
        Ok(jacobian)
    }
}

/// Levenberg–Marquardt damping: `μ` (unset until the first Jacobian) and Nielsen's factor `ν`.
struct Damping {
    mu: f64,
    nu: f64,
}

impl<F, E> Problem<'_, F>
where
    F: Fn(&[f64]) -> Result<Vec<f64>, E> + Sync,
    E: Send,
{
    /// Residual evaluations of one Jacobian.
    fn jacobian_cost(&self) -> usize {
        self.parameters.len() * if self.options.central_differences { 2 } else { 1 }
    }

    /// Iterates from normalised point `z` with residual `r` until a stopping test holds (module
    /// docs); the Jacobian of the returned state is current when one was computed at its point.
    fn iterate(&mut self, z: Vec<f64>, r: Vec<f64>) -> Result<State, RunError<E>> {
        let mut state = State {
            history: vec![cost(&r)],
            z,
            r,
            jacobian: None,
            iterations: 0,
            termination: Termination::MaxIterations,
        };
        let mut damping = Damping { mu: f64::NAN, nu: 2.0 };
        while state.iterations < self.options.max_iterations {
            if let Some(reason) = self.step(&mut state, &mut damping)? {
                state.termination = reason;
                break;
            }
        }
        Ok(state)
    }

    /// One iteration: Jacobian if stale, stopping tests, one damped step accepted or rejected.
    fn step(&mut self, s: &mut State, d: &mut Damping) -> Result<Option<Termination>, RunError<E>> {
        let o = *self.options;
        if s.jacobian.is_none() {
            if self.evaluations + self.jacobian_cost() > o.max_evaluations {
                return Ok(Some(Termination::MaxEvaluations));
            }
            s.jacobian = Some(self.jacobian(&s.z, &s.r)?);
        }
        let Some(j) = s.jacobian.as_ref() else { return Ok(Some(Termination::Stalled)) };
        let g = gradient(j, &s.r);
        let free: Vec<usize> = (0..s.z.len())
            .filter(|&i| !((s.z[i] <= 0.0 && g[i] > 0.0) || (s.z[i] >= 1.0 && g[i] < 0.0)))
            .collect();
        if max_cosine(j, &s.r, &g, &free) <= o.gradient_tolerance {
            return Ok(Some(Termination::Gradient));
        }
        if d.mu.is_nan() {
            d.mu = 1e-3 * (0..j.ncols()).map(|c| column_norm(j, c).powi(2)).fold(0.0, f64::max);
        }
        let h = damped_step(j, &s.r, &free, d.mu);
        let trial: Vec<f64> = s.z.iter().zip(&h).map(|(z, h)| (z + h).clamp(0.0, 1.0)).collect();
        let step: Vec<f64> = trial.iter().zip(&s.z).map(|(t, z)| t - z).collect();
        if norm(&step) <= o.step_tolerance * (norm(&s.z) + o.step_tolerance) {
            return Ok(Some(Termination::Step));
        }
        if self.evaluations >= o.max_evaluations {
            return Ok(Some(Termination::MaxEvaluations));
        }
        s.iterations += 1;
        let predicted = -dot(&g, &step) - 0.5 * norm(&apply(j, &step)).powi(2);
        let current = cost(&s.r);
        match self.evaluate(&trial)? {
            Some(r) if predicted > 0.0 && cost(&r) < current => {
                let new_cost = cost(&r);
                let rho = (current - new_cost) / predicted;
                d.mu *= (1.0 - (2.0 * rho - 1.0).powi(3)).max(1.0 / 3.0);
                d.nu = 2.0;
                (s.z, s.r, s.jacobian) = (trial, r, None);
                s.history.push(new_cost);
                if current - new_cost <= o.cost_tolerance * current {
                    return Ok(Some(Termination::Cost));
                }
            }
            _ => {
                d.mu *= d.nu;
                d.nu *= 2.0;
                if !(d.mu.is_finite() && d.mu < 1e300) {
                    return Ok(Some(Termination::Stalled));
                }
            }
        }
        Ok(None)
    }

    /// The statistics at the final state (module docs): a current Jacobian, σ, standard errors,
    /// correlations and identifiability.
    fn finish(&mut self, mut s: State, rms_before: f64) -> Result<Calibration, RunError<E>> {
        let jacobian_z = match s.jacobian.take() {
            Some(j) => j,
            None => self.jacobian(&s.z, &s.r)?,
        };
        let p = self.parameters;
        // ∂r/∂θ_j = (∂r/∂z_j) / (upper_j − lower_j).
        let jacobian = Mat::from_fn(jacobian_z.nrows(), p.len(), |i, j| {
            jacobian_z[(i, j)] / (p[j].upper - p[j].lower)
        });
        let o = self.options;
        let analysis = analyse(&jacobian, o.correlation_threshold, o.collinearity_threshold)?;
        let m = s.r.len();
        let noise = o.noise.unwrap_or_else(|| (2.0 * cost(&s.r) / (m - p.len()) as f64).sqrt());
        let standard_error = analysis
            .unit_variance
            .iter()
            .map(|&v| if v.is_finite() { noise * v.sqrt() } else { f64::INFINITY })
            .collect();
        Ok(Calibration {
            estimate: self.theta(&s.z),
            standard_error,
            correlation: analysis.correlation,
            at_bound: s.z.iter().map(|&z| z <= 0.0 || z >= 1.0).collect(),
            residual_rms_before: rms_before,
            residual_rms_after: rms(&s.r),
            residuals: s.r,
            noise,
            noise_estimated: o.noise.is_none(),
            evaluations: self.evaluations,
            iterations: s.iterations,
            termination: s.termination,
            cost_history: s.history,
            identifiability: analysis.identifiability,
        })
    }
}

/// `Jᵀ r`.
fn gradient(j: &Mat<f64>, r: &[f64]) -> Vec<f64> {
    (0..j.ncols()).map(|c| (0..j.nrows()).map(|i| j[(i, c)] * r[i]).sum()).collect()
}

/// `J h`.
fn apply(j: &Mat<f64>, h: &[f64]) -> Vec<f64> {
    (0..j.nrows()).map(|i| (0..j.ncols()).map(|c| j[(i, c)] * h[c]).sum()).collect()
}

/// Euclidean norm of column `c`.
fn column_norm(j: &Mat<f64>, c: usize) -> f64 {
    (0..j.nrows()).map(|i| j[(i, c)].powi(2)).sum::<f64>().sqrt()
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

fn norm(a: &[f64]) -> f64 {
    dot(a, a).sqrt()
}

/// The largest cosine between the residual and a free, non-zero Jacobian column (MINPACK's
/// orthogonality test); 0 when the residual vanishes or no such column exists.
fn max_cosine(j: &Mat<f64>, r: &[f64], g: &[f64], free: &[usize]) -> f64 {
    let r_norm = norm(r);
    if r_norm <= 0.0 {
        return 0.0;
    }
    free.iter()
        .map(|&c| (c, column_norm(j, c)))
        .filter(|&(_, n)| n > 0.0)
        .map(|(c, n)| g[c].abs() / (n * r_norm))
        .fold(0.0, f64::max)
}

/// The damped Gauss–Newton step on the free parameters: the least-squares solution of
/// `[J_F; √μ I] h_F = [−r; 0]` by Householder QR (no normal equations); held parameters get 0.
fn damped_step(j: &Mat<f64>, r: &[f64], free: &[usize], mu: f64) -> Vec<f64> {
    let (m, f) = (j.nrows(), free.len());
    let mut step = vec![0.0; j.ncols()];
    if f == 0 {
        return step;
    }
    let root = mu.sqrt();
    let a = Mat::from_fn(m + f, f, |i, c| {
        if i < m {
            j[(i, free[c])]
        } else if i - m == c {
            root
        } else {
            0.0
        }
    });
    let b = Mat::from_fn(m + f, 1, |i, _| if i < m { -r[i] } else { 0.0 });
    let h = a.qr().solve_lstsq(&b);
    for (c, &index) in free.iter().enumerate() {
        step[index] = h[(c, 0)];
    }
    step
}
