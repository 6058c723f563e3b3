//! The triangle mesh of an axisymmetric (r, z) cross-section.
//!
//! Coordinates are in metres, `x = r >= 0` and `y = z`. The mesh is the geometric (first-order)
//! mesh; higher-order elements add their extra degrees of freedom on top of it.

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
