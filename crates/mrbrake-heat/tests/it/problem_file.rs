//! The `[transient]` step keys of heat problem files: fixed `dt` (evened out to land on `t_end`),
//! `adaptive = { rtol, dt_initial }` (the core's step control, as in magnetics files), the scheme
//! and the step bound, and the errors of bad combinations naming the key.

use std::path::Path;

use mrbrake_fem::mesh::gmsh::to_msh22;
use mrbrake_fem::mesh::structured::{SideTags, graded_lines, rectangle_mesh};
use mrbrake_heat::HeatError;
use mrbrake_heat::problem_file::{HeatReport, solve_file};

/// A cylinder r < 10 mm (tag 1) cooling from 400 K by convection (h = 100, to 300 K) from its
/// surface (tag 2), adiabatic ends, with the `[transient]` table `transient`.
fn solve(dir: &Path, transient: &str) -> Result<HeatReport, HeatError> {
    let sides = SideTags { r_min: 1, r_max: 2, z_min: 3, z_max: 4 };
    let mesh = rectangle_mesh(
        &graded_lines(0.0, 10.0, 12, 1.0),
        &graded_lines(0.0, 4.0, 2, 1.0),
        |_, _| 1,
        sides,
    )
    .unwrap();
    std::fs::write(dir.join("c.msh"), to_msh22(&mesh, 1.0)).unwrap();
    let text = format!(
        "physics = \"heat\"\nmesh = \"c.msh\"\nlength_unit = \"mm\"\norder = 2\n[[region]]\n\
         physical = 1\nmaterial = {{ k_W_per_mK = 1.0, rho_kg_per_m3 = 1000.0, c_J_per_kgK = \
         1000.0 }}\n[[boundary]]\nphysical = 2\nkind = \"convection\"\nh_W_per_m2K = 100.0\n\
         T_amb_C = 26.85\n[[probe]]\nname = \"surface\"\nr = 10.0\nz = 2.0\n[transient]\n\
         T_initial_C = 126.85\n{transient}\n"
    );
    let path = dir.join("c.toml");
    std::fs::write(&path, text).unwrap();
    solve_file(&path, None).map(|(report, _, _)| report)
}

fn final_surface(report: &HeatReport) -> f64 {
    let series = &report.transient.as_ref().expect("a transient").probes[0].t_c;
    series[series.len() - 1]
}

#[test]
fn adaptive_steps_in_a_heat_file_match_fixed_steps_in_fewer_steps() {
    let dir = tempfile::tempdir().unwrap();
    let fixed = solve(dir.path(), "t_end = 200.0\ndt = 0.25").unwrap();
    let adaptive =
        solve(dir.path(), "t_end = 200.0\nadaptive = { rtol = 1e-6, dt_initial = 0.01 }").unwrap();
    let (f, a) = (fixed.transient.as_ref().unwrap(), adaptive.transient.as_ref().unwrap());
    let (fixed_steps, adaptive_steps) = (f.time_s.len() - 1, a.time_s.len() - 1);
    let gap = (final_surface(&fixed) - final_surface(&adaptive)).abs();
    println!(
        "fixed: {fixed_steps} steps, adaptive: {adaptive_steps} steps ({:?} rejected), surface \
         temperatures at 200 s differ by {gap:.2e} K",
        a.rejected_steps
    );
    assert!((a.time_s[a.time_s.len() - 1] - 200.0).abs() < 1e-9, "lands on t_end");
    assert!(adaptive_steps < fixed_steps / 2, "{adaptive_steps} against {fixed_steps}");
    // Within the local tolerances the steps were allowed (rtol · max T per step, max T = 400 K)
    // of the fine fixed-step run.
    assert!(gap < adaptive_steps as f64 * 1e-6 * 400.0, "{gap:e} K");
    assert_eq!((f.rejected_steps, a.rejected_steps.is_some()), (None, true));
    assert!(a.max_energy_imbalance_w < 1e-9, "{}", a.max_energy_imbalance_w);
}

#[test]
fn fixed_steps_even_out_to_land_on_t_end() {
    let dir = tempfile::tempdir().unwrap();
    let report = solve(dir.path(), "t_end = 100.0\ndt = 30.0\nscheme = \"euler\"").unwrap();
    let t = report.transient.unwrap();
    assert_eq!(t.time_s, [0.0, 25.0, 50.0, 75.0, 100.0]);
    assert_eq!(t.factorizations_or_iterations, 1, "implicit Euler: one step size");
}

#[test]
fn bad_step_keys_are_field_errors_naming_the_key() {
    let dir = tempfile::tempdir().unwrap();
    let cases = [
        ("t_end = 10.0\ndt = 1.0\nadaptive = { rtol = 1e-4, dt_initial = 0.1 }", "adaptive"),
        ("t_end = 10.0", "transient[0].dt"),
        ("t_end = 10.0\nadaptive = { rtol = 2.0, dt_initial = 0.1 }", "adaptive.rtol"),
        ("t_end = 10.0\ndt = 1.0\nscheme = \"trapezoid\"", "\"trapezoid\" is not known"),
        ("t_end = 10.0\ndt = 1e-6\nmax_steps = 1000", "exceeds the limit of 1000 steps"),
        ("t_end = 1.0\ndt = 2.0", "shorter than dt"),
    ];
    for (transient, expected) in cases {
        let error = solve(dir.path(), transient).unwrap_err();
        assert!(matches!(error, HeatError::Fields(_)), "{error}");
        let message = error.to_string();
        assert!(message.contains(expected) && message.contains("c.toml"), "{message}");
    }
}
