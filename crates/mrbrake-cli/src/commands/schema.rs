//! `mrbrake schema FORMAT [--markdown]`: the JSON Schema of an input format (spec, magnetics, heat,
//! study), or its reference page; both are composed by `mrbrake_report::reference` from the schema
//! the format's reader uses, and kept in `docs/reference/`.

use clap::{Args, ValueEnum};
use mrbrake::report::reference::Format;

use crate::error::CommandResult;

/// The formats `mrbrake schema` describes.
#[derive(Debug, Clone, Copy, ValueEnum)]
pub enum FormatName {
    /// The brake spec (analyze, report, response, thermal, sweep, optimize, studio).
    Spec,
    /// A magnetic problem file of `fem solve` ([transient] and [harmonic] included).
    Magnetics,
    /// A heat problem file of `fem solve` (physics = "heat").
    Heat,
    /// An optimisation problem of `optimize`.
    Study,
}

/// Arguments of `mrbrake schema`.
#[derive(Debug, Args)]
pub struct SchemaArgs {
    /// The input format.
    format: FormatName,
    /// Print the reference page (Markdown) instead of the JSON Schema.
    #[arg(long)]
    markdown: bool,
}

/// Runs `mrbrake schema`.
pub fn run(a: SchemaArgs) -> CommandResult {
    let format = match a.format {
        FormatName::Spec => Format::Spec,
        FormatName::Magnetics => Format::Magnetics,
        FormatName::Heat => Format::Heat,
        FormatName::Study => Format::Study,
    };
    let text = if a.markdown { format.markdown() } else { format.schema_text() };
    crate::output::print_text(&text)
}
