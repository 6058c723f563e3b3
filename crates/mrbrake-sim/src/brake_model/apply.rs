//! A brake model in the simulators: the virtual rig's `[brake]` and the haptic device's two brakes.
//!
//! Each function returns notes that say what the model did not give and what was used instead
//! (e.g. the thesis's measured lag where the model has no dynamics), for the front end to show.

use mrbrake_control::{Branch, InverseModel};

use super::{BrakeModel, UnitBranches, UnitModel};
use crate::SimError;
use crate::haptic::brake::PreisachBrake;
use crate::haptic::{HapticConfig, TorqueLag};
use crate::rig::RigConfig;

/// Fractions of the branches' common torque range the rig's frequency-response demand is moved to
/// when the configured demand leaves the model's range: 10 %–90 % (the thesis's 0.5–3.5 N·m is
/// 9.5 %–91 % of the prototype's 0.15–3.84 N·m, §5.3.2).
pub const DEMAND_RANGE_FRACTIONS: (f64, f64) = (0.1, 0.9);

/// A note on how unit `k`'s branches were obtained.
fn branch_note(unit: &UnitModel, branches: &UnitBranches) -> Option<String> {
    let fit = branches.fit?;
    if let Some(table) = unit.hysteresis.everett() {
        return Some(format!(
            "unit {}: Preisach hysteresis ({} levels); the controller's branches are its major loop fitted by degree-{} polynomials + {} N·m seal friction (largest error {:.4} N·m)",
            unit.unit,
            table.levels(),
            fit.degree,
            unit.off_state.seal_friction_nm,
            fit.max_error_nm
        ));
    }
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
/// drives both), in the plant and in the controller (a unit with a `preisach` table: the plant
/// runs the Preisach model itself, the controller its major loop's fitted branches,
/// [`crate::haptic::brake`]); the units' lags where the model has dynamics
/// (else the thesis's (5.5)/(5.6) stay), the viscous coefficient of unit 1 added to the device's
/// viscous friction for an anhysteretic model, and the device's inertia `J` the model's rotor
/// inertia ([`rotor_inertia`]).
///
/// The device's `J` is the rotating inertia engaged per direction (thesis §4.3), 54.8 kg·mm² by
/// default: the thesis prototype's rotor. A model that states its rotor inertia replaces it, so a
/// lighter rotor is felt; the simulator has one `J` for both directions, so a bidirectional model
/// whose two rotors differ gives the larger (the heavier direction, conservative for free motion;
/// a note says so). A model without it (a version-1 file) keeps the default, with a note.
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
        config.brakes[k].preisach = match unit.hysteresis.everett() {
            Some(table) => {
                let friction_nm = unit.off_state.seal_friction_nm;
                let plant = PreisachBrake::from_table(&table, friction_nm).map_err(|e| {
                    mrbrake_error::FieldError::new(
                        format!("units[{}].hysteresis", unit.unit - 1),
                        e.to_string(),
                    )
                })?;
                Some(plant)
            }
            None => None,
        };
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
    match rotor_inertia(model) {
        Some((inertia, note)) => {
            config.device_parameters.inertia_kg_m2 = inertia;
            notes.extend(note);
        }
        None => notes.push(format!(
            "the model gives no rotor inertia (a version-1 file): the device keeps its {:.1} kg·mm²",
            config.device_parameters.inertia_kg_m2 * 1e6
        )),
    }
    config.validate()?;
    Ok(notes)
}

/// The rotor inertia the haptic device runs with (see [`apply_to_haptic`]): the largest of the
/// units' when every unit states one, with a note when they differ; `None` when a unit has none.
pub fn rotor_inertia(model: &BrakeModel) -> Option<(f64, Option<String>)> {
    let inertias: Vec<f64> =
        model.units.iter().map(|u| u.rotor_inertia_kg_m2).collect::<Option<_>>()?;
    let largest = inertias.iter().copied().fold(f64::MIN_POSITIVE, f64::max);
    let smallest = inertias.iter().copied().fold(f64::INFINITY, f64::min);
    let note = (largest > smallest).then(|| {
        format!(
            "the two rotors differ ({:.2} and {:.2} kg·mm²): the device has one inertia, the larger",
            inertias[0] * 1e6,
            inertias[inertias.len() - 1] * 1e6
        )
    });
    Some((largest, note))
}

/// Puts unit `unit` of `model` on the virtual rig: its branches (and, for a `preisach` hysteresis,
/// the Preisach model the plant runs, [`crate::rig::config::BrakeConfig::everett`]), maximum
/// current, dynamics (else the
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
    // The plant runs the Preisach model itself (with the seal friction), the controller the fit.
    config.brake.everett =
        u.hysteresis.everett().map(|t| t.with_offset(u.off_state.seal_friction_nm));
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::brake_model::prototype::haptic_prototype;
    use crate::haptic::{DeviceKind, Scenario, simulate};

    /// The free-motion torque of the prototype model with rotor inertia `inertia` (both units).
    fn free_motion(inertia: Option<f64>) -> (f64, HapticConfig, Vec<String>) {
        let mut model = haptic_prototype();
        for unit in &mut model.units {
            unit.rotor_inertia_kg_m2 = inertia;
        }
        let mut config = HapticConfig::new(DeviceKind::Bidirectional, Scenario::PressWithdraw);
        let notes = apply_to_haptic(&model, &mut config).unwrap();
        let metrics = simulate(&config, false).unwrap().metrics;
        (metrics.free_motion_torque_nm, config, notes)
    }

    #[test]
    fn the_rotor_inertia_of_the_model_is_felt_in_free_motion() {
        let (light, config, notes) = free_motion(Some(20e-6));
        assert!((config.device_parameters.inertia_kg_m2 - 20e-6).abs() < 1e-18);
        assert!(notes.is_empty(), "{notes:?}");
        let (heavy, config, _) = free_motion(Some(2000e-6));
        assert!((config.device_parameters.inertia_kg_m2 - 2000e-6).abs() < 1e-18);
        // The press-withdraw approach peaks near 8 rad/s² (minimum jerk, 0.4 rad in 0.8 s, and
        // faster after the release): 1980 kg·mm² more rotor is several mN·m more at the grip.
        assert!(heavy > light + 5e-3, "heavy {heavy} vs light {light}");
        // At least the free-motion drag (bearing + the brake's off-state torque) is always felt.
        assert!(light >= config.device_parameters.coulomb_nm, "{light}");
        let (_, config, notes) = free_motion(None);
        let default = HapticConfig::new(DeviceKind::Bidirectional, Scenario::PressWithdraw);
        let kept = config.device_parameters.inertia_kg_m2 - default.device_parameters.inertia_kg_m2;
        assert!(kept.abs() < 1e-18, "{kept}");
        assert!(notes.iter().any(|n| n.contains("no rotor inertia")), "{notes:?}");
        let mut model = haptic_prototype();
        model.units[1].rotor_inertia_kg_m2 = Some(80e-6);
        let mut config = default;
        let notes = apply_to_haptic(&model, &mut config).unwrap();
        assert!((config.device_parameters.inertia_kg_m2 - 80e-6).abs() < 1e-18);
        assert!(notes.iter().any(|n| n.contains("rotors differ")), "{notes:?}");
    }
}
