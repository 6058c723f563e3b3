//! Degrees of freedom of a Lagrange space of order 1 or 2 on a triangle mesh.
//!
//! Numbering: the mesh vertices first (DOF `v` is vertex `v`, so a P1 field and the vertex part of
//! a P2 field are indexed alike), then, for order 2, one DOF per unique edge of the triangles, at
//! the edge midpoint, numbered in the order the edges are first met when walking the triangles.
//! Element DOF lists follow the local order of [`crate::discretisation::element`]: vertices 0, 1, 2, then (P2) the
//! edges (0, 1), (1, 2), (2, 0).
//!
//! The map also gives what the forms and solvers need around it: the coordinates of every DOF
//! (for a geometric fill-reducing order and for interpolating prescribed values), the DOFs of the
//! tagged boundary edges (a tagged edge's midpoint DOF gets the edge's condition) and the DOFs on
//! the symmetry axis (vertices with `r = 0` and midpoints of edges with both ends there).
//!
//! The map shares the mesh (`Arc`): for P1 its element DOF lists and coordinates are the mesh's
//! triangles and nodes themselves, so a P1 map costs no memory.

use std::sync::Arc;

use crate::mesh::Mesh;

/// Polynomial order of the Lagrange elements.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Hash)]
pub enum ElementOrder {
    /// Linear triangles: one DOF per vertex.
    #[default]
    P1,
    /// Quadratic (6-node) triangles: vertices and edge midpoints.
    P2,
}

impl ElementOrder {
    /// The polynomial degree, 1 or 2.
    pub fn degree(self) -> usize {
        match self {
            Self::P1 => 1,
            Self::P2 => 2,
        }
    }

    /// The order of polynomial degree `degree`, or `None` for anything but 1 and 2.
    pub fn from_degree(degree: i64) -> Option<Self> {
        match degree {
            1 => Some(Self::P1),
            2 => Some(Self::P2),
            _ => None,
        }
    }

    /// DOFs per triangle (3 or 6).
    pub fn dofs_per_triangle(self) -> usize {
        match self {
            Self::P1 => 3,
            Self::P2 => 6,
        }
    }
}

/// The order of polynomial degree `degree`, the one rule of an element order for every front end
/// and problem file: anything but 1 and 2 is a field error naming `order`, the value and `1 or 2`
/// (the caller locates it in its file or names its flag).
impl TryFrom<i64> for ElementOrder {
    type Error = Box<mrbrake_error::FieldError>;

    fn try_from(degree: i64) -> Result<Self, Self::Error> {
        Self::from_degree(degree).ok_or_else(|| {
            Box::new(mrbrake_error::FieldError::out_of_range("order", degree, "1 or 2"))
        })
    }
}

impl std::fmt::Display for ElementOrder {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "P{}", self.degree())
    }
}

/// The global numbering of the DOFs of one order on one mesh.
#[derive(Debug, Clone, PartialEq)]
pub struct DofMap {
    mesh: Arc<Mesh>,
    order: ElementOrder,
    n_vertices: usize,
    /// End vertices `[a, b]` (`a < b`) of each edge DOF `n_vertices + k`.
    edges: Vec<[usize; 2]>,
    /// P2: the 6 global DOFs per triangle (P1: empty, the mesh triangles are the lists).
    element_dofs: Vec<usize>,
    /// P2: `[r, z]` of every DOF, vertices then edge midpoints (P1: empty, the mesh nodes).
    coordinates: Vec<[f64; 2]>,
    /// Edges by their lower vertex (compressed rows): the upper vertex and the edge index.
    edge_start: Vec<usize>,
    edge_upper: Vec<(usize, usize)>,
}

impl DofMap {
    /// Numbers the DOFs of `order` on `mesh` (which should pass [`Mesh::validate`]; node indices
    /// out of range panic).
    pub fn new(mesh: Arc<Mesh>, order: ElementOrder) -> Self {
        let n_vertices = mesh.nodes.len();
        let mut coordinates = Vec::new();
        let (mut edges, mut edge_start, mut edge_upper) = (Vec::new(), Vec::new(), Vec::new());
        let element_dofs = match order {
            ElementOrder::P1 => Vec::new(),
            ElementOrder::P2 => {
                // Upper bound of the edges per lower vertex (shared edges are counted twice).
                let mut count = vec![0usize; n_vertices + 1];
                for tri in &mesh.triangles {
                    for [i, j] in crate::discretisation::element::P2_EDGES {
                        count[tri[i].min(tri[j]) + 1] += 1;
                    }
                }
                for v in 0..n_vertices {
                    count[v + 1] += count[v];
                }
                let mut filled = vec![0usize; n_vertices];
                let mut slots = vec![(usize::MAX, usize::MAX); count[n_vertices]];
                let mut dofs = Vec::with_capacity(6 * mesh.triangles.len());
                for tri in &mesh.triangles {
                    dofs.extend_from_slice(tri);
                    for [i, j] in crate::discretisation::element::P2_EDGES {
                        let (a, b) = (tri[i].min(tri[j]), tri[i].max(tri[j]));
                        let known = slots[count[a]..count[a] + filled[a]]
                            .iter()
                            .find(|(upper, _)| *upper == b)
                            .map(|&(_, edge)| edge);
                        let edge = match known {
                            Some(edge) => edge,
                            None => {
                                let edge = edges.len();
                                edges.push([a, b]);
                                slots[count[a] + filled[a]] = (b, edge);
                                filled[a] += 1;
                                edge
                            }
                        };
                        dofs.push(n_vertices + edge);
                    }
                }
                // Compact the rows.
                edge_start.reserve(n_vertices + 1);
                edge_start.push(0);
                edge_upper.reserve(edges.len());
                for v in 0..n_vertices {
                    edge_upper.extend_from_slice(&slots[count[v]..count[v] + filled[v]]);
                    edge_start.push(edge_upper.len());
                }
                coordinates.reserve(n_vertices + edges.len());
                coordinates.extend_from_slice(&mesh.nodes);
                coordinates.extend(edges.iter().map(|&[a, b]| {
                    let (pa, pb) = (mesh.nodes[a], mesh.nodes[b]);
                    [0.5 * (pa[0] + pb[0]), 0.5 * (pa[1] + pb[1])]
                }));
                dofs
            }
        };
        Self { mesh, order, n_vertices, edges, element_dofs, coordinates, edge_start, edge_upper }
    }

    /// The mesh the DOFs are numbered on.
    pub fn mesh(&self) -> &Arc<Mesh> {
        &self.mesh
    }

    /// The element order.
    pub fn order(&self) -> ElementOrder {
        self.order
    }

    /// Total number of DOFs (vertices plus, for P2, edges).
    pub fn len(&self) -> usize {
        self.n_vertices + self.edges.len()
    }

    /// True for a mesh without nodes.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Number of vertex DOFs (the mesh nodes): DOFs `0..n_vertices()`.
    pub fn n_vertices(&self) -> usize {
        self.n_vertices
    }

    /// DOFs per triangle.
    pub fn dofs_per_triangle(&self) -> usize {
        self.order.dofs_per_triangle()
    }

    /// Global DOFs of triangle `t` in local order.
    pub fn element(&self, t: usize) -> &[usize] {
        let k = self.dofs_per_triangle();
        &self.element_dofs()[t * k..(t + 1) * k]
    }

    /// The DOF lists of all triangles, [`Self::dofs_per_triangle`] per triangle (for P1 the
    /// mesh's triangles).
    pub fn element_dofs(&self) -> &[usize] {
        match self.order {
            ElementOrder::P1 => self.mesh.triangles.as_flattened(),
            ElementOrder::P2 => &self.element_dofs,
        }
    }

    /// `[r, z]` of every DOF: the vertex, or the midpoint of the edge (for P1 the mesh's nodes).
    pub fn coordinates(&self) -> &[[f64; 2]] {
        match self.order {
            ElementOrder::P1 => &self.mesh.nodes,
            ElementOrder::P2 => &self.coordinates,
        }
    }

    /// End vertices of edge DOF `dof`, or `None` for a vertex DOF (or an index out of range).
    pub fn edge_vertices(&self, dof: usize) -> Option<[usize; 2]> {
        dof.checked_sub(self.n_vertices).and_then(|k| self.edges.get(k).copied())
    }

    /// The DOF at the midpoint of the edge between vertices `a` and `b`: `None` for P1, or when
    /// no triangle has that edge.
    pub fn edge_dof(&self, a: usize, b: usize) -> Option<usize> {
        if self.order == ElementOrder::P1 {
            return None;
        }
        let (lo, hi) = (a.min(b), a.max(b));
        let row = self.edge_start.get(lo..=lo + 1)?;
        self.edge_upper[row[0]..row[1]]
            .iter()
            .find(|(upper, _)| *upper == hi)
            .map(|&(_, edge)| self.n_vertices + edge)
    }

    /// DOFs of the mesh edges tagged `tag` (their vertices and, for P2, their midpoints), sorted
    /// and de-duplicated. A tagged edge that is not the side of a triangle contributes its vertices
    /// only.
    pub fn boundary_dofs(&self, tag: u32) -> Vec<usize> {
        let mesh = &self.mesh;
        let mut dofs = Vec::new();
        for (e, _) in mesh.edges.iter().zip(&mesh.edge_tags).filter(|(_, t)| **t == tag) {
            dofs.extend_from_slice(e);
            dofs.extend(self.edge_dof(e[0], e[1]));
        }
        dofs.sort_unstable();
        dofs.dedup();
        dofs
    }

    /// DOFs on the symmetry axis: the vertices of [`Mesh::axis_nodes`] and, for P2, the midpoints
    /// of edges with both ends among them. Sorted.
    pub fn axis_dofs(&self) -> Vec<usize> {
        let mut dofs = self.mesh.axis_nodes();
        let mut on_axis = vec![false; self.n_vertices];
        for &v in &dofs {
            on_axis[v] = true;
        }
        for (k, &[a, b]) in self.edges.iter().enumerate() {
            if on_axis[a] && on_axis[b] {
                dofs.push(self.n_vertices + k);
            }
        }
        dofs
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::structured::{SideTags, graded_lines, rectangle_mesh};

    fn grid(nr: usize, nz: usize) -> Arc<Mesh> {
        let r = graded_lines(0.0, 1.0, nr, 2.0);
        let z = graded_lines(-1.0, 1.0, nz, 1.0);
        let sides = SideTags { r_min: 1, r_max: 2, z_min: 3, z_max: 4 };
        Arc::new(rectangle_mesh(&r, &z, |_, _| 1, sides).unwrap())
    }

    #[test]
    fn p1_dofs_are_the_vertices() {
        let mesh = grid(3, 2);
        let map = DofMap::new(mesh.clone(), ElementOrder::P1);
        assert_eq!(map.len(), mesh.nodes.len());
        assert_eq!(map.coordinates(), &mesh.nodes[..]);
        assert_eq!(map.element(1), &mesh.triangles[1]);
        assert_eq!(map.edge_dof(0, 1), None);
        assert_eq!(map.axis_dofs(), mesh.axis_nodes());
        assert_eq!(map.boundary_dofs(2), mesh.boundary_nodes(2));
    }

    /// Euler's formula for a triangulated disc: E = V + T − 1; every edge is shared by at most
    /// two triangles and the midpoint DOF of each local edge is the edge's.
    #[test]
    fn p2_numbers_each_edge_once() {
        let mesh = grid(5, 4);
        let map = DofMap::new(mesh.clone(), ElementOrder::P2);
        let (v, t) = (mesh.nodes.len(), mesh.triangles.len());
        let n_edges = map.len() - v;
        assert_eq!(n_edges, v + t - 1);
        assert_eq!(map.n_vertices(), v);
        let mut uses = vec![0usize; map.len()];
        for t in 0..t {
            let dofs = map.element(t);
            assert_eq!(&dofs[..3], &mesh.triangles[t]);
            for (local, [i, j]) in crate::discretisation::element::P2_EDGES.iter().enumerate() {
                let d = dofs[3 + local];
                uses[d] += 1;
                assert_eq!(map.edge_dof(dofs[*i], dofs[*j]), Some(d));
                assert_eq!(map.edge_dof(dofs[*j], dofs[*i]), Some(d));
                let mut ends = map.edge_vertices(d).unwrap();
                ends.sort_unstable();
                let mut expected = [dofs[*i], dofs[*j]];
                expected.sort_unstable();
                assert_eq!(ends, expected);
                let (p, a, b) =
                    (map.coordinates()[d], mesh.nodes[expected[0]], mesh.nodes[expected[1]]);
                assert!((p[0] - 0.5 * (a[0] + b[0])).abs() < 1e-15);
                assert!((p[1] - 0.5 * (a[1] + b[1])).abs() < 1e-15);
            }
        }
        assert!(uses[v..].iter().all(|&u| u == 1 || u == 2));
        // Boundary edges (used once) are the 2 (5 + 4) sides of the rectangle.
        assert_eq!(uses[v..].iter().filter(|&&u| u == 1).count(), 2 * (5 + 4));
        assert_eq!(map.edge_dof(0, mesh.nodes.len() - 1), None);
        assert_eq!(map.edge_vertices(0), None);
    }

    #[test]
    fn p2_boundary_and_axis_dofs_include_the_midpoints() {
        let mesh = grid(3, 2);
        let map = DofMap::new(mesh, ElementOrder::P2);
        // The axis side r = 0 has 3 vertices and 2 edges.
        let axis = map.axis_dofs();
        assert_eq!(axis.len(), 5);
        for &d in &axis {
            assert!(map.coordinates()[d][0].abs() < 1e-15);
        }
        // The side r = r_max (tag 2) likewise; every DOF on it has r = 1.
        let side = map.boundary_dofs(2);
        assert_eq!(side.len(), 5);
        assert!(side.iter().all(|&d| (map.coordinates()[d][0] - 1.0).abs() < 1e-15));
        // The top z = 1 (tag 4): 4 vertices, 3 midpoints.
        assert_eq!(map.boundary_dofs(4).len(), 7);
    }
}
