//! `no_std`, allocation-free real-time controller for a bidirectional MR brake.
//!
//! Brief overview: a [`DirectionalController`] (immutable configuration: brake layout, the two
//! brakes' [`InverseModel`]s, `I_max`, encoder resolution, input limits) turns a [`ControlInput`]
//! (encoder counts, velocity estimate, [`VirtualWall`]) and a [`ControllerState`] into a
//! [`ControlOutput`]: two coil currents in `[0, I_max]`, a [`Fault`] flag and a [`Breakdown`] of the
//! step for logging. An optional demagnetising release ([`demag`], [`Demagnetiser`]) drives a
//! released brake's coil through zero against the steel's remanence (its current may then be
//! negative, down to the driver's reverse limit). [`VelocityEstimator`] gives the velocity from successive encoder angles;
//! [`BranchPolynomial`] is one hysteresis branch `T(i)` and its bounded-iteration inverse.
//!
//! The crate uses neither `std` nor `alloc` (only `core` and `libm`), has no `unsafe`, and its step
//! never panics, so it can run in a 1 kHz interrupt on a microcontroller. The `std` feature only adds
//! `std::error::Error` for [`ControlError`]; the `serde` feature (no_std, no allocation) reads and
//! writes an [`InverseModel`] as the inverse-model file whose schema [`InverseModelFile`] documents
//! (the file `mrbrake characterize --save-model` writes).
//!
//! ```
//! use mrbrake_control::*;
//! // A linear stand-in for an identified brake: 0.15 Nm off-state, +1.845 Nm/A.
//! let brake = InverseModel::new(&[0.15, 1.845], &[0.25, 1.795], 0.0, 2.0)?;
//! let controller = DirectionalController::new(
//!     BrakeLayout::Bidirectional, [brake, brake], 2.0, 80_000, InputLimits::default(), 0.01)?;
//! let mut state = ControllerState::default();
//! let wall = VirtualWall { position_rad: 0.0, side: WallSide::Positive,
//!     stiffness_nm_per_rad: 20.0, damping_nms_per_rad: 0.0, field_damping_nms_per_rad: 0.0 };
//! // 1000 counts = 0.0785 rad into the wall: brake 1 resists, brake 2 stays off.
//! let out = controller.step(&mut state, &ControlInput { encoder_counts: 1000, velocity_rad_s: 0.1, wall });
//! assert!(out.current_a[0] > 0.5 && out.current_a[1].abs() < 1e-12 && out.fault.is_none());
//! # Ok::<(), ControlError>(())
//! ```
#![cfg_attr(not(any(test, feature = "std")), no_std)]
#![forbid(unsafe_code)]

pub mod controller;
pub mod demag;
pub mod error;
pub mod inverse;
pub mod operator;
pub mod polynomial;
pub mod torque_inverse;
pub mod velocity;
pub mod wall;

pub use controller::{
    BrakeLayout, Breakdown, ControlInput, ControlOutput, ControllerState, DirectionalController,
    Fault, InputLimits,
};
pub use demag::{
    DemagOutput, DemagSettings, DemagState, DemagWaveform, Demagnetiser, MAX_DEMAG_TICKS,
    MAX_HALF_CYCLES,
};
pub use error::ControlError;
pub use inverse::{Branch, CURRENT_LIMIT_A, CompensationState, InverseModel, InverseModelFile};
pub use operator::{
    MAX_PLAYS, MAX_SEGMENTS, OPERATOR_SCHEMA, OPERATOR_SCHEMA_VERSION, OperatorCompensation,
    OperatorModel, OperatorParts, OperatorState,
};
pub use polynomial::{BranchPolynomial, MAX_DEGREE, MAX_INVERSE_ITERATIONS};
pub use torque_inverse::{TorqueInverse, TorqueInverseState};
pub use velocity::{VelocityEstimator, VelocityState};
pub use wall::{VirtualWall, WallSide};
