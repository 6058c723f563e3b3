//! The saturating benchmark problem of the performance target (issue 3): an axisymmetric pot-core
//! electromagnet (steel pot and armature separated by a 1 mm gap, coil in the window) on a graded
//! structured mesh of about `target_nodes` nodes, driven far into saturation (peak |B| above 2 T).
//! Used by `benches/saturating.rs` and `examples/saturating_benchmark.rs`; with a linear conducting
//! core ([`conducting_pot_core`]) the magnetodynamics benchmark of `benches/dynamics.rs`.

use std::sync::Arc;

use mrbrake_fem::mesh::structured::{SideTags, graded_lines, join_lines, rectangle_mesh};

use crate::MagneticsError;
use crate::dynamics::{Coil, Conductor, Drive, Dynamics, Waveform};
use crate::material::Magnetic;
use crate::problem::{Boundary, BoundaryCondition, Problem, Region, Source};
use crate::solver::{Solver, SolverOptions};

/// Region tags of the benchmark.
pub const STEEL: u32 = 1;
/// Coil region tag.
pub const COIL: u32 = 2;
/// Air region tag.
pub const AIR: u32 = 3;

/// The pot core with a linear conducting core (μr = 1000, σ = 5.8 MS/m, FEMM's steel value) on
/// about `target_nodes` nodes, its 500-turn coil driven by a current step to 1 A: the transient
/// and harmonic benchmark of `benches/dynamics.rs`.
pub fn conducting_pot_core(target_nodes: usize) -> Result<Dynamics, MagneticsError> {
    let problem = pot_core_problem(target_nodes, Magnetic::Linear { mu_r: 1000.0 }, 1.0)?;
    let solver = Solver::new(problem, SolverOptions::default())?;
    let conductors = [Conductor { tag: STEEL, conductivity_s_per_m: 5.8e6 }];
    let coil = Coil {
        tag: COIL,
        turns: 500.0,
        drive: Drive::Current { amplitude_a: 1.0 },
        waveform: Waveform::Step { initial: 0.0 },
    };
    Dynamics::new(solver, &conductors, vec![coil])
}

/// Builds the benchmark problem with about `target_nodes` nodes, `current_a` in a 500-turn coil and
/// the given steel (e.g. the library's `steel-1010`).
pub fn pot_core_problem(
    target_nodes: usize,
    steel: Magnetic,
    current_a: f64,
) -> Result<Problem, MagneticsError> {
    // Geometry (m): pot r 0..30 mm, z −20..15 mm with window r 10..25 mm, z −15..15 mm; plate z 16..21 mm;
    // coil r 12..23 mm, z −13..13 mm; air box r 0..60 mm, z −60..60 mm.
    let mm = 1e-3;
    // Cells per mm in the core, chosen so that the grid has about target_nodes nodes.
    let base = ((target_nodes as f64) / 3_900.0).sqrt().max(0.2);
    let cells = |length_mm: f64| ((length_mm * base).ceil() as usize).max(1);
    let r_breaks: [f64; 6] = [0.0, 10.0, 12.0, 23.0, 25.0, 30.0];
    let z_breaks: [f64; 7] = [-20.0, -15.0, -13.0, 13.0, 15.0, 16.0, 21.0];
    let mut r_segments: Vec<Vec<f64>> = r_breaks
        .windows(2)
        .map(|w| graded_lines(w[0] * mm, w[1] * mm, cells(w[1] - w[0]), 1.0))
        .collect();
    r_segments.push(graded_lines(30.0 * mm, 60.0 * mm, cells(30.0) / 2 + 1, 4.0));
    let mut z_segments = vec![graded_lines(-60.0 * mm, -20.0 * mm, cells(40.0) / 2 + 1, 0.25)];
    z_segments.extend(z_breaks.windows(2).map(|w| {
        // The 1 mm gap gets at least 4 cells.
        let n =
            if (w[1] - w[0] - 1.0).abs() < 1e-9 { cells(1.0).max(4) } else { cells(w[1] - w[0]) };
        graded_lines(w[0] * mm, w[1] * mm, n, 1.0)
    }));
    z_segments.push(graded_lines(21.0 * mm, 60.0 * mm, cells(39.0) / 2 + 1, 4.0));
    let r = join_lines(&r_segments);
    let z = join_lines(&z_segments);
    let tag = |rc: f64, zc: f64| {
        let (rm, zm) = (rc / mm, zc / mm);
        let in_pot =
            rm < 30.0 && zm > -20.0 && zm < 15.0 && !(rm > 10.0 && rm < 25.0 && zm > -15.0);
        let in_plate = rm < 30.0 && zm > 16.0 && zm < 21.0;
        let in_coil = rm > 12.0 && rm < 23.0 && zm > -13.0 && zm < 13.0;
        if in_pot || in_plate {
            STEEL
        } else if in_coil {
            COIL
        } else {
            AIR
        }
    };
    let sides = SideTags { r_min: 20, r_max: 21, z_min: 21, z_max: 21 };
    let mesh = rectangle_mesh(&r, &z, tag, sides)?;
    Ok(Problem {
        mesh: Arc::new(mesh),
        regions: vec![
            Region { tag: STEEL, material: steel, source: None },
            Region {
                tag: COIL,
                material: Magnetic::air(),
                source: Some(Source::Coil { turns: 500.0, current_a }),
            },
            Region { tag: AIR, material: Magnetic::air(), source: None },
        ],
        boundaries: vec![Boundary { tag: 21, condition: BoundaryCondition::Dirichlet }],
    })
}
