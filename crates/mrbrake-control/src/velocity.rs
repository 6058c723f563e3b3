//! Velocity estimate from encoder angles: backward difference, optionally low-pass filtered.
//!
//! `ω_k = (θ_k − θ_{k−1}) / T` is the estimator assumed by the passivity condition (2.2) (Colgate &
//! Brown 1994). A first-order low-pass `ω̂_k = ω̂_{k−1} + α (ω_k − ω̂_{k−1})`, `α = 1 − e^{−2π f_c T}`,
//! reduces the quantisation noise of a fine encoder at the cost of phase lag; `f_c = 0` disables it.

/// Configuration of the estimator.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VelocityEstimator {
    sample_period_s: f64,
    smoothing: f64,
}

/// State of the estimator (previous angle and filtered velocity).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct VelocityState {
    previous_angle_rad: Option<f64>,
    filtered_rad_s: f64,
}

impl VelocityEstimator {
    /// An estimator for sample period `sample_period_s` (> 0) and low-pass cut-off `cutoff_hz`
    /// (0 or negative: plain backward difference). Returns `None` for a non-positive or non-finite
    /// period or a non-finite cut-off.
    pub fn new(sample_period_s: f64, cutoff_hz: f64) -> Option<Self> {
        if !(sample_period_s.is_finite() && sample_period_s > 0.0 && cutoff_hz.is_finite()) {
            return None;
        }
        let smoothing = if cutoff_hz > 0.0 {
            1.0 - libm::exp(-2.0 * core::f64::consts::PI * cutoff_hz * sample_period_s)
        } else {
            1.0
        };
        Some(Self { sample_period_s, smoothing })
    }

    /// Updates the estimate with a new angle and returns it, rad/s (0 on the first call).
    #[inline]
    pub fn update(&self, state: &mut VelocityState, angle_rad: f64) -> f64 {
        let raw = match state.previous_angle_rad {
            Some(previous) => (angle_rad - previous) / self.sample_period_s,
            None => 0.0,
        };
        state.previous_angle_rad = Some(angle_rad);
        state.filtered_rad_s += self.smoothing * (raw - state.filtered_rad_s);
        state.filtered_rad_s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn backward_difference_is_exact_for_a_ramp() {
        let estimator = VelocityEstimator::new(1e-3, 0.0).unwrap();
        let mut state = VelocityState::default();
        assert!(estimator.update(&mut state, 0.0).abs() < 1e-15);
        for k in 1..10 {
            let v = estimator.update(&mut state, 0.002 * k as f64);
            assert!((v - 2.0).abs() < 1e-9);
        }
    }

    #[test]
    fn filtered_estimate_converges_to_the_ramp_slope() {
        let estimator = VelocityEstimator::new(1e-3, 50.0).unwrap();
        let mut state = VelocityState::default();
        let mut v = 0.0;
        for k in 0..200 {
            v = estimator.update(&mut state, 0.5e-3 * k as f64);
        }
        assert!((v - 0.5).abs() < 1e-6);
        assert!(VelocityEstimator::new(0.0, 1.0).is_none());
    }
}
