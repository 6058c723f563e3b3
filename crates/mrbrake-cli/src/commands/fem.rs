//! `mrbrake fem solve PROBLEM.toml [--order 1|2] [--json] [--vtu out.vtu] [--plot out.svg]`:
//! axisymmetric non-linear magnetostatics driven by a problem file (see
//! `mrbrake_magnetics::problem_file`).

use std::path::PathBuf;

use clap::{Args, Subcommand};
use mrbrake_magnetics::ElementOrder;
use mrbrake_magnetics::problem_file::{solve_file_with_order, vtu_files};
use mrbrake_report::field_map::{FieldMap, View, save_field_map};

use crate::error::CommandResult;
use crate::output::print_json;

/// `mrbrake fem ...` subcommands.
#[derive(Debug, Subcommand)]
pub enum FemCommand {
    /// Solve a magnetostatic problem file (mesh, materials, sources, boundaries, probes).
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
    #[arg(long, value_name = "1|2", value_parser = clap::value_parser!(u8).range(1..=2))]
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
    let order = args
        .order
        .map(|degree| ElementOrder::from_degree(degree.into()).expect("clap accepts only 1 and 2"));
    // `physics = "heat"` files go to the heat solver; every other file is magnetostatic.
    if super::fem_heat::is_heat(&args.problem) {
        let (vtu, plot) = (args.vtu.as_deref(), args.plot.as_deref());
        return super::fem_heat::solve(&args.problem, order, args.json, vtu, plot);
    }
    let (report, solver, solution) = solve_file_with_order(&args.problem, order)?;
    if let Some(path) = &args.vtu {
        // The static field, a transient's chosen instants or a harmonic solve's phasors.
        for (file, text) in vtu_files(&report, &solver, &solution, path) {
            mrbrake_report::write_atomic(&file, text.as_bytes())?;
        }
    }
    if args.plot.is_some() {
        let field = solver.field_snapshot(&solution);
        if let Some(path) = &args.plot {
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
                b_abs_t: &field.element_b_abs_t,
                flux_function: &field.flux_function_wb,
                flux_lines: args.flux_lines,
                regions: &[],
                view: View::Whole,
            };
            save_field_map(&map, path)?;
        }
    }
    if args.json {
        return print_json(&report);
    }
    crate::out!("{}", report.text(&args.problem.display().to_string()));
    Ok(())
}
