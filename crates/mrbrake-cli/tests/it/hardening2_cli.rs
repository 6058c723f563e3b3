//! Issue 33 through the binary: every example of its classes as a regression test. A command
//! either answers with trustworthy numbers (no NaN or infinity anywhere in what it prints or
//! writes) or refuses, naming the file or flag, and then writes nothing.

use crate::common;

use std::path::Path;

use common::{expect_input_error, json, mrbrake, path_str};

const SPEC: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../../examples/specs/single-disc.toml");

/// True when `text` spells a non-finite number as a value (`NaN`, `inf`, `-inf`).
fn has_non_finite(text: &str) -> bool {
    text.split(|c: char| !(c.is_ascii_alphanumeric() || c == '-'))
        .any(|w| matches!(w.trim_start_matches('-'), "NaN" | "nan" | "inf" | "Infinity"))
}

/// Class 1: a step response over 1e6 s no longer interpolates t63 inside one giant first step
/// (it reported 63 s): the first step is bounded by the brake's own time scales, and a rise time
/// is reported only when the steps resolve it.
#[test]
#[cfg_attr(not(heavy_tests), ignore = "release only: transients of a brake")]
fn a_long_duration_keeps_the_rise_time_of_a_few_milliseconds() {
    let v = json(&["response", SPEC, "--mesh", "coarse", "--duration", "1e6s", "--json"]);
    for step in v["step"].as_array().expect("step responses") {
        match step["t63_s"].as_f64() {
            Some(t63) => assert!(t63 < 0.05, "t63 = {t63} s is not the brake's: {step}"),
            None => assert!(step["t63_s"].is_null()),
        }
        let time = step["time_s"].as_array().expect("time levels");
        let first = time[1].as_f64().expect("a number");
        assert!(first < 1e-3, "first step {first} s jumps over the response");
    }
    let short = json(&["response", SPEC, "--mesh", "coarse", "--json"]);
    let (long_t63, short_t63) =
        (v["step"][0]["t63_s"].as_f64(), short["step"][0]["t63_s"].as_f64());
    if let (Some(a), Some(b)) = (long_t63, short_t63) {
        assert!((a - b).abs() < 0.2 * b, "t63 {a} s over 1e6 s, {b} s over 100 ms");
    }
}

/// Class 1: a zero bias has no small-signal gain (the yield torque is flat at 0 A): an input
/// error naming the flag, not a table of NaN magnitudes; `--frd` then writes nothing. A bias above
/// the coil's maximum current is refused too.
#[test]
#[cfg_attr(not(heavy_tests), ignore = "release only: a frequency response of a brake")]
fn a_bias_without_gain_or_above_the_rating_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let frd = dir.path().join("frd.csv");
    let args = ["response", SPEC, "--mesh", "coarse", "--bias", "0A", "--frd", path_str(&frd)];
    expect_input_error(&args, &["--bias", "got 0 A", "small-signal gain"]);
    assert!(!frd.exists(), "a refused response wrote {}", frd.display());
    expect_input_error(
        &["response", SPEC, "--mesh", "coarse", "--bias", "100A"],
        &["--bias", "got 100 A", "maximum current", "coil.max_current"],
    );
}

/// Writes an FRD whose response is the same at every frequency (no dynamics).
fn write_flat_frd(path: &Path) {
    let mut text = String::from("omega_rad_s,re,im\n");
    for k in 0..20 {
        text.push_str(&format!("{},1,0\n", 10f64.powf(f64::from(k) / 5.0)));
    }
    std::fs::write(path, text).unwrap();
}

/// Class 1: `tfest` on a response without dynamics printed "fit: −inf %"; it is an input error
/// saying why.
#[test]
fn tfest_of_a_response_without_dynamics_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let frd = dir.path().join("flat.csv");
    write_flat_frd(&frd);
    expect_input_error(&["tfest", path_str(&frd), "--poles", "2"], &["no dynamics", "frequency"]);
}

/// A manifest of one sinusoidal test and its log, the input's sample 1500 replaced by `value`.
fn write_sine_test(dir: &Path, value: &str) -> std::path::PathBuf {
    let omega = 20.0_f64;
    let mut log = String::from("time_s,input,output\n");
    for k in 0..2000 {
        let t = f64::from(k) * 1e-3;
        let input = if k == 1500 { value.to_string() } else { format!("{}", (omega * t).sin()) };
        log.push_str(&format!("{t},{input},{}\n", 0.5 * (omega * t - 0.3).sin()));
    }
    std::fs::write(dir.join("sine.csv"), log).unwrap();
    let manifest = dir.join("manifest.csv");
    std::fs::write(&manifest, format!("frequency_rad_s,file\n{omega},sine.csv\n")).unwrap();
    manifest
}

/// Class 1: a 1e308 sample overflowed the fits and `freqresp` printed "inf": the log is refused,
/// named, with the size of its largest sample; an ordinary log still answers.
#[test]
fn freqresp_refuses_samples_that_overflow_its_fits() {
    let dir = tempfile::tempdir().unwrap();
    let manifest = write_sine_test(dir.path(), "0.9");
    let ok = mrbrake(&["freqresp", path_str(&manifest), "--min-quality", "0"]);
    assert!(ok.status.success(), "{}", String::from_utf8_lossy(&ok.stderr));
    assert!(!has_non_finite(&String::from_utf8_lossy(&ok.stdout)));
    let manifest = write_sine_test(dir.path(), "1e308");
    let out = mrbrake(&["freqresp", path_str(&manifest), "--min-quality", "0"]);
    let stdout = String::from_utf8_lossy(&out.stdout);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "exit 0 with {stdout}");
    assert!(!has_non_finite(&stdout), "{stdout}");
    assert!(stderr.contains("sine.csv") && stderr.contains("1e308"), "{stderr}");
}

const FEM: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../../examples/fem");

/// The example heat problem (`potcore-heat.toml`) with its mesh path made absolute and `edit`
/// applied to its text, written into `dir`.
fn heat_problem(dir: &Path, name: &str, edit: impl Fn(String) -> String) -> String {
    let text = std::fs::read_to_string(format!("{FEM}/potcore-heat.toml")).unwrap();
    let text = text.replace("mesh = \"potcore.msh\"", &format!("mesh = \"{FEM}/potcore.msh\""));
    let path = dir.join(name);
    std::fs::write(&path, edit(text)).unwrap();
    path_str(&path).to_string()
}

/// The example eddy-current problem with its mesh path absolute and `edit` applied.
fn eddy_problem(dir: &Path, name: &str, edit: impl Fn(String) -> String) -> String {
    let text = std::fs::read_to_string(format!("{FEM}/eddy-cylinder/eddy-cylinder.toml")).unwrap();
    let mesh = format!("mesh = \"{FEM}/eddy-cylinder/cylinder.msh\"");
    let text = text.replace("mesh = \"cylinder.msh\"", &mesh);
    let path = dir.join(name);
    std::fs::write(&path, edit(text)).unwrap();
    path_str(&path).to_string()
}

/// Class 2: a heat region defined twice is refused (the magnetic reader's rule); an ambient the
/// `thermal` command refuses is refused in a heat file too; a step bound above 1e6 is refused as
/// in every physics.
#[test]
fn heat_files_follow_the_rules_of_the_other_readers() {
    let dir = tempfile::tempdir().unwrap();
    let twice = heat_problem(dir.path(), "twice.toml", |t| {
        t + "\n[[region]]\nphysical = 1\nmaterial = \"air\"\n"
    });
    expect_input_error(&["fem", "solve", &twice], &["twice.toml", "region[3].physical", "twice"]);
    let hot =
        heat_problem(dir.path(), "hot.toml", |t| t.replace("T_amb_C = 25.0", "T_amb_C = 1e6"));
    expect_input_error(
        &["fem", "solve", &hot],
        &["hot.toml", "T_amb_C", "allowed (-273.15, 200] °C"],
    );
    expect_input_error(&["thermal", "--ambient", "1e6"], &["ambient", "(-273.15, 200] °C"]);
    let long = heat_problem(dir.path(), "long.toml", |t| {
        t + "\n[transient]\nt_end = 1e9\nadaptive = { rtol = 1e-3, dt_initial = 1.0 }\nmax_steps = 1000000000\n"
    });
    expect_input_error(&["fem", "solve", &long], &["long.toml", "max_steps", "1000000"]);
}

/// Class 2 (issue 31's leftover): every bad step key of a magnetic `[transient]` at once.
#[test]
fn magnetic_step_keys_are_reported_all_at_once() {
    let dir = tempfile::tempdir().unwrap();
    let bad = eddy_problem(dir.path(), "bad.toml", |t| {
        t.replace("scheme = \"bdf2\"", "scheme = \"rk4\"\nmax_steps = 0")
    });
    expect_input_error(
        &["fem", "solve", &bad],
        &["bad.toml", "transient.scheme", "transient.max_steps"],
    );
}

/// Class 2: a Preisach rig whose prior width is far narrower than a cell and centred between the
/// grid's widths wrote 30 000 NaN torques; it is refused naming both parameters. The plant checks
/// carry the value and the allowed range.
#[test]
fn degenerate_preisach_rigs_and_plant_values_are_named() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let rig = dir.path().join("preisach.toml");
    std::fs::write(
        &rig,
        "[hysteresis]\nmodel = \"preisach\"\nwidth_mean = 0.2037\nwidth_spread = 1e-9\n",
    )
    .unwrap();
    let args = ["rig", "characterize", "--config", path_str(&rig), "--out", path_str(&out)];
    expect_input_error(&args, &["preisach.toml", "width_spread", "width_mean = 0.2037"]);
    assert!(!out.exists(), "a refused rig wrote {}", out.display());
    let belt = dir.path().join("belt.toml");
    std::fs::write(&belt, "[motor]\nbelt_ratio = -2\n").unwrap();
    let args = ["rig", "characterize", "--config", path_str(&belt), "--out", path_str(&out)];
    expect_input_error(&args, &["belt.toml", "motor.belt_ratio", "-2", "> 0"]);
}

/// Class 3: inputs pointed at an endless stream are refused at their kind's size limit, not read
/// until memory runs out; a brake model with more curve points than the limit is an input error.
#[cfg(unix)]
#[test]
fn endless_inputs_stop_at_the_size_limit() {
    let dir = tempfile::tempdir().unwrap();
    let eddy = eddy_problem(dir.path(), "wave.toml", |t| {
        t.replace(
            "waveform = { kind = \"step\" }",
            "waveform = { kind = \"csv\", file = \"/dev/zero\" }",
        )
    });
    expect_input_error(&["fem", "solve", &eddy], &["/dev/zero", "size limit"]);
    let mesh = heat_problem(dir.path(), "zero.toml", |t| {
        t.replace(&format!("mesh = \"{FEM}/potcore.msh\""), "mesh = \"/dev/zero\"")
    });
    expect_input_error(&["fem", "solve", &mesh], &["/dev/zero", "size limit"]);
    let out = dir.path().join("out");
    expect_input_error(
        &["rig", "characterize", "--brake-model", "/dev/zero", "--out", path_str(&out)],
        &["/dev/zero", "size limit"],
    );
}

/// Class 4: values valid in form but physically absurd are refused up front with their key.
#[test]
fn absurd_physical_values_are_refused_before_the_solve() {
    let dir = tempfile::tempdir().unwrap();
    for (name, from, to, needle) in [
        ("turns.toml", "turns = 10,", "turns = 1e300,", "turns"),
        (
            "sigma.toml",
            "material = \"steel-1010\"",
            "material = \"steel-1010\"\nconductivity_S_per_m = 1e15",
            "conductivity_S_per_m",
        ),
        (
            "ramp.toml",
            "waveform = { kind = \"step\" }",
            "waveform = { kind = \"ramp\", rise_s = 5e-324 }",
            "rise_s",
        ),
        (
            "ohm.toml",
            "source = { turns = 10, current_A = 0.1 }",
            "source = { turns = 10, drive = { voltage_V = 1.0, series_resistance_ohm = 1e-300 } }",
            "series_resistance_ohm",
        ),
    ] {
        let file = eddy_problem(dir.path(), name, |t| t.replace(from, to));
        expect_input_error(&["fem", "solve", &file], &[name, needle]);
    }
    let adiabatic = heat_problem(dir.path(), "adiabatic.toml", |t| {
        t.replace("kind = \"convection\"", "kind = \"adiabatic\"")
            .replace("h_W_per_m2K = 10.0\n", "")
            .replace("T_amb_C = 25.0\n", "")
    });
    expect_input_error(&["fem", "solve", &adiabatic], &["adiabatic.toml", "no heat leaves"]);
}

/// Class 5: a response whose last output fails (a brake model that is not there) writes nothing:
/// neither the FRD nor the plots it used to leave behind.
#[test]
#[cfg_attr(not(heavy_tests), ignore = "release only: transients of a brake")]
fn a_failing_response_writes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let (frd, plots) = (dir.path().join("frd.csv"), dir.path().join("plots"));
    let missing = dir.path().join("missing.json");
    let args = [
        "response",
        SPEC,
        "--mesh",
        "coarse",
        "--frd",
        path_str(&frd),
        "--plot-dir",
        path_str(&plots),
        "--save-model",
        path_str(&missing),
    ];
    expect_input_error(&args, &["missing.json"]);
    let left: Vec<_> = std::fs::read_dir(dir.path()).unwrap().map(|e| e.unwrap().path()).collect();
    assert!(left.is_empty(), "a failed response left {left:?}");
}

/// Class 6: `analyze --save-model` with a 5-point curve wrote a model the rig then refused
/// without naming it; the model is checked as the simulators use it when it is written.
#[test]
#[cfg_attr(not(heavy_tests), ignore = "release only: an analysis of a brake")]
fn a_saved_model_is_checked_as_the_simulators_use_it() {
    let dir = tempfile::tempdir().unwrap();
    let model = dir.path().join("m5.json");
    let args =
        ["analyze", SPEC, "--mesh", "coarse", "--points", "5", "--save-model", path_str(&model)];
    let out = mrbrake(&args);
    if out.status.success() {
        // The curve fits: the rig must then run it.
        let rig = dir.path().join("rig");
        let run = mrbrake(&[
            "rig",
            "characterize",
            "--brake-model",
            path_str(&model),
            "--out",
            path_str(&rig),
        ]);
        assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
    } else {
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{err}");
        assert!(err.contains("static_curve") && err.contains("--points"), "{err}");
        assert!(!model.exists());
    }
}

/// Class 6: a bare `gap = 0.5` (read in metres) is named at the gap, with the SI rule and the
/// fix, before any geometric rule blames the envelope or the housing it overflows.
#[test]
fn a_bare_gap_in_metres_is_named_at_the_gap() {
    let dir = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(SPEC).unwrap();
    assert!(text.contains("gap = \"0.5mm\""), "the example's gap line moved");
    let path = dir.path().join("bare-gap.toml");
    std::fs::write(&path, text.replace("gap = \"0.5mm\"", "gap = 0.5")).unwrap();
    let args = ["analyze", path_str(&path), "--mesh", "coarse"];
    expect_input_error(
        &args,
        &[
            "bare-gap.toml:26: disc.gap: 500 mm must be a fluid gap",
            "a bare 0.5, read in metres (SI): write \"0.5mm\"",
        ],
    );
    let err = String::from_utf8_lossy(&mrbrake(&args).stderr).to_string();
    assert!(!err.contains("envelope") && !err.contains("housing"), "{err}");
    // A gap with a unit, or a bare number that is a plausible gap, has no such note.
    std::fs::write(&path, text.replace("gap = \"0.5mm\"", "gap = \"50mm\"")).unwrap();
    expect_input_error(&args, &["disc.gap: 50 mm must be a fluid gap"]);
    assert!(!String::from_utf8_lossy(&mrbrake(&args).stderr).contains("a bare"));
}

/// Found by the fuzzer's `cli-analyze` target: a brake model the simulators cannot run (three
/// currents of the drum example) was refused without naming the output, the flag or the spec.
#[test]
#[cfg_attr(not(heavy_tests), ignore = "release only: an analysis of a brake")]
fn an_unrunnable_saved_model_names_the_flag_and_the_spec() {
    let dir = tempfile::tempdir().unwrap();
    let model = dir.path().join("m.json");
    let spec = concat!(env!("CARGO_MANIFEST_DIR"), "/../../examples/specs/drum.toml");
    let plots = dir.path().join("plots");
    let (model_arg, plots_arg) = (path_str(&model), path_str(&plots));
    let args = [
        "analyze",
        spec,
        "--mesh",
        "coarse",
        "--points",
        "3",
        "--save-model",
        model_arg,
        "--plot-dir",
        plots_arg,
    ];
    expect_input_error(&args, &["--save-model", "m.json", "drum.toml", "static_curve"]);
    assert!(!model.exists() && !plots.exists(), "nothing written, no plots either");
}

/// Class 1: an unknown `--set` path made every design of a study infeasible and exited 0; it is
/// now an input error naming `--set` and the path, in `sweep` and `optimize` alike.
#[test]
fn an_unknown_set_path_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let store = dir.path().join("s.sqlite");
    let sweep = ["sweep", "--set", "nope=1", "--vary", "drum.gap=0.5mm,0.6mm", "--store"];
    let mut args = sweep.to_vec();
    args.push(path_str(&store));
    expect_input_error(&args, &["--set", "'nope'", "names no field of a brake spec"]);
    assert!(!store.exists(), "nothing stored");
    let problem = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../examples/optimize/thesis-requirement-quick.toml"
    );
    expect_input_error(&["optimize", problem, "--set", "drum.gapp=1mm"], &["'drum.gapp'"]);
}
