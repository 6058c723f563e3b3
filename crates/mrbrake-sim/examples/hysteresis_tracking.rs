//! Torque tracking on the virtual rig with the Preisach brake: the polynomial-branch inverse of the
//! thesis (§5.3.2) against the operator inverse (modified Prandtl–Ishlinskii), RMSE (5.2).
//!
//! Identification and scoring use different logs:
//! - branches: `characterization.csv` of `mrbrake rig characterize` (full ramps, noise seed 1),
//!   quintic fits as in the thesis;
//! - operators: `minor_loops.csv` of `mrbrake rig minor-loops` (FORCs and decaying triangles, seed 1),
//!   12 plays and 12 output segments;
//! - scoring: fresh tracking runs with noise seeds 101…, demands (a) 0.5–3.5 N·m sinusoid at 0.1 rad/s
//!   (the thesis's Fig. 5.8: 3.54 % and 3.07 % measured), (b) 50 % and 25 % of that range about
//!   2 N·m, (c) a band-limited random demand (random-phase multisine, 0.1–2 rad/s) over 0.5–3.5 N·m.
//!
//! Run: `cargo run --release -p mrbrake-sim --example hysteresis_tracking`.

use mrbrake_control::TorqueInverse;
use mrbrake_sim::rig::preisach::HysteresisKind;
use mrbrake_sim::rig::tracking::{Demand, track};
use mrbrake_sim::rig::{RigConfig, characterization_samples, minor_loops::minor_loop_samples};
use mrbrake_sysid::characterize::{CharacterizeOptions, characterize};
use mrbrake_sysid::operator_fit::{OperatorOptions, fit_operator_model};
use mrbrake_sysid::tracking::tracking_error;

/// (RMSE N·m, RMSE % of the demand's range) over the samples after `skip_s`.
fn score(samples: &[[f64; 4]], skip_s: f64) -> (f64, f64) {
    let kept: Vec<&[f64; 4]> = samples.iter().filter(|s| s[0] >= skip_s).collect();
    let demand: Vec<f64> = kept.iter().map(|s| s[1]).collect();
    let measured: Vec<f64> = kept.iter().map(|s| s[2]).collect();
    let e = tracking_error(&demand, &measured).expect("equal, non-empty signals");
    (e.rmse_nm, e.rmse_percent_of_range)
}

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

    let period = 2.0 * std::f64::consts::PI / 0.1;
    let sine = |amplitude_nm| Demand::Sine { mid_nm: 2.0, amplitude_nm, omega_rad_s: 0.1 };
    let random = Demand::band_limited(2.0, 1.5, (0.1, 2.0), 16, 120.0, 7);
    let cases = [
        ("(a) full range 0.5–3.5 N·m, 0.1 rad/s", sine(1.5), 1.25 * period, 0.25 * period),
        ("(b) 50 % of range about 2 N·m, 0.1 rad/s", sine(0.75), 1.25 * period, 0.25 * period),
        ("(b) 25 % of range about 2 N·m, 0.1 rad/s", sine(0.375), 1.25 * period, 0.25 * period),
        ("(c) band-limited random 0.5–3.5 N·m, 0.1–2 rad/s", random, 120.0, 5.0),
    ];
    println!("| demand | branch inverse RMSE | operator inverse RMSE |");
    println!("|---|---|---|");
    for (k, (name, demand, duration, skip)) in cases.iter().enumerate() {
        let mut cells = Vec::new();
        for (_, inverse) in &inverses {
            let run = track(&config, demand, *duration, inverse, 101 + k as u64)?;
            let (nm, percent) = score(&run, *skip);
            // Sane bounds, not tuned numbers: finite, and well below the demand's own range.
            assert!(nm.is_finite() && percent > 0.0 && percent < 25.0, "{name}: {percent} %");
            cells.push(format!("{percent:.2} % ({nm:.4} N·m)"));
        }
        println!("| {name} | {} | {} |", cells[0], cells[1]);
    }
    Ok(())
}
