//! Compass search, the simplest generalised pattern search, for one objective with constraints.
//!
//! Kolda, Lewis & Torczon (2003), "Optimization by direct search: new perspectives on some classical
//! and modern methods", SIAM Review 45(3), 385–482 (compass search, Algorithm 3.1); Torczon (1997),
//! "On the convergence of pattern search algorithms", SIAM J. Optim. 7(1), 1–25.
//!
//! Each iteration polls the `2n` points `x ± Δ_i e_i` (coordinate steps scaled to each variable's
//! range: `Δ_i = f · (upper_i − lower_i)`), evaluated in **one** `evaluate_batch` call so the caller can
//! run the FEA in parallel. If the best poll point is strictly better than `x`, the search moves
//! there and doubles `f`; otherwise it halves `f`. Because `f` only ever changes by factors 2 and ½,
//! the iterates stay on a rational lattice and simple decrease suffices for the convergence theory of
//! Torczon (1997). The run stops, *converged*, when a poll fails with `f` below
//! [`PatternSearchOptions::min_step_fraction`] (and integer steps at 1), or when the evaluation
//! budget is spent.
//!
//! * No derivatives and no model: suited to FEA objectives with discretisation noise (remeshing makes
//!   the objective piecewise-smooth at best).
//! * Constraints: Deb's feasibility rules ([`crate::pareto::feasibility_order`]): feasible beats
//!   infeasible, a smaller violation beats a larger, then the smaller objective. Designs that cannot be
//!   evaluated (infinite violation) never win.
//! * Integer variables: their step is `max(1, round(f · range))`, so they stay integral and keep moving
//!   by at least 1; poll points are repaired into the bounds.
//!
//! Limitation (Kolda et al. 2003, Sec. 8): coordinate directions do not conform to constraints that
//! are not aligned with the axes; at such a boundary the search can stop at a point where every
//! coordinate move is either infeasible or uphill, short of the constrained optimum. For such
//! problems (a torque constraint cutting obliquely through the geometry variables) choose
//! [`PollDirections::RandomOrthogonal`]: each poll uses the `±` columns of a fresh random orthogonal
//! basis (a Householder matrix `I − 2 v vᵀ` of a random unit vector `v`, the construction of
//! OrthoMADS: Abramson, Audet, Dennis & Le Digabel (2009), "OrthoMADS: a deterministic MADS instance
//! with orthogonal directions", SIAM J. Optim. 20(2), 948–966), so over the iterations the poll
//! directions fill the sphere and each poll finds feasible descent along an oblique boundary with
//! positive probability (the idea behind the extreme-barrier analysis of Audet & Dennis (2006), "Mesh
//! adaptive direct search algorithms for constrained optimization", SIAM J. Optim. 17(1), 188–217).
//! The descent cone narrows towards a constrained optimum, so the final approach is slow: on the
//! 2-D test `x + y <= 2` it stops within 0.6 % of the optimal objective where compass search stops
//! 6–25 % above it (`tests/it/pattern_search_validation.rs`). The poll has the same `2n` points;
//! integer variables keep their coordinate moves. Random directions leave the rational lattice, so
//! the convergence theory would call for a sufficient-decrease test (Kolda et al. 2003, Sec. 3.7.1);
//! simple decrease is kept here, which is what the tests measure.

use mrbrake_observe::Observer;

use crate::pareto::{Evaluation, feasibility_order};
use crate::problem::evaluate_checked;
use crate::rng::Rng;
use crate::space::{Bounds, validate_bounds, validate_design};
use crate::{OptimError, Problem, RunError};

/// Step contraction after a failed poll with random directions. A random basis contains a descent
/// direction only with some probability p; Gratton, Royer, Vicente & Zhang (2015), "Direct search
/// based on probabilistic descent", SIAM J. Optim. 25(3), 1515–1541, show convergence needs
/// p > ln θ / ln(θ/γ) for contraction θ and expansion γ: 0.29 for θ = 0.75, γ = 2 (0.5 for the
/// compass factor θ = 0.5), which a descent cone narrowed by an active constraint can still meet.
const RANDOM_POLL_CONTRACTION: f64 = 0.75;

/// Settings of a pattern-search run.
#[derive(Debug, Clone, PartialEq)]
pub struct PatternSearchOptions {
    /// First step as a fraction of each variable's range, in `(0, 1]`. Default 0.25.
    pub initial_step_fraction: f64,
    /// Converged once a poll fails with the step fraction below this, in `(0, initial]`.
    /// Default 1e-3.
    pub min_step_fraction: f64,
    /// Budget of evaluations, the start point included; at least 1. Default 1000.
    pub max_evaluations: usize,
    /// Start design (inside the bounds, integral where required); `None` starts at the centre of the
    /// bounds (integers rounded).
    pub start: Option<Vec<f64>>,
    /// Seed of the random poll bases of [`PollDirections::RandomOrthogonal`]; no effect with
    /// [`PollDirections::Compass`], whose poll order is fixed (`+e_1, −e_1, +e_2, ...`, ties going to
    /// the earliest point).
    pub seed: u64,
    /// Which directions each poll uses. Default [`PollDirections::Compass`].
    pub poll: PollDirections,
}

/// The poll directions of a pattern search.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum PollDirections {
    /// `±` the coordinate directions (compass search, Kolda et al. 2003, Algorithm 3.1).
    #[default]
    Compass,
    /// `±` the columns of a fresh random orthogonal basis each poll for the continuous variables
    /// (Householder construction of OrthoMADS, Abramson et al. 2009), coordinate moves for the integer
    /// ones; for constraints oblique to the axes (see the module docs). The step contracts by ¾
    /// (not ½) after a failed poll, since a random basis holds a descent direction only with some
    /// probability (Gratton et al. 2015); expect 2–3 times the evaluations of compass search.
    RandomOrthogonal,
}

impl Default for PatternSearchOptions {
    fn default() -> Self {
        Self {
            initial_step_fraction: 0.25,
            min_step_fraction: 1e-3,
            max_evaluations: 1000,
            start: None,
            seed: 0,
            poll: PollDirections::Compass,
        }
    }
}

/// The outcome of a pattern-search run.
#[derive(Debug, Clone, PartialEq)]
pub struct PatternSearchResult {
    /// The best design found.
    pub best_x: Vec<f64>,
    /// Its evaluation.
    pub best: Evaluation,
    /// Designs evaluated (start point included).
    pub evaluations: usize,
    /// Polls performed.
    pub iterations: usize,
    /// After the start point and after each poll: (evaluations so far, best objective, its
    /// violation).
    pub history: Vec<(usize, f64, f64)>,
    /// True when the step fell below the minimum (a mesh-local optimum), false when the budget ran
    /// out first or the observer stopped the search.
    pub converged: bool,
    /// True when the observer asked to stop before the search converged or spent its budget.
    pub stopped: bool,
}

/// What an observer sees after the start point and after every poll.
#[derive(Debug, Clone, Copy)]
pub struct PollReport<'a> {
    /// 0 for the start point, then the polls performed so far.
    pub iteration: usize,
    /// Designs evaluated so far (the start point included).
    pub evaluations: usize,
    /// The incumbent design.
    pub best_x: &'a [f64],
    /// Its evaluation.
    pub best: &'a Evaluation,
    /// The current step as a fraction of each variable's range (before this poll's update).
    pub step_fraction: f64,
}

/// Runs compass search on `problem` (exactly one objective), calling `observer` with a
/// [`PollReport`] after the start point and after every poll; [`Flow::Stop`] ends the search
/// after that poll with [`PatternSearchResult::stopped`] set.
///
/// [`Flow::Stop`]: mrbrake_observe::Flow::Stop
///
/// Errors: [`RunError::Optim`] for invalid options, bounds or start point, a problem with other than
/// one objective, or an evaluator that breaks the [`Problem::evaluate_batch`] contract;
/// [`RunError::Problem`] with the evaluator's own error, unchanged.
pub fn run<P: Problem>(
    problem: &mut P,
    options: &PatternSearchOptions,
    observer: &mut impl for<'a> Observer<PollReport<'a>>,
) -> Result<PatternSearchResult, RunError<P::Error>> {
    let bounds = problem.bounds().to_vec();
    validate(&bounds, problem.objectives(), options)?;

    let x: Vec<f64> = match &options.start {
        Some(start) => start.iter().zip(&bounds).map(|(&v, b)| b.repair(v)).collect(),
        None => bounds
            .iter()
            .map(|b| {
                let (lo, hi) = b.feasible_range();
                b.repair(0.5 * (lo + hi))
            })
            .collect(),
    };
    let best = evaluate_checked(problem, std::slice::from_ref(&x))?
        .pop()
        .ok_or(OptimError::WrongEvaluationCount { expected: 1, got: 0 })?;
    let mut search = Search {
        history: vec![(1, objective(&best), best.violation)],
        x,
        best,
        evaluations: 1,
        iterations: 0,
        fraction: options.initial_step_fraction,
        rng: Rng::new(options.seed),
    };
    let mut stopped = observer.observe(&search.report(options.initial_step_fraction)).is_stop();
    let mut converged = false;
    while !stopped && search.evaluations < options.max_evaluations {
        let fraction = search.fraction;
        let steps: Vec<f64> = bounds.iter().map(|b| step(b, fraction)).collect();
        let polled = search.poll(problem, &bounds, &steps, options)?;
        if polled {
            stopped = observer.observe(&search.report(fraction)).is_stop();
        }
        if search.fraction < fraction {
            let integers_at_unit_step =
                bounds.iter().zip(&steps).all(|(b, &s)| !b.is_integer() || s <= 1.0);
            if search.fraction < options.min_step_fraction && integers_at_unit_step {
                converged = true;
                break;
            }
        }
    }
    let Search { x, best, evaluations, iterations, history, .. } = search;
    Ok(PatternSearchResult {
        best_x: x,
        best,
        evaluations,
        iterations,
        history,
        converged,
        stopped,
    })
}

/// The state of a search: the incumbent, the counts, the step fraction and the random generator
/// of the poll bases.
struct Search {
    x: Vec<f64>,
    best: Evaluation,
    evaluations: usize,
    iterations: usize,
    history: Vec<(usize, f64, f64)>,
    fraction: f64,
    rng: Rng,
}

impl Search {
    /// The observer's view of the search, whose last poll used step fraction `fraction`.
    fn report(&self, fraction: f64) -> PollReport<'_> {
        PollReport {
            iteration: self.iterations,
            evaluations: self.evaluations,
            best_x: &self.x,
            best: &self.best,
            step_fraction: fraction,
        }
    }

    /// One poll (within the evaluation budget) and the step update: the best poll point replaces
    /// the incumbent when strictly better and the step doubles, otherwise the step contracts.
    /// Returns whether any point was evaluated.
    fn poll<P: Problem>(
        &mut self,
        problem: &mut P,
        bounds: &[Bounds],
        steps: &[f64],
        options: &PatternSearchOptions,
    ) -> Result<bool, RunError<P::Error>> {
        let mut poll = match options.poll {
            PollDirections::Compass => poll_points(&self.x, steps, bounds),
            PollDirections::RandomOrthogonal => {
                rotated_poll_points(&self.x, self.fraction, bounds, &mut self.rng)
            }
        };
        poll.truncate(options.max_evaluations - self.evaluations);
        let mut improved = false;
        let polled = !poll.is_empty();
        if polled {
            let results = evaluate_checked(problem, &poll)?;
            self.evaluations += poll.len();
            self.iterations += 1;
            // The earliest of the best poll points: `min_by` keeps the first of equal elements.
            let winner = results
                .iter()
                .enumerate()
                .min_by(|a, b| feasibility_order(a.1, b.1))
                .map(|(k, _)| k);
            if let Some(k) = winner
                && feasibility_order(&results[k], &self.best).is_lt()
            {
                self.x = poll.swap_remove(k);
                self.best = results[k].clone();
                improved = true;
            }
            self.history.push((self.evaluations, objective(&self.best), self.best.violation));
        }
        self.fraction = if improved {
            (2.0 * self.fraction).min(1.0)
        } else {
            self.fraction
                * match options.poll {
                    PollDirections::Compass => 0.5,
                    PollDirections::RandomOrthogonal => RANDOM_POLL_CONTRACTION,
                }
        };
        Ok(polled)
    }
}

/// The single objective of an evaluation (infinity if absent, which the contract check prevents).
fn objective(e: &Evaluation) -> f64 {
    e.objectives.first().copied().unwrap_or(f64::INFINITY)
}

/// The coordinate step of one variable at step fraction `fraction`: `fraction · range`, and for an
/// integer variable at least 1 and integral (0 when the range is a single value).
fn step(b: &Bounds, fraction: f64) -> f64 {
    let width = b.width();
    if b.is_integer() {
        if width < 1.0 { 0.0 } else { (fraction * width).round().max(1.0) }
    } else {
        fraction * width
    }
}

/// The compass poll set `x ± Δ_i e_i`, repaired into the bounds, without points equal to `x` (a step
/// clamped away at a bound) or repeated.
fn poll_points(x: &[f64], steps: &[f64], bounds: &[Bounds]) -> Vec<Vec<f64>> {
    let mut poll: Vec<Vec<f64>> = Vec::with_capacity(2 * x.len());
    for (i, (b, &delta)) in bounds.iter().zip(steps).enumerate() {
        if delta <= 0.0 {
            continue;
        }
        let up = b.repair(x[i] + delta);
        let down = b.repair(x[i] - delta);
        // Only coordinate i differs from x, so comparing it is enough to spot repeats.
        let mut moves = vec![up];
        if down.total_cmp(&up).is_ne() {
            moves.push(down);
        }
        for moved in moves {
            if moved.total_cmp(&x[i]).is_ne() {
                let mut y = x.to_vec();
                y[i] = moved;
                poll.push(y);
            }
        }
    }
    poll
}

/// The poll set of [`PollDirections::RandomOrthogonal`]: for the continuous variables (in coordinates
/// scaled by each range) `x ± f · h_j` for the columns `h_j` of the Householder matrix
/// `H = I − 2 v vᵀ` of a random unit vector `v` (orthogonal and symmetric, so its columns are an
/// orthonormal basis; Abramson et al. 2009, Sec. 3); for the integer variables the coordinate moves
/// of [`poll_points`]. Points are repaired into the bounds; points equal to `x` are dropped.
fn rotated_poll_points(
    x: &[f64],
    fraction: f64,
    bounds: &[Bounds],
    rng: &mut Rng,
) -> Vec<Vec<f64>> {
    let continuous: Vec<usize> =
        (0..bounds.len()).filter(|&i| !bounds[i].is_integer() && bounds[i].width() > 0.0).collect();
    let mut poll = Vec::with_capacity(2 * bounds.len());
    if !continuous.is_empty() {
        // A random direction: independent standard normal deviates (Box–Muller), normalised.
        let mut v: Vec<f64> = Vec::with_capacity(continuous.len());
        let mut norm = 0.0;
        while norm < 1e-12 {
            v = (0..continuous.len())
                .map(|_| {
                    let radius = (-2.0 * (1.0 - rng.uniform()).ln()).sqrt();
                    radius * (std::f64::consts::TAU * rng.uniform()).cos()
                })
                .collect();
            norm = v.iter().map(|a| a * a).sum::<f64>().sqrt();
        }
        for a in &mut v {
            *a /= norm;
        }
        for j in 0..continuous.len() {
            for sign in [1.0, -1.0] {
                let mut y = x.to_vec();
                for (k, &i) in continuous.iter().enumerate() {
                    let householder = f64::from(u8::from(k == j)) - 2.0 * v[k] * v[j];
                    let b = &bounds[i];
                    y[i] = b.repair(x[i] + sign * fraction * b.width() * householder);
                }
                if y.iter().zip(x).any(|(a, b)| a.total_cmp(b).is_ne()) {
                    poll.push(y);
                }
            }
        }
    }
    let integer_steps: Vec<f64> =
        bounds.iter().map(|b| if b.is_integer() { step(b, fraction) } else { 0.0 }).collect();
    poll.extend(poll_points(x, &integer_steps, bounds));
    poll
}

/// Checks bounds, objective count, options and start point before anything is evaluated.
fn validate(
    bounds: &[Bounds],
    objectives: usize,
    options: &PatternSearchOptions,
) -> Result<(), OptimError> {
    validate_bounds(bounds)?;
    if objectives != 1 {
        return Err(OptimError::ObjectiveCount {
            method: "pattern search",
            got: objectives,
            allowed: "exactly 1",
        });
    }
    let initial = options.initial_step_fraction;
    if !(initial > 0.0 && initial <= 1.0) {
        return Err(OptimError::InvalidOption {
            name: "initial_step_fraction",
            value: initial,
            allowed: "a fraction of the range in (0, 1]",
        });
    }
    let minimum = options.min_step_fraction;
    if !(minimum > 0.0 && minimum <= initial) {
        return Err(OptimError::InvalidOption {
            name: "min_step_fraction",
            value: minimum,
            allowed: "a fraction in (0, initial_step_fraction]",
        });
    }
    if options.max_evaluations == 0 {
        return Err(OptimError::InvalidOption {
            name: "max_evaluations",
            value: 0.0,
            allowed: "at least 1",
        });
    }
    if let Some(start) = &options.start {
        validate_design(bounds, start, "start point")?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::FnProblem;
    use mrbrake_error::Kind as _;
    use mrbrake_observe::Silent;

    #[test]
    fn poll_set_is_clamped_and_deduplicated() {
        let bounds = [Bounds::continuous(0.0, 1.0), Bounds::integer(1.0, 3.0)];
        let poll = poll_points(&[1.0, 1.0], &[0.25, 1.0], &bounds);
        // +x is clamped back onto x (dropped), -x moves, +y moves, -y is clamped (dropped).
        assert_eq!(poll, vec![vec![0.75, 1.0], vec![1.0, 2.0]]);
    }

    #[test]
    fn integer_steps_are_integral_and_at_least_one() {
        let b = Bounds::integer(0.0, 10.0);
        approx::assert_abs_diff_eq!(step(&b, 0.25), 3.0);
        approx::assert_abs_diff_eq!(step(&b, 0.01), 1.0);
        approx::assert_abs_diff_eq!(step(&Bounds::integer(2.0, 2.0), 0.5), 0.0);
    }

    #[test]
    fn rejects_multi_objective_problems_and_bad_options() {
        let mut two = FnProblem::new(vec![Bounds::continuous(0.0, 1.0)], 2, |x: &[f64]| {
            Evaluation::new(vec![x[0], -x[0]], 0.0)
        });
        let e = run(&mut two, &PatternSearchOptions::default(), &mut Silent).unwrap_err();
        assert!(e.is_input_error());
        let mut one = FnProblem::new(vec![Bounds::continuous(0.0, 1.0)], 1, |x: &[f64]| {
            Evaluation::new(vec![x[0]], 0.0)
        });
        for options in [
            PatternSearchOptions { initial_step_fraction: 0.0, ..Default::default() },
            PatternSearchOptions { min_step_fraction: 0.5, ..Default::default() },
            PatternSearchOptions { max_evaluations: 0, ..Default::default() },
            PatternSearchOptions { start: Some(vec![3.0]), ..Default::default() },
        ] {
            assert!(run(&mut one, &options, &mut Silent).unwrap_err().is_input_error());
        }
        assert_eq!(one.evaluations(), 0);
    }

    #[test]
    fn budget_is_never_exceeded() {
        let mut problem =
            FnProblem::new(vec![Bounds::continuous(-1.0, 1.0); 3], 1, |x: &[f64]| {
                Evaluation::new(vec![x.iter().map(|v| (v - 0.123).powi(2)).sum()], 0.0)
            });
        let options = PatternSearchOptions { max_evaluations: 20, ..Default::default() };
        let result = run(&mut problem, &options, &mut Silent).unwrap();
        assert_eq!(result.evaluations, 20);
        assert_eq!(problem.evaluations(), 20);
        assert!(!result.converged);
    }
}
