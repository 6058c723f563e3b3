//! NSGA-II, the elitist non-dominated sorting genetic algorithm for constrained multi-objective
//! problems.
//!
//! Deb, Pratap, Agarwal & Meyarivan (2002), "A fast and elitist multiobjective genetic algorithm:
//! NSGA-II", IEEE Trans. Evol. Comput. 6(2), 182–197:
//!
//! 1. The first population is a Latin hypercube over the bounds ([`crate::sampling::latin_hypercube`])
//!    plus the caller's designs ([`Nsga2Options::initial`], e.g. a known baseline); it is evaluated in
//!    one batch and ranked by the fast non-dominated sort under constrained domination, with crowding
//!    distance inside each front ([`crate::pareto`]).
//! 2. Each generation, parents are picked by binary tournament with the crowded-comparison operator
//!    (lower rank wins, then larger crowding distance, then a coin flip; Deb et al. 2002, Sec. III-B),
//!    recombined by simulated binary crossover (SBX; Deb & Agrawal 1995, "Simulated binary crossover
//!    for continuous search space", Complex Systems 9, 115–148) and perturbed by polynomial mutation
//!    (Deb & Goyal 1996, "A combined genetic adaptive search (GeneAS) for engineering design",
//!    Computer Science and Informatics 26(4), 30–45). Both operators use the bounded forms of Deb's
//!    reference implementation (NSGA-II v1.1, KanGAL), so children never leave the bounds.
//! 3. Integer variables are varied over their range widened by half a unit on each side, then
//!    repaired (rounded and clamped, [`crate::space::Bounds::repair`]), so every integer value has an
//!    equal share of the real line; a mutated integer variable moves by at least one unit (creep
//!    mutation), so a variable with few levels keeps all of them within reach.
//!    A categorical variable (unordered levels, [`crate::space::VariableKind::Categorical`]) is
//!    never interpolated: crossover passes each parent's level to one child or the other with equal
//!    probability (uniform crossover, Syswerda 1989, "Uniform crossover in genetic algorithms",
//!    ICGA 3, 2–9) and mutation resets it to another level drawn uniformly (random resetting, Eiben &
//!    Smith, *Introduction to Evolutionary Computing*, 2nd ed. 2015, §4.3.1).
//! 4. The offspring (as many as the population) are evaluated in **one** `evaluate_batch` call; parents
//!    and offspring are merged and the best `population` survive by front, the last front cut by
//!    descending crowding distance ((μ+λ) elitism, Deb et al. 2002, Sec. III-C).
//!
//! Constraints follow the constrained-domination rule (Deb et al. 2002, Sec. VI), so no penalty
//! parameter is needed and designs that failed to evaluate (infinite violation) simply lose.
//!
//! Every random choice comes from one [`Rng`] seeded by [`Nsga2Options::seed`], in a fixed order: the
//! same seed and evaluator give the same result bit for bit.
//!
//! The caller's [`Observer`] sees a [`GenerationReport`] after the initial population and after
//! every generation; [`Flow::Stop`](mrbrake_observe::Flow::Stop) ends the run after that generation, with its population as the
//! result ([`Nsga2Result::stopped`]).

use std::cmp::Ordering;

use mrbrake_observe::Observer;

use crate::pareto::{Evaluation, crowding_distance, non_dominated_sort};
use crate::problem::evaluate_checked;
use crate::rng::Rng;
use crate::sampling::latin_hypercube;
use crate::space::{Bounds, validate_bounds, validate_design};
use crate::{OptimError, Problem, RunError};

/// Settings of an NSGA-II run.
#[derive(Debug, Clone, PartialEq)]
pub struct Nsga2Options {
    /// Designs per generation; even and at least 4. Default 40.
    pub population: usize,
    /// Generations after the initial one. Default 50 (2 040 evaluations with the default
    /// population).
    pub generations: usize,
    /// Probability that a pair of parents is recombined (otherwise copied); in `[0, 1]`. Default 0.9.
    pub crossover_probability: f64,
    /// SBX distribution index η_c (larger keeps children closer to their parents); `>= 0`.
    /// Default 15.
    pub crossover_eta: f64,
    /// Polynomial-mutation distribution index η_m; `>= 0`. Default 20.
    pub mutation_eta: f64,
    /// Probability that each variable is mutated, in `[0, 1]`; `None` means 1 / (number of
    /// variables), Deb's recommendation. Default `None`.
    pub mutation_probability: Option<f64>,
    /// Seed of the random generator. Default 0.
    pub seed: u64,
    /// Designs placed in the first population before the Latin hypercube fills it (e.g. a known
    /// baseline). Each must lie inside the bounds, integral where required; at most `population`.
    pub initial: Vec<Vec<f64>>,
}

impl Default for Nsga2Options {
    fn default() -> Self {
        Self {
            population: 40,
            generations: 50,
            crossover_probability: 0.9,
            crossover_eta: 15.0,
            mutation_eta: 20.0,
            mutation_probability: None,
            seed: 0,
            initial: Vec::new(),
        }
    }
}

/// One member of a population.
#[derive(Debug, Clone, PartialEq)]
pub struct Individual {
    /// The design variables.
    pub x: Vec<f64>,
    /// Its evaluation.
    pub evaluation: Evaluation,
    /// Its front under constrained domination (0 = non-dominated).
    pub rank: usize,
    /// Its crowding distance within its front (infinite at the front's extremes).
    pub crowding: f64,
}

/// What an observer sees after the initial population (generation 0) and after every generation.
#[derive(Debug, Clone, Copy)]
pub struct GenerationReport<'a> {
    /// 0 for the initial population, then 1, 2, ...
    pub generation: usize,
    /// Designs evaluated so far (including the initial population).
    pub evaluations: usize,
    /// The population that survived this generation, best fronts first.
    pub population: &'a [Individual],
}

/// The outcome of an NSGA-II run.
#[derive(Debug, Clone, PartialEq)]
pub struct Nsga2Result {
    /// The final population, best fronts first.
    pub population: Vec<Individual>,
    /// The feasible rank-0 members of the final population (each distinct design once), sorted by
    /// the first objective, then the following ones.
    pub front: Vec<Individual>,
    /// Designs evaluated in total.
    pub evaluations: usize,
    /// Generations run after the initial population (fewer than asked for when stopped).
    pub generations: usize,
    /// True when the observer asked to stop before the last generation.
    pub stopped: bool,
}

/// Runs NSGA-II on `problem`, calling `observer` after the initial population and after each
/// generation (for progress bars and checkpoints); [`Flow::Stop`](mrbrake_observe::Flow::Stop) ends the run after that
/// generation, with [`Nsga2Result::stopped`] set.
///
/// Errors: [`RunError::Optim`] for invalid options, bounds or initial designs, or an evaluator that
/// breaks the [`Problem::evaluate_batch`] contract; [`RunError::Problem`] with the evaluator's own
/// error, unchanged.
pub fn run<P: Problem>(
    problem: &mut P,
    options: &Nsga2Options,
    observer: &mut impl for<'a> Observer<GenerationReport<'a>>,
) -> Result<Nsga2Result, RunError<P::Error>> {
    let bounds = problem.bounds().to_vec();
    let objectives = problem.objectives();
    validate(&bounds, objectives, options)?;
    let mutation_probability = options.mutation_probability.unwrap_or(1.0 / bounds.len() as f64);
    let mut rng = Rng::new(options.seed);

    let mut designs: Vec<Vec<f64>> = options
        .initial
        .iter()
        .map(|x| x.iter().zip(&bounds).map(|(&v, b)| b.repair(v)).collect())
        .collect();
    designs.extend(latin_hypercube(options.population - designs.len(), &bounds, &mut rng));
    let evaluations = evaluate_checked(problem, &designs)?;
    let mut evaluation_count = designs.len();
    let mut population = rank_and_select(
        designs
            .into_iter()
            .zip(evaluations)
            .map(|(x, evaluation)| Individual { x, evaluation, rank: 0, crowding: 0.0 })
            .collect(),
        options.population,
    );
    let first =
        GenerationReport { generation: 0, evaluations: evaluation_count, population: &population };
    let mut flow = observer.observe(&first);
    let mut generations = 0;

    for generation in 1..=options.generations {
        if flow.is_stop() {
            break;
        }
        let offspring_x =
            make_offspring(&population, &bounds, options, mutation_probability, &mut rng);
        let offspring_evaluations = evaluate_checked(problem, &offspring_x)?;
        evaluation_count += offspring_x.len();
        let mut combined = population;
        combined.extend(
            offspring_x.into_iter().zip(offspring_evaluations).map(|(x, evaluation)| Individual {
                x,
                evaluation,
                rank: 0,
                crowding: 0.0,
            }),
        );
        population = rank_and_select(combined, options.population);
        generations = generation;
        flow = observer.observe(&GenerationReport {
            generation,
            evaluations: evaluation_count,
            population: &population,
        });
    }

    let front = final_front(&population);
    let stopped = flow.is_stop() && generations < options.generations;
    Ok(Nsga2Result { population, front, evaluations: evaluation_count, generations, stopped })
}

/// Checks bounds, objective count and options before anything is evaluated.
fn validate(
    bounds: &[Bounds],
    objectives: usize,
    options: &Nsga2Options,
) -> Result<(), OptimError> {
    validate_bounds(bounds)?;
    if objectives == 0 {
        return Err(OptimError::ObjectiveCount {
            method: "NSGA-II",
            got: objectives,
            allowed: "at least 1",
        });
    }
    if options.population < 4 || options.population % 2 != 0 {
        return Err(OptimError::InvalidOption {
            name: "population",
            value: options.population as f64,
            allowed: "an even number >= 4",
        });
    }
    let probability = |name, value: f64| {
        if (0.0..=1.0).contains(&value) {
            Ok(())
        } else {
            Err(OptimError::InvalidOption { name, value, allowed: "a probability in [0, 1]" })
        }
    };
    probability("crossover_probability", options.crossover_probability)?;
    if let Some(p) = options.mutation_probability {
        probability("mutation_probability", p)?;
    }
    for (name, value) in
        [("crossover_eta", options.crossover_eta), ("mutation_eta", options.mutation_eta)]
    {
        if !(value.is_finite() && value >= 0.0) {
            return Err(OptimError::InvalidOption {
                name,
                value,
                allowed: "a finite distribution index >= 0",
            });
        }
    }
    if options.initial.len() > options.population {
        return Err(OptimError::InvalidOption {
            name: "initial",
            value: options.initial.len() as f64,
            allowed: "at most `population` initial designs",
        });
    }
    for (k, x) in options.initial.iter().enumerate() {
        validate_design(bounds, x, &format!("initial design {k}"))?;
    }
    Ok(())
}

/// Non-dominated sort of `candidates`, then the best `size` by front and, in the front that does not
/// fit whole, by descending crowding distance (Deb et al. 2002, Sec. III-C). Each survivor carries
/// the rank and crowding distance computed among all candidates.
fn rank_and_select(candidates: Vec<Individual>, size: usize) -> Vec<Individual> {
    let evaluations: Vec<Evaluation> = candidates.iter().map(|c| c.evaluation.clone()).collect();
    let fronts = non_dominated_sort(&evaluations);
    let mut slots: Vec<Option<Individual>> = candidates.into_iter().map(Some).collect();
    let mut survivors = Vec::with_capacity(size);
    for (rank, front) in fronts.iter().enumerate() {
        if survivors.len() >= size {
            break;
        }
        let crowding = crowding_distance(&evaluations, front);
        let mut members: Vec<(usize, f64)> = front.iter().copied().zip(crowding).collect();
        if survivors.len() + members.len() > size {
            // Stable sort, so equal distances keep index order and the run stays deterministic.
            members.sort_by(|a, b| b.1.total_cmp(&a.1));
            members.truncate(size - survivors.len());
        }
        for (index, crowding) in members {
            if let Some(mut individual) = slots[index].take() {
                individual.rank = rank;
                individual.crowding = crowding;
                survivors.push(individual);
            }
        }
    }
    survivors
}

/// The crowded-comparison operator (Deb et al. 2002, Sec. III-B): `Less` when `a` is better.
fn crowded_comparison(a: &Individual, b: &Individual) -> Ordering {
    a.rank.cmp(&b.rank).then_with(|| b.crowding.total_cmp(&a.crowding))
}

/// Binary tournament: two distinct random members, the better by crowded comparison, a coin flip on
/// a tie.
fn tournament<'a>(population: &'a [Individual], rng: &mut Rng) -> &'a Individual {
    let n = population.len();
    let a = rng.index(n);
    let mut b = rng.index(n - 1);
    if b >= a {
        b += 1;
    }
    match crowded_comparison(&population[a], &population[b]) {
        Ordering::Less => &population[a],
        Ordering::Greater => &population[b],
        Ordering::Equal => {
            if rng.bernoulli(0.5) {
                &population[a]
            } else {
                &population[b]
            }
        }
    }
}

/// The interval the variation operators work in: the bounds for a continuous variable, the integer
/// range widened by half a unit each side for an integer one (see the module docs).
fn operator_range(b: &Bounds) -> (f64, f64) {
    let (lo, hi) = b.feasible_range();
    if b.is_integer() { (lo - 0.5, hi + 0.5) } else { (lo, hi) }
}

/// One generation of offspring: `population.len()` children from tournament-selected pairs, SBX
/// crossover, polynomial mutation, repair.
fn make_offspring(
    population: &[Individual],
    bounds: &[Bounds],
    options: &Nsga2Options,
    mutation_probability: f64,
    rng: &mut Rng,
) -> Vec<Vec<f64>> {
    let mut offspring = Vec::with_capacity(population.len());
    while offspring.len() < population.len() {
        let parent1 = tournament(population, rng);
        let parent2 = tournament(population, rng);
        let (mut child1, mut child2) = if rng.bernoulli(options.crossover_probability) {
            sbx_crossover(&parent1.x, &parent2.x, bounds, options.crossover_eta, rng)
        } else {
            (parent1.x.clone(), parent2.x.clone())
        };
        for child in [&mut child1, &mut child2] {
            polynomial_mutation(child, bounds, options.mutation_eta, mutation_probability, rng);
            for (value, b) in child.iter_mut().zip(bounds) {
                *value = b.repair(*value);
            }
        }
        offspring.push(child1);
        offspring.push(child2);
    }
    offspring.truncate(population.len());
    offspring
}

/// Bounded simulated binary crossover (Deb & Agrawal 1995; bounded spread factor as in Deb's NSGA-II
/// v1.1 code). Each variable is recombined with probability 1/2. With `y1 < y2` the parents, the
/// spread factor `β_q` is drawn from the polynomial density of index `η_c` truncated so that children
/// stay within `[y_l, y_u]`:
/// `β = 1 + 2 (y1 − y_l)/(y2 − y1)`, `α = 2 − β^−(η_c+1)`,
/// `β_q = (u α)^(1/(η_c+1))` if `u <= 1/α`, else `(1/(2 − u α))^(1/(η_c+1))`,
/// `c1 = ½[(y1 + y2) − β_q (y2 − y1)]` (and symmetrically for `c2` with `β = 1 + 2 (y_u − y2)/(y2 − y1)`).
fn sbx_crossover(
    parent1: &[f64],
    parent2: &[f64],
    bounds: &[Bounds],
    eta: f64,
    rng: &mut Rng,
) -> (Vec<f64>, Vec<f64>) {
    let mut child1 = parent1.to_vec();
    let mut child2 = parent2.to_vec();
    let exponent = 1.0 / (eta + 1.0);
    for (i, b) in bounds.iter().enumerate() {
        if !rng.bernoulli(0.5) {
            continue;
        }
        if b.is_categorical() {
            // Uniform crossover: each child takes either parent's level with probability 1/2.
            if rng.bernoulli(0.5) {
                std::mem::swap(&mut child1[i], &mut child2[i]);
            }
            continue;
        }
        let (yl, yu) = operator_range(b);
        let (y1, y2) = if parent1[i] < parent2[i] {
            (parent1[i], parent2[i])
        } else {
            (parent2[i], parent1[i])
        };
        if y2 - y1 <= 1e-14 || yu - yl <= 0.0 {
            continue;
        }
        let u = rng.uniform();
        let spread = |beta: f64| {
            let alpha = 2.0 - beta.powf(-(eta + 1.0));
            if u <= 1.0 / alpha {
                (u * alpha).powf(exponent)
            } else {
                (1.0 / (2.0 - u * alpha)).powf(exponent)
            }
        };
        let beta_q1 = spread(1.0 + 2.0 * (y1 - yl) / (y2 - y1));
        let beta_q2 = spread(1.0 + 2.0 * (yu - y2) / (y2 - y1));
        let c1 = (0.5 * ((y1 + y2) - beta_q1 * (y2 - y1))).clamp(yl, yu);
        let c2 = (0.5 * ((y1 + y2) + beta_q2 * (y2 - y1))).clamp(yl, yu);
        if rng.bernoulli(0.5) {
            child1[i] = c2;
            child2[i] = c1;
        } else {
            child1[i] = c1;
            child2[i] = c2;
        }
    }
    (child1, child2)
}

/// Bounded polynomial mutation (Deb & Goyal 1996; bounded form of Deb's NSGA-II v1.1 code). Each
/// variable mutates with probability `probability`: with `δ1 = (y − y_l)/(y_u − y_l)`,
/// `δ2 = (y_u − y)/(y_u − y_l)` and `u` uniform,
/// `δ_q = [2u + (1 − 2u)(1 − δ1)^(η+1)]^(1/(η+1)) − 1` if `u <= ½`, else
/// `δ_q = 1 − [2(1 − u) + 2(u − ½)(1 − δ2)^(η+1)]^(1/(η+1))`, and `y ← y + δ_q (y_u − y_l)`.
/// A categorical variable is reset to another level instead ([`random_reset`]).
fn polynomial_mutation(
    x: &mut [f64],
    bounds: &[Bounds],
    eta: f64,
    probability: f64,
    rng: &mut Rng,
) {
    let exponent = 1.0 / (eta + 1.0);
    for (value, b) in x.iter_mut().zip(bounds) {
        if !rng.bernoulli(probability) {
            continue;
        }
        if b.is_categorical() {
            *value = random_reset(b, *value, rng);
            continue;
        }
        let (yl, yu) = operator_range(b);
        let width = yu - yl;
        if width <= 0.0 {
            continue;
        }
        let y = *value;
        let delta1 = (y - yl) / width;
        let delta2 = (yu - y) / width;
        let u = rng.uniform();
        let delta_q = if u <= 0.5 {
            let xy = 1.0 - delta1;
            let val = 2.0 * u + (1.0 - 2.0 * u) * xy.powf(eta + 1.0);
            val.powf(exponent) - 1.0
        } else {
            let xy = 1.0 - delta2;
            let val = 2.0 * (1.0 - u) + 2.0 * (u - 0.5) * xy.powf(eta + 1.0);
            1.0 - val.powf(exponent)
        };
        let mutated = (y + delta_q * width).clamp(yl, yu);
        *value = if b.is_integer() { integer_step(b, y, mutated, delta_q) } else { mutated };
    }
}

/// A mutated integer variable always moves: when the polynomial perturbation rounds back to the
/// value it started from (with `η_m = 20` it mostly does: a few levels span little of the operator
/// range), it creeps one unit in the perturbation's direction instead, or the other way at a bound
/// (creep mutation for integer genes, Eiben & Smith, *Introduction to Evolutionary Computing*, 2nd
/// ed. 2015, §4.3.1). Without this, a variable with few levels (the number of drums, 1..3) is fixed
/// once the population agrees on it, and the search never returns to the other levels.
fn integer_step(b: &Bounds, start: f64, mutated: f64, direction: f64) -> f64 {
    let before = b.repair(start);
    let after = b.repair(mutated);
    if (after - before).abs() >= 0.5 {
        return after;
    }
    let step = if direction >= 0.0 { 1.0 } else { -1.0 };
    let forward = b.repair(before + step);
    if (forward - before).abs() >= 0.5 { forward } else { b.repair(before - step) }
}

/// A categorical variable's new level: one of the *other* levels, uniformly (random resetting,
/// Eiben & Smith 2015, §4.3.1); a variable with a single level keeps it.
fn random_reset(b: &Bounds, level: f64, rng: &mut Rng) -> f64 {
    let levels = b.levels().unwrap_or(1);
    if levels < 2 {
        return b.repair(level);
    }
    let current = b.repair(level);
    let draw = rng.index(levels - 1) as f64;
    // Skip the current level: draws at or above it move up by one.
    if draw >= current { draw + 1.0 } else { draw }
}

/// The feasible rank-0 individuals, each distinct design once, sorted by objectives.
fn final_front(population: &[Individual]) -> Vec<Individual> {
    let mut front: Vec<Individual> = Vec::new();
    for individual in population.iter().filter(|i| i.rank == 0 && i.evaluation.feasible()) {
        let duplicate = front
            .iter()
            .any(|f| f.x.iter().zip(&individual.x).all(|(a, b)| a.total_cmp(b).is_eq()));
        if !duplicate {
            front.push(individual.clone());
        }
    }
    front.sort_by(|a, b| {
        a.evaluation
            .objectives
            .iter()
            .zip(&b.evaluation.objectives)
            .map(|(p, q)| p.total_cmp(q))
            .find(|o| o.is_ne())
            .unwrap_or(Ordering::Equal)
    });
    front
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::FnProblem;
    use mrbrake_error::Kind as _;

    #[test]
    fn sbx_and_mutation_keep_children_in_bounds() {
        let bounds = vec![Bounds::continuous(0.0, 1.0), Bounds::integer(1.0, 5.0)];
        let mut rng = Rng::new(5);
        for _ in 0..2000 {
            let p1 = vec![rng.uniform(), 1.0 + rng.index(5) as f64];
            let p2 = vec![rng.uniform(), 1.0 + rng.index(5) as f64];
            let (mut c1, mut c2) = sbx_crossover(&p1, &p2, &bounds, 15.0, &mut rng);
            polynomial_mutation(&mut c1, &bounds, 20.0, 1.0, &mut rng);
            polynomial_mutation(&mut c2, &bounds, 20.0, 1.0, &mut rng);
            for c in [&c1, &c2] {
                assert!((0.0..=1.0).contains(&c[0]));
                assert!((0.5..=5.5).contains(&c[1]));
            }
        }
    }

    #[test]
    fn a_mutated_integer_always_changes_and_reaches_every_level() {
        // Three levels (the number of drums): with η_m = 20 the polynomial perturbation alone
        // rounds back to the start most of the time; the creep step moves it every time.
        let bounds = vec![Bounds::integer(1.0, 3.0)];
        let mut rng = Rng::new(3);
        let mut reached = [0usize; 3];
        for start in [1.0, 2.0, 3.0] {
            for _ in 0..300 {
                let mut x = vec![start];
                polynomial_mutation(&mut x, &bounds, 20.0, 1.0, &mut rng);
                let level = bounds[0].repair(x[0]);
                assert!((level - start).abs() >= 1.0 - 1e-12, "{start} -> {}", x[0]);
                reached[level as usize - 1] += 1;
            }
        }
        assert!(reached.iter().all(|&k| k > 100), "{reached:?}");
        // Not mutated (probability 0): unchanged.
        let mut x = vec![2.0];
        polynomial_mutation(&mut x, &bounds, 20.0, 0.0, &mut rng);
        assert!((x[0] - 2.0).abs() < 1e-15);
    }

    #[test]
    fn categorical_variables_are_swapped_or_reset_never_interpolated() {
        // A material choice of four levels beside a continuous variable.
        let bounds = vec![Bounds::categorical(4), Bounds::continuous(0.0, 1.0)];
        let mut rng = Rng::new(17);
        let (mut kept, mut swapped) = (0usize, 0usize);
        for _ in 0..4000 {
            let (c1, c2) = sbx_crossover(&[0.0, 0.2], &[3.0, 0.8], &bounds, 15.0, &mut rng);
            let levels = (c1[0] as i32, c2[0] as i32);
            if levels == (0, 3) {
                kept += 1;
            } else if levels == (3, 0) {
                swapped += 1;
            } else {
                panic!("crossover made level {levels:?} from levels 0 and 3");
            }
        }
        // Swapped with probability 1/4 (recombined 1/2, then a fair coin): 1000 ± 27 (1 σ).
        assert!((swapped as f64 - 1000.0).abs() < 150.0, "kept {kept}, swapped {swapped}");
        let mut reached = [0usize; 4];
        for _ in 0..3000 {
            let mut x = vec![2.0, 0.5];
            polynomial_mutation(&mut x, &bounds, 20.0, 1.0, &mut rng);
            assert!((x[0] - 2.0).abs() >= 1.0, "mutation kept level 2");
            assert!((x[0] - x[0].round()).abs() < 1e-15 && (0.0..=3.0).contains(&x[0]));
            reached[x[0] as usize] += 1;
        }
        // The other three levels, 1000 each (± 26 at 1 σ).
        assert_eq!(reached[2], 0);
        for level in [0, 1, 3] {
            assert!((reached[level] as f64 - 1000.0).abs() < 150.0, "{reached:?}");
        }
        let mut single = vec![0.0, 0.5];
        polynomial_mutation(&mut single, &[Bounds::categorical(1), bounds[1]], 20.0, 1.0, &mut rng);
        assert!(single[0].abs() < 1e-15);
    }

    #[test]
    fn sbx_children_are_symmetric_about_the_parents_mean_inside_the_bounds() {
        // Far from the bounds both spread factors are equal, so c1 + c2 = p1 + p2 (Deb & Agrawal 1995).
        let bounds = vec![Bounds::continuous(-100.0, 100.0)];
        let mut rng = Rng::new(11);
        for _ in 0..200 {
            let (c1, c2) = sbx_crossover(&[0.3], &[0.7], &bounds, 15.0, &mut rng);
            assert!((c1[0] + c2[0] - 1.0).abs() < 1e-6, "{c1:?} {c2:?}");
        }
    }

    #[test]
    fn invalid_options_are_input_errors() {
        let mut problem = FnProblem::new(vec![Bounds::continuous(0.0, 1.0)], 1, |x: &[f64]| {
            Evaluation::new(vec![x[0]], 0.0)
        });
        let bad = [
            Nsga2Options { population: 5, ..Default::default() },
            Nsga2Options { population: 2, ..Default::default() },
            Nsga2Options { crossover_probability: 1.5, ..Default::default() },
            Nsga2Options { mutation_eta: f64::NAN, ..Default::default() },
            Nsga2Options { initial: vec![vec![2.0]], ..Default::default() },
        ];
        for options in &bad {
            let error = run(&mut problem, options, &mut mrbrake_observe::Silent).unwrap_err();
            assert!(error.is_input_error(), "{error}");
        }
        assert_eq!(problem.evaluations(), 0);
    }

    #[test]
    fn survivors_are_best_fronts_first() {
        let individuals: Vec<Individual> = [[3.0, 3.0], [1.0, 2.0], [2.0, 1.0], [4.0, 4.0]]
            .iter()
            .map(|o| Individual {
                x: vec![o[0]],
                evaluation: Evaluation::new(o.to_vec(), 0.0),
                rank: 9,
                crowding: 0.0,
            })
            .collect();
        let survivors = rank_and_select(individuals, 3);
        let ranks: Vec<usize> = survivors.iter().map(|s| s.rank).collect();
        assert_eq!(ranks, vec![0, 0, 1]);
        assert_eq!(survivors[2].x, vec![3.0]);
    }
}
