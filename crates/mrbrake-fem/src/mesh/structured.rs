//! Structured triangle meshes for rectangles of blocks and for half-discs (tests, benchmarks, simple
//! geometries). The general-purpose mesher lives in `mesher`.
//!
//! - [`graded_lines`] spaces grid lines geometrically (ratio of last to first cell).
//! - [`rectangle_mesh`] meshes the tensor grid `r_lines × z_lines`: each cell is split into two
//!   triangles, the diagonal alternating in a chequerboard so the mesh has no preferred direction; the
//!   region tag of a cell is chosen by a closure of the cell centre, and the four sides get edge tags.
//! - [`half_disc_mesh`] meshes `{ρ <= ρ_max, r >= 0}` on rings (polar grid) with a fan at the centre;
//!   used for spheres and spherical outer boundaries.

use crate::FemError;
use crate::mesh::{Mesh, signed_area};
use mrbrake_error::FieldError;

/// Edge tags of the four sides of a rectangle mesh.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SideTags {
    /// Tag of the side `r = r_min` (the axis when `r_min = 0`).
    pub r_min: u32,
    /// Tag of the side `r = r_max`.
    pub r_max: u32,
    /// Tag of the side `z = z_min`.
    pub z_min: u32,
    /// Tag of the side `z = z_max`.
    pub z_max: u32,
}

/// `cells + 1` grid lines from `start` to `end`, cell sizes in geometric progression with
/// `last cell / first cell = ratio` (`ratio = 1` gives uniform spacing).
pub fn graded_lines(start: f64, end: f64, cells: usize, ratio: f64) -> Vec<f64> {
    let cells = cells.max(1);
    if cells == 1 || (ratio - 1.0).abs() < 1e-12 || ratio <= 0.0 {
        return (0..=cells).map(|i| start + (end - start) * i as f64 / cells as f64).collect();
    }
    let q = ratio.powf(1.0 / (cells - 1) as f64);
    let total: f64 = (0..cells).map(|i| q.powi(i as i32)).sum();
    let mut lines = Vec::with_capacity(cells + 1);
    let mut x = start;
    lines.push(x);
    for i in 0..cells {
        x += (end - start) * q.powi(i as i32) / total;
        lines.push(x);
    }
    lines[cells] = end;
    lines
}

/// Concatenates grid-line segments (each from [`graded_lines`]), dropping the repeated joints.
pub fn join_lines(segments: &[Vec<f64>]) -> Vec<f64> {
    let mut out: Vec<f64> = Vec::new();
    for seg in segments {
        for &x in seg {
            if out.last().is_none_or(|&last| x > last + 1e-15 * (1.0 + x.abs())) {
                out.push(x);
            }
        }
    }
    out
}

/// Meshes the grid `r_lines × z_lines` (both strictly increasing, at least two lines each).
/// `region_of(r_centre, z_centre)` gives the tag of each cell; `sides` tags the boundary edges.
pub fn rectangle_mesh(
    r_lines: &[f64],
    z_lines: &[f64],
    region_of: impl Fn(f64, f64) -> u32,
    sides: SideTags,
) -> Result<Mesh, FemError> {
    check_increasing("r_lines", r_lines)?;
    check_increasing("z_lines", z_lines)?;
    let (nr, nz) = (r_lines.len(), z_lines.len());
    let id = |i: usize, j: usize| j * nr + i;
    let mut mesh = Mesh {
        nodes: Vec::with_capacity(nr * nz),
        triangles: Vec::with_capacity(2 * (nr - 1) * (nz - 1)),
        triangle_tags: Vec::with_capacity(2 * (nr - 1) * (nz - 1)),
        ..Mesh::default()
    };
    for &z in z_lines {
        for &r in r_lines {
            mesh.nodes.push([r, z]);
        }
    }
    for j in 0..nz - 1 {
        for i in 0..nr - 1 {
            let tag =
                region_of(0.5 * (r_lines[i] + r_lines[i + 1]), 0.5 * (z_lines[j] + z_lines[j + 1]));
            let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
            if (i + j) % 2 == 0 {
                mesh.triangles.extend([[a, b, c], [a, c, d]]);
            } else {
                mesh.triangles.extend([[a, b, d], [b, c, d]]);
            }
            mesh.triangle_tags.extend([tag, tag]);
        }
    }
    for i in 0..nr - 1 {
        mesh.edges.push([id(i, 0), id(i + 1, 0)]);
        mesh.edge_tags.push(sides.z_min);
        mesh.edges.push([id(i, nz - 1), id(i + 1, nz - 1)]);
        mesh.edge_tags.push(sides.z_max);
    }
    for j in 0..nz - 1 {
        mesh.edges.push([id(0, j), id(0, j + 1)]);
        mesh.edge_tags.push(sides.r_min);
        mesh.edges.push([id(nr - 1, j), id(nr - 1, j + 1)]);
        mesh.edge_tags.push(sides.r_max);
    }
    mesh.validate()?;
    Ok(mesh)
}

/// Meshes the half disc `ρ = √(r² + z²) <= radii.last()`, `r >= 0`, on the rings `radii` (strictly
/// increasing, first > 0) with `n_theta` angular cells from the +z axis (θ = 0) to the −z axis (θ = π).
/// `region_of(r, z)` tags each triangle from its centroid.
/// The outer arc gets `outer_tag`, the axis `axis_tag`.
pub fn half_disc_mesh(
    radii: &[f64],
    n_theta: usize,
    region_of: impl Fn(f64, f64) -> u32,
    outer_tag: u32,
    axis_tag: u32,
) -> Result<Mesh, FemError> {
    check_increasing("radii", radii)?;
    if radii[0] <= 0.0 {
        return Err(FieldError::out_of_range("radii[0]", radii[0], "> 0").into());
    }
    if n_theta < 2 {
        return Err(FieldError::out_of_range("n_theta", n_theta, ">= 2").into());
    }
    let nt = n_theta + 1;
    let mut mesh = Mesh { nodes: vec![[0.0, 0.0]], ..Mesh::default() };
    for &rho in radii {
        for j in 0..nt {
            let theta = std::f64::consts::PI * j as f64 / n_theta as f64;
            let r = if j == 0 || j == n_theta { 0.0 } else { rho * theta.sin() };
            mesh.nodes.push([r, rho * theta.cos()]);
        }
    }
    let id = |ring: usize, j: usize| 1 + ring * nt + j;
    let push = |mesh: &mut Mesh, mut tri: [usize; 3]| {
        let centroid = |k: usize| {
            (mesh.nodes[tri[0]][k] + mesh.nodes[tri[1]][k] + mesh.nodes[tri[2]][k]) / 3.0
        };
        let tag = region_of(centroid(0), centroid(1));
        if signed_area(mesh.nodes[tri[0]], mesh.nodes[tri[1]], mesh.nodes[tri[2]]) < 0.0 {
            tri.swap(1, 2);
        }
        mesh.triangles.push(tri);
        mesh.triangle_tags.push(tag);
    };
    for j in 0..n_theta {
        push(&mut mesh, [0, id(0, j), id(0, j + 1)]);
    }
    for ring in 0..radii.len() - 1 {
        for j in 0..n_theta {
            let (a, b, c, d) = (id(ring, j), id(ring, j + 1), id(ring + 1, j + 1), id(ring + 1, j));
            if (ring + j) % 2 == 0 {
                push(&mut mesh, [a, b, c]);
                push(&mut mesh, [a, c, d]);
            } else {
                push(&mut mesh, [a, b, d]);
                push(&mut mesh, [b, c, d]);
            }
        }
    }
    let last = radii.len() - 1;
    for j in 0..n_theta {
        mesh.edges.push([id(last, j), id(last, j + 1)]);
        mesh.edge_tags.push(outer_tag);
    }
    let mut previous_top = 0;
    let mut previous_bottom = 0;
    for ring in 0..radii.len() {
        mesh.edges.push([previous_top, id(ring, 0)]);
        mesh.edges.push([previous_bottom, id(ring, n_theta)]);
        mesh.edge_tags.extend([axis_tag, axis_tag]);
        previous_top = id(ring, 0);
        previous_bottom = id(ring, n_theta);
    }
    mesh.validate()?;
    Ok(mesh)
}

fn check_increasing(name: &str, lines: &[f64]) -> Result<(), FemError> {
    if lines.len() < 2 {
        let e = FieldError::out_of_range(name, format!("{} values", lines.len()), ">= 2 values");
        return Err(e.into());
    }
    for (k, w) in lines.windows(2).enumerate() {
        if w[1].partial_cmp(&w[0]) != Some(std::cmp::Ordering::Greater)
            || !w[0].is_finite()
            || !w[1].is_finite()
        {
            let e = FieldError::new(format!("{name}[{}]", k + 1), "not after the value before it");
            let e = e.with_value(w[1]).with_allowed(format!("finite, > {name}[{k}] = {}", w[0]));
            return Err(e.into());
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    const SIDES: SideTags = SideTags { r_min: 1, r_max: 2, z_min: 3, z_max: 4 };

    #[test]
    fn graded_lines_hit_ends_and_ratio() {
        let l = graded_lines(0.0, 1.0, 10, 4.0);
        assert_eq!(l.len(), 11);
        assert!(l[0].abs() < 1e-15 && (l[10] - 1.0).abs() < 1e-15);
        let ratio = (l[10] - l[9]) / (l[1] - l[0]);
        assert!((ratio - 4.0).abs() < 1e-9);
    }

    #[test]
    fn rectangle_mesh_counts_and_area() {
        let r = graded_lines(0.0, 2.0, 4, 1.0);
        let z = graded_lines(-1.0, 1.0, 3, 2.0);
        let m = rectangle_mesh(&r, &z, |r, _| if r < 1.0 { 10 } else { 20 }, SIDES).unwrap();
        assert_eq!(m.nodes.len(), 5 * 4);
        assert_eq!(m.triangles.len(), 2 * 4 * 3);
        assert!((m.region_area(10) + m.region_area(20) - 4.0).abs() < 1e-12);
        assert!((m.region_area(10) - 2.0).abs() < 1e-12);
        assert_eq!(m.boundary_nodes(1).len(), 4);
    }

    #[test]
    fn half_disc_area_converges_to_half_circle() {
        let radii = graded_lines(0.1, 1.0, 9, 1.0);
        let m = half_disc_mesh(&radii, 64, |_, _| 1, 5, 6).unwrap();
        let exact = 0.5 * std::f64::consts::PI;
        // Inscribed polygon: relative area deficit ≈ (π/n)²/6.
        assert!((m.region_area(1) - exact).abs() / exact < 1e-3);
        assert!(m.axis_nodes().len() == 2 * 10 + 1);
    }

    #[test]
    fn bad_lines_are_rejected() {
        assert!(rectangle_mesh(&[0.0, 0.0], &[0.0, 1.0], |_, _| 1, SIDES).is_err());
        assert!(rectangle_mesh(&[0.0], &[0.0, 1.0], |_, _| 1, SIDES).is_err());
    }
}
