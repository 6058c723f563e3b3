//! Reports of the identification chain (thesis chapter 5): a characterisation of the hysteresis loop
//! (§5.3.1), a measured frequency response and an estimated transfer function (§5.3.2), as text, JSON
//! and plots.
//!
//! Each report is composed here from the result of `mrbrake-sysid` and returned as a `String`, a
//! `serde_json::Value` or a written figure, so that the command-line program, the Python package and
//! the HTML report print the same thing.

use std::fmt::Write as _;
use std::path::Path;

use mrbrake_sysid::characterize::Characterization;
use mrbrake_sysid::frd::Frd;
use mrbrake_sysid::freqresp::{self, MeasuredPoint};
use mrbrake_sysid::polynomial::Polynomial;
use mrbrake_sysid::tfest::{TfestResult, TfestSummary, logspace};
use serde_json::{Value, json};

use crate::ReportError;
use crate::bode::{BodeCurve, save_bode};
use crate::hysteresis::{HysteresisPlot, save_hysteresis};

/// Points per fitted branch on the hysteresis plot.
const BRANCH_PLOT_POINTS: usize = 200;
/// Frequencies of the model curve on the transfer-function Bode plot.
const MODEL_PLOT_POINTS: usize = 400;

/// A characterisation with the log it came from.
#[derive(Debug, Clone, Copy)]
pub struct CharacterizationReport<'a> {
    /// The result.
    pub characterization: &'a Characterization,
    /// The log file.
    pub log: &'a Path,
    /// Samples in the log.
    pub samples: usize,
    /// Mean sample rate of the log, Hz.
    pub sample_rate_hz: f64,
}

impl CharacterizationReport<'_> {
    /// The characterisation's own fields at the top level (as in the model file), plus the log's
    /// (`log`, `samples`, `sample_rate_Hz`).
    pub fn json(&self) -> Result<Value, ReportError> {
        let mut report = serde_json::to_value(self.characterization)?;
        if let Some(map) = report.as_object_mut() {
            map.insert("log".into(), json!(self.log));
            map.insert("samples".into(), json!(self.samples));
            map.insert("sample_rate_Hz".into(), json!(self.sample_rate_hz));
        }
        Ok(report)
    }

    /// The text report: repetitions, current range, both branches with their fit, the loop figures.
    pub fn text(&self) -> String {
        let c = self.characterization;
        let mut out = String::new();
        let _ = writeln!(
            out,
            "log: {} ({} samples, {:.1} Hz)",
            self.log.display(),
            self.samples,
            self.sample_rate_hz
        );
        let _ = writeln!(out, "repetitions: {}", c.repetitions);
        let _ = writeln!(out, "current range: {:.4} .. {:.4} A", c.current_min_a, c.current_max_a);
        for (name, b) in [("rising", &c.rising), ("falling", &c.falling)] {
            let coeffs: Vec<String> = b.coefficients.iter().map(|v| format!("{v:.6e}")).collect();
            let _ = writeln!(
                out,
                "{name:8} T(I) = [{}] (ascending powers of I in A, N·m)",
                coeffs.join(", ")
            );
            let _ = writeln!(
                out,
                "{:8} fit {:.2} % (raw samples), {:.2} % (averaged)",
                "", b.fit_percent, b.fit_percent_mean
            );
        }
        let _ = writeln!(out, "off-state torque: {:.4} N·m", c.off_state_torque_nm);
        let _ = writeln!(out, "max torque: {:.4} N·m", c.max_torque_nm);
        let _ = writeln!(
            out,
            "max hysteresis: {:.4} N·m at {:.3} A",
            c.max_hysteresis_nm, c.max_hysteresis_current_a
        );
        out
    }

    /// The loop plot's data: the raw samples, the repetition-averaged branches and the fits.
    pub fn hysteresis_plot(&self, current_a: &[f64], torque_nm: &[f64]) -> HysteresisPlot {
        let c = self.characterization;
        let grid = |coefficients: &[f64]| {
            let p = Polynomial::new(coefficients.to_vec());
            (0..=BRANCH_PLOT_POINTS)
                .map(|k| {
                    let i = c.current_min_a
                        + (c.current_max_a - c.current_min_a) * k as f64
                            / BRANCH_PLOT_POINTS as f64;
                    (i, p.eval(i))
                })
                .collect::<Vec<_>>()
        };
        HysteresisPlot {
            raw: current_a.iter().copied().zip(torque_nm.iter().copied()).collect(),
            rising_mean: c.rising_mean.clone(),
            falling_mean: c.falling_mean.clone(),
            rising_fit: grid(&c.rising.coefficients),
            falling_fit: grid(&c.falling.coefficients),
        }
    }

    /// Writes the loop plot (thesis Figure 5.6) to `path`, SVG or PNG by extension.
    pub fn save_plot(
        &self,
        path: &Path,
        current_a: &[f64],
        torque_nm: &[f64],
    ) -> Result<(), ReportError> {
        let title =
            format!("Torque–current loop ({} repetitions)", self.characterization.repetitions);
        save_hysteresis(path, &title, &self.hysteresis_plot(current_a, torque_nm))
    }
}

/// The JSON report of a frequency response: the FRD file written and the points.
pub fn frequency_response_json(
    points: &[MeasuredPoint],
    frd_file: &Path,
) -> Result<Value, ReportError> {
    Ok(json!({ "frd_file": frd_file, "points": serde_json::to_value(points)? }))
}

/// The text report of a frequency response: one row per test frequency.
pub fn frequency_response_text(points: &[MeasuredPoint], frd_file: &Path) -> String {
    let mut out = String::new();
    let _ = writeln!(out, "frequency response of {} tests → {}", points.len(), frd_file.display());
    let _ = writeln!(
        out,
        "{:>12} {:>10} {:>10} {:>9} {:>10} {:>8}",
        "omega rad/s", "gain dB", "phase deg", "quality%", "RMSE N·m", "RMSE %"
    );
    for p in points {
        let _ = writeln!(
            out,
            "{:>12.4} {:>10.3} {:>10.2} {:>9.2} {:>10.4} {:>8.2}",
            p.point.omega_rad_s,
            p.point.magnitude_db(),
            p.point.phase_deg(),
            p.quality_percent,
            p.tracking.rmse_nm,
            p.tracking.rmse_percent_of_range
        );
    }
    out
}

/// Writes the measured Bode diagram of a frequency response to `path`.
pub fn save_frequency_response_plot(
    path: &Path,
    points: &[MeasuredPoint],
) -> Result<(), ReportError> {
    let curve =
        BodeCurve { label: "measured".into(), response: freqresp::frd(points), markers: true };
    save_bode(path, "Frequency response", &[curve])
}

/// The text report of a transfer-function estimate: the model, its poles, corners, bandwidth, gain
/// and fit.
pub fn tfest_text(summary: &TfestSummary) -> String {
    let mut out = String::new();
    let delay_s = summary.delay_s;
    let _ = writeln!(
        out,
        "G(s) = N(s)/D(s), highest power first{}",
        if delay_s > 0.0 { format!(", times e^(-{delay_s} s)") } else { String::new() }
    );
    let _ = writeln!(out, "  numerator:   {:?}", summary.numerator);
    let _ = writeln!(out, "  denominator: {:?}", summary.denominator);
    for p in &summary.poles {
        let _ = writeln!(out, "  pole: {:.6} {:+.6}j rad/s", p[0], p[1]);
    }
    let _ = writeln!(out, "  corner frequencies: {:?} rad/s", summary.corner_frequencies_rad_s);
    match summary.bandwidth_rad_s {
        Some(b) => _ = writeln!(out, "  bandwidth (−3 dB): {b:.4} rad/s"),
        None => _ = writeln!(out, "  bandwidth (−3 dB): undefined"),
    }
    let _ = writeln!(out, "  DC gain: {:.6}", summary.dc_gain);
    let _ = writeln!(
        out,
        "  fit: {:.3} %, MSE {:.4e}, stable: {}",
        summary.fit_percent, summary.mse, summary.stable
    );
    out
}

/// The measured points and the fitted model's response (delay included) as Bode curves; the
/// model's phase is unwrapped and put on the data's branch at the lowest frequency.
pub fn tfest_bode_curves(frd: &Frd, fit: &TfestResult) -> Vec<BodeCurve> {
    let mut model = Frd::default();
    if let (Some(first), Some(last)) = (frd.points.first(), frd.points.last()) {
        let omega = logspace(first.omega_rad_s, last.omega_rad_s, MODEL_PLOT_POINTS);
        model = Frd::sample(&omega, |w| fit.response(w));
        model.align_phase(first.phase_deg());
    }
    vec![
        BodeCurve { label: "measured".into(), response: frd.clone(), markers: true },
        BodeCurve { label: "model".into(), response: model, markers: false },
    ]
}

/// Writes the measured points and the fitted model of a `poles`/`zeros` estimate to `path`.
pub fn save_tfest_plot(
    path: &Path,
    frd: &Frd,
    fit: &TfestResult,
    poles: usize,
    zeros: usize,
) -> Result<(), ReportError> {
    if frd.is_empty() {
        return Err(ReportError::Data("Bode plot: no frequency point".into()));
    }
    let title = format!(
        "Estimated transfer function ({poles} poles, {zeros} zeros, fit {:.2} %)",
        fit.fit_percent
    );
    save_bode(path, &title, &tfest_bode_curves(frd, fit))
}

#[cfg(test)]
mod tests {
    use super::*;
    use mrbrake_sysid::tfest::{TfestOptions, tfest};
    use mrbrake_sysid::transfer_function::TransferFunction;

    #[test]
    fn tfest_report_and_curves_follow_the_model() {
        let g = TransferFunction::new(vec![1.0], vec![0.01, 1.0]).unwrap();
        let frd = Frd::sample(&logspace(1.0, 1000.0, 21), |w| g.response(w));
        let fit = tfest(&frd, &TfestOptions::new(1, 0)).unwrap();
        let text = tfest_text(&fit.summary().unwrap());
        assert!(text.starts_with("G(s) = N(s)/D(s), highest power first\n"), "{text}");
        assert!(text.contains("  pole: -100.000000 +0.000000j rad/s"), "{text}");
        let curves = tfest_bode_curves(&frd, &fit);
        assert_eq!(curves[1].response.len(), MODEL_PLOT_POINTS);
        // At the corner: −3 dB and −45°.
        let corner = curves[1]
            .response
            .points
            .iter()
            .min_by(|a, b| (a.omega_rad_s - 100.0).abs().total_cmp(&(b.omega_rad_s - 100.0).abs()))
            .unwrap();
        let (db, deg) = (corner.magnitude_db(), corner.phase_deg());
        assert!((db + 3.0).abs() < 0.1 && (deg + 45.0).abs() < 1.0, "{corner:?}");
    }
}
