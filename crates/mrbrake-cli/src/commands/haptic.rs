//! `mrbrake haptic …`: the 1-DOF haptic simulation (sticky wall, conventional vs bidirectional brake
//! vs motor) and the Z-width map.

use std::path::PathBuf;

use crate::error::Context;
use clap::{Args, Subcommand, ValueEnum};
use mrbrake_report::haptic::{
    save_zwidth_plot, trace_csv, wall_metrics_text, wall_plot_title, wall_runs_figure,
    zwidth_summary,
};
use mrbrake_sim::brake_model::BrakeModel;
use mrbrake_sim::brake_model::apply::apply_to_haptic;
use mrbrake_sim::haptic::zwidth::{ZWidthConfig, sweep};
use mrbrake_sim::haptic::{DeviceKind, HapticConfig, HapticRun, Scenario, simulate};
use mrbrake_sysid::model_file::read_inverse_model;
use mrbrake_units::{Dimension, parse};

use crate::error::CommandResult;
use crate::error::InputError;
use crate::output::print_json;

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
    /// Virtual wall stiffness K in N·m/rad.
    #[arg(long = "stiffness-nm-per-rad", default_value_t = 30.0)]
    stiffness: f64,
    /// Virtual wall damping B in N·m·s/rad.
    #[arg(long = "damping-nms-per-rad", default_value_t = 0.02)]
    damping: f64,
    /// Run length (e.g. 4s, 10s); default: the scenario's 4 s.
    #[arg(long, value_name = "TIME")]
    duration: Option<String>,
    /// Characterisation JSON (rising/falling coefficients, current_min_A/current_max_A) used for both
    /// brakes, in the plant and in the controller; default: built-in prototype-like branches.
    #[arg(long, value_name = "FILE")]
    model: Option<PathBuf>,
    /// Brake model (JSON from `mrbrake analyze --save-model`): brake 1 runs unit 1, brake 2 unit 2
    /// (a single-unit model drives both), in the plant and in the controller, with the model's
    /// dynamics where it has them (see `mrbrake_sim::brake_model`); default: the built-in
    /// prototype-like brakes (examples/brake-models/prototype.json).
    #[arg(long, value_name = "FILE.json", conflicts_with = "model")]
    brake_model: Option<PathBuf>,
    /// Print the metrics as JSON.
    #[arg(long)]
    json: bool,
    /// Write the time-history plot (SVG, or PNG by extension). With --compare: conventional,
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
    /// Largest virtual stiffness K of the grid, N·m/rad.
    #[arg(long = "stiffness-max-nm-per-rad", default_value_t = 100.0)]
    stiffness_max: f64,
    /// Largest virtual damping B of the grid, N·m·s/rad.
    #[arg(long = "damping-max-nms-per-rad", default_value_t = 0.05)]
    damping_max: f64,
    /// Grid points along each axis (2..=1000).
    #[arg(long, default_value_t = 50)]
    points: usize,
    /// Sample period T of the haptic loop (e.g. 1ms).
    #[arg(long, default_value = "1ms", value_name = "TIME")]
    period: String,
    /// Physical damping b of the device, N·m·s/rad.
    #[arg(long = "physical-damping-nms-per-rad", default_value_t = 0.005)]
    physical_damping: f64,
    /// Controllable MR damping b_c of the hybrid device, N·m·s/rad (thesis (2.4)).
    #[arg(long = "controllable-damping-nms-per-rad", default_value_t = 0.05)]
    controllable_damping: f64,
    /// Write the map as CSV (one row per (K, B) pair).
    #[arg(long, value_name = "FILE")]
    csv: Option<PathBuf>,
    /// Write the map plot (SVG, or PNG by extension).
    #[arg(long, value_name = "FILE")]
    plot: Option<PathBuf>,
    /// Print a JSON summary.
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

fn wall_config(args: &WallArgs, device: DeviceKind) -> CommandResult<HapticConfig> {
    let mut config = HapticConfig::new(device, args.scenario.into());
    config.wall_stiffness_nm_per_rad = args.stiffness;
    config.wall_damping_nms_per_rad = args.damping;
    if let Some(text) = &args.duration {
        config.duration_s = parse(text, Dimension::Time).context("--duration")?;
    }
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
    Ok(config)
}

fn wall(args: WallArgs) -> CommandResult {
    for (flag, value) in
        [("--stiffness-nm-per-rad", args.stiffness), ("--damping-nms-per-rad", args.damping)]
    {
        if !(value.is_finite() && value >= 0.0) {
            return Err(InputError(format!("{flag} = {value} must be a number ≥ 0")).into());
        }
    }
    let device: DeviceKind = args.device.into();
    let record = args.plot.is_some() || args.csv.is_some();
    let run = simulate(&wall_config(&args, device)?, record)?;
    if let Some(path) = &args.csv {
        mrbrake_report::write_atomic(path, trace_csv(device, &run)?.as_bytes())?;
    }
    if let Some(path) = &args.plot {
        let title = wall_plot_title(run.metrics.scenario, args.stiffness, args.damping);
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
    crate::out!("{}", wall_metrics_text(&run.metrics, args.stiffness));
    Ok(())
}

fn zwidth(args: ZwidthArgs) -> CommandResult {
    let period = parse(&args.period, Dimension::Time).context("--period")?;
    if !(2..=1000).contains(&args.points) {
        return Err(InputError(format!("--points = {} must be in 2..=1000", args.points)).into());
    }
    let config = ZWidthConfig {
        stiffness_max_nm_per_rad: args.stiffness_max,
        stiffness_points: args.points,
        damping_max_nms_per_rad: args.damping_max,
        damping_points: args.points,
        sample_period_s: period,
        physical_damping_nms_per_rad: args.physical_damping,
        controllable_damping_nms_per_rad: args.controllable_damping,
        ..ZWidthConfig::default()
    };
    let map = sweep(&config)?;
    if let Some(path) = &args.csv {
        mrbrake_report::write_atomic(path, map.to_csv().as_bytes())?;
    }
    if let Some(path) = &args.plot {
        save_zwidth_plot(path, &map)?;
    }
    let summary = zwidth_summary(&map);
    if args.json {
        return print_json(&summary);
    }
    crate::outln!("{}", crate::output::json_text(&summary)?);
    Ok(())
}
