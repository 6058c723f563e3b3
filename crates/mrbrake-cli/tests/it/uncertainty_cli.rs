//! `mrbrake uncertainty`: the JSON contract of issue 29 on a small coarse run (with the torque
//! band and the plots), a resumed run analysing nothing, the report's uncertainty section from the
//! saved JSON, and bad declarations or documents exiting 2 with the file and the key.

use crate::common;

use common::{expect_input_error, json, mrbrake, path_str};

const INPUTS: &str = "[[input]]\npath = \"fluid.yield_stress_scale\"\ndistribution = \"normal\"\n\
mean = 1.0\nstd = 0.1\ntruncate = [0.7, 1.3]\n[[input]]\npath = \"fluid.fill_fraction\"\n\
distribution = \"uniform\"\nlower = 0.8\nupper = 1.0\n";

#[test]
fn the_json_has_the_contracted_keys_and_a_resumed_run_analyses_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let inputs = dir.path().join("inputs.toml");
    std::fs::write(&inputs, INPUTS).unwrap();
    let store = dir.path().join("u.store");
    let plots = dir.path().join("plots");
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
        "--curve-points",
        "3",
        "--plots",
        path_str(&plots),
        "--json",
    ];
    let v = json(&args);
    let band = v["torque_band"].as_array().unwrap();
    assert_eq!(band.len(), 3, "{band:?}");
    for p in band {
        let at = |key: &str| p[key].as_f64().unwrap_or_else(|| panic!("{key}: {p}"));
        assert!(at("p5_Nm") <= at("p50_Nm") && at("p50_Nm") <= at("p95_Nm"), "{p}");
        assert!(at("mean_Nm").is_finite() && at("std_Nm") >= 0.0 && at("current_A") >= 0.0);
    }
    assert_eq!(band[2]["p95_Nm"], v["outputs"]["torque_max_Nm"]["p95"]);
    for name in ["torque_band.svg", "tornado.svg"] {
        let bytes = std::fs::metadata(plots.join(name)).map(|m| m.len()).unwrap_or(0);
        assert!(bytes > 1000, "{name}: {bytes} bytes");
    }
    // The report's section from the saved JSON (a bad file fails before the analysis).
    let saved = dir.path().join("u.json");
    std::fs::write(&saved, serde_json::to_string(&v).unwrap()).unwrap();
    let html = dir.path().join("r.html");
    let report = ["report", "-o", path_str(&html), "--mesh", "coarse", "--points", "3"];
    let out = mrbrake(&[&report[..], &["--uncertainty", path_str(&saved)]].concat());
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let page = std::fs::read_to_string(&html).unwrap();
    assert!(page.contains("<section id=\"uncertainty\">") && page.contains("torque–current band"));
    assert!(page.contains("3.840 N·m at 2.000 A is"), "the thesis prototype's point is judged");
    std::fs::write(&saved, "{\"samples\": 8}").unwrap();
    expect_input_error(
        &[&report[..], &["--uncertainty", path_str(&saved)]].concat(),
        &[path_str(&saved), "mrbrake uncertainty --json"],
    );
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
    assert_eq!(again["torque_band"], v["torque_band"]);
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
    let inputs = dir.path().join("inputs.toml");
    std::fs::write(&inputs, INPUTS).unwrap();
    for count in ["1", "42"] {
        let store = dir.path().join(format!("points{count}.store"));
        let args = ["uncertainty", "--inputs", path_str(&inputs), "--store", path_str(&store)];
        expect_input_error(&[&args[..], &["--curve-points", count]].concat(), &["--curve-points"]);
    }
}
