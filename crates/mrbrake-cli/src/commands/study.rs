//! `mrbrake study …`: design studies. `thesis-tables` re-runs the thesis's comparison Tables 4.1–4.4
//! on mrbrake's own geometries and prints each beside the thesis's values.

use clap::{Args, Subcommand};
use mrbrake::design::analysis::AnalysisOptions;
use mrbrake::design::mesh_build::MeshLevel;
use mrbrake::design::study;
use mrbrake::report::study::thesis_tables_text;

use crate::error::CommandResult;
use crate::output::{print_json, print_text};

/// `mrbrake study` subcommands.
#[derive(Debug, Subcommand)]
pub enum StudyCommand {
    /// Tables 4.1–4.4 of the thesis (disc thickness, gap width, coil location, configurations) on
    /// mrbrake's geometries (base design: examples/specs/study-single-disc.toml).
    ThesisTables(ThesisTablesArgs),
}

/// Arguments of `study thesis-tables`.
#[derive(Debug, Args)]
pub struct ThesisTablesArgs {
    /// Mesh density: coarse, default or fine.
    #[arg(long, default_value = "default")]
    mesh: String,
    /// Print a JSON array of tables instead of text.
    #[arg(long)]
    json: bool,
}

/// Runs `mrbrake study …`.
pub fn run(command: StudyCommand) -> CommandResult {
    match command {
        StudyCommand::ThesisTables(a) => {
            let options = AnalysisOptions {
                mesh: MeshLevel::parse(&a.mesh).map_err(super::field_flags::design)?,
                ..AnalysisOptions::default()
            };
            let tables = study::thesis_tables(&options)?;
            if a.json {
                return print_json(&tables);
            }
            print_text(&thesis_tables_text(&tables))
        }
    }
}
