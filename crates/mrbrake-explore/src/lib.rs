//! Design-space exploration for MR brakes: sweeps and optimisation over the fields of a brake spec,
//! where every design is analysed by the real FEA (`mrbrake analyze`) and kept in a durable,
//! resumable results store.
//!
//! Brief overview, in data-flow order:
//! * [`variable`]: which spec fields a study may vary (`drum.gap`, or the thesis symbol `g`), their
//!   units, and how a value is written into a spec;
//! * [`design`]: a [`design::DesignSpace`] (base spec + variables + settings) and its points, each a
//!   [`design::Design`] with a canonical SHA-256 key over everything its result depends on;
//! * [`evaluate`]: one analysis reduced to named metrics ([`evaluate::METRICS`]), or the reason the
//!   design is infeasible or failed;
//! * [`metrics`]: the dynamics and heat metrics, computed only when a study asks for them, in a
//!   cascade of fidelity levels after the static analysis;
//! * [`runner`]: evaluates a batch of designs in parallel, storing each result in the
//!   [`mrbrake_store::Store`] the moment it completes and never recomputing a stored design;
//! * [`stored`]: reading and merging stores under the current metric names;
//! * [`plan`]: sweep plans (lists, ranges, Latin hypercube, Sobol') and deterministic shards;
//! * [`problem`] and [`optimize`]: optimisation problem files (variables, constraints, objectives)
//!   solved by NSGA-II, the surrogate-assisted optimiser ([`surrogate`]) or pattern search from
//!   [`mrbrake_optim`], every evaluation through the store; [`hypervolume`] measures every run,
//!   [`front`] writes the front's designs (in the base spec's units, rounded and evaluated again),
//!   [`polish`] refines one by a local pattern search.
//!
//! [`uncertainty`] propagates declared input spreads through the FEA; [`calibrate`] fits spec
//! fields to a rig's measured loop.
//!
//! Runs and optimisations report to an [`mrbrake_observe::Observer`] ([`Progress`] per stored
//! design, [`optimize::OptimizeProgress`] over a whole optimisation), which may stop them; every
//! evaluation finished before a stop stays in the store.

pub mod calibrate;
pub mod design;
pub mod evaluate;
pub mod front;
pub mod hypervolume;
pub mod metrics;
pub mod optimize;
pub mod plan;
pub mod polish;
pub mod problem;
pub mod runner;
pub mod stored;
pub mod surrogate;
pub mod uncertainty;
pub mod variable;

pub use design::{Design, DesignSpace};
pub use evaluate::{EvaluationSettings, METRICS, Outcome};
pub use runner::{Progress, RunSummary, Runner};

/// Errors of this crate.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ExploreError {
    /// Bad input: a variable, value, problem-file field or plan that is not allowed: the file
    /// (the problem file, when the input came from one), the field (a problem-file key such as
    /// `algorithm.population` or `variable[2].min`, a spec path, or an argument such as `--vary`),
    /// the value and what is allowed.
    #[error(transparent)]
    Input(Box<mrbrake_error::FieldError>),
    /// The base spec or the analysis set-up.
    #[error(transparent)]
    Design(#[from] mrbrake_design::DesignError),
    /// The base spec of a study is not a valid brake where a valid one is needed.
    #[error("{what}: the base spec is invalid")]
    InvalidBase {
        /// What needed it, e.g. `algorithm.start = "base"`.
        what: &'static str,
        /// Why it is invalid (its invalid fields).
        source: std::sync::Arc<mrbrake_design::DesignError>,
    },
    /// A material name or curve.
    #[error(transparent)]
    Material(#[from] mrbrake_materials::MaterialError),
    /// The results store (a foreign or corrupt file, an existing store without `--resume`, I/O).
    #[error(transparent)]
    Store(#[from] mrbrake_store::StoreError),
    /// The optimiser's set-up.
    #[error(transparent)]
    Optim(#[from] mrbrake_optim::OptimError),
    /// The uncertainty core (a law's parameters, a surrogate fit).
    #[error(transparent)]
    Uq(#[from] mrbrake_uq::UqError),
    /// A rig log or its characterisation (`mrbrake calibrate --log`).
    #[error(transparent)]
    Sysid(#[from] mrbrake_sysid::SysidError),
    /// The caller's observer stopped a run before every design was evaluated; every evaluation
    /// finished before the stop (and those in flight then) is in the store.
    #[error(
        "the study was stopped after {} of {} evaluations (each finished one is stored)",
        progress.computed,
        progress.to_compute
    )]
    Stopped {
        /// Where the run stood when it stopped.
        progress: Progress,
    },
    /// A defect or an unexpected internal state.
    #[error("internal error: {0}")]
    Internal(String),
}

impl From<mrbrake_error::FieldError> for ExploreError {
    fn from(error: mrbrake_error::FieldError) -> Self {
        Self::Input(Box::new(error))
    }
}

impl From<Box<mrbrake_error::FieldError>> for ExploreError {
    fn from(error: Box<mrbrake_error::FieldError>) -> Self {
        Self::Input(error)
    }
}

impl ExploreError {
    /// An input error about `field` (empty: the whole input) saying `message`.
    pub(crate) fn input(field: impl Into<String>, message: impl Into<String>) -> Self {
        mrbrake_error::FieldError::new(field, message).into()
    }

    /// The field error of an input error of this crate or of the design crate (an option the
    /// design library checks); `None` for any other error.
    fn field_error(self) -> Result<Box<mrbrake_error::FieldError>, Self> {
        match self {
            Self::Input(field) | Self::Design(mrbrake_design::DesignError::Input(field)) => {
                Ok(field)
            }
            other => Err(other),
        }
    }

    /// The same error with `change` applied to its field error, when it has one.
    pub(crate) fn map_field(
        self,
        change: impl FnOnce(mrbrake_error::FieldError) -> mrbrake_error::FieldError,
    ) -> Self {
        match self.field_error() {
            Ok(field) => Self::Input(Box::new(change(*field))),
            Err(other) => other,
        }
    }

    /// The same error with the field of an input error inside `parent` (the `[response]`
    /// options' `duration` becomes `response.duration`).
    pub(crate) fn under(self, parent: &str) -> Self {
        self.map_field(|f| f.under(parent))
    }

    /// The same error located in `file`, when it is an input error not located yet.
    pub(crate) fn in_file(self, file: &str) -> Self {
        self.map_field(|f| if f.file.is_some() { f } else { f.in_file(file, None) })
    }

    /// The same error saying that `metric` needs the field (a setting the metric's analysis uses).
    pub(crate) fn for_metric(self, metric: &str) -> Self {
        self.map_field(|mut f| {
            f.message = if f.message.is_empty() {
                format!("for metric '{metric}'")
            } else {
                format!("{}, for metric '{metric}'", f.message)
            };
            f
        })
    }

    /// The same error with the field of an input error named as a front end names it (see
    /// [`mrbrake_error::FieldError::renamed`]: the CLI's `--max-evaluations` for
    /// `max_evaluations`); an error located in a file keeps the file's key (a problem file's
    /// `speed` is not the `--speed` flag), other errors are unchanged.
    pub fn with_field_names(self, names: &[(&str, &str)]) -> Self {
        self.map_field(|f| if f.file.is_some() { f } else { f.renamed(names) })
    }
}

impl mrbrake_error::Kind for ExploreError {
    /// Input for bad variables, values and problem files; wrapped errors keep their own kind. A
    /// stop is the caller's own request, not a failure: input, as for the design crate's stop.
    fn kind(&self) -> mrbrake_error::ErrorKind {
        use mrbrake_error::ErrorKind;
        match self {
            Self::Input(_) | Self::Stopped { .. } => ErrorKind::Input,
            Self::Design(e) => e.kind(),
            Self::InvalidBase { source, .. } => source.kind(),
            Self::Material(e) => e.kind(),
            Self::Store(e) => e.kind(),
            Self::Optim(e) => e.kind(),
            Self::Uq(e) => e.kind(),
            Self::Sysid(e) => e.kind(),
            Self::Internal(_) => ErrorKind::Internal,
        }
    }
}
