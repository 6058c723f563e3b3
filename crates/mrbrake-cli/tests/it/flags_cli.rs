//! Issue 19, one voice across the CLI: quantities with units on every flag (the old unit-named
//! flags still accepted), one meaning for `--out` / `-o/--output` and one name for saving a model,
//! text output by default, plot paths refused unless `.svg` or `.png`, progress lines on stderr
//! when it is not a terminal, `optimize` budget overrides, and the wording fixes.
//!
//! The tests compare outputs of equivalent spellings with each other (never JSON keys, which
//! have their own convention test), so they check the parsing, not a number.

use crate::common;

use std::path::Path;
use std::process::{Command, Output};

use common::{expect_input_error, mrbrake, path_str};

const SPEC: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../../examples/specs/single-disc.toml");

/// Runs `mrbrake ARGS…` with `MRBRAKE_PROGRESS` set to `progress` (or unset).
fn mrbrake_with_progress(progress: Option<&str>, args: &[&str]) -> Output {
    let mut command = Command::new(env!("CARGO_BIN_EXE_mrbrake"));
    command.args(args).env_remove("MRBRAKE_PROGRESS");
    if let Some(value) = progress {
        command.env("MRBRAKE_PROGRESS", value);
    }
    command.output().expect("the mrbrake binary runs")
}

fn stdout_of(args: &[&str]) -> String {
    let out = mrbrake(args);
    assert!(out.status.success(), "{args:?}: {}", String::from_utf8_lossy(&out.stderr));
    String::from_utf8(out.stdout).expect("UTF-8 output")
}

fn wall(extra: &[&str]) -> String {
    let mut args = vec!["haptic", "wall", "--device", "bidirectional"];
    args.extend_from_slice(extra);
    stdout_of(&args)
}

#[test]
fn haptic_wall_gains_take_units_and_the_old_flags_still_work() {
    let default = wall(&[]);
    for spelling in [
        ["--stiffness", "30N·m/rad"],
        ["--stiffness", "30Nm/rad"],
        ["--stiffness", "30 N.m/rad"],
        ["--stiffness", "30000mNm/rad"],
        ["--stiffness", "30"],
        ["--stiffness-nm-per-rad", "30"],
    ] {
        assert_eq!(wall(&spelling), default, "{spelling:?}");
    }
    for spelling in [["--damping", "20mNms/rad"], ["--damping-nms-per-rad", "0.02"]] {
        assert_eq!(wall(&spelling), default, "{spelling:?}");
    }
    assert_ne!(wall(&["--stiffness", "40Nm/rad"]), default, "the flag is read");
    // Wrong dimension, negative value: input errors naming the flag and what is allowed.
    let base = ["haptic", "wall", "--device", "bidirectional"];
    let with = |flag: &'static str, value: &'static str| {
        let mut args = base.to_vec();
        args.extend([flag, value]);
        args
    };
    expect_input_error(&with("--stiffness", "30Nms/rad"), &["--stiffness", "N·m/rad"]);
    expect_input_error(
        &with("--stiffness", "-5Nm/rad"),
        &["--stiffness: haptic (got -5;", "allowed: [0, 100000]"],
    );
    expect_input_error(
        &with("--damping", "-1mNms/rad"),
        &["--damping: haptic (got -0.001;", "allowed: [0, 100]"],
    );
}

#[test]
fn haptic_zwidth_prints_text_by_default_and_takes_units() {
    let base = ["haptic", "zwidth", "--points", "4"];
    let run = |extra: &[&str]| {
        let mut args = base.to_vec();
        args.extend_from_slice(extra);
        stdout_of(&args)
    };
    let text = run(&[]);
    assert!(text.starts_with("Z-width map: 4 × 4 (K, B) pairs"), "{text}");
    assert!(serde_json::from_str::<serde_json::Value>(&text).is_err(), "text, not JSON: {text}");
    let json: serde_json::Value = serde_json::from_str(&run(&["--json"])).expect("--json is JSON");
    assert!(json.is_object());
    let units = run(&[
        "--stiffness-max",
        "50N·m/rad",
        "--damping-max",
        "30mNms/rad",
        "--physical-damping",
        "4mNms/rad",
        "--controllable-damping",
        "0.04Nms/rad",
    ]);
    let old = run(&[
        "--stiffness-max-nm-per-rad",
        "50",
        "--damping-max-nms-per-rad",
        "0.03",
        "--physical-damping-nms-per-rad",
        "0.004",
        "--controllable-damping-nms-per-rad",
        "0.04",
    ]);
    assert_eq!(units, old);
    assert_ne!(units, text);
    assert!(units.contains("K 0–50 N·m/rad, B 0–0.03 N·m·s/rad"), "{units}");
}

/// Every command with a plot-path flag refuses `.pdf`, another extension or none, before any
/// work (the inputs need not exist) and without writing anything.
#[test]
fn plot_paths_must_be_svg_or_png() {
    let dir = tempfile::tempdir().unwrap();
    for name in ["fig.pdf", "fig.jpeg", "fig"] {
        let plot = dir.path().join(name);
        let plot = path_str(&plot);
        let missing = path_str(dir.path()).to_string() + "/missing.csv";
        let commands: [Vec<&str>; 6] = [
            vec!["haptic", "wall", "--device", "conventional", "--plot", plot],
            vec!["haptic", "zwidth", "--points", "2", "--plot", plot],
            vec!["characterize", &missing, "--plot", plot],
            vec!["tfest", &missing, "--poles", "1", "--plot", plot],
            vec!["freqresp", &missing, "--plot", plot],
            vec!["fem", "solve", &missing, "--plot", plot],
        ];
        for args in commands {
            expect_input_error(&args, &[name, "unsupported plot format", ".svg, .png", "--plot"]);
        }
        assert!(!Path::new(plot).exists(), "{name} written");
    }
    // Upper case is the same format.
    let png = dir.path().join("wall.PNG");
    let out = mrbrake(&["haptic", "zwidth", "--points", "2", "--plot", path_str(&png)]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(std::fs::read(&png).unwrap().starts_with(b"\x89PNG"));
}

/// Writes a two-frequency test: input 1 + 0.5 sin(ωt), output 0.8 times it, 0.01 ω rad late (a
/// delay, so that the response varies with frequency: `tfest` refuses data without dynamics).
fn write_manifest(dir: &Path) -> std::path::PathBuf {
    let mut manifest = String::from("frequency_rad_s,file\n");
    for (k, omega) in [10.0f64, 30.0].into_iter().enumerate() {
        let mut log = String::from("time_s,input,output\n");
        for i in 0..4000 {
            let t = f64::from(i) * 1e-3;
            let input = 1.0 + 0.5 * (omega * t).sin();
            let output = 1.0 + 0.4 * (omega * t - 0.01 * omega).sin();
            log.push_str(&format!("{t},{input},{output}\n"));
        }
        let name = format!("log{k}.csv");
        std::fs::write(dir.join(&name), log).unwrap();
        manifest.push_str(&format!("{omega},{name}\n"));
    }
    let path = dir.join("manifest.csv");
    std::fs::write(&path, manifest).unwrap();
    path
}

/// `freqresp -o/--output FILE` writes a file; `--out`, a folder everywhere else, is refused here
/// (no hidden alias taking a file); `tfest --save-model` is the name of saving a model (`--save`
/// a hidden alias).
#[test]
fn output_files_and_saved_models_have_one_name() {
    let dir = tempfile::tempdir().unwrap();
    let manifest = write_manifest(dir.path());
    let mut written = Vec::new();
    for flag in ["-o", "--output"] {
        let frd = dir.path().join(format!("frd{flag}.csv"));
        let out = mrbrake(&["freqresp", path_str(&manifest), flag, path_str(&frd)]);
        assert!(out.status.success(), "{flag}: {}", String::from_utf8_lossy(&out.stderr));
        written.push(std::fs::read_to_string(&frd).expect("FRD written"));
    }
    assert!(written.windows(2).all(|w| w[0] == w[1]));
    let frd = dir.path().join("frd--out.csv");
    let out_flag = ["freqresp", path_str(&manifest), "--out", path_str(&frd)];
    expect_input_error(&out_flag, &["'--out'", "--output"]);
    assert!(!frd.exists(), "--out wrote a file");
    let frd = dir.path().join("frd-o.csv");
    let mut models = Vec::new();
    for flag in ["--save-model", "--save"] {
        let model = dir.path().join(format!("tf{flag}.json"));
        let args = ["tfest", path_str(&frd), "--poles", "1", flag, path_str(&model)];
        let out = mrbrake(&args);
        assert!(out.status.success(), "{flag}: {}", String::from_utf8_lossy(&out.stderr));
        models.push(std::fs::read_to_string(&model).expect("model written"));
    }
    assert_eq!(models[0], models[1]);
    let help = stdout_of(&["tfest", "--help"]);
    assert!(help.contains("--save-model") && !help.contains("--save "), "{help}");
    let help = stdout_of(&["freqresp", "--help"]);
    assert!(help.contains("-o, --output") && !help.contains("--out "), "{help}");
}

/// A negative quantity reaches the command's range check (exit 2, the flag and the allowed
/// range named) instead of clap's "unexpected argument '-1s'": every quantity flag takes a value
/// starting with a hyphen.
#[test]
fn negative_quantities_get_the_range_message() {
    let dir = tempfile::tempdir().unwrap();
    let manifest = write_manifest(dir.path());
    let manifest = path_str(&manifest);
    let cases: [(&[&str], &[&str]); 8] = [
        (&["response", "--duration", "-1s"], &["--duration: duration", "got -1 s", "> 0"]),
        (&["response", "--fluid-lag", "-1ms"], &["--fluid-lag", "got -0.001 s", ">= 0"]),
        (&["thermal", "--current", "-2A"], &["--current", "(0, 100] A"]),
        (&["thermal", "--period", "-1s"], &["--period", "> 0"]),
        (&["thermal", "--duty", "-0.5"], &["--duty", "(0, 1]"]),
        (&["freqresp", manifest, "--settle", "-1s"], &["--settle: got -1 s", ">= 0 s"]),
        (
            &["haptic", "wall", "--device", "conventional", "--stiffness", "-1"],
            &["--stiffness: haptic (got -1; allowed: [0, 100000])"],
        ),
        (
            &["haptic", "wall", "--device", "conventional", "--duration", "-1s"],
            &["--duration: haptic (got -1; allowed: [0.001, 3600])"],
        ),
    ];
    for (args, needles) in cases {
        expect_input_error(args, needles);
        let err = String::from_utf8_lossy(&mrbrake(args).stderr).into_owned();
        assert!(!err.contains("unexpected argument"), "{args:?}: {err}");
    }
}

#[test]
fn progress_lines_go_to_stderr_when_it_is_not_a_terminal() {
    // Short work is quiet by default (stderr is a pipe here).
    let quick = mrbrake_with_progress(None, &["haptic", "zwidth", "--points", "3"]);
    assert!(quick.status.success());
    assert!(quick.stderr.is_empty(), "{}", String::from_utf8_lossy(&quick.stderr));
    // MRBRAKE_PROGRESS=lines: every step, even for short work; stdout unchanged.
    let lines = mrbrake_with_progress(Some("lines"), &["haptic", "zwidth", "--points", "3"]);
    let err = String::from_utf8_lossy(&lines.stderr);
    for k in 1..=3 {
        assert!(err.contains(&format!("haptic zwidth: {k}/3 stiffness rows done")), "{err}");
    }
    assert_eq!(lines.stdout, quick.stdout);
    let off = mrbrake_with_progress(Some("off"), &["haptic", "zwidth", "--points", "3"]);
    assert!(off.stderr.is_empty());

    let analyze = ["analyze", SPEC, "--mesh", "coarse", "--points", "3", "--json"];
    let out = mrbrake_with_progress(Some("lines"), &analyze);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{err}");
    assert!(err.contains("analyze: 3/3 currents done"), "{err}");
    serde_json::from_slice::<serde_json::Value>(&out.stdout).expect("stdout stays pure JSON");

    let dir = tempfile::tempdir().unwrap();
    let store = dir.path().join("s.sqlite");
    let sweep = [
        "sweep",
        SPEC,
        "--vary",
        "g=0.4mm,0.6mm",
        "--mesh",
        "coarse",
        "--store",
        path_str(&store),
        "--json",
    ];
    let out = mrbrake_with_progress(Some("lines"), &sweep);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{err}");
    for k in 1..=2 {
        assert!(err.contains(&format!("sweep: {k}/2 designs done")), "{err}");
    }
    serde_json::from_slice::<serde_json::Value>(&out.stdout).expect("stdout stays pure JSON");
}

/// `optimize` progress lines count over the whole run with the generation, never restarting at
/// a new generation's batch and never "0/N".
#[test]
fn optimize_progress_lines_are_cumulative_with_the_generation() {
    let dir = tempfile::tempdir().unwrap();
    let objective = "[[objective]]\nmetric = \"rotor_inertia_kg_m2\"\n\
                     [[objective]]\nmetric = \"torque_max_Nm\"\ngoal = \"maximize\"";
    let nsga = problem(
        dir.path(),
        "progress.toml",
        objective,
        "kind = \"nsga2\"\npopulation = 4\ngenerations = 2\nseed = 5",
    );
    let store = dir.path().join("progress.sqlite");
    let args = ["optimize", path_str(&nsga), "--store", path_str(&store), "--json"];
    let out = mrbrake_with_progress(Some("lines"), &args);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{err}");
    serde_json::from_slice::<serde_json::Value>(&out.stdout).expect("stdout stays pure JSON");
    let lines: Vec<&str> = err.lines().filter(|l| l.starts_with("optimize: ")).collect();
    // (done, total) of each line: "optimize: generation 1/2, 6/12 designs done, …".
    let counts: Vec<(usize, usize)> = lines
        .iter()
        .map(|line| {
            let (_, rest) = line.split_once(", ").expect("a stage, then the count");
            let (count, _) = rest.split_once(" designs done").expect("designs done");
            let (done, total) = count.split_once('/').expect("done/total");
            (done.parse().unwrap(), total.parse().unwrap())
        })
        .collect();
    // Population 4 for the initial population and each of 2 generations (no reference design).
    assert!(counts.iter().all(|&(_, total)| total == 12), "{err}");
    assert!(counts.windows(2).all(|w| w[0].0 < w[1].0), "done must only grow: {err}");
    assert!(counts.iter().all(|&(done, _)| done > 0), "no 0/N line: {err}");
    assert_eq!(counts.last(), Some(&(12, 12)), "{err}");
    for stage in [
        "optimize: initial population, ",
        "optimize: generation 1/2, ",
        "optimize: generation 2/2, ",
    ] {
        assert!(lines.iter().any(|l| l.starts_with(stage)), "no line of {stage:?}: {err}");
    }
    assert!(!err.contains("0/0"), "{err}");
    // Replayed from the store: the same cumulative count, all designs reused.
    let mut resume = args.to_vec();
    resume.push("--resume");
    let out = mrbrake_with_progress(Some("lines"), &resume);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{err}");
    assert!(err.contains("optimize: generation 2/2, 12/12 designs done"), "{err}");
    assert!(!err.contains(" 0/"), "{err}");
}

/// A problem file `name` on the single-disc spec: gap g in 0.3–1 mm, `objectives`, `algorithm`.
fn problem(dir: &Path, name: &str, objectives: &str, algorithm: &str) -> std::path::PathBuf {
    let path = dir.join(name);
    let text = format!(
        "spec = \"{SPEC}\"\nmesh = \"coarse\"\nreference = false\n[[variable]]\nname = \"g\"\n\
         min = \"0.3mm\"\nmax = \"1mm\"\n{objectives}\n[algorithm]\n{algorithm}\n"
    );
    std::fs::write(&path, text).unwrap();
    path
}

#[test]
fn optimize_budget_overrides_make_a_quick_run() {
    let dir = tempfile::tempdir().unwrap();
    let two = "[[objective]]\nmetric = \"rotor_inertia_kg_m2\"\n\
               [[objective]]\nmetric = \"torque_max_nm\"\ngoal = \"maximize\"";
    let nsga = problem(
        dir.path(),
        "nsga.toml",
        two,
        "kind = \"nsga2\"\npopulation = 4\ngenerations = 50\nseed = 3",
    );
    let store = dir.path().join("quick.sqlite");
    let args = ["optimize", path_str(&nsga), "--store", path_str(&store), "--generations", "1"];
    let out = mrbrake_with_progress(Some("off"), &args);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    // One generation after the initial population (not the file's 50), said in the singular.
    assert!(text.contains(": 1 generation;"), "{text}");
    assert!(!text.contains("1 generations") && !text.contains("of 1 designs"), "{text}");

    let other = dir.path().join("other.sqlite");
    expect_input_error(
        &["optimize", path_str(&nsga), "--store", path_str(&other), "--max-evaluations", "3"],
        &["--max-evaluations: less than one generation", "got 3", ">= 4"],
    );
    let one = "[[objective]]\nmetric = \"rotor_inertia_kg_m2\"";
    let ps = problem(dir.path(), "ps.toml", one, "kind = \"pattern-search\"");
    expect_input_error(
        &["optimize", path_str(&ps), "--store", path_str(&other), "--generations", "2"],
        &["--generations: applies to NSGA-II", "max_evaluations"],
    );
    assert!(!other.exists(), "an input error creates no store");
}

#[test]
fn formula_wording() {
    let coil =
        ["formula", "coil", "--window-width", "12mm", "--window-height", "12mm", "--awg", "24"];
    let text = stdout_of(&coil);
    let line = text.lines().find(|l| l.contains("resistance")).expect("a resistance line");
    assert_eq!(line.matches('Ω').count(), 1, "at 20 °C the resistance once: {line}");
    let mut hot = coil.to_vec();
    hot.extend(["--temperature", "75C"]);
    let text = stdout_of(&hot);
    let line = text.lines().find(|l| l.contains("resistance")).expect("a resistance line");
    assert!(line.contains("at 20 °C") && line.contains("at 75 °C"), "{line}");

    // The library's rule names its fields (the CLI's flags are --tau-y and --b).
    expect_input_error(
        &["formula", "single-disc", "--r1", "10mm", "--r2", "20mm"],
        &["tau_y or b", "flux density"],
    );
    let drum = [
        "formula",
        "multi-drum",
        "--r0",
        "25mm",
        "--h",
        "9mm",
        "--d",
        "1mm",
        "--g",
        "0.5mm",
        "--tau-y",
        "25kPa",
        "--surfaces",
        "100000000",
    ];
    expect_input_error(&drum, &["--surfaces", "got 100000000", "1 to 100"]);
}

#[test]
fn materials_list_names_the_thesis_steel_right() {
    let text = stdout_of(&["materials", "list"]);
    let line = text.lines().find(|l| l.contains("steel-1020")).expect("steel-1020 listed");
    assert!(!line.contains("the thesis's flux-path steel"), "{line}");
    assert!(line.contains("AISI 1008"), "{line}");
}

/// A printed command (the provenance of a brake model) quotes a path with spaces.
#[test]
fn printed_commands_quote_paths_with_spaces() {
    let dir = tempfile::tempdir().unwrap();
    let spec = dir.path().join("my brake.toml");
    std::fs::copy(SPEC, &spec).unwrap();
    let model = dir.path().join("model.json");
    let out = mrbrake(&[
        "analyze",
        path_str(&spec),
        "--mesh",
        "coarse",
        "--points",
        "2",
        "--save-model",
        path_str(&model),
    ]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let text = std::fs::read_to_string(&model).unwrap();
    let quoted = format!("mrbrake analyze '{}' (", spec.display());
    assert!(text.contains(&quoted), "{text}");
}
