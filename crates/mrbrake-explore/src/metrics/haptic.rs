//! The haptic metrics: the design's brake model driving the haptic simulation's virtual wall
//! (`mrbrake haptic wall --brake-model`), with the study's `[haptic]` settings.
//!
//! ```toml
//! [haptic]                   # haptic metrics (withdraw_excess_torque_Nm, release_time_s, …)
//! device = "bidirectional"   # or "conventional" (the brake model's units on the device's brakes)
//! scenario = "press-withdraw"  # or "slide-hold", "moving-wall"
//! stiffness = "30N·m/rad"    # the virtual wall's K
//! damping = "0.02N·m·s/rad"  # the virtual wall's B
//! duration = "4s"            # run length (default: the scenario's)
//! control_period = "1ms"     # the controller's period (1 kHz, as `haptic wall`)
//! points = 21                # currents of the static curve (`analyze --points`)
//! dynamics = "predicted"     # the torque lag: the design's ("predicted") or the thesis's ("thesis")
//! ```
//!
//! One metric evaluation is what these commands do for the same design and settings:
//! `mrbrake analyze SPEC --mesh M --order O --points P --save-model m.json` (the static curve, the
//! off-state torque — the gaps' viscous torque and the study's seal friction — and the rotor
//! inertia), with `dynamics = "predicted"` also `mrbrake response SPEC --mesh M --save-model
//! m.json` (the torque lag fitted to the small-signal frequency response at the `[response]` bias,
//! the level-1 analysis the study shares), then `mrbrake haptic wall --device D --scenario S
//! --stiffness K --damping B --brake-model m.json --json`. The metrics are that JSON's
//! `withdraw_excess_torque_Nm.peak` (`withdraw_excess_torque_Nm`), `release_time_s`,
//! `displayed_stiffness_Nm_per_rad` and `free_motion_torque_Nm` (peak grip torque in free motion:
//! off-state drag + rotor inertia × the motion's acceleration,
//! [`mrbrake_sim::haptic::metrics`]). `haptic wall` has no flag for the control period: the
//! command equals a study at the default 1 ms.
//!
//! Defaults are `haptic wall`'s, except `device`, which the command requires: the bidirectional
//! device, the thesis's design (a conventional brake's sticky wall is a property of the device,
//! not of the brake design).

use mrbrake_design::analysis::{AnalysisOptions, AnalysisRequest};
use mrbrake_design::response::ResponseDrive;
use mrbrake_design::spec::BrakeSpec;
use mrbrake_sim::brake_model::apply::apply_to_haptic;
use mrbrake_sim::haptic::{DeviceKind, HapticConfig, Scenario, simulate};
use mrbrake_store::MetricValue;
use mrbrake_sysid::frd::Frd;
use mrbrake_units::{Dimension, parse};
use schemars::JsonSchema;
use serde::Deserialize;
use serde_json::{Value, json};

use crate::evaluate::EvaluationSettings;

/// Most currents of the brake model's static curve a study may ask for (each is a non-linear
/// field solution of every design; 201 is a 0.01 A step on 0–2 A).
pub const MAX_POINTS: usize = 201;

/// Where the simulated brake's torque lag comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum HapticDynamics {
    /// The design's: a two-pole fit to its small-signal frequency response (`response
    /// --save-model`).
    Predicted,
    /// The thesis prototype's measured lags (5.5)/(5.6) (a model without dynamics).
    Thesis,
}

/// What the haptic metrics are computed with (`mrbrake haptic wall`'s options).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HapticSettings {
    /// The device the brake model is mounted in.
    pub device: DeviceKind,
    /// What the hand does.
    pub scenario: Scenario,
    /// Virtual wall stiffness K (N·m/rad).
    pub stiffness_nm_per_rad: f64,
    /// Virtual wall damping B (N·m·s/rad).
    pub damping_nms_per_rad: f64,
    /// Run length (s); `None`: the scenario's.
    pub duration_s: Option<f64>,
    /// Controller period (s).
    pub control_period_s: f64,
    /// Currents of the static torque–current curve (≥ 2).
    pub points: usize,
    /// The brake's torque lag.
    pub dynamics: HapticDynamics,
}

impl Default for HapticSettings {
    fn default() -> Self {
        let wall = HapticConfig::new(DeviceKind::Bidirectional, Scenario::PressWithdraw);
        Self {
            device: wall.device,
            scenario: wall.scenario,
            stiffness_nm_per_rad: wall.wall_stiffness_nm_per_rad,
            damping_nms_per_rad: wall.wall_damping_nms_per_rad,
            duration_s: None,
            control_period_s: wall.control_period_s,
            points: AnalysisOptions::default().points,
            dynamics: HapticDynamics::Predicted,
        }
    }
}

impl HapticSettings {
    /// The settings as a JSON object (part of the design key and of every stored record).
    pub fn canonical(&self) -> Value {
        json!({
            "device": self.device.name(),
            "scenario": self.scenario.name(),
            "stiffness_Nm_per_rad": self.stiffness_nm_per_rad,
            "damping_Nm_s_per_rad": self.damping_nms_per_rad,
            "duration_s": self.duration_s,
            "control_period_s": self.control_period_s,
            "points": self.points,
            "dynamics": match self.dynamics {
                HapticDynamics::Predicted => "predicted",
                HapticDynamics::Thesis => "thesis",
            },
        })
    }

    /// The wall configuration of these settings before the brake model is applied; an error
    /// names the `[haptic]` key.
    pub fn config(&self) -> Result<HapticConfig, String> {
        let mut config = HapticConfig::new(self.device, self.scenario);
        config.wall_stiffness_nm_per_rad = self.stiffness_nm_per_rad;
        config.wall_damping_nms_per_rad = self.damping_nms_per_rad;
        config.duration_s = self.duration_s.unwrap_or(config.duration_s);
        config.control_period_s = self.control_period_s;
        config.validate().map_err(|e| format!("[haptic] {e}"))?;
        if !(2..=MAX_POINTS).contains(&self.points) {
            return Err(format!("[haptic] points = {} must be in 2..={MAX_POINTS}", self.points));
        }
        Ok(config)
    }
}

/// The four haptic metrics of one run of the design's brake model, or why there are none (the
/// error text and whether it is the design's: input).
pub(super) fn haptic_metrics(
    spec: &BrakeSpec,
    evaluation: &EvaluationSettings,
    settings: &HapticSettings,
    frequency_response: Option<(&Frd, f64, ResponseDrive)>,
) -> Result<Vec<(&'static str, MetricValue)>, (String, bool)> {
    let options = AnalysisOptions {
        mesh: evaluation.mesh,
        points: settings.points,
        speed_rad_s: evaluation.speed_rad_s,
        seal_friction_nm: evaluation.seal_friction_nm,
        temperature_c: evaluation.temperature_c,
        order: evaluation.order,
    };
    let analysis = AnalysisRequest::of(spec).options(options).run().map_err(fail)?;
    let source = "mrbrake study ([haptic] metrics)";
    let mut model = mrbrake_device::brake_model::from_analysis(&analysis, &options, None, source)
        .map_err(fail)?;
    if let Some((frd, bias, drive)) = frequency_response {
        mrbrake_device::brake_model::add_frequency_response(&mut model, frd, (bias, drive), source)
            .map_err(fail)?;
    }
    let mut config = settings.config().map_err(|e| (e, true))?;
    apply_to_haptic(&model, &mut config).map_err(fail)?;
    let wall = simulate(&config, false).map_err(fail)?.metrics;
    // A hand that never left the wall released at least the rest of the run after the withdrawal
    // began; a scenario without withdrawal has no release.
    let release = match (wall.release_time_s, config.scenario.withdraw_start_s()) {
        (Some(t), _) => MetricValue::Value(t),
        (None, Some(start)) => MetricValue::AtLeast((config.duration_s - start).max(0.0)),
        (None, None) => MetricValue::NotApplicable,
    };
    let stiffness = wall.displayed_stiffness_nm_per_rad.ok_or_else(|| {
        let why = "the hand did not press into the wall long enough to measure a stiffness";
        (format!("haptic wall ({}): {why}", settings.scenario.name()), true)
    })?;
    Ok(vec![
        ("withdraw_excess_torque_Nm", wall.withdraw_excess_torque_nm.peak.into()),
        ("release_time_s", release),
        ("displayed_stiffness_Nm_per_rad", stiffness.into()),
        ("free_motion_torque_Nm", wall.free_motion_torque_nm.into()),
    ])
}

fn fail<E: std::error::Error + mrbrake_error::Kind>(e: E) -> (String, bool) {
    (crate::evaluate::with_causes(&e), e.is_input_error())
}

/// `[haptic]`: the settings of the haptic metrics (defaults: `mrbrake haptic wall`'s).
#[derive(Debug, Default, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawHaptic {
    /// `bidirectional` (default: the thesis's device) or `conventional`.
    #[serde(default)]
    device: Option<String>,
    /// `press-withdraw` (default), `slide-hold` or `moving-wall`.
    #[serde(default)]
    scenario: Option<String>,
    /// Virtual wall stiffness K (e.g. `"30N·m/rad"`, the default).
    #[serde(default)]
    stiffness: Option<String>,
    /// Virtual wall damping B (e.g. `"0.02N·m·s/rad"`, the default).
    #[serde(default)]
    damping: Option<String>,
    /// Run length (e.g. `"4s"`; default the scenario's, 4 s).
    #[serde(default)]
    duration: Option<String>,
    /// The controller's period (e.g. `"1ms"`, the default: a 1 kHz haptic loop).
    #[serde(default)]
    control_period: Option<String>,
    /// Currents of the brake model's static curve (default 21, as `mrbrake analyze`).
    #[serde(default)]
    points: Option<usize>,
    /// `predicted` (default: the design's torque lag, from its small-signal response) or
    /// `thesis` (the prototype's measured lags (5.5)/(5.6)).
    #[serde(default)]
    dynamics: Option<String>,
}

impl RawHaptic {
    /// The settings over the defaults; an error names `haptic.KEY`.
    pub(crate) fn settings(&self) -> Result<HapticSettings, String> {
        let q = |key: &str, text: &str, d| parse(text, d).map_err(|e| format!("haptic.{key}: {e}"));
        let mut s = HapticSettings::default();
        if let Some(device) = &self.device {
            s.device = match DeviceKind::from_name(device) {
                Some(d @ (DeviceKind::Bidirectional | DeviceKind::Conventional)) => d,
                _ => {
                    return Err(format!(
                        "haptic.device: '{device}' is not a brake device: bidirectional or conventional"
                    ));
                }
            };
        }
        if let Some(scenario) = &self.scenario {
            s.scenario = Scenario::from_name(scenario).ok_or_else(|| {
                let names: Vec<&str> = Scenario::ALL.iter().map(|s| s.name()).collect();
                format!("haptic.scenario: '{scenario}' is none of {}", names.join(", "))
            })?;
        }
        if let Some(k) = &self.stiffness {
            s.stiffness_nm_per_rad = q("stiffness", k, Dimension::RotationalStiffness)?;
        }
        if let Some(b) = &self.damping {
            s.damping_nms_per_rad = q("damping", b, Dimension::RotationalDamping)?;
        }
        if let Some(t) = &self.duration {
            s.duration_s = Some(q("duration", t, Dimension::Time)?);
        }
        if let Some(t) = &self.control_period {
            s.control_period_s = q("control_period", t, Dimension::Time)?;
        }
        s.points = self.points.unwrap_or(s.points);
        if let Some(dynamics) = &self.dynamics {
            s.dynamics = match dynamics.as_str() {
                "predicted" => HapticDynamics::Predicted,
                "thesis" => HapticDynamics::Thesis,
                other => {
                    return Err(format!(
                        "haptic.dynamics: '{other}' is neither 'predicted' nor 'thesis'"
                    ));
                }
            };
        }
        s.config()?;
        Ok(s)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_are_the_wall_command_s_and_bad_keys_are_named() {
        let s = RawHaptic::default().settings().unwrap();
        assert_eq!(s, HapticSettings::default());
        let wall = HapticConfig::new(DeviceKind::Bidirectional, Scenario::PressWithdraw);
        assert_eq!(s.config().unwrap(), wall);
        let bad = |raw: RawHaptic| raw.settings().unwrap_err();
        let e = bad(RawHaptic { device: Some("motor".into()), ..Default::default() });
        assert!(e.contains("haptic.device"), "{e}");
        let e = bad(RawHaptic { stiffness: Some("-3N·m/rad".into()), ..Default::default() });
        assert!(e.contains("wall_stiffness"), "{e}");
        let e = bad(RawHaptic { points: Some(1), ..Default::default() });
        assert!(e.contains("points"), "{e}");
        let e = bad(RawHaptic { dynamics: Some("fast".into()), ..Default::default() });
        assert!(e.contains("haptic.dynamics"), "{e}");
    }
}
