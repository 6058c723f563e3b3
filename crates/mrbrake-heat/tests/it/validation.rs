//! Validation of the heat solver against closed-form solutions (`mrbrake_heat::exact`): long
//! cylinders meshed as a strip `r ∈ [r_in, R] × z ∈ [0, H]` with adiabatic ends, so the exact
//! radial solutions apply. Measured: L2 errors and observed orders under uniform refinement (2 for
//! P1, 3 for P2 in L2: Brenner & Scott, *The Mathematical Theory of Finite Element Methods*,
//! Thm 5.4.8), orders in time (1 for implicit Euler, 2 for BDF2), the energy balance of every
//! step, the Joule coupling's self-consistency and the runaway error.

use std::sync::Arc;

use mrbrake_fem::discretisation::basis::Basis;
use mrbrake_fem::discretisation::element::TriangleBasis;
use mrbrake_fem::mesh::structured::{SideTags, graded_lines, rectangle_mesh};
use mrbrake_fem::workflow::time::{Event, Outcome, Scheme, TimeOptions, TimeStep};
use mrbrake_heat::exact;
use mrbrake_heat::{
    Boundary, BoundaryCondition, ElementOrder, HeatError, HeatProblem, HeatSolver, Region,
    SolverOptions, Source,
};
use mrbrake_observe::Flow;

const SIDES: SideTags = SideTags { r_min: 1, r_max: 2, z_min: 3, z_max: 4 };
const H: f64 = 0.004;

fn strip(
    r_in: f64,
    r_out: f64,
    cells: usize,
    region: impl Fn(f64) -> u32,
    breaks: &[f64],
) -> Arc<mrbrake_fem::mesh::Mesh> {
    let mut points = vec![r_in];
    points.extend_from_slice(breaks);
    points.push(r_out);
    let segments: Vec<Vec<f64>> = points
        .windows(2)
        .map(|w| {
            graded_lines(
                w[0],
                w[1],
                (cells * ((w[1] - w[0]) / (r_out - r_in)).round().max(1.0) as usize).max(1),
                1.0,
            )
        })
        .collect();
    let r = mrbrake_fem::mesh::structured::join_lines(&segments);
    let z = graded_lines(0.0, H, 2, 1.0);
    Arc::new(rectangle_mesh(&r, &z, |rc, _| region(rc), SIDES).unwrap())
}

fn convection(tag: u32, h: f64, ambient_k: f64) -> Boundary {
    Boundary { tag, condition: BoundaryCondition::Convection { h_w_per_m2k: h, ambient_k } }
}

fn fixed(tag: u32, t_k: f64) -> Boundary {
    Boundary { tag, condition: BoundaryCondition::Temperature { t_k } }
}

fn options(order: ElementOrder) -> SolverOptions {
    SolverOptions { order, ..SolverOptions::default() }
}

/// The L2 error `(∫ (T_h − T)² r dr dz / ∫ r dr dz)^{1/2}` with a degree-5 rule.
fn l2_error(solver: &HeatSolver, t: &[f64], exact: impl Fn(f64) -> f64) -> f64 {
    let basis = Basis::with_dofs(
        solver.basis().dofs().clone(),
        5,
        mrbrake_fem::discretisation::basis::Weighting::Axisymmetric,
    );
    let (mut sum, mut volume) = (0.0, 0.0);
    for e in 0..basis.n_elements() {
        let (s, v) = mrbrake_fem::by_order!(basis.order(), element_error(&basis, e, t, &exact));
        sum += s;
        volume += v;
    }
    (sum / volume).sqrt()
}

fn element_error<E: TriangleBasis<N>, const N: usize>(
    basis: &Basis,
    e: usize,
    t: &[f64],
    exact: &impl Fn(f64) -> f64,
) -> (f64, f64) {
    let element = basis.element::<E, N>(e);
    let geometry = element.geometry();
    let local = element.dofs().map(|d| t[d]);
    element.points(&geometry).fold((0.0, 0.0), |(s, v), q| {
        let th: f64 = (0..N).map(|i| local[i] * q.phi[i]).sum();
        (s + q.weight * (th - exact(q.point[0])).powi(2), v + q.weight)
    })
}

fn orders(errors: &[f64]) -> Vec<f64> {
    errors.windows(2).map(|w| (w[0] / w[1]).log2()).collect()
}

/// Solid cylinder R = 10 mm, q = 1 MW/m³, k = 1 W/(m K), h = 20 W/(m² K), T∞ = 300 K.
fn solid_cylinder(cells: usize, order: ElementOrder) -> (f64, f64, f64) {
    let (radius, q, k, h, ta) = (0.01, 1e6, 1.0, 20.0, 300.0);
    let problem = HeatProblem {
        mesh: strip(0.0, radius, cells, |_| 1, &[]),
        regions: vec![Region::isotropic(1, k, 1e6).with_source(Source::Uniform { w_per_m3: q })],
        boundaries: vec![convection(2, h, ta)],
    };
    let mut solver = HeatSolver::new(problem, options(order)).unwrap();
    let (t, report) = solver.steady(None).unwrap();
    assert_eq!(report.iterations, 1, "linear: one Newton step");
    let error = l2_error(&solver, &t, |r| exact::solid_cylinder(r, radius, q, k, h, ta));
    let centre = solver.temperature_at(&t, [0.0, H / 2.0]).unwrap();
    let balance = solver.energy_balance(&t);
    assert!(balance.imbalance_w.abs() < 1e-10 * balance.generated_w, "{balance:?}");
    (error, centre - exact::solid_cylinder(0.0, radius, q, k, h, ta), balance.generated_w)
}

#[test]
fn solid_cylinder_with_generation_and_convection_converges_at_second_order() {
    let runs: Vec<(f64, f64, f64)> =
        [4, 8, 16, 32].iter().map(|&n| solid_cylinder(n, ElementOrder::P1)).collect();
    let errors: Vec<f64> = runs.iter().map(|r| r.0).collect();
    let o = orders(&errors);
    println!(
        "solid cylinder P1: L2 errors (K) {errors:?}, orders {o:.3?}, centre errors {:?}",
        runs.iter().map(|r| r.1).collect::<Vec<_>>()
    );
    assert!(o.iter().all(|&x| x > 1.9 && x < 2.2), "orders {o:?}");
    // 2π R H q: the source is integrated exactly.
    let exact_power = 1e6 * std::f64::consts::PI * 0.01f64.powi(2) * H;
    assert!((runs[0].2 - exact_power).abs() < 1e-9 * exact_power);
    // P2 reproduces the quadratic exactly (to round-off).
    let (p2, _, _) = solid_cylinder(4, ElementOrder::P2);
    println!("solid cylinder P2 (4 cells): L2 error {p2:.3e} K");
    assert!(p2 < 1e-9, "{p2}");
}

#[test]
fn hollow_cylinder_log_profile_and_wall_heat() {
    let (r1, r2, t1, t2, k) = (0.01, 0.03, 400.0, 300.0, 15.0);
    let mut errors = Vec::new();
    for order in [ElementOrder::P1, ElementOrder::P2] {
        let mut e = Vec::new();
        for cells in [4, 8, 16, 32] {
            let problem = HeatProblem {
                mesh: strip(r1, r2, cells, |_| 1, &[]),
                regions: vec![Region::isotropic(1, k, 1e6)],
                boundaries: vec![fixed(1, t1), fixed(2, t2)],
            };
            let mut solver = HeatSolver::new(problem, options(order)).unwrap();
            let (t, _) = solver.steady(None).unwrap();
            e.push(l2_error(&solver, &t, |r| exact::hollow_cylinder(r, r1, r2, t1, t2)));
            let heat = solver.boundary_heat(&t);
            let exact_heat = 2.0 * std::f64::consts::PI * k * H * (t1 - t2) / (r2 / r1).ln();
            let relative = (heat[1].heat_out_w - exact_heat) / exact_heat;
            if cells == 32 {
                println!(
                    "hollow cylinder {order}: wall heat {:.6} W, exact {exact_heat:.6} W, relative {relative:.2e}",
                    heat[1].heat_out_w
                );
                assert!(relative.abs() < 1e-3, "{relative}");
            }
            let balance = solver.energy_balance(&t);
            assert!(balance.imbalance_w.abs() < 1e-10 * exact_heat, "{balance:?}");
        }
        let o = orders(&e);
        println!("hollow cylinder {order}: L2 errors (K) {e:?}, orders {o:.3?}");
        errors.push(o);
    }
    assert!(errors[0].iter().all(|&x| x > 1.9 && x < 2.2), "P1 {:?}", errors[0]);
    assert!(errors[1].iter().all(|&x| x > 2.8 && x < 3.3), "P2 {:?}", errors[1]);
}

#[test]
fn two_layer_composite_cylinder() {
    let (radii, k, h, t1, ta) = ([0.01, 0.02, 0.03], [50.0, 0.5], 10.0, 400.0, 300.0);
    let mut e = Vec::new();
    for cells in [4, 8, 16, 32] {
        let problem = HeatProblem {
            mesh: strip(
                radii[0],
                radii[2],
                cells,
                |r| if r < radii[1] { 1 } else { 5 },
                &[radii[1]],
            ),
            regions: vec![Region::isotropic(1, k[0], 1e6), Region::isotropic(5, k[1], 1e6)],
            boundaries: vec![fixed(1, t1), convection(2, h, ta)],
        };
        let mut solver = HeatSolver::new(problem, options(ElementOrder::P1)).unwrap();
        let (t, _) = solver.steady(None).unwrap();
        e.push(l2_error(&solver, &t, |r| exact::composite_cylinder(r, radii, k, h, t1, ta)));
        let heat = solver.boundary_heat(&t);
        // Heat in at r1 = heat out by convection at r3.
        assert!((heat[0].heat_out_w + heat[1].heat_out_w).abs() < 1e-9 * heat[1].heat_out_w.abs());
    }
    let o = orders(&e);
    println!("composite cylinder P1: L2 errors (K) {e:?}, orders {o:.3?}");
    assert!(o.iter().all(|&x| x > 1.9 && x < 2.2), "orders {o:?}");
}

/// Transient cylinder R = 10 mm, k = 1, ρc = 1 MJ/(m³ K) (R²/κ = 100 s), cooling from 400 K by
/// convection to 300 K in `steps` fixed steps; returns the L2 error at `t_end` against the series
/// solution, the largest relative energy imbalance of the steps and the mean temperature.
fn transient_cylinder(
    h: f64,
    cells: usize,
    order: ElementOrder,
    steps: usize,
    t_end: f64,
    scheme: Scheme,
) -> (f64, f64, f64) {
    let step = TimeStep::Fixed { dt_s: t_end / steps as f64 };
    let (error, worst, mean, outcome) = cooling_cylinder(h, cells, order, step, t_end, scheme);
    let expected = if scheme == Scheme::Bdf2 { 2 } else { 1 };
    assert_eq!(outcome.factorizations, expected, "one factorisation per step matrix");
    (error, worst, mean)
}

/// [`transient_cylinder`] with any step control; also returns the run's outcome.
fn cooling_cylinder(
    h: f64,
    cells: usize,
    order: ElementOrder,
    step: TimeStep,
    t_end: f64,
    scheme: Scheme,
) -> (f64, f64, f64, Outcome) {
    let (radius, k, rho_c, t0, ta) = (0.01, 1.0, 1e6, 400.0, 300.0);
    let problem = HeatProblem {
        mesh: strip(0.0, radius, cells, |_| 1, &[]),
        regions: vec![Region::isotropic(1, k, rho_c)],
        boundaries: vec![convection(2, h, ta)],
    };
    let mut solver = HeatSolver::new(problem, options(order)).unwrap();
    let initial = solver.uniform(t0);
    let options = TimeOptions::new(t_end, scheme, step);
    let mut worst: f64 = 0.0;
    let outcome = solver
        .transient(&initial, &options, |e: &Event<'_, HeatSolver>| {
            if e.level.index > 0 {
                let b = e.problem.energy_balance(e.level.u);
                worst = worst.max(b.imbalance_w.abs() / b.out_w.abs());
            }
            Flow::Continue
        })
        .unwrap();
    let eigenvalues = exact::cylinder_eigenvalues(h * radius / k, 40);
    let error = l2_error(&solver, &outcome.u, |r| {
        exact::transient_cylinder(r, t_end, radius, k, rho_c, t0, ta, &eigenvalues)
    });
    let mean = solver.region_stats(&outcome.u)[0].mean_k;
    (error, worst, mean, outcome)
}

#[test]
fn transient_cylinder_orders_in_time_and_energy_balance_every_step() {
    for (scheme, low, high) in [(Scheme::ImplicitEuler, 0.9, 1.1), (Scheme::Bdf2, 1.85, 2.2)] {
        let runs: Vec<(f64, f64, f64)> = [10, 20, 40]
            .iter()
            .map(|&n| transient_cylinder(100.0, 24, ElementOrder::P2, n, 50.0, scheme))
            .collect();
        let errors: Vec<f64> = runs.iter().map(|r| r.0).collect();
        let o = orders(&errors);
        let worst = runs.iter().map(|r| r.1).fold(0.0, f64::max);
        println!(
            "transient cylinder Bi = 1, {scheme}: L2 errors at 50 s (K) {errors:?}, orders {o:.3?}, worst step imbalance {worst:.1e} (relative to heat out)"
        );
        assert!(o.iter().all(|&x| x > low && x < high), "{scheme} orders {o:?}");
        assert!(worst < 1e-9, "energy balance {worst}");
    }
}

/// The cooling cylinder (Bi = 1, P2) over 500 s, five diffusion times: the largest error of its
/// surface temperature against the series solution over the levels after 2 s (before, the
/// boundary layer of the jump to the ambient is finer than the mesh), its final state and the
/// run's outcome.
fn surface_history(step: TimeStep) -> (f64, Vec<f64>, Outcome) {
    let (radius, k, rho_c, t0, ta, h) = (0.01, 1.0, 1e6, 400.0, 300.0, 100.0);
    let problem = HeatProblem {
        mesh: strip(0.0, radius, 16, |_| 1, &[]),
        regions: vec![Region::isotropic(1, k, rho_c)],
        boundaries: vec![convection(2, h, ta)],
    };
    let mut solver = HeatSolver::new(problem, options(ElementOrder::P2)).unwrap();
    let initial = solver.uniform(t0);
    let eigenvalues = exact::cylinder_eigenvalues(h * radius / k, 40);
    let mut worst = 0.0_f64;
    let options = TimeOptions::new(500.0, Scheme::Bdf2, step);
    let outcome = solver
        .transient(&initial, &options, |e: &Event<'_, HeatSolver>| {
            let t = e.level.t;
            if t >= 2.0 {
                let surface = e.problem.temperature_at(e.level.u, [radius, 0.5 * H]).unwrap();
                let exact =
                    exact::transient_cylinder(radius, t, radius, k, rho_c, t0, ta, &eigenvalues);
                worst = worst.max((surface - exact).abs());
            }
            Flow::Continue
        })
        .unwrap();
    (worst, outcome.u.clone(), outcome)
}

#[test]
fn adaptive_steps_match_fixed_steps_within_their_tolerance_in_fewer_steps() {
    // Fast at first (the boundary layer after the jump to the ambient), slow later: adaptive
    // BDF2 takes small steps first and large ones after.
    let (_, fine, _) = surface_history(TimeStep::Fixed { dt_s: 500.0 / 4000.0 });
    let gap = |u: &[f64]| u.iter().zip(&fine).fold(0.0_f64, |m, (a, b)| m.max((a - b).abs()));
    for rtol in [1e-5, 1e-6] {
        let (error, end, o) = surface_history(TimeStep::Adaptive { rtol, dt_initial_s: 1e-2 });
        let fixed_steps = 4 * o.steps;
        let (fixed_error, _, _) =
            surface_history(TimeStep::Fixed { dt_s: 500.0 / fixed_steps as f64 });
        println!(
            "adaptive rtol {rtol:e}: {} steps ({} rejected, {} factorisations), surface error \
             after 2 s {error:.2e} K, final state {:.2e} K from the 4000-step run; {fixed_steps} \
             fixed steps: surface error {fixed_error:.2e} K",
            o.steps,
            o.rejected_steps,
            o.factorizations,
            gap(&end)
        );
        // The end state within the local tolerances the steps were allowed (rtol · max|T| per
        // step, max|T| = 400 K) of the converged fixed-step run ...
        let allowed = o.steps as f64 * rtol * 400.0;
        assert!(gap(&end) < allowed, "rtol {rtol}: {:e} K", gap(&end));
        // ... and the history more accurate than fixed steps four times as many.
        assert!(error < fixed_error, "rtol {rtol}: {error:e} K against {fixed_error:e} K");
    }
}

#[test]
fn small_biot_cylinder_follows_the_lumped_limit() {
    // Bi = h R / k = 0.01: the mean temperature follows exp(−t/τ), τ = ρc R/(2h) = 5000 s.
    let (h, t_end) = (1.0, 3000.0);
    let (error, _, mean) = transient_cylinder(h, 8, ElementOrder::P1, 300, t_end, Scheme::Bdf2);
    let lumped = exact::lumped_cylinder(t_end, 0.01, 1e6, h, 400.0, 300.0);
    let series = exact::transient_cylinder(
        0.0,
        t_end,
        0.01,
        1.0,
        1e6,
        400.0,
        300.0,
        &exact::cylinder_eigenvalues(0.01 * h, 40),
    );
    let relative = (mean - lumped) / (400.0 - lumped);
    println!(
        "lumped limit Bi = 0.01 at {t_end} s: FE mean {mean:.4} K, lumped {lumped:.4} K (rel. to the drop {relative:.2e}), series centre {series:.4} K, L2 error vs series {error:.2e} K"
    );
    assert!(relative.abs() < 5e-3, "{relative}");
    assert!(error < 1e-2, "{error}");
}

/// The Joule source of a solid cylinder at current `current` (R20 = 2 Ω over the region).
fn joule_problem(cells: usize, current: f64) -> (HeatProblem, f64) {
    let radius = 0.01;
    let mesh = strip(0.0, radius, cells, |_| 1, &[]);
    let source =
        Source::Joule { current_a: current, resistance_20c_ohm: 2.0, alpha_per_k: 0.00393 };
    let problem = HeatProblem {
        mesh,
        regions: vec![Region::isotropic(1, 0.8, 3e6).with_source(source)],
        boundaries: vec![convection(2, 15.0, 298.15)],
    };
    let volume = std::f64::consts::PI * radius * radius * H;
    (problem, volume)
}

#[test]
fn joule_coupling_is_self_consistent_and_matches_the_bessel_solution() {
    let current = 0.3;
    let mut errors = Vec::new();
    for cells in [4, 8, 16, 32] {
        let (problem, volume) = joule_problem(cells, current);
        let q20 = current * current * 2.0 / volume;
        let mut solver = HeatSolver::new(problem, options(ElementOrder::P1)).unwrap();
        let (t, report) = solver.steady(None).unwrap();
        assert_eq!(report.iterations, 1);
        let stats = solver.region_stats(&t)[0];
        let resistance = 2.0 * (1.0 + 0.00393 * (stats.mean_k - mrbrake_heat::T20_K));
        let consistency = (stats.heat_w - current * current * resistance).abs() / stats.heat_w;
        assert!(
            consistency < 1e-6,
            "P = {} W vs I²R(T̄) = {} W",
            stats.heat_w,
            current * current * resistance
        );
        let exact = |r: f64| {
            exact::joule_cylinder(r, 0.01, q20, 0.00393, mrbrake_heat::T20_K, 0.8, 15.0, 298.15)
                .unwrap()
        };
        errors.push(l2_error(&solver, &t, exact));
        if cells == 32 {
            println!(
                "Joule cylinder: P = {:.4} W at T̄ = {:.3} K, R(T̄) = {resistance:.5} Ω, |P − I²R(T̄)|/P = {consistency:.1e}; centre {:.4} K exact {:.4} K",
                stats.heat_w,
                stats.mean_k,
                solver.temperature_at(&t, [0.0, H / 2.0]).unwrap(),
                exact(0.0)
            );
        }
    }
    let o = orders(&errors);
    println!("Joule cylinder P1: L2 errors (K) {errors:?}, orders {o:.3?}");
    assert!(o.iter().all(|&x| x > 1.9 && x < 2.2), "orders {o:?}");
}

#[test]
fn runaway_joule_heating_is_a_numerical_error() {
    // The exact solution has no steady state beyond the current where h J0(mR) = k m J1(mR).
    // Critical current ≈ 0.68 A here (m R = ζ1(Bi = 0.1875) ≈ 0.60); 2 A is beyond it.
    let (problem, volume) = joule_problem(8, 2.0);
    let q20 = 4.0 * 2.0 / volume;
    assert!(
        exact::joule_cylinder(0.0, 0.01, q20, 0.00393, mrbrake_heat::T20_K, 0.8, 15.0, 298.15)
            .is_none()
    );
    let mut solver = HeatSolver::new(problem, options(ElementOrder::P1)).unwrap();
    let error = solver.steady(None).unwrap_err();
    assert!(matches!(error, HeatError::Runaway(_)), "{error}");
    assert_eq!(mrbrake_error::Kind::kind(&error), mrbrake_error::ErrorKind::Numerical);
}

#[test]
fn radiation_by_newton_matches_the_exact_surface_balance() {
    // Solid cylinder with generation, radiation only: ε σ (T_s⁴ − T∞⁴) = q R/2 at the surface,
    // T(r) = T_s + q (R² − r²)/(4k).
    let (radius, q, k, eps, ta) = (0.01, 2e5, 2.0, 0.8, 300.0_f64);
    let ts = (q * radius / 2.0 / (eps * mrbrake_heat::STEFAN_BOLTZMANN) + ta.powi(4)).powf(0.25);
    let mut e = Vec::new();
    for cells in [8, 16, 32] {
        let problem = HeatProblem {
            mesh: strip(0.0, radius, cells, |_| 1, &[]),
            regions: vec![
                Region::isotropic(1, k, 1e6).with_source(Source::Uniform { w_per_m3: q }),
            ],
            boundaries: vec![Boundary {
                tag: 2,
                condition: BoundaryCondition::Radiation { emissivity: eps, ambient_k: ta },
            }],
        };
        let mut solver = HeatSolver::new(problem, options(ElementOrder::P1)).unwrap();
        let (t, report) = solver.steady(None).unwrap();
        assert!(report.iterations > 1 && report.iterations < 15, "{}", report.iterations);
        let balance = solver.energy_balance(&t);
        assert!(balance.imbalance_w.abs() < 1e-8 * balance.generated_w, "{balance:?}");
        e.push(l2_error(&solver, &t, |r| ts + q * (radius * radius - r * r) / (4.0 * k)));
    }
    let o = orders(&e);
    println!("radiation cylinder P1 (T_s = {ts:.3} K): L2 errors (K) {e:?}, orders {o:.3?}");
    assert!(o.iter().all(|&x| x > 1.9 && x < 2.2), "orders {o:?}");
}

#[test]
fn bad_values_are_input_errors() {
    let problem = HeatProblem {
        mesh: strip(0.0, 0.01, 4, |_| 1, &[]),
        regions: vec![Region::isotropic(1, -1.0, 1e6)],
        boundaries: vec![
            convection(2, -5.0, 300.0),
            Boundary {
                tag: 3,
                condition: BoundaryCondition::Radiation { emissivity: 1.5, ambient_k: 300.0 },
            },
            fixed(4, -3.0),
        ],
    };
    let error = HeatSolver::new(problem, options(ElementOrder::P1)).unwrap_err();
    let message = error.to_string();
    let needles = [
        "region[physical=1].k_radial: got -1; allowed: > 0",
        "boundary[physical=2].h: got -5",
        "boundary[physical=3].emissivity: got 1.5; allowed: [0, 1]",
        "boundary[physical=4].T: got -3 K; allowed: > 0 K",
    ];
    for needle in needles {
        assert!(message.contains(needle), "{message}");
    }
    assert_eq!(mrbrake_error::Kind::kind(&error), mrbrake_error::ErrorKind::Input);
    let mrbrake_heat::HeatError::Fields(fields) = &error else { panic!("{error:?}") };
    let first = &fields.errors()[0];
    assert_eq!((first.value.as_deref(), first.allowed.as_deref()), (Some("-1"), Some("> 0")));
}
