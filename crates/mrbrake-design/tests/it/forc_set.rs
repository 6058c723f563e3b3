//! The first-order reversal curves of a design (`mrbrake_design::forc`): the FORC set's major loop
//! (the rising branch from the reference state and the FORC from `I_max`) is the predicted loop of
//! `mrbrake_design::hysteresis` at the currents they share, whatever the chains; its FORCs lie
//! inside the major loop; and bad options are input errors naming their field.

use mrbrake_design::analysis::AnalysisOptions;
use mrbrake_design::forc::{ForcOptions, run};
use mrbrake_design::hysteresis::{self, LoopOptions};
use mrbrake_design::mesh_build::MeshLevel;
use mrbrake_design::spec::default_spec;
use mrbrake_error::{ErrorKind, Kind};

fn options() -> AnalysisOptions {
    AnalysisOptions { mesh: MeshLevel::Coarse, points: 5, ..AnalysisOptions::default() }
}

#[test]
#[cfg_attr(not(heavy_tests), ignore = "release only: 260 non-linear solves of the thesis brake")]
fn the_thesis_brakes_forc_major_loop_is_the_predicted_loop() {
    let spec = default_spec();
    let levels = 10;
    let forc_options = ForcOptions { levels, steps_per_level: 2, chains: Some(2) };
    let forcs = run(&spec, &options(), &forc_options).unwrap();
    // The loop on the same current steps: 20 per leg = 2 per level.
    let n = 20;
    let loop_options = LoopOptions { peak_current_a: None, points_per_leg: n };
    let predicted = hysteresis::run(&spec, &options(), &loop_options).unwrap();
    let yield_at = |index: usize| predicted.path[index].yield_torque_nm;
    let peak = forcs.rising_nm[levels];
    // Tolerance: 0.5 % of the peak torque (the chains' FORCs before the last start from the state
    // their previous FORC left at 0 A, not from the loop's: the wiping-out defect, below).
    let tolerance = 5e-3 * peak;
    for a in 0..=levels {
        let k = a * n / levels;
        // Rising: leg 3 (path[2n + k]); falling from I_max: leg 2 (path[n + (n − k)]).
        let rising = yield_at(2 * n + k);
        let falling = yield_at(n + (n - k));
        let forc_rising = forcs.rising_nm[a];
        let forc_falling = forcs.forcs_nm[levels][a];
        assert!(
            (forc_rising - rising).abs() <= tolerance,
            "rising at level {a}: {forc_rising} vs {rising}"
        );
        assert!(
            (forc_falling - falling).abs() <= tolerance,
            "falling at level {a}: {forc_falling} vs {falling}"
        );
    }
    assert!((forcs.rising_nm[0] - predicted.remanent_torque_nm).abs() <= tolerance);
    assert!(forcs.wiping_out_defect_nm <= tolerance, "{}", forcs.wiping_out_defect_nm);
    // Every FORC lies inside the major loop (above the rising branch, below the falling one).
    for (a, forc) in forcs.forcs_nm.iter().enumerate() {
        for (b, t) in forc.iter().enumerate() {
            assert!(*t >= forcs.rising_nm[b] - tolerance, "T({a}, {b}) = {t}");
            assert!(*t <= forcs.forcs_nm[levels][b] + tolerance, "T({a}, {b}) = {t}");
        }
    }
    assert_eq!(forcs.chains, 2);
    // Each chain walks the reference path (2 levels · 2 steps each way), each FORC 2k level steps.
    let forc_steps: usize = (1..=levels).map(|k| 2 * k * 2).sum();
    assert_eq!(forcs.solves, 2 * (2 * levels * 2) + forc_steps);
    eprintln!(
        "FORC set: {} solves, wall {:.1} s, chains {:.1} s; wiping-out defect {:.3e} N·m of {peak:.3} N·m",
        forcs.solves, forcs.timings_s.wall, forcs.timings_s.chains, forcs.wiping_out_defect_nm
    );
}

#[test]
fn bad_forc_options_are_input_errors() {
    let spec = default_spec();
    for forc_options in [
        ForcOptions { levels: 1, ..ForcOptions::default() },
        ForcOptions { levels: usize::MAX, ..ForcOptions::default() },
        ForcOptions { steps_per_level: 0, ..ForcOptions::default() },
        ForcOptions { chains: Some(0), ..ForcOptions::default() },
    ] {
        let e = run(&spec, &options(), &forc_options).unwrap_err();
        assert_eq!(e.kind(), ErrorKind::Input, "{e}");
    }
}
