//! Validation of the mesher: exact region areas, angle bound, tags, tagged edges, size scaling.

use super::quality::{area_by_tag, min_angle_deg, triangle_points};
use super::*;
use mrbrake_error::Kind as _;

/// An L-shaped steel part, a thin gap and a coil in an air box: the shapes a brake model has.
fn sample() -> (Pslg, Vec<(u32, f64)>) {
    let mut g = Pslg::new();
    // Air box [0, 0.05] x [0, 0.04] minus the parts below, given as the outer boundary + parts.
    g.add_rectangle(0.0, 0.05, 0.0, 0.04).unwrap();
    // L-shaped steel: polygon.
    let l =
        [[0.005, 0.005], [0.025, 0.005], [0.025, 0.01], [0.01, 0.01], [0.01, 0.03], [0.005, 0.03]];
    g.add_polygon(&l).unwrap();
    // A 0.5 mm gap beside the L's vertical leg.
    g.add_rectangle(0.01, 0.0105, 0.015, 0.025).unwrap();
    // A coil.
    g.add_rectangle(0.015, 0.025, 0.015, 0.025).unwrap();
    g.add_segment([0.0, 0.0], [0.0, 0.04], Some(1)).unwrap();
    g.add_segment([0.01, 0.015], [0.01, 0.025], Some(20)).unwrap();
    g.add_seed([0.007, 0.02], 3);
    g.add_seed([0.01025, 0.02], 4);
    g.add_seed([0.02, 0.02], 5);
    g.add_seed([0.04, 0.035], 6);
    let a_l = 0.02 * 0.005 + 0.005 * 0.02;
    let a_gap = 0.0005 * 0.01;
    let a_coil = 0.01 * 0.01;
    let a_air = 0.05 * 0.04 - a_l - a_gap - a_coil;
    (g, vec![(3, a_l), (4, a_gap), (5, a_coil), (6, a_air)])
}

fn size(h_max: f64) -> SizeField {
    SizeField::uniform(h_max).with_region(4, h_max / 16.0)
}

#[test]
fn region_areas_are_exact_and_tags_complete() {
    let (g, areas) = sample();
    let mesh = triangulate(&g, &size(0.004), &MeshOptions::default()).unwrap();
    let got = area_by_tag(&mesh);
    for (tag, expected) in areas {
        let a = got[&tag];
        assert!((a - expected).abs() <= 1e-12 * expected.max(1e-9), "tag {tag}: {a} vs {expected}");
    }
    assert_eq!(mesh.triangles.len(), mesh.triangle_tags.len());
    for t in 0..mesh.triangles.len() {
        let [a, b, c] = triangle_points(&mesh, t);
        assert!(quality::signed_area(a, b, c) > 0.0, "triangle {t} is not counter-clockwise");
    }
}

#[test]
fn min_angle_respects_the_limit() {
    let (g, _) = sample();
    let options = MeshOptions { min_angle_deg: 28.0, ..MeshOptions::default() };
    let mesh = triangulate(&g, &size(0.004), &options).unwrap();
    let worst = (0..mesh.triangles.len())
        .map(|t| min_angle_deg(triangle_points(&mesh, t)))
        .fold(f64::INFINITY, f64::min);
    // All input angles are 90° or 180°, so no exception applies; allow round-off.
    assert!(worst >= 28.0 - 1e-6, "smallest angle {worst}°");
}

#[test]
fn no_node_inside_a_region_of_another_tag() {
    let (g, _) = sample();
    let mesh = triangulate(&g, &size(0.004), &MeshOptions::default()).unwrap();
    // Every triangle's centroid lies in the region its tag says (regions known analytically).
    let region_of = |p: [f64; 2]| -> u32 {
        let in_rect =
            |r0: f64, r1: f64, z0: f64, z1: f64| p[0] > r0 && p[0] < r1 && p[1] > z0 && p[1] < z1;
        if in_rect(0.005, 0.025, 0.005, 0.01) || in_rect(0.005, 0.01, 0.01, 0.03) {
            3
        } else if in_rect(0.01, 0.0105, 0.015, 0.025) {
            4
        } else if in_rect(0.015, 0.025, 0.015, 0.025) {
            5
        } else {
            6
        }
    };
    for (t, tag) in mesh.triangle_tags.iter().enumerate() {
        let [a, b, c] = triangle_points(&mesh, t);
        let centroid = [(a[0] + b[0] + c[0]) / 3.0, (a[1] + b[1] + c[1]) / 3.0];
        assert_eq!(region_of(centroid), *tag, "triangle {t} at {centroid:?}");
    }
}

#[test]
fn tagged_segments_are_covered_by_tagged_edges() {
    let (g, _) = sample();
    let mesh = triangulate(&g, &size(0.004), &MeshOptions::default()).unwrap();
    let length = |tag: u32| -> f64 {
        mesh.edges
            .iter()
            .zip(&mesh.edge_tags)
            .filter(|(_, t)| **t == tag)
            .map(|(e, _)| {
                let (p, q) = (mesh.nodes[e[0]], mesh.nodes[e[1]]);
                ((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2)).sqrt()
            })
            .sum()
    };
    assert!((length(1) - 0.04).abs() < 1e-12, "axis length {}", length(1));
    assert!((length(20) - 0.01).abs() < 1e-12, "gap wall length {}", length(20));
    for (e, t) in mesh.edges.iter().zip(&mesh.edge_tags) {
        let (p, q) = (mesh.nodes[e[0]], mesh.nodes[e[1]]);
        match t {
            1 => assert!(p[0].abs() < 1e-15 && q[0].abs() < 1e-15),
            20 => assert!((p[0] - 0.01).abs() < 1e-15 && (q[0] - 0.01).abs() < 1e-15),
            _ => panic!("unexpected tag {t}"),
        }
    }
}

#[test]
fn thin_gap_gets_its_target_size() {
    let (g, _) = sample();
    let mesh = triangulate(&g, &size(0.004), &MeshOptions::default()).unwrap();
    let h_gap = 0.004 / 16.0;
    let max_area = 3f64.sqrt() / 4.0 * h_gap * h_gap;
    let mut longest = 0.0f64;
    for (t, tag) in mesh.triangle_tags.iter().enumerate() {
        if *tag == 4 {
            let p = triangle_points(&mesh, t);
            let area = quality::signed_area(p[0], p[1], p[2]);
            assert!(area <= max_area * (1.0 + 1e-6), "gap triangle area {area} > {max_area}");
            for i in 0..3 {
                let (a, b) = (p[i], p[(i + 1) % 3]);
                longest = longest.max(((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2)).sqrt());
            }
        }
    }
    // With the 28° bound, an area-limited triangle has edges below ~2 h.
    assert!(longest <= 2.0 * h_gap, "longest gap edge {longest} vs h {h_gap}");
}

#[test]
fn node_count_grows_about_fourfold_when_size_halves() {
    let mut g = Pslg::new();
    g.add_rectangle(0.0, 0.04, 0.0, 0.03).unwrap();
    g.add_seed([0.01, 0.01], 1);
    let n1 =
        triangulate(&g, &SizeField::uniform(0.002), &MeshOptions::default()).unwrap().nodes.len();
    let n2 =
        triangulate(&g, &SizeField::uniform(0.001), &MeshOptions::default()).unwrap().nodes.len();
    let ratio = n2 as f64 / n1 as f64;
    assert!((3.2..=4.8).contains(&ratio), "nodes {n1} -> {n2}, ratio {ratio}");
}

#[test]
fn missing_seed_and_open_region_are_input_errors() {
    let mut g = Pslg::new();
    g.add_rectangle(0.0, 1.0, 0.0, 1.0).unwrap();
    g.add_rectangle(0.2, 0.4, 0.2, 0.4).unwrap();
    g.add_seed([0.8, 0.8], 1);
    let err = triangulate(&g, &SizeField::uniform(0.2), &MeshOptions::default()).unwrap_err();
    assert!(err.is_input_error() && err.to_string().contains("no region seed"), "{err}");
    g.add_seed([0.3, 0.3], 2);
    assert!(triangulate(&g, &SizeField::uniform(0.2), &MeshOptions::default()).is_ok());
    let mut h = Pslg::new();
    h.add_rectangle(0.0, 1.0, 0.0, 1.0).unwrap();
    h.add_seed([2.0, 2.0], 1);
    assert!(
        triangulate(&h, &SizeField::uniform(0.2), &MeshOptions::default())
            .unwrap_err()
            .is_input_error()
    );
}

mod properties {
    use proptest::prelude::*;

    use super::super::quality::{area_by_tag, min_angle_deg, triangle_points};
    use super::super::*;

    proptest! {
        #![proptest_config(ProptestConfig { cases: 24, ..ProptestConfig::default() })]

        /// Any grid of rectangles (random column widths and row heights, one region per cell, one
        /// random cell refined 8×) meshes with exact cell areas and the angle bound.
        #[test]
        fn random_rectangle_grids_mesh_exactly(
            widths in proptest::collection::vec(0.2f64..3.0, 1..4),
            heights in proptest::collection::vec(0.05f64..3.0, 1..4),
            fine_pick in 0usize..16,
        ) {
            let rs: Vec<f64> = std::iter::once(0.0).chain(widths.iter().scan(0.0, |s, w| { *s += w; Some(*s) })).collect();
            let zs: Vec<f64> = std::iter::once(0.0).chain(heights.iter().scan(0.0, |s, h| { *s += h; Some(*s) })).collect();
            let mut g = Pslg::new();
            let mut expected = Vec::new();
            let mut tag = 0;
            for i in 0..widths.len() {
                for j in 0..heights.len() {
                    tag += 1;
                    g.add_rectangle(rs[i], rs[i + 1], zs[j], zs[j + 1]).unwrap();
                    g.add_seed([0.5 * (rs[i] + rs[i + 1]), 0.5 * (zs[j] + zs[j + 1])], tag);
                    expected.push((tag, widths[i] * heights[j]));
                }
            }
            let fine_tag = (fine_pick % expected.len()) as u32 + 1;
            let size = SizeField::uniform(0.5).with_region(fine_tag, 0.0625);
            let mesh = triangulate(&g, &size, &MeshOptions::default()).unwrap();
            let areas = area_by_tag(&mesh);
            for (tag, a) in expected {
                prop_assert!((areas[&tag] - a).abs() <= 1e-12 * a.max(1.0), "tag {} area {} vs {}", tag, areas[&tag], a);
            }
            let worst = (0..mesh.triangles.len()).map(|t| min_angle_deg(triangle_points(&mesh, t))).fold(f64::INFINITY, f64::min);
            prop_assert!(worst >= 28.0 - 1e-6, "smallest angle {}", worst);
        }
    }
}

/// Issue 18: memory stays bounded by the vertex budget whatever the size field asks for. A mesh
/// either fits the budget or the mesher stops with an input error naming it (the old path ran to
/// 5 million vertices and ~7 GB for a 0.5 µm part).
#[test]
fn the_vertex_budget_bounds_the_mesh_and_is_an_input_error() {
    let (g, _) = sample();
    let options = MeshOptions { max_vertices: 20_000, ..MeshOptions::default() };
    // A gap target of 10 nm: millions of vertices along the 10 mm gap walls.
    let size = SizeField::uniform(0.004).with_region(4, 1e-8);
    let e = triangulate(&g, &size, &options).unwrap_err();
    assert!(e.is_input_error(), "{e}");
    assert!(e.to_string().contains("budget of 20000 vertices"), "{e}");
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig::with_cases(12))]
    /// Whatever the gap size asked for, the result has at most `max_vertices` vertices, or is
    /// the budget's input error.
    #[test]
    fn meshes_never_exceed_the_vertex_budget(log_gap in -9.0f64..-3.5, budget in 2_000usize..20_000) {
        let (g, _) = sample();
        let options = MeshOptions { max_vertices: budget, ..MeshOptions::default() };
        let size = SizeField::uniform(0.004).with_region(4, 10f64.powf(log_gap));
        match triangulate(&g, &size, &options) {
            Ok(mesh) => proptest::prop_assert!(mesh.nodes.len() <= budget),
            Err(e) => proptest::prop_assert!(e.is_input_error() && e.to_string().contains("budget"), "{}", e),
        }
    }
}

/// CI's proptest found a 23.6° triangle at a 90° corner of a rectangle grid: spade skips a skinny
/// triangle whose shortest edge joins two of its own splits of segments that meet at a corner, as
/// if the input angle there were small. The mesher now refines such triangles in a further pass.
#[test]
fn skinny_triangles_at_right_angled_corners_are_refined() {
    let widths = [1.6566443529105148, 0.321099820139515, 1.8578536176427234];
    let heights = [0.857606100962271, 0.20414773544985657, 2.6503750629638314];
    let edges = |sizes: &[f64]| -> Vec<f64> {
        std::iter::once(0.0)
            .chain(sizes.iter().scan(0.0, |s, w| {
                *s += w;
                Some(*s)
            }))
            .collect()
    };
    let (rs, zs) = (edges(&widths), edges(&heights));
    let mut g = Pslg::new();
    for i in 0..3 {
        for j in 0..3 {
            g.add_rectangle(rs[i], rs[i + 1], zs[j], zs[j + 1]).unwrap();
            g.add_seed(
                [0.5 * (rs[i] + rs[i + 1]), 0.5 * (zs[j] + zs[j + 1])],
                (3 * i + j + 1) as u32,
            );
        }
    }
    let size = SizeField::uniform(0.5).with_region(5, 0.0625);
    let mesh = triangulate(&g, &size, &MeshOptions::default()).unwrap();
    let worst = (0..mesh.triangles.len())
        .map(|t| super::quality::min_angle_deg(super::quality::triangle_points(&mesh, t)))
        .fold(f64::INFINITY, f64::min);
    assert!(worst >= 28.0 - 1e-6, "smallest angle {worst}");
}
