//! A designed MR brake as a device: [`brake_model`] turns what the design's analyses predict (the
//! finite-element torque–current sweep, the step and frequency response, the hot coil) into the
//! brake model file the virtual rig and the haptic simulation run
//! ([`mrbrake_sim::brake_model::BrakeModel`]), each number with its provenance.
//!
//! Why a crate of its own: building the model needs the design's results (`mrbrake-design`) and
//! the file type (`mrbrake-sim`, which holds no finite-element code and should not pull it in),
//! and the studies of `mrbrake-explore` build it for their haptic metrics, so it sits below explore
//! (which gives the design key and model revision that identify the design,
//! [`brake_model::DesignIdentity`]). The report crate only presents. What
//! does not depend on a design — the dynamics fitted to any frequency-response data, predicted or
//! measured — lives next to the file type ([`mrbrake_sim::brake_model::fit`]).

pub mod brake_model;

/// Errors of this crate.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum DeviceError {
    /// A result the model cannot be amended with: of another design (names both), or a thermal
    /// analysis without a steady state.
    /// The field is the model file's design `name` or the thermal analysis's `current`.
    #[error(transparent)]
    Input(Box<mrbrake_error::FieldError>),
    /// The brake model: a fit, an invalid predicted value (names the field), a refused model.
    #[error(transparent)]
    Sim(#[from] mrbrake_sim::SimError),
}

impl From<mrbrake_error::FieldError> for DeviceError {
    fn from(error: mrbrake_error::FieldError) -> Self {
        Self::Input(Box::new(error))
    }
}

impl mrbrake_error::Kind for DeviceError {
    /// Input for a result that does not fit the model; wrapped errors keep their own kind.
    fn kind(&self) -> mrbrake_error::ErrorKind {
        match self {
            Self::Input(_) => mrbrake_error::ErrorKind::Input,
            Self::Sim(e) => e.kind(),
        }
    }
}
