//! `mrbrake study …`: design studies. `thesis-tables` re-runs the thesis's comparison Tables 4.1–4.4
//! on mrbrake's own geometries and prints each beside the thesis's values.

use clap::{Args, Subcommand};
use mrbrake_design::analysis::AnalysisOptions;
use mrbrake_design::mesh_build::MeshLevel;
use mrbrake_design::study;

use crate::output::print_json;

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
pub fn run(command: StudyCommand) -> anyhow::Result<()> {
    match command {
        StudyCommand::ThesisTables(a) => {
            let options =
                AnalysisOptions { mesh: MeshLevel::parse(&a.mesh)?, ..AnalysisOptions::default() };
            let tables = study::thesis_tables(&options)?;
            if a.json {
                return print_json(&tables);
            }
            for t in &tables {
                crate::outln!("{}: {} — ours | thesis", t.table, t.title);
                crate::outln!(
                    "  {:<32} {:>8} {:>10} {:>10} {:>10} | {:>8} {:>10} {:>8}",
                    "",
                    "B [T]",
                    "tau [kPa]",
                    "T mean-B",
                    "T local",
                    "B [T]",
                    "tau [kPa]",
                    "T [N·m]"
                );
                for r in &t.rows {
                    crate::outln!(
                        "  {:<32} {:>8.4} {:>10.3} {:>10.3} {:>10.3} | {:>8.4} {:>10.4} {:>8.2}",
                        r.label,
                        r.mean_b_t,
                        r.tau_y_kpa,
                        r.thesis_method_nm,
                        r.local_nm,
                        r.thesis_b_t,
                        r.thesis_tau_y_kpa,
                        r.thesis_torque_nm
                    );
                }
                crate::outln!();
            }
            Ok(())
        }
    }
}
