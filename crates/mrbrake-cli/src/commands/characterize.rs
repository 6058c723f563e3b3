//! `mrbrake characterize LOG.csv`: hysteresis branches, inverse model and loop figures from a
//! repeated-ramp test-rig log (thesis §5.3.1).

use std::path::PathBuf;

use clap::Args;
use mrbrake_report::hysteresis::{HysteresisPlot, save_hysteresis};
use mrbrake_sysid::characterize::{CharacterizeOptions, characterize};
use mrbrake_sysid::log::read_log;
use mrbrake_sysid::polynomial::Polynomial;
use serde_json::json;

use crate::exit::InputError;
use crate::output::print_json;

/// Arguments of `mrbrake characterize`.
#[derive(Debug, Args)]
pub struct CharacterizeArgs {
    /// Log file (CSV with a header row) of the repeated current ramps.
    log: PathBuf,
    /// Polynomial order of each branch (the thesis uses 5).
    #[arg(long, default_value_t = 5)]
    order: usize,
    /// Number of current bins used to average the repetitions.
    #[arg(long, default_value_t = 200)]
    bins: usize,
    /// Name of the time column (seconds).
    #[arg(long, default_value = "time_s")]
    time_col: String,
    /// Name of the current column (amperes).
    #[arg(long, default_value = "current_A")]
    current_col: String,
    /// Name of the torque column (newton-metres).
    #[arg(long, default_value = "torque_Nm")]
    torque_col: String,
    /// Write the model (branches and current range; the controller's inverse-model file) as JSON here.
    #[arg(long, value_name = "FILE.json")]
    save_model: Option<PathBuf>,
    /// Draw the hysteresis loop (SVG, or PNG for a .png name).
    #[arg(long, value_name = "FILE.svg")]
    plot: Option<PathBuf>,
    /// Print a JSON object instead of text.
    #[arg(long)]
    json: bool,
}

/// Runs `mrbrake characterize`.
pub fn run(args: CharacterizeArgs) -> anyhow::Result<()> {
    if args.order == 0 || args.order > 12 {
        return Err(InputError(format!("--order {} is outside 1..=12", args.order)).into());
    }
    let log = read_log(
        &args.log,
        &args.time_col,
        &[&args.current_col, &args.torque_col],
        2 * (args.order + 1),
    )?;
    let (current, torque) = (&log.channels[0], &log.channels[1]);
    let c =
        characterize(current, torque, CharacterizeOptions { order: args.order, bins: args.bins })?;
    // The characterisation's own fields at the top level (as in the model file), plus the log's.
    let mut report = serde_json::to_value(&c)?;
    if let Some(map) = report.as_object_mut() {
        map.insert("log".into(), json!(args.log));
        map.insert("samples".into(), json!(log.len()));
        map.insert("sample_rate_Hz".into(), json!(log.mean_sample_rate_hz()));
    }
    if let Some(path) = &args.save_model {
        let text = serde_json::to_string_pretty(&c)?;
        mrbrake_report::write_atomic(path, text.as_bytes())?;
    }
    if let Some(path) = &args.plot {
        let grid = |coefficients: &[f64]| {
            let p = Polynomial::new(coefficients.to_vec());
            (0..=200)
                .map(|k| {
                    let i =
                        c.current_min_a + (c.current_max_a - c.current_min_a) * k as f64 / 200.0;
                    (i, p.eval(i))
                })
                .collect::<Vec<_>>()
        };
        let data = HysteresisPlot {
            raw: current.iter().copied().zip(torque.iter().copied()).collect(),
            rising_mean: c.rising_mean.clone(),
            falling_mean: c.falling_mean.clone(),
            rising_fit: grid(&c.rising.coefficients),
            falling_fit: grid(&c.falling.coefficients),
        };
        save_hysteresis(
            path,
            &format!("Torque–current loop ({} repetitions)", c.repetitions),
            &data,
        )?;
    }
    if args.json {
        return print_json(&report);
    }
    crate::outln!(
        "log: {} ({} samples, {:.1} Hz)",
        args.log.display(),
        log.len(),
        log.mean_sample_rate_hz()
    );
    crate::outln!("repetitions: {}", c.repetitions);
    crate::outln!("current range: {:.4} .. {:.4} A", c.current_min_a, c.current_max_a);
    for (name, b) in [("rising", &c.rising), ("falling", &c.falling)] {
        let coeffs: Vec<String> = b.coefficients.iter().map(|v| format!("{v:.6e}")).collect();
        crate::outln!("{name:8} T(I) = [{}] (ascending powers of I in A, N·m)", coeffs.join(", "));
        crate::outln!(
            "{:8} fit {:.2} % (raw samples), {:.2} % (averaged)",
            "",
            b.fit_percent,
            b.fit_percent_mean
        );
    }
    crate::outln!("off-state torque: {:.4} N·m", c.off_state_torque_nm);
    crate::outln!("max torque: {:.4} N·m", c.max_torque_nm);
    crate::outln!(
        "max hysteresis: {:.4} N·m at {:.3} A",
        c.max_hysteresis_nm,
        c.max_hysteresis_current_a
    );
    Ok(())
}
