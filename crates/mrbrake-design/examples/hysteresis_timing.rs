//! Times the quasi-static hysteretic solves of the thesis brake (the default spec, default mesh):
//! the predicted loop of `mrbrake_design::hysteresis` (7 legs of `points` currents) and the FORC
//! set of `mrbrake_design::forc` (11 levels, 2 steps per level), with their work counts (Newton
//! iterations, numeric factorisations) and the loop's figures, so that a change of the solver can
//! be judged on time, work and answers at once.
//!
//! Issue 30's targets: the loop (≥ 40 currents per branch) ≤ 10 s on one core, the FORC set
//! ≤ 60 s on two:
//!
//! ```text
//! RAYON_NUM_THREADS=1 taskset -c 0 cargo run --release -p mrbrake-design --example hysteresis_timing -- loop 40
//! RAYON_NUM_THREADS=2 cargo run --release -p mrbrake-design --example hysteresis_timing -- forc
//! ```
//!
//! Instructions (repeatable on a shared machine): `valgrind --tool=callgrind` on the built example
//! (`target/release/examples/hysteresis_timing loop 8`).

use std::time::Instant;

use mrbrake_design::analysis::AnalysisOptions;
use mrbrake_design::forc::{self, ForcOptions};
use mrbrake_design::hysteresis::{self, LoopOptions};
use mrbrake_design::spec::default_spec;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let what = args.first().map_or("loop", String::as_str);
    let points = match args.get(1) {
        Some(p) => p.parse()?,
        None => hysteresis::DEFAULT_POINTS_PER_LEG,
    };
    let spec = default_spec();
    let options = AnalysisOptions::default();
    if what == "loop" || what == "both" {
        let start = Instant::now();
        let loop_options = LoopOptions { peak_current_a: None, points_per_leg: points };
        let predicted = hysteresis::run(&spec, &options, &loop_options)?;
        let iterations: usize = predicted.path.iter().map(|p| p.newton_iterations).sum();
        let factorizations: usize = predicted.path.iter().map(|p| p.factorizations).sum();
        println!(
            "loop: {} solves, {iterations} Newton iterations, {factorizations} factorisations, \
             {:.2} s (set-up {:.2} s, solves {:.2} s); remanent torque {:.12} N·m, width at mid \
             current {:.12} N·m (bipolar {:.12} N·m), dissipated per bipolar cycle {:.12e} J",
            predicted.path.len() - 1,
            start.elapsed().as_secs_f64(),
            predicted.timings_s.setup,
            predicted.timings_s.solve,
            predicted.remanent_torque_nm,
            predicted.width_at_mid_current_nm,
            predicted.bipolar_width_at_mid_current_nm,
            predicted.dissipated_per_bipolar_cycle_j,
        );
    }
    if what == "forc" || what == "both" {
        let set = forc::run(&spec, &options, &ForcOptions::default())?;
        println!(
            "forc: {} solves in {} chains, {} Newton iterations, {} factorisations, {:.2} s wall \
             ({:.2} s summed over the chains); wiping-out defect {:.12e} N·m, rising at I_max \
             {:.12} N·m",
            set.solves,
            set.chains,
            set.work.newton_iterations,
            set.work.factorizations,
            set.timings_s.wall,
            set.timings_s.chains,
            set.wiping_out_defect_nm,
            set.rising_nm.last().copied().unwrap_or(f64::NAN),
        );
    }
    Ok(())
}
