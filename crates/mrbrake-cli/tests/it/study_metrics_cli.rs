//! The dynamics and heat metrics of studies through the binary: listed with their units, stored
//! by `sweep --record` equal to `mrbrake response`'s JSON, and bad input refused with exit 2
//! before any analysis (no store left behind).

use crate::common;

use common::{expect_input_error, json, mrbrake, path_str};

const THESIS: &str =
    concat!(env!("CARGO_MANIFEST_DIR"), "/../../examples/specs/thesis-bidirectional.toml");

#[test]
fn list_metrics_shows_the_dynamics_and_heat_metrics_with_units() {
    let out = mrbrake(&["optimize", "--list-metrics"]);
    assert!(out.status.success());
    let text = String::from_utf8_lossy(&out.stdout);
    for (name, unit) in [
        ("bandwidth_rad_s", "rad/s"),
        ("t63_fall_s", "s"),
        ("t90_dir2_s", "s"),
        ("continuous_torque_Nm", "N·m"),
        ("coil_max_T_C", "°C"),
        ("max_duty_at_max_current", "1"),
    ] {
        let line = text.lines().find(|l| l.starts_with(&format!("{name} "))).unwrap_or_default();
        assert!(line.split_whitespace().nth(1) == Some(unit), "{name}: '{line}'");
    }
}

#[test]
fn unknown_or_impossible_metrics_exit_2_before_any_analysis() {
    let dir = tempfile::tempdir().unwrap();
    let store = dir.path().join("s.sqlite");
    let store = path_str(&store);
    expect_input_error(
        &["sweep", THESIS, "--vary", "g=0.5mm", "--record", "t64_s", "--store", store],
        &["--record", "t64_s", "unknown metric"],
    );
    assert!(!std::path::Path::new(store).exists(), "no store for a refused sweep");
    // A flux path the library gives no conductivity for cannot give a dynamics metric.
    let spec = dir.path().join("motorproto.toml");
    let text = std::fs::read_to_string(THESIS)
        .unwrap()
        .replace("flux_path = \"steel-1008\"", "flux_path = \"steel-1010-motorproto\"");
    std::fs::write(&spec, text).unwrap();
    let problem = dir.path().join("p.toml");
    std::fs::write(
        &problem,
        "spec = \"motorproto.toml\"\n[[variable]]\nname = \"g\"\nmin = \"0.4mm\"\nmax = \
         \"0.6mm\"\n[[objective]]\nmetric = \"t63_fall_s\"\n[algorithm]\nkind = \"nsga2\"\n",
    )
    .unwrap();
    let store = dir.path().join("p.sqlite");
    expect_input_error(
        &["optimize", path_str(&problem), "--store", path_str(&store)],
        &["p.toml", "t63_fall_s", "conductivity", "steel-1010-motorproto"],
    );
    assert!(!store.exists(), "no store for a refused problem");
}

/// `sweep --record t63_fall_s` stores the release's t63 of `mrbrake response --step 2A..0A` (the
/// thesis brake's maximum current is 2 A), and the fall time of direction 2.
#[test]
#[cfg_attr(not(heavy_tests), ignore = "release only: two step responses per direction")]
fn a_recorded_fall_time_equals_the_response_command() {
    let dir = tempfile::tempdir().unwrap();
    let store = dir.path().join("s.sqlite");
    let store = path_str(&store);
    let args = ["--mesh", "coarse", "--json"];
    let sweep_args = ["sweep", THESIS, "--vary", "g=0.5mm", "--store", store];
    let records = ["--record", "t63_fall_s", "--record", "t90_fall_dir2_s"];
    json(&[&sweep_args[..], &records[..], &args[..]].concat());
    let exported = json(&["export", store, "--json"]);
    let metrics = &exported[0]["metrics"];
    let command = json(&[&["response", THESIS, "--step", "2A..0A"][..], &args[..]].concat());
    let pairs = [
        ("t63_fall_s", &command["step"][0]["t63_s"]),
        ("t90_fall_dir2_s", &command["step"][1]["t90_s"]),
    ];
    for (name, expected) in pairs {
        let (stored, expected) = (metrics[name].as_f64().unwrap(), expected.as_f64().unwrap());
        assert!((stored - expected).abs() <= 1e-9 * expected, "{name}: {stored} vs {expected}");
    }
    assert_eq!(exported[0]["settings"]["metrics_asked"], "t63_fall_s t90_fall_dir2_s");
}

/// `sweep --resume` asking for one more metric completes the stored designs: the same keys,
/// one evaluation each (the missing metric), the stored metrics kept; once complete, nothing runs.
#[test]
fn a_resumed_sweep_with_one_more_metric_completes_the_stored_designs() {
    let dir = tempfile::tempdir().unwrap();
    let store = dir.path().join("s.sqlite");
    let store = path_str(&store);
    let base = ["sweep", THESIS, "--vary", "g=0.45mm,0.55mm", "--mesh", "coarse", "--store", store];
    let first = json(&[&base[..], &["--json"]].concat());
    assert_eq!(first["summary"]["computed"], 2, "{first}");
    let more = [&base[..], &["--resume", "--record", "coil_max_T_C", "--json"]].concat();
    let second = json(&more);
    assert_eq!(
        (&second["summary"]["computed"], &second["summary"]["reused"]),
        (&2.into(), &0.into())
    );
    let third = json(&more);
    assert_eq!(
        (&third["summary"]["computed"], &third["summary"]["reused"]),
        (&0.into(), &2.into())
    );
    let exported = json(&["export", store, "--json"]);
    let records = exported.as_array().unwrap();
    assert_eq!(records.len(), 2, "completed in place, not added: {exported}");
    let keys = |v: &serde_json::Value| -> Vec<String> {
        v["designs"].as_array().unwrap().iter().map(|d| d["key"].to_string()).collect()
    };
    assert_eq!(keys(&first), keys(&second), "the metric list is not part of the key");
    for r in records {
        assert!(
            r["metrics"]["torque_max_Nm"].is_number() && r["metrics"]["coil_max_T_C"].is_number(),
            "{r}"
        );
    }
}
