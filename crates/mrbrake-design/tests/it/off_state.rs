//! The off-state torque's breakdown (`[drag]`, `mrbrake_design::drag`) through a whole analysis:
//! the terms add up, the constant friction shifts every point of the curve by exactly its value,
//! a spec without `[drag]` is the viscous torque alone with every other term stated, and the
//! rotors' magnetic pull loads the bearings.

use mrbrake_design::analysis::{Analysis, AnalysisOptions, AnalysisRequest};
use mrbrake_design::mesh_build::MeshLevel;
use mrbrake_design::spec::{BrakeSpec, DEFAULT_SPEC_TOML};

const DRAG: &str = r#"
[drag]
seals_per_rotor = 2
seal_torque = "20 mNm"
seal_source = "a test value"
bearings = 2
bearing_kind = "deep-groove-ball"
bearing_bore = "10 mm"
bearing_load = "40 N"
freewheel_drag = "5 mNm"
freewheel_source = "a test value"
"#;

fn analyse(toml: &str) -> Analysis {
    let spec = BrakeSpec::from_toml_str(toml, "test.toml").expect("a valid spec");
    let options =
        AnalysisOptions { mesh: MeshLevel::Coarse, points: 3, ..AnalysisOptions::default() };
    AnalysisRequest::of(&spec).options(options).run().expect("the analysis runs")
}

fn close(a: f64, b: f64, tol: f64) -> bool {
    (a - b).abs() <= tol * (1.0 + a.abs().max(b.abs()))
}

#[test]
fn the_breakdown_adds_up_and_shifts_the_whole_curve() {
    let bare = analyse(DEFAULT_SPEC_TOML);
    let with_drag = analyse(&format!("{DEFAULT_SPEC_TOML}\n{DRAG}"));

    // Without [drag]: the viscous torque alone, every other term stated.
    let b = &bare.torque_off;
    assert!(close(b.total_nm, b.viscous_nm, 1e-14));
    assert!(close(b.total_nm, bare.torque.off_state_nm, 1e-12), "{b:?}");
    assert!(b.sources.seal.contains("not given") && b.sources.remanent.contains("not modelled"));

    // With it: seals 2 × 0.02, bearings ½ × 0.0015 × (2 × 40 N) × 0.01 m, freewheel 0.005
    // (below the idle rotor's 0.04 N·m of seals and its viscous drag).
    let d = &with_drag.torque_off;
    assert!(close(d.seal_nm, 0.04, 1e-14));
    assert!(close(d.bearing_nm, 0.5 * 0.0015 * 80.0 * 0.01, 1e-14));
    assert!(close(d.freewheel_nm, 0.005, 1e-14));
    let sum = d.viscous_nm + d.seal_nm + d.bearing_nm + d.freewheel_nm + d.remanent_nm;
    assert!(close(d.total_nm, sum, 1e-14));
    assert!(close(with_drag.torque.off_state_nm, d.total_nm, 1e-12));

    // The constant friction moves every torque by exactly its value, nothing else.
    let friction = d.constant_friction_nm();
    for (p, q) in bare.torque_current_curve.iter().zip(&with_drag.torque_current_curve) {
        assert!(close(q.torque_nm - p.torque_nm, friction, 1e-12));
        assert!(close(q.yield_torque_nm, p.yield_torque_nm, 1e-14));
    }
    let dir2 = |a: &Analysis| a.torque.direction2_at_max_current_nm.expect("bidirectional");
    assert!(close(dir2(&with_drag) - dir2(&bare), friction, 1e-12));
}

#[test]
fn the_rotors_magnetic_pull_loads_the_bearings() {
    let a = analyse(&format!("{DEFAULT_SPEC_TOML}\n{DRAG}"));
    let f = &a.rotor_forces;
    assert_eq!(f.units.len(), 2, "both units' rotating steel: {f:?}");
    assert!(f.units.iter().all(|u| u.axial_force_n.is_finite() && !u.parts.is_empty()));
    let total: f64 = f.units.iter().map(|u| u.axial_force_n).sum();
    assert!(close(f.total_axial_force_n, total, 1e-14));
    let load = 2.0 * 40.0 + total.abs();
    assert!(close(f.bearing_friction_nm, 0.5 * 0.0015 * load * 0.01, 1e-12));
    println!("axial pull at {} A: {:?}", f.current_a, f.units);
}

#[test]
fn bad_drag_fields_are_named_with_their_range() {
    let bad = format!(
        "{DEFAULT_SPEC_TOML}\n[drag]\nseals_per_rotor = 2\nbearings = 100\nbearing_load = \"-3 N\"\n"
    );
    let err = BrakeSpec::from_toml_str(&bad, "bad.toml")
        .and_then(|s| s.validate().map(|_| ()))
        .expect_err("refused");
    let text = format!("{err}");
    for field in ["drag.seal_torque", "drag.bearings", "drag.bearing_load"] {
        assert!(text.contains(field), "{field} not in: {text}");
    }
}
