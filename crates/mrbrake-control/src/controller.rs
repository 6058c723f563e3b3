//! The directional brake controller: configuration, state, one step.
//!
//! Each tick (1 kHz in the thesis's haptic loop, §2.1) [`DirectionalController::step`] turns the
//! measured angle and velocity and the virtual environment into two coil currents:
//!
//! 1. **Demand.** Inside the wall the resisting torque demand is `D = max(0, K·p + B·s·ω)` (the
//!    sampled spring–damper of (2.2); a brake can only resist, so the part that would push is
//!    dropped). A damping field adds `B_field·|ω|` on the brake that resists the present motion.
//! 2. **Direction logic.** With the bidirectional brake (thesis §4.3, Fig. 4.8) brake 1 is coupled
//!    through its one-way bearing only for positive motion and brake 2 only for negative motion, so
//!    the wall demand goes to the brake that resists motion *into* the wall and the other brake stays
//!    at zero: withdrawing is free. With a conventional single brake (no bearing) the one brake gets
//!    the demand whenever the handle penetrates, and it resists both directions: the sticky wall.
//! 3. **Hysteresis compensation.** The demand's change since the last tick selects the rising or the
//!    falling branch (thesis §5.3.2, Fig. 5.7), whose inverse gives the current (safeguarded Newton,
//!    warm-started from the previous tick's current, at most [`crate::MAX_INVERSE_ITERATIONS`]
//!    iterations): [`InverseModel::compensate`], one per brake.
//! 4. **Safety.** Non-finite or out-of-range input gives both currents 0 and a [`Fault`]; every
//!    current is finally clamped to `[0, I_max]`.
//! 5. **Demagnetising release** (optional, [`DirectionalController::with_demagnetisation`]): when a
//!    brake's demand is released the [`crate::demag`] waveform drives its coil through zero; its
//!    current may then be negative, down to the driver's reverse limit. Without it (the default, or
//!    a reverse limit of 0) the outputs are bit-identical to a controller without the feature.

use crate::demag::{DemagSettings, DemagState, Demagnetiser};
use crate::error::{ControlError, check_range};
use crate::inverse::{Branch, CURRENT_LIMIT_A, CompensationState, InverseModel};
use crate::torque_inverse::{TorqueInverse, TorqueInverseState};
use crate::wall::{VirtualWall, WallSide};

/// The mechanical arrangement the controller drives.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BrakeLayout {
    /// One MR brake rigidly on the shaft (output 0); output 1 is always 0.
    Conventional,
    /// Two MR brakes on opposite one-way bearings: output 0 (brake 1) resists positive motion,
    /// output 1 (brake 2) resists negative motion.
    Bidirectional,
}

/// Bounds that make an input plausible; anything outside is a [`Fault`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct InputLimits {
    /// Largest |angle| (shaft and wall), rad.
    pub angle_max_rad: f64,
    /// Largest |velocity|, rad/s.
    pub velocity_max_rad_s: f64,
    /// Largest virtual stiffness, Nm/rad.
    pub stiffness_max_nm_per_rad: f64,
    /// Largest virtual damping (wall and field), Nm·s/rad.
    pub damping_max_nms_per_rad: f64,
}

impl Default for InputLimits {
    /// Generous bounds for a 1-DOF paddle: ±100 turns, 200 rad/s, 10⁵ Nm/rad, 100 Nm·s/rad.
    fn default() -> Self {
        Self {
            angle_max_rad: 200.0 * core::f64::consts::PI,
            velocity_max_rad_s: 200.0,
            stiffness_max_nm_per_rad: 1e5,
            damping_max_nms_per_rad: 100.0,
        }
    }
}

/// Immutable controller configuration (validated on construction).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DirectionalController {
    layout: BrakeLayout,
    brakes: [TorqueInverse; 2],
    current_max_a: f64,
    radians_per_count: f64,
    limits: InputLimits,
    branch_deadband_nm: f64,
    demag: Demagnetiser,
}

/// Mutable controller state carried between ticks: each brake's hysteresis compensation (reference
/// demand, branch, and the previous current that warm-starts the next inversion) and the fault count.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ControllerState {
    compensation: [TorqueInverseState; 2],
    fault_count: u32,
    demag: [DemagState; 2],
}

impl ControllerState {
    /// Number of ticks that ended in a fault since the state was created.
    pub fn fault_count(&self) -> u32 {
        self.fault_count
    }

    /// The branch compensation of brake 1 and brake 2 (the state of [`TorqueInverse::Branches`]).
    pub fn compensation(&self) -> [CompensationState; 2] {
        [self.compensation[0].branches, self.compensation[1].branches]
    }

    /// The full inverse state of brake 1 and brake 2 (either model's memory).
    pub fn inverse_states(&self) -> &[TorqueInverseState; 2] {
        &self.compensation
    }

    /// The demagnetising release of brake 1 and brake 2 ([`crate::demag`]).
    pub fn demag_states(&self) -> &[DemagState; 2] {
        &self.demag
    }
}

/// Measurements and environment for one tick.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ControlInput {
    /// Encoder position, counts (zero at the reference angle).
    pub encoder_counts: i64,
    /// Velocity estimate, rad/s (e.g. from [`crate::VelocityEstimator`]).
    pub velocity_rad_s: f64,
    /// The environment to render.
    pub wall: VirtualWall,
}

/// Why a tick produced the safe output.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Fault {
    /// An input was NaN or infinite.
    NonFiniteInput,
    /// The shaft or wall angle exceeded [`InputLimits::angle_max_rad`].
    AngleOutOfRange,
    /// |velocity| exceeded [`InputLimits::velocity_max_rad_s`].
    VelocityOutOfRange,
    /// Stiffness or damping was negative or above its limit.
    EnvironmentOutOfRange,
}

/// What the step computed on the way to the currents (for logging and plots).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Breakdown {
    /// Shaft angle from the encoder, rad.
    pub angle_rad: f64,
    /// Penetration into the wall, rad (negative outside).
    pub penetration_rad: f64,
    /// Spring part of the wall demand `K·p`, Nm (0 outside).
    pub spring_torque_nm: f64,
    /// Damping part of the wall demand `B·s·ω`, Nm (0 outside).
    pub damping_torque_nm: f64,
    /// Damping-field part `B_field·|ω|`, Nm.
    pub field_torque_nm: f64,
    /// Resisting torque demanded from each brake, Nm (≥ 0).
    pub demand_nm: [f64; 2],
    /// Hysteresis branch used for each brake.
    pub branch: [Branch; 2],
}

/// Result of one tick.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ControlOutput {
    /// Coil currents for brake 1 and brake 2, A, in `[0, I_max]`; with a demagnetising release in
    /// `[−reverse_limit_a, I_max]`, negative only during a brake's release ([`crate::demag`]).
    pub current_a: [f64; 2],
    /// Set when the input was rejected and the currents forced to zero.
    pub fault: Option<Fault>,
    /// Intermediate values of this tick.
    pub breakdown: Breakdown,
}

impl DirectionalController {
    /// Builds a controller. `brakes[0]` is brake 1 (resists positive motion), `brakes[1]` brake 2
    /// (ignored by the conventional layout). `current_max_a` is `I_max` (0 < I_max ≤ 100 A),
    /// `counts_per_revolution` the encoder resolution (≥ 1), `branch_deadband_nm` (≥ 0) the demand
    /// change below which the hysteresis branch is kept (rejects velocity noise).
    pub fn new(
        layout: BrakeLayout,
        brakes: [InverseModel; 2],
        current_max_a: f64,
        counts_per_revolution: u32,
        limits: InputLimits,
        branch_deadband_nm: f64,
    ) -> Result<Self, ControlError> {
        let brakes = brakes.map(TorqueInverse::Branches);
        Self::with_inverses(
            layout,
            brakes,
            current_max_a,
            counts_per_revolution,
            limits,
            branch_deadband_nm,
        )
    }

    /// [`Self::new`] with either inverse per brake (polynomial branches or the operator model).
    pub fn with_inverses(
        layout: BrakeLayout,
        brakes: [TorqueInverse; 2],
        current_max_a: f64,
        counts_per_revolution: u32,
        limits: InputLimits,
        branch_deadband_nm: f64,
    ) -> Result<Self, ControlError> {
        let current_max_a =
            check_range("current_max_a", current_max_a, f64::MIN_POSITIVE, CURRENT_LIMIT_A)?;
        if counts_per_revolution == 0 {
            return Err(ControlError::OutOfRange {
                field: "counts_per_revolution",
                value: 0.0,
                min: 1.0,
                max: u32::MAX as f64,
            });
        }
        check_range("angle_max_rad", limits.angle_max_rad, 0.0, f64::MAX)?;
        check_range("velocity_max_rad_s", limits.velocity_max_rad_s, 0.0, f64::MAX)?;
        check_range("stiffness_max_nm_per_rad", limits.stiffness_max_nm_per_rad, 0.0, f64::MAX)?;
        check_range("damping_max_nms_per_rad", limits.damping_max_nms_per_rad, 0.0, f64::MAX)?;
        let branch_deadband_nm =
            check_range("branch_deadband_nm", branch_deadband_nm, 0.0, f64::MAX)?;
        Ok(Self {
            layout,
            brakes,
            current_max_a,
            radians_per_count: 2.0 * core::f64::consts::PI / counts_per_revolution as f64,
            limits,
            branch_deadband_nm,
            demag: Demagnetiser::disabled(),
        })
    }

    /// This controller with the demagnetising release `settings` ([`crate::demag`]) for a loop of
    /// tick `control_period_s`; the errors name the field and its range. A reverse limit of 0 (a
    /// unipolar driver) leaves the controller as it was.
    pub fn with_demagnetisation(
        self,
        settings: &DemagSettings,
        control_period_s: f64,
    ) -> Result<Self, ControlError> {
        let demag = Demagnetiser::new(settings, control_period_s, self.current_max_a)?;
        Ok(Self { demag, ..self })
    }

    /// The demagnetising release (disabled unless [`Self::with_demagnetisation`] enabled it).
    pub fn demagnetiser(&self) -> &Demagnetiser {
        &self.demag
    }

    /// The brake arrangement.
    pub fn layout(&self) -> BrakeLayout {
        self.layout
    }

    /// `I_max`, A.
    pub fn current_max_a(&self) -> f64 {
        self.current_max_a
    }

    /// Encoder resolution, rad per count.
    pub fn radians_per_count(&self) -> f64 {
        self.radians_per_count
    }

    /// The inverse models of brake 1 and brake 2.
    pub fn brakes(&self) -> &[TorqueInverse; 2] {
        &self.brakes
    }

    /// Checks the input; `Some(fault)` when it must be rejected.
    fn check(&self, input: &ControlInput, angle_rad: f64) -> Option<Fault> {
        let wall = &input.wall;
        let finite = angle_rad.is_finite()
            && input.velocity_rad_s.is_finite()
            && wall.position_rad.is_finite()
            && wall.stiffness_nm_per_rad.is_finite()
            && wall.damping_nms_per_rad.is_finite()
            && wall.field_damping_nms_per_rad.is_finite();
        if !finite {
            return Some(Fault::NonFiniteInput);
        }
        if angle_rad.abs() > self.limits.angle_max_rad
            || wall.position_rad.abs() > self.limits.angle_max_rad
        {
            return Some(Fault::AngleOutOfRange);
        }
        if input.velocity_rad_s.abs() > self.limits.velocity_max_rad_s {
            return Some(Fault::VelocityOutOfRange);
        }
        let in_range = |value: f64, max: f64| (0.0..=max).contains(&value);
        if !(in_range(wall.stiffness_nm_per_rad, self.limits.stiffness_max_nm_per_rad)
            && in_range(wall.damping_nms_per_rad, self.limits.damping_max_nms_per_rad)
            && in_range(wall.field_damping_nms_per_rad, self.limits.damping_max_nms_per_rad))
        {
            return Some(Fault::EnvironmentOutOfRange);
        }
        None
    }

    /// One control tick: returns the two coil currents (in `[0, I_max]`; with a demagnetising release
    /// in `[−reverse_limit_a, I_max]`), a fault flag and the breakdown. Never panics, never allocates.
    pub fn step(&self, state: &mut ControllerState, input: &ControlInput) -> ControlOutput {
        let angle_rad = input.encoder_counts as f64 * self.radians_per_count;
        if let Some(fault) = self.check(input, angle_rad) {
            state.compensation = [TorqueInverseState::default(); 2];
            state.demag = [DemagState::default(); 2];
            state.fault_count = state.fault_count.saturating_add(1);
            return ControlOutput {
                current_a: [0.0; 2],
                fault: Some(fault),
                breakdown: Breakdown { angle_rad, ..Breakdown::default() },
            };
        }
        let mut breakdown = self.demands(input, angle_rad);
        let mut current_a = [0.0; 2];
        for k in 0..2 {
            current_a[k] = self.brakes[k].compensate(
                &mut state.compensation[k],
                breakdown.demand_nm[k],
                self.current_max_a,
                self.branch_deadband_nm,
            );
            breakdown.branch[k] = state.compensation[k].branch(&self.brakes[k]);
            let demag = self.demag.apply(&mut state.demag[k], breakdown.demand_nm[k], current_a[k]);
            current_a[k] = demag.current_a;
            if demag.completed {
                // The loop is back near its demagnetised origin: compensate from rest again.
                state.compensation[k] = TorqueInverseState::default();
            }
        }
        if self.layout == BrakeLayout::Conventional {
            current_a[1] = 0.0;
        }
        ControlOutput { current_a, fault: None, breakdown }
    }

    /// Steps 1 and 2 of the module docs: the wall and field demands and the brake that carries each
    /// (the breakdown without its branches).
    #[inline]
    fn demands(&self, input: &ControlInput, angle_rad: f64) -> Breakdown {
        let wall = &input.wall;
        let velocity = input.velocity_rad_s;
        let s = wall.side.sign();
        let penetration_rad = wall.penetration_rad(angle_rad);
        let (spring_torque_nm, damping_torque_nm) = if penetration_rad > 0.0 {
            (wall.stiffness_nm_per_rad * penetration_rad, wall.damping_nms_per_rad * s * velocity)
        } else {
            (0.0, 0.0)
        };
        let wall_demand = (spring_torque_nm + damping_torque_nm).max(0.0);
        let field_torque_nm = wall.field_damping_nms_per_rad * velocity.abs();

        // Direction logic: which output carries the wall demand and which the field demand.
        let mut demand_nm = [0.0; 2];
        match self.layout {
            BrakeLayout::Conventional => demand_nm[0] = wall_demand + field_torque_nm,
            BrakeLayout::Bidirectional => {
                let into_wall = match wall.side {
                    WallSide::Positive => 0,
                    WallSide::Negative => 1,
                };
                demand_nm[into_wall] += wall_demand;
                // The field resists the present motion: brake 1 for ω > 0, brake 2 for ω < 0.
                let along_motion = if velocity >= 0.0 { 0 } else { 1 };
                demand_nm[along_motion] += field_torque_nm;
            }
        }
        Breakdown {
            angle_rad,
            penetration_rad,
            spring_torque_nm,
            damping_torque_nm,
            field_torque_nm,
            demand_nm,
            branch: [Branch::Rising; 2],
        }
    }
}
