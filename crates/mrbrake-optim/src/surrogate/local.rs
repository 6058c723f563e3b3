//! A small box-constrained quasi-Newton minimiser, for the Gaussian processes' likelihood.
//!
//! Limited-memory BFGS (Nocedal 1980, "Updating quasi-Newton matrices with limited storage",
//! Math. Comp. 35, 773–782; two-loop recursion of Nocedal & Wright, *Numerical Optimization*, 2nd
//! ed. 2006, Algorithm 7.4) in the projected form: each trial point is projected onto the box, and
//! the variables held at a bound by a gradient pointing outwards are left out of the step (the
//! active-set idea of L-BFGS-B, Byrd, Lu, Nocedal & Zhu 1995, without its Cauchy-point search —
//! hyper-parameter fitting has a handful of variables and bounds that only keep the search in a
//! sensible region). Backtracking Armijo line search along the projected path (Nocedal & Wright
//! 2006, Algorithm 3.1, with the sufficient-decrease test on the projected step, Bertsekas 1982),
//! the step cut by quadratic interpolation (Nocedal & Wright 2006, eq. 3.57, safeguarded to
//! `[0.1, 0.5]` of the rejected step). Trial points are evaluated without the gradient, which
//! costs the likelihood three times as much as its value.

use std::collections::VecDeque;

/// The best point a local search found.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct LocalMinimum {
    /// The point.
    pub x: Vec<f64>,
    /// The objective there.
    pub value: f64,
}

/// Curvature pairs kept (the "m" of L-BFGS; 5 to 10 is the usual advice).
const MEMORY: usize = 6;

/// The function minimised: its value at `x` and, when the flag asks, its gradient (else an empty
/// vector); `None` where it is undefined.
pub(crate) type Objective<'a> = dyn FnMut(&[f64], bool) -> Option<(f64, Vec<f64>)> + 'a;

/// Relative decrease of the objective under which the search stops.
const TOLERANCE: f64 = 1e-9;

/// Minimises `objective` over the box `[lower, upper]` from `start`, for at most
/// `max_iterations` quasi-Newton steps. `None` when the objective is undefined at the (projected)
/// start.
pub(crate) fn minimise_in_box(
    objective: &mut Objective<'_>,
    start: &[f64],
    lower: &[f64],
    upper: &[f64],
    max_iterations: usize,
) -> Option<LocalMinimum> {
    let project = |x: &mut [f64]| {
        for ((v, &lo), &hi) in x.iter_mut().zip(lower).zip(upper) {
            *v = v.clamp(lo, hi);
        }
    };
    let mut x = start.to_vec();
    project(&mut x);
    let (mut value, mut gradient) = objective(&x, true).filter(|(f, g)| finite(*f, g))?;
    let mut memory: VecDeque<(Vec<f64>, Vec<f64>)> = VecDeque::new();
    for _ in 0..max_iterations {
        let free: Vec<bool> = (0..x.len())
            .map(|i| {
                let held_low = x[i] <= lower[i] && gradient[i] > 0.0;
                let held_high = x[i] >= upper[i] && gradient[i] < 0.0;
                !(held_low || held_high)
            })
            .collect();
        let masked: Vec<f64> =
            gradient.iter().zip(&free).map(|(&g, &f)| if f { g } else { 0.0 }).collect();
        if norm(&masked) <= 1e-8 {
            break;
        }
        let mut direction = two_loop(&masked, &memory, &free);
        if dot(&direction, &masked) >= 0.0 {
            memory.clear();
            direction = masked.iter().map(|g| -g).collect();
        }
        // The first step (no curvature known yet) moves at most one unit.
        let step = if memory.is_empty() { 1.0 / norm(&direction).max(1.0) } else { 1.0 };
        let Some(Accepted { point: trial, moved, value: f, gradient: g }) =
            line_search(objective, &x, value, &gradient, &direction, step, &project)
        else {
            break;
        };
        let change: Vec<f64> = g.iter().zip(&gradient).map(|(a, b)| a - b).collect();
        if dot(&moved, &change) > 1e-12 {
            memory.push_back((moved, change));
            if memory.len() > MEMORY {
                memory.pop_front();
            }
        }
        let converged = value - f <= TOLERANCE * (1.0 + value.abs());
        (x, value, gradient) = (trial, f, g);
        if converged {
            break;
        }
    }
    Some(LocalMinimum { x, value })
}

/// A point accepted by the line search.
struct Accepted {
    point: Vec<f64>,
    /// `point − x`.
    moved: Vec<f64>,
    value: f64,
    gradient: Vec<f64>,
}

/// A step along `direction` from `x` that decreases the objective enough (Armijo), evaluated
/// without the gradient until accepted.
fn line_search(
    objective: &mut Objective<'_>,
    x: &[f64],
    value: f64,
    gradient: &[f64],
    direction: &[f64],
    mut step: f64,
    project: &dyn Fn(&mut [f64]),
) -> Option<Accepted> {
    for _ in 0..30 {
        let mut trial: Vec<f64> = x.iter().zip(direction).map(|(a, d)| a + step * d).collect();
        project(&mut trial);
        let moved: Vec<f64> = trial.iter().zip(x).map(|(t, a)| t - a).collect();
        let slope = dot(gradient, &moved);
        match objective(&trial, false).map(|(f, _)| f).filter(|f| f.is_finite()) {
            Some(f) if f <= value + 1e-4 * slope => {
                let (value, gradient) = objective(&trial, true).filter(|(f, g)| finite(*f, g))?;
                return Some(Accepted { point: trial, moved, value, gradient });
            }
            // Minimum of the quadratic through value, slope and f, kept within [0.1, 0.5] step.
            Some(f) if slope < 0.0 => {
                let fraction = -slope / (2.0 * (f - value - slope));
                step *= fraction.clamp(0.1, 0.5);
            }
            _ => step *= 0.5,
        }
    }
    None
}

/// The quasi-Newton direction `−H g` by the two-loop recursion (Nocedal & Wright 2006,
/// Algorithm 7.4), restricted to the free variables.
fn two_loop(gradient: &[f64], memory: &VecDeque<(Vec<f64>, Vec<f64>)>, free: &[bool]) -> Vec<f64> {
    let mut q = gradient.to_vec();
    let mut alphas = Vec::with_capacity(memory.len());
    for (s, y) in memory.iter().rev() {
        let alpha = dot(s, &q) / dot(s, y);
        q.iter_mut().zip(y).for_each(|(qi, yi)| *qi -= alpha * yi);
        alphas.push(alpha);
    }
    if let Some((s, y)) = memory.back() {
        let gamma = dot(s, y) / dot(y, y);
        q.iter_mut().for_each(|qi| *qi *= gamma);
    }
    for ((s, y), alpha) in memory.iter().zip(alphas.into_iter().rev()) {
        let beta = dot(y, &q) / dot(s, y);
        q.iter_mut().zip(s).for_each(|(qi, si)| *qi += (alpha - beta) * si);
    }
    q.iter().zip(free).map(|(&v, &f)| if f { -v } else { 0.0 }).collect()
}

fn finite(value: f64, gradient: &[f64]) -> bool {
    value.is_finite() && gradient.iter().all(|g| g.is_finite())
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

fn norm(a: &[f64]) -> f64 {
    dot(a, a).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_the_rosenbrock_minimum_and_stops_at_an_active_bound() {
        let mut rosenbrock = |x: &[f64], _: bool| {
            let (a, b) = (x[0], x[1]);
            let f = (1.0 - a).powi(2) + 100.0 * (b - a * a).powi(2);
            let g = vec![-2.0 * (1.0 - a) - 400.0 * a * (b - a * a), 200.0 * (b - a * a)];
            Some((f, g))
        };
        let free =
            minimise_in_box(&mut rosenbrock, &[-1.2, 1.0], &[-5.0; 2], &[5.0; 2], 500).unwrap();
        assert!((free.x[0] - 1.0).abs() < 1e-4 && (free.x[1] - 1.0).abs() < 1e-4, "{free:?}");
        // With b <= 0.5 the minimum lies on the bound b = 0.5, where 2(1 − a) = 400 a (a² − 0.5):
        // a = 0.70857.
        let bounded =
            minimise_in_box(&mut rosenbrock, &[-1.2, 0.0], &[-5.0, -5.0], &[5.0, 0.5], 500)
                .unwrap();
        assert!((bounded.x[1] - 0.5).abs() < 1e-12, "{bounded:?}");
        assert!((bounded.x[0] - 0.70857).abs() < 1e-3, "{bounded:?}");
        // Undefined at the start: no result.
        let mut undefined = |_: &[f64], _: bool| None;
        assert!(minimise_in_box(&mut undefined, &[0.0], &[-1.0], &[1.0], 10).is_none());
    }
}
