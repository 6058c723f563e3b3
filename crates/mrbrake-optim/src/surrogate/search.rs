//! The inner optimiser: the batch of designs that maximise the acquisition, one after the other.
//!
//! The acquisition is cheap next to an evaluation but multimodal and flat far from the data, so it
//! is maximised in two stages:
//!
//! 1. **Screening** a candidate pool: `candidates` points of a randomly shifted Sobol' sequence over
//!    the whole space, and as many perturbations of the current front's designs (each feature moved
//!    by a normal step of 20 %, 5 % or 1 % of its range, a categorical reset with probability
//!    1/variables): the front is where improvement is likeliest, and its designs often sit on a
//!    bound that uniform points rarely reach.
//! 2. **Refining** the best few by a compass search on the acquisition (Kolda, Lewis & Torczon 2003,
//!    as in [`crate::pattern_search`]): each continuous feature moved by `±step` (halved when nothing
//!    improves, from 5 % down to 0.1 % of the range), each integer by at least one unit, each
//!    categorical to every other level.
//!
//! Every candidate is decoded to a legal design (integers and levels rounded) before it is scored,
//! and candidates that repeat an evaluated design or an earlier member of the batch score nothing
//! (de-duplication). The batch is built by the *kriging believer* (Ginsbourger, Le Riche & Carraro
//! 2010, "Kriging is well-suited to parallelize optimization", in *Computational Intelligence in
//! Expensive Optimization Problems*, Springer, 131–162): once a member is chosen, the models are
//! conditioned on their own predicted means there (its variance collapses) and, if it is predicted
//! feasible, its predicted objectives join the front, so the next member is sought elsewhere.

use super::acquisition::{Acquirer, standard_normal};
use super::encoding::Encoding;
use super::models::Models;
use crate::rng::Rng;
use crate::sampling::{MAX_SOBOL_DIMENSION, sobol_unit};

/// Candidates refined by the compass search per batch member.
const REFINED: usize = 3;
/// Acquisition evaluations per refinement and variable.
const REFINE_EVALUATIONS_PER_VARIABLE: usize = 20;
/// First and smallest compass step (fraction of a feature's range).
const STEP: (f64, f64) = (0.05, 1e-3);
/// Squared feature distance (per feature) under which two designs count as the same.
const SAME_DESIGN: f64 = 1e-12;

/// One chosen design and its acquisition value when it was chosen.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Proposal {
    pub x: Vec<f64>,
    pub acquisition: f64,
}

/// Chooses `batch` designs (module docs). `evaluated` holds the features of every design already
/// evaluated, `front` those of the current front (perturbed for local candidates).
pub(crate) fn propose_batch(
    models: Models,
    mut acquirer: Acquirer,
    encoding: &Encoding,
    evaluated: &[Vec<f64>],
    front: &[Vec<f64>],
    batch: usize,
    candidates: usize,
    rng: &mut Rng,
) -> Vec<Proposal> {
    let pool = candidate_pool(encoding, front, candidates, rng);
    let mut excluded: Vec<Vec<f64>> = evaluated.to_vec();
    let mut models = models;
    let mut proposals = Vec::with_capacity(batch);
    for _ in 0..batch {
        let score = |points: &[Vec<f64>]| -> Vec<f64> {
            let predictions = models.predict(points);
            points
                .iter()
                .zip(&predictions)
                .map(|(z, p)| if is_repeat(z, &excluded) { -1.0 } else { acquirer.value(p) })
                .collect()
        };
        let values = score(&pool);
        let mut order: Vec<usize> = (0..pool.len()).collect();
        order.sort_by(|&a, &b| values[b].total_cmp(&values[a]).then(a.cmp(&b)));
        let best = order
            .iter()
            .take(REFINED)
            .filter(|&&i| values[i] > 0.0)
            .map(|&i| refine(pool[i].clone(), values[i], &score, encoding))
            .max_by(|a, b| a.1.total_cmp(&b.1));
        let (z, acquisition) = match best {
            Some(found) => found,
            // Nothing to gain anywhere (or every candidate repeats a design): explore instead.
            None => (farthest(&pool, &excluded), 0.0),
        };
        let prediction = models.predict(std::slice::from_ref(&z)).remove(0);
        if prediction.feasibility >= 0.5 {
            acquirer.believe(&prediction.objectives.iter().map(|p| p.mean).collect::<Vec<_>>());
        }
        if let Ok(believed) = models.with_fantasy(&z, &prediction) {
            models = believed;
        }
        excluded.push(z.clone());
        proposals.push(Proposal { x: encoding.decode(&z), acquisition });
    }
    proposals
}

/// Screening candidates: shifted Sobol' points over the space and perturbations of the front
/// (module docs), as legal designs' features.
fn candidate_pool(
    encoding: &Encoding,
    front: &[Vec<f64>],
    count: usize,
    rng: &mut Rng,
) -> Vec<Vec<f64>> {
    let d = encoding.dimension();
    let shift: Vec<f64> = (0..d).map(|_| rng.uniform()).collect();
    let unit: Vec<Vec<f64>> = if d <= MAX_SOBOL_DIMENSION {
        sobol_unit(count, d).unwrap_or_default()
    } else {
        (0..count).map(|_| (0..d).map(|_| rng.uniform()).collect()).collect()
    };
    let mut pool: Vec<Vec<f64>> = unit
        .iter()
        .map(|u| {
            let shifted: Vec<f64> = u.iter().zip(&shift).map(|(a, s)| (a + s).fract()).collect();
            legal(encoding, &unit_to_features(encoding, &shifted))
        })
        .collect();
    if !front.is_empty() {
        for _ in 0..count {
            let centre = &front[rng.index(front.len())];
            let sigma = [0.2, 0.05, 0.01][rng.index(3)];
            let moved: Vec<f64> = (0..d)
                .map(|k| match encoding.levels(k) {
                    Some(levels) if rng.bernoulli(1.0 / d as f64) => rng.index(levels) as f64,
                    Some(_) => centre[k],
                    None => centre[k] + sigma * standard_normal(rng),
                })
                .collect();
            pool.push(legal(encoding, &moved));
        }
    }
    pool
}

/// Unit-cube sample → features: the unit value itself for ordered features, a level for
/// categorical ones (every level an equal share).
fn unit_to_features(encoding: &Encoding, u: &[f64]) -> Vec<f64> {
    u.iter()
        .enumerate()
        .map(|(k, &v)| match encoding.levels(k) {
            Some(levels) => (v * levels as f64).floor().min(levels as f64 - 1.0),
            None => v,
        })
        .collect()
}

/// The features of the legal design nearest to `z`.
fn legal(encoding: &Encoding, z: &[f64]) -> Vec<f64> {
    encoding.encode(&encoding.decode(z))
}

/// Compass search on the acquisition from `start` (module docs); the best point and value.
fn refine(
    start: Vec<f64>,
    value: f64,
    score: &dyn Fn(&[Vec<f64>]) -> Vec<f64>,
    encoding: &Encoding,
) -> (Vec<f64>, f64) {
    let mut budget = REFINE_EVALUATIONS_PER_VARIABLE * encoding.dimension();
    let (mut current, mut best, mut step) = (start, value, STEP.0);
    while budget > 0 {
        let neighbours = neighbours(&current, step, encoding);
        if neighbours.is_empty() {
            break;
        }
        budget = budget.saturating_sub(neighbours.len());
        let values = score(&neighbours);
        let (i, v) = values
            .iter()
            .copied()
            .enumerate()
            .max_by(|a, b| a.1.total_cmp(&b.1).then(b.0.cmp(&a.0)))
            .unwrap_or((0, f64::NEG_INFINITY));
        if v > best {
            (current, best) = (neighbours[i].clone(), v);
        } else if step <= STEP.1 {
            break;
        } else {
            step = (step * 0.5).max(STEP.1);
        }
    }
    (current, best)
}

/// The compass neighbours of `z`: each ordered feature `±step` (an integer at least one unit), each
/// categorical at every other level; legal and distinct from `z`.
fn neighbours(z: &[f64], step: f64, encoding: &Encoding) -> Vec<Vec<f64>> {
    let mut out = Vec::new();
    for k in 0..z.len() {
        let moves: Vec<f64> = match (encoding.levels(k), encoding.integer_step(k)) {
            (Some(levels), _) => (0..levels).map(|l| l as f64).collect(),
            (None, Some(unit)) => vec![z[k] - step.max(unit), z[k] + step.max(unit)],
            (None, None) => vec![z[k] - step, z[k] + step],
        };
        for value in moves {
            let mut moved = z.to_vec();
            moved[k] = value;
            let moved = legal(encoding, &moved);
            if !is_repeat(&moved, std::slice::from_ref(&z.to_vec())) {
                out.push(moved);
            }
        }
    }
    out
}

/// True when `z` is (numerically) one of `others`.
fn is_repeat(z: &[f64], others: &[Vec<f64>]) -> bool {
    let tolerance = SAME_DESIGN * z.len() as f64;
    others.iter().any(|o| o.iter().zip(z).map(|(a, b)| (a - b).powi(2)).sum::<f64>() <= tolerance)
}

/// The pool member farthest from every excluded design (maximin), for iterations where the
/// acquisition is zero everywhere.
fn farthest(pool: &[Vec<f64>], excluded: &[Vec<f64>]) -> Vec<f64> {
    let nearest = |z: &Vec<f64>| {
        excluded
            .iter()
            .map(|o| o.iter().zip(z).map(|(a, b)| (a - b).powi(2)).sum::<f64>())
            .fold(f64::INFINITY, f64::min)
    };
    pool.iter().max_by(|a, b| nearest(a).total_cmp(&nearest(b))).cloned().unwrap_or_default()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::space::Bounds;

    #[test]
    fn neighbours_are_legal_and_move_integers_and_levels() {
        let encoding = Encoding::new(&[
            Bounds::continuous(0.0, 1.0),
            Bounds::integer(1.0, 3.0),
            Bounds::categorical(3),
        ]);
        let z = encoding.encode(&[1.0, 2.0, 1.0]);
        let around = neighbours(&z, 0.01, &encoding);
        // Continuous: only downwards (at the upper bound); integer: both sides; categorical: 2 others.
        assert_eq!(around.len(), 1 + 2 + 2, "{around:?}");
        for n in &around {
            let x = encoding.decode(n);
            assert!(x[1].fract().abs() < 1e-15 && x[2].fract().abs() < 1e-15, "{x:?}");
        }
    }

    #[test]
    fn compass_refinement_climbs_to_the_maximum_of_a_smooth_function() {
        let encoding = Encoding::new(&[Bounds::continuous(0.0, 1.0), Bounds::continuous(0.0, 1.0)]);
        let score = |points: &[Vec<f64>]| -> Vec<f64> {
            points.iter().map(|z| 1.0 - (z[0] - 0.3).powi(2) - (z[1] - 0.71).powi(2)).collect()
        };
        // Budget 40 evaluations for two variables, as in a run.
        let (z, value) = refine(vec![0.4, 0.6], score(&[vec![0.4, 0.6]])[0], &score, &encoding);
        assert!((z[0] - 0.3).abs() < 1e-2 && (z[1] - 0.71).abs() < 1e-2, "{z:?} {value}");
    }
}
