//! `mrbrake studio [SPEC | --store STUDY.sqlite] [--port N] [--open]`: the local web
//! application of `mrbrake_studio`. The first line on stdout is its address with the session
//! token; it serves until interrupted (Ctrl-C ends it: the signal handler exits the process).

use std::net::IpAddr;
use std::path::PathBuf;

use clap::Args;
use mrbrake_studio::{Config, Studio};

use crate::error::{CommandResult, InputError};

/// Arguments of `mrbrake studio`.
#[derive(Debug, Args)]
pub struct StudioArgs {
    /// Brake specification (TOML) to start from (docs/reference/spec.md). Omitted: the embedded
    /// thesis bidirectional brake.
    #[arg(conflicts_with = "store")]
    spec: Option<PathBuf>,
    /// A results store (from `mrbrake optimize` or `sweep`) to explore: its Pareto front, a click
    /// loads a design into the editor.
    #[arg(long, value_name = "STUDY.sqlite")]
    store: Option<PathBuf>,
    /// The port (0 picks a free one).
    #[arg(long, default_value_t = 8421)]
    port: u16,
    /// Open the page in the default browser.
    #[arg(long)]
    open: bool,
    /// Serve on this address instead of 127.0.0.1. Anyone who can reach it and has the printed
    /// token can use the studio (and its CPU): only on a network you trust.
    #[arg(long, value_name = "ADDRESS")]
    bind: Option<IpAddr>,
}

/// Runs `mrbrake studio`.
pub fn run(a: StudioArgs) -> CommandResult {
    let mut config = Config { port: a.port, spec: a.spec, store: a.store, ..Config::default() };
    if let Some(address) = a.bind {
        if !address.is_loopback() {
            eprintln!(
                "warning: serving on {address}, not only this machine: anyone who can reach it \
                 and has the token can use the studio"
            );
        }
        config.bind = address;
    }
    let studio = Studio::start(config)?;
    crate::output::print_text(studio.url())?;
    eprintln!("mrbrake studio: open the address above in a browser; Ctrl-C stops it.");
    if a.open {
        open_browser(studio.url());
    }
    studio.wait();
    Err(InputError("the studio stopped".into()).into())
}

/// Asks the desktop to open `url` (xdg-open, open, start); a failure only leaves it to the user.
fn open_browser(url: &str) {
    let command = if cfg!(target_os = "macos") {
        ("open", vec![url.to_string()])
    } else if cfg!(windows) {
        ("cmd", vec!["/C".into(), "start".into(), String::new(), url.to_string()])
    } else {
        ("xdg-open", vec![url.to_string()])
    };
    if std::process::Command::new(command.0).args(&command.1).spawn().is_err() {
        eprintln!("note: could not open a browser; open the address yourself");
    }
}
