//! One time integrator for every physics: implicit Euler and variable-step BDF2, fixed or adaptive
//! steps, Newton in every step, one observer call per accepted step.
//!
//! A physics in time is the semi-discrete system (on the free DOFs of `u`)
//!
//! `M u̇ + S(u) + L(u, t) = 0`,
//!
//! with `S` the static form (what a steady solve assembles), `M` a constant mass (capacity)
//! matrix, positive semi-definite (`σ M` of eddy currents, `ρc M` of heat; zero for a
//! quasi-static sequence of load steps) and `L` what depends on the time: loads and couplings to
//! *auxiliary states* `y(u)`, scalars that are linear functionals of `u` and whose rates the
//! physics needs (a coil's flux linkage `λ = 2π c·a` in its circuit equation `v = R i + dλ/dt`).
//! The physics says all this through [`TransientProblem`]; this module knows no physics.
//!
//! Schemes (Hairer & Wanner, *Solving Ordinary Differential Equations II*, 2nd ed., §III.1 and
//! §V.1; both A-stable, and L-stable so the jump of a step input is damped, not rung):
//! - implicit Euler, `u̇_{n+1} ≈ (u_{n+1} − u_n)/Δt`, first order;
//! - BDF2 with variable steps, `u̇_{n+1} ≈ [γ u_{n+1} − (1+ω) u_n + ω²/(1+ω) u_{n−1}]/Δt_n`,
//!   `ω = Δt_n/Δt_{n−1}`, `γ = (1+2ω)/(1+ω)` (Hairer, Nørsett & Wanner, *Solving ODEs I*, 2nd ed.,
//!   §III.5, the variable-step BDF of eq. (5.8) for k = 2; for `ω = 1` the classical
//!   `(3u_{n+1} − 4u_n + u_{n−1})/(2Δt)`), second order, started by one implicit-Euler step (its
//!   local error is `O(Δt²)`, so the global order stays two: *Solving ODEs I*, §III.3).
//!
//! Both are written `u̇_{n+1} ≈ ρ (u_{n+1} − h)` with the rate `ρ = γ/Δt` and the history `h`
//! ([`Step`]); the auxiliary states are discretised by the same coefficients. A step solves
//!
//! `R(u) = S(u) + ρ M (u − h) + L(u, t_{n+1}) = 0`
//!
//! by the core's Newton solver ([`crate::workflow::newton`]) through the physics' own
//! [`NonlinearSystem`]: the step's Jacobian `K(u) + ρ M` (plus, e.g., an eliminated circuit's
//! rank-one term) stays symmetric positive definite. Newton starts from the scheme's predictor
//! (the polynomial through the last levels, about one iteration less than the newest level) with
//! the previous step's factor as the CG preconditioner ([`NewtonOptions::reuse_factor`]).
//!
//! **Linear fast path.** When the step's system is linear ([`TransientProblem::is_linear`]), its
//! Jacobian depends on the step only through `ρ`: it is factorised once per rate (once for a
//! fixed-step run, twice with BDF2's Euler start; minimum-degree order, the fewest factor entries
//! for many solves) and every step is affine, `R(u₀ + δ) = R(u₀) + J δ` with `u₀` the lifting
//! (prescribed values, zero elsewhere). `R(u₀)` splits into the static residual `S(u₀)`, constant
//! over the run (one quadrature loop per run), the mass term `ρ M (u₀ − h)` (one mass product) and
//! the step's loads `L(u₀, t)`; so a step costs one mass product and one solve instead of a
//! quadrature loop over the mesh.
//!
//! **Adaptive steps** ([`TimeStep::Adaptive`]) estimate the local error by Milne's device from the
//! difference between the solution and a polynomial predictor through the previous levels
//! (Hairer, Nørsett & Wanner, *Solving ODEs I*, §III.7; Gresho & Sani, *Incompressible Flow and
//! the FEM*, §3.16.4 for the same device with BDF/trapezoidal correctors): linear extrapolation
//! and `LTE ≈ (1/3)|u − u_pred|` for implicit Euler, quadratic extrapolation and
//! `LTE ≈ (2/11)|u − u_pred|` for BDF2 (the constant-step error constants, used also for variable
//! steps). The error is measured in the max norm relative to `rtol · max|u|` over the run so far;
//! the step is accepted when that ratio is <= 1 and the next step is
//! `Δt · clamp(0.9 ratio^{−1/(p+1)}, 0.2, 2)`, at most `t_end/20`. Adaptive steps land on the
//! physics' breakpoints ([`TransientProblem::breakpoints`], e.g. a waveform's corners) and on
//! `t_end`. A step whose Newton iteration fails is halved (adaptive) or reported with its number,
//! time and Newton's residual history ([`TimeError::Step`]).
//!
//! **Fixed steps** are uniform, `t_end / ceil(t_end / dt)` (the requested step evened out to land
//! on `t_end`), at times `n·Δt` (no accumulated round-off).
//!
//! **Observers.** [`integrate`] calls [`TransientProblem::accept`] (the physics commits the level:
//! a material's state, its post-processing) and then the observer (`mrbrake_observe`) once per
//! accepted level, the initial state (`t = 0`, [`Level::index`] 0) first. An observer that returns
//! [`Flow::Stop`] ends the run cleanly after that level: [`integrate`] returns `Ok` with
//! [`Outcome::stopped`] set and [`Outcome::t`] the last level's time (before `t_end`); nothing
//! finished is lost.
//!
//! A new physics implements [`TransientProblem`]; `crates/mrbrake-fem/tests/it/second_physics.rs`
//! is the template (diffusion in `(r, z)`), `mrbrake-magnetics`' dynamics (eddy currents with
//! voltage-driven coils as auxiliary states) and `mrbrake-heat` (capacity, Joule feedback,
//! radiation by Newton) the full examples.

mod run;
#[cfg(test)]
mod tests;

use std::str::FromStr;

use mrbrake_error::{FieldError, FieldErrors};
use mrbrake_observe::{Flow, Observer};
use serde::{Deserialize, Serialize};

use crate::workflow::constraints::Constraints;
use crate::workflow::newton::{NewtonError, NewtonOptions, NewtonSolver, NonlinearSystem};

/// The time discretisation.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Scheme {
    /// Implicit (backward) Euler, first order.
    ImplicitEuler,
    /// Variable-step BDF2, second order, started by one implicit-Euler step.
    Bdf2,
}

impl Scheme {
    /// The order of accuracy.
    pub fn order(self) -> usize {
        match self {
            Self::ImplicitEuler => 1,
            Self::Bdf2 => 2,
        }
    }
}

impl std::fmt::Display for Scheme {
    /// The scheme's name in words (`BDF2`, `implicit Euler`).
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Self::ImplicitEuler => "implicit Euler",
            Self::Bdf2 => "BDF2",
        })
    }
}

/// A scheme name that is not known.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("= \"{0}\" is not known; allowed: \"bdf2\" (BDF2), \"euler\" (implicit Euler)")]
pub struct UnknownScheme(pub String);

impl FromStr for Scheme {
    type Err = UnknownScheme;

    /// The spellings of problem files: `"bdf2"` and `"euler"`.
    fn from_str(name: &str) -> Result<Self, Self::Err> {
        match name {
            "bdf2" => Ok(Self::Bdf2),
            "euler" => Ok(Self::ImplicitEuler),
            other => Err(UnknownScheme(other.to_string())),
        }
    }
}

/// Fixed or adaptive time steps.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum TimeStep {
    /// Uniform steps: `t_end / ceil(t_end / dt_s)` (the requested step, evened out to land on
    /// `t_end`).
    Fixed {
        /// Requested step (s).
        dt_s: f64,
    },
    /// Steps chosen from a local error estimate (module docs).
    Adaptive {
        /// Relative tolerance of the local error, in (0, 1).
        rtol: f64,
        /// First step (s).
        dt_initial_s: f64,
    },
}

/// Default and largest bound on the number of steps of one run.
pub const DEFAULT_MAX_STEPS: usize = 1_000_000;

/// The settings of one run: from `t = 0` to `t_end_s`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TimeOptions {
    /// End time (s).
    pub t_end_s: f64,
    /// Time scheme.
    pub scheme: Scheme,
    /// Step control.
    pub step: TimeStep,
    /// Largest number of step attempts (a bound on work; exceeding it is an input error).
    pub max_steps: usize,
}

/// The `adaptive = { rtol, dt_initial }` key of a problem file's `[transient]` table (the same in
/// every physics' files; its JSON Schema is part of theirs).
#[derive(Debug, Clone, Copy, PartialEq, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct AdaptiveKeys {
    /// Relative tolerance of the local error estimate, in (0, 1).
    pub rtol: f64,
    /// The first step (s), at most `t_end`.
    pub dt_initial: f64,
}

/// The step keys of a problem file's `[transient]` table as read, before checking (the same keys
/// in every physics' files).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct StepKeys<'a> {
    /// `t_end` (s).
    pub t_end: f64,
    /// `dt` (s): fixed steps.
    pub dt: Option<f64>,
    /// `adaptive`: adaptive steps.
    pub adaptive: Option<AdaptiveKeys>,
    /// `scheme` (default `"bdf2"`).
    pub scheme: Option<&'a str>,
    /// `max_steps` (default [`DEFAULT_MAX_STEPS`]).
    pub max_steps: Option<usize>,
}

impl TimeOptions {
    /// Options with the default step bound.
    pub fn new(t_end_s: f64, scheme: Scheme, step: TimeStep) -> Self {
        Self { t_end_s, scheme, step, max_steps: DEFAULT_MAX_STEPS }
    }

    /// Checks `t_end`, the step and the step bound.
    pub fn validate(&self) -> Result<(), TimeError> {
        self.field_errors().into_result(()).map_err(TimeError::Options)
    }

    /// The options of a problem file's step keys, or every invalid key (fields relative to the
    /// table: `dt`, `adaptive.rtol`, …).
    pub fn from_keys(keys: &StepKeys<'_>) -> Result<Self, FieldErrors> {
        let mut errors = FieldErrors::new();
        let scheme = keys.scheme.unwrap_or("bdf2").parse().unwrap_or_else(|e: UnknownScheme| {
            errors.add("scheme", e.to_string());
            Scheme::Bdf2
        });
        let step = match (keys.dt, keys.adaptive) {
            (Some(dt_s), None) => TimeStep::Fixed { dt_s },
            (None, Some(a)) => TimeStep::Adaptive { rtol: a.rtol, dt_initial_s: a.dt_initial },
            (Some(_), Some(_)) => {
                errors.add("adaptive", "cannot be given with `dt`: fixed steps or adaptive ones");
                return Err(errors);
            }
            (None, None) => {
                errors.add("dt", "is missing: give `dt` (s) or `adaptive = { rtol, dt_initial }`");
                return Err(errors);
            }
        };
        let options = Self {
            max_steps: keys.max_steps.unwrap_or(DEFAULT_MAX_STEPS),
            ..Self::new(keys.t_end, scheme, step)
        };
        for e in options.field_errors().errors() {
            errors.push(e.clone());
        }
        errors.into_result(options)
    }

    /// Every invalid setting, named by its problem-file key.
    fn field_errors(&self) -> FieldErrors {
        let mut errors = FieldErrors::new();
        let t_end = self.t_end_s;
        if !(t_end > 0.0 && t_end.is_finite()) {
            errors.add("t_end", format!("= {t_end} s must be finite and > 0"));
        }
        if self.max_steps == 0 {
            errors.add("max_steps", "= 0: a run needs at least one step");
        } else if self.max_steps > DEFAULT_MAX_STEPS {
            // The bound is a bound on work: a file may lower it, never raise it (every physics and
            // `thermal` stop at the same 1e6 steps, issue 33).
            errors.add(
                "max_steps",
                format!("= {} exceeds the limit of {DEFAULT_MAX_STEPS} steps", self.max_steps),
            );
        }
        match self.step {
            TimeStep::Fixed { dt_s } if !(dt_s > 0.0 && dt_s.is_finite()) => {
                errors.add("dt", format!("= {dt_s} s must be finite and > 0"));
            }
            TimeStep::Fixed { dt_s } if t_end < dt_s => {
                errors.add("t_end", format!("= {t_end} s is shorter than dt = {dt_s} s"));
            }
            TimeStep::Fixed { dt_s } => {
                let steps = (t_end / dt_s).ceil();
                if steps > self.max_steps as f64 {
                    errors.add(
                        "dt",
                        format!(
                            "= {dt_s} s: t_end / dt = {steps:.3e} steps exceeds the limit of {} \
                             steps",
                            self.max_steps
                        ),
                    );
                }
            }
            TimeStep::Adaptive { rtol, dt_initial_s } => {
                if !(rtol > 0.0 && rtol < 1.0) {
                    errors.add("adaptive.rtol", format!("= {rtol} must be in (0, 1)"));
                }
                if !(dt_initial_s > 0.0 && dt_initial_s <= t_end) {
                    errors.add(
                        "adaptive.dt_initial",
                        format!("= {dt_initial_s} s must be > 0 and <= t_end"),
                    );
                }
            }
        }
        errors
    }
}

/// Why a run failed (besides the physics' own errors).
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum TimeError {
    /// Invalid options (every invalid setting, named by its problem-file key).
    #[error(transparent)]
    Options(FieldErrors),
    /// The step bound was reached before `t_end`.
    #[error(
        "the transient needs more than {max_steps} steps to reach t_end = {t_end_s} s (at t = \
         {t_s:.6e} s): raise the step limit or the tolerance"
    )]
    TooManySteps {
        /// The bound ([`TimeOptions::max_steps`]).
        max_steps: usize,
        /// The end time (s).
        t_end_s: f64,
        /// The time reached (s).
        t_s: f64,
    },
    /// A step's solve failed (fixed steps, or an adaptive step already at its smallest size):
    /// Newton's failure and residual history are the source.
    #[error("time step {step} (t = {time_s:.6e} s) failed")]
    Step {
        /// 1-based number of the step attempt.
        step: usize,
        /// The time the step was to reach (s).
        time_s: f64,
        /// Why (Newton's failure, or the factorisation of a linear step's matrix).
        #[source]
        source: NewtonError,
    },
}

impl mrbrake_error::Kind for TimeError {
    /// Bad options and an exhausted step bound are the input's; a failed step is numerical.
    fn kind(&self) -> mrbrake_error::ErrorKind {
        match self {
            Self::Options(_) | Self::TooManySteps { .. } => mrbrake_error::ErrorKind::Input,
            Self::Step { source, .. } => mrbrake_error::Kind::kind(source),
        }
    }
}

impl From<FieldError> for TimeError {
    fn from(error: FieldError) -> Self {
        let mut errors = FieldErrors::new();
        errors.push(error);
        Self::Options(errors)
    }
}

/// One step of the scheme: `u̇_{n+1} ≈ rate · (u_{n+1} − history)`, and the same for the
/// auxiliary states.
#[derive(Debug, Clone, PartialEq)]
pub struct Step {
    /// The time the step reaches (s).
    pub t: f64,
    /// The step (s).
    pub dt: f64,
    /// `ρ = γ/Δt` (1/s).
    pub rate: f64,
    /// The history `h` at every DOF.
    pub history: Vec<f64>,
    /// The histories of the auxiliary states ([`TransientProblem::auxiliary`]).
    pub auxiliary_history: Vec<f64>,
}

/// An accepted time level, as the physics commits it ([`TransientProblem::accept`]) and observers
/// see it ([`Event`]).
#[derive(Debug, Clone, Copy)]
pub struct Level<'a> {
    /// Accepted steps before this level (0: the initial state).
    pub index: usize,
    /// Time (s).
    pub t: f64,
    /// The step that reached it (s; 0 for the initial state).
    pub dt: f64,
    /// The state at every DOF.
    pub u: &'a [f64],
    /// The auxiliary states.
    pub auxiliary: &'a [f64],
    /// The step's rate `ρ` (0 for the initial state).
    pub rate: f64,
    /// The step's history `h` (the state itself for the initial state).
    pub history: &'a [f64],
    /// The step's auxiliary histories.
    pub auxiliary_history: &'a [f64],
    /// Newton iterations of the step (1 for a linear step, 0 for the initial state).
    pub newton_iterations: usize,
}

impl Level<'_> {
    /// `u̇` at every DOF as the scheme discretises it, `ρ (u − h)` (zero for the initial state).
    pub fn derivative(&self) -> Vec<f64> {
        self.u.iter().zip(self.history).map(|(u, h)| self.rate * (u - h)).collect()
    }

    /// `ẏ_k` of auxiliary state `k` as the scheme discretises it (zero for the initial state).
    pub fn auxiliary_derivative(&self, k: usize) -> f64 {
        self.rate * (self.auxiliary[k] - self.auxiliary_history[k])
    }
}

/// What an observer sees after every accepted level: the level and the physics (for its
/// post-processing).
pub struct Event<'a, P: ?Sized> {
    /// The level.
    pub level: Level<'a>,
    /// The physics.
    pub problem: &'a P,
}

/// How a run ended.
#[derive(Debug, Clone, PartialEq)]
pub struct Outcome {
    /// The state of the last level (`t_end`, or where the observer stopped the run).
    pub u: Vec<f64>,
    /// The time of the last level (s).
    pub t: f64,
    /// True when an observer stopped the run before `t_end`.
    pub stopped: bool,
    /// Accepted steps.
    pub steps: usize,
    /// Rejected adaptive steps (error estimate too large, or a failed Newton iteration).
    pub rejected_steps: usize,
    /// Numeric factorisations of the run (the linear path's and Newton's).
    pub factorizations: usize,
    /// Newton iterations of the accepted steps (1 per linear step).
    pub newton_iterations: usize,
}

/// A physics in time: what [`integrate`] needs of it (module docs for the system).
pub trait TransientProblem {
    /// The physics' error; the integrator's own failures convert into it.
    type Error: From<TimeError>;
    /// The non-linear system of one step.
    type System<'a>: NonlinearSystem
    where
        Self: 'a;

    /// Which DOFs are free, and the prescribed values of the others.
    fn constraints(&self) -> &Constraints;

    /// The Newton solver that owns the step matrices' factor.
    fn newton(&mut self) -> &mut NewtonSolver;

    /// Newton's settings for a step ([`NewtonOptions::reuse_factor`] is set by the integrator).
    fn newton_options(&self) -> NewtonOptions;

    /// The stopping scale of a step's Newton iterations (asked once per run: a norm of the loads,
    /// which does not depend on the iterate).
    fn residual_scale(&mut self) -> f64;

    /// A new rate `ρ`: updates what of the step's Jacobian is constant (called before the first
    /// [`Self::step_system`] at that rate).
    fn prepare(&mut self, step: &Step);

    /// The step's system `R(u) = S(u) + ρ M (u − h) + L(u, t)` with its Jacobian, and the Newton
    /// solver.
    fn step_system<'a>(&'a mut self, step: &'a Step) -> (&'a mut NewtonSolver, Self::System<'a>);

    /// True when every step's system is linear (its Jacobian then depends on the step only
    /// through `ρ`): the linear fast path applies (module docs).
    fn is_linear(&self) -> bool;

    /// `S(u)` on the free DOFs: the static residual (constant loads included, no mass term and no
    /// step loads). Linear fast path only.
    fn static_residual(&mut self, u: &[f64]) -> Vec<f64>;

    /// `M x` at every DOF. Linear fast path only.
    fn mass_product(&self, x: &[f64]) -> Vec<f64>;

    /// Adds the step's loads `L(u, t)` to `residual` (free DOFs). Linear fast path only.
    fn add_step_loads(&self, step: &Step, u: &[f64], residual: &mut [f64]);

    /// The auxiliary states `y(u)` (none by default).
    fn auxiliary(&self, u: &[f64]) -> Vec<f64> {
        let _ = u;
        Vec::new()
    }

    /// Times in `(0, t_end)` where the data has corners (a waveform's); adaptive steps land on
    /// them (none by default).
    fn breakpoints(&self, t_end: f64) -> Vec<f64> {
        let _ = t_end;
        Vec::new()
    }

    /// Commits an accepted level (e.g. a material's history, the physics' post-processing of the
    /// step); called before the observer. Nothing by default.
    fn accept(&mut self, level: &Level<'_>) -> Result<(), Self::Error> {
        let _ = level;
        Ok(())
    }
}

/// Integrates `problem` from `initial` (one value per DOF; constrained entries take their
/// prescribed values) at `t = 0` to `options.t_end_s`, calling `observer` once per accepted level
/// (the initial one first; module docs for [`Flow::Stop`]).
pub fn integrate<P, O>(
    problem: &mut P,
    initial: Vec<f64>,
    options: &TimeOptions,
    mut observer: O,
) -> Result<Outcome, P::Error>
where
    P: TransientProblem,
    O: for<'a> Observer<Event<'a, P>>,
{
    options.validate()?;
    run::Run::new(problem, initial, options).integrate(problem, &mut observer)
}

/// Observes `level` of `problem`.
fn observe<P, O>(observer: &mut O, problem: &P, level: Level<'_>) -> Flow
where
    O: for<'a> Observer<Event<'a, P>>,
{
    observer.observe(&Event { level, problem })
}
