//! Cost of the statistics of an `uncertainty` run next to its FEA: the polynomial-chaos fit with
//! degree selection (leave-one-out) and the Sobol' indices with 200 bootstrap refits, at 256
//! samples × 8 inputs (the brake-level target: 256 samples in ≤ 5 min on 2 cores, dominated by the
//! FEA). The output is a smooth, mildly interacting function of mixed input laws.

use criterion::{Criterion, criterion_group, criterion_main};
use mrbrake_uq::distribution::Distribution;
use mrbrake_uq::pce::{Pce, PceOptions};
use mrbrake_uq::qmc::sample;
use mrbrake_uq::sensitivity::{SensitivityOptions, sobol_indices};
use std::hint::black_box;

fn bench(c: &mut Criterion) {
    let inputs = [
        Distribution::normal(1.0, 0.1).unwrap(),
        Distribution::uniform(0.9, 1.1).unwrap(),
        Distribution::triangular(0.7, 0.8, 1.0).unwrap(),
        Distribution::log_normal_from_mean_std(1.0, 0.05).unwrap(),
        Distribution::normal(0.5, 0.02).unwrap().truncated(0.45, 0.55).unwrap(),
        Distribution::uniform(20.0, 60.0).unwrap(),
        Distribution::normal(2.0, 0.2).unwrap(),
        Distribution::uniform(0.0, 1.0).unwrap(),
    ];
    let s = sample(&inputs, 256, 11).unwrap();
    let y: Vec<f64> = s
        .values
        .iter()
        .map(|x| x[0] * x[1] * x[2] / x[4] + 0.3 * x[3] * x[3] + 0.002 * x[5] + 0.05 * x[6] * x[7])
        .collect();
    c.bench_function("pce_fit_256x8", |b| {
        b.iter(|| Pce::fit(black_box(&s.unit), black_box(&y), &PceOptions::default()).unwrap())
    });
    let options = SensitivityOptions { bootstrap: 200, ..Default::default() };
    c.bench_function("sobol_indices_256x8_bootstrap200", |b| {
        b.iter(|| sobol_indices(black_box(&s.unit), black_box(&y), &options).unwrap())
    });
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(10);
    targets = bench
}
criterion_main!(benches);
