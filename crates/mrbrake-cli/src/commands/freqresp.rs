//! `mrbrake freqresp MANIFEST.csv`: gain (5.3)/(5.4), phase and tracking RMSE (5.2) per test frequency
//! from sinusoidal test logs, written as frequency-response data (thesis §5.3.2).

use std::path::PathBuf;

use clap::Args;
use mrbrake::report::identification::{
    frequency_response_json, frequency_response_text, save_frequency_response_plot,
};
use mrbrake::sysid::freqresp::{FreqRespOptions, frd_csv, frequency_response};
use mrbrake::units::{Dimension, parse};

use crate::error::{CommandResult, Context as _};
use crate::output::{print_json, print_text};

/// Arguments of `mrbrake freqresp`.
#[derive(Debug, Args)]
pub struct FreqRespArgs {
    /// Manifest CSV with columns frequency_rad_s,file (files relative to the manifest).
    manifest: PathBuf,
    /// Output FRD file (default: frd.csv beside the manifest).
    #[arg(short, long, value_name = "FRD.csv")]
    output: Option<PathBuf>,
    /// Name of the time column of the test logs (seconds).
    #[arg(long, default_value = "time_s")]
    time_col: String,
    /// Name of the input column (the desired torque).
    #[arg(long, default_value = "input")]
    input_col: String,
    /// Name of the output column (the measured torque).
    #[arg(long, default_value = "output")]
    output_col: String,
    /// Periods discarded at the start of each test (start-up transient).
    #[arg(long, default_value_t = 1.0, allow_hyphen_values = true)]
    discard_periods: f64,
    /// Time discarded at the start of each test (the larger discard applies), e.g. 0.5s.
    #[arg(long, default_value = "0.5s", allow_hyphen_values = true)]
    settle: String,
    /// Lowest accepted output sine-fit quality of a point, %: a point below it stops the analysis
    /// with an error naming its log (a frequency that does not match the log); 0 accepts all.
    #[arg(
        long,
        value_name = "PERCENT",
        default_value_t = mrbrake::sysid::freqresp::DEFAULT_MIN_QUALITY_PERCENT,
        allow_hyphen_values = true
    )]
    min_quality: f64,
    /// Draw the measured Bode diagram (.svg or .png).
    #[arg(long, value_name = "FILE.svg")]
    plot: Option<PathBuf>,
    /// Print a JSON object instead of text.
    #[arg(long)]
    json: bool,
}

/// Runs `mrbrake freqresp`.
pub fn run(args: FreqRespArgs) -> CommandResult {
    crate::output::check_plot_path("--plot", args.plot.as_deref())?;
    let settle_s = parse(&args.settle, Dimension::Time).context("--settle")?;
    let options = FreqRespOptions {
        time_col: args.time_col.clone(),
        input_col: args.input_col.clone(),
        output_col: args.output_col.clone(),
        discard_periods: args.discard_periods,
        settle_s,
        min_quality_percent: args.min_quality,
    };
    let flags = [
        ("settle", "--settle"),
        ("discard_periods", "--discard-periods"),
        ("min_quality", "--min-quality"),
    ];
    options.check().map_err(|e| e.with_field_names(&flags))?;
    let points = frequency_response(&args.manifest, &options)?;
    let out = args.output.clone().unwrap_or_else(|| args.manifest.with_file_name("frd.csv"));
    mrbrake::report::write_atomic(&out, frd_csv(&points).as_bytes())?;
    if let Some(path) = &args.plot {
        save_frequency_response_plot(path, &points)?;
    }
    if args.json {
        return print_json(&frequency_response_json(&points, &out)?);
    }
    print_text(&frequency_response_text(&points, &out))
}
