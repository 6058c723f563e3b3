//! The virtual environment rendered at each tick: a one-sided wall (spring + damper) and an optional
//! damping field.
//!
//! Inside the wall (penetration `p > 0`) the ideal rendered torque is the sampled spring–damper of the
//! Z-width literature (Colgate & Brown 1994; thesis (2.2)): `τ = −s·(K·p + B·s·ω)`, where `s = ±1`
//! is the side of the wall (`+1`: the wall occupies angles above its position). A motor renders this
//! torque directly; a brake can only resist motion, so its demand is the resisting part
//! `max(0, K·p + B·s·ω)` (see [`crate::controller`]).

/// Which side of its position the wall occupies.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum WallSide {
    /// The wall fills angles above `position_rad`; it resists positive (clockwise) motion.
    #[default]
    Positive,
    /// The wall fills angles below `position_rad`; it resists negative motion.
    Negative,
}

impl WallSide {
    /// `+1.0` for [`WallSide::Positive`], `-1.0` for [`WallSide::Negative`].
    #[inline]
    pub fn sign(self) -> f64 {
        match self {
            Self::Positive => 1.0,
            Self::Negative => -1.0,
        }
    }
}

/// A virtual wall: position, stiffness `K` and damping `B`, plus a damping field felt everywhere.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VirtualWall {
    /// Angle of the wall surface, rad.
    pub position_rad: f64,
    /// The side the wall occupies.
    pub side: WallSide,
    /// Virtual stiffness `K`, Nm/rad.
    pub stiffness_nm_per_rad: f64,
    /// Virtual damping `B` inside the wall, Nm·s/rad.
    pub damping_nms_per_rad: f64,
    /// Viscous damping field applied everywhere (a "thick fluid" effect), Nm·s/rad; 0 for none.
    pub field_damping_nms_per_rad: f64,
}

impl VirtualWall {
    /// A spring–damper wall at `position_rad` occupying `side`, without a damping field.
    pub const fn new(
        position_rad: f64,
        side: WallSide,
        stiffness_nm_per_rad: f64,
        damping_nms_per_rad: f64,
    ) -> Self {
        Self {
            position_rad,
            side,
            stiffness_nm_per_rad,
            damping_nms_per_rad,
            field_damping_nms_per_rad: 0.0,
        }
    }

    /// Penetration `p = s·(θ − θ_wall)`, rad (positive inside the wall).
    #[inline]
    pub fn penetration_rad(&self, angle_rad: f64) -> f64 {
        self.side.sign() * (angle_rad - self.position_rad)
    }

    /// The ideal (motor-rendered) torque on the shaft, Nm: the spring–damper inside the wall plus the
    /// damping field, `τ = −s·(K·p + B·s·ω)·[p > 0] − B_field·ω`.
    #[inline]
    pub fn ideal_torque_nm(&self, angle_rad: f64, velocity_rad_s: f64) -> f64 {
        let p = self.penetration_rad(angle_rad);
        let s = self.side.sign();
        let wall = if p > 0.0 {
            -s * (self.stiffness_nm_per_rad * p + self.damping_nms_per_rad * s * velocity_rad_s)
        } else {
            0.0
        };
        wall - self.field_damping_nms_per_rad * velocity_rad_s
    }
}
