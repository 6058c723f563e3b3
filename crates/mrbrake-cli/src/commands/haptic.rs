//! `mrbrake haptic …`: the 1-DOF haptic simulation (sticky wall, conventional vs bidirectional brake
//! vs motor) and the Z-width map.

use std::path::PathBuf;

use anyhow::Context;
use clap::{Args, Subcommand, ValueEnum};
use mrbrake_report::haptic::{
    ClassifiedPair, TimeHistory, ZWidthPanel, wall_comparison_figure, zwidth_figure,
};
use mrbrake_sim::haptic::characterization::load_inverse_model;
use mrbrake_sim::haptic::zwidth::{ZWidthConfig, sweep};
use mrbrake_sim::haptic::{DeviceKind, HapticConfig, HapticRun, Scenario, simulate};
use mrbrake_units::{Dimension, parse};
use serde_json::json;

use crate::exit::InputError;
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
pub fn run(command: HapticCommand) -> anyhow::Result<()> {
    match command {
        HapticCommand::Wall(args) => wall(args),
        HapticCommand::Zwidth(args) => zwidth(args),
    }
}

fn wall_config(args: &WallArgs, device: DeviceKind) -> anyhow::Result<HapticConfig> {
    let mut config = HapticConfig::new(device, args.scenario.into());
    config.wall_stiffness_nm_per_rad = args.stiffness;
    config.wall_damping_nms_per_rad = args.damping;
    if let Some(text) = &args.duration {
        config.duration_s = parse(text, Dimension::Time).context("--duration")?;
    }
    if let Some(path) = &args.model {
        let model = load_inverse_model(path)?;
        config.brakes[0].branches = model;
        config.brakes[1].branches = model;
        config.controller_models = [model, model];
    }
    Ok(config)
}

fn history<'a>(label: &'a str, run: &'a HapticRun) -> anyhow::Result<TimeHistory<'a>> {
    let trace =
        run.trace.as_ref().ok_or_else(|| anyhow::anyhow!("internal: run recorded no trace"))?;
    Ok(TimeHistory {
        label,
        time_s: &trace.time_s,
        angle_rad: &trace.angle_rad,
        intended_rad: &trace.intended_rad,
        wall_rad: &trace.wall_rad,
        current_a: [&trace.current_a[0], &trace.current_a[1]],
        device_torque_nm: &trace.device_torque_nm,
        hand_torque_nm: &trace.hand_torque_nm,
    })
}

fn wall(args: WallArgs) -> anyhow::Result<()> {
    if !(args.stiffness.is_finite() && args.stiffness >= 0.0) {
        return Err(InputError(format!(
            "--stiffness-nm-per-rad = {} must be a number ≥ 0",
            args.stiffness
        ))
        .into());
    }
    if !(args.damping.is_finite() && args.damping >= 0.0) {
        return Err(InputError(format!(
            "--damping-nms-per-rad = {} must be a number ≥ 0",
            args.damping
        ))
        .into());
    }
    let device: DeviceKind = args.device.into();
    let record = args.plot.is_some() || args.csv.is_some();
    let run = simulate(&wall_config(&args, device)?, record)?;
    if let Some(path) = &args.csv {
        let trace =
            run.trace.as_ref().ok_or_else(|| anyhow::anyhow!("internal: run recorded no trace"))?;
        mrbrake_report::write_atomic(path, trace.to_csv().as_bytes())?;
    }
    if let Some(path) = &args.plot {
        let title = format!(
            "Virtual wall, {} (K = {} N·m/rad, B = {} N·m·s/rad)",
            run.metrics.scenario, args.stiffness, args.damping
        );
        if args.compare {
            let kinds = [DeviceKind::Conventional, DeviceKind::Bidirectional, DeviceKind::Motor];
            let runs: Vec<HapticRun> = kinds
                .iter()
                .map(|&kind| {
                    simulate(&wall_config(&args, kind)?, true).map_err(anyhow::Error::from)
                })
                .collect::<anyhow::Result<_>>()?;
            let histories: Vec<TimeHistory> = kinds
                .iter()
                .zip(&runs)
                .map(|(k, r)| history(k.name(), r))
                .collect::<anyhow::Result<_>>()?;
            wall_comparison_figure(&title, &histories).save(path)?;
        } else {
            wall_comparison_figure(&title, &[history(device.name(), &run)?]).save(path)?;
        }
    }
    let m = &run.metrics;
    if args.json {
        return print_json(m);
    }
    crate::outln!("device {}, scenario {}", m.device, m.scenario);
    crate::outln!("  max penetration            {:.4} rad", m.max_penetration_rad);
    match m.displayed_stiffness_nm_per_rad {
        Some(k) => {
            crate::outln!(
                "  displayed stiffness        {k:.2} N·m/rad (virtual {})",
                args.stiffness
            )
        }
        None => crate::outln!("  displayed stiffness        n/a"),
    }
    crate::outln!(
        "  withdraw resisting torque  peak {:.3} N·m, mean {:.3} N·m (excess over {:.3} N·m drag: peak {:.3}, mean {:.3})",
        m.withdraw_resisting_torque_nm.peak,
        m.withdraw_resisting_torque_nm.mean,
        m.outward_drag_nm,
        m.withdraw_excess_torque_nm.peak,
        m.withdraw_excess_torque_nm.mean
    );
    crate::outln!(
        "  withdraw energy            {:.5} J over {:.3} s",
        m.withdraw_energy_j,
        m.withdraw_duration_s
    );
    match m.release_time_s {
        Some(t) => crate::outln!("  release time               {t:.3} s"),
        None => crate::outln!("  release time               not released / no withdrawal"),
    }
    crate::outln!(
        "  device energy              {:.5} J (running peak {:.2e} J)",
        m.device_energy_j,
        m.device_energy_peak_j
    );
    crate::outln!("  passive                    {} (stable {})", m.passive, m.stable);
    crate::outln!(
        "  peak coil current          {:.3} A, faults {}",
        m.current_peak_a,
        m.fault_ticks
    );
    Ok(())
}

fn zwidth(args: ZwidthArgs) -> anyhow::Result<()> {
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
    let b = config.physical_damping_nms_per_rad;
    let bc = config.controllable_damping_nms_per_rad;
    if let Some(path) = &args.plot {
        let pairs = |pick: fn(&mrbrake_sim::haptic::zwidth::ZWidthCell) -> &'static str| -> Vec<ClassifiedPair> {
            map.cells
                .iter()
                .map(|c| ClassifiedPair {
                    stiffness_nm_per_rad: c.stiffness_nm_per_rad,
                    damping_nms_per_rad: c.damping_nms_per_rad,
                    class: pick(c),
                })
                .collect()
        };
        let panels = [
            ZWidthPanel {
                label: format!("motor, b = {b} N·m·s/rad (2.2)"),
                pairs: pairs(|c| c.motor.name()),
                boundary_damping_nms_per_rad: Some(b),
            },
            ZWidthPanel {
                label: format!("motor + MR damper, b + b_c = {} (2.4)", b + bc),
                pairs: pairs(|c| c.hybrid.name()),
                boundary_damping_nms_per_rad: Some(b + bc),
            },
            ZWidthPanel {
                label: "bidirectional MR brake".into(),
                pairs: pairs(|c| c.brake.name()),
                boundary_damping_nms_per_rad: None,
            },
        ];
        zwidth_figure(&format!("Z-width, T = {} ms", period * 1e3), period, &panels).save(path)?;
    }
    let count = |f: &dyn Fn(&mrbrake_sim::haptic::zwidth::ZWidthCell) -> bool| {
        map.cells.iter().filter(|c| f(c)).count()
    };
    use mrbrake_sim::haptic::zwidth::Interaction as I;
    let summary = json!({
        "cells": map.cells.len(),
        "motor": {"passive": count(&|c| c.motor == I::Passive), "stable": count(&|c| c.motor == I::Stable),
                  "unstable": count(&|c| c.motor == I::Unstable),
                  "agree_with_2_2": count(&|c| (c.motor == I::Passive) == c.motor_predicted_passive)},
        "hybrid": {"passive": count(&|c| c.hybrid == I::Passive), "stable": count(&|c| c.hybrid == I::Stable),
                   "unstable": count(&|c| c.hybrid == I::Unstable),
                   "agree_with_2_4": count(&|c| (c.hybrid == I::Passive) == c.hybrid_predicted_passive)},
        "brake": {"passive": count(&|c| c.brake == I::Passive), "stable": count(&|c| c.brake == I::Stable),
                  "unstable": count(&|c| c.brake == I::Unstable)},
    });
    if args.json {
        return print_json(&summary);
    }
    crate::outln!("{}", serde_json::to_string_pretty(&summary)?);
    Ok(())
}
