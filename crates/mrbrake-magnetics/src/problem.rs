//! The magnetostatic problem as a library value: mesh, materials and sources by region tag,
//! boundary conditions by edge tag. No file format here (see `problem_file` for TOML).
//!
//! Boundary conditions of the A_phi formulation:
//! - the symmetry axis `r = 0` always has `A_phi = 0` (B finite on the axis), whatever the tags say;
//! - [`BoundaryCondition::Dirichlet`]: `A_phi = 0` (flux cannot cross: B tangential);
//! - [`BoundaryCondition::Prescribed`]: `A_phi = g(r, z)` (validation against exact solutions);
//! - [`BoundaryCondition::Open`]: first-order asymptotic condition on a circular outer boundary
//!   (see [`crate::assembly`]), so a small air box behaves like unbounded space;
//! - edges with no condition are natural (Neumann): `n × H = 0`, B normal to the boundary
//!   (a symmetry plane of a coil, or the mid-plane of an infinitely long solenoid).

use std::sync::Arc;

use mrbrake_fem::mesh::Mesh;

use crate::material::MagneticMaterial;

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
    pub material: MagneticMaterial,
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
}
