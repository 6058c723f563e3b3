//! The brake model predicted from a design: [`from_analysis`] turns a finite-element
//! [`Analysis`] into the simulators' [`BrakeModel`] file (schema in [`mrbrake_sim::brake_model`]);
//! [`add_dynamics`] and [`add_thermal`] amend it with the design's predicted response and hot coil.
//! (Why here and not in the design, the report or the simulator crate: the crate docs.)
//!
//! What is predicted and what is assumed, per unit:
//! - the static curve of unit 1 is the analysis's sweep of the local Bingham yield torque (FEA);
//! - the viscous coefficient is the sum of the unit's gaps' viscous torques at the analysis speed
//!   divided by that speed (the Bingham viscous term is linear in the shear rate, thesis (3.3));
//! - the seal/bearing friction is the analysis option (`--seal-friction`, default 0 N·m): assumed,
//!   the FEA has no seals;
//! - unit 2 of a bidirectional brake is solved only at the maximum current, so its curve is unit 1's
//!   scaled by the ratio of the two yield torques there (assumed shape, predicted end point);
//! - the rotor inertia of each unit is the analysis's `mechanics` (the parts that turn with the
//!   shaft in that unit's direction, from the modelled parts' densities: predicted, without
//!   bearings, seals and bolts, which the spec does not model);
//! - no hysteresis (anhysteretic B–H curves), no dynamics, no thermal data: stated as such;
//!   [`set_predicted_hysteresis`] adds the Preisach model of the design's predicted first-order
//!   reversal curves (`analyze --hysteresis --save-model`);
//!   `response --save-model` ([`add_dynamics`]) and `thermal --save-model` ([`add_thermal`]) add
//!   the last two.

use mrbrake_design::analysis::{Analysis, AnalysisOptions};
use mrbrake_design::forc::ForcSet;
use mrbrake_design::response::{Response, ResponseDrive};
use mrbrake_design::thermal::ThermalResult;
use mrbrake_sim::brake_model::fit::{DYNAMICS_POLES, fit_dynamics};
use mrbrake_sim::brake_model::{
    BrakeModel, Dynamics, Hysteresis, OffState, Provenance, SCHEMA, SCHEMA_VERSION, StaticCurve,
    Thermal, UnitModel,
};
use mrbrake_sim::rig::everett::EverettTable;
use mrbrake_sysid::frd::Frd;

use crate::DeviceError;
use mrbrake_error::FieldError;

/// Why a predicted model has no hysteresis.
pub const NO_HYSTERESIS_NOTE: &str = "the finite-element analysis uses anhysteretic B–H curves: it predicts no loop; identify one on a rig (mrbrake characterize --save-model)";

/// The viscous coefficient (N·m·s/rad) of unit `unit` (0-based) from the gaps at the analysis speed.
fn viscous_coefficient(analysis: &Analysis, unit: usize) -> f64 {
    let sum: f64 =
        analysis.gaps.iter().filter(|g| g.unit == unit).map(|g| g.viscous_torque_nm).sum();
    if analysis.speed_rad_s > 0.0 { sum / analysis.speed_rad_s } else { 0.0 }
}

/// Which design a predicted model is of: the design key of `mrbrake-explore` (spec, materials,
/// settings, solver) and its model revision (`mrbrake_explore::design::analysis_identity` gives
/// both for an analysis).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct DesignIdentity {
    /// SHA-256 of the design.
    pub spec_sha256: String,
    /// `mrbrake_explore::design::MODEL_REVISION` of the analysis.
    pub model_revision: u32,
}

/// The brake model of `analysis` (run with `options`) of the design `identity`; `source` says how
/// it was produced (e.g. the command line and the spec file).
pub fn from_analysis(
    analysis: &Analysis,
    options: &AnalysisOptions,
    identity: Option<DesignIdentity>,
    source: &str,
) -> Result<BrakeModel, DeviceError> {
    let curve = &analysis.torque_current_curve;
    let unit1_yield: Vec<f64> = curve.iter().map(|p| p.yield_torque_nm).collect();
    let mut units = vec![unit_model(analysis, 1, unit1_yield.clone(), "FEA")];
    units[0].rotor_inertia_kg_m2 = Some(analysis.mechanics.rotor_inertia_kg_m2);
    let mut assumed = vec![
        format!(
            "constant friction {} N·m (seals, bearings, freewheel from the spec's [drag] and \
             --seal-friction; the FEA models none of them)",
            analysis.torque_off.constant_friction_nm()
        ),
        "no hysteresis: anhysteretic B–H curves".to_string(),
        "no dynamics (mrbrake response --save-model adds them)".to_string(),
        "no thermal data".to_string(),
    ];
    if let Some(total2) = analysis.torque.direction2_at_max_current_nm {
        let yield2 = total2
            - viscous_coefficient(analysis, 1) * analysis.speed_rad_s
            - analysis.torque_off.constant_friction_nm();
        let yield1 = unit1_yield.last().copied().unwrap_or(0.0);
        let ratio = if yield1 > 0.0 { yield2 / yield1 } else { 1.0 };
        let scaled = unit1_yield.iter().map(|t| t * ratio).collect();
        let mut unit2 = unit_model(analysis, 2, scaled, "unit 1's FEA curve scaled");
        unit2.rotor_inertia_kg_m2 = analysis.mechanics.rotor_inertia_direction2_kg_m2;
        units.push(unit2);
        assumed.push(format!(
            "unit 2's curve: unit 1's shape scaled by {ratio:.6} (unit 2 is solved at the maximum current only)"
        ));
    }
    let model = BrakeModel {
        schema: SCHEMA.into(),
        schema_version: SCHEMA_VERSION,
        name: analysis.name.clone(),
        provenance: Provenance {
            mrbrake_version: env!("CARGO_PKG_VERSION").to_string(),
            source: source.to_string(),
            spec_sha256: identity.as_ref().map(|i| i.spec_sha256.clone()),
            model_revision: identity.as_ref().map(|i| i.model_revision),
            predicted: vec![
                format!(
                    "static torque–current curve of unit 1: local Bingham yield torque over the gaps, {} currents 0–{} A (FEA, {} mesh, P{})",
                    curve.len(),
                    analysis.max_current_a,
                    format!("{:?}", options.mesh).to_lowercase(),
                    analysis.mesh.order
                ),
                format!(
                    "viscous off-state coefficient: gaps' viscous torque at {} rad/s ÷ speed",
                    analysis.speed_rad_s
                ),
                "rotor inertia per unit: the modelled parts turning with the shaft in its direction (no bearings, seals or bolts)".to_string(),
            ],
            assumed,
            amended: Vec::new(),
        },
        units,
    };
    // A curve the reader would refuse (e.g. a torque that drops with the current) is not written.
    model.check("(predicted from the analysis)")?;
    Ok(model)
}

/// Where the model's constant friction comes from: the seal, bearing, freewheel and remanent
/// terms of the analysis's off-state breakdown, each with its source.
fn friction_source(off: &mrbrake_design::drag::OffStateTorque) -> String {
    let s = &off.sources;
    format!(
        "the off-state breakdown of mrbrake analyze: seal {} N·m ({}); bearing {} N·m ({}); \
         freewheel {} N·m ({}); remanent {} N·m ({})",
        off.seal_nm,
        s.seal,
        off.bearing_nm,
        s.bearing,
        off.freewheel_nm,
        s.freewheel,
        off.remanent_nm,
        s.remanent
    )
}

/// One unit: its yield curve, off-state, no hysteresis, no dynamics.
fn unit_model(analysis: &Analysis, unit: u32, yield_nm: Vec<f64>, how: &str) -> UnitModel {
    let current_a = analysis.torque_current_curve.iter().map(|p| p.current_a).collect();
    UnitModel {
        unit,
        current_max_a: analysis.max_current_a,
        rotor_inertia_kg_m2: None,
        static_curve: StaticCurve {
            current_a,
            torque_nm: yield_nm,
            source: format!("{how}: local Bingham yield torque (mrbrake analyze)"),
        },
        off_state: OffState {
            viscous_nm_s_per_rad: viscous_coefficient(analysis, unit as usize - 1),
            reference_speed_rad_s: analysis.speed_rad_s,
            seal_friction_nm: analysis.torque_off.constant_friction_nm(),
            seal_friction_source: friction_source(&analysis.torque_off),
        },
        hysteresis: Hysteresis::None { note: NO_HYSTERESIS_NOTE.into() },
        dynamics: None,
        thermal: None,
    }
}

/// What [`set_predicted_hysteresis`] identified.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PredictedHysteresis {
    /// Levels of the Everett table.
    pub levels: usize,
    /// Largest `|T(α, 0) − T(0)|` of the FORCs, N·m (`mrbrake_sim::rig::everett`).
    pub wiping_out_defect_nm: f64,
    /// Sum of the negative Preisach weights set to zero, N·m.
    pub projected_weight_nm: f64,
    /// Largest change of a node's torque by that projection, N·m.
    pub projection_nm: f64,
}

/// Gives every unit of `model` (predicted from `analysis`) the Preisach hysteresis identified
/// from the design's first-order reversal curves `forcs` (`mrbrake_design::forc`; the Everett
/// function `E(α, β) = T(α) − T(α, β)`, `mrbrake_sim::rig::everett`). Unit 2 of a bidirectional
/// brake gets unit 1's table scaled by the ratio of the two static curves' end torques (as its
/// curve). The remanent torque is then the model's own (its torque at 0 A), so the remanent term of
/// the analysis's off-state breakdown leaves the constant friction.
pub fn set_predicted_hysteresis(
    model: &mut BrakeModel,
    forcs: &ForcSet,
    analysis: &Analysis,
    source: &str,
) -> Result<PredictedHysteresis, DeviceError> {
    let identified = EverettTable::from_forcs(&forcs.levels_a, &forcs.forcs_nm)
        .map_err(|(field, message)| FieldError::new(format!("forc.{field}"), message))?;
    let table = &identified.table;
    let how = format!(
        "predicted: Preisach model identified from {} first-order reversal curves of the \
         hysteretic FEA on {} levels 0–{} A ({} current steps per level; steel sets: {}); \
         wiping-out defect {:.3e} N·m; non-Preisach part projected out: negative weights \
         {:.3e} N·m, largest node change {:.3e} N·m ({source})",
        table.levels(),
        table.levels(),
        analysis.max_current_a,
        forcs.steps_per_level,
        forcs
            .steels
            .iter()
            .map(|s| format!("{} (trust {})", s.material, s.trust))
            .collect::<Vec<_>>()
            .join(", "),
        identified.wiping_out_defect_nm,
        identified.projected_weight_nm,
        identified.projection_nm,
    );
    let end = |u: &UnitModel| u.static_curve.torque_nm.last().copied().unwrap_or(0.0);
    let unit1_end = model.units.first().map_or(0.0, end);
    let remanent = analysis.torque_off.remanent_nm;
    for unit in &mut model.units {
        let ratio = if unit1_end > 0.0 { end(unit) / unit1_end } else { 1.0 };
        let t = table.scaled(ratio);
        unit.hysteresis = Hysteresis::Preisach {
            levels_a: t.levels_a,
            rising_nm: t.rising_nm,
            everett_nm: t.everett_nm,
            source: how.clone(),
        };
        let o = &mut unit.off_state;
        o.seal_friction_nm = (o.seal_friction_nm - remanent).max(0.0);
        o.seal_friction_source.push_str(
            "; the remanent term is in the Preisach hysteresis (its torque at 0 A), not here",
        );
    }
    let p = &mut model.provenance;
    p.predicted.push(format!("hysteresis: {how}"));
    p.assumed.retain(|a| !a.starts_with("no hysteresis"));
    if model.units.len() > 1 {
        p.assumed.push("unit 2's hysteresis: unit 1's Preisach table scaled as its curve".into());
    }
    model.check("(with the predicted hysteresis)")?;
    Ok(PredictedHysteresis {
        levels: table.levels(),
        wiping_out_defect_nm: identified.wiping_out_defect_nm,
        projected_weight_nm: identified.projected_weight_nm,
        projection_nm: identified.projection_nm,
    })
}

/// Adds the predicted dynamics of `response` (the same design) to every unit of `model`: a
/// [`DYNAMICS_POLES`]-pole, no-zero transfer function fitted to the predicted small-signal
/// frequency response, which is already normalised by its DC gain (torque per current ÷ dT/dI at
/// 0 Hz: static torque → brake torque), scaled to a DC gain of exactly 1
/// ([`mrbrake_sim::brake_model::fit`]). Unit 2 gets direction 2's own fit when the response has
/// it (bidirectional brakes), else unit 1's (stated in the model). Returns the fit's
/// `fit_percent` (the lower of the two).
pub fn add_dynamics(
    model: &mut BrakeModel,
    response: &Response,
    source: &str,
) -> Result<f64, DeviceError> {
    if model.name != response.name {
        return Err(FieldError::new("name", "analyse and respond the same design")
            .with_value(format!("'{}' in the brake model", model.name))
            .with_allowed(format!("'{}', the design of the response", response.name))
            .into());
    }
    let direction_2 = response.direction_2.as_ref().map(|d| &d.frequency_response);
    let operating_point = (response.bias_a, response.drive);
    set_dynamics(model, &response.frequency_response, direction_2, operating_point, source)
}

/// The [`DYNAMICS_POLES`]-pole fit to direction `direction`'s normalised frequency response and
/// its `fit_percent`.
fn dynamics_of(
    frd: &Frd,
    (bias_a, drive): (f64, ResponseDrive),
    direction: usize,
    source: &str,
) -> Result<(Dynamics, f64), DeviceError> {
    let fitted = fit_dynamics(frd)?;
    let omegas: Vec<f64> = frd.omegas().collect();
    let dynamics = Dynamics {
        numerator: fitted.transfer_function.numerator.clone(),
        denominator: fitted.transfer_function.denominator.clone(),
        source: format!(
            "predicted: {DYNAMICS_POLES}-pole tfest fit ({:.2} % fit{}) to the small-signal frequency response of direction {direction} at {} A bias, {} drive, {} points {:.3}–{:.1} rad/s ({source})",
            fitted.fit_percent,
            fitted.reflection_note(),
            bias_a,
            format!("{drive:?}").to_lowercase(),
            omegas.len(),
            omegas.first().copied().unwrap_or(0.0),
            omegas.last().copied().unwrap_or(0.0),
        ),
    };
    Ok((dynamics, fitted.fit_percent))
}

/// [`add_dynamics`] from the design's normalised small-signal frequency response `frd` at
/// `(bias_a, drive)` (what `ResponseModel::frequency_response` gives a study), without the name
/// check: the caller knows the model and the response are of the same design. Unit 2 gets unit
/// 1's (stated in the model).
pub fn add_frequency_response(
    model: &mut BrakeModel,
    frd: &Frd,
    operating_point: (f64, ResponseDrive),
    source: &str,
) -> Result<f64, DeviceError> {
    set_dynamics(model, frd, None, operating_point, source)
}

/// Sets every unit's dynamics to the fit of direction 1's response, unit 2's to the fit of
/// `direction_2`'s own when given, and records where they come from; returns the lowest
/// `fit_percent` of the fits made.
fn set_dynamics(
    model: &mut BrakeModel,
    direction_1: &Frd,
    direction_2: Option<&Frd>,
    operating_point: (f64, ResponseDrive),
    source: &str,
) -> Result<f64, DeviceError> {
    let (first, fit_1) = dynamics_of(direction_1, operating_point, 1, source)?;
    let second = match direction_2.filter(|_| model.units.len() > 1) {
        Some(frd) => Some(dynamics_of(frd, operating_point, 2, source)?),
        None => None,
    };
    let fit_percent = second.as_ref().map_or(fit_1, |(_, fit_2)| fit_1.min(*fit_2));
    for (k, unit) in model.units.iter_mut().enumerate() {
        let own = second.as_ref().filter(|_| k == 1).map(|(d, _)| d);
        unit.dynamics = Some(own.unwrap_or(&first).clone());
    }
    let p = &mut model.provenance;
    p.amended.push(format!("dynamics: {source}"));
    if model.units.len() > 1 && second.is_none() {
        p.assumed
            .push("unit 2's dynamics: unit 1's (direction 1's frequency response only)".into());
    }
    p.assumed.retain(|a| !a.starts_with("no dynamics"));
    model.check("(amended with dynamics)")?;
    Ok(fit_percent)
}

/// Adds the hot coil of `thermal` (a thermal analysis of the design called `spec_name`) to every
/// unit of `model`: the coil's mean steady temperature and its resistance there, and the
/// continuous current (steady hot spot at the insulation limit). The simulators are
/// current-driven, so these are recorded for the user, not used by them.
pub fn add_thermal(
    model: &mut BrakeModel,
    thermal: &ThermalResult,
    spec_name: &str,
    source: &str,
) -> Result<(), DeviceError> {
    if model.name != spec_name {
        return Err(FieldError::new("name", "use the same design")
            .with_value(format!("'{}' in the brake model", model.name))
            .with_allowed(format!("'{spec_name}', the design of the thermal analysis"))
            .into());
    }
    let Some(steady) = thermal.steady else {
        return Err(FieldError::new(
            "current",
            "no steady state (thermal runaway): no hot resistance to save",
        )
        .with_value(format!("{} A", thermal.current_a))
        .with_allowed(format!("<= {} A (continuous)", thermal.continuous_current_a))
        .into());
    };
    let data = Thermal {
        hot_temperature_c: steady.coil_mean_t_c,
        hot_resistance_ohm: steady.coil_resistance_ohm,
        continuous_current_a: thermal.continuous_current_a,
        source: format!(
            "predicted: steady coil mean temperature and resistance at {} A, duty {}, ambient {} °C, {} cooling; continuous current at the {} °C limit ({source})",
            thermal.current_a,
            thermal.duty,
            thermal.ambient_c,
            thermal.cooling.kind,
            thermal.limit_c
        ),
    };
    for unit in &mut model.units {
        unit.thermal = Some(data.clone());
    }
    model.provenance.amended.push(format!("thermal: {source}"));
    model.provenance.assumed.retain(|a| !a.starts_with("no thermal"));
    if model.units.len() > 1 {
        model
            .provenance
            .assumed
            .push("unit 2's thermal data: unit 1's (one coil energised)".into());
    }
    model.check("(amended with thermal data)")?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use mrbrake_design::response::{ResponseDrive, ResponseTimings};
    use mrbrake_error::Kind as _;
    use mrbrake_sim::brake_model::prototype::haptic_prototype;
    use mrbrake_sysid::tfest::logspace;
    use mrbrake_sysid::transfer_function::TransferFunction;

    use super::*;

    /// A response whose frequency response is the thesis's lag (5.6) normalised to DC gain 1.
    fn response(name: &str) -> Response {
        let lag = TransferFunction::new(vec![1.0], vec![2.309e-5, 0.01726, 1.0]).unwrap();
        Response {
            name: name.into(),
            drive: ResponseDrive::Current,
            step: Vec::new(),
            bias_a: 1.0,
            dc_gain_nm_per_a: 1.3,
            frequency_response: Frd::sample(&logspace(0.1, 1000.0, 41), |w| lag.response(w)),
            bandwidth_rad_s: None,
            direction_2: None,
            flux_path_conductivity_s_per_m: 2e6,
            conductivity_source: "test".into(),
            fluid_lag_s: 0.0,
            nodes: 0,
            timings_s: ResponseTimings { step: 0.0, frequency: 0.0, total: 0.0 },
            eddy: None,
        }
    }

    #[test]
    fn predicted_dynamics_go_to_every_unit_with_their_provenance() {
        let mut model = haptic_prototype();
        model.provenance.assumed.push("no dynamics (test)".into());
        let predicted = response(&model.name);
        let fit = add_dynamics(&mut model, &predicted, "test run").unwrap();
        assert!(fit > 99.99, "{fit}");
        for unit in &model.units {
            let d = unit.dynamics.as_ref().unwrap();
            assert!((d.denominator[0] / 2.309e-5 - 1.0).abs() < 1e-6, "{d:?}");
            assert!(d.source.contains("2-pole tfest fit") && d.source.contains("(test run)"));
        }
        assert!(model.provenance.amended.iter().any(|a| a == "dynamics: test run"));
        assert!(!model.provenance.assumed.iter().any(|a| a.starts_with("no dynamics")));
        let e = add_dynamics(&mut model, &response("another brake"), "x").unwrap_err();
        assert!(e.is_input_error() && e.to_string().contains("another brake"), "{e}");
    }
}
