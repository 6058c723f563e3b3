//! The TOML layout of heat problem files, as read by serde (unknown keys are errors).

use mrbrake_fem::workflow::time::AdaptiveKeys;
use serde::Deserialize;

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawFile {
    pub physics: String,
    pub mesh: String,
    #[serde(default)]
    pub length_unit: Option<String>,
    #[serde(default)]
    pub order: Option<i64>,
    #[serde(default)]
    pub solver: Option<RawSolver>,
    #[serde(default)]
    pub region: Vec<RawRegion>,
    #[serde(default)]
    pub boundary: Vec<RawBoundary>,
    #[serde(default)]
    pub transient: Option<RawTransient>,
    #[serde(default)]
    pub probe: Vec<RawProbe>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawSolver {
    pub max_iterations: Option<usize>,
    pub tolerance: Option<f64>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawRegion {
    pub physical: u32,
    pub material: Option<RawMaterial>,
    #[serde(rename = "heat_source_W_per_m3")]
    pub heat_source_w_per_m3: Option<f64>,
    #[serde(rename = "heat_W")]
    pub heat_w: Option<f64>,
    pub joule: Option<RawJoule>,
}

#[derive(Debug, Deserialize)]
#[serde(untagged)]
pub(super) enum RawMaterial {
    Name(String),
    Table(RawMaterialTable),
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawMaterialTable {
    #[serde(rename = "k_W_per_mK")]
    pub k: Option<f64>,
    #[serde(rename = "k_radial_W_per_mK")]
    pub k_radial: Option<f64>,
    #[serde(rename = "k_axial_W_per_mK")]
    pub k_axial: Option<f64>,
    #[serde(rename = "rho_kg_per_m3")]
    pub rho: Option<f64>,
    #[serde(rename = "c_J_per_kgK")]
    pub c: Option<f64>,
    /// A homogenised winding in impregnating resin with this copper fill factor.
    pub winding_fill_factor: Option<f64>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawJoule {
    #[serde(rename = "current_A")]
    pub current_a: f64,
    pub turns: Option<f64>,
    pub wire_diameter_m: Option<f64>,
    #[serde(rename = "resistance_20C_ohm")]
    pub resistance_20c_ohm: Option<f64>,
    #[serde(rename = "alpha_per_K")]
    pub alpha_per_k: Option<f64>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawBoundary {
    pub physical: u32,
    pub kind: String,
    #[serde(rename = "h_W_per_m2K")]
    pub h: Option<f64>,
    #[serde(rename = "T_amb_C")]
    pub t_amb_c: Option<f64>,
    #[serde(rename = "T_C")]
    pub t_c: Option<f64>,
    pub emissivity: Option<f64>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawTransient {
    pub t_end: f64,
    pub dt: Option<f64>,
    pub adaptive: Option<AdaptiveKeys>,
    #[serde(rename = "T_initial_C")]
    pub t_initial_c: Option<f64>,
    pub scheme: Option<String>,
    pub max_steps: Option<usize>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawProbe {
    pub name: String,
    pub r: f64,
    pub z: f64,
}
