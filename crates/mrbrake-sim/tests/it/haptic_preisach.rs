//! The haptic plant of a brake model with a Preisach table (issue 30 §3): it is the rig's Preisach
//! model (same torques along any current history), its torque after a peak is the table's, its
//! minor loops close (return-point memory, wiping-out), the demagnetising release acts on it, a
//! remanence that would count the table's twice and a bad table are refused, and a model without
//! a table keeps the clamp plant.

use crate::haptic_demag::remanence as release;
use mrbrake_control::Branch;
use mrbrake_sim::brake_model::apply::{apply_to_haptic, apply_to_rig};
use mrbrake_sim::brake_model::prototype::haptic_prototype;
use mrbrake_sim::brake_model::{BrakeModel, Hysteresis};
use mrbrake_sim::haptic::brake::{BrakeState, PreisachBrake};
use mrbrake_sim::haptic::{
    BrakePlant, DeviceKind, HapticConfig, RemanenceState, Scenario, simulate,
};
use mrbrake_sim::rig::RigConfig;
use mrbrake_sim::rig::everett::EverettTable;
use mrbrake_sim::rig::preisach::PreisachHysteresis;
use proptest::prelude::*;

/// Levels of the test table.
const LEVELS: usize = 8;
/// The table's remanent (yield) torque at 0 A in its reference state, N·m.
const REMANENT_NM: f64 = 0.2;
/// Uniform Preisach density `c`: `E(α, β) = c (α − β)² / 2`, N·m/A².
const DENSITY: f64 = 0.5;
/// Seal friction of the test model, N·m.
const SEAL_NM: f64 = 0.03;

/// A Preisach table with a uniform density on `[0, i_max]` (closed form: the weight of every cell
/// is `c h²`), rising branch `T(α) = R + E(α, 0)` (as identified from FORCs, `rig::everett`: the
/// reference state's torque plus the relays the rise switches on).
fn uniform_table(i_max: f64) -> EverettTable {
    let level = |k: usize| i_max * k as f64 / LEVELS as f64;
    let e = |a: f64, b: f64| DENSITY * (a - b) * (a - b) / 2.0;
    EverettTable {
        levels_a: (0..=LEVELS).map(level).collect(),
        rising_nm: (0..=LEVELS).map(|k| REMANENT_NM + e(level(k), 0.0)).collect(),
        everett_nm: (0..=LEVELS)
            .map(|a| (0..=a).map(|b| e(level(a), level(b))).collect())
            .collect(),
    }
}

/// The prototype model with the uniform table on both units and `SEAL_NM` seal friction.
fn preisach_model() -> BrakeModel {
    let mut model = haptic_prototype();
    for unit in &mut model.units {
        let t = uniform_table(unit.current_max_a);
        unit.off_state.seal_friction_nm = SEAL_NM;
        unit.hysteresis = Hysteresis::Preisach {
            levels_a: t.levels_a,
            rising_nm: t.rising_nm,
            everett_nm: t.everett_nm,
            source: "test: uniform density".into(),
        };
    }
    model.check("(test)").unwrap();
    model
}

/// The haptic configuration of `model` on `device`.
fn haptic(model: &BrakeModel, device: DeviceKind) -> HapticConfig {
    let mut config = HapticConfig::new(device, Scenario::PressWithdraw);
    apply_to_haptic(model, &mut config).unwrap();
    config
}

/// Drives `brake` from rest through `currents`; the static torque after each.
fn drive(brake: &BrakePlant, currents: &[f64]) -> (Vec<f64>, BrakeState) {
    let mut state = brake.rest_state();
    let torques = currents
        .iter()
        .map(|i| {
            brake.apply_current(&mut state, *i);
            state.static_torque_nm
        })
        .collect();
    (torques, state)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    /// The haptic plant and the virtual rig's plant build the same Preisach model from a brake
    /// model and give the same torque along any current history (reverse currents included: both
    /// take them as 0 A).
    #[test]
    fn the_haptic_plant_is_the_rigs_preisach_model(
        currents in proptest::collection::vec(-0.5..2.5f64, 1..80)
    ) {
        let model = preisach_model();
        let config = haptic(&model, DeviceKind::Bidirectional);
        let mut rig = RigConfig::default();
        apply_to_rig(&model, 1, &mut rig).unwrap();
        let mut reference = PreisachHysteresis::from_everett(rig.brake.everett.as_ref().unwrap(), 0.0)
            .unwrap();
        let brake = &config.brakes[0];
        prop_assert!(brake.preisach.is_some());
        let (torques, _) = drive(brake, &currents);
        for (i, t) in currents.iter().zip(torques) {
            let expected = reference.torque_nm(*i);
            prop_assert!((t - expected).abs() < 1e-12, "{t} vs {expected} at {i} A");
        }
    }
}

#[test]
fn after_a_peak_the_torque_is_the_tables_reversal_curve_and_at_0_a_its_remanence() {
    let model = preisach_model();
    let config = haptic(&model, DeviceKind::Conventional);
    let brake = &config.brakes[0];
    let unit = model.unit(1).unwrap();
    let table = unit.hysteresis.everett().unwrap();
    let rest = brake.rest_state().static_torque_nm;
    assert!((rest - (REMANENT_NM + SEAL_NM)).abs() < 1e-12, "{rest}");
    for peak in 1..=LEVELS {
        for beta in 0..peak {
            let (torques, _) = drive(brake, &[table.levels_a[peak], table.levels_a[beta]]);
            // The first-order reversal curve T(α_k, β_j) = T(α_k) − E(α_k, β_j), plus the seal.
            let forc = table.rising_nm[peak] - table.everett_nm[peak][beta] + SEAL_NM;
            assert!((torques[1] - forc).abs() < 1e-12, "peak {peak}, β {beta}: {torques:?}");
        }
        // Back at 0 A after any peak: the reference state's remanent torque (wiping-out at 0 A),
        // whatever the peak.
        let (torques, _) = drive(brake, &[table.levels_a[peak], 0.0]);
        assert!((torques[1] - (REMANENT_NM + SEAL_NM)).abs() < 1e-12, "{torques:?}");
    }
    // The clamp between the branches would hold the torque flat on a small reversal from below
    // the peak; the Preisach plant falls along the reversal curve at once.
    let (i_hi, i_lo) = (table.levels_a[5], table.levels_a[4]);
    let (torques, _) = drive(brake, &[i_hi, i_lo]);
    let mut clamp = brake.clone();
    clamp.preisach = None;
    let (flat, _) = drive(&clamp, &[i_hi, i_lo]);
    assert!(torques[1] < flat[1] - 1e-3, "Preisach {torques:?} vs clamp {flat:?}");
}

#[test]
fn a_minor_loop_closes_and_is_wiped_out() {
    let config = haptic(&preisach_model(), DeviceKind::Conventional);
    let brake = &config.brakes[0];
    let history = [1.7, 0.3, 1.4, 0.6];
    let (hi, lo) = (1.2, 0.8);
    let mut path = history.to_vec();
    path.extend([hi, lo]);
    let (before, state) = drive(brake, &path);
    let (at_hi, at_lo) = (before[path.len() - 2], before[path.len() - 1]);
    // Wander inside [lo, hi], then return to each turning point: its torque again.
    let inner = [0.9, 1.1, 0.85, 1.15, 1.0];
    let mut s = state.clone();
    for i in inner.iter().chain(&[hi]) {
        brake.apply_current(&mut s, *i);
    }
    assert!((s.static_torque_nm - at_hi).abs() < 1e-12, "{} vs {at_hi}", s.static_torque_nm);
    for i in inner.iter().chain(&[lo]) {
        brake.apply_current(&mut s, *i);
    }
    assert!((s.static_torque_nm - at_lo).abs() < 1e-12, "{} vs {at_lo}", s.static_torque_nm);
    // Past the history's previous maximum the minor loops are wiped out: the same state as a
    // history that went straight there.
    for i in [1.8, 0.5] {
        brake.apply_current(&mut s, i);
    }
    let (straight, _) = drive(brake, &[1.8, 0.5]);
    assert!((s.static_torque_nm - straight[1]).abs() < 1e-12);
    assert_eq!(s.preisach.as_ref().unwrap().turning_points().len(), 2);
}

#[test]
fn the_release_removes_its_share_of_the_tables_remanence_until_a_full_peak() {
    let config = haptic(&preisach_model(), DeviceKind::Conventional);
    let brake = &config.brakes[0];
    let preisach = brake.preisach.as_ref().unwrap();
    // R₀ = 0.175 N·m after 2 A, a 0.3 A reverse pulse leaving ρ = 1/4.
    let remanence = release(Some(0.25));
    let (mut s, mut r) = (brake.rest_state(), RemanenceState::default());
    let apply = |i: f64, s: &mut BrakeState, r: &mut RemanenceState| {
        remanence.apply_current(brake, s, r, i);
        s.static_torque_nm
    };
    // Magnetising comes from the table: R₀ of the remanence file is not added.
    apply(2.0, &mut s, &mut r);
    let at_zero = apply(0.0, &mut s, &mut r);
    assert!((at_zero - (REMANENT_NM + SEAL_NM)).abs() < 1e-12, "{at_zero}");
    // The full pulse (0.3 A after the 2 A reference peak) leaves ρ of the table's remanence.
    apply(-0.3, &mut s, &mut r);
    let left = apply(0.0, &mut s, &mut r);
    assert!((left - (SEAL_NM + 0.25 * REMANENT_NM)).abs() < 1e-12, "{left}");
    assert!((r.remanent_nm() - 0.25 * REMANENT_NM).abs() < 1e-12);
    // A peak at 1 A restores the share g = E(1, 0)/E(2, 0) = 1/4 of the deficit.
    let deficit = 0.75 * REMANENT_NM;
    let g = preisach.rising_share(1.0);
    assert!((g - 0.25).abs() < 1e-12, "{g}");
    let at_one = apply(1.0, &mut s, &mut r);
    let mut plain = brake.rest_state();
    for i in [2.0, 0.0, 1.0] {
        brake.apply_current(&mut plain, i);
    }
    assert!((at_one - (plain.static_torque_nm - deficit * (1.0 - g))).abs() < 1e-12);
    let back = apply(0.0, &mut s, &mut r);
    assert!((back - (SEAL_NM + REMANENT_NM - deficit * (1.0 - g))).abs() < 1e-12, "{back}");
    // A peak at I_max restores the reference state.
    apply(2.0, &mut s, &mut r);
    let full = apply(0.0, &mut s, &mut r);
    assert!((full - (REMANENT_NM + SEAL_NM)).abs() < 1e-12, "{full}");
}

#[test]
fn a_remanence_without_release_on_a_preisach_brake_is_refused() {
    let mut config = haptic(&preisach_model(), DeviceKind::Bidirectional);
    config.remanence = Some(release(None));
    let e = config.validate().unwrap_err().to_string();
    assert!(e.starts_with("remanence: ") && e.contains("twice"), "{e}");
    config.remanence = Some(release(Some(0.1)));
    config.validate().unwrap();
}

#[test]
fn a_table_with_nan_is_refused_naming_the_field() {
    let mut table = uniform_table(2.0);
    table.everett_nm[5][2] = f64::NAN;
    let e = PreisachBrake::from_table(&table, 0.0).unwrap_err().to_string();
    assert!(e.contains("everett_Nm[5]"), "{e}");
    let mut model = preisach_model();
    if let Hysteresis::Preisach { rising_nm, .. } = &mut model.units[1].hysteresis {
        rising_nm[3] = f64::NAN;
    }
    let e = model.check("m.json").unwrap_err().to_string();
    assert!(e.contains("m.json") && e.contains("units[1].hysteresis.rising_Nm[3]"), "{e}");
}

#[test]
fn without_a_table_the_plant_is_the_clamp_between_the_branches() {
    let config = haptic(&haptic_prototype(), DeviceKind::Bidirectional);
    assert!(config.brakes.iter().all(|b| b.preisach.is_none()));
    let brake = &config.brakes[0];
    let currents = [0.3, 1.7, 0.9, 1.2, 0.0, 0.4, -0.2, 2.0, 1.99];
    let (torques, _) = drive(brake, &currents);
    let mut t = brake.branches.torque_nm(Branch::Rising, brake.branches.current_min_a());
    for (i, got) in currents.iter().zip(torques) {
        let lower = brake.branches.torque_nm(Branch::Rising, *i);
        let upper = brake.branches.torque_nm(Branch::Falling, *i);
        t = t.max(lower).min(upper.max(lower));
        assert!((got - t).abs() < 1e-15, "{got} vs {t}");
    }
}

#[test]
fn after_a_wall_the_free_motion_drag_is_the_tables_remanence() {
    let model = preisach_model();
    let config = haptic(&model, DeviceKind::Bidirectional);
    let metrics = simulate(&config, false).unwrap().metrics;
    assert!(metrics.current_peak_a > 0.5, "{}", metrics.current_peak_a);
    let gain = config.brakes[0].lag.gain;
    let expected = config.device_parameters.coulomb_nm + gain * (REMANENT_NM + SEAL_NM);
    let inward = metrics.drag_after_nm.inward;
    assert!((inward - expected).abs() < 1e-6, "{inward} vs {expected}");
}
