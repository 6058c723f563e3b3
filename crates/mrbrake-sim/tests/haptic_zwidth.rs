//! The simulated passivity map agrees with Colgate & Brown's condition b > K·T/2 + B (thesis (2.2))
//! and its controllable-damping form (2.4) away from the boundary; the brake device is passive
//! everywhere. See: issue #6.

use mrbrake_sim::haptic::zwidth::*;

#[test]
fn passivity_map_agrees_with_2_2_and_2_4_away_from_the_boundary() {
    let config =
        ZWidthConfig { stiffness_points: 12, damping_points: 8, ..ZWidthConfig::default() };
    let map = sweep(&config).unwrap();
    let t = config.sample_period_s;
    let b = config.physical_damping_nms_per_rad;
    let bc = config.controllable_damping_nms_per_rad;
    let (mut checked, mut agree, mut near) = (0, 0, 0);
    for c in &map.cells {
        for (damping, class, predicted) in [
            (b, c.motor, c.motor_predicted_passive),
            (b + bc, c.hybrid, c.hybrid_predicted_passive),
        ] {
            let margin = damping - (c.stiffness_nm_per_rad * t / 2.0 + c.damping_nms_per_rad);
            // Within 1 % of the boundary the finite set of test frequencies decides; skip.
            if margin.abs() < 0.01 * damping {
                near += 1;
                continue;
            }
            checked += 1;
            if (class == Interaction::Passive) == predicted {
                agree += 1;
            } else {
                println!("disagree: {c:?}");
            }
        }
        assert_eq!(c.brake, Interaction::Passive, "{c:?}");
        assert!(c.brake_energy_j <= 0.0);
    }
    println!(
        "{agree}/{checked} cells agree with (2.2)/(2.4); {near} within 1 % of the boundary skipped"
    );
    assert_eq!(agree, checked);
    // Both classes occur for both devices, so the test is not vacuous.
    assert!(map.cells.iter().any(|c| c.motor == Interaction::Passive));
    assert!(map.cells.iter().any(|c| c.motor != Interaction::Passive));
    assert!(map.cells.iter().any(|c| c.hybrid != Interaction::Passive));
    // Passive implies stable: no passive cell's free response may grow.
    for c in map.cells.iter().filter(|c| c.motor == Interaction::Passive) {
        assert!(free_response_decays(
            c.stiffness_nm_per_rad,
            c.damping_nms_per_rad,
            b,
            config.inertia_kg_m2,
            t
        ));
    }
}

#[test]
fn spring_energy_per_cycle_matches_the_closed_form() {
    // For a pure spring the device energy over one window at frequency x = ΩT is
    // N A² (1 − cos x)(K T/2 − b)/T (piecewise-linear motion), so it changes sign exactly at b = K T/2.
    let t = 1e-3;
    let k = 40.0;
    let b = 0.5 * k * t;
    assert!(motor_test_energy(k, 0.0, b * 1.001, t) < 0.0);
    assert!(motor_test_energy(k, 0.0, b * 0.999, t) > 0.0);
}
