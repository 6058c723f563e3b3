//! Plant models, virtual test rig and haptic simulation.
//!
//! Brief overview: [`lti`] discretises a continuous-time transfer function
//! ([`mrbrake_sysid::transfer_function::TransferFunction`], the one such type) exactly for a
//! zero-order-hold input, with the crate's one matrix exponential [`lti::expm`]; [`rig`] is the
//! virtual test rig that writes the logs of the thesis's experiments; [`haptic`] closes the 1 kHz
//! loop around the `no_std` controller of `mrbrake-control`. The brake model every stage shares is
//! the controller's [`mrbrake_control::InverseModel`] (read from a file by
//! [`mrbrake_sysid::model_file`]). [`brake_model`] is the brake model file (a design's predicted
//! static curve, off-state, dynamics, thermal limits and hysteresis description) that the rig and
//! the haptic simulation can run instead of their built-in prototype-like brakes.

pub mod brake_model;
pub mod haptic;
pub mod lti;
pub mod rig;

/// Errors of this crate.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum SimError {
    /// Invalid input: the file when known, the field (a configuration key such as
    /// `hysteresis.levels`, or an argument such as `dt`), the value and what is allowed.
    #[error(transparent)]
    Input(Box<mrbrake_error::FieldError>),
    /// A configuration file is not valid TOML, or has an unknown or mistyped field.
    #[error("{file}")]
    Toml {
        /// The file (or in-memory source name).
        file: String,
        /// The TOML parser's error (it names the field and shows the line).
        source: toml::de::Error,
    },
    /// A file could not be read.
    #[error("cannot read {what} '{}'", path.display())]
    Io {
        /// What the file is, e.g. `"rig configuration"`.
        what: &'static str,
        /// The file.
        path: std::path::PathBuf,
        /// The underlying I/O error.
        source: std::io::Error,
    },
    /// An identification step inside a simulation (a model file, log parsing) failed.
    #[error(transparent)]
    Sysid(#[from] mrbrake_sysid::SysidError),
    /// A model of the plant is unusable (e.g. an improper transfer function), with which one.
    #[error("{what}")]
    Model {
        /// The model, e.g. `"brake dynamics"`.
        what: &'static str,
        /// Why it was refused.
        source: mrbrake_sysid::SysidError,
    },
    /// A brake model file is not JSON, has a foreign schema or version, or a missing, unknown or
    /// invalid field: names the file and the field.
    #[error("brake model '{file}', field {field}: {message}")]
    BrakeModel {
        /// The file (or in-memory source name).
        file: String,
        /// The dotted path of the field, e.g. `units[0].static_curve.torque_Nm[3]`.
        field: String,
        /// What is wrong and what is allowed.
        message: String,
    },
    /// The controller refused its configuration or a brake model, with where.
    #[error("{what}")]
    Control {
        /// What was being built, e.g. `"haptic controller"`.
        what: &'static str,
        /// The controller's error.
        source: mrbrake_control::ControlError,
    },
}

impl From<mrbrake_error::FieldError> for SimError {
    fn from(error: mrbrake_error::FieldError) -> Self {
        Self::Input(Box::new(error))
    }
}

impl SimError {
    /// The same error with the field of an input error named as a front end names it (see
    /// [`mrbrake_error::FieldError::renamed`]: the CLI's `--stiffness` for
    /// `wall_stiffness_nm_per_rad`); other errors are unchanged.
    pub fn with_field_names(self, names: &[(&str, &str)]) -> Self {
        match self {
            Self::Input(field) => Self::Input(Box::new(field.renamed(names))),
            Self::Sysid(e) => Self::Sysid(e.with_field_names(names)),
            other => other,
        }
    }
}

impl mrbrake_error::Kind for SimError {
    /// Input for bad configurations; wrapped identification and controller errors keep their kind.
    fn kind(&self) -> mrbrake_error::ErrorKind {
        match self {
            Self::Input(_) | Self::Toml { .. } | Self::BrakeModel { .. } => {
                mrbrake_error::ErrorKind::Input
            }
            Self::Io { source, .. } => mrbrake_error::Kind::kind(source),
            Self::Sysid(e) | Self::Model { source: e, .. } => e.kind(),
            Self::Control { source, .. } => source.kind(),
        }
    }
}
