//! Newton–Raphson for symmetric positive-definite non-linear systems, with a safeguarded line
//! search and an inexact (Krylov) tail; any physics that is the stationarity condition of a convex
//! energy uses it through the small [`NonlinearSystem`] trait.
//!
//! The system gives the residual `R(u)` on the free DOFs and its Jacobian `K(u)` (symmetric, on a
//! [`SymmetricPattern`]); the solver owns the sparse Cholesky factorisation (symbolic analysis once
//! per pattern) and runs (Dennis & Schnabel, *Numerical Methods for Unconstrained Optimization and
//! Nonlinear Equations*, §6.3):
//!
//! 1. evaluate `R(u)` and `K(u)`;
//! 2. stop when `‖R‖₂ <= rtol · s`, with the residual scale `s` given by the caller (a norm of the
//!    loads that does not depend on the iterate: the physics knows what it is), or when a full
//!    step solved with a fresh factor moved the iterate by round-off only
//!    (`‖δ‖∞ <= `[`ROUND_OFF_UPDATE`]` ‖u‖∞`: the residual left is the round-off of evaluating it,
//!    as for a start that already is the answer; PETSc's step-length test with a tiny `stol`);
//! 3. factorise `K` (numeric Cholesky on the stored symbolic analysis) and solve `K δ = −R`;
//! 4. line search along `δ` on the energy `W(u)` whose gradient is `R`: for a convex `W`,
//!    `g(α) = δ · R(u + αδ) = dW/dα` is increasing, with `g(0) = −δᵀKδ < 0`. The full step is
//!    accepted when `g(1) <= 0` (W decreases on the whole step) or `|g(1)| <= 0.3 |g(0)|`;
//!    otherwise the root of `g` in `(0, 1)` is bracketed and approached until
//!    `|g(α)| <= 0.3 |g(0)|` (an approximate exact line search). Each trial is a Newton step on `g`
//!    itself, `α ← α − g(α)/g'(α)` with `g'(α) = δᵀ K(u + αδ) δ` (one product with the Jacobian
//!    the trial evaluated anyway), kept when it falls inside the bracket; otherwise Illinois false
//!    position (or bisection while the bracket is open on the right) — a safeguarded Newton
//!    iteration (Dennis & Schnabel §6.3.2; Press et al., *Numerical Recipes*, `rtsafe`). Only
//!    residuals and Jacobians are needed, no energy values. This is what makes saturated magnetic
//!    problems converge from `u = 0`, where the first Newton step (with the initial permeability
//!    of the iron) overshoots by orders of magnitude; `g` is then flat up to the onset of
//!    saturation and steep beyond it, so false position alone creeps in from the left where Newton
//!    from the overshoot side lands near the root at once.
//!
//! Tail phase (inexact Newton–Krylov, Eisenstat & Walker, SIAM J. Sci. Comput. 17(1) 1996,
//! 16–32): once a full Newton step has cut the residual at least tenfold (`‖R_k‖ <= 0.1 ‖R_{k−1}‖`:
//! the quadratic phase has begun), the Jacobian changes little between iterations, so the new
//! system `K_k δ = −R_k` is first solved by conjugate gradients preconditioned with the *previous*
//! Cholesky factor (rounded to single precision, [`SparseCholesky::precondition_in_place`]: the
//! preconditioner stays symmetric positive definite and its triangular solves read half the
//! memory), to the forcing tolerance `‖K_k δ + R_k‖ <= η_k ‖R_k‖`,
//! `η_k = min(0.1, max(0.9 (‖R_k‖/‖R_{k−1}‖)², 0.5 rtol s / ‖R_k‖))` (Eisenstat–Walker choice 2,
//! which keeps the local convergence superlinear, floored where a more accurate step could not
//! change the outcome of the stopping test). If CG has not reached `η_k` within
//! [`NewtonOptions::tail_cg_max_iterations`] iterations, the Jacobian is factorised and the step
//! solved exactly. The CG step starts from 0, so it minimises the quadratic model on a Krylov
//! space and is a descent direction (`δ·R = −δᵀK_kδ < 0` at every CG iterate): the line search and
//! its guarantee are unchanged, and so is the stopping rule (always evaluated on the true
//! residual).
//!
//! Warm start ([`NewtonOptions::reuse_factor`]): a sequence of nearby systems on one pattern (the
//! steps of a transient: each step's Jacobian differs from the last one's by the change of the
//! saturation over one step) can begin each solve in the tail's mode, with the factor the previous
//! solve left as the CG preconditioner and the forcing tolerance [`WARM_START_FORCING`]; when CG
//! does not reach it within the iteration limit the Jacobian is factorised as usual, so the
//! outcome (the stopping rule on the true residual) is the same and only the work changes.
//!
//! A step that cannot be found (40 trials), a non-finite residual, a failed factorisation (a
//! Jacobian that is not positive definite, with the failing pivot's unknown) or the iteration limit
//! gives a [`NewtonError`]: the [`NewtonFailure`] that stopped it and the whole residual history. A linear system
//! ([`NonlinearSystem::is_linear`]) is accepted after its first step unless the direct solver's
//! round-off is abnormal (ill-conditioning).
//!
//! Each Newton iteration costs one evaluation with the Jacobian, one numeric factorisation (or a
//! few preconditioned CG iterations in the tail) and one triangular solve, plus one evaluation per
//! rejected line-search trial: the accepted trial point's Jacobian is the next iteration's.

use std::sync::Arc;
use std::time::Instant;

use serde::Serialize;

use crate::FemError;
use crate::linalg::cholesky::SparseCholesky;
use crate::linalg::low_rank::{LowRankTerm, Woodbury};
use crate::linalg::ordering::nested_dissection;
use crate::linalg::pattern::{CONSTRAINED, SymmetricPattern};
use crate::workflow::assemble::{Assembly, ElementForm};
use crate::workflow::constraints::Constraints;

/// A non-linear system `R(u) = 0` on the free DOFs of a full DOF vector `u`, with a symmetric
/// Jacobian that is positive definite (the gradient of a convex energy).
pub trait NonlinearSystem {
    /// Which DOFs are free; constrained entries of `u` keep their values.
    fn constraints(&self) -> &Constraints;

    /// The residual at `u` on the free DOFs and, when `jacobian` is given, the Jacobian's values on
    /// the solver's pattern.
    fn evaluate(&mut self, u: &[f64], residual: &mut [f64], jacobian: Option<&mut [f64]>);

    /// True when the Jacobian does not depend on `u` (one Newton step solves the system).
    fn is_linear(&self) -> bool;

    /// Dense symmetric rank-one terms `w c cᵀ` of the Jacobian besides its sparse part (none by
    /// default), constant during a solve: the solver applies them with the sparse factor by the
    /// Woodbury formula ([`crate::linalg::low_rank`]); the residual must include their contribution.
    fn low_rank(&self) -> &[LowRankTerm] {
        &[]
    }
}

/// An [`Assembly`] with an [`ElementForm`]: the usual [`NonlinearSystem`] of a finite-element
/// problem.
pub struct AssembledSystem<'a, F> {
    /// The assembly (basis, constraints, pattern), prepared with `form`.
    pub assembly: &'a mut Assembly,
    /// The form.
    pub form: &'a F,
}

impl<F: ElementForm> NonlinearSystem for AssembledSystem<'_, F> {
    fn constraints(&self) -> &Constraints {
        self.assembly.constraints()
    }

    fn evaluate(&mut self, u: &[f64], residual: &mut [f64], jacobian: Option<&mut [f64]>) {
        self.assembly.evaluate(self.form, u, residual, jacobian);
    }

    fn is_linear(&self) -> bool {
        self.assembly.is_linear()
    }
}

/// Relative update `‖δ‖∞/‖u‖∞` of a full, directly solved Newton step below which the iterate is
/// converged to round-off (about 450 ulp).
pub const ROUND_OFF_UPDATE: f64 = 1e-13;

/// Forcing tolerance of the first step of a warm start ([`NewtonOptions::reuse_factor`]): the
/// step solves the Newton system to 1 %, as accurate as the tail phase's first steps.
pub const WARM_START_FORCING: f64 = 1e-2;

/// Settings of the Newton iteration.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NewtonOptions {
    /// Maximum Newton iterations.
    pub max_iterations: usize,
    /// Relative residual tolerance `rtol` of the stopping rule `‖R‖ <= rtol · s`.
    pub residual_tolerance: f64,
    /// Line-search acceptance `|g(α)| <= line_search_slope · |g(0)|`.
    pub line_search_slope: f64,
    /// Largest number of line-search trials per iteration.
    pub max_line_search_trials: usize,
    /// Largest number of conjugate-gradient iterations (each costs one pair of single-precision
    /// triangular solves, about a tenth of a numeric factorisation) tried with the previous factor
    /// before refactorising.
    pub tail_cg_max_iterations: usize,
    /// Residual reduction of a full Newton step that marks the start of the tail phase.
    pub tail_phase_reduction: f64,
    /// Start the solve with the factor left by the previous solve as the CG preconditioner
    /// (a warm start: see the module docs). For sequences of nearby systems on one pattern,
    /// e.g. the steps of a transient.
    pub reuse_factor: bool,
}

impl Default for NewtonOptions {
    fn default() -> Self {
        Self {
            max_iterations: 50,
            residual_tolerance: 1e-9,
            line_search_slope: 0.3,
            max_line_search_trials: 40,
            tail_cg_max_iterations: 4,
            tail_phase_reduction: 0.1,
            reuse_factor: false,
        }
    }
}

/// One Newton iteration in the history.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct NewtonStep {
    /// Residual norm `‖R‖₂` before the step (in the units of the weak form).
    pub residual: f64,
    /// Residual relative to the scale `s` of the stopping rule.
    pub relative_residual: f64,
    /// Accepted line-search factor α.
    pub step_length: f64,
    /// `‖α δ‖∞ / ‖u‖∞` after the step.
    pub relative_update: f64,
    /// Conjugate-gradient iterations that gave the step with the previous factor (tail phase), or 0
    /// when the Jacobian was factorised and the step solved directly.
    pub cg_iterations: usize,
}

/// Timings of one solve (seconds).
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize)]
pub struct SolveTimings {
    /// Evaluation of residuals and Jacobians.
    pub assemble_s: f64,
    /// Numeric Cholesky factorisations.
    pub factor_s: f64,
    /// Triangular solves.
    pub solve_s: f64,
    /// Whole Newton loop.
    pub total_s: f64,
}

/// Outcome of the Newton iterations.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct NewtonReport {
    /// Number of Newton steps (linear systems solved, directly or by preconditioned CG).
    pub iterations: usize,
    /// Number of numeric Cholesky factorisations (at most `iterations`).
    pub factorizations: usize,
    /// True when the stopping rule was met.
    pub converged: bool,
    /// Residual scale `s` of the stopping rule.
    pub residual_scale: f64,
    /// Final relative residual.
    pub final_relative_residual: f64,
    /// History, one entry per iteration.
    pub history: Vec<NewtonStep>,
    /// Time split.
    pub timings: SolveTimings,
}

/// Newton failed: why, and the history of the iterations up to the failure.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error(
    "Newton-Raphson failed: {failure}; residual history (relative): {}",
    format_history(history)
)]
pub struct NewtonError {
    /// Why it stopped.
    pub failure: NewtonFailure,
    /// One entry per iteration.
    pub history: Vec<NewtonStep>,
    /// Residual scale of the stopping rule.
    pub residual_scale: f64,
}

/// Why a Newton solve failed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum NewtonFailure {
    /// The stopping rule was not met within the iteration limit.
    #[error("no convergence in {iterations} Newton iterations")]
    IterationLimit {
        /// The limit ([`NewtonOptions::max_iterations`]).
        iterations: usize,
    },
    /// The Jacobian is not positive definite: its Cholesky factorisation met a pivot that is not
    /// positive (a non-monotone material law, or a source that grows faster than the losses).
    #[error(
        "the Jacobian is not positive definite (the Cholesky pivot of unknown {row} of {rows} is \
         not positive): is a material law non-monotone?"
    )]
    NotPositiveDefinite {
        /// The free DOF whose pivot failed.
        row: usize,
        /// The number of free DOFs.
        rows: usize,
    },
    /// The residual is NaN or infinite.
    #[error("the residual is not finite (NaN or infinite material value?)")]
    NonFiniteResidual,
    /// No trial along the Newton direction lowered the energy.
    #[error("the line search found no step lowering the energy in {trials} trials")]
    LineSearch {
        /// Trials made ([`NewtonOptions::max_line_search_trials`]).
        trials: usize,
    },
    /// Another failure of the linear algebra (a singular low-rank correction, memory).
    #[error("{0}")]
    LinearAlgebra(String),
}

impl From<FemError> for NewtonFailure {
    fn from(error: FemError) -> Self {
        match error {
            FemError::NotPositiveDefinite { row, rows } => Self::NotPositiveDefinite { row, rows },
            other => Self::LinearAlgebra(other.to_string()),
        }
    }
}

impl NewtonError {
    /// A failure before any iteration (e.g. the factorisation of a linear step's Jacobian).
    pub fn before_iterating(failure: impl Into<NewtonFailure>, residual_scale: f64) -> Self {
        Self { failure: failure.into(), history: Vec::new(), residual_scale }
    }
}

impl mrbrake_error::Kind for NewtonError {
    fn kind(&self) -> mrbrake_error::ErrorKind {
        mrbrake_error::ErrorKind::Numerical
    }
}

fn format_history(history: &[NewtonStep]) -> String {
    if history.is_empty() {
        return "(none)".into();
    }
    history
        .iter()
        .enumerate()
        .map(|(k, s)| format!("#{} {:.3e} (step {:.3})", k + 1, s.relative_residual, s.step_length))
        .collect::<Vec<_>>()
        .join(", ")
}

/// The linear algebra of Newton solves on one sparsity pattern: the Cholesky factorisation
/// (symbolic analysis done once), the Jacobian values and the work vectors. Reused by every solve
/// on the same pattern (a current sweep, the time steps of a transient).
#[derive(Debug)]
pub struct NewtonSolver {
    pattern: Arc<SymmetricPattern>,
    cholesky: SparseCholesky,
    /// Jacobian values on the pattern (the last evaluation with a Jacobian).
    values: Vec<f64>,
    work: NewtonWork,
    /// The system's low-rank Jacobian terms with the current factor.
    woodbury: Woodbury,
    symbolic_s: f64,
    /// The free DOFs' coordinates (for a geometric order) and the factorisation's threads.
    free_coordinates: Vec<[f64; 2]>,
    threads: usize,
    order: EliminationOrder,
}

/// The fill-reducing elimination order of the sparse factor.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum EliminationOrder {
    /// Geometric nested dissection ([`crate::linalg::ordering`]): the least work per numeric
    /// factorisation on 2D meshes and two independent halves for parallel solves; the default,
    /// for Newton's many factorisations.
    NestedDissection,
    /// Approximate minimum degree (faer's AMD): fewer factor entries than nested dissection on 2D
    /// meshes (478 k against 755 k on the 16 k-unknown pot core of `mrbrake-magnetics`'
    /// benchmarks), so cheaper triangular solves, which read the factor once per direction:
    /// the choice for many solves with one factor (a linear transient at a fixed step).
    MinimumDegree,
}

impl NewtonSolver {
    /// The solver for systems on `pattern`, with a nested-dissection elimination order from the
    /// free DOFs' coordinates `free_coordinates` (less work per numeric factorisation than AMD on
    /// 2D meshes, see [`crate::linalg::ordering`]). `threads` is the parallelism of the numeric
    /// factorisation ([`SparseCholesky::new`]).
    pub fn new(
        pattern: &Arc<SymmetricPattern>,
        free_coordinates: &[[f64; 2]],
        threads: usize,
    ) -> Result<Self, FemError> {
        let start = Instant::now();
        let order = nested_dissection(pattern, free_coordinates);
        let cholesky = SparseCholesky::with_order(pattern, threads, Some(&order))?;
        Ok(Self {
            values: vec![0.0; pattern.nnz()],
            pattern: Arc::clone(pattern),
            cholesky,
            work: NewtonWork::default(),
            woodbury: Woodbury::default(),
            symbolic_s: start.elapsed().as_secs_f64(),
            free_coordinates: free_coordinates.to_vec(),
            threads,
            order: EliminationOrder::NestedDissection,
        })
    }

    /// The elimination order of the factor.
    pub fn elimination_order(&self) -> EliminationOrder {
        self.order
    }

    /// Switches the factor to `order` (a new symbolic analysis when it differs; the numeric
    /// factor is then gone: factorise before the next solve).
    pub fn set_elimination_order(&mut self, order: EliminationOrder) -> Result<(), FemError> {
        if order == self.order {
            return Ok(());
        }
        let start = Instant::now();
        self.cholesky = match order {
            EliminationOrder::NestedDissection => {
                let elimination = nested_dissection(&self.pattern, &self.free_coordinates);
                SparseCholesky::with_order(&self.pattern, self.threads, Some(&elimination))?
            }
            EliminationOrder::MinimumDegree => SparseCholesky::new(&self.pattern, self.threads)?,
        };
        self.woodbury = Woodbury::default();
        self.symbolic_s += start.elapsed().as_secs_f64();
        self.order = order;
        Ok(())
    }

    /// The solver for the systems of `assembly` (its pattern and free-DOF coordinates).
    pub fn for_assembly(assembly: &Assembly, threads: usize) -> Result<Self, FemError> {
        let coordinates = assembly.constraints().free_coordinates(assembly.basis().dofs());
        Self::new(assembly.pattern(), &coordinates, threads)
    }

    /// Seconds spent in the ordering and the symbolic factorisation.
    pub fn symbolic_factorisation_s(&self) -> f64 {
        self.symbolic_s
    }

    /// Stored entries of the Cholesky factor (fill-in measure).
    pub fn factor_nnz(&self) -> usize {
        self.cholesky.factor_nnz()
    }

    /// The sparsity pattern.
    pub fn pattern(&self) -> &SymmetricPattern {
        &self.pattern
    }

    /// Evaluates the Jacobian of `system` at `u` and factorises it (for solves with the tangent
    /// matrix at a solution, e.g. a small-signal response, or every step of a linear transient at
    /// a fixed step). Returns the residual at `u`.
    pub fn factorize_at<S: NonlinearSystem>(
        &mut self,
        system: &mut S,
        u: &[f64],
    ) -> Result<Vec<f64>, FemError> {
        let mut residual = vec![0.0; system.constraints().n_free()];
        system.evaluate(u, &mut residual, Some(&mut self.values));
        self.woodbury.set_terms(system.low_rank())?;
        self.factorize()?;
        Ok(residual)
    }

    /// Factorises the stored Jacobian values and refreshes the low-rank terms' data for it.
    fn factorize(&mut self) -> Result<(), FemError> {
        self.cholesky.factorize(&self.values)?;
        let cholesky = &mut self.cholesky;
        self.woodbury.refresh(|v| cholesky.solve_in_place(v))
    }

    /// Solves `K x = rhs` in place with the sparse part `K` of the last factorisation
    /// ([`Self::factorize_at`] or the last Newton factorisation).
    pub fn solve_in_place(&mut self, rhs: &mut [f64]) -> Result<(), FemError> {
        self.cholesky.solve_in_place(rhs)
    }

    /// Solves `J x = rhs` in place with the whole Jacobian of the last factorisation: its sparse
    /// part and its low-rank terms ([`NonlinearSystem::low_rank`]).
    pub fn solve_jacobian_in_place(&mut self, rhs: &mut [f64]) -> Result<(), FemError> {
        self.cholesky.solve_in_place(rhs)?;
        self.woodbury.correct(rhs)
    }

    /// Solves `R(u) = 0` from the start `u` (one value per DOF; its constrained entries are set to
    /// their prescribed values), in place, with the stopping scale `scale` (see the module docs).
    pub fn solve<S: NonlinearSystem>(
        &mut self,
        system: &mut S,
        u: &mut Vec<f64>,
        scale: f64,
        options: &NewtonOptions,
    ) -> Result<NewtonReport, NewtonError> {
        let start = Instant::now();
        system.constraints().impose(u);
        let n_free = system.constraints().n_free();
        self.work.resize(n_free);
        let free_index = system.constraints().free_index().to_vec();
        let mut iteration = Iteration::new(free_index, u.clone(), scale);
        self.woodbury.set_terms(system.low_rank()).map_err(|e| iteration.failure(e))?;
        let t = Instant::now();
        system.evaluate(u, &mut iteration.residual, Some(&mut self.values));
        iteration.timings.assemble_s += t.elapsed().as_secs_f64();
        let converged = loop {
            match self.step(system, &mut iteration, options)? {
                StepOutcome::Converged => break true,
                StepOutcome::IterationLimit => break false,
                StepOutcome::Continue => {}
            }
        };
        iteration.timings.total_s = start.elapsed().as_secs_f64();
        if !converged {
            return Err(NewtonError {
                failure: NewtonFailure::IterationLimit { iterations: options.max_iterations },
                history: iteration.history,
                residual_scale: scale,
            });
        }
        *u = std::mem::take(&mut iteration.u);
        Ok(iteration.report(converged))
    }

    /// One Newton iteration: stopping test, step, line search.
    fn step<S: NonlinearSystem>(
        &mut self,
        system: &mut S,
        it: &mut Iteration,
        options: &NewtonOptions,
    ) -> Result<StepOutcome, NewtonError> {
        let r_norm = norm2(&it.residual);
        if !r_norm.is_finite() {
            return Err(it.failure(NewtonFailure::NonFiniteResidual));
        }
        if r_norm <= options.residual_tolerance * it.scale {
            return Ok(StepOutcome::Converged);
        }
        if it.iterations >= options.max_iterations {
            return Ok(StepOutcome::IterationLimit);
        }
        it.iterations += 1;
        let cg_iterations = self.direction(it, r_norm, options)?;
        let (alpha, accepted) = self.line_search(system, it, options);
        let a_max = it.u.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
        let d_max = it.delta.iter().fold(0.0_f64, |m, x| m.max(x.abs())) * alpha;
        let relative_update = d_max / a_max.max(f64::MIN_POSITIVE);
        it.history.push(NewtonStep {
            residual: r_norm,
            relative_residual: r_norm / it.scale,
            step_length: if accepted { alpha } else { 0.0 },
            relative_update,
            cg_iterations,
        });
        if !accepted {
            return Err(
                it.failure(NewtonFailure::LineSearch { trials: options.max_line_search_trials })
            );
        }
        it.previous = Some((r_norm, (alpha - 1.0).abs() <= f64::EPSILON));
        std::mem::swap(&mut it.u, &mut it.trial);
        std::mem::swap(&mut it.residual, &mut it.trial_residual);
        // A linear system's first solve is exact up to the round-off of the direct solver: accept
        // it unless that round-off is abnormal (ill-conditioning).
        if system.is_linear() && norm2(&it.residual) <= 1e-6 * it.scale {
            return Ok(StepOutcome::Converged);
        }
        // A full step from a fresh factorisation that moves the iterate by round-off only: what
        // residual is left is the round-off of evaluating it (e.g. a start that is already the
        // answer, whose residual no tolerance relative to it can meet). PETSc's step-length
        // test `‖δ‖ ≤ stol ‖u‖` (default stol 1e-8), here at a few hundred ulp.
        let full_direct_step = cg_iterations == 0 && (alpha - 1.0).abs() <= f64::EPSILON;
        if full_direct_step && relative_update <= ROUND_OFF_UPDATE {
            return Ok(StepOutcome::Converged);
        }
        Ok(StepOutcome::Continue)
    }

    /// The Newton direction `δ` into `it.delta`: by CG with the previous factor in the tail phase
    /// (returns its iteration count), else by factorising the Jacobian (returns 0).
    /// With low-rank terms the tail is skipped (the stale factor would need their correction
    /// too) and the exact step includes them.
    fn direction(
        &mut self,
        it: &mut Iteration,
        r_norm: f64,
        options: &NewtonOptions,
    ) -> Result<usize, NewtonError> {
        if let Some(forcing) = self.cg_forcing(it, r_norm, options) {
            let t = Instant::now();
            let outcome = self
                .stale_factor_cg(&it.residual, forcing, &mut it.delta, options)
                .map_err(|e| it.failure(e))?;
            it.timings.solve_s += t.elapsed().as_secs_f64();
            if let Some(cg_iterations) = outcome {
                return Ok(cg_iterations);
            }
        }
        let t = Instant::now();
        self.factorize().map_err(|e| it.failure(e))?;
        it.factorizations += 1;
        it.timings.factor_s += t.elapsed().as_secs_f64();
        let t = Instant::now();
        for (d, r) in it.delta.iter_mut().zip(&it.residual) {
            *d = -r;
        }
        self.solve_jacobian_in_place(&mut it.delta).map_err(|e| it.failure(e))?;
        it.timings.solve_s += t.elapsed().as_secs_f64();
        Ok(0)
    }

    /// The forcing tolerance of a CG step with the stored factor, or `None` for a factorisation:
    /// in the tail phase (a full step cut the residual by [`NewtonOptions::tail_phase_reduction`])
    /// Eisenstat–Walker choice 2; at the first iteration of a warm start
    /// ([`NewtonOptions::reuse_factor`]) [`WARM_START_FORCING`]; both floored where a more
    /// accurate step could not change the stopping test. Never with low-rank terms (the stale
    /// factor would need their correction too).
    fn cg_forcing(&self, it: &Iteration, r_norm: f64, options: &NewtonOptions) -> Option<f64> {
        if !self.woodbury.is_empty() {
            return None;
        }
        let warm = options.reuse_factor && self.cholesky.is_factorised();
        let rtol_floor = 0.5 * options.residual_tolerance * it.scale / r_norm;
        match it.previous {
            Some((previous_norm, true))
                if (it.factorizations > 0 || warm)
                    && r_norm <= options.tail_phase_reduction * previous_norm =>
            {
                let ratio = r_norm / previous_norm;
                Some((0.9 * ratio * ratio).max(rtol_floor).min(0.1))
            }
            None if warm => Some(WARM_START_FORCING.max(rtol_floor).min(0.1)),
            _ => None,
        }
    }

    /// The safeguarded line search (module docs) from `it.u` along `it.delta`; leaves the
    /// accepted point, its residual and (in `self.values`) its Jacobian in `it.trial`,
    /// `it.trial_residual`. Returns `(α, accepted)`.
    fn line_search<S: NonlinearSystem>(
        &mut self,
        system: &mut S,
        it: &mut Iteration,
        options: &NewtonOptions,
    ) -> (f64, bool) {
        let g0: f64 = dot(&it.delta, &it.residual);
        let mut alpha = 1.0;
        let mut bracket = Bracket::new(g0);
        for trial_count in 0..options.max_line_search_trials {
            for (v, &d) in it.free_index.iter().enumerate() {
                it.trial[v] =
                    if d == CONSTRAINED { it.u[v] } else { it.u[v] + alpha * it.delta[d] };
            }
            let t = Instant::now();
            system.evaluate(&it.trial, &mut it.trial_residual, Some(&mut self.values));
            it.timings.assemble_s += t.elapsed().as_secs_f64();
            let g: f64 = dot(&it.delta, &it.trial_residual);
            if g.is_finite()
                && (g.abs() <= options.line_search_slope * g0.abs()
                    || (trial_count == 0 && g <= 0.0))
            {
                return (alpha, true);
            }
            // Slope g'(α) = δᵀ K(u + αδ) δ with the Jacobian this trial evaluated.
            self.pattern.symmetric_mul(&self.values, &it.delta, &mut self.work.slope);
            let slope = dot(&it.delta, &self.work.slope) + self.woodbury.curvature(&it.delta);
            alpha = bracket.next(alpha, g, slope);
        }
        (alpha, false)
    }

    /// Preconditioned conjugate gradients on `K δ = −R` (`K` the current Jacobian, the
    /// preconditioner the Cholesky factor of an earlier Jacobian rounded to single precision),
    /// from `δ = 0`, until `‖K δ + R‖ <= forcing ‖R‖`. Returns the iteration count, or `None` (and
    /// `delta` undefined) when the iteration limit did not suffice or the curvature `pᵀKp` was not
    /// positive.
    fn stale_factor_cg(
        &mut self,
        residual: &[f64],
        forcing: f64,
        delta: &mut [f64],
        options: &NewtonOptions,
    ) -> Result<Option<usize>, FemError> {
        let n = residual.len();
        self.work.resize(n);
        let NewtonWork { r, z, p, kp, .. } = &mut self.work;
        delta.iter_mut().for_each(|d| *d = 0.0);
        for (ri, res) in r.iter_mut().zip(residual) {
            *ri = -res;
        }
        let target = forcing * norm2(r);
        z.copy_from_slice(r);
        self.cholesky.precondition_in_place(z)?;
        p.copy_from_slice(z);
        let mut rz = dot(r, z);
        for iteration in 1..=options.tail_cg_max_iterations {
            self.pattern.symmetric_mul(&self.values, p, kp);
            let curvature = dot(p, kp);
            if !(curvature > 0.0 && curvature.is_finite()) {
                return Ok(None);
            }
            let step = rz / curvature;
            for i in 0..n {
                delta[i] += step * p[i];
                r[i] -= step * kp[i];
            }
            if norm2(r) <= target {
                return Ok(Some(iteration));
            }
            if iteration == options.tail_cg_max_iterations {
                break;
            }
            z.copy_from_slice(r);
            self.cholesky.precondition_in_place(z)?;
            let rz_next = dot(r, z);
            let beta = rz_next / rz;
            rz = rz_next;
            for i in 0..n {
                p[i] = z[i] + beta * p[i];
            }
        }
        Ok(None)
    }
}

/// What the iteration does next.
enum StepOutcome {
    Continue,
    Converged,
    IterationLimit,
}

/// The state of one Newton solve.
struct Iteration {
    /// Free index of every DOF, or CONSTRAINED.
    free_index: Vec<usize>,
    u: Vec<f64>,
    trial: Vec<f64>,
    residual: Vec<f64>,
    trial_residual: Vec<f64>,
    delta: Vec<f64>,
    scale: f64,
    iterations: usize,
    factorizations: usize,
    /// Residual norm before the previous step, and whether that step was a full step.
    previous: Option<(f64, bool)>,
    history: Vec<NewtonStep>,
    timings: SolveTimings,
}

impl Iteration {
    fn new(free_index: Vec<usize>, u: Vec<f64>, scale: f64) -> Self {
        let n_free = free_index.iter().filter(|&&d| d != CONSTRAINED).count();
        Self {
            free_index,
            trial: u.clone(),
            u,
            residual: vec![0.0; n_free],
            trial_residual: vec![0.0; n_free],
            delta: vec![0.0; n_free],
            scale,
            iterations: 0,
            factorizations: 0,
            previous: None,
            history: Vec::new(),
            timings: SolveTimings::default(),
        }
    }

    fn failure(&self, failure: impl Into<NewtonFailure>) -> NewtonError {
        NewtonError {
            failure: failure.into(),
            history: self.history.clone(),
            residual_scale: self.scale,
        }
    }

    fn report(&self, converged: bool) -> NewtonReport {
        NewtonReport {
            iterations: self.iterations,
            factorizations: self.factorizations,
            converged,
            residual_scale: self.scale,
            final_relative_residual: norm2(&self.residual) / self.scale,
            history: self.history.clone(),
            timings: self.timings,
        }
    }
}

/// The bracket of the line search's root of `g(α)` and the choice of the next trial.
struct Bracket {
    lo: f64,
    g_lo: f64,
    hi: f64,
    g_hi: f64,
    /// Which end moved last (−1 low, +1 high), for the Illinois modification.
    last_moved: i8,
}

impl Bracket {
    fn new(g0: f64) -> Self {
        Self { lo: 0.0, g_lo: g0, hi: 1.0, g_hi: f64::INFINITY, last_moved: 0 }
    }

    /// Updates the bracket with the trial `(α, g(α), g'(α))` and returns the next α: Newton on
    /// `g` when it stays inside the bracket, else false position (bisection while the right end is
    /// unbounded); the trial is kept off the ends by 1 % of the bracket so that it always shrinks.
    fn next(&mut self, alpha: f64, g: f64, slope: f64) -> f64 {
        let newton_alpha = alpha - g / slope;
        if !g.is_finite() || g > 0.0 {
            self.hi = alpha;
            self.g_hi = if g.is_finite() { g } else { f64::INFINITY };
            if self.last_moved == 1 {
                self.g_lo *= 0.5; // Illinois: the same end moved twice, halve the other's weight
            }
            self.last_moved = 1;
        } else {
            self.lo = alpha;
            self.g_lo = g;
            if self.last_moved == -1 {
                self.g_hi *= 0.5;
            }
            self.last_moved = -1;
        }
        let (lo, hi) = (self.lo, self.hi);
        let margin = 0.01 * (hi - lo);
        let next = if slope > 0.0 && newton_alpha > lo + margin && newton_alpha < hi - margin {
            newton_alpha
        } else if self.g_hi.is_finite() {
            lo - self.g_lo * (hi - lo) / (self.g_hi - self.g_lo)
        } else {
            0.5 * (lo + hi)
        };
        next.clamp(lo + margin, hi - margin)
    }
}

/// Work vectors kept between iterations and solves.
#[derive(Debug, Default)]
struct NewtonWork {
    r: Vec<f64>,
    z: Vec<f64>,
    p: Vec<f64>,
    kp: Vec<f64>,
    slope: Vec<f64>,
}

impl NewtonWork {
    fn resize(&mut self, n: usize) {
        for v in [&mut self.r, &mut self.z, &mut self.p, &mut self.kp, &mut self.slope] {
            v.resize(n, 0.0);
        }
    }
}

/// Euclidean norm `‖v‖₂` (the norm of the stopping rule).
pub fn norm2(v: &[f64]) -> f64 {
    v.iter().map(|x| x * x).sum::<f64>().sqrt()
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}
