//! Gmsh reader: the same geometry saved as MSH 2.2 and 4.1 (fixtures made by `gmsh` from
//! `fixtures/two_regions.geo`) reads to the same mesh; malformed files give errors with line numbers.

use std::path::PathBuf;

use mrbrake_fem::FemError;
use mrbrake_fem::gmsh::{parse_msh, read_msh, to_msh22};

fn fixture(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures").join(name)
}

#[test]
fn msh22_and_msh41_read_the_same_mesh() {
    let v2 = read_msh(&fixture("two_regions_v22.msh"), 1e-3).unwrap();
    let v4 = read_msh(&fixture("two_regions_v41.msh"), 1e-3).unwrap();
    for m in [&v2.mesh, &v4.mesh] {
        assert!(m.validate().is_ok());
        assert_eq!(m.region_tags(), vec![1, 2]);
        assert_eq!(m.boundary_tags(), vec![10, 11, 12, 13]);
        // Areas in m²: 10 mm × 5 mm and 10 mm × 3 mm.
        assert!((m.region_area(1) - 50e-6).abs() < 1e-15);
        assert!((m.region_area(2) - 30e-6).abs() < 1e-15);
        // Axis nodes lie on the axis curve.
        assert_eq!(m.boundary_nodes(10), m.axis_nodes());
    }
    assert_eq!(v2.mesh.nodes.len(), v4.mesh.nodes.len());
    assert_eq!(v2.mesh.triangles.len(), v4.mesh.triangles.len());
    assert_eq!(v4.physical_tag(2, "iron"), Some(1));
    assert_eq!(v2.physical_tag(1, "outer"), Some(11));
}

#[test]
fn written_msh22_round_trips() {
    let v4 = read_msh(&fixture("two_regions_v41.msh"), 1e-3).unwrap();
    let text = to_msh22(&v4.mesh, 1e-3);
    let back = parse_msh(&text, "roundtrip.msh", 1e-3).unwrap();
    assert_eq!(back.mesh.triangles.len(), v4.mesh.triangles.len());
    assert!((back.mesh.region_area(1) - v4.mesh.region_area(1)).abs() < 1e-15);
}

fn parse_error(text: &str) -> (usize, String) {
    match parse_msh(text, "bad.msh", 1.0) {
        Err(FemError::Parse { line, message, .. }) => (line, message),
        other => panic!("expected a parse error, got {other:?}"),
    }
}

#[test]
fn truncated_file_reports_the_last_line_and_section() {
    let text = std::fs::read_to_string(fixture("two_regions_v22.msh")).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    let cut = lines[..lines.len() / 2].join("\n");
    let (line, message) = parse_error(&cut);
    assert_eq!(line, lines.len() / 2);
    assert!(message.contains("ends early"), "{message}");
    let err = parse_msh(&cut, "bad.msh", 1.0).unwrap_err();
    assert!(err.is_input_error());
    assert!(err.to_string().starts_with("bad.msh:"));
}

#[test]
fn malformed_lines_are_named() {
    let text = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n2\n1 0 0 0\n2 x 0 0\n$EndNodes\n";
    let (line, message) = parse_error(text);
    assert_eq!(line, 7);
    assert!(message.contains("coordinate x"), "{message}");

    let text = "$MeshFormat\n3.0 0 8\n$EndMeshFormat\n";
    let (line, message) = parse_error(text);
    assert_eq!(line, 2);
    assert!(message.contains("unsupported MSH version"), "{message}");

    let text = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n3\n1 0 0 0\n2 1 0 0\n3 0 1 0\n$EndNodes\n$Elements\n1\n1 2 2 0 5 1 2 3\n$EndElements\n";
    let (line, message) = parse_error(text);
    assert_eq!(line, 12);
    assert!(message.contains("no physical group"), "{message}");

    let text = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n3\n1 0 0 0\n2 1 0 0\n3 0 1 0\n$EndNodes\n$Elements\n1\n1 2 2 7 5 1 2 9\n$EndElements\n";
    let (line, message) = parse_error(text);
    assert_eq!(line, 12);
    assert!(message.contains("node 9"), "{message}");

    let text = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n1\n1 0 0 0.5\n$EndNodes\n";
    let (line, message) = parse_error(text);
    assert_eq!(line, 6);
    assert!(message.contains("z = 0"), "{message}");
}

#[test]
fn negative_radius_is_an_input_error() {
    let text = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n3\n1 -1 0 0\n2 1 0 0\n3 0 1 0\n$EndNodes\n$Elements\n1\n1 2 2 7 5 1 2 3\n$EndElements\n";
    let err = parse_msh(text, "neg.msh", 1.0).unwrap_err();
    assert!(err.is_input_error());
    assert!(err.to_string().contains("r >= 0"), "{err}");
}
