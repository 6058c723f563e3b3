//! Mesh and current-step convergence of the remanent flux of the hysteretic solve
//! ([`mrbrake_magnetics::hysteresis`]) on the pot core of [`mrbrake_magnetics::benchmark`] (a steel
//! pot and plate across a 1 mm air gap, a 500-turn coil): the coil is driven `0 → I_p → 0` and the
//! flux linkage left at 0 A (the remanent flux, times the turns) is compared on grids with 0.5, 1
//! and 2 cells per mm in the steel (element size h, h/2, h/4; linear elements) and with the steps
//! per leg doubled twice. The differences between successive levels must shrink; the observed
//! order `log2(d₁/d₂)` is printed.

use std::sync::Arc;

use mrbrake_magnetics::benchmark::{COIL, STEEL, pot_core_problem};
use mrbrake_magnetics::problem::Source;
use mrbrake_magnetics::{Solution, Solver, SolverOptions};
use mrbrake_materials::Magnetic;
use mrbrake_materials::hysteresis::{NormalCurve, library};

/// Peak current of the history, A (1000 A-turns across the 1 mm gap: about 1.2 T there).
const PEAK_A: f64 = 2.0;

/// The benchmark's turns.
const TURNS: f64 = 500.0;

/// The coil's flux linkage at 0 A after `0 → PEAK_A → 0` with `per_leg` steps per leg, on the pot
/// core of about `target_nodes` nodes, Wb.
fn remanent_linkage(target_nodes: usize, per_leg: usize) -> f64 {
    let params = Arc::clone(&library::for_material("steel-1008").unwrap().params);
    let steel = Magnetic::NonLinear(Arc::new(NormalCurve::new(Arc::clone(&params))));
    let problem = pot_core_problem(target_nodes, steel, 0.0).unwrap();
    let mut solver = Solver::new(problem, SolverOptions::default()).unwrap();
    solver.set_hysteresis(&[(STEEL, params)]).unwrap();
    let history = (1..=per_leg)
        .map(|k| PEAK_A * k as f64 / per_leg as f64)
        .chain((1..=per_leg).map(|k| PEAK_A * (1.0 - k as f64 / per_leg as f64)));
    let mut previous: Option<Solution> = None;
    for current in history {
        solver.set_source(COIL, Some(Source::Coil { turns: TURNS, current_a: current })).unwrap();
        let (solution, _) = solver.solve_step(previous.as_ref().map(|s| s.a_phi())).unwrap();
        previous = Some(solution);
    }
    let last = previous.expect("at least one step");
    solver.coils(&last).iter().find(|c| c.physical == COIL).unwrap().flux_linkage_wb
}

/// `(d₁, d₂, log2(d₁/d₂))` of three successive levels.
fn differences(levels: &[f64]) -> (f64, f64, f64) {
    let d1 = (levels[1] - levels[0]).abs();
    let d2 = (levels[2] - levels[1]).abs();
    (d1, d2, (d1 / d2).log2())
}

#[test]
#[cfg_attr(not(heavy_tests), ignore = "release only: 224 non-linear solves up to 16 k nodes")]
fn remanent_flux_converges_with_the_mesh_and_the_current_steps() {
    let per_leg = 16;
    // 3 900 nodes give 1 cell per mm in the steel; the cells per mm scale as √nodes.
    let mesh: Vec<f64> =
        [975, 3_900, 15_600].iter().map(|&n| remanent_linkage(n, per_leg)).collect();
    let steps: Vec<f64> = [8, 16, 32].iter().map(|&k| remanent_linkage(3_900, k)).collect();
    let (m1, m2, mesh_order) = differences(&mesh);
    let (s1, s2, step_order) = differences(&steps);
    eprintln!(
        "remanent flux linkage, mesh h, h/2, h/4 ({per_leg} steps per leg): {mesh:?} Wb; \
         differences {m1:.3e}, {m2:.3e}, observed order {mesh_order:.2}"
    );
    eprintln!(
        "remanent flux linkage, 8, 16, 32 steps per leg (mesh h/2): {steps:?} Wb; \
         differences {s1:.3e}, {s2:.3e}, observed order {step_order:.2}"
    );
    let remanent = mesh[2].abs();
    assert!(remanent > 0.0, "no remanent flux");
    assert!(m2 < m1, "the mesh differences do not shrink: {m1:.3e} then {m2:.3e}");
    assert!(m2 <= 0.05 * remanent, "h/2 → h/4 still moves the remanent flux by {m2:.3e} Wb");
    // The step differences may already be at the solver's tolerance: then they need not shrink.
    let floor = 1e-7 * remanent;
    assert!(s2 < s1 || s2 <= floor, "the step differences do not shrink: {s1:.3e} then {s2:.3e}");
    assert!(s2 <= 0.05 * remanent, "16 → 32 steps still move the remanent flux by {s2:.3e} Wb");
}
