//! 1-DOF haptic simulation: the sticky wall of a conventional MR brake and its cure by the
//! bidirectional brake (thesis ch. 2 and §4.3), plus the passivity / Z-width map (thesis (2.2)–(2.4)).
//!
//! Brief overview: a [`HapticConfig`] (device kind, [`DeviceParameters`], [`HandModel`],
//! [`Scenario`], virtual wall, [`BrakePlant`]s and the controller's inverse models) is run by
//! [`simulate()`], which closes the loop around the `no_std` controller of `mrbrake-control` at 1 kHz
//! with zero-order hold and integrates the plant on a finer step; it returns [`WallMetrics`] and,
//! optionally, a [`Trace`]. A brake whose model carries a Preisach table runs it
//! ([`PreisachBrake`], the rig's Preisach operator), any other the clamp between its branches.
//! [`remanence`] adds the steel's predicted remanent torque to the plant and the controller's
//! demagnetising release that removes it. [`zwidth`] sweeps stiffness and damping and classifies
//! each pair as passive, stable or unstable. [`prototype`] holds the built-in prototype-like branches; an
//! identified model is read with [`mrbrake_sysid::model_file::read_inverse_model`].

pub mod bearing;
pub mod brake;
pub mod device;
pub mod hand;
pub mod metrics;
pub mod prototype;
pub mod remanence;
pub mod scenario;
pub mod simulate;
pub mod zwidth;

pub use brake::{BrakePlant, PreisachBrake, TorqueLag};
pub use device::{DeviceKind, DeviceParameters};
pub use hand::HandModel;
pub use metrics::{DragAfter, PeakMean, WallMetrics};
pub use remanence::{PlantRemanence, ReleaseModel, RemanenceState};
pub use scenario::Scenario;
pub use simulate::{HapticConfig, HapticRun, Trace, simulate};

use mrbrake_error::FieldError;

use crate::SimError;

/// `Ok` for a finite `value` in `[min, max]`, else an input error naming `context`, the field and the
/// range (the settings checks of a run and of a sweep).
pub(crate) fn check_range(
    context: &str,
    field: &str,
    value: f64,
    min: f64,
    max: f64,
) -> Result<(), SimError> {
    if value.is_finite() && value >= min && value <= max {
        Ok(())
    } else {
        let e = FieldError::new(field, context).with_value(value);
        Err(e.with_allowed(format!("[{min}, {max}]")).into())
    }
}
