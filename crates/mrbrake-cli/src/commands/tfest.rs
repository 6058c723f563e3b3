//! `mrbrake tfest FRD.csv --poles N --zeros M`: a continuous-time transfer function from
//! frequency-response data (Levy / Sanathanan–Koerner, then Levenberg–Marquardt).

use std::path::PathBuf;

use clap::{Args, ValueEnum};
use mrbrake::report::identification::{save_tfest_plot, tfest_text};
use mrbrake::sysid::frd::read_frd;
use mrbrake::sysid::tfest::{TfestOptions, Weighting, tfest};
use mrbrake::units::{Dimension, parse};

use crate::error::{CommandResult, Context as _};
use crate::output::{print_json, print_text};

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
    #[arg(long, default_value = "0s", allow_hyphen_values = true)]
    delay: String,
    /// Draw measured points and the fitted model (.svg or .png).
    #[arg(long, value_name = "FILE.svg")]
    plot: Option<PathBuf>,
    /// Also write the fitted model (the JSON result) to this file.
    #[arg(long, value_name = "FILE.json", alias = "save")]
    save_model: Option<PathBuf>,
    /// Print a JSON object instead of text.
    #[arg(long)]
    json: bool,
}

/// The flags of the library's [`TfestOptions`] fields (named in its field errors).
pub const FLAGS: &[(&str, &str)] =
    &[("poles", "--poles"), ("zeros", "--zeros"), ("delay", "--delay")];

/// Runs `mrbrake tfest`.
pub fn run(args: TfestArgs) -> CommandResult {
    crate::output::check_plot_path("--plot", args.plot.as_deref())?;
    let delay_s = parse(&args.delay, Dimension::Time).context("--delay")?;
    let mut options = TfestOptions::new(args.poles, args.zeros);
    options.delay_s = delay_s;
    options.weighting = match args.weighting {
        WeightingArg::Uniform => Weighting::Uniform,
        WeightingArg::Relative => Weighting::InverseMagnitude,
    };
    options.check().map_err(|e| e.with_field_names(FLAGS))?;
    let frd = read_frd(&args.frd, args.weight_col.as_deref())?;
    let fit = tfest(&frd, &options)
        .map_err(|e| e.with_field_names(FLAGS))
        .with_context(|| args.frd.display().to_string())?;
    let summary = fit.summary()?;
    if let Some(path) = &args.save_model {
        mrbrake::report::write_atomic(path, crate::output::json_text(&summary)?.as_bytes())?;
    }
    if let Some(path) = &args.plot {
        save_tfest_plot(path, &frd, &fit, args.poles, args.zeros)?;
    }
    if args.json {
        return print_json(&summary);
    }
    print_text(&tfest_text(&summary))
}
