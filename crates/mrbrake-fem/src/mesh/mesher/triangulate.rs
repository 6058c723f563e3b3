//! The meshing driver: constrained Delaunay triangulation, region flood fill, graded Delaunay
//! refinement, and conversion to a [`Mesh`].
//!
//! Algorithm:
//! 1. Normalise the PSLG and triangulate it (spade's `ConstrainedDelaunayTriangulation`, bulk load).
//! 2. Flood-fill region tags from the seeds across non-constraint edges; faces reachable from
//!    outside the outer boundary are excluded. This tells which regions each segment bounds.
//! 3. Subdivide every segment with steps equal to the local target size h(x) (walking along the
//!    segment), and triangulate again: boundary vertices now carry the grading.
//! 4. Repeat: Ruppert/Chew Delaunay refinement with the angle limit (spade `refine`, which also
//!    splits encroached constraint segments); flood fill; insert the centroid of every triangle whose
//!    area exceeds that of the equilateral triangle of edge h at its centroid. Stop after a refinement pass that leaves no triangle
//!    too large. The final step is always a quality refinement, so the angle bound holds.
//! 5. Extract nodes, counter-clockwise triangles with their tags, and the tagged edges found by
//!    walking the constraint edges along each tagged input segment.

use std::collections::VecDeque;

use spade::handles::{FixedFaceHandle, FixedVertexHandle, InnerTag};
use spade::{
    AngleLimit, ConstrainedDelaunayTriangulation, Point2, PositionInTriangulation,
    RefinementParameters, Triangulation,
};

use super::pslg::{NormalizedPslg, Pslg, RegionSeed};
use super::size_field::{FineRegion, ResolvedSizeField, SizeField};
use crate::FemError;
use crate::mesh::Mesh;
use mrbrake_error::FieldError;

type Cdt = ConstrainedDelaunayTriangulation<Point2<f64>>;

/// Quality and budget options of the mesher.
#[derive(Debug, Clone, PartialEq)]
pub struct MeshOptions {
    /// Smallest allowed triangle angle (degrees). Delaunay refinement guarantees it except at small
    /// input angles; above ~30° refinement may not terminate (spade caps it with a vertex budget).
    pub min_angle_deg: f64,
    /// Maximum number of size-refinement passes before giving up.
    pub max_passes: usize,
    /// Maximum number of mesh vertices before giving up (protects against a size field that asks
    /// for an absurd mesh): reaching it is an input error naming the budget, checked while the
    /// segments are subdivided and while refining, so memory stays bounded by it.
    pub max_vertices: usize,
    /// Tag given to enclosed areas that no seed reaches (`None`: such an area is an input error).
    pub default_tag: Option<u32>,
}

impl Default for MeshOptions {
    fn default() -> Self {
        Self { min_angle_deg: 28.0, max_passes: 60, max_vertices: 5_000_000, default_tag: None }
    }
}

/// Meshes a PSLG with a size field: see the module docs for the algorithm.
pub fn triangulate(pslg: &Pslg, size: &SizeField, options: &MeshOptions) -> Result<Mesh, FemError> {
    size.validate()?;
    check_angle(options.min_angle_deg)?;
    let graph = pslg.normalized()?;
    if graph.seeds.is_empty() && options.default_tag.is_none() {
        return Err(FemError::field(
            "seeds",
            "mesher: no region seed given (every region needs one)",
        ));
    }

    // Stage A: coarse CDT of the input graph, to learn which regions every segment bounds.
    let cdt_a =
        load(&graph.vertices, &graph.segments.iter().map(|s| [s.a, s.b]).collect::<Vec<_>>())?;
    let tags_a = flood_fill(&cdt_a, &graph, options.default_tag)?;
    let resolved = resolve_size_field(&cdt_a, &tags_a, &graph, size);

    // Stage B: subdivide each segment at the local size, then triangulate again.
    let (vertices_b, edges_b, tagged_b) =
        subdivide_segments(&cdt_a, &tags_a, &graph, &resolved, options.max_vertices)?;
    let mut cdt = load(&vertices_b, &edges_b)?;
    let tags = refine(&mut cdt, &graph, &resolved, options)?;
    Ok(extract(&cdt, &tags, &vertices_b, &tagged_b))
}

/// Refuses an angle limit outside the range Delaunay refinement can honour.
fn check_angle(min_angle_deg: f64) -> Result<(), FemError> {
    if min_angle_deg.is_finite() && (0.0..=34.0).contains(&min_angle_deg) {
        Ok(())
    } else {
        Err(FieldError::out_of_range("min_angle_deg", min_angle_deg, "[0, 34] degrees").into())
    }
}

/// Step 4 of the algorithm: alternates quality refinement with the insertion of the centroids of
/// the triangles larger than the size field, until a quality pass leaves none too large. Returns
/// the region of every face of the final triangulation.
fn refine(
    cdt: &mut Cdt,
    graph: &NormalizedPslg,
    resolved: &ResolvedSizeField,
    options: &MeshOptions,
) -> Result<Vec<FaceRegion>, FemError> {
    let angle = AngleLimit::from_deg(options.min_angle_deg);
    let max_area = 3f64.sqrt() / 4.0 * resolved.field.max_edge_m * resolved.field.max_edge_m;
    let mut passes = 0;
    let mut last_skinny = usize::MAX;
    loop {
        passes += 1;
        let params = RefinementParameters::<f64>::new()
            // spade's outer-face exclusion peels constraint layers even-odd (nested parts would
            // count as holes), so refine everything; faces outside the boundary are dropped later.
            .exclude_outer_faces(false)
            .with_angle_limit(angle)
            .with_max_allowed_area(max_area)
            .with_max_additional_vertices(options.max_vertices.saturating_sub(cdt.num_vertices()));
        let result = cdt.refine(params);
        if !result.refinement_complete {
            return Err(over_budget(
                options.max_vertices,
                &format!("refining for quality (pass {passes})"),
            ));
        }
        let tags = flood_fill(cdt, graph, options.default_tag)?;
        let centroids = oversized_centroids(cdt, &tags, resolved);
        if centroids.is_empty() {
            // spade skips a skinny triangle whose shortest edge joins two of its own segment
            // splits that share an input vertex, as if the input angle there were small — also
            // at a 90° corner. Its record of those splits lives for one `refine` call only, so
            // another pass refines them; stop when a pass no longer reduces their number (what
            // is left sits at truly small input angles, where no refinement can help).
            let skinny = skinny_count(cdt, &tags, options.min_angle_deg);
            if skinny == 0 || skinny >= last_skinny || passes >= options.max_passes {
                return Ok(tags);
            }
            last_skinny = skinny;
            continue;
        }
        if cdt.num_vertices() + centroids.len() > options.max_vertices {
            return Err(over_budget(options.max_vertices, "refining to the size field"));
        }
        if passes >= options.max_passes {
            return Err(FemError::Numerical(format!(
                "size refinement did not converge: {} triangles still larger than the size field after \
                 {passes} passes ({} vertices)",
                centroids.len(),
                cdt.num_vertices()
            )));
        }
        for c in centroids {
            cdt.insert(c).map_err(|e| {
                FemError::Numerical(format!(
                    "inserting a refinement point: {}",
                    coordinate_words(e)
                ))
            })?;
        }
    }
}

/// The number of region triangles whose smallest angle is below the limit (degrees).
fn skinny_count(cdt: &Cdt, tags: &[FaceRegion], min_angle_deg: f64) -> usize {
    cdt.inner_faces()
        .filter(|face| tags[face.fix().index()].region().is_some())
        .filter(|face| {
            let p = face.positions().map(|q| [q.x, q.y]);
            super::quality::min_angle_deg(p) < min_angle_deg - 1e-6
        })
        .count()
}

/// The centroids of the region triangles whose area exceeds that of the equilateral triangle of
/// edge h(centroid), in face order.
fn oversized_centroids(
    cdt: &Cdt,
    tags: &[FaceRegion],
    resolved: &ResolvedSizeField,
) -> Vec<Point2<f64>> {
    let mut centroids = Vec::new();
    for face in cdt.inner_faces() {
        let Some(tag) = tags[face.fix().index()].region() else { continue };
        let p = face.positions();
        let c = [(p[0].x + p[1].x + p[2].x) / 3.0, (p[0].y + p[1].y + p[2].y) / 3.0];
        // Size test by area, like spade's own max-area rule: a triangle is too large when its
        // area exceeds that of the equilateral triangle of edge h(centroid). (A longest-edge
        // test would over-refine: the refiner's 28°-quality triangles are not equilateral.)
        let area = 0.5
            * ((p[1].x - p[0].x) * (p[2].y - p[0].y) - (p[1].y - p[0].y) * (p[2].x - p[0].x)).abs();
        let h = resolved.at(c, Some(tag));
        if area > 3f64.sqrt() / 4.0 * h * h * (1.0 + 1e-9) {
            centroids.push(Point2::new(c[0], c[1]));
        }
    }
    centroids
}

/// Region membership of a face.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum FaceRegion {
    /// Not reached yet.
    Unset,
    /// Outside the outer boundary (reachable from the convex hull without crossing a segment).
    Outside,
    /// Inside the region with this tag.
    Tag(u32),
}

impl FaceRegion {
    fn region(self) -> Option<u32> {
        match self {
            FaceRegion::Tag(t) => Some(t),
            _ => None,
        }
    }
}

/// spade's refusal of a coordinate, in words (it prints as `Debug`, e.g. `TooSmall`).
fn coordinate_words(e: spade::InsertionError) -> String {
    match e {
        spade::InsertionError::TooSmall => format!(
            "a coordinate is nonzero but below {:e} m in magnitude",
            spade::MIN_ALLOWED_VALUE
        ),
        spade::InsertionError::TooLarge => {
            format!("a coordinate exceeds {:e} m in magnitude", spade::MAX_ALLOWED_VALUE)
        }
        spade::InsertionError::NAN => "a coordinate is not a number (NaN)".to_string(),
    }
}

fn load(vertices: &[[f64; 2]], edges: &[[usize; 2]]) -> Result<Cdt, FemError> {
    let points: Vec<Point2<f64>> = vertices.iter().map(|p| Point2::new(p[0], p[1])).collect();
    let mut conflicts = Vec::new();
    let cdt =
        Cdt::try_bulk_load_cdt(points, edges.to_vec(), |e| conflicts.push(e)).map_err(|e| {
            FemError::field(
                "segments",
                format!("mesher: the triangulation rejected the input: {}", coordinate_words(e)),
            )
        })?;
    if cdt.num_vertices() != vertices.len() {
        return Err(FemError::field(
            "vertices",
            "mesher: duplicate vertices survived normalisation",
        ));
    }
    if let Some([a, b]) = conflicts.first() {
        let (p, q) = (vertices[*a], vertices[*b]);
        return Err(FemError::field(
            "segments",
            format!(
                "mesher: segment ({}, {})-({}, {}) intersects another segment",
                p[0], p[1], q[0], q[1]
            ),
        ));
    }
    Ok(cdt)
}

/// Neighbour faces across non-constraint edges.
fn flood(
    cdt: &Cdt,
    tags: &mut [FaceRegion],
    start: FixedFaceHandle<InnerTag>,
    value: FaceRegion,
) -> Result<(), [f64; 2]> {
    let mut queue = VecDeque::from([start]);
    tags[start.index()] = value;
    while let Some(f) = queue.pop_front() {
        for edge in cdt.face(f).adjacent_edges() {
            if edge.as_undirected().is_constraint_edge() {
                continue;
            }
            let Some(next) = edge.rev().face().as_inner() else { continue };
            match tags[next.fix().index()] {
                FaceRegion::Unset => {
                    tags[next.fix().index()] = value;
                    queue.push_back(next.fix());
                }
                other if other != value => {
                    let c = next.center();
                    return Err([c.x, c.y]);
                }
                _ => {}
            }
        }
    }
    Ok(())
}

/// Step 2 of the algorithm: the region of every face. Faces reachable from the convex hull without
/// crossing a segment are outside; each seed's enclosed area takes its tag; an area no seed reaches
/// takes `default_tag`, or is an error without one.
fn flood_fill(
    cdt: &Cdt,
    graph: &NormalizedPslg,
    default_tag: Option<u32>,
) -> Result<Vec<FaceRegion>, FemError> {
    let mut tags = vec![FaceRegion::Unset; cdt.num_all_faces()];
    flood_outside(cdt, &mut tags)?;
    for seed in &graph.seeds {
        flood_seed(cdt, &mut tags, seed)?;
    }
    flood_unseeded(cdt, &mut tags, default_tag)?;
    Ok(tags)
}

/// Marks as outside the inner faces adjacent to the convex hull through a non-constraint hull
/// edge, and everything they reach.
fn flood_outside(cdt: &Cdt, tags: &mut [FaceRegion]) -> Result<(), FemError> {
    let hull_starts: Vec<_> = cdt
        .convex_hull()
        .filter(|e| !e.as_undirected().is_constraint_edge())
        .filter_map(|e| e.rev().face().as_inner().map(|f| f.fix()))
        .collect();
    for f in hull_starts {
        if tags[f.index()] == FaceRegion::Unset {
            flood(cdt, tags, f, FaceRegion::Outside).map_err(|_| {
                FemError::field("segments", "mesher: the outer boundary is not closed")
            })?;
        }
    }
    Ok(())
}

/// The face a seed point lies in: on a face, on a non-constraint edge, or on a Steiner point with
/// no constraint edge around it. `None` on a segment or outside the triangulation.
fn seed_face(cdt: &Cdt, point: [f64; 2]) -> Option<FixedFaceHandle<InnerTag>> {
    match cdt.locate(Point2::new(point[0], point[1])) {
        PositionInTriangulation::OnFace(f) => Some(f),
        PositionInTriangulation::OnEdge(e)
            if !cdt.directed_edge(e).as_undirected().is_constraint_edge() =>
        {
            cdt.directed_edge(e).face().as_inner().map(|f| f.fix())
        }
        // A seed on a Steiner point inside its region: any face around the point will do.
        PositionInTriangulation::OnVertex(v)
            if !cdt.vertex(v).out_edges().any(|e| e.as_undirected().is_constraint_edge()) =>
        {
            cdt.vertex(v).out_edges().find_map(|e| e.face().as_inner().map(|f| f.fix()))
        }
        _ => None,
    }
}

/// Gives the seed's tag to its enclosed area (nothing to do if an earlier seed of the same tag
/// already did).
fn flood_seed(cdt: &Cdt, tags: &mut [FaceRegion], seed: &RegionSeed) -> Result<(), FemError> {
    let Some(face) = seed_face(cdt, seed.point) else {
        return Err(FemError::field(
            "seeds",
            format!(
                "mesher: seed of region {} at ({}, {}) is not strictly inside a region (outside the outer \
             boundary or on a segment)",
                seed.tag, seed.point[0], seed.point[1]
            ),
        ));
    };
    match tags[face.index()] {
        FaceRegion::Unset => {}
        FaceRegion::Tag(t) if t == seed.tag => return Ok(()),
        FaceRegion::Tag(t) => {
            return Err(FemError::field(
                "seeds",
                format!(
                    "mesher: seeds of regions {t} and {} at ({}, {}) lie in the same enclosed area",
                    seed.tag, seed.point[0], seed.point[1]
                ),
            ));
        }
        FaceRegion::Outside => {
            return Err(FemError::field(
                "seeds",
                format!(
                    "mesher: seed of region {} at ({}, {}) lies outside the closed outer boundary",
                    seed.tag, seed.point[0], seed.point[1]
                ),
            ));
        }
    }
    flood(cdt, tags, face, FaceRegion::Tag(seed.tag)).map_err(|c| {
        FemError::field("seeds", format!(
            "mesher: the region of seed {} at ({}, {}) is open: it reaches another region near ({:.6}, {:.6})",
            seed.tag, seed.point[0], seed.point[1], c[0], c[1]
        ))
    })
}

/// Gives `default_tag` to every area no seed reached, or fails on the first one without it.
fn flood_unseeded(
    cdt: &Cdt,
    tags: &mut [FaceRegion],
    default_tag: Option<u32>,
) -> Result<(), FemError> {
    let unset: Vec<_> =
        cdt.fixed_inner_faces().filter(|f| tags[f.index()] == FaceRegion::Unset).collect();
    for f in unset {
        if tags[f.index()] != FaceRegion::Unset {
            continue;
        }
        match default_tag {
            Some(t) => flood(cdt, tags, f, FaceRegion::Tag(t)).map_err(|c| {
                FemError::field(
                    "segments",
                    format!("mesher: an unseeded area near ({:.6}, {:.6}) is open", c[0], c[1]),
                )
            })?,
            None => {
                let c = cdt.face(f).center();
                return Err(FemError::field(
                    "seeds",
                    format!(
                        "mesher: the enclosed area around ({:.6}, {:.6}) has no region seed",
                        c.x, c.y
                    ),
                ));
            }
        }
    }
    Ok(())
}

/// Finds the tags on both sides of every input segment and collects the boundaries of the regions
/// with a target size below the global maximum.
fn resolve_size_field(
    cdt: &Cdt,
    tags: &[FaceRegion],
    graph: &NormalizedPslg,
    size: &SizeField,
) -> ResolvedSizeField {
    let mut fine: Vec<(u32, FineRegion)> = size
        .region_edge_m
        .iter()
        .filter(|(_, h)| **h < size.max_edge_m)
        .map(|(t, h)| {
            (
                *t,
                FineRegion {
                    edge_m: *h,
                    segments: Vec::new(),
                    bbox: [f64::INFINITY, f64::NEG_INFINITY, f64::INFINITY, f64::NEG_INFINITY],
                },
            )
        })
        .collect();
    for seg in &graph.segments {
        for tag in side_tags(cdt, tags, seg.a, seg.b).into_iter().flatten() {
            if let Some((_, region)) = fine.iter_mut().find(|(t, _)| *t == tag) {
                let (p, q) = (graph.vertices[seg.a], graph.vertices[seg.b]);
                region.segments.push([p, q]);
                region.bbox = [
                    region.bbox[0].min(p[0]).min(q[0]),
                    region.bbox[1].max(p[0]).max(q[0]),
                    region.bbox[2].min(p[1]).min(q[1]),
                    region.bbox[3].max(p[1]).max(q[1]),
                ];
            }
        }
    }
    ResolvedSizeField {
        field: size.clone(),
        fine: fine.into_iter().map(|(_, r)| r).filter(|r| !r.segments.is_empty()).collect(),
    }
}

/// The region tags on the two sides of the input segment between vertices a and b.
fn side_tags(cdt: &Cdt, tags: &[FaceRegion], a: usize, b: usize) -> [Option<u32>; 2] {
    let va = FixedVertexHandle::from_index(a);
    let vb = FixedVertexHandle::from_index(b);
    match cdt.get_edge_from_neighbors(va, vb) {
        Some(e) => [e.face(), e.rev().face()]
            .map(|f| f.as_inner().and_then(|f| tags[f.fix().index()].region())),
        None => [None, None],
    }
}

/// Subdivides each input segment by walking along it with the local target size; returns the new
/// vertex list, the constraint edges, and each tagged input segment as (first, last vertex, tag).
/// More than `max_vertices` points on the segments alone is the vertex budget's input error.
#[allow(clippy::type_complexity)]
fn subdivide_segments(
    cdt: &Cdt,
    tags: &[FaceRegion],
    graph: &NormalizedPslg,
    resolved: &ResolvedSizeField,
    max_vertices: usize,
) -> Result<(Vec<[f64; 2]>, Vec<[usize; 2]>, Vec<(usize, usize, u32)>), FemError> {
    let mut vertices = graph.vertices.clone();
    let mut edges = Vec::new();
    let mut tagged = Vec::new();
    for seg in &graph.segments {
        let (p, q) = (graph.vertices[seg.a], graph.vertices[seg.b]);
        let side = side_tags(cdt, tags, seg.a, seg.b);
        let h_at =
            |x: [f64; 2]| side.iter().map(|t| resolved.at(x, *t)).fold(f64::INFINITY, f64::min);
        let len = ((q[0] - p[0]).powi(2) + (q[1] - p[1]).powi(2)).sqrt();
        // Walk with the local size, then stretch the steps so that the walk ends exactly at q.
        let mut ts = vec![0.0];
        let mut t = 0.0;
        while t < 1.0 {
            let x = [p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1])];
            let step = h_at(x) / len;
            t += step.max(1e-6);
            ts.push(t.min(1.0));
            if vertices.len() + ts.len() > max_vertices {
                return Err(over_budget(max_vertices, "subdividing the boundary segments"));
            }
        }
        // ts ends at 1.0; the last step may be a tiny remainder: merge it with the previous one.
        let n = ts.len();
        if n > 2 && ts[n - 1] - ts[n - 2] < 0.5 * (ts[n - 2] - ts[n - 3]) {
            ts.remove(n - 2);
        }
        let scale = 1.0 / ts[ts.len() - 1];
        let mut prev = seg.a;
        for &ti in &ts[1..ts.len() - 1] {
            let s = ti * scale;
            vertices.push([p[0] + s * (q[0] - p[0]), p[1] + s * (q[1] - p[1])]);
            let cur = vertices.len() - 1;
            edges.push([prev, cur]);
            prev = cur;
        }
        edges.push([prev, seg.b]);
        if let Some(tag) = seg.tag {
            tagged.push((seg.a, seg.b, tag));
        }
    }
    Ok((vertices, edges, tagged))
}

/// The vertex budget's error: an input error (the geometry and size field ask for a mesh larger
/// than allowed), naming the budget and the stage that reached it.
fn over_budget(max_vertices: usize, stage: &str) -> FemError {
    FemError::field(
        "size_field",
        format!(
            "mesher: the mesh would exceed its budget of {max_vertices} vertices (~{} triangles) while \
         {stage}: a feature is too thin for the size field, or the size field too fine; coarsen \
         it, thicken the feature, or raise the budget",
            2 * max_vertices
        ),
    )
}

fn extract(
    cdt: &Cdt,
    tags: &[FaceRegion],
    vertices: &[[f64; 2]],
    tagged: &[(usize, usize, u32)],
) -> Mesh {
    let mut node_of = vec![usize::MAX; cdt.num_vertices()];
    let mut mesh = Mesh::default();
    for face in cdt.inner_faces() {
        let Some(tag) = tags[face.fix().index()].region() else { continue };
        let vs = face.vertices();
        let mut tri = [0usize; 3];
        for (k, v) in vs.iter().enumerate() {
            let i = v.fix().index();
            if node_of[i] == usize::MAX {
                let p = v.position();
                node_of[i] = mesh.nodes.len();
                mesh.nodes.push([p.x, p.y]);
            }
            tri[k] = node_of[i];
        }
        let [a, b, c] = tri.map(|i| mesh.nodes[i]);
        if (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]) < 0.0 {
            tri.swap(1, 2);
        }
        mesh.triangles.push(tri);
        mesh.triangle_tags.push(tag);
    }
    for &(a, b, tag) in tagged {
        let (pa, pb) = (vertices[a], vertices[b]);
        let d = [pb[0] - pa[0], pb[1] - pa[1]];
        let len = (d[0] * d[0] + d[1] * d[1]).sqrt();
        let dir = [d[0] / len, d[1] / len];
        let mut cur = FixedVertexHandle::from_index(a);
        let target = FixedVertexHandle::from_index(b);
        let mut guard = 0usize;
        while cur != target && guard < cdt.num_vertices() {
            guard += 1;
            let here = cdt.vertex(cur).position();
            let t_here = (here.x - pa[0]) * dir[0] + (here.y - pa[1]) * dir[1];
            let next = cdt
                .vertex(cur)
                .out_edges()
                .filter(|e| e.as_undirected().is_constraint_edge())
                .find(|e| {
                    let to = e.to().position();
                    let w = [to.x - here.x, to.y - here.y];
                    let wl = (w[0] * w[0] + w[1] * w[1]).sqrt();
                    let along = (w[0] * dir[0] + w[1] * dir[1]) / wl;
                    let t_to = (to.x - pa[0]) * dir[0] + (to.y - pa[1]) * dir[1];
                    along > 1.0 - 1e-9 && t_to > t_here && t_to <= len * (1.0 + 1e-12)
                });
            let Some(next) = next else { break };
            let to = next.to().fix();
            let (i, j) = (node_of[cur.index()], node_of[to.index()]);
            if i != usize::MAX && j != usize::MAX {
                mesh.edges.push([i, j]);
                mesh.edge_tags.push(tag);
            }
            cur = to;
        }
    }
    mesh
}
