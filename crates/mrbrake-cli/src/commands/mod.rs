//! One module per subcommand; each defines its clap arguments and a `run` function.

use clap::Subcommand;

/// The subcommands of `mrbrake`.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Print the mrbrake version and the crates it is built from.
    Version,
}

/// Runs one subcommand.
pub fn run(command: Command) -> anyhow::Result<()> {
    match command {
        Command::Version => {
            println!("mrbrake {}", env!("CARGO_PKG_VERSION"));
            Ok(())
        }
    }
}
