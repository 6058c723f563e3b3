//! The TOML layout of problem files, as read by serde (unknown keys are errors).

use mrbrake_fem::workflow::time::AdaptiveKeys;
use serde::Deserialize;

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawFile {
    pub mesh: String,
    #[serde(default)]
    pub length_unit: Option<String>,
    #[serde(default)]
    pub order: Option<toml::Value>,
    #[serde(default)]
    pub solver: Option<RawSolver>,
    #[serde(default)]
    pub region: Vec<RawRegion>,
    #[serde(default)]
    pub boundary: Vec<RawBoundary>,
    #[serde(default)]
    pub probe: Vec<RawProbe>,
    #[serde(default)]
    pub line: Vec<RawLine>,
    #[serde(default)]
    pub transient: Option<RawTransient>,
    #[serde(default)]
    pub harmonic: Option<RawHarmonic>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawSolver {
    pub max_iterations: Option<usize>,
    pub tolerance: Option<f64>,
    pub quadrature_degree: Option<usize>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawRegion {
    pub physical: u32,
    pub material: Option<toml::Value>,
    pub source: Option<toml::Value>,
    #[serde(rename = "conductivity_S_per_m")]
    pub conductivity: Option<f64>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawBoundary {
    pub physical: u32,
    pub kind: String,
    pub centre_z: Option<f64>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawProbe {
    pub name: String,
    pub r: f64,
    pub z: f64,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawLine {
    pub name: String,
    pub from: [f64; 2],
    pub to: [f64; 2],
    pub samples: Option<usize>,
}

/// `[transient]`: a time-stepped solve (see `super::dynamics`).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawTransient {
    pub t_end: f64,
    pub dt: Option<f64>,
    pub adaptive: Option<AdaptiveKeys>,
    pub scheme: Option<String>,
    pub waveform: Option<RawWaveform>,
    pub vtu_times: Option<Vec<f64>>,
    pub max_steps: Option<usize>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawWaveform {
    pub kind: String,
    pub rise_s: Option<f64>,
    #[serde(rename = "frequency_Hz")]
    pub frequency_hz: Option<f64>,
    pub offset: Option<f64>,
    pub file: Option<String>,
}

/// `[harmonic]`: time-harmonic (or small-signal) solves.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawHarmonic {
    #[serde(rename = "frequencies_Hz")]
    pub frequencies_hz: Vec<f64>,
    pub bias: Option<RawBias>,
    #[serde(rename = "vtu_frequencies_Hz")]
    pub vtu_frequencies_hz: Option<Vec<f64>>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawBias {
    /// Every coil at this current.
    #[serde(rename = "current_A")]
    pub current_a: Option<f64>,
    /// Or each listed coil at its own current (the others at 0 A).
    pub coils: Option<Vec<RawCoilBias>>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawCoilBias {
    pub physical: u32,
    #[serde(rename = "current_A")]
    pub current_a: f64,
}
