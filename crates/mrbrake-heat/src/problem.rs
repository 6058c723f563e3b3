//! A heat-conduction problem in SI: the mesh, each region's conductivity, heat capacity and
//! source, and the boundary conditions. Temperatures are in kelvin.

use std::sync::Arc;

use mrbrake_fem::mesh::Mesh;
use serde::Serialize;

use crate::{HeatError, T20_K};

/// A heat source in a region.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub enum Source {
    /// No source.
    None,
    /// Uniform volumetric generation \[W/m³\].
    Uniform {
        /// Power per volume \[W/m³\].
        w_per_m3: f64,
    },
    /// A total power spread uniformly over the region (e.g. viscous dissipation in a gap) \[W\].
    Power {
        /// Total power \[W\].
        watts: f64,
    },
    /// The Joule loss of a coil carrying `current_a` whose resistance is
    /// `R(T) = R20 (1 + α (T − 20 °C))`, applied at the local temperature: the loss per volume is
    /// `q(T) = q20 (1 + α (T − 20 °C))`, `q20 = I² R20 / V`, so that the region's total is
    /// `I² R(T̄)` with `T̄` its volume-mean temperature (see the crate docs).
    Joule {
        /// Current \[A\] (the same in every turn).
        current_a: f64,
        /// Resistance of the whole winding at 20 °C \[Ω\].
        resistance_20c_ohm: f64,
        /// Temperature coefficient of resistance at 20 °C \[1/K\].
        alpha_per_k: f64,
    },
}

impl Source {
    /// The source as an affine law `q(T) = q0 + q1 T` \[W/m³\] (T in kelvin) in a region of
    /// volume `volume_m3`.
    pub fn affine(&self, volume_m3: f64) -> (f64, f64) {
        match *self {
            Self::None => (0.0, 0.0),
            Self::Uniform { w_per_m3 } => (w_per_m3, 0.0),
            Self::Power { watts } => (watts / volume_m3, 0.0),
            Self::Joule { current_a, resistance_20c_ohm, alpha_per_k } => {
                let q20 = current_a * current_a * resistance_20c_ohm / volume_m3;
                (q20 * (1.0 - alpha_per_k * T20_K), q20 * alpha_per_k)
            }
        }
    }
}

/// One region (physical surface) of the mesh.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Region {
    /// Physical tag.
    pub tag: u32,
    /// Radial conductivity \[W/(m·K)\].
    pub k_radial: f64,
    /// Axial conductivity \[W/(m·K)\].
    pub k_axial: f64,
    /// Heat capacity per volume `ρ c` \[J/(m³·K)\].
    pub rho_c: f64,
    /// Heat source.
    pub source: Source,
}

impl Region {
    /// An isotropic region without a source.
    pub fn isotropic(tag: u32, k: f64, rho_c: f64) -> Self {
        Self { tag, k_radial: k, k_axial: k, rho_c, source: Source::None }
    }

    /// The same region with a source.
    pub fn with_source(mut self, source: Source) -> Self {
        self.source = source;
        self
    }
}

/// A boundary condition on a tagged boundary.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub enum BoundaryCondition {
    /// Convection to an ambient: outward flux `h (T − T_∞)`.
    Convection {
        /// Heat-transfer coefficient \[W/(m²·K)\].
        h_w_per_m2k: f64,
        /// Ambient temperature \[K\].
        ambient_k: f64,
    },
    /// Radiation to large surroundings: outward flux `ε σ (T⁴ − T_∞⁴)`.
    Radiation {
        /// Emissivity in [0, 1].
        emissivity: f64,
        /// Temperature of the surroundings \[K\].
        ambient_k: f64,
    },
    /// A fixed temperature \[K\].
    Temperature {
        /// The temperature \[K\].
        t_k: f64,
    },
    /// No heat flow (also what every untagged edge and the axis get).
    Adiabatic,
}

/// A boundary: a tag of the mesh's edges and its condition. A tag may appear twice (convection and
/// radiation from the same surface).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Boundary {
    /// Physical tag of the edges.
    pub tag: u32,
    /// The condition.
    pub condition: BoundaryCondition,
}

/// A heat-conduction problem.
#[derive(Debug, Clone)]
pub struct HeatProblem {
    /// The mesh (metres).
    pub mesh: Arc<Mesh>,
    /// One entry per physical surface of the mesh.
    pub regions: Vec<Region>,
    /// Boundary conditions.
    pub boundaries: Vec<Boundary>,
}

fn positive(value: f64) -> bool {
    value.is_finite() && value > 0.0
}

impl HeatProblem {
    /// The region with tag `tag`.
    pub fn region(&self, tag: u32) -> Option<&Region> {
        self.regions.iter().find(|r| r.tag == tag)
    }

    /// Checks every value against its allowed range and the tags against the mesh; the error lists
    /// every problem found.
    pub fn validate(&self) -> Result<(), HeatError> {
        let mut problems = Vec::new();
        for r in &self.regions {
            let name = format!("region physical = {}", r.tag);
            for (field, value) in
                [("k_radial", r.k_radial), ("k_axial", r.k_axial), ("rho_c", r.rho_c)]
            {
                if !positive(value) {
                    problems.push(format!("{name}: {field} = {value} must be > 0"));
                }
            }
            if let Source::Joule { resistance_20c_ohm, alpha_per_k, current_a } = r.source {
                if !(positive(resistance_20c_ohm) && alpha_per_k.is_finite() && alpha_per_k >= 0.0)
                {
                    problems.push(format!("{name}: Joule source needs R20 > 0 and alpha >= 0"));
                }
                if !current_a.is_finite() {
                    problems.push(format!("{name}: current = {current_a} must be finite"));
                }
            }
        }
        let tags = self.mesh.region_tags();
        for tag in &tags {
            if self.region(*tag).is_none() {
                problems.push(format!(
                    "the mesh's physical surface {tag} has no region (thermal data)"
                ));
            }
        }
        for r in &self.regions {
            if tags.binary_search(&r.tag).is_err() {
                problems.push(format!(
                    "region physical = {}: not a surface of the mesh {tags:?}",
                    r.tag
                ));
            }
        }
        let edge_tags = self.mesh.boundary_tags();
        for b in &self.boundaries {
            let name = format!("boundary physical = {}", b.tag);
            if edge_tags.binary_search(&b.tag).is_err() {
                problems.push(format!("{name}: not a boundary of the mesh {edge_tags:?}"));
            }
            problems.extend(check_condition(&b.condition).map(|m| format!("{name}: {m}")));
        }
        if problems.is_empty() { Ok(()) } else { Err(HeatError::Input(problems.join("; "))) }
    }
}

/// The range check of one boundary condition, or `None`.
fn check_condition(condition: &BoundaryCondition) -> Option<String> {
    let below_zero = |t: f64| !(t.is_finite() && t > 0.0);
    match *condition {
        BoundaryCondition::Convection { h_w_per_m2k, ambient_k } => {
            if !(h_w_per_m2k.is_finite() && h_w_per_m2k >= 0.0) {
                Some(format!("h = {h_w_per_m2k} W/(m2 K) must be >= 0"))
            } else if below_zero(ambient_k) {
                Some(format!("T_amb = {ambient_k} K is below absolute zero"))
            } else {
                None
            }
        }
        BoundaryCondition::Radiation { emissivity, ambient_k } => {
            if !(0.0..=1.0).contains(&emissivity) {
                Some(format!("emissivity = {emissivity} must be in [0, 1]"))
            } else if below_zero(ambient_k) {
                Some(format!("T_amb = {ambient_k} K is below absolute zero"))
            } else {
                None
            }
        }
        BoundaryCondition::Temperature { t_k } => {
            below_zero(t_k).then(|| format!("T = {t_k} K is below absolute zero"))
        }
        BoundaryCondition::Adiabatic => None,
    }
}
