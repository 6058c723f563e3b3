//! `mrbrake uncertainty`: the JSON contract of issue 29 on a small coarse run, a resumed run
//! analysing nothing, and bad declarations exiting 2 with the file and the key.

mod common;

use common::{expect_input_error, json, path_str};

const INPUTS: &str = "[[input]]\npath = \"fluid.yield_stress_scale\"\ndistribution = \"normal\"\n\
mean = 1.0\nstd = 0.1\ntruncate = [0.7, 1.3]\n[[input]]\npath = \"fluid.fill_fraction\"\n\
distribution = \"uniform\"\nlower = 0.8\nupper = 1.0\n";

#[test]
fn the_json_has_the_contracted_keys_and_a_resumed_run_analyses_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let inputs = dir.path().join("inputs.toml");
    std::fs::write(&inputs, INPUTS).unwrap();
    let store = dir.path().join("u.store");
    let args = [
        "uncertainty",
        "--inputs",
        path_str(&inputs),
        "--samples",
        "8",
        "--mesh",
        "coarse",
        "--bootstrap",
        "10",
        "--store",
        path_str(&store),
        "--json",
    ];
    let v = json(&args);
    assert_eq!(v["samples"], 8);
    assert_eq!(v["inputs"][0]["name"], "fluid.yield_stress_scale");
    assert_eq!(v["inputs"][0]["distribution"], "normal");
    let torque = &v["outputs"]["torque_max_Nm"];
    for key in ["mean", "std", "p5", "p50", "p95"] {
        assert!(torque[key].is_number(), "{key}: {torque}");
    }
    let s = &v["sobol"]["torque_max_Nm"]["fluid.yield_stress_scale"];
    for key in ["first", "total", "first_ci", "total_ci"] {
        assert!(!s[key].is_null(), "{key}: {s}");
    }
    assert_eq!(v["surrogate"]["kind"], "polynomial_chaos");
    assert!(v["surrogate"]["loo_error"].is_number() && v["timings_s"]["total"].is_number());
    let mut resumed = args.to_vec();
    resumed.push("--resume");
    let again = json(&resumed);
    assert_eq!(again["computed"], 0);
    assert_eq!(again["outputs"], v["outputs"]);
}

#[test]
fn bad_declarations_exit_2_naming_the_file_and_key() {
    let dir = tempfile::tempdir().unwrap();
    let cases = [
        (
            "[[input]]\npath = \"drum.gapp\"\ndistribution = \"uniform\"\nlower = 1\nupper = 2\n",
            "input[1].path",
        ),
        (
            "[[input]]\npath = \"drum.gap\"\ndistribution = \"normal\"\nmean = \"0.5mm\"\nstd = -1\n",
            "input[1].",
        ),
        (
            "[[input]]\npath = \"fluid.fill_fraction\"\ndistribution = \"uniform\"\nlower = 0.9\nupper = 1.1\n",
            "input[1].distribution",
        ),
    ];
    for (k, (text, key)) in cases.iter().enumerate() {
        let file = dir.path().join(format!("bad{k}.toml"));
        std::fs::write(&file, text).unwrap();
        let store = dir.path().join(format!("bad{k}.store"));
        expect_input_error(
            &["uncertainty", "--inputs", path_str(&file), "--store", path_str(&store)],
            &[path_str(&file), key],
        );
    }
}
