//! Criterion benchmark of the saturating pot-core problem (issue 3 performance target):
//! `cargo bench -p mrbrake-magnetics --bench saturating`. Sizes 25k and 100k nodes (the 400k case
//! is run with `examples/saturating_benchmark.rs`, too slow for criterion's repeated sampling).
//! Each sample: solver setup (pattern, symbolic factorisation) + Newton solve from A = 0 + region
//! statistics, coil flux, energy and one probe.

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use mrbrake_magnetics::benchmark::{STEEL, pot_core_problem};
use mrbrake_magnetics::material::MagneticMaterial;
use mrbrake_magnetics::{Solver, SolverOptions};

fn saturating(c: &mut Criterion) {
    let steel = mrbrake_materials::library::get("steel-1010").expect("built-in material");
    let mut group = c.benchmark_group("saturating_pot_core");
    group.sample_size(10);
    for nodes in [25_000usize, 100_000] {
        let problem =
            pot_core_problem(nodes, MagneticMaterial::from_library(&steel.magnetic), 10.0)
                .expect("valid benchmark problem");
        group.bench_with_input(
            BenchmarkId::from_parameter(problem.mesh.nodes.len()),
            &problem,
            |b, problem| {
                b.iter(|| {
                    let mut solver =
                        Solver::new(problem.clone(), SolverOptions::default()).expect("setup");
                    let solution = solver.solve(None).expect("converges");
                    let stats = solver.region_stats(&solution, STEEL).expect("steel region");
                    let coils = solver.coils(&solution);
                    let energy = solver.energy(&solution);
                    let probe = solver.b_at(&solution, [5e-3, 15.5e-3]).expect("inside");
                    (stats.max_b_t, coils.len(), energy.0, probe.b_abs_t)
                })
            },
        );
    }
    group.finish();
}

criterion_group!(benches, saturating);
criterion_main!(benches);
