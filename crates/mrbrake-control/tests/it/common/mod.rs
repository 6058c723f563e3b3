//! Shared fixtures for the controller's validation tests.
#![allow(dead_code)]

use mrbrake_control::*;

/// Prototype-like quintic branches (0.15 Nm at 0 A, 3.84 Nm at 2 A; falling branch above rising),
/// in powers of u = i / 2 A, converted to powers of i.
pub fn prototype_model() -> InverseModel {
    let span = 3.84 - 0.15;
    let rising_u = [0.15, span * 1.2, span * 0.6, span * -1.6, span * 0.9, span * -0.1];
    // Falling = rising + 0.1·span·4u(1−u).
    let mut falling_u = rising_u;
    falling_u[1] += 0.4 * span;
    falling_u[2] -= 0.4 * span;
    let to_i = |u: [f64; 6]| {
        let mut c = [0.0; 6];
        for k in 0..6 {
            c[k] = u[k] / 2f64.powi(k as i32);
        }
        c
    };
    InverseModel::new(&to_i(rising_u), &to_i(falling_u), 0.0, 2.0).expect("valid prototype model")
}

/// A controller for `layout` with the prototype model on both brakes.
pub fn controller(layout: BrakeLayout) -> DirectionalController {
    let m = prototype_model();
    DirectionalController::new(layout, [m, m], 2.0, 80_000, InputLimits::default(), 0.005)
        .expect("valid config")
}

/// A stiff wall at 0 rad on the positive side.
pub fn wall(k: f64, b: f64) -> VirtualWall {
    VirtualWall::new(0.0, WallSide::Positive, k, b)
}
