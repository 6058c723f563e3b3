//! Validation of the sampling plans: Sobol' points against the published sequence, the
//! (0, m, 1)-net property of every one-dimensional projection, and the Latin hypercube
//! stratification property (McKay, Beckman & Conover 1979).

use mrbrake_optim::rng::Rng;
use mrbrake_optim::sampling::{
    MAX_SOBOL_DIMENSION, full_factorial, latin_hypercube, sobol, sobol_unit,
};
use mrbrake_optim::space::Bounds;
use proptest::prelude::*;

#[test]
fn sobol_first_points_in_two_dimensions_match_the_published_sequence() {
    // Joe & Kuo's generator (and e.g. SciPy's unscrambled `qmc.Sobol(d=2)`) after the zero point.
    let expected = [
        [0.5, 0.5],
        [0.75, 0.25],
        [0.25, 0.75],
        [0.375, 0.375],
        [0.875, 0.875],
        [0.625, 0.125],
        [0.125, 0.625],
    ];
    let points = sobol_unit(expected.len(), 2).unwrap();
    for (p, e) in points.iter().zip(&expected) {
        approx::assert_abs_diff_eq!(p.as_slice(), e.as_slice(), epsilon = 1e-15);
    }
}

#[test]
fn sobol_third_dimension_uses_the_joe_kuo_recurrence() {
    // Dimension 3: s = 2, a = 1, m = (1, 3) -> V1 = 1/2, V2 = 3/4, V3 = V1 ^ V1/4 ^ V2 = 3/8.
    // Gray-code points: 1/2, 1/2 ^ 3/4 = 1/4, 1/4 ^ 1/2 = 3/4, 3/4 ^ 3/8 = 5/8.
    let points = sobol_unit(4, 3).unwrap();
    let third: Vec<f64> = points.iter().map(|p| p[2]).collect();
    approx::assert_abs_diff_eq!(
        third.as_slice(),
        [0.5, 0.25, 0.75, 0.625].as_slice(),
        epsilon = 1e-15
    );
}

#[test]
fn every_sobol_coordinate_is_a_0_m_1_net() {
    // With the zero point, the first 2^m points put exactly one point in each interval
    // [k/2^m, (k+1)/2^m) of every coordinate: true of any valid direction numbers, so it catches
    // a mis-typed table row or a broken recurrence.
    let m = 10;
    let n = 1usize << m;
    let points = sobol_unit(n - 1, MAX_SOBOL_DIMENSION).unwrap();
    for d in 0..MAX_SOBOL_DIMENSION {
        let mut seen = vec![false; n];
        seen[0] = true; // the skipped zero point
        for p in &points {
            let k = (p[d] * n as f64) as usize;
            assert!(!seen[k], "dimension {d}: interval {k} hit twice");
            seen[k] = true;
        }
    }
}

#[test]
fn every_two_dimensional_sobol_projection_is_balanced_over_quadrants() {
    // Any pair of coordinates: the first 2^m points (zero included) put 2^(m-2) points in each
    // quadrant of the unit square (a (t, m, 2)-net with t <= m - 2).
    let n = 256;
    let points = sobol_unit(n - 1, MAX_SOBOL_DIMENSION).unwrap();
    for a in 0..MAX_SOBOL_DIMENSION {
        for b in (a + 1)..MAX_SOBOL_DIMENSION {
            let mut counts = [1usize, 0, 0, 0]; // the zero point sits in quadrant 0
            for p in &points {
                let q = usize::from(p[a] >= 0.5) + 2 * usize::from(p[b] >= 0.5);
                counts[q] += 1;
            }
            assert_eq!(counts, [64, 64, 64, 64], "dimensions {a}, {b}");
        }
    }
}

#[test]
fn sobol_is_scaled_to_bounds_and_integers_are_repaired() {
    let bounds = [Bounds::continuous(-2.0, 2.0), Bounds::integer(1.0, 4.0)];
    let plan = sobol(63, &bounds).unwrap();
    assert_eq!(plan.len(), 63);
    approx::assert_abs_diff_eq!(plan[0][0], 0.0, epsilon = 1e-15);
    let mut counts = [0usize; 4];
    for p in &plan {
        assert!((-2.0..=2.0).contains(&p[0]));
        assert!((p[1] - p[1].round()).abs() < 1e-300);
        counts[(p[1] - 1.0) as usize] += 1;
    }
    // 63 real points + the skipped zero (which would map to 1): 15 ones, 16 of the rest.
    assert_eq!(counts, [15, 16, 16, 16]);
    assert!(sobol(4, &vec![Bounds::continuous(0.0, 1.0); MAX_SOBOL_DIMENSION + 1]).is_err());
}

#[test]
fn full_factorial_first_variable_varies_slowest() {
    let plan = full_factorial(&[vec![1.0, 2.0, 3.0], vec![0.5, 0.75]]);
    let expected: Vec<Vec<f64>> = vec![
        vec![1.0, 0.5],
        vec![1.0, 0.75],
        vec![2.0, 0.5],
        vec![2.0, 0.75],
        vec![3.0, 0.5],
        vec![3.0, 0.75],
    ];
    assert_eq!(plan, expected);
}

proptest! {
    #[test]
    fn latin_hypercube_has_one_point_per_stratum(n in 1usize..60, dims in 1usize..6, seed in any::<u64>()) {
        let bounds = vec![Bounds::continuous(0.0, 1.0); dims];
        let plan = latin_hypercube(n, &bounds, &mut Rng::new(seed));
        prop_assert_eq!(plan.len(), n);
        for d in 0..dims {
            let mut seen = vec![false; n];
            for p in &plan {
                prop_assert_eq!(p.len(), dims);
                let k = ((p[d] * n as f64) as usize).min(n - 1);
                prop_assert!(!seen[k], "stratum {} of dimension {} hit twice", k, d);
                seen[k] = true;
            }
        }
    }

    #[test]
    fn latin_hypercube_respects_scaled_and_integer_bounds(
        n in 1usize..40,
        lower in -100.0f64..100.0,
        width in 0.0f64..50.0,
        seed in any::<u64>(),
    ) {
        let bounds = [Bounds::continuous(lower, lower + width), Bounds::integer(lower, lower + width + 1.0)];
        let plan = latin_hypercube(n, &bounds, &mut Rng::new(seed));
        for p in &plan {
            prop_assert!(p[0] >= lower && p[0] <= lower + width);
            prop_assert!(bounds[1].contains(p[1]));
        }
    }

    #[test]
    fn full_factorial_has_the_product_of_level_counts(counts in proptest::collection::vec(1usize..5, 1..5)) {
        let levels: Vec<Vec<f64>> = counts.iter().map(|&c| (0..c).map(|k| k as f64).collect()).collect();
        let plan = full_factorial(&levels);
        prop_assert_eq!(plan.len(), counts.iter().product::<usize>());
        // Rows are distinct and in lexicographic order.
        for w in plan.windows(2) {
            prop_assert!(w[0].partial_cmp(&w[1]) == Some(std::cmp::Ordering::Less));
        }
    }
}
