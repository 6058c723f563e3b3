//! `mrbrake fem solve PROBLEM.toml [--order 1|2] [--json] [--vtu out.vtu] [--plot out.svg]`:
//! axisymmetric non-linear magnetostatics driven by a problem file (see
//! `mrbrake::magnetics::problem_file`).

use std::path::PathBuf;

use clap::{Args, Subcommand};
use mrbrake::problem_file::{self, Physics};
use mrbrake::report::field_map::{FieldMap, View, save_field_map};

use crate::error::{CommandResult, InputError};
use crate::output::{print_json, print_text};

/// `mrbrake fem ...` subcommands.
#[derive(Debug, Subcommand)]
pub enum FemCommand {
    /// Solve a problem file: magnetostatic (mesh, materials, sources, boundaries, probes), its
    /// transient or harmonic magnetodynamics, or `physics = "heat"`.
    Solve(SolveArgs),
}

/// Arguments of `mrbrake fem solve`.
#[derive(Debug, Args)]
pub struct SolveArgs {
    /// Problem file (TOML): `mesh = "file.msh"`, `[[region]]`, `[[boundary]]`, `[[probe]]`, `[[line]]`
    /// (every key: docs/reference/magnetics.md and heat.md, or `mrbrake schema magnetics|heat`).
    problem: PathBuf,
    /// Element order: 1 (linear triangles) or 2 (quadratic, 6-node triangles on the same mesh);
    /// overrides the problem file's `order` key (default 1).
    #[arg(long, value_name = "1|2")]
    order: Option<u8>,
    /// Print a JSON object (probes, regions, coils, energy_J, newton_iterations, converged, nodes,
    /// elements, order, unknowns, timings_s) instead of text.
    #[arg(long)]
    json: bool,
    /// Write the field (A_phi and r·A_phi at the mesh nodes, B at the triangle centroids, |B|,
    /// region) as a ParaView .vtu file; for a `[transient]`, at its `vtu_times` (default the final
    /// state; several instants go to FILE_000.vtu, … with a FILE.pvd collection); for a
    /// `[harmonic]`, the phasors (re, im) at its `vtu_frequencies_Hz` (default every frequency;
    /// the .pvd's time steps are the frequencies in Hz).
    #[arg(long, value_name = "FILE.vtu")]
    vtu: Option<PathBuf>,
    /// Draw the |B| map with flux lines (.svg or .png).
    #[arg(long, value_name = "FILE.svg")]
    plot: Option<PathBuf>,
    /// Number of flux lines in the plot.
    #[arg(long, default_value_t = 24)]
    flux_lines: usize,
}

/// Runs `mrbrake fem ...`.
pub fn run(command: FemCommand) -> CommandResult {
    match command {
        FemCommand::Solve(args) => solve(args),
    }
}

fn solve(args: SolveArgs) -> CommandResult {
    crate::output::check_plot_path("--plot", args.plot.as_deref())?;
    let order = args.order.map(super::field_flags::order).transpose()?;
    // The library reads the file's physics and solves it; a plot (|B| and flux lines) only has a
    // meaning for a magnetic file, so a heat file's --plot is refused before the solve.
    if args.plot.is_some() {
        let settings = mrbrake::error::read::SETTINGS;
        let text = mrbrake::error::read::text(&args.problem, settings).unwrap_or_default();
        if problem_file::physics_of(&text, &args.problem)? == Physics::Heat {
            return Err(InputError(
                "--plot draws |B| maps of magnetostatic files; for a heat file use --vtu".into(),
            )
            .into());
        }
    }
    let solved = problem_file::solve(&args.problem, order)?;
    if let Some(path) = &args.vtu {
        // The static field, a transient's chosen instants, a harmonic solve's phasors, or the
        // temperature of a heat file.
        for (file, text) in solved.vtu_files(path) {
            mrbrake::report::write_atomic(&file, text.as_bytes())?;
        }
    }
    if let Some(path) = &args.plot {
        let field = solved.field();
        // The problem's name (its file name without the folder), not a path.
        let name = args.problem.file_stem().map_or_else(
            || args.problem.display().to_string(),
            |s| s.to_string_lossy().into_owned(),
        );
        let title = format!("{name}: |B| and flux lines");
        let map = FieldMap {
            title: &title,
            nodes: &field.nodes,
            triangles: &field.triangles,
            region_tags: &field.region_tags,
            b_abs_t: &field.values,
            flux_function: field.flux_function_wb.as_deref().unwrap_or_default(),
            flux_lines: args.flux_lines,
            regions: &[],
            view: View::Whole,
        };
        save_field_map(&map, path)?;
    }
    if args.json {
        return print_json(&solved.report());
    }
    print_text(&solved.text(&args.problem.display().to_string()))
}
