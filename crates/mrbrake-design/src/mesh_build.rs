//! From a [`BrakeGeometry`] to a [`Mesh`]: the planar graph, the size field that resolves the fluid
//! gaps, and the in-process mesher (`mrbrake_fem::mesh::mesher`).
//!
//! The gap regions get a target edge length g / c, where c is the number of cells across a gap of
//! the chosen [`MeshLevel`] (coarse 3, default 4, fine 6); the size grows away from the gaps at
//! `growth` (m/m) up to the global maximum (a fraction of the device radius).
//!
//! Resources are bounded before and while meshing (issue 18): the smallest edge a level resolves
//! is its maximum edge / [`MAX_EDGE_RATIO`] ([`MeshSettings::smallest_edge_m`]); a spec part
//! thinner than that, or a gap narrower than its cells across at that size, is an input error
//! naming the spec field and the smallest size resolvable at that `--mesh` level
//! ([`check_resolvable`]). The mesher itself stops at a budget of [`DEFAULT_MAX_ELEMENTS`]
//! triangles (overridable with the environment variable `MRBRAKE_MAX_ELEMENTS`), also an input
//! error.

use mrbrake_fem::mesh::Mesh;
use mrbrake_fem::mesh::mesher::{MeshOptions, Pslg, SizeField, quality, triangulate};

use crate::DesignError;
use crate::geometry::{BrakeGeometry, GapInfo, GapOrientation};
use crate::spec::{BrakeSpec, Configuration, WorkingSurfaces, fmt_mm};

/// The smallest edge a level resolves is its largest edge divided by this: at the default level and
/// a 40 mm device radius, 4 mm / 400 = 10 µm, so a gap of 4 cells must be ≥ 40 µm. The thesis
/// designs' smallest parts (0.5 mm bobbin walls and gaps) sit 20–50 times above it.
pub const MAX_EDGE_RATIO: f64 = 400.0;

/// The mesher's default budget, in triangles (about 1 GB of mesher memory; the finest thesis
/// meshes have under 100 000).
pub const DEFAULT_MAX_ELEMENTS: usize = 2_000_000;

/// The environment variable that overrides [`DEFAULT_MAX_ELEMENTS`] (a whole number of triangles).
pub const MAX_ELEMENTS_ENV: &str = "MRBRAKE_MAX_ELEMENTS";

/// The element budget: `MRBRAKE_MAX_ELEMENTS` when set to a whole number ≥ 1000, else
/// [`DEFAULT_MAX_ELEMENTS`].
pub fn max_elements() -> usize {
    std::env::var(MAX_ELEMENTS_ENV)
        .ok()
        .and_then(|v| v.trim().parse::<usize>().ok())
        .filter(|&n| n >= 1000)
        .unwrap_or(DEFAULT_MAX_ELEMENTS)
}

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
            other => Err(mrbrake_error::FieldError::new("mesh", "not a mesh level")
                .with_value(format!("'{other}'"))
                .with_allowed("coarse, default, fine")
                .into()),
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

impl MeshLevel {
    /// The name used on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Self::Coarse => "coarse",
            Self::Default => "default",
            Self::Fine => "fine",
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

impl MeshSettings {
    /// The smallest edge these settings resolve: the largest edge / [`MAX_EDGE_RATIO`] (m).
    pub fn smallest_edge_m(&self) -> f64 {
        self.max_edge_m / MAX_EDGE_RATIO
    }
}

/// The spec's thickness-like fields (the sizes of thin parts and gaps) with their values in metres
/// and whether the field is a fluid gap (meshed with `gap_cells_across` cells).
fn thin_fields(spec: &BrakeSpec) -> Vec<(&'static str, f64, bool)> {
    let h = &spec.housing;
    let c = &spec.coil;
    let mut out = vec![
        ("housing.case_thickness", h.case_thickness.m(), false),
        ("housing.end_plate_thickness", h.end_plate_thickness.m(), false),
        ("housing.inner_case_thickness", h.inner_case_thickness.m(), false),
        ("coil.window_width", c.window_width.m(), false),
        ("coil.window_height", c.window_height.m(), false),
        ("coil.bobbin_wall", c.bobbin_wall.m(), false),
    ];
    if let Some(t) = h.cover_thickness {
        out.push(("housing.cover_thickness", t.m(), false));
    }
    if let Some(t) = h.rotor_disc_thickness {
        out.push(("housing.rotor_disc_thickness", t.m(), false));
    }
    match spec.configuration.surfaces() {
        WorkingSurfaces::Drums(d) => {
            out.push(("drum.cylinder_thickness", d.cylinder_thickness.m(), false));
            out.push(("drum.gap", d.gap.m(), true));
        }
        WorkingSurfaces::Discs(d) => {
            out.push(("disc.thickness", d.thickness.m(), false));
            out.push(("disc.gap", d.gap.m(), true));
        }
    }
    if let Configuration::Bidirectional { spacer, .. } = &spec.configuration {
        out.push(("spacer.thickness", spacer.thickness.m(), false));
    }
    out
}

/// Refuses a spec with a part too thin for the mesh at `level` before meshing: each thin field
/// below the smallest resolvable size (gaps: their cells across times it) is a field error of the
/// spec (file and line), naming that size; a thinner part of the assembled geometry (a difference
/// of fields) is an input error naming the part.
pub fn check_resolvable(
    spec: &BrakeSpec,
    geometry: &BrakeGeometry,
    level: MeshLevel,
) -> Result<(), DesignError> {
    let settings = level.settings(geometry.device.r1);
    let h = settings.smallest_edge_m();
    let mut errors = mrbrake_error::FieldErrors::new();
    for (field, value, is_gap) in thin_fields(spec) {
        let needed = if is_gap { h * settings.gap_cells_across } else { h };
        if value < needed {
            errors.add(
                field,
                format!(
                    "{} is too thin for the mesh: at --mesh {} this brake resolves sizes ≥ {}{} \
                     (the largest edge {} / {MAX_EDGE_RATIO})",
                    fmt_mm(value),
                    level.name(),
                    fmt_mm(needed),
                    if is_gap { " for a gap (its cells across)" } else { "" },
                    fmt_mm(settings.max_edge_m),
                ),
            );
        }
    }
    if !errors.is_empty() {
        return Err(spec.invalid(errors));
    }
    for region in &geometry.regions {
        for rc in &region.rects {
            let thin = (rc.r1 - rc.r0).min(rc.z1 - rc.z0);
            if thin < h {
                // Not one field of the spec but a difference of fields: an error of the whole
                // spec (its file), like the thin fields above.
                let e = mrbrake_error::FieldError::new(
                    "",
                    format!(
                        "part {} is {} thick, too thin for the mesh: at --mesh {} this brake \
                         resolves sizes ≥ {}; change the fields that size it",
                        region.name,
                        fmt_mm(thin),
                        level.name(),
                        fmt_mm(h)
                    ),
                );
                return Err(spec.invalid(e.into()));
            }
        }
    }
    Ok(())
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

/// Meshes the validated `geometry` of `spec` at a level, after [`check_resolvable`]: the entry
/// point of every analysis (a too-thin part is then a field error of the spec, not a mesher
/// failure or a run out of memory).
pub fn mesh_spec(
    spec: &BrakeSpec,
    geometry: &BrakeGeometry,
    level: MeshLevel,
) -> Result<Mesh, DesignError> {
    check_resolvable(spec, geometry, level)?;
    mesh(geometry, level)
}

/// Meshes the geometry at a level.
pub fn mesh(geometry: &BrakeGeometry, level: MeshLevel) -> Result<Mesh, DesignError> {
    mesh_with(geometry, &level.settings(geometry.device.r1))
}

/// Meshes the geometry with explicit settings.
pub fn mesh_with(geometry: &BrakeGeometry, settings: &MeshSettings) -> Result<Mesh, DesignError> {
    let graph = pslg(geometry)?;
    let size = size_field(geometry, settings);
    let options = MeshOptions {
        min_angle_deg: settings.min_angle_deg,
        // About two triangles per vertex.
        max_vertices: max_elements() / 2,
        ..MeshOptions::default()
    };
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
