//! Property tests of the design space and the generator: repair lands inside the bounds and is
//! idempotent; `Rng::below` stays below its bound.

use mrbrake_optim::rng::Rng;
use mrbrake_optim::space::Bounds;
use proptest::prelude::*;

proptest! {
    #[test]
    fn repair_is_inside_and_idempotent(
        lower in -1e3f64..1e3,
        width in 0.0f64..1e3,
        x in prop_oneof![any::<f64>(), -1e4f64..1e4],
        integer in any::<bool>(),
    ) {
        let b = if integer {
            Bounds::integer(lower, lower + width + 1.0)
        } else {
            Bounds::continuous(lower, lower + width)
        };
        prop_assert!(b.validate(0).is_ok());
        let r = b.repair(x);
        prop_assert!(b.contains(r), "{} -> {} outside {:?}", x, r, b);
        prop_assert_eq!(b.repair(r).to_bits(), r.to_bits());
        let u = b.from_unit(x.abs().fract());
        prop_assert!(b.contains(u));
    }

    #[test]
    fn below_stays_below(n in 1u64..u64::MAX, seed in any::<u64>()) {
        let mut rng = Rng::new(seed);
        for _ in 0..16 {
            prop_assert!(rng.below(n) < n);
        }
    }
}
