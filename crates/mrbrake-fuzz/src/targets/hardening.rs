//! The input kinds of issue 33 (magnetodynamic problem files, brake models, Preisach rigs and
//! minor-loop programs, `response` and `thermal` options) and its properties, checked on every
//! execution: an accepted input gives only finite numbers, and a refused file-based input names
//! its file. A property that fails panics, so the harness records the input as a crash (a
//! finding), as it does for a real panic.

use mrbrake_control::Branch;
use mrbrake_design::response::{ResponseOptions, check_options};
use mrbrake_design::thermal::{ThermalOptions, validate_options};
use mrbrake_sim::brake_model::BrakeModel;
use mrbrake_sim::rig::{self, RigConfig};
use mrbrake_units::{Dimension, parse};

use super::{Target, read, scratch_with, small_rig, text, write_scratch};
use crate::Outcome;

/// The targets of this module.
pub fn targets() -> Vec<Target> {
    vec![
        Target {
            name: "magnetodynamic-problem",
            seeds: vec![read("examples/fem/eddy-cylinder/eddy-cylinder.toml")],
            run: run_magnetodynamic_problem,
        },
        Target {
            name: "brake-model",
            seeds: vec![
                read("examples/brake-models/prototype.json"),
                read("examples/brake-models/rig-prototype.json"),
            ],
            run: run_brake_model,
        },
        Target { name: "preisach-rig", seeds: preisach_seeds(), run: run_preisach_rig },
        Target { name: "response-thermal-options", seeds: option_seeds(), run: run_options },
    ]
}

/// A refused input must name its file (issue 33: numerical failures named nothing).
fn named<T, E: mrbrake_error::Kind + std::fmt::Display>(
    result: Result<T, E>,
    file: &str,
) -> Outcome {
    if let Err(e) = &result {
        let message = e.to_string();
        assert!(message.contains(file), "the error does not name {file}: {message}");
    }
    Outcome::of(result)
}

/// Panics (a finding) when any of `values` is not finite.
fn all_finite(what: &str, values: impl IntoIterator<Item = f64>) {
    if let Some(v) = values.into_iter().find(|v| !v.is_finite()) {
        panic!("an accepted input gave a non-finite {what}: {v}");
    }
}

fn run_magnetodynamic_problem(input: &[u8]) -> Outcome {
    scratch_with("cylinder.msh", "examples/fem/eddy-cylinder/cylinder.msh");
    let path = write_scratch("d.toml", input);
    named(mrbrake_magnetics::problem_file::load(&path), "d.toml")
}

/// Brake model: read and check; an accepted model writes JSON that reads back the same, and the
/// branches the simulators run are finite.
fn run_brake_model(input: &[u8]) -> Outcome {
    let result = BrakeModel::from_json("model.json", &text(input)).map(|model| {
        let again = BrakeModel::from_json("again.json", &model.to_json());
        assert!(again.is_ok(), "a model read does not read back: {again:?}");
        for unit in &model.units {
            let branches = unit.branches().expect("a checked model has branches");
            for branch in [Branch::Rising, Branch::Falling] {
                let currents = (0..=20).map(|k| f64::from(k) / 20.0 * unit.current_max_a);
                all_finite("branch torque", currents.map(|i| branches.model.torque_nm(branch, i)));
            }
        }
        model.units.len()
    });
    named(result, "model.json")
}

/// Rig configurations with the Preisach hysteresis and a minor-loop program.
fn preisach_seeds() -> Vec<Vec<u8>> {
    let mut config = small_rig();
    config.hysteresis.model = rig::preisach::HysteresisKind::Preisach;
    config.hysteresis.levels = 16;
    let mut lorentz = config.clone();
    lorentz.hysteresis.weight = rig::preisach::WeightShape::Lorentzian;
    vec![config.to_toml().into_bytes(), lorentz.to_toml().into_bytes()]
}

/// Preisach rig: read and check; a short characterisation and minor-loop program are run and
/// every sample must be finite.
fn run_preisach_rig(input: &[u8]) -> Outcome {
    let result = RigConfig::from_toml("rig.toml", &text(input)).and_then(|config| {
        let steps = rig::characterization_duration_s(&config) * config.daq.output_rate_hz;
        if steps > 20_000.0 {
            return Ok(0);
        }
        let samples = rig::characterization_samples(&config)?;
        all_finite("rig sample", samples.iter().flatten().copied());
        let program = rig::minor_loops::program(&config);
        let duration: f64 = program.iter().map(|r| r.duration_s).sum();
        if duration * config.daq.output_rate_hz <= 20_000.0 {
            let (loops, _) = rig::minor_loops::minor_loop_samples(&config)?;
            all_finite("minor-loop sample", loops.iter().flatten().copied());
        }
        Ok(samples.len())
    });
    named(result, "rig.toml")
}

fn option_seeds() -> Vec<Vec<u8>> {
    vec![
        b"duration=100ms\nbias=1A\nstep=0A\nfluid-lag=0.48ms\nconductivity=2MS/m\n".to_vec(),
        b"current=2A\nduty=0.5\nambient=25\nh=10\nemissivity=0.9\n".to_vec(),
    ]
}

/// `response` and `thermal` options as `flag=value` lines: parsed with their units, then checked
/// by the libraries' own rules (the flags' parsing and range rules, without the solves).
fn run_options(input: &[u8]) -> Outcome {
    let mut response = ResponseOptions::default();
    let mut thermal = ThermalOptions::default();
    for line in text(input).lines() {
        let Some((flag, value)) = line.split_once('=') else { continue };
        let quantity = |d: Dimension| parse(value, d).map_err(|e| format!("--{flag}: {e}"));
        let parsed = match flag {
            "duration" => quantity(Dimension::Time).map(|v| response.duration_s = v),
            "bias" => quantity(Dimension::Current).map(|v| response.bias_a = Some(v)),
            "step" => quantity(Dimension::Current).map(|v| response.step_from_a = v),
            "fluid-lag" => quantity(Dimension::Time).map(|v| response.fluid_lag_s = v),
            "conductivity" => quantity(Dimension::Conductivity)
                .map(|v| response.flux_path_conductivity_s_per_m = Some(v)),
            "current" => quantity(Dimension::Current).map(|v| thermal.current_a = v),
            "duty" => value.trim().parse().map(|v| thermal.duty = v).map_err(|e| format!("{e}")),
            "ambient" => {
                value.trim().parse().map(|v| thermal.ambient_c = v).map_err(|e| format!("{e}"))
            }
            "emissivity" => {
                value.trim().parse().map(|v| thermal.emissivity = v).map_err(|e| format!("{e}"))
            }
            _ => Ok(()),
        };
        if let Err(message) = parsed {
            return Outcome::Refused(format!("Input: {message}"));
        }
    }
    let checked = check_options(&response).map_err(|e| e.to_string());
    let checked = checked.and_then(|()| validate_options(&thermal).map_err(|e| e.to_string()));
    match checked {
        Ok(()) => Outcome::Ok,
        Err(message) => Outcome::Refused(format!("Input: {}", crate::normalise(&message))),
    }
}
