//! The acquisition: expected hypervolume improvement (EHVI) times the probability of feasibility.
//!
//! For independent Gaussian predictions `Y_j ~ N(μ_j, s_j²)` of the objectives (minimised), the
//! current front `P` (feasible, non-dominated, inside the reference box) and the reference `r`:
//!
//! * one objective: the expected improvement `E[(f* − Y)⁺] = (f* − μ) Φ(u) + s φ(u)`,
//!   `u = (f* − μ)/s`, `f* = min(best, r)` (Jones, Schonlau & Welch 1998, eq. (15));
//! * two objectives, exact (the strip decomposition of Emmerich, Deutz & Klinkenberg 2011,
//!   "Hypervolume-based expected improvement: monotonicity properties and exact computation", IEEE
//!   CEC, 2147–2154): with `P` sorted by the first objective, `p_0 = (−∞, r_2)` and
//!   `p_(k+1) = (r_1, −∞)`, the improvement of a point in strip `j` factorises, and
//!   `EHVI = Σ_(j=1)^(k+1) [ψ_1(p_(j,1)) − ψ_1(p_(j−1,1))] ψ_2(p_(j−1,2))` with
//!   `ψ_i(c) = E[(c − Y_i)⁺]` (the expected-improvement formula above, `ψ_i(−∞) = 0`);
//! * three or more objectives: a Monte Carlo mean over a fixed set of standard normal draws (common
//!   random numbers, so candidates are ranked without sampling noise between them), each draw's
//!   improvement being the volume of the box `[y, r]` less the hypervolume of `{max(p, y) : p ∈ P}`
//!   (the exclusive contribution of `y`).
//!
//! The acquisition is `EHVI × P(feasible)` (Schonlau, Welch & Jones 1998); until a feasible design
//! has been evaluated it is `P(feasible)` alone (Gelbart, Snoek & Adams 2014, "Bayesian
//! optimization with unknown constraints", UAI, Sec. 3: find the feasible region first).

use super::gp::Prediction;
use super::models::CandidatePrediction;
use crate::pareto::{dominates, hypervolume};
use crate::rng::Rng;

/// Monte Carlo draws of the EHVI for three or more objectives.
const MONTE_CARLO_DRAWS: usize = 128;

/// The standard normal density.
pub(crate) fn normal_pdf(x: f64) -> f64 {
    (-0.5 * x * x).exp() / (2.0 * std::f64::consts::PI).sqrt()
}

/// The standard normal distribution function, `½ erfc(−x/√2)` (libm's erfc: relative error below
/// 1e-15 even far in the tails, where `1 − erf` would cancel).
pub(crate) fn normal_cdf(x: f64) -> f64 {
    0.5 * libm::erfc(-x / std::f64::consts::SQRT_2)
}

/// `E[(c − Y)⁺]` for `Y ~ N(μ, s²)` (Jones et al. 1998, eq. (15)); `max(c − μ, 0)` when `s = 0`.
pub(crate) fn expected_shortfall_below(c: f64, p: &Prediction) -> f64 {
    if c.is_infinite() && c < 0.0 {
        return 0.0;
    }
    if p.sd <= 0.0 {
        return (c - p.mean).max(0.0);
    }
    let u = (c - p.mean) / p.sd;
    ((c - p.mean) * normal_cdf(u) + p.sd * normal_pdf(u)).max(0.0)
}

/// What the acquisition compares candidates against: the front and the reference point.
#[derive(Debug, Clone)]
pub(crate) struct Acquirer {
    /// Non-dominated objective vectors strictly inside the reference box, sorted by the first
    /// objective; empty when no feasible design is known (the probability-of-feasibility phase).
    front: Vec<Vec<f64>>,
    reference: Vec<f64>,
    /// `false` until a feasible design has been evaluated.
    improving: bool,
    draws: Vec<Vec<f64>>,
}

impl Acquirer {
    /// `front`: objective vectors of the feasible designs (evaluated, plus believed ones of the
    /// batch); `reference`: `None` while no feasible design exists.
    pub fn new(front: &[Vec<f64>], reference: Option<&[f64]>) -> Self {
        let Some(reference) = reference else {
            return Self {
                front: Vec::new(),
                reference: Vec::new(),
                improving: false,
                draws: Vec::new(),
            };
        };
        let mut inside: Vec<Vec<f64>> = front
            .iter()
            .filter(|p| p.iter().zip(reference).all(|(v, r)| v < r))
            .filter(|p| !front.iter().any(|q| dominates(q, p)))
            .cloned()
            .collect();
        inside.sort_by(|a, b| {
            a.iter()
                .zip(b.iter())
                .map(|(x, y)| x.total_cmp(y))
                .find(|o| o.is_ne())
                .unwrap_or(std::cmp::Ordering::Equal)
        });
        inside.dedup_by(|a, b| a.iter().zip(b.iter()).all(|(x, y)| x.total_cmp(y).is_eq()));
        let draws =
            if reference.len() > 2 { standard_normal_draws(reference.len()) } else { Vec::new() };
        Self { front: inside, reference: reference.to_vec(), improving: true, draws }
    }

    /// Adds a believed point (a batch member's predicted objectives) to the front.
    pub fn believe(&mut self, objectives: &[f64]) {
        if self.improving {
            let mut front = self.front.clone();
            front.push(objectives.to_vec());
            *self = Self::new(&front, Some(&self.reference.clone()));
        }
    }

    /// The acquisition value of one candidate (≥ 0, finite).
    pub fn value(&self, prediction: &CandidatePrediction) -> f64 {
        if !self.improving {
            return prediction.feasibility;
        }
        let ehvi = match self.reference.len() {
            1 => {
                let best = self.front.first().map_or(self.reference[0], |p| p[0]);
                expected_shortfall_below(best, &prediction.objectives[0])
            }
            2 => self.ehvi_2d(&prediction.objectives[0], &prediction.objectives[1]),
            _ => self.ehvi_monte_carlo(&prediction.objectives),
        };
        let value = ehvi * prediction.feasibility;
        if value.is_finite() { value.max(0.0) } else { 0.0 }
    }

    /// Exact two-objective EHVI (module docs).
    fn ehvi_2d(&self, first: &Prediction, second: &Prediction) -> f64 {
        let mut total = 0.0;
        let mut previous = (f64::NEG_INFINITY, self.reference[1]);
        for j in 0..=self.front.len() {
            let right = self.front.get(j).map_or(self.reference[0], |p| p[0]);
            let width = expected_shortfall_below(right, first)
                - expected_shortfall_below(previous.0, first);
            total += width * expected_shortfall_below(previous.1, second);
            if let Some(p) = self.front.get(j) {
                previous = (p[0], p[1]);
            }
        }
        total
    }

    /// Monte Carlo EHVI for three or more objectives (module docs).
    fn ehvi_monte_carlo(&self, predictions: &[Prediction]) -> f64 {
        let total: f64 = self
            .draws
            .iter()
            .map(|draw| {
                let y: Vec<f64> =
                    predictions.iter().zip(draw).map(|(p, z)| p.mean + p.sd * z).collect();
                exclusive_hypervolume(&y, &self.front, &self.reference)
            })
            .sum();
        total / self.draws.len() as f64
    }
}

/// The hypervolume `y` adds to `front` below `reference`.
pub(crate) fn exclusive_hypervolume(y: &[f64], front: &[Vec<f64>], reference: &[f64]) -> f64 {
    if y.iter().zip(reference).any(|(v, r)| v >= r || !v.is_finite()) {
        return 0.0;
    }
    let own: f64 = y.iter().zip(reference).map(|(v, r)| r - v).product();
    let clipped: Vec<Vec<f64>> =
        front.iter().map(|p| p.iter().zip(y).map(|(a, b)| a.max(*b)).collect()).collect();
    (own - hypervolume(&clipped, reference)).max(0.0)
}

/// Fixed standard normal draws (Box–Muller on the crate's generator with a fixed seed).
fn standard_normal_draws(dimension: usize) -> Vec<Vec<f64>> {
    let mut rng = Rng::new(0x5EED_E4F1);
    (0..MONTE_CARLO_DRAWS)
        .map(|_| (0..dimension).map(|_| standard_normal(&mut rng)).collect())
        .collect()
}

/// One standard normal draw (Box & Muller 1958).
pub(crate) fn standard_normal(rng: &mut Rng) -> f64 {
    let u1 = 1.0 - rng.uniform(); // in (0, 1]
    let u2 = rng.uniform();
    (-2.0 * u1.ln()).sqrt() * (2.0 * std::f64::consts::PI * u2).cos()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::pareto::hypervolume_2d;

    fn candidate(objectives: &[(f64, f64)], feasibility: f64) -> CandidatePrediction {
        CandidatePrediction {
            objectives: objectives.iter().map(|&(mean, sd)| Prediction { mean, sd }).collect(),
            constraints: Vec::new(),
            classifier: None,
            feasibility,
        }
    }

    fn mean_and_standard_error(samples: &[f64]) -> (f64, f64) {
        let n = samples.len() as f64;
        let mean = samples.iter().sum::<f64>() / n;
        let variance = samples.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0);
        (mean, (variance / n).sqrt())
    }

    #[test]
    fn expected_improvement_matches_monte_carlo() {
        let mut rng = Rng::new(1);
        let p = Prediction { mean: 0.3, sd: 0.5 };
        let n = 400_000;
        let mc: f64 = (0..n)
            .map(|_| (0.1 - (p.mean + p.sd * standard_normal(&mut rng))).max(0.0))
            .sum::<f64>()
            / n as f64;
        let exact = expected_shortfall_below(0.1, &p);
        // Standard error of the mean ≈ 0.3 / sqrt(n) = 5e-4.
        assert!((exact - mc).abs() < 2.5e-3, "{exact} vs {mc}");
        assert!(
            (expected_shortfall_below(1.0, &Prediction { mean: 0.4, sd: 0.0 }) - 0.6).abs() < 1e-15
        );
        assert!(expected_shortfall_below(f64::NEG_INFINITY, &p).abs() < 1e-300);
        // Far in the tail: tiny but positive, never negative or NaN.
        let tail = expected_shortfall_below(-40.0, &Prediction { mean: 0.0, sd: 1.0 });
        assert!((0.0..1e-300).contains(&tail));
    }

    #[test]
    fn two_objective_ehvi_matches_monte_carlo_and_single_objective_is_ei() {
        let front = vec![vec![0.2, 0.8], vec![0.5, 0.4], vec![0.9, 0.1], vec![1.5, 0.0]];
        let reference = [1.2, 1.1];
        let acquirer = Acquirer::new(&front, Some(&reference));
        assert_eq!(acquirer.front.len(), 3, "the point outside the box is dropped");
        let pairs: Vec<(f64, f64)> = front.iter().map(|p| (p[0], p[1])).collect();
        let base = hypervolume_2d(&pairs, (reference[0], reference[1]));
        let mut rng = Rng::new(2);
        for (m1, s1, m2, s2) in [(0.4, 0.2, 0.3, 0.15), (0.1, 0.05, 1.0, 0.3), (1.0, 0.4, 1.0, 0.4)]
        {
            let c = candidate(&[(m1, s1), (m2, s2)], 1.0);
            let exact = acquirer.value(&c);
            let n = 200_000;
            let samples: Vec<f64> = (0..n)
                .map(|_| {
                    let y =
                        (m1 + s1 * standard_normal(&mut rng), m2 + s2 * standard_normal(&mut rng));
                    let mut with = pairs.clone();
                    with.push(y);
                    hypervolume_2d(&with, (reference[0], reference[1])) - base
                })
                .collect();
            let (mc, error) = mean_and_standard_error(&samples);
            assert!((exact - mc).abs() < 4.0 * error, "{exact} vs {mc} ± {error}");
            // The Monte Carlo form used for three or more objectives, on its 128 fixed draws.
            let exclusive = Acquirer { draws: standard_normal_draws(2), ..acquirer.clone() };
            let per_draw: Vec<f64> = exclusive
                .draws
                .iter()
                .map(|z| {
                    let y = [m1 + s1 * z[0], m2 + s2 * z[1]];
                    exclusive_hypervolume(&y, &exclusive.front, &reference)
                })
                .collect();
            let (estimate, error) = mean_and_standard_error(&per_draw);
            assert!((estimate - exclusive.ehvi_monte_carlo(&c.objectives)).abs() < 1e-15);
            assert!((estimate - exact).abs() < 4.0 * error, "{estimate} ± {error} vs {exact}");
        }
        // Feasibility multiplies; the infeasible phase ranks by feasibility alone.
        let c = candidate(&[(0.4, 0.2), (0.3, 0.15)], 0.25);
        assert!(
            (acquirer.value(&c)
                - 0.25 * acquirer.value(&candidate(&[(0.4, 0.2), (0.3, 0.15)], 1.0)))
            .abs()
                < 1e-15
        );
        assert!((Acquirer::new(&[], None).value(&c) - 0.25).abs() < 1e-15);
        // One objective: the expected improvement on the best value.
        let single = Acquirer::new(&[vec![0.5], vec![0.7]], Some(&[2.0]));
        let c = candidate(&[(0.6, 0.3)], 1.0);
        assert!((single.value(&c) - expected_shortfall_below(0.5, &c.objectives[0])).abs() < 1e-15);
    }

    #[test]
    fn exclusive_hypervolume_in_three_objectives() {
        let front = vec![vec![0.0, 1.0, 1.0], vec![1.0, 0.0, 2.0]];
        let reference = [3.0, 3.0, 3.0];
        let base = hypervolume(&front, &reference);
        for y in
            [vec![0.5, 0.5, 0.5], vec![2.0, 2.0, 2.0], vec![0.0, 0.0, 2.9], vec![4.0, 0.0, 0.0]]
        {
            let mut with = front.clone();
            with.push(y.clone());
            let expected = hypervolume(&with, &reference) - base;
            assert!(
                (exclusive_hypervolume(&y, &front, &reference) - expected).abs() < 1e-12,
                "{y:?}"
            );
        }
    }
}
