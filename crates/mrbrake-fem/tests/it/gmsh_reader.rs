//! Gmsh reader: the same geometry saved as MSH 2.2 and 4.1 (fixtures made by `gmsh` from
//! `fixtures/two_regions.geo`) reads to the same mesh; malformed files give errors with line numbers.

use mrbrake_error::Kind as _;
use std::path::PathBuf;

use mrbrake_fem::FemError;
use mrbrake_fem::mesh::gmsh::{parse_msh, read_msh, to_msh22};

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

/// Second-order meshes (`gmsh -order 2`): 6-node triangles (type 9) and 3-node lines (type 8) are
/// read by their corner nodes, and the mid-side nodes are dropped (the solver's P2 space puts its
/// edge DOFs at the midpoints of the straight edges).
#[test]
fn second_order_elements_are_read_by_their_corners() {
    // Unit square split along (0,0)-(1,1); mid-side nodes 5-9; the axis r = 0 is a 3-node line.
    let nodes = "9\n1 0 0 0\n2 1 0 0\n3 1 1 0\n4 0 1 0\n5 0.5 0 0\n6 1 0.5 0\n7 0.5 0.5 0\n8 0.5 1 0\n9 0 0.5 0\n";
    let v2 = format!(
        "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n{nodes}$EndNodes\n$Elements\n3\n\
         1 8 2 10 1 4 1 9\n2 9 2 7 1 1 2 3 5 6 7\n3 9 2 7 1 1 3 4 7 8 9\n$EndElements\n"
    );
    let v4_nodes: String = (1..=9)
        .map(|k| {
            let line = nodes.lines().nth(k).unwrap();
            let xyz: Vec<&str> = line.split_whitespace().skip(1).collect();
            format!("0 {k} 0 1\n{k}\n{}\n", xyz.join(" "))
        })
        .collect();
    let v4 = format!(
        "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Entities\n0 1 1 0\n\
         1 0 0 0 0 1 0 1 10 0\n1 0 0 0 1 1 0 1 7 0\n$EndEntities\n\
         $Nodes\n9 9 1 9\n{v4_nodes}$EndNodes\n$Elements\n2 3 1 3\n\
         1 1 8 1\n1 4 1 9\n2 1 9 2\n2 1 2 3 5 6 7\n3 1 3 4 7 8 9\n$EndElements\n"
    );
    for (name, text) in [("order2_v22.msh", v2), ("order2_v41.msh", v4)] {
        let m = parse_msh(&text, name, 1.0).unwrap_or_else(|e| panic!("{name}: {e}")).mesh;
        assert_eq!(m.nodes.len(), 4, "{name}: mid-side nodes are dropped");
        assert_eq!(m.triangles.len(), 2, "{name}");
        assert!((m.region_area(7) - 1.0).abs() < 1e-15, "{name}");
        assert_eq!(m.edges, vec![[3, 0]], "{name}: the line joins its end nodes");
        assert_eq!(m.edge_tags, vec![10], "{name}");
        assert_eq!(m.boundary_nodes(10), m.axis_nodes(), "{name}");
    }
}

/// The section structure: each missing section is named (at line 1 for the format, else at the
/// last line), unknown sections are skipped, and stray or misplaced markers are refused.
#[test]
fn missing_and_misplaced_sections_are_named() {
    let format = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n";
    let nodes = "$Nodes\n3\n1 0 0 0\n2 1 0 0\n3 0 1 0\n$EndNodes\n";
    let line = "$Elements\n1\n1 1 2 10 3 1 2\n$EndElements\n";
    let triangle = "$Elements\n1\n1 2 2 7 5 1 2 3\n$EndElements\n";
    let cases = [
        (format!("{nodes}{triangle}"), 1, "before $MeshFormat"),
        (String::new(), 1, "missing $MeshFormat section"),
        (format!("{format}{triangle}"), 7, "missing $Nodes section"),
        (format!("{format}{nodes}"), 9, "missing $Elements section"),
        (format!("{format}{nodes}{line}"), 13, "no triangles"),
        (format!("{format}$EndNodes\n"), 4, "unexpected `$EndNodes` outside its section"),
        (
            format!("{format}hello\n"),
            4,
            "expected a section header such as `$Nodes`, found `hello`",
        ),
        (format!("{format}$NodeData\n1\n"), 5, "expected `$EndNodeData`"),
        (format!("{format}$Entities\n0 0 0 0\n$EndEntities\n"), 4, "not valid in MSH version 2"),
    ];
    for (text, want_line, want_message) in cases {
        let (line, message) = parse_error(&text);
        assert_eq!(line, want_line, "{message}");
        assert!(message.contains(want_message), "{message} should contain {want_message}");
    }
    // An unknown section with its end marker is skipped; physical names are kept.
    let names = "$PhysicalNames\n1\n2 7 \"iron core\"\n$EndPhysicalNames\n";
    let skipped = "$NodeData\n1\n\"B\"\n$EndNodeData\n";
    let text = format!("{format}{names}{skipped}{nodes}{triangle}");
    let read = parse_msh(&text, "ok.msh", 1e-3).unwrap();
    assert_eq!(read.physical_tag(2, "iron core"), Some(7));
    assert_eq!(read.mesh.triangles.len(), 1);
    assert!((read.mesh.nodes[1][0] - 1e-3).abs() < 1e-18, "coordinates are scaled");
}

/// Counts in section headers are untrusted: a count the file cannot hold is refused (an input
/// error naming the line) before anything is allocated for it, in both formats.
#[test]
fn huge_header_counts_are_refused_without_allocating() {
    let v2 = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n999999999999\n1 0 0 0\n$EndNodes\n";
    let (line, message) = parse_error(v2);
    assert_eq!(line, 5);
    assert!(message.contains("999999999999") && message.contains("at most"), "{message}");
    let v2 = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n1\n1 0 0 0\n$EndNodes\n\
              $Elements\n18446744073709551615\n$EndElements\n";
    let (line, message) = parse_error(v2);
    assert_eq!(line, 9);
    assert!(message.contains("number of elements"), "{message}");

    let text = std::fs::read_to_string(fixture("two_regions_v41.msh")).unwrap();
    let nodes = text.replace("$Nodes\n15 41 1 41", "$Nodes\n15 999999999999 1 41");
    let (_, message) = parse_error(&nodes);
    assert!(message.contains("number of nodes"), "{message}");
    let block =
        text.replace("$Nodes\n15 41 1 41\n0 1 0 1", "$Nodes\n15 41 1 41\n0 1 0 99999999999");
    let (_, message) = parse_error(&block);
    assert!(message.contains("nodes in the block"), "{message}");
    let elements = text.replace("$Elements\n8 80 1 80", "$Elements\n999999999999 80 1 80");
    let (_, message) = parse_error(&elements);
    assert!(message.contains("number of entity blocks"), "{message}");
}

/// Found by the fuzzer (mrbrake-fuzz, target msh41): a physical-tag count of 1e300 on an entity
/// line overflowed the length check (a panic in debug builds); an element line with a huge tag
/// count did the same in MSH 2.2. Both are parse errors now.
#[test]
fn huge_counts_inside_lines_are_parse_errors() {
    let text = std::fs::read_to_string(fixture("two_regions_v41.msh")).unwrap();
    let entity = text.replacen("4 0 5 0 0 \n", "4 0 5 0 1e300 \n", 1);
    assert_ne!(entity, text);
    let (_, message) = parse_error(&entity);
    assert!(message.contains("physical tags"), "{message}");
    let v2 = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n1\n1 0 0 0\n$EndNodes\n\
              $Elements\n1\n1 2 18446744073709551615 1 1 1\n$EndElements\n";
    let (line, message) = parse_error(v2);
    assert_eq!(line, 10);
    assert!(message.contains("needs"), "{message}");
}

/// Issue 19: a mesh error names the file's 1-based node and element tags (and the line), not
/// the mesh's 0-based renumbered indices.
#[test]
fn mesh_errors_use_the_files_tags() {
    // Element 7's corners 11, 12, 13 are collinear; node tags start at 11.
    let text = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n4\n11 0 0 0\n12 1 0 0\n13 2 0 0\n14 0 1 0\n$EndNodes\n$Elements\n2\n6 2 2 7 5 11 12 14\n7 2 2 7 5 11 12 13\n$EndElements\n";
    let (line, message) = parse_error(text);
    assert_eq!(line, 14);
    assert!(message.contains("triangle 7") && message.contains("[11, 12, 13]"), "{message}");

    let text = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n3\n21 0 0 0\n22 1 0 0\n23 -1 1 0\n$EndNodes\n$Elements\n1\n1 2 2 7 5 21 22 23\n$EndElements\n";
    let err = parse_msh(text, "neg.msh", 1.0).unwrap_err();
    let mrbrake_fem::FemError::Input(field) = &err else { panic!("{err:?}") };
    assert_eq!((field.file.as_deref(), field.field.as_str()), (Some("neg.msh"), "nodes"));
    assert_eq!(
        (field.value.as_deref(), field.allowed.as_deref()),
        (Some("r = -1 m"), Some("r >= 0"))
    );
    assert!(err.to_string().contains("node 23"), "{err}");
}

/// Issue 19: `nan` and `inf` (which Rust parses as numbers) are refused while the nodes are read,
/// naming the file's node tag and line, in both formats; a zero-area triangle whose corners
/// coincide is named by its element tag.
#[test]
fn non_finite_coordinates_and_coinciding_corners_use_the_files_tags() {
    let elements = "$Elements\n1\n1 2 2 7 5 31 32 33\n$EndElements\n";
    for (value, shown) in [("nan", "NaN"), ("inf", "inf"), ("-inf", "-inf")] {
        let text = format!(
            "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n3\n31 0 0 0\n32 1 {value} 0\n\
             33 0 1 0\n$EndNodes\n{elements}"
        );
        let (line, message) = parse_error(&text);
        assert_eq!(line, 7, "{message}");
        assert!(
            message.contains(&format!("node 32 has a non-finite coordinate y = {shown}")),
            "{message}"
        );
    }
    let v4 = "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Entities\n0 0 1 0\n\
              1 0 0 0 1 1 0 1 5 0\n$EndEntities\n$Nodes\n1 3 41 43\n2 1 0 3\n41\n42\n43\n\
              0 0 0\nnan 0 0\n0 1 0\n$EndNodes\n";
    let (line, message) = parse_error(v4);
    assert_eq!(line, 15, "{message}");
    assert!(message.contains("node 42 has a non-finite coordinate x = NaN"), "{message}");

    // Corners 51 and 52 coincide: zero area, reported as the file's element 9 on its line.
    let text = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n4\n51 1 1 0\n52 1 1 0\n53 0 1 0\n54 2 0 0\n$EndNodes\n$Elements\n2\n8 2 2 7 5 51 54 53\n9 2 2 7 5 51 52 53\n$EndElements\n";
    let (line, message) = parse_error(text);
    assert_eq!(line, 14);
    assert!(message.contains("triangle 9") && message.contains("[51, 52, 53]"), "{message}");
    assert!(message.contains("degenerate"), "{message}");
}
