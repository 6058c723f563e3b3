//! The TOML layout of problem files, as read by serde (unknown keys are errors).

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
