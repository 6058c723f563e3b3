//! Presentation of a brake's predicted dynamics ([`mrbrake_design::response`]): the text summary,
//! the frequency response as an FRD CSV file (`mrbrake tfest` reads it), and the plots (step
//! response; Bode diagram with, for the embedded thesis brake, its measured transfer functions
//! (5.5) and (5.6)).

use std::fmt::Write as _;
use std::path::Path;

use mrbrake_design::response::Response;

use crate::ReportError;
use crate::atomic::write_atomic;
use crate::bode::{BodeCurve, save_bode};
use crate::chart::{Figure, Panel, Series, SeriesLabelPosition};

/// The thesis's measured transfer functions `1/(a s² + b s + 1)` scaled by `k`: (5.5) first brake,
/// (5.6) second brake (Karabulut 2017, 5.3.2).
pub const THESIS_TRANSFER_FUNCTIONS: [(&str, f64, f64, f64); 2] = [
    ("thesis (5.5), brake 1", 1.0, 1.791e-5, 0.01702),
    ("thesis (5.6), brake 2", 0.9818, 2.309e-5, 0.01726),
];

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
    let _ = writeln!(s, "  omega [rad/s]  magnitude [dB]  phase [deg]");
    for p in r.frequency_response.iter().step_by(5) {
        let _ = writeln!(
            s,
            "  {:>13.3}  {:>14.2}  {:>11.2}",
            p.omega_rad_s, p.magnitude_db, p.phase_deg
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
    t.map_or("not reached".into(), |t| format!("{:.2} ms", t * 1e3))
}

/// The frequency response as FRD CSV (`omega_rad_s,re,im,magnitude_dB,phase_deg`), atomically.
pub fn write_frd(r: &Response, path: &Path) -> Result<(), ReportError> {
    let mut csv = String::from("omega_rad_s,re,im,magnitude_dB,phase_deg\n");
    for p in &r.frequency_response {
        let _ =
            writeln!(csv, "{},{},{},{},{}", p.omega_rad_s, p.re, p.im, p.magnitude_db, p.phase_deg);
    }
    write_atomic(path, csv.as_bytes())
}

/// `(ω, dB, deg)` of `k/(a s² + b s + 1)` at `omegas`.
pub fn second_order_points(k: f64, a: f64, b: f64, omegas: &[f64]) -> Vec<(f64, f64, f64)> {
    omegas
        .iter()
        .map(|&w| {
            let (re, im) = (1.0 - a * w * w, b * w);
            let magnitude = k / re.hypot(im);
            (w, 20.0 * magnitude.log10(), -im.atan2(re).to_degrees())
        })
        .collect()
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

/// The Bode curves: the prediction, and the thesis's measured transfer functions when `thesis`.
pub fn bode_curves(r: &Response, thesis: bool) -> Vec<BodeCurve> {
    let predicted: Vec<(f64, f64, f64)> =
        r.frequency_response.iter().map(|p| (p.omega_rad_s, p.magnitude_db, p.phase_deg)).collect();
    let omegas: Vec<f64> = predicted.iter().map(|p| p.0).collect();
    let mut curves =
        vec![BodeCurve { label: "predicted".into(), points: predicted, markers: false }];
    if thesis {
        for (label, k, a, b) in THESIS_TRANSFER_FUNCTIONS {
            let points = second_order_points(k, a, b, &omegas);
            curves.push(BodeCurve { label: label.into(), points, markers: false });
        }
    }
    curves
}

/// The Bode title.
pub const BODE_TITLE: &str = "torque per current, normalised";

/// Writes `step_response.svg` and `bode.svg` into `dir` (with the thesis's measured transfer
/// functions when `thesis` is true).
pub fn write_plots(r: &Response, dir: &Path, thesis: bool) -> Result<(), ReportError> {
    step_figure(r).save(&dir.join("step_response.svg"))?;
    save_bode(&dir.join("bode.svg"), BODE_TITLE, &bode_curves(r, thesis))
}
