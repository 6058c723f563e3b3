//! Spec validation, geometry and meshing of every configuration (issue 4).

use mrbrake_design::geometry::{self, Direction, GapOrientation, PartKind};
use mrbrake_design::mesh_build::{self, MeshLevel};
use mrbrake_design::spec::{BrakeSpec, default_spec};
use mrbrake_error::Kind as _;
use mrbrake_fem::mesh::mesher::quality::area_by_tag;

fn example(name: &str) -> BrakeSpec {
    let path =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/specs").join(name);
    BrakeSpec::from_path(&path).unwrap()
}

fn with_edit(text: &str, from: &str, to: &str) -> BrakeSpec {
    assert!(text.contains(from), "test edit '{from}' not found");
    BrakeSpec::from_toml_str(&text.replacen(from, to, 1), "edited.toml").unwrap()
}

#[test]
fn default_spec_is_valid_and_matches_the_thesis_numbers() {
    let spec = default_spec();
    let warnings = spec.validate().unwrap().warnings;
    assert!(warnings.is_empty(), "{warnings:?}");
    let drum = spec.configuration.drum().unwrap();
    assert_eq!(drum.surfaces(), 4);
    // (4.5): R_3 = 25 + 3 (1 + 0.5) = 29.5 mm.
    assert!((drum.surface_radius_m(3) - 0.0295).abs() < 1e-12);
    assert_eq!(spec.turns(), 450);
}

#[test]
fn each_rule_names_its_field() {
    let text = mrbrake_design::spec::DEFAULT_SPEC_TOML;
    let cases = [
        ("gap = \"0.5mm\"", "gap = \"-0.5mm\"", "drum.gap"),
        ("outer_radius = \"40mm\"", "outer_radius = \"31mm\"", "housing.outer_radius"),
        (
            "inner_case_thickness = \"7mm\"",
            "inner_case_thickness = \"21mm\"",
            "housing.inner_case_thickness",
        ),
        ("window_width = \"10mm\"", "window_width = \"14mm\"", "coil.window_width"),
        ("turns = 450", "turns = 5000", "coil.turns"),
        ("fluid = \"mrf-122eg\"", "fluid = \"air\"", "materials.fluid"),
        (
            "diameter = \"80mm\"               # Table",
            "diameter = \"70mm\" # Table",
            "envelope.diameter",
        ),
        ("length = \"124mm\"", "length = \"50mm\"", "envelope.length"),
        ("rotating_cylinders = 2", "rotating_cylinders = 0", "drum.rotating_cylinders"),
        ("placement = \"inner\"", "placement = \"two-sided\"", "coil.placement"),
        (
            "thickness = \"4mm\"               # A4\n\n[envelope]",
            "thickness = \"0mm\"\n\n[envelope]",
            "spacer.thickness",
        ),
    ];
    for (from, to, field) in cases {
        let spec = with_edit(text, from, to);
        let err = spec.validate().expect_err(field);
        assert!(err.is_input_error());
        let msg = err.to_string();
        assert!(msg.contains(field), "expected '{field}' in: {msg}");
    }
}

#[test]
fn overcurrent_is_a_warning_not_an_error() {
    let spec = with_edit(
        mrbrake_design::spec::DEFAULT_SPEC_TOML,
        "max_current = \"2A\"",
        "max_current = \"3A\"",
    );
    let warnings = spec.validate().unwrap().warnings;
    assert!(
        warnings.iter().any(|w| w.field == "coil.max_current" && w.message.contains("rating")),
        "{warnings:?}"
    );
}

#[test]
fn unknown_fields_and_bad_units_are_input_errors() {
    let text = mrbrake_design::spec::DEFAULT_SPEC_TOML;
    let err =
        BrakeSpec::from_toml_str(&text.replacen("r0 = \"25mm\"", "r0 = \"25kg\"", 1), "x.toml")
            .unwrap_err();
    assert!(
        err.is_input_error()
            && err.to_string().contains("x.toml")
            && err.to_string().contains("r0"),
        "{err}"
    );
    let err =
        BrakeSpec::from_toml_str(&text.replacen("r0 = \"25mm\"", "r_0 = \"25mm\"", 1), "x.toml")
            .unwrap_err();
    assert!(err.to_string().contains("r_0"), "{err}");
}

#[test]
fn examples_are_valid() {
    for name in ["single-disc.toml", "multi-disc.toml", "drum.toml", "thesis-bidirectional.toml"] {
        let spec = example(name);
        spec.validate().unwrap_or_else(|e| panic!("{name}: {e}"));
    }
}

#[test]
fn bidirectional_has_two_mirrored_units_separated_by_the_spacer() {
    let g = geometry::build(&default_spec()).unwrap();
    assert_eq!(g.units, 2);
    assert_eq!(g.coils.len(), 2);
    assert_eq!(g.gaps.len(), 8);
    let spacer = g.regions.iter().find(|r| r.kind == PartKind::Spacer).unwrap().rects[0];
    let mid = 0.5 * (spacer.z0 + spacer.z1);
    for k in 0..4 {
        let a = g.gaps.iter().find(|x| x.unit == 0 && x.index_in_unit == k).unwrap();
        let b = g.gaps.iter().find(|x| x.unit == 1 && x.index_in_unit == k).unwrap();
        assert_eq!(a.direction, Direction::Clockwise);
        assert_eq!(b.direction, Direction::CounterClockwise);
        assert!((a.rect.r0 - b.rect.r0).abs() < 1e-15 && (a.rect.r1 - b.rect.r1).abs() < 1e-15);
        assert!(
            (mid - a.rect.z1 - (b.rect.z0 - mid)).abs() < 1e-12,
            "gaps not mirrored about the spacer"
        );
        assert!(a.rect.z1 < spacer.z0 && b.rect.z0 > spacer.z1);
        assert!((a.shear_radius_m - (0.025 + k as f64 * 0.0015)).abs() < 1e-12);
        assert_eq!(a.orientation, GapOrientation::Cylindrical);
    }
    // Each unit's rotating parts turn only in its own direction.
    for r in &g.regions {
        if let (Some(unit), Some(dir)) = (r.unit, r.rotates)
            && r.kind != PartKind::Shaft
        {
            assert_eq!(
                dir,
                if unit == 0 { Direction::Clockwise } else { Direction::CounterClockwise },
                "{}",
                r.name
            );
        }
    }
    assert!(g.coils[0].rect.z1 < spacer.z0 && g.coils[1].rect.z0 > spacer.z1);
}

fn check_mesh(spec: &BrakeSpec, level: MeshLevel) -> usize {
    let g = geometry::build(spec).unwrap();
    let mesh = mesh_build::mesh(&g, level).unwrap();
    let areas = area_by_tag(&mesh);
    for region in &g.regions {
        let a = areas.get(&region.tag).copied().unwrap_or(0.0);
        let expected = region.area_m2();
        assert!(
            (a - expected).abs() <= 1e-9 * expected,
            "{}: mesh area {a} vs {expected}",
            region.name
        );
    }
    for gap in &g.gaps {
        let across = mesh_build::elements_across(&mesh, gap, 5);
        assert!(
            across >= 3,
            "gap {} of unit {}: {across} elements across",
            gap.index_in_unit,
            gap.unit
        );
    }
    let axis: f64 = mesh
        .edges
        .iter()
        .zip(&mesh.edge_tags)
        .filter(|(_, t)| **t == g.axis_tag)
        .map(|(e, _)| (mesh.nodes[e[0]][1] - mesh.nodes[e[1]][1]).abs())
        .sum();
    assert!((axis - (g.domain.z1 - g.domain.z0)).abs() < 1e-12);
    mesh.nodes.len()
}

#[test]
fn every_configuration_meshes_with_resolved_gaps_and_exact_areas() {
    for name in ["single-disc.toml", "multi-disc.toml", "drum.toml", "thesis-bidirectional.toml"] {
        check_mesh(&example(name), MeshLevel::Coarse);
    }
    check_mesh(&default_spec(), MeshLevel::Default);
}

#[test]
fn two_sided_disc_has_two_coils_with_opposite_signs() {
    let text = std::fs::read_to_string(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../../examples/specs/single-disc.toml"),
    )
    .unwrap();
    let spec = with_edit(&text, "placement = \"outer\"", "placement = \"two-sided\"");
    let g = geometry::build(&spec).unwrap();
    assert_eq!(g.coils.len(), 2);
    assert!((g.coils[0].current_sign + g.coils[1].current_sign).abs() < 1e-15);
    check_mesh(&spec, MeshLevel::Coarse);
}

#[test]
fn geo_export_has_every_physical_group() {
    let g = geometry::build(&default_spec()).unwrap();
    let text =
        mrbrake_design::geo_export::to_geo(&g, &MeshLevel::Coarse.settings(g.device.r1), "test")
            .unwrap();
    for region in &g.regions {
        assert!(
            text.contains(&format!("Physical Surface(\"{}\", {})", region.name, region.tag)),
            "{}",
            region.name
        );
    }
    assert!(text.contains("Physical Curve(\"axis\", 1)"));
    assert!(text.contains("Physical Curve(\"outer_boundary\", 2)"));
}

#[test]
fn mesh_levels_refine_the_default_brake() {
    let g = geometry::build(&default_spec()).unwrap();
    let mut counts = Vec::new();
    for level in [MeshLevel::Coarse, MeshLevel::Default, MeshLevel::Fine] {
        let started = std::time::Instant::now();
        let mesh = mesh_build::mesh(&g, level).unwrap();
        let fewest =
            g.gaps.iter().map(|gap| mesh_build::elements_across(&mesh, gap, 5)).min().unwrap();
        println!(
            "{level:?}: {} nodes, {} triangles, fewest elements across a gap {fewest}, {:.3} s",
            mesh.nodes.len(),
            mesh.triangles.len(),
            started.elapsed().as_secs_f64()
        );
        counts.push(mesh.nodes.len());
    }
    assert!(counts[0] < counts[1] && counts[1] < counts[2], "{counts:?}");
}

/// The bobbin is its own part in every configuration: one per unit with a coil, in the bobbin
/// material, made of the filler cells within one bobbin wall of a winding window, so that it covers
/// at least the wall beside the window over its height; naming a bobbin material changes its
/// material only, not the partition (a default spec meshes exactly as before).
#[test]
fn every_coil_has_a_bobbin_of_its_own_material() {
    let names = ["thesis-bidirectional.toml", "drum.toml", "single-disc.toml", "multi-disc.toml"];
    for name in names {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../../examples/specs")
            .join(name);
        let text = std::fs::read_to_string(&path).unwrap();
        let base = BrakeSpec::from_toml_str(&text, name).unwrap();
        let with_pom = with_edit(&text, "[materials]\n", "[materials]\nbobbin = \"pom\"\n");
        let (g, g_pom) = (geometry::build(&base).unwrap(), geometry::build(&with_pom).unwrap());
        let wall = base.coil.bobbin_wall.m();
        for unit in 0..g.units {
            let coils: Vec<_> = g.coils.iter().filter(|c| c.unit == unit).collect();
            let of_kind = |g: &geometry::BrakeGeometry, kind| {
                g.regions.iter().find(|r| r.unit == Some(unit) && r.kind == kind).cloned()
            };
            let bobbin =
                of_kind(&g, PartKind::Bobbin).unwrap_or_else(|| panic!("{name}: no bobbin"));
            assert_eq!(bobbin.material, base.materials.non_magnetic, "{name}: default material");
            let least: f64 = coils.iter().map(|c| wall * (c.rect.z1 - c.rect.z0)).sum();
            assert!(bobbin.area_m2() >= least * (1.0 - 1e-9), "{name}: {}", bobbin.area_m2());
            for rect in &bobbin.rects {
                let near = coils.iter().any(|c| {
                    rect.r0 < c.rect.r1 + wall + 1e-12
                        && rect.r1 > c.rect.r0 - wall - 1e-12
                        && rect.z0 < c.rect.z1 + wall + 1e-12
                        && rect.z1 > c.rect.z0 - wall - 1e-12
                });
                assert!(near, "{name}: bobbin cell {rect:?} is not beside a winding");
            }
            let pom = of_kind(&g_pom, PartKind::Bobbin).unwrap();
            assert_eq!(pom.material, "pom");
            assert_eq!(pom.rects, bobbin.rects, "{name}: the material does not move the bobbin");
            let filler = of_kind(&g_pom, PartKind::NonMagnetic).unwrap();
            assert_eq!(filler.material, base.materials.non_magnetic);
        }
    }
}
