//! Continuous-time transfer functions G(s) = N(s)/D(s): frequency response, poles, DC gain, bandwidth.
//!
//! Coefficients are stored in **descending** powers of s (the convention of MATLAB's `tf` and of the
//! thesis's (5.1), (5.5), (5.6)); the estimator normalises the denominator's constant term to 1. The
//! one continuous-time model type of mrbrake: [`crate::tfest`] estimates it, and `mrbrake-sim`
//! discretises it exactly (zero-order hold) for the virtual rig's brake and motor.

use mrbrake_error::FieldError;
use num_complex::Complex64;

use crate::SysidError;
use crate::complex::div;
use crate::frd::HALF_POWER;
use crate::polynomial::roots_descending;

/// G(s) = N(s)/D(s), coefficients in descending powers of s, proper (deg N ≤ deg D), no leading zeros.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct TransferFunction {
    /// Numerator coefficients, highest power first.
    pub numerator: Vec<f64>,
    /// Denominator coefficients, highest power first.
    pub denominator: Vec<f64>,
}

/// `coefficients` without its leading zeros, keeping the last one of an all-zero list.
fn without_leading_zeros(coefficients: Vec<f64>) -> Vec<f64> {
    let first = coefficients
        .iter()
        .position(|c| c.abs() > 0.0)
        .unwrap_or(coefficients.len().saturating_sub(1));
    coefficients[first..].to_vec()
}

/// Evaluates a polynomial given in descending powers at `z` (Horner).
fn eval_descending(c: &[f64], z: Complex64) -> Complex64 {
    c.iter().fold(Complex64::default(), |acc, v| acc * z + Complex64::new(*v, 0.0))
}

impl TransferFunction {
    /// A proper transfer function. Leading zero coefficients are dropped (an all-zero numerator keeps
    /// one zero); fails on non-finite coefficients, an empty numerator, a zero denominator or a
    /// numerator of higher degree than the denominator (improper).
    pub fn new(numerator: Vec<f64>, denominator: Vec<f64>) -> Result<Self, SysidError> {
        if numerator.iter().chain(&denominator).any(|c| !c.is_finite()) {
            return Err(FieldError::new("coefficients", "transfer function")
                .with_allowed("finite numbers")
                .into());
        }
        let numerator = without_leading_zeros(numerator);
        let denominator = without_leading_zeros(denominator);
        if denominator.iter().all(|c| c.abs() <= 0.0) {
            return Err(
                FieldError::new("denominator", "transfer function: must not be zero").into()
            );
        }
        if numerator.is_empty() {
            return Err(FieldError::new("numerator", "transfer function: must not be empty").into());
        }
        if numerator.len() > denominator.len() {
            return Err(FieldError::new("numerator", "transfer function: improper")
                .with_value(format!("degree {}", numerator.len() - 1))
                .with_allowed(format!("degree <= {} (the denominator's)", denominator.len() - 1))
                .into());
        }
        Ok(Self { numerator, denominator })
    }

    /// Order: the degree of the denominator.
    pub fn order(&self) -> usize {
        self.denominator.len() - 1
    }

    /// G(jω).
    pub fn response(&self, omega_rad_s: f64) -> Complex64 {
        let s = Complex64::new(0.0, omega_rad_s);
        div(eval_descending(&self.numerator, s), eval_descending(&self.denominator, s))
    }

    /// G(s) at a complex s.
    pub fn eval(&self, s: Complex64) -> Complex64 {
        div(eval_descending(&self.numerator, s), eval_descending(&self.denominator, s))
    }

    /// Poles (roots of D), sorted by increasing modulus.
    pub fn poles(&self) -> Result<Vec<Complex64>, SysidError> {
        roots_descending(&self.denominator)
    }

    /// Zeros (roots of N), sorted by increasing modulus.
    pub fn zeros(&self) -> Result<Vec<Complex64>, SysidError> {
        roots_descending(&self.numerator)
    }

    /// G(0) = N(0)/D(0) (infinite for a pole at the origin).
    pub fn dc_gain(&self) -> f64 {
        let n0 = self.numerator.last().copied().unwrap_or(0.0);
        let d0 = self.denominator.last().copied().unwrap_or(0.0);
        n0 / d0
    }

    /// Corner (break) frequencies in rad/s: the moduli of the poles, one per complex-conjugate pair,
    /// ascending. For real poles these are the thesis's corner frequencies (62.92 and 887.23 rad/s for
    /// (5.5)).
    pub fn corner_frequencies_rad_s(&self) -> Result<Vec<f64>, SysidError> {
        Ok(self
            .poles()?
            .iter()
            .filter(|p| p.im >= 0.0)
            .map(|p| p.norm())
            .filter(|w| *w > 0.0)
            .collect())
    }

    /// −3 dB bandwidth: the lowest frequency at which |G(jω)| falls to |G(0)|/√2
    /// ([`crate::frd::HALF_POWER`]), by the one bandwidth search ([`crate::frd::bandwidth_rad_s`])
    /// on a 1 % log grid from 10⁻⁴ times the lowest corner to 10⁶ times the highest, bisected on
    /// the model; `None` when the DC gain is zero or infinite, or the magnitude never falls that
    /// low on the grid.
    pub fn bandwidth_rad_s(&self) -> Option<f64> {
        let dc = self.dc_gain().abs();
        if !(dc.is_finite() && dc > 0.0) {
            return None;
        }
        let corners = self.corner_frequencies_rad_s().ok()?;
        let lo = corners.first().copied().unwrap_or(1.0).max(1e-12) * 1e-4;
        let hi = corners.last().copied().unwrap_or(1.0).max(1e-12) * 1e6;
        let grid = std::iter::successors(Some(lo), |w| Some(w * 1.01)).take_while(|w| *w < hi);
        let magnitude = |w: f64| self.response(w).norm();
        crate::frd::bandwidth_rad_s(grid.map(|w| (w, magnitude(w))), magnitude, dc * HALF_POWER)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn thesis_brake_1_corners() {
        // (5.5): corners stated as 62.92 and 887.23 rad/s; the printed (rounded) coefficients give
        // 62.93 and 887.38 rad/s.
        let g = TransferFunction::new(vec![1.0], vec![1.791e-5, 0.01702, 1.0]).unwrap();
        let c = g.corner_frequencies_rad_s().unwrap();
        assert!((c[0] - 62.92).abs() / 62.92 < 5e-4, "{c:?}");
        assert!((c[1] - 887.23).abs() / 887.23 < 5e-4, "{c:?}");
        assert!((g.dc_gain() - 1.0).abs() < 1e-15);
    }

    #[test]
    fn leading_zeros_are_dropped_and_improper_models_refused() {
        let g = TransferFunction::new(vec![0.0, 0.0, 2.0], vec![0.0, 0.01, 1.0]).unwrap();
        assert_eq!((g.numerator.len(), g.denominator.len(), g.order()), (1, 2, 1));
        let zero = TransferFunction::new(vec![0.0, 0.0], vec![1.0, 1.0]).unwrap();
        assert_eq!(zero.numerator.len(), 1);
        let err = TransferFunction::new(vec![1.0, 0.0, 0.0], vec![1.0, 1.0]).unwrap_err();
        assert!(err.to_string().contains("improper"), "{err}");
        assert!(TransferFunction::new(vec![1.0], vec![0.0, 0.0]).is_err());
        assert!(TransferFunction::new(vec![], vec![1.0]).is_err());
        assert!(TransferFunction::new(vec![f64::NAN], vec![1.0]).is_err());
    }

    #[test]
    fn first_order_bandwidth_is_the_pole() {
        let g = TransferFunction::new(vec![2.0], vec![0.01, 1.0]).unwrap();
        let bw = g.bandwidth_rad_s().unwrap();
        assert!((bw - 100.0).abs() < 1e-8, "{bw}");
    }

    #[test]
    fn response_matches_closed_form() {
        let g = TransferFunction::new(vec![1.0], vec![1.0, 1.0]).unwrap();
        let r = g.response(1.0);
        assert!((r.norm() - 1.0 / 2f64.sqrt()).abs() < 1e-15);
        assert!((r.arg() + std::f64::consts::FRAC_PI_4).abs() < 1e-15);
    }
}
