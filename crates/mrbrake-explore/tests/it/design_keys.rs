//! The results store's design keys are pinned: a key is the SHA-256 of the spec's JSON (field names,
//! `null` for absent options), its materials' curves, the settings and the model revision, so a
//! refactoring of `BrakeSpec` that changed its JSON would silently orphan every stored result. These
//! values were computed before the brake configuration became a payload enum (issue 12) and must
//! not change unless `MODEL_REVISION` is bumped on purpose.

use mrbrake_design::spec::{BrakeSpec, default_spec};
use mrbrake_explore::EvaluationSettings;
use mrbrake_explore::design::design_key;

fn example(name: &str) -> BrakeSpec {
    let path =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/specs").join(name);
    BrakeSpec::from_path(&path).expect("example spec parses")
}

fn key(spec: &BrakeSpec) -> String {
    design_key(spec, &EvaluationSettings::default()).expect("a valid spec has a key")
}

#[test]
fn design_keys_of_the_shipped_specs_are_pinned() {
    let cases = [
        (
            "embedded default",
            key(&default_spec()),
            "cb30de5516413efdb122781e48dc3808fb348db60aca0a4eead54d89e7dee151",
        ),
        (
            "single-disc.toml",
            key(&example("single-disc.toml")),
            "7a6c4e0f6af094f6e116278e38a204ab50a3168bfc11679a7693b9ac84601a56",
        ),
        (
            "multi-disc.toml",
            key(&example("multi-disc.toml")),
            "4894ae54ce5bd3c6ebdbc7bade585840d86f5e1b5945d1b305ca907e07e9364b",
        ),
        (
            "drum.toml",
            key(&example("drum.toml")),
            "a153128409d37e28b82d44c76d137764599d3c0eb5bc6b19a58869a22c1d60d3",
        ),
        (
            "concept-multi-disc.toml",
            key(&example("concept-multi-disc.toml")),
            "a5c900b108b01f69ffe16dcfba9244055fc070198635deb18f47bd81cfa65e60",
        ),
        (
            "study-single-disc.toml",
            key(&example("study-single-disc.toml")),
            "758dccd7b12730f57dabae5c193348960a3f1b1e368735749a0c8f1ec82f2fe3",
        ),
    ];
    for (name, got, want) in cases {
        assert_eq!(got, want, "design key of {name} changed");
    }
}

#[test]
fn design_keys_of_study_points_are_pinned() {
    let space = |variables: &[&str]| {
        mrbrake_explore::DesignSpace::new(
            mrbrake_design::spec::DEFAULT_SPEC_TOML,
            "default",
            &[("coil.turns".to_string(), "fill".to_string())],
            &variables.iter().map(|v| v.to_string()).collect::<Vec<_>>(),
            EvaluationSettings::default(),
        )
        .expect("the default space")
    };
    let valid = space(&["g", "n"]).design(&[0.6e-3, 3.0]).expect("a design");
    assert!(valid.spec.is_ok());
    let invalid = space(&["drum.gap"]).design(&[-1e-3]).expect("a design");
    assert!(invalid.spec.is_err());
    let disc = mrbrake_explore::DesignSpace::new(
        &std::fs::read_to_string(
            std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
                .join("../../examples/specs/multi-disc.toml"),
        )
        .expect("the example"),
        "multi-disc.toml",
        &[],
        &["R2".to_string(), "AWG".to_string()],
        EvaluationSettings::default(),
    )
    .expect("the multi-disc space")
    .design(&[0.03, 26.0])
    .expect("a design");
    let cases = [
        (
            "default g=0.6mm n=3",
            valid.key,
            "8910a02531b356afdbdc8e1432ece3ef90cdfd4d2ff33cc160858c727bbcad76",
        ),
        (
            "default drum.gap=-1mm (invalid)",
            invalid.key,
            "8d480f28ac198df0fd63f486b3fb062e1dec6108912f7188ce4ae8d2b25ad542",
        ),
        (
            "multi-disc R2=30mm AWG=26",
            disc.key,
            "d276f287796387d76bd15913c0de92c26b3462ac050c735542507dc2882933b7",
        ),
    ];
    for (name, got, want) in cases {
        assert_eq!(got, want, "design key of {name} changed");
    }
}
