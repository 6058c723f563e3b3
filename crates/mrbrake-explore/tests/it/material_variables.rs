//! A part's material as a study variable (issue 27, "Variables a designer actually changes"): a
//! sweep over the bobbin's material stores one design per material, keeps the material by name in
//! the record and the exports, and the stored metrics follow the material; NSGA-II varies a
//! material beside a number and a fixed variable stays out of the search.

use std::path::PathBuf;

use mrbrake_design::geometry::{self, PartKind};
use mrbrake_design::mesh_build::MeshLevel;
use mrbrake_design::spec::BrakeSpec;
use mrbrake_explore::optimize;
use mrbrake_explore::plan::{Sampling, Shard, SweepRequest, sweep_plan};
use mrbrake_explore::problem::OptimizationProblem;
use mrbrake_explore::{EvaluationSettings, Runner};
use mrbrake_observe::Silent;
use mrbrake_store::{Status, Store, VariableValue, to_csv, to_json};

fn spec_path() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../examples/specs/single-disc.toml")
}

fn coarse() -> EvaluationSettings {
    EvaluationSettings { mesh: MeshLevel::Coarse, ..EvaluationSettings::default() }
}

fn density(name: &str) -> f64 {
    mrbrake_materials::library::get(name).unwrap().density_kg_m3.as_ref().unwrap().value
}

/// The bobbin's volume (m³) of the single-disc example: the parts' volumes of kind bobbin.
fn bobbin_volume(spec: &BrakeSpec) -> f64 {
    let g = geometry::build(spec).unwrap();
    g.regions.iter().filter(|r| r.kind == PartKind::Bobbin).map(|r| r.volume_m3()).sum()
}

#[test]
fn a_swept_bobbin_material_is_stored_by_name_and_moves_the_mass() {
    let text = std::fs::read_to_string(spec_path()).unwrap();
    let vary = ["materials.bobbin=aluminium,stainless-304,POM".to_string()];
    let request = SweepRequest {
        spec_text: &text,
        origin: "single-disc.toml",
        overrides: &[],
        vary: &vary,
        sampling: Sampling::FullFactorial,
        shard: Shard::ALL,
        settings: coarse(),
    };
    let plan = sweep_plan(&request).unwrap();
    assert_eq!(plan.plan_points, 3);
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("s.sqlite");
    let mut store = Store::open_or_create(&path, false).unwrap();
    let (records, _) =
        Runner::new(&mut store, coarse(), 1).run(&plan.designs, &mut Silent).unwrap();
    drop(store);
    let stored = Store::open(&path).unwrap().records().unwrap();
    assert_eq!(stored.len(), 3);
    let materials = ["aluminium", "stainless-304", "pom"];
    for (record, material) in records.iter().zip(materials) {
        assert_eq!(record.status, Status::Ok, "{material}: {:?}", record.reason);
        let back = stored.iter().find(|r| r.key == record.key).expect("stored");
        let value = back.variable_value("materials.bobbin").and_then(VariableValue::as_level);
        assert_eq!(value, Some(material), "stored by name");
        assert!(back.spec_toml.contains(&format!("bobbin = \"{material}\"")), "{}", back.spec_toml);
    }
    let keys: std::collections::HashSet<_> = records.iter().map(|r| r.key.as_str()).collect();
    assert_eq!(keys.len(), 3, "each material is its own design");

    // The parts are the same cells in every design, so the mass moves by the bobbin's volume times
    // the change of density, and the field (every level has mu_r = 1) does not move.
    let volume = bobbin_volume(&BrakeSpec::from_toml_str(&text, "single-disc.toml").unwrap());
    assert!(volume > 0.0);
    let metric = |k: usize, name: &str| records[k].metric(name).unwrap();
    for k in 1..3 {
        let expected = volume * (density(materials[k]) - density(materials[0]));
        let got = metric(k, "mass_kg") - metric(0, "mass_kg");
        assert!((got - expected).abs() <= 1e-9 * metric(0, "mass_kg"), "{k}: {got} vs {expected}");
        let (t0, t) = (metric(0, "torque_max_Nm"), metric(k, "torque_max_Nm"));
        assert!((t - t0).abs() <= 1e-9 * t0, "{}: torque {t} vs {t0}", materials[k]);
    }
    assert!(
        metric(2, "mass_kg") < metric(0, "mass_kg") && metric(0, "mass_kg") < metric(1, "mass_kg")
    );

    // The exports write the material by name.
    let csv = String::from_utf8(to_csv(&stored).unwrap()).unwrap();
    let header = csv.lines().next().unwrap();
    assert!(header.starts_with("key,status,reason,materials.bobbin,"), "{header}");
    assert!(csv.lines().skip(1).any(|l| l.contains(",pom,")), "{csv}");
    let json = to_json(&stored);
    let mut names: Vec<&str> = json
        .as_array()
        .unwrap()
        .iter()
        .filter_map(|r| r["variables"]["materials.bobbin"].as_str())
        .collect();
    names.sort_unstable();
    assert_eq!(names, ["aluminium", "pom", "stainless-304"]);
}

#[test]
fn nsga2_varies_a_material_beside_a_number_and_leaves_a_fixed_variable_alone() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("problem.toml");
    let text = format!(
        "spec = {:?}\nmesh = \"coarse\"\nreference = false\n\
         [[variable]]\nname = \"g\"\nmin = \"0.4mm\"\nmax = \"0.8mm\"\n\
         [[variable]]\nname = \"materials.bobbin\"\nvalues = [\"aluminium\", \"pom\"]\n\
         [[variable]]\nname = \"coil.max_current\"\nvalue = \"1.5A\"\n\
         [[objective]]\nmetric = \"mass_kg\"\ngoal = \"minimize\"\n\
         [[objective]]\nmetric = \"torque_max_Nm\"\ngoal = \"maximize\"\n\
         [algorithm]\nkind = \"nsga2\"\npopulation = 4\ngenerations = 1\nseed = 3\n",
        spec_path().display().to_string()
    );
    std::fs::write(&path, text).unwrap();
    let problem = OptimizationProblem::from_path(&path).unwrap();
    assert_eq!(problem.variables.len(), 2, "the fixed current is not a variable");
    assert!(problem.notes.iter().any(|n| n.contains("coil.max_current")), "{:?}", problem.notes);
    let mut store = Store::open_or_create(&dir.path().join("o.sqlite"), false).unwrap();
    let result = optimize::run(&problem, &mut store, 1, &mut Silent).unwrap();
    // Two generations of four, less the offspring that repeat a design.
    assert!((4..=8).contains(&result.evaluated.len()), "{}", result.evaluated.len());
    let mut seen = std::collections::BTreeSet::new();
    for e in &result.evaluated {
        let r = &e.record;
        let names: Vec<&str> = r.variables.iter().map(|(n, _)| n.as_str()).collect();
        assert_eq!(names, ["g", "materials.bobbin"]);
        let level = r.variable_value("materials.bobbin").and_then(VariableValue::as_level);
        let level = level.expect("a material by name");
        assert!(["aluminium", "pom"].contains(&level), "{level}");
        assert!(r.spec_toml.contains(&format!("bobbin = \"{level}\"")), "{}", r.spec_toml);
        assert!(r.spec_toml.contains("max_current = 1.5"), "{}", r.spec_toml);
        let current = r.metric("max_current_A").unwrap();
        assert!((current - 1.5).abs() < 1e-12, "{current}");
        seen.insert(level.to_string());
    }
    // The initial population spreads the levels evenly (each of the two twice).
    assert_eq!(seen.len(), 2, "{seen:?}");
    // The written front designs keep their source's material (a material is stored by name: read
    // back as its level's index, not lost as a number the record does not have).
    assert!(!result.front_designs.is_empty());
    for front in &result.front_designs {
        let source = &result.evaluated[front.source].record;
        let level = source.variable_value("materials.bobbin").and_then(VariableValue::as_level);
        let level = level.expect("a material by name");
        assert!(front.spec_text.contains(&format!("bobbin = \"{level}\"")), "{}", front.spec_text);
        let written = front.evaluated.record.variable_value("materials.bobbin");
        assert_eq!(written.and_then(VariableValue::as_level), Some(level));
    }
}
