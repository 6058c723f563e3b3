//! Haptic simulator speed: 10 s of interaction (1 kHz control, 10 kHz plant) must take ≤ 10 ms
//! (≥ 1000× real time); a 50 × 50 Z-width map ≤ 30 s.

use criterion::{Criterion, criterion_group, criterion_main};
use mrbrake_sim::haptic::zwidth::{ZWidthConfig, sweep};
use mrbrake_sim::haptic::{DeviceKind, HapticConfig, Scenario, simulate};
use std::hint::black_box;

fn bench_wall(c: &mut Criterion) {
    for device in [DeviceKind::Conventional, DeviceKind::Bidirectional, DeviceKind::Motor] {
        let mut config = HapticConfig::new(device, Scenario::PressWithdraw);
        config.duration_s = 10.0;
        c.bench_function(&format!("wall_10s_{}", device.name()), |b| {
            b.iter(|| black_box(simulate(black_box(&config), false).expect("valid config")))
        });
    }
}

fn bench_zwidth(c: &mut Criterion) {
    let mut group = c.benchmark_group("zwidth");
    group.sample_size(10);
    let config = ZWidthConfig::default();
    group.bench_function("map_50x50", |b| {
        b.iter(|| {
            black_box(
                sweep(black_box(&config), &mut mrbrake_observe::Silent).expect("valid config"),
            )
        })
    });
    group.finish();
}

criterion_group!(benches, bench_wall, bench_zwidth);
criterion_main!(benches);
