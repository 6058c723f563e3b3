//! Property tests of the inverse model for any non-decreasing branch: the current stays in its range,
//! reproduces the target torque within the inversion tolerance, and never falls by more than that
//! tolerance when the target rises (the compensation cannot make the current jump back).

use mrbrake_control::{Branch, InverseModel};
use proptest::prelude::*;

/// Branches with non-negative coefficients increase on `[0, i_max]`.
fn model() -> impl Strategy<Value = InverseModel> {
    (prop::collection::vec(0.0f64..3.0, 1..8), 0.5f64..5.0).prop_map(|(c, i_max)| {
        let falling: Vec<f64> = c.iter().map(|v| v * 1.1 + 0.05).collect();
        InverseModel::new(&c, &falling, 0.0, i_max).expect("non-decreasing branches")
    })
}

proptest! {
    #[test]
    fn inverse_is_in_range_accurate_and_monotone_within_tolerance(
        model in model(),
        targets in prop::collection::vec(-5.0f64..50.0, 2..40),
    ) {
        let i_max = model.current_max_a();
        for branch in [Branch::Rising, Branch::Falling] {
            let (t_lo, t_hi) = (model.torque_nm(branch, 0.0), model.torque_nm(branch, i_max));
            // The inversion stops within 1e-4 of the branch's torque span.
            let tolerance = 1e-4 * (t_hi - t_lo).max(1e-9);
            let mut sorted = targets.clone();
            sorted.sort_by(f64::total_cmp);
            let mut last_torque = f64::NEG_INFINITY;
            for &target in &sorted {
                let i = model.current_for(branch, target, i_max);
                prop_assert!((0.0..=i_max).contains(&i));
                let torque = model.torque_nm(branch, i);
                if target > t_lo && target < t_hi {
                    prop_assert!((torque - target).abs() <= tolerance, "{torque} vs {target}");
                }
                prop_assert!(torque >= last_torque - 2.0 * tolerance);
                last_torque = torque;
            }
        }
    }
}
