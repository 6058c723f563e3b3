//! Solves a problem file as `mrbrake fem solve` does (read, solve, post-processing, incremental
//! inductance) and prints the time split and the Newton history: the profiling driver of the
//! static non-linear solve (issue 34).
//!
//! ```text
//! cargo build --profile profiling -p mrbrake-magnetics --example solve_file
//! RAYON_NUM_THREADS=1 target/profiling/examples/solve_file problem.toml
//! RAYON_NUM_THREADS=1 valgrind --tool=callgrind target/profiling/examples/solve_file problem.toml
//! ```
//! Per Newton iteration: the relative residual before the step, the line-search step length and
//! the conjugate-gradient iterations with the previous factor (0: the Jacobian was factorised).

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let path = std::env::args().nth(1).ok_or("usage: solve_file PROBLEM.toml")?;
    let (report, solver, solution) =
        mrbrake_magnetics::problem_file::solve_file(std::path::Path::new(&path))?;
    let t = &report.timings_s;
    println!(
        "nodes {} unknowns {} factor entries {} | total {:.3} s = read {:.3} + assemble {:.3} + \
         solve {:.3} (factorisations, solves, incremental inductance) + post {:.3}",
        report.nodes,
        report.unknowns,
        solver.factor_nnz(),
        t.total,
        t.read,
        t.assemble,
        t.solve,
        t.post,
    );
    let newton = &solution.report;
    println!(
        "Newton: {} iterations, {} factorisations (numeric factorisation {:.3} s, triangular \
         solves {:.3} s)",
        newton.iterations, newton.factorizations, newton.timings.factor_s, newton.timings.solve_s
    );
    for step in &newton.history {
        println!(
            "  residual {:.3e}  step {:.4}  cg {}",
            step.relative_residual, step.step_length, step.cg_iterations
        );
    }
    for coil in &report.coils {
        println!(
            "coil {}: flux linkage {:.13e} Wb, incremental inductance {:.13e} H",
            coil.physical, coil.flux_linkage_wb, coil.incremental_inductance_h
        );
    }
    println!("energy {:.13e} J", report.energy_j);
    Ok(())
}
