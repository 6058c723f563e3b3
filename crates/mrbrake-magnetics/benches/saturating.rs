//! Criterion benchmark of the saturating pot-core problem (issue 3 performance target):
//! `cargo bench -p mrbrake-magnetics --bench saturating`. Linear (P1) triangles on 25k and 100k
//! nodes (the 400k case is run with `examples/saturating_benchmark.rs`, too slow for criterion's
//! repeated sampling), and quadratic (P2) triangles on 6.25k and 25k nodes (about the same numbers
//! of unknowns; ids `P2/<unknowns>`). Each sample: solver setup (pattern, symbolic factorisation) +
//! Newton solve from A = 0 + region statistics, coil flux, energy and one probe.

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use mrbrake_magnetics::benchmark::{STEEL, pot_core_problem};
use mrbrake_magnetics::{ElementOrder, Solver, SolverOptions};

fn saturating(c: &mut Criterion) {
    let steel = mrbrake_materials::library::get("steel-1010").expect("built-in material");
    let mut group = c.benchmark_group("saturating_pot_core");
    group.sample_size(10);
    let cases = [
        (ElementOrder::P1, 25_000usize),
        (ElementOrder::P1, 100_000),
        (ElementOrder::P2, 6_250),
        (ElementOrder::P2, 25_000),
    ];
    for (order, nodes) in cases {
        let problem =
            pot_core_problem(nodes, steel.magnetic.clone(), 10.0).expect("valid benchmark problem");
        let options = SolverOptions { order, ..SolverOptions::default() };
        // P1 keeps its historical ids (the node count); P2 is named by its unknowns.
        let id = match order {
            ElementOrder::P1 => BenchmarkId::from_parameter(problem.mesh.nodes.len()),
            ElementOrder::P2 => BenchmarkId::new(
                "P2",
                Solver::new(problem.clone(), options).expect("setup").unknowns(),
            ),
        };
        group.bench_with_input(id, &problem, |b, problem| {
            b.iter(|| {
                let mut solver = Solver::new(problem.clone(), options).expect("setup");
                let solution = solver.solve(None).expect("converges");
                let stats = solver.region_stats(&solution, STEEL).expect("steel region");
                let coils = solver.coils(&solution);
                let energy = solver.energy(&solution);
                let probe = solver.b_at(&solution, [5e-3, 15.5e-3]).expect("inside");
                (stats.max_b_t, coils.len(), energy.0, probe.b_abs_t)
            })
        });
    }
    group.finish();
}

criterion_group!(benches, saturating);
criterion_main!(benches);
