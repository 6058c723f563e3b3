//! `mrbrake characterize LOG.csv`: hysteresis branches, inverse model and loop figures from a
//! repeated-ramp test-rig log (thesis §5.3.1).

use std::path::PathBuf;

use clap::Args;
use mrbrake::report::identification::CharacterizationReport;
use mrbrake::report::operator::{operator_fit_json, operator_fit_text};
use mrbrake::sysid::characterize::{CharacterizeOptions, characterize};
use mrbrake::sysid::log::read_log;
use mrbrake::sysid::operator_fit::{OperatorOptions, fit_operator_model};
use mrbrake::sysid::outliers::check_outliers;

use crate::error::{CommandResult, Context as _};
use crate::output::{print_json, print_text};

/// Arguments of `mrbrake characterize`.
#[derive(Debug, Args)]
pub struct CharacterizeArgs {
    /// Log file (CSV with a header row) of the repeated current ramps.
    log: PathBuf,
    /// Polynomial order of each branch (the thesis uses 5).
    #[arg(long, default_value_t = mrbrake::sysid::characterize::DEFAULT_ORDER)]
    order: usize,
    /// Number of current bins used to average the repetitions.
    #[arg(long, default_value_t = mrbrake::sysid::characterize::DEFAULT_BINS)]
    bins: usize,
    /// Name of the time column (seconds).
    #[arg(long, default_value = "time_s")]
    time_col: String,
    /// Name of the current column (amperes).
    #[arg(long, default_value = "current_A")]
    current_col: String,
    /// Name of the torque column (newton-metres).
    #[arg(long, default_value = "torque_Nm")]
    torque_col: String,
    /// Identify the operator hysteresis model (modified Prandtl–Ishlinskii, minor loops, exact inverse)
    /// with this many play operators instead of the polynomial branches; the log must contain minor
    /// loops (`mrbrake rig minor-loops`). At most 32 (the controller's capacity).
    #[arg(long, value_name = "N")]
    operators: Option<usize>,
    /// Segments of the operator model's output map (with --operators; at most 32).
    #[arg(long, default_value_t = 12, value_name = "M")]
    segments: usize,
    /// Write the model as JSON here: the branches and current range (the controller's inverse-model
    /// file) or, with --operators, the operator-model file (schema mrbrake.operator-model).
    #[arg(long, value_name = "FILE.json", alias = "save")]
    save_model: Option<PathBuf>,
    /// Also put the identified branches into this brake model file (from `mrbrake analyze
    /// --save-model`) as the hysteresis of `--unit`; the file is rewritten atomically.
    #[arg(long, value_name = "FILE.json")]
    brake_model: Option<PathBuf>,
    /// The unit of `--brake-model` the log is of: 1 or 2.
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..=2), requires = "brake_model")]
    unit: u32,
    /// Fit samples the outlier screen refuses (mrbrake::sysid::outliers: a sample more than ten
    /// times the channel's 1st–99th percentile spread beyond them).
    #[arg(long)]
    keep_outliers: bool,
    /// Draw the hysteresis loop (.svg or .png).
    #[arg(long, value_name = "FILE.svg")]
    plot: Option<PathBuf>,
    /// Print a JSON object instead of text.
    #[arg(long)]
    json: bool,
}

/// The flags of the library's field names (its field errors name `order`, `plays`, …).
const FLAGS: &[(&str, &str)] = &[
    ("order", "--order"),
    ("bins", "--bins"),
    ("plays", "--operators"),
    ("segments", "--segments"),
];

/// Runs `mrbrake characterize`.
pub fn run(args: CharacterizeArgs) -> CommandResult {
    crate::output::check_plot_path("--plot", args.plot.as_deref())?;
    if let Some(plays) = args.operators {
        return run_operators(&args, plays);
    }
    let options = CharacterizeOptions { order: args.order, bins: args.bins };
    options.check().map_err(|e| e.with_field_names(FLAGS))?;
    let log = read_log(
        &args.log,
        &args.time_col,
        &[&args.current_col, &args.torque_col],
        2 * (args.order + 1),
    )?;
    let (current, torque) = (&log.channels[0], &log.channels[1]);
    if !args.keep_outliers {
        check_outliers(&args.log, &args.current_col, &log.time_s, current)?;
        check_outliers(&args.log, &args.torque_col, &log.time_s, torque)?;
    }
    let c = characterize(current, torque, options)
        .map_err(|e| e.with_field_names(FLAGS))
        .with_context(|| args.log.display().to_string())?;
    let report = CharacterizationReport {
        characterization: &c,
        log: &args.log,
        samples: log.len(),
        sample_rate_hz: log.mean_sample_rate_hz(),
    };
    if let Some(path) = &args.save_model {
        // The characterisation's JSON is the inverse-model file (mrbrake::sysid::model_file).
        let text = crate::output::json_text(&c)?;
        mrbrake::report::write_atomic(path, text.as_bytes())?;
    }
    if let Some(path) = &args.brake_model {
        let mut model = mrbrake::sim::brake_model::BrakeModel::read(path)?;
        let source = format!(
            "mrbrake characterize {} (order {}, {} repetitions)",
            mrbrake::report::wording::shell_quote(&args.log),
            args.order,
            c.repetitions
        );
        model.set_identified_branches(args.unit, &c.model()?, &source)?;
        mrbrake::report::write_atomic(path, model.to_json().as_bytes())?;
    }
    if let Some(path) = &args.plot {
        report.save_plot(path, current, torque)?;
    }
    if args.json {
        return print_json(&report.json()?);
    }
    print_text(&report.text())
}

/// `mrbrake characterize --operators N`: the operator model from a log with minor loops.
fn run_operators(args: &CharacterizeArgs, plays: usize) -> CommandResult {
    let log = read_log(&args.log, &args.time_col, &[&args.current_col, &args.torque_col], 10)?;
    let (current, torque) = (&log.channels[0], &log.channels[1]);
    let options = OperatorOptions { plays, segments: args.segments };
    let fit =
        fit_operator_model(current, torque, options).map_err(|e| e.with_field_names(FLAGS))?;
    if let Some(path) = &args.save_model {
        let text = crate::output::json_text(&fit)?;
        mrbrake::report::write_atomic(path, text.as_bytes())?;
    }
    if args.json {
        return print_json(&operator_fit_json(&fit, &args.log)?);
    }
    print_text(&operator_fit_text(&fit, &args.log, log.len()))
}
