//! Frequency response from sinusoidal tests (thesis §5.3.2): gain (5.3)/(5.4) and phase per frequency.
//!
//! For each test, input and output are fitted in the least-squares sense by `c + a cos ωt + b sin ωt`
//! at the known test frequency ω (the "sine-fit" of IEEE Std 1057, three-parameter form), after
//! discarding the start-up transient: the first `discard_periods` periods or `settle_s` seconds,
//! whichever is longer, then keeping the largest whole number of periods that remain. With the phasors
//! U = a_u − j b_u and Y = a_y − j b_y the response is G(jω) = Y/U, i.e. gain |T_o/T_i| (5.3) and the
//! phase difference. The quality figure of a point is the fit percentage of the output sine,
//! 100·(1 − ‖y − ŷ‖/‖y − mean y‖): near 100 % for a clean sinusoid, lower with noise or distortion.
//!
//! Each test gives a [`MeasuredPoint`]: the one frequency-response point ([`FrequencyPoint`],
//! G(jω) at ω) with the quality, tracking error and log it was measured with; [`frd`] is the
//! points as data for the estimator, [`frd_csv`] their FRD file (the one writer,
//! [`crate::frd::write_csv`]).

use std::path::{Path, PathBuf};

use mrbrake_error::FieldError;
use num_complex::Complex64;

use crate::SysidError;
use crate::characterize::fit_percent;
use crate::complex::div;
use crate::frd::{Column, Frd, FrequencyPoint, unwrap_phase, write_csv};
use crate::linalg::{Matrix, least_squares};
use crate::log::read_log;
use crate::tracking::{TrackingError, tracking_error};

/// The default lowest accepted point quality, %: a sine at the stated frequency explains at
/// least a fifth of the output's variance-like spread. The thesis rig's points are above 90 %; a
/// frequency 1.6 times off gives under 1 %.
pub const DEFAULT_MIN_QUALITY_PERCENT: f64 = 20.0;

/// Settings of the frequency-response analysis.
#[derive(Debug, Clone)]
pub struct FreqRespOptions {
    /// Time column name.
    pub time_col: String,
    /// Input column name (the desired torque T_i in the thesis).
    pub input_col: String,
    /// Output column name (the measured torque T_o).
    pub output_col: String,
    /// Periods discarded at the start.
    pub discard_periods: f64,
    /// Seconds discarded at the start (the larger of the two discards applies).
    pub settle_s: f64,
    /// Lowest accepted quality (output sine-fit percentage) of a point: below it the analysis
    /// stops with an error naming the log (a manifest frequency that does not match the log's sine
    /// gives ~0 %); 0 accepts every point.
    pub min_quality_percent: f64,
}

impl FreqRespOptions {
    /// Checks the discards (finite and ≥ 0: fields `settle` and `discard_periods`) and the minimum
    /// quality (a percentage: `min_quality`).
    pub fn check(&self) -> Result<(), SysidError> {
        let non_negative = |v: f64| v.is_finite() && v >= 0.0;
        if !non_negative(self.settle_s) {
            let value = format!("{} s", self.settle_s);
            return Err(FieldError::out_of_range("settle", value, "finite, >= 0 s").into());
        }
        if !non_negative(self.discard_periods) {
            let e =
                FieldError::out_of_range("discard_periods", self.discard_periods, "finite, >= 0");
            return Err(e.into());
        }
        if !(0.0..=100.0).contains(&self.min_quality_percent) {
            let e = FieldError::out_of_range("min_quality", self.min_quality_percent, "0..=100 %");
            return Err(e.into());
        }
        Ok(())
    }
}

impl Default for FreqRespOptions {
    fn default() -> Self {
        Self {
            time_col: "time_s".into(),
            input_col: "input".into(),
            output_col: "output".into(),
            discard_periods: 1.0,
            settle_s: 0.5,
            min_quality_percent: DEFAULT_MIN_QUALITY_PERCENT,
        }
    }
}

/// A fitted sinusoid c + Re{X e^{jωt}}.
#[derive(Debug, Clone, Copy)]
pub struct SineFit {
    /// Complex64 amplitude (phasor) X.
    pub phasor: Complex64,
    /// Constant offset c.
    pub offset: f64,
    /// Fit percentage of the sine model to the samples.
    pub fit_percent: f64,
}

/// Least-squares sine fit at the known frequency `omega_rad_s`.
pub fn sine_fit(time_s: &[f64], y: &[f64], omega_rad_s: f64) -> Result<SineFit, SysidError> {
    let mut a = Matrix::zeros(time_s.len(), 3);
    for (i, t) in time_s.iter().enumerate() {
        a.set(i, 0, 1.0);
        a.set(i, 1, (omega_rad_s * t).cos());
        a.set(i, 2, (omega_rad_s * t).sin());
    }
    let x = least_squares(&a, y)?;
    let y_hat: Vec<f64> = time_s
        .iter()
        .map(|t| x[0] + x[1] * (omega_rad_s * t).cos() + x[2] * (omega_rad_s * t).sin())
        .collect();
    Ok(SineFit {
        phasor: Complex64::new(x[1], -x[2]),
        offset: x[0],
        fit_percent: fit_percent(y, &y_hat),
    })
}

/// The result at one test frequency: the measured response G(jω) = Y/U and how well it was
/// measured. In JSON the point's keys ([`FrequencyPoint`]: `omega_rad_s`, `magnitude_dB`,
/// `phase_deg`, `re`, `im`) sit beside the measurement's.
#[derive(Debug, Clone, serde::Serialize)]
pub struct MeasuredPoint {
    /// The response at the test frequency (phase unwrapped along frequency in a full analysis).
    #[serde(flatten)]
    pub point: FrequencyPoint,
    /// Output sine-fit percentage (quality of the point).
    pub quality_percent: f64,
    /// Input sine-fit percentage (how sinusoidal the demand was).
    pub input_fit_percent: f64,
    /// Tracking error (5.2) between input and output over the analysed window.
    pub tracking: TrackingError,
    /// Whole periods analysed.
    pub periods: usize,
    /// The log this point came from.
    pub file: PathBuf,
}

/// The properties of a test's data without which a sine fit has no answer: four samples, the
/// frequency below the samples' Nyquist frequency (above it a fit aliases), and input and output
/// that vary; `Err(message)` names the first one missing.
fn check_test_data(
    omega_rad_s: f64,
    time_s: &[f64],
    input: &[f64],
    output: &[f64],
    options: &FreqRespOptions,
) -> Result<(), String> {
    let n = time_s.len();
    if n < 4 {
        return Err(format!("{n} samples are too few for a sine fit"));
    }
    let nyquist = std::f64::consts::PI * (n - 1) as f64 / (time_s[n - 1] - time_s[0]);
    if nyquist.is_nan() || omega_rad_s >= nyquist {
        return Err(format!(
            "test frequency {omega_rad_s} rad/s is not below the log's Nyquist frequency \
             {nyquist:.4} rad/s (π / mean sample step): check the manifest's frequency_rad_s"
        ));
    }
    for (column, values) in [(&options.input_col, input), (&options.output_col, output)] {
        if let Some(v) = constant_value(values) {
            return Err(format!(
                "column `{column}` is constant ({v}): it has no sine at {omega_rad_s} rad/s to fit"
            ));
        }
    }
    Ok(())
}

/// Analyses one sinusoidal test from its samples.
pub fn analyse_test(
    source: &Path,
    omega_rad_s: f64,
    time_s: &[f64],
    input: &[f64],
    output: &[f64],
    options: &FreqRespOptions,
) -> Result<MeasuredPoint, SysidError> {
    options.check()?;
    let file_err =
        |message: String| SysidError::File { file: source.to_path_buf(), line: None, message };
    if !(omega_rad_s > 0.0 && omega_rad_s.is_finite()) {
        return Err(file_err(format!("test frequency {omega_rad_s} rad/s must be positive")));
    }
    let n = time_s.len();
    check_test_data(omega_rad_s, time_s, input, output, options).map_err(file_err)?;
    let period = 2.0 * std::f64::consts::PI / omega_rad_s;
    let (t0, t_end) = (time_s[0], time_s[n - 1]);
    let start = t0 + (options.discard_periods * period).max(options.settle_s);
    let whole = ((t_end - start) / period).floor();
    if whole < 1.0 {
        return Err(file_err(format!(
            "the log lasts {:.4} s; at {omega_rad_s} rad/s at least {:.4} s are needed (start-up discard {:.4} s + one period {:.4} s)",
            t_end - t0,
            start - t0 + period,
            start - t0,
            period
        )));
    }
    let window_start = t_end - whole * period;
    let first = time_s.partition_point(|t| *t < window_start - 1e-12 * period);
    let (t, u, y) = (&time_s[first..], &input[first..], &output[first..]);
    if t.len() < 4 {
        return Err(file_err(format!(
            "only {} samples in the analysed window at {omega_rad_s} rad/s",
            t.len()
        )));
    }
    let fu = sine_fit(t, u, omega_rad_s)?;
    let fy = sine_fit(t, y, omega_rad_s)?;
    if fu.phasor.norm().is_nan() || fu.phasor.norm() <= 0.0 {
        return Err(file_err(format!("the input has no component at {omega_rad_s} rad/s")));
    }
    if fy.fit_percent.is_nan() || fy.fit_percent < options.min_quality_percent {
        return Err(file_err(format!(
            "the output sine fit at {omega_rad_s} rad/s explains only {:.2} % of the output (minimum \
             {} %): the manifest frequency may not match the log, or the output is noise; check \
             the frequency, or lower the minimum quality (--min-quality 0) to proceed",
            fy.fit_percent, options.min_quality_percent
        )));
    }
    let g = div(fy.phasor, fu.phasor);
    if !(g.re.is_finite() && g.im.is_finite()) || g.norm() <= 0.0 {
        return Err(file_err(format!(
            "the output has no component at {omega_rad_s} rad/s: gain and phase are undefined"
        )));
    }
    let measured = MeasuredPoint {
        point: FrequencyPoint::new(omega_rad_s, g),
        quality_percent: fy.fit_percent,
        input_fit_percent: fu.fit_percent,
        tracking: tracking_error(u, y)?,
        periods: whole as usize,
        file: source.to_path_buf(),
    };
    check_finite(&measured, u, y).map_err(file_err)?;
    Ok(measured)
}

/// Every number a point reports must be finite: samples near the largest double (1e308) overflow
/// the sums of squares of the fits and the tracking error (issue 33: `freqresp` printed "inf"),
/// so such a log is refused with the size of its largest sample.
fn check_finite(point: &MeasuredPoint, input: &[f64], output: &[f64]) -> Result<(), String> {
    let g = point.point.response;
    let numbers = [
        g.re,
        g.im,
        point.point.magnitude_db(),
        point.quality_percent,
        point.input_fit_percent,
        point.tracking.rmse_nm,
    ];
    if numbers.iter().all(|v| v.is_finite()) {
        return Ok(());
    }
    let largest = input.iter().chain(output).fold(0.0_f64, |m, v| m.max(v.abs()));
    Err(format!(
        "the samples are too large to analyse at {} rad/s (largest |sample| {largest:e}: the fit's \
         sums of squares overflow double precision); check the log's units",
        point.point.omega_rad_s
    ))
}

/// The value of a column whose samples are all equal (`None` when they vary).
fn constant_value(values: &[f64]) -> Option<f64> {
    let first = *values.first()?;
    values.iter().all(|v| v.to_bits() == first.to_bits()).then_some(first)
}

/// One manifest row: a test frequency and its log file (resolved against the manifest's folder).
#[derive(Debug, Clone)]
pub struct ManifestEntry {
    /// Test frequency, rad/s.
    pub omega_rad_s: f64,
    /// Log file.
    pub file: PathBuf,
}

/// Reads a manifest CSV with columns `frequency_rad_s,file`.
pub fn read_manifest(path: &Path) -> Result<Vec<ManifestEntry>, SysidError> {
    let text = mrbrake_error::read::text(path, mrbrake_error::read::LOG)
        .map_err(|source| SysidError::Io { path: path.to_path_buf(), source })?;
    let base = path.parent().unwrap_or(Path::new("."));
    let file_err = crate::log::file_error(path);
    let mut rdr = crate::log::csv_reader(text.as_bytes(), false);
    let header = rdr
        .headers()
        .map_err(|e| crate::log::csv_error(path, Some(1), "cannot read the header row", e))?
        .clone();
    let (Some(fi), Some(pi)) = (
        header.iter().position(|h| h == "frequency_rad_s"),
        header.iter().position(|h| h == "file"),
    ) else {
        return Err(file_err(
            Some(1),
            "the header must name the columns frequency_rad_s and file".into(),
        ));
    };
    let mut entries = Vec::new();
    for rec in rdr.records() {
        let rec = rec.map_err(|e| crate::log::csv_error(path, None, "malformed CSV", e))?;
        let line = rec.position().map(|p| p.line());
        let w: f64 = rec
            .get(fi)
            .and_then(|c| c.parse().ok())
            .filter(|w: &f64| w.is_finite() && *w > 0.0)
            .ok_or_else(|| file_err(line, "frequency_rad_s must be a positive number".into()))?;
        let f = rec
            .get(pi)
            .filter(|f| !f.is_empty())
            .ok_or_else(|| file_err(line, "file is empty".into()))?;
        if let Some(twin) =
            entries.iter().position(|e: &ManifestEntry| (e.omega_rad_s - w).abs() <= 1e-12 * w)
        {
            return Err(file_err(
                line,
                format!(
                    "frequency_rad_s {w} repeats test {} of the manifest: each frequency appears \
                     once (the FRD cannot hold two points at one frequency)",
                    twin + 1
                ),
            ));
        }
        entries.push(ManifestEntry { omega_rad_s: w, file: base.join(f) });
    }
    if entries.is_empty() {
        return Err(file_err(None, "the manifest lists no test".into()));
    }
    Ok(entries)
}

/// Analyses every test of a manifest; points sorted by frequency, phase unwrapped along frequency.
pub fn frequency_response(
    manifest: &Path,
    options: &FreqRespOptions,
) -> Result<Vec<MeasuredPoint>, SysidError> {
    options.check()?;
    let entries = read_manifest(manifest)?;
    let mut points = Vec::with_capacity(entries.len());
    for e in &entries {
        let log =
            read_log(&e.file, &options.time_col, &[&options.input_col, &options.output_col], 4)?;
        points.push(analyse_test(
            &e.file,
            e.omega_rad_s,
            &log.time_s,
            &log.channels[0],
            &log.channels[1],
            options,
        )?);
    }
    Ok(finish(points))
}

/// Sorts points by frequency and unwraps their phase.
pub fn finish(mut points: Vec<MeasuredPoint>) -> Vec<MeasuredPoint> {
    points.sort_by(|a, b| a.point.omega_rad_s.total_cmp(&b.point.omega_rad_s));
    unwrap_phase(points.iter_mut().map(|p| &mut p.point));
    points
}

/// The measured responses as frequency-response data (the points themselves, without their
/// quality), e.g. for [`crate::tfest`].
pub fn frd(points: &[MeasuredPoint]) -> Frd {
    Frd { points: points.iter().map(|p| p.point).collect(), weight: None }
}

/// The points as an FRD CSV text ([`crate::frd::write_csv`]), with each point's
/// `quality_percent,rmse_Nm,rmse_percent` after the response.
pub fn frd_csv(points: &[MeasuredPoint]) -> String {
    let quality: Vec<f64> = points.iter().map(|p| p.quality_percent).collect();
    let rmse: Vec<f64> = points.iter().map(|p| p.tracking.rmse_nm).collect();
    let percent: Vec<f64> = points.iter().map(|p| p.tracking.rmse_percent_of_range).collect();
    let extra: [Column<'_>; 3] =
        [("quality_percent", &quality), ("rmse_Nm", &rmse), ("rmse_percent", &percent)];
    write_csv(points.iter().map(|p| &p.point), &extra)
}

#[cfg(test)]
mod tests {
    use super::*;
    use mrbrake_error::Kind as _;

    #[test]
    fn sine_fit_recovers_gain_and_phase_of_a_delayed_sine() {
        let w = 7.0;
        let t: Vec<f64> = (0..5000).map(|i| i as f64 * 1e-3).collect();
        let u: Vec<f64> = t.iter().map(|t| 2.0 + (w * t).sin()).collect();
        // Output: gain 0.5, phase −60°, plus a decaying transient that the discard removes.
        let y: Vec<f64> = t
            .iter()
            .map(|t| 1.0 + 0.5 * (w * t - 60f64.to_radians()).sin() + 0.3 * (-t / 0.05).exp())
            .collect();
        let p =
            analyse_test(Path::new("x.csv"), w, &t, &u, &y, &FreqRespOptions::default()).unwrap();
        let (db, deg) = (p.point.magnitude_db(), p.point.phase_deg());
        assert!((db - 20.0 * 0.5f64.log10()).abs() < 1e-6, "{db}");
        assert!((deg + 60.0).abs() < 1e-4, "{deg}");
        assert!(p.quality_percent > 99.99);
    }

    /// A measured point's JSON keeps the keys of `freqresp --json` (the response's beside the
    /// measurement's), and its FRD file the columns `tfest` and a spreadsheet read.
    #[test]
    fn measured_points_keep_their_keys_and_columns() {
        let (t, u, y) = sine_test(7.0);
        let p =
            analyse_test(Path::new("x.csv"), 7.0, &t, &u, &y, &FreqRespOptions::default()).unwrap();
        let v = serde_json::to_value(&p).unwrap();
        let keys: Vec<&String> = v.as_object().unwrap().keys().collect();
        for key in ["omega_rad_s", "magnitude_dB", "phase_deg", "re", "im", "quality_percent"] {
            assert!(keys.iter().any(|k| *k == key), "{key} missing in {keys:?}");
        }
        let csv = frd_csv(std::slice::from_ref(&p));
        let header =
            "omega_rad_s,magnitude_dB,phase_deg,re,im,quality_percent,rmse_Nm,rmse_percent";
        assert!(csv.starts_with(header), "{csv}");
        let back = crate::frd::read_frd_from(Path::new("f.csv"), &csv, None).unwrap();
        assert_eq!(back, frd(&[p]));
    }

    #[test]
    fn too_short_log_names_the_file() {
        let t: Vec<f64> = (0..100).map(|i| i as f64 * 1e-3).collect();
        let err =
            analyse_test(Path::new("short.csv"), 1.0, &t, &t, &t, &FreqRespOptions::default())
                .unwrap_err();
        assert!(err.to_string().contains("short.csv") && err.is_input_error());
    }

    fn sine_test(w: f64) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
        let t: Vec<f64> = (0..5000).map(|i| i as f64 * 1e-3).collect();
        let u: Vec<f64> = t.iter().map(|t| 2.0 + (w * t).sin()).collect();
        let y: Vec<f64> = t.iter().map(|t| 1.0 + 0.5 * (w * t - 0.5).sin()).collect();
        (t, u, y)
    }

    fn refused(w: f64, t: &[f64], u: &[f64], y: &[f64]) -> String {
        let e = analyse_test(Path::new("sine.csv"), w, t, u, y, &FreqRespOptions::default())
            .unwrap_err();
        assert!(e.is_input_error(), "{e}");
        let text = e.to_string();
        assert!(text.contains("sine.csv"), "{text}");
        text
    }

    /// Issue 18, class 4: inputs that used to give −inf dB, NaN quality or a 0.1 % point without a
    /// word are errors naming the log and the property.
    #[test]
    fn degenerate_logs_are_refused_not_answered() {
        let (t, u, y) = sine_test(7.0);
        let zeros = vec![0.0; t.len()];
        let e = refused(7.0, &t, &u, &zeros);
        assert!(e.contains("`output` is constant"), "{e}");
        let e = refused(7.0, &t, &zeros, &zeros);
        assert!(e.contains("`input` is constant"), "{e}");
        // The stated frequency does not match the log's sine (50 rad/s for a 31.6 rad/s test).
        let (t, u, y2) = sine_test(31.6);
        let e = refused(50.0, &t, &u, &y2);
        assert!(e.contains("--min-quality"), "{e}");
        // With the threshold off the point is computed (the explicit way to proceed).
        let lenient = FreqRespOptions { min_quality_percent: 0.0, ..FreqRespOptions::default() };
        assert!(analyse_test(Path::new("sine.csv"), 50.0, &t, &u, &y2, &lenient).is_ok());
        let e = refused(1e300, &t, &u, &y);
        assert!(e.contains("Nyquist"), "{e}");
    }

    #[test]
    fn duplicated_manifest_rows_are_refused() {
        let dir = tempfile::tempdir().unwrap();
        let manifest = dir.path().join("manifest.csv");
        std::fs::write(&manifest, "frequency_rad_s,file\n1.0,a.csv\n2.0,b.csv\n1.0,a.csv\n")
            .unwrap();
        let e = read_manifest(&manifest).unwrap_err();
        assert!(e.is_input_error());
        let text = e.to_string();
        assert!(text.contains("manifest.csv") && text.contains("repeats test 1"), "{text}");
    }
}
