//! `mrbrake fem solve PROBLEM.toml [--order 1|2] [--json] [--vtu out.vtu] [--plot out.svg]`:
//! axisymmetric non-linear magnetostatics driven by a problem file (see
//! `mrbrake_magnetics::problem_file`).

use std::path::PathBuf;

use clap::{Args, Subcommand};
use mrbrake_fem::vtu::{Field, to_vtu};
use mrbrake_magnetics::ElementOrder;
use mrbrake_magnetics::problem_file::solve_file_with_order;
use mrbrake_report::field_map::{FieldMap, save_field_map};

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
    /// Problem file (TOML): `mesh = "file.msh"`, `[[region]]`, `[[boundary]]`, `[[probe]]`, `[[line]]`.
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
    /// region) as a ParaView .vtu file.
    #[arg(long, value_name = "FILE.vtu")]
    vtu: Option<PathBuf>,
    /// Draw the |B| map with flux lines (SVG, or PNG for a .png name).
    #[arg(long, value_name = "FILE.svg")]
    plot: Option<PathBuf>,
    /// Number of flux lines in the plot.
    #[arg(long, default_value_t = 24)]
    flux_lines: usize,
}

/// Runs `mrbrake fem ...`.
pub fn run(command: FemCommand) -> anyhow::Result<()> {
    match command {
        FemCommand::Solve(args) => solve(args),
    }
}

fn solve(args: SolveArgs) -> anyhow::Result<()> {
    let order = args
        .order
        .map(|degree| ElementOrder::from_degree(degree.into()).expect("clap accepts only 1 and 2"));
    let (report, solver, solution) = solve_file_with_order(&args.problem, order)?;
    let mesh = solver.mesh();
    let need_fields = args.vtu.is_some() || args.plot.is_some();
    let (element_b, b_abs, flux_function) = if need_fields {
        let element_b = solver.element_b(&solution);
        let b_abs: Vec<f64> = element_b.iter().map(|b| b[0].hypot(b[1])).collect();
        (element_b, b_abs, solver.flux_function(&solution))
    } else {
        (Vec::new(), Vec::new(), Vec::new())
    };
    if let Some(path) = &args.vtu {
        let b3: Vec<f64> = element_b.iter().flat_map(|b| [b[0], b[1], 0.0]).collect();
        let text = to_vtu(
            mesh,
            &[
                Field { name: "A_phi_Wb_per_m", components: 1, values: solution.vertex_a_phi() },
                Field { name: "flux_function_r_A_phi", components: 1, values: &flux_function },
            ],
            &[
                Field { name: "B_T", components: 3, values: &b3 },
                Field { name: "B_abs_T", components: 1, values: &b_abs },
            ],
        );
        mrbrake_report::write_atomic(path, text.as_bytes())?;
    }
    if let Some(path) = &args.plot {
        let title = format!("|B| and flux lines: {}", args.problem.display());
        let map = FieldMap {
            title: &title,
            nodes: &mesh.nodes,
            triangles: &mesh.triangles,
            region_tags: &mesh.triangle_tags,
            b_abs_t: &b_abs,
            flux_function: &flux_function,
            flux_lines: args.flux_lines,
        };
        save_field_map(&map, path)?;
    }
    if args.json {
        return print_json(&report);
    }
    crate::outln!(
        "{}: {} nodes, {} triangles, {} unknowns (P{}); Newton {} iteration(s), converged: {}",
        args.problem.display(),
        report.nodes,
        report.elements,
        report.unknowns,
        report.order,
        report.newton_iterations,
        report.converged
    );
    for p in &report.probes {
        crate::outln!(
            "  probe {:<16} r = {:>9.4} mm  z = {:>9.4} mm  B_r = {:>9.5} T  B_z = {:>9.5} T  |B| = {:.5} T",
            p.name,
            p.r * 1e3,
            p.z * 1e3,
            p.b_r_t,
            p.b_z_t,
            p.b_abs_t
        );
    }
    for r in &report.regions {
        crate::outln!(
            "  region {:>4}: area {:.4e} m²  mean |B| {:.4} T  max |B| {:.4} T",
            r.physical,
            r.area_m2,
            r.mean_b_t,
            r.max_b_t
        );
    }
    for c in &report.coils {
        crate::outln!(
            "  coil {:>4}: flux linkage {:.5e} Wb  L = {:.5e} H  dλ/dI = {:.5e} H",
            c.physical,
            c.flux_linkage_wb,
            c.inductance_h,
            c.incremental_inductance_h
        );
    }
    for l in &report.lines {
        crate::outln!(
            "  line {}: {} samples, max |B| {:.4} T",
            l.name,
            l.points.len(),
            l.points.iter().map(|p| p.b_abs_t).fold(0.0, f64::max)
        );
    }
    crate::outln!("  energy {:.5e} J, co-energy {:.5e} J", report.energy_j, report.coenergy_j);
    let t = report.timings_s;
    crate::outln!(
        "  time: read {:.3} s, assemble {:.3} s, solve {:.3} s, post {:.3} s, total {:.3} s",
        t.read,
        t.assemble,
        t.solve,
        t.post,
        t.total
    );
    Ok(())
}
