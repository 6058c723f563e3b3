//! Point location: which triangle contains a point `(r, z)`.
//!
//! A uniform bucket grid over the bounding box, with about one triangle per bucket, lists the
//! triangles whose bounding boxes overlap each bucket. Building it is O(triangles); a query tests the
//! few triangles of one bucket. A point just outside the mesh (round-off on the boundary) is given to
//! the triangle of its bucket with the least negative barycentric coordinate, if within a tolerance.
//!
//! For a handful of points, building the grid (two passes over the triangles with a bucket range
//! each) costs more than testing every triangle once: [`locate_by_scan`] does that, with the same
//! answer (the lowest-numbered triangle containing the point).
//!
//! A [`Probe`] is a named point where a physics samples its field (a problem file's `[[probe]]`).

use crate::discretisation::element::P1Triangle;
use crate::mesh::Mesh;

/// A named point where a field is sampled (every physics' `[[probe]]`).
#[derive(Debug, Clone, PartialEq)]
pub struct Probe {
    /// Name in the output.
    pub name: String,
    /// `[r, z]` (m).
    pub point: [f64; 2],
}

/// Bucket grid for point-in-triangle queries on one mesh.
#[derive(Debug, Clone)]
pub struct PointLocator {
    origin: [f64; 2],
    cell: [f64; 2],
    dims: [usize; 2],
    start: Vec<usize>,
    triangles: Vec<usize>,
}

impl PointLocator {
    /// Builds the grid for `mesh`.
    pub fn new(mesh: &Mesh) -> Self {
        let (lo, hi) = mesh.bounding_box();
        let n_tri = mesh.triangles.len().max(1);
        let width = (hi[0] - lo[0]).max(1e-300);
        let height = (hi[1] - lo[1]).max(1e-300);
        let per_unit = (n_tri as f64 / (width * height)).sqrt();
        let dims = [
            ((width * per_unit).ceil() as usize).clamp(1, 4096),
            ((height * per_unit).ceil() as usize).clamp(1, 4096),
        ];
        let cell = [width / dims[0] as f64, height / dims[1] as f64];
        let n_cells = dims[0] * dims[1];
        let bucket_range = |t: usize| {
            let tri = mesh.triangles[t];
            let mut bl = [f64::INFINITY; 2];
            let mut bh = [f64::NEG_INFINITY; 2];
            for &v in &tri {
                for k in 0..2 {
                    bl[k] = bl[k].min(mesh.nodes[v][k]);
                    bh[k] = bh[k].max(mesh.nodes[v][k]);
                }
            }
            let idx = |x: f64, k: usize| {
                (((x - lo[k]) / cell[k]).floor().max(0.0) as usize).min(dims[k] - 1)
            };
            (idx(bl[0], 0), idx(bh[0], 0), idx(bl[1], 1), idx(bh[1], 1))
        };
        let mut count = vec![0usize; n_cells + 1];
        for t in 0..mesh.triangles.len() {
            let (i0, i1, j0, j1) = bucket_range(t);
            for j in j0..=j1 {
                for i in i0..=i1 {
                    count[j * dims[0] + i + 1] += 1;
                }
            }
        }
        for c in 0..n_cells {
            count[c + 1] += count[c];
        }
        let mut fill = count.clone();
        let mut triangles = vec![0; count[n_cells]];
        for t in 0..mesh.triangles.len() {
            let (i0, i1, j0, j1) = bucket_range(t);
            for j in j0..=j1 {
                for i in i0..=i1 {
                    let c = j * dims[0] + i;
                    triangles[fill[c]] = t;
                    fill[c] += 1;
                }
            }
        }
        Self { origin: lo, cell, dims, start: count, triangles }
    }

    /// The triangle containing `p` and the barycentric coordinates of `p` in it, or `None` outside the
    /// mesh (beyond a relative tolerance of 1e-9 in barycentric coordinates).
    pub fn locate(&self, mesh: &Mesh, p: [f64; 2]) -> Option<(usize, [f64; 3])> {
        let i = ((p[0] - self.origin[0]) / self.cell[0]).floor();
        let j = ((p[1] - self.origin[1]) / self.cell[1]).floor();
        let inside_box = |x: f64, n: usize| x >= -1.0 && x <= n as f64;
        if !p[0].is_finite()
            || !p[1].is_finite()
            || !inside_box(i, self.dims[0])
            || !inside_box(j, self.dims[1])
        {
            return None;
        }
        let i = (i.max(0.0) as usize).min(self.dims[0] - 1);
        let j = (j.max(0.0) as usize).min(self.dims[1] - 1);
        let c = j * self.dims[0] + i;
        first_containing(mesh, p, self.triangles[self.start[c]..self.start[c + 1]].iter().copied())
    }
}

/// Barycentric tolerance for points just outside the mesh (round-off on the boundary).
const OUTSIDE_TOLERANCE: f64 = 1e-9;

/// The lowest-numbered triangle of `mesh` containing `p`, with the barycentric coordinates of `p`,
/// by testing every triangle (O(triangles), no set-up); `None` outside the mesh beyond the same
/// tolerance as [`PointLocator::locate`].
pub fn locate_by_scan(mesh: &Mesh, p: [f64; 2]) -> Option<(usize, [f64; 3])> {
    if !p[0].is_finite() || !p[1].is_finite() {
        return None;
    }
    // Cheap bounding-box rejection before the barycentric coordinates.
    let near = |t: &usize| {
        let [a, b, d] = mesh.triangles[*t];
        let (na, nb, nd) = (mesh.nodes[a], mesh.nodes[b], mesh.nodes[d]);
        let outside_box = |k: usize| {
            let (lo, hi) = (na[k].min(nb[k]).min(nd[k]), na[k].max(nb[k]).max(nd[k]));
            let slack = OUTSIDE_TOLERANCE * (hi - lo);
            p[k] < lo - slack || p[k] > hi + slack
        };
        !(outside_box(0) || outside_box(1))
    };
    first_containing(mesh, p, (0..mesh.triangles.len()).filter(near))
}

/// Among `candidates` (triangle indices, tested in the order given), the first triangle that
/// contains `p` (every barycentric coordinate >= 0) with the barycentric coordinates of `p`; if
/// none does, the one `p` is least outside of, provided it is within [`OUTSIDE_TOLERANCE`].
fn first_containing(
    mesh: &Mesh,
    p: [f64; 2],
    candidates: impl Iterator<Item = usize>,
) -> Option<(usize, [f64; 3])> {
    let mut best: Option<(usize, [f64; 3], f64)> = None;
    for t in candidates {
        let [a, b, d] = mesh.triangles[t];
        let l = P1Triangle::new([mesh.nodes[a], mesh.nodes[b], mesh.nodes[d]]).barycentric(p);
        let worst = l[0].min(l[1]).min(l[2]);
        if worst >= 0.0 {
            return Some((t, l));
        }
        if best.as_ref().is_none_or(|b| worst > b.2) {
            best = Some((t, l, worst));
        }
    }
    best.filter(|b| b.2 > -OUTSIDE_TOLERANCE).map(|(t, l, _)| (t, l))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::structured::{SideTags, graded_lines, rectangle_mesh};

    #[test]
    fn finds_points_and_rejects_outside() {
        let r = graded_lines(0.0, 1.0, 7, 3.0);
        let z = graded_lines(-1.0, 1.0, 9, 1.0);
        let m =
            rectangle_mesh(&r, &z, |_, _| 1, SideTags { r_min: 1, r_max: 2, z_min: 3, z_max: 4 })
                .unwrap();
        let loc = PointLocator::new(&m);
        for p in [[0.0, 0.0], [0.33, 0.71], [1.0, 1.0], [0.999, -0.999]] {
            let (t, l) = loc.locate(&m, p).expect("inside");
            let [a, b, c] = m.triangles[t];
            let tri = P1Triangle::new([m.nodes[a], m.nodes[b], m.nodes[c]]);
            let q = tri.point(l);
            assert!((q[0] - p[0]).abs() < 1e-12 && (q[1] - p[1]).abs() < 1e-12);
        }
        assert!(loc.locate(&m, [1.5, 0.0]).is_none());
        assert!(loc.locate(&m, [0.5, 1.2]).is_none());
        // The scan gives the same triangle (the lowest-numbered one containing the point).
        for k in 0..200 {
            let p = [(k % 17) as f64 / 16.0, -1.0 + (k % 23) as f64 / 11.0];
            assert_eq!(loc.locate(&m, p), locate_by_scan(&m, p), "{p:?}");
        }
        assert!(locate_by_scan(&m, [1.5, 0.0]).is_none());
        assert!(locate_by_scan(&m, [f64::NAN, 0.0]).is_none());
    }
}
