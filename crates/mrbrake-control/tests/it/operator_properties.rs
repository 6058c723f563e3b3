//! Property tests of the operator inverse (modified Prandtl–Ishlinskii model) for any valid model:
//! the current stays in `[0, min(limit, I_max)]` for any demand sequence, NaN and infinities included;
//! inside the reachable torque range the inverse is exact (the forward model driven by the computed
//! current reproduces the demand); the controller runs it with a fault-free, in-range output; and the
//! operator-model file round-trips and refuses lists beyond the fixed capacity.

use mrbrake_control::*;
use proptest::prelude::*;

/// Valid models: 1..=MAX_PLAYS plays on a uniform grid, 1..=MAX_SEGMENTS segments, torque at rest
/// 0.1–1.1 N·m.
fn model() -> impl Strategy<Value = OperatorModel> {
    (
        prop::collection::vec(0.0f64..1.0, 1..MAX_PLAYS),
        prop::collection::vec(0.05f64..3.0, 1..MAX_SEGMENTS),
        0.5f64..5.0,
        0.0f64..1.0,
    )
        .prop_map(|(weights, slopes, i_max, lift)| {
            let mut weights = weights;
            weights[0] += 0.1; // a₀ > 0
            let thresholds: Vec<f64> =
                (0..weights.len()).map(|k| k as f64 * i_max / (2 * weights.len()) as f64).collect();
            let knots: Vec<f64> = (0..slopes.len()).map(|k| 0.1 + 0.3 * k as f64).collect();
            // D(0.1 N·m + lift) = Π at rest: the brake's torque at rest is positive, as a brake's is.
            let rest: f64 = weights.iter().zip(&thresholds).map(|(a, r)| a * r).sum();
            let offset = rest - slopes[0] * lift;
            OperatorModel::new(&OperatorParts {
                thresholds_a: &thresholds,
                weights: &weights,
                knots_nm: &knots,
                slopes_a_per_nm: &slopes,
                offset_a: offset,
                current_min_a: 0.0,
                current_max_a: i_max,
            })
            .expect("valid model")
        })
}

fn demand() -> impl Strategy<Value = f64> {
    prop_oneof![
        8 => -2.0f64..20.0,
        1 => Just(f64::NAN),
        1 => Just(f64::INFINITY),
        1 => Just(f64::NEG_INFINITY),
    ]
}

proptest! {
    #[test]
    fn current_is_always_in_range(model in model(),
                                  demands in prop::collection::vec(demand(), 1..60),
                                  limit in 0.1f64..10.0) {
        let mut state = OperatorCompensation::default();
        let upper = limit.min(model.current_max_a());
        for d in demands {
            let i = model.compensate(&mut state, d, limit);
            prop_assert!(i.is_finite() && (0.0..=upper).contains(&i), "{i} for {d}");
        }
    }

    #[test]
    fn the_forward_model_reproduces_reachable_demands(model in model(),
                                                      currents in prop::collection::vec(0.0f64..1.0, 1..40)) {
        // Demands produced by the forward model itself are reachable: the inverse must return the
        // current that produced them.
        let (mut forward, mut inverse) = (OperatorState::default(), OperatorCompensation::default());
        for f in currents {
            let i = 1e-6 + f * (model.current_max_a() - 1e-6);
            let t = model.torque_nm(&mut forward, i);
            prop_assert!(t > 0.0, "the model's torque at rest is ≥ 0.1 N·m");
            let back = model.compensate(&mut inverse, t, model.current_max_a());
            prop_assert!((back - i).abs() < 1e-9 * (1.0 + i), "{i} → {t} → {back}");
        }
    }

    #[test]
    fn the_controller_runs_operator_inverses_in_range(model in model(),
                                                      counts in prop::collection::vec(-3000i64..3000, 1..50)) {
        let inverse = TorqueInverse::Operators(model);
        let controller = DirectionalController::with_inverses(
            BrakeLayout::Bidirectional, [inverse, inverse], 2.0, 80_000, InputLimits::default(), 0.0,
        ).unwrap();
        let mut state = ControllerState::default();
        let wall = VirtualWall::new(0.0, WallSide::Positive, 30.0, 0.05);
        for c in counts {
            let out = controller.step(&mut state, &ControlInput { encoder_counts: c, velocity_rad_s: 0.2, wall });
            for i in out.current_a {
                prop_assert!((0.0..=2.0).contains(&i));
            }
        }
    }
}

#[test]
fn the_file_round_trips_and_refuses_too_many_operators() {
    let model = OperatorModel::new(&OperatorParts {
        thresholds_a: &[0.0, 0.5],
        weights: &[1.0, 0.25],
        knots_nm: &[0.15, 2.0],
        slopes_a_per_nm: &[0.5, 0.8],
        offset_a: 0.1,
        current_min_a: 0.0,
        current_max_a: 2.0,
    })
    .unwrap();
    let text = serde_json::to_string(&model).unwrap();
    assert!(text.starts_with(r#"{"schema":"mrbrake.operator-model","version":1,"#), "{text}");
    assert_eq!(serde_json::from_str::<OperatorModel>(&text).unwrap(), model);
    let many: Vec<String> = (0..=MAX_PLAYS).map(|k| format!("{}.0", k)).collect();
    let too_many = text.replace("[0.0,0.5]", &format!("[{}]", many.join(",")));
    let e = serde_json::from_str::<OperatorModel>(&too_many).unwrap_err().to_string();
    assert!(e.contains("invalid length 33, expected a list of 1 to 32"), "{e}");
    let v2 = text.replace(r#""version":1"#, r#""version":2"#);
    let e = serde_json::from_str::<OperatorModel>(&v2).unwrap_err().to_string();
    assert!(e.contains("version 2 is not supported"), "{e}");
    let mismatched = text.replace("[1.0,0.25]", "[1.0]");
    let e = serde_json::from_str::<OperatorModel>(&mismatched).unwrap_err().to_string();
    assert!(e.contains("weights: 1 entries, expected 2"), "{e}");
}
