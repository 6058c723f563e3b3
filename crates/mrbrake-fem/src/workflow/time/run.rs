//! The time loop of [`super::integrate`]: step sizes, the scheme's coefficients, the linear fast
//! path and Newton per step, Milne's error estimate, accepted levels.

use mrbrake_observe::Observer;

use super::{
    Event, Level, Outcome, Scheme, Step, TimeError, TimeOptions, TimeStep, TransientProblem,
    observe,
};
use crate::FemError;
use crate::workflow::newton::{EliminationOrder, NewtonError, NewtonOptions};

/// One stored time level.
#[derive(Debug, Clone)]
struct Stored {
    t: f64,
    /// The step that reached this level (0 for the initial one): BDF2's step ratio uses it, so
    /// fixed steps have exactly ω = 1 (no round-off from differences of times).
    dt: f64,
    u: Vec<f64>,
    auxiliary: Vec<f64>,
}

/// A solved (not yet accepted) step.
pub(super) struct Attempt {
    step: Step,
    u: Vec<f64>,
    newton_iterations: usize,
}

/// The state of one run.
pub(super) struct Run {
    options: TimeOptions,
    /// The newest levels, oldest first (at most three: BDF2's predictor needs them).
    levels: Vec<Stored>,
    outcome: Outcome,
    /// The rate the physics was last prepared with.
    prepared_rate: Option<f64>,
    /// The rate of the stored factor of a linear step's matrix.
    factor_rate: Option<f64>,
    /// `S(u₀)` at the lifting (linear fast path; constant over a run).
    static_offset: Option<Vec<f64>>,
    /// The lifting `u₀`: prescribed values, zero at the free DOFs.
    lifting: Vec<f64>,
    /// Newton's stopping scale (asked on the first Newton step).
    scale: Option<f64>,
    /// `max |u|` over the accepted levels (the error reference of adaptive steps).
    u_max: f64,
}

impl Run {
    pub(super) fn new<P: TransientProblem>(
        problem: &P,
        mut initial: Vec<f64>,
        options: &TimeOptions,
    ) -> Self {
        let constraints = problem.constraints();
        constraints.impose(&mut initial);
        let auxiliary = problem.auxiliary(&initial);
        let outcome = Outcome {
            u: Vec::new(),
            t: 0.0,
            stopped: false,
            steps: 0,
            rejected_steps: 0,
            factorizations: 0,
            newton_iterations: 0,
        };
        Self {
            options: *options,
            u_max: max_abs(&initial),
            lifting: constraints.lifting(),
            levels: vec![Stored { t: 0.0, dt: 0.0, u: initial, auxiliary }],
            outcome,
            prepared_rate: None,
            factor_rate: None,
            static_offset: None,
            scale: None,
        }
    }

    /// The time loop.
    pub(super) fn integrate<P, O>(
        mut self,
        problem: &mut P,
        observer: &mut O,
    ) -> Result<Outcome, P::Error>
    where
        P: TransientProblem,
        O: for<'a> Observer<Event<'a, P>>,
    {
        if self.commit(problem, observer, None)? {
            return Ok(self.finish(true));
        }
        let t_end = self.options.t_end_s;
        let mut breakpoints = problem.breakpoints(t_end);
        breakpoints.sort_by(f64::total_cmp);
        let (mut dt, adaptive_rtol, fixed_steps) = match self.options.step {
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
            if step > self.options.max_steps {
                let max_steps = self.options.max_steps;
                return Err(TimeError::TooManySteps { max_steps, t_end_s: t_end, t_s: t }.into());
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
            let attempt = match self.attempt(problem, t_next, dt_try) {
                Ok(attempt) => attempt,
                Err(_) if adaptive_rtol.is_some() && dt_try > 1e-9 * t_end => {
                    self.outcome.rejected_steps += 1;
                    dt = 0.5 * dt_try;
                    continue;
                }
                Err(source) => {
                    return Err(TimeError::Step { step, time_s: t_next, source }.into());
                }
            };
            if let Some(rtol) = adaptive_rtol {
                let ratio = self.error_ratio(&attempt, rtol);
                let p = self.options.scheme.order() as f64;
                let factor = (0.9 * ratio.max(1e-10).powf(-1.0 / (p + 1.0))).clamp(0.2, 2.0);
                if ratio > 1.0 {
                    self.outcome.rejected_steps += 1;
                    dt = dt_try * factor.min(0.5);
                    continue;
                }
                dt = (dt_try * factor).min(t_end / 20.0);
            }
            t = attempt.step.t;
            if self.commit(problem, observer, Some(attempt))? {
                return Ok(self.finish(true));
            }
        }
        Ok(self.finish(false))
    }

    /// Solves the step to `t_next`.
    pub(super) fn attempt<P: TransientProblem>(
        &mut self,
        problem: &mut P,
        t_next: f64,
        dt: f64,
    ) -> Result<Attempt, NewtonError> {
        let step = self.step_to(t_next, dt);
        let rate = step.rate;
        let beyond_tolerance = self.prepared_rate.is_none_or(|r| (r - rate).abs() > 1e-12 * rate);
        // A linear step keeps its factor while the rate stays within round-off; a non-linear one
        // is prepared with its exact rate.
        let changed = self.prepared_rate.map(f64::to_bits) != Some(rate.to_bits());
        if changed && (beyond_tolerance || !problem.is_linear()) {
            problem.prepare(&step);
            self.prepared_rate = Some(rate);
            if beyond_tolerance {
                self.factor_rate = None;
            }
        }
        let (u, newton_iterations) = if problem.is_linear() {
            (self.affine_step(problem, &step)?, 1)
        } else {
            // Newton starts from the scheme's predictor (the polynomial through the last levels),
            // closer to the step's solution than the newest level: about one Newton iteration
            // less per step.
            let start = predictor(self.options.scheme, &self.levels, t_next)
                .map_or_else(|| self.newest().u.clone(), |(p, _)| p);
            self.newton_step(problem, &step, start)?
        };
        Ok(Attempt { step, u, newton_iterations })
    }

    /// A step of a non-linear problem: Newton from `u`.
    fn newton_step<P: TransientProblem>(
        &mut self,
        problem: &mut P,
        step: &Step,
        mut u: Vec<f64>,
    ) -> Result<(Vec<f64>, usize), NewtonError> {
        // Consecutive steps' Jacobians are close: start from the last step's factor.
        let options = NewtonOptions { reuse_factor: true, ..problem.newton_options() };
        let scale = *self.scale.get_or_insert_with(|| problem.residual_scale());
        let (newton, mut system) = problem.step_system(step);
        let report = newton.solve(&mut system, &mut u, scale, &options)?;
        self.outcome.factorizations += report.factorizations;
        Ok((u, report.iterations))
    }

    /// A step of a linear problem with the stored factor (factorised on the first step at this
    /// rate): `u = u₀ − J⁻¹ R(u₀)` with `R(u₀) = S(u₀) + ρ M (u₀ − h) + L(u₀, t)` (module docs).
    fn affine_step<P: TransientProblem>(
        &mut self,
        problem: &mut P,
        step: &Step,
    ) -> Result<Vec<f64>, NewtonError> {
        let failed = |e: FemError| NewtonError::before_iterating(e, 0.0);
        if self.factor_rate.is_none() {
            let (newton, mut system) = problem.step_system(step);
            // Hundreds of solves per factorisation: the order with the fewest factor entries.
            newton.set_elimination_order(EliminationOrder::MinimumDegree).map_err(failed)?;
            newton.factorize_at(&mut system, &self.lifting).map_err(failed)?;
            self.outcome.factorizations += 1;
            self.factor_rate = Some(step.rate);
        }
        let offset = match self.static_offset.take() {
            Some(offset) => offset,
            None => problem.static_residual(&self.lifting),
        };
        let mass_argument: Vec<f64> =
            self.lifting.iter().zip(&step.history).map(|(u, h)| u - h).collect();
        let mass = problem.constraints().restrict(&problem.mass_product(&mass_argument));
        let mut residual: Vec<f64> =
            offset.iter().zip(&mass).map(|(r, m)| r + step.rate * m).collect();
        self.static_offset = Some(offset);
        problem.add_step_loads(step, &self.lifting, &mut residual);
        residual.iter_mut().for_each(|r| *r = -*r);
        problem.newton().solve_jacobian_in_place(&mut residual).map_err(failed)?;
        let delta = problem.constraints().extend_with_zeros(&residual);
        Ok(self.lifting.iter().zip(&delta).map(|(u, d)| u + d).collect())
    }

    /// The step of `dt` to `t`: `ρ`, `h` and the auxiliary histories after the stored levels.
    fn step_to(&self, t: f64, dt: f64) -> Step {
        let newest = self.newest();
        if self.options.scheme == Scheme::ImplicitEuler || self.levels.len() < 2 {
            return Step {
                t,
                dt,
                rate: 1.0 / dt,
                history: newest.u.clone(),
                auxiliary_history: newest.auxiliary.clone(),
            };
        }
        let older = &self.levels[self.levels.len() - 2];
        let omega = dt / newest.dt;
        let gamma = (1.0 + 2.0 * omega) / (1.0 + omega);
        let (w_n, w_old) = ((1.0 + omega) / gamma, omega * omega / (1.0 + omega) / gamma);
        let combine = |x: &[f64], y: &[f64]| -> Vec<f64> {
            x.iter().zip(y).map(|(x, y)| w_n * x - w_old * y).collect()
        };
        Step {
            t,
            dt,
            rate: gamma / dt,
            history: combine(&newest.u, &older.u),
            auxiliary_history: combine(&newest.auxiliary, &older.auxiliary),
        }
    }

    /// The state of the newest level.
    #[cfg(test)]
    pub(super) fn state(&self) -> &[f64] {
        &self.newest().u
    }

    fn newest(&self) -> &Stored {
        &self.levels[self.levels.len() - 1]
    }

    /// The estimated local error over `rtol · max|u|` (0 while the predictor lacks history).
    fn error_ratio(&self, attempt: &Attempt, rtol: f64) -> f64 {
        let Some((predicted, constant)) =
            predictor(self.options.scheme, &self.levels, attempt.step.t)
        else {
            return 0.0;
        };
        let difference =
            attempt.u.iter().zip(&predicted).fold(0.0_f64, |m, (u, p)| m.max((u - p).abs()));
        let reference = self.u_max.max(max_abs(&attempt.u));
        if reference <= 0.0 {
            return 0.0;
        }
        constant * difference / (rtol * reference)
    }

    /// Makes `attempt` the newest level (the initial level when `None`), lets the physics commit
    /// it and the observer see it. Returns true when the observer asks to stop.
    pub(super) fn commit<P, O>(
        &mut self,
        problem: &mut P,
        observer: &mut O,
        attempt: Option<Attempt>,
    ) -> Result<bool, P::Error>
    where
        P: TransientProblem,
        O: for<'a> Observer<Event<'a, P>>,
    {
        let step = attempt.map(|a| {
            let auxiliary = problem.auxiliary(&a.u);
            self.u_max = self.u_max.max(max_abs(&a.u));
            self.outcome.steps += 1;
            self.outcome.newton_iterations += a.newton_iterations;
            if self.levels.len() == 3 {
                self.levels.remove(0);
            }
            self.levels.push(Stored { t: a.step.t, dt: a.step.dt, u: a.u, auxiliary });
            (a.step, a.newton_iterations)
        });
        let newest = &self.levels[self.levels.len() - 1];
        let level = match &step {
            Some((step, newton_iterations)) => Level {
                index: self.outcome.steps,
                t: newest.t,
                dt: newest.dt,
                u: &newest.u,
                auxiliary: &newest.auxiliary,
                rate: step.rate,
                history: &step.history,
                auxiliary_history: &step.auxiliary_history,
                newton_iterations: *newton_iterations,
            },
            None => Level {
                index: 0,
                t: newest.t,
                dt: 0.0,
                u: &newest.u,
                auxiliary: &newest.auxiliary,
                rate: 0.0,
                history: &newest.u,
                auxiliary_history: &newest.auxiliary,
                newton_iterations: 0,
            },
        };
        problem.accept(&level)?;
        Ok(observe(observer, problem, level).is_stop())
    }

    fn finish(mut self, stopped: bool) -> Outcome {
        let newest = self.levels.pop().expect("a run always has its initial level");
        Outcome { u: newest.u, t: newest.t, stopped, ..self.outcome }
    }
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
fn predictor(scheme: Scheme, levels: &[Stored], t: f64) -> Option<(Vec<f64>, f64)> {
    let n = levels.len();
    match scheme {
        Scheme::ImplicitEuler if n >= 2 => {
            let (l0, l1) = (&levels[n - 2], &levels[n - 1]);
            let w = (t - l1.t) / (l1.t - l0.t);
            let p = l1.u.iter().zip(&l0.u).map(|(u1, u0)| u1 + w * (u1 - u0)).collect();
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
            let p = (0..l2.u.len()).map(|i| w0 * l0.u[i] + w1 * l1.u[i] + w2 * l2.u[i]).collect();
            Some((p, 2.0 / 11.0))
        }
        _ => None,
    }
}

fn max_abs(x: &[f64]) -> f64 {
    x.iter().fold(0.0_f64, |m, v| m.max(v.abs()))
}
