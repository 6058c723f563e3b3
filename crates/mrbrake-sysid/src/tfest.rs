//! Continuous-time transfer-function estimation from frequency-response data.
//!
//! Model: G(s) = e^{−sτ}·N(s)/D(s) with N of degree `zeros`, D of degree `poles` and D(0) = 1; the
//! optional input delay τ is known (e.g. the half-sample delay of a zero-order-hold output) and removed
//! from the data before fitting. Criterion: the weighted complex error
//! V(θ) = Σ_k w_k² |N(jω_k)/D(jω_k) − G_k|² (with unit weights this is what MATLAB's `tfest` minimises
//! on frequency-domain data).
//!
//! 1. **Linear initialisation**: Levy's linearisation (Levy 1959, IRE Trans. Autom. Control 4:37)
//!    w_k |N(jω_k) − G_k D(jω_k)|², then Sanathanan–Koerner iterations (Sanathanan & Koerner 1963, IEEE
//!    Trans. Autom. Control 8:56) that divide each equation by |D_prev(jω_k)| so the linear problem
//!    converges towards the true output-error criterion.
//! 2. **Non-linear least squares**: Levenberg–Marquardt (Marquardt 1963, SIAM J. Appl. Math. 11:431) on
//!    V(θ) with the analytic Jacobian ∂Ĝ/∂b_i = sⁱ/D, ∂Ĝ/∂a_i = −N sⁱ/D², each step solved by QR of the
//!    augmented system [J; √λ·diag(JᵀJ)^{1/2}] δ = [−r; 0] (no normal equations).
//!
//! Frequencies are scaled by ω_s = √(ω_min ω_max) during the fit (s = ω_s p), which keeps the powers of
//! jω within a few decades of 1; D(0) = 1 is unaffected by that scaling.

use mrbrake_error::FieldError;
use num_complex::Complex64;

use crate::SysidError;
use crate::complex::{div, recip};
use crate::frd::Frd;
use crate::linalg::{Matrix, least_squares};
use crate::transfer_function::TransferFunction;

/// Per-point weighting of the complex error.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Weighting {
    /// w_k = 1 (MATLAB's default): absolute complex error; the high-gain band dominates.
    #[default]
    Uniform,
    /// w_k = 1/|G_k|: relative error; every decade counts alike.
    InverseMagnitude,
}

/// Settings of the estimator.
#[derive(Debug, Clone)]
pub struct TfestOptions {
    /// Number of poles (degree of D), ≥ 1.
    pub poles: usize,
    /// Number of zeros (degree of N), ≤ poles.
    pub zeros: usize,
    /// Weighting of the complex error (multiplied by the FRD's own weights, if any).
    pub weighting: Weighting,
    /// Known input delay τ in seconds (0 for none).
    pub delay_s: f64,
    /// Maximum Sanathanan–Koerner iterations.
    pub max_sk_iterations: usize,
    /// Maximum Levenberg–Marquardt iterations.
    pub max_lm_iterations: usize,
}

impl TfestOptions {
    /// Options for `poles` poles and `zeros` zeros, other settings at their defaults.
    pub fn new(poles: usize, zeros: usize) -> Self {
        Self {
            poles,
            zeros,
            weighting: Weighting::Uniform,
            delay_s: 0.0,
            max_sk_iterations: 30,
            max_lm_iterations: 300,
        }
    }

    /// Checks the orders (at least one pole, no more zeros than poles: fields `poles`, `zeros`)
    /// and the delay (finite and ≥ 0: `delay`). [`tfest`] checks them too; a front end calls this
    /// before reading data.
    pub fn check(&self) -> Result<(), SysidError> {
        let (m, n) = (self.zeros, self.poles);
        if n == 0 {
            return Err(FieldError::out_of_range("poles", n, ">= 1").into());
        }
        if m > n {
            return Err(FieldError::out_of_range("zeros", m, format!("<= poles ({n})")).into());
        }
        if !(self.delay_s >= 0.0 && self.delay_s.is_finite()) {
            let e = FieldError::out_of_range("delay", format!("{} s", self.delay_s), ">= 0 s");
            return Err(e.into());
        }
        Ok(())
    }
}

/// The estimated model and how well it fits.
#[derive(Debug, Clone)]
pub struct TfestResult {
    /// The rational part N(s)/D(s) (descending powers, D(0) = 1).
    pub model: TransferFunction,
    /// The input delay used, s.
    pub delay_s: f64,
    /// MATLAB's fit: 100·(1 − ‖G − Ĝ‖/‖G − mean G‖) over the complex response.
    pub fit_percent: f64,
    /// Mean squared complex error, mean |G − Ĝ|².
    pub mse: f64,
    /// Weighted cost V after each Sanathanan–Koerner iteration.
    pub sk_history: Vec<f64>,
    /// Weighted cost V after each accepted Levenberg–Marquardt iteration.
    pub lm_history: Vec<f64>,
}

/// The JSON summary of an estimate.
#[derive(Debug, Clone, serde::Serialize)]
pub struct TfestSummary {
    /// Numerator, highest power first.
    pub numerator: Vec<f64>,
    /// Denominator, highest power first, constant term 1.
    pub denominator: Vec<f64>,
    /// Poles as [re, im], by increasing modulus.
    pub poles: Vec<[f64; 2]>,
    /// Zeros as [re, im].
    pub zeros: Vec<[f64; 2]>,
    /// G(0).
    pub dc_gain: f64,
    /// −3 dB bandwidth, rad/s (null when undefined).
    pub bandwidth_rad_s: Option<f64>,
    /// Pole moduli (one per conjugate pair), rad/s.
    pub corner_frequencies_rad_s: Vec<f64>,
    /// True when every pole has a negative real part.
    pub stable: bool,
    /// Fit percentage on the complex response.
    pub fit_percent: f64,
    /// Mean squared complex error.
    pub mse: f64,
    /// Input delay, s.
    pub delay_s: f64,
    /// Sanathanan–Koerner iterations run.
    pub sk_iterations: usize,
    /// Levenberg–Marquardt iterations accepted.
    pub lm_iterations: usize,
}

impl TfestResult {
    /// Model response including the delay, e^{−jωτ} N(jω)/D(jω).
    pub fn response(&self, omega_rad_s: f64) -> Complex64 {
        self.model.response(omega_rad_s) * Complex64::from_polar(1.0, -omega_rad_s * self.delay_s)
    }

    /// Poles, zeros, gains and fit as a serialisable summary.
    pub fn summary(&self) -> Result<TfestSummary, SysidError> {
        let poles = self.model.poles()?;
        let zeros = self.model.zeros()?;
        Ok(TfestSummary {
            numerator: self.model.numerator.clone(),
            denominator: self.model.denominator.clone(),
            stable: poles.iter().all(|p| p.re < 0.0),
            poles: poles.iter().map(|p| [p.re, p.im]).collect(),
            zeros: zeros.iter().map(|p| [p.re, p.im]).collect(),
            dc_gain: self.model.dc_gain(),
            bandwidth_rad_s: self.model.bandwidth_rad_s(),
            corner_frequencies_rad_s: self.model.corner_frequencies_rad_s()?,
            fit_percent: self.fit_percent,
            mse: self.mse,
            delay_s: self.delay_s,
            sk_iterations: self.sk_history.len(),
            lm_iterations: self.lm_history.len(),
        })
    }
}

/// Fitting problem in the scaled frequency variable p = s/ω_s.
struct Problem {
    m: usize,
    n: usize,
    /// Powers (jω_k/ω_s)^i for i = 0..=max(m, n).
    powers: Vec<Vec<Complex64>>,
    /// Data with the delay removed.
    data: Vec<Complex64>,
    weight: Vec<f64>,
}

impl Problem {
    fn unknowns(&self) -> usize {
        self.m + 1 + self.n
    }

    /// N(p_k), D(p_k) for parameters θ = [b_0..b_m, a_1..a_n].
    fn nd(&self, theta: &[f64], k: usize) -> (Complex64, Complex64) {
        let pw = &self.powers[k];
        let mut num = Complex64::default();
        for i in 0..=self.m {
            num += pw[i].scale(theta[i]);
        }
        let mut den = Complex64::new(1.0, 0.0);
        for i in 1..=self.n {
            den += pw[i].scale(theta[self.m + i]);
        }
        (num, den)
    }

    fn cost(&self, theta: &[f64]) -> f64 {
        (0..self.data.len())
            .map(|k| {
                let (num, den) = self.nd(theta, k);
                (div(num, den) - self.data[k]).norm_sqr() * self.weight[k] * self.weight[k]
            })
            .sum()
    }

    /// One Levy (previous = None) or Sanathanan–Koerner step.
    fn linear_step(&self, previous: Option<&[f64]>) -> Result<Vec<f64>, SysidError> {
        let rows = 2 * self.data.len();
        let mut a = Matrix::zeros(rows, self.unknowns());
        let mut b = vec![0.0; rows];
        for k in 0..self.data.len() {
            let c = match previous {
                Some(theta) => self.weight[k] / self.nd(theta, k).1.norm(),
                None => self.weight[k],
            };
            let pw = &self.powers[k];
            let g = self.data[k];
            for i in 0..=self.m {
                a.set(2 * k, i, c * pw[i].re);
                a.set(2 * k + 1, i, c * pw[i].im);
            }
            for i in 1..=self.n {
                let v = (g * pw[i]).scale(-c);
                a.set(2 * k, self.m + i, v.re);
                a.set(2 * k + 1, self.m + i, v.im);
            }
            b[2 * k] = c * g.re;
            b[2 * k + 1] = c * g.im;
        }
        least_squares(&a, &b)
    }

    /// Residual vector r (stacked re/im) and Jacobian at θ.
    fn residual_jacobian(&self, theta: &[f64]) -> (Vec<f64>, Matrix) {
        let rows = 2 * self.data.len();
        let mut r = vec![0.0; rows];
        let mut j = Matrix::zeros(rows, self.unknowns());
        for k in 0..self.data.len() {
            let (num, den) = self.nd(theta, k);
            let w = self.weight[k];
            let e = (div(num, den) - self.data[k]).scale(w);
            r[2 * k] = e.re;
            r[2 * k + 1] = e.im;
            let pw = &self.powers[k];
            let inv_d = recip(den);
            for i in 0..=self.m {
                let d = (pw[i] * inv_d).scale(w);
                j.set(2 * k, i, d.re);
                j.set(2 * k + 1, i, d.im);
            }
            let g_over_d = num * inv_d * inv_d;
            for i in 1..=self.n {
                let d = (pw[i] * g_over_d).scale(-w);
                j.set(2 * k, self.m + i, d.re);
                j.set(2 * k + 1, self.m + i, d.im);
            }
        }
        (r, j)
    }
}

/// Estimates a continuous-time transfer function from frequency-response data (see module docs).
pub fn tfest(frd: &Frd, options: &TfestOptions) -> Result<TfestResult, SysidError> {
    check_request(frd, options)?;
    let (problem, omega_scale) = Problem::new(frd, options);
    // 1. Levy, then Sanathanan–Koerner.
    let (theta, sk_history) = problem
        .linear_initialisation(options.max_sk_iterations)
        .map_err(|e| with_data_summary(e, frd))?;
    // 2. Levenberg–Marquardt.
    let (theta, lm_history) = problem
        .levenberg_marquardt(theta, options.max_lm_iterations, &sk_history)
        .map_err(|e| with_data_summary(e, frd))?;

    // Unscale: coefficient of sⁱ = coefficient of pⁱ / ω_sⁱ; descending order.
    let (m, n) = (problem.m, problem.n);
    let numerator: Vec<f64> =
        (0..=m).rev().map(|i| theta[i] / omega_scale.powi(i as i32)).collect();
    let mut denominator: Vec<f64> =
        (1..=n).rev().map(|i| theta[m + i] / omega_scale.powi(i as i32)).collect();
    denominator.push(1.0);
    let model = TransferFunction::new(numerator, denominator)?;
    let mut result = TfestResult {
        model,
        delay_s: options.delay_s,
        fit_percent: 0.0,
        mse: 0.0,
        sk_history,
        lm_history,
    };
    let data: Vec<Complex64> = frd.responses().collect();
    let fitted: Vec<Complex64> = frd.omegas().map(|w| result.response(w)).collect();
    result.fit_percent = complex_fit_percent(&data, &fitted);
    result.mse =
        data.iter().zip(&fitted).map(|(g, h)| (*g - *h).norm_sqr()).sum::<f64>() / frd.len() as f64;
    Ok(result)
}

/// A numerical failure with what the data look like appended (how many points, the frequency
/// range, the magnitude range), so the message says which property of the data defeated the fit.
fn with_data_summary(error: SysidError, frd: &Frd) -> SysidError {
    match error {
        SysidError::Numerical { message, history } => {
            let range = |v: &mut dyn Iterator<Item = f64>| {
                v.fold((f64::INFINITY, 0.0f64), |(lo, hi), x| (lo.min(x), hi.max(x)))
            };
            let (w_lo, w_hi) = range(&mut frd.omegas());
            let (g_lo, g_hi) = range(&mut frd.responses().map(|g| g.norm()));
            SysidError::Numerical {
                message: format!(
                    "{message}; the data: {} points from {w_lo:e} to {w_hi:e} rad/s, |G| from \
                     {g_lo:e} to {g_hi:e}",
                    frd.len()
                ),
                history,
            }
        }
        other => other,
    }
}

/// The widest frequency span (decades × model degree) the scaled design matrix can hold: its
/// columns are powers (ω/ω_s)ⁱ, so their magnitudes span 10^(decades·degree/2) either way; beyond
/// 10^20 the least-squares problem is beyond double precision (the thesis data: 4 decades, degree 2).
const MAX_DECADES_TIMES_DEGREE: f64 = 40.0;

/// Checks the model orders, the number of points, the delay and the data.
fn check_request(frd: &Frd, options: &TfestOptions) -> Result<(), SysidError> {
    options.check()?;
    let (m, n) = (options.zeros, options.poles);
    let count = frd.len();
    if let Some(w) = frd.weight.as_ref().filter(|w| w.len() != count) {
        return Err(FieldError::new("weight", "tfest: one weight per frequency point")
            .with_value(format!("{} weights", w.len()))
            .with_allowed(format!("{count} weights"))
            .into());
    }
    if 2 * count < m + 1 + n {
        return Err(FieldError::new(
            "frd",
            format!("tfest: too few frequency points for {} parameters", m + 1 + n),
        )
        .with_value(format!("{count} points"))
        .with_allowed(format!(">= {} points", (m + 1 + n).div_ceil(2)))
        .into());
    }
    if frd.responses().any(|g| !g.is_finite()) || frd.omegas().any(|w| !(w.is_finite() && w > 0.0))
    {
        return Err(FieldError::new("frd", "tfest: invalid data")
            .with_allowed("finite frequencies > 0 and finite responses")
            .into());
    }
    if frd.responses().all(|g| g.norm() <= 0.0) {
        return Err(FieldError::new("frd", "tfest: every response is zero: nothing to fit").into());
    }
    check_has_dynamics(frd)?;
    let w_min = frd.omegas().fold(f64::INFINITY, f64::min);
    let w_max = frd.omegas().fold(0.0, f64::max);
    let decades = (w_max / w_min).log10();
    let span = decades * m.max(n) as f64;
    if span.is_nan() || span > MAX_DECADES_TIMES_DEGREE {
        return Err(FieldError::new(
            "frd",
            format!(
                "tfest: the frequencies span too many decades ({w_min:e} to {w_max:e} rad/s) for a \
                 degree-{} model: remove the extreme points",
                m.max(n)
            ),
        )
        .with_value(format!("{decades:.1} decades"))
        .with_allowed(format!("<= {:.1} decades", MAX_DECADES_TIMES_DEGREE / m.max(n) as f64))
        .into());
    }
    Ok(())
}

/// Data whose response is the same at every frequency carry no dynamics: every model with the
/// right DC gain fits them and the fit percentage (relative to the data's spread) is undefined
/// (issue 33: it printed "−inf %"), so the request is refused.
fn check_has_dynamics(frd: &Frd) -> Result<(), SysidError> {
    let n = frd.len().max(1) as f64;
    let mean = frd.responses().fold(Complex64::default(), |a, g| a + g).scale(1.0 / n);
    let spread = frd.responses().map(|g| (g - mean).norm()).fold(0.0, f64::max);
    let scale = frd.responses().map(|g| g.norm()).fold(0.0, f64::max);
    if spread <= 1e-12 * scale {
        return Err(FieldError::new(
            "frd",
            "tfest: the response is the same at every frequency: no dynamics to fit (a constant \
             gain has no poles)",
        )
        .with_value(format!("G = {} {:+}j at all {} points", mean.re, mean.im, frd.len()))
        .with_allowed("a response that varies with frequency")
        .into());
    }
    Ok(())
}

impl Problem {
    /// The problem of a checked request, and the frequency scale ω_s = √(ω_min ω_max).
    fn new(frd: &Frd, options: &TfestOptions) -> (Self, f64) {
        let (m, n) = (options.zeros, options.poles);
        let w_min = frd.omegas().fold(f64::INFINITY, f64::min);
        let w_max = frd.omegas().fold(0.0, f64::max);
        let omega_scale = (w_min * w_max).sqrt();
        let degree = m.max(n);
        let powers: Vec<Vec<Complex64>> = frd
            .omegas()
            .map(|w| {
                let p = Complex64::new(0.0, w / omega_scale);
                let mut v = vec![Complex64::new(1.0, 0.0)];
                for i in 1..=degree {
                    let last = v[i - 1];
                    v.push(last * p);
                }
                v
            })
            .collect();
        let data: Vec<Complex64> = frd
            .points
            .iter()
            .map(|p| p.response * Complex64::from_polar(1.0, p.omega_rad_s * options.delay_s))
            .collect();
        let weight: Vec<f64> = (0..frd.len())
            .map(|k| {
                let base = match options.weighting {
                    Weighting::Uniform => 1.0,
                    Weighting::InverseMagnitude => {
                        1.0 / frd.points[k].response.norm().max(f64::MIN_POSITIVE)
                    }
                };
                base * frd.weight.as_ref().map_or(1.0, |w| w[k])
            })
            .collect();
        (Self { m, n, powers, data, weight }, omega_scale)
    }

    /// Step 1 of the module docs: Levy's solution refined by up to `max_iterations`
    /// Sanathanan–Koerner steps; returns θ and the cost after each step.
    fn linear_initialisation(
        &self,
        max_iterations: usize,
    ) -> Result<(Vec<f64>, Vec<f64>), SysidError> {
        let mut theta = self.linear_step(None)?;
        let mut history = vec![self.cost(&theta)];
        for _ in 0..max_iterations {
            let next = self.linear_step(Some(&theta))?;
            let change = next
                .iter()
                .zip(&theta)
                .map(|(a, b)| (a - b).abs() / a.abs().max(1e-12))
                .fold(0.0, f64::max);
            theta = next;
            history.push(self.cost(&theta));
            if change < 1e-10 {
                break;
            }
        }
        if !history.last().is_some_and(|c| c.is_finite()) {
            return Err(SysidError::numerical(
                "tfest: the Sanathanan–Koerner iterations diverged",
                history,
            ));
        }
        Ok((theta, history))
    }

    /// Step 2 of the module docs: Levenberg–Marquardt from `theta` for at most `max_iterations`
    /// iterations; returns θ and the cost after each accepted step. A failure to converge is a
    /// numerical error whose history is `sk_history` followed by the accepted costs.
    fn levenberg_marquardt(
        &self,
        mut theta: Vec<f64>,
        max_iterations: usize,
        sk_history: &[f64],
    ) -> Result<(Vec<f64>, Vec<f64>), SysidError> {
        let mut cost = self.cost(&theta);
        let mut history = Vec::new();
        let mut lambda = 1e-3;
        for _ in 0..max_iterations {
            match self.lm_iteration(&theta, cost, &mut lambda)? {
                LmStep::Accepted { theta: next, cost: next_cost, converged } => {
                    theta = next;
                    cost = next_cost;
                    history.push(cost);
                    if converged || cost <= 0.0 {
                        return Ok((theta, history));
                    }
                }
                // No step decreases the cost even with a tiny step: θ is a (local) minimum to
                // working precision.
                LmStep::Stalled => return Ok((theta, history)),
            }
        }
        let mut all = sk_history.to_vec();
        all.extend(&history);
        Err(SysidError::numerical(
            format!("tfest: Levenberg–Marquardt did not converge in {max_iterations} iterations"),
            all,
        ))
    }

    /// One Levenberg–Marquardt iteration at θ with cost `cost`: raises the damping λ until a step
    /// lowers the cost (then lowers λ for the next iteration), each step the QR solution of the
    /// augmented system [J; √λ·diag(JᵀJ)^{1/2}] δ = [−r; 0].
    fn lm_iteration(
        &self,
        theta: &[f64],
        cost: f64,
        lambda: &mut f64,
    ) -> Result<LmStep, SysidError> {
        let (r, j) = self.residual_jacobian(theta);
        let p = self.unknowns();
        let rows = r.len();
        let mut aug = Matrix::zeros(rows + p, p);
        let mut rhs = vec![0.0; rows + p];
        let mut diag = vec![0.0; p];
        for c in 0..p {
            for row in 0..rows {
                aug.set(row, c, j.get(row, c));
                diag[c] += j.get(row, c) * j.get(row, c);
            }
        }
        for row in 0..rows {
            rhs[row] = -r[row];
        }
        while *lambda < 1e16 {
            for c in 0..p {
                aug.set(rows + c, c, (*lambda * diag[c].max(1e-300)).sqrt());
            }
            let step = least_squares(&aug, &rhs)?;
            let trial: Vec<f64> = theta.iter().zip(&step).map(|(t, s)| t + s).collect();
            let trial_cost = self.cost(&trial);
            if trial_cost.is_finite() && trial_cost < cost {
                let rel_step = step
                    .iter()
                    .zip(theta)
                    .map(|(s, t)| s.abs() / t.abs().max(1e-12))
                    .fold(0.0, f64::max);
                let rel_gain = (cost - trial_cost) / cost.max(f64::MIN_POSITIVE);
                *lambda = (*lambda / 3.0).max(1e-12);
                return Ok(LmStep::Accepted {
                    theta: trial,
                    cost: trial_cost,
                    converged: rel_step < 1e-10 || rel_gain < 1e-14,
                });
            }
            *lambda *= 4.0;
        }
        Ok(LmStep::Stalled)
    }
}

/// The outcome of one Levenberg–Marquardt iteration.
enum LmStep {
    /// A step lowered the cost; `converged` when it was negligible (relative step < 1e-10 or
    /// relative gain < 1e-14).
    Accepted { theta: Vec<f64>, cost: f64, converged: bool },
    /// No damping up to λ = 1e16 lowers the cost.
    Stalled,
}

/// MATLAB's fit on complex data: 100·(1 − ‖g − ĝ‖/‖g − mean g‖).
pub fn complex_fit_percent(g: &[Complex64], g_hat: &[Complex64]) -> f64 {
    let n = g.len().max(1) as f64;
    let mean = g.iter().fold(Complex64::default(), |a, b| a + *b).scale(1.0 / n);
    let err: f64 = g.iter().zip(g_hat).map(|(a, b)| (*a - *b).norm_sqr()).sum::<f64>().sqrt();
    let spread: f64 = g.iter().map(|a| (*a - mean).norm_sqr()).sum::<f64>().sqrt();
    100.0 * (1.0 - err / spread)
}

/// `count` log-spaced frequencies from `lo` to `hi` rad/s inclusive.
pub fn logspace(lo: f64, hi: f64, count: usize) -> Vec<f64> {
    if count < 2 {
        return vec![lo];
    }
    (0..count).map(|k| lo * (hi / lo).powf(k as f64 / (count - 1) as f64)).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use mrbrake_error::Kind as _;

    fn frd_of(g: &TransferFunction, omega: &[f64]) -> Frd {
        Frd::sample(omega, |w| g.response(w))
    }

    /// Each range rule names its argument, the value and what is allowed, so that a front end can
    /// name its own flag or keyword.
    #[test]
    fn bad_orders_and_delays_are_field_errors() {
        let g = TransferFunction::new(vec![1.0], vec![0.01, 1.0]).unwrap();
        let frd = frd_of(&g, &logspace(1.0, 100.0, 9));
        let field = |options: TfestOptions| match tfest(&frd, &options) {
            Err(SysidError::Input(f)) => *f,
            other => panic!("{other:?}"),
        };
        let e = field(TfestOptions::new(0, 0));
        assert_eq!((e.field.as_str(), e.value.as_deref()), ("poles", Some("0")));
        assert_eq!(e.allowed.as_deref(), Some(">= 1"));
        let e = field(TfestOptions::new(1, 2));
        assert_eq!((e.field.as_str(), e.value.as_deref()), ("zeros", Some("2")));
        let mut options = TfestOptions::new(1, 0);
        options.delay_s = f64::NAN;
        assert_eq!(field(options).field, "delay");
        let renamed = SysidError::from(FieldError::out_of_range("poles", 0, ">= 1"))
            .with_field_names(&[("poles", "--poles")]);
        assert!(renamed.is_input_error());
        assert!(renamed.to_string().starts_with("--poles: got 0"), "{renamed}");
    }

    #[test]
    fn exact_data_of_thesis_brake_2_is_recovered() {
        // (5.6): 0.9818/(2.309e-5 s² + 0.01726 s + 1), corners 63.3 and 684.4 rad/s.
        let truth = TransferFunction::new(vec![0.9818], vec![2.309e-5, 0.01726, 1.0]).unwrap();
        let frd = frd_of(&truth, &logspace(0.1, 1000.0, 41));
        let r = tfest(&frd, &TfestOptions::new(2, 0)).unwrap();
        for (a, b) in r.model.denominator.iter().zip(&truth.denominator) {
            assert!((a - b).abs() / b.abs() < 1e-8, "{:?}", r.model);
        }
        let s = r.summary().unwrap();
        assert!(
            (s.corner_frequencies_rad_s[0] - 63.3).abs() < 0.05,
            "{:?}",
            s.corner_frequencies_rad_s
        );
        assert!(
            (s.corner_frequencies_rad_s[1] - 684.4).abs() < 0.5,
            "{:?}",
            s.corner_frequencies_rad_s
        );
        assert!(r.fit_percent > 99.9999);
    }

    #[test]
    fn delay_is_removed_before_fitting() {
        let truth = TransferFunction::new(vec![2.0], vec![0.01, 1.0]).unwrap();
        let omega = logspace(1.0, 1000.0, 31);
        let tau = 5e-4;
        let frd = Frd::sample(&omega, |w| truth.response(w) * Complex64::from_polar(1.0, -w * tau));
        let mut o = TfestOptions::new(1, 0);
        o.delay_s = tau;
        let r = tfest(&frd, &o).unwrap();
        assert!(
            (r.model.denominator[0] - 0.01).abs() < 1e-10 && (r.model.dc_gain() - 2.0).abs() < 1e-9
        );
    }

    #[test]
    fn non_convergence_is_a_numerical_error_with_history() {
        let truth = TransferFunction::new(vec![1.0], vec![1.791e-5, 0.01702, 1.0]).unwrap();
        let omega = logspace(0.1, 1000.0, 41);
        let mut frd = frd_of(&truth, &omega);
        for (k, p) in frd.points.iter_mut().enumerate() {
            let noise = Complex64::new((k as f64).sin(), (k as f64 * 1.3).cos());
            p.response += noise.scale(0.05 * p.response.norm());
        }
        let mut o = TfestOptions::new(2, 0);
        o.max_sk_iterations = 0;
        o.max_lm_iterations = 1;
        match tfest(&frd, &o) {
            Err(SysidError::Numerical { history, .. }) => {
                assert!(history.len() >= 2, "{history:?}")
            }
            other => panic!("expected a numerical error, got {other:?}"),
        }
    }

    #[test]
    fn improper_request_is_an_input_error() {
        let frd = Frd::sample(&[1.0, 2.0], |_| Complex64::new(1.0, 0.0));
        assert!(tfest(&frd, &TfestOptions::new(1, 2)).unwrap_err().is_input_error());
        assert!(tfest(&frd, &TfestOptions::new(3, 1)).unwrap_err().is_input_error());
    }

    /// Issue 18, class 5: data that make the fit impossible are named as such (a 5e-324 rad/s
    /// point, an all-zero response) instead of "column 2 of the design matrix is zero".
    #[test]
    fn impossible_data_are_named() {
        let g = TransferFunction::new(vec![1.0], vec![1.791e-5, 0.01702, 1.0]).unwrap();
        let mut omega = logspace(1.0, 100.0, 10);
        omega[0] = 5e-324;
        let frd = frd_of(&g, &omega);
        let e = tfest(&frd, &TfestOptions::new(2, 0)).unwrap_err();
        assert!(e.is_input_error() && e.to_string().contains("decades"), "{e}");
        let zero = Frd::sample(&logspace(1.0, 100.0, 10), |_| Complex64::new(0.0, 0.0));
        let e = tfest(&zero, &TfestOptions::new(2, 0)).unwrap_err();
        assert!(e.to_string().contains("every response is zero"), "{e}");
        let summary = with_data_summary(SysidError::numerical("tfest: x", vec![1.0]), &zero);
        assert!(summary.to_string().contains("10 points from 1e0 to 1e2 rad/s"), "{summary}");
    }
}
