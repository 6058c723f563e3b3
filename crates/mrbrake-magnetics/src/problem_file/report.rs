//! The result of a file-driven solve: the `--json` object of `mrbrake fem solve` (its text is
//! composed by `mrbrake_report::fem`, as every command's text).

use serde::Serialize;

use crate::field::{PointField, RegionStats};

/// B at a named probe (JSON field names as documented for `mrbrake fem solve --json`).
#[derive(Debug, Clone, Serialize)]
pub struct ProbeReport {
    /// Probe name.
    pub name: String,
    /// Radius (m).
    #[serde(rename = "r_m")]
    pub r: f64,
    /// Axial position (m).
    #[serde(rename = "z_m")]
    pub z: f64,
    /// Radial flux density (T).
    #[serde(rename = "B_r_T")]
    pub b_r_t: f64,
    /// Axial flux density (T).
    #[serde(rename = "B_z_T")]
    pub b_z_t: f64,
    /// |B| (T).
    #[serde(rename = "B_abs_T")]
    pub b_abs_t: f64,
}

/// Region statistics in the report.
#[derive(Debug, Clone, Serialize)]
pub struct RegionReport {
    /// Physical tag.
    pub physical: u32,
    /// Cross-section area (m²).
    pub area_m2: f64,
    /// Volume-weighted mean |B| (T).
    #[serde(rename = "mean_B_T")]
    pub mean_b_t: f64,
    /// Max |B| (T).
    #[serde(rename = "max_B_T")]
    pub max_b_t: f64,
    /// 10/50/90 % volume quantiles of |B| (T).
    #[serde(rename = "quantiles_B_T")]
    pub quantiles_b_t: [f64; 3],
}

/// Coil results in the report.
#[derive(Debug, Clone, Serialize)]
pub struct CoilReport {
    /// Physical tag.
    pub physical: u32,
    /// Flux linkage (Wb).
    #[serde(rename = "flux_linkage_Wb")]
    pub flux_linkage_wb: f64,
    /// Secant inductance λ/I (H).
    #[serde(rename = "inductance_H")]
    pub inductance_h: f64,
    /// Incremental inductance dλ/dI (H).
    #[serde(rename = "incremental_inductance_H")]
    pub incremental_inductance_h: f64,
}

/// B along a named line.
#[derive(Debug, Clone, Serialize)]
pub struct LineReport {
    /// Line name.
    pub name: String,
    /// Samples.
    pub points: Vec<ProbeReport>,
}

/// Timings of a file-driven magnetic solve (s).
#[derive(Debug, Clone, Copy, Default, Serialize)]
pub struct MagneticsTimings {
    /// Reading the problem and mesh files.
    pub read: f64,
    /// Assembly (all Newton iterations and line-search trials).
    pub assemble: f64,
    /// Symbolic + numeric factorisations and triangular solves.
    pub solve: f64,
    /// Post-processing (probes, regions, coils, energy).
    pub post: f64,
    /// Everything.
    pub total: f64,
}

/// The result of `mrbrake fem solve` (the `--json` object).
#[derive(Debug, Clone, Serialize)]
pub struct SolveReport {
    /// B at the probes.
    pub probes: Vec<ProbeReport>,
    /// |B| statistics per region.
    pub regions: Vec<RegionReport>,
    /// Coils: flux linkage and inductances.
    pub coils: Vec<CoilReport>,
    /// B along the lines.
    pub lines: Vec<LineReport>,
    /// Stored magnetic energy (J).
    #[serde(rename = "energy_J")]
    pub energy_j: f64,
    /// Co-energy (J).
    #[serde(rename = "coenergy_J")]
    pub coenergy_j: f64,
    /// Newton iterations (linear solves).
    pub newton_iterations: usize,
    /// True when the stopping rule was met.
    pub converged: bool,
    /// Relative residual after each iteration.
    pub residual_history: Vec<f64>,
    /// Mesh nodes.
    pub nodes: usize,
    /// Mesh triangles.
    pub elements: usize,
    /// Element order: 1 (linear) or 2 (quadratic triangles).
    pub order: usize,
    /// Free unknowns.
    pub unknowns: usize,
    /// Timings (s).
    pub timings_s: MagneticsTimings,
    /// Conductivities and the transient or harmonic solve (absent for a static file).
    #[serde(flatten, skip_serializing_if = "Option::is_none")]
    pub dynamics: Option<super::DynamicsReport>,
}

pub(super) fn probe_report(name: &str, f: &PointField) -> ProbeReport {
    ProbeReport {
        name: name.to_string(),
        r: f.r,
        z: f.z,
        b_r_t: f.b_r_t,
        b_z_t: f.b_z_t,
        b_abs_t: f.b_abs_t,
    }
}

impl From<&RegionStats> for RegionReport {
    fn from(s: &RegionStats) -> Self {
        Self {
            physical: s.physical,
            area_m2: s.area_m2,
            mean_b_t: s.mean_b_t,
            max_b_t: s.max_b_t,
            quantiles_b_t: s.quantiles_b_t,
        }
    }
}
