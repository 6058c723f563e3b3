//! Every scenario and device runs passively-bounded, keeps the controller's currents in range, and the
//! plant step is converged (the measures barely change when the plant step is refined 4×).
//! See: issue #6.

use mrbrake_error::Kind as _;
use mrbrake_sim::haptic::*;

#[test]
fn all_scenarios_stay_in_range_and_brakes_stay_passive() {
    for scenario in [Scenario::PressWithdraw, Scenario::SlideHold, Scenario::MovingWall] {
        for device in [DeviceKind::Conventional, DeviceKind::Bidirectional, DeviceKind::Motor] {
            let run = simulate(&HapticConfig::new(device, scenario), true).unwrap();
            let m = &run.metrics;
            let trace = run.trace.unwrap();
            assert_eq!(trace.time_s.len(), 4000);
            for k in 0..2 {
                assert!(trace.current_a[k].iter().all(|&i| (0.0..=2.0).contains(&i)));
            }
            if device == DeviceKind::Conventional {
                assert!(trace.current_a[1].iter().all(|&i| i.abs() < 1e-300));
            }
            assert!(m.stable, "{m:?}");
            assert_eq!(m.fault_ticks, 0);
            if device != DeviceKind::Motor {
                assert!(m.passive && m.device_energy_peak_j <= 0.0, "{m:?}");
            }
            assert!(m.max_penetration_rad > 0.0, "{m:?}");
        }
    }
}

#[test]
fn sliding_inside_the_wall_is_sticky_only_with_the_conventional_brake() {
    let conventional =
        simulate(&HapticConfig::new(DeviceKind::Conventional, Scenario::SlideHold), false)
            .unwrap()
            .metrics;
    let bidirectional =
        simulate(&HapticConfig::new(DeviceKind::Bidirectional, Scenario::SlideHold), false)
            .unwrap()
            .metrics;
    println!(
        "slide/hold excess resisting torque peak: conventional {:.3} N·m, bidirectional {:.3} N·m",
        conventional.withdraw_excess_torque_nm.peak, bidirectional.withdraw_excess_torque_nm.peak
    );
    assert!(
        conventional.withdraw_excess_torque_nm.peak
            > 10.0 * bidirectional.withdraw_excess_torque_nm.peak.max(0.01)
    );
}

#[test]
fn plant_step_is_converged() {
    for device in [DeviceKind::Conventional, DeviceKind::Bidirectional, DeviceKind::Motor] {
        let coarse = HapticConfig::new(device, Scenario::PressWithdraw);
        let fine = HapticConfig { substeps: 40, ..coarse.clone() };
        let a = simulate(&coarse, false).unwrap().metrics;
        let b = simulate(&fine, false).unwrap().metrics;
        let rel = |x: f64, y: f64| (x - y).abs() / y.abs().max(1e-9);
        println!(
            "{}: max penetration {:.5} vs {:.5} rad, peak resisting {:.4} vs {:.4} N·m",
            device.name(),
            a.max_penetration_rad,
            b.max_penetration_rad,
            a.withdraw_resisting_torque_nm.peak,
            b.withdraw_resisting_torque_nm.peak
        );
        assert!(rel(a.max_penetration_rad, b.max_penetration_rad) < 0.02);
        assert!(
            rel(a.withdraw_resisting_torque_nm.peak, b.withdraw_resisting_torque_nm.peak) < 0.05
        );
    }
}

#[test]
fn invalid_configuration_is_an_input_error() {
    let mut config = HapticConfig::new(DeviceKind::Bidirectional, Scenario::PressWithdraw);
    config.wall_stiffness_nm_per_rad = f64::NAN;
    let err = simulate(&config, false).unwrap_err();
    assert!(err.is_input_error());
    assert!(err.to_string().contains("wall_stiffness_nm_per_rad"), "{err}");
}
