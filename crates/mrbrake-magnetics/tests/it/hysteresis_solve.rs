//! Validation of the quasi-static hysteretic solve ([`mrbrake_magnetics::hysteresis`]):
//! (a) a uniform-field case equals the material model driven directly, (b) the first loading step
//! and the solve without hysteresis are the anhysteretic solves, (c) the electrical work of a current
//! cycle equals the energy the model dissipates.
//!
//! The uniform-field case of the axisymmetric A_phi formulation is the infinitely long solenoid (a
//! toroid's field is azimuthal, which A_phi cannot carry): a steel core `r < R1` inside a winding
//! `R1 < r < R2`, a slab `0 < z < L` with natural conditions on every outer edge (`n × H = 0`: no
//! field outside, no radial field). Ampère's law then gives the core `H = N I / L` exactly.

use std::sync::Arc;

use mrbrake_fem::mesh::structured::{SideTags, graded_lines, rectangle_mesh};
use mrbrake_magnetics::hysteresis::HysteresisCommit;
use mrbrake_magnetics::problem::{Boundary, BoundaryCondition, Problem, Region, Source};
use mrbrake_magnetics::{ElementOrder, Solution, Solver, SolverOptions};
use mrbrake_materials::Magnetic;
use mrbrake_materials::hysteresis::{HysteresisParams, HysteresisState, NormalCurve, library};

const CORE: u32 = 1;
const COIL: u32 = 2;
const AIR: u32 = 3;
const R1: f64 = 0.01;
const R2: f64 = 0.012;
const LENGTH: f64 = 0.004;
const TURNS: f64 = 100.0;

fn steel() -> Arc<HysteresisParams> {
    Arc::clone(&library::for_material("steel-1008").unwrap().params)
}

/// The long solenoid (module docs), P1 or P2.
/// The winding is meshed finely (16 layers): the field varies across it, and a uniform core field
/// that is steep in B(H) magnifies its discretisation error.
fn solenoid(order: ElementOrder) -> Solver {
    let mut r = graded_lines(0.0, R1, 10, 1.0);
    r.extend(graded_lines(R1, R2, 16, 1.0).into_iter().skip(1));
    let z = graded_lines(0.0, LENGTH, 1, 1.0);
    let region = |r: f64, _| if r < R1 { CORE } else { COIL };
    let sides = SideTags { r_min: 10, r_max: 11, z_min: 12, z_max: 13 };
    let mesh = rectangle_mesh(&r, &z, region, sides).unwrap();
    let steel = Magnetic::NonLinear(Arc::new(NormalCurve::new(steel())));
    let problem = Problem {
        mesh: Arc::new(mesh),
        regions: vec![
            Region { tag: CORE, material: steel, source: None },
            Region { tag: COIL, material: Magnetic::air(), source: None },
        ],
        boundaries: vec![],
    };
    Solver::new(problem, SolverOptions { order, ..SolverOptions::default() }).unwrap()
}

/// `0 → peak → 0 → −peak → 0 → peak`, `per_leg` steps per leg (the first point excluded).
fn major_history(peak: f64, per_leg: usize) -> Vec<f64> {
    let legs = [(0.0, peak), (peak, 0.0), (0.0, -peak), (-peak, 0.0), (0.0, peak)];
    let mut history = Vec::new();
    for (from, to) in legs {
        for k in 1..=per_leg {
            history.push(from + (to - from) * k as f64 / per_leg as f64);
        }
    }
    history
}

/// Runs `history` on the coil; per step the current, the solution and the commit.
fn run(solver: &mut Solver, history: &[f64]) -> Vec<(f64, Solution, HysteresisCommit)> {
    let mut previous: Option<Solution> = None;
    let mut steps = Vec::new();
    for &current in history {
        solver.set_source(COIL, Some(Source::Coil { turns: TURNS, current_a: current })).unwrap();
        let (solution, commit) = solver.solve_step(previous.as_ref().map(|s| s.a_phi())).unwrap();
        previous = Some(solution.clone());
        steps.push((current, solution, commit));
    }
    steps
}

/// (a) The core's B along a major loop and a minor loop equals the model driven by `H = N I / L`:
/// with P2 elements to 1e-5 T; with P1, whose error in the winding is larger (A is not linear
/// there), the core's field H (the model run B-driven on the FEA's B) is within 3 % of `N I / L`.
#[test]
fn uniform_field_loop_equals_the_material_model() {
    let params = steel();
    for order in [ElementOrder::P2, ElementOrder::P1] {
        let mut solver = solenoid(order);
        solver.set_hysteresis(&[(CORE, Arc::clone(&params))]).unwrap();
        // A major loop (H peak 8 kA/m) with a minor loop inside its rising branch.
        let peak = 8000.0 * LENGTH / TURNS;
        let mut history = major_history(peak, 12);
        history.extend([0.5 * peak, 0.1 * peak, 0.4 * peak, 0.7 * peak]);
        let mut driven = HysteresisState::demagnetised();
        let mut followed = HysteresisState::demagnetised();
        let (mut worst_b, mut worst_h): (f64, f64) = (0.0, 0.0);
        for (current, solution, commit) in run(&mut solver, &history) {
            let h = TURNS * current / LENGTH;
            let expected = driven.step_h(&params, h).b;
            let b = solver.b_at(&solution, [0.5 * R1, 0.5 * LENGTH]).unwrap();
            worst_b = worst_b.max((b.b_z_t - expected).abs()).max(b.b_r_t.abs());
            let h_fea = followed.step(&params, b.b_z_t).h;
            worst_h = worst_h.max((h_fea - h).abs() / (8000.0f64).max(h.abs()));
            assert!(commit.max_perpendicular_b_t < 1e-4, "{order:?}: the field turned: {commit:?}");
        }
        match order {
            ElementOrder::P2 => assert!(worst_b < 1e-5, "P2: largest |B − B_model| = {worst_b} T"),
            ElementOrder::P1 => assert!(worst_h < 0.03, "P1: largest H error {worst_h}"),
        }
        eprintln!("{order:?}: largest |B − B_model| {worst_b:.3e} T, H error {worst_h:.3e}");
    }
}

/// A steel core of finite length in an air box: a field that is not uniform and turns.
fn pot(order: ElementOrder) -> Solver {
    let r = graded_lines(0.0, 0.06, 24, 1.0);
    let z = graded_lines(-0.06, 0.06, 48, 1.0);
    let region = |r: f64, z: f64| {
        if r < 0.01 && z.abs() < 0.02 {
            CORE
        } else if (0.012..0.016).contains(&r) && z.abs() < 0.015 {
            COIL
        } else {
            AIR
        }
    };
    let sides = SideTags { r_min: 10, r_max: 11, z_min: 12, z_max: 13 };
    let mesh = rectangle_mesh(&r, &z, region, sides).unwrap();
    let steel = Magnetic::NonLinear(Arc::new(NormalCurve::new(steel())));
    let dirichlet = |tag| Boundary { tag, condition: BoundaryCondition::Dirichlet };
    let problem = Problem {
        mesh: Arc::new(mesh),
        regions: vec![
            Region { tag: CORE, material: steel, source: None },
            Region { tag: COIL, material: Magnetic::air(), source: None },
            Region { tag: AIR, material: Magnetic::air(), source: None },
        ],
        boundaries: vec![dirichlet(11), dirichlet(12), dirichlet(13)],
    };
    Solver::new(problem, SolverOptions { order, ..SolverOptions::default() }).unwrap()
}

/// (b) From the demagnetised state the first step is the model's normal curve, isotropic: the
/// anhysteretic solve on [`NormalCurve`]; and a solver whose hysteresis is switched off again
/// gives today's anhysteretic solve bit for bit.
#[test]
fn first_step_and_switched_off_solves_are_the_anhysteretic_solve() {
    let current = 3000.0 / TURNS;
    let source = Some(Source::Coil { turns: TURNS, current_a: current });
    let mut plain = pot(ElementOrder::P1);
    plain.set_source(COIL, source).unwrap();
    let anhysteretic = plain.solve(None).unwrap();

    let mut hysteretic = pot(ElementOrder::P1);
    hysteretic.set_source(COIL, source).unwrap();
    hysteretic.set_hysteresis(&[(CORE, steel())]).unwrap();
    let first = hysteretic.solve(None).unwrap();
    let scale = anhysteretic.a_phi().iter().fold(0.0_f64, |m, a| m.max(a.abs()));
    let worst = first
        .a_phi()
        .iter()
        .zip(anhysteretic.a_phi())
        .fold(0.0_f64, |m, (x, y)| m.max((x - y).abs()));
    assert!(worst <= 1e-8 * scale, "first step differs by {worst} (scale {scale})");

    hysteretic.set_hysteresis(&[]).unwrap();
    assert!(!hysteretic.has_hysteresis());
    let off = hysteretic.solve(None).unwrap();
    let same =
        off.a_phi().iter().zip(anhysteretic.a_phi()).all(|(x, y)| x.to_bits() == y.to_bits());
    assert!(same, "the solve without hysteresis changed");
}

/// (c) Over a closed current cycle the electrical work `∮ I dλ` equals the energy the model
/// dissipated, and per unit core volume the material's own loop area `∮ H dB`; on a non-uniform
/// field (the core in air) too, where it also checks that the field barely turns.
#[test]
#[cfg_attr(not(heavy_tests), ignore = "release only: 1600 non-linear solves")]
fn cycle_work_equals_dissipated_energy() {
    let params = steel();
    for (name, mut solver, peak) in [
        ("solenoid", solenoid(ElementOrder::P1), 2.0),
        ("core in air", pot(ElementOrder::P1), 60.0),
    ] {
        solver.set_hysteresis(&[(CORE, Arc::clone(&params))]).unwrap();
        let per_leg = 320;
        let steps = run(&mut solver, &major_history(peak, per_leg));
        // The last full cycle: from the peak (end of leg 1) back to the peak (end of leg 5).
        let cycle = &steps[per_leg - 1..];
        let linkage = |s: &Solution| {
            solver.coils(s).iter().find(|c| c.physical == COIL).unwrap().flux_linkage_wb
        };
        let mut work = 0.0;
        for pair in cycle.windows(2) {
            let (i0, l0) = (pair[0].0, linkage(&pair[0].1));
            let (i1, l1) = (pair[1].0, linkage(&pair[1].1));
            work += 0.5 * (i0 + i1) * (l1 - l0);
        }
        let dissipated: f64 = cycle[1..].iter().map(|s| s.2.dissipated_j).sum();
        assert!(dissipated > 0.0);
        assert!(
            (work - dissipated).abs() <= 0.01 * dissipated,
            "{name}: ∮ I dλ = {work} J, dissipated {dissipated} J"
        );
        let turned = steps.iter().map(|s| s.2.max_perpendicular_b_t).fold(0.0, f64::max);
        eprintln!("{name}: largest |B⊥| {turned} T");
        if name == "solenoid" {
            let h_peak = TURNS * peak / LENGTH;
            let area = mrbrake_materials::hysteresis::loop_measures(
                &mrbrake_materials::hysteresis::major_loop(&params, h_peak, 4000),
            )
            .area_j_per_m3;
            let volume = std::f64::consts::PI * R1 * R1 * LENGTH;
            assert!(
                (area * volume - dissipated).abs() <= 0.01 * dissipated,
                "loop area × volume {} J vs {dissipated} J",
                area * volume
            );
        }
    }
}

/// Newton's iterations per step along the major loop stay few (the consistent tangent).
#[test]
fn newton_iterations_per_step_stay_few() {
    let mut solver = solenoid(ElementOrder::P1);
    solver.set_hysteresis(&[(CORE, steel())]).unwrap();
    let history = major_history(8000.0 * LENGTH / TURNS, 12);
    let steps = run(&mut solver, &history);
    let most = steps.iter().map(|s| s.1.report.iterations).max().unwrap();
    let total: usize = steps.iter().map(|s| s.1.report.iterations).sum();
    eprintln!("Newton iterations over {} steps: {total}, at most {most} per step", steps.len());
    assert!(most <= 12, "a step took {most} Newton iterations");
    // The history ends at its peak: energy is stored in the core; none once demagnetised.
    assert!(solver.stored_hysteresis_energy_j() > 0.0);
    solver.demagnetise();
    assert!(solver.stored_hysteresis_energy_j().abs() < 1e-30);
}
