//! From a [`BrakeGeometry`] to a [`Mesh`]: the planar graph, the size field that resolves the fluid
//! gaps, and the in-process mesher (`mrbrake_fem::mesher`).
//!
//! The gap regions get a target edge length g / c, where c is the number of cells across a gap of
//! the chosen [`MeshLevel`] (coarse 3, default 4, fine 6); the size grows away from the gaps at
//! `growth` (m/m) up to the global maximum (a fraction of the device radius).

use mrbrake_fem::mesh::Mesh;
use mrbrake_fem::mesher::{MeshOptions, Pslg, SizeField, quality, triangulate};

use crate::DesignError;
use crate::geometry::{BrakeGeometry, GapInfo, GapOrientation};

/// Mesh density levels (`--mesh coarse|default|fine`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum MeshLevel {
    /// Quick look: 3 cells across a gap.
    Coarse,
    /// The default: 4 cells across a gap.
    #[default]
    Default,
    /// Convergence checks: 6 cells across a gap.
    Fine,
}

impl MeshLevel {
    /// Parses `coarse`, `default` or `fine`.
    pub fn parse(text: &str) -> Result<Self, DesignError> {
        match text {
            "coarse" => Ok(Self::Coarse),
            "default" => Ok(Self::Default),
            "fine" => Ok(Self::Fine),
            other => Err(DesignError::Input(format!(
                "mesh level '{other}' is not one of coarse, default, fine"
            ))),
        }
    }

    /// The size-field settings of this level for a device of outer radius `r_out_m`.
    pub fn settings(self, r_out_m: f64) -> MeshSettings {
        let (cells, max_fraction, growth) = match self {
            Self::Coarse => (3.0, 1.0 / 6.0, 0.4),
            Self::Default => (4.0, 1.0 / 10.0, 0.3),
            Self::Fine => (6.0, 1.0 / 16.0, 0.2),
        };
        MeshSettings {
            gap_cells_across: cells,
            max_edge_m: r_out_m * max_fraction,
            growth,
            min_angle_deg: 28.0,
        }
    }
}

/// Explicit size-field settings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MeshSettings {
    /// Target number of cells across each fluid gap.
    pub gap_cells_across: f64,
    /// Largest edge anywhere (m).
    pub max_edge_m: f64,
    /// Growth of the size away from the gaps (m per m).
    pub growth: f64,
    /// Minimum triangle angle (degrees).
    pub min_angle_deg: f64,
}

/// The planar graph of the geometry: every rectangle of every region, one seed per rectangle, the
/// axis, the outer boundary and the gap walls tagged.
pub fn pslg(geometry: &BrakeGeometry) -> Result<Pslg, DesignError> {
    let mut g = Pslg::new();
    // The geometry has passed validation, so a graph the mesher rejects is our defect, not the
    // user's input: an internal failure (exit 1; a study records the design as failed).
    let fem = |source| DesignError::GeometryGraph { stage: "mesh", source };
    // Coordinates on a 1 pm grid: parts computed along different arithmetic paths (a + b against
    // c − d) can meet 1e-17 m apart, which the mesher would see as two crossing segments.
    let snap = |x: f64| (x * 1e12).round() / 1e12;
    let p = |r: f64, z: f64| [snap(r), snap(z)];
    for region in &geometry.regions {
        for rc in &region.rects {
            g.add_rectangle(snap(rc.r0), snap(rc.r1), snap(rc.z0), snap(rc.z1)).map_err(fem)?;
            g.add_seed(rc.centre(), region.tag);
        }
    }
    let d = geometry.domain;
    g.add_segment(p(0.0, d.z0), p(0.0, d.z1), Some(geometry.axis_tag)).map_err(fem)?;
    g.add_segment(p(0.0, d.z0), p(d.r1, d.z0), Some(geometry.outer_tag)).map_err(fem)?;
    g.add_segment(p(d.r1, d.z0), p(d.r1, d.z1), Some(geometry.outer_tag)).map_err(fem)?;
    g.add_segment(p(0.0, d.z1), p(d.r1, d.z1), Some(geometry.outer_tag)).map_err(fem)?;
    for gap in &geometry.gaps {
        let r = gap.rect;
        let (inner, outer) = match gap.orientation {
            GapOrientation::Cylindrical => {
                ((p(r.r0, r.z0), p(r.r0, r.z1)), (p(r.r1, r.z0), p(r.r1, r.z1)))
            }
            GapOrientation::Annular => {
                ((p(r.r0, r.z0), p(r.r1, r.z0)), (p(r.r0, r.z1), p(r.r1, r.z1)))
            }
        };
        g.add_segment(inner.0, inner.1, Some(gap.inner_wall_tag)).map_err(fem)?;
        g.add_segment(outer.0, outer.1, Some(gap.outer_wall_tag)).map_err(fem)?;
    }
    Ok(g)
}

/// The size field of a level: gaps at g / cells, everything else graded up to the maximum.
pub fn size_field(geometry: &BrakeGeometry, settings: &MeshSettings) -> SizeField {
    let mut field =
        SizeField { growth: settings.growth, ..SizeField::uniform(settings.max_edge_m) };
    for gap in &geometry.gaps {
        field.region_edge_m.insert(gap.tag, gap.width_m / settings.gap_cells_across);
    }
    field
}

/// Meshes the geometry at a level.
pub fn mesh(geometry: &BrakeGeometry, level: MeshLevel) -> Result<Mesh, DesignError> {
    mesh_with(geometry, &level.settings(geometry.device.r1))
}

/// Meshes the geometry with explicit settings.
pub fn mesh_with(geometry: &BrakeGeometry, settings: &MeshSettings) -> Result<Mesh, DesignError> {
    let graph = pslg(geometry)?;
    let size = size_field(geometry, settings);
    let options = MeshOptions { min_angle_deg: settings.min_angle_deg, ..MeshOptions::default() };
    // The mesher's error keeps its kind: a size it cannot reach is input, a failure numerical.
    Ok(triangulate(&graph, &size, &options)?)
}

/// The fewest triangles a straight line across the gap passes through, over `lines` lines spread
/// along the gap (the "elements across the gap" a field sample sees). The crossings are found by
/// sampling each line at 400 points and locating them among the gap's triangles.
pub fn elements_across(mesh: &Mesh, gap: &GapInfo, lines: usize) -> usize {
    let tris: Vec<usize> =
        (0..mesh.triangles.len()).filter(|&t| mesh.triangle_tags[t] == gap.tag).collect();
    let r = gap.rect;
    let mut fewest = usize::MAX;
    for l in 0..lines {
        let s = (l as f64 + 0.5) / lines as f64;
        let mut hit: Vec<usize> = Vec::new();
        for i in 0..400 {
            let t = (i as f64 + 0.5) / 400.0;
            let p = match gap.orientation {
                GapOrientation::Cylindrical => [r.r0 + t * (r.r1 - r.r0), r.z0 + s * (r.z1 - r.z0)],
                GapOrientation::Annular => [r.r0 + s * (r.r1 - r.r0), r.z0 + t * (r.z1 - r.z0)],
            };
            if let Some(&tri) = tris
                .iter()
                .find(|&&tri| quality::triangle_contains(quality::triangle_points(mesh, tri), p))
                && !hit.contains(&tri)
            {
                hit.push(tri);
            }
        }
        fewest = fewest.min(hit.len());
    }
    fewest
}
