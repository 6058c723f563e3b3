//! A brake model's dynamics from frequency-response data: the transfer function from the static
//! torque to the brake torque that the simulators run, fitted to a predicted response
//! (`mrbrake response`, normalised by its DC gain) or to a measured one (`mrbrake freqresp`) alike,
//! since both are sysid's [`Frd`].
//!
//! The fit is sysid's [`tfest`] with [`DYNAMICS_POLES`] poles and no zero (Sanathanan–Koerner
//! iterations, then Levenberg–Marquardt); a pole it puts in the right half-plane is reflected into
//! the left ([`FittedDynamics::reflected`]); the result is scaled to a DC gain of exactly 1 (the
//! static curve carries the gain).

use mrbrake_sysid::frd::Frd;
use mrbrake_sysid::tfest::{TfestOptions, complex_fit_percent, tfest};
use mrbrake_sysid::transfer_function::TransferFunction;
use num_complex::Complex64;

use crate::SimError;

/// Poles of the transfer function fitted to a frequency response: two, like the thesis's
/// identified lags (5.5)/(5.6), and the form the haptic simulation runs (`k / (a s² + b s + 1)`).
pub const DYNAMICS_POLES: usize = 2;

/// A brake's dynamics fitted to frequency-response data.
#[derive(Debug, Clone, PartialEq)]
pub struct FittedDynamics {
    /// The transfer function, DC gain 1, every pole in the left half-plane.
    pub transfer_function: TransferFunction,
    /// The fit percentage on the complex response (after any reflection).
    pub fit_percent: f64,
    /// The real parts (rad/s) of the fitted poles that were in the right half-plane and were
    /// reflected; empty when none was.
    pub reflected: Vec<f64>,
}

impl FittedDynamics {
    /// What the fit did beyond the plain estimate, for a model's `source` text: empty, or a
    /// sentence (starting with "; ") naming the reflected poles.
    pub fn reflection_note(&self) -> String {
        if self.reflected.is_empty() {
            return String::new();
        }
        let at: Vec<String> = self.reflected.iter().map(|re| format!("+{re:.4e}")).collect();
        format!(
            "; the fit's unstable pole(s) at {} rad/s (real part), beyond the band, reflected into the left half-plane (same magnitude response; Gustavsen & Semlyen 1999), fit after reflection",
            at.join(", ")
        )
    }
}

/// Fits [`DYNAMICS_POLES`] poles and no zero to `frd` (module docs).
pub fn fit_dynamics(frd: &Frd) -> Result<FittedDynamics, SimError> {
    let fit = tfest(frd, &TfestOptions::new(DYNAMICS_POLES, 0))
        .map_err(|source| SimError::Model { what: "brake dynamics (tfest)", source })?;
    let mut model = fit.model;
    let mut fit_percent = fit.fit_percent;
    let reflected = reflect_unstable_poles(&mut model)?;
    if !reflected.is_empty() {
        let data: Vec<Complex64> = frd.responses().collect();
        let fitted: Vec<Complex64> = frd.omegas().map(|w| model.response(w)).collect();
        fit_percent = complex_fit_percent(&data, &fitted);
    }
    let gain = model.dc_gain();
    let numerator = model.numerator.iter().map(|c| c / gain).collect();
    let transfer_function = TransferFunction::new(numerator, model.denominator)
        .map_err(|source| SimError::Model { what: "brake dynamics (unit DC gain)", source })?;
    Ok(FittedDynamics { transfer_function, fit_percent, reflected })
}

/// Moves every pole of `tf` with a non-negative real part to the left half-plane (`p → −p̄`),
/// keeping `D(0) = 1`, and returns the real parts of the poles moved. An unconstrained rational fit
/// to a band that ends below a fast pole can put that pole on the wrong side (a two-pole fit with a
/// negative s² coefficient); reflecting it leaves |G(jω)| unchanged at every ω and the phase nearly
/// so in the band, the pole flipping of vector fitting (Gustavsen & Semlyen 1999, IEEE Trans. Power
/// Delivery 14(3), 1052–1061, §III-B).
fn reflect_unstable_poles(tf: &mut TransferFunction) -> Result<Vec<f64>, SimError> {
    let poles =
        tf.poles().map_err(|source| SimError::Model { what: "brake dynamics (poles)", source })?;
    let moved: Vec<f64> = poles.iter().filter(|p| p.re >= 0.0).map(|p| p.re).collect();
    if moved.is_empty() {
        return Ok(moved);
    }
    // Π (s − p), descending powers, from the reflected poles.
    let mut coefficients = vec![Complex64::new(1.0, 0.0)];
    for p in &poles {
        let p = if p.re >= 0.0 { Complex64::new(-p.re, p.im) } else { *p };
        let mut next = coefficients.clone();
        next.push(Complex64::new(0.0, 0.0));
        for (k, c) in coefficients.iter().enumerate() {
            next[k + 1] -= p * c;
        }
        coefficients = next;
    }
    let constant = coefficients.last().map_or(1.0, |c| c.re);
    let denominator: Vec<f64> = coefficients.iter().map(|c| c.re / constant).collect();
    *tf = TransferFunction::new(tf.numerator.clone(), denominator)
        .map_err(|source| SimError::Model { what: "brake dynamics (reflected)", source })?;
    Ok(moved)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_unstable_fast_pole_is_reflected_keeping_the_magnitude_and_dc_gain() {
        // The front design's fit: −6.2968e-8 s² + 0.0095125 s + 1, poles ≈ −107 and +1.51e5 rad/s.
        let mut tf = TransferFunction::new(vec![0.64], vec![-6.2968e-8, 0.0095125, 1.0]).unwrap();
        let before = tf.clone();
        let moved = reflect_unstable_poles(&mut tf).unwrap();
        assert_eq!(moved.len(), 1);
        assert!((moved[0] - 1.5117e5).abs() < 1e2, "{moved:?}");
        assert!(tf.poles().unwrap().iter().all(|p| p.re < 0.0));
        assert!(tf.denominator.iter().all(|c| *c > 0.0), "{:?}", tf.denominator);
        assert!((tf.dc_gain() - 0.64).abs() < 1e-12);
        for w in [0.1, 10.0, 100.0, 1e3, 1e5] {
            let (a, b) = (before.response(w).norm(), tf.response(w).norm());
            assert!((a - b).abs() <= 1e-9 * a, "{w} rad/s: {a} vs {b}");
        }
        // A stable model is left as it is.
        let mut stable = TransferFunction::new(vec![1.0], vec![1.0157e-6, 0.0075757, 1.0]).unwrap();
        assert!(reflect_unstable_poles(&mut stable).unwrap().is_empty());
        assert_eq!(stable.denominator, vec![1.0157e-6, 0.0075757, 1.0]);
    }

    /// A measured-looking response of the thesis's brake 2 (5.6) gives back its lag at DC gain 1.
    #[test]
    fn the_fit_recovers_a_two_pole_lag_at_unit_dc_gain() {
        let truth = TransferFunction::new(vec![0.9818], vec![2.309e-5, 0.01726, 1.0]).unwrap();
        let omegas = mrbrake_sysid::tfest::logspace(0.1, 1000.0, 41);
        let fitted = fit_dynamics(&Frd::sample(&omegas, |w| truth.response(w))).unwrap();
        assert!(fitted.reflected.is_empty() && fitted.reflection_note().is_empty());
        assert!((fitted.transfer_function.dc_gain() - 1.0).abs() < 1e-12);
        let den = &fitted.transfer_function.denominator;
        assert!((den[0] / 2.309e-5 - 1.0).abs() < 1e-6 && (den[1] / 0.01726 - 1.0).abs() < 1e-6);
        assert!(fitted.fit_percent > 99.99);
    }
}
