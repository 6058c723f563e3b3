//! The torque–current band of a propagation: per current of the nominal design's curve, the
//! statistics ([`mrbrake_uq::statistics::Summary`]: mean, standard deviation, 5/50/95 %) of every
//! evaluated sample's torque at that current, read from the sample's stored curve
//! ([`crate::evaluate::torque_curve`]).
//!
//! Each sample's curve is swept at the same fractions of its own maximum current; when that
//! current is itself uncertain the samples' currents differ, so each curve is read at the band's
//! currents by linear interpolation between its two neighbouring points (exact when the currents
//! agree, the usual case), and a sample whose curve ends below a current is left out of that
//! current's statistics (each point counts its samples).

use serde::Serialize;

use mrbrake_uq::UqError;
use mrbrake_uq::statistics::{Summary, summarize};

/// One current of the band.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct BandPoint {
    /// The current (A).
    pub current_a: f64,
    /// The samples' torques at this current (N·m); `count` is how many samples reach it.
    pub torque: Summary,
    /// The nominal design's torque at this current (N·m), when its analysis succeeded.
    pub nominal_nm: Option<f64>,
}

/// Relative tolerance within which a sample's curve is taken to reach a current (the currents
/// are fractions of the same maximum current, computed alike, so equal ones agree to rounding).
const REACH_TOLERANCE: f64 = 1e-9;

/// The band of `curves` (each `(current A, torque N·m)` in increasing current) at the currents of
/// `nominal` (the nominal design's curve), or of the first curve when the nominal has none.
/// Currents that fewer than two samples reach are left out.
pub fn torque_band(
    nominal: Option<&[(f64, f64)]>,
    curves: &[Vec<(f64, f64)>],
) -> Result<Vec<BandPoint>, UqError> {
    let Some(grid) = nominal.or(curves.first().map(Vec::as_slice)) else {
        return Ok(Vec::new());
    };
    let mut band = Vec::with_capacity(grid.len());
    for &(current, nominal_torque) in grid {
        let torques: Vec<f64> = curves.iter().filter_map(|c| torque_at(c, current)).collect();
        if torques.len() < 2 {
            continue;
        }
        band.push(BandPoint {
            current_a: current,
            torque: summarize(&torques)?,
            nominal_nm: nominal.map(|_| nominal_torque),
        });
    }
    Ok(band)
}

/// The value of `curve` (`(x, y)` in increasing `x`) at `current` by linear interpolation between
/// its neighbouring points (a point within rounding of `current` as it is), `None` outside its
/// range.
pub fn torque_at(curve: &[(f64, f64)], current: f64) -> Option<f64> {
    let (first, last) = (curve.first()?, curve.last()?);
    let slack = REACH_TOLERANCE * last.0.abs().max(current.abs());
    if current < first.0 - slack || current > last.0 + slack {
        return None;
    }
    if let Some(&(_, t)) = curve.iter().find(|(i, _)| (i - current).abs() <= slack) {
        return Some(t);
    }
    let above = curve.iter().position(|&(i, _)| i > current)?;
    let ((i0, t0), (i1, t1)) = (curve[above.checked_sub(1)?], curve[above]);
    Some(t0 + (t1 - t0) * (current - i0) / (i1 - i0))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn curve(max_current: f64, scale: f64) -> Vec<(f64, f64)> {
        (0..5).map(|k| (max_current * k as f64 / 4.0, scale * (k as f64))).collect()
    }

    #[test]
    fn band_is_ordered_per_current_and_keeps_the_nominal() {
        let curves: Vec<_> = (0..50).map(|k| curve(2.0, 0.5 + 0.02 * k as f64)).collect();
        let nominal = curve(2.0, 1.0);
        let band = torque_band(Some(&nominal), &curves).unwrap();
        assert_eq!(band.len(), 5);
        for (p, (i, t)) in band.iter().zip(&nominal) {
            assert!((p.current_a - i).abs() < 1e-15 && p.nominal_nm == Some(*t));
            let s = p.torque;
            assert!(s.p5 <= s.p50 && s.p50 <= s.p95 && s.count == 50, "{s:?}");
        }
        // At 2 A the torques are 4 × (0.5 … 1.48): the median is 4 × 0.99.
        assert!((band[4].torque.p50 - 3.96).abs() < 1e-12);
    }

    #[test]
    fn curves_of_other_currents_are_interpolated_or_left_out() {
        // One sample reaches only 1.5 A; the others 2 A and 2.5 A (linear curves: exact).
        let curves = vec![curve(1.5, 0.75), curve(2.0, 1.0), curve(2.5, 1.25)];
        let band = torque_band(Some(&curve(2.0, 1.0)), &curves).unwrap();
        // At 1 A every curve is T = 2 I: 2 N·m each.
        assert_eq!(band[2].torque.count, 3);
        assert!((band[2].torque.p5 - 2.0).abs() < 1e-12 && band[2].torque.std < 1e-12);
        assert_eq!(band[4].torque.count, 2, "the 1.5 A sample does not reach 2 A");
        assert_eq!(torque_at(&curve(2.0, 1.0), -0.1), None);
    }

    #[test]
    fn without_a_nominal_the_first_curve_sets_the_currents() {
        let curves = vec![curve(2.0, 1.0), curve(2.0, 2.0)];
        let band = torque_band(None, &curves).unwrap();
        assert_eq!(band.len(), 5);
        assert!(band.iter().all(|p| p.nominal_nm.is_none()));
        assert!(torque_band(None, &[]).unwrap().is_empty());
    }
}
