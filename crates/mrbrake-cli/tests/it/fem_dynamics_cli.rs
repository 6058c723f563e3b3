//! CLI behaviour of `mrbrake fem solve` on magnetodynamic problem files (issue 13): the shipped
//! eddy-current example's `transient` JSON and its `.vtu` instants with a `.pvd` collection; bad
//! input exits 2 naming file and field; a Newton failure at a time step exits 1 with the step,
//! time and residual history and writes nothing.

use crate::common;

use common::{expect_input_error, json, mrbrake, path_str};

use std::path::{Path, PathBuf};

fn example_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/fem/eddy-cylinder")
}

/// Writes `text` (a problem file on the example's mesh, copied beside it) into `dir`.
fn problem(dir: &Path, name: &str, text: &str) -> String {
    std::fs::copy(example_dir().join("cylinder.msh"), dir.join("cylinder.msh")).unwrap();
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path_str(&path).to_owned()
}

fn regions(source: &str) -> String {
    format!(
        "mesh = \"cylinder.msh\"\nlength_unit = \"mm\"\n\
         [[region]]\nphysical = 1\nmaterial = \"steel-1010\"\n\
         [[region]]\nphysical = 2\nmaterial = \"air\"\n\
         [[region]]\nphysical = 3\nmaterial = \"air\"\nsource = {source}\n\
         [[region]]\nphysical = 4\nmaterial = \"air\"\n"
    )
}

#[test]
fn eddy_example_reports_a_transient_and_writes_its_instants() {
    let example = example_dir().join("eddy-cylinder.toml");
    let dir = tempfile::tempdir().unwrap();
    let vtu = dir.path().join("eddy.vtu");
    let v = json(&["fem", "solve", path_str(&example), "--json", "--vtu", path_str(&vtu)]);
    let t = &v["transient"];
    let times = t["time_s"].as_array().unwrap();
    assert!((times.last().unwrap().as_f64().unwrap() - 0.5).abs() < 1e-12);
    for key in ["current_A", "flux_linkage_Wb", "voltage_V"] {
        assert_eq!(t["coils"][0][key].as_array().unwrap().len(), times.len(), "{key}");
    }
    assert_eq!(t["probes"][1]["name"], "surface");
    assert_eq!(t["eddy_loss_W"].as_array().unwrap().len(), times.len());
    assert_eq!(v["conductors"][0]["conductivity_S_per_m"].as_f64(), Some(5.8e6));
    for k in 0..3 {
        let text = std::fs::read_to_string(dir.path().join(format!("eddy_{k:03}.vtu"))).unwrap();
        assert!(text.trim_end().ends_with("</VTKFile>"));
    }
    let pvd = std::fs::read_to_string(dir.path().join("eddy.pvd")).unwrap();
    assert_eq!(pvd.matches("<DataSet").count(), 3, "{pvd}");
}

#[test]
fn bad_dynamic_files_exit_2() {
    let dir = tempfile::tempdir().unwrap();
    let both = problem(
        dir.path(),
        "both.toml",
        &format!(
            "{}[transient]\nt_end = 0.01\ndt = 0.001\n[harmonic]\nfrequencies_Hz = [1.0]\n",
            regions("{ turns = 10, current_A = 0.1 }")
        ),
    );
    expect_input_error(&["fem", "solve", &both], &["both.toml", "[transient]", "[harmonic]"]);
    let scheme = problem(
        dir.path(),
        "scheme.toml",
        &format!(
            "{}[transient]\nt_end = 0.01\ndt = 0.001\nscheme = \"trapezoid\"\n",
            regions("{ turns = 10, current_A = 0.1 }")
        ),
    );
    expect_input_error(&["fem", "solve", &scheme], &["scheme.toml", "transient.scheme"]);
}

#[test]
fn newton_failure_at_a_step_exits_1_and_writes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("w.csv"), "time_s,value\n0,0\n0.001,400\n").unwrap();
    let path = problem(
        dir.path(),
        "fails.toml",
        &format!(
            "{}[solver]\nmax_iterations = 6\n[transient]\nt_end = 0.01\ndt = 0.002\n\
             waveform = {{ kind = \"csv\", file = \"w.csv\" }}\n",
            regions("{ turns = 10, current_A = 0.01 }")
        ),
    );
    let vtu = dir.path().join("out.vtu");
    let out = mrbrake(&["fem", "solve", &path, "--vtu", path_str(&vtu)]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(err.contains("time step 1") && err.contains("residual history"), "{err}");
    assert!(!vtu.exists(), "nothing is written after a failure");
}

/// A harmonic file's `--vtu`: the phasors (real and imaginary parts) at every frequency with a
/// `.pvd` whose time steps are the frequencies, or one file at `vtu_frequencies_Hz`; a
/// frequency that was not solved is an input error.
#[test]
fn harmonic_vtu_writes_the_phasors_at_the_chosen_frequencies() {
    let dir = tempfile::tempdir().unwrap();
    let source = regions("{ turns = 10, current_A = 0.1 }");
    let every = problem(
        dir.path(),
        "every.toml",
        &format!("{source}[harmonic]\nfrequencies_Hz = [1.0, 100.0]\n"),
    );
    let vtu = dir.path().join("h.vtu");
    let out = mrbrake(&["fem", "solve", &every, "--vtu", path_str(&vtu)]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let pvd = std::fs::read_to_string(dir.path().join("h.pvd")).unwrap();
    assert!(pvd.contains("timestep=\"1e0\"") && pvd.contains("timestep=\"1e2\""), "{pvd}");
    for k in 0..2 {
        let text = std::fs::read_to_string(dir.path().join(format!("h_{k:03}.vtu"))).unwrap();
        for name in ["A_phi_re_Wb_per_m", "A_phi_im_Wb_per_m", "B_re_T", "B_im_T"] {
            assert!(text.contains(name), "h_{k:03}.vtu lacks {name}");
        }
    }
    let one = problem(
        dir.path(),
        "one.toml",
        &format!(
            "{source}[harmonic]\nfrequencies_Hz = [1.0, 100.0]\nvtu_frequencies_Hz = [100.0]\n"
        ),
    );
    let single = dir.path().join("single.vtu");
    let out = mrbrake(&["fem", "solve", &one, "--vtu", path_str(&single)]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(std::fs::read_to_string(&single).unwrap().contains("B_phasor_norm_T"));
    assert!(!dir.path().join("single.pvd").exists());
    let unknown = problem(
        dir.path(),
        "unknown.toml",
        &format!("{source}[harmonic]\nfrequencies_Hz = [1.0]\nvtu_frequencies_Hz = [50.0]\n"),
    );
    expect_input_error(&["fem", "solve", &unknown], &["unknown.toml", "vtu_frequencies_Hz[0]"]);
}
