//! CLI behaviour of `mrbrake analyze`, `mrbrake export-geo` and `mrbrake study thesis-tables`: the
//! JSON fields issue 4 asks for on the embedded thesis brake (coarse mesh, short sweep), their
//! internal consistency (P = I²R, τ = L/R, gap torques adding up), the plots, the Gmsh export, the
//! four study tables, and a bad spec (negative gap) giving a message naming the field and exit code 2.

use crate::common;

use common::{close, expect_input_error, json, mrbrake, number};

use std::path::{Path, PathBuf};

fn examples_specs() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/specs")
}

fn default_analysis() -> serde_json::Value {
    json(&["analyze", "--mesh", "coarse", "--points", "3", "--json"])
}

#[test]
fn default_brake_json_has_the_issue_fields() {
    let v = default_analysis();

    let curve = v["torque_current_curve"].as_array().expect("torque_current_curve is an array");
    assert_eq!(curve.len(), 3);
    for point in curve {
        for field in ["current_A", "torque_Nm", "mean_B_T"] {
            assert!(number(point, field).is_finite(), "{point}");
        }
    }
    // The sweep runs from 0 to the maximum current (2 A for the thesis design).
    assert!(number(&curve[0], "current_A").abs() < 1e-12);
    assert!(close(number(&curve[2], "current_A"), 2.0, 1e-12));

    let torque = &v["torque"];
    let at_max = number(torque, "at_max_current_Nm");
    let off_state = number(torque, "off_state_Nm");
    let thesis_formula = number(torque, "thesis_formula_Nm");
    assert!(at_max > 1.0 && off_state >= 0.0 && off_state < at_max, "{torque}");
    assert!(thesis_formula > 0.0, "{torque}");
    assert!(close(at_max, number(&curve[2], "torque_Nm"), 1e-12), "{torque}");
    assert!(close(off_state, number(&curve[0], "torque_Nm"), 1e-12), "{torque}");

    // Four fluid surfaces per unit, two units.
    let gaps = v["gaps"].as_array().expect("gaps is an array");
    assert_eq!(gaps.len(), 8);
    for (i, gap) in gaps.iter().enumerate() {
        // Gaps and units are numbered from 1, as in the text output and the plots.
        assert_eq!(gap["index"].as_u64(), Some(i as u64 + 1), "{gap}");
        assert_eq!(gap["unit"].as_u64(), Some(i as u64 / 4 + 1), "{gap}");
        for field in ["r_m", "height_m", "mean_B_T", "tau_y_Pa", "torque_Nm"] {
            assert!(number(gap, field) > 0.0, "{gap}");
        }
        // The thesis design: 9 mm high drums from R0 = 25 mm outwards.
        assert!(close(number(gap, "height_m"), 9e-3, 1e-9), "{gap}");
        assert!(number(gap, "r_m") >= 0.025 - 1e-12, "{gap}");
    }
    // The gaps of one unit carry the yield torque of one direction at the maximum current.
    let unit0_torque: f64 =
        gaps.iter().filter(|g| g["unit"] == 1).map(|g| number(g, "torque_Nm")).sum();
    let yield_at_max = number(&curve[2], "yield_torque_Nm");
    assert!(close(unit0_torque, yield_at_max, 1e-9), "{unit0_torque} vs {yield_at_max}");

    let coil = &v["coil"];
    for field in [
        "turns",
        "wire_length_m",
        "resistance_ohm",
        "current_density_A_per_mm2",
        "power_W",
        "inductance_H",
        "time_constant_s",
    ] {
        assert!(number(coil, field) > 0.0, "coil.{field}: {coil}");
    }
    assert_eq!(coil["turns"].as_u64(), Some(450));
    let resistance = number(coil, "resistance_ohm");
    assert!(close(number(coil, "power_W"), 2.0 * 2.0 * resistance, 1e-9), "{coil}");
    assert!(
        close(number(coil, "time_constant_s"), number(coil, "inductance_H") / resistance, 1e-9),
        "{coil}"
    );
    // Thesis (4.1) with 0.5 mm wire at 2 A: 4.62 A/mm² (same figure as `formula coil`).
    assert!((number(coil, "current_density_A_per_mm2") - 4.62).abs() < 5e-3, "{coil}");

    let mechanics = &v["mechanics"];
    for field in ["mass_kg", "volume_m3", "rotor_inertia_kg_m2"] {
        assert!(number(mechanics, field) > 0.0, "mechanics.{field}: {mechanics}");
    }
    // An 80 mm × 124 mm envelope holds at most π · 0.04² · 0.124 m³.
    let envelope = std::f64::consts::PI * 0.04f64.powi(2) * 0.124;
    assert!(number(mechanics, "volume_m3") <= envelope * (1.0 + 1e-9), "{mechanics}");

    let mesh = &v["mesh"];
    let nodes = mesh["nodes"].as_u64().expect("mesh.nodes is an integer");
    let elements = mesh["elements"].as_u64().expect("mesh.elements is an integer");
    assert!(nodes > 100 && elements > nodes, "{mesh}");
    assert!(number(&v["timings_s"], "total") > 0.0);
}

#[test]
fn mechanics_torque_density_uses_the_issue_field_name() {
    // Issue 4 names the field `torque_density_Nm_per_m3`; it is torque at max current / volume.
    let v = default_analysis();
    let mechanics = &v["mechanics"];
    let density = number(mechanics, "torque_density_Nm_per_m3");
    let expected = number(&v["torque"], "at_max_current_Nm") / number(mechanics, "volume_m3");
    assert!(close(density, expected, 1e-9), "{density} vs {expected}");
}

#[test]
fn torque_increases_with_current() {
    let v = json(&["analyze", "--mesh", "coarse", "--points", "4", "--json"]);
    let curve = v["torque_current_curve"].as_array().expect("torque_current_curve is an array");
    assert_eq!(curve.len(), 4);
    for pair in curve.windows(2) {
        let (a, b) = (&pair[0], &pair[1]);
        assert!(number(b, "current_A") > number(a, "current_A"), "{a} → {b}");
        assert!(number(b, "torque_Nm") > number(a, "torque_Nm"), "{a} → {b}");
        assert!(number(b, "mean_B_T") > number(a, "mean_B_T"), "{a} → {b}");
    }
}

#[test]
fn plot_dir_gets_the_three_plots() {
    let dir = tempfile::tempdir().expect("temporary directory");
    let plots = dir.path().join("plots");
    let out = mrbrake(&[
        "analyze",
        "--mesh",
        "coarse",
        "--points",
        "2",
        "--plot-dir",
        plots.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    for name in ["field_map.svg", "torque_current.svg", "gap_flux_density.svg"] {
        let text = std::fs::read_to_string(plots.join(name))
            .unwrap_or_else(|e| panic!("{name} not written: {e}"));
        assert!(text.contains("<svg") && text.trim_end().ends_with("</svg>"), "{name}");
    }
}

#[test]
fn negative_gap_exits_2_naming_the_field() {
    let dir = tempfile::tempdir().expect("temporary directory");
    let drum = std::fs::read_to_string(examples_specs().join("drum.toml")).expect("drum.toml");
    assert!(drum.contains("gap = \"0.5mm\""), "the example changed; update this test");
    let bad = dir.path().join("negative-gap.toml");
    std::fs::write(&bad, drum.replace("gap = \"0.5mm\"", "gap = \"-0.5mm\"")).unwrap();
    let out = mrbrake(&["analyze", bad.to_str().unwrap(), "--mesh", "coarse", "--points", "2"]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "stderr: {err}");
    assert!(err.contains("drum.gap"), "{err}");
    assert!(!err.contains("panicked"), "{err}");
}

#[test]
fn quadratic_elements_agree_with_linear_ones_and_report_their_unknowns() {
    let p1 = default_analysis();
    let p2 = json(&["analyze", "--mesh", "coarse", "--points", "3", "--order", "2", "--json"]);
    assert_eq!(p1["mesh"]["order"].as_u64(), Some(1));
    assert_eq!(p2["mesh"]["order"].as_u64(), Some(2));
    assert_eq!(p2["mesh"]["nodes"], p1["mesh"]["nodes"], "the same mesh");
    let (u1, u2) = (number(&p1["mesh"], "unknowns"), number(&p2["mesh"], "unknowns"));
    assert!(u2 > 3.5 * u1 && u2 < 4.5 * u1, "P2 has about four times the unknowns: {u1} / {u2}");
    let torque = |v: &serde_json::Value| number(&v["torque"], "at_max_current_Nm");
    assert!(close(torque(&p2), torque(&p1), 2e-3), "{} vs {}", torque(&p2), torque(&p1));
    expect_input_error(&["analyze", "--order", "3"], &["--order", "3"]);
}

#[test]
fn export_geo_writes_physical_groups() {
    let dir = tempfile::tempdir().expect("temporary directory");
    let geo = dir.path().join("x.geo");
    let spec = examples_specs().join("drum.toml");
    let out = mrbrake(&["export-geo", spec.to_str().unwrap(), "-o", geo.to_str().unwrap()]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let text = std::fs::read_to_string(&geo).expect("the .geo file is written");
    assert!(text.contains("Physical Surface"), "{text}");
    assert!(text.contains("Point(") && text.contains("Plane Surface"), "{text}");
}

/// Issue 19: units and gaps are numbered from 1 in the `.geo` physical names and in the JSON,
/// as everywhere else (the bidirectional default has two units).
#[test]
fn export_geo_numbers_units_and_gaps_from_1() {
    let dir = tempfile::tempdir().expect("temporary directory");
    let geo = dir.path().join("bidirectional.geo");
    let v = json(&["export-geo", "-o", geo.to_str().unwrap(), "--json"]);
    let text = std::fs::read_to_string(&geo).expect("the .geo file is written");
    let names: Vec<&str> = text
        .lines()
        .filter(|l| l.starts_with("Physical "))
        .filter_map(|l| l.split('"').nth(1))
        .collect();
    for first in ["unit1.gap1", "unit2.gap1", "unit1.coil", "unit2.coil"] {
        assert!(names.iter().any(|n| n.starts_with(first)), "no {first} in {names:?}");
    }
    assert!(!names.iter().any(|n| n.contains("unit0") || n.contains("gap0")), "{names:?}");
    let gaps = v["gaps"].as_array().expect("gaps");
    let numbers = |field: &str| -> Vec<u64> {
        gaps.iter().map(|g| g[field].as_u64().expect("a number")).collect()
    };
    assert_eq!(numbers("index").iter().min(), Some(&1), "{v}");
    assert_eq!(numbers("index_in_unit").iter().min(), Some(&1), "{v}");
    assert_eq!(
        numbers("unit").iter().copied().collect::<std::collections::BTreeSet<_>>(),
        [1, 2].into()
    );
    let coil_units: Vec<u64> =
        v["coils"].as_array().expect("coils").iter().map(|c| c["unit"].as_u64().unwrap()).collect();
    assert!(coil_units.contains(&1) && coil_units.contains(&2) && !coil_units.contains(&0), "{v}");
}

#[test]
fn study_thesis_tables_returns_four_tables() {
    let v = json(&["study", "thesis-tables", "--mesh", "coarse", "--json"]);
    let tables = v.as_array().expect("a JSON array of tables");
    assert_eq!(tables.len(), 4);
    for (table, expected) in tables.iter().zip(["4.1", "4.2", "4.3", "4.4"]) {
        let name = table["table"].as_str().expect("table name");
        assert!(name.contains(expected), "{name} should be Table {expected}");
        let rows = table["rows"].as_array().expect("rows");
        assert!(rows.len() >= 2, "{table}");
        for row in rows {
            assert!(row["label"].is_string(), "{row}");
            assert!(number(row, "local_Nm") > 0.0, "{row}");
        }
    }
}
