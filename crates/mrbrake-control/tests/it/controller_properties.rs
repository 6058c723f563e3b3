//! Property tests of the controller's invariants: the currents never leave `[0, I_max]` whatever the
//! input sequence, bad input always gives the safe output, and the direction logic energises only the
//! brake that resists motion into the wall.

use crate::common;

use mrbrake_control::*;
use proptest::prelude::*;

/// Any f64, including NaN, infinities, huge and tiny values.
fn any_value() -> impl Strategy<Value = f64> {
    prop_oneof![
        4 => -10.0..10.0f64,
        2 => -1e6..1e6f64,
        1 => Just(f64::NAN),
        1 => Just(f64::INFINITY),
        1 => Just(f64::NEG_INFINITY),
        1 => any::<f64>(),
    ]
}

fn any_input() -> impl Strategy<Value = ControlInput> {
    (
        any::<i64>(),
        -200_000i64..200_000,
        any::<bool>(),
        any_value(),
        any_value(),
        any_value(),
        any_value(),
        any_value(),
        any::<bool>(),
    )
        .prop_map(|(wild_counts, counts, wild, velocity, position, k, b, field, positive)| {
            ControlInput {
                encoder_counts: if wild { wild_counts } else { counts },
                velocity_rad_s: velocity,
                wall: VirtualWall {
                    position_rad: position,
                    side: if positive { WallSide::Positive } else { WallSide::Negative },
                    stiffness_nm_per_rad: k.abs() * 10.0,
                    damping_nms_per_rad: b,
                    field_damping_nms_per_rad: field,
                },
            }
        })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    #[test]
    fn no_input_sequence_gives_a_current_outside_the_range(
        inputs in proptest::collection::vec(any_input(), 1..64),
        bidirectional in any::<bool>(),
    ) {
        let layout = if bidirectional { BrakeLayout::Bidirectional } else { BrakeLayout::Conventional };
        let controller = common::controller(layout);
        let mut state = ControllerState::default();
        for input in &inputs {
            let out = controller.step(&mut state, input);
            for &i in &out.current_a {
                prop_assert!(i.is_finite() && (0.0..=controller.current_max_a()).contains(&i), "current {i}");
            }
            if layout == BrakeLayout::Conventional {
                prop_assert!(out.current_a[1].abs() < 1e-300);
            }
        }
    }

    #[test]
    fn non_finite_input_gives_zero_currents_and_a_fault(
        counts in -1000i64..1000, which in 0usize..5, bad in prop_oneof![Just(f64::NAN), Just(f64::INFINITY), Just(f64::NEG_INFINITY)],
    ) {
        let controller = common::controller(BrakeLayout::Bidirectional);
        let mut state = ControllerState::default();
        let mut input = ControlInput { encoder_counts: counts, velocity_rad_s: 0.1, wall: common::wall(30.0, 0.05) };
        match which {
            0 => input.velocity_rad_s = bad,
            1 => input.wall.position_rad = bad,
            2 => input.wall.stiffness_nm_per_rad = bad,
            3 => input.wall.damping_nms_per_rad = bad,
            _ => input.wall.field_damping_nms_per_rad = bad,
        }
        let out = controller.step(&mut state, &input);
        prop_assert_eq!(out.fault, Some(Fault::NonFiniteInput));
        prop_assert!(out.current_a[0].abs() < 1e-300 && out.current_a[1].abs() < 1e-300);
        prop_assert_eq!(state.fault_count(), 1);
    }

    #[test]
    fn bidirectional_energises_only_the_brake_resisting_motion_into_the_wall(
        counts in 1i64..20_000, velocity in -5.0..5.0f64, positive in any::<bool>(),
    ) {
        let controller = common::controller(BrakeLayout::Bidirectional);
        let mut state = ControllerState::default();
        let side = if positive { WallSide::Positive } else { WallSide::Negative };
        let mut wall = common::wall(30.0, 0.0);
        wall.side = side;
        // Place the shaft inside the wall on either side.
        let encoder_counts = if positive { counts } else { -counts };
        let out = controller.step(&mut state, &ControlInput { encoder_counts, velocity_rad_s: velocity, wall });
        let (resisting, other) = if positive { (0, 1) } else { (1, 0) };
        prop_assert!(out.current_a[other].abs() < 1e-300);
        prop_assert!(out.breakdown.penetration_rad > 0.0);
        prop_assert!(out.breakdown.demand_nm[resisting] > 0.0);
        prop_assert!(out.breakdown.demand_nm[other].abs() < 1e-300);
        // Current flows once the demand exceeds the off-state torque (0.15 Nm at 0 A).
        if out.breakdown.demand_nm[resisting] > 0.16 {
            prop_assert!(out.current_a[resisting] > 0.0);
        }
    }
}

#[test]
fn out_of_range_inputs_are_faults() {
    let controller = common::controller(BrakeLayout::Bidirectional);
    let mut state = ControllerState::default();
    let good =
        ControlInput { encoder_counts: 100, velocity_rad_s: 0.1, wall: common::wall(30.0, 0.05) };
    assert!(controller.step(&mut state, &good).fault.is_none());
    let mut fast = good;
    fast.velocity_rad_s = 1e4;
    assert_eq!(controller.step(&mut state, &fast).fault, Some(Fault::VelocityOutOfRange));
    let mut negative_k = good;
    negative_k.wall.stiffness_nm_per_rad = -1.0;
    assert_eq!(controller.step(&mut state, &negative_k).fault, Some(Fault::EnvironmentOutOfRange));
    let mut far = good;
    far.encoder_counts = i64::MAX;
    assert_eq!(controller.step(&mut state, &far).fault, Some(Fault::AngleOutOfRange));
    assert_eq!(state.fault_count(), 3);
}

#[test]
fn outside_the_wall_both_brakes_are_off() {
    for layout in [BrakeLayout::Conventional, BrakeLayout::Bidirectional] {
        let controller = common::controller(layout);
        let mut state = ControllerState::default();
        let out = controller.step(
            &mut state,
            &ControlInput {
                encoder_counts: -500,
                velocity_rad_s: 1.0,
                wall: common::wall(30.0, 0.1),
            },
        );
        assert!(out.current_a.iter().all(|i| i.abs() < 1e-300));
        assert!(out.breakdown.penetration_rad < 0.0);
    }
}
