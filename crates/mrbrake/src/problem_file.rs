//! `mrbrake fem solve`'s problem files, whatever their physics: the one place the `physics` key
//! is read and the solver chosen, for every front end (the CLI's `fem solve`, Python's
//! `mrbrake.fem.solve`).
//!
//! Brief overview: [`physics_of`] reads a file's header once (only its `physics` key, with a
//! typed struct that ignores the rest) and names its [`Physics`]: absent for magnetics (static,
//! or magnetodynamic with `[transient]` / `[harmonic]`, read by
//! [`mrbrake_magnetics::problem_file`]), `"heat"` for heat conduction
//! ([`mrbrake_heat::problem_file`]); any other value is an input error naming the allowed ones.
//! [`solve`] reads, solves and post-processes the file with that physics's reader and returns a
//! [`Solved`]: the report (its JSON is [`Solved::report`], its text [`Solved::text`], composed by
//! `mrbrake_report::fem` and `mrbrake_report::heat`), the field on the mesh as plain data
//! ([`Solved::field`]) and the ParaView files ([`Solved::vtu_files`]).
//!
//! Why here: the facade is the one crate that sees both physics (magnetics and heat are
//! independent crates on the finite-element core) and the reports that present them.

use std::path::{Path, PathBuf};

use mrbrake_error::{ErrorKind, Kind};
use mrbrake_fem::discretisation::dofs::ElementOrder;
use mrbrake_heat::problem_file::HeatReport;
use mrbrake_heat::solver::HeatSolver;
use mrbrake_magnetics::problem_file::SolveReport;
use mrbrake_magnetics::{Solution, Solver};
use serde::{Deserialize, Serialize};

/// The physics of a problem file.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Physics {
    /// Magnetostatics in A_phi, or its transient or harmonic magnetodynamics (no `physics` key).
    Magnetics,
    /// Heat conduction (`physics = "heat"`).
    Heat,
}

impl Physics {
    /// The name front ends show: `"magnetostatic"` or `"heat"`.
    pub fn name(self) -> &'static str {
        match self {
            Self::Magnetics => "magnetostatic",
            Self::Heat => "heat",
        }
    }
}

/// Errors of reading or solving a problem file.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ProblemFileError {
    /// The file could not be read (a missing file is an input error, a failing disk I/O).
    #[error("{}: cannot read", path.display())]
    Read {
        /// The file.
        path: PathBuf,
        /// The I/O error.
        source: std::io::Error,
    },
    /// The header's `physics` key names no physics mrbrake solves.
    #[error(
        "{}: physics = {value}: not allowed; leave `physics` out for magnetics (static, or with \
         [transient] or [harmonic]) or write physics = \"heat\"",
        path.display()
    )]
    UnknownPhysics {
        /// The file.
        path: PathBuf,
        /// The value given (as TOML).
        value: String,
    },
    /// A magnetic problem file's error (its reader and solver).
    #[error(transparent)]
    Magnetics(#[from] mrbrake_magnetics::MagneticsError),
    /// A heat problem file's error (its reader and solver).
    #[error(transparent)]
    Heat(#[from] mrbrake_heat::HeatError),
    /// A solve of a valid file failed numerically: the file and, in words, the keys most likely
    /// responsible; the solver's own error (with its step, time and history) is the cause.
    #[error("{}: the solve failed; check {keys}", path.display())]
    Solve {
        /// The file.
        path: PathBuf,
        /// The keys of the file most likely responsible.
        keys: &'static str,
        /// The solver's failure.
        #[source]
        source: Box<ProblemFileError>,
    },
}

/// The keys of a magnetic problem file behind most numerical failures.
const MAGNETIC_KEYS: &str = "the regions' materials and conductivity_S_per_m, the sources' turns, \
    current_A and drive, and the [transient] waveform and steps (a value valid on its own can \
    still be far outside what the mesh and the time steps resolve)";

/// The keys of a heat problem file behind most numerical failures.
const HEAT_KEYS: &str = "the regions' materials and heat sources (a Joule current too large for \
    the cooling), the boundaries' h_W_per_m2K, emissivity and temperatures, and the [transient] \
    steps";

impl ProblemFileError {
    /// A numerical failure of the solve of `path` wrapped with `keys`; other errors unchanged.
    fn in_solve(self, path: &Path, keys: &'static str) -> Self {
        if self.kind() == ErrorKind::Numerical {
            Self::Solve { path: path.to_owned(), keys, source: Box::new(self) }
        } else {
            self
        }
    }
}

impl Kind for ProblemFileError {
    /// Input for an unknown physics; the I/O error's kind for an unreadable file; the physics's
    /// own kind otherwise.
    fn kind(&self) -> ErrorKind {
        match self {
            Self::Read { source, .. } => Kind::kind(source),
            Self::UnknownPhysics { .. } => ErrorKind::Input,
            Self::Magnetics(e) => e.kind(),
            Self::Heat(e) => e.kind(),
            Self::Solve { source, .. } => source.kind(),
        }
    }
}

/// The header of every problem file: the `physics` key (the rest is each reader's).
#[derive(Deserialize)]
struct Header {
    physics: Option<toml::Value>,
}

/// The physics of the problem file `text` read from `path`. A file that is not TOML is left to
/// the magnetic reader, which reports where its syntax fails.
pub fn physics_of(text: &str, path: &Path) -> Result<Physics, ProblemFileError> {
    let Ok(header) = toml::from_str::<Header>(text) else { return Ok(Physics::Magnetics) };
    match header.physics {
        None => Ok(Physics::Magnetics),
        Some(toml::Value::String(name)) if name == "heat" => Ok(Physics::Heat),
        Some(other) => Err(ProblemFileError::UnknownPhysics {
            path: path.to_owned(),
            value: other.to_string(),
        }),
    }
}

/// A solved problem file.
pub enum Solved {
    /// A magnetic solve: its report, and the solver and solution of the (final) static state.
    Magnetics {
        /// The report (`fem solve --json`).
        report: Box<SolveReport>,
        /// The solver (mesh, basis, materials).
        solver: Box<Solver>,
        /// The potential.
        solution: Solution,
    },
    /// A heat solve: its report, the solver and the temperature (K) at every degree of freedom.
    Heat {
        /// The report (`fem solve --json`).
        report: Box<HeatReport>,
        /// The solver (mesh, problem).
        solver: Box<HeatSolver>,
        /// Temperature (K) per degree of freedom: the mesh nodes first.
        temperature_k: Vec<f64>,
    },
}

/// The report of a [`Solved`] problem, serialised as that physics's `--json` object.
#[derive(Debug, Clone, Copy, Serialize)]
#[serde(untagged)]
pub enum Report<'a> {
    /// A magnetic solve's report.
    Magnetics(&'a SolveReport),
    /// A heat solve's report.
    Heat(&'a HeatReport),
}

/// A solved field on the mesh as plain data (for plots, NumPy arrays).
#[derive(Debug, Clone, PartialEq)]
pub struct ProblemField {
    /// Node coordinates `[r, z]` (m).
    pub nodes: Vec<[f64; 2]>,
    /// Triangles (node indices, counter-clockwise; the vertices of P2 elements).
    pub triangles: Vec<[usize; 3]>,
    /// Physical tag of every triangle.
    pub region_tags: Vec<u32>,
    /// |B| per triangle (T) for magnetics, the temperature per node (°C) for heat.
    pub values: Vec<f64>,
    /// The flux function `ψ = r A_phi` per node (Wb/rad) for magnetics; `None` for heat.
    pub flux_function_wb: Option<Vec<f64>>,
}

/// Reads, solves and post-processes the problem file at `path` with the solver of its physics;
/// `order` replaces the file's element order (`fem solve --order`).
pub fn solve(path: &Path, order: Option<ElementOrder>) -> Result<Solved, ProblemFileError> {
    let text = mrbrake_error::read::text(path, mrbrake_error::read::SETTINGS)
        .map_err(|source| ProblemFileError::Read { path: path.to_owned(), source })?;
    Ok(match physics_of(&text, path)? {
        Physics::Magnetics => {
            let (report, solver, solution) =
                mrbrake_magnetics::problem_file::solve_file_with_order(path, order)
                    .map_err(|e| ProblemFileError::from(e).in_solve(path, MAGNETIC_KEYS))?;
            Solved::Magnetics { report: Box::new(report), solver: Box::new(solver), solution }
        }
        Physics::Heat => {
            let (report, solver, temperature_k) =
                mrbrake_heat::problem_file::solve_file(path, order)
                    .map_err(|e| ProblemFileError::from(e).in_solve(path, HEAT_KEYS))?;
            Solved::Heat { report: Box::new(report), solver: Box::new(solver), temperature_k }
        }
    })
}

impl Solved {
    /// The physics that was solved.
    pub fn physics(&self) -> Physics {
        match self {
            Self::Magnetics { .. } => Physics::Magnetics,
            Self::Heat { .. } => Physics::Heat,
        }
    }

    /// The report, serialised as `fem solve --json` prints it.
    pub fn report(&self) -> Report<'_> {
        match self {
            Self::Magnetics { report, .. } => Report::Magnetics(report),
            Self::Heat { report, .. } => Report::Heat(report),
        }
    }

    /// The text report of the problem named `name` (as `fem solve` prints it).
    pub fn text(&self, name: &str) -> String {
        match self {
            Self::Magnetics { report, .. } => mrbrake_report::fem::solve_text(report, name),
            Self::Heat { report, .. } => mrbrake_report::heat::solve_text(report, name),
        }
    }

    /// The solved field on the mesh (|B| per triangle, or the temperature per node in °C).
    pub fn field(&self) -> ProblemField {
        match self {
            Self::Magnetics { solver, solution, .. } => {
                let snapshot = solver.field_snapshot(solution);
                ProblemField {
                    nodes: snapshot.nodes,
                    triangles: snapshot.triangles,
                    region_tags: snapshot.region_tags,
                    values: snapshot.element_b_abs_t,
                    flux_function_wb: Some(snapshot.flux_function_wb),
                }
            }
            Self::Heat { solver, temperature_k, .. } => {
                let mesh = solver.problem().mesh.as_ref();
                ProblemField {
                    nodes: mesh.nodes.clone(),
                    triangles: mesh.triangles.clone(),
                    region_tags: mesh.triangle_tags.clone(),
                    values: celsius_at_nodes(mesh.nodes.len(), temperature_k),
                    flux_function_wb: None,
                }
            }
        }
    }

    /// The ParaView files of `fem solve --vtu path`: a magnetic file's static field, a
    /// transient's chosen instants or a harmonic solve's phasors (with a `.pvd` collection when
    /// there are several); a heat file's temperature (°C) at the nodes and region tags.
    pub fn vtu_files(&self, path: &Path) -> Vec<(PathBuf, String)> {
        match self {
            Self::Magnetics { report, solver, solution } => {
                mrbrake_magnetics::problem_file::vtu_files(report, solver, solution, path)
            }
            Self::Heat { solver, temperature_k, .. } => {
                use mrbrake_fem::mesh::vtu::{Field, to_vtu};
                let mesh = solver.problem().mesh.as_ref();
                let celsius = celsius_at_nodes(mesh.nodes.len(), temperature_k);
                let regions: Vec<f64> = mesh.triangle_tags.iter().map(|&t| f64::from(t)).collect();
                let point = [Field { name: "T_C", components: 1, values: &celsius }];
                let cell = [Field { name: "region", components: 1, values: &regions }];
                vec![(path.to_owned(), to_vtu(mesh, &point, &cell))]
            }
        }
    }
}

/// The temperature (°C) of the first `nodes` degrees of freedom (the mesh nodes).
fn celsius_at_nodes(nodes: usize, temperature_k: &[f64]) -> Vec<f64> {
    temperature_k[..nodes].iter().map(|&t| mrbrake_heat::celsius(t)).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn examples() -> PathBuf {
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../examples/fem")
    }

    #[test]
    fn the_header_names_the_physics_once() {
        let path = Path::new("p.toml");
        assert_eq!(physics_of("mesh = \"m.msh\"\n", path).unwrap(), Physics::Magnetics);
        assert_eq!(physics_of("physics = \"heat\"\nmesh = \"m\"\n", path).unwrap(), Physics::Heat);
        // Not TOML: the magnetic reader reports the syntax error with its line.
        assert_eq!(physics_of("mesh = [", path).unwrap(), Physics::Magnetics);
        for bad in ["physics = \"thermal\"", "physics = 3"] {
            let e = physics_of(bad, path).unwrap_err();
            assert!(e.is_input_error(), "{e}");
            let message = e.to_string();
            assert!(message.starts_with("p.toml: physics = "), "{message}");
            assert!(message.contains("\"heat\""), "{message}");
        }
    }

    /// Each shipped example goes to its physics, with its report, text and field.
    #[test]
    fn examples_are_solved_by_their_physics() {
        for (file, physics) in
            [("potcore.toml", Physics::Magnetics), ("potcore-heat.toml", Physics::Heat)]
        {
            let solved = solve(&examples().join(file), None).unwrap();
            assert_eq!(solved.physics(), physics, "{file}");
            let json = serde_json::to_value(solved.report()).unwrap();
            assert!(json["nodes"].as_u64().is_some_and(|n| n > 0), "{file}: {json}");
            assert!(solved.text(file).starts_with(file), "{file}");
            let field = solved.field();
            let per =
                if physics == Physics::Heat { field.nodes.len() } else { field.triangles.len() };
            assert_eq!(field.values.len(), per, "{file}");
            assert_eq!(field.flux_function_wb.is_some(), physics == Physics::Magnetics);
            let files = solved.vtu_files(Path::new("out.vtu"));
            assert!(files[0].1.contains("<VTKFile"), "{file}");
        }
        let missing = solve(Path::new("no/such/problem.toml"), None).err().unwrap();
        assert!(missing.is_input_error(), "{missing}");
    }
}
