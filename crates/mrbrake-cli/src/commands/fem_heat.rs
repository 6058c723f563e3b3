//! `mrbrake fem solve` for `physics = "heat"` problem files (see
//! `mrbrake_heat::problem_file`): steady or transient heat conduction, text or `--json`
//! (probes, regions, boundaries, energy_balance_W, transient), `--vtu` with the temperature.

use std::path::Path;

use mrbrake_heat::ElementOrder;
use mrbrake_heat::problem_file::{is_heat_file, solve_file};

use crate::error::{CommandResult, InputError};
use crate::output::print_json;

/// True when `path` is a readable TOML file with `physics = "heat"`.
pub fn is_heat(path: &Path) -> bool {
    std::fs::read_to_string(path).map(|text| is_heat_file(&text)).unwrap_or(false)
}

/// Solves the heat problem file `path` and prints or writes the outputs.
pub fn solve(
    path: &Path,
    order: Option<ElementOrder>,
    json: bool,
    vtu: Option<&Path>,
    plot: Option<&Path>,
) -> CommandResult {
    if plot.is_some() {
        return Err(InputError(
            "--plot draws |B| maps of magnetostatic files; for a heat file use --vtu".into(),
        )
        .into());
    }
    let (report, solver, temperature) = solve_file(path, order)?;
    if let Some(path) = vtu {
        let mesh = solver.problem().mesh.as_ref();
        let celsius: Vec<f64> =
            temperature[..mesh.nodes.len()].iter().map(|&t| mrbrake_heat::celsius(t)).collect();
        let regions: Vec<f64> = mesh.triangle_tags.iter().map(|&t| f64::from(t)).collect();
        let point =
            [mrbrake_fem::mesh::vtu::Field { name: "T_C", components: 1, values: &celsius }];
        let cell =
            [mrbrake_fem::mesh::vtu::Field { name: "region", components: 1, values: &regions }];
        mrbrake_report::write_atomic(
            path,
            mrbrake_fem::mesh::vtu::to_vtu(mesh, &point, &cell).as_bytes(),
        )?;
    }
    if json {
        return print_json(&report);
    }
    crate::out!("{}", mrbrake_report::heat::solve_text(&report, &path.display().to_string()));
    Ok(())
}
