//! Bode diagram: magnitude (dB, (5.4)) and phase (degrees) against frequency on a log axis, measured
//! points and fitted or predicted models, in two stacked panels like the thesis's Figures 5.9 and
//! 5.10. Every curve is sysid's frequency-response data ([`Frd`]), whatever it comes from: a
//! measurement, a design's prediction, a model sampled at jω.

use std::path::Path;

use mrbrake_sysid::frd::Frd;

use crate::ReportError;
use crate::chart::{Figure, Panel, Series, SeriesLabelPosition};

/// One frequency-response curve.
#[derive(Debug, Clone)]
pub struct BodeCurve {
    /// Legend label.
    pub label: String,
    /// The response, frequency increasing, phase unwrapped along it.
    pub response: Frd,
    /// Markers (measured data) rather than a line (model).
    pub markers: bool,
}

/// The Bode figure of `curves`. The legends sit in the lower-left corners, which a low-pass
/// response (flat, then falling) leaves empty.
pub fn bode_figure(title: &str, curves: &[BodeCurve]) -> Figure {
    let mut magnitude = Panel::new("frequency [rad/s]", "magnitude [dB]")
        .log_x()
        .legend(SeriesLabelPosition::LowerLeft);
    let mut phase = Panel::new("frequency [rad/s]", "phase [deg]")
        .log_x()
        .legend(SeriesLabelPosition::LowerLeft);
    for (k, c) in curves.iter().enumerate() {
        let points = &c.response.points;
        let mag: Vec<(f64, f64)> =
            points.iter().map(|p| (p.omega_rad_s, p.magnitude_db())).collect();
        let ph: Vec<(f64, f64)> = points.iter().map(|p| (p.omega_rad_s, p.phase_deg())).collect();
        let (m, p) = if c.markers {
            (Series::points(c.label.clone(), mag), Series::points(c.label.clone(), ph))
        } else {
            (Series::line(c.label.clone(), mag), Series::line(c.label.clone(), ph))
        };
        magnitude = magnitude.series(m.color(k));
        phase = phase.series(p.color(k));
    }
    Figure::new(title).panel(magnitude).panel(phase).size(900, 800)
}

/// Writes the Bode figure to `path` (SVG, or PNG for a `.png` name), atomically.
pub fn save_bode(path: &Path, title: &str, curves: &[BodeCurve]) -> Result<(), ReportError> {
    if curves.iter().all(|c| c.response.is_empty()) {
        return Err(ReportError::Data("Bode plot: no frequency point".into()));
    }
    bode_figure(title, curves).save(path)
}

#[cfg(test)]
mod tests {
    use super::*;
    use num_complex::Complex64;

    #[test]
    fn renders_measured_and_model() {
        let omegas: Vec<f64> = (0..41).map(|k| 0.1 * 10f64.powf(k as f64 / 10.0)).collect();
        let response =
            Frd::sample(&omegas, |w| Complex64::new(1.0, 0.0) / Complex64::new(1.0, w / 63.0));
        let svg = bode_figure(
            "Bode",
            &[
                BodeCurve { label: "measured".into(), response: response.clone(), markers: true },
                BodeCurve { label: "model".into(), response, markers: false },
            ],
        )
        .to_svg()
        .unwrap();
        assert!(svg.contains("magnitude") && svg.contains("phase"));
    }
}
