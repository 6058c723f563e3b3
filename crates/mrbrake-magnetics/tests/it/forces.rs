//! Validation of the electromagnetic force (`mrbrake_magnetics::force`) against closed forms and
//! against the virtual work of the co-energy:
//! - two coaxial coils in air: the force by virtual work on the element layer and the Lorentz
//!   force on the coil's current against the elliptic-integral force of the sections
//!   (`exact::thick_coils_force_z`), under mesh refinement, and Newton's third law;
//! - a pot core and its plate across an air gap (non-linear steel): the force on the plate by the
//!   element layer against the derivative of the co-energy with the gap at constant current
//!   (`F = ∂W'/∂g`, central differences on meshes whose gap cells stretch), under refinement.

use std::sync::Arc;

use mrbrake_fem::mesh::structured::{SideTags, graded_lines, join_lines, rectangle_mesh};
use mrbrake_magnetics::exact::{CoilSection, thick_coil_a_phi, thick_coils_force_z};
use mrbrake_magnetics::material::Magnetic;
use mrbrake_magnetics::problem::{Boundary, BoundaryCondition, Problem, Region, Source};
use mrbrake_magnetics::{ElementOrder, Solver, SolverOptions};

const AXIS: u32 = 100;
const OUTER: u32 = 101;
const AIR: u32 = 1;
const COIL_1: u32 = 2;
const COIL_2: u32 = 3;

fn air(tag: u32) -> Region {
    Region { tag, material: Magnetic::air(), source: None }
}

/// Grid lines through `breaks` (m) with cells no longer than `h` inside `[inner_from, inner_to]`
/// and graded cells outside.
fn lines(breaks: &[f64], h: f64) -> Vec<f64> {
    let segments: Vec<Vec<f64>> = breaks
        .windows(2)
        .map(|w| graded_lines(w[0], w[1], ((w[1] - w[0]) / h).ceil().max(1.0) as usize, 1.0))
        .collect();
    join_lines(&segments)
}

/// The two coils of the coaxial test: `(coil 1, coil 2)`, 1 MA/m² each, the same direction.
fn coils() -> (CoilSection, CoilSection) {
    let mm = 1e-3;
    let j = 1e6;
    (
        CoilSection { r1: 18.0 * mm, r2: 22.0 * mm, z1: -2.0 * mm, z2: 2.0 * mm, j },
        CoilSection { r1: 25.0 * mm, r2: 29.0 * mm, z1: 6.0 * mm, z2: 10.0 * mm, j },
    )
}

/// `(virtual work on coil 2, Lorentz on coil 2, virtual work on coil 1)` (N) on a mesh of cell
/// size `h` near the coils, with the exact potential of both coils on the box `r ≤ 80 mm`,
/// `|z| ≤ 80 mm`.
fn coaxial_coil_forces(h: f64, order: ElementOrder) -> (f64, f64, f64) {
    let (c1, c2) = coils();
    coil_pair_forces(c1, c2, h, order)
}

/// [`coaxial_coil_forces`] for any two coil sections whose edges lie on the grid's breaks.
fn coil_pair_forces(
    c1: CoilSection,
    c2: CoilSection,
    h: f64,
    order: ElementOrder,
) -> (f64, f64, f64) {
    let mm = 1e-3;
    let r = lines(&[0.0, 18.0 * mm, 22.0 * mm, 25.0 * mm, 29.0 * mm, 40.0 * mm], h);
    let r = join_lines(&[r, graded_lines(40.0 * mm, 80.0 * mm, 12, 3.0)]);
    let z_core = lines(&[-20.0 * mm, -2.0 * mm, 2.0 * mm, 6.0 * mm, 10.0 * mm, 25.0 * mm], h);
    let z = join_lines(&[
        graded_lines(-80.0 * mm, -20.0 * mm, 12, 1.0 / 3.0),
        z_core,
        graded_lines(25.0 * mm, 80.0 * mm, 12, 3.0),
    ]);
    let inside = |c: &CoilSection, r: f64, z: f64| r > c.r1 && r < c.r2 && z > c.z1 && z < c.z2;
    let tag = move |rc: f64, zc: f64| {
        if inside(&c1, rc, zc) {
            COIL_1
        } else if inside(&c2, rc, zc) {
            COIL_2
        } else {
            AIR
        }
    };
    let sides = SideTags { r_min: AXIS, r_max: OUTER, z_min: OUTER, z_max: OUTER };
    let exact = move |p: [f64; 2]| {
        thick_coil_a_phi(&c1, p[0], p[1], 2) + thick_coil_a_phi(&c2, p[0], p[1], 2)
    };
    let coil = |tag: u32, c: &CoilSection| Region {
        tag,
        material: Magnetic::air(),
        source: Some(Source::CurrentDensity { a_per_m2: c.j }),
    };
    let problem = Problem {
        mesh: Arc::new(rectangle_mesh(&r, &z, tag, sides).unwrap()),
        regions: vec![air(AIR), coil(COIL_1, &c1), coil(COIL_2, &c2)],
        boundaries: vec![Boundary {
            tag: OUTER,
            condition: BoundaryCondition::Prescribed(Arc::new(exact)),
        }],
    };
    let mut solver = Solver::new(problem, SolverOptions { order, ..Default::default() }).unwrap();
    let solution = solver.solve(None).unwrap();
    (
        solver.axial_force(&solution, &[COIL_2]).unwrap(),
        solver.lorentz_force_z(&solution, COIL_2).unwrap(),
        solver.axial_force(&solution, &[COIL_1]).unwrap(),
    )
}

#[test]
fn coaxial_coils_match_the_elliptic_integral_force() {
    let (c1, c2) = coils();
    let exact = thick_coils_force_z(&c1, &c2, 2);
    assert!(exact < 0.0, "currents the same way attract: {exact}");
    for order in [ElementOrder::P1, ElementOrder::P2] {
        let mut errors = Vec::new();
        for h_mm in [1.0, 0.5, 0.25] {
            let (work, lorentz, on_coil_1) = coaxial_coil_forces(h_mm * 1e-3, order);
            let error = |f: f64| (f - exact).abs() / exact.abs();
            println!(
                "{order:?} h = {h_mm} mm: virtual work {work:.6e} N ({:.2e}), Lorentz {lorentz:.6e} N ({:.2e}), on coil 1 {on_coil_1:.6e} N, exact {exact:.6e} N",
                error(work),
                error(lorentz)
            );
            errors.push((error(work), error(lorentz), (work + on_coil_1).abs() / exact.abs()));
        }
        let (work, lorentz, third_law) = errors[errors.len() - 1];
        assert!(work < 2e-3 && lorentz < 2e-3, "{order:?}: {errors:?}");
        assert!(third_law < 2e-3, "{order:?}: action and reaction differ: {errors:?}");
        assert!(errors[2].0 < errors[0].0, "{order:?}: no convergence {errors:?}");
    }
}

const STEEL_POT: u32 = 10;
const STEEL_PLATE: u32 = 11;
const POT_COIL: u32 = 12;
const GAP: u32 = 13;

/// The pot core of `tests/it/validation.rs` (pot r < 30 mm, z −20..15 mm, window r 10..25 mm,
/// z −15..15 mm; 500 turns at `current`; the plate 5 mm thick above a gap of `gap_mm`) on a
/// tensor mesh of `cells_per_mm` cells per mm in the core and 4 cells across the gap; air box
/// r < 60 mm, z −60..60 mm, A = 0 on it. Returns the solver and solution.
fn pot_core(gap_mm: f64, cells_per_mm: f64, current: f64) -> (Solver, mrbrake_magnetics::Solution) {
    let mm = 1e-3;
    let h = mm / cells_per_mm;
    let plate = 15.0 + gap_mm;
    let mut r = lines(&[0.0, 10.0 * mm, 12.0 * mm, 23.0 * mm, 25.0 * mm, 30.0 * mm], h);
    r = join_lines(&[r, graded_lines(30.0 * mm, 60.0 * mm, 16, 4.0)]);
    let z = join_lines(&[
        graded_lines(-60.0 * mm, -20.0 * mm, 16, 0.25),
        lines(&[-20.0 * mm, -15.0 * mm, -13.0 * mm, 13.0 * mm, 15.0 * mm], h),
        graded_lines(15.0 * mm, plate * mm, 4, 1.0),
        lines(&[plate * mm, (plate + 5.0) * mm], h),
        graded_lines((plate + 5.0) * mm, 60.0 * mm, 16, 4.0),
    ]);
    let tag = move |rc: f64, zc: f64| {
        let (rm, zm) = (rc / mm, zc / mm);
        if rm < 30.0 && zm > -20.0 && zm < 15.0 && !(rm > 10.0 && rm < 25.0 && zm > -15.0) {
            STEEL_POT
        } else if rm < 30.0 && zm > plate && zm < plate + 5.0 {
            STEEL_PLATE
        } else if rm > 12.0 && rm < 23.0 && zm > -13.0 && zm < 13.0 {
            POT_COIL
        } else if rm < 30.0 && zm > 15.0 && zm < plate {
            GAP
        } else {
            AIR
        }
    };
    let sides = SideTags { r_min: AXIS, r_max: OUTER, z_min: OUTER, z_max: OUTER };
    let steel = mrbrake_materials::library::get("steel-1010").unwrap().magnetic.clone();
    let problem = Problem {
        mesh: Arc::new(rectangle_mesh(&r, &z, tag, sides).unwrap()),
        regions: vec![
            Region { tag: STEEL_POT, material: steel.clone(), source: None },
            Region { tag: STEEL_PLATE, material: steel, source: None },
            Region {
                tag: POT_COIL,
                material: Magnetic::air(),
                source: Some(Source::Coil { turns: 500.0, current_a: current }),
            },
            air(AIR),
            air(GAP),
        ],
        boundaries: vec![Boundary { tag: OUTER, condition: BoundaryCondition::Dirichlet }],
    };
    let mut solver = Solver::new(problem, SolverOptions::default()).unwrap();
    let solution = solver.solve(None).unwrap();
    (solver, solution)
}

/// `(layer force on the plate, co-energy derivative)` (N) for a 1 mm gap.
fn pot_core_forces(cells_per_mm: f64, current: f64) -> (f64, f64) {
    let (gap, delta) = (1.0, 0.01);
    let (solver, solution) = pot_core(gap, cells_per_mm, current);
    let layer = solver.axial_force(&solution, &[STEEL_PLATE]).unwrap();
    let co_energy = |g: f64| {
        let (s, sol) = pot_core(g, cells_per_mm, current);
        s.energy(&sol).1
    };
    let virtual_work = (co_energy(gap + delta) - co_energy(gap - delta)) / (2.0 * delta * 1e-3);
    (layer, virtual_work)
}

#[test]
fn pot_core_plate_force_equals_the_co_energy_derivative() {
    for current in [0.5, 2.0] {
        let mut differences = Vec::new();
        for cells in [1.0, 2.0] {
            let (layer, virtual_work) = pot_core_forces(cells, current);
            let difference = (layer - virtual_work).abs() / virtual_work.abs();
            println!(
                "pot core {current} A, {cells} cells/mm: layer {layer:.5} N, dW'/dg {virtual_work:.5} N, difference {difference:.2e}"
            );
            assert!(layer < 0.0 && virtual_work < 0.0, "the plate is pulled towards the pot");
            differences.push(difference);
        }
        assert!(differences[1] < 0.01, "{current} A: {differences:?}");
    }
}

/// Two coils that touch (one on top of the other): the layer of each lies partly in the other's
/// current, where the stress is not divergence-free, and the force takes that Lorentz force off.
/// The layer force then equals the Lorentz force on the coil, action equals reaction, and both
/// tend to the elliptic-integral force of the two sections under refinement.
#[test]
fn touching_coils_keep_action_and_reaction() {
    let mm = 1e-3;
    let lower = CoilSection { r1: 18.0 * mm, r2: 22.0 * mm, z1: -2.0 * mm, z2: 2.0 * mm, j: 1e6 };
    let upper = CoilSection { z1: 2.0 * mm, z2: 6.0 * mm, ..lower };
    let exact = thick_coils_force_z(&lower, &upper, 4);
    let mut rows = Vec::new();
    for h_mm in [1.0, 0.5, 0.25] {
        let (work, lorentz, on_lower) =
            coil_pair_forces(lower, upper, h_mm * 1e-3, ElementOrder::P2);
        let (vs_lorentz, third_law) =
            ((work - lorentz).abs() / lorentz.abs(), (work + on_lower).abs() / lorentz.abs());
        println!(
            "h = {h_mm} mm: layer {work:.6e} N, Lorentz {lorentz:.6e} N, on the lower coil \
             {on_lower:.6e} N, elliptic integrals {exact:.6e} N"
        );
        rows.push((vs_lorentz, third_law, (work - exact).abs() / exact.abs()));
    }
    let (vs_lorentz, third_law, vs_exact) = rows[rows.len() - 1];
    assert!(vs_lorentz < 1e-4 && third_law < 1e-4, "{rows:?}");
    assert!(vs_exact < 2e-2 && rows[2].2 < rows[0].2, "{rows:?}");
}
