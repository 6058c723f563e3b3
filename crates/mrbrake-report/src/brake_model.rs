//! The brake model predicted from a design: [`from_analysis`] turns a finite-element
//! [`Analysis`] into the simulators' [`BrakeModel`] file (schema in [`mrbrake_sim::brake_model`]).
//!
//! It lives here, not in `mrbrake-design`, because the provenance needs the design key and the
//! model revision of `mrbrake-explore` (which depends on the design crate), and the model type lives
//! in `mrbrake-sim`; this crate already depends on all three.
//!
//! What is predicted and what is assumed, per unit:
//! - the static curve of unit 1 is the analysis's sweep of the local Bingham yield torque (FEA);
//! - the viscous coefficient is the sum of the unit's gaps' viscous torques at the analysis speed
//!   divided by that speed (the Bingham viscous term is linear in the shear rate, thesis (3.3));
//! - the seal/bearing friction is the analysis option (`--seal-friction`, default 0 N·m): assumed,
//!   the FEA has no seals;
//! - unit 2 of a bidirectional brake is solved only at the maximum current, so its curve is unit 1's
//!   scaled by the ratio of the two yield torques there (assumed shape, predicted end point);
//! - no hysteresis (anhysteretic B–H curves), no dynamics, no thermal data: stated as such;
//!   `response --save-model` and `thermal --save-model` add the last two.

use mrbrake_design::analysis::{Analysis, AnalysisOptions};
use mrbrake_design::response::Response;
use mrbrake_design::spec::BrakeSpec;
use mrbrake_design::thermal::ThermalResult;
use mrbrake_explore::design::{MODEL_REVISION, design_key};
use mrbrake_explore::evaluate::EvaluationSettings;
use mrbrake_sim::SimError;
use mrbrake_sim::brake_model::{
    BrakeModel, Dynamics, Hysteresis, OffState, Provenance, SCHEMA, SCHEMA_VERSION, StaticCurve,
    Thermal, UnitModel,
};
use mrbrake_sysid::frd::Frd;
use mrbrake_sysid::tfest::{TfestOptions, complex_fit_percent, tfest};
use mrbrake_sysid::transfer_function::TransferFunction;
use num_complex::Complex64;

use crate::ReportError;

/// Why a predicted model has no hysteresis.
pub const NO_HYSTERESIS_NOTE: &str = "the finite-element analysis uses anhysteretic B–H curves: it predicts no loop; identify one on a rig (mrbrake characterize --save-model)";

/// The viscous coefficient (N·m·s/rad) of unit `unit` (0-based) from the gaps at the analysis speed.
fn viscous_coefficient(analysis: &Analysis, unit: usize) -> f64 {
    let sum: f64 =
        analysis.gaps.iter().filter(|g| g.unit == unit).map(|g| g.viscous_torque_nm).sum();
    if analysis.speed_rad_s > 0.0 { sum / analysis.speed_rad_s } else { 0.0 }
}

/// The brake model of `analysis` (of `spec` under `options`); `source` says how it was produced
/// (e.g. the command line and the spec file).
pub fn from_analysis(
    analysis: &Analysis,
    spec: &BrakeSpec,
    options: &AnalysisOptions,
    source: &str,
) -> Result<BrakeModel, ReportError> {
    let settings = EvaluationSettings {
        mesh: options.mesh,
        speed_rad_s: options.speed_rad_s,
        seal_friction_nm: options.seal_friction_nm,
        temperature_c: options.temperature_c,
        order: options.order,
        ..EvaluationSettings::default()
    };
    let key = design_key(spec, &settings)?;
    let curve = &analysis.torque_current_curve;
    let unit1_yield: Vec<f64> = curve.iter().map(|p| p.yield_torque_nm).collect();
    let mut units = vec![unit_model(analysis, options, 1, unit1_yield.clone(), "FEA")];
    let mut assumed = vec![
        format!(
            "seal/bearing friction {} N·m (analyze --seal-friction; the FEA does not model seals or bearings)",
            options.seal_friction_nm
        ),
        "no hysteresis: anhysteretic B–H curves".to_string(),
        "no dynamics (mrbrake response --save-model adds them)".to_string(),
        "no thermal data".to_string(),
    ];
    if let Some(total2) = analysis.torque.direction2_at_max_current_nm {
        let yield2 = total2
            - viscous_coefficient(analysis, 1) * analysis.speed_rad_s
            - options.seal_friction_nm;
        let yield1 = unit1_yield.last().copied().unwrap_or(0.0);
        let ratio = if yield1 > 0.0 { yield2 / yield1 } else { 1.0 };
        let scaled = unit1_yield.iter().map(|t| t * ratio).collect();
        units.push(unit_model(analysis, options, 2, scaled, "unit 1's FEA curve scaled"));
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
            spec_sha256: Some(key),
            model_revision: Some(MODEL_REVISION),
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
            ],
            assumed,
            amended: Vec::new(),
        },
        units,
    };
    // A curve the reader would refuse (e.g. a torque that drops with the current) is not written.
    model.validate().map_err(|(field, message)| SimError::BrakeModel {
        file: "(predicted from the analysis)".into(),
        field,
        message,
    })?;
    Ok(model)
}

/// One unit: its yield curve, off-state, no hysteresis, no dynamics.
fn unit_model(
    analysis: &Analysis,
    options: &AnalysisOptions,
    unit: u32,
    yield_nm: Vec<f64>,
    how: &str,
) -> UnitModel {
    let current_a = analysis.torque_current_curve.iter().map(|p| p.current_a).collect();
    UnitModel {
        unit,
        current_max_a: analysis.max_current_a,
        static_curve: StaticCurve {
            current_a,
            torque_nm: yield_nm,
            source: format!("{how}: local Bingham yield torque (mrbrake analyze)"),
        },
        off_state: OffState {
            viscous_nm_s_per_rad: viscous_coefficient(analysis, unit as usize - 1),
            reference_speed_rad_s: analysis.speed_rad_s,
            seal_friction_nm: options.seal_friction_nm,
            seal_friction_source:
                "assumed: the analysis option --seal-friction (default 0 N·m); not predicted".into(),
        },
        hysteresis: Hysteresis::None { note: NO_HYSTERESIS_NOTE.into() },
        dynamics: None,
        thermal: None,
    }
}

/// Poles of the transfer function fitted to a predicted frequency response: two, like the thesis's
/// identified lags (5.5)/(5.6), and the form the haptic simulation runs (`k / (a s² + b s + 1)`).
pub const DYNAMICS_POLES: usize = 2;

/// Adds the predicted dynamics of `response` (the same design) to every unit of `model`: a
/// two-pole, no-zero transfer function fitted by sysid's `tfest` (Sanathanan–Koerner iterations,
/// then Levenberg–Marquardt) to the predicted small-signal frequency response normalised by its DC
/// gain (torque per current ÷ dT/dI at 0 Hz: static torque → brake torque), then scaled to a DC
/// gain of exactly 1. Unit 2 gets unit 1's (only direction 1's frequency response is predicted;
/// stated in the model). Returns the fit's `fit_percent`.
pub fn add_dynamics(
    model: &mut BrakeModel,
    response: &Response,
    source: &str,
) -> Result<f64, ReportError> {
    if model.name != response.name {
        return Err(SimError::Input(format!(
            "the brake model is of '{}', the response of '{}': analyse and respond the same design",
            model.name, response.name
        ))
        .into());
    }
    let frd = Frd {
        omega_rad_s: response.frequency_response.iter().map(|p| p.omega_rad_s).collect(),
        response: response.frequency_response.iter().map(|p| Complex64::new(p.re, p.im)).collect(),
        weight: None,
    };
    let mut fit = tfest(&frd, &TfestOptions::new(DYNAMICS_POLES, 0))
        .map_err(|source| SimError::Model { what: "predicted dynamics (tfest)", source })?;
    let reflected = reflect_unstable_poles(&mut fit.model)?;
    let mut note = String::new();
    if !reflected.is_empty() {
        let fitted: Vec<Complex64> =
            frd.omega_rad_s.iter().map(|w| fit.model.response(*w)).collect();
        fit.fit_percent = complex_fit_percent(&frd.response, &fitted);
        let at: Vec<String> = reflected.iter().map(|re| format!("+{re:.4e}")).collect();
        note = format!(
            "; the fit's unstable pole(s) at {} rad/s (real part), beyond the band, reflected into the left half-plane (same magnitude response; Gustavsen & Semlyen 1999), fit after reflection",
            at.join(", ")
        );
    }
    let gain = fit.model.dc_gain();
    let numerator: Vec<f64> = fit.model.numerator.iter().map(|c| c / gain).collect();
    for unit in &mut model.units {
        unit.dynamics = Some(Dynamics {
            numerator: numerator.clone(),
            denominator: fit.model.denominator.clone(),
            source: format!(
                "predicted: {DYNAMICS_POLES}-pole tfest fit ({:.2} % fit{note}) to the small-signal frequency response of direction 1 at {} A bias, {} drive, {} points {:.3}–{:.1} rad/s ({source})",
                fit.fit_percent,
                response.bias_a,
                format!("{:?}", response.drive).to_lowercase(),
                frd.omega_rad_s.len(),
                frd.omega_rad_s.first().copied().unwrap_or(0.0),
                frd.omega_rad_s.last().copied().unwrap_or(0.0),
            ),
        });
    }
    let p = &mut model.provenance;
    p.amended.push(format!("dynamics: {source}"));
    if model.units.len() > 1 {
        p.assumed
            .push("unit 2's dynamics: unit 1's (direction 1's frequency response only)".into());
    }
    p.assumed.retain(|a| !a.starts_with("no dynamics"));
    model.validate().map_err(|(field, message)| SimError::BrakeModel {
        file: "(amended with dynamics)".into(),
        field,
        message,
    })?;
    Ok(fit.fit_percent)
}

/// Moves every pole of `tf` with a non-negative real part to the left half-plane (`p → −p̄`),
/// keeping `D(0) = 1`, and returns the real parts of the poles moved. An unconstrained rational fit
/// to a band that ends below a fast pole can put that pole on the wrong side (a two-pole fit with a
/// negative s² coefficient); reflecting it leaves |G(jω)| unchanged at every ω and the phase nearly
/// so in the band, the pole flipping of vector fitting (Gustavsen & Semlyen 1999, IEEE Trans. Power
/// Delivery 14(3), 1052–1061, §III-B).
fn reflect_unstable_poles(tf: &mut TransferFunction) -> Result<Vec<f64>, ReportError> {
    let poles = tf
        .poles()
        .map_err(|source| SimError::Model { what: "predicted dynamics (poles)", source })?;
    let moved: Vec<f64> = poles.iter().filter(|p| p.re >= 0.0).map(|p| p.re).collect();
    if moved.is_empty() {
        return Ok(moved);
    }
    // Π (s − p), descending powers, from the reflected poles.
    let mut coefficients = vec![Complex64::new(1.0, 0.0)];
    for p in &poles {
        let p = if p.re >= 0.0 { Complex64::new(-p.re, p.im) } else { *p };
        let mut next = coefficients.clone();
        next.push(Complex64::new(0.0, 0.0));
        for (k, c) in coefficients.iter().enumerate() {
            next[k + 1] -= p * c;
        }
        coefficients = next;
    }
    let constant = coefficients.last().map_or(1.0, |c| c.re);
    let denominator: Vec<f64> = coefficients.iter().map(|c| c.re / constant).collect();
    *tf = TransferFunction::new(tf.numerator.clone(), denominator)
        .map_err(|source| SimError::Model { what: "predicted dynamics (reflected)", source })?;
    Ok(moved)
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
) -> Result<(), ReportError> {
    if model.name != spec_name {
        return Err(SimError::Input(format!(
            "the brake model is of '{}', the thermal analysis of '{spec_name}': use the same design",
            model.name
        ))
        .into());
    }
    let Some(steady) = thermal.steady else {
        return Err(SimError::Input(format!(
            "no steady state at {} A (thermal runaway): no hot resistance to save",
            thermal.current_a
        ))
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
    model.validate().map_err(|(field, message)| SimError::BrakeModel {
        file: "(amended with thermal data)".into(),
        field,
        message,
    })?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_unstable_fast_pole_is_reflected_keeping_the_magnitude_and_dc_gain() {
        // The front design's fit: −6.2968e-8 s² + 0.0095125 s + 1, poles ≈ −107 and +1.51e5 rad/s.
        let mut tf = TransferFunction::new(vec![0.64], vec![-6.2968e-8, 0.0095125, 1.0]).unwrap();
        let before = tf.clone();
        let moved = reflect_unstable_poles(&mut tf).unwrap();
        assert_eq!(moved.len(), 1);
        assert!((moved[0] - 1.5117e5).abs() < 1e2, "{moved:?}");
        assert!(tf.poles().unwrap().iter().all(|p| p.re < 0.0));
        assert!(tf.denominator.iter().all(|c| *c > 0.0), "{:?}", tf.denominator);
        assert!((tf.dc_gain() - 0.64).abs() < 1e-12);
        for w in [0.1, 10.0, 100.0, 1e3, 1e5] {
            let (a, b) = (before.response(w).norm(), tf.response(w).norm());
            assert!((a - b).abs() <= 1e-9 * a, "{w} rad/s: {a} vs {b}");
        }
        // A stable model is left as it is.
        let mut stable = TransferFunction::new(vec![1.0], vec![1.0157e-6, 0.0075757, 1.0]).unwrap();
        assert!(reflect_unstable_poles(&mut stable).unwrap().is_empty());
        assert_eq!(stable.denominator, vec![1.0157e-6, 0.0075757, 1.0]);
    }
}
