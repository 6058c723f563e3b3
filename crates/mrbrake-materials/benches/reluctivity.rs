//! Cost of the reluctivity evaluation a Newton magnetostatic solver makes at every quadrature point:
//! `ν(B²)` plus `dν/dB²`. Each iteration of the benchmark evaluates both at 1024 values of B² spread
//! over `[0, (1.3 B_last)²]` (all pieces and the μ0 extrapolation), so time per call = time / 1024.

use std::hint::black_box;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use mrbrake_materials::library;

const SAMPLES: usize = 1024;

fn bench_reluctivity(c: &mut Criterion) {
    let mut group = c.benchmark_group("reluctivity");
    group.throughput(Throughput::Elements(SAMPLES as u64));
    for name in ["steel-1008", "steel-1020", "mrf-122eg"] {
        let curve = library::bh_curve(name).expect("built-in curve");
        let (_, b_last) = curve.last_point();
        // A scrambled order (multiplicative hashing of the index) defeats the branch predictor the way
        // an unstructured mesh does.
        let b2: Vec<f64> = (0..SAMPLES)
            .map(|i| {
                let k = (i * 613) % SAMPLES;
                (1.3 * b_last * k as f64 / SAMPLES as f64).powi(2)
            })
            .collect();
        group.bench_function(format!("{name}/nu_of_b2+dnu_db2"), |bench| {
            bench.iter(|| {
                let mut sum = 0.0;
                for &x in &b2 {
                    sum += curve.nu_of_b2(black_box(x)) + curve.dnu_db2(black_box(x));
                }
                sum
            })
        });
        group.bench_function(format!("{name}/nu_and_dnu_db2"), |bench| {
            bench.iter(|| {
                let mut sum = 0.0;
                for &x in &b2 {
                    let (nu, dnu) = curve.nu_and_dnu_db2(black_box(x));
                    sum += nu + dnu;
                }
                sum
            })
        });
    }
    group.finish();
}

criterion_group!(benches, bench_reluctivity);
criterion_main!(benches);
