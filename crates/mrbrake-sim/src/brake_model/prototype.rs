//! The built-in prototype-like brakes as brake models: what `examples/brake-models/` ships.
//!
//! The simulators keep their built-in defaults (so their outputs do not change); these functions
//! write the same numbers as model files, with the assumptions in them, and the tests check that a
//! simulator given the file is configured exactly as by default.

use super::{
    BrakeModel, Dynamics, Hysteresis, OffState, Provenance, SCHEMA, SCHEMA_VERSION, StaticCurve,
    UnitModel,
};
use crate::haptic::TorqueLag;
use crate::haptic::device::DeviceParameters;
use crate::haptic::prototype::{CURRENT_MAX_A, prototype_coefficients};
use crate::rig::config::BrakeConfig;

/// Samples of the static curve written for a prototype (every 0.1 A on 0–2 A).
const CURVE_SAMPLES: usize = 21;

fn provenance(source: &str, assumed: Vec<String>) -> Provenance {
    Provenance {
        mrbrake_version: env!("CARGO_PKG_VERSION").to_string(),
        source: source.to_string(),
        spec_sha256: None,
        model_revision: None,
        predicted: Vec::new(),
        assumed,
        amended: Vec::new(),
    }
}

fn lag_dynamics(lag: TorqueLag, equation: &str) -> Dynamics {
    Dynamics {
        numerator: vec![lag.gain],
        denominator: vec![lag.a_s2, lag.b_s, 1.0],
        source: format!("thesis ({equation}): the prototype's measured torque lag"),
    }
}

/// A unit whose hysteresis is the two polynomial branches and whose static curve is their mean.
fn unit_of_branches(
    unit: u32,
    rising: &[f64],
    falling: &[f64],
    current_max_a: f64,
    dynamics: Dynamics,
) -> UnitModel {
    let eval = |c: &[f64], i: f64| c.iter().rev().fold(0.0, |acc, v| acc * i + v);
    let current_a: Vec<f64> =
        (0..CURVE_SAMPLES).map(|k| current_max_a * k as f64 / (CURVE_SAMPLES - 1) as f64).collect();
    // Rounded to 1e-12 N·m: short decimals, which serde_json reads back to the same numbers.
    let torque_nm = current_a
        .iter()
        .map(|&i| (0.5e12 * (eval(rising, i) + eval(falling, i))).round() / 1e12)
        .collect();
    UnitModel {
        unit,
        current_max_a,
        // The thesis's rotor inertia per direction (§4.3, Table 4.7), the haptic device's default.
        rotor_inertia_kg_m2: Some(DeviceParameters::default().inertia_kg_m2),
        static_curve: StaticCurve {
            current_a,
            torque_nm,
            source: "assumed: the mean of the two branches below (not measured)".into(),
        },
        off_state: OffState {
            viscous_nm_s_per_rad: 0.0,
            reference_speed_rad_s: 1.0,
            seal_friction_nm: 0.0,
            seal_friction_source: "assumed: 0; the thesis's measured 0.15 N·m off-state torque (§5.3.1) is inside the branches".into(),
        },
        hysteresis: Hysteresis::PolynomialBranches {
            rising: rising.to_vec(),
            falling: falling.to_vec(),
            source: "assumed: prototype-like branches through the thesis's 0.15 N·m at 0 A and 3.84 N·m at 2 A (§5.3.1); the thesis does not print its fitted coefficients".into(),
        },
        dynamics: Some(dynamics),
        thermal: None,
    }
}

/// The haptic simulation's built-in brakes (`haptic::prototype`): the same quintic branches for
/// both units, lags (5.5) and (5.6).
pub fn haptic_prototype() -> BrakeModel {
    let (rising, falling) = prototype_coefficients();
    BrakeModel {
        schema: SCHEMA.into(),
        schema_version: SCHEMA_VERSION,
        name: "prototype-like (haptic default)".into(),
        provenance: provenance(
            "mrbrake_sim::haptic::prototype (built in)",
            vec![
                "hysteresis branches: invented quintics through the thesis's end points, loop width 10 % of the span at 1 A".into(),
                "static curve: mean of the branches".into(),
                "off-state: inside the branches; viscous and seal terms 0".into(),
            ],
        ),
        units: vec![
            unit_of_branches(1, &rising, &falling, CURRENT_MAX_A, lag_dynamics(TorqueLag::BRAKE_1, "5.5")),
            unit_of_branches(2, &rising, &falling, CURRENT_MAX_A, lag_dynamics(TorqueLag::BRAKE_2, "5.6")),
        ],
    }
}

/// The virtual rig's built-in brake (`[brake]` of the default rig configuration): illustrative
/// cubic branches and lag (5.5).
pub fn rig_prototype() -> BrakeModel {
    let b = BrakeConfig::default();
    let dynamics = Dynamics {
        numerator: b.dynamics_numerator.clone(),
        denominator: b.dynamics_denominator.clone(),
        source: "thesis (5.5): brake 1's measured torque lag".into(),
    };
    let mut unit = unit_of_branches(1, &b.rising, &b.falling, b.current_max_a, dynamics);
    if let Hysteresis::PolynomialBranches { source, .. } = &mut unit.hysteresis {
        *source = "assumed: illustrative cubics through 0.15 N·m at 0 A and 3.84 N·m at 2 A, widest gap 0.3 N·m at 1 A (§5.3.1)".into();
    }
    BrakeModel {
        schema: SCHEMA.into(),
        schema_version: SCHEMA_VERSION,
        name: "prototype-like (rig default)".into(),
        provenance: provenance(
            "mrbrake_sim::rig::config::BrakeConfig::default (built in)",
            vec![
                "hysteresis branches: illustrative cubics through the thesis's end points".into(),
                "static curve: mean of the branches".into(),
                "off-state: inside the branches; viscous and seal terms 0".into(),
            ],
        ),
        units: vec![unit],
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::brake_model::apply::{apply_to_haptic, apply_to_rig};
    use crate::haptic::{DeviceKind, HapticConfig, Scenario};
    use crate::rig::RigConfig;

    /// The shipped file `name`; with `MRBRAKE_BLESS=1` it is (re)written from `model` first.
    fn shipped(name: &str, model: &BrakeModel) -> String {
        let path = format!("{}/../../examples/brake-models/{name}", env!("CARGO_MANIFEST_DIR"));
        if std::env::var_os("MRBRAKE_BLESS").is_some() {
            std::fs::write(&path, model.to_json()).unwrap();
        }
        std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path}: {e}"))
    }

    #[test]
    fn shipped_files_are_the_built_in_brakes() {
        for (name, model) in
            [("prototype.json", haptic_prototype()), ("rig-prototype.json", rig_prototype())]
        {
            let text = shipped(name, &model);
            assert_eq!(BrakeModel::from_json(name, &text).unwrap(), model, "{name}");
            assert_eq!(text, model.to_json(), "{name}: regenerate it from the code");
        }
    }

    #[test]
    fn the_prototype_files_configure_the_simulators_exactly_as_the_defaults() {
        for device in DeviceKind::ALL {
            let default = HapticConfig::new(device, Scenario::PressWithdraw);
            let mut from_file = default.clone();
            let notes = apply_to_haptic(&haptic_prototype(), &mut from_file).unwrap();
            assert_eq!(from_file, default);
            assert!(notes.is_empty(), "{notes:?}");
        }
        let default = RigConfig::default();
        let mut from_file = default.clone();
        let notes = apply_to_rig(&rig_prototype(), 1, &mut from_file).unwrap();
        assert_eq!(from_file, default);
        assert!(notes.is_empty(), "{notes:?}");
    }
}
