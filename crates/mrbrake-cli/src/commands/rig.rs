//! `mrbrake rig …`: the virtual test rig writes the logs of the thesis's experiments.

use std::path::{Path, PathBuf};

use clap::{Args, Subcommand};
use mrbrake_sim::rig::{self, RigConfig, RigFile};
use mrbrake_sysid::inverse::HysteresisModel;

use crate::exit::InputError;
use crate::output::print_json;

/// `mrbrake rig` subcommands.
#[derive(Debug, Subcommand)]
pub enum RigCommand {
    /// Characterisation protocol (§5.3.1): current ramps 0 → I_max → 0, pause, repeated; one log.
    Characterize(RigArgs),
    /// Frequency-response protocol (§5.3.2): sinusoidal torque demands through the inverse model;
    /// one log per frequency and a manifest.
    Freqresp(RigFreqArgs),
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

fn load_config(args: &RigArgs) -> anyhow::Result<RigConfig> {
    let mut config = match &args.config {
        Some(path) => {
            let text = std::fs::read_to_string(path).map_err(|e| {
                InputError(format!("cannot read rig configuration '{}': {e}", path.display()))
            })?;
            RigConfig::from_toml(&path.display().to_string(), &text)?
        }
        None => RigConfig::default(),
    };
    if let Some(seed) = args.seed {
        config.seed = seed;
    }
    Ok(config)
}

fn write_files(dir: &Path, config: &RigConfig, files: &[RigFile]) -> anyhow::Result<Vec<PathBuf>> {
    std::fs::create_dir_all(dir)
        .map_err(|e| InputError(format!("cannot create output folder '{}': {e}", dir.display())))?;
    let mut written = Vec::new();
    for f in files {
        let path = dir.join(&f.name);
        mrbrake_report::write_atomic(&path, f.csv.as_bytes())?;
        written.push(path);
    }
    let path = dir.join("rig.toml");
    mrbrake_report::write_atomic(&path, config.to_toml().as_bytes())?;
    written.push(path);
    Ok(written)
}

/// Runs `mrbrake rig …`.
pub fn run(command: RigCommand) -> anyhow::Result<()> {
    match command {
        RigCommand::Config => {
            crate::out!("{}", RigConfig::default().to_toml());
            Ok(())
        }
        RigCommand::Characterize(args) => {
            let config = load_config(&args)?;
            let file = rig::characterization_log(&config)?;
            let written = write_files(&args.out, &config, std::slice::from_ref(&file))?;
            report(&args, &written, "characterization log")
        }
        RigCommand::Freqresp(args) => {
            let config = load_config(&args.common)?;
            let model = match &args.model {
                Some(path) => {
                    let text = std::fs::read_to_string(path).map_err(|e| {
                        InputError(format!("cannot read model '{}': {e}", path.display()))
                    })?;
                    Some(HysteresisModel::from_json(&path.display().to_string(), &text)?)
                }
                None => None,
            };
            let files = rig::frequency_response_logs(&config, model.as_ref())?;
            let written = write_files(&args.common.out, &config, &files)?;
            report(&args.common, &written, "frequency-response logs")
        }
    }
}

fn report(args: &RigArgs, written: &[PathBuf], what: &str) -> anyhow::Result<()> {
    if args.json {
        return print_json(&serde_json::json!({ "files": written }));
    }
    crate::outln!("{what}: {} files in {}", written.len(), args.out.display());
    for p in written.iter().filter(|p| {
        p.file_name().is_some_and(|n| n == "manifest.csv" || n == "characterization.csv")
    }) {
        crate::outln!("  {}", p.display());
    }
    Ok(())
}
