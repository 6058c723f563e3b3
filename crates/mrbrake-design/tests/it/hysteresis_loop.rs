//! The predicted torque–current hysteresis loop of a design (`mrbrake_design::hysteresis`): the
//! loop's shape follows from the steel's hysteresis (remanent torque, falling above rising), the
//! loop closes (the major-loop tip is reached again from either side: the play model's wiping-out
//! property), the first magnetisation is close to the anhysteretic analysis, the remanent torque
//! enters the off-state breakdown, and bad options are input errors naming their field.

use mrbrake_design::analysis::{AnalysisOptions, AnalysisRequest};
use mrbrake_design::hysteresis::{LoopOptions, run};
use mrbrake_design::mesh_build::MeshLevel;
use mrbrake_design::spec::default_spec;
use mrbrake_error::{ErrorKind, Kind};

fn options() -> AnalysisOptions {
    AnalysisOptions { mesh: MeshLevel::Coarse, points: 5, ..AnalysisOptions::default() }
}

#[test]
#[cfg_attr(not(heavy_tests), ignore = "release only: 70 non-linear solves of the thesis brake")]
fn the_thesis_brake_has_a_closed_loop_with_remanence() {
    let spec = default_spec();
    let loop_options = LoopOptions { peak_current_a: None, points_per_leg: 10 };
    let predicted = run(&spec, &options(), &loop_options).unwrap();
    let b = &predicted.branches;
    let n = b.current_a.len() - 1;
    assert!(predicted.remanent_torque_nm > 0.0, "{}", predicted.remanent_torque_nm);
    assert!(predicted.width_at_mid_current_nm > 0.0);
    assert!(predicted.bipolar_width_at_mid_current_nm >= predicted.width_at_mid_current_nm * 0.99);
    for k in 1..n {
        assert!(b.falling_nm[k] >= b.rising_nm[k] - 1e-9, "at {} A", b.current_a[k]);
    }
    // Wiping out: the tip is the same whichever way it is reached.
    let tip = b.initial_nm[n];
    for end in [b.rising_nm[n], b.bipolar_rising_nm[n], b.falling_nm[n]] {
        assert!((end - tip).abs() <= 1e-3 * tip, "tip {tip} vs {end}");
    }
    // The steel's loss per cycle is positive, and the field barely leaves each point's axis.
    assert!(predicted.dissipated_per_bipolar_cycle_j > 0.0);
    // The first magnetisation against the anhysteretic analysis on the library curve (the model's
    // normal curve is a fit of it): within 10 % at the peak.
    let analysis = AnalysisRequest::of(&spec).options(options()).run().unwrap();
    let anhysteretic = analysis.torque_current_curve.last().unwrap().torque_nm;
    assert!((tip - anhysteretic).abs() <= 0.1 * anhysteretic, "{tip} vs {anhysteretic}");
    let off = predicted.off_state_with_remanence(&analysis.torque_off);
    assert!((off.remanent_nm - predicted.remanent_torque_nm).abs() < 1e-15);
    let expected_total = analysis.torque_off.total_nm + predicted.remanent_torque_nm;
    assert!((off.total_nm - expected_total).abs() < 1e-12);
    assert!(off.sources.remanent.contains("hysteretic"));
}

#[test]
fn bad_loop_options_are_input_errors() {
    let spec = default_spec();
    for loop_options in [
        LoopOptions { peak_current_a: Some(-1.0), points_per_leg: 10 },
        LoopOptions { peak_current_a: Some(1e3), points_per_leg: 10 },
        LoopOptions { peak_current_a: None, points_per_leg: 0 },
        LoopOptions { peak_current_a: None, points_per_leg: usize::MAX },
    ] {
        let e = run(&spec, &options(), &loop_options).unwrap_err();
        assert_eq!(e.kind(), ErrorKind::Input, "{e}");
    }
}
