//! A heat-conduction problem in SI: the mesh, each region's conductivity, heat capacity and
//! source, and the boundary conditions. Temperatures are in kelvin.

use std::sync::Arc;

use mrbrake_fem::mesh::Mesh;
use serde::Serialize;

use crate::{HeatError, T20_K};
use mrbrake_error::{FieldError, FieldErrors};

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
    /// every problem found, each field named `region[physical=3].k_radial`,
    /// `boundary[physical=5].h`, ….
    pub fn validate(&self) -> Result<(), HeatError> {
        let mut errors = FieldErrors::new();
        let tags = self.mesh.region_tags();
        for r in &self.regions {
            let name = format!("region[physical={}]", r.tag);
            for (field, value) in
                [("k_radial", r.k_radial), ("k_axial", r.k_axial), ("rho_c", r.rho_c)]
            {
                if !positive(value) {
                    errors.push(FieldError::out_of_range(field, value, "> 0").under(&name));
                }
            }
            if let Source::Joule { resistance_20c_ohm, alpha_per_k, current_a } = r.source {
                if !positive(resistance_20c_ohm) {
                    let e = FieldError::out_of_range("resistance_20C", resistance_20c_ohm, "> 0 Ω");
                    errors.push(e.under(&name));
                }
                if !(alpha_per_k.is_finite() && alpha_per_k >= 0.0) {
                    let e = FieldError::out_of_range("alpha", alpha_per_k, ">= 0 1/K");
                    errors.push(e.under(&name));
                }
                if !current_a.is_finite() {
                    errors.push(
                        FieldError::out_of_range("current", current_a, "finite").under(&name),
                    );
                }
            }
            if tags.binary_search(&r.tag).is_err() {
                let e = FieldError::new("physical", "not a surface of the mesh").with_value(r.tag);
                errors.push(e.with_allowed(format!("{tags:?}")).under(&name));
            }
        }
        for tag in tags.iter().filter(|t| self.region(**t).is_none()) {
            let message = "the mesh's physical surface has no region (thermal data)";
            errors.push(FieldError::new("region", message).with_value(tag));
        }
        let edge_tags = self.mesh.boundary_tags();
        for b in &self.boundaries {
            let name = format!("boundary[physical={}]", b.tag);
            if edge_tags.binary_search(&b.tag).is_err() {
                let e = FieldError::new("physical", "not a boundary of the mesh").with_value(b.tag);
                errors.push(e.with_allowed(format!("{edge_tags:?}")).under(&name));
            }
            if let Some(e) = check_condition(&b.condition) {
                errors.push(e.under(&name));
            }
        }
        Ok(errors.into_result(())?)
    }
}

/// The range check of one boundary condition (the field relative to the boundary), or `None`.
fn check_condition(condition: &BoundaryCondition) -> Option<FieldError> {
    let below_zero = |t: f64| !(t.is_finite() && t > 0.0);
    let absolute =
        |field: &str, t_k: f64| FieldError::out_of_range(field, format!("{t_k} K"), "> 0 K");
    match *condition {
        BoundaryCondition::Convection { h_w_per_m2k, ambient_k } => {
            if !(h_w_per_m2k.is_finite() && h_w_per_m2k >= 0.0) {
                Some(FieldError::out_of_range("h", format!("{h_w_per_m2k} W/(m2 K)"), ">= 0"))
            } else if below_zero(ambient_k) {
                Some(absolute("T_amb", ambient_k))
            } else {
                None
            }
        }
        BoundaryCondition::Radiation { emissivity, ambient_k } => {
            if !(0.0..=1.0).contains(&emissivity) {
                Some(FieldError::out_of_range("emissivity", emissivity, "[0, 1]"))
            } else if below_zero(ambient_k) {
                Some(absolute("T_amb", ambient_k))
            } else {
                None
            }
        }
        BoundaryCondition::Temperature { t_k } => below_zero(t_k).then(|| absolute("T", t_k)),
        BoundaryCondition::Adiabatic => None,
    }
}
