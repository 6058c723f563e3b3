//! Gmsh `.geo` export of a brake geometry, so the same model can be meshed and solved elsewhere.
//!
//! The file uses Gmsh's built-in kernel: one `Point` per vertex of the planar graph (x = r,
//! y = z, metres) with a characteristic length from the same size field as the in-process mesher
//! (gap target at points on a gap, else the global maximum), one `Line` per graph segment, one
//! `Plane Surface` per rectangle of every region, `Physical Surface("name", tag)` per region and
//! `Physical Curve("name", tag)` for the axis, the outer boundary and the gap walls, with the same
//! tags as [`crate::mesh_build`] gives the in-process mesh.

use std::collections::HashMap;
use std::fmt::Write as _;

use crate::DesignError;
use crate::geometry::{BrakeGeometry, Rect};
use crate::mesh_build::{MeshSettings, pslg};
use mrbrake_fem::mesh::mesher::Segment;

/// Writes the `.geo` text of a geometry meshed with `settings`.
pub fn to_geo(
    geometry: &BrakeGeometry,
    settings: &MeshSettings,
    title: &str,
) -> Result<String, DesignError> {
    let graph = pslg(geometry)?
        .normalized()
        .map_err(|source| DesignError::GeometryGraph { stage: ".geo", source })?;
    let mut out = String::new();
    line(&mut out, format!("// {title}: exported by mrbrake export-geo (x = r, y = z, metres)."));
    line(&mut out, "// Physical Surface tags = region tags of the mrbrake mesh; Physical Curve tags = edge tags.".into());
    write_points(&mut out, geometry, settings, &graph.vertices);
    let mut line_of: HashMap<(usize, usize), usize> = HashMap::new();
    for (k, s) in graph.segments.iter().enumerate() {
        line(&mut out, format!("Line({}) = {{{}, {}}};", k + 1, s.a + 1, s.b + 1));
        line_of.insert((s.a, s.b), k + 1);
    }
    write_surfaces(&mut out, geometry, &graph.vertices, &line_of)?;
    write_physical_curves(&mut out, geometry, &graph.segments);
    line(&mut out, "Mesh.CharacteristicLengthExtendFromBoundary = 1;".into());
    line(&mut out, "Mesh.Algorithm = 6; // Frontal-Delaunay".into());
    Ok(out)
}

fn line(out: &mut String, text: String) {
    out.push_str(&text);
    out.push('\n');
}

/// One `Point` per vertex, its characteristic length the finest target among the gaps it touches.
fn write_points(
    out: &mut String,
    geometry: &BrakeGeometry,
    settings: &MeshSettings,
    vertices: &[[f64; 2]],
) {
    let mut lc = vec![settings.max_edge_m; vertices.len()];
    for gap in &geometry.gaps {
        let h = gap.width_m / settings.gap_cells_across;
        for (i, p) in vertices.iter().enumerate() {
            if on_rect(&gap.rect, *p) {
                lc[i] = lc[i].min(h);
            }
        }
    }
    for (i, p) in vertices.iter().enumerate() {
        line(
            out,
            format!("Point({}) = {{{:.12e}, {:.12e}, 0, {:.6e}}};", i + 1, p[0], p[1], lc[i]),
        );
    }
}

/// One `Plane Surface` per rectangle of every region, then one `Physical Surface` per region.
fn write_surfaces(
    out: &mut String,
    geometry: &BrakeGeometry,
    vertices: &[[f64; 2]],
    line_of: &HashMap<(usize, usize), usize>,
) -> Result<(), DesignError> {
    let mut surface = 0usize;
    let mut physical_surfaces = Vec::new();
    for region in &geometry.regions {
        let mut ids = Vec::new();
        for rc in &region.rects {
            surface += 1;
            let loop_lines = curve_loop(rc, vertices, line_of, &region.name)?;
            let list: Vec<String> = loop_lines.iter().map(i64::to_string).collect();
            line(out, format!("Curve Loop({surface}) = {{{}}};", list.join(", ")));
            line(out, format!("Plane Surface({surface}) = {{{surface}}};"));
            ids.push(surface.to_string());
        }
        physical_surfaces.push(format!(
            "Physical Surface(\"{}\", {}) = {{{}}};",
            region.name,
            region.tag,
            ids.join(", ")
        ));
    }
    for text in physical_surfaces {
        line(out, text);
    }
    Ok(())
}

/// The signed lines around a rectangle, counter-clockwise, through every vertex on its sides.
fn curve_loop(
    rc: &Rect,
    vertices: &[[f64; 2]],
    line_of: &HashMap<(usize, usize), usize>,
    region: &str,
) -> Result<Vec<i64>, DesignError> {
    let corners = [[rc.r0, rc.z0], [rc.r1, rc.z0], [rc.r1, rc.z1], [rc.r0, rc.z1]];
    let mut loop_lines: Vec<i64> = Vec::new();
    for side in 0..4 {
        let (a, b) = (corners[side], corners[(side + 1) % 4]);
        let mut on: Vec<(f64, usize)> = vertices
            .iter()
            .enumerate()
            .filter(|(_, p)| on_segment(a, b, **p))
            .map(|(i, p)| ((p[0] - a[0]) * (b[0] - a[0]) + (p[1] - a[1]) * (b[1] - a[1]), i))
            .collect();
        on.sort_by(|x, y| x.0.total_cmp(&y.0));
        for pair in on.windows(2) {
            let (i, j) = (pair[0].1, pair[1].1);
            let id = if let Some(&l) = line_of.get(&(i, j)) {
                l as i64
            } else if let Some(&l) = line_of.get(&(j, i)) {
                -(l as i64)
            } else {
                return Err(DesignError::Internal(format!(
                    "geometry → .geo: no line between points {} and {} of region {region}",
                    i + 1,
                    j + 1,
                )));
            };
            loop_lines.push(id);
        }
    }
    Ok(loop_lines)
}

/// One `Physical Curve` per edge tag (axis, outer boundary, gap walls), in tag order.
fn write_physical_curves(out: &mut String, geometry: &BrakeGeometry, segments: &[Segment]) {
    let mut curves: Vec<(u32, String, Vec<usize>)> = Vec::new();
    let names: HashMap<u32, String> = std::iter::once((geometry.axis_tag, "axis".to_string()))
        .chain(std::iter::once((geometry.outer_tag, "outer_boundary".to_string())))
        .chain(geometry.gaps.iter().flat_map(|g| {
            let base = format!("unit{}.gap{}", g.unit + 1, g.index_in_unit + 1);
            [
                (g.inner_wall_tag, format!("{base}.inner_wall")),
                (g.outer_wall_tag, format!("{base}.outer_wall")),
            ]
        }))
        .collect();
    for (k, s) in segments.iter().enumerate() {
        if let Some(tag) = s.tag {
            match curves.iter_mut().find(|c| c.0 == tag) {
                Some(c) => c.2.push(k + 1),
                None => curves.push((
                    tag,
                    names.get(&tag).cloned().unwrap_or_else(|| format!("edge{tag}")),
                    vec![k + 1],
                )),
            }
        }
    }
    curves.sort_by_key(|c| c.0);
    for (tag, name, lines) in curves {
        let list: Vec<String> = lines.iter().map(usize::to_string).collect();
        let _ = writeln!(out, "Physical Curve(\"{name}\", {tag}) = {{{}}};", list.join(", "));
    }
}

fn on_segment(a: [f64; 2], b: [f64; 2], p: [f64; 2]) -> bool {
    let tol = 1e-12;
    let cross = (b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0]);
    let len = ((b[0] - a[0]).powi(2) + (b[1] - a[1]).powi(2)).sqrt();
    cross.abs() <= tol * len.max(1e-300) * 1e3
        && p[0] >= a[0].min(b[0]) - tol
        && p[0] <= a[0].max(b[0]) + tol
        && p[1] >= a[1].min(b[1]) - tol
        && p[1] <= a[1].max(b[1]) + tol
}

fn on_rect(r: &Rect, p: [f64; 2]) -> bool {
    let tol = 1e-12;
    p[0] >= r.r0 - tol && p[0] <= r.r1 + tol && p[1] >= r.z0 - tol && p[1] <= r.z1 + tol
}
