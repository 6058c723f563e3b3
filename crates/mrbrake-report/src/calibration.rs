//! The report of `mrbrake calibrate`: its JSON (the contract of issue 29: `parameters[]`,
//! `correlation`, `unidentifiable`, `residual_rms_before_Nm`, `residual_rms_after_Nm`, `noise_Nm`,
//! `evaluations`, `timings_s.total`, plus the compared curve) and its text.

use plotters::prelude::SeriesLabelPosition;
use serde_json::{Value, json};

use crate::chart::{Figure, Panel, Series, Shape};

use mrbrake_explore::calibrate::{Calibrated, FrequencyFit};
use mrbrake_sysid::frd::{Frd, MINUS_3_DB};

/// The JSON of a calibration.
pub fn json(c: &Calibrated) -> Value {
    let fit = &c.fit;
    let m = &c.measured;
    let curve: Vec<Value> = (0..m.current_a.len())
        .map(|k| {
            json!({
                "current_A": m.current_a[k],
                "measured_Nm": m.torque_nm[k],
                "rising_Nm": m.rising_nm[k],
                "falling_Nm": m.falling_nm[k],
                "predicted_before_Nm": c.predicted_before_nm[k],
                "predicted_after_Nm": c.predicted_after_nm[k],
            })
        })
        .collect();
    let weak: Vec<Value> = fit
        .identifiability
        .weak_directions
        .iter()
        .map(|d| {
            json!({
                "collinearity_index": finite(d.collinearity_index()),
                "loadings": d.loadings,
                "parameters": d.parameters.iter().map(|&j| c.parameters[j].name.clone()).collect::<Vec<_>>(),
            })
        })
        .collect();
    json!({
        "log": m.source,
        "parameters": c.parameters.iter().map(|p| json!({
            "name": p.name,
            "path": p.path,
            "unit": p.unit,
            "start": p.start,
            "estimate": p.estimate,
            "standard_error": finite(p.standard_error),
            "lower": p.lower,
            "upper": p.upper,
            "at_bound": p.at_bound,
        })).collect::<Vec<_>>(),
        "correlation": fit.correlation,
        "unidentifiable": c.unidentifiable,
        "weak_directions": weak,
        "residual_rms_before_Nm": c.torque_rms_before_nm,
        "residual_rms_after_Nm": c.torque_rms_after_nm,
        "frequency_response": c.frequency_response.as_ref().map(frequency_json),
        "noise_Nm": m.sample_noise_nm,
        "point_noise_Nm": m.point_noise_nm,
        "lack_of_fit": finite(c.lack_of_fit),
        "evaluations": fit.evaluations,
        "iterations": fit.iterations,
        "termination": fit.termination,
        "converged": fit.termination.converged(),
        "log_current_range_A": [m.current_range_a.0, m.current_range_a.1],
        "repetitions": m.repetitions,
        "curve": curve,
        "predictions": c.predictions,
        "calibrated": {
            "torque_at_max_current_Nm": c.analysis.torque.at_max_current_nm,
            "torque_off_Nm": c.analysis.torque.off_state_nm,
            "time_constant_s": c.analysis.coil.time_constant_s,
        },
        "timings_s": { "total": c.total_s },
    })
}

/// A number, or `null` where it is not finite (docs/CONVENTIONS.md: an infinite standard error is
/// a parameter the data do not determine).
fn finite(x: f64) -> Value {
    if x.is_finite() { json!(x) } else { Value::Null }
}

/// The text of a calibration: the parameters with their errors, the correlations, the groups the
/// data cannot separate, and the curve before and after.
pub fn text(c: &Calibrated, name: &str) -> String {
    let fit = &c.fit;
    let m = &c.measured;
    let mut out = format!(
        "{name}: calibrated to {} ({} repetitions, {:.3}–{:.3} A), {} evaluations, {} iterations \
         ({:?}), {:.1} s\n",
        m.source,
        m.repetitions,
        m.current_range_a.0,
        m.current_range_a.1,
        fit.evaluations,
        fit.iterations,
        fit.termination,
        c.total_s
    );
    out.push_str(&parameters_text(c));
    out.push_str(&format!(
        "residual RMS {:.5} N·m → {:.5} N·m; noise {:.5} N·m per sample, {:.5} N·m per compared \
         point; lack of fit {:.1} (1: the model explains the loop to within the noise)\n",
        c.torque_rms_before_nm,
        c.torque_rms_after_nm,
        m.sample_noise_nm,
        m.point_noise_nm,
        c.lack_of_fit
    ));
    out.push_str("current [A]  measured [N·m]  before [N·m]  after [N·m]\n");
    for k in 0..m.current_a.len() {
        out.push_str(&format!(
            "  {:>8.4}  {:>13.5}  {:>12.5}  {:>11.5}\n",
            m.current_a[k], m.torque_nm[k], c.predicted_before_nm[k], c.predicted_after_nm[k]
        ));
    }
    out.push_str(&predictions_text(c));
    out.push_str(&format!(
        "calibrated design: {:.4} N·m at the maximum current, {:.4} N·m off, coil time constant \
         {:.2} ms",
        c.analysis.torque.at_max_current_nm,
        c.analysis.torque.off_state_nm,
        c.analysis.coil.time_constant_s * 1e3
    ));
    out
}

/// The parameters with their errors, the correlations and the groups the data cannot separate.
fn parameters_text(c: &Calibrated) -> String {
    let mut out = String::from("parameters (start → estimate ± standard error, bounds):\n");
    for p in &c.parameters {
        let se = if p.standard_error.is_finite() {
            format!("{:.4e}", p.standard_error)
        } else {
            "not determined".into()
        };
        out.push_str(&format!(
            "  {:<28} {:.6} → {:.6} ± {se} {}  [{}, {}]{}\n",
            p.path,
            p.start,
            p.estimate,
            p.unit,
            p.lower,
            p.upper,
            if p.at_bound { "  (on a bound)" } else { "" }
        ));
    }
    if c.parameters.len() > 1 {
        out.push_str("correlation:\n");
        for (p, row) in c.parameters.iter().zip(&c.fit.correlation) {
            let cells: Vec<String> = row.iter().map(|r| format!("{r:>7.3}")).collect();
            out.push_str(&format!("  {:<28} {}\n", p.path, cells.join(" ")));
        }
    }
    for group in &c.unidentifiable {
        out.push_str(&format!(
            "unidentifiable together: {} — the static curve moves them alike; data that \
             separate them: a second quantity they affect differently (the coil's time constant \
             or a frequency response, the off-state torque, a measured gap)\n",
            group.join(", ")
        ));
    }
    out
}

/// The frequency response's misfit and bandwidths, and the study metrics before and after.
fn predictions_text(c: &Calibrated) -> String {
    let mut out = String::new();
    if let Some(f) = &c.frequency_response {
        let bw = |frd: &Frd| {
            bandwidth(frd).map_or("beyond the data".to_string(), |b| format!("{b:.1} rad/s"))
        };
        out.push_str(&format!(
            "frequency response ({}, bias {} A): RMS difference {:.4} → {:.4}; −3 dB bandwidth \
             measured {}, predicted {} → {}\n",
            f.source,
            f.bias_a,
            f.rms(&f.before),
            f.rms(&f.after),
            bw(&f.measured),
            bw(&f.before),
            bw(&f.after)
        ));
    }
    for p in &c.predictions {
        let show = |v: Option<f64>| v.map_or("—".to_string(), |v| format!("{v:.5}"));
        out.push_str(&format!(
            "predicted {}: {} before, {} calibrated\n",
            p.metric,
            show(p.before),
            show(p.after)
        ));
    }
    out
}

/// The calibration's figure: the measured branches and the middle of the loop the fit compares
/// with, the prediction at the start and at the estimate, and the residuals below.
pub fn figure(c: &Calibrated) -> Figure {
    let m = &c.measured;
    let curve = |values: &[f64]| -> Vec<(f64, f64)> {
        m.current_a.iter().copied().zip(values.iter().copied()).collect()
    };
    let residual = |values: &[f64]| -> Vec<(f64, f64)> {
        m.current_a
            .iter()
            .zip(values.iter().zip(&m.torque_nm))
            .map(|(&i, (p, t))| (i, p - t))
            .collect()
    };
    let loop_panel = Panel::new("current [A]", "torque [N·m]")
        .series(Series::dashed("measured, rising", curve(&m.rising_nm)).color(0))
        .series(Series::dashed("measured, falling", curve(&m.falling_nm)).color(1))
        .series(
            Series::points("measured, middle of the loop", curve(&m.torque_nm))
                .color(2)
                .shape(Shape::Ring)
                .marker_size(5),
        )
        .series(Series::line("predicted, start", curve(&c.predicted_before_nm)).color(3))
        .series(
            Series::line("predicted, calibrated", curve(&c.predicted_after_nm))
                .color(4)
                .line_width(2),
        )
        .legend(SeriesLabelPosition::LowerRight);
    let residuals = Panel::new("current [A]", "predicted − measured [N·m]")
        .series(Series::line_points("start", residual(&c.predicted_before_nm)).color(3))
        .series(Series::line_points("calibrated", residual(&c.predicted_after_nm)).color(4));
    let figure =
        Figure::new(format!("calibration to {}", m.source)).panel(loop_panel).panel(residuals);
    match &c.frequency_response {
        None => figure.row_weights(vec![2.0, 1.0]).size(900, 800),
        Some(f) => {
            let magnitude = |frd: &Frd| -> Vec<(f64, f64)> {
                frd.points.iter().map(|p| (p.omega_rad_s, p.magnitude_db())).collect()
            };
            let bode = Panel::new("angular frequency [rad/s]", "magnitude [dB]")
                .log_x()
                .series(
                    Series::points(format!("measured ({})", f.source), magnitude(&f.measured))
                        .color(2)
                        .shape(Shape::Ring)
                        .marker_size(4),
                )
                .series(Series::line("predicted, start", magnitude(&f.before)).color(3))
                .series(
                    Series::line("predicted, calibrated", magnitude(&f.after))
                        .color(4)
                        .line_width(2),
                )
                .legend(SeriesLabelPosition::LowerLeft);
            figure.panel(bode).row_weights(vec![2.0, 1.0, 1.5]).size(900, 1100)
        }
    }
}

/// The frequency-response block of the JSON: measured and predicted points and bandwidths.
/// The points are sysid's one serialisation of an `Frd` (`omega_rad_s`, `magnitude_dB`,
/// `phase_deg`, `re`, `im`).
fn frequency_json(f: &FrequencyFit) -> Value {
    let points = |frd: &Frd| serde_json::to_value(frd).unwrap_or(Value::Null);
    let bandwidth = |frd: &Frd| bandwidth(frd).map_or(Value::Null, |b| json!(b));
    json!({
        "frd": f.source,
        "bias_A": f.bias_a,
        "rms_before": f.rms(&f.before),
        "rms_after": f.rms(&f.after),
        "bandwidth_measured_rad_s": bandwidth(&f.measured),
        "bandwidth_before_rad_s": bandwidth(&f.before),
        "bandwidth_after_rad_s": bandwidth(&f.after),
        "measured": points(&f.measured),
        "predicted_before": points(&f.before),
        "predicted_after": points(&f.after),
    })
}

/// The −3 dB bandwidth of a response normalised to unit DC gain (the design crate's convention).
fn bandwidth(frd: &Frd) -> Option<f64> {
    frd.bandwidth_rad_s(MINUS_3_DB)
}
