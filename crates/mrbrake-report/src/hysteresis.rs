//! Hysteresis-loop plot: measured torque against current, the repetition-averaged branches and the
//! fitted rising and falling polynomials (thesis Figure 5.6).

use std::path::Path;

use crate::ReportError;
use crate::chart::{Figure, Panel, Series};

/// Data of a hysteresis-loop plot; all points are (current A, torque N·m).
#[derive(Debug, Clone, Default)]
pub struct HysteresisPlot {
    /// Raw samples (decimated to at most `MAX_RAW_POINTS` when drawn).
    pub raw: Vec<(f64, f64)>,
    /// Repetition-averaged rising branch.
    pub rising_mean: Vec<(f64, f64)>,
    /// Repetition-averaged falling branch.
    pub falling_mean: Vec<(f64, f64)>,
    /// Fitted rising branch.
    pub rising_fit: Vec<(f64, f64)>,
    /// Fitted falling branch.
    pub falling_fit: Vec<(f64, f64)>,
}

/// Raw samples drawn at most (an SVG with half a million circles is unusable).
pub const MAX_RAW_POINTS: usize = 4000;

/// The hysteresis-loop figure.
pub fn hysteresis_figure(title: &str, data: &HysteresisPlot) -> Figure {
    let stride = data.raw.len().div_ceil(MAX_RAW_POINTS).max(1);
    let raw: Vec<(f64, f64)> = data.raw.iter().step_by(stride).copied().collect();
    let mut panel = Panel::new("current [A]", "torque [N·m]");
    if !raw.is_empty() {
        panel = panel.series(Series::points("measured", raw).color(7));
    }
    panel = panel
        .series(Series::points("rising, mean", data.rising_mean.clone()).color(0))
        .series(Series::points("falling, mean", data.falling_mean.clone()).color(1))
        .series(Series::line("rising, fit", data.rising_fit.clone()).color(0))
        .series(Series::line("falling, fit", data.falling_fit.clone()).color(1));
    Figure::new(title).panel(panel).size(900, 650)
}

/// Writes the hysteresis-loop figure to `path`, atomically.
pub fn save_hysteresis(path: &Path, title: &str, data: &HysteresisPlot) -> Result<(), ReportError> {
    if data.rising_fit.is_empty() || data.falling_fit.is_empty() {
        return Err(ReportError::Data("hysteresis plot: both fitted branches are needed".into()));
    }
    hysteresis_figure(title, data).save(path)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn renders_loop() {
        let up: Vec<(f64, f64)> =
            (0..=20).map(|k| (k as f64 * 0.1, 0.15 + 1.8 * k as f64 * 0.1)).collect();
        let down: Vec<(f64, f64)> = up.iter().map(|(i, t)| (*i, t + 0.3 * i * (2.0 - i))).collect();
        let data = HysteresisPlot {
            raw: up.iter().chain(&down).copied().collect(),
            rising_mean: up.clone(),
            falling_mean: down.clone(),
            rising_fit: up,
            falling_fit: down,
        };
        let svg = hysteresis_figure("loop", &data).to_svg().unwrap();
        assert!(svg.contains("current"));
    }
}
