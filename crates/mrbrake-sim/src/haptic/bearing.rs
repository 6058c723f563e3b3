//! One-way bearings and the set-valued (Coulomb) brake torque on the shaft, stepped implicitly.
//!
//! An MR brake holds up to its capacity `C` and slips beyond it: a Coulomb element whose torque is
//! set-valued at zero velocity. A one-way bearing between shaft and brake rotor transmits torque only
//! in its direction (thesis §4.3, Fig. 4.11): brake 1's bearing locks for positive shaft motion,
//! brake 2's for negative. So the shaft sees a resistance of up to `C⁺` against positive motion and up
//! to `C⁻` against negative motion: `C⁺ = C₁, C⁻ = C₂` for the bidirectional brake,
//! `C⁺ = C⁻ = C` for a conventional brake rigidly on the shaft.
//!
//! The step is the backward-Euler (time-stepping) treatment of set-valued friction (Moreau 1988;
//! Stewart 2000, SIAM Review 42(1)): with the friction-free prediction `ω*`, the new velocity is
//! `ω* − ΔC⁺` if `ω* > ΔC⁺`, `ω* + ΔC⁻` if `ω* < −ΔC⁻`, else 0 (stick), with `ΔC = dt·C/J`. It never
//! reverses the motion by friction alone and holds exactly when the brake can.

/// Velocity after one implicit friction step and the friction torque that produced it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FrictionStep {
    /// New velocity, rad/s.
    pub velocity_rad_s: f64,
    /// Friction torque on the shaft during the step, Nm (opposes `ω*`).
    pub torque_nm: f64,
}

/// Implicit Coulomb step: `free_velocity_rad_s` is `ω*`, `resist_positive_nm`/`resist_negative_nm`
/// are `C⁺`/`C⁻` (≥ 0), `inertia_kg_m2` is `J`, `dt_s` the step.
#[inline]
pub fn friction_step(
    free_velocity_rad_s: f64,
    resist_positive_nm: f64,
    resist_negative_nm: f64,
    inertia_kg_m2: f64,
    dt_s: f64,
) -> FrictionStep {
    let per_torque = dt_s / inertia_kg_m2;
    let reach_positive = resist_positive_nm.max(0.0) * per_torque;
    let reach_negative = resist_negative_nm.max(0.0) * per_torque;
    let velocity = if free_velocity_rad_s > reach_positive {
        free_velocity_rad_s - reach_positive
    } else if free_velocity_rad_s < -reach_negative {
        free_velocity_rad_s + reach_negative
    } else {
        0.0
    };
    FrictionStep {
        velocity_rad_s: velocity,
        torque_nm: (velocity - free_velocity_rad_s) / per_torque,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_way_resistance_holds_one_direction_and_frees_the_other() {
        // Brake 1 energised (3 Nm), brake 2 at 0: positive motion is stopped, negative is free.
        let stop = friction_step(0.5, 3.0, 0.0, 1e-3, 1e-3);
        assert!(stop.velocity_rad_s.abs() < 1e-15);
        assert!((stop.torque_nm + 0.5).abs() < 1e-12);
        let free = friction_step(-0.5, 3.0, 0.0, 1e-3, 1e-3);
        assert!((free.velocity_rad_s + 0.5).abs() < 1e-15);
        assert!(free.torque_nm.abs() < 1e-12);
        // Slip: the torque equals the capacity.
        let slip = friction_step(10.0, 3.0, 0.0, 1e-3, 1e-3);
        assert!((slip.torque_nm + 3.0).abs() < 1e-9);
    }
}
