//! Property tests of the demagnetising release ([`mrbrake_control::demag`]): the currents stay within
//! `[−reverse_limit_a, I_max]` whatever the input, a released brake's sequence ends at exactly 0 A
//! within its bounded number of ticks, a new demand interrupts it, and with the release disabled the
//! controller is bit-identical to the one without it.

use crate::common;

use mrbrake_control::*;
use proptest::prelude::*;

/// A waveform of either kind from the strategy's numbers.
fn waveform(ac: bool, amplitude: f64, ratio: f64, ticks: u32, half_cycles: u32) -> DemagWaveform {
    if ac {
        DemagWaveform::DecayingAc {
            first_amplitude_a: amplitude,
            decay_ratio: ratio,
            half_period_s: f64::from(ticks) * 1e-3,
            half_cycles,
        }
    } else {
        DemagWaveform::ReversePulse { amplitude_a: amplitude, duration_s: f64::from(ticks) * 1e-3 }
    }
}

fn settings(waveform: DemagWaveform, reverse_limit_a: f64) -> DemagSettings {
    DemagSettings {
        waveform,
        reverse_limit_a,
        arm_above_nm: 0.5,
        release_below_nm: 0.0,
        reference_peak_a: 2.0,
    }
}

/// A controller for `layout` with the release `settings` at 1 kHz.
fn demag_controller(layout: BrakeLayout, settings: &DemagSettings) -> DirectionalController {
    common::controller(layout).with_demagnetisation(settings, 1e-3).expect("valid settings")
}

/// The shaft `counts` into a stiff wall at 0 rad (positive side), at rest.
fn input(counts: i64) -> ControlInput {
    ControlInput { encoder_counts: counts, velocity_rad_s: 0.0, wall: common::wall(30.0, 0.0) }
}

/// Any input: inside or outside the wall, sometimes non-finite.
fn any_input() -> impl Strategy<Value = ControlInput> {
    (-30_000i64..30_000, -5.0..5.0f64, prop_oneof![9 => Just(false), 1 => Just(true)]).prop_map(
        |(counts, velocity, nan)| ControlInput {
            encoder_counts: counts,
            velocity_rad_s: if nan { f64::NAN } else { velocity },
            wall: common::wall(30.0, 0.05),
        },
    )
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(128))]

    #[test]
    fn currents_stay_within_the_driver_limits(
        inputs in proptest::collection::vec(any_input(), 1..200),
        ac in any::<bool>(), limit in 0.01..2.0f64, fraction in 0.01..1.0f64,
        ratio in 0.05..0.95f64, ticks in 1u32..8, half_cycles in 1u32..10,
        bidirectional in any::<bool>(),
    ) {
        let layout = if bidirectional { BrakeLayout::Bidirectional } else { BrakeLayout::Conventional };
        let s = settings(waveform(ac, limit * fraction, ratio, ticks, half_cycles), limit);
        let controller = demag_controller(layout, &s);
        let mut state = ControllerState::default();
        for input in &inputs {
            let out = controller.step(&mut state, input);
            for &i in &out.current_a {
                prop_assert!(i.is_finite() && (-limit..=controller.current_max_a()).contains(&i), "{i}");
            }
            if out.fault.is_some() {
                prop_assert!(out.current_a.iter().all(|i| i.abs() < f64::MIN_POSITIVE));
            }
        }
    }

    #[test]
    fn a_release_ends_at_exactly_zero_within_its_ticks(
        ac in any::<bool>(), amplitude in 0.01..1.0f64, ratio in 0.05..0.95f64,
        ticks in 1u32..20, half_cycles in 1u32..12, depth in 3_000i64..20_000,
    ) {
        let s = settings(waveform(ac, amplitude, ratio, ticks, half_cycles), 1.0);
        let controller = demag_controller(BrakeLayout::Bidirectional, &s);
        let n = controller.demagnetiser().sequence_ticks();
        prop_assert!(n <= MAX_DEMAG_TICKS);
        let mut state = ControllerState::default();
        for _ in 0..5 {
            controller.step(&mut state, &input(depth));
        }
        // Out of the wall: the demand is 0, the release runs for n ticks, then exactly 0 A.
        let mut reversed = false;
        for k in 0..n {
            let out = controller.step(&mut state, &input(-100));
            prop_assert!(state.demag_states()[0].is_releasing(), "tick {k}");
            reversed |= out.current_a[0] < 0.0;
        }
        prop_assert!(reversed);
        for _ in 0..10 {
            let out = controller.step(&mut state, &input(-100));
            prop_assert!(out.current_a[0].abs() < f64::MIN_POSITIVE);
            prop_assert!(!state.demag_states()[0].is_releasing());
        }
    }

    #[test]
    fn a_new_demand_interrupts_the_release(
        amplitude in 0.01..1.0f64, ticks in 3u32..50, after in 1u32..3, depth in 3_000i64..20_000,
    ) {
        let s = settings(waveform(false, amplitude, 0.5, ticks, 1), 1.0);
        let controller = demag_controller(BrakeLayout::Bidirectional, &s);
        let reference = common::controller(BrakeLayout::Bidirectional);
        let mut state = ControllerState::default();
        let mut reference_state = ControllerState::default();
        for _ in 0..5 {
            controller.step(&mut state, &input(depth));
        }
        for _ in 0..after {
            let out = controller.step(&mut state, &input(-100));
            prop_assert!(out.current_a[0] < 0.0);
        }
        // Back into the wall: the compensated current, at once (as a controller without release).
        let back = controller.step(&mut state, &input(depth));
        prop_assert!(!state.demag_states()[0].is_releasing());
        prop_assert!(back.current_a[0] > 0.0);
        for _ in 0..5 {
            reference.step(&mut reference_state, &input(depth));
        }
        let fresh = reference.step(&mut reference_state, &input(depth));
        prop_assert!((back.current_a[0] - fresh.current_a[0]).abs() < 0.2 * fresh.current_a[0]);
    }

    #[test]
    fn a_disabled_release_is_bit_identical(
        inputs in proptest::collection::vec(any_input(), 1..200),
        amplitude in 0.0..2.0f64, bidirectional in any::<bool>(),
    ) {
        let layout = if bidirectional { BrakeLayout::Bidirectional } else { BrakeLayout::Conventional };
        let plain = common::controller(layout);
        let s = settings(waveform(false, amplitude, 0.5, 5, 1), 0.0);
        let off = demag_controller(layout, &s);
        prop_assert!(!off.demagnetiser().is_enabled());
        let (mut a, mut b) = (ControllerState::default(), ControllerState::default());
        for input in &inputs {
            let (x, y) = (plain.step(&mut a, input), off.step(&mut b, input));
            prop_assert_eq!(x.current_a[0].to_bits(), y.current_a[0].to_bits());
            prop_assert_eq!(x.current_a[1].to_bits(), y.current_a[1].to_bits());
            prop_assert_eq!(x.fault, y.fault);
        }
        prop_assert_eq!(a, b);
    }
}

#[test]
fn bad_settings_name_their_field() {
    let controller = common::controller(BrakeLayout::Bidirectional);
    let cases = [
        (settings(waveform(false, -0.3, 0.5, 5, 1), 1.0), "amplitude_a"),
        (settings(waveform(false, f64::NAN, 0.5, 5, 1), 1.0), "amplitude_a"),
        (settings(waveform(true, 0.3, 1.5, 5, 4), 1.0), "decay_ratio"),
        (settings(waveform(true, 0.3, 0.5, 5, 100_000), 1.0), "half_cycles"),
        (settings(waveform(false, 0.3, 0.5, 5, 1), f64::INFINITY), "reverse_limit_a"),
    ];
    for (s, expected) in cases {
        match controller.with_demagnetisation(&s, 1e-3) {
            Err(ControlError::OutOfRange { field, .. }) => assert_eq!(field, expected),
            other => panic!("{expected}: {other:?}"),
        }
    }
    let err = controller
        .with_demagnetisation(&settings(waveform(false, 0.3, 0.5, 5, 1), 1.0), f64::NAN)
        .unwrap_err();
    assert!(err.to_string().contains("control_period_s"), "{err}");
}
