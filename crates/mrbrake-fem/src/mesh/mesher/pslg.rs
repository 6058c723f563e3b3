//! The mesher's input: a planar straight-line graph (PSLG) in (r, z) metres.
//!
//! A [`Pslg`] holds vertices, segments (each optionally carrying a physical tag, e.g. the axis or an
//! interface line that post-processing samples), and region seeds (a point inside a region and the
//! region's physical tag). Builders ([`Pslg::add_polygon`], [`Pslg::add_rectangle`]) let a geometry be
//! written as overlapping-edge polygons: [`Pslg::normalized`] merges coincident vertices (within
//! [`Pslg::snap_m`]), splits segments at vertices lying on them (T-junctions, shared edges of
//! neighbouring rectangles) and removes duplicates, so that the constrained triangulation receives
//! a valid graph. Properly crossing segments are rejected with an input error: the mesher never
//! invents intersection points silently.

use std::collections::HashMap;

use crate::FemError;

/// A region seed: any point strictly inside the region, and the region's physical tag.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RegionSeed {
    /// A point `[r, z]` (m) strictly inside the region, away from every segment.
    pub point: [f64; 2],
    /// The physical tag given to every triangle of the region.
    pub tag: u32,
}

/// One straight segment between two vertex indices, with an optional physical tag.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Segment {
    /// First vertex index.
    pub a: usize,
    /// Second vertex index.
    pub b: usize,
    /// Physical tag of the mesh edges lying on this segment (`None`: an untagged constraint).
    pub tag: Option<u32>,
}

/// A planar straight-line graph with region seeds.
#[derive(Debug, Clone)]
pub struct Pslg {
    vertices: Vec<[f64; 2]>,
    lookup: HashMap<(i64, i64), usize>,
    segments: Vec<Segment>,
    seeds: Vec<RegionSeed>,
    snap_m: f64,
}

/// The PSLG after [`Pslg::normalized`]: no duplicate vertices, no vertex inside a segment, no
/// duplicate or crossing segments.
#[derive(Debug, Clone)]
pub struct NormalizedPslg {
    /// Vertex coordinates `[r, z]` (m).
    pub vertices: Vec<[f64; 2]>,
    /// Segments between vertex indices, with merged tags.
    pub segments: Vec<Segment>,
    /// Region seeds.
    pub seeds: Vec<RegionSeed>,
}

impl Default for Pslg {
    fn default() -> Self {
        Self::new()
    }
}

impl Pslg {
    /// An empty graph with the default snapping tolerance of 1 nm (machined brake parts are
    /// dimensioned to micrometres, so points closer than a nanometre are the same point).
    pub fn new() -> Self {
        Self::with_snap(1e-9)
    }

    /// An empty graph whose vertices closer than `snap_m` (m) are merged.
    pub fn with_snap(snap_m: f64) -> Self {
        Self {
            vertices: Vec::new(),
            lookup: HashMap::new(),
            segments: Vec::new(),
            seeds: Vec::new(),
            snap_m,
        }
    }

    /// The snapping tolerance (m).
    pub fn snap_m(&self) -> f64 {
        self.snap_m
    }

    /// The vertices added so far.
    pub fn vertices(&self) -> &[[f64; 2]] {
        &self.vertices
    }

    /// The segments added so far (before normalisation).
    pub fn segments(&self) -> &[Segment] {
        &self.segments
    }

    /// The region seeds.
    pub fn seeds(&self) -> &[RegionSeed] {
        &self.seeds
    }

    /// Adds (or finds) a vertex and returns its index. Vertices within the snapping tolerance are
    /// merged by rounding to a grid of that pitch.
    pub fn add_vertex(&mut self, point: [f64; 2]) -> Result<usize, FemError> {
        if !(point[0].is_finite() && point[1].is_finite()) {
            return Err(FemError::field(
                "vertices",
                format!("mesher: vertex ({}, {}) is not finite", point[0], point[1]),
            ));
        }
        let key =
            ((point[0] / self.snap_m).round() as i64, (point[1] / self.snap_m).round() as i64);
        if let Some(&index) = self.lookup.get(&key) {
            return Ok(index);
        }
        self.vertices.push(point);
        self.lookup.insert(key, self.vertices.len() - 1);
        Ok(self.vertices.len() - 1)
    }

    /// Adds a segment between two points (vertices are added or found).
    pub fn add_segment(
        &mut self,
        a: [f64; 2],
        b: [f64; 2],
        tag: Option<u32>,
    ) -> Result<(), FemError> {
        let ia = self.add_vertex(a)?;
        let ib = self.add_vertex(b)?;
        if ia == ib {
            return Err(FemError::field(
                "segments",
                format!(
                    "mesher: segment from ({}, {}) to ({}, {}) has zero length",
                    a[0], a[1], b[0], b[1]
                ),
            ));
        }
        self.segments.push(Segment { a: ia, b: ib, tag });
        Ok(())
    }

    /// Adds a closed polygon (its edges become untagged constraints).
    pub fn add_polygon(&mut self, points: &[[f64; 2]]) -> Result<(), FemError> {
        if points.len() < 3 {
            return Err(FemError::field(
                "polygon",
                format!("mesher: a polygon needs at least 3 points, got {}", points.len()),
            ));
        }
        for i in 0..points.len() {
            self.add_segment(points[i], points[(i + 1) % points.len()], None)?;
        }
        Ok(())
    }

    /// Adds the boundary of the axis-aligned rectangle `[r0, r1] x [z0, z1]` (untagged).
    pub fn add_rectangle(&mut self, r0: f64, r1: f64, z0: f64, z1: f64) -> Result<(), FemError> {
        self.add_polygon(&[[r0, z0], [r1, z0], [r1, z1], [r0, z1]])
    }

    /// Adds a region seed.
    pub fn add_seed(&mut self, point: [f64; 2], tag: u32) {
        self.seeds.push(RegionSeed { point, tag });
    }

    /// Merges, splits and checks the segments (see the module docs).
    ///
    /// Cost: O(S·V) for the T-junction split and O(S²) (bounding-box pruned) for the crossing check,
    /// where S and V are the input segment and vertex counts: the input graph of a brake has a few
    /// hundred segments; the mesh itself is generated later and is not touched here.
    pub fn normalized(&self) -> Result<NormalizedPslg, FemError> {
        let tol = self.snap_m;
        let mut pieces: HashMap<(usize, usize), Option<u32>> = HashMap::new();
        let mut order: Vec<(usize, usize)> = Vec::new();
        for seg in &self.segments {
            let pa = self.vertices[seg.a];
            let pb = self.vertices[seg.b];
            let d = [pb[0] - pa[0], pb[1] - pa[1]];
            let len2 = d[0] * d[0] + d[1] * d[1];
            let len = len2.sqrt();
            let mut inner: Vec<(f64, usize)> = Vec::new();
            for (iv, pv) in self.vertices.iter().enumerate() {
                if iv == seg.a || iv == seg.b {
                    continue;
                }
                let w = [pv[0] - pa[0], pv[1] - pa[1]];
                let t = (w[0] * d[0] + w[1] * d[1]) / len2;
                if t * len <= tol || (1.0 - t) * len <= tol {
                    continue;
                }
                let dist = (w[0] * d[1] - w[1] * d[0]).abs() / len;
                if dist <= tol {
                    inner.push((t, iv));
                }
            }
            inner.sort_by(|x, y| x.0.total_cmp(&y.0));
            let mut chain = Vec::with_capacity(inner.len() + 2);
            chain.push(seg.a);
            chain.extend(inner.iter().map(|&(_, iv)| iv));
            chain.push(seg.b);
            for pair in chain.windows(2) {
                let key = (pair[0].min(pair[1]), pair[0].max(pair[1]));
                match pieces.get_mut(&key) {
                    None => {
                        pieces.insert(key, seg.tag);
                        order.push(key);
                    }
                    Some(existing) => match (*existing, seg.tag) {
                        (None, Some(t)) => *existing = Some(t),
                        (Some(t0), Some(t1)) if t0 != t1 => {
                            let p = self.vertices[key.0];
                            let q = self.vertices[key.1];
                            return Err(FemError::field(
                                "segments",
                                format!(
                                    "mesher: the segment ({}, {})-({}, {}) is given two different tags, {t0} and {t1}",
                                    p[0], p[1], q[0], q[1]
                                ),
                            ));
                        }
                        _ => {}
                    },
                }
            }
        }
        let segments: Vec<Segment> =
            order.iter().map(|&(a, b)| Segment { a, b, tag: pieces[&(a, b)] }).collect();
        check_no_crossings(&self.vertices, &segments, tol)?;
        Ok(NormalizedPslg { vertices: self.vertices.clone(), segments, seeds: self.seeds.clone() })
    }
}

/// Rejects segments whose interiors cross (a crossing would need an intersection vertex the caller
/// did not ask for) or overlap collinearly without sharing vertices.
fn check_no_crossings(
    vertices: &[[f64; 2]],
    segments: &[Segment],
    tol: f64,
) -> Result<(), FemError> {
    let boxes: Vec<[f64; 4]> = segments
        .iter()
        .map(|s| {
            let (p, q) = (vertices[s.a], vertices[s.b]);
            [p[0].min(q[0]), p[0].max(q[0]), p[1].min(q[1]), p[1].max(q[1])]
        })
        .collect();
    let mut by_rmin: Vec<usize> = (0..segments.len()).collect();
    by_rmin.sort_by(|&i, &j| boxes[i][0].total_cmp(&boxes[j][0]));
    for (k, &i) in by_rmin.iter().enumerate() {
        for &j in &by_rmin[k + 1..] {
            if boxes[j][0] > boxes[i][1] + tol {
                break;
            }
            if boxes[j][2] > boxes[i][3] + tol || boxes[i][2] > boxes[j][3] + tol {
                continue;
            }
            let (si, sj) = (segments[i], segments[j]);
            let shared = si.a == sj.a || si.a == sj.b || si.b == sj.a || si.b == sj.b;
            if shared {
                continue;
            }
            if segments_intersect(vertices[si.a], vertices[si.b], vertices[sj.a], vertices[sj.b]) {
                let (p, q, u, v) = (vertices[si.a], vertices[si.b], vertices[sj.a], vertices[sj.b]);
                return Err(FemError::field(
                    "segments",
                    format!(
                        "mesher: segments ({}, {})-({}, {}) and ({}, {})-({}, {}) cross; split them at their \
                     intersection or move one of them",
                        p[0], p[1], q[0], q[1], u[0], u[1], v[0], v[1]
                    ),
                ));
            }
        }
    }
    Ok(())
}

fn orient(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> f64 {
    (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
}

/// True when the closed segments pq and uv (which share no endpoint) touch or cross.
fn segments_intersect(p: [f64; 2], q: [f64; 2], u: [f64; 2], v: [f64; 2]) -> bool {
    let d1 = orient(u, v, p);
    let d2 = orient(u, v, q);
    let d3 = orient(p, q, u);
    let d4 = orient(p, q, v);
    if ((d1 > 0.0 && d2 < 0.0) || (d1 < 0.0 && d2 > 0.0))
        && ((d3 > 0.0 && d4 < 0.0) || (d3 < 0.0 && d4 > 0.0))
    {
        return true;
    }
    let on = |a: [f64; 2], b: [f64; 2], c: [f64; 2], o: f64| {
        o.abs() <= f64::EPSILON * 16.0 * ((b[0] - a[0]).abs() + (b[1] - a[1]).abs()).powi(2)
            && c[0] >= a[0].min(b[0])
            && c[0] <= a[0].max(b[0])
            && c[1] >= a[1].min(b[1])
            && c[1] <= a[1].max(b[1])
    };
    on(u, v, p, d1) || on(u, v, q, d2) || on(p, q, u, d3) || on(p, q, v, d4)
}

#[cfg(test)]
mod tests {
    use super::*;
    use mrbrake_error::Kind as _;

    #[test]
    fn neighbouring_rectangles_share_split_edges() {
        let mut g = Pslg::new();
        g.add_rectangle(0.0, 2.0, 0.0, 1.0).unwrap();
        g.add_rectangle(0.0, 1.0, 1.0, 2.0).unwrap();
        let n = g.normalized().unwrap();
        // 4 edges of the lower rectangle, with its top split at (1, 1): 5; the upper adds 3 more.
        assert_eq!(n.segments.len(), 8);
    }

    #[test]
    fn crossing_segments_are_an_input_error() {
        let mut g = Pslg::new();
        g.add_segment([0.0, 0.0], [1.0, 1.0], None).unwrap();
        g.add_segment([0.0, 1.0], [1.0, 0.0], None).unwrap();
        let err = g.normalized().unwrap_err();
        assert!(err.is_input_error());
        assert!(err.to_string().contains("cross"));
    }

    #[test]
    fn conflicting_tags_are_an_input_error() {
        let mut g = Pslg::new();
        g.add_segment([0.0, 0.0], [1.0, 0.0], Some(1)).unwrap();
        g.add_segment([0.0, 0.0], [2.0, 0.0], Some(2)).unwrap();
        assert!(g.normalized().unwrap_err().to_string().contains("two different tags"));
    }

    #[test]
    fn tag_survives_overlap_with_untagged_rectangle_edge() {
        let mut g = Pslg::new();
        g.add_rectangle(0.0, 1.0, 0.0, 1.0).unwrap();
        g.add_segment([0.0, 0.0], [0.0, 1.0], Some(7)).unwrap();
        let n = g.normalized().unwrap();
        assert_eq!(n.segments.iter().filter(|s| s.tag == Some(7)).count(), 1);
        assert_eq!(n.segments.len(), 4);
    }
}
