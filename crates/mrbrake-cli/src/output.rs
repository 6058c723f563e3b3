//! Printing helpers shared by the subcommands (JSON to stdout), and the check of plot paths.

use std::io::Write;
use std::path::Path;

use serde::Serialize;

use crate::error::{CommandResult, InternalError};

/// Refuses a plot path whose extension is not a supported picture format (`.svg`, `.png`), before
/// any work starts; the error names `flag`, the path and the supported extensions (exit code 2).
pub fn check_plot_path(flag: &str, path: Option<&Path>) -> CommandResult {
    use crate::error::Context;
    match path {
        Some(path) => {
            mrbrake_report::plot_format::PlotFormat::from_path(path).context(flag.to_string())?;
            Ok(())
        }
        None => Ok(()),
    }
}

/// `value` as pretty JSON text. Every result type serialises; a failure is a bug (internal).
pub fn json_text<T: Serialize>(value: &T) -> CommandResult<String> {
    serde_json::to_string_pretty(value)
        .map_err(|e| InternalError(format!("cannot write the result as JSON: {e}")).into())
}

/// Prints `value` as pretty JSON on stdout. A closed pipe (`mrbrake … --json | head`) ends the
/// output quietly instead of panicking as `println!` would.
pub fn print_json<T: Serialize>(value: &T) -> CommandResult {
    let text = json_text(value)?;
    let mut out = std::io::stdout().lock();
    match writeln!(out, "{text}").and_then(|()| out.flush()) {
        Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => Ok(()),
        other => Ok(other?),
    }
}

/// Writes formatted text to stdout; when the reader has gone (`mrbrake … | head`), exits quietly
/// with status 0 instead of panicking as `print!` does on a closed pipe.
pub fn write_stdout(args: std::fmt::Arguments<'_>) {
    let mut out = std::io::stdout().lock();
    if let Err(e) = out.write_fmt(args) {
        if e.kind() == std::io::ErrorKind::BrokenPipe {
            std::process::exit(0);
        }
        eprintln!("error: cannot write to stdout: {e}");
        std::process::exit(1);
    }
}

/// `println!` that ends quietly on a closed pipe (see [`write_stdout`]).
#[macro_export]
macro_rules! outln {
    () => { $crate::output::write_stdout(format_args!("\n")) };
    ($($arg:tt)*) => { $crate::output::write_stdout(format_args!("{}\n", format_args!($($arg)*))) };
}

/// `print!` that ends quietly on a closed pipe (see [`write_stdout`]).
#[macro_export]
macro_rules! out {
    ($($arg:tt)*) => { $crate::output::write_stdout(format_args!($($arg)*)) };
}
