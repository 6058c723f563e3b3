//! Issue 18, classes 2 and 3: geometry that would explode the mesh or break the mesher is an input
//! error naming the spec field (file and line) and the smallest size the mesher resolves at that
//! `--mesh` level, found before any meshing; the mesher's budget bounds what is left.

use std::time::Instant;

use mrbrake_design::analysis::{AnalysisOptions, AnalysisRequest};
use mrbrake_design::mesh_build::{self, MAX_EDGE_RATIO, MeshLevel};
use mrbrake_design::spec::BrakeSpec;
use mrbrake_error::Kind as _;

fn example_text(name: &str) -> String {
    let path =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/specs").join(name);
    std::fs::read_to_string(path).unwrap()
}

fn edited(name: &str, from: &str, to: &str) -> BrakeSpec {
    let text = example_text(name);
    assert!(text.contains(from), "test edit '{from}' not found");
    BrakeSpec::from_toml_str(&text.replacen(from, to, 1), "edited.toml").unwrap()
}

/// The error of an analysis at `level`, which must come back at once (no meshing).
fn refused(spec: &BrakeSpec, level: MeshLevel) -> String {
    let start = Instant::now();
    let options = AnalysisOptions { mesh: level, ..AnalysisOptions::default() };
    let e = AnalysisRequest::of(spec).options(options).run().unwrap_err();
    assert!(e.is_input_error(), "{e}");
    assert!(start.elapsed().as_secs_f64() < 5.0, "refused only after {:?}", start.elapsed());
    e.to_string()
}

#[test]
fn too_thin_fields_name_the_field_the_file_and_the_resolvable_size() {
    let cases = [
        (
            "drum.toml",
            "end_plate_thickness = \"5mm\"",
            "end_plate_thickness = \"0.5um\"",
            "housing.end_plate_thickness",
        ),
        ("single-disc.toml", "gap = \"0.5mm\"", "gap = \"10um\"", "disc.gap"),
        ("drum.toml", "gap = \"0.5mm\"", "gap = \"1um\"", "drum.gap"),
        // Class 3: these reached the mesher as "segment has zero length" / "segments cross".
        (
            "drum.toml",
            "case_thickness = \"3mm\"",
            "case_thickness = \"1e-9mm\"",
            "housing.case_thickness",
        ),
        ("drum.toml", "gap = \"0.5mm\"", "gap = \"1e-6mm\"", "drum.gap"),
    ];
    for (file, from, to, field) in cases {
        let spec = edited(file, from, to);
        for level in [MeshLevel::Coarse, MeshLevel::Default, MeshLevel::Fine] {
            let e = refused(&spec, level);
            assert!(e.contains("edited.toml:") && e.contains(field), "{to}: {e}");
            assert!(e.contains("too thin for the mesh") && e.contains(level.name()), "{e}");
        }
    }
}

/// The limit is where the documentation says: a gap just above cells × (largest edge / ratio)
/// meshes, just below it is refused.
#[test]
fn the_resolvable_size_is_the_documented_one() {
    let spec = edited("drum.toml", "gap = \"0.5mm\"", "gap = \"0.5mm\"");
    let geometry = spec.validate().unwrap().geometry;
    let settings = MeshLevel::Coarse.settings(geometry.device.r1);
    let limit = settings.max_edge_m / MAX_EDGE_RATIO * settings.gap_cells_across;
    let below = format!("gap = \"{}um\"", (limit * 0.9e6).round());
    let above = format!("gap = \"{}um\"", (limit * 1.1e6).round());
    for (text, ok) in [(below, false), (above, true)] {
        let spec = edited("drum.toml", "gap = \"0.5mm\"", &text);
        let validated = spec.validate().unwrap();
        let check = mesh_build::check_resolvable(&spec, &validated.geometry, MeshLevel::Coarse);
        assert_eq!(check.is_ok(), ok, "{text}: {check:?}");
    }
}
