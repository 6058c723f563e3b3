//! Benchmarks of the identification hot paths (issue #5 targets):
//! - `tfest` on 41 points: ≤ 10 ms;
//! - `characterize` on a ten-repetition log of ~450 000 samples, CSV reading included: ≤ 1 s.

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use mrbrake_sysid::characterize::{CharacterizeOptions, characterize};
use mrbrake_sysid::frd::Frd;
use mrbrake_sysid::log::read_log;
use mrbrake_sysid::tfest::{TfestOptions, Weighting, logspace, tfest};
use mrbrake_sysid::transfer_function::TransferFunction;
use num_complex::Complex64;

fn tfest_41_points(c: &mut Criterion) {
    let g = TransferFunction::new(vec![1.0], vec![1.791e-5, 0.01702, 1.0]).unwrap();
    // Deterministic 1 % perturbation so the optimiser has real work to do.
    let mut k = 0;
    let frd = Frd::sample(&logspace(0.1, 1000.0, 41), |w| {
        let r = g.response(w);
        let noise = Complex64::new((k as f64 * 1.7).sin(), (k as f64 * 2.3).cos());
        k += 1;
        r + noise.scale(0.01 * r.norm())
    });
    let mut o = TfestOptions::new(2, 0);
    c.bench_function("tfest 41 points, 2 poles", |b| {
        b.iter(|| tfest(black_box(&frd), &o).unwrap())
    });
    o.weighting = Weighting::InverseMagnitude;
    o.poles = 3;
    o.zeros = 1;
    c.bench_function("tfest 41 points, 3 poles 1 zero, relative", |b| {
        b.iter(|| tfest(black_box(&frd), &o).unwrap())
    });
}

/// The thesis protocol (0 → 2 A in 1 mA / 10 ms steps, back, 5 s pause, ten times) at 1 kHz with a
/// static loop and a deterministic ripple standing in for noise: 450 100 samples.
fn protocol_csv() -> String {
    let mut s = String::from("time_s,current_A,torque_Nm\n");
    let mut k = 0usize;
    let mut push = |s: &mut String, i: f64, t: f64| {
        s.push_str(&format!(
            "{:.3},{:.4},{:.6}\n",
            k as f64 * 1e-3,
            i,
            t + 0.003 * ((k as f64) * 0.37).sin()
        ));
        k += 1;
    };
    for _ in 0..10 {
        for step in 0..=2000 {
            let i = step as f64 * 1e-3;
            for _ in 0..10 {
                push(&mut s, i, 0.15 + 3.69 * i - 1.38375 * i * i + 0.230625 * i * i * i);
            }
        }
        for step in (0..2000).rev() {
            let i = step as f64 * 1e-3;
            for _ in 0..10 {
                push(&mut s, i, 0.15 + 4.29 * i - 1.68375 * i * i + 0.230625 * i * i * i);
            }
        }
        for _ in 0..5000 {
            push(&mut s, 0.0, 0.15);
        }
    }
    s
}

fn characterize_full_log(c: &mut Criterion) {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("characterization.csv");
    std::fs::write(&path, protocol_csv()).unwrap();
    let mut group = c.benchmark_group("characterize");
    group.sample_size(10);
    group.bench_function("450k-sample log, read + fit", |b| {
        b.iter(|| {
            let log =
                read_log(black_box(&path), "time_s", &["current_A", "torque_Nm"], 12).unwrap();
            characterize(&log.channels[0], &log.channels[1], CharacterizeOptions::default())
                .unwrap()
        })
    });
    let log = read_log(&path, "time_s", &["current_A", "torque_Nm"], 12).unwrap();
    group.bench_function("450k-sample log, fit only", |b| {
        b.iter(|| {
            characterize(
                black_box(&log.channels[0]),
                &log.channels[1],
                CharacterizeOptions::default(),
            )
            .unwrap()
        })
    });
    group.finish();
}

criterion_group!(benches, tfest_41_points, characterize_full_log);
criterion_main!(benches);
