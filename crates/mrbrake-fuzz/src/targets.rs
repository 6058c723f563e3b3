//! The fuzz targets: one per input format, each with its seeds and the loader (and, where cheap,
//! the next stage) an input goes through. Seeds are read from the repository (`examples/`, the
//! fem crate's MSH fixtures) and made by the libraries themselves (rig logs, FRD, model file,
//! results store), so every seed is a file the tool accepts.

use std::cell::RefCell;
use std::path::{Path, PathBuf};

use mrbrake_design::mesh_build::{self, MeshLevel};
use mrbrake_design::spec::BrakeSpec;
use mrbrake_explore::problem::OptimizationProblem;
use mrbrake_sim::rig::{self, RigConfig};
use mrbrake_store::{Record, Status, Store};
use mrbrake_sysid::characterize::{CharacterizeOptions, characterize};
use mrbrake_sysid::freqresp::{FreqRespOptions, frequency_response};
use mrbrake_sysid::tfest::{TfestOptions, tfest};

use crate::Outcome;

mod cli;
mod hardening;
mod studio;

/// One input format: its name, seed inputs and the function that runs one input.
pub struct Target {
    /// Short name (`spec`, `msh22`, …).
    pub name: &'static str,
    /// Seed inputs (valid files).
    pub seeds: Vec<Vec<u8>>,
    /// Feeds one input through the loader; panics are what the fuzzer looks for.
    pub run: fn(&[u8]) -> Outcome,
}

/// The repository root (seeds are read from it).
pub fn repo_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn read(relative: &str) -> Vec<u8> {
    std::fs::read(repo_root().join(relative)).unwrap_or_else(|e| panic!("seed {relative}: {e}"))
}

fn text(input: &[u8]) -> String {
    String::from_utf8_lossy(input).into_owned()
}

thread_local! {
    /// A scratch folder per thread for loaders that read files (problem files next to their mesh,
    /// manifests next to their logs, stores).
    static SCRATCH: RefCell<Option<tempfile::TempDir>> = const { RefCell::new(None) };
}

/// The scratch folder, made on first use with the files the file-based targets refer to.
fn scratch() -> PathBuf {
    SCRATCH.with(|cell| {
        let mut cell = cell.borrow_mut();
        if cell.is_none() {
            let dir = tempfile::tempdir().expect("a temporary folder");
            std::fs::write(dir.path().join("potcore.msh"), read("examples/fem/potcore.msh"))
                .expect("write the mesh");
            for (name, csv) in sine_logs() {
                std::fs::write(dir.path().join(name), csv).expect("write a sine log");
            }
            *cell = Some(dir);
        }
        cell.as_ref().map(|d| d.path().to_path_buf()).unwrap_or_default()
    })
}

/// Copies the repository file `relative` into the scratch folder as `name` (once per thread).
fn scratch_with(name: &str, relative: &str) {
    let path = scratch().join(name);
    if !path.exists() {
        std::fs::write(&path, read(relative)).expect("write a scratch file");
    }
}

fn write_scratch(name: &str, input: &[u8]) -> PathBuf {
    let path = scratch().join(name);
    std::fs::write(&path, input).expect("write the input");
    path
}

/// Every target.
pub fn targets() -> Vec<Target> {
    vec![
        Target { name: "spec", seeds: spec_seeds(), run: run_spec },
        Target { name: "spec-mesh", seeds: spec_seeds(), run: run_spec_mesh },
        Target {
            name: "magnetic-problem",
            seeds: vec![read("examples/fem/potcore.toml")],
            run: run_magnetic_problem,
        },
        Target {
            name: "heat-problem",
            seeds: vec![
                read("examples/fem/potcore-heat.toml"),
                read("examples/fem/potcore-warmup.toml"),
            ],
            run: run_heat_problem,
        },
        Target {
            name: "msh22",
            seeds: vec![
                read("crates/mrbrake-fem/tests/fixtures/two_regions_v22.msh"),
                read("examples/fem/eddy-cylinder/cylinder.msh"),
            ],
            run: run_msh,
        },
        Target {
            name: "msh41",
            seeds: vec![read("crates/mrbrake-fem/tests/fixtures/two_regions_v41.msh")],
            run: run_msh,
        },
        Target {
            name: "optimisation-problem",
            seeds: vec![
                read("examples/optimize/thesis-requirement.toml"),
                read("examples/optimize/concept-multi-disc.toml"),
            ],
            run: run_optimisation_problem,
        },
        Target {
            name: "rig-config",
            seeds: vec![small_rig().to_toml().into_bytes()],
            run: run_rig,
        },
        Target { name: "characterization-log", seeds: vec![characterization_seed()], run: run_log },
        Target { name: "sine-manifest", seeds: vec![manifest_seed()], run: run_manifest },
        Target { name: "frd", seeds: vec![frd_seed()], run: run_frd },
        Target { name: "model-json", seeds: vec![model_seed()], run: run_model },
        Target { name: "store", seeds: vec![store_seed()], run: run_store },
    ]
    .into_iter()
    .chain(hardening::targets())
    .chain(studio::targets())
    .chain(cli::targets())
    .collect()
}

fn spec_seeds() -> Vec<Vec<u8>> {
    let mut seeds = Vec::new();
    if let Ok(entries) = std::fs::read_dir(repo_root().join("examples/specs")) {
        let mut paths: Vec<PathBuf> = entries.filter_map(|e| e.ok().map(|e| e.path())).collect();
        paths.sort();
        for path in paths.into_iter().filter(|p| p.extension().is_some_and(|e| e == "toml")) {
            seeds.push(std::fs::read(path).expect("read a spec"));
        }
    }
    seeds
}

/// Spec: parse, validate (fields and geometry), the mesh-resolution check.
fn run_spec(input: &[u8]) -> Outcome {
    Outcome::of(BrakeSpec::from_toml_str(&text(input), "fuzz.toml").and_then(|spec| {
        let validated = spec.validate()?;
        mesh_build::check_resolvable(&spec, &validated.geometry, MeshLevel::Coarse)
    }))
}

/// Spec through the mesher at the coarse level (the budget in `MRBRAKE_MAX_ELEMENTS` applies).
fn run_spec_mesh(input: &[u8]) -> Outcome {
    Outcome::of(BrakeSpec::from_toml_str(&text(input), "fuzz.toml").and_then(|spec| {
        let validated = spec.validate()?;
        mesh_build::mesh_spec(&spec, &validated.geometry, MeshLevel::Coarse).map(|m| m.nodes.len())
    }))
}

fn run_magnetic_problem(input: &[u8]) -> Outcome {
    let path = write_scratch("p.toml", input);
    Outcome::of(mrbrake_magnetics::problem_file::load(&path))
}

fn run_heat_problem(input: &[u8]) -> Outcome {
    let path = write_scratch("h.toml", input);
    Outcome::of(mrbrake_heat::problem_file::load(&path))
}

fn run_msh(input: &[u8]) -> Outcome {
    Outcome::of(mrbrake_fem::mesh::gmsh::parse_msh(&text(input), "fuzz.msh", 1e-3))
}

fn run_optimisation_problem(input: &[u8]) -> Outcome {
    let path = repo_root().join("examples/optimize/fuzz.toml");
    Outcome::of(OptimizationProblem::from_toml_str(&text(input), &path))
}

/// A rig whose protocols are short (two repetitions of 20 mA steps; three sine tests of about a
/// second, long enough for the default analysis settings).
fn small_rig() -> RigConfig {
    let mut c = RigConfig::default();
    c.characterization.repetitions = 2;
    c.characterization.step_a = 0.02;
    c.characterization.pause_s = 0.2;
    c.frequency_response.omega_min_rad_s = 10.0;
    c.frequency_response.omega_max_rad_s = 100.0;
    c.frequency_response.points_per_decade = 2;
    c.frequency_response.min_measure_s = 0.5;
    c.frequency_response.settle_s = 0.6;
    c
}

/// Rig configuration: read and check; a short enough characterisation is run too.
fn run_rig(input: &[u8]) -> Outcome {
    Outcome::of(RigConfig::from_toml("rig.toml", &text(input)).and_then(|config| {
        let steps = rig::characterization_duration_s(&config) * config.daq.output_rate_hz;
        if steps <= 20_000.0 {
            rig::characterization_samples(&config).map(|s| s.len())
        } else {
            Ok(0)
        }
    }))
}

fn characterization_seed() -> Vec<u8> {
    rig::characterization_log(&small_rig()).expect("the small rig runs").csv.into_bytes()
}

/// Characterisation log: read, screen for outliers, characterise.
fn run_log(input: &[u8]) -> Outcome {
    let source = Path::new("fuzz.csv");
    let log =
        mrbrake_sysid::log::read_log_from(source, input, "time_s", &["current_A", "torque_Nm"], 12);
    Outcome::of(log.and_then(|log| {
        mrbrake_sysid::outliers::check_outliers(
            source,
            "torque_Nm",
            &log.time_s,
            &log.channels[1],
        )?;
        characterize(
            &log.channels[0],
            &log.channels[1],
            CharacterizeOptions { order: 5, bins: 200 },
        )
    }))
}

/// The small rig's sine logs (name, CSV) and manifest.
fn sine_files() -> Vec<(String, String)> {
    rig::frequency_response_logs(&small_rig(), None)
        .expect("the small rig runs")
        .into_iter()
        .map(|f| (f.name, f.csv))
        .collect()
}

fn sine_logs() -> Vec<(String, String)> {
    sine_files().into_iter().filter(|(n, _)| n != "manifest.csv").collect()
}

fn manifest_seed() -> Vec<u8> {
    sine_files()
        .into_iter()
        .find(|(n, _)| n == "manifest.csv")
        .map(|(_, csv)| csv.into_bytes())
        .unwrap_or_default()
}

/// Manifest (the logs it names are the small rig's): the whole frequency-response analysis.
fn run_manifest(input: &[u8]) -> Outcome {
    let path = write_scratch("manifest.csv", input);
    Outcome::of(frequency_response(&path, &FreqRespOptions::default()))
}

fn frd_seed() -> Vec<u8> {
    let g = mrbrake_sysid::transfer_function::TransferFunction::new(
        vec![1.0],
        vec![1.791e-5, 0.01702, 1.0],
    )
    .expect("the thesis model");
    let omegas = mrbrake_sysid::tfest::logspace(0.1, 1000.0, 21);
    mrbrake_sysid::frd::Frd::sample(&omegas, |w| g.response(w)).to_csv().into_bytes()
}

/// FRD: read, then a second-order estimate.
fn run_frd(input: &[u8]) -> Outcome {
    let frd = mrbrake_sysid::frd::read_frd_from(Path::new("fuzz.csv"), &text(input), None);
    Outcome::of(frd.and_then(|frd| tfest(&frd, &TfestOptions::new(2, 0))))
}

fn model_seed() -> Vec<u8> {
    let log = rig::characterization_samples(&small_rig()).expect("the small rig runs");
    let current: Vec<f64> = log.iter().map(|s| s[1]).collect();
    let torque: Vec<f64> = log.iter().map(|s| s[2]).collect();
    let c = characterize(&current, &torque, CharacterizeOptions { order: 3, bins: 50 })
        .expect("the small rig's log characterises");
    serde_json::to_vec_pretty(&c).expect("a characterisation serialises")
}

fn run_model(input: &[u8]) -> Outcome {
    Outcome::of(mrbrake_sysid::model_file::parse_inverse_model(Path::new("m.json"), &text(input)))
}

fn store_seed() -> Vec<u8> {
    let dir = tempfile::tempdir().expect("a temporary folder");
    let path = dir.path().join("seed.sqlite");
    let mut store = Store::create(&path).expect("create a store");
    for (k, status) in [Status::Ok, Status::Infeasible, Status::Failed].into_iter().enumerate() {
        let record = Record {
            key: format!("{k:064x}"),
            status,
            reason: (status != Status::Ok).then(|| "a reason".to_string()),
            variables: vec![("drum.gap".into(), (5e-4 + k as f64 * 1e-4).into())],
            metrics: if status == Status::Ok {
                vec![("torque_max_Nm".into(), 3.5.into())]
            } else {
                vec![]
            },
            spec_toml: "name = \"x\"\n".into(),
            eval_seconds: 1.5,
            solver_version: "0.1.0".into(),
            settings: Default::default(),
        };
        store.insert(&record).expect("insert a record");
    }
    store.close().expect("close the store");
    std::fs::read(&path).expect("read the store back")
}

/// Results store: open read-only, read every record, export CSV and JSON.
fn run_store(input: &[u8]) -> Outcome {
    let dir = scratch();
    for leftover in ["s.sqlite-wal", "s.sqlite-shm"] {
        let _ = std::fs::remove_file(dir.join(leftover));
    }
    let path = write_scratch("s.sqlite", input);
    Outcome::of(Store::open_read_only(&path).and_then(|store| {
        let records = store.records()?;
        mrbrake_store::to_csv(&records)?;
        Ok(mrbrake_store::to_json(&records))
    }))
}
