//! The haptic wall on a brake model with a Preisach table (e.g. `mrbrake analyze --hysteresis
//! --save-model M.json`): the plant that runs the table against the clamp between its fitted
//! major-loop branches (the plant before issue 30 §3), each without and with the demagnetising
//! release of `mrbrake analyze --hysteresis --demag --json` (the README's figures).
//!
//! ```text
//! cargo run --release -p mrbrake-sim --example haptic_preisach -- M.json [DEMAG.json]
//!     [--stiffness 1000] [--only preisach|clamp]
//! ```
//!
//! `--only` runs one plant once, without the release and without recording (for an instruction
//! count: `valgrind --tool=callgrind --toggle-collect='*haptic*simulate*' …`).

use mrbrake_sim::brake_model::BrakeModel;
use mrbrake_sim::brake_model::apply::apply_to_haptic;
use mrbrake_sim::haptic::{
    DeviceKind, HapticConfig, PlantRemanence, RemanenceState, Scenario, Trace, simulate,
};

/// Brake 1's torque thresholds of the release table, N·m.
const THRESHOLDS_NM: [f64; 3] = [0.25, 0.2, 0.1];

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let flag = |name: &str| args.iter().position(|a| a == name).and_then(|k| args.get(k + 1));
    let positional: Vec<&String> = args
        .iter()
        .enumerate()
        .filter(|(k, a)| !a.starts_with("--") && (*k == 0 || !args[k - 1].starts_with("--")))
        .map(|(_, a)| a)
        .collect();
    let model_path = positional.first().ok_or("usage: haptic_preisach M.json [DEMAG.json]")?;
    let model = BrakeModel::read(std::path::Path::new(model_path.as_str()))?;
    let stiffness: f64 = flag("--stiffness").map_or(Ok(1000.0), |s| s.parse())?;
    let mut config = HapticConfig::new(DeviceKind::Bidirectional, Scenario::PressWithdraw);
    config.wall_stiffness_nm_per_rad = stiffness;
    apply_to_haptic(&model, &mut config)?;
    if config.brakes.iter().all(|b| b.preisach.is_none()) {
        return Err("the model has no Preisach table".into());
    }
    let mut clamp = config.clone();
    clamp.brakes.iter_mut().for_each(|b| b.preisach = None);
    if let Some(only) = flag("--only") {
        let chosen = if only == "clamp" { &clamp } else { &config };
        let run = simulate(chosen, false)?;
        println!("{only}: free-motion torque {:.6} N·m", run.metrics.free_motion_torque_nm);
        return Ok(());
    }
    let release = match positional.get(1) {
        Some(path) => Some(PlantRemanence::from_analysis_json(
            &std::fs::read_to_string(path.as_str())?,
            Some(5e-3),
        )?),
        None => None,
    };
    println!(
        "plant     release  drag after in/out [N·m]  free-motion [N·m]  release time [s]  brake 1 below {THRESHOLDS_NM:?} N·m after 0 A [ms]  turning points (max)"
    );
    for (name, base) in [("preisach", &config), ("clamp", &clamp)] {
        let mut cases = vec![(None, "none")];
        if let Some(r) = &release {
            // The clamp plant gets the remanence file's linear-in-peak remanence with the release
            // (the pre-Preisach plant); the Preisach plant the release alone (its table magnetises).
            cases.push((Some(*r), "pulse"));
            if name == "clamp" {
                cases.push((Some(PlantRemanence { release: None, ..*r }), "R0 only"));
            }
        }
        for (remanence, label) in cases {
            let mut c = base.clone();
            c.remanence = remanence;
            let run = simulate(&c, true)?;
            let m = &run.metrics;
            let trace = run.trace.as_ref().ok_or("no trace")?;
            println!(
                "{name:<9} {label:<8} {:.4} / {:.4}          {:.4}             {}            {:<40} {}",
                m.drag_after_nm.inward,
                m.drag_after_nm.outward,
                m.free_motion_torque_nm,
                m.release_time_s.map_or("never".into(), |t| format!("{t:.3}")),
                below_after_drop(trace),
                turning_points(&c, trace),
            );
        }
    }
    Ok(())
}

/// Milliseconds from brake 1's current reaching ≤ 0 after its peak to its torque capacity falling
/// below each threshold (`never` if it does not).
fn below_after_drop(trace: &Trace) -> String {
    let current = &trace.current_a[0];
    let peak = (0..current.len()).max_by(|&a, &b| current[a].total_cmp(&current[b])).unwrap_or(0);
    let Some(drop) = (peak..current.len()).find(|&k| current[k] <= 0.0) else {
        return "no drop".into();
    };
    let t0 = trace.time_s[drop];
    THRESHOLDS_NM
        .iter()
        .map(|&level| {
            (drop..current.len())
                .find(|&k| trace.capacity_nm[0][k] < level)
                .map_or("never".into(), |k| format!("{:.0}", 1e3 * (trace.time_s[k] - t0)))
        })
        .collect::<Vec<_>>()
        .join(" / ")
}

/// The largest number of turning points brake 1's Preisach memory held over the run (its
/// currents replayed through the plant; 0 for the clamp).
fn turning_points(config: &HapticConfig, trace: &Trace) -> usize {
    let brake = &config.brakes[0];
    let mut state = brake.rest_state();
    let mut remanence = RemanenceState::default();
    let mut most = 0;
    for &i in &trace.current_a[0] {
        match &config.remanence {
            Some(r) => r.apply_current(brake, &mut state, &mut remanence, i),
            None => brake.apply_current(&mut state, i),
        }
        most = most.max(state.preisach.as_ref().map_or(0, |p| p.turning_points().len()));
    }
    most
}
