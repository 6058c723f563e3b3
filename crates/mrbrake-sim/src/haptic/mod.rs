//! 1-DOF haptic simulation: the sticky wall of a conventional MR brake and its cure by the
//! bidirectional brake (thesis ch. 2 and §4.3), plus the passivity / Z-width map (thesis (2.2)–(2.4)).
//!
//! Brief overview: a [`HapticConfig`] (device kind, [`DeviceParameters`], [`HandModel`],
//! [`Scenario`], virtual wall, [`BrakeModel`]s and the controller's inverse models) is run by
//! [`simulate()`], which closes the loop around the `no_std` controller of `mrbrake-control` at 1 kHz
//! with zero-order hold and integrates the plant on a finer step; it returns [`WallMetrics`] and,
//! optionally, a [`Trace`]. [`zwidth`] sweeps stiffness and damping and classifies each pair as
//! passive, stable or unstable. [`characterization`] converts an identification JSON into the
//! controller's fixed-size model; [`prototype`] holds the built-in prototype-like branches.

pub mod bearing;
pub mod brake;
pub mod characterization;
pub mod device;
pub mod hand;
pub mod metrics;
pub mod prototype;
pub mod scenario;
pub mod simulate;
pub mod zwidth;

pub use brake::{BrakeModel, TorqueLag};
pub use device::{DeviceKind, DeviceParameters};
pub use hand::HandModel;
pub use metrics::{PeakMean, WallMetrics};
pub use scenario::Scenario;
pub use simulate::{HapticConfig, HapticRun, Trace, simulate};
