//! `mrbrake rig …`: the virtual test rig writes the logs of the thesis's experiments.

use std::path::PathBuf;

use clap::{Args, Subcommand};
use mrbrake::report::operator::tracking_text;
use mrbrake::report::rig::{rig_json, rig_text, write_rig_folder};
use mrbrake::sim::brake_model::BrakeModel;
use mrbrake::sim::brake_model::apply::apply_to_rig;
use mrbrake::sim::rig::{self, RigConfig};
use mrbrake::sysid::model_file::read_inverse_model;
use mrbrake::sysid::operator_fit::read_torque_inverse;

use crate::error::CommandResult;
use crate::output::{print_json, print_text};

/// `mrbrake rig` subcommands.
#[derive(Debug, Subcommand)]
pub enum RigCommand {
    /// Characterisation protocol (§5.3.1): current ramps 0 → I_max → 0, pause, repeated; one log.
    Characterize(RigArgs),
    /// Frequency-response protocol (§5.3.2): sinusoidal torque demands through the inverse model;
    /// one log per frequency and a manifest.
    Freqresp(RigFreqArgs),
    /// Minor-loop protocol: first-order reversal curves from below and above and decaying triangles
    /// (`[minor_loops]` of the configuration); one log in the characterisation's format and a
    /// manifest of the ramps, for `mrbrake characterize --operators`.
    MinorLoops(RigArgs),
    /// Torque tracking (RMSE of thesis (5.2)): full-range, 50 % and 25 % sinusoids at 0.1 rad/s and a
    /// band-limited random demand through an inverse model (branch or operator-model file); one log per
    /// demand and a manifest with the scores.
    Track(RigTrackArgs),
    /// Print the default rig configuration (TOML) to start a configuration file from.
    Config,
}

/// Common arguments of the rig protocols.
#[derive(Debug, Args)]
pub struct RigArgs {
    /// Output folder (created if missing).
    #[arg(long, value_name = "DIR")]
    out: PathBuf,
    /// Rig configuration (TOML); default: the thesis rig.
    #[arg(long, value_name = "FILE.toml")]
    config: Option<PathBuf>,
    /// Noise seed (overrides the configuration's).
    #[arg(long)]
    seed: Option<u64>,
    /// Brake model (JSON from `mrbrake analyze --save-model`) replacing the configuration's
    /// `[brake]`: its branches, maximum current, dynamics and viscous term (see
    /// `mrbrake::sim::brake_model`); default: the configured (built-in prototype-like) brake.
    #[arg(long, value_name = "FILE.json")]
    brake_model: Option<PathBuf>,
    /// Which unit of the brake model is on the rig: 1 or 2.
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..=2), requires = "brake_model")]
    unit: u32,
    /// Print a JSON object instead of text.
    #[arg(long)]
    json: bool,
}

/// Arguments of `rig freqresp`.
#[derive(Debug, Args)]
pub struct RigFreqArgs {
    #[command(flatten)]
    common: RigArgs,
    /// Inverse model used to shape the current (JSON from `characterize --save-model`); default: the
    /// configured branches.
    #[arg(long, value_name = "FILE.json")]
    model: Option<PathBuf>,
}

/// Arguments of `rig track`.
#[derive(Debug, Args)]
pub struct RigTrackArgs {
    #[command(flatten)]
    common: RigArgs,
    /// Inverse model: `characterize --save-model` JSON, polynomial branches or (with --operators) the
    /// operator-model file; default: the configured branches.
    #[arg(long, value_name = "FILE.json")]
    model: Option<PathBuf>,
}

fn load_config(args: &RigArgs) -> CommandResult<RigConfig> {
    let mut config = match &args.config {
        Some(path) => RigConfig::read(path)?,
        None => RigConfig::default(),
    };
    if let Some(seed) = args.seed {
        config.seed = seed;
    }
    if let Some(path) = &args.brake_model {
        let model = BrakeModel::read(path)?;
        for note in apply_to_rig(&model, args.unit, &mut config)? {
            eprintln!("note: {note}");
        }
    }
    Ok(config)
}

/// Runs `mrbrake rig …`.
pub fn run(command: RigCommand) -> CommandResult {
    match command {
        RigCommand::Config => print_text(&RigConfig::default().to_toml()),
        RigCommand::Characterize(args) => {
            let config = load_config(&args)?;
            let file = rig::characterization_log(&config)?;
            let written = write_rig_folder(&args.out, &config, std::slice::from_ref(&file))?;
            report(&args, &written, "characterization log")
        }
        RigCommand::MinorLoops(args) => {
            let config = load_config(&args)?;
            let files = rig::minor_loops::minor_loop_logs(&config)?;
            let written = write_rig_folder(&args.out, &config, &files)?;
            report(&args, &written, "minor-loop log")
        }
        RigCommand::Track(args) => {
            let config = load_config(&args.common)?;
            let inverse = match &args.model {
                Some(path) => read_torque_inverse(path)?,
                None => rig::configured_model(&config)?.into(),
            };
            let (files, scores) = rig::tracking::tracking_logs(&config, &inverse)?;
            let written = write_rig_folder(&args.common.out, &config, &files)?;
            if args.common.json {
                return print_json(
                    &serde_json::json!({ "files": rig_json(&written), "scores": scores }),
                );
            }
            print_text(&tracking_text(&scores))?;
            report(&args.common, &written, "tracking logs")
        }
        RigCommand::Freqresp(args) => {
            let config = load_config(&args.common)?;
            let model = args.model.as_deref().map(read_inverse_model).transpose()?;
            let files = rig::frequency_response_logs(&config, model.as_ref())?;
            let written = write_rig_folder(&args.common.out, &config, &files)?;
            report(&args.common, &written, "frequency-response logs")
        }
    }
}

fn report(args: &RigArgs, written: &[PathBuf], what: &str) -> CommandResult {
    if args.json {
        return print_json(&rig_json(written));
    }
    print_text(&rig_text(what, &args.out, written))
}
