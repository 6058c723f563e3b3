//! Design studies end to end through the binary: shards in separate processes merge to the
//! single-process result; a sweep killed with SIGKILL at a random point resumes without losing or
//! duplicating a design; corrupt or foreign stores are refused untouched; a small optimisation writes
//! its outputs and replays from the store; a surrogate-assisted optimisation killed with SIGKILL
//! resumes from its stored designs without losing or recomputing one.
//!
//! The plans use the single-disc example on the coarse mesh so the debug suite stays quick.

use crate::common;

use std::collections::BTreeMap;
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Instant, SystemTime, UNIX_EPOCH};

use common::{expect_input_error, json, mrbrake, path_str};

const SPEC: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../../examples/specs/single-disc.toml");

/// The plan of the tests: 4 gaps × 3 disc thicknesses, plus one infeasible outer radius.
fn plan_args(store: &Path) -> Vec<String> {
    [
        SPEC,
        "--vary",
        "g=0.3mm..0.9mm:4",
        "--vary",
        "d=1mm,1.5mm,2mm",
        "--mesh",
        "coarse",
        "--store",
        path_str(store),
        "--json",
    ]
    .iter()
    .map(|s| s.to_string())
    .collect()
}

fn sweep(store: &Path, extra: &[&str]) -> serde_json::Value {
    let mut args: Vec<String> = vec!["sweep".into()];
    args.extend(plan_args(store));
    args.extend(extra.iter().map(|s| s.to_string()));
    let refs: Vec<&str> = args.iter().map(String::as_str).collect();
    json(&refs)
}

/// The store's designs by key: (status, metrics).
fn exported(store: &Path) -> BTreeMap<String, (String, BTreeMap<String, f64>)> {
    let v = json(&["export", path_str(store), "--json"]);
    let mut map = BTreeMap::new();
    for d in v.as_array().expect("an array of designs") {
        let key = d["key"].as_str().expect("key").to_string();
        let status = d["status"].as_str().expect("status").to_string();
        let metrics: BTreeMap<String, f64> = d["metrics"]
            .as_object()
            .expect("metrics object")
            .iter()
            .filter_map(|(k, v)| v.as_f64().map(|x| (k.clone(), x)))
            .collect();
        assert!(map.insert(key.clone(), (status, metrics)).is_none(), "key {key} twice");
    }
    map
}

/// Same designs, same statuses, same metrics (to 1e-9 relative: the energy sum is parallel, so the
/// last bits may differ between runs).
fn assert_same_results(
    a: &BTreeMap<String, (String, BTreeMap<String, f64>)>,
    b: &BTreeMap<String, (String, BTreeMap<String, f64>)>,
) {
    assert_eq!(a.keys().collect::<Vec<_>>(), b.keys().collect::<Vec<_>>(), "different designs");
    for (key, (status, metrics)) in a {
        let (status_b, metrics_b) = &b[key];
        assert_eq!(status, status_b, "{key}");
        assert_eq!(metrics.keys().collect::<Vec<_>>(), metrics_b.keys().collect::<Vec<_>>());
        for (name, x) in metrics {
            let y = metrics_b[name];
            assert!((x - y).abs() <= 1e-9 * x.abs().max(1e-30), "{key} {name}: {x} vs {y}");
        }
    }
}

#[test]
fn shards_in_separate_processes_merge_to_the_single_process_result() {
    let dir = tempfile::tempdir().unwrap();
    let single = dir.path().join("single.sqlite");
    let v = sweep(&single, &["--jobs", "2"]);
    assert_eq!(v["summary"]["computed"].as_u64(), Some(12));
    let reference = exported(&single);
    assert_eq!(reference.len(), 12);

    let n = 3;
    let children: Vec<_> = (0..n)
        .map(|k| {
            let store = dir.path().join(format!("shard-{k}.sqlite"));
            let mut args: Vec<String> = vec!["sweep".into()];
            args.extend(plan_args(&store));
            args.extend(["--shard".to_string(), format!("{k}/{n}"), "--jobs".into(), "1".into()]);
            Command::new(env!("CARGO_BIN_EXE_mrbrake"))
                .args(&args)
                .stdout(Stdio::null())
                .stderr(Stdio::piped())
                .spawn()
                .expect("spawn a shard")
        })
        .collect();
    for child in children {
        let out = child.wait_with_output().unwrap();
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    }
    let merged = dir.path().join("merged.sqlite");
    let shard_paths: Vec<String> = (0..n)
        .map(|k| path_str(&dir.path().join(format!("shard-{k}.sqlite"))).to_string())
        .collect();
    let mut args = vec!["merge", path_str(&merged)];
    args.extend(shard_paths.iter().map(String::as_str));
    let out = mrbrake(&args);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    // Each shard holds a third of the plan, and no design is in two shards.
    let sizes: Vec<usize> =
        (0..n).map(|k| exported(&dir.path().join(format!("shard-{k}.sqlite"))).len()).collect();
    assert_eq!(sizes, vec![4, 4, 4]);
    assert_same_results(&reference, &exported(&merged));

    // Merging again adds nothing.
    let out = mrbrake(&args);
    assert!(String::from_utf8_lossy(&out.stdout).contains("12 designs (0 added)"));
}

#[test]
fn a_sweep_killed_at_a_random_point_resumes_without_loss_or_duplicates() {
    let dir = tempfile::tempdir().unwrap();
    let reference_store = dir.path().join("reference.sqlite");
    let t0 = Instant::now();
    sweep(&reference_store, &["--jobs", "1"]);
    let duration = t0.elapsed();
    let reference = exported(&reference_store);

    // Kill at pseudo-random points until two kills have landed inside a running sweep (the
    // process killed with designs still to compute).
    let args = |store: &Path| {
        let mut args: Vec<String> = vec!["sweep".into()];
        args.extend(plan_args(store));
        args.extend(["--jobs".to_string(), "1".to_string()]);
        args
    };
    kill_and_resume(dir.path(), duration, &args, |store, killed| {
        let before = if store.exists() { exported(store) } else { BTreeMap::new() };
        for key in before.keys() {
            assert!(reference.contains_key(key), "a design not in the plan: {key}");
        }
        let v = sweep(store, &["--resume", "--jobs", "1"]);
        let computed = v["summary"]["computed"].as_u64().unwrap() as usize;
        let reused = v["summary"]["reused"].as_u64().unwrap() as usize;
        assert_eq!(reused, before.len(), "every stored design is reused");
        assert_eq!(computed + reused, 12, "nothing recomputed, nothing missing");
        assert_same_results(&reference, &exported(store));
        eprintln!("{} of 12 designs stored; resume computed {computed}", before.len());
        killed && before.len() < 12
    });
}

/// `mrbrake ARGS`'s JSON on stdout.
fn run_json(args: &[String]) -> serde_json::Value {
    json(&args.iter().map(String::as_str).collect::<Vec<_>>())
}

/// Runs `mrbrake ARGS(store)` into fresh stores and SIGKILLs it at pseudo-random points (10 % to
/// 90 % of `duration`, the uninterrupted run's) until two kills have landed mid-run; `resume`
/// checks each store after its kill (whether the process was killed, not finished) and says
/// whether the kill landed mid-run. A kill after the run finished (the reference run, the first,
/// pays for cold caches) halves the time scale for the next try.
fn kill_and_resume(
    dir: &Path,
    duration: std::time::Duration,
    args: &dyn Fn(&Path) -> Vec<String>,
    mut resume: impl FnMut(&Path, bool) -> bool,
) {
    let (mut interrupted, mut scale) = (0, 1.0);
    for attempt in 0.. {
        assert!(attempt < 10, "no kill landed inside a running study in 10 attempts");
        let nanos = SystemTime::now().duration_since(UNIX_EPOCH).unwrap().subsec_nanos();
        let fraction = scale * (0.1 + 0.8 * f64::from(nanos % 1000) / 1000.0);
        let store = dir.join(format!("killed-{attempt}.sqlite"));
        let mut child = Command::new(env!("CARGO_BIN_EXE_mrbrake"))
            .args(args(&store))
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .unwrap();
        std::thread::sleep(duration.mul_f64(fraction));
        child.kill().expect("SIGKILL the study"); // SIGKILL on Unix
        let killed = !child.wait().unwrap().success();
        eprint!("kill at {:.0} % of {:.2} s: ", fraction * 100.0, duration.as_secs_f64());
        if resume(&store, killed) {
            interrupted += 1;
            if interrupted == 2 {
                break;
            }
        } else {
            scale *= 0.5;
        }
    }
}

#[test]
fn corrupt_and_foreign_stores_are_refused_and_left_untouched() {
    let dir = tempfile::tempdir().unwrap();
    let garbage = dir.path().join("garbage.sqlite");
    let bytes: Vec<u8> = (0..8192u32).map(|i| (i.wrapping_mul(2654435761) >> 13) as u8).collect();
    std::fs::write(&garbage, &bytes).unwrap();
    let mut args: Vec<String> = vec!["sweep".into()];
    args.extend(plan_args(&garbage));
    args.push("--resume".into());
    let refs: Vec<&str> = args.iter().map(String::as_str).collect();
    expect_input_error(&refs, &["garbage.sqlite"]);
    assert_eq!(std::fs::read(&garbage).unwrap(), bytes, "the file was modified");
    expect_input_error(&["export", path_str(&garbage), "--json"], &["garbage.sqlite"]);

    // Without --resume an existing file is never overwritten.
    let refs: Vec<&str> = refs[..refs.len() - 1].to_vec();
    expect_input_error(&refs, &["--resume"]);
    assert_eq!(std::fs::read(&garbage).unwrap(), bytes);

    expect_input_error(&["export", "/nonexistent/store.sqlite"], &["/nonexistent/store.sqlite"]);
    expect_input_error(
        &["sweep", SPEC, "--vary", "gapp=1mm", "--store", path_str(&dir.path().join("x.sqlite"))],
        &["gapp", "drum.gap"],
    );
    expect_input_error(
        &[
            "sweep",
            SPEC,
            "--vary",
            "g=1mm..0.5mm:3",
            "--store",
            path_str(&dir.path().join("y.sqlite")),
        ],
        &["g=1mm..0.5mm:3"],
    );
    // A negative speed is the library's input error, before any store is created.
    let z = dir.path().join("z.sqlite");
    expect_input_error(
        &["sweep", SPEC, "--vary", "g=1mm", "--speed=-1rad/s", "--store", path_str(&z)],
        &["speed", ">= 0"],
    );
    assert!(!z.exists(), "a refused sweep leaves no store");
}

#[test]
fn a_small_optimisation_writes_its_outputs_and_replays_from_the_store() {
    let dir = tempfile::tempdir().unwrap();
    let problem = dir.path().join("problem.toml");
    std::fs::write(
        &problem,
        format!(
            r#"
spec = "{SPEC}"
mesh = "coarse"
[[variable]]
name = "g"
min = "0.3mm"
max = "1mm"
[[variable]]
name = "d"
min = "1mm"
max = "2mm"
[[constraint]]
metric = "torque_max_Nm"
min = "0.5Nm"
[[objective]]
metric = "rotor_inertia_kg_m2"
[[objective]]
metric = "torque_max_Nm"
goal = "maximize"
[algorithm]
kind = "nsga2"
population = 4
generations = 1
seed = 7
"#
        ),
    )
    .unwrap();
    let out_dir = dir.path().join("out");
    let store = dir.path().join("opt.sqlite");
    let args = [
        "optimize",
        path_str(&problem),
        "--store",
        path_str(&store),
        "--out",
        path_str(&out_dir),
        "--json",
    ];
    let first = json(&args);
    let evaluated = first["evaluated"].as_u64().unwrap();
    assert!(evaluated >= 5, "reference + 2 batches of 4, minus repeats: {evaluated}");
    for file in ["evaluations.csv", "pareto.csv", "pareto.svg", "constraints.svg"] {
        assert!(out_dir.join(file).exists(), "{file} missing");
    }
    let front = first["front"].as_array().unwrap();
    assert!(!front.is_empty());
    // Every front design is written as a spec that analyses as it is.
    let design = out_dir.join("designs").join("front-01.toml");
    let v = json(&["analyze", path_str(&design), "--mesh", "coarse", "--points", "2", "--json"]);
    assert!(v["torque"]["at_max_current_Nm"].as_f64().unwrap() > 0.5);

    // The seeded optimiser replays the same designs from the store: nothing recomputed.
    let mut resume = args.to_vec();
    resume.push("--resume");
    let second = json(&resume);
    assert_eq!(second["computed"].as_u64(), Some(0));
    assert_eq!(second["evaluated"], first["evaluated"]);
    assert_eq!(second["front"], first["front"]);
}

#[test]
fn a_single_objective_pattern_search_returns_one_feasible_best_design() {
    let dir = tempfile::tempdir().unwrap();
    let problem = dir.path().join("single.toml");
    std::fs::write(
        &problem,
        format!(
            r#"
spec = "{SPEC}"
mesh = "coarse"
reference = false
[[variable]]
name = "R2"
min = "24mm"
max = "30mm"
[[constraint]]
metric = "torque_max_nm"
min = "1.2Nm"
[[objective]]
metric = "rotor_inertia_kg_m2"
[algorithm]
kind = "pattern-search"
max_evaluations = 10
"#
        ),
    )
    .unwrap();
    let store = dir.path().join("single.sqlite");
    // The problem names the torque by its legacy metric name: it still works, with a note.
    let out = mrbrake(&["optimize", path_str(&problem), "--store", path_str(&store), "--json"]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    assert!(stderr.contains("'torque_max_nm' is now named 'torque_max_Nm'"), "{stderr}");
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).expect("JSON on stdout");
    let front = v["front"].as_array().unwrap();
    assert_eq!(front.len(), 1, "one objective: the best feasible design");
    let best = &front[0]["metrics"];
    assert!(best["torque_max_Nm"].as_f64().unwrap() >= 1.2);
    let evaluated = v["evaluated"].as_u64().unwrap();
    assert!((2..=10).contains(&evaluated), "budget respected: {evaluated}");
    // Every evaluated design meeting the torque has at least the best design's inertia.
    let all = json(&["export", path_str(&store), "--json"]);
    let best_j = best["rotor_inertia_kg_m2"].as_f64().unwrap();
    for d in all.as_array().unwrap() {
        let m = &d["metrics"];
        if m["torque_max_Nm"].as_f64().is_some_and(|t| t >= 1.2) {
            assert!(m["rotor_inertia_kg_m2"].as_f64().unwrap() >= best_j * (1.0 - 1e-12));
        }
    }
}

/// A small sweep of the single-disc example over the gaps `gaps` into `store`, as JSON.
fn gap_sweep(store: &Path, gaps: &str, extra: &[&str]) -> serde_json::Value {
    let vary = format!("g={gaps}");
    let mut args = vec!["sweep", SPEC, "--vary", &vary, "--mesh", "coarse", "--store"];
    args.extend([path_str(store), "--json"]);
    args.extend_from_slice(extra);
    json(&args)
}

/// Asserts that every design of `designs` (a JSON array) names its metrics the current way.
fn assert_current_names(designs: &serde_json::Value) {
    for design in designs.as_array().expect("an array of designs") {
        let metrics = design["metrics"].as_object().expect("metrics");
        assert!(metrics.contains_key("torque_max_Nm"), "{design}");
        for (old, _) in mrbrake::explore::evaluate::LEGACY_METRIC_NAMES {
            assert!(!metrics.contains_key(*old), "legacy {old} in {design}");
        }
    }
}

/// A store written before the unit convention (`torque_max_nm`, …) exports under the current
/// names, merges with a store of the same designs under the new names without a conflict (in
/// either direction), and resumes.
#[test]
fn a_store_with_the_old_metric_names_exports_merges_and_resumes() {
    let dir = tempfile::tempdir().expect("temporary directory");
    let new = dir.path().join("new.sqlite");
    gap_sweep(&new, "0.4mm,0.6mm", &[]);
    // The old store: the same records under the legacy names, written through the store (which
    // computes each record's checksum, as the old version did).
    let old = dir.path().join("old.sqlite");
    {
        let source = mrbrake::store::Store::open_read_only(&new).expect("new store");
        let mut target = mrbrake::store::Store::create(&old).expect("old store");
        for mut record in source.records().expect("records") {
            for (name, _) in &mut record.metrics {
                let legacy = mrbrake::explore::evaluate::LEGACY_METRIC_NAMES.iter();
                if let Some((old_name, _)) = legacy.clone().find(|(_, current)| current == name) {
                    *name = (*old_name).to_string();
                }
            }
            assert!(target.insert(&record).expect("insert"));
        }
        let stored = target.records().expect("records");
        assert!(stored.iter().all(|r| r.metric("torque_max_nm").is_some()), "legacy names kept");
        target.close().expect("close");
    }

    assert_current_names(&json(&["export", path_str(&old), "--json"]));
    assert_same_results(&exported(&new), &exported(&old));

    for (name, first, second) in [("a.sqlite", &new, &old), ("b.sqlite", &old, &new)] {
        let merged = dir.path().join(name);
        let out = mrbrake(&["merge", path_str(&merged), path_str(first), path_str(second)]);
        let text = String::from_utf8_lossy(&out.stdout);
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
        assert!(!text.contains("CONFLICTS"), "{text}");
        let second_line = format!("{}: 0 added, 2 already present\n", second.display());
        assert!(text.contains(&second_line), "{text}");
        assert!(text.ends_with(&format!("{}: 2 designs (2 added)\n", merged.display())), "{text}");
        assert_current_names(&json(&["export", path_str(&merged), "--json"]));
    }

    // Resuming the old store reuses its two designs and reports every design by the new names.
    let resumed = gap_sweep(&old, "0.4mm,0.6mm,0.8mm", &["--resume"]);
    assert_current_names(&resumed["designs"]);
    assert_eq!(resumed["designs"].as_array().map(Vec::len), Some(3), "{resumed}");
    assert_current_names(&json(&["export", path_str(&old), "--json"]));
}

/// A surrogate-assisted problem on the single-disc example: 10 designs from an initial plan of 4,
/// batch 2, written as evaluated (no rounding, so every stored design is one the algorithm chose).
fn surrogate_problem(dir: &Path) -> std::path::PathBuf {
    let problem = dir.join("surrogate.toml");
    std::fs::write(
        &problem,
        format!(
            r#"
spec = "{SPEC}"
mesh = "coarse"
manufacturing_resolution = 0
[[variable]]
name = "g"
min = "0.3mm"
max = "1mm"
[[variable]]
name = "R2"
min = "24mm"
max = "30mm"
[[constraint]]
metric = "torque_max_Nm"
min = "0.8Nm"
[[objective]]
metric = "rotor_inertia_kg_m2"
[[objective]]
metric = "torque_max_Nm"
goal = "maximize"
[algorithm]
kind = "surrogate"
max_evaluations = 10
initial_size = 4
batch = 2
seed = 11
"#
        ),
    )
    .unwrap();
    problem
}

#[test]
fn a_surrogate_optimisation_killed_at_a_random_point_resumes_without_loss() {
    let dir = tempfile::tempdir().unwrap();
    let problem = surrogate_problem(dir.path());
    let args_with = |store: &Path, extra: &[&str]| -> Vec<String> {
        let mut a: Vec<String> = ["optimize", path_str(&problem), "--store", path_str(store)]
            .iter()
            .map(|s| s.to_string())
            .collect();
        a.extend(["--jobs", "1", "--json"].iter().chain(extra).map(|s| s.to_string()));
        a
    };
    let reference_store = dir.path().join("reference.sqlite");
    let t0 = Instant::now();
    let full = run_json(&args_with(&reference_store, &[]));
    let duration = t0.elapsed();
    assert_eq!(full["evaluated"], 10, "{full}");
    assert_eq!(full["algorithm"], "surrogate");
    assert_eq!(full["surrogate"]["stop"], "budget");
    assert!(full["hypervolume"]["value"].as_f64().is_some_and(|v| v > 0.0), "{full}");

    let args = |store: &Path| args_with(store, &[]);
    kill_and_resume(dir.path(), duration, &args, |store, killed| {
        let before = if store.exists() { exported(store) } else { BTreeMap::new() };
        let v = run_json(&args_with(store, &["--resume"]));
        let after = exported(store);
        // Every design stored before the kill is still there, unchanged, and none is computed
        // twice: what the resumed run computed is exactly what the store gained.
        let kept: BTreeMap<_, _> = after
            .iter()
            .filter(|(k, _)| before.contains_key(*k))
            .map(|(k, v)| (k.clone(), v.clone()))
            .collect();
        assert_same_results(&before, &kept);
        let computed = v["computed"].as_u64().unwrap() as usize;
        assert_eq!(before.len() + computed, after.len(), "{v}");
        assert_eq!(v["evaluated"], 10, "the budget counts the stored designs: {v}");
        // The reference design (the base spec) is stored first and is not a design of the search.
        let designs_before = before.len().saturating_sub(1);
        let mid_run = killed && designs_before < 10;
        if mid_run {
            assert_eq!(v["surrogate"]["resumed_from"], designs_before, "{v}");
        }
        eprintln!("{} records stored; resume computed {computed}", before.len());
        mid_run
    });
}

#[test]
fn surrogate_settings_out_of_range_are_input_errors_naming_the_key() {
    let dir = tempfile::tempdir().unwrap();
    let problem = surrogate_problem(dir.path());
    let text = std::fs::read_to_string(&problem).unwrap();
    for (from, to, key) in [
        ("batch = 2", "batch = 0", "algorithm.batch"),
        ("initial_size = 4", "initial_size = 2", "algorithm.initial_size"),
        ("seed = 11", "seed = 11\nacquisition = \"parego\"", "acquisition"),
    ] {
        let bad = dir.path().join("bad.toml");
        std::fs::write(&bad, text.replace(from, to)).unwrap();
        let store = dir.path().join("bad.sqlite");
        expect_input_error(&["optimize", path_str(&bad), "--store", path_str(&store)], &[key]);
        assert!(!store.exists(), "a refused problem leaves no store");
    }
    let store = dir.path().join("g.sqlite");
    expect_input_error(
        &["optimize", path_str(&problem), "--store", path_str(&store), "--generations", "2"],
        &["--generations: applies to NSGA-II"],
    );
}
