//! Problem files: the shipped example solves; bad input gives input errors naming the file and field;
//! Newton failure is a numerical error carrying the residual history.

use mrbrake_error::Kind as _;
use std::path::{Path, PathBuf};

use mrbrake_magnetics::problem_file::{solve_file, solve_file_with_order};
use mrbrake_magnetics::{ElementOrder, MagneticsError};

fn repo_root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn fixture_mesh() -> String {
    repo_root().join("crates/mrbrake-fem/tests/fixtures/two_regions_v41.msh").display().to_string()
}

fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path
}

#[test]
fn example_potcore_solves_and_reports() {
    let (report, _solver, _solution) =
        solve_file(&repo_root().join("examples/fem/potcore.toml")).unwrap();
    assert!(report.converged);
    assert!(report.newton_iterations >= 2, "steel is non-linear");
    assert_eq!(report.probes.len(), 3);
    let pole = report.probes.iter().find(|p| p.name == "pole_gap").unwrap();
    // Magnetic-circuit bound: B in the 1 mm gap cannot exceed μ0 N I / g = 1.26 T.
    assert!(pole.b_abs_t > 0.3 && pole.b_abs_t < 1.26, "{}", pole.b_abs_t);
    let axis = report.probes.iter().find(|p| p.name == "axis_centre").unwrap();
    assert!(axis.b_r_t.abs() < 1e-12);
    assert_eq!(report.coils.len(), 1);
    let coil = &report.coils[0];
    assert!(coil.inductance_h > 0.0 && coil.incremental_inductance_h > 0.0);
    assert!(report.energy_j > 0.0);
    let json = serde_json::to_value(&report).unwrap();
    for key in [
        "probes",
        "regions",
        "coils",
        "energy_J",
        "newton_iterations",
        "converged",
        "nodes",
        "elements",
        "timings_s",
    ] {
        assert!(json.get(key).is_some(), "missing {key}");
    }
    for key in ["read", "assemble", "solve", "total"] {
        assert!(json["timings_s"].get(key).is_some(), "missing timings_s.{key}");
    }
    assert!(json["probes"][0].get("B_abs_T").is_some());
    assert!(json["regions"][0].get("mean_B_T").is_some());
    assert!(json["coils"][0].get("flux_linkage_Wb").is_some());
}

fn input_error(toml: &str, extra: &[(&str, &str)]) -> String {
    let dir = tempfile::tempdir().unwrap();
    for (name, text) in extra {
        write(dir.path(), name, text);
    }
    let path = write(dir.path(), "p.toml", toml);
    match solve_file(&path) {
        Err(e) => {
            assert!(e.is_input_error(), "expected an input error, got {e}");
            e.to_string()
        }
        Ok(_) => panic!("expected an error"),
    }
}

#[test]
fn bad_problem_files_are_input_errors_naming_the_field() {
    let mesh = fixture_mesh();
    let ok_regions = "[[region]]\nphysical = 1\nmaterial = { mu_r = 100.0 }\nsource = { current_density_A_per_m2 = 1e6 }\n[[region]]\nphysical = 2\nmaterial = \"air\"\n";
    let head = format!("mesh = {mesh:?}\nlength_unit = \"mm\"\n");

    let e = input_error(
        &format!("{head}{ok_regions}[[region]]\nphysical = 7\nmaterial = \"air\"\n"),
        &[],
    );
    assert!(e.contains("physical = 7") && e.contains("not a physical surface"), "{e}");

    let e = input_error(&format!("{head}[[region]]\nphysical = 1\nmaterial = \"air\"\n"), &[]);
    assert!(e.contains("surface 2 has no [[region]]"), "{e}");

    let e = input_error(
        &format!("{head}[[region]]\nphysical = 1\n[[region]]\nphysical = 2\nmaterial = \"air\"\n"),
        &[],
    );
    assert!(e.contains("region[0]") && e.contains("missing `material`"), "{e}");

    let e = input_error(
        &format!("{head}{ok_regions}[[boundary]]\nphysical = 11\nkind = \"magic\"\n"),
        &[],
    );
    assert!(e.contains("boundary[0].kind: physical = 11 (got \"magic\"; allowed:"), "{e}");

    let e = input_error(
        &format!("{head}{ok_regions}[[boundary]]\nphysical = 99\nkind = \"dirichlet\"\n"),
        &[],
    );
    assert!(
        e.contains("boundary[0].physical: physical = 99: the mesh") && e.contains("no curve"),
        "{e}"
    );

    let e = input_error(&format!("mesh = {mesh:?}\nlength_unit = \"furlong\"\n{ok_regions}"), &[]);
    assert!(e.contains("length_unit"), "{e}");

    let e = input_error(
        &format!("{head}{ok_regions}[[probe]]\nname = \"far\"\nr = 100.0\nz = 0.0\n"),
        &[],
    );
    assert!(e.contains("probe[far].point: outside the mesh (got (r = 0.1 m"), "{e}");

    let e = input_error(
        &format!(
            "{head}[[region]]\nphysical = 1\nmaterial = \"unobtainium\"\n[[region]]\nphysical = 2\nmaterial = \"air\"\n"
        ),
        &[],
    );
    assert!(e.contains("unobtainium"), "{e}");

    // A non-monotone B-H curve.
    let bh = "H_A_per_m,B_T\n0,0\n100,0.5\n200,0.4\n400,1.0\n800,1.2\n";
    let e = input_error(
        &format!(
            "{head}[[region]]\nphysical = 1\nmaterial = {{ bh_csv = \"bh.csv\" }}\n[[region]]\nphysical = 2\nmaterial = \"air\"\n"
        ),
        &[("bh.csv", bh)],
    );
    assert!(e.contains("bh.csv"), "{e}");

    let e = input_error(
        &format!(
            "{head}[[region]]\nphysical = 1\nmaterial = \"air\"\nsource = {{ turns = 10 }}\n[[region]]\nphysical = 2\nmaterial = \"air\"\n"
        ),
        &[],
    );
    assert!(e.contains("current_A"), "{e}");

    let e = input_error("mesh = \"missing.msh\"\n", &[]);
    assert!(e.contains("missing.msh"), "{e}");

    let e = input_error(&format!("{head}{ok_regions}typo = 3\n"), &[]);
    assert!(e.contains("typo"), "{e}");

    for bad in ["3", "0", "\"2\"", "1.5"] {
        let e = input_error(&format!("{head}order = {bad}\n{ok_regions}"), &[]);
        assert!(
            e.contains("p.toml")
                && e.contains(&format!("order: got {bad};"))
                && e.contains("allowed: 1"),
            "{e}"
        );
    }
}

/// The shipped example with quadratic elements, from the `order` key and from the override: the
/// same mesh with about four times the unknowns, and the same field to within the discretisation
/// error.
#[test]
fn example_potcore_solves_with_p2() {
    let example = repo_root().join("examples/fem/potcore.toml");
    let (p1, _, _) = solve_file(&example).unwrap();
    let (p2, solver, solution) = solve_file_with_order(&example, Some(ElementOrder::P2)).unwrap();
    assert_eq!((p1.order, p2.order), (1, 2));
    assert!(p2.converged && p2.nodes == p1.nodes && p2.elements == p1.elements);
    // Unknowns: nodes + edges ≈ 4 × nodes on a triangulation (edges ≈ 3 × nodes).
    assert!(
        p2.unknowns > 3 * p1.unknowns && p2.unknowns < 5 * p1.unknowns,
        "{} vs {}",
        p2.unknowns,
        p1.unknowns
    );
    assert_eq!(solution.a_phi().len(), solver.dof_count());
    assert_eq!(solution.vertex_a_phi().len(), p2.nodes);
    for (a, b) in p1.probes.iter().zip(&p2.probes) {
        assert_eq!(a.name, b.name);
        assert!(
            (a.b_abs_t - b.b_abs_t).abs() < 0.05 * a.b_abs_t.max(0.05),
            "{}: {} vs {}",
            a.name,
            a.b_abs_t,
            b.b_abs_t
        );
    }
    assert!((p1.energy_j - p2.energy_j).abs() < 0.05 * p2.energy_j);
    let json = serde_json::to_value(&p2).unwrap();
    assert_eq!(json["order"], 2);

    // The same through the file's `order` key; the override wins over it.
    let dir = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(&example).unwrap().replacen(
        "mesh = \"potcore.msh\"",
        &format!("order = 2\nmesh = {:?}", repo_root().join("examples/fem/potcore.msh")),
        1,
    );
    assert!(text.contains("order = 2"), "the example names its mesh `potcore.msh`");
    let path = write(dir.path(), "p2.toml", &text);
    let (from_key, _, _) = solve_file(&path).unwrap();
    assert_eq!((from_key.order, from_key.unknowns), (2, p2.unknowns));
    let (overridden, _, _) = solve_file_with_order(&path, Some(ElementOrder::P1)).unwrap();
    assert_eq!((overridden.order, overridden.unknowns), (1, p1.unknowns));
}

#[test]
fn newton_failure_is_numerical_with_history() {
    let mesh = fixture_mesh();
    let toml = format!(
        "mesh = {mesh:?}\nlength_unit = \"mm\"\n[solver]\nmax_iterations = 1\n[[region]]\nphysical = 1\nmaterial = \"steel-1010\"\nsource = {{ current_density_A_per_m2 = 5e8 }}\n[[region]]\nphysical = 2\nmaterial = \"air\"\n[[boundary]]\nphysical = 11\nkind = \"dirichlet\"\n"
    );
    let dir = tempfile::tempdir().unwrap();
    let path = write(dir.path(), "p.toml", &toml);
    match solve_file(&path) {
        Err(e @ MagneticsError::NotConverged { .. }) => {
            assert!(!e.is_input_error());
            let text = e.to_string();
            assert!(text.contains("residual history") && text.contains("#1"), "{text}");
        }
        other => panic!("expected NotConverged, got {:?}", other.map(|r| r.0.newton_iterations)),
    }
}

/// Issue 18: `samples = 1000000000` on a `[[line]]` hung the solve; it is an input error naming
/// the line, before the mesh is solved.
#[test]
fn line_samples_are_bounded() {
    let mesh = fixture_mesh();
    let text = format!(
        "mesh = {mesh:?}\nlength_unit = \"mm\"\n[[region]]\nphysical = 1\nmaterial = {{ mu_r = 100.0 }}\n\
         [[region]]\nphysical = 2\nmaterial = \"air\"\n[[line]]\nname = \"cut\"\nfrom = [1.0, 1.0]\n\
         to = [2.0, 2.0]\nsamples = 1000000000\n"
    );
    let e = input_error(&text, &[]);
    assert!(e.contains("p.toml") && e.contains("'cut'") && e.contains("samples"), "{e}");
}

/// Issue 18: `current_A = 0.0` gave an inductance of NaN (null in JSON). With no other source the
/// secant inductance is its limit, the incremental inductance at zero current; with flux from
/// another coil it has no value, and the input is refused naming the coil.
#[test]
fn zero_current_coil_has_a_finite_inductance_or_an_input_error() {
    let mesh = fixture_mesh();
    let head = format!("mesh = {mesh:?}\nlength_unit = \"mm\"\n");
    let alone = format!(
        "{head}[[region]]\nphysical = 1\nmaterial = {{ mu_r = 100.0 }}\nsource = {{ turns = 100, current_A = 0.0 }}\n\
         [[region]]\nphysical = 2\nmaterial = \"air\"\n"
    );
    let dir = tempfile::tempdir().unwrap();
    let (report, _, _) = solve_file(&write(dir.path(), "p.toml", &alone)).unwrap();
    let c = &report.coils[0];
    assert!(c.inductance_h.is_finite() && c.inductance_h > 0.0, "{c:?}");
    assert!((c.inductance_h - c.incremental_inductance_h).abs() <= 1e-12 * c.inductance_h);

    let mutual = format!(
        "{head}[[region]]\nphysical = 1\nmaterial = {{ mu_r = 100.0 }}\nsource = {{ turns = 100, current_A = 0.0 }}\n\
         [[region]]\nphysical = 2\nmaterial = \"air\"\nsource = {{ turns = 50, current_A = 1.0 }}\n"
    );
    let e = input_error(&mutual, &[]);
    assert!(e.contains("physical = 1") && e.contains("undefined"), "{e}");
}

/// Issue 18, class 5: "unknown material `x`" named neither the file nor the region.
#[test]
fn unknown_material_names_file_and_region() {
    let mesh = fixture_mesh();
    let text = format!(
        "mesh = {mesh:?}\nlength_unit = \"mm\"\n[[region]]\nphysical = 1\nmaterial = \"unobtainium\"\n\
         [[region]]\nphysical = 2\nmaterial = \"air\"\n"
    );
    let e = input_error(&text, &[]);
    assert!(e.contains("p.toml") && e.contains("physical = 1") && e.contains("unobtainium"), "{e}");
}

/// The forces of `fem solve` (`regions[].force_z_N`) obey Newton's third law: the steel (pot and
/// plate, region 1) and the coil (region 2) are the only bodies in air, so their forces cancel (the
/// field far away carries no momentum in statics). Each is a small net force (a few N) left over
/// from the ~10³ N pull between pot and plate, so the residue is measured against that scale (the
/// co-energy over the 1 mm gap) and shrinks with the element order; the coil's force also equals
/// its Lorentz force, an independent formula.
#[test]
fn region_forces_of_the_pot_core_cancel() {
    let example = repo_root().join("examples/fem/potcore.toml");
    let mut residues = Vec::new();
    for order in [ElementOrder::P1, ElementOrder::P2] {
        let (report, solver, solution) = solve_file_with_order(&example, Some(order)).unwrap();
        let force = |tag: u32| report.regions.iter().find(|r| r.physical == tag).unwrap().force_z_n;
        let (steel, coil) = (force(1), force(2));
        let lorentz = solver.lorentz_force_z(&solution, 2).unwrap();
        let scale = report.coenergy_j / 1e-3;
        let residue = (steel + coil).abs() / scale;
        eprintln!(
            "{order:?}: F_steel = {steel:.6e} N, F_coil = {coil:.6e} N, Lorentz {lorentz:.6e} N, \
             scale {scale:.3e} N, residue {residue:.2e}"
        );
        assert!((coil - lorentz).abs() <= 0.02 * lorentz.abs(), "{coil} vs {lorentz}");
        residues.push(residue);
    }
    assert!(residues[0] < 5e-3 && residues[1] < 0.5 * residues[0], "{residues:?}");
}
