//! The triangle mesh of an axisymmetric (r, z) cross-section.
//!
//! Coordinates are in metres, `x = r >= 0` and `y = z`. The mesh is the geometric (first-order)
//! mesh; higher-order elements add their extra degrees of freedom on top of it.
//!
//! [`Mesh::validate`] checks the invariants every consumer relies on (indices in range, tag arrays of
//! the right length, `r >= 0`, non-degenerate counter-clockwise triangles); the Gmsh reader, the
//! structured generator and the mesher all produce meshes that pass it.
//!
//! The mesh side of the core, beside the [`Mesh`] type: [`structured`] (graded rectangle and
//! half-disc meshes for tests and simple geometries), [`mesher`] (constrained Delaunay with
//! refinement), [`gmsh`] (MSH 2.2 / 4.1 reader), [`vtu`] (ParaView output) and [`locate`] (point
//! location).

pub mod gmsh;
pub mod locate;
pub mod mesher;
pub mod structured;
pub mod vtu;

use crate::FemError;

/// A planar triangle mesh with physical tags on triangles and boundary edges.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Mesh {
    /// Node coordinates `[r, z]` in metres.
    pub nodes: Vec<[f64; 2]>,
    /// Triangles as three node indices, counter-clockwise.
    pub triangles: Vec<[usize; 3]>,
    /// Physical (region) tag of each triangle, same length as `triangles`.
    pub triangle_tags: Vec<u32>,
    /// Tagged boundary (or interface) edges as two node indices.
    pub edges: Vec<[usize; 2]>,
    /// Physical tag of each edge in `edges`, same length as `edges`.
    pub edge_tags: Vec<u32>,
}

impl Mesh {
    /// Signed area (m²) of triangle `t`: positive when its nodes are counter-clockwise in (r, z).
    pub fn signed_area(&self, t: usize) -> f64 {
        let [a, b, c] = self.triangles[t];
        signed_area(self.nodes[a], self.nodes[b], self.nodes[c])
    }

    /// Area (m²) of the cross-section covered by triangles tagged `tag`.
    pub fn region_area(&self, tag: u32) -> f64 {
        (0..self.triangles.len())
            .filter(|&t| self.triangle_tags[t] == tag)
            .map(|t| self.signed_area(t).abs())
            .sum()
    }

    /// Sorted, de-duplicated triangle (region) tags.
    pub fn region_tags(&self) -> Vec<u32> {
        let mut tags = self.triangle_tags.clone();
        tags.sort_unstable();
        tags.dedup();
        tags
    }

    /// Sorted, de-duplicated edge (boundary) tags.
    pub fn boundary_tags(&self) -> Vec<u32> {
        let mut tags = self.edge_tags.clone();
        tags.sort_unstable();
        tags.dedup();
        tags
    }

    /// Bounding box `([r_min, z_min], [r_max, z_max])` of the nodes (zeros for an empty mesh).
    pub fn bounding_box(&self) -> ([f64; 2], [f64; 2]) {
        if self.nodes.is_empty() {
            return ([0.0; 2], [0.0; 2]);
        }
        let mut lo = [f64::INFINITY; 2];
        let mut hi = [f64::NEG_INFINITY; 2];
        for p in &self.nodes {
            for k in 0..2 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
        (lo, hi)
    }

    /// Length (m) of the bounding-box diagonal, the scale for geometric tolerances.
    pub fn size_scale(&self) -> f64 {
        let (lo, hi) = self.bounding_box();
        (hi[0] - lo[0]).hypot(hi[1] - lo[1])
    }

    /// Reorders the nodes of clockwise triangles so that every triangle is counter-clockwise.
    pub fn orient_counter_clockwise(&mut self) {
        for t in 0..self.triangles.len() {
            if self.signed_area(t) < 0.0 {
                self.triangles[t].swap(1, 2);
            }
        }
    }

    /// Checks the mesh invariants: tag arrays as long as their element arrays, node indices in range,
    /// finite coordinates with `r >= -tol`, and triangles counter-clockwise with an area above
    /// `1e-14 ×` the squared bounding-box diagonal. The error names the first offending item.
    pub fn validate(&self) -> Result<(), FemError> {
        if self.triangles.len() != self.triangle_tags.len() {
            return Err(FemError::field(
                "triangle_tags",
                format!(
                    "mesh has {} triangles but {} triangle tags",
                    self.triangles.len(),
                    self.triangle_tags.len()
                ),
            ));
        }
        if self.edges.len() != self.edge_tags.len() {
            return Err(FemError::field(
                "edge_tags",
                format!(
                    "mesh has {} edges but {} edge tags",
                    self.edges.len(),
                    self.edge_tags.len()
                ),
            ));
        }
        if self.triangles.is_empty() {
            return Err(FemError::field("triangles", "mesh has no triangles"));
        }
        let scale = self.size_scale();
        // Indices here are the mesh's own, 0-based; a mesh read from a file is checked in the
        // file's own tags first (`crate::mesh::gmsh`), so these messages are for meshes built in code.
        for (i, p) in self.nodes.iter().enumerate() {
            if !p[0].is_finite() || !p[1].is_finite() {
                return Err(FemError::field(
                    "nodes",
                    format!("mesh node {i} (0-based index) has a non-finite coordinate {p:?}"),
                ));
            }
            if p[0] < -1e-9 * scale {
                return Err(FemError::field(
                    "nodes",
                    format!(
                        "mesh node {i} has r = {} m < 0: an axisymmetric mesh must lie in r >= 0",
                        p[0]
                    ),
                ));
            }
        }
        let n = self.nodes.len();
        for (t, tri) in self.triangles.iter().enumerate() {
            if tri.iter().any(|&v| v >= n) {
                return Err(FemError::field(
                    "triangles",
                    format!("triangle {t} references node {tri:?} but the mesh has {n} nodes"),
                ));
            }
            let area = self.signed_area(t);
            if area <= 1e-14 * scale * scale {
                return Err(FemError::field(
                    "triangles",
                    format!(
                        "triangle {t} (0-based index; nodes {tri:?}) is degenerate or clockwise (signed area \
                     {area:e} m²)"
                    ),
                ));
            }
        }
        for (e, edge) in self.edges.iter().enumerate() {
            if edge.iter().any(|&v| v >= n) || edge[0] == edge[1] {
                return Err(FemError::field(
                    "edges",
                    format!("edge {e} has invalid nodes {edge:?} ({n} nodes)"),
                ));
            }
        }
        Ok(())
    }

    /// Nodes that lie on the symmetry axis, `r <= 1e-9 ×` the mesh size scale.
    pub fn axis_nodes(&self) -> Vec<usize> {
        let tol = 1e-9 * self.size_scale();
        (0..self.nodes.len()).filter(|&i| self.nodes[i][0] <= tol).collect()
    }

    /// Nodes of the edges tagged `tag`, sorted and de-duplicated.
    pub fn boundary_nodes(&self, tag: u32) -> Vec<usize> {
        let mut nodes: Vec<usize> = self
            .edges
            .iter()
            .zip(&self.edge_tags)
            .filter(|(_, t)| **t == tag)
            .flat_map(|(e, _)| e.iter().copied())
            .collect();
        nodes.sort_unstable();
        nodes.dedup();
        nodes
    }
}

/// Signed area of the triangle (a, b, c): half the cross product, positive counter-clockwise.
pub fn signed_area(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> f64 {
    0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1]))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn unit_square() -> Mesh {
        Mesh {
            nodes: vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]],
            triangles: vec![[0, 1, 2], [0, 2, 3]],
            triangle_tags: vec![1, 2],
            edges: vec![[0, 1]],
            edge_tags: vec![7],
        }
    }

    #[test]
    fn areas_and_tags() {
        let m = unit_square();
        assert!(m.validate().is_ok());
        assert!((m.region_area(1) - 0.5).abs() < 1e-15);
        assert_eq!(m.region_tags(), vec![1, 2]);
        assert_eq!(m.boundary_nodes(7), vec![0, 1]);
        assert_eq!(m.axis_nodes(), vec![0, 3]);
    }

    #[test]
    fn orientation_is_fixed_and_checked() {
        let mut m = unit_square();
        m.triangles[0] = [0, 2, 1];
        assert!(m.validate().is_err());
        m.orient_counter_clockwise();
        assert!(m.validate().is_ok());
    }

    #[test]
    fn negative_radius_is_rejected() {
        let mut m = unit_square();
        m.nodes[0][0] = -0.5;
        let err = m.validate().unwrap_err().to_string();
        assert!(err.contains("r >= 0"), "{err}");
    }
}
