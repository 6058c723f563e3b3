//! Torque tracking on the virtual rig with the Preisach brake: the polynomial-branch inverse of the
//! thesis (§5.3.2) against the operator inverse (modified Prandtl–Ishlinskii), RMSE (5.2).
//!
//! Identification and scoring use different logs:
//! - branches: `characterization.csv` of `mrbrake rig characterize` (full ramps, noise seed 1),
//!   quintic fits as in the thesis;
//! - operators: `minor_loops.csv` of `mrbrake rig minor-loops` (FORCs and decaying triangles, seed 1),
//!   12 plays and 12 output segments;
//! - scoring: the logs of `mrbrake rig track` (fresh runs, noise seeds 102…105), demands (a) a
//!   0.5–3.5 N·m sinusoid at 0.1 rad/s (the thesis's Fig. 5.8: 3.54 % and 3.07 % measured), (b) 50 %
//!   and 25 % of that range about 2 N·m, (c) a band-limited random demand (random-phase multisine,
//!   0.1–2 rad/s) over 0.5–3.5 N·m ([`mrbrake_sim::rig::tracking::tracking_suite`]).
//!
//! Run: `cargo run --release -p mrbrake-sim --example hysteresis_tracking`.

use mrbrake_control::TorqueInverse;
use mrbrake_sim::rig::preisach::HysteresisKind;
use mrbrake_sim::rig::tracking::tracking_logs;
use mrbrake_sim::rig::{RigConfig, characterization_samples, minor_loops::minor_loop_samples};
use mrbrake_sysid::characterize::{CharacterizeOptions, characterize};
use mrbrake_sysid::operator_fit::{OperatorOptions, fit_operator_model};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut config = RigConfig::default();
    config.hysteresis.model = HysteresisKind::Preisach;

    let ramps = characterization_samples(&config)?;
    let (i, t): (Vec<f64>, Vec<f64>) = ramps.iter().map(|s| (s[1], s[2])).unzip();
    let branches = characterize(&i, &t, CharacterizeOptions::default())?.model()?;
    let (loops, _) = minor_loop_samples(&config)?;
    let (i, t): (Vec<f64>, Vec<f64>) = loops.iter().map(|s| (s[1], s[2])).unzip();
    let fit = fit_operator_model(&i, &t, OperatorOptions { plays: 12, segments: 12 })?;
    println!(
        "operator model on minor_loops.csv: RMSE {:.4} N·m, fit {:.2} %, {} inner reversals",
        fit.fit.rmse_nm, fit.fit.fit_percent, fit.fit.inner_reversals
    );
    let inverses =
        [("branches", TorqueInverse::Branches(branches)), ("operators", fit.model.0.into())];

    let scores: Vec<_> = inverses
        .iter()
        .map(|(_, inverse)| tracking_logs(&config, inverse).map(|(_, scores)| scores))
        .collect::<Result<_, _>>()?;
    println!("| demand (scoring log) | branch inverse RMSE | operator inverse RMSE |");
    println!("|---|---|---|");
    for (b, o) in scores[0].iter().zip(&scores[1]) {
        for s in [b, o] {
            // Sane bounds, not tuned numbers: finite, and well below the demand's own range.
            let p = s.rmse_percent_of_range;
            assert!(s.rmse_nm.is_finite() && p > 0.0 && p < 25.0, "{}: {p} %", s.demand);
        }
        println!(
            "| {} (`{}`) | {:.2} % ({:.4} N·m) | {:.2} % ({:.4} N·m) |",
            b.demand,
            b.file,
            b.rmse_percent_of_range,
            b.rmse_nm,
            o.rmse_percent_of_range,
            o.rmse_nm
        );
    }
    Ok(())
}
