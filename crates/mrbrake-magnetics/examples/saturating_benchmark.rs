//! Release-mode timing of the saturating benchmark (issue 3 performance target), with the time split.
//!
//! ```text
//! cargo run --release -p mrbrake-magnetics --example saturating_benchmark -- 100000 [current_A] [repeats] [order]
//! /usr/bin/time -v target/release/examples/saturating_benchmark 100000   # peak memory
//! cargo run --release -p mrbrake-magnetics --example saturating_benchmark -- 25000 10 5 2
//! ```
//! The first argument is the number of mesh nodes; `order` is 1 (linear triangles, the default)
//! or 2 (quadratic triangles: about four unknowns per node, so 25 000 nodes give about as many
//! unknowns as the 100 000-node P1 run).
//! Prints nodes, unknowns, Newton iterations, the median wall time over the repeats, and the split
//! into setup (pattern + symbolic factorisation), assembly, numeric factorisation, triangular
//! solves and post-processing (region statistics, coil flux linkage, energy, probes).

use std::time::Instant;

use mrbrake_magnetics::benchmark::{COIL, STEEL, pot_core_problem};
use mrbrake_magnetics::{ElementOrder, Solver, SolverOptions};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    let target: usize = args.get(1).map(|s| s.parse()).transpose()?.unwrap_or(100_000);
    let current: f64 = args.get(2).map(|s| s.parse()).transpose()?.unwrap_or(10.0);
    let repeats: usize = args.get(3).map(|s| s.parse()).transpose()?.unwrap_or(5);
    let degree: i64 = args.get(4).map(|s| s.parse()).transpose()?.unwrap_or(1);
    let order = ElementOrder::from_degree(degree)
        .ok_or_else(|| format!("order must be 1 or 2, got {degree}"))?;
    let steel = mrbrake_materials::library::get("steel-1010")?;
    let mut rows = Vec::new();
    for _ in 0..repeats.max(1) {
        let problem = pot_core_problem(target, steel.magnetic.clone(), current)?;
        let nodes = problem.mesh.nodes.len();
        let start = Instant::now();
        let mut solver = Solver::new(problem, SolverOptions { order, ..SolverOptions::default() })?;
        let setup = start.elapsed().as_secs_f64();
        let solution = solver.solve(None)?;
        let post_start = Instant::now();
        let steel_stats = solver.region_stats(&solution, STEEL)?;
        let t_stats = post_start.elapsed().as_secs_f64();
        let coils = solver.coils(&solution);
        let t_coils = post_start.elapsed().as_secs_f64();
        let (energy, _) = solver.energy(&solution);
        let t_energy = post_start.elapsed().as_secs_f64();
        let gap = solver.b_at(&solution, [5e-3, 15.5e-3])?;
        let post = post_start.elapsed().as_secs_f64();
        println!(
            "post split: stats {t_stats:.3} coils {:.3} energy {:.3} probe {:.3}; history {:?}",
            t_coils - t_stats,
            t_energy - t_coils,
            post - t_energy,
            solution
                .report
                .history
                .iter()
                .map(|h| format!(
                    "{:.1e}@{:.2}{}",
                    h.relative_residual,
                    h.step_length,
                    if h.cg_iterations > 0 {
                        format!("cg{}", h.cg_iterations)
                    } else {
                        String::new()
                    }
                ))
                .collect::<Vec<_>>()
        );
        let total = start.elapsed().as_secs_f64();
        let t = solution.report.timings;
        rows.push((
            total,
            setup,
            t.assemble_s,
            t.factor_s,
            t.solve_s,
            post,
            solution.report.iterations,
        ));
        println!(
            "{order} nodes {nodes} unknowns {} factor nnz {} | iterations {} ({} factorisations) | total {total:.3} s = setup {setup:.3} (symbolic {:.3}) + assemble {:.3} + factor {:.3} + solve {:.3} + post {post:.3} | max |B| steel {:.3} T, gap B {:.3} T, λ {:.4e} Wb, W {energy:.4e} J",
            solver.unknowns(),
            solver.factor_nnz(),
            solution.report.iterations,
            solution.report.factorizations,
            solver.symbolic_factorisation_s(),
            t.assemble_s,
            t.factor_s,
            t.solve_s,
            steel_stats.max_b_t,
            gap.b_abs_t,
            coils.iter().find(|c| c.physical == COIL).map_or(f64::NAN, |c| c.flux_linkage_wb),
        );
    }
    rows.sort_by(|a, b| a.0.total_cmp(&b.0));
    let m = rows[rows.len() / 2];
    println!(
        "{order} median of {}: total {:.3} s (setup {:.3}, assemble {:.3}, factor {:.3}, solve {:.3}, post {:.3}), {} Newton iterations",
        rows.len(),
        m.0,
        m.1,
        m.2,
        m.3,
        m.4,
        m.5,
        m.6
    );
    Ok(())
}
