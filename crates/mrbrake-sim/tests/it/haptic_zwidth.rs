//! The simulated passivity map agrees with Colgate & Brown's condition b > K·T/2 + B (thesis (2.2))
//! and its controllable-damping form (2.4) away from the boundary; the brake device is passive
//! everywhere. See: issue #6.

use mrbrake_sim::haptic::zwidth::*;

#[test]
fn passivity_map_agrees_with_2_2_and_2_4_away_from_the_boundary() {
    let config =
        ZWidthConfig { stiffness_points: 12, damping_points: 8, ..ZWidthConfig::default() };
    let map = sweep(&config, &mut mrbrake_observe::Silent).unwrap();
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

/// Spectral radius of the exact sampled-data loop: `J ẇ = −b w + τ_k` held over `[kT, (k+1)T)`,
/// `τ_k = −K p_k − B (p_k − p_{k−1})/T`, state `[p_k, w_k, p_{k−1}]`, estimated from the growth of
/// `‖M^(2^m)‖` by repeated squaring.
fn spectral_radius(k: f64, bv: f64, b: f64, j: f64, t: f64) -> f64 {
    let a = b / j;
    let e = (-a * t).exp();
    let g = (1.0 - e) / a; // ∫₀ᵀ e^{−aτ} dτ
    // Position and velocity after one hold with torque τ: p⁺ = p + g w + (T − g) τ / b, w⁺ = e w + (1 − e) τ / b.
    let tau = [-(k + bv / t), 0.0, bv / t]; // τ as a row over the state
    let mut m = [[0.0; 3]; 3];
    for c in 0..3 {
        m[0][c] = (t - g) / b * tau[c];
        m[1][c] = (1.0 - e) / b * tau[c];
    }
    m[0][0] += 1.0;
    m[0][1] += g;
    m[1][1] += e;
    m[2][0] = 1.0;
    let mut log_scale = 0.0;
    let mut power = 1.0;
    for _ in 0..14 {
        let mut sq = [[0.0; 3]; 3];
        for r in 0..3 {
            for c in 0..3 {
                sq[r][c] = (0..3).map(|q| m[r][q] * m[q][c]).sum();
            }
        }
        let norm = sq.iter().flatten().fold(0.0f64, |x, y| x.max(y.abs())).max(1e-300);
        for row in sq.iter_mut() {
            for x in row.iter_mut() {
                *x /= norm;
            }
        }
        log_scale = 2.0 * log_scale + norm.ln();
        power *= 2.0;
        m = sq;
    }
    (log_scale / power).exp()
}

#[test]
fn stability_classification_matches_the_exact_sampled_data_eigenvalues() {
    let c = ZWidthConfig::default();
    let (t, b, j) = (c.sample_period_s, c.physical_damping_nms_per_rad, c.inertia_kg_m2);
    let (mut checked, mut agree) = (0, 0);
    for i in 0..=20 {
        for n in 0..=10 {
            let k = 100.0 * i as f64 / 20.0;
            let bv = 0.05 * n as f64 / 10.0;
            let rho = spectral_radius(k, bv, b, j, t);
            if (rho - 1.0).abs() < 0.01 {
                continue;
            }
            checked += 1;
            if (rho < 1.0) == free_response_decays(k, bv, b, j, t) {
                agree += 1;
            } else {
                println!("K = {k}, B = {bv}: spectral radius {rho:.4}");
            }
        }
    }
    println!("{agree}/{checked} free responses agree with the exact spectral radius");
    assert_eq!(agree, checked);
}

/// An observer's stop ends the sweep after the row it saw; the finished rows are those of the
/// whole map.
#[test]
fn a_stop_keeps_the_finished_rows() {
    use mrbrake_observe::{Count, Flow};
    let config = ZWidthConfig { stiffness_points: 5, damping_points: 3, ..ZWidthConfig::default() };
    let mut seen = Vec::new();
    let stopped = sweep(&config, &mut |c: &Count| {
        seen.push((c.done, c.total));
        Flow::stop_if(c.done == 2)
    })
    .unwrap();
    assert_eq!(seen, [(1, 5), (2, 5)]);
    assert!(stopped.stopped);
    assert_eq!(stopped.cells.len(), 2 * 3);
    let full = sweep(&config, &mut mrbrake_observe::Silent).unwrap();
    assert!(!full.stopped);
    assert_eq!(full.cells.len(), 5 * 3);
    assert_eq!(stopped.cells[..], full.cells[..6]);
    assert!(serde_json::to_value(&full).unwrap().get("stopped").is_none());
}
