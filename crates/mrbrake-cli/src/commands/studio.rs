//! `mrbrake studio`: placeholder until the server lands.

use clap::Args;

use crate::error::{CommandResult, InputError};

/// Arguments of `mrbrake studio`.
#[derive(Debug, Args)]
pub struct StudioArgs {}

/// Runs `mrbrake studio`.
pub fn run(_: StudioArgs) -> CommandResult {
    Err(InputError("not yet".into()).into())
}
