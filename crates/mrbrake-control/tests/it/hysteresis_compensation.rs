//! The inverse model with branch selection reproduces a torque demand through the forward hysteresis
//! model (thesis §5.3.2: the current is shaped so that the torque follows the demand).

use crate::common;

use mrbrake_control::*;

/// Forward rate-independent hysteresis consistent with the two branches: the static torque stays
/// between the rising (lower) and the falling (upper) branch.
fn forward(model: &InverseModel, held_nm: f64, current_a: f64) -> f64 {
    let lower = model.torque_nm(Branch::Rising, current_a);
    let upper = model.torque_nm(Branch::Falling, current_a);
    held_nm.clamp(lower, upper)
}

#[test]
fn sinusoidal_demand_is_tracked_through_the_loop() {
    let controller = common::controller(BrakeLayout::Bidirectional);
    let TorqueInverse::Branches(model) = controller.brakes()[0] else {
        panic!("the common controller uses branch models")
    };
    let mut state = ControllerState::default();
    let k = 30.0; // Nm/rad
    let rad_per_count = controller.radians_per_count();
    let mut held = model.torque_nm(Branch::Rising, 0.0);
    let mut worst_error: f64 = 0.0;
    let mut worst_uncompensated: f64 = 0.0;
    for n in 0..4000 {
        // Demand 0.5 .. 3.5 Nm at 1 Hz, rendered as a penetration into a K = 30 Nm/rad wall.
        let t = n as f64 * 1e-3;
        let demand = 2.0 + 1.5 * (2.0 * std::f64::consts::PI * t).sin();
        let counts = (demand / k / rad_per_count).round() as i64;
        let out = controller.step(
            &mut state,
            &ControlInput {
                encoder_counts: counts,
                velocity_rad_s: 0.0,
                wall: common::wall(k, 0.0),
            },
        );
        held = forward(&model, held, out.current_a[0]);
        let realised_demand = out.breakdown.demand_nm[0];
        if n > 1000 {
            worst_error = worst_error.max((held - realised_demand).abs());
            // What a single (rising-branch) inverse would give on the falling half.
            let naive_current = model.current_for(Branch::Rising, realised_demand, 2.0);
            let naive = model.torque_nm(Branch::Falling, naive_current);
            worst_uncompensated = worst_uncompensated.max((naive - realised_demand).abs());
        }
    }
    // Compensated: limited by the encoder quantisation and the deadband (mNm level).
    assert!(worst_error < 0.02, "worst tracking error {worst_error} Nm");
    assert!(worst_uncompensated > 0.2, "uncompensated error {worst_uncompensated} Nm");
}
