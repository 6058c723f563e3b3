//! Printing helpers shared by the subcommands: the one text writer ([`print_text`]: every
//! command's text ends with exactly one newline), JSON to stdout ([`print_json`]), and the check
//! of plot paths. Commands print through these only, so none can end without a newline (the next
//! shell prompt would run into its last line) or with a blank line.

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
            mrbrake::report::plot_format::PlotFormat::from_path(path).context(flag.to_string())?;
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

/// Prints `value` as pretty JSON on stdout (one final newline, as [`print_text`]).
pub fn print_json<T: Serialize>(value: &T) -> CommandResult {
    write_line(&json_text(value)?)
}

/// Prints a command's text output on stdout, ending with exactly one newline whatever `text`
/// ends with (none, one or several); empty text prints nothing.
pub fn print_text(text: &str) -> CommandResult {
    let body = body_of(text);
    if body.is_empty() { Ok(()) } else { write_line(body) }
}

/// `text` without its trailing line ends: what [`print_text`] writes before its one newline.
fn body_of(text: &str) -> &str {
    text.trim_end_matches(['\n', '\r'])
}

/// Writes `line` and a newline to stdout. A closed pipe (`mrbrake … | head`) ends the output
/// quietly instead of panicking as `println!` would; another write error is an I/O error.
fn write_line(line: &str) -> CommandResult {
    let mut out = std::io::stdout().lock();
    match writeln!(out, "{line}").and_then(|()| out.flush()) {
        Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => Ok(()),
        other => Ok(other?),
    }
}

#[cfg(test)]
mod tests {
    use super::body_of;

    #[test]
    fn text_loses_its_trailing_line_ends_before_the_one_newline() {
        assert_eq!(body_of("a\nb"), "a\nb");
        assert_eq!(body_of("a\nb\n"), "a\nb");
        assert_eq!(body_of("a\n\n\n"), "a");
        assert_eq!(body_of("a\r\n"), "a");
        assert_eq!(body_of("\n"), "");
        assert_eq!(body_of("  indented\n"), "  indented");
    }
}
