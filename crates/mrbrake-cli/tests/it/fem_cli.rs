//! CLI behaviour of `mrbrake fem solve` on the shipped pot-core example: the JSON fields issue 3
//! asks for, a converged solve whose numbers agree with the example's own geometry and a magnetic-
//! circuit estimate, the `.vtu` and SVG outputs, and bad problem files (missing file, unknown
//! physical group, region without material) giving a message that names the culprit and exit code 2.

use crate::common;

use common::{expect_input_error, json, mrbrake, number};

use std::path::{Path, PathBuf};

fn examples_fem() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/fem")
}

fn potcore_problem() -> String {
    examples_fem().join("potcore.toml").to_str().expect("UTF-8 path").to_owned()
}

#[test]
fn potcore_json_has_the_issue_fields_and_converges() {
    let v = json(&["fem", "solve", &potcore_problem(), "--json"]);

    assert_eq!(v["converged"], true, "{v}");
    let iterations = v["newton_iterations"].as_u64().expect("newton_iterations is an integer");
    assert!((1..=50).contains(&iterations), "{iterations}");
    let nodes = v["nodes"].as_u64().expect("nodes is an integer");
    let elements = v["elements"].as_u64().expect("elements is an integer");
    assert!(nodes > 1000 && elements > nodes, "{nodes} nodes, {elements} elements");
    assert!(number(&v, "energy_J") > 0.0);

    let timings = &v["timings_s"];
    for field in ["read", "assemble", "solve", "total"] {
        let t = number(timings, field);
        assert!(t.is_finite() && t >= 0.0, "timings_s.{field} = {t}");
    }
    assert!(number(timings, "total") >= number(timings, "solve"));

    // Probes: the three of the problem file, in order, with |B| = sqrt(B_r² + B_z²).
    let probes = v["probes"].as_array().expect("probes is an array");
    let names: Vec<&str> = probes.iter().map(|p| p["name"].as_str().unwrap()).collect();
    assert_eq!(names, ["gap_centre", "pole_gap", "axis_centre"]);
    for p in probes {
        let (b_r, b_z, b_abs) = (number(p, "B_r_T"), number(p, "B_z_T"), number(p, "B_abs_T"));
        assert!((b_r.hypot(b_z) - b_abs).abs() < 1e-9, "{p}");
        assert!(p["r_m"].is_number() && p["z_m"].is_number(), "{p}");
    }
    // Probe coordinates come back in metres (the problem file is in mm).
    assert!((number(&probes[1], "r_m") - 0.005).abs() < 1e-12);
    assert!((number(&probes[1], "z_m") - 0.0155).abs() < 1e-12);
    // On the axis the field is purely axial by symmetry.
    assert!(number(&probes[2], "B_r_T").abs() < 1e-9, "{}", probes[2]);

    // Magnetic-circuit estimate for the centre-pole gap (steel reluctance and fringing neglected):
    // B = μ0 N I / (g + g · A_pole / A_outer), N I = 500 · 2 A, g = 1 mm, pole radius 10 mm,
    // outer ring 25–30 mm (potcore.geo). The FEA must land within 10 % of it.
    let mu0 = 4e-7 * std::f64::consts::PI;
    let a_pole = std::f64::consts::PI * 10f64.powi(2);
    let a_outer = std::f64::consts::PI * (30f64.powi(2) - 25f64.powi(2));
    let b_circuit = mu0 * 1000.0 / (1e-3 * (1.0 + a_pole / a_outer));
    let b_pole = number(&probes[1], "B_abs_T");
    assert!(
        (b_pole - b_circuit).abs() / b_circuit < 0.10,
        "FEA {b_pole} T vs circuit {b_circuit} T"
    );

    // Regions: steel 750 mm² (pot 30×35 − 15×30, plate 30×5), coil 11×26 = 286 mm², all of them
    // filling the half disc of radius 80 mm (polygonal boundary: within 0.5 %).
    let regions = v["regions"].as_array().expect("regions is an array");
    assert_eq!(regions.len(), 3);
    let mut area_sum = 0.0;
    for r in regions {
        for field in ["area_m2", "mean_B_T", "max_B_T"] {
            assert!(number(r, field) >= 0.0, "{r}");
        }
        assert!(number(r, "max_B_T") >= number(r, "mean_B_T"), "{r}");
        area_sum += number(r, "area_m2");
    }
    let area_of = |physical: u64| {
        let region = regions.iter().find(|r| r["physical"] == physical).expect("region present");
        number(region, "area_m2")
    };
    assert!((area_of(1) - 750e-6).abs() < 1e-12, "{}", area_of(1));
    assert!((area_of(2) - 286e-6).abs() < 1e-12, "{}", area_of(2));
    let half_disc = std::f64::consts::PI * 0.08f64.powi(2) / 2.0;
    assert!((area_sum - half_disc).abs() / half_disc < 5e-3, "{area_sum} vs {half_disc}");

    // Coil: the secant inductance is the flux linkage over the 2 A current.
    let coils = v["coils"].as_array().expect("coils is an array");
    assert_eq!(coils.len(), 1);
    assert_eq!(coils[0]["physical"], 2);
    let linkage = number(&coils[0], "flux_linkage_Wb");
    let inductance = number(&coils[0], "inductance_H");
    assert!(linkage > 0.0);
    assert!((inductance - linkage / 2.0).abs() < 1e-12 * linkage.max(1.0), "{}", coils[0]);
}

#[test]
fn vtu_and_plot_are_written() {
    let dir = tempfile::tempdir().expect("temporary directory");
    let vtu = dir.path().join("potcore.vtu");
    let svg = dir.path().join("potcore.svg");
    let out = mrbrake(&[
        "fem",
        "solve",
        &potcore_problem(),
        "--vtu",
        vtu.to_str().unwrap(),
        "--plot",
        svg.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));

    let vtu_text = std::fs::read_to_string(&vtu).expect("the .vtu file is written");
    assert!(vtu_text.contains("<VTKFile") && vtu_text.contains("UnstructuredGrid"));
    assert!(vtu_text.trim_end().ends_with("</VTKFile>"), "truncated .vtu");
    // Same mesh as the JSON run reports.
    let v = json(&["fem", "solve", &potcore_problem(), "--json"]);
    let piece = format!(
        "NumberOfPoints=\"{}\" NumberOfCells=\"{}\"",
        v["nodes"].as_u64().unwrap(),
        v["elements"].as_u64().unwrap()
    );
    assert!(vtu_text.contains(&piece), "missing {piece}");

    let svg_text = std::fs::read_to_string(&svg).expect("the SVG file is written");
    assert!(svg_text.contains("<svg") && svg_text.trim_end().ends_with("</svg>"));
}

/// Writes a problem file into `dir` that uses the example mesh by absolute path and `regions` as
/// its `[[region]]` tables; returns its path.
fn problem_with_regions(dir: &Path, name: &str, regions: &str) -> String {
    let mesh = examples_fem().join("potcore.msh");
    let text = format!(
        "mesh = {mesh:?}\nlength_unit = \"mm\"\n{regions}\n[[boundary]]\nphysical = 10\nkind = \"dirichlet\"\n",
        mesh = mesh.to_str().expect("UTF-8 path"),
    );
    let path = dir.join(name);
    std::fs::write(&path, text).expect("problem file written");
    path.to_str().expect("UTF-8 path").to_owned()
}

#[test]
fn the_bad_problem_helper_is_valid_when_nothing_is_wrong() {
    // Guards the bad-input test below: the same file with correct regions solves.
    let dir = tempfile::tempdir().expect("temporary directory");
    let good = problem_with_regions(
        dir.path(),
        "good.toml",
        "[[region]]\nphysical = 1\nmaterial = \"steel-1010\"\n\
         [[region]]\nphysical = 2\nmaterial = \"air\"\nsource = { turns = 500, current_A = 2.0 }\n\
         [[region]]\nphysical = 3\nmaterial = \"air\"\n",
    );
    let v = json(&["fem", "solve", &good, "--json"]);
    assert_eq!(v["converged"], true);
}

#[test]
fn bad_problem_files_exit_2_naming_the_file_and_field() {
    let dir = tempfile::tempdir().expect("temporary directory");

    let missing = dir.path().join("no-such-problem.toml");
    expect_input_error(&["fem", "solve", missing.to_str().unwrap()], &["no-such-problem.toml"]);

    let unknown_group = problem_with_regions(
        dir.path(),
        "unknown-group.toml",
        "[[region]]\nphysical = 1\nmaterial = \"steel-1010\"\n\
         [[region]]\nphysical = 2\nmaterial = \"air\"\nsource = { turns = 500, current_A = 2.0 }\n\
         [[region]]\nphysical = 3\nmaterial = \"air\"\n\
         [[region]]\nphysical = 77\nmaterial = \"air\"\n",
    );
    expect_input_error(&["fem", "solve", &unknown_group], &["unknown-group.toml", "77"]);

    let no_material = problem_with_regions(
        dir.path(),
        "no-material.toml",
        "[[region]]\nphysical = 1\nmaterial = \"steel-1010\"\n\
         [[region]]\nphysical = 2\nsource = { turns = 500, current_A = 2.0 }\n\
         [[region]]\nphysical = 3\nmaterial = \"air\"\n",
    );
    expect_input_error(&["fem", "solve", &no_material], &["no-material.toml", "material", "2"]);
}

/// `--order 2`: quadratic triangles on the same mesh, reported in the JSON (`order`, `unknowns`);
/// the field agrees with the P1 run to within the discretisation error, and the .vtu keeps one
/// point per mesh node. `--order 3` is a usage error (exit 2) naming the allowed values.
#[test]
fn order_2_solves_the_example_with_quadratic_triangles() {
    let p1 = json(&["fem", "solve", &potcore_problem(), "--json"]);
    let dir = tempfile::tempdir().expect("temporary directory");
    let vtu = dir.path().join("p2.vtu");
    let p2 = json(&[
        "fem",
        "solve",
        &potcore_problem(),
        "--order",
        "2",
        "--json",
        "--vtu",
        vtu.to_str().unwrap(),
    ]);
    assert_eq!(p1["order"], 1, "{p1}");
    assert_eq!(p2["order"], 2, "{p2}");
    assert_eq!(p2["converged"], true);
    assert_eq!(p1["nodes"], p2["nodes"]);
    let (u1, u2) = (p1["unknowns"].as_u64().unwrap(), p2["unknowns"].as_u64().unwrap());
    assert!(u2 > 3 * u1 && u2 < 5 * u1, "unknowns P1 {u1}, P2 {u2}");
    let pole = |v: &serde_json::Value| number(&v["probes"][1], "B_abs_T");
    assert!((pole(&p1) - pole(&p2)).abs() < 0.05 * pole(&p2), "{} vs {}", pole(&p1), pole(&p2));
    let vtu_text = std::fs::read_to_string(&vtu).expect("the .vtu file is written");
    let piece = format!(
        "NumberOfPoints=\"{}\" NumberOfCells=\"{}\"",
        p2["nodes"].as_u64().unwrap(),
        p2["elements"].as_u64().unwrap()
    );
    assert!(vtu_text.contains(&piece), "missing {piece}");

    expect_input_error(
        &["fem", "solve", &potcore_problem(), "--order", "3"],
        &["--order: got 3", "1 or 2"],
    );
}
