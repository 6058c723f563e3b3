//! The settings of the dynamics and heat metrics: a problem file's `[response]` and `[thermal]`
//! tables, with the keys, units and defaults of `mrbrake response` and `mrbrake thermal`, so a
//! metric of a study equals the command's JSON for the same design and settings.
//!
//! ```toml
//! [response]                 # dynamics metrics (bandwidth_rad_s, t63_s, t63_fall_s, …)
//! drive = "current"          # or "voltage" (through the coil's resistance)
//! step = "0A..2A"            # the step up; the release (fall times) is the step back, 2A..0A
//! bias = "1A"                # bias of the small-signal response (default half the max current)
//! duration = "100ms"         # of each step response
//! conductivity = "5.8MS/m"   # flux-path steel (default: the material library's value)
//! fluid_lag = "0.48ms"       # first-order lag of the fluid (default T90 = 1.1 ms over ln 10)
//! [thermal]                  # heat metrics (continuous_current_A, coil_max_T_C, …)
//! current = "2A"             # current when on (default the spec's maximum current)
//! duty = 1.0                 # in (0, 1]
//! ambient = "25C"
//! h = "10W/(m²·K)"           # or "natural" (still air, axis horizontal)
//! emissivity = 0.0
//! insulation_class = "F"     # or a temperature, "155C"
//! time = "2h"                # warm-up duration (time_to_limit_s)
//! dt = "10s"                 # warm-up step
//! speed = "0rad/s"           # shaft speed of the viscous heat
//! ```

use mrbrake_design::response::{ResponseDrive, ResponseOptions, parse_step};
use mrbrake_design::spec::BrakeSpec;
use mrbrake_design::thermal::{Cooling, ThermalOptions, insulation_limit_c};
use mrbrake_units::{Dimension, parse};
use schemars::JsonSchema;
use serde::Deserialize;
use serde_json::{Value, json};

use crate::evaluate::EvaluationSettings;

/// What the dynamics metrics are computed with (`mrbrake response`'s options).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ResponseSettings {
    /// Current or voltage drive.
    pub drive: ResponseDrive,
    /// The step up starts here (A); the release ends here.
    pub step_from_a: f64,
    /// The step up ends here (A); `None`: the spec's maximum current.
    pub step_to_a: Option<f64>,
    /// DC bias of the frequency response (A); `None`: half the maximum current.
    pub bias_a: Option<f64>,
    /// Duration of each step response (s).
    pub duration_s: f64,
    /// First-order lag of the fluid (s).
    pub fluid_lag_s: f64,
    /// Conductivity of the flux-path steel (S/m); `None`: the library's.
    pub conductivity_s_per_m: Option<f64>,
}

impl Default for ResponseSettings {
    fn default() -> Self {
        let o = ResponseOptions::default();
        Self {
            drive: o.drive,
            step_from_a: o.step_from_a,
            step_to_a: o.step_to_a,
            bias_a: o.bias_a,
            duration_s: o.duration_s,
            fluid_lag_s: o.fluid_lag_s,
            conductivity_s_per_m: o.flux_path_conductivity_s_per_m,
        }
    }
}

impl ResponseSettings {
    /// The response options of one evaluation (mesh, order and copper temperature of the study).
    pub fn options(&self, evaluation: &EvaluationSettings) -> ResponseOptions {
        ResponseOptions {
            mesh: evaluation.mesh,
            order: evaluation.order,
            drive: self.drive,
            step_from_a: self.step_from_a,
            step_to_a: self.step_to_a,
            bias_a: self.bias_a,
            duration_s: self.duration_s,
            fluid_lag_s: self.fluid_lag_s,
            flux_path_conductivity_s_per_m: self.conductivity_s_per_m,
            temperature_c: evaluation.temperature_c,
            ..ResponseOptions::default()
        }
    }

    /// The settings as a JSON object (part of the design key and of every stored record).
    pub fn canonical(&self) -> Value {
        json!({
            "drive": match self.drive { ResponseDrive::Current => "current", ResponseDrive::Voltage => "voltage" },
            "step_from_A": self.step_from_a,
            "step_to_A": self.step_to_a,
            "bias_A": self.bias_a,
            "duration_s": self.duration_s,
            "fluid_lag_s": self.fluid_lag_s,
            "conductivity_S_per_m": self.conductivity_s_per_m,
        })
    }
}

/// What the heat metrics are computed with (`mrbrake thermal`'s options).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ThermalSettings {
    /// Current when on (A); `None`: the spec's maximum current.
    pub current_a: Option<f64>,
    /// Duty cycle in (0, 1].
    pub duty: f64,
    /// Ambient (°C).
    pub ambient_c: f64,
    /// Cooling of the housing.
    pub cooling: Cooling,
    /// Emissivity of the housing.
    pub emissivity: f64,
    /// Insulation limit (°C).
    pub limit_c: f64,
    /// Warm-up duration (s).
    pub time_s: f64,
    /// Warm-up step (s).
    pub dt_s: f64,
    /// Shaft speed of the viscous heat (rad/s).
    pub speed_rad_s: f64,
}

impl Default for ThermalSettings {
    fn default() -> Self {
        let o = ThermalOptions::default();
        Self {
            current_a: None,
            duty: o.duty,
            ambient_c: o.ambient_c,
            cooling: o.cooling,
            emissivity: o.emissivity,
            limit_c: o.limit_c,
            time_s: o.time_s,
            dt_s: o.dt_s,
            speed_rad_s: o.speed_rad_s,
        }
    }
}

impl ThermalSettings {
    /// The thermal options of one evaluation of `spec` (the study's mesh).
    pub fn options(&self, spec: &BrakeSpec, evaluation: &EvaluationSettings) -> ThermalOptions {
        ThermalOptions {
            current_a: self.current_a.unwrap_or_else(|| spec.coil.max_current.a()),
            duty: self.duty,
            period_s: None,
            ambient_c: self.ambient_c,
            cooling: self.cooling,
            emissivity: self.emissivity,
            limit_c: self.limit_c,
            time_s: self.time_s,
            dt_s: self.dt_s,
            speed_rad_s: self.speed_rad_s,
            mesh: evaluation.mesh,
            behaviour: false,
        }
    }

    /// The settings as a JSON object (part of the design key and of every stored record).
    pub fn canonical(&self) -> Value {
        let h = match self.cooling {
            Cooling::Fixed { h_w_per_m2k } => json!(h_w_per_m2k),
            Cooling::Natural => json!("natural"),
        };
        json!({
            "current_A": self.current_a,
            "duty": self.duty,
            "ambient_C": self.ambient_c,
            "h_W_per_m2_K": h,
            "emissivity": self.emissivity,
            "limit_C": self.limit_c,
            "time_s": self.time_s,
            "dt_s": self.dt_s,
            "speed_rad_s": self.speed_rad_s,
        })
    }
}

/// A number or a text (a quantity with its unit, or a word).
#[derive(Debug, Clone, PartialEq, Deserialize, JsonSchema)]
#[serde(untagged)]
pub(crate) enum NumberOrText {
    /// A number (SI, or the key's stated unit).
    Number(f64),
    /// A quantity with its unit, or a word.
    Text(String),
}

/// `[response]`: the settings of the dynamics metrics (defaults: `mrbrake response`'s).
#[derive(Debug, Default, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawResponse {
    /// `current` (a current amplifier, default) or `voltage` (through the coil's resistance).
    #[serde(default)]
    drive: Option<String>,
    /// The current step `FROM..TO` of `t63_s`/`t90_s` (e.g. `"0A..2A"`; default 0 A to the
    /// maximum current); the release of the fall times is the step back, `TO..FROM`.
    #[serde(default)]
    step: Option<String>,
    /// DC bias of the small-signal response of `bandwidth_rad_s` (e.g. `"1A"`; default half the
    /// maximum current).
    #[serde(default)]
    bias: Option<String>,
    /// Duration of each step response (e.g. `"100ms"`, the default).
    #[serde(default)]
    duration: Option<String>,
    /// Conductivity of the flux-path steel (e.g. `"5.8MS/m"`; default the library's value).
    #[serde(default)]
    conductivity: Option<String>,
    /// First-order lag of the fluid (e.g. `"0.48ms"`; default T90 = 1.1 ms over ln 10).
    #[serde(default)]
    fluid_lag: Option<String>,
}

/// `[thermal]`: the settings of the heat metrics (defaults: `mrbrake thermal`'s).
#[derive(Debug, Default, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawThermal {
    /// Coil current when on (e.g. `"2A"`; default the spec's maximum current).
    #[serde(default)]
    current: Option<String>,
    /// Duty cycle in (0, 1] (default 1).
    #[serde(default)]
    duty: Option<f64>,
    /// Ambient temperature (e.g. `"25C"`, the default).
    #[serde(default)]
    ambient: Option<String>,
    /// Heat-transfer coefficient of the housing (`"10W/(m²·K)"`; a number is W/(m²·K); default
    /// 10), or `"natural"` (natural convection to still air, axis horizontal).
    #[serde(default)]
    h: Option<NumberOrText>,
    /// Emissivity of the housing in [0, 1] (default 0: no radiation).
    #[serde(default)]
    emissivity: Option<f64>,
    /// Insulation limit: a temperature (`"155C"`, the default) or a class letter (A, E, B, F, H).
    #[serde(default)]
    insulation_class: Option<String>,
    /// Warm-up duration of `time_to_limit_s` (e.g. `"2h"`, the default).
    #[serde(default)]
    time: Option<String>,
    /// Warm-up time step (e.g. `"10s"`, the default).
    #[serde(default)]
    dt: Option<String>,
    /// Shaft speed of the viscous heat (e.g. `"0rad/s"`, the default).
    #[serde(default)]
    speed: Option<String>,
}

fn quantity(table: &str, key: &str, text: &str, dimension: Dimension) -> Result<f64, String> {
    parse(text, dimension).map_err(|e| format!("{table}.{key}: {e}"))
}

impl RawResponse {
    /// The settings over the defaults; an error names `response.KEY`.
    pub(crate) fn settings(&self) -> Result<ResponseSettings, String> {
        let q = |key: &str, text: &str, d| quantity("response", key, text, d);
        let mut s = ResponseSettings::default();
        if let Some(drive) = &self.drive {
            s.drive = ResponseDrive::parse(drive).map_err(|e| format!("response.drive: {e}"))?;
        }
        if let Some(step) = &self.step {
            let (from, to) = parse_step(step).map_err(|e| format!("response.step: {e}"))?;
            if !(from.is_finite() && from >= 0.0 && to.is_finite() && to > from) {
                return Err(format!(
                    "response.step: {from} A..{to} A must be a step up from a current >= 0"
                ));
            }
            (s.step_from_a, s.step_to_a) = (from, Some(to));
        }
        if let Some(bias) = &self.bias {
            s.bias_a = Some(q("bias", bias, Dimension::Current)?);
        }
        if let Some(duration) = &self.duration {
            s.duration_s = q("duration", duration, Dimension::Time)?;
        }
        if let Some(sigma) = &self.conductivity {
            s.conductivity_s_per_m = Some(q("conductivity", sigma, Dimension::Conductivity)?);
        }
        if let Some(lag) = &self.fluid_lag {
            s.fluid_lag_s = q("fluid_lag", lag, Dimension::Time)?;
        }
        Ok(s)
    }
}

impl RawThermal {
    /// The settings over the defaults; an error names `thermal.KEY`.
    pub(crate) fn settings(&self) -> Result<ThermalSettings, String> {
        let q = |key: &str, text: &str, d| quantity("thermal", key, text, d);
        let mut s = ThermalSettings::default();
        if let Some(current) = &self.current {
            s.current_a = Some(q("current", current, Dimension::Current)?);
        }
        s.duty = self.duty.unwrap_or(s.duty);
        if let Some(ambient) = &self.ambient {
            s.ambient_c = q("ambient", ambient, Dimension::TemperatureCelsius)?;
        }
        match &self.h {
            Some(NumberOrText::Number(h)) => s.cooling = Cooling::Fixed { h_w_per_m2k: *h },
            Some(NumberOrText::Text(t)) => {
                s.cooling = Cooling::parse(t).map_err(|e| format!("thermal.h: {e}"))?
            }
            None => {}
        }
        s.emissivity = self.emissivity.unwrap_or(s.emissivity);
        if let Some(class) = &self.insulation_class {
            s.limit_c =
                insulation_limit_c(class).map_err(|e| format!("thermal.insulation_class: {e}"))?;
        }
        if let Some(time) = &self.time {
            s.time_s = q("time", time, Dimension::Time)?;
        }
        if let Some(dt) = &self.dt {
            s.dt_s = q("dt", dt, Dimension::Time)?;
        }
        if let Some(speed) = &self.speed {
            s.speed_rad_s = q("speed", speed, Dimension::AngularVelocity)?;
        }
        Ok(s)
    }
}

/// The [`super::StudyMetrics`] of a problem file: the metrics of `record`, the constraints and
/// the objectives, the constraints as gates, and the `[response]`, `[thermal]` and `[haptic]`
/// settings; an
/// error names the key.
pub(crate) fn study_of(
    record: &[String],
    response: &Option<RawResponse>,
    thermal: &Option<RawThermal>,
    haptic: &Option<super::haptic::RawHaptic>,
    constraints: &[crate::problem::Constraint],
    objectives: &[crate::problem::Objective],
) -> Result<super::StudyMetrics, String> {
    let mut asked: Vec<&str> = Vec::new();
    for (i, name) in record.iter().enumerate() {
        let info = crate::problem::known_metric(name)
            .map_err(|e| format!("record[{i}] ('{name}'): {e}"))?;
        asked.push(info.name);
    }
    asked.extend(constraints.iter().map(|c| c.metric.as_str()));
    asked.extend(objectives.iter().map(|o| o.metric.as_str()));
    let response =
        response.as_ref().map_or(Ok(ResponseSettings::default()), RawResponse::settings)?;
    let thermal = thermal.as_ref().map_or(Ok(ThermalSettings::default()), RawThermal::settings)?;
    let haptic = haptic.as_ref().map_or(Ok(super::HapticSettings::default()), |h| h.settings())?;
    let mut study = super::StudyMetrics::new(asked, constraints, response, thermal);
    study.haptic = haptic;
    Ok(study)
}
