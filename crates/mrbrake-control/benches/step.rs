//! One controller step (target ≤ 100 ns on the host): a tick inside the wall with a moving demand, so
//! the branch inverse runs its Newton iterations every time; and the same tick with the operator
//! inverse (modified Prandtl–Ishlinskii) at the default identification size (12 plays, 12 segments)
//! and at the controller's full capacity (32 plays, 32 segments).

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

/// An operator model with `plays` plays and `segments` output segments spanning the prototype's range.
fn operator_model(plays: usize, segments: usize) -> OperatorModel {
    let thresholds: Vec<f64> = (0..plays).map(|k| k as f64 * 1.0 / plays as f64).collect();
    let weights: Vec<f64> = (0..plays).map(|k| if k == 0 { 1.0 } else { 0.3 / k as f64 }).collect();
    let knots: Vec<f64> = (0..segments).map(|k| 0.15 + 3.7 * k as f64 / segments as f64).collect();
    let slopes: Vec<f64> = (0..segments).map(|k| 0.4 + 0.05 * k as f64).collect();
    OperatorModel::new(&OperatorParts {
        thresholds_a: &thresholds,
        weights: &weights,
        knots_nm: &knots,
        slopes_a_per_nm: &slopes,
        offset_a: 0.0,
        current_min_a: 0.0,
        current_max_a: 2.0,
    })
    .expect("valid operator model")
}

fn bench_step(c: &mut Criterion) {
    let model = TorqueInverse::Branches(prototype_model());
    run_bench(c, "controller_step", model, 0.005);
    run_bench(c, "controller_step_operators_12x12", operator_model(12, 12).into(), 0.0);
    let full = operator_model(MAX_PLAYS, MAX_SEGMENTS).into();
    run_bench(c, "controller_step_operators_32x32", full, 0.0);
}

fn run_bench(c: &mut Criterion, name: &str, model: TorqueInverse, deadband_nm: f64) {
    let controller = DirectionalController::with_inverses(
        BrakeLayout::Bidirectional,
        [model, model],
        2.0,
        80_000,
        InputLimits::default(),
        deadband_nm,
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
    c.bench_function(name, |b| {
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
