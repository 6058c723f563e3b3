//! A brake model in the simulators: the virtual rig's `[brake]` and the haptic device's two brakes.
//!
//! Each function returns notes that say what the model did not give and what was used instead
//! (e.g. the thesis's measured lag where the model has no dynamics), for the front end to show.

use mrbrake_control::{Branch, InverseModel};

use super::{BrakeModel, UnitBranches, UnitModel};
use crate::SimError;
use crate::haptic::{HapticConfig, TorqueLag};
use crate::rig::RigConfig;

/// Fractions of the branches' common torque range the rig's frequency-response demand is moved to
/// when the configured demand leaves the model's range: 10 %–90 % (the thesis's 0.5–3.5 N·m is
/// 9.5 %–91 % of the prototype's 0.15–3.84 N·m, §5.3.2).
pub const DEMAND_RANGE_FRACTIONS: (f64, f64) = (0.1, 0.9);

/// A note on how unit `k`'s branches were obtained.
fn branch_note(unit: &UnitModel, branches: &UnitBranches) -> Option<String> {
    let fit = branches.fit?;
    let t = &unit.static_curve.torque_nm;
    let span = t[t.len() - 1] - t[0];
    Some(format!(
        "unit {}: no hysteresis in the model: rising = falling = a degree-{} polynomial through the static curve + {} N·m seal friction (largest error {:.4} N·m, {:.2} % of the curve's span)",
        unit.unit,
        fit.degree,
        unit.off_state.seal_friction_nm,
        fit.max_error_nm,
        100.0 * fit.max_error_nm / span.max(f64::MIN_POSITIVE)
    ))
}

/// The haptic lag of a model's dynamics: `k / (a s² + b s + 1)` (the form of thesis (5.5)/(5.6)).
fn torque_lag(unit: &UnitModel) -> Result<Option<TorqueLag>, SimError> {
    let Some(dynamics) = &unit.dynamics else { return Ok(None) };
    let tf = dynamics.transfer_function()?;
    match (tf.numerator.as_slice(), tf.denominator.as_slice()) {
        ([k], [a, b, c]) if *c > 0.0 => {
            Ok(Some(TorqueLag { gain: k / c, a_s2: a / c, b_s: b / c }))
        }
        _ => Err(mrbrake_error::FieldError::new(
            format!("units[{}].dynamics", unit.unit - 1),
            "the haptic simulation runs lags k/(a s² + b s + 1) only",
        )
        .with_value(format!("{:?}/{:?}", tf.numerator, tf.denominator))
        .with_allowed("k/(a s² + b s + 1)")
        .into()),
    }
}

/// Runs the haptic device on `model`: brake 1 on unit 1, brake 2 on unit 2 (a single-unit model
/// drives both), in the plant and in the controller; the units' lags where the model has dynamics
/// (else the thesis's (5.5)/(5.6) stay), the viscous coefficient of unit 1 added to the device's
/// viscous friction for an anhysteretic model.
pub fn apply_to_haptic(
    model: &BrakeModel,
    config: &mut HapticConfig,
) -> Result<Vec<String>, SimError> {
    let mut notes = Vec::new();
    for k in 0..2 {
        let unit = model.unit(k as u32 + 1)?;
        let branches = unit.branches()?;
        if k == 0 || model.units.len() == 2 {
            notes.extend(branch_note(unit, &branches));
        }
        config.brakes[k].branches = branches.model;
        config.controller_models[k] = branches.model;
        match torque_lag(unit)? {
            Some(lag) => config.brakes[k].lag = lag,
            None => notes.push(format!(
                "brake {}: the model has no dynamics; the thesis prototype's measured lag ({}) is used",
                k + 1,
                if k == 0 { "5.5" } else { "5.6" }
            )),
        }
    }
    let unit1 = model.unit(1)?;
    if unit1.adds_off_state() {
        config.device_parameters.viscous_nms_per_rad += unit1.off_state.viscous_nm_s_per_rad;
    }
    config.validate()?;
    Ok(notes)
}

/// Puts unit `unit` of `model` on the virtual rig: its branches, maximum current, dynamics (else the
/// configured ones, thesis (5.5) by default) and, for an anhysteretic model, its viscous
/// coefficient. When the configured frequency-response demand leaves the range both branches
/// reach, it is moved to [`DEMAND_RANGE_FRACTIONS`] of that range (with a note).
pub fn apply_to_rig(
    model: &BrakeModel,
    unit: u32,
    config: &mut RigConfig,
) -> Result<Vec<String>, SimError> {
    let u = model.unit(unit)?;
    let branches = u.branches()?;
    let mut notes: Vec<String> = branch_note(u, &branches).into_iter().collect();
    let coefficients = |branch| {
        let c = branches.model.branch(branch).coefficients();
        let used = c.iter().rposition(|v| v.abs() > 0.0).map_or(1, |p| p + 1);
        c[..used].to_vec()
    };
    config.brake.rising = coefficients(Branch::Rising);
    config.brake.falling = coefficients(Branch::Falling);
    config.brake.current_max_a = u.current_max_a;
    config.brake.viscous_nm_s_per_rad =
        if u.adds_off_state() { u.off_state.viscous_nm_s_per_rad } else { 0.0 };
    match &u.dynamics {
        Some(d) => {
            let tf = d.transfer_function()?;
            config.brake.dynamics_numerator = tf.numerator;
            config.brake.dynamics_denominator = tf.denominator;
        }
        None => notes.push(format!(
            "unit {unit}: the model has no dynamics; the rig configuration's brake dynamics are used ({:?}/{:?})",
            config.brake.dynamics_numerator, config.brake.dynamics_denominator
        )),
    }
    notes.extend(fit_demand(&branches.model, config));
    config.characterization.step_a = config.characterization.step_a.min(u.current_max_a);
    config.validate("rig configuration with the brake model")?;
    Ok(notes)
}

/// Moves the frequency-response demand into the model's range when it leaves it.
fn fit_demand(model: &InverseModel, config: &mut RigConfig) -> Option<String> {
    let at = |branch, i| model.torque_nm(branch, i);
    let (i0, i1) = (model.current_min_a(), model.current_max_a());
    let lo = at(Branch::Rising, i0).max(at(Branch::Falling, i0));
    let hi = at(Branch::Rising, i1).min(at(Branch::Falling, i1));
    let f = &mut config.frequency_response;
    if f.torque_min_nm >= lo && f.torque_max_nm <= hi {
        return None;
    }
    let old = (f.torque_min_nm, f.torque_max_nm);
    f.torque_min_nm = lo + DEMAND_RANGE_FRACTIONS.0 * (hi - lo);
    f.torque_max_nm = lo + DEMAND_RANGE_FRACTIONS.1 * (hi - lo);
    Some(format!(
        "frequency response: the demand {:.4}..{:.4} N·m leaves the model's range {lo:.4}..{hi:.4} N·m; it is {:.4}..{:.4} N·m (10 %–90 % of the range)",
        old.0, old.1, f.torque_min_nm, f.torque_max_nm
    ))
}
