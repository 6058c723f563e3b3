//! `explore::uncertainty` end to end on a coarse mesh: samples become stored designs (a second
//! run analyses none), the bands hold the nominal design, the torque–current band is read from
//! every sample's stored curve, and the Sobol' indices rank an input that scales the torque above
//! one that barely moves it.

use mrbrake_design::mesh_build::MeshLevel;
use mrbrake_design::spec::DEFAULT_SPEC_TOML;
use mrbrake_explore::EvaluationSettings;
use mrbrake_explore::uncertainty::{Declarations, UncertaintyRequest, propagate};
use mrbrake_observe::Silent;
use mrbrake_store::Store;

const INPUTS: &str = "[[input]]\npath = \"fluid.yield_stress_scale\"\ndistribution = \"uniform\"\n\
lower = 0.7\nupper = 1.1\n[[input]]\npath = \"envelope.length\"\ndistribution = \"uniform\"\n\
lower = \"0.2m\"\nupper = \"0.3m\"\n";

#[test]
fn samples_are_stored_designs_and_the_torque_follows_the_yield_scale() {
    let declarations = Declarations::from_toml_str(INPUTS, "inputs.toml", true).unwrap();
    let settings = EvaluationSettings {
        mesh: MeshLevel::Coarse,
        curve_points: 5,
        ..EvaluationSettings::default()
    };
    let request = UncertaintyRequest {
        spec_toml: DEFAULT_SPEC_TOML,
        spec_origin: "thesis.toml",
        declarations: &declarations,
        samples: 16,
        seed: 3,
        settings,
        metrics: vec!["torque_max_Nm".into(), "volume_m3".into()],
        bootstrap: 20,
        jobs: 2,
    };
    let dir = tempfile::tempdir().unwrap();
    let mut store = Store::open_or_create(&dir.path().join("u.store"), false).unwrap();
    let u = propagate(&mut store, &request, &mut Silent).unwrap();
    assert_eq!((u.samples, u.evaluated, u.computed), (16, 16, 17));
    let torque = &u.outputs.iter().find(|(m, _)| m == "torque_max_Nm").unwrap().1;
    let nominal = u.nominal.iter().find(|(m, _)| m == "torque_max_Nm").unwrap().1;
    // The yield scale spans 0.7..1.1 of the nominal fluid: the torque band straddles 0.9 x nominal.
    assert!(torque.p5 < 0.8 * nominal && torque.p95 > 0.95 * nominal, "{torque:?} vs {nominal}");
    // The envelope is a constraint, not the brake: it moves nothing; the volume is constant.
    let sobol = &u.sobol.iter().find(|(m, _)| m == "torque_max_Nm").unwrap().1;
    let (scale, envelope) = (&sobol.inputs[0].1, &sobol.inputs[1].1);
    assert!(scale.total > 0.95 && envelope.total < 0.05, "{scale:?} {envelope:?}");
    assert!(!u.sobol.iter().any(|(m, _)| m == "volume_m3"));
    // The band: 5 currents from 0 A to the maximum, ordered percentiles at each, the nominal
    // curve's torques, and at the maximum current exactly the torque_max_Nm statistics.
    let band = &u.torque_band;
    assert_eq!(band.len(), 5);
    assert!(band[0].current_a.abs() < 1e-15 && (band[4].current_a - 2.0).abs() < 1e-12);
    for (k, p) in band.iter().enumerate() {
        let t = p.torque;
        assert!(t.p5 <= t.p50 && t.p50 <= t.p95 && t.count == 16, "point {k}: {t:?}");
        assert!(k == 0 || band[k - 1].torque.p50 < t.p50, "the torque rises with the current");
    }
    assert_eq!(band[4].torque, *torque);
    assert_eq!(band[4].nominal_nm, Some(nominal));
    // Resumed: every sample comes from the store, its curve with it.
    let again = propagate(&mut store, &request, &mut Silent).unwrap();
    assert_eq!(again.computed, 0);
    assert_eq!(again.outputs[0].1, u.outputs[0].1);
    assert_eq!(again.torque_band, u.torque_band);
}
