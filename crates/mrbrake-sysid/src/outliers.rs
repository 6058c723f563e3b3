//! Outlier screening of logged channels (issue 18): one corrupted sample (a torque of 1e308 N·m
//! from a flaky acquisition) would otherwise dominate a least-squares fit and turn every result
//! into NaN or nonsense without a word.
//!
//! The test is robust to the sample itself: with the 1st and 99th percentiles p₁, p₉₉ of the
//! channel and its spread R = p₉₉ − p₁, a sample outside [p₁ − k·R, p₉₉ + k·R] (k =
//! [`OUTLIER_SPREADS`]) is an outlier. A real loop never reaches ten times its own spread beyond
//! its extreme percentiles; a spike of any size beyond that is caught whatever its neighbours are.
//! Non-finite samples are refused by the log reader before this.

use std::path::Path;

use crate::SysidError;

/// How many spreads (p₉₉ − p₁) beyond the extreme percentiles make a sample an outlier.
pub const OUTLIER_SPREADS: f64 = 10.0;

/// The indices of the outliers of `values` (module docs), in order.
pub fn outliers(values: &[f64]) -> Vec<usize> {
    if values.len() < 3 {
        return Vec::new();
    }
    let mut sorted: Vec<f64> = values.to_vec();
    sorted.sort_by(f64::total_cmp);
    let at = |q: f64| sorted[((sorted.len() - 1) as f64 * q).round() as usize];
    let (p1, p99) = (at(0.01), at(0.99));
    let spread = (p99 - p1).max(1e-9 * p1.abs().max(p99.abs())).max(f64::MIN_POSITIVE);
    let (lo, hi) = (p1 - OUTLIER_SPREADS * spread, p99 + OUTLIER_SPREADS * spread);
    values.iter().enumerate().filter(|(_, v)| !(lo..=hi).contains(*v)).map(|(k, _)| k).collect()
}

/// An input error naming `file`, `column`, the number of outliers and the first one (its sample
/// index and time), when `values` has any; `time_s` gives the times of the samples.
pub fn check_outliers(
    file: &Path,
    column: &str,
    time_s: &[f64],
    values: &[f64],
) -> Result<(), SysidError> {
    let found = outliers(values);
    let Some(&first) = found.first() else { return Ok(()) };
    Err(SysidError::File {
        file: file.to_path_buf(),
        line: None,
        message: format!(
            "column `{column}` has {} outlier sample(s), the first {} at t = {} s (sample {}): more \
             than {OUTLIER_SPREADS} times the spread of its 1st–99th percentiles beyond them; remove \
             them from the log, or pass --keep-outliers to fit them anyway",
            found.len(),
            values[first],
            time_s.get(first).copied().unwrap_or(f64::NAN),
            first + 1
        ),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_spike_is_found_and_a_clean_loop_is_not() {
        let loop_: Vec<f64> =
            (0..4000).map(|k| 0.15 + 3.7 * ((k as f64) * 0.003).sin().abs()).collect();
        assert!(outliers(&loop_).is_empty());
        let mut spiked = loop_.clone();
        spiked[1234] = 1e308;
        spiked[2000] = -5e3;
        assert_eq!(outliers(&spiked), vec![1234, 2000]);
        let t: Vec<f64> = (0..4000).map(|k| k as f64 * 1e-3).collect();
        let e = check_outliers(Path::new("c.csv"), "torque_Nm", &t, &spiked).unwrap_err();
        let text = e.to_string();
        assert!(
            text.contains("c.csv") && text.contains("2 outlier") && text.contains("1.234"),
            "{text}"
        );
        // A long pause at one level (most samples equal) does not make the ramps outliers.
        let mut paused = vec![0.15; 9000];
        paused.extend(&loop_);
        assert!(outliers(&paused).is_empty());
    }
}
