//! Transient magnetodynamics: backward differentiation in time, Newton in every step.
//!
//! Schemes (Hairer & Wanner, *Solving Ordinary Differential Equations II*, 2nd ed., §III.1 and
//! §V.1; both A-stable, and L-stable so the jump of a step input is damped, not rung):
//! - implicit Euler, `ȧ_{n+1} ≈ (a_{n+1} − a_n)/Δt`, first order;
//! - BDF2 with variable steps, `ȧ_{n+1} ≈ [γ a_{n+1} − (1+ω) a_n + ω²/(1+ω) a_{n−1}]/Δt_n`,
//!   `ω = Δt_n/Δt_{n−1}`, `γ = (1+2ω)/(1+ω)` (Hairer–Wanner eq. III.5.x; for `ω = 1` the classical
//!   `(3a_{n+1} − 4a_n + a_{n−1})/(2Δt)`), second order, started by one implicit-Euler step.
//!
//! Both are `ȧ_{n+1} ≈ ρ (a_{n+1} − h)` with the rate `ρ = γ/Δt` and the history `h`; the same
//! discretisation is applied to the flux linkages in the circuit equations.
//!
//! Coils: a current-driven coil adds `−i(t_{n+1}) c` to the residual. For a voltage-driven coil,
//! the discrete circuit equation `v = R i + ρ (λ(a) − λ_h)` with `λ(a) = 2π c · a` gives the current
//! as a function of the field, `i(a) = [v + ρ λ_h − 2πρ c·a]/R`, which is eliminated: the residual
//! gains `−i(a) c` and the Jacobian the dense rank-one term `(2πρ/R) c cᵀ` (applied with the sparse
//! factor by the Woodbury formula, [`mrbrake_fem::linalg::low_rank`]). The step's system stays the
//! gradient of a convex energy, so the core's Newton solver and line search apply unchanged, and
//! the coil's own `L/R` and the eddy currents both appear in the response.
//!
//! A linear problem (linear materials) at a fixed step has the same Jacobian in every step (once
//! BDF2 is past its Euler start): it is factorised once for the run and every step is one residual
//! evaluation and one pair of triangular solves.
//!
//! Adaptive steps (`TimeStep::Adaptive`) estimate the local error by Milne's device from the
//! difference between the solution and a polynomial predictor through the previous steps
//! (Hairer, Nørsett & Wanner, *Solving ODEs I*, §III.7; Gresho & Sani, *Incompressible Flow and
//! the FEM*, §3.16.4 for the same device with BDF/trapezoidal correctors): linear extrapolation
//! and `LTE ≈ (1/3)|a − a_pred|` for implicit Euler, quadratic extrapolation and
//! `LTE ≈ (2/11)|a − a_pred|` for BDF2 (the constant-step error constants, used also for variable
//! steps). The error is measured in the max norm relative to `rtol · max|a|` over the run so far;
//! the step is accepted when that ratio is <= 1 and the next step is
//! `Δt · clamp(0.9 ratio^{−1/(p+1)}, 0.2, 2)`. Steps land on the waveforms' corners and on
//! `t_end`. A step whose Newton iteration fails is halved (adaptive) or reported with its time and
//! residual history (fixed).

use std::time::Instant;

use mrbrake_fem::linalg::low_rank::LowRankTerm;
use mrbrake_fem::workflow::assemble::Assembly;
use mrbrake_fem::workflow::newton::{
    EliminationOrder, NewtonOptions, NewtonSolver, NonlinearSystem,
};
use serde::Serialize;

use super::form::TransientForm;
use super::{CoilData, Drive, Dynamics, TWO_PI, dot};
use crate::MagneticsError;
use crate::solver::Solver;

/// The time discretisation.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Scheme {
    /// Implicit (backward) Euler, first order.
    ImplicitEuler,
    /// Variable-step BDF2, second order.
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
        /// Relative tolerance of the local error.
        rtol: f64,
        /// First step (s).
        dt_initial_s: f64,
    },
}

/// A point where B is recorded every step.
#[derive(Debug, Clone, PartialEq)]
pub struct Probe {
    /// Name in the output.
    pub name: String,
    /// `[r, z]` (m).
    pub point: [f64; 2],
}

/// Settings of a transient solve.
#[derive(Debug, Clone, PartialEq)]
pub struct TransientOptions {
    /// End time (s); the solve starts at 0 from the DC state of the drives at `t = 0`.
    pub t_end_s: f64,
    /// Time scheme.
    pub scheme: Scheme,
    /// Step control.
    pub step: TimeStep,
    /// B probes.
    pub probes: Vec<Probe>,
    /// Record the stored magnetic energy every step (one quadrature loop per step).
    pub energy: bool,
    /// Keep the potential at the first step at or after each of these times (s).
    pub snapshot_times_s: Vec<f64>,
    /// Largest number of steps (a bound on work and memory; exceeding it is an input error).
    pub max_steps: usize,
}

/// Default bound on the number of steps of one transient.
pub const DEFAULT_MAX_STEPS: usize = 1_000_000;

impl TransientOptions {
    /// Options with no probes, no energy, no snapshots and the default step bound.
    pub fn new(t_end_s: f64, scheme: Scheme, step: TimeStep) -> Self {
        Self {
            t_end_s,
            scheme,
            step,
            probes: Vec::new(),
            energy: false,
            snapshot_times_s: Vec::new(),
            max_steps: DEFAULT_MAX_STEPS,
        }
    }

    /// Checks `t_end`, the step and the step bound.
    pub fn validate(&self) -> Result<(), MagneticsError> {
        let bad = |m: String| Err(MagneticsError::Input(m));
        if !(self.t_end_s > 0.0 && self.t_end_s.is_finite()) {
            return bad(format!("t_end = {} s must be finite and > 0", self.t_end_s));
        }
        match self.step {
            TimeStep::Fixed { dt_s } => {
                if !(dt_s > 0.0 && dt_s.is_finite()) {
                    return bad(format!("dt = {dt_s} s must be finite and > 0"));
                }
                if self.t_end_s < dt_s {
                    return bad(format!(
                        "t_end = {} s is shorter than dt = {dt_s} s",
                        self.t_end_s
                    ));
                }
                let steps = (self.t_end_s / dt_s).ceil();
                if steps > self.max_steps as f64 {
                    return bad(format!(
                        "t_end / dt = {steps:.3e} steps exceeds the limit of {} steps",
                        self.max_steps
                    ));
                }
            }
            TimeStep::Adaptive { rtol, dt_initial_s } => {
                if !(rtol > 0.0 && rtol < 1.0) {
                    return bad(format!("adaptive rtol = {rtol} must be in (0, 1)"));
                }
                if !(dt_initial_s > 0.0 && dt_initial_s <= self.t_end_s) {
                    return bad(format!(
                        "adaptive dt_initial = {dt_initial_s} s must be > 0 and <= t_end"
                    ));
                }
            }
        }
        Ok(())
    }
}

/// A coil's current, flux linkage and terminal voltage over time.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CoilTrace {
    /// Physical tag of the coil region.
    pub physical: u32,
    /// Current (A).
    #[serde(rename = "current_A")]
    pub current_a: Vec<f64>,
    /// Flux linkage (Wb).
    #[serde(rename = "flux_linkage_Wb")]
    pub flux_linkage_wb: Vec<f64>,
    /// Voltage (V): the source voltage of a voltage drive; `dλ/dt` (the induced EMF, no winding
    /// resistance) for a current drive.
    #[serde(rename = "voltage_V")]
    pub voltage_v: Vec<f64>,
}

/// B at a probe over time.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ProbeTrace {
    /// Probe name.
    pub name: String,
    /// `B_r` (T).
    #[serde(rename = "B_r_T")]
    pub b_r_t: Vec<f64>,
    /// `B_z` (T).
    #[serde(rename = "B_z_T")]
    pub b_z_t: Vec<f64>,
}

/// The outcome of a transient solve: one entry per accepted time level, `t = 0` first.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TransientResult {
    /// Times (s).
    pub time_s: Vec<f64>,
    /// Every driven coil.
    pub coils: Vec<CoilTrace>,
    /// Every probe.
    pub probes: Vec<ProbeTrace>,
    /// Eddy-current loss of all conductors (W) at each level.
    #[serde(rename = "eddy_loss_W")]
    pub eddy_loss_w: Vec<f64>,
    /// `R i²` of the voltage-driven circuits (W).
    #[serde(rename = "winding_loss_W")]
    pub winding_loss_w: Vec<f64>,
    /// Stored magnetic energy (J), when asked for.
    #[serde(rename = "stored_energy_J", skip_serializing_if = "Vec::is_empty")]
    pub stored_energy_j: Vec<f64>,
    /// Energy delivered to the field by the coils, `Σ_k Σ_n i_k (λ_k,n+1 − λ_k,n)` (J).
    #[serde(rename = "source_energy_J")]
    pub source_energy_j: Vec<f64>,
    /// Energy dissipated by eddy currents, `Σ_n Δt_n P_n+1` (J).
    #[serde(rename = "eddy_energy_J")]
    pub eddy_energy_j: Vec<f64>,
    /// Newton iterations of each step (0 at `t = 0`).
    pub newton_iterations: Vec<usize>,
    /// Numeric factorisations of the whole run (sparse part).
    pub factorizations: usize,
    /// Rejected adaptive steps.
    pub rejected_steps: usize,
    /// Potentials kept at the requested snapshot times: `(t, a at every DOF)`.
    #[serde(skip)]
    pub snapshots: Vec<(f64, Vec<f64>)>,
    /// Wall time of the solve (s).
    pub total_s: f64,
}

/// What an observer sees after every accepted step (and at `t = 0`).
pub struct StepView<'a> {
    /// Time (s).
    pub t: f64,
    /// The potential at every DOF.
    pub a: &'a [f64],
    /// Coil currents (A), in the order of the coils.
    pub currents: &'a [f64],
    /// `∂A/∂t` at every DOF as the scheme discretises it (`ρ (a − h)`, Wb/(m s)); zero at `t = 0`
    /// (the DC state). With [`Dynamics::eddy_current_density`] it gives the eddy currents.
    pub rate: &'a [f64],
    /// The dynamics (solver, post-processing).
    pub dynamics: &'a Dynamics,
}

/// One time level of the history.
#[derive(Debug, Clone)]
struct Level {
    t: f64,
    /// The step that reached this level (0 for the initial one): BDF2's step ratio uses it, so
    /// fixed steps have exactly ω = 1 (no round-off from differences of times).
    dt: f64,
    a: Vec<f64>,
    lambda: Vec<f64>,
}

/// The coil terms of one step.
#[derive(Debug, Clone, Copy)]
enum StepDrive {
    Current(f64),
    Circuit { voltage: f64, resistance: f64, rate: f64, lambda_history: f64 },
}

impl StepDrive {
    /// The current for the flux linkage `lambda`.
    fn current(&self, lambda: f64) -> f64 {
        match *self {
            Self::Current(i) => i,
            Self::Circuit { voltage, resistance, rate, lambda_history } => {
                (voltage - rate * (lambda - lambda_history)) / resistance
            }
        }
    }
}

/// The non-linear system of one step: the transient form plus the coil terms.
struct StepSystem<'a> {
    assembly: &'a mut Assembly,
    form: TransientForm<'a>,
    coils: &'a [CoilData],
    drives: Vec<StepDrive>,
    terms: Vec<LowRankTerm>,
}

impl NonlinearSystem for StepSystem<'_> {
    fn constraints(&self) -> &mrbrake_fem::workflow::constraints::Constraints {
        self.assembly.constraints()
    }

    fn evaluate(&mut self, u: &[f64], residual: &mut [f64], jacobian: Option<&mut [f64]>) {
        self.assembly.evaluate(&self.form, u, residual, jacobian);
        for (coil, drive) in self.coils.iter().zip(&self.drives) {
            let current = drive.current(TWO_PI * dot(&coil.full, u));
            for (r, c) in residual.iter_mut().zip(&coil.free) {
                *r -= current * c;
            }
        }
    }

    fn is_linear(&self) -> bool {
        self.assembly.is_linear()
    }

    fn low_rank(&self) -> &[LowRankTerm] {
        &self.terms
    }
}

/// The coefficients of one step: rate `ρ`, DOF history `h`, flux-linkage histories.
struct StepCoefficients {
    rate: f64,
    history: Vec<f64>,
    lambda_history: Vec<f64>,
}

/// `ρ`, `h` for a step of `dt` after the levels `levels` (newest last).
fn coefficients(scheme: Scheme, levels: &[Level], dt: f64) -> StepCoefficients {
    let newest = &levels[levels.len() - 1];
    if scheme == Scheme::ImplicitEuler || levels.len() < 2 {
        return StepCoefficients {
            rate: 1.0 / dt,
            history: newest.a.clone(),
            lambda_history: newest.lambda.clone(),
        };
    }
    let older = &levels[levels.len() - 2];
    let omega = dt / newest.dt;
    let gamma = (1.0 + 2.0 * omega) / (1.0 + omega);
    let (w_n, w_old) = ((1.0 + omega) / gamma, omega * omega / (1.0 + omega) / gamma);
    let combine = |x: &[f64], y: &[f64]| -> Vec<f64> {
        x.iter().zip(y).map(|(x, y)| w_n * x - w_old * y).collect()
    };
    StepCoefficients {
        rate: gamma / dt,
        history: combine(&newest.a, &older.a),
        lambda_history: combine(&newest.lambda, &older.lambda),
    }
}

impl Dynamics {
    /// Integrates from the DC state at `t = 0` to `options.t_end_s`.
    pub fn transient(
        &mut self,
        options: &TransientOptions,
    ) -> Result<TransientResult, MagneticsError> {
        self.transient_observed(options, |_| Ok(()))
    }

    /// [`Self::transient`], calling `observer` at `t = 0` and after every accepted step (e.g. to
    /// compute a torque from the field).
    pub fn transient_observed(
        &mut self,
        options: &TransientOptions,
        mut observer: impl FnMut(&StepView<'_>) -> Result<(), MagneticsError>,
    ) -> Result<TransientResult, MagneticsError> {
        options.validate()?;
        let start = Instant::now();
        let mut run = Run::new(self, options)?;
        let outcome = run.integrate(self, options, &mut observer);
        // Leave the static solver as it was (its form's constant Jacobian).
        self.solver.assembly.prepare(&self.solver.form);
        let mut result = outcome.map(|()| run.result)?;
        result.total_s = start.elapsed().as_secs_f64();
        Ok(result)
    }
}

/// The state of one transient run.
struct Run {
    levels: Vec<Level>,
    result: TransientResult,
    /// The rate the assembly was prepared and factorised with (linear fast path).
    factor_rate: Option<f64>,
    /// The static form's residual at the lifting (linear fast path; constant over a run).
    static_offset: Option<Vec<f64>>,
    scale: f64,
    a_max: f64,
    next_snapshot: usize,
    /// `∂A/∂t` of the newest level (zero at `t = 0`).
    rate: Vec<f64>,
}

impl Run {
    fn new(dynamics: &mut Dynamics, options: &TransientOptions) -> Result<Self, MagneticsError> {
        let currents: Vec<f64> = dynamics.coils.iter().map(|c| c.coil.dc_current_a(0.0)).collect();
        let initial = dynamics.static_solution(&currents)?;
        let a = initial.a_phi().to_vec();
        let lambda = (0..dynamics.coils.len()).map(|k| dynamics.flux_linkage(k, &a)).collect();
        let scale = residual_scale(dynamics);
        let result = TransientResult {
            time_s: Vec::new(),
            coils: dynamics
                .coils
                .iter()
                .map(|c| CoilTrace {
                    physical: c.coil.tag,
                    current_a: Vec::new(),
                    flux_linkage_wb: Vec::new(),
                    voltage_v: Vec::new(),
                })
                .collect(),
            probes: options
                .probes
                .iter()
                .map(|p| ProbeTrace { name: p.name.clone(), b_r_t: Vec::new(), b_z_t: Vec::new() })
                .collect(),
            eddy_loss_w: Vec::new(),
            winding_loss_w: Vec::new(),
            stored_energy_j: Vec::new(),
            source_energy_j: Vec::new(),
            eddy_energy_j: Vec::new(),
            newton_iterations: Vec::new(),
            factorizations: 0,
            rejected_steps: 0,
            snapshots: Vec::new(),
            total_s: 0.0,
        };
        let a_max = max_abs(&a);
        let rate = vec![0.0; a.len()];
        let levels = vec![Level { t: 0.0, dt: 0.0, a, lambda }];
        Ok(Self {
            levels,
            result,
            factor_rate: None,
            static_offset: None,
            scale,
            a_max,
            next_snapshot: 0,
            rate,
        })
    }
}

/// The stopping scale of the step's Newton iterations: the static scale (non-coil sources and
/// boundary values) plus `Σ_k |I_k| ‖c_k‖` at each coil's reference current (its amplitude, or
/// `V/R`).
fn residual_scale(dynamics: &mut Dynamics) -> f64 {
    let mut scale = dynamics.solver.residual_scale();
    for coil in &dynamics.coils {
        let reference = match coil.coil.drive {
            Drive::Current { amplitude_a } => amplitude_a.abs(),
            Drive::Voltage { amplitude_v, series_resistance_ohm } => {
                (amplitude_v / series_resistance_ohm).abs()
            }
        };
        scale += reference * dot(&coil.free, &coil.free).sqrt();
    }
    scale.max(f64::MIN_POSITIVE)
}

fn max_abs(x: &[f64]) -> f64 {
    x.iter().fold(0.0_f64, |m, v| m.max(v.abs()))
}

/// Calls `f` with the Newton solver and the step's system (the transient form of `coefficients`
/// with the coil terms).
fn with_step_system<R>(
    dynamics: &mut Dynamics,
    coefficients: &StepCoefficients,
    drives: &[StepDrive],
    terms: Vec<LowRankTerm>,
    f: impl FnOnce(&mut NewtonSolver, &mut StepSystem<'_>) -> R,
) -> R {
    let Dynamics { solver, sigma, mass, coils } = dynamics;
    let (assembly, statics, newton) = parts(solver);
    let form = TransientForm {
        statics,
        sigma,
        mass,
        history: &coefficients.history,
        rate: coefficients.rate,
    };
    let mut system = StepSystem { assembly, form, coils, drives: drives.to_vec(), terms };
    f(newton, &mut system)
}

/// The solver parts a step borrows.
fn parts(solver: &mut Solver) -> (&mut Assembly, &crate::form::AphiForm, &mut NewtonSolver) {
    (&mut solver.assembly, &solver.form, &mut solver.newton)
}

/// A solved (not yet accepted) step.
struct Attempt {
    t: f64,
    dt: f64,
    a: Vec<f64>,
    coefficients: StepCoefficients,
    drives: Vec<StepDrive>,
    iterations: usize,
}

impl Run {
    /// The time loop.
    fn integrate(
        &mut self,
        dynamics: &mut Dynamics,
        options: &TransientOptions,
        observer: &mut impl FnMut(&StepView<'_>) -> Result<(), MagneticsError>,
    ) -> Result<(), MagneticsError> {
        self.record_initial(dynamics, options)?;
        self.observe(dynamics, observer)?;
        let t_end = options.t_end_s;
        let breakpoints = breakpoints(dynamics, t_end);
        let (mut dt, adaptive_rtol, fixed_steps) = match options.step {
            TimeStep::Fixed { dt_s } => {
                let n = (t_end / dt_s - 1e-9).ceil().max(1.0);
                (t_end / n, None, Some(n as usize))
            }
            TimeStep::Adaptive { rtol, dt_initial_s } => (dt_initial_s, Some(rtol), None),
        };
        let mut step = 0usize;
        let mut t = 0.0;
        while t < t_end * (1.0 - 1e-12) {
            step += 1;
            if step > options.max_steps {
                return Err(MagneticsError::Input(format!(
                    "the transient needs more than {} steps to reach t_end = {t_end} s (at t = \
                     {t:.6e} s): raise the step limit or the tolerance",
                    options.max_steps
                )));
            }
            let (t_next, dt_try) = match fixed_steps {
                // Fixed: every step exactly dt, times n·dt (no accumulated round-off).
                Some(n) if step >= n => (t_end, dt),
                Some(_) => (step as f64 * dt, dt),
                None => {
                    let h = step_to_next_stop(t, dt, t_end, &breakpoints);
                    (t + h, h)
                }
            };
            let attempt = match self.attempt(dynamics, options.scheme, t_next, dt_try) {
                Ok(attempt) => attempt,
                Err(e) if adaptive_rtol.is_some() && dt_try > 1e-9 * t_end => {
                    let _ = e;
                    self.result.rejected_steps += 1;
                    dt = 0.5 * dt_try;
                    continue;
                }
                Err(e) => {
                    return Err(MagneticsError::TimeStep {
                        step,
                        time_s: t_next,
                        source: Box::new(e),
                    });
                }
            };
            if let Some(rtol) = adaptive_rtol {
                let ratio = self.error_ratio(options.scheme, &attempt, rtol);
                let p = options.scheme.order() as f64;
                let factor = (0.9 * ratio.max(1e-10).powf(-1.0 / (p + 1.0))).clamp(0.2, 2.0);
                if ratio > 1.0 {
                    self.result.rejected_steps += 1;
                    dt = dt_try * factor.min(0.5);
                    continue;
                }
                dt = (dt_try * factor).min(t_end / 20.0);
            }
            t = attempt.t;
            self.accept(dynamics, options, attempt)?;
            self.observe(dynamics, observer)?;
        }
        Ok(())
    }

    /// Solves the step to `t_next`.
    fn attempt(
        &mut self,
        dynamics: &mut Dynamics,
        scheme: Scheme,
        t_next: f64,
        dt: f64,
    ) -> Result<Attempt, MagneticsError> {
        let coefficients = coefficients(scheme, &self.levels, dt);
        let drives = step_drives(dynamics, &coefficients, t_next);
        let terms = low_rank_terms(dynamics, &drives);
        let rate = coefficients.rate;
        let rate_changed = self.factor_rate.is_none_or(|r| (r - rate).abs() > 1e-12 * rate);
        if rate_changed {
            let (assembly, statics, _) = parts(&mut dynamics.solver);
            assembly.prepare(&TransientForm {
                statics,
                sigma: &dynamics.sigma,
                mass: &dynamics.mass,
                history: &coefficients.history,
                rate,
            });
            self.factor_rate = None;
        }
        let (a, iterations) = if dynamics.solver.assembly.is_linear() {
            (self.affine_step(dynamics, &coefficients, &drives, terms)?, 1)
        } else {
            // Newton starts from the scheme's predictor (the polynomial through the last levels),
            // closer to the step's solution than the newest level: about one Newton iteration
            // less per step.
            let start = predictor(scheme, &self.levels, t_next)
                .map_or_else(|| self.levels[self.levels.len() - 1].a.clone(), |(p, _)| p);
            self.newton_step(dynamics, &coefficients, &drives, terms, start)?
        };
        Ok(Attempt { t: t_next, dt, a, coefficients, drives, iterations })
    }

    /// A step of a non-linear problem: Newton from `a`.
    fn newton_step(
        &mut self,
        dynamics: &mut Dynamics,
        coefficients: &StepCoefficients,
        drives: &[StepDrive],
        terms: Vec<LowRankTerm>,
        mut a: Vec<f64>,
    ) -> Result<(Vec<f64>, usize), MagneticsError> {
        // Consecutive steps' Jacobians are close: start from the last step's factor.
        let options = NewtonOptions { reuse_factor: true, ..dynamics.solver.options.newton() };
        let scale = self.scale;
        let report = with_step_system(dynamics, coefficients, drives, terms, |newton, system| {
            newton.solve(system, &mut a, scale, &options)
        })?;
        self.result.factorizations += report.factorizations;
        Ok((a, report.iterations))
    }

    /// A step of a linear problem with the stored factor (factorised on the first step at this
    /// rate). The residual is affine, `R(u₀ + δ) = R(u₀) + J δ` with `u₀` the lifting (prescribed
    /// values, zero elsewhere), and `R(u₀)` splits into the static form's part, constant over the
    /// run (one quadrature loop per run), the eddy term `ρ σ M (u₀ − h)` (the conductors' mass
    /// product) and the coils' currents at `λ(u₀)`; so a step costs one mass product and one
    /// solve instead of a quadrature loop over the mesh.
    fn affine_step(
        &mut self,
        dynamics: &mut Dynamics,
        coefficients: &StepCoefficients,
        drives: &[StepDrive],
        terms: Vec<LowRankTerm>,
    ) -> Result<Vec<f64>, MagneticsError> {
        let lifting = dynamics.solver.assembly.constraints().lifting();
        if self.factor_rate.is_none() {
            with_step_system(dynamics, coefficients, drives, terms, |newton, system| {
                // Hundreds of solves per factorisation: the order with the fewest factor entries.
                newton.set_elimination_order(EliminationOrder::MinimumDegree)?;
                newton.factorize_at(system, &lifting)
            })?;
            self.result.factorizations += 1;
            self.factor_rate = Some(coefficients.rate);
        }
        let offset = match self.static_offset.take() {
            Some(offset) => offset,
            None => {
                let (assembly, statics, _) = parts(&mut dynamics.solver);
                let mut offset = vec![0.0; assembly.constraints().n_free()];
                assembly.evaluate(statics, &lifting, &mut offset, None);
                offset
            }
        };
        let eddy_argument: Vec<f64> =
            lifting.iter().zip(&coefficients.history).map(|(u, h)| u - h).collect();
        let constraints = dynamics.solver.assembly.constraints();
        let eddy = constraints.restrict(&dynamics.mass_mul(&eddy_argument));
        let mut rhs: Vec<f64> =
            offset.iter().zip(&eddy).map(|(r, m)| -(r + coefficients.rate * m)).collect();
        for (coil, drive) in dynamics.coils.iter().zip(drives) {
            let current = drive.current(TWO_PI * dot(&coil.full, &lifting));
            rhs.iter_mut().zip(&coil.free).for_each(|(r, c)| *r += current * c);
        }
        self.static_offset = Some(offset);
        dynamics.solver.newton.solve_jacobian_in_place(&mut rhs)?;
        let delta = dynamics.solver.assembly.constraints().extend_with_zeros(&rhs);
        Ok(lifting.iter().zip(&delta).map(|(u, d)| u + d).collect())
    }

    /// The estimated local error over `rtol · max|a|` (0 while the predictor lacks history).
    fn error_ratio(&self, scheme: Scheme, attempt: &Attempt, rtol: f64) -> f64 {
        let Some((predicted, constant)) = predictor(scheme, &self.levels, attempt.t) else {
            return 0.0;
        };
        let difference =
            attempt.a.iter().zip(&predicted).fold(0.0_f64, |m, (a, p)| m.max((a - p).abs()));
        let reference = self.a_max.max(max_abs(&attempt.a));
        if reference <= 0.0 {
            return 0.0;
        }
        constant * difference / (rtol * reference)
    }

    fn observe(
        &self,
        dynamics: &Dynamics,
        observer: &mut impl FnMut(&StepView<'_>) -> Result<(), MagneticsError>,
    ) -> Result<(), MagneticsError> {
        let level = &self.levels[self.levels.len() - 1];
        let currents: Vec<f64> =
            self.result.coils.iter().map(|c| c.current_a[c.current_a.len() - 1]).collect();
        observer(&StepView {
            t: level.t,
            a: &level.a,
            currents: &currents,
            rate: &self.rate,
            dynamics,
        })
    }
}

/// The coil terms of a step to `t_next`.
fn step_drives(dynamics: &Dynamics, c: &StepCoefficients, t_next: f64) -> Vec<StepDrive> {
    dynamics
        .coils
        .iter()
        .enumerate()
        .map(|(k, coil)| {
            let w = coil.coil.waveform.value(t_next);
            match coil.coil.drive {
                Drive::Current { amplitude_a } => StepDrive::Current(amplitude_a * w),
                Drive::Voltage { amplitude_v, series_resistance_ohm } => StepDrive::Circuit {
                    voltage: amplitude_v * w,
                    resistance: series_resistance_ohm,
                    rate: c.rate,
                    lambda_history: c.lambda_history[k],
                },
            }
        })
        .collect()
}

/// The rank-one Jacobian terms `(2πρ/R) c cᵀ` of the voltage-driven coils.
fn low_rank_terms(dynamics: &Dynamics, drives: &[StepDrive]) -> Vec<LowRankTerm> {
    dynamics
        .coils
        .iter()
        .zip(drives)
        .filter_map(|(coil, drive)| match *drive {
            StepDrive::Circuit { resistance, rate, .. } => {
                Some(LowRankTerm { vector: coil.free.clone(), weight: TWO_PI * rate / resistance })
            }
            StepDrive::Current(_) => None,
        })
        .collect()
}

/// The waveforms' corners in `(0, t_end)`, sorted.
fn breakpoints(dynamics: &Dynamics, t_end: f64) -> Vec<f64> {
    let mut points: Vec<f64> =
        dynamics.coils.iter().flat_map(|c| c.coil.waveform.breakpoints(t_end)).collect();
    points.sort_by(f64::total_cmp);
    points
}

/// The step from `t`: `dt`, shortened to land on the next breakpoint or on `t_end` (and
/// stretched by up to 1 % rather than leave a sliver).
fn step_to_next_stop(t: f64, dt: f64, t_end: f64, breakpoints: &[f64]) -> f64 {
    let next_stop = breakpoints.iter().copied().find(|&b| b > t * (1.0 + 1e-12)).unwrap_or(t_end);
    let remaining = next_stop - t;
    if dt >= remaining * 0.99 { remaining } else { dt }
}

/// The predictor at `t` through the newest levels, with the constant of Milne's estimate
/// (module docs), or `None` while the history is too short.
fn predictor(scheme: Scheme, levels: &[Level], t: f64) -> Option<(Vec<f64>, f64)> {
    let n = levels.len();
    match scheme {
        Scheme::ImplicitEuler if n >= 2 => {
            let (l0, l1) = (&levels[n - 2], &levels[n - 1]);
            let w = (t - l1.t) / (l1.t - l0.t);
            let p = l1.a.iter().zip(&l0.a).map(|(a1, a0)| a1 + w * (a1 - a0)).collect();
            Some((p, 1.0 / 3.0))
        }
        Scheme::Bdf2 if n >= 3 => {
            let (l0, l1, l2) = (&levels[n - 3], &levels[n - 2], &levels[n - 1]);
            let lagrange =
                |ti: f64, tj: f64, tk: f64| (t - tj) * (t - tk) / ((ti - tj) * (ti - tk));
            let (w0, w1, w2) = (
                lagrange(l0.t, l1.t, l2.t),
                lagrange(l1.t, l0.t, l2.t),
                lagrange(l2.t, l0.t, l1.t),
            );
            let p = (0..l2.a.len()).map(|i| w0 * l0.a[i] + w1 * l1.a[i] + w2 * l2.a[i]).collect();
            Some((p, 2.0 / 11.0))
        }
        _ => None,
    }
}

impl Run {
    /// Records the level at `t = 0` (the DC state: no rates, no losses but the windings').
    fn record_initial(
        &mut self,
        dynamics: &Dynamics,
        options: &TransientOptions,
    ) -> Result<(), MagneticsError> {
        let level = self.levels[0].clone();
        let mut winding_loss = 0.0;
        for (k, coil) in dynamics.coils.iter().enumerate() {
            let current = coil.coil.dc_current_a(0.0);
            let voltage = match coil.coil.drive {
                Drive::Current { .. } => 0.0,
                Drive::Voltage { amplitude_v, series_resistance_ohm } => {
                    winding_loss += series_resistance_ohm * current * current;
                    amplitude_v * coil.coil.waveform.value(0.0)
                }
            };
            let trace = &mut self.result.coils[k];
            trace.current_a.push(current);
            trace.flux_linkage_wb.push(level.lambda[k]);
            trace.voltage_v.push(voltage);
        }
        self.result.eddy_loss_w.push(0.0);
        self.result.winding_loss_w.push(winding_loss);
        self.result.source_energy_j.push(0.0);
        self.result.eddy_energy_j.push(0.0);
        self.result.newton_iterations.push(0);
        self.record_field(dynamics, options, &level)
    }

    /// Records an accepted step and makes it the newest level.
    fn accept(
        &mut self,
        dynamics: &Dynamics,
        options: &TransientOptions,
        attempt: Attempt,
    ) -> Result<(), MagneticsError> {
        let previous = &self.levels[self.levels.len() - 1];
        let lambda: Vec<f64> =
            (0..dynamics.coils.len()).map(|k| dynamics.flux_linkage(k, &attempt.a)).collect();
        let c = &attempt.coefficients;
        let (mut source_energy, mut winding_loss) = (0.0, 0.0);
        for (k, drive) in attempt.drives.iter().enumerate() {
            let current = drive.current(lambda[k]);
            source_energy += current * (lambda[k] - previous.lambda[k]);
            let voltage = match *drive {
                StepDrive::Current(_) => c.rate * (lambda[k] - c.lambda_history[k]),
                StepDrive::Circuit { voltage, resistance, .. } => {
                    winding_loss += resistance * current * current;
                    voltage
                }
            };
            let trace = &mut self.result.coils[k];
            trace.current_a.push(current);
            trace.flux_linkage_wb.push(lambda[k]);
            trace.voltage_v.push(voltage);
        }
        let rates: Vec<f64> =
            attempt.a.iter().zip(&c.history).map(|(a, h)| c.rate * (a - h)).collect();
        let eddy = dynamics.eddy_loss(&rates);
        self.rate = rates;
        let r = &mut self.result;
        r.eddy_loss_w.push(eddy);
        r.winding_loss_w.push(winding_loss);
        r.source_energy_j.push(r.source_energy_j[r.source_energy_j.len() - 1] + source_energy);
        r.eddy_energy_j.push(r.eddy_energy_j[r.eddy_energy_j.len() - 1] + attempt.dt * eddy);
        r.newton_iterations.push(attempt.iterations);
        self.a_max = self.a_max.max(max_abs(&attempt.a));
        let level = Level { t: attempt.t, dt: attempt.dt, a: attempt.a, lambda };
        self.record_field(dynamics, options, &level)?;
        if self.levels.len() == 3 {
            self.levels.remove(0);
        }
        self.levels.push(level);
        Ok(())
    }

    /// Time, probes, stored energy and snapshots of a level.
    fn record_field(
        &mut self,
        dynamics: &Dynamics,
        options: &TransientOptions,
        level: &Level,
    ) -> Result<(), MagneticsError> {
        self.result.time_s.push(level.t);
        if options.probes.is_empty() && !options.energy {
            return self.snapshot(options, level);
        }
        let solution = dynamics.solution(level.a.clone());
        for (trace, probe) in self.result.probes.iter_mut().zip(&options.probes) {
            let b = dynamics.solver.b_at(&solution, probe.point)?;
            trace.b_r_t.push(b.b_r_t);
            trace.b_z_t.push(b.b_z_t);
        }
        if options.energy {
            self.result.stored_energy_j.push(dynamics.solver.energy(&solution).0);
        }
        self.snapshot(options, level)
    }

    fn snapshot(
        &mut self,
        options: &TransientOptions,
        level: &Level,
    ) -> Result<(), MagneticsError> {
        while let Some(&t) = options.snapshot_times_s.get(self.next_snapshot) {
            if level.t < t * (1.0 - 1e-12) {
                break;
            }
            self.result.snapshots.push((level.t, level.a.clone()));
            self.next_snapshot += 1;
        }
        Ok(())
    }
}
