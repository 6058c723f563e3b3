//! `mrbrake`: design, simulate and characterise magnetorheological fluid brakes.
//!
//! The binary is glue: it parses arguments (clap), calls the library crates and prints. No numerics
//! live here. Errors are printed with their whole chain; bad input exits with code 2, numerical
//! failure with code 1.

mod commands;
mod error;
mod output;
mod progress;
mod signals;

use clap::Parser;

/// Design, simulate and characterise magnetorheological (MR) fluid brakes for haptic devices.
#[derive(Debug, Parser)]
#[command(
    name = "mrbrake",
    version,
    about = "Design, simulate and characterise magnetorheological (MR) fluid brakes for haptic devices.",
    propagate_version = true
)]
struct Cli {
    #[command(subcommand)]
    command: commands::Command,
}

fn main() {
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => {
            // clap prints help/version to stdout with exit 0 and usage errors to stderr with exit 2.
            e.exit();
        }
    };
    signals::install();
    match commands::run(cli.command) {
        Ok(()) => {}
        Err(err) => {
            eprintln!("error: {err}");
            std::process::exit(err.exit_code());
        }
    }
}
