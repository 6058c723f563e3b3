//! Demagnetising releases on the predicted loop (`mrbrake_design::demag`): on the thesis brake the
//! chosen reverse pulse leaves less remanent torque than a plain release to 0 A, the scan's chosen
//! pulse is its least, and bad options are input errors naming their field.

use mrbrake_design::analysis::AnalysisOptions;
use mrbrake_design::demag::{Candidate, DemagOptions, Release, run};
use mrbrake_design::mesh_build::MeshLevel;
use mrbrake_design::spec::default_spec;
use mrbrake_error::{ErrorKind, Kind};

fn options() -> AnalysisOptions {
    AnalysisOptions { mesh: MeshLevel::Coarse, points: 5, ..AnalysisOptions::default() }
}

#[test]
#[cfg_attr(not(heavy_tests), ignore = "release only: ~300 non-linear solves of the thesis brake")]
fn the_chosen_pulse_leaves_less_remanence_than_no_release() {
    let spec = default_spec();
    let demag = DemagOptions {
        points_per_leg: 6,
        scan_points: 5,
        golden_steps: 3,
        ..DemagOptions::default()
    };
    let d = run(&spec, &options(), &demag).unwrap();
    println!("{}", serde_json::to_string_pretty(&d).unwrap());
    let without = d.remanent_torque_without_nm;
    assert!(without > 0.0, "{without}");
    assert!(d.chosen_pulse.remanent_torque_nm < without, "{:?}", d.chosen_pulse);
    assert!(d.chosen_pulse.remanence_fraction < 1.0);
    let Release::ReversePulse { amplitude_a } = d.chosen_pulse.release else {
        panic!("the chosen release is a pulse: {:?}", d.chosen_pulse.release)
    };
    assert!(amplitude_a > 0.0 && amplitude_a <= d.reverse_limit_a);
    // The chosen pulse is the least of every pulse tried.
    for c in &d.candidates {
        if matches!(c.release, Release::ReversePulse { .. }) {
            assert!(c.remanent_torque_nm >= d.chosen_pulse.remanent_torque_nm, "{c:?}");
        }
    }
    // The largest pulse (the full peak current backwards: the scan ends at min(I_p, a_max))
    // magnetises the steel the other way: it leaves more than the chosen one.
    let end = d.reverse_limit_a.min(d.peak_current_a);
    let is_end = |c: &&Candidate| match c.release {
        Release::ReversePulse { amplitude_a } => (amplitude_a - end).abs() < 1e-12,
        _ => false,
    };
    let largest = d.candidates.iter().find(is_end).expect("the scan ends at min(I_p, a_max)");
    assert!(largest.remanent_torque_nm > d.chosen_pulse.remanent_torque_nm);
    // The decaying alternating current also demagnetises.
    assert!(d.decaying_ac.remanent_torque_nm < without, "{:?}", d.decaying_ac);
}

#[test]
fn bad_demag_options_are_input_errors() {
    let spec = default_spec();
    for demag in [
        DemagOptions { reverse_limit_a: Some(-1.0), ..DemagOptions::default() },
        DemagOptions { reverse_limit_a: Some(f64::NAN), ..DemagOptions::default() },
        DemagOptions { ac_decay_ratio: 1.0, ..DemagOptions::default() },
        DemagOptions { scan_points: usize::MAX, ..DemagOptions::default() },
        DemagOptions { ac_half_cycles: 1_000_000, ..DemagOptions::default() },
    ] {
        let e = run(&spec, &options(), &demag).unwrap_err();
        assert_eq!(e.kind(), ErrorKind::Input, "{e}");
        assert!(e.to_string().contains("demag_"), "{e}");
    }
}
