//! CLI behaviour of `mrbrake fem solve` on `physics = "heat"` files: the shipped pot-core heat
//! example (steady: the JSON keys, heat out = Joule loss; transient: the history arrays),
//! a file with bad values (every field named with its line, exit code 2) and runaway Joule heating
//! (exit code 1 with a message naming the limit).

use crate::common;

use common::{expect_input_error, json, number};

use std::path::{Path, PathBuf};
use std::process::Command;

fn example(name: &str) -> String {
    let path: PathBuf = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/fem").join(name);
    path.to_str().expect("UTF-8 path").to_owned()
}

#[test]
fn steady_heat_file_reports_probes_regions_boundaries_and_balance() {
    let v = json(&["fem", "solve", &example("potcore-heat.toml"), "--json"]);
    assert_eq!(v["physics"], "heat");
    let regions = v["regions"].as_array().expect("regions");
    assert_eq!(regions.len(), 3);
    let coil = &regions[1];
    assert_eq!(coil["physical"], 2);
    let joule = number(coil, "heat_W");
    assert!(joule > 0.3 && joule < 1.0, "{joule}");
    assert!(number(coil, "max_T_C") >= number(coil, "mean_T_C"));
    let out = number(&v["boundaries"][0], "heat_out_W");
    assert!((out - joule).abs() < 1e-9 * joule, "{out} vs {joule}");
    assert!(number(&v, "energy_balance_W").abs() < 1e-9);
    let probe = &v["probes"][0];
    assert_eq!(probe["name"], "coil_centre");
    assert!(number(probe, "T_C") > 25.0 && number(probe, "r_m") > 0.0);
    assert!(v["transient"].is_null());
}

#[test]
fn transient_heat_file_reports_histories() {
    let v = json(&["fem", "solve", &example("potcore-warmup.toml"), "--json"]);
    let t = &v["transient"];
    let times = t["time_s"].as_array().expect("time_s");
    assert_eq!(times.len(), 721);
    let coil = t["probes"][0]["T_C"].as_array().expect("probe series");
    assert_eq!(coil.len(), times.len());
    assert!((coil[0].as_f64().unwrap() - 25.0).abs() < 1e-9);
    let series: Vec<f64> = coil.iter().map(|x| x.as_f64().unwrap()).collect();
    assert!(series.windows(2).all(|w| w[1] >= w[0] - 1e-12), "warming up monotonically");
    assert_eq!(t["regions"][1]["max_T_C"].as_array().expect("region series").len(), times.len());
    assert!(number(t, "max_energy_imbalance_W") < 1e-9);
}

#[test]
fn bad_heat_values_name_every_field_with_exit_code_2() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = example("potcore.msh");
    let text = format!(
        "physics = \"heat\"\nmesh = \"{mesh}\"\nlength_unit = \"mm\"\n[[region]]\nphysical = 1\n\
         material = {{ k_W_per_mK = -3, rho_kg_per_m3 = 7800, c_J_per_kgK = 450 }}\n[[region]]\n\
         physical = 2\nmaterial = \"air\"\n[[region]]\nphysical = 3\nmaterial = \"air\"\n\
         [[boundary]]\nphysical = 10\nkind = \"radiation\"\nemissivity = 1.5\nT_amb_C = -400\n"
    );
    let path = dir.path().join("bad.toml");
    std::fs::write(&path, text).unwrap();
    expect_input_error(
        &["fem", "solve", path.to_str().unwrap()],
        &[
            "bad.toml:6: region[0].material: k_W_per_mK = -3",
            "emissivity: = 1.5",
            "below absolute zero",
        ],
    );
}

#[test]
fn runaway_joule_heating_exits_1_naming_the_limit() {
    let dir = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(example("potcore-heat.toml"))
        .unwrap()
        .replace("mesh = \"potcore.msh\"", &format!("mesh = \"{}\"", example("potcore.msh")))
        .replace("current_A = 0.3", "current_A = 1.0");
    let path = dir.path().join("runaway.toml");
    std::fs::write(&path, text).unwrap();
    let output = Command::new(env!("CARGO_BIN_EXE_mrbrake"))
        .args(["fem", "solve", path.to_str().unwrap()])
        .output()
        .unwrap();
    assert_eq!(output.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(stderr.contains("thermal runaway"), "{stderr}");
}
