//! Property tests of the Pareto utilities: fronts of the fast non-dominated sort (Deb et al. 2002)
//! and the hypervolume (2-D sweep, and the slicing algorithm in 3 and 4 objectives against a
//! count of unit cells).

use mrbrake_optim::pareto::{
    Evaluation, constrained_dominates, crowding_distance, dominates, hypervolume, hypervolume_2d,
    non_dominated_sort, pareto_front,
};
use proptest::prelude::*;

fn evaluation() -> impl Strategy<Value = Evaluation> {
    // Small integer-valued objectives make ties and duplicates frequent; a quarter infeasible.
    (
        proptest::collection::vec(0i32..6, 2..=3),
        prop_oneof![3 => Just(0.0), 1 => (1i32..4).prop_map(f64::from), 1 => Just(f64::INFINITY)],
    )
        .prop_map(|(o, v)| Evaluation::new(o.into_iter().map(f64::from).collect(), v))
}

fn evaluations() -> impl Strategy<Value = Vec<Evaluation>> {
    (2usize..=3).prop_flat_map(|m| {
        proptest::collection::vec(evaluation(), 0..40).prop_map(move |mut v| {
            for e in &mut v {
                e.objectives.resize(m, 0.0);
            }
            v
        })
    })
}

proptest! {
    #[test]
    fn fronts_partition_the_set_and_respect_domination(evals in evaluations()) {
        let fronts = non_dominated_sort(&evals);
        let mut all: Vec<usize> = fronts.iter().flatten().copied().collect();
        all.sort_unstable();
        prop_assert_eq!(all, (0..evals.len()).collect::<Vec<_>>());
        for (k, front) in fronts.iter().enumerate() {
            prop_assert!(!front.is_empty());
            for &p in front {
                // No point of front k is dominated by a point in front k or a later one...
                for later in &fronts[k..] {
                    for &q in later {
                        prop_assert!(!constrained_dominates(&evals[q], &evals[p]), "{} dominates {}", q, p);
                    }
                }
                // ...and every point beyond front 0 is dominated by some point of the previous front.
                if k > 0 {
                    prop_assert!(fronts[k - 1].iter().any(|&q| constrained_dominates(&evals[q], &evals[p])));
                }
            }
        }
    }

    #[test]
    fn pareto_front_is_feasible_non_dominated_and_complete(evals in evaluations()) {
        let front = pareto_front(&evals);
        for &i in &front {
            prop_assert!(evals[i].feasible());
            for e in &evals {
                prop_assert!(!(e.feasible() && dominates(&e.objectives, &evals[i].objectives)));
            }
        }
        // Every feasible non-dominated objective vector is represented exactly once.
        for (i, e) in evals.iter().enumerate() {
            let non_dominated = e.feasible()
                && !evals.iter().any(|o| o.feasible() && dominates(&o.objectives, &e.objectives));
            if non_dominated {
                let represented = front.iter().filter(|&&j| evals[j].objectives == e.objectives).count();
                prop_assert_eq!(represented, 1, "evaluation {}", i);
            } else {
                prop_assert!(!front.contains(&i), "evaluation {}", i);
            }
        }
        for w in front.windows(2) {
            prop_assert!(evals[w[0]].objectives[0] <= evals[w[1]].objectives[0]);
        }
    }

    #[test]
    fn crowding_is_infinite_at_extremes_and_non_negative(evals in evaluations()) {
        for front in non_dominated_sort(&evals) {
            let d = crowding_distance(&evals, &front);
            prop_assert_eq!(d.len(), front.len());
            prop_assert!(d.iter().all(|&v| v >= 0.0));
            if front.len() <= 2 {
                prop_assert!(d.iter().all(|v| v.is_infinite()));
            } else {
                prop_assert!(d.iter().filter(|v| v.is_infinite()).count() >= 2);
            }
        }
    }

    #[test]
    fn hypervolume_is_monotone_and_ignores_dominated_points(
        points in proptest::collection::vec((0.0f64..10.0, 0.0f64..10.0), 1..30),
        extra in (0.0f64..10.0, 0.0f64..10.0),
    ) {
        let reference = (10.0, 10.0);
        let hv = hypervolume_2d(&points, reference);
        let mut more = points.clone();
        more.push(extra);
        let hv_more = hypervolume_2d(&more, reference);
        prop_assert!(hv_more >= hv - 1e-12);
        prop_assert!(hv <= 100.0 + 1e-12);
        // A point dominated by an existing one changes nothing.
        let (x, y) = points[0];
        let mut dominated = points.clone();
        dominated.push(((x + 10.0) / 2.0, (y + 10.0) / 2.0));
        prop_assert!((hypervolume_2d(&dominated, reference) - hv).abs() < 1e-9);
        // Brute-force check on a fine grid of cell centres.
        let n = 200;
        let cell = 10.0 / n as f64;
        let mut covered = 0usize;
        for i in 0..n {
            for j in 0..n {
                let cx = (i as f64 + 0.5) * cell;
                let cy = (j as f64 + 0.5) * cell;
                if points.iter().any(|&(px, py)| px <= cx && py <= cy) {
                    covered += 1;
                }
            }
        }
        let grid = covered as f64 * cell * cell;
        // Each staircase edge can misclassify at most one row/column of cells.
        prop_assert!((grid - hv).abs() <= 2.0 * 10.0 * cell * points.len() as f64 + 1e-9);
    }

    #[test]
    fn hypervolume_in_three_and_four_objectives_counts_dominated_unit_cells(
        m in 3usize..=4,
        raw in proptest::collection::vec(proptest::collection::vec(0i32..5, 4), 0..12),
    ) {
        // Integer points below reference (5, ..., 5): the dominated region is a union of unit
        // cells, each dominated exactly when some point is <= its lower corner.
        let points: Vec<Vec<f64>> =
            raw.iter().map(|p| p[..m].iter().map(|&v| f64::from(v)).collect()).collect();
        let reference = vec![5.0; m];
        let mut cells = 0usize;
        for index in 0..5usize.pow(m as u32) {
            let corner: Vec<f64> = (0..m).map(|k| ((index / 5usize.pow(k as u32)) % 5) as f64).collect();
            if points.iter().any(|p| p.iter().zip(&corner).all(|(a, c)| a <= c)) {
                cells += 1;
            }
        }
        prop_assert!((hypervolume(&points, &reference) - cells as f64).abs() < 1e-9);
    }
}
