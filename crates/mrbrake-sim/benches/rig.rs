//! Benchmark of the virtual rig (issue #5 target: the 450 s characterisation protocol in ≤ 1 s).

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use mrbrake_sim::rig::{self, RigConfig};

fn rig_characterize(c: &mut Criterion) {
    let config = RigConfig::default();
    let mut group = c.benchmark_group("rig characterize");
    group.sample_size(10);
    group.bench_function("450 s protocol at 1 kHz, simulation", |b| {
        b.iter(|| rig::characterization_samples(black_box(&config)).unwrap())
    });
    group.bench_function("450 s protocol at 1 kHz, simulation + CSV text", |b| {
        b.iter(|| rig::characterization_log(black_box(&config)).unwrap())
    });
    group.finish();
}

criterion_group!(benches, rig_characterize);
criterion_main!(benches);
