//! Presentation of a brake's predicted dynamics ([`mrbrake_design::response`]): the text summary
//! and the plots (step response; Bode diagram with, for the embedded thesis brake, its measured
//! transfer functions (5.5) and (5.6); the eddy-current density map at a chosen instant). The
//! frequency response's FRD CSV file (`mrbrake tfest` reads it) is sysid's one writer,
//! [`mrbrake_sysid::frd::Frd::to_csv`].

use std::fmt::Write as _;
use std::path::Path;

use mrbrake_design::response::{EddyField, Response};
use mrbrake_sim::haptic::TorqueLag;
use mrbrake_sysid::frd::Frd;

use crate::ReportError;
use crate::bode::{BodeCurve, save_bode};
use crate::chart::{Figure, Panel, Series, SeriesLabelPosition};
use crate::field_map::{ScalarMap, Window, save_scalar_map, window_above};

/// The thesis's measured transfer functions `k/(a s² + b s + 1)` with their labels: (5.5) first
/// brake, (5.6) second brake (Karabulut 2017, 5.3.2), the haptic plant's lags.
pub const THESIS_TRANSFER_FUNCTIONS: [(&str, TorqueLag); 2] =
    [("thesis (5.5), brake 1", TorqueLag::BRAKE_1), ("thesis (5.6), brake 2", TorqueLag::BRAKE_2)];

/// The text summary.
pub fn text(r: &Response, source: &str) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "{} ({source})", r.name);
    let _ = writeln!(
        s,
        "flux-path conductivity {:.3} MS/m ({}); fluid lag {:.3} ms; {} drive; mesh {} nodes\n",
        r.flux_path_conductivity_s_per_m / 1e6,
        r.conductivity_source,
        r.fluid_lag_s * 1e3,
        match r.drive {
            mrbrake_design::response::ResponseDrive::Current => "current",
            mrbrake_design::response::ResponseDrive::Voltage => "voltage",
        },
        r.nodes
    );
    for step in &r.step {
        let first = step.current_a.first().copied().unwrap_or(0.0);
        let last = step.current_a.last().copied().unwrap_or(0.0);
        let _ = writeln!(
            s,
            "step response, direction {} ({first:.3} A -> {last:.3} A): torque {:.4} -> {:.4} N·m, \
             t63 {}, t90 {} ({} steps, {} rejected)",
            step.direction,
            step.torque_nm.first().copied().unwrap_or(0.0),
            step.torque_nm.last().copied().unwrap_or(0.0),
            ms(step.t63_s),
            ms(step.t90_s),
            step.steps[0],
            step.steps[1]
        );
    }
    let _ = writeln!(
        s,
        "\nsmall-signal torque/current at {:.3} A bias: DC gain {:.4} N·m/A, bandwidth (-3 dB) {}",
        r.bias_a,
        r.dc_gain_nm_per_a,
        r.bandwidth_rad_s.map_or("above the highest frequency".into(), |w| format!("{w:.1} rad/s"))
    );
    if let Some(d2) = &r.direction_2 {
        let _ = writeln!(
            s,
            "direction 2 (its own coils and gaps): DC gain {:.4} N·m/A, bandwidth (-3 dB) {}",
            d2.dc_gain_nm_per_a,
            d2.bandwidth_rad_s
                .map_or("above the highest frequency".into(), |w| format!("{w:.1} rad/s"))
        );
    }
    let _ = writeln!(s, "  omega [rad/s]  magnitude [dB]  phase [deg] (direction 1)");
    for p in r.frequency_response.points.iter().step_by(5) {
        let _ = writeln!(
            s,
            "  {:>13.3}  {:>14.2}  {:>11.2}",
            p.omega_rad_s,
            p.magnitude_db(),
            p.phase_deg()
        );
    }
    let _ = writeln!(s, "  (every 5th point; --json or --frd for all)");
    let _ = write!(
        s,
        "\ntimings: step {:.2} s, frequency {:.2} s, total {:.2} s",
        r.timings_s.step, r.timings_s.frequency, r.timings_s.total
    );
    s
}

fn ms(t: Option<f64>) -> String {
    t.map_or("not reached or not resolved by the steps".into(), |t| format!("{:.2} ms", t * 1e3))
}

/// The step-response figure (torque against time, each direction; the second dashed, as the
/// two nearly coincide), the legend in the lower right, which a step leaves empty.
pub fn step_figure(r: &Response) -> Figure {
    let mut panel = Panel::new("time [ms]", "torque [N·m]").legend(SeriesLabelPosition::LowerRight);
    for (k, step) in r.step.iter().enumerate() {
        let points = step.time_s.iter().zip(&step.torque_nm).map(|(t, q)| (t * 1e3, *q)).collect();
        let label = format!("direction {}", step.direction);
        let series =
            if k == 0 { Series::line(label, points) } else { Series::dashed(label, points) };
        panel = panel.series(series.color(k));
    }
    Figure::new("predicted torque step response").panel(panel)
}

/// The Bode curves: the prediction, and the thesis's measured transfer functions at the same
/// frequencies when `thesis`.
pub fn bode_curves(r: &Response, thesis: bool) -> Result<Vec<BodeCurve>, ReportError> {
    let predicted = r.frequency_response.clone();
    let omegas: Vec<f64> = predicted.omegas().collect();
    let mut curves =
        vec![BodeCurve { label: "predicted".into(), response: predicted, markers: false }];
    if thesis {
        for (label, lag) in THESIS_TRANSFER_FUNCTIONS {
            let g = lag.transfer_function()?;
            let response = Frd::sample(&omegas, |w| g.response(w));
            curves.push(BodeCurve { label: label.into(), response, markers: false });
        }
    }
    Ok(curves)
}

/// The Bode title.
pub const BODE_TITLE: &str = "torque per current, normalised";

/// Writes `step_response.svg` and `bode.svg` into `dir` (with the thesis's measured transfer
/// functions when `thesis` is true), and `eddy_current.svg` when the response kept an
/// eddy-current field; PNG copies too with `png`.
pub fn write_plots(r: &Response, dir: &Path, thesis: bool, png: bool) -> Result<(), ReportError> {
    let eddy = r.eddy.as_ref().map(EddyMap::new).transpose()?;
    let (step, bode) = (step_figure(r), bode_curves(r, thesis)?);
    for ext in if png { &["svg", "png"][..] } else { &["svg"][..] } {
        step.save(&dir.join(format!("step_response.{ext}")))?;
        save_bode(&dir.join(format!("bode.{ext}")), BODE_TITLE, &bode)?;
        if let Some(map) = &eddy {
            save_scalar_map(&map.scalar_map(), &dir.join(format!("eddy_current.{ext}")))?;
        }
    }
    Ok(())
}

/// The conducting parts of an [`EddyField`], as a mesh of their own: every region keeps its own
/// copy of the nodes on its boundary, since `J = −σ ∂A/∂t` jumps with `σ` between parts; `J` in
/// A/mm², shown in the window where it flows.
pub struct EddyMap {
    /// Title: the instant and the direction.
    pub title: String,
    /// Node coordinates `[r, z]` (m).
    pub nodes: Vec<[f64; 2]>,
    /// Triangles.
    pub triangles: Vec<[usize; 3]>,
    /// Region tag per triangle.
    pub region_tags: Vec<u32>,
    /// `J_φ` (A/mm²) per node.
    pub j_a_per_mm2: Vec<f64>,
    /// The window shown: the triangles where `|J|` is at least [`EDDY_FRACTION`] of its largest,
    /// with the field map's margins ([`window_above`]).
    pub window: Window,
}

/// The share of the largest `|J|` that puts a triangle inside the eddy-current map's window
/// (lower than the |B| map's: the steel's currents are a few per cent of a conducting bobbin's).
pub const EDDY_FRACTION: f64 = 0.002;

impl EddyMap {
    /// The map of `field`.
    pub fn new(field: &EddyField) -> Result<Self, ReportError> {
        let mut map = Self {
            title: format!(
                "eddy-current density J_φ, direction {} step at t = {:.2} ms",
                field.direction,
                field.time_s * 1e3
            ),
            nodes: Vec::new(),
            triangles: Vec::new(),
            region_tags: Vec::new(),
            j_a_per_mm2: Vec::new(),
            window: ([0.0; 2], [0.0; 2]),
        };
        let mut index = std::collections::HashMap::new();
        let mut magnitude = Vec::new();
        for (t, tri) in field.triangles.iter().enumerate() {
            if !field.conducting[t] {
                continue;
            }
            let tag = field.region_tags[t];
            let mut local = [0; 3];
            for (k, &v) in tri.iter().enumerate() {
                local[k] = *index.entry((v, tag)).or_insert_with(|| {
                    map.nodes.push(field.nodes[v]);
                    map.j_a_per_mm2.push(field.j_a_per_m2[t][k] * 1e-6);
                    map.nodes.len() - 1
                });
            }
            map.triangles.push(local);
            map.region_tags.push(tag);
            magnitude.push(field.j_a_per_m2[t].iter().map(|j| j.abs()).sum::<f64>() / 3.0);
        }
        if map.triangles.is_empty() {
            return Err(ReportError::Data("eddy-current map: no conducting part".into()));
        }
        map.window = window_above(&map.nodes, &map.triangles, &magnitude, EDDY_FRACTION);
        Ok(map)
    }

    /// The map to draw.
    pub fn scalar_map(&self) -> ScalarMap<'_> {
        ScalarMap {
            title: &self.title,
            nodes: &self.nodes,
            triangles: &self.triangles,
            region_tags: &self.region_tags,
            values: &self.j_a_per_mm2,
            label: "J_φ [A/mm²]",
            levels: 8,
            window: Some(self.window),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two unit squares side by side, each of two triangles: region 1 (r 0..1 mm) conducts with
    /// J = −2 A/mm², region 2 (r 1..2 mm) with J = −1 A/mm²; region 3 (r 2..3 mm) does not conduct.
    fn field() -> EddyField {
        let mm = 1e-3;
        let nodes: Vec<[f64; 2]> =
            (0..4).flat_map(|i| [[i as f64 * mm, 0.0], [i as f64 * mm, mm]]).collect();
        let square = |i: usize| [[2 * i, 2 * i + 2, 2 * i + 3], [2 * i, 2 * i + 3, 2 * i + 1]];
        let triangles: Vec<[usize; 3]> = (0..3).flat_map(square).collect();
        let j = [-2e6, -1e6, 0.0];
        EddyField {
            time_s: 2e-3,
            direction: 1,
            nodes,
            triangles,
            region_tags: vec![1, 1, 2, 2, 3, 3],
            conducting: vec![true, true, true, true, false, false],
            j_a_per_m2: (0..6).map(|t| [j[t / 2]; 3]).collect(),
        }
    }

    #[test]
    fn eddy_map_keeps_the_jump_between_parts_and_leaves_out_non_conductors() {
        let map = EddyMap::new(&field()).unwrap();
        // Region 1's four nodes and region 2's four (the shared edge's two nodes twice).
        assert_eq!(map.triangles.len(), 4);
        assert_eq!(map.nodes.len(), 8);
        let at_interface: Vec<f64> = map
            .nodes
            .iter()
            .zip(&map.j_a_per_mm2)
            .filter(|(p, _)| (p[0] - 1e-3).abs() < 1e-12)
            .map(|(_, j)| *j)
            .collect();
        assert_eq!(at_interface.len(), 4);
        assert!(at_interface.iter().any(|j| (j + 2.0).abs() < 1e-12));
        assert!(at_interface.iter().any(|j| (j + 1.0).abs() < 1e-12));
        assert!(map.title.contains("t = 2.00 ms") && map.title.contains("direction 1"));
        let svg = crate::field_map::scalar_map_svg(&map.scalar_map()).unwrap();
        assert!(svg.contains("J_φ [A/mm²]"));
    }

    #[test]
    fn an_eddy_field_without_conductors_is_an_error() {
        let mut f = field();
        f.conducting = vec![false; 6];
        assert!(EddyMap::new(&f).is_err());
    }
}
