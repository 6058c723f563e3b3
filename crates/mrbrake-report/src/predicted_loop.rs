//! The report of a design's predicted hysteresis loop (`mrbrake analyze --hysteresis`): the
//! analysis JSON with a `hysteresis` object and the remanent torque in its off-state breakdown,
//! the loop's text, and its figure (the branches over the program's path).

use std::path::Path;

use mrbrake_design::analysis::Analysis;
use mrbrake_design::forc::ForcSet;
use mrbrake_design::hysteresis::HysteresisLoop;
use serde_json::Value;

use crate::ReportError;
use crate::chart::{Figure, GREY, Panel, Series, SeriesLabelPosition, Shape};

/// The analysis with the loop's remanent torque in `torque_off` (its term and total).
pub fn with_remanence(analysis: &Analysis, predicted: &HysteresisLoop) -> Analysis {
    let mut with = analysis.clone();
    with.torque_off = predicted.off_state_with_remanence(&analysis.torque_off);
    with
}

/// `analyze --json` with the loop: the analysis (its off-state breakdown with the remanent torque)
/// and a `hysteresis` object (the loop's fields).
pub fn json(analysis: &Analysis, predicted: &HysteresisLoop) -> Result<Value, ReportError> {
    let mut value = serde_json::to_value(with_remanence(analysis, predicted))
        .map_err(|e| ReportError::Data(format!("analysis JSON: {e}")))?;
    let object = value
        .as_object_mut()
        .ok_or_else(|| ReportError::Data("analysis JSON is not an object".into()))?;
    let hysteresis = serde_json::to_value(predicted)
        .map_err(|e| ReportError::Data(format!("hysteresis JSON: {e}")))?;
    object.insert("hysteresis".into(), hysteresis);
    Ok(value)
}

/// The loop's lines of the analysis text.
pub fn text(predicted: &HysteresisLoop) -> String {
    let b = &predicted.branches;
    let mut out = format!(
        "\nHysteresis loop (peak {:.3} A, {} currents per leg)\n  material model: {}\n",
        predicted.peak_current_a,
        b.current_a.len() - 1,
        predicted.material_model
    );
    for s in &predicted.steels {
        out.push_str(&format!(
            "  {}: Hc {:.0} A/m, Br {:.3} T, trust {} ({})\n",
            s.material, s.coercivity_a_per_m, s.remanence_t, s.trust, s.method
        ));
    }
    out.push_str(&format!(
        "  remanent torque at 0 A after the peak  {:.4} N·m\n  loop width at {:.3} A (unipolar)    \
         {:.4} N·m\n  loop width at {:.3} A (bipolar)     {:.4} N·m\n",
        predicted.remanent_torque_nm,
        0.5 * predicted.peak_current_a,
        predicted.width_at_mid_current_nm,
        0.5 * predicted.peak_current_a,
        predicted.bipolar_width_at_mid_current_nm
    ));
    out.push_str(&format!(
        "  steel loss per bipolar cycle {:.3e} J; largest |B| across a point's axis {:.3} T\n",
        predicted.dissipated_per_bipolar_cycle_j, predicted.max_perpendicular_b_t
    ));
    out.push_str("  current [A]   rising [N·m]   falling [N·m]   bipolar rising [N·m]\n");
    let stride = (b.current_a.len() / 10).max(1);
    for k in (0..b.current_a.len()).step_by(stride) {
        out.push_str(&format!(
            "  {:>10.3}   {:>12.4}   {:>13.4}   {:>20.4}\n",
            b.current_a[k], b.rising_nm[k], b.falling_nm[k], b.bipolar_rising_nm[k]
        ));
    }
    let iterations: usize = predicted.path.iter().map(|p| p.newton_iterations).sum();
    out.push_str(&format!(
        "  {} solves, {} Newton iterations, {:.2} s\n",
        predicted.path.len() - 1,
        iterations,
        predicted.timings_s.total
    ));
    out
}

/// The loop's figure: the program's path in grey, the branches as lines.
pub fn figure(predicted: &HysteresisLoop) -> Figure {
    let b = &predicted.branches;
    let branch = |values: &[f64]| -> Vec<(f64, f64)> {
        b.current_a.iter().copied().zip(values.iter().copied()).collect()
    };
    let path: Vec<(f64, f64)> = predicted.path.iter().map(|p| (p.current_a, p.torque_nm)).collect();
    let panel = Panel::new("current [A]", "torque [N·m]")
        .series(Series::points("program", path).color(GREY).shape(Shape::Circle).marker_size(2))
        .series(Series::line("rising (from remanence)", branch(&b.rising_nm)).color(0))
        .series(Series::line("falling", branch(&b.falling_nm)).color(1))
        .series(Series::dashed("rising (after −peak)", branch(&b.bipolar_rising_nm)).color(2))
        .legend(SeriesLabelPosition::LowerRight);
    Figure::new("predicted torque–current hysteresis").panel(panel).size(900, 640)
}

/// Writes the loop's figure to `path`, atomically.
pub fn save_figure(path: &Path, predicted: &HysteresisLoop) -> Result<(), ReportError> {
    figure(predicted).save(path)
}

/// One line on the FORC set behind a saved Preisach model: its size, time and how far the FEA is
/// from a Preisach system (`(projected weight, largest node change)` of the identification, N·m).
pub fn forc_line(forcs: &ForcSet, (projected_nm, projection_nm): (f64, f64)) -> String {
    format!(
        "brake model hysteresis: Preisach from {} FORCs on {} levels 0–{} A ({} steps per level, \
         {} field solves in {} chain(s)): {:.1} s wall, {:.1} s summed over the chains; \
         wiping-out defect {:.2e} N·m; non-Preisach part projected out: negative weights \
         {:.2e} N·m, largest node change {:.2e} N·m",
        forcs.levels_a.len() - 1,
        forcs.levels_a.len() - 1,
        forcs.levels_a.last().copied().unwrap_or(0.0),
        forcs.steps_per_level,
        forcs.solves,
        forcs.chains,
        forcs.timings_s.wall,
        forcs.timings_s.chains,
        forcs.wiping_out_defect_nm,
        projected_nm,
        projection_nm
    )
}

/// The FORC set's summary for `analyze --json` (key `forc`): grid, work, timings and how far the
/// FEA is from a Preisach system (`(projected weight, largest node change)`, N·m).
pub fn forc_json(forcs: &ForcSet, (projected_nm, projection_nm): (f64, f64)) -> Value {
    serde_json::json!({
        "levels": forcs.levels_a.len() - 1,
        "levels_A": forcs.levels_a,
        "steps_per_level": forcs.steps_per_level,
        "chains": forcs.chains,
        "solves": forcs.solves,
        "wiping_out_defect_Nm": forcs.wiping_out_defect_nm,
        "projected_weight_Nm": projected_nm,
        "largest_node_change_Nm": projection_nm,
        "timings_s": forcs.timings_s,
    })
}
