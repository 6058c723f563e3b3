//! The report of the demagnetisation scan (`mrbrake analyze --hysteresis --demag`): its lines of the
//! analysis text and its place in the JSON (`hysteresis.demagnetisation`).

use mrbrake_design::demag::{Candidate, Demagnetisation, Release};
use serde_json::Value;

use crate::ReportError;

/// The release of a candidate in words.
fn release_words(release: &Release) -> String {
    match release {
        Release::None => "no release (0 A)".into(),
        Release::ReversePulse { amplitude_a } => format!("reverse pulse {amplitude_a:.3} A"),
        Release::DecayingAc { first_amplitude_a, decay_ratio, half_cycles } => format!(
            "decaying AC {first_amplitude_a:.3} A, ratio {decay_ratio}, {half_cycles} half cycles"
        ),
    }
}

/// One candidate's line.
fn line(c: &Candidate) -> String {
    format!(
        "  {:<46} {:>8.4} N·m  {:>5.1} %\n",
        release_words(&c.release),
        c.remanent_torque_nm,
        100.0 * c.remanence_fraction
    )
}

/// The scan's lines of the analysis text.
pub fn text(d: &Demagnetisation) -> String {
    let mut out = format!(
        "\nDemagnetising release after {:.3} A (reverse currents up to {:.3} A; {})\n  \
         release                                        remanent torque at 0 A\n",
        d.peak_current_a, d.reverse_limit_a, d.model
    );
    let mut sorted: Vec<&Candidate> = d.candidates.iter().collect();
    sorted.sort_by(|a, b| {
        let amplitude = |c: &Candidate| match c.release {
            Release::None => -1.0,
            Release::ReversePulse { amplitude_a } => amplitude_a,
            Release::DecayingAc { .. } => f64::INFINITY,
        };
        amplitude(a).total_cmp(&amplitude(b))
    });
    for c in sorted {
        out.push_str(&line(c));
    }
    out.push_str(&format!(
        "  chosen: {} leaves {:.4} N·m ({:.1} % of {:.4} N·m)\n",
        release_words(&d.chosen_pulse.release),
        d.chosen_pulse.remanent_torque_nm,
        100.0 * d.chosen_pulse.remanence_fraction,
        d.remanent_torque_without_nm
    ));
    let h = &d.half_peak_check;
    out.push_str(&format!(
        "  check at {:.3} A with half the pulse: {:.4} N·m without, {:.4} N·m after ({:.1} %)\n  \
         {} field solves, {:.1} s\n",
        h.peak_current_a,
        h.no_release_nm,
        h.half_pulse_nm,
        if h.no_release_nm > 0.0 { 100.0 * h.half_pulse_nm / h.no_release_nm } else { 0.0 },
        d.candidates.iter().map(|c| c.solves).sum::<usize>(),
        d.seconds
    ));
    out
}

/// Adds the scan to `analyze --json`'s value (made by
/// [`crate::predicted_loop::json`]) as `hysteresis.demagnetisation`.
pub fn insert_json(value: &mut Value, d: &Demagnetisation) -> Result<(), ReportError> {
    let scan = serde_json::to_value(d)
        .map_err(|e| ReportError::Data(format!("demagnetisation JSON: {e}")))?;
    let hysteresis = value
        .get_mut("hysteresis")
        .and_then(Value::as_object_mut)
        .ok_or_else(|| ReportError::Data("analysis JSON has no hysteresis object".into()))?;
    hysteresis.insert("demagnetisation".into(), scan);
    Ok(())
}
