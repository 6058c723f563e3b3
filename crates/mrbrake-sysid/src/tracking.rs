//! Torque-tracking error between a demanded and a measured torque signal, thesis equation (5.2).

use crate::SysidError;
use mrbrake_error::FieldError;

/// Root-mean-square tracking error.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct TrackingError {
    /// RMSE = √(Σ (T_d − T_m)² / n), in N·m (5.2).
    #[serde(rename = "rmse_Nm")]
    pub rmse_nm: f64,
    /// RMSE as a percentage of the demand's range max(T_d) − min(T_d).
    pub rmse_percent_of_range: f64,
    /// Number of samples compared.
    pub samples: usize,
}

/// RMSE (5.2) between the demanded torque `demand_nm` and the measured torque `measured_nm`.
pub fn tracking_error(demand_nm: &[f64], measured_nm: &[f64]) -> Result<TrackingError, SysidError> {
    if demand_nm.len() != measured_nm.len() || demand_nm.is_empty() {
        return Err(FieldError::new("measured", "tracking error: two equally long signals")
            .with_value(format!("{} and {} samples", demand_nm.len(), measured_nm.len()))
            .with_allowed(">= 1 sample each, equally many")
            .into());
    }
    let n = demand_nm.len();
    let sum_sq: f64 = demand_nm.iter().zip(measured_nm).map(|(d, m)| (d - m) * (d - m)).sum();
    let rmse_nm = (sum_sq / n as f64).sqrt();
    let (lo, hi) = demand_nm
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), v| (l.min(*v), h.max(*v)));
    let range = hi - lo;
    let rmse_percent_of_range = if range > 0.0 { 100.0 * rmse_nm / range } else { f64::NAN };
    Ok(TrackingError { rmse_nm, rmse_percent_of_range, samples: n })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn constant_offset_gives_offset_rmse() {
        let d: Vec<f64> = (0..100).map(|i| (i as f64 * 0.1).sin() + 2.0).collect();
        let m: Vec<f64> = d.iter().map(|v| v + 0.05).collect();
        let e = tracking_error(&d, &m).unwrap();
        assert!((e.rmse_nm - 0.05).abs() < 1e-12);
        let range = 2.0 * 0.99999;
        assert!((e.rmse_percent_of_range - 100.0 * 0.05 / range).abs() < 0.01);
    }
}
