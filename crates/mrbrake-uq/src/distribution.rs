//! Probability laws of uncertain inputs: normal, uniform, triangular and log-normal, each
//! optionally truncated to `[lower, upper]`, with CDF, quantile (inverse CDF), density, mean and
//! standard deviation of the (truncated) law.
//!
//! Numbers are SI values chosen by the caller; the laws know no units.
//!
//! # Formulas
//!
//! * Normal `N(μ, σ²)`: `F(x) = Φ((x − μ)/σ)` and `F⁻¹(p) = μ + σ Φ⁻¹(p)` with the standard normal
//!   functions of [`crate::special`] (erfc; Wichura's AS 241 quantile with a Newton polish).
//! * Uniform `U(a, b)`: `F(x) = (x − a)/(b − a)`.
//! * Triangular `(a, c, b)` with mode `c`: the integral of the piecewise-linear density,
//!   `F(x) = (x − a)²/((b − a)(c − a))` on `[a, c]`, `1 − (b − x)²/((b − a)(b − c))` on `[c, b]`,
//!   inverted in closed form.
//! * Log-normal: `ln X ~ N(μ, σ²)` (`log_mean` μ, `log_std_dev` σ; Johnson, Kotz & Balakrishnan,
//!   *Continuous Univariate Distributions* vol. 1 (JKB), 2nd ed., 1994, ch. 14); [`Distribution::log_normal_from_mean_std`] converts a mean `m` and
//!   standard deviation `s` of X by `σ² = ln(1 + s²/m²)`, `μ = ln m − σ²/2`.
//!
//! **Truncation** to `[a, b]` renormalises the law on the interval:
//! `F_T(x) = (F(x) − F(a)) / (F(b) − F(a))` and `F_T⁻¹(p) = F⁻¹(F(a) + p (F(b) − F(a)))`
//! (inverse-CDF sampling of the renormalised interval; e.g. Devroye, *Non-Uniform Random Variate
//! Generation*, 1986, ch. II §2). When the interval lies above the law's median both are written with
//! the survival function `S = 1 − F` instead (`F_T(x) = (S(a) − S(x))/(S(a) − S(b))`,
//! `F_T⁻¹(p) = S⁻¹(S(a) − p (S(a) − S(b)))`), so a truncation far in the upper tail keeps its
//! precision. Moments of the truncated laws are closed forms: the truncated normal's from JKB
//! vol. 1, ch. 13 (the doubly truncated normal), the log-normal's
//! partial moments `E[X^k; a < X < b] = exp(kμ + k²σ²/2) [Φ(β − kσ) − Φ(α − kσ)]`
//! (JKB vol. 1, ch. 14), the uniform's trivially, the triangular's by exact Gauss–Legendre
//! quadrature of its piecewise-linear density.

use crate::UqError;
use crate::special::{
    std_normal_cdf, std_normal_isf, std_normal_mass, std_normal_pdf, std_normal_quantile,
    std_normal_sf,
};
use serde::Serialize;

/// A probability law before truncation, with its parameters in SI units chosen by the caller.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[serde(tag = "distribution", rename_all = "snake_case")]
pub enum Law {
    /// Normal (Gaussian) law `N(mean, std_dev²)`.
    Normal {
        /// Mean μ.
        mean: f64,
        /// Standard deviation σ > 0.
        std_dev: f64,
    },
    /// Uniform law on `[lower, upper]`.
    Uniform {
        /// Lower end.
        lower: f64,
        /// Upper end (> lower).
        upper: f64,
    },
    /// Triangular law on `[lower, upper]` with its peak at `mode`.
    Triangular {
        /// Lower end.
        lower: f64,
        /// Mode, in `[lower, upper]`.
        mode: f64,
        /// Upper end (> lower).
        upper: f64,
    },
    /// Log-normal law: `ln X ~ N(log_mean, log_std_dev²)`.
    LogNormal {
        /// Mean μ of `ln X`.
        log_mean: f64,
        /// Standard deviation σ > 0 of `ln X`.
        log_std_dev: f64,
    },
}

/// A truncation interval `[lower, upper]`; either end may be infinite (one-sided truncation).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Truncation {
    /// Lower bound (may be `−∞`).
    pub lower: f64,
    /// Upper bound (may be `+∞`), greater than `lower`.
    pub upper: f64,
}

/// A validated, optionally truncated law: the marginal distribution of one uncertain input.
///
/// ```
/// use mrbrake_uq::distribution::Distribution;
/// // A gap of 0.5 mm ± 20 µm (1σ), truncated to the machinable 0.45–0.55 mm.
/// let gap = Distribution::normal(0.5e-3, 20e-6)?.truncated(0.45e-3, 0.55e-3)?;
/// let median = gap.quantile(0.5)?;
/// assert!((median - 0.5e-3).abs() < 1e-12);
/// assert!((gap.cdf(gap.quantile(0.9)?) - 0.9).abs() < 1e-12);
/// assert!(gap.std_dev() < 20e-6); // truncation narrows the law
/// # Ok::<(), mrbrake_uq::UqError>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Distribution {
    law: Law,
    truncation: Option<Truncation>,
    #[serde(skip)]
    window: Window,
}

/// The renormalised interval of a (possibly truncated) law: its effective ends and how its CDF
/// is measured (from the lower tail by `F`, or from the upper tail by `S` when above the median).
#[derive(Debug, Clone, Copy, PartialEq)]
struct Window {
    /// Effective lower end: the truncation's lower bound clipped to the law's support.
    lower: f64,
    /// Effective upper end.
    upper: f64,
    /// True when probabilities are measured by the survival function (interval above the median).
    upper_tail: bool,
    /// `F(lower)` (or `S(lower)` in upper-tail mode).
    start: f64,
    /// The law's probability of the interval, `F(upper) − F(lower)`.
    mass: f64,
}

impl Law {
    /// The law's name as it appears in errors and JSON (`normal`, `uniform`, …).
    pub fn name(&self) -> &'static str {
        match self {
            Self::Normal { .. } => "normal",
            Self::Uniform { .. } => "uniform",
            Self::Triangular { .. } => "triangular",
            Self::LogNormal { .. } => "log_normal",
        }
    }

    /// Checks the parameters: finite, positive spreads, ordered ends, mode inside.
    fn validate(&self) -> Result<(), UqError> {
        let law = self.name();
        let bad = |parameter, value, allowed| {
            Err(UqError::InvalidParameter { law, parameter, value, allowed })
        };
        let finite = |parameter: &'static str, value: f64| {
            if value.is_finite() { Ok(()) } else { bad(parameter, value, "a finite number") }
        };
        match *self {
            Self::Normal { mean, std_dev } => {
                finite("mean", mean)?;
                if !(std_dev.is_finite() && std_dev > 0.0) {
                    return bad("std_dev", std_dev, "positive and finite");
                }
            }
            Self::Uniform { lower, upper } => {
                finite("lower", lower)?;
                finite("upper", upper)?;
                if upper <= lower {
                    return bad("upper", upper, "greater than `lower`");
                }
            }
            Self::Triangular { lower, mode, upper } => {
                finite("lower", lower)?;
                finite("mode", mode)?;
                finite("upper", upper)?;
                if upper <= lower {
                    return bad("upper", upper, "greater than `lower`");
                }
                if !(lower..=upper).contains(&mode) {
                    return bad("mode", mode, "within [lower, upper]");
                }
            }
            Self::LogNormal { log_mean, log_std_dev } => {
                finite("log_mean", log_mean)?;
                if !(log_std_dev.is_finite() && log_std_dev > 0.0) {
                    return bad("log_std_dev", log_std_dev, "positive and finite");
                }
            }
        }
        Ok(())
    }

    /// The support `[lower, upper]` of the untruncated law.
    fn support(&self) -> (f64, f64) {
        match *self {
            Self::Normal { .. } => (f64::NEG_INFINITY, f64::INFINITY),
            Self::Uniform { lower, upper } | Self::Triangular { lower, upper, .. } => {
                (lower, upper)
            }
            Self::LogNormal { .. } => (0.0, f64::INFINITY),
        }
    }

    /// The standardised variable of the normal and log-normal laws (`(x − μ)/σ` or
    /// `(ln x − μ)/σ`); `None` for the others.
    fn standardised(&self, x: f64) -> Option<f64> {
        match *self {
            Self::Normal { mean, std_dev } => Some((x - mean) / std_dev),
            Self::LogNormal { log_mean, log_std_dev } => {
                Some(if x <= 0.0 { f64::NEG_INFINITY } else { (x.ln() - log_mean) / log_std_dev })
            }
            _ => None,
        }
    }

    /// CDF `F(x)` of the untruncated law.
    fn cdf(&self, x: f64) -> f64 {
        if let Some(z) = self.standardised(x) {
            return std_normal_cdf(z);
        }
        let (lower, upper) = self.support();
        if x <= lower {
            return 0.0;
        }
        if x >= upper {
            return 1.0;
        }
        match *self {
            Self::Triangular { mode, .. } if x <= mode => {
                (x - lower).powi(2) / ((upper - lower) * (mode - lower))
            }
            Self::Triangular { mode, .. } => {
                1.0 - (upper - x).powi(2) / ((upper - lower) * (upper - mode))
            }
            _ => (x - lower) / (upper - lower),
        }
    }

    /// Survival function `S(x) = 1 − F(x)` of the untruncated law, accurate in the upper tail.
    fn sf(&self, x: f64) -> f64 {
        if let Some(z) = self.standardised(x) {
            return std_normal_sf(z);
        }
        match *self {
            Self::Triangular { lower, mode, upper } if x > mode && x < upper => {
                (upper - x).powi(2) / ((upper - lower) * (upper - mode))
            }
            _ => 1.0 - self.cdf(x),
        }
    }

    /// Quantile `F⁻¹(p)` of the untruncated law for `p ∈ [0, 1]`.
    fn quantile(&self, p: f64) -> f64 {
        match *self {
            Self::Normal { mean, std_dev } => mean + std_dev * std_normal_quantile(p),
            Self::LogNormal { log_mean, log_std_dev } => {
                (log_mean + log_std_dev * std_normal_quantile(p)).exp()
            }
            Self::Uniform { lower, upper } => lower + p * (upper - lower),
            Self::Triangular { lower, mode, upper } => {
                if p * (upper - lower) <= mode - lower {
                    lower + (p * (upper - lower) * (mode - lower)).sqrt()
                } else {
                    upper - ((1.0 - p) * (upper - lower) * (upper - mode)).sqrt()
                }
            }
        }
    }

    /// Inverse survival function: `x` with `S(x) = q`, accurate for small `q`.
    fn isf(&self, q: f64) -> f64 {
        match *self {
            Self::Normal { mean, std_dev } => mean + std_dev * std_normal_isf(q),
            Self::LogNormal { log_mean, log_std_dev } => {
                (log_mean + log_std_dev * std_normal_isf(q)).exp()
            }
            Self::Uniform { lower, upper } => upper - q * (upper - lower),
            Self::Triangular { lower, mode, upper } if q * (upper - lower) <= upper - mode => {
                upper - (q * (upper - lower) * (upper - mode)).sqrt()
            }
            Self::Triangular { .. } => self.quantile(1.0 - q),
        }
    }

    /// Density `f(x)` of the untruncated law.
    fn pdf(&self, x: f64) -> f64 {
        let (lower, upper) = self.support();
        if x < lower || x > upper {
            return 0.0;
        }
        match *self {
            Self::Normal { mean, std_dev } => std_normal_pdf((x - mean) / std_dev) / std_dev,
            Self::LogNormal { log_mean, log_std_dev } if x > 0.0 => {
                std_normal_pdf((x.ln() - log_mean) / log_std_dev) / (x * log_std_dev)
            }
            Self::LogNormal { .. } => 0.0,
            Self::Uniform { .. } => 1.0 / (upper - lower),
            Self::Triangular { mode, .. } if x <= mode => {
                2.0 * (x - lower) / ((upper - lower) * (mode - lower))
            }
            Self::Triangular { mode, .. } => 2.0 * (upper - x) / ((upper - lower) * (upper - mode)),
        }
    }
}

impl Distribution {
    /// A law, optionally truncated to `(lower, upper)`; checks the parameters and that the
    /// truncation is an interval holding probability.
    pub fn new(law: Law, truncation: Option<(f64, f64)>) -> Result<Self, UqError> {
        law.validate()?;
        let truncation = truncation.map(|(lower, upper)| Truncation { lower, upper });
        let window = window_of(&law, truncation)?;
        Ok(Self { law, truncation, window })
    }

    /// The normal law `N(mean, std_dev²)`.
    pub fn normal(mean: f64, std_dev: f64) -> Result<Self, UqError> {
        Self::new(Law::Normal { mean, std_dev }, None)
    }

    /// The uniform law on `[lower, upper]`.
    pub fn uniform(lower: f64, upper: f64) -> Result<Self, UqError> {
        Self::new(Law::Uniform { lower, upper }, None)
    }

    /// The triangular law on `[lower, upper]` peaking at `mode`.
    pub fn triangular(lower: f64, mode: f64, upper: f64) -> Result<Self, UqError> {
        Self::new(Law::Triangular { lower, mode, upper }, None)
    }

    /// The log-normal law with `ln X ~ N(log_mean, log_std_dev²)`.
    pub fn log_normal(log_mean: f64, log_std_dev: f64) -> Result<Self, UqError> {
        Self::new(Law::LogNormal { log_mean, log_std_dev }, None)
    }

    /// The log-normal law whose own mean and standard deviation are `mean` and `std_dev`
    /// (`σ² = ln(1 + std_dev²/mean²)`, `μ = ln mean − σ²/2`).
    pub fn log_normal_from_mean_std(mean: f64, std_dev: f64) -> Result<Self, UqError> {
        let bad = |parameter, value| UqError::InvalidParameter {
            law: "log_normal",
            parameter,
            value,
            allowed: "positive and finite",
        };
        if !(mean.is_finite() && mean > 0.0) {
            return Err(bad("mean", mean));
        }
        if !(std_dev.is_finite() && std_dev > 0.0) {
            return Err(bad("std_dev", std_dev));
        }
        let variance = (std_dev / mean).powi(2).ln_1p();
        Self::log_normal(mean.ln() - 0.5 * variance, variance.sqrt())
    }

    /// This law truncated to `[lower, upper]` (replacing any earlier truncation); either end may
    /// be infinite.
    pub fn truncated(self, lower: f64, upper: f64) -> Result<Self, UqError> {
        Self::new(self.law, Some((lower, upper)))
    }

    /// The untruncated law.
    pub fn law(&self) -> &Law {
        &self.law
    }

    /// The truncation interval, if any.
    pub fn truncation(&self) -> Option<Truncation> {
        self.truncation
    }

    /// The support `[lower, upper]` of the (truncated) law.
    pub fn support(&self) -> (f64, f64) {
        (self.window.lower, self.window.upper)
    }

    /// CDF of the (truncated) law; 0 below and 1 above the support (NaN for a NaN `x`).
    pub fn cdf(&self, x: f64) -> f64 {
        let w = &self.window;
        if x.is_nan() {
            return f64::NAN;
        }
        if x <= w.lower {
            return 0.0;
        }
        if x >= w.upper {
            return 1.0;
        }
        let p = if w.upper_tail {
            (w.start - self.law.sf(x)) / w.mass
        } else {
            (self.law.cdf(x) - w.start) / w.mass
        };
        p.clamp(0.0, 1.0)
    }

    /// Quantile (inverse CDF) of the (truncated) law for `p ∈ [0, 1]`: the support's ends at 0 and
    /// 1 (infinite for an unbounded side). Errors for `p` outside `[0, 1]` or NaN.
    pub fn quantile(&self, p: f64) -> Result<f64, UqError> {
        if !(0.0..=1.0).contains(&p) {
            return Err(UqError::InvalidProbability { value: p });
        }
        let w = &self.window;
        let x = if w.upper_tail {
            self.law.isf((w.start - p * w.mass).max(0.0))
        } else {
            self.law.quantile((w.start + p * w.mass).min(1.0))
        };
        Ok(x.clamp(w.lower, w.upper))
    }

    /// Density of the (truncated) law.
    pub fn pdf(&self, x: f64) -> f64 {
        if x < self.window.lower || x > self.window.upper {
            return 0.0;
        }
        self.law.pdf(x) / self.window.mass
    }

    /// Mean of the (truncated) law.
    pub fn mean(&self) -> f64 {
        self.moments().0
    }

    /// Standard deviation of the (truncated) law.
    pub fn std_dev(&self) -> f64 {
        self.moments().1
    }

    /// `(mean, standard deviation)` of the (truncated) law, in closed form (module docs).
    fn moments(&self) -> (f64, f64) {
        let (a, b) = (self.window.lower, self.window.upper);
        match self.law {
            Law::Normal { mean, std_dev } => {
                let (m, v) =
                    std_truncated_normal_moments((a - mean) / std_dev, (b - mean) / std_dev);
                (mean + std_dev * m, std_dev * v.sqrt())
            }
            Law::Uniform { .. } => (0.5 * (a + b), (b - a) / 12f64.sqrt()),
            Law::Triangular { .. } => triangular_moments(&self.law, a, b),
            Law::LogNormal { log_mean, log_std_dev } => log_normal_moments(
                log_mean,
                log_std_dev,
                self.law.standardised(a).unwrap_or(f64::NEG_INFINITY),
                self.law.standardised(b).unwrap_or(f64::INFINITY),
            ),
        }
    }
}

/// The renormalisation window of `law` truncated to `truncation` (or its whole support).
fn window_of(law: &Law, truncation: Option<Truncation>) -> Result<Window, UqError> {
    let (support_lower, support_upper) = law.support();
    let Some(Truncation { lower, upper }) = truncation else {
        return Ok(Window {
            lower: support_lower,
            upper: support_upper,
            upper_tail: false,
            start: 0.0,
            mass: 1.0,
        });
    };
    let invalid = |reason| UqError::InvalidTruncation { law: law.name(), lower, upper, reason };
    if lower.is_nan() || upper.is_nan() {
        return Err(invalid("a bound is NaN"));
    }
    if lower >= upper {
        return Err(invalid("`lower` must be below `upper`"));
    }
    let (a, b) = (lower.max(support_lower), upper.min(support_upper));
    if a >= b {
        return Err(invalid("the interval lies outside the law's support"));
    }
    let upper_tail = law.cdf(a) > 0.5;
    let (start, mass) = if upper_tail {
        let start = law.sf(a);
        (start, start - law.sf(b))
    } else {
        let start = law.cdf(a);
        (start, law.cdf(b) - start)
    };
    let mass = match *law {
        // The normal laws' interval probability without cancellation in either tail.
        Law::Normal { .. } | Law::LogNormal { .. } => std_normal_mass(
            law.standardised(a).unwrap_or(f64::NEG_INFINITY),
            law.standardised(b).unwrap_or(f64::INFINITY),
        ),
        _ => mass,
    };
    if !(mass > 0.0 && mass.is_finite()) {
        return Err(invalid("the interval holds no probability of the law"));
    }
    Ok(Window { lower: a, upper: b, upper_tail, start, mass })
}

/// Mean and variance of the standard normal truncated to `[α, β]` (JKB vol. 1, ch. 13):
/// `m = (φ(α) − φ(β))/Z`, `v = 1 + (αφ(α) − βφ(β))/Z − m²`, `Z = Φ(β) − Φ(α)`. An interval
/// centred above 0 is mirrored (`[−β, −α]`, mean negated) so `Z` and the densities are evaluated
/// in the lower tail, where they are accurate.
fn std_truncated_normal_moments(alpha: f64, beta: f64) -> (f64, f64) {
    if alpha + beta > 0.0 {
        let (m, v) = std_truncated_normal_moments(-beta, -alpha);
        return (-m, v);
    }
    let z = std_normal_mass(alpha, beta);
    let density = |t: f64| if t.is_finite() { std_normal_pdf(t) } else { 0.0 };
    let moment = |t: f64| if t.is_finite() { t * std_normal_pdf(t) } else { 0.0 };
    let m = (density(alpha) - density(beta)) / z;
    let v = 1.0 + (moment(alpha) - moment(beta)) / z - m * m;
    (m, v.max(0.0))
}

/// Mean and standard deviation of the log-normal `ln X ~ N(μ, σ²)` truncated to the standardised
/// interval `[α, β]` of `ln X`, from its partial moments (JKB vol. 1, ch. 14):
/// `E[X^k | α < Z < β] = exp(kμ + k²σ²/2) (Φ(β − kσ) − Φ(α − kσ)) / (Φ(β) − Φ(α))`.
fn log_normal_moments(mu: f64, sigma: f64, alpha: f64, beta: f64) -> (f64, f64) {
    let mass = std_normal_mass(alpha, beta);
    let raw = |k: f64| {
        (k * mu + 0.5 * k * k * sigma * sigma).exp()
            * std_normal_mass(alpha - k * sigma, beta - k * sigma)
            / mass
    };
    let (m1, m2) = (raw(1.0), raw(2.0));
    (m1, variance_from_raw(m1, m2).sqrt())
}

/// `E[X²] − E[X]²`, clamped at 0 against rounding, and infinite (not NaN) when `E[X²]` overflows.
fn variance_from_raw(m1: f64, m2: f64) -> f64 {
    if m2.is_infinite() {
        return f64::INFINITY;
    }
    (m2 - m1 * m1).max(0.0)
}

/// Mean and standard deviation of a triangular law truncated to `[a, b]` (inside its support):
/// the density is linear on `[a, c]` and `[c, b]`, so each piece's moments `∫ (x − s)^k f(x) dx`,
/// `k ≤ 2`, are integrated exactly by 2-point Gauss–Legendre (exact to degree 3), about the
/// interval's midpoint `s` to avoid cancellation in the variance.
fn triangular_moments(law: &Law, a: f64, b: f64) -> (f64, f64) {
    let Law::Triangular { mode, .. } = *law else {
        return (f64::NAN, f64::NAN);
    };
    let shift = 0.5 * (a + b);
    let mut sums = [0.0; 3];
    let pieces = [(a, mode.clamp(a, b)), (mode.clamp(a, b), b)];
    let node = 0.5 / 3f64.sqrt();
    for (lo, hi) in pieces {
        let (centre, width) = (0.5 * (lo + hi), hi - lo);
        for x in [centre - node * width, centre + node * width] {
            let f = law.pdf(x) * 0.5 * width;
            let d = x - shift;
            sums[0] += f;
            sums[1] += f * d;
            sums[2] += f * d * d;
        }
    }
    let mean = sums[1] / sums[0];
    (shift + mean, (sums[2] / sums[0] - mean * mean).max(0.0).sqrt())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bad_parameters_are_named() {
        let e = Distribution::normal(1.0, -0.1).unwrap_err();
        assert!(matches!(e, UqError::InvalidParameter { parameter: "std_dev", .. }), "{e}");
        let e = Distribution::uniform(2.0, 1.0).unwrap_err();
        assert!(matches!(e, UqError::InvalidParameter { parameter: "upper", .. }));
        let e = Distribution::triangular(0.0, 2.0, 1.0).unwrap_err();
        assert!(matches!(e, UqError::InvalidParameter { parameter: "mode", .. }));
        let e = Distribution::log_normal(f64::NAN, 1.0).unwrap_err();
        assert!(matches!(e, UqError::InvalidParameter { parameter: "log_mean", .. }));
        let e = Distribution::log_normal_from_mean_std(-1.0, 1.0).unwrap_err();
        assert!(matches!(e, UqError::InvalidParameter { parameter: "mean", .. }));
    }

    #[test]
    fn bad_truncations_are_rejected() {
        let n = Distribution::normal(0.0, 1.0).unwrap();
        assert!(matches!(n.truncated(1.0, 1.0), Err(UqError::InvalidTruncation { .. })));
        assert!(matches!(n.truncated(f64::NAN, 1.0), Err(UqError::InvalidTruncation { .. })));
        // 40 σ out: the probability underflows to zero.
        assert!(matches!(n.truncated(40.0, 41.0), Err(UqError::InvalidTruncation { .. })));
        let u = Distribution::uniform(0.0, 1.0).unwrap();
        assert!(matches!(u.truncated(2.0, 3.0), Err(UqError::InvalidTruncation { .. })));
        let l = Distribution::log_normal(0.0, 1.0).unwrap();
        assert!(matches!(l.truncated(-2.0, 0.0), Err(UqError::InvalidTruncation { .. })));
        // A far but representable upper tail is fine and precise.
        let tail = n.truncated(10.0, f64::INFINITY).unwrap();
        let median = tail.quantile(0.5).unwrap();
        assert!(median > 10.0 && median < 10.1, "{median}");
        assert!((tail.cdf(median) - 0.5).abs() < 1e-12);
    }

    #[test]
    fn closed_form_moments() {
        // Half-normal: mean σ√(2/π), variance σ²(1 − 2/π).
        let half = Distribution::normal(0.0, 2.0).unwrap().truncated(0.0, f64::INFINITY).unwrap();
        assert!((half.mean() - 2.0 * (2.0 / std::f64::consts::PI).sqrt()).abs() < 1e-14);
        let sd = 2.0 * (1.0 - 2.0 / std::f64::consts::PI).sqrt();
        assert!((half.std_dev() - sd).abs() < 1e-14);
        // Triangular (0, 1, 3): mean 4/3, variance (a²+b²+c²−ab−ac−bc)/18 = 7/18.
        let t = Distribution::triangular(0.0, 1.0, 3.0).unwrap();
        assert!((t.mean() - 4.0 / 3.0).abs() < 1e-14);
        assert!((t.std_dev() - (7.0f64 / 18.0).sqrt()).abs() < 1e-14);
        // Log-normal: mean exp(μ + σ²/2), variance (exp(σ²) − 1) exp(2μ + σ²).
        let l = Distribution::log_normal_from_mean_std(3.0, 0.6).unwrap();
        assert!((l.mean() - 3.0).abs() < 1e-13 && (l.std_dev() - 0.6).abs() < 1e-13);
        let u = Distribution::uniform(1.0, 5.0).unwrap().truncated(2.0, 9.0).unwrap();
        assert!((u.mean() - 3.5).abs() < 1e-15 && (u.std_dev() - 3.0 / 12f64.sqrt()).abs() < 1e-15);
    }
}
