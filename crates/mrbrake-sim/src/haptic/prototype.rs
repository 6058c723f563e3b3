//! Built-in brake characteristic used when no identification file is given.
//!
//! **Prototype-like, not measured.** The thesis reports the prototype's end points — 0.15 Nm at 0 A
//! (off-state) and 3.84 Nm at 2 A (§5.3.1, Table 5.1) — and fits quintics to the rising and falling
//! halves of the hysteresis loop (Fig. 5.6), but does not print their coefficients. These branches
//! reproduce the end points exactly, rise steeply and saturate gently like the thesis's curves, and
//! open a loop whose width peaks at 10 % of the span (0.37 Nm) at 1 A, closing at both ends. In the
//! normalised current `u = i / 2 A`, with span `S = 3.84 − 0.15` Nm:
//!
//! `T_rise(u) = 0.15 + S·(1.2u + 0.6u² − 1.6u³ + 0.9u⁴ − 0.1u⁵)`,
//! `T_fall(u) = T_rise(u) + 0.1·S·4u(1 − u)`.
//!
//! Replace them with `mrbrake characterize --save-model` output (read by
//! [`mrbrake_sysid::model_file::read_inverse_model`]) for a real brake.

use mrbrake_control::InverseModel;

/// Off-state torque of the prototype at 0 A, Nm (thesis §5.3.1).
pub const OFF_STATE_TORQUE_NM: f64 = 0.15;
/// Torque of the prototype at 2 A, Nm (thesis §5.3.1).
pub const FULL_TORQUE_NM: f64 = 3.84;
/// Maximum operating current, A (thesis §4.1).
pub const CURRENT_MAX_A: f64 = 2.0;

/// Ascending coefficients in powers of the current in A for (rising, falling).
pub fn prototype_coefficients() -> ([f64; 6], [f64; 6]) {
    let span = FULL_TORQUE_NM - OFF_STATE_TORQUE_NM;
    let rising_u =
        [OFF_STATE_TORQUE_NM, span * 1.2, span * 0.6, span * -1.6, span * 0.9, span * -0.1];
    let mut falling_u = rising_u;
    falling_u[1] += 0.4 * span;
    falling_u[2] -= 0.4 * span;
    let mut rising = [0.0; 6];
    let mut falling = [0.0; 6];
    let mut scale = 1.0;
    for k in 0..6 {
        rising[k] = rising_u[k] * scale;
        falling[k] = falling_u[k] * scale;
        scale /= CURRENT_MAX_A;
    }
    (rising, falling)
}

/// The prototype-like model on `[0, 2]` A.
pub fn prototype_model() -> InverseModel {
    let (rising, falling) = prototype_coefficients();
    InverseModel::new(&rising, &falling, 0.0, CURRENT_MAX_A)
        .expect("the built-in branches are monotone on [0, 2] A")
}

#[cfg(test)]
mod tests {
    use super::*;
    use mrbrake_control::Branch;

    #[test]
    fn end_points_and_loop_width_match_the_documented_values() {
        let m = prototype_model();
        for branch in [Branch::Rising, Branch::Falling] {
            assert!((m.torque_nm(branch, 0.0) - 0.15).abs() < 1e-12);
            assert!((m.torque_nm(branch, 2.0) - 3.84).abs() < 1e-12);
        }
        let width = m.torque_nm(Branch::Falling, 1.0) - m.torque_nm(Branch::Rising, 1.0);
        assert!((width - 0.369).abs() < 1e-9);
    }
}
