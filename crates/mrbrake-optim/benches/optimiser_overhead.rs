//! Overhead of the optimisers themselves (everything but the evaluations), to compare with the
//! ~0.3 s of one FEA evaluation: the non-dominated sort of a merged NSGA-II population (200 designs,
//! 2 objectives) and an NSGA-II run of the initial population plus one generation (200 evaluations) on a free evaluator.

use criterion::{Criterion, criterion_group, criterion_main};
use mrbrake_optim::FnProblem;
use mrbrake_optim::nsga2::{self, Nsga2Options};
use mrbrake_optim::pareto::{Evaluation, non_dominated_sort};
use mrbrake_optim::rng::Rng;
use mrbrake_optim::space::Bounds;
use std::hint::black_box;

fn bench(c: &mut Criterion) {
    let mut rng = Rng::new(1);
    let evals: Vec<Evaluation> = (0..200)
        .map(|_| {
            let x = rng.uniform();
            Evaluation::new(vec![x, 1.0 - x.sqrt() + 0.5 * rng.uniform()], 0.0)
        })
        .collect();
    c.bench_function("non_dominated_sort_200x2", |b| {
        b.iter(|| non_dominated_sort(black_box(&evals)))
    });

    c.bench_function("nsga2_pop100_10vars_initial_plus_1_generation", |b| {
        b.iter(|| {
            let mut problem =
                FnProblem::new(vec![Bounds::continuous(0.0, 1.0); 10], 2, |x: &[f64]| {
                    let g = 1.0 + 9.0 * x[1..].iter().sum::<f64>() / 9.0;
                    Evaluation::new(vec![x[0], g * (1.0 - (x[0] / g).sqrt())], 0.0)
                });
            let options = Nsga2Options { population: 100, generations: 1, ..Default::default() };
            nsga2::run(&mut problem, &options, &mut mrbrake_observe::Silent).map(|r| r.evaluations)
        })
    });
}

criterion_group!(benches, bench);
criterion_main!(benches);
