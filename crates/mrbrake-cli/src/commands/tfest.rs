//! `mrbrake tfest FRD.csv --poles N --zeros M`: a continuous-time transfer function from
//! frequency-response data (Levy / Sanathanan–Koerner, then Levenberg–Marquardt).

use std::path::PathBuf;

use clap::{Args, ValueEnum};
use mrbrake_report::bode::{BodeCurve, save_bode};
use mrbrake_sysid::frd::read_frd;
use mrbrake_sysid::tfest::{TfestOptions, Weighting, logspace, tfest};
use mrbrake_units::{Dimension, parse};

use crate::exit::InputError;
use crate::output::print_json;

/// Weighting of the complex fitting error.
#[derive(Debug, Clone, Copy, ValueEnum)]
pub enum WeightingArg {
    /// Absolute complex error (MATLAB's default); right when the noise on G is of equal size everywhere.
    Uniform,
    /// Relative error, weight 1/|G|; right when the noise is a fixed percentage of G.
    Relative,
}

/// Arguments of `mrbrake tfest`.
#[derive(Debug, Args)]
pub struct TfestArgs {
    /// FRD CSV: omega_rad_s with re, im or magnitude_dB, phase_deg.
    frd: PathBuf,
    /// Number of poles (denominator degree).
    #[arg(long)]
    poles: usize,
    /// Number of zeros (numerator degree, at most --poles).
    #[arg(long, default_value_t = 0)]
    zeros: usize,
    /// Weighting of the complex error.
    #[arg(long, value_enum, default_value_t = WeightingArg::Uniform)]
    weighting: WeightingArg,
    /// Extra per-point weights from this FRD column (multiplied with --weighting).
    #[arg(long, value_name = "COLUMN")]
    weight_col: Option<String>,
    /// Known input delay removed before fitting (e.g. 0.5ms for a 1 kHz zero-order hold).
    #[arg(long, default_value = "0s")]
    delay: String,
    /// Draw measured points and the fitted model (SVG, or PNG for a .png name).
    #[arg(long, value_name = "FILE.svg")]
    plot: Option<PathBuf>,
    /// Also write the JSON result to this file.
    #[arg(long, value_name = "FILE.json")]
    save: Option<PathBuf>,
    /// Print a JSON object instead of text.
    #[arg(long)]
    json: bool,
}

/// Runs `mrbrake tfest`.
pub fn run(args: TfestArgs) -> anyhow::Result<()> {
    if args.poles == 0 || args.zeros > args.poles {
        return Err(InputError(format!(
            "--poles must be ≥ 1 and --zeros ≤ --poles (got {} and {})",
            args.poles, args.zeros
        ))
        .into());
    }
    let delay_s = parse(&args.delay, Dimension::Time)?;
    let frd = read_frd(&args.frd, args.weight_col.as_deref())?;
    let mut options = TfestOptions::new(args.poles, args.zeros);
    options.delay_s = delay_s;
    options.weighting = match args.weighting {
        WeightingArg::Uniform => Weighting::Uniform,
        WeightingArg::Relative => Weighting::InverseMagnitude,
    };
    let fit = tfest(&frd, &options)?;
    let summary = fit.summary()?;
    if let Some(path) = &args.save {
        mrbrake_report::write_atomic(path, serde_json::to_string_pretty(&summary)?.as_bytes())?;
    }
    if let Some(path) = &args.plot {
        let mag = frd.magnitude_db();
        let ph = frd.phase_deg_unwrapped();
        let measured: Vec<(f64, f64, f64)> =
            frd.omega_rad_s.iter().enumerate().map(|(k, w)| (*w, mag[k], ph[k])).collect();
        let w_lo = frd.omega_rad_s[0];
        let w_hi = frd.omega_rad_s[frd.omega_rad_s.len() - 1];
        let omega = logspace(w_lo, w_hi, 400);
        let raw_phase: Vec<f64> =
            omega.iter().map(|w| fit.response(*w).arg().to_degrees()).collect();
        let mut phase = mrbrake_sysid::frd::unwrap_deg(&raw_phase);
        // Align the model's phase branch with the data at the lowest frequency.
        let shift = 360.0 * ((ph[0] - phase[0]) / 360.0).round();
        phase.iter_mut().for_each(|p| *p += shift);
        let model: Vec<(f64, f64, f64)> = omega
            .iter()
            .zip(&phase)
            .map(|(w, p)| (*w, 20.0 * fit.response(*w).abs().log10(), *p))
            .collect();
        save_bode(
            path,
            &format!(
                "Estimated transfer function ({} poles, {} zeros, fit {:.2} %)",
                args.poles, args.zeros, fit.fit_percent
            ),
            &[
                BodeCurve { label: "measured".into(), points: measured, markers: true },
                BodeCurve { label: "model".into(), points: model, markers: false },
            ],
        )?;
    }
    if args.json {
        return print_json(&summary);
    }
    crate::outln!(
        "G(s) = N(s)/D(s), highest power first{}",
        if delay_s > 0.0 { format!(", times e^(-{delay_s} s)") } else { String::new() }
    );
    crate::outln!("  numerator:   {:?}", summary.numerator);
    crate::outln!("  denominator: {:?}", summary.denominator);
    for p in &summary.poles {
        crate::outln!("  pole: {:.6} {:+.6}j rad/s", p[0], p[1]);
    }
    crate::outln!("  corner frequencies: {:?} rad/s", summary.corner_frequencies_rad_s);
    match summary.bandwidth_rad_s {
        Some(b) => crate::outln!("  bandwidth (−3 dB): {b:.4} rad/s"),
        None => crate::outln!("  bandwidth (−3 dB): undefined"),
    }
    crate::outln!("  DC gain: {:.6}", summary.dc_gain);
    crate::outln!(
        "  fit: {:.3} %, MSE {:.4e}, stable: {}",
        summary.fit_percent,
        summary.mse,
        summary.stable
    );
    Ok(())
}
