//! One controller step (target ≤ 100 ns on the host): a tick inside the wall with a moving demand, so
//! the branch inverse runs its Newton iterations every time.

use criterion::{Criterion, criterion_group, criterion_main};
use mrbrake_control::*;
use std::hint::black_box;

fn prototype_model() -> InverseModel {
    let span = 3.84 - 0.15;
    let rising = [
        0.15,
        span * 1.2 / 2.0,
        span * 0.6 / 4.0,
        span * -1.6 / 8.0,
        span * 0.9 / 16.0,
        span * -0.1 / 32.0,
    ];
    let mut falling = rising;
    falling[1] += 0.4 * span / 2.0;
    falling[2] -= 0.4 * span / 4.0;
    InverseModel::new(&rising, &falling, 0.0, 2.0).expect("valid model")
}

fn bench_step(c: &mut Criterion) {
    let model = prototype_model();
    let controller = DirectionalController::new(
        BrakeLayout::Bidirectional,
        [model, model],
        2.0,
        80_000,
        InputLimits::default(),
        0.005,
    )
    .expect("valid config");
    let wall = VirtualWall {
        position_rad: 0.0,
        side: WallSide::Positive,
        stiffness_nm_per_rad: 30.0,
        damping_nms_per_rad: 0.05,
        field_damping_nms_per_rad: 0.0,
    };
    let mut state = ControllerState::default();
    let mut counts = 0i64;
    c.bench_function("controller_step", |b| {
        b.iter(|| {
            // Sweep 0..1500 counts (0..0.118 rad, demand 0..3.5 Nm) back and forth.
            counts = (counts + 7) % 3000;
            let encoder_counts = if counts < 1500 { counts } else { 3000 - counts };
            let input = ControlInput { encoder_counts, velocity_rad_s: 0.3, wall };
            black_box(controller.step(&mut state, black_box(&input)))
        })
    });
}

criterion_group!(benches, bench_step);
criterion_main!(benches);
