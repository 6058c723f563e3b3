//! Haptic plots: side-by-side time histories of wall interactions (e.g. conventional vs bidirectional
//! brake: the sticky wall and its cure) and the Z-width map.
//!
//! The functions take plain slices, so this crate does not depend on the simulator.

use crate::chart::{Figure, Panel, Series, SeriesLabelPosition};

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
    /// Device torque on the shaft, Nm.
    pub device_torque_nm: &'a [f64],
    /// Hand torque on the shaft, Nm.
    pub hand_torque_nm: &'a [f64],
}

/// Largest number of points drawn per series (the SVG stays small; 1 kHz data is decimated).
const MAX_POINTS: usize = 1200;

fn decimated(time: &[f64], values: &[f64]) -> Vec<(f64, f64)> {
    let n = time.len().min(values.len());
    let stride = n.div_ceil(MAX_POINTS).max(1);
    (0..n).step_by(stride).map(|k| (time[k], values[k])).collect()
}

/// One column per run and three rows: angle (with intention and wall), coil currents, torques.
pub fn wall_comparison_figure(title: &str, runs: &[TimeHistory<'_>]) -> Figure {
    let mut figure =
        Figure::new(title).columns(runs.len().max(1)).size(520 * runs.len().max(1) as u32, 900);
    let mut rows: [Vec<Panel>; 3] = Default::default();
    for run in runs {
        let t = run.time_s;
        rows[0].push(
            Panel::new("time [s]", "angle [rad]")
                .caption(format!("{}: handle angle", run.label))
                .legend(SeriesLabelPosition::LowerRight)
                .series(Series::line("handle", decimated(t, run.angle_rad)).color(0))
                .series(Series::dashed("intended", decimated(t, run.intended_rad)).color(6))
                .series(Series::dashed("wall", decimated(t, run.wall_rad)).color(1)),
        );
        rows[1].push(
            Panel::new("time [s]", "current [A]")
                .caption(format!("{}: coil currents", run.label))
                .legend(SeriesLabelPosition::UpperRight)
                .series(
                    Series::line("brake 1 (resists +)", decimated(t, run.current_a[0])).color(0),
                )
                .series(
                    Series::line("brake 2 (resists −)", decimated(t, run.current_a[1])).color(1),
                ),
        );
        rows[2].push(
            Panel::new("time [s]", "torque [N·m]")
                .caption(format!("{}: torques on the shaft", run.label))
                .legend(SeriesLabelPosition::LowerLeft)
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

/// Z-width maps side by side: passive / stable / unstable markers and the predicted boundary.
pub fn zwidth_figure(title: &str, sample_period_s: f64, panels: &[ZWidthPanel<'_>]) -> Figure {
    let mut figure =
        Figure::new(title).columns(panels.len().max(1)).size(520 * panels.len().max(1) as u32, 520);
    for p in panels {
        let k_max = p.pairs.iter().map(|c| c.stiffness_nm_per_rad).fold(0.0, f64::max);
        let b_max = p.pairs.iter().map(|c| c.damping_nms_per_rad).fold(0.0, f64::max);
        let mut panel =
            Panel::new("virtual stiffness K [N·m/rad]", "virtual damping B [N·m·s/rad]")
                .caption(p.label.clone())
                .legend(SeriesLabelPosition::UpperRight)
                .x_range(0.0, k_max.max(1e-9) * 1.02)
                .y_range(0.0, b_max.max(1e-9) * 1.05);
        for (class, color) in [("passive", 2), ("stable", 4), ("unstable", 1)] {
            let points: Vec<(f64, f64)> = p
                .pairs
                .iter()
                .filter(|c| c.class == class)
                .map(|c| (c.stiffness_nm_per_rad, c.damping_nms_per_rad))
                .collect();
            if !points.is_empty() {
                panel = panel.series(Series::points(class, points).color(color));
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

#[cfg(test)]
mod tests {
    use super::*;

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
            device_torque_nm: &y,
            hand_torque_nm: &y,
        };
        let svg = wall_comparison_figure("wall", &[run, run]).to_svg().unwrap();
        assert!(svg.contains("bidirectional: coil currents"));
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
