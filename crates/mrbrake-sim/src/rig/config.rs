//! Configuration of the virtual test rig (TOML), with the thesis rig as the default.
//!
//! Every field has a default, so an empty file is the thesis set-up; unknown fields are rejected so a
//! typo does not silently fall back to a default. `mrbrake rig config` prints the defaults.

use std::path::Path;

use serde::{Deserialize, Serialize};

use crate::SimError;
use mrbrake_error::FieldError;

/// The whole rig.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct RigConfig {
    /// Seed of the sensor noise (same seed, same logs).
    pub seed: u64,
    /// The MR brake under test.
    pub brake: BrakeConfig,
    /// The DC motor that drives the shaft.
    pub motor: MotorConfig,
    /// The torque sensor and its amplifier.
    pub sensor: SensorConfig,
    /// Data acquisition.
    pub daq: DaqConfig,
    /// Characterisation protocol (§5.3.1).
    pub characterization: CharacterizationProtocol,
    /// Frequency-response protocol (§5.3.2).
    pub frequency_response: FrequencyResponseProtocol,
    /// Static hysteresis model of the brake (default: the play-type clamp).
    pub hysteresis: super::preisach::HysteresisConfig,
    /// Minor-loop protocol (`mrbrake rig minor-loops`).
    pub minor_loops: super::minor_loops::MinorLoopProtocol,
}

/// The brake: static hysteresis branches and a linear dynamic model.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct BrakeConfig {
    /// Static torque (N·m) on the rising-current branch, ascending powers of the current in A.
    pub rising: Vec<f64>,
    /// Static torque (N·m) on the falling-current branch, ascending powers of the current in A.
    pub falling: Vec<f64>,
    /// Highest allowed current, A.
    #[serde(rename = "current_max_A")]
    pub current_max_a: f64,
    /// Numerator of the torque dynamics (static torque → brake torque), highest power first.
    pub dynamics_numerator: Vec<f64>,
    /// Denominator of the torque dynamics, highest power first.
    pub dynamics_denominator: Vec<f64>,
    /// Viscous torque per unit shaft speed, N·m·s/rad.
    #[serde(rename = "viscous_Nm_s_per_rad")]
    pub viscous_nm_s_per_rad: f64,
    /// A tabulated Preisach model of the static torque (a brake model's `preisach` hysteresis,
    /// set by `brake_model::apply::apply_to_rig`; not a key of the TOML file). When set the plant
    /// runs it instead of `[hysteresis]`; the branches stay the controller's inverse.
    #[serde(skip)]
    pub everett: Option<super::everett::EverettTable>,
}

impl Default for BrakeConfig {
    /// Illustrative branches shaped like the prototype's loop (0.15 N·m at 0 A, 3.84 N·m at 2 A, widest
    /// gap 0.3 N·m at 1 A, falling branch above the rising one) and the thesis's brake-1 dynamics (5.5).
    fn default() -> Self {
        Self {
            rising: vec![0.15, 3.69, -1.38375, 0.230625],
            falling: vec![0.15, 4.29, -1.68375, 0.230625],
            current_max_a: 2.0,
            dynamics_numerator: vec![1.0],
            dynamics_denominator: vec![1.791e-5, 0.01702, 1.0],
            viscous_nm_s_per_rad: 0.0,
            everett: None,
        }
    }
}

/// The DC motor (voltage → speed, thesis (5.1)) and the belt to the brake shaft.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct MotorConfig {
    /// Numerator of voltage → motor speed (rad/s per V), highest power first.
    pub numerator: Vec<f64>,
    /// Denominator, highest power first.
    pub denominator: Vec<f64>,
    /// Constant drive voltage, V (the thesis drives the motor at a steady, slow speed).
    #[serde(rename = "voltage_V")]
    pub voltage_v: f64,
    /// Speed reduction from the motor shaft to the brake shaft (the 6:1 belt).
    pub belt_ratio: f64,
}

impl Default for MotorConfig {
    fn default() -> Self {
        Self {
            numerator: vec![10.35],
            denominator: vec![2e-5, 0.000368, 1.0],
            voltage_v: 1.0,
            belt_ratio: 6.0,
        }
    }
}

/// Torque sensor (FUTEK TRS300 with CSG110 amplifier, Appendix A).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SensorConfig {
    /// Torsional stiffness, N·m/rad (955 for the TRS300); used for the twist column of the logs.
    #[serde(rename = "stiffness_Nm_per_rad")]
    pub stiffness_nm_per_rad: f64,
    /// Torque at full-scale output, N·m (±10 N·m).
    #[serde(rename = "full_scale_Nm")]
    pub full_scale_nm: f64,
    /// Full-scale output voltage, V (±10 V).
    #[serde(rename = "full_scale_V")]
    pub full_scale_v: f64,
    /// Noise standard deviation at the amplifier output, V (15 mV peak-to-peak ≈ 2.5 mV RMS, Table A.2).
    #[serde(rename = "noise_std_V")]
    pub noise_std_v: f64,
    /// ADC resolution over ±full-scale voltage, bits (16 for the PXI-6229, Appendix B).
    pub adc_bits: u32,
}

impl Default for SensorConfig {
    fn default() -> Self {
        Self {
            stiffness_nm_per_rad: 955.0,
            full_scale_nm: 10.0,
            full_scale_v: 10.0,
            noise_std_v: 0.0025,
            adc_bits: 16,
        }
    }
}

/// Sampling and actuation rates.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct DaqConfig {
    /// Logging rate, Hz (1 kHz in the thesis).
    #[serde(rename = "sample_rate_Hz")]
    pub sample_rate_hz: f64,
    /// Rate at which the current command is updated (zero-order hold), Hz; an integer multiple of the
    /// sample rate. At 1 kHz the hold delays the command by about half a sample (0.5 ms).
    #[serde(rename = "output_rate_Hz")]
    pub output_rate_hz: f64,
}

impl Default for DaqConfig {
    fn default() -> Self {
        Self { sample_rate_hz: 1000.0, output_rate_hz: 1000.0 }
    }
}

/// §5.3.1: 0 → I_max in steps, back down, pause, repeated.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct CharacterizationProtocol {
    /// Current step, A (1 mA).
    #[serde(rename = "step_A")]
    pub step_a: f64,
    /// Duration of each step, s (10 ms).
    pub step_s: f64,
    /// Pause at 0 A after each sequence, s (5 s).
    pub pause_s: f64,
    /// Number of sequences (10).
    pub repetitions: usize,
}

impl Default for CharacterizationProtocol {
    fn default() -> Self {
        Self { step_a: 1e-3, step_s: 0.01, pause_s: 5.0, repetitions: 10 }
    }
}

/// §5.3.2: sinusoidal torque demands at log-spaced frequencies.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct FrequencyResponseProtocol {
    /// Lowest frequency, rad/s.
    pub omega_min_rad_s: f64,
    /// Highest frequency, rad/s.
    pub omega_max_rad_s: f64,
    /// Test points per decade (10).
    pub points_per_decade: usize,
    /// Lowest torque of the sinusoidal demand, N·m.
    #[serde(rename = "torque_min_Nm")]
    pub torque_min_nm: f64,
    /// Highest torque of the sinusoidal demand, N·m.
    #[serde(rename = "torque_max_Nm")]
    pub torque_max_nm: f64,
    /// Periods recorded before the analysed part (start-up).
    pub periods_discarded: f64,
    /// Minimum seconds recorded before the analysed part.
    pub settle_s: f64,
    /// Periods analysed.
    pub periods_measured: f64,
    /// Minimum seconds analysed.
    pub min_measure_s: f64,
}

impl Default for FrequencyResponseProtocol {
    fn default() -> Self {
        Self {
            omega_min_rad_s: 0.1,
            omega_max_rad_s: 1000.0,
            points_per_decade: 10,
            torque_min_nm: 0.5,
            torque_max_nm: 3.5,
            periods_discarded: 1.0,
            settle_s: 0.5,
            periods_measured: 2.0,
            min_measure_s: 2.0,
        }
    }
}

impl Default for RigConfig {
    fn default() -> Self {
        Self {
            seed: 1,
            brake: BrakeConfig::default(),
            motor: MotorConfig::default(),
            sensor: SensorConfig::default(),
            daq: DaqConfig::default(),
            characterization: CharacterizationProtocol::default(),
            frequency_response: FrequencyResponseProtocol::default(),
            hysteresis: Default::default(),
            minor_loops: Default::default(),
        }
    }
}

impl RigConfig {
    /// Reads and checks a configuration file.
    pub fn read(path: &Path) -> Result<Self, SimError> {
        let text =
            mrbrake_error::read::text(path, mrbrake_error::read::SETTINGS).map_err(|source| {
                SimError::Io { what: "rig configuration", path: path.to_path_buf(), source }
            })?;
        Self::from_toml(&path.display().to_string(), &text)
    }

    /// Parses TOML text; `source` names the file in errors.
    pub fn from_toml(source: &str, text: &str) -> Result<Self, SimError> {
        let config: Self = toml::from_str(text)
            .map_err(|e| SimError::Toml { file: source.to_string(), source: e })?;
        config.validate(source)?;
        Ok(config)
    }

    /// The configuration as TOML text.
    pub fn to_toml(&self) -> String {
        toml::to_string(self).unwrap_or_default()
    }

    /// Checks ranges; the error names the file, the field, its value and what is allowed.
    pub fn validate(&self, source: &str) -> Result<(), SimError> {
        let pair = |(field, msg): (&'static str, String)| Box::new(FieldError::new(field, msg));
        self.check_plant()
            .and_then(|()| self.check_protocols())
            .and_then(|()| super::check_run_size(self).map_err(pair))
            .and_then(|()| self.hysteresis.check().map_err(pair))
            .and_then(|()| self.minor_loops.check(self.brake.current_max_a).map_err(pair))
            .map_err(|e| SimError::from((*e).in_file(source, None)))?;
        self.check_preisach().map_err(|e| match e {
            SimError::Input(field) => SimError::from((*field).in_file(source, None)),
            other => other,
        })
    }

    /// The Preisach model is built once here, so that a loop and prior it cannot represent are
    /// refused naming the file (found by the fuzzer: the run named only the field).
    fn check_preisach(&self) -> Result<(), SimError> {
        let b = &self.brake;
        if let Some(table) = &b.everett {
            return super::preisach::PreisachHysteresis::from_everett(table, 0.0).map(|_| ());
        }
        if self.hysteresis.model != super::preisach::HysteresisKind::Preisach {
            return Ok(());
        }
        super::preisach::PreisachHysteresis::new(
            &self.hysteresis,
            &b.rising,
            &b.falling,
            b.current_max_a,
        )
        .map(|_| ())
    }

    /// Brake, motor, sensor and acquisition: the first bad field.
    fn check_plant(&self) -> Result<(), Box<FieldError>> {
        let coefficients = "a non-empty list of finite coefficients";
        for (field, list) in
            [("brake.rising", &self.brake.rising), ("brake.falling", &self.brake.falling)]
        {
            if list.is_empty() || list.iter().any(|c| !c.is_finite()) {
                let bad = list.iter().find(|c| !c.is_finite()).map_or("[]".into(), f64::to_string);
                return Err(Box::new(FieldError::out_of_range(field, bad, coefficients)));
            }
        }
        let s = &self.sensor;
        let checks: [(&str, f64, bool, String); 9] = [
            (
                "brake.current_max_A",
                self.brake.current_max_a,
                positive(self.brake.current_max_a),
                "> 0 A".into(),
            ),
            (
                "brake.viscous_Nm_s_per_rad",
                self.brake.viscous_nm_s_per_rad,
                non_negative(self.brake.viscous_nm_s_per_rad),
                ">= 0".into(),
            ),
            (
                "motor.belt_ratio",
                self.motor.belt_ratio,
                positive(self.motor.belt_ratio),
                "> 0".into(),
            ),
            // Found by the fuzzer: an infinite motor voltage was accepted and the log held NaN.
            (
                "motor.voltage_V",
                self.motor.voltage_v,
                positive(self.motor.voltage_v) && self.motor.voltage_v <= 1e6,
                "(0, 1e6] V".into(),
            ),
            (
                "sensor.stiffness_Nm_per_rad",
                s.stiffness_nm_per_rad,
                positive(s.stiffness_nm_per_rad),
                "> 0".into(),
            ),
            ("sensor.full_scale_Nm", s.full_scale_nm, positive(s.full_scale_nm), "> 0".into()),
            (
                "sensor.full_scale_V",
                s.full_scale_v,
                positive(s.full_scale_v) && s.full_scale_v <= super::MAX_FULL_SCALE_V,
                format!("(0, {}] V", super::MAX_FULL_SCALE_V),
            ),
            ("sensor.noise_std_V", s.noise_std_v, non_negative(s.noise_std_v), ">= 0 V".into()),
            (
                "sensor.adc_bits",
                f64::from(s.adc_bits),
                (1..=32).contains(&s.adc_bits),
                "1..=32".into(),
            ),
        ];
        first_failed(&checks)?;
        let d = &self.daq;
        let ratio = d.output_rate_hz / d.sample_rate_hz;
        let checks: [(&str, f64, bool, String); 3] = [
            ("daq.sample_rate_Hz", d.sample_rate_hz, positive(d.sample_rate_hz), "> 0 Hz".into()),
            ("daq.output_rate_Hz", d.output_rate_hz, positive(d.output_rate_hz), "> 0 Hz".into()),
            (
                "daq.output_rate_Hz",
                d.output_rate_hz,
                ratio >= 1.0 && (ratio - ratio.round()).abs() <= 1e-9,
                format!("an integer multiple of sample_rate_Hz = {} Hz", d.sample_rate_hz),
            ),
        ];
        first_failed(&checks)
    }

    /// The characterisation and frequency-response protocols: the first bad field.
    fn check_protocols(&self) -> Result<(), Box<FieldError>> {
        let c = &self.characterization;
        let max = self.brake.current_max_a;
        let f = &self.frequency_response;
        let checks: [(&str, f64, bool, String); 11] = [
            (
                "characterization.step_A",
                c.step_a,
                positive(c.step_a) && c.step_a <= max,
                format!("(0, current_max_A = {max}] A"),
            ),
            ("characterization.step_s", c.step_s, positive(c.step_s), "> 0 s".into()),
            ("characterization.pause_s", c.pause_s, non_negative(c.pause_s), ">= 0 s".into()),
            (
                "characterization.repetitions",
                c.repetitions as f64,
                c.repetitions >= 1,
                ">= 1".into(),
            ),
            (
                "frequency_response.omega_min_rad_s",
                f.omega_min_rad_s,
                positive(f.omega_min_rad_s),
                "> 0 rad/s".into(),
            ),
            (
                "frequency_response.omega_max_rad_s",
                f.omega_max_rad_s,
                non_negative(f.omega_max_rad_s - f.omega_min_rad_s),
                format!(">= omega_min_rad_s = {} rad/s", f.omega_min_rad_s),
            ),
            (
                "frequency_response.points_per_decade",
                f.points_per_decade as f64,
                f.points_per_decade >= 1,
                ">= 1".into(),
            ),
            (
                "frequency_response.torque_max_Nm",
                f.torque_max_nm,
                positive(f.torque_max_nm - f.torque_min_nm),
                format!("> torque_min_Nm = {} N·m", f.torque_min_nm),
            ),
            (
                "frequency_response.periods_measured",
                f.periods_measured,
                positive(f.periods_measured),
                "> 0".into(),
            ),
            (
                "frequency_response.periods_discarded",
                f.periods_discarded,
                non_negative(f.periods_discarded),
                ">= 0".into(),
            ),
            (
                "frequency_response.settle_s",
                f.settle_s,
                non_negative(f.settle_s) && non_negative(f.min_measure_s),
                "settle_s and min_measure_s >= 0 s".into(),
            ),
        ];
        first_failed(&checks)
    }
}

/// The first check that failed, as a field error with its value and the allowed range.
fn first_failed(checks: &[(&str, f64, bool, String)]) -> Result<(), Box<FieldError>> {
    match checks.iter().find(|(_, _, ok, _)| !ok) {
        Some((field, value, _, allowed)) => {
            Err(Box::new(FieldError::out_of_range(*field, value, allowed.clone())))
        }
        None => Ok(()),
    }
}

/// True for a finite number > 0.
fn positive(v: f64) -> bool {
    v.is_finite() && v > 0.0
}

/// True for a finite number ≥ 0.
fn non_negative(v: f64) -> bool {
    v.is_finite() && v >= 0.0
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn empty_file_is_the_default_and_round_trips() {
        let c = RigConfig::from_toml("rig.toml", "").unwrap();
        assert_eq!(c, RigConfig::default());
        let back = RigConfig::from_toml("rig.toml", &c.to_toml()).unwrap();
        assert_eq!(back, c);
    }

    #[test]
    fn typo_and_bad_value_name_file_and_field() {
        let e = RigConfig::from_toml("rig.toml", "[brake]\ncurent_max_A = 2.0\n").unwrap_err();
        assert!(matches!(&e, SimError::Toml { file, .. } if file == "rig.toml"));
        let cause = std::error::Error::source(&e).unwrap().to_string();
        assert!(cause.contains("curent_max_A"), "{cause}");
        let missing = RigConfig::read(Path::new("no/such/rig.toml")).unwrap_err();
        assert!(missing.to_string().contains("no/such/rig.toml"));
        assert!(mrbrake_error::Kind::is_input_error(&missing));
        let e = RigConfig::from_toml("rig.toml", "[daq]\noutput_rate_Hz = 1500\n")
            .unwrap_err()
            .to_string();
        assert!(e.contains("daq.output_rate_Hz"), "{e}");
    }
}
