//! `mrbrake haptic …`: the 1-DOF haptic simulation (sticky wall, conventional vs bidirectional brake
//! vs motor) and the Z-width map.

use std::path::PathBuf;

use crate::error::{Context, InputError};
use clap::{Args, Subcommand, ValueEnum};
use mrbrake::observe::{Count, Flow};
use mrbrake::report::haptic::{
    save_zwidth_plot, trace_csv, wall_metrics_text, wall_plot_title, wall_runs_figure,
    zwidth_summary, zwidth_text,
};
use mrbrake::sim::brake_model::BrakeModel;
use mrbrake::sim::brake_model::apply::apply_to_haptic;
use mrbrake::sim::haptic::zwidth::{ZWidthConfig, sweep};
use mrbrake::sim::haptic::{
    DeviceKind, HapticConfig, HapticRun, PlantRemanence, Scenario, simulate,
};
use mrbrake::sysid::model_file::read_inverse_model;
use mrbrake::units::{Dimension, parse};

use crate::error::CommandResult;
use crate::output::{print_json, print_text};
use crate::progress::ProgressDisplay;

/// `mrbrake haptic` subcommands.
#[derive(Debug, Subcommand)]
pub enum HapticCommand {
    /// Simulate a hand pressing into a virtual wall and withdrawing; report the sticky-wall measures.
    Wall(WallArgs),
    /// Sweep virtual stiffness K and damping B; classify passive / stable / unstable (thesis (2.2), (2.4)).
    Zwidth(ZwidthArgs),
}

/// The actuator of the simulated device.
#[derive(Debug, Clone, Copy, ValueEnum)]
pub enum DeviceArg {
    /// One MR brake fixed to the shaft (resists both directions).
    Conventional,
    /// Two MR brakes on opposite one-way bearings (the thesis's design).
    Bidirectional,
    /// An ideal DC motor rendering the same wall (active reference).
    Motor,
}

impl From<DeviceArg> for DeviceKind {
    fn from(d: DeviceArg) -> Self {
        match d {
            DeviceArg::Conventional => DeviceKind::Conventional,
            DeviceArg::Bidirectional => DeviceKind::Bidirectional,
            DeviceArg::Motor => DeviceKind::Motor,
        }
    }
}

/// What the user does.
#[derive(Debug, Clone, Copy, ValueEnum)]
pub enum ScenarioArg {
    /// Press into the wall, hold, withdraw.
    PressWithdraw,
    /// Press, then swing in and out while in contact.
    SlideHold,
    /// Keep pressing against a moving wall.
    MovingWall,
}

impl From<ScenarioArg> for Scenario {
    fn from(s: ScenarioArg) -> Self {
        match s {
            ScenarioArg::PressWithdraw => Scenario::PressWithdraw,
            ScenarioArg::SlideHold => Scenario::SlideHold,
            ScenarioArg::MovingWall => Scenario::MovingWall,
        }
    }
}

/// Arguments of `haptic wall`.
#[derive(Debug, Args)]
pub struct WallArgs {
    /// The device's actuator.
    #[arg(long, value_enum)]
    device: DeviceArg,
    /// The interaction scenario.
    #[arg(long, value_enum, default_value = "press-withdraw")]
    scenario: ScenarioArg,
    /// Virtual wall stiffness K, ≥ 0 (e.g. 30N·m/rad, 30Nm/rad; a bare number is N·m/rad).
    #[arg(
        long,
        value_name = "STIFFNESS",
        default_value = "30N·m/rad",
        allow_hyphen_values = true,
        alias = "stiffness-nm-per-rad"
    )]
    stiffness: String,
    /// Virtual wall damping B, ≥ 0 (e.g. 0.02N·m·s/rad, 20mNms/rad; a bare number is N·m·s/rad).
    #[arg(
        long,
        value_name = "DAMPING",
        default_value = "0.02N·m·s/rad",
        allow_hyphen_values = true,
        alias = "damping-nms-per-rad"
    )]
    damping: String,
    /// Run length (e.g. 4s, 10s); default: the scenario's 4 s.
    #[arg(long, value_name = "TIME", allow_hyphen_values = true)]
    duration: Option<String>,
    /// Characterisation JSON (rising/falling coefficients, current_min_A/current_max_A) used for both
    /// brakes, in the plant and in the controller; default: built-in prototype-like branches.
    #[arg(long, value_name = "FILE")]
    model: Option<PathBuf>,
    /// Brake model (JSON from `mrbrake analyze --save-model`): brake 1 runs unit 1, brake 2 unit 2
    /// (a single-unit model drives both), in the plant and in the controller, with the model's
    /// dynamics where it has them (see `mrbrake::sim::brake_model`); default: the built-in
    /// prototype-like brakes (examples/brake-models/prototype.json).
    #[arg(long, value_name = "FILE.json", conflicts_with = "model")]
    brake_model: Option<PathBuf>,
    /// The steel's predicted remanence in the plant: the JSON of `mrbrake analyze --hysteresis
    /// --demag --json` (its remanent torque after the peak; with --demag-release, the chosen
    /// reverse pulse and the share of the remanence it leaves). See `mrbrake::sim::haptic::remanence`.
    /// With a --brake-model that has a Preisach table, the table holds the remanence: only
    /// --remanence with --demag-release is accepted (the release's part).
    #[arg(long, value_name = "ANALYSIS.json")]
    remanence: Option<PathBuf>,
    /// With --remanence: the controller drives each released brake through the predicted reverse
    /// pulse (a bipolar driver; the controller's output may go negative).
    #[arg(long, requires = "remanence")]
    demag_release: bool,
    /// Length of the demagnetising pulse (e.g. 5ms), rounded up to whole control ticks.
    #[arg(long, requires = "demag_release", default_value = "5ms", value_name = "TIME")]
    demag_duration: String,
    /// Print the metrics as JSON instead of text.
    #[arg(long)]
    json: bool,
    /// Write the time-history plot (.svg or .png). With --compare: conventional,
    /// bidirectional and motor side by side.
    #[arg(long, value_name = "FILE")]
    plot: Option<PathBuf>,
    /// Plot all three devices side by side (the sticky wall and its cure) instead of --device alone.
    #[arg(long)]
    compare: bool,
    /// Write the time histories of --device as CSV (1 kHz rows).
    #[arg(long, value_name = "FILE")]
    csv: Option<PathBuf>,
}

/// Arguments of `haptic zwidth`.
#[derive(Debug, Args)]
pub struct ZwidthArgs {
    /// Largest virtual stiffness K of the grid (e.g. 100N·m/rad; a bare number is N·m/rad).
    #[arg(
        long,
        value_name = "STIFFNESS",
        default_value = "100N·m/rad",
        allow_hyphen_values = true,
        alias = "stiffness-max-nm-per-rad"
    )]
    stiffness_max: String,
    /// Largest virtual damping B of the grid (e.g. 0.05N·m·s/rad; a bare number is N·m·s/rad).
    #[arg(
        long,
        value_name = "DAMPING",
        default_value = "0.05N·m·s/rad",
        allow_hyphen_values = true,
        alias = "damping-max-nms-per-rad"
    )]
    damping_max: String,
    /// Grid points along each axis (2..=1000).
    #[arg(long, default_value_t = 50)]
    points: usize,
    /// Sample period T of the haptic loop (e.g. 1ms).
    #[arg(long, default_value = "1ms", value_name = "TIME", allow_hyphen_values = true)]
    period: String,
    /// Physical damping b of the device (e.g. 5mNms/rad; a bare number is N·m·s/rad).
    #[arg(
        long,
        value_name = "DAMPING",
        default_value = "0.005N·m·s/rad",
        allow_hyphen_values = true,
        alias = "physical-damping-nms-per-rad"
    )]
    physical_damping: String,
    /// Controllable MR damping b_c of the hybrid device, thesis (2.4) (e.g. 0.05N·m·s/rad; a bare
    /// number is N·m·s/rad).
    #[arg(
        long,
        value_name = "DAMPING",
        default_value = "0.05N·m·s/rad",
        allow_hyphen_values = true,
        alias = "controllable-damping-nms-per-rad"
    )]
    controllable_damping: String,
    /// Write the map as CSV (one row per (K, B) pair).
    #[arg(long, value_name = "FILE")]
    csv: Option<PathBuf>,
    /// Write the map plot (.svg or .png).
    #[arg(long, value_name = "FILE")]
    plot: Option<PathBuf>,
    /// Print a JSON summary instead of text.
    #[arg(long)]
    json: bool,
}

/// Runs a `haptic` subcommand.
pub fn run(command: HapticCommand) -> CommandResult {
    match command {
        HapticCommand::Wall(args) => wall(args),
        HapticCommand::Zwidth(args) => zwidth(args),
    }
}

/// A quantity flag's value in SI, with the flag in front of any error.
fn quantity(flag: &str, text: &str, dimension: Dimension) -> CommandResult<f64> {
    parse(text, dimension).context(flag.to_string())
}

/// The wall's K and B (N·m/rad, N·m·s/rad) as given; their ranges are the library's
/// ([`HapticConfig::validate`], with [`WALL_FLAGS`]).
fn wall_gains(args: &WallArgs) -> CommandResult<(f64, f64)> {
    let k = quantity("--stiffness", &args.stiffness, Dimension::RotationalStiffness)?;
    let b = quantity("--damping", &args.damping, Dimension::RotationalDamping)?;
    Ok((k, b))
}

/// The flags of the [`HapticConfig`] fields its range errors name.
const WALL_FLAGS: &[(&str, &str)] = &[
    ("wall_stiffness_nm_per_rad", "--stiffness"),
    ("wall_damping_nms_per_rad", "--damping"),
    ("duration_s", "--duration"),
];

fn wall_config(args: &WallArgs, device: DeviceKind) -> CommandResult<HapticConfig> {
    let mut config = HapticConfig::new(device, args.scenario.into());
    (config.wall_stiffness_nm_per_rad, config.wall_damping_nms_per_rad) = wall_gains(args)?;
    if let Some(text) = &args.duration {
        config.duration_s = parse(text, Dimension::Time).context("--duration")?;
    }
    config.validate().map_err(|e| e.with_field_names(WALL_FLAGS))?;
    if let Some(path) = &args.model {
        config.use_inverse_model(read_inverse_model(path)?);
    }
    if let Some(path) = &args.brake_model {
        let notes = apply_to_haptic(&BrakeModel::read(path)?, &mut config)?;
        // Said once, for the device the user named (--compare builds three configurations).
        if device == DeviceKind::from(args.device) {
            for note in notes {
                eprintln!("note: {note}");
            }
        }
    }
    if let Some(path) = &args.remanence {
        let duration = parse(&args.demag_duration, Dimension::Time).context("--demag-duration")?;
        let text = std::fs::read_to_string(path)
            .map_err(|e| InputError(format!("--remanence {}: {e}", path.display())))?;
        let remanence =
            PlantRemanence::from_analysis_json(&text, args.demag_release.then_some(duration))
                .map_err(|e| InputError(format!("--remanence {}: {e}", path.display())))?;
        config.remanence = Some(remanence);
        // With a Preisach brake model the table magnetises; a remanence without its release is
        // refused (it would count the remanence twice): the library's "remanence" is this flag.
        config.validate().map_err(|e| e.with_field_names(&[("remanence", "--remanence")]))?;
    }
    Ok(config)
}

fn wall(args: WallArgs) -> CommandResult {
    let (stiffness, damping) = wall_gains(&args)?;
    crate::output::check_plot_path("--plot", args.plot.as_deref())?;
    let device: DeviceKind = args.device.into();
    let record = args.plot.is_some() || args.csv.is_some();
    let run = simulate(&wall_config(&args, device)?, record)?;
    if let Some(path) = &args.csv {
        mrbrake::report::write_atomic(path, trace_csv(device, &run)?.as_bytes())?;
    }
    if let Some(path) = &args.plot {
        let title = wall_plot_title(run.metrics.scenario, stiffness, damping);
        let compared: Vec<(DeviceKind, HapticRun)> = if args.compare {
            [DeviceKind::Conventional, DeviceKind::Bidirectional, DeviceKind::Motor]
                .into_iter()
                .map(|kind| Ok((kind, simulate(&wall_config(&args, kind)?, true)?)))
                .collect::<CommandResult<_>>()?
        } else {
            Vec::new()
        };
        let runs: Vec<(DeviceKind, &HapticRun)> = if args.compare {
            compared.iter().map(|(kind, r)| (*kind, r)).collect()
        } else {
            vec![(device, &run)]
        };
        wall_runs_figure(&title, &runs)?.save(path)?;
    }
    if args.json {
        return print_json(&run.metrics);
    }
    print_text(&wall_metrics_text(&run.metrics, stiffness))
}

fn zwidth(args: ZwidthArgs) -> CommandResult {
    let period = parse(&args.period, Dimension::Time).context("--period")?;
    crate::output::check_plot_path("--plot", args.plot.as_deref())?;
    let (stiffness, damping) = (Dimension::RotationalStiffness, Dimension::RotationalDamping);
    let config = ZWidthConfig {
        stiffness_max_nm_per_rad: quantity("--stiffness-max", &args.stiffness_max, stiffness)?,
        stiffness_points: args.points,
        damping_max_nms_per_rad: quantity("--damping-max", &args.damping_max, damping)?,
        damping_points: args.points,
        sample_period_s: period,
        physical_damping_nms_per_rad: quantity(
            "--physical-damping",
            &args.physical_damping,
            damping,
        )?,
        controllable_damping_nms_per_rad: quantity(
            "--controllable-damping",
            &args.controllable_damping,
            damping,
        )?,
        ..ZWidthConfig::default()
    };
    let mut display = ProgressDisplay::steps("haptic zwidth", "stiffness rows", args.json);
    let map = sweep(&config, &mut |c: &Count| {
        display.step(c.done, c.total);
        Flow::Continue
    })?;
    display.finish();
    if let Some(path) = &args.csv {
        mrbrake::report::write_atomic(path, map.to_csv().as_bytes())?;
    }
    if let Some(path) = &args.plot {
        save_zwidth_plot(path, &map)?;
    }
    if args.json {
        return print_json(&zwidth_summary(&map));
    }
    print_text(&zwidth_text(&map))
}
