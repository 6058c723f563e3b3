//! The sticky wall, measured: with one conventional MR brake the wall resists the user's withdrawal;
//! with the bidirectional brake (two brakes on opposite one-way bearings, thesis §4.3) it does not.
//! See: issue #6.

use mrbrake_sim::haptic::*;

fn run(device: DeviceKind, scenario: Scenario) -> WallMetrics {
    let config = HapticConfig::new(device, scenario);
    let run = simulate(&config, false).expect("default configuration is valid");
    println!("{}", serde_json::to_string(&run.metrics).unwrap());
    run.metrics
}

#[test]
fn conventional_brake_resists_withdrawal_and_bidirectional_does_not() {
    let conventional = run(DeviceKind::Conventional, Scenario::PressWithdraw);
    let bidirectional = run(DeviceKind::Bidirectional, Scenario::PressWithdraw);
    let motor = run(DeviceKind::Motor, Scenario::PressWithdraw);

    let peak_ratio = conventional.withdraw_resisting_torque_nm.peak
        / bidirectional.withdraw_resisting_torque_nm.peak;
    let mean_ratio = conventional.withdraw_resisting_torque_nm.mean
        / bidirectional.withdraw_resisting_torque_nm.mean;
    let energy_ratio = conventional.withdraw_energy_j / bidirectional.withdraw_energy_j;
    let excess_ratio =
        conventional.withdraw_excess_torque_nm.peak / bidirectional.withdraw_excess_torque_nm.peak;
    println!(
        "resisting torque ratio (conventional / bidirectional): peak {peak_ratio:.2}, mean {mean_ratio:.2}; \
         excess over off-state drag, peak {excess_ratio:.1}; withdraw energy {energy_ratio:.2}"
    );

    // The bidirectional brake resists withdrawal only with the off-state torque of the brake whose
    // bearing engages on the way out (0.15 Nm) plus bearing friction.
    assert!(bidirectional.withdraw_resisting_torque_nm.peak < 0.2, "{bidirectional:?}");
    // The conventional brake holds the hand with the torque it was pressed with (~0.8 Nm).
    assert!(conventional.withdraw_resisting_torque_nm.peak > 0.5, "{conventional:?}");
    assert!(
        peak_ratio > 5.0 && mean_ratio > 4.0 && energy_ratio > 4.0,
        "{peak_ratio} {mean_ratio} {energy_ratio}"
    );
    // Beyond the off-state drag that is felt everywhere, the bidirectional wall does not hold at all.
    assert!(bidirectional.withdraw_excess_torque_nm.peak < 0.03, "{bidirectional:?}");
    assert!(excess_ratio > 30.0, "{excess_ratio}");
    // The conventional brake lets go much later.
    let released_conventional = conventional.release_time_s.expect("the hand eventually gets out");
    let released_bidirectional = bidirectional.release_time_s.expect("the hand gets out");
    assert!(released_conventional > released_bidirectional + 0.1);
    // Brakes cannot supply energy; the motor rendered the same wall.
    assert!(conventional.passive && bidirectional.passive);
    assert!(conventional.device_energy_j < 0.0 && bidirectional.device_energy_j < 0.0);
    assert!(motor.stable);
    // All three displayed a stiff wall while pressing.
    for m in [&conventional, &bidirectional, &motor] {
        assert!(m.max_penetration_rad > 0.005 && m.max_penetration_rad < 0.1, "{m:?}");
        assert!(m.current_peak_a <= 2.0);
        assert_eq!(m.fault_ticks, 0);
    }
}
