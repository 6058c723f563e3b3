//! Per-iteration overhead of the surrogate-assisted optimiser (model fits and batch selection;
//! the evaluations here are free), at 50, 100 and 200 evaluated designs of a problem with 6
//! variables, 2 objectives and 1 constraint, batch 2 (`--jobs 2`).
//!
//! * `surrogate_cold_iteration/n`: one iteration from `n` designs with no warm start (every model's
//!   likelihood searched from the default start and two Sobol' restarts): what the first iteration
//!   of a run, or of a resumed run, costs.
//! * `surrogate_ten_iterations/n`: ten iterations from `n` designs (the first cold, the others
//!   warm-started, as in a run); `(ten − cold) / 9` is the cost of a warm iteration.
//! * `surrogate_study_60_to_200`: a whole study's overhead: the 60-design initial plan (10 × 6
//!   variables), then batches of 2 up to 200 evaluations. Compare with the evaluations' wall time,
//!   `100 × t_eval` on two cores (30 initial rounds and 70 iterations).

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use mrbrake_observe::Silent;
use mrbrake_optim::FnProblem;
use mrbrake_optim::pareto::Evaluation;
use mrbrake_optim::rng::Rng;
use mrbrake_optim::sampling::latin_hypercube;
use mrbrake_optim::space::Bounds;
use mrbrake_optim::surrogate::{self, EvaluatedDesign, SurrogateOptions};

/// A smooth constrained test problem: ZDT1-like objectives and one nonlinear constraint.
fn evaluate(x: &[f64]) -> Evaluation {
    let g = 1.0 + 9.0 * x[1..].iter().sum::<f64>() / 5.0;
    let f2 = g * (1.0 - (x[0] / g).sqrt());
    let c = 0.3 - (x[0] - 0.5).powi(2) - (x[1] - 0.2).powi(2) - 0.5 * x[2] * x[3];
    let constraint = -c;
    Evaluation::new(vec![x[0], f2], constraint.max(0.0)).with_constraints(vec![constraint])
}

fn previous(n: usize, bounds: &[Bounds]) -> Vec<EvaluatedDesign> {
    latin_hypercube(n, bounds, &mut Rng::new(n as u64))
        .into_iter()
        .map(|x| EvaluatedDesign { evaluation: evaluate(&x), x })
        .collect()
}

fn bench(c: &mut Criterion) {
    let bounds = vec![Bounds::continuous(0.0, 1.0); 6];
    let mut group = c.benchmark_group("surrogate");
    group.sample_size(10);
    for n in [50usize, 100, 200] {
        let data = previous(n, &bounds);
        for (name, iterations) in [("cold_iteration", 1usize), ("ten_iterations", 10)] {
            let options = SurrogateOptions {
                initial_size: Some(7),
                batch: 2,
                max_evaluations: n + 2 * iterations,
                stall_iterations: 0,
                reference: Some(vec![1.1, 10.0]),
                ..Default::default()
            };
            group.bench_with_input(BenchmarkId::new(name, n), &data, |b, data| {
                b.iter(|| {
                    let mut problem = FnProblem::new(bounds.clone(), 2, evaluate);
                    surrogate::run(&mut problem, &options, data, &mut Silent).map(|r| r.iterations)
                })
            });
        }
    }
    group.bench_function("study_60_to_200", |b| {
        let options = SurrogateOptions {
            batch: 2,
            max_evaluations: 200,
            stall_iterations: 0,
            reference: Some(vec![1.1, 10.0]),
            ..Default::default()
        };
        b.iter(|| {
            let mut problem = FnProblem::new(bounds.clone(), 2, evaluate);
            surrogate::run(&mut problem, &options, &[], &mut Silent).map(|r| r.iterations)
        })
    });
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
