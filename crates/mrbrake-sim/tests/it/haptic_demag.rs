//! The steel's remanence in the haptic plant and the demagnetising release
//! (`mrbrake_sim::haptic::remanence`, `mrbrake_control::demag`): after a press into the wall the
//! conventional brake keeps its remanent torque in free motion; the reverse pulse removes the share
//! the predicted loop says it removes, so the free-motion drag and the free-motion torque are lower
//! with the release, and the release does not slow leaving the wall.

use mrbrake_control::{DemagSettings, DemagWaveform};
use mrbrake_error::Kind;
use mrbrake_sim::haptic::*;

/// A remanence like the thesis brake's predicted one (0.175 N·m after 2 A) and, with `fraction`,
/// a 5 ms reverse pulse of 0.3 A that leaves that share of it.
pub(crate) fn remanence(fraction: Option<f64>) -> PlantRemanence {
    PlantRemanence {
        remanent_torque_nm: 0.175,
        reference_peak_a: 2.0,
        release: fraction.map(|remanence_fraction| ReleaseModel {
            settings: DemagSettings {
                waveform: DemagWaveform::ReversePulse { amplitude_a: 0.3, duration_s: 5e-3 },
                reverse_limit_a: 1.0,
                arm_above_nm: 0.175,
                release_below_nm: 0.0,
                reference_peak_a: 2.0,
            },
            remanence_fraction,
        }),
    }
}

fn run(device: DeviceKind, remanence: Option<PlantRemanence>) -> HapticRun {
    let mut config = HapticConfig::new(device, Scenario::PressWithdraw);
    config.remanence = remanence;
    simulate(&config, true).expect("valid configuration")
}

/// Brake 1's torque capacity at the end of the run (the hand at rest outside the wall), N·m.
fn final_capacity(run: &HapticRun) -> f64 {
    *run.trace.as_ref().unwrap().capacity_nm[0].last().unwrap()
}

#[test]
fn the_release_removes_the_remanent_free_motion_drag() {
    let plain = run(DeviceKind::Conventional, None);
    let sticky = run(DeviceKind::Conventional, Some(remanence(None)));
    let released = run(DeviceKind::Conventional, Some(remanence(Some(0.1))));
    let rest = plain.metrics.outward_drag_nm
        - HapticConfig::new(DeviceKind::Conventional, Scenario::PressWithdraw)
            .device_parameters
            .coulomb_nm;
    println!(
        "final brake capacity: plain {:.4}, remanence {:.4}, released {:.4} N·m; free-motion \
         torque {:.4} / {:.4} / {:.4} N·m; release time {:?} / {:?} / {:?}",
        final_capacity(&plain),
        final_capacity(&sticky),
        final_capacity(&released),
        plain.metrics.free_motion_torque_nm,
        sticky.metrics.free_motion_torque_nm,
        released.metrics.free_motion_torque_nm,
        plain.metrics.release_time_s,
        sticky.metrics.release_time_s,
        released.metrics.release_time_s,
    );
    // Without a release the brake keeps the remanent torque of its peak current (linear in the
    // peak below the reference 2 A); the pulse leaves 10 % of it.
    let peak = sticky.metrics.current_peak_a;
    assert!(peak > 0.1 && peak <= 2.0, "{peak}");
    let remanent = 0.175 * peak / 2.0;
    assert!((final_capacity(&plain) - rest).abs() < 1e-3);
    assert!((final_capacity(&sticky) - (rest + remanent)).abs() < 1e-3);
    assert!((final_capacity(&released) - (rest + 0.1 * remanent)).abs() < 1e-3);
    // The drag the hand feels from then on, and the free-motion torque (a peak over the run).
    let drag = |r: &HapticRun| r.metrics.drag_after_nm.outward;
    assert!((drag(&sticky) - drag(&released) - 0.9 * remanent).abs() < 1e-3);
    assert!(released.metrics.free_motion_torque_nm <= sticky.metrics.free_motion_torque_nm + 1e-9);
    // The pulse is negative, bounded, and over by the end of the run.
    let currents = &released.trace.as_ref().unwrap().current_a[0];
    let least = currents.iter().copied().fold(f64::INFINITY, f64::min);
    // The pulse's amplitude scales with the peak current like the remanence it removes.
    assert!((least + 0.3 * peak / 2.0).abs() < 1e-9, "{least}");
    assert!(currents.last().unwrap().abs() < f64::MIN_POSITIVE);
    assert!(sticky.trace.as_ref().unwrap().current_a[0].iter().all(|&i| i >= 0.0));
    // The release happens as the wall is left: it cannot delay leaving it.
    let (with, without) =
        (released.metrics.release_time_s.unwrap(), sticky.metrics.release_time_s.unwrap());
    assert!(with <= without + 1e-3, "{with} vs {without}");
}

#[test]
fn zero_remanence_without_release_is_the_plain_plant() {
    for device in [DeviceKind::Conventional, DeviceKind::Bidirectional] {
        let plain = run(device, None);
        let zero = PlantRemanence { remanent_torque_nm: 0.0, ..remanence(None) };
        let same = run(device, Some(zero));
        assert_eq!(plain.metrics, same.metrics, "{device:?}");
    }
}

#[test]
fn bad_remanence_settings_are_input_errors() {
    let mut config = HapticConfig::new(DeviceKind::Conventional, Scenario::PressWithdraw);
    config.remanence = Some(PlantRemanence { remanent_torque_nm: f64::NAN, ..remanence(None) });
    assert!(simulate(&config, false).unwrap_err().is_input_error());
    let mut bad_pulse = remanence(Some(0.1));
    if let Some(release) = bad_pulse.release.as_mut() {
        release.settings.waveform =
            DemagWaveform::ReversePulse { amplitude_a: -0.3, duration_s: 5e-3 };
    }
    config.remanence = Some(bad_pulse);
    let e = simulate(&config, false).unwrap_err();
    assert!(e.is_input_error());
    let chain = format!(
        "{e}: {}",
        std::error::Error::source(&e).map(|s| s.to_string()).unwrap_or_default()
    );
    assert!(chain.contains("amplitude_a"), "{chain}");
}
