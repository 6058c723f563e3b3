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
//! Runs and optimisations report to an [`mrbrake_observe::Observer`] ([`Progress`] per stored
//! design, [`optimize::OptimizeProgress`] over a whole optimisation), which may stop them; every
//! evaluation finished before a stop stays in the store.

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
    /// Bad input: a variable, value, problem-file field or plan that is not allowed (the message
    /// names it and the allowed values).
    #[error("{0}")]
    Input(String),
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
            Self::Internal(_) => ErrorKind::Internal,
        }
    }
}
