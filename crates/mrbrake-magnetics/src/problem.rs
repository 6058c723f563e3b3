//! The magnetostatic problem as a library value: mesh, materials and sources by region tag,
//! boundary conditions by edge tag. No file format here (see `problem_file` for TOML).
//!
//! Boundary conditions of the A_phi formulation:
//! - the symmetry axis `r = 0` always has `A_phi = 0` (B finite on the axis), whatever the tags say;
//! - [`BoundaryCondition::Dirichlet`]: `A_phi = 0` (flux cannot cross: B tangential);
//! - [`BoundaryCondition::Prescribed`]: `A_phi = g(r, z)` (validation against exact solutions);
//! - [`BoundaryCondition::Open`]: first-order asymptotic condition on a circular outer boundary
//!   (see [`crate::open_boundary`]), so a small air box behaves like unbounded space;
//! - edges with no condition are natural (Neumann): `n × H = 0`, B normal to the boundary
//!   (a symmetry plane of a coil, or the mid-plane of an infinitely long solenoid).

use std::sync::Arc;

use mrbrake_fem::mesh::Mesh;

use mrbrake_materials::Magnetic;

use crate::MagneticsError;

/// The current source of a region (azimuthal current, positive along +φ).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Source {
    /// Uniform current density `J_phi` (A/m²).
    CurrentDensity {
        /// Current density (A/m²).
        a_per_m2: f64,
    },
    /// A coil of `turns` turns carrying `current_a`, spread uniformly: `J = N I / S` (thesis eq. 4.1).
    Coil {
        /// Number of turns.
        turns: f64,
        /// Current per turn (A).
        current_a: f64,
    },
}

/// A region (physical surface): its material and optional source.
#[derive(Debug, Clone)]
pub struct Region {
    /// Physical tag of the triangles.
    pub tag: u32,
    /// Magnetic material.
    pub material: Magnetic,
    /// Current source, if any.
    pub source: Option<Source>,
}

/// Prescribed potential as a function of `[r, z]` (m) returning `A_phi` (Wb/m).
pub type PotentialFn = Arc<dyn Fn([f64; 2]) -> f64 + Send + Sync>;

/// A boundary condition on the edges of one tag.
#[derive(Clone)]
pub enum BoundaryCondition {
    /// `A_phi = 0`.
    Dirichlet,
    /// `A_phi = g(r, z)`.
    Prescribed(PotentialFn),
    /// Asymptotic open boundary on a circle centred on the axis at `z = centre_z_m`.
    Open {
        /// Axial position of the circle centre (m).
        centre_z_m: f64,
    },
}

impl std::fmt::Debug for BoundaryCondition {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::Dirichlet => write!(f, "Dirichlet"),
            Self::Prescribed(_) => write!(f, "Prescribed(fn)"),
            Self::Open { centre_z_m } => write!(f, "Open {{ centre_z_m: {centre_z_m} }}"),
        }
    }
}

/// A boundary condition attached to an edge tag.
#[derive(Debug, Clone)]
pub struct Boundary {
    /// Physical tag of the edges.
    pub tag: u32,
    /// The condition.
    pub condition: BoundaryCondition,
}

/// A complete axisymmetric magnetostatic problem.
#[derive(Debug, Clone)]
pub struct Problem {
    /// The mesh (shared: the geometry builder and the solver keep it without copying).
    pub mesh: Arc<Mesh>,
    /// Every triangle tag of the mesh must have exactly one region.
    pub regions: Vec<Region>,
    /// Boundary conditions by edge tag (untagged or unlisted edges are natural).
    pub boundaries: Vec<Boundary>,
}

impl Problem {
    /// The region with `tag`, if any.
    pub fn region(&self, tag: u32) -> Option<&Region> {
        self.regions.iter().find(|r| r.tag == tag)
    }

    /// Checks the problem (a valid mesh; one region per mesh surface and no region or boundary
    /// without mesh entities; valid linear permeabilities) and returns the region index of every
    /// triangle.
    pub fn element_regions(&self) -> Result<Vec<u32>, MagneticsError> {
        self.mesh.validate()?;
        let mut sorted_tags: Vec<u32> = self.regions.iter().map(|r| r.tag).collect();
        sorted_tags.sort_unstable();
        if let Some(w) = sorted_tags.windows(2).find(|w| w[0] == w[1]) {
            return Err(MagneticsError::field(
                "regions",
                format!("region {} is defined twice", w[0]),
            ));
        }
        let mesh_tags = self.mesh.region_tags();
        if let Some(tag) = mesh_tags.iter().find(|tag| self.region(**tag).is_none()) {
            return Err(MagneticsError::field(
                "regions",
                format!(
                    "mesh region (physical surface) {tag} has no material: add a region with physical = {tag}"
                ),
            ));
        }
        for region in &self.regions {
            self.check_region(region, &mesh_tags)?;
        }
        let edge_tags = self.mesh.boundary_tags();
        for boundary in &self.boundaries {
            if edge_tags.binary_search(&boundary.tag).is_err() {
                return Err(MagneticsError::field(
                    format!("boundary[physical={}]", boundary.tag),
                    format!(
                        "boundary physical = {} is not a curve of the mesh (mesh curves: {edge_tags:?})",
                        boundary.tag
                    ),
                ));
            }
        }
        let index = |tag: &u32| self.regions.iter().position(|r| r.tag == *tag);
        Ok(self
            .mesh
            .triangle_tags
            .iter()
            .map(|t| index(t).expect("every mesh tag has a region (checked)") as u32)
            .collect())
    }

    fn check_region(&self, region: &Region, mesh_tags: &[u32]) -> Result<(), MagneticsError> {
        if mesh_tags.binary_search(&region.tag).is_err() {
            return Err(MagneticsError::field(
                format!("region[physical={}]", region.tag),
                format!(
                    "region physical = {} is not a surface of the mesh (mesh surfaces: {mesh_tags:?})",
                    region.tag
                ),
            ));
        }
        if let Magnetic::Linear { mu_r } = region.material
            && !(mu_r.is_finite() && mu_r > 0.0)
        {
            let field = format!("region[physical={}].mu_r", region.tag);
            return Err(mrbrake_error::FieldError::out_of_range(field, mu_r, "finite, > 0").into());
        }
        Ok(())
    }
}
