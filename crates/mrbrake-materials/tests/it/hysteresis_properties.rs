//! Property tests of the energy-based hysteresis model's loop shape (`mrbrake_materials::hysteresis`),
//! for random parameter sets and field amplitudes: a symmetric cycle closes, B is monotone along a
//! monotone H branch (B-driven, H is monotone along a monotone B branch), and after a descent to a
//! reversal point H₁, an excursion up to H₂ and back down to H₁ comes back to the B it left
//! (return-point memory, which the play operators have exactly).

use mrbrake_materials::hysteresis::{HysteresisParams, HysteresisState, Term};
use proptest::prelude::*;

/// Random parameter sets: 1–4 cells, pinning fields 0–2 kA/m, 1–3 terms per cell.
fn arbitrary_params() -> impl Strategy<Value = HysteresisParams> {
    prop::collection::vec(
        (0.0..2000.0_f64, prop::collection::vec((0.05..1.0_f64, 10.0..50_000.0_f64), 1..4)),
        1..5,
    )
    .prop_map(|cells| {
        let pinning: Vec<f64> = cells.iter().map(|c| c.0).collect();
        let terms: Vec<Term> = cells
            .iter()
            .enumerate()
            .flat_map(|(k, c)| {
                c.1.iter().map(move |&(js, a)| Term {
                    cell: k,
                    polarisation_t: js,
                    field_a_per_m: a,
                })
            })
            .collect();
        HysteresisParams::new(&pinning, &terms).unwrap()
    })
}

/// `n` H-driven steps from the state's field to `to`; the B of each.
fn ramp(p: &HysteresisParams, state: &mut HysteresisState, to: f64, n: usize) -> Vec<f64> {
    let from = state.h();
    (1..=n).map(|k| state.step_h(p, from + (to - from) * k as f64 / n as f64).b).collect()
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-9 * (1.0 + a.abs().max(b.abs()))
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// After the first magnetisation to `h_max`, every full symmetric cycle returns to the same tip.
    #[test]
    fn a_symmetric_cycle_closes(p in arbitrary_params(), h_max in 10.0..50_000.0_f64, n in 2usize..30) {
        let mut state = HysteresisState::demagnetised();
        ramp(&p, &mut state, h_max, n);
        let tip = state.b();
        for _ in 0..2 {
            ramp(&p, &mut state, -h_max, 2 * n);
            ramp(&p, &mut state, h_max, 2 * n);
            prop_assert!(close(state.b(), tip), "{} vs {tip}", state.b());
        }
    }

    /// B never decreases along an increasing H ramp and never increases along a decreasing one,
    /// from any state; and B-driven, H follows B monotonically with a positive tangent.
    #[test]
    fn branches_are_monotone(
        p in arbitrary_params(),
        waypoints in prop::collection::vec(-30_000.0..30_000.0_f64, 2..6),
    ) {
        let mut state = HysteresisState::demagnetised();
        for &to in &waypoints {
            let direction = (to - state.h()).signum();
            let mut previous = state.b();
            for b in ramp(&p, &mut state, to, 16) {
                prop_assert!(direction * (b - previous) >= -1e-12, "{previous} → {b}");
                previous = b;
            }
        }
        let mut driven = HysteresisState::demagnetised();
        let mut previous_h = 0.0;
        for k in 1..=20 {
            let r = driven.step(&p, 1.8 * k as f64 / 20.0);
            prop_assert!(r.h >= previous_h && r.dh_db > 0.0);
            previous_h = r.h;
        }
    }

    /// Return-point memory: descending to `H₁`, up to `H₂ > H₁` and back to `H₁` restores B.
    #[test]
    fn a_minor_loop_returns_to_its_start(
        p in arbitrary_params(),
        h_max in 100.0..30_000.0_f64,
        f1 in -0.9..0.9_f64,
        f2 in -1.0..1.0_f64,
    ) {
        let mut state = HysteresisState::demagnetised();
        ramp(&p, &mut state, h_max, 8);
        let h1 = f1 * h_max;
        ramp(&p, &mut state, h1, 8);
        let b1 = state.b();
        // h1 is a reversal (reached descending): an excursion up to h2 and back down returns.
        let h2 = h1 + (0.5 * (f2 + 1.0) * (h_max - h1)).max(1.0);
        ramp(&p, &mut state, h2, 8);
        ramp(&p, &mut state, h1, 8);
        prop_assert!(close(state.b(), b1), "{} vs {b1}", state.b());
    }
}
