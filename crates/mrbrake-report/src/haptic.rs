//! Haptic reports: the sticky-wall measures of a run as text, side-by-side time histories of wall
//! interactions (e.g. conventional vs bidirectional brake: the sticky wall and its cure) and the
//! Z-width map with its summary.
//!
//! The figures take plain slices ([`TimeHistory`], [`ClassifiedPair`]); [`TimeHistory::from_trace`],
//! [`zwidth_panels`] and the text and JSON reports compose them from the simulator's results.

use std::fmt::Write as _;
use std::path::Path;

use mrbrake_sim::haptic::zwidth::{Interaction, ZWidthCell, ZWidthMap};
use mrbrake_sim::haptic::{DeviceKind, HapticRun, Trace, WallMetrics};
use serde_json::{Value, json};

use crate::ReportError;
use crate::chart::{Figure, Panel, Series, SeriesLabelPosition, Shape};

/// Time histories of one run, at any uniform rate.
#[derive(Debug, Clone, Copy)]
pub struct TimeHistory<'a> {
    /// Column title (e.g. the device name).
    pub label: &'a str,
    /// Time, s.
    pub time_s: &'a [f64],
    /// Handle angle, rad.
    pub angle_rad: &'a [f64],
    /// The hand's intended angle, rad.
    pub intended_rad: &'a [f64],
    /// Wall surface, rad.
    pub wall_rad: &'a [f64],
    /// Coil currents of brake 1 and 2, A.
    pub current_a: [&'a [f64]; 2],
    /// How many brake coils the device has (0: a motor, no current panel; 1: one brake that
    /// resists both ways; 2: the bidirectional pair).
    pub coils: usize,
    /// Device torque on the shaft, Nm.
    pub device_torque_nm: &'a [f64],
    /// Hand torque on the shaft, Nm.
    pub hand_torque_nm: &'a [f64],
}

impl<'a> TimeHistory<'a> {
    /// The histories of a simulator trace of `device`, under `label`.
    pub fn from_trace(label: &'a str, device: DeviceKind, trace: &'a Trace) -> Self {
        let coils = match device {
            DeviceKind::Conventional => 1,
            DeviceKind::Bidirectional => 2,
            DeviceKind::Motor => 0,
        };
        Self {
            label,
            coils,
            time_s: &trace.time_s,
            angle_rad: &trace.angle_rad,
            intended_rad: &trace.intended_rad,
            wall_rad: &trace.wall_rad,
            current_a: [&trace.current_a[0], &trace.current_a[1]],
            device_torque_nm: &trace.device_torque_nm,
            hand_torque_nm: &trace.hand_torque_nm,
        }
    }
}

/// The title of a wall plot: scenario, virtual stiffness `K` and damping `B`.
pub fn wall_plot_title(
    scenario: &str,
    stiffness_nm_per_rad: f64,
    damping_nms_per_rad: f64,
) -> String {
    format!(
        "Virtual wall, {scenario} (K = {stiffness_nm_per_rad} N·m/rad, B = {damping_nms_per_rad} N·m·s/rad)"
    )
}

/// The text report of a wall run; `stiffness_nm_per_rad` is the virtual stiffness the displayed one
/// is compared with.
pub fn wall_metrics_text(m: &WallMetrics, stiffness_nm_per_rad: f64) -> String {
    let mut out = String::new();
    let _ = writeln!(out, "device {}, scenario {}", m.device, m.scenario);
    let _ = writeln!(out, "  max penetration            {:.4} rad", m.max_penetration_rad);
    match m.displayed_stiffness_nm_per_rad {
        Some(k) => {
            _ = writeln!(
                out,
                "  displayed stiffness        {k:.2} N·m/rad (virtual {stiffness_nm_per_rad})"
            )
        }
        None => _ = writeln!(out, "  displayed stiffness        n/a"),
    }
    let _ = writeln!(
        out,
        "  withdraw resisting torque  peak {:.3} N·m, mean {:.3} N·m (excess over {:.3} N·m drag: peak {:.3}, mean {:.3})",
        m.withdraw_resisting_torque_nm.peak,
        m.withdraw_resisting_torque_nm.mean,
        m.outward_drag_nm,
        m.withdraw_excess_torque_nm.peak,
        m.withdraw_excess_torque_nm.mean
    );
    let _ = writeln!(
        out,
        "  withdraw energy            {:.5} J over {:.3} s",
        m.withdraw_energy_j, m.withdraw_duration_s
    );
    let _ = writeln!(
        out,
        "  free motion                peak hand torque {:.3} N·m; drag after the run: outward \
         {:.3} N·m, inward {:.3} N·m",
        m.free_motion_torque_nm, m.drag_after_nm.outward, m.drag_after_nm.inward
    );
    match m.release_time_s {
        Some(t) => _ = writeln!(out, "  release time               {t:.3} s"),
        None => _ = writeln!(out, "  release time               not released / no withdrawal"),
    }
    let _ = writeln!(
        out,
        "  device energy              {:.5} J (running peak {:.2e} J)",
        m.device_energy_j, m.device_energy_peak_j
    );
    let _ = writeln!(out, "  passive                    {} (stable {})", m.passive, m.stable);
    let _ = writeln!(
        out,
        "  peak coil current          {:.3} A, faults {}",
        m.current_peak_a, m.fault_ticks
    );
    out
}

/// The recorded trace of `run` (an error names `device` if the run was simulated without
/// recording).
fn trace_of(device: DeviceKind, run: &HapticRun) -> Result<&Trace, ReportError> {
    run.trace.as_ref().ok_or_else(|| {
        ReportError::Data(format!("the {} run recorded no trace to report", device.name()))
    })
}

/// The time histories of a recorded run as CSV (1 kHz rows).
pub fn trace_csv(device: DeviceKind, run: &HapticRun) -> Result<String, ReportError> {
    Ok(trace_of(device, run)?.to_csv())
}

/// The wall plot of recorded runs, one column per run titled with its device's name (see
/// [`wall_comparison_figure`]).
pub fn wall_runs_figure(
    title: &str,
    runs: &[(DeviceKind, &HapticRun)],
) -> Result<Figure, ReportError> {
    let histories: Vec<TimeHistory> = runs
        .iter()
        .map(|&(device, run)| {
            Ok(TimeHistory::from_trace(device.name(), device, trace_of(device, run)?))
        })
        .collect::<Result<_, ReportError>>()?;
    Ok(wall_comparison_figure(title, &histories))
}

/// Largest number of points drawn per series (the SVG stays small; 1 kHz data is decimated).
const MAX_POINTS: usize = 1200;

fn decimated(time: &[f64], values: &[f64]) -> Vec<(f64, f64)> {
    let n = time.len().min(values.len());
    let stride = n.div_ceil(MAX_POINTS).max(1);
    (0..n).step_by(stride).map(|k| (time[k], values[k])).collect()
}

/// One column per run and three rows: angle (with intention and wall), coil currents, torques.
/// Each row shares its y range across the runs, so the columns compare at a glance; a device
/// without coils (the motor) gets a note instead of an empty current panel.
pub fn wall_comparison_figure(title: &str, runs: &[TimeHistory<'_>]) -> Figure {
    let columns = runs.len().max(1);
    let mut figure = Figure::new(title).columns(columns).size((520 * columns as u32).max(900), 900);
    let ranges = shared_ranges(runs);
    let mut rows: [Vec<Panel>; 3] = Default::default();
    for run in runs {
        let t = run.time_s;
        rows[0].push(
            Panel::new("time [s]", "angle [rad]")
                .caption(format!("{}: handle angle", run.label))
                .legend(SeriesLabelPosition::LowerLeft)
                .y_range(ranges[0].0, ranges[0].1)
                .series(Series::line("handle", decimated(t, run.angle_rad)).color(0))
                .series(Series::dashed("intended", decimated(t, run.intended_rad)).color(6))
                .series(Series::dashed("wall", decimated(t, run.wall_rad)).color(1)),
        );
        rows[1].push(current_panel(run, ranges[1]));
        rows[2].push(
            Panel::new("time [s]", "torque [N·m]")
                .caption(format!("{}: torques on the shaft", run.label))
                .legend(SeriesLabelPosition::LowerLeft)
                .y_range(ranges[2].0, ranges[2].1)
                .series(Series::line("device", decimated(t, run.device_torque_nm)).color(0))
                .series(Series::line("hand", decimated(t, run.hand_torque_nm)).color(2)),
        );
    }
    for row in rows {
        for panel in row {
            figure = figure.panel(panel);
        }
    }
    figure
}

/// The coil-current panel of `run` on the shared range `y`: one line per coil the device has.
fn current_panel(run: &TimeHistory<'_>, y: (f64, f64)) -> Panel {
    let caption = format!("{}: coil current{}", run.label, if run.coils == 1 { "" } else { "s" });
    if run.coils == 0 {
        return Panel::note(run.label, "no brake coil: the motor applies the torque directly");
    }
    let t = run.time_s;
    let mut panel = Panel::new("time [s]", "current [A]")
        .caption(caption)
        .legend(SeriesLabelPosition::UpperRight)
        .y_range(y.0, y.1);
    if run.coils == 1 {
        panel = panel.series(
            Series::line("brake (resists both ways)", decimated(t, run.current_a[0])).color(0),
        );
    } else {
        panel = panel
            .series(Series::line("brake 1 (resists +)", decimated(t, run.current_a[0])).color(0))
            .series(Series::dashed("brake 2 (resists −)", decimated(t, run.current_a[1])).color(1));
    }
    panel
}

/// The y ranges of the three rows (angles, currents, torques) over every run, padded by 5 %
/// (with 35 % headroom on the current row for its legend); the current row starts at 0.
fn shared_ranges(runs: &[TimeHistory<'_>]) -> [(f64, f64); 3] {
    let span = |values: &mut dyn Iterator<Item = f64>| {
        values
            .filter(|v| v.is_finite())
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| (lo.min(v), hi.max(v)))
    };
    let pad = |(lo, hi): (f64, f64), top: f64| {
        if !lo.is_finite() {
            return (-1.0, 1.0);
        }
        let d = if hi > lo { hi - lo } else { hi.abs().max(1.0) };
        (lo - 0.05 * d, hi + top * d)
    };
    let angles = span(
        &mut runs
            .iter()
            .flat_map(|r| r.angle_rad.iter().chain(r.intended_rad).chain(r.wall_rad).copied()),
    );
    let currents = span(
        &mut runs
            .iter()
            .filter(|r| r.coils > 0)
            .flat_map(|r| r.current_a[0].iter().chain(r.current_a[1]).copied())
            .chain([0.0]),
    );
    let torques = span(
        &mut runs.iter().flat_map(|r| r.device_torque_nm.iter().chain(r.hand_torque_nm).copied()),
    );
    let (c0, c1) = pad(currents, 0.35);
    let c0 = if currents.0 >= 0.0 { 0.0 } else { c0 };
    [pad(angles, 0.05), (c0, c1), pad(torques, 0.05)]
}

/// A classified (K, B) pair of a Z-width map; `class` is `"passive"`, `"stable"` or `"unstable"`.
#[derive(Debug, Clone, Copy)]
pub struct ClassifiedPair<'a> {
    /// Virtual stiffness, Nm/rad.
    pub stiffness_nm_per_rad: f64,
    /// Virtual damping, Nm·s/rad.
    pub damping_nms_per_rad: f64,
    /// Classification.
    pub class: &'a str,
}

/// One Z-width panel: the device's name, its classified pairs, and the physical damping `b` of its
/// passivity boundary `B = b − K T/2` (thesis (2.2)/(2.4); `None`: no boundary drawn).
#[derive(Debug, Clone)]
pub struct ZWidthPanel<'a> {
    /// Panel caption.
    pub label: String,
    /// The pairs.
    pub pairs: Vec<ClassifiedPair<'a>>,
    /// Physical damping for the predicted boundary, Nm·s/rad.
    pub boundary_damping_nms_per_rad: Option<f64>,
}

/// Colour (palette index) and marker of each Z-width class: passive bluish-green circles, stable
/// blue triangles, unstable vermilion crosses (told apart by shape as well as by colour, for
/// colour-blind readers and grey print).
const ZWIDTH_STYLES: [(&str, usize, Shape); 3] =
    [("passive", 2, Shape::Circle), ("stable", 0, Shape::Triangle), ("unstable", 1, Shape::Cross)];

/// Z-width maps side by side: passive / stable / unstable markers and the predicted boundary.
pub fn zwidth_figure(title: &str, sample_period_s: f64, panels: &[ZWidthPanel<'_>]) -> Figure {
    let mut figure =
        Figure::new(title).columns(panels.len().max(1)).size(520 * panels.len().max(1) as u32, 520);
    for p in panels {
        let k_max = p.pairs.iter().map(|c| c.stiffness_nm_per_rad).fold(0.0, f64::max);
        let b_max = p.pairs.iter().map(|c| c.damping_nms_per_rad).fold(0.0, f64::max);
        // The y range leaves the top third free for the legend, off the grid of pairs.
        let mut panel =
            Panel::new("virtual stiffness K [N·m/rad]", "virtual damping B [N·m·s/rad]")
                .caption(p.label.clone())
                .legend(SeriesLabelPosition::UpperRight)
                .x_range(0.0, k_max.max(1e-9) * 1.02)
                .y_range(0.0, b_max.max(1e-9) * 1.5);
        for (class, color, shape) in ZWIDTH_STYLES {
            let points: Vec<(f64, f64)> = p
                .pairs
                .iter()
                .filter(|c| c.class == class)
                .map(|c| (c.stiffness_nm_per_rad, c.damping_nms_per_rad))
                .collect();
            if !points.is_empty() {
                panel = panel
                    .series(Series::points(class, points).color(color).shape(shape).marker_size(4));
            }
        }
        if let Some(b) = p.boundary_damping_nms_per_rad {
            // B = b − K T/2, drawn where it lies inside the plotted range.
            let k_end = (2.0 * b / sample_period_s).min(k_max);
            let line: Vec<(f64, f64)> = (0..=100)
                .map(|n| k_end * n as f64 / 100.0)
                .map(|k| (k, b - k * sample_period_s / 2.0))
                .collect();
            panel = panel.series(Series::dashed("b = K·T/2 + B", line).color(6));
        }
        figure = figure.panel(panel);
    }
    figure
}

/// The three panels of a Z-width map: the motor with the boundary of (2.2) at its physical damping
/// `b`, the motor + MR damper with the boundary of (2.4) at `b + b_c`, and the bidirectional brake.
pub fn zwidth_panels(map: &ZWidthMap) -> [ZWidthPanel<'static>; 3] {
    let b = map.config.physical_damping_nms_per_rad;
    let bc = map.config.controllable_damping_nms_per_rad;
    let pairs = |pick: fn(&ZWidthCell) -> Interaction| -> Vec<ClassifiedPair<'static>> {
        map.cells
            .iter()
            .map(|c| ClassifiedPair {
                stiffness_nm_per_rad: c.stiffness_nm_per_rad,
                damping_nms_per_rad: c.damping_nms_per_rad,
                class: pick(c).name(),
            })
            .collect()
    };
    [
        ZWidthPanel {
            label: format!("motor, b = {b} N·m·s/rad (2.2)"),
            pairs: pairs(|c| c.motor),
            boundary_damping_nms_per_rad: Some(b),
        },
        ZWidthPanel {
            label: format!("motor + MR damper, b + b_c = {} (2.4)", b + bc),
            pairs: pairs(|c| c.hybrid),
            boundary_damping_nms_per_rad: Some(b + bc),
        },
        ZWidthPanel {
            label: "bidirectional MR brake".into(),
            pairs: pairs(|c| c.brake),
            boundary_damping_nms_per_rad: None,
        },
    ]
}

/// Writes the Z-width map's three panels to `path` (SVG, or PNG by extension).
pub fn save_zwidth_plot(path: &Path, map: &ZWidthMap) -> Result<(), ReportError> {
    let period = map.config.sample_period_s;
    zwidth_figure(&format!("Z-width, T = {} ms", period * 1e3), period, &zwidth_panels(map))
        .save(path)
}

/// The Z-width summary: cells per class and device, and how many agree with (2.2) and (2.4).
pub fn zwidth_summary(map: &ZWidthMap) -> Value {
    let count = |f: &dyn Fn(&ZWidthCell) -> bool| map.cells.iter().filter(|c| f(c)).count();
    use Interaction as I;
    json!({
        "cells": map.cells.len(),
        "motor": {"passive": count(&|c| c.motor == I::Passive), "stable": count(&|c| c.motor == I::Stable),
                  "unstable": count(&|c| c.motor == I::Unstable),
                  "agree_with_2_2": count(&|c| (c.motor == I::Passive) == c.motor_predicted_passive)},
        "hybrid": {"passive": count(&|c| c.hybrid == I::Passive), "stable": count(&|c| c.hybrid == I::Stable),
                   "unstable": count(&|c| c.hybrid == I::Unstable),
                   "agree_with_2_4": count(&|c| (c.hybrid == I::Passive) == c.hybrid_predicted_passive)},
        "brake": {"passive": count(&|c| c.brake == I::Passive), "stable": count(&|c| c.brake == I::Stable),
                  "unstable": count(&|c| c.brake == I::Unstable)},
    })
}

/// The Z-width map as text (the CLI's default output): the grid, then per device the cells that
/// are passive, stable and unstable, and how many of the motor's and the hybrid device's cells
/// agree with the passivity conditions (2.2) and (2.4).
pub fn zwidth_text(map: &ZWidthMap) -> String {
    use Interaction as I;
    let c = &map.config;
    let count = |f: &dyn Fn(&ZWidthCell) -> bool| map.cells.iter().filter(|cell| f(cell)).count();
    let mut out = String::new();
    let _ = writeln!(
        out,
        "Z-width map: {} × {} (K, B) pairs, K 0–{} N·m/rad, B 0–{} N·m·s/rad, T = {} ms",
        c.stiffness_points,
        c.damping_points,
        c.stiffness_max_nm_per_rad,
        c.damping_max_nms_per_rad,
        c.sample_period_s * 1e3
    );
    let _ = writeln!(
        out,
        "  physical damping b = {} N·m·s/rad, controllable MR damping b_c = {} N·m·s/rad",
        c.physical_damping_nms_per_rad, c.controllable_damping_nms_per_rad
    );
    let _ = writeln!(out, "  {:<28} {:>8} {:>8} {:>8}", "device", "passive", "stable", "unstable");
    type ClassOf = fn(&ZWidthCell) -> Interaction;
    let devices: [(&str, ClassOf); 3] = [
        ("motor", |cell| cell.motor),
        ("hybrid (motor + MR damper)", |cell| cell.hybrid),
        ("bidirectional brake", |cell| cell.brake),
    ];
    for (name, class) in devices {
        let _ = writeln!(
            out,
            "  {name:<28} {:>8} {:>8} {:>8}",
            count(&|cell| class(cell) == I::Passive),
            count(&|cell| class(cell) == I::Stable),
            count(&|cell| class(cell) == I::Unstable)
        );
    }
    let total = map.cells.len();
    let motor = count(&|cell| (cell.motor == I::Passive) == cell.motor_predicted_passive);
    let hybrid = count(&|cell| (cell.hybrid == I::Passive) == cell.hybrid_predicted_passive);
    let _ = writeln!(out, "  motor agrees with (2.2) b > KT/2 + B in {motor} of {total} cells");
    let _ =
        writeln!(out, "  hybrid agrees with (2.4) b + b_c > KT/2 + B in {hybrid} of {total} cells");
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use mrbrake_sim::haptic::zwidth::{ZWidthConfig, sweep};
    use mrbrake_sim::haptic::{HapticConfig, Scenario, simulate};

    #[test]
    fn wall_report_and_history_come_from_the_run() {
        let mut config = HapticConfig::new(DeviceKind::Bidirectional, Scenario::PressWithdraw);
        config.duration_s = 0.2;
        let run = simulate(&config, true).unwrap();
        let text = wall_metrics_text(&run.metrics, 30.0);
        assert!(text.starts_with("device bidirectional, scenario press-withdraw\n"), "{text}");
        assert!(text.contains("  passive                    true"), "{text}");
        assert_eq!(text.lines().count(), 10);
        let trace = run.trace.as_ref().unwrap();
        let history = TimeHistory::from_trace("bidirectional", DeviceKind::Bidirectional, trace);
        assert_eq!(history.coils, 2);
        assert_eq!(history.time_s.len(), 200);
        assert_eq!(history.current_a[1].len(), trace.current_a[1].len());
    }

    #[test]
    fn zwidth_summary_counts_every_cell_once_per_device() {
        let config =
            ZWidthConfig { stiffness_points: 3, damping_points: 2, ..ZWidthConfig::default() };
        let map = sweep(&config, &mut mrbrake_observe::Silent).unwrap();
        let summary = zwidth_summary(&map);
        assert_eq!(summary["cells"], 6);
        for device in ["motor", "hybrid", "brake"] {
            let total: u64 = ["passive", "stable", "unstable"]
                .iter()
                .map(|class| summary[device][class].as_u64().unwrap())
                .sum();
            assert_eq!(total, 6, "{device}: {summary}");
        }
        let text = zwidth_text(&map);
        assert!(text.starts_with("Z-width map: 3 × 2 (K, B) pairs"), "{text}");
        assert!(text.contains("of 6 cells"), "{text}");
        let panels = zwidth_panels(&map);
        assert_eq!(panels[0].boundary_damping_nms_per_rad, Some(0.005));
        assert!(panels[2].pairs.iter().all(|p| p.class == "passive"));
    }

    #[test]
    fn figures_render_to_svg() {
        let t: Vec<f64> = (0..3000).map(|k| k as f64 * 1e-3).collect();
        let y: Vec<f64> = t.iter().map(|x| x.sin()).collect();
        let run = TimeHistory {
            label: "bidirectional",
            time_s: &t,
            angle_rad: &y,
            intended_rad: &y,
            wall_rad: &y,
            current_a: [&y, &y],
            coils: 2,
            device_torque_nm: &y,
            hand_torque_nm: &y,
        };
        let motor = TimeHistory { label: "motor", coils: 0, ..run };
        let svg = wall_comparison_figure("wall", &[run, motor]).to_svg().unwrap();
        assert!(svg.contains("bidirectional: coil currents"));
        assert!(svg.contains("no brake coil") && !svg.contains("motor: coil current"));
        // Every row shares its y range across the columns (the motor's torques are twice as
        // large here), and the current row starts at 0.
        let y2: Vec<f64> = y.iter().map(|v| 2.0 * v).collect();
        let motor = TimeHistory { device_torque_nm: &y2, ..motor };
        let figure = wall_comparison_figure("wall", &[run, motor]);
        for row in [0, 2] {
            assert_eq!(figure.panels[2 * row].y_range, figure.panels[2 * row + 1].y_range);
        }
        let (_, hi) = figure.panels[4].y_range.unwrap();
        assert!(hi > 1.99, "the bidirectional column shows the motor's 2 N·m: {hi}");
        assert!(figure.panels[2].y_range.unwrap().0.abs() < 1e-15);
        let pairs = vec![
            ClassifiedPair {
                stiffness_nm_per_rad: 0.0,
                damping_nms_per_rad: 0.0,
                class: "passive",
            },
            ClassifiedPair {
                stiffness_nm_per_rad: 50.0,
                damping_nms_per_rad: 0.01,
                class: "unstable",
            },
        ];
        let panel =
            ZWidthPanel { label: "motor".into(), pairs, boundary_damping_nms_per_rad: Some(0.005) };
        assert!(zwidth_figure("z", 1e-3, &[panel]).to_svg().unwrap().contains("motor"));
    }
}
