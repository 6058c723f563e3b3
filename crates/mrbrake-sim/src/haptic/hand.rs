//! The user's hand: a mass–spring–damper that tracks an intended motion.
//!
//! The hand grips the handle at lever arm `r`, so its endpoint impedance (mass `m`, damping `b_h`,
//! stiffness `k_h` toward the intended position) becomes rotational: `J_h = m r²`, `B_h = b_h r²`,
//! `K_h = k_h r²`, and the hand torque on the shaft is `τ_h = K_h (θ_i − θ) + B_h (ω_i − ω)`
//! (the "intended trajectory + impedance" hand of Hogan 1985 and of the Z-width studies, e.g.
//! Colgate & Brown 1994). The mass moves with the handle (firm grasp).
//!
//! Default values are nominal, not one subject's: endpoint mass 1 kg, damping 10 N·s/m, stiffness
//! 300 N/m, inside the ranges reported for the human arm holding a posture (Dolan, Friedman & Dolan
//! 1993, J. Biomech. 26(4–5); Tsuji, Morasso, Goto & Ito 1995, Biol. Cybern. 72(6)); the lever arm
//! of 0.1 m is a paddle handle like the thesis's 1-DOF haptic paddle (Karabulut et al. 2015).

/// Hand parameters (SI, translational at the grip) and the lever arm.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct HandModel {
    /// Effective endpoint mass moving with the handle, kg.
    pub mass_kg: f64,
    /// Endpoint damping, N·s/m.
    pub damping_ns_per_m: f64,
    /// Endpoint stiffness toward the intended position, N/m.
    pub stiffness_n_per_m: f64,
    /// Lever arm from the shaft to the grip, m.
    pub lever_arm_m: f64,
}

impl Default for HandModel {
    fn default() -> Self {
        Self { mass_kg: 1.0, damping_ns_per_m: 10.0, stiffness_n_per_m: 300.0, lever_arm_m: 0.1 }
    }
}

impl HandModel {
    /// Rotational inertia `J_h = m r²`, kg·m².
    pub fn inertia_kg_m2(&self) -> f64 {
        self.mass_kg * self.lever_arm_m * self.lever_arm_m
    }

    /// Rotational damping `B_h = b_h r²`, Nm·s/rad.
    pub fn damping_nms_per_rad(&self) -> f64 {
        self.damping_ns_per_m * self.lever_arm_m * self.lever_arm_m
    }

    /// Rotational stiffness `K_h = k_h r²`, Nm/rad.
    pub fn stiffness_nm_per_rad(&self) -> f64 {
        self.stiffness_n_per_m * self.lever_arm_m * self.lever_arm_m
    }
}
