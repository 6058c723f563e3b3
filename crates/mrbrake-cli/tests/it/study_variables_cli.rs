//! Study variables a designer changes, through the binary (issue 27): a part's material as a
//! variable of `sweep`, `optimize --set PATH=VALUE` fixing a field (and the problem's variable on
//! it), and the bad inputs of material and fixed variables: exit 2 naming the file, the key and
//! what is allowed.
//!
//! The studies use the single-disc example on the coarse mesh so the debug suite stays quick.

use crate::common;

use std::path::{Path, PathBuf};

use common::{expect_input_error, json, mrbrake, path_str};

const SPEC: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../../examples/specs/single-disc.toml");

/// A problem file in `dir` with the single-disc spec, the coarse mesh, no reference design, the
/// front designs written as evaluated (no rounding, so the store holds the optimiser's designs
/// only), one mass objective and `variables` (TOML of `[[variable]]` tables) and `algorithm`
/// (TOML lines of `[algorithm]`).
fn problem(dir: &Path, variables: &str, algorithm: &str) -> PathBuf {
    let path = dir.join("problem.toml");
    let text = format!(
        "spec = \"{SPEC}\"\nmesh = \"coarse\"\nreference = false\n\
         manufacturing_resolution = 0\n{variables}\n\
         [[objective]]\nmetric = \"mass_kg\"\n[algorithm]\n{algorithm}\n"
    );
    std::fs::write(&path, text).unwrap();
    path
}

const NSGA2: &str = "kind = \"nsga2\"\npopulation = 4\ngenerations = 0\nseed = 5";

#[test]
fn optimize_set_fixes_a_field_and_the_variable_on_it() {
    let dir = tempfile::tempdir().unwrap();
    let variables = "[[variable]]\nname = \"g\"\nmin = \"0.4mm\"\nmax = \"0.8mm\"\n\
                     [[variable]]\nname = \"materials.bobbin\"\nvalues = [\"aluminium\", \"pom\"]";
    let path = problem(dir.path(), variables, NSGA2);
    let (store, out_dir) = (dir.path().join("o.sqlite"), dir.path().join("out"));
    let args = [
        "optimize",
        path_str(&path),
        "--set",
        "materials.bobbin=pom",
        "--set",
        "coil.max_current=1.5A",
        "--store",
        path_str(&store),
        "--out",
        path_str(&out_dir),
        "--json",
    ];
    let out = mrbrake(&args);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    assert!(
        stderr.contains("--set materials.bobbin=pom: variable 'materials.bobbin' is fixed"),
        "{stderr}"
    );
    let designs = json(&["export", path_str(&store), "--json"]);
    let designs = designs.as_array().unwrap();
    assert_eq!(designs.len(), 4);
    for d in designs {
        let names: Vec<&String> = d["variables"].as_object().unwrap().keys().collect();
        assert_eq!(names, ["g"], "the fixed material is not a variable");
        let current = d["metrics"]["max_current_A"].as_f64().unwrap();
        assert!((current - 1.5).abs() < 1e-12, "{current}");
    }
    let front = std::fs::read_to_string(out_dir.join("designs").join("front-01.toml")).unwrap();
    assert!(front.contains("bobbin = \"pom\""), "{front}");

    // A --set that fixes every variable leaves nothing to optimise; a --set without '=' is refused.
    let all = ["optimize", path_str(&path), "--set", "g=0.5mm", "--set", "materials.bobbin=pom"];
    expect_input_error(&all, &["problem.toml", "set: fixes every variable"]);
    expect_input_error(
        &["optimize", path_str(&path), "--set", "g"],
        &["--set: expected PATH=VALUE (got 'g'", "PATH=VALUE"],
    );
}

#[test]
fn a_sweep_over_a_material_reports_it_by_name() {
    let dir = tempfile::tempdir().unwrap();
    let store = dir.path().join("s.sqlite");
    let args = [
        "sweep",
        SPEC,
        "--vary",
        "materials.bobbin=aluminium,pom",
        "--mesh",
        "coarse",
        "--store",
        path_str(&store),
    ];
    let out = mrbrake(&args);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let rows: Vec<&str> = text.lines().filter(|l| l.contains(" ok ")).collect();
    assert_eq!(rows.len(), 2, "{text}");
    assert!(
        rows[0].trim_start().starts_with("aluminium") && rows[1].trim_start().starts_with("pom")
    );
    // The example's window is filled by the turn formula beyond what can be wound.
    assert!(text.contains("warning: 2 designs fill the coil window"), "{text}");
    let csv = dir.path().join("s.csv");
    let out = mrbrake(&["export", path_str(&store), "--csv", path_str(&csv)]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let csv = std::fs::read_to_string(&csv).unwrap();
    assert!(csv.starts_with("key,status,reason,materials.bobbin,"), "{csv}");
    assert!(csv.contains(",pom,") && csv.contains(",aluminium,"), "{csv}");
}

#[test]
fn bad_material_and_fixed_variables_exit_2_naming_the_key_and_what_is_allowed() {
    let dir = tempfile::tempdir().unwrap();
    let cases: [(&str, &str, &[&str]); 6] = [
        (
            "[[variable]]\nname = \"materials.bobbin\"\nvalues = [\"aluminium\", \"unobtainium\"]",
            NSGA2,
            &[
                "problem.toml",
                "materials.bobbin",
                ".values",
                "'unobtainium'",
                "pom",
                "stainless-304",
            ],
        ),
        (
            "[[variable]]\nname = \"materials.bobbin\"\nvalues = []",
            NSGA2,
            &["problem.toml", ".values", "at least one material", "pom"],
        ),
        (
            "[[variable]]\nname = \"materials.bobbin\"\nvalues = [\"steel-1008\", \"pom\"]",
            NSGA2,
            &["problem.toml", "materials.bobbin", "steel-1008", "does not suit", "pom"],
        ),
        (
            "[[variable]]\nname = \"g\"\nvalues = [\"0.5mm\", \"0.6mm\"]",
            NSGA2,
            &["problem.toml", "variable[1].values", "materials.bobbin", "min and max"],
        ),
        (
            "[[variable]]\nname = \"g\"\nmin = \"0.8mm\"\nmax = \"0.4mm\"",
            NSGA2,
            &["problem.toml", "variable[1].max", "min ≤ max", "0.0008", "0.0004"],
        ),
        (
            "[[variable]]\nname = \"materials.bobbin\"\nvalues = [\"aluminium\", \"pom\"]",
            "kind = \"pattern-search\"\nmax_evaluations = 4",
            &["problem.toml", "algorithm.kind", "nsga2", "aluminium, pom"],
        ),
    ];
    for (variables, algorithm, needles) in cases {
        let path = problem(dir.path(), variables, algorithm);
        expect_input_error(&["optimize", path_str(&path)], needles);
        assert!(!dir.path().join("problem.sqlite").exists(), "a refused problem leaves no store");
    }
    let store = dir.path().join("s.sqlite");
    let sweep = |vary: &str| {
        vec!["sweep", SPEC, "--vary", vary, "--store", path_str(&store)]
            .into_iter()
            .map(String::from)
            .collect::<Vec<_>>()
    };
    for (vary, needles) in [
        (
            "materials.bobbin=pom,unobtainium",
            &["materials.bobbin", "'unobtainium'", "aluminium"][..],
        ),
        (
            "materials.bobbin=aluminium..pom",
            &["--vary: a material takes a list", "list of names"][..],
        ),
        ("materials.bobbin=", &["materials.bobbin", "at least one material"][..]),
    ] {
        let args = sweep(vary);
        let refs: Vec<&str> = args.iter().map(String::as_str).collect();
        expect_input_error(&refs, needles);
    }
    assert!(!store.exists(), "a refused sweep leaves no store");
}
