//! Cost of the per-point update of the hysteretic law that an FEA with the energy-based model makes at
//! every quadrature point of the flux path in every Newton iteration: a B-driven trial step from the
//! committed state (`HysteresisState::trial`, returning H and dH/dB), and the committing step.
//!
//! 1024 points are prepared in different states (each driven through its own history: virgin curve,
//! a reversal, part of a descending branch); each benchmark iteration then steps all of them by a
//! typical increment of one current step of a loop with 40 steps per branch (|ΔB| ≈ 2 T / 40 =
//! 0.05 T, both directions, some across a reversal). Time per point = time / 1024. Run with
//! `cargo bench -p mrbrake-materials --bench hysteresis`.

use std::hint::black_box;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use mrbrake_materials::hysteresis::{HysteresisState, library};

const POINTS: usize = 1024;

fn bench_hysteresis(c: &mut Criterion) {
    let mut group = c.benchmark_group("hysteresis");
    group.throughput(Throughput::Elements(POINTS as u64));
    for name in ["steel-1008", "steel-1018"] {
        let set = library::steel(name).expect("built-in set");
        let params = &*set.params;
        // Scrambled states: a tip between 0.5 and 1.9 T, then down to a point of the descending branch.
        let states: Vec<HysteresisState> = (0..POINTS)
            .map(|i| {
                let k = (i * 613) % POINTS;
                let tip = 0.5 + 1.4 * k as f64 / POINTS as f64;
                let mut s = HysteresisState::demagnetised();
                s.step(params, tip);
                s.step(params, tip * (1.0 - 2.0 * ((i * 389) % POINTS) as f64 / POINTS as f64));
                s
            })
            .collect();
        let targets: Vec<f64> = states
            .iter()
            .enumerate()
            .map(|(i, s)| s.b() + if i % 3 == 0 { 0.05 } else { -0.05 })
            .collect();
        group.bench_function(format!("{name}/trial (B-driven, not committed)"), |bench| {
            bench.iter(|| {
                let mut sum = 0.0;
                for (s, &b) in states.iter().zip(&targets) {
                    let (r, _) = s.trial(params, black_box(b));
                    sum += r.h + r.dh_db;
                }
                sum
            })
        });
        // A later Newton iteration: the trial B moved by 1e-4 T from the previous trial, whose H is
        // passed as the guess.
        let guesses: Vec<f64> = states
            .iter()
            .zip(&targets)
            .map(|(s, &b)| s.trial(params, b - 1e-4 * (b - s.b()).signum()).0.h)
            .collect();
        group.bench_function(format!("{name}/trial_near (B-driven, warm start)"), |bench| {
            bench.iter(|| {
                let mut sum = 0.0;
                for ((s, &b), &guess) in states.iter().zip(&targets).zip(&guesses) {
                    let (r, _) = s.trial_near(params, black_box(b), guess);
                    sum += r.h + r.dh_db;
                }
                sum
            })
        });
        group.bench_function(format!("{name}/step_h (H-driven)"), |bench| {
            bench.iter(|| {
                let mut sum = 0.0;
                for s in &states {
                    let mut next = *s;
                    let r = next.step_h(params, black_box(s.h() + 200.0));
                    sum += r.b;
                }
                sum
            })
        });
    }
    group.finish();
}

criterion_group!(benches, bench_hysteresis);
criterion_main!(benches);
