//! `mrbrake calibrate`: fits chosen spec fields so that the design's predicted static
//! torque–current curve matches a rig log's measured loop, with standard errors, correlations
//! and the parameter groups the data cannot separate (`mrbrake_explore::calibrate`); writes the
//! calibrated spec and, on request, its brake model.

use std::path::PathBuf;

use clap::Args;
use mrbrake::explore::calibrate::{self, CalibrationRequest, DEFAULT_POINTS};
use mrbrake::explore::variable::parse_sets;
use mrbrake::uq::calibration::CalibrationOptions;

use super::field_flags;
use super::sweep::{AnalysisSettingsArgs, base_spec, recorded_metrics};
use crate::error::CommandResult;
use crate::output::{print_json, print_text};

/// Arguments of `mrbrake calibrate`.
#[derive(Debug, Args)]
pub struct CalibrateArgs {
    /// Brake specification (TOML). Omitted: the embedded thesis bidirectional brake.
    spec: Option<PathBuf>,
    /// The rig log: a repeated-ramp characterisation CSV (time_s, current_A, torque_Nm), as
    /// `mrbrake rig characterize` writes it. Its currents must reach the spec's maximum current.
    #[arg(long, value_name = "LOG.csv")]
    log: PathBuf,
    /// Frequency-response data of the same brake (FRD CSV from `mrbrake freqresp`): the
    /// predicted small-signal response (normalised, about `[response]`'s bias: half the maximum
    /// current) is fitted to it as well, each block weighing alike.
    #[arg(long, value_name = "FRD.csv")]
    frd: Option<PathBuf>,
    /// A spec field to fit: PATH (bounds ½ to 1½ times its value) or PATH=LOW..HIGH with units
    /// (drum.gap=0.5mm..0.8mm, fluid.yield_stress_scale=0.5..1.2, drag.seal_torque=0..0.2Nm).
    /// Repeatable.
    #[arg(long = "parameter", value_name = "PATH[=LOW..HIGH]", required = true)]
    parameter: Vec<String>,
    /// A fixed change before fitting, PATH=VALUE (e.g. drag.seals_per_rotor=2). Repeatable.
    #[arg(long = "set", value_name = "PATH=VALUE")]
    set: Vec<String>,
    /// Currents compared, evenly from 0 to the maximum current.
    #[arg(long, default_value_t = DEFAULT_POINTS)]
    points: usize,
    /// Most residual evaluations (each one an FEA of the torque–current curve).
    #[arg(long, default_value_t = 120)]
    max_evaluations: usize,
    /// Analyses run at the same time (0: one per core).
    #[arg(long, default_value_t = 0)]
    jobs: usize,
    #[command(flatten)]
    analysis: AnalysisSettingsArgs,
    /// Also predict a dynamics or heat metric (e.g. bandwidth_rad_s) of the start and the
    /// calibrated design, to compare with a measurement the fit did not use. Repeatable.
    #[arg(long = "record", value_name = "METRIC")]
    record: Vec<String>,
    /// Write the calibrated spec here (the spec's text with the estimates and their provenance).
    #[arg(short = 'o', long = "output", value_name = "FILE.toml")]
    output: Option<PathBuf>,
    /// Write the calibrated design's brake model (JSON) here, for the rig and the haptic simulation.
    #[arg(long, value_name = "FILE.json")]
    save_model: Option<PathBuf>,
    /// Plot the measured loop and the prediction before and after (SVG or PNG by the extension).
    #[arg(long, value_name = "FILE.svg")]
    plot: Option<PathBuf>,
    /// Print a JSON object instead of text.
    #[arg(long)]
    json: bool,
}

/// Runs `mrbrake calibrate`.
pub fn run(a: CalibrateArgs) -> CommandResult {
    let (spec_toml, spec_origin) = base_spec(a.spec.as_ref())?;
    let request = CalibrationRequest {
        spec_toml,
        spec_origin: spec_origin.clone(),
        overrides: parse_sets(&a.set).map_err(field_flags::study)?,
        parameters: a.parameter.clone(),
        log: a.log.clone(),
        frd: a.frd.clone(),
        points: a.points,
        settings: mrbrake::explore::EvaluationSettings {
            study: recorded_metrics(&a.record)?,
            ..a.analysis.settings()?
        },
        jobs: a.jobs,
        options: CalibrationOptions {
            max_evaluations: a.max_evaluations,
            ..CalibrationOptions::default()
        },
    };
    let result = calibrate::run(&request).map_err(field_flags::study)?;
    if let Some(path) = &a.plot {
        mrbrake::report::calibration::figure(&result).save(path)?;
    }
    if let Some(path) = &a.output {
        mrbrake::report::write_atomic(path, result.calibrated_spec.as_bytes())?;
    }
    if let Some(path) = &a.save_model {
        let how = format!("mrbrake calibrate {spec_origin} --log {}", a.log.display());
        let identity =
            mrbrake::explore::design::analysis_identity(&result.spec, &result.analysis_options)?;
        let model = mrbrake::device::brake_model::from_analysis(
            &result.analysis,
            &result.analysis_options,
            Some(identity),
            &how,
        )?;
        mrbrake::report::write_atomic(path, model.to_json().as_bytes())?;
    }
    if a.json {
        return print_json(&mrbrake::report::calibration::json(&result));
    }
    print_text(&mrbrake::report::calibration::text(&result, &result.spec.name))
}
