//! Writing a spec as TOML and reading it back gives the same spec (design studies write their chosen
//! designs this way), for every shipped example.

use mrbrake_design::spec::BrakeSpec;

#[test]
fn every_example_spec_round_trips_through_toml() {
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/../../examples/specs");
    let mut checked = 0;
    for entry in std::fs::read_dir(dir).expect("examples/specs exists") {
        let path = entry.expect("readable entry").path();
        if path.extension().and_then(|e| e.to_str()) != Some("toml") {
            continue;
        }
        let spec = BrakeSpec::from_path(&path).expect("example parses");
        let text = spec.to_toml_string().expect("serialises");
        let back = BrakeSpec::from_toml_str(&text, "round trip").expect("reads back");
        assert_eq!(spec, back, "{}", path.display());
        checked += 1;
    }
    assert!(checked >= 4, "only {checked} example specs found");
}
