//! The 1-DOF rotary haptic device: handle and shaft, its friction, its actuator, its encoder.
//!
//! `J θ̈ = τ_hand − b θ̇ − τ_c sgn θ̇ + τ_actuator`, with
//! - `J`: the rotating inertia engaged per direction, 54.8 kg·mm² for the thesis's bidirectional
//!   brake (§4.3; only one rotor turns with the shaft in each direction), used for every device so
//!   that they differ only by their actuator;
//! - `b`, `τ_c`: viscous and Coulomb friction of the shaft bearings (assumed: 0.005 Nm·s/rad and
//!   0.005 Nm; the thesis does not measure them — the brakes' 0.15 Nm off-state torque, which
//!   dominates, comes with the brake model);
//! - the actuator: a conventional MR brake, the bidirectional MR brake, or an ideal DC motor;
//! - an incremental encoder of 80 000 counts/rev (the thesis's test-rig encoder, §3.2).

/// Which actuator the device has.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum DeviceKind {
    /// One MR brake fixed to the shaft: resists both directions.
    Conventional,
    /// Two MR brakes on opposite one-way bearings (the thesis's design).
    Bidirectional,
    /// An ideal torque source (DC motor with perfect current control), the active reference.
    Motor,
}

impl DeviceKind {
    /// Every device, in the order the CLI lists them.
    pub const ALL: [Self; 3] = [Self::Conventional, Self::Bidirectional, Self::Motor];

    /// The device called `name` (as [`DeviceKind::name`] gives it), if there is one.
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|d| d.name() == name)
    }

    /// The name used on the command line and in JSON.
    pub fn name(self) -> &'static str {
        match self {
            Self::Conventional => "conventional",
            Self::Bidirectional => "bidirectional",
            Self::Motor => "motor",
        }
    }
}

/// Mechanical parameters of the device.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct DeviceParameters {
    /// Rotating inertia, kg·m².
    pub inertia_kg_m2: f64,
    /// Viscous friction `b`, Nm·s/rad.
    pub viscous_nms_per_rad: f64,
    /// Coulomb friction of the bearings, Nm.
    pub coulomb_nm: f64,
    /// Encoder resolution, counts per revolution.
    pub encoder_counts_per_rev: u32,
    /// Torque limit of the motor (motor device only), Nm; set to the brakes' 3.84 Nm for fairness.
    pub motor_torque_max_nm: f64,
}

impl Default for DeviceParameters {
    fn default() -> Self {
        Self {
            inertia_kg_m2: 54.8e-6,
            viscous_nms_per_rad: 0.005,
            coulomb_nm: 0.005,
            encoder_counts_per_rev: 80_000,
            motor_torque_max_nm: 3.84,
        }
    }
}

/// Encoder reading of `angle_rad`: the count whose interval contains the angle (truncation toward
/// −∞, as an incremental encoder counts edges).
#[inline]
pub fn encoder_counts(angle_rad: f64, counts_per_rev: u32) -> i64 {
    (angle_rad * counts_per_rev as f64 / core::f64::consts::TAU).floor() as i64
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn encoder_quantises_to_the_interval_below() {
        let per_count = core::f64::consts::TAU / 80_000.0;
        assert_eq!(encoder_counts(2.5 * per_count, 80_000), 2);
        assert_eq!(encoder_counts(-0.5 * per_count, 80_000), -1);
        assert_eq!(encoder_counts(0.0, 80_000), 0);
    }
}
