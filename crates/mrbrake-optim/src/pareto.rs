//! Evaluations, constrained Pareto dominance, non-dominated sorting, crowding distance and the
//! hypervolume (exact, any number of objectives).
//!
//! All objectives are **minimised** (negate a quantity to maximise it). Constraints enter through one
//! number, the total normalised violation (0 for a feasible design), and are handled by the
//! constrained-domination rule of Deb, Pratap, Agarwal & Meyarivan (2002), "A fast and elitist
//! multiobjective genetic algorithm: NSGA-II", IEEE Trans. Evol. Comput. 6(2), 182–197, Sec. VI,
//! which in turn follows Deb (2000), "An efficient constraint handling method for genetic algorithms",
//! Comput. Methods Appl. Mech. Eng. 186, 311–338.

use std::cmp::Ordering;

/// The outcome of evaluating one design.
#[derive(Debug, Clone, PartialEq)]
pub struct Evaluation {
    /// Objective values, all minimised.
    pub objectives: Vec<f64>,
    /// 0 when the design is feasible; otherwise the total normalised constraint violation (> 0), or
    /// `f64::INFINITY` when the design could not be evaluated at all (invalid geometry, solver
    /// failure). Never NaN or negative.
    pub violation: f64,
    /// Optional: each constraint's signed, normalised value `g_j / scale_j`, satisfied when `<= 0`
    /// (so `violation` is usually `Σ_j max(0, g_j / scale_j)`). Empty when the evaluator reports
    /// only the total violation, and for a failed design. Dominance and sorting never read it; the
    /// surrogate optimiser models each constraint from it ([`crate::surrogate`]), which learns far
    /// more from a margin than from a violation that is 0 everywhere in the feasible region.
    pub constraints: Vec<f64>,
}

impl Evaluation {
    /// An evaluation with the given objectives and violation (no per-constraint values).
    pub fn new(objectives: Vec<f64>, violation: f64) -> Self {
        Self { objectives, violation, constraints: Vec::new() }
    }

    /// The same evaluation carrying each constraint's signed normalised value (see
    /// [`Evaluation::constraints`]).
    ///
    /// ```
    /// use mrbrake_optim::pareto::{Evaluation, normalised_violation};
    /// // torque 2.7 Nm against a 3 Nm minimum; diameter 78 mm against an 80 mm maximum.
    /// let g = [(3.0 - 2.7) / 3.0, (0.078 - 0.080) / 0.080];
    /// let e = Evaluation::new(vec![0.2], normalised_violation(&[(g[0], 1.0), (g[1], 1.0)]))
    ///     .with_constraints(g.to_vec());
    /// assert!(!e.feasible() && e.constraints.len() == 2);
    /// ```
    pub fn with_constraints(mut self, constraints: Vec<f64>) -> Self {
        self.constraints = constraints;
        self
    }

    /// A design that could not be evaluated: infinite violation and `objectives` infinite
    /// objective values, so it loses every comparison with an evaluated design.
    pub fn failed(objectives: usize) -> Self {
        Self::new(vec![f64::INFINITY; objectives], f64::INFINITY)
    }

    /// True when the design satisfies every constraint (`violation <= 0`).
    pub fn feasible(&self) -> bool {
        self.violation <= 0.0
    }
}

/// The total normalised violation of constraints written as `g_j(x) <= 0`, each divided by a
/// positive scale: `Σ_j max(0, g_j / scale_j)` (Deb 2000, eq. (3): constraints are normalised so
/// that no single one dominates the sum).
///
/// ```
/// use mrbrake_optim::pareto::normalised_violation;
/// // torque 2.7 Nm against a 3 Nm target (g = 3 - T <= 0, scale 3 Nm); diameter 78 mm <= 80 mm.
/// let v = normalised_violation(&[(3.0 - 2.7, 3.0), (0.078 - 0.080, 0.080)]);
/// assert!((v - 0.1).abs() < 1e-12);
/// ```
pub fn normalised_violation(constraints: &[(f64, f64)]) -> f64 {
    constraints.iter().map(|&(g, scale)| (g / scale).max(0.0)).sum()
}

/// Pareto dominance between objective vectors (minimisation): `a` is no worse than `b` in every
/// objective and strictly better in at least one.
pub fn dominates(a: &[f64], b: &[f64]) -> bool {
    let mut strictly_better = false;
    for (&ai, &bi) in a.iter().zip(b) {
        if ai > bi || ai.is_nan() || bi.is_nan() {
            return false;
        }
        if ai < bi {
            strictly_better = true;
        }
    }
    strictly_better
}

/// Constrained domination (Deb et al. 2002, Definition 1): `a` dominates `b` if `a` is feasible and
/// `b` is not; or both are infeasible and `a` has the smaller violation; or both are feasible and `a`
/// Pareto-dominates `b`.
pub fn constrained_dominates(a: &Evaluation, b: &Evaluation) -> bool {
    match (a.feasible(), b.feasible()) {
        (true, false) => true,
        (false, true) => false,
        (false, false) => a.violation < b.violation,
        (true, true) => dominates(&a.objectives, &b.objectives),
    }
}

/// Deb's feasibility rules for a single objective (Deb 2000, Sec. 3): a feasible design beats an
/// infeasible one; of two infeasible ones the smaller violation wins; of two feasible ones the
/// smaller first objective wins. `Less` means `a` is better.
pub fn feasibility_order(a: &Evaluation, b: &Evaluation) -> Ordering {
    match (a.feasible(), b.feasible()) {
        (true, false) => Ordering::Less,
        (false, true) => Ordering::Greater,
        (false, false) => a.violation.total_cmp(&b.violation),
        (true, true) => {
            let fa = a.objectives.first().copied().unwrap_or(f64::INFINITY);
            let fb = b.objectives.first().copied().unwrap_or(f64::INFINITY);
            fa.total_cmp(&fb)
        }
    }
}

/// Fronts of the constrained-domination order, best first: indices into `evals` (fast non-dominated
/// sort, Deb et al. 2002, Sec. III-A, O(M N²)). Front 0 holds the designs no other design dominates;
/// front k those dominated only by designs of earlier fronts. Indices within a front are ascending.
pub fn non_dominated_sort(evals: &[Evaluation]) -> Vec<Vec<usize>> {
    let n = evals.len();
    let mut dominated_by_me: Vec<Vec<usize>> = vec![Vec::new(); n];
    let mut domination_count = vec![0usize; n];
    for p in 0..n {
        for q in (p + 1)..n {
            if constrained_dominates(&evals[p], &evals[q]) {
                dominated_by_me[p].push(q);
                domination_count[q] += 1;
            } else if constrained_dominates(&evals[q], &evals[p]) {
                dominated_by_me[q].push(p);
                domination_count[p] += 1;
            }
        }
    }
    let mut fronts = Vec::new();
    let mut current: Vec<usize> = (0..n).filter(|&p| domination_count[p] == 0).collect();
    while !current.is_empty() {
        let mut next = Vec::new();
        for &p in &current {
            for &q in &dominated_by_me[p] {
                domination_count[q] -= 1;
                if domination_count[q] == 0 {
                    next.push(q);
                }
            }
        }
        next.sort_unstable();
        fronts.push(current);
        current = next;
    }
    fronts
}

/// Crowding distance of each member of `front` (Deb et al. 2002, Sec. III-B): for each objective the
/// members are sorted, the two extremes get infinity and each interior member adds the normalised gap
/// `(f_(i+1) − f_(i−1)) / (f_max − f_min)` between its neighbours. Objectives whose range over the
/// front is zero or not finite (failed designs) add nothing. Returned in the order of `front`.
pub fn crowding_distance(evals: &[Evaluation], front: &[usize]) -> Vec<f64> {
    let size = front.len();
    let mut distance = vec![0.0; size];
    if size <= 2 {
        return vec![f64::INFINITY; size];
    }
    let objectives = front.iter().map(|&i| evals[i].objectives.len()).min().unwrap_or(0);
    let mut order: Vec<usize> = (0..size).collect();
    for m in 0..objectives {
        let value = |k: usize| evals[front[k]].objectives[m];
        order.sort_by(|&a, &b| value(a).total_cmp(&value(b)).then(a.cmp(&b)));
        distance[order[0]] = f64::INFINITY;
        distance[order[size - 1]] = f64::INFINITY;
        let range = value(order[size - 1]) - value(order[0]);
        if !(range.is_finite() && range > 0.0) {
            continue;
        }
        for k in 1..(size - 1) {
            distance[order[k]] += (value(order[k + 1]) - value(order[k - 1])) / range;
        }
    }
    distance
}

/// Indices of the feasible, non-dominated evaluations: the Pareto front of `evals`.
///
/// Evaluations with a NaN objective are ignored; of several with identical objective vectors only
/// the first (lowest index) is kept. Sorted by the first objective, then the following ones.
pub fn pareto_front(evals: &[Evaluation]) -> Vec<usize> {
    let candidates: Vec<usize> = (0..evals.len())
        .filter(|&i| evals[i].feasible() && !evals[i].objectives.iter().any(|v| v.is_nan()))
        .collect();
    let mut front: Vec<usize> = Vec::new();
    for &i in &candidates {
        let dominated =
            candidates.iter().any(|&j| dominates(&evals[j].objectives, &evals[i].objectives));
        let duplicate =
            front.iter().any(|&j| same_objectives(&evals[j].objectives, &evals[i].objectives));
        if !dominated && !duplicate {
            front.push(i);
        }
    }
    front.sort_by(|&a, &b| {
        lexicographic(&evals[a].objectives, &evals[b].objectives).then(a.cmp(&b))
    });
    front
}

/// True when both vectors hold bit-for-bit the same values (total order equality).
fn same_objectives(a: &[f64], b: &[f64]) -> bool {
    a.len() == b.len() && a.iter().zip(b).all(|(x, y)| x.total_cmp(y).is_eq())
}

/// Lexicographic total order of objective vectors.
fn lexicographic(a: &[f64], b: &[f64]) -> Ordering {
    a.iter()
        .zip(b)
        .map(|(x, y)| x.total_cmp(y))
        .find(|o| o.is_ne())
        .unwrap_or_else(|| a.len().cmp(&b.len()))
}

/// The area dominated by `points` (two minimised objectives) and bounded by `reference`
/// (the hypervolume indicator of Zitzler & Thiele 1998, "Multiobjective optimization using
/// evolutionary algorithms — a comparative case study", PPSN V; computed exactly by a sweep over the
/// first objective). Points not strictly better than the reference in both objectives, or not finite,
/// contribute nothing.
///
/// ```
/// use mrbrake_optim::pareto::hypervolume_2d;
/// let hv = hypervolume_2d(&[(0.0, 1.0), (1.0, 0.0)], (2.0, 2.0));
/// assert!((hv - 3.0).abs() < 1e-12);
/// ```
pub fn hypervolume_2d(points: &[(f64, f64)], reference: (f64, f64)) -> f64 {
    let (rx, ry) = reference;
    let mut inside: Vec<(f64, f64)> = points
        .iter()
        .copied()
        .filter(|&(x, y)| x.is_finite() && y.is_finite() && x < rx && y < ry)
        .collect();
    inside.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.total_cmp(&b.1)));
    let mut volume = 0.0;
    let mut lowest_y = ry;
    for (x, y) in inside {
        if y < lowest_y {
            volume += (rx - x) * (lowest_y - y);
            lowest_y = y;
        }
    }
    volume
}

/// The hypervolume indicator (Zitzler & Thiele 1998) of `points` (minimised objective vectors)
/// bounded by `reference`: the volume of the region each point dominates inside the box below the
/// reference, for any number of objectives.
///
/// Computed exactly: one objective is the distance from the best value to the reference, two are
/// [`hypervolume_2d`], and more are sliced along the last objective (the "hypervolume by slicing
/// objectives" algorithm of While, Hingston, Barone & Huband 2006, "A faster algorithm for
/// calculating hypervolume", IEEE Trans. Evol. Comput. 10(1), 29–38): between consecutive values
/// of the last objective the slab's volume is its thickness times the (m − 1)-objective
/// hypervolume of the points at or below it. Cost `O(n^(m−1) log n)`, ample for fronts of a few
/// hundred designs in three or four objectives.
///
/// Points with a non-finite value, a length different from the reference's, or not strictly better
/// than the reference in every objective contribute nothing.
///
/// ```
/// use mrbrake_optim::pareto::hypervolume;
/// // Two cubes of side 1 overlapping in a 1 x 1 x 0.5 slab, below reference (2, 2, 2).
/// let hv = hypervolume(&[vec![1.0, 1.0, 1.0], vec![1.0, 1.0, 1.5]], &[2.0, 2.0, 2.0]);
/// assert!((hv - 1.0).abs() < 1e-12);
/// ```
pub fn hypervolume(points: &[Vec<f64>], reference: &[f64]) -> f64 {
    let inside: Vec<&[f64]> = points
        .iter()
        .map(Vec::as_slice)
        .filter(|p| {
            p.len() == reference.len()
                && p.iter().zip(reference).all(|(&v, &r)| v.is_finite() && v < r)
        })
        .collect();
    sliced_hypervolume(inside, reference)
}

/// [`hypervolume`] of points already known to lie inside the reference box.
fn sliced_hypervolume(mut points: Vec<&[f64]>, reference: &[f64]) -> f64 {
    let m = reference.len();
    if points.is_empty() || m == 0 {
        return 0.0;
    }
    match m {
        1 => reference[0] - points.iter().map(|p| p[0]).fold(f64::INFINITY, f64::min),
        2 => {
            let pairs: Vec<(f64, f64)> = points.iter().map(|p| (p[0], p[1])).collect();
            hypervolume_2d(&pairs, (reference[0], reference[1]))
        }
        _ => {
            points.sort_by(|a, b| a[m - 1].total_cmp(&b[m - 1]));
            let mut volume = 0.0;
            for k in 0..points.len() {
                let top = points.get(k + 1).map_or(reference[m - 1], |p| p[m - 1]);
                let thickness = top - points[k][m - 1];
                if thickness > 0.0 {
                    let slab: Vec<&[f64]> = points[..=k].iter().map(|p| &p[..m - 1]).collect();
                    volume += thickness * sliced_hypervolume(slab, &reference[..m - 1]);
                }
            }
            volume
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn feasible(objectives: &[f64]) -> Evaluation {
        Evaluation::new(objectives.to_vec(), 0.0)
    }

    #[test]
    fn constrained_domination_rules() {
        let good = feasible(&[1.0, 1.0]);
        let worse = feasible(&[2.0, 1.0]);
        let other = feasible(&[0.5, 3.0]);
        let slightly_infeasible = Evaluation::new(vec![0.0, 0.0], 0.1);
        let very_infeasible = Evaluation::new(vec![0.0, 0.0], 2.0);
        let failed = Evaluation::failed(2);
        assert!(constrained_dominates(&good, &worse));
        assert!(!constrained_dominates(&worse, &good));
        assert!(!constrained_dominates(&good, &other));
        assert!(!constrained_dominates(&other, &good));
        assert!(constrained_dominates(&worse, &slightly_infeasible));
        assert!(constrained_dominates(&slightly_infeasible, &very_infeasible));
        assert!(constrained_dominates(&very_infeasible, &failed));
        assert!(!constrained_dominates(&failed, &Evaluation::failed(2)));
        assert!(!constrained_dominates(&good, &good.clone()));
    }

    #[test]
    fn sort_and_crowding_on_a_small_example() {
        let evals = vec![
            feasible(&[1.0, 4.0]),                // front 0
            feasible(&[2.0, 2.0]),                // front 0
            feasible(&[4.0, 1.0]),                // front 0
            feasible(&[3.0, 3.0]),                // dominated by 1
            feasible(&[4.0, 4.0]),                // dominated by 3
            Evaluation::new(vec![0.0, 0.0], 1.0), // infeasible
        ];
        let fronts = non_dominated_sort(&evals);
        assert_eq!(fronts, vec![vec![0, 1, 2], vec![3], vec![4], vec![5]]);
        let d = crowding_distance(&evals, &fronts[0]);
        assert!(d[0].is_infinite() && d[2].is_infinite());
        // Interior point: (4 - 1)/3 + (4 - 1)/3 = 2.
        assert!((d[1] - 2.0).abs() < 1e-12);
    }

    #[test]
    fn pareto_front_filters_infeasible_and_duplicates() {
        let evals = vec![
            feasible(&[3.0, 1.0]),
            feasible(&[1.0, 3.0]),
            feasible(&[1.0, 3.0]),
            feasible(&[2.0, 2.0]),
            feasible(&[2.5, 2.5]),
            Evaluation::new(vec![0.0, 0.0], 0.5),
            feasible(&[f64::NAN, 0.0]),
        ];
        assert_eq!(pareto_front(&evals), vec![1, 3, 0]);
    }

    #[test]
    fn hypervolume_of_a_staircase() {
        let pts = [(1.0, 3.0), (2.0, 2.0), (3.0, 1.0), (2.5, 2.5), (5.0, 0.0)];
        // Reference (4, 4): columns [1,2]x[3,4] + [2,3]x[2,4] + [3,4]x[1,4] = 1 + 2 + 3.
        assert!((hypervolume_2d(&pts, (4.0, 4.0)) - 6.0).abs() < 1e-12);
        assert!(hypervolume_2d(&[], (1.0, 1.0)).abs() < 1e-300);
    }

    #[test]
    fn hypervolume_agrees_with_the_2d_sweep_and_with_boxes_in_3d() {
        let pts = [(1.0, 3.0), (2.0, 2.0), (3.0, 1.0), (2.5, 2.5)];
        let as_vectors: Vec<Vec<f64>> = pts.iter().map(|&(a, b)| vec![a, b]).collect();
        assert!((hypervolume(&as_vectors, &[4.0, 4.0]) - 6.0).abs() < 1e-12);
        // One objective: distance from the best to the reference.
        assert!((hypervolume(&[vec![3.0], vec![1.0]], &[4.0]) - 3.0).abs() < 1e-12);
        // Three objectives: union of [1,3]x[0,3]x[0,3]... as inclusion-exclusion of two boxes.
        // a = (0, 1, 1) dominates [0,3]x[1,3]x[1,3] = 3*2*2 = 12; b = (1, 0, 2): 2*3*1 = 6;
        // overlap [1,3]x[1,3]x[2,3] = 2*2*1 = 4; union 14.
        let three = [vec![0.0, 1.0, 1.0], vec![1.0, 0.0, 2.0]];
        assert!((hypervolume(&three, &[3.0, 3.0, 3.0]) - 14.0).abs() < 1e-12);
        // A point outside the reference box, a NaN and a wrong length add nothing.
        let mut noisy = three.to_vec();
        noisy.extend([vec![0.0, 0.0, 3.5], vec![f64::NAN, 0.0, 0.0], vec![0.0, 0.0]]);
        assert!((hypervolume(&noisy, &[3.0, 3.0, 3.0]) - 14.0).abs() < 1e-12);
        assert!(hypervolume(&[], &[1.0, 1.0, 1.0]).abs() < 1e-300);
    }

    #[test]
    fn feasibility_order_follows_deb() {
        let a = feasible(&[2.0]);
        let b = feasible(&[1.0]);
        let c = Evaluation::new(vec![0.0], 0.1);
        assert_eq!(feasibility_order(&b, &a), Ordering::Less);
        assert_eq!(feasibility_order(&a, &c), Ordering::Less);
        assert_eq!(feasibility_order(&c, &Evaluation::failed(1)), Ordering::Less);
    }

    #[test]
    fn normalised_violation_sums_positive_parts() {
        assert!(normalised_violation(&[(-1.0, 1.0), (-2.0, 5.0)]).abs() < 1e-300);
        assert!((normalised_violation(&[(1.0, 2.0), (3.0, 3.0), (-5.0, 1.0)]) - 1.5).abs() < 1e-12);
    }
}
