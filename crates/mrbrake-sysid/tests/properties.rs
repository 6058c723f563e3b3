//! Property tests of invariants: the inverse model is monotone and clamped for any branch shape, and
//! a polynomial fit reproduces any polynomial of its own order.

use mrbrake_sysid::inverse::{BranchPolynomial, Direction, HysteresisModel, InverseModel};
use mrbrake_sysid::polynomial::{Polynomial, fit};
use proptest::prelude::*;

proptest! {
    #[test]
    fn inverse_is_monotone_and_clamped(
        c in prop::collection::vec(-3.0f64..3.0, 2..7),
        i_max in 0.5f64..5.0,
        torques in prop::collection::vec(-20.0f64..20.0, 2..40),
    ) {
        let model = HysteresisModel {
            rising: BranchPolynomial { coefficients: c.clone() },
            falling: BranchPolynomial { coefficients: c },
            current_min_a: 0.0,
            current_max_a: i_max,
        };
        let inv = InverseModel::new(&model).unwrap();
        let mut t = torques;
        t.sort_by(f64::total_cmp);
        let mut last = f64::NEG_INFINITY;
        for tq in t {
            let i = inv.current_for(tq, Direction::Rising);
            prop_assert!((0.0..=i_max).contains(&i));
            prop_assert!(i >= last - 1e-12);
            last = i;
        }
    }

    #[test]
    fn fit_reproduces_polynomials_of_its_order(c in prop::collection::vec(-5.0f64..5.0, 1..7), lo in -3.0f64..1.0, width in 0.5f64..4.0) {
        let p = Polynomial::new(c.clone());
        let x: Vec<f64> = (0..60).map(|k| lo + width * k as f64 / 59.0).collect();
        let y: Vec<f64> = x.iter().map(|v| p.eval(*v)).collect();
        let q = fit(&x, &y, c.len() - 1).unwrap();
        for v in &x {
            prop_assert!((q.eval(*v) - p.eval(*v)).abs() < 1e-8 * (1.0 + p.eval(*v).abs()));
        }
    }
}
