//! Mesh quality and bookkeeping measures: triangle angles, areas per region, point location.
//!
//! Used by the mesher's tests and by callers that check a mesh (gap resolution, region areas).

use std::collections::BTreeMap;

use crate::mesh::Mesh;

/// Signed area of the triangle abc (positive when counter-clockwise), m².
pub fn signed_area(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> f64 {
    0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]))
}

/// The three node coordinates of triangle `t`.
pub fn triangle_points(mesh: &Mesh, t: usize) -> [[f64; 2]; 3] {
    mesh.triangles[t].map(|i| mesh.nodes[i])
}

/// The smallest interior angle of a triangle, degrees.
pub fn min_angle_deg(p: [[f64; 2]; 3]) -> f64 {
    let mut smallest = f64::INFINITY;
    for i in 0..3 {
        let (a, b, c) = (p[i], p[(i + 1) % 3], p[(i + 2) % 3]);
        let u = [b[0] - a[0], b[1] - a[1]];
        let v = [c[0] - a[0], c[1] - a[1]];
        let cos = (u[0] * v[0] + u[1] * v[1])
            / ((u[0] * u[0] + u[1] * u[1]).sqrt() * (v[0] * v[0] + v[1] * v[1]).sqrt());
        smallest = smallest.min(cos.clamp(-1.0, 1.0).acos().to_degrees());
    }
    smallest
}

/// Total planar area (m²) of the triangles of each tag.
pub fn area_by_tag(mesh: &Mesh) -> BTreeMap<u32, f64> {
    let mut areas = BTreeMap::new();
    for (t, tag) in mesh.triangle_tags.iter().enumerate() {
        let [a, b, c] = triangle_points(mesh, t);
        *areas.entry(*tag).or_insert(0.0) += signed_area(a, b, c);
    }
    areas
}

/// True when point x lies in the closed triangle p (with a relative tolerance on the edges).
pub fn triangle_contains(p: [[f64; 2]; 3], x: [f64; 2]) -> bool {
    let area = signed_area(p[0], p[1], p[2]).abs();
    let tol = -1e-12 * area.max(f64::MIN_POSITIVE);
    let s0 = signed_area(p[0], p[1], x);
    let s1 = signed_area(p[1], p[2], x);
    let s2 = signed_area(p[2], p[0], x);
    s0 >= tol && s1 >= tol && s2 >= tol
}

/// Brute-force list of the triangles containing x (O(triangles); for tests and small queries).
pub fn triangles_at(mesh: &Mesh, x: [f64; 2]) -> Vec<usize> {
    (0..mesh.triangles.len()).filter(|&t| triangle_contains(triangle_points(mesh, t), x)).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn equilateral_angles_and_area() {
        let p = [[0.0, 0.0], [1.0, 0.0], [0.5, 3f64.sqrt() / 2.0]];
        assert!((min_angle_deg(p) - 60.0).abs() < 1e-9);
        assert!((signed_area(p[0], p[1], p[2]) - 3f64.sqrt() / 4.0).abs() < 1e-15);
        assert!(triangle_contains(p, [0.5, 0.2]));
        assert!(!triangle_contains(p, [0.5, -0.2]));
    }
}
