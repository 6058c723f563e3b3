//! Statistics of propagated samples: mean, standard deviation and percentiles of a scalar output,
//! and the per-point band of a curve (e.g. torque against current).
//!
//! * Standard deviation: the sample standard deviation with Bessel's correction (`n − 1`), 0 for a
//!   single sample.
//! * Percentiles: linear interpolation between order statistics, Hyndman & Fan (1996), "Sample
//!   quantiles in statistical packages", Am. Stat. 50(4), 361–365, **definition 7** (the default of
//!   R's `quantile` and NumPy's `percentile`): for sorted `x_(0) ≤ … ≤ x_(n−1)` and a fraction `q`,
//!   `h = (n − 1) q`, `Q(q) = x_(⌊h⌋) + (h − ⌊h⌋) (x_(⌊h⌋+1) − x_(⌊h⌋))`.

use crate::UqError;
use serde::Serialize;

/// Mean, standard deviation and the 5th, 50th and 95th percentiles of one output.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Summary {
    /// Number of samples.
    pub count: usize,
    /// Sample mean.
    pub mean: f64,
    /// Sample standard deviation (`n − 1`).
    pub std: f64,
    /// 5th percentile (Hyndman & Fan definition 7).
    pub p5: f64,
    /// Median.
    pub p50: f64,
    /// 95th percentile.
    pub p95: f64,
}

/// The band of a curve: per point (e.g. per current), the [`Summary`] of the samples' values.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Band {
    /// One summary per point of the curve, in the curve's order.
    pub points: Vec<Summary>,
}

impl Band {
    /// The 5th percentiles, point by point.
    pub fn p5(&self) -> Vec<f64> {
        self.points.iter().map(|s| s.p5).collect()
    }

    /// The medians, point by point.
    pub fn p50(&self) -> Vec<f64> {
        self.points.iter().map(|s| s.p50).collect()
    }

    /// The 95th percentiles, point by point.
    pub fn p95(&self) -> Vec<f64> {
        self.points.iter().map(|s| s.p95).collect()
    }

    /// The means, point by point.
    pub fn mean(&self) -> Vec<f64> {
        self.points.iter().map(|s| s.mean).collect()
    }

    /// The standard deviations, point by point.
    pub fn std(&self) -> Vec<f64> {
        self.points.iter().map(|s| s.std).collect()
    }
}

/// The [`Summary`] of `samples`. Errors when there are none or one is not finite (a failed sample
/// must be dropped or re-run by the caller, never averaged).
pub fn summarize(samples: &[f64]) -> Result<Summary, UqError> {
    let sorted = sorted_finite(samples, "output samples")?;
    let n = sorted.len() as f64;
    let mean = sorted.iter().sum::<f64>() / n;
    let std = if sorted.len() > 1 {
        (sorted.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1.0)).sqrt()
    } else {
        0.0
    };
    Ok(Summary {
        count: sorted.len(),
        mean,
        std,
        p5: percentile_of_sorted(&sorted, 0.05),
        p50: percentile_of_sorted(&sorted, 0.5),
        p95: percentile_of_sorted(&sorted, 0.95),
    })
}

/// The `fraction` quantile (`0 ≤ fraction ≤ 1`; 0.95 for the 95th percentile) of `samples` by
/// Hyndman & Fan's definition 7 (module docs).
pub fn percentile(samples: &[f64], fraction: f64) -> Result<f64, UqError> {
    if !(0.0..=1.0).contains(&fraction) {
        return Err(UqError::InvalidProbability { value: fraction });
    }
    Ok(percentile_of_sorted(&sorted_finite(samples, "samples")?, fraction))
}

/// The band of a curve from `samples[k][j]` = the value of sample `k` at point `j` (rows of equal
/// length): one [`Summary`] per point.
pub fn band(samples: &[Vec<f64>]) -> Result<Band, UqError> {
    let width = samples.first().map_or(0, Vec::len);
    if let Some(k) = samples.iter().position(|row| row.len() != width) {
        return Err(UqError::samples(
            "curve samples",
            format!("sample {k} has {} points, sample 0 has {width}", samples[k].len()),
        ));
    }
    if samples.is_empty() || width == 0 {
        return Err(UqError::samples("curve samples", "no samples or no points"));
    }
    let points = (0..width)
        .map(|j| {
            let column: Vec<f64> = samples.iter().map(|row| row[j]).collect();
            summarize(&column).map_err(|_| {
                let k = column.iter().position(|x| !x.is_finite()).unwrap_or(0);
                UqError::samples("curve samples", format!("sample {k}, point {j} is not finite"))
            })
        })
        .collect::<Result<_, _>>()?;
    Ok(Band { points })
}

/// A sorted copy of `samples`, or an error naming the first non-finite sample.
fn sorted_finite(samples: &[f64], what: &'static str) -> Result<Vec<f64>, UqError> {
    if samples.is_empty() {
        return Err(UqError::samples(what, "there are none"));
    }
    if let Some(k) = samples.iter().position(|x| !x.is_finite()) {
        return Err(UqError::samples(what, format!("sample {k} is {}", samples[k])));
    }
    let mut sorted = samples.to_vec();
    sorted.sort_by(f64::total_cmp);
    Ok(sorted)
}

/// Hyndman & Fan definition 7 on non-empty sorted data, `fraction ∈ [0, 1]`.
pub(crate) fn percentile_of_sorted(sorted: &[f64], fraction: f64) -> f64 {
    let h = (sorted.len() - 1) as f64 * fraction;
    let below = h.floor() as usize;
    let above = (below + 1).min(sorted.len() - 1);
    sorted[below] + (h - below as f64) * (sorted[above] - sorted[below])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn definition_7_matches_numpy() {
        // numpy.percentile([1, 2, 3, 4, 10], [5, 50, 95]) = [1.2, 3.0, 8.8]
        let s = summarize(&[4.0, 1.0, 10.0, 3.0, 2.0]).unwrap();
        assert!((s.p5 - 1.2).abs() < 1e-12 && (s.p50 - 3.0).abs() < 1e-12);
        assert!((s.p95 - 8.8).abs() < 1e-12);
        assert!((s.mean - 4.0).abs() < 1e-15);
        assert!((s.std - (50.0f64 / 4.0).sqrt()).abs() < 1e-12);
        let one = summarize(&[2.5]).unwrap();
        assert!(one.std.abs() < 1e-300 && (one.p95 - 2.5).abs() < 1e-300);
    }

    #[test]
    fn bad_samples_are_named() {
        assert!(summarize(&[]).is_err());
        let e = summarize(&[1.0, f64::NAN]).unwrap_err();
        assert!(e.to_string().contains("sample 1"), "{e}");
        let e = band(&[vec![1.0, 2.0], vec![1.0]]).unwrap_err();
        assert!(e.to_string().contains("sample 1 has 1 points"), "{e}");
        let e = band(&[vec![1.0, 2.0], vec![1.0, f64::INFINITY]]).unwrap_err();
        assert!(e.to_string().contains("sample 1, point 1"), "{e}");
        assert!(percentile(&[1.0], 1.5).is_err());
    }

    #[test]
    fn band_per_point() {
        let rows: Vec<Vec<f64>> = (0..101).map(|k| vec![k as f64, 2.0 * k as f64]).collect();
        let b = band(&rows).unwrap();
        assert!((b.p5()[0] - 5.0).abs() < 1e-12 && (b.p95()[1] - 190.0).abs() < 1e-12);
        assert!((b.p50()[1] - 100.0).abs() < 1e-12 && (b.mean()[0] - 50.0).abs() < 1e-12);
    }
}
