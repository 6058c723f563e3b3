//! Repeatable workloads for instruction counts (`valgrind --tool=callgrind`), one per solver path:
//! the criterion benchmarks' problems, run a fixed number of times (criterion's timing loop is not
//! repeatable). Build with `cargo build --release -p mrbrake-design --example workloads`, then
//!
//! `valgrind --tool=callgrind --callgrind-out-file=/dev/null target/release/examples/workloads NAME`
//!
//! with NAME one of
//! - `static`: the saturating pot core (P1, ~25 k nodes, 10 A) set up and solved by Newton, with
//!   the post-processing of `benches/saturating.rs` (mrbrake-magnetics);
//! - `transient`: the linear conducting pot core (~16 k nodes), a current step, 500 fixed BDF2
//!   steps (`linear_transient` of `benches/dynamics.rs`);
//! - `harmonic`: the same problem at 31 frequencies by the reduced-basis sweep (`harmonic`);
//! - `heat`: the thesis brake's 2 h warm-up at 10 s steps, 720 BDF2 steps
//!   (`warmup/2h_10s` of `benches/thermal.rs`);
//! - `heat-steady`: its steady temperature (`steady/thesis_default_mesh`);
//! - `eddy`: `examples/fem/eddy-cylinder/eddy-cylinder.toml` (saturating steel, adaptive BDF2,
//!   Newton in every step), as `mrbrake fem solve` runs it;
//!
//! and NAME-setup the same set-up without the measured solve, so that the difference of the two
//! counts is the solve alone.

use mrbrake_design::spec::default_spec;
use mrbrake_design::thermal::{ThermalOptions, thermal_problem};
use mrbrake_fem::workflow::time::{Event, Scheme, TimeOptions, TimeStep};
use mrbrake_heat::{HeatSolver, SolverOptions as HeatOptions, kelvin};
use mrbrake_magnetics::benchmark::{STEEL, conducting_pot_core, pot_core_problem};
use mrbrake_magnetics::dynamics::Dynamics;
use mrbrake_magnetics::dynamics::harmonic::HarmonicMethod;
use mrbrake_magnetics::dynamics::transient::TransientOptions;
use mrbrake_magnetics::{Solver, SolverOptions};

fn dynamics() -> Dynamics {
    conducting_pot_core(16_000).expect("dynamics")
}

fn heat_solver() -> HeatSolver {
    let (problem, _) =
        thermal_problem(&default_spec(), &ThermalOptions::default()).expect("problem");
    HeatSolver::new(problem, HeatOptions::default()).expect("setup")
}

fn main() {
    let name = std::env::args().nth(1).unwrap_or_default();
    let (workload, solve) = match name.strip_suffix("-setup") {
        Some(w) => (w.to_string(), false),
        None => (name.clone(), true),
    };
    let value = match workload.as_str() {
        "static" => {
            let steel = mrbrake_materials::library::get("steel-1010").expect("material");
            let problem = pot_core_problem(25_000, steel.magnetic.clone(), 10.0).expect("problem");
            let mut solver = Solver::new(problem, SolverOptions::default()).expect("setup");
            if !solve {
                return;
            }
            let solution = solver.solve(None).expect("converges");
            let stats = solver.region_stats(&solution, STEEL).expect("steel region");
            let energy = solver.energy(&solution);
            stats.max_b_t + energy.0
        }
        "transient" => {
            let mut d = dynamics();
            if !solve {
                return;
            }
            let options = TransientOptions::new(0.05, Scheme::Bdf2, TimeStep::Fixed { dt_s: 1e-4 });
            let result = d.transient(&options).expect("transient");
            assert_eq!(result.time_s.len(), 501);
            result.coils[0].flux_linkage_wb[500]
        }
        "harmonic" => {
            let mut d = dynamics();
            if !solve {
                return;
            }
            let frequencies: Vec<f64> = (0..31).map(|k| 10f64.powf(k as f64 / 10.0)).collect();
            let (potentials, _) = d
                .harmonic_potentials_by(&frequencies, None, HarmonicMethod::default())
                .expect("harmonic");
            potentials.len() as f64
        }
        "heat" | "heat-steady" => {
            let mut s = heat_solver();
            if !solve {
                return;
            }
            if workload == "heat-steady" {
                s.steady(None).expect("steady").0[0]
            } else {
                warmup(&mut s)
            }
        }
        "eddy" => {
            let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
                .join("../../examples/fem/eddy-cylinder/eddy-cylinder.toml");
            if !solve {
                return;
            }
            let (report, _, _) = mrbrake_magnetics::problem_file::solve_file(&path).expect("solve");
            let transient = report.dynamics.and_then(|d| d.transient).expect("a transient");
            transient.result.time_s.len() as f64
        }
        _ => {
            eprintln!("usage: workloads static|transient|harmonic|heat|heat-steady|eddy[-setup]");
            std::process::exit(2);
        }
    };
    println!("{name}: {value:.12e}");
}

/// The 2 h warm-up at 10 s steps from 25 °C; the final temperature of the first DOF.
fn warmup(s: &mut HeatSolver) -> f64 {
    let options = TimeOptions::new(7200.0, Scheme::Bdf2, TimeStep::Fixed { dt_s: 10.0 });
    let start = s.uniform(kelvin(25.0));
    let mut steps = 0;
    let outcome = s
        .transient(&start, &options, |e: &Event<'_, HeatSolver>| {
            steps = e.level.index;
            mrbrake_observe::Flow::Continue
        })
        .expect("transient");
    assert_eq!(steps, 720);
    outcome.u[0]
}
