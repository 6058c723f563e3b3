//! Property tests of invariants: a polynomial fit reproduces any polynomial of its own order. (The
//! inverse model's properties are tested where it lives, in `mrbrake-control`.)

use mrbrake_sysid::polynomial::{Polynomial, fit};
use proptest::prelude::*;

proptest! {
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
