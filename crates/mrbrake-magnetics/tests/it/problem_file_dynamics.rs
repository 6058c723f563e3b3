//! Problem files with `[transient]` / `[harmonic]` (`mrbrake fem solve`): a voltage-driven L/R
//! circuit read from a file against its closed form `i(t) = V/R (1 − e^{−tR/L})` (L from the file's
//! static solve), the harmonic low-frequency limit `Z → jωL`, the shipped example, every bad input
//! as an input error naming file and field, and a Newton failure at a step as a numerical error.
//!
//! The set-up (as in `tests/it/dynamics.rs`): a long solid cylinder (radius 10 mm, tag 1) in a thin
//! solenoid (tag 3) with air between (2) and outside (4), one period of 2 mm height with natural
//! top and bottom; written as MSH 2.2 in millimetres.

use std::path::{Path, PathBuf};

use mrbrake_error::Kind as _;
use mrbrake_fem::mesh::Mesh;
use mrbrake_fem::mesh::gmsh::to_msh22;
use mrbrake_fem::mesh::structured::{SideTags, graded_lines, rectangle_mesh};
use mrbrake_fem::workflow::time::TimeError;
use mrbrake_magnetics::MagneticsError;
use mrbrake_magnetics::problem_file::{SolveReport, solve_file};

const A: f64 = 0.01; // conductor radius (m)
const B: f64 = 0.012; // coil inner radius
const C: f64 = 0.013; // coil outer radius
const D: f64 = 0.015; // outer boundary
const H: f64 = 0.002; // period height

fn repo_root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// The cylinder-in-solenoid mesh, `cells` radial cells in the conductor (graded to its surface).
fn cylinder_mesh(cells: usize) -> Mesh {
    let mut r = graded_lines(0.0, A, cells, 0.04);
    for (start, end, n) in [(A, B, 6), (B, C, 4), (C, D, 4)] {
        r.extend_from_slice(&graded_lines(start, end, n, 1.0)[1..]);
    }
    let z = graded_lines(0.0, H, 2, 1.0);
    let band = |r: f64, _z: f64| match r {
        r if r < A => 1,
        r if r < B => 2,
        r if r < C => 3,
        _ => 4,
    };
    let sides = SideTags { r_min: 10, r_max: 11, z_min: 12, z_max: 13 };
    rectangle_mesh(&r, &z, band, sides).unwrap()
}

fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path
}

/// A directory holding `cyl.msh` (mm).
fn mesh_dir() -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    write(dir.path(), "cyl.msh", &to_msh22(&cylinder_mesh(20), 1e-3));
    dir
}

/// The problem file: core material and extra keys of region 1, the coil's source, the tail.
fn problem(core: &str, coil_source: &str, tail: &str) -> String {
    format!(
        "mesh = \"cyl.msh\"\nlength_unit = \"mm\"\n\
         [[region]]\nphysical = 1\nmaterial = {core}\n\
         [[region]]\nphysical = 2\nmaterial = \"air\"\n\
         [[region]]\nphysical = 3\nmaterial = \"air\"\nsource = {coil_source}\n\
         [[region]]\nphysical = 4\nmaterial = \"air\"\n\
         [[probe]]\nname = \"axis\"\nr = 0.0\nz = 1.0\n{tail}"
    )
}

fn solve_in(dir: &Path, text: &str) -> Result<SolveReport, MagneticsError> {
    solve_file(&write(dir, "p.toml", text)).map(|r| r.0)
}

const LINEAR_CORE: &str = "{ mu_r = 50.0 }";

#[test]
fn voltage_step_in_a_file_follows_the_lr_closed_form() {
    let dir = mesh_dir();
    let (voltage, resistance) = (3.0, 0.5);
    let statics =
        solve_in(dir.path(), &problem(LINEAR_CORE, "{ turns = 10, current_A = 1.0 }", "")).unwrap();
    let inductance = statics.coils[0].inductance_h;
    let tau = inductance / resistance;
    let drive = format!(
        "{{ turns = 10, drive = {{ voltage_V = {voltage}, series_resistance_ohm = {resistance} }} }}"
    );
    let tail = format!(
        "[transient]\nt_end = {}\ndt = {}\nscheme = \"bdf2\"\nwaveform = {{ kind = \"step\" }}\n",
        3.0 * tau,
        tau / 100.0
    );
    let report = solve_in(dir.path(), &problem(LINEAR_CORE, &drive, &tail)).unwrap();
    let transient = &report.dynamics.as_ref().unwrap().transient.as_ref().unwrap().result;
    assert_eq!(transient.time_s.len(), 301);
    let final_current = voltage / resistance;
    let worst = transient
        .time_s
        .iter()
        .zip(&transient.coils[0].current_a)
        .map(|(&t, &i)| (i - final_current * (1.0 - (-t / tau).exp())).abs() / final_current)
        .fold(0.0, f64::max);
    println!(
        "L/R from a problem file: L = {inductance:.5e} H, max |i − exact| / (V/R) = {worst:.3e}"
    );
    assert!(worst < 1e-4, "worst relative error {worst:.3e}");
    // The static part of the report is the DC state at V/R.
    assert!((report.coils[0].flux_linkage_wb - inductance * final_current).abs() < 1e-9);
    let json = serde_json::to_value(&report).unwrap();
    for key in ["time_s", "coils", "probes", "eddy_loss_W", "newton_iterations"] {
        assert!(json["transient"].get(key).is_some(), "missing transient.{key}");
    }
    for key in ["physical", "current_A", "flux_linkage_Wb", "voltage_V"] {
        assert!(json["transient"]["coils"][0].get(key).is_some(), "missing coils[0].{key}");
    }
    assert!(json["transient"]["probes"][0].get("B_z_T").is_some());
    // The axial force on every region at every level (values: `tests/it/forces.rs`, the static one
    // in `tests/it/problem_file.rs`).
    assert_eq!(transient.forces.len(), report.regions.len());
    for trace in &transient.forces {
        assert_eq!(trace.force_z_n.len(), transient.time_s.len());
        assert!(trace.force_z_n.iter().all(|f| f.is_finite()));
    }
    assert!(json["transient"]["forces"][0].get("force_z_N").is_some());
    assert!(json.get("harmonic").is_none());
    // (Its text is `mrbrake_report::fem`'s, tested there and by the CLI.)
    assert_eq!(json["transient"]["scheme"], "bdf2");
}

#[test]
fn harmonic_file_tends_to_the_inductance_at_low_frequency() {
    let dir = mesh_dir();
    let core = format!("{LINEAR_CORE}\nconductivity_S_per_m = 5.8e6");
    let statics =
        solve_in(dir.path(), &problem(&core, "{ turns = 10, current_A = 2.0 }", "")).unwrap();
    let inductance = statics.coils[0].inductance_h;
    let tail = "[harmonic]\nfrequencies_Hz = [0.01, 100.0]\n";
    let report =
        solve_in(dir.path(), &problem(&core, "{ turns = 10, current_A = 2.0 }", tail)).unwrap();
    let dynamics = report.dynamics.as_ref().unwrap();
    assert!((dynamics.conductors[0].conductivity_s_per_m - 5.8e6).abs() < 1.0);
    let points = dynamics.harmonic.as_ref().unwrap();
    let low = &points[0];
    let omega = 2.0 * std::f64::consts::PI * low.frequency_hz;
    let z = low.coils[0].impedance_ohm;
    let error = (z[1] / omega - inductance).abs() / inductance;
    println!(
        "harmonic at 0.01 Hz: Im Z / ω = {:.6e} H, static L = {inductance:.6e} H, rel. error {error:.2e}",
        z[1] / omega
    );
    assert!(error < 1e-4, "{error:.3e}");
    assert!(z[0] >= 0.0, "eddy losses give Re Z >= 0: {z:?}");
    // At 100 Hz the skin depth (~0.3 mm for μ_r = 50) is far below the radius: the core is
    // screened, the inductance falls and the loss resistance rises.
    let high = &points[1].coils[0].impedance_ohm;
    let omega_high = 2.0 * std::f64::consts::PI * 100.0;
    assert!(high[1] / omega_high < 0.5 * inductance && high[0] > z[0], "{high:?}");
    let json = serde_json::to_value(&report).unwrap();
    let first = &json["harmonic"][0];
    assert!(first["coils"][0]["impedance_ohm"].as_array().unwrap().len() == 2);
    for key in ["frequency_Hz", "coils", "probes", "eddy_loss_W"] {
        assert!(first.get(key).is_some(), "missing harmonic[0].{key}");
    }
}

/// An input error naming `needle` (and the file) for the problem with core `core`, coil source
/// `source`, tail `tail` and extra files.
fn bad(core: &str, source: &str, tail: &str, extra: &[(&str, &str)], needle: &str) {
    let dir = mesh_dir();
    for (name, text) in extra {
        write(dir.path(), name, text);
    }
    match solve_in(dir.path(), &problem(core, source, tail)) {
        Err(e) => {
            let message = e.to_string();
            assert!(e.is_input_error(), "expected an input error, got {message}");
            assert!(message.contains("p.toml"), "names the file: {message}");
            assert!(message.contains(needle), "names `{needle}`: {message}");
        }
        Ok(_) => panic!("expected an input error naming `{needle}`"),
    }
}

const CURRENT: &str = "{ turns = 10, current_A = 1.0 }";
const STEP: &str = "[transient]\nt_end = 0.01\ndt = 0.001\n";

#[test]
fn bad_dynamic_inputs_are_input_errors_naming_file_and_field() {
    let sigma = |s: &str| format!("{LINEAR_CORE}\nconductivity_S_per_m = {s}");
    bad(&sigma("-1.0"), CURRENT, STEP, &[], "conductivity_S_per_m");
    bad(&sigma("nan"), CURRENT, STEP, &[], "conductivity_S_per_m");
    bad(&sigma("inf"), CURRENT, STEP, &[], "conductivity_S_per_m");
    bad(LINEAR_CORE, CURRENT, "[transient]\nt_end = 0.01\ndt = 0.0\n", &[], "transient.dt");
    bad(LINEAR_CORE, CURRENT, "[transient]\nt_end = 0.01\ndt = -1e-3\n", &[], "transient.dt");
    bad(LINEAR_CORE, CURRENT, "[transient]\nt_end = 0.001\ndt = 0.01\n", &[], "transient.t_end");
    let scheme = format!("{STEP}scheme = \"rk4\"\n");
    bad(LINEAR_CORE, CURRENT, &scheme, &[], "transient.scheme");
    let kind = format!("{STEP}waveform = {{ kind = \"square\" }}\n");
    bad(LINEAR_CORE, CURRENT, &kind, &[], "transient.waveform");
    let csv = format!("{STEP}waveform = {{ kind = \"csv\", file = \"w.csv\" }}\n");
    let not_increasing = [("w.csv", "time_s,value\n0.0,0.0\n0.002,1.0\n0.001,1.0\n")];
    bad(LINEAR_CORE, CURRENT, &csv, &not_increasing, "increase strictly");
    bad(LINEAR_CORE, CURRENT, &csv, &not_increasing, "w.csv");
    let both = format!("{STEP}[harmonic]\nfrequencies_Hz = [1.0]\n");
    bad(LINEAR_CORE, CURRENT, &both, &[], "[harmonic]");
    let no_resistance = "{ turns = 10, drive = { voltage_V = 3.0 } }";
    bad(LINEAR_CORE, no_resistance, STEP, &[], "series_resistance_ohm");
    let zero_resistance = "{ turns = 10, drive = { voltage_V = 3.0, series_resistance_ohm = 0 } }";
    bad(LINEAR_CORE, zero_resistance, STEP, &[], "series_resistance_ohm");
    let conducting_coil = format!("{CURRENT}\nconductivity_S_per_m = 1e6");
    bad(LINEAR_CORE, &conducting_coil, STEP, &[], "stranded winding");
    let ramp_without_rise = format!("{STEP}waveform = {{ kind = \"ramp\" }}\n");
    bad(LINEAR_CORE, CURRENT, &ramp_without_rise, &[], "rise_s");
    let voltage_static = "{ turns = 10, drive = { voltage_V = 3.0, series_resistance_ohm = 1 } }";
    bad(LINEAR_CORE, voltage_static, "", &[], "[transient]");
    let voltage_harmonic = "[harmonic]\nfrequencies_Hz = [1.0]\n";
    bad(LINEAR_CORE, voltage_static, voltage_harmonic, &[], "current");
}

#[test]
fn csv_and_ramp_waveforms_drive_the_coil() {
    let dir = mesh_dir();
    write(dir.path(), "w.csv", "time_s,value\n0,0\n0.004,1\n0.01,0.5\n");
    for waveform in ["{ kind = \"csv\", file = \"w.csv\" }", "{ kind = \"ramp\", rise_s = 0.004 }"]
    {
        let tail = format!(
            "[transient]\nt_end = 0.01\ndt = 0.001\nscheme = \"euler\"\nwaveform = {waveform}\n"
        );
        let report = solve_in(dir.path(), &problem(LINEAR_CORE, CURRENT, &tail)).unwrap();
        let t = &report.dynamics.as_ref().unwrap().transient.as_ref().unwrap().result;
        // A prescribed current follows the waveform exactly (amplitude 1 A).
        let i4 = t.coils[0].current_a[4];
        assert!((i4 - 1.0).abs() < 1e-12, "{waveform}: i(4 ms) = {i4}");
    }
}

#[test]
fn newton_failure_at_a_step_is_numerical_with_step_time_and_history() {
    let dir = mesh_dir();
    // The static part (DC at 0.01 A) converges in few iterations; the table then drives the coil
    // to 400 × 0.01 A = 4 A within the first step, deep into saturation, which six Newton
    // iterations cannot reach.
    write(dir.path(), "w.csv", "time_s,value\n0,0\n0.001,400\n");
    let text = problem(
        "\"steel-1010\"",
        "{ turns = 10, current_A = 0.01 }",
        "[solver]\nmax_iterations = 6\n[transient]\nt_end = 0.01\ndt = 0.002\n\
         waveform = { kind = \"csv\", file = \"w.csv\" }\n",
    );
    match solve_in(dir.path(), &text) {
        Err(e @ MagneticsError::Time(TimeError::Step { .. })) => {
            assert!(!e.is_input_error(), "{e}");
            let message = e.to_string();
            // Fixed steps are uniform (times n·dt): the first step ends at 2 ms.
            assert!(message.contains("time step 1") && message.contains("t = 2.0"), "{message}");
            let cause = std::error::Error::source(&e).map(|s| s.to_string()).unwrap_or_default();
            assert!(cause.contains("residual history") && cause.contains("#6"), "{cause}");
        }
        Err(e) => panic!("expected a failed time step, got {e}"),
        Ok(_) => panic!("six Newton iterations cannot reach saturation in one step"),
    }
}

/// The shipped example: its mesh is the generator's, it solves, and the sourced conductivity
/// of its steel is reported.
#[test]
fn example_eddy_cylinder_solves() {
    let dir = repo_root().join("examples/fem/eddy-cylinder");
    let mesh = to_msh22(&cylinder_mesh(20), 1e-3);
    if std::env::var_os("MRBRAKE_WRITE_EXAMPLE_MESH").is_some() {
        std::fs::write(dir.join("cylinder.msh"), &mesh).unwrap();
    }
    let shipped = std::fs::read_to_string(dir.join("cylinder.msh")).unwrap();
    assert!(shipped == mesh, "regenerate with MRBRAKE_WRITE_EXAMPLE_MESH=1");
    let (report, _, _) = solve_file(&dir.join("eddy-cylinder.toml")).unwrap();
    let dynamics = report.dynamics.as_ref().unwrap();
    assert!(dynamics.conductors[0].source.contains("steel-1010"));
    let t = &dynamics.transient.as_ref().unwrap().result;
    let axis = &t.probes[0].b_z_t;
    // The flux diffuses in: B on the axis rises from 0 and lags the surface.
    assert!(axis[0].abs() < 1e-12 && axis[axis.len() - 1] > 0.5, "{:?}", axis.last());
}

/// Small-signal about a saturated DC state: at low frequency `Im Z / ω` is the incremental
/// inductance `dλ/dI` of the static solve at the bias current (the report's static part, the DC
/// state at `current_A`, here equal to the bias).
#[test]
fn small_signal_file_tends_to_the_incremental_inductance() {
    let dir = mesh_dir();
    let core = "\"steel-1010\"";
    let source = "{ turns = 10, current_A = 0.5 }";
    let tail = "[harmonic]\nfrequencies_Hz = [0.001]\nbias = { current_A = 0.5 }\n";
    let report = solve_in(dir.path(), &problem(core, source, tail)).unwrap();
    let incremental = report.coils[0].incremental_inductance_h;
    let secant = report.coils[0].inductance_h;
    let point = &report.dynamics.as_ref().unwrap().harmonic.as_ref().unwrap()[0];
    let omega = 2.0 * std::f64::consts::PI * point.frequency_hz;
    let small_signal = point.coils[0].impedance_ohm[1] / omega;
    let error = (small_signal - incremental).abs() / incremental;
    println!(
        "small signal at 0.5 A: Im Z / ω = {small_signal:.6e} H, dλ/dI = {incremental:.6e} H \
         (secant L = {secant:.6e} H), rel. error {error:.2e}"
    );
    assert!(error < 1e-3, "{error:.3e}");
    assert!((secant - incremental).abs() > 0.05 * secant, "the bias saturates the steel");
}

#[test]
fn a_static_file_refuses_a_negative_conductivity_and_ignores_a_valid_one() {
    bad(
        &format!("{LINEAR_CORE}\nconductivity_S_per_m = -2.0"),
        CURRENT,
        "",
        &[],
        "conductivity_S_per_m",
    );
    let dir = mesh_dir();
    let core = format!("{LINEAR_CORE}\nconductivity_S_per_m = 1e6");
    let report = solve_in(dir.path(), &problem(&core, CURRENT, "")).unwrap();
    assert!(report.dynamics.is_none());
    assert!(serde_json::to_value(&report).unwrap().get("conductors").is_none());
}

/// A per-coil bias (`bias.coils`) with every coil listed is the uniform `current_A` bias; with
/// two coils, the unlisted one is at 0 A and the report lists each coil's bias.
#[test]
fn per_coil_bias_matches_the_uniform_bias_and_is_reported_per_coil() {
    let dir = mesh_dir();
    let core = "\"steel-1010\"";
    let source = "{ turns = 10, current_A = 0.5 }";
    let harmonic = "[harmonic]\nfrequencies_Hz = [0.001, 50.0]\n";
    let uniform = format!("{harmonic}bias = {{ current_A = 0.5 }}\n");
    let per_coil =
        format!("{harmonic}bias = {{ coils = [{{ physical = 3, current_A = 0.5 }}] }}\n");
    let a = solve_in(dir.path(), &problem(core, source, &uniform)).unwrap();
    let b = solve_in(dir.path(), &problem(core, source, &per_coil)).unwrap();
    let (da, db) = (a.dynamics.as_ref().unwrap(), b.dynamics.as_ref().unwrap());
    assert_eq!(db.harmonic_bias_a, Some(0.5));
    assert!(db.harmonic_bias_coils.is_empty());
    for (pa, pb) in da.harmonic.as_ref().unwrap().iter().zip(db.harmonic.as_ref().unwrap()) {
        let (za, zb) = (pa.coils[0].impedance_ohm, pb.coils[0].impedance_ohm);
        assert!((za[0] - zb[0]).abs() <= 1e-12 * za[0].abs().max(za[1].abs()), "{za:?} {zb:?}");
        assert!((za[1] - zb[1]).abs() <= 1e-12 * za[1].abs(), "{za:?} {zb:?}");
    }
    // The outer air band as a second coil, unbiased.
    let two_coils = problem(core, source, &per_coil).replace(
        "physical = 4\nmaterial = \"air\"\n",
        "physical = 4\nmaterial = \"air\"\nsource = { turns = 5, current_A = 0.1 }\n",
    );
    let c = solve_in(dir.path(), &two_coils).unwrap();
    let dc = c.dynamics.as_ref().unwrap();
    assert_eq!(dc.harmonic_bias_a, None);
    let listed: Vec<(u32, f64)> =
        dc.harmonic_bias_coils.iter().map(|b| (b.physical, b.current_a)).collect();
    assert_eq!(listed.len(), 2);
    assert!(listed[0].0 == 3 && (listed[0].1 - 0.5).abs() < 1e-15, "{listed:?}");
    assert!(listed[1].0 == 4 && listed[1].1.abs() < 1e-15, "{listed:?}");
}

#[test]
fn bad_per_coil_bias_is_an_input_error_naming_the_field() {
    let harmonic = "[harmonic]\nfrequencies_Hz = [1.0]\n";
    let with = |bias: &str| format!("{harmonic}bias = {bias}\n");
    let unknown = with("{ coils = [{ physical = 7, current_A = 1.0 }] }");
    bad(LINEAR_CORE, CURRENT, &unknown, &[], "harmonic.bias.coils[0].physical = 7");
    let twice =
        with("{ coils = [{ physical = 3, current_A = 1.0 }, { physical = 3, current_A = 2.0 }] }");
    bad(LINEAR_CORE, CURRENT, &twice, &[], "listed twice");
    let both = with("{ current_A = 1.0, coils = [{ physical = 3, current_A = 1.0 }] }");
    bad(LINEAR_CORE, CURRENT, &both, &[], "not both or neither");
    bad(LINEAR_CORE, CURRENT, &with("{}"), &[], "not both or neither");
    let nan = with("{ coils = [{ physical = 3, current_A = nan }] }");
    bad(LINEAR_CORE, CURRENT, &nan, &[], "harmonic.bias.coils[0].current_A");
}

#[test]
fn harmonic_frequency_lists_are_bounded_and_vtu_frequencies_checked() {
    let many: Vec<String> = (0..=10_000).map(|k| format!("{}.0", k + 1)).collect();
    let too_many = format!("[harmonic]\nfrequencies_Hz = [{}]\n", many.join(", "));
    bad(
        LINEAR_CORE,
        CURRENT,
        &too_many,
        &[],
        "harmonic.frequencies_Hz: got 10001 frequencies; allowed: <= 10000",
    );
    let empty = "[harmonic]\nfrequencies_Hz = [1.0]\nvtu_frequencies_Hz = []\n";
    bad(LINEAR_CORE, CURRENT, empty, &[], "harmonic.vtu_frequencies_Hz: is empty");
    let unknown = "[harmonic]\nfrequencies_Hz = [1.0]\nvtu_frequencies_Hz = [1.0, 2.0]\n";
    bad(LINEAR_CORE, CURRENT, unknown, &[], "harmonic.vtu_frequencies_Hz[1]: 2 Hz is not one of");
}
