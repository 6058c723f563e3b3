//! Axisymmetric heat conduction on the mrbrake finite-element core: the coil's temperature, the
//! brake's continuous current rating and the fluid's temperature on the same meshes as the
//! magnetics.
//!
//! The physics is `ρc ∂T/∂t = (1/r) ∂_r(r k_r ∂_r T) + ∂_z(k_z ∂_z T) + q(T)` in the (r, z)
//! half-plane (e.g. Incropera et al., *Fundamentals of Heat and Mass Transfer*, 6th ed., eq. 2.24
//! with an anisotropic conductivity), as forms on `mrbrake-fem` (nothing of the core is copied):
//!
//! - [`problem`]: the problem in SI (kelvin inside): regions with conductivity (radial and axial,
//!   for the homogenised winding), heat capacity per volume and a source (uniform, or the coil's
//!   Joule loss `I² R(T)` with `R(T) = R20 (1 + α (T − 20 °C))`), boundaries (convection
//!   `h (T − T_∞)`, radiation `εσ(T⁴ − T_∞⁴)`, fixed temperature, adiabatic), validated field by
//!   field;
//! - [`form`]: the weak form as an `ElementForm` (conduction, the affine source, the capacity term of
//!   a time step);
//! - [`solver`]: the set-up and the steady solve (Newton for radiation), the boundary fluxes
//!   through the core's `EdgeFlux` seam;
//! - [`transient`]: the heat problem on the core's time integrator (implicit Euler or BDF2, fixed
//!   or adaptive steps; a linear problem is factorised once per step size, a step is one capacity
//!   product and one solve);
//! - [`post`]: probes, region mean/max/heat, boundary heat out and the energy balance;
//! - [`problem_file`]: the `physics = "heat"` TOML problem files of `mrbrake fem solve`;
//! - [`convection`]: natural-convection correlations (Churchill–Chu) for `h(T_s)`;
//! - [`exact`]: closed-form solutions the validation tests compare with.
//!
//! The Joule source is applied locally: with the same current in every turn, the loss per volume is
//! `J² ρ_e(T)/λ` at the local temperature, so the coil's total loss is `I² R(T̄)` with `T̄` its
//! volume-mean temperature — the self-consistent coupling is an affine source in `T`, solved by the
//! same Newton iteration as everything else (one step when nothing else is non-linear). When the
//! Joule feedback outruns the cooling there is no steady state (thermal runaway): the system matrix
//! stops being positive definite and the solve fails with a numerical error saying so.

pub mod convection;
pub mod exact;
pub mod form;
pub mod post;
pub mod problem;
pub mod problem_file;
pub mod solver;
pub mod transient;

pub use mrbrake_fem::discretisation::dofs::ElementOrder;
pub use problem::{Boundary, BoundaryCondition, HeatProblem, Region, Source};
pub use solver::{HeatSolver, SolverOptions};

/// Stefan–Boltzmann constant σ = 5.670 374 419·10⁻⁸ W/(m²·K⁴), exact in the 2019 SI (CODATA 2018).
pub const STEFAN_BOLTZMANN: f64 = 5.670_374_419e-8;

/// 0 °C in kelvin.
pub const ZERO_CELSIUS_K: f64 = 273.15;

/// The reference temperature of resistances, 20 °C, in kelvin.
pub const T20_K: f64 = ZERO_CELSIUS_K + 20.0;

/// Errors of the heat solver.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum HeatError {
    /// Invalid input: the file (if any), the field (a problem-file key or an argument such as
    /// `point`), the value and what is allowed.
    #[error(transparent)]
    Input(Box<mrbrake_error::FieldError>),
    /// Every invalid field of a problem file.
    #[error(transparent)]
    Fields(#[from] mrbrake_error::FieldErrors),
    /// A mesh or finite-element error.
    #[error(transparent)]
    Fem(#[from] mrbrake_fem::FemError),
    /// A material-library error.
    #[error(transparent)]
    Material(#[from] mrbrake_materials::MaterialError),
    /// Newton failed; the history says how far it got.
    #[error(transparent)]
    NotConverged(#[from] mrbrake_fem::workflow::newton::NewtonError),
    /// A transient failed: its options, its step bound, or a step (which one, at what time, and
    /// why: Newton's residual history is the next error of the chain).
    #[error(transparent)]
    Time(#[from] mrbrake_fem::workflow::time::TimeError),
    /// The Joule (or another temperature-increasing) source outruns the cooling: no steady state.
    #[error(
        "thermal runaway: {0}; the heat generated grows faster with temperature than the \
         boundaries remove it, so there is no steady state (lower the current, raise the cooling)"
    )]
    Runaway(String),
    /// A transient that crossed a limit it was given.
    #[error("{0}")]
    LimitCrossed(String),
    /// A broken invariant of the solver (a bug: please report it).
    #[error("internal error of the heat solver: {0}")]
    Internal(String),
}

impl From<mrbrake_error::FieldError> for HeatError {
    fn from(error: mrbrake_error::FieldError) -> Self {
        Self::Input(Box::new(error))
    }
}

impl mrbrake_error::Kind for HeatError {
    /// Bad input is input; wrapped errors keep their kind; solver failures are numerical.
    fn kind(&self) -> mrbrake_error::ErrorKind {
        use mrbrake_error::ErrorKind;
        match self {
            Self::Input(_) | Self::Fields(_) => ErrorKind::Input,
            Self::Fem(e) => e.kind(),
            Self::Material(e) => e.kind(),
            Self::NotConverged(e) => e.kind(),
            Self::Time(e) => e.kind(),
            Self::Runaway(_) | Self::LimitCrossed(_) => ErrorKind::Numerical,
            Self::Internal(_) => ErrorKind::Internal,
        }
    }
}

/// The ambient temperatures every reader accepts (°C): above absolute zero, at most 200 °C (the
/// range of the air properties of natural convection and of the brake's materials' thermal
/// data). One rule for `thermal --ambient` and a heat problem file's `T_amb_C` (issue 33).
pub const AMBIENT_C: mrbrake_schema::Bounds =
    mrbrake_schema::Bounds::open_closed(-ZERO_CELSIUS_K, 200.0);

/// The fixed and initial temperatures a heat problem file accepts (°C): above absolute zero, at
/// most 2000 °C (no thermal data of the library holds beyond; a larger value is a unit mistake).
pub const TEMPERATURE_C: mrbrake_schema::Bounds =
    mrbrake_schema::Bounds::open_closed(-ZERO_CELSIUS_K, 2000.0);

/// Kelvin of degrees Celsius.
pub fn kelvin(celsius: f64) -> f64 {
    celsius + ZERO_CELSIUS_K
}

/// Degrees Celsius of kelvin.
pub fn celsius(kelvin: f64) -> f64 {
    kelvin - ZERO_CELSIUS_K
}
