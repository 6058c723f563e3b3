//! Hysteresis-loop plot: measured torque against current, the repetition-averaged branches and the
//! fitted rising and falling polynomials (thesis Figure 5.6).

use std::path::Path;

use crate::ReportError;
use crate::chart::{Figure, GREY, Panel, Series, SeriesLabelPosition, Shape};

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

/// Markers drawn per averaged branch: enough to show where the mean lies, few enough that the
/// fitted line and the raw samples stay visible between them.
pub const MEAN_MARKERS: usize = 40;

/// Every `len / count`-th element of `points` (all of them when there are fewer than `count`).
fn thinned(points: &[(f64, f64)], count: usize) -> Vec<(f64, f64)> {
    let stride = points.len().div_ceil(count.max(1)).max(1);
    points.iter().step_by(stride).copied().collect()
}

/// `mean − fit` at each averaged point, the fit interpolated linearly at the mean's current.
fn residual(mean: &[(f64, f64)], fit: &[(f64, f64)]) -> Vec<(f64, f64)> {
    let mut sorted: Vec<(f64, f64)> = fit.iter().copied().filter(|p| p.0.is_finite()).collect();
    sorted.sort_by(|a, b| a.0.total_cmp(&b.0));
    let at = |x: f64| -> Option<f64> {
        let k = sorted.partition_point(|p| p.0 < x);
        let (a, b) = (sorted.get(k.checked_sub(1)?)?, sorted.get(k)?);
        let span = b.0 - a.0;
        Some(if span > 0.0 { a.1 + (x - a.0) / span * (b.1 - a.1) } else { a.1 })
    };
    mean.iter().filter_map(|&(x, y)| Some((x, y - at(x)?))).collect()
}

/// The hysteresis-loop figure: the raw samples in grey, the averaged branches as open markers
/// and the fits as lines over them; under it, the residual `mean − fit` of each branch, which
/// shows what the loop's scale hides.
pub fn hysteresis_figure(title: &str, data: &HysteresisPlot) -> Figure {
    let raw = thinned(&data.raw, MAX_RAW_POINTS);
    let mut panel = Panel::new("current [A]", "torque [N·m]");
    if !raw.is_empty() {
        panel = panel.series(
            Series::points("raw samples", raw).color(GREY).shape(Shape::Circle).marker_size(2),
        );
    }
    panel = panel
        .series(Series::line("rising, fit", data.rising_fit.clone()).color(0).line_width(1))
        .series(Series::line("falling, fit", data.falling_fit.clone()).color(1).line_width(1))
        .series(
            Series::points("rising, mean", thinned(&data.rising_mean, MEAN_MARKERS))
                .color(0)
                .shape(Shape::Ring)
                .marker_size(5),
        )
        .series(
            Series::points("falling, mean", thinned(&data.falling_mean, MEAN_MARKERS))
                .color(1)
                .shape(Shape::Triangle)
                .marker_size(4),
        )
        .legend(SeriesLabelPosition::LowerRight);
    let mut figure = Figure::new(title).panel(panel);
    let rising = residual(&data.rising_mean, &data.rising_fit);
    let falling = residual(&data.falling_mean, &data.falling_fit);
    if !rising.is_empty() || !falling.is_empty() {
        let residuals = Panel::new("current [A]", "mean − fit [N·m]")
            .series(Series::line("rising", rising).color(0))
            .series(Series::dashed("falling", falling).color(1))
            .legend(SeriesLabelPosition::UpperRight);
        figure = figure.panel(residuals).row_weights(vec![3.0, 1.2]);
    }
    figure.size(900, 820)
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
        assert!(svg.contains("current") && svg.contains("mean − fit"));
    }

    /// The residual panel shows mean − fit at the mean's currents (the fit interpolated), so a
    /// perfect fit gives zeros and an offset shows as that offset.
    #[test]
    fn residual_is_mean_minus_interpolated_fit() {
        let fit = vec![(0.0, 0.0), (1.0, 2.0), (2.0, 2.0)];
        let mean = vec![(0.5, 1.25), (1.5, 2.0), (3.0, 9.0)];
        let r = residual(&mean, &fit);
        assert_eq!(r.len(), 2, "a current outside the fit has no residual: {r:?}");
        assert!((r[0].1 - 0.25).abs() < 1e-12 && r[1].1.abs() < 1e-12, "{r:?}");
        assert_eq!(thinned(&[(0.0, 0.0); 100], 40).len(), 34);
        assert_eq!(thinned(&[(0.0, 0.0); 10], 40).len(), 10);
    }
}
