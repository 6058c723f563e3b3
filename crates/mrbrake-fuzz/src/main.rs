//! `mrbrake-fuzz`: runs the fuzz targets of [`mrbrake_fuzz`] for a time budget and reports, per
//! target, the executions, the corpus and outcomes found, crashes and slow inputs.
//!
//! ```text
//! mrbrake-fuzz [--seconds TOTAL] [--target NAME]... [--seed N] [--out DIR] [--slow-after S]
//! ```
//!
//! The time is shared equally among the targets. Each input is written to `DIR/current-<target>`
//! before it runs, so an abort (allocation failure) or a hang leaves its culprit on disk; crashes
//! and slow inputs are written to `DIR/crashes/` and `DIR/slow/`. Exit status 1 when any target
//! crashed or ran an input slower than `--slow-after` seconds, 2 for bad arguments.

use std::path::PathBuf;
use std::time::Duration;

use mrbrake_fuzz::{Budget, Report, fuzz, targets};

struct Args {
    seconds: f64,
    targets: Vec<String>,
    seed: u64,
    out: PathBuf,
    slow_after: f64,
}

fn parse_args() -> Result<Args, String> {
    let mut args = Args {
        seconds: 60.0,
        targets: Vec::new(),
        seed: 1,
        out: PathBuf::from("target/fuzz"),
        slow_after: 10.0,
    };
    let mut it = std::env::args().skip(1);
    while let Some(flag) = it.next() {
        let mut value = || it.next().ok_or_else(|| format!("{flag} needs a value"));
        match flag.as_str() {
            "--seconds" => {
                args.seconds = value()?.parse().map_err(|e| format!("--seconds: {e}"))?
            }
            "--target" => args.targets.push(value()?),
            "--seed" => args.seed = value()?.parse().map_err(|e| format!("--seed: {e}"))?,
            "--out" => args.out = PathBuf::from(value()?),
            "--slow-after" => {
                args.slow_after = value()?.parse().map_err(|e| format!("--slow-after: {e}"))?;
            }
            "--list" => {
                for t in targets() {
                    println!("{} ({} seeds)", t.name, t.seeds.len());
                }
                std::process::exit(0);
            }
            other => return Err(format!("unknown argument {other}")),
        }
    }
    if !(args.seconds > 0.0 && args.seconds.is_finite() && args.slow_after > 0.0) {
        return Err("--seconds and --slow-after must be positive".into());
    }
    Ok(args)
}

fn save(dir: &std::path::Path, name: &str, data: &[u8]) {
    let _ = std::fs::create_dir_all(dir);
    let _ = std::fs::write(dir.join(name), data);
}

fn print_report(r: &Report) {
    println!(
        "{:<22} {:>9} execs {:>7.1} s {:>8.0}/s  corpus {:>5}  outcomes {:>4}  crashes {}  slow {}",
        r.target,
        r.executions,
        r.seconds,
        r.executions as f64 / r.seconds.max(1e-9),
        r.corpus,
        r.outcomes,
        r.crashes.len(),
        r.slow.len()
    );
    for c in &r.crashes {
        println!("    crash: {}", c.message.lines().next().unwrap_or_default());
    }
}

fn main() {
    let args = parse_args().unwrap_or_else(|e| {
        eprintln!("mrbrake-fuzz: {e}");
        std::process::exit(2);
    });
    // Panics are the findings: keep their messages out of the output (they are reported).
    std::panic::set_hook(Box::new(|_| {}));
    let all = targets();
    let chosen: Vec<_> = all
        .iter()
        .filter(|t| args.targets.is_empty() || args.targets.iter().any(|n| n == t.name))
        .collect();
    if chosen.is_empty() {
        eprintln!("mrbrake-fuzz: no such target; --list shows them");
        std::process::exit(2);
    }
    let share = Duration::from_secs_f64(args.seconds / chosen.len() as f64);
    let mut failed = false;
    for (k, target) in chosen.iter().enumerate() {
        let budget = Budget {
            time: share,
            max_executions: u64::MAX,
            slow_after: Duration::from_secs_f64(args.slow_after),
            seed: args.seed.wrapping_add(k as u64),
        };
        let current = args.out.join(format!("current-{}", target.name));
        let _ = std::fs::create_dir_all(&args.out);
        let report = fuzz(target, budget, |input| {
            let _ = std::fs::write(&current, input);
        });
        print_report(&report);
        for (i, c) in report.crashes.iter().enumerate() {
            save(&args.out.join("crashes"), &format!("{}-{i}", target.name), &c.input);
        }
        for (i, (input, _)) in report.slow.iter().enumerate() {
            save(&args.out.join("slow"), &format!("{}-{i}", target.name), input);
        }
        failed |= !report.crashes.is_empty() || !report.slow.is_empty();
    }
    std::process::exit(i32::from(failed));
}
