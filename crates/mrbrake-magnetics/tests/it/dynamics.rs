//! Validation of the magnetodynamics ([`mrbrake_magnetics::dynamics`]) against closed-form
//! solutions: the skin effect in a long conductor (time-harmonic, complex Bessel functions), the
//! flux diffusing into it after a step (Bessel series), an L/R circuit driven by a voltage step;
//! observed orders in time (1 for implicit Euler, 2 for BDF2); the energy balance; and the
//! consistency of the transient, harmonic and small-signal solves with the static solver.
//!
//! The conductor set-up: a long solid cylinder (radius `a`, tag 1) inside a long thin solenoid
//! (tag 3) with an air gap (tag 2) and air outside (tag 4). The mesh is one period of height `h`
//! with natural (`∂A/∂z = 0`) top and bottom, so the fields are those of infinitely long parts:
//! inside the solenoid `H_z = N I / h` whatever the cylinder does (Ampère), outside it zero
//! (natural outer boundary: tangential H = 0).

use std::sync::Arc;

use mrbrake_fem::mesh::locate::Probe;
use mrbrake_fem::mesh::structured::{SideTags, graded_lines, rectangle_mesh};
use mrbrake_fem::workflow::time::{Scheme, TimeStep};
use mrbrake_magnetics::dynamics::transient::{StepView, TransientOptions};
use mrbrake_magnetics::dynamics::{Coil, Conductor, Drive, Dynamics, Waveform};
use mrbrake_magnetics::exact::{conducting_cylinder_potential, cylinder_step_flux};
use mrbrake_magnetics::material::MarroccoCurve;
use mrbrake_magnetics::problem::{Boundary, BoundaryCondition, Problem, Region, Source};
use mrbrake_magnetics::{ElementOrder, Solver, SolverOptions};
use mrbrake_materials::{MU_0, Magnetic};
use mrbrake_observe::Flow;
use num_complex::Complex64;

const A: f64 = 0.01; // conductor radius (m)
const B: f64 = 0.012; // coil inner radius
const C: f64 = 0.013; // coil outer radius
const D: f64 = 0.015; // outer boundary
const H: f64 = 0.002; // period height
const SIGMA: f64 = 5.8e6; // S/m (FEMM's steel value)
const TURNS: f64 = 10.0;
const CURRENT: f64 = 2.0;

/// Surface field `H0 = N I / h` (A/m).
fn h0() -> f64 {
    TURNS * CURRENT / H
}

/// Lines of the radial bands; the conductor's cells shrink towards its surface (`surface_cell`).
fn radial_lines(cells: usize) -> Vec<f64> {
    radial_lines_refined(cells, 1)
}

/// [`radial_lines`] with the bands outside the conductor refined `outer` times (every cell
/// halves when `cells` and `outer` double: the mesh family of the spatial convergence study).
fn radial_lines_refined(cells: usize, outer: usize) -> Vec<f64> {
    let mut r = graded_lines(0.0, A, cells, 0.04);
    for (start, end, n) in [(A, B, 6), (B, C, 4), (C, D, 4)] {
        r.extend_from_slice(&graded_lines(start, end, n * outer, 1.0)[1..]);
    }
    r
}

fn band(r: f64) -> u32 {
    match r {
        r if r < A => 1,
        r if r < B => 2,
        r if r < C => 3,
        _ => 4,
    }
}

/// The cylinder in its solenoid, with core material `core`, conductivity `sigma`, and the coil's
/// drive; `cells` radial cells in the conductor.
fn cylinder(
    cells: usize,
    core: Magnetic,
    sigma: f64,
    drive: Drive,
    waveform: Waveform,
) -> Dynamics {
    let z = graded_lines(0.0, H, 2, 1.0);
    cylinder_on(&radial_lines(cells), &z, SolverOptions::default(), core, sigma, drive, waveform)
}

/// [`cylinder`] on the grid lines `r`, `z` with the solver `options` (element order).
fn cylinder_on(
    r: &[f64],
    z: &[f64],
    options: SolverOptions,
    core: Magnetic,
    sigma: f64,
    drive: Drive,
    waveform: Waveform,
) -> Dynamics {
    let sides = SideTags { r_min: 10, r_max: 11, z_min: 12, z_max: 13 };
    let mesh = rectangle_mesh(r, z, |r, _| band(r), sides).unwrap();
    let region = |tag, material| Region { tag, material, source: None };
    let problem = Problem {
        mesh: Arc::new(mesh),
        regions: vec![
            region(1, core),
            region(2, Magnetic::air()),
            Region {
                tag: 3,
                material: Magnetic::air(),
                source: Some(Source::Coil { turns: TURNS, current_a: CURRENT }),
            },
            region(4, Magnetic::air()),
        ],
        boundaries: vec![],
    };
    let solver = Solver::new(problem, options).unwrap();
    let conductors = [Conductor { tag: 1, conductivity_s_per_m: sigma }];
    let coil = Coil { tag: 3, turns: TURNS, drive, waveform };
    Dynamics::new(solver, &conductors, vec![coil]).unwrap()
}

fn current_drive() -> Drive {
    Drive::Current { amplitude_a: CURRENT }
}

/// `π σ ω² ∫_0^a |A(r)|² r dr · h`: the exact time-averaged loss of the period (composite
/// Gauss–Legendre, 400 panels of 5 points).
fn exact_loss(mu: f64, omega: f64) -> f64 {
    let nodes = [
        -0.906_179_845_938_664,
        -0.538_469_310_105_683,
        0.0,
        0.538_469_310_105_683,
        0.906_179_845_938_664,
    ];
    let weights = [
        0.236_926_885_056_189,
        0.478_628_670_499_366,
        0.568_888_888_888_889,
        0.478_628_670_499_366,
        0.236_926_885_056_189,
    ];
    let panels = 400;
    let width = A / panels as f64;
    let mut integral = 0.0;
    for p in 0..panels {
        let centre = (p as f64 + 0.5) * width;
        for (x, w) in nodes.iter().zip(weights) {
            let r = centre + 0.5 * width * x;
            let a = conducting_cylinder_potential(r, A, mu, SIGMA, omega, h0());
            integral += 0.5 * width * w * a.norm_sqr() * r;
        }
    }
    std::f64::consts::PI * SIGMA * omega * omega * integral * H
}

#[test]
fn harmonic_skin_effect_matches_the_bessel_solution() {
    let mut dynamics =
        cylinder(80, Magnetic::air(), SIGMA, current_drive(), Waveform::Step { initial: 0.0 });
    // a/δ = 0.5, 2, 5, 10 with δ = sqrt(2/(ωμσ)).
    let ratios = [0.5, 2.0, 5.0, 10.0];
    let omegas: Vec<f64> =
        ratios.iter().map(|x: &f64| 2.0 * x * x / (MU_0 * SIGMA * A * A)).collect();
    let frequencies: Vec<f64> = omegas.iter().map(|w| w / (2.0 * std::f64::consts::PI)).collect();
    let potentials = dynamics.harmonic_potentials(&frequencies, None).unwrap();
    let surface = [A, 0.5 * H];
    for ((p, &omega), ratio) in potentials.iter().zip(&omegas).zip(ratios) {
        let solver = dynamics.solver();
        let re = solver.a_phi_at(&dynamics.solution(p.re.clone()), surface).unwrap();
        let im = solver.a_phi_at(&dynamics.solution(p.im.clone()), surface).unwrap();
        let fe = Complex64::new(re, im);
        let exact = conducting_cylinder_potential(A, A, MU_0, SIGMA, omega, h0());
        let flux_error = (fe - exact).norm() / exact.norm();
        let point = dynamics.harmonic_point(p, &[]).unwrap();
        let loss_exact = exact_loss(MU_0, omega);
        let loss_error = (point.eddy_loss_w - loss_exact).abs() / loss_exact;
        println!(
            "a/δ = {ratio:>4}: flux {:.6e}{:+.6e}j Wb (exact {:.6e}{:+.6e}j), error {flux_error:.2e}; \
             loss {:.6e} W (exact {loss_exact:.6e}), error {loss_error:.2e}",
            2.0 * std::f64::consts::PI * A * fe.re,
            2.0 * std::f64::consts::PI * A * fe.im,
            2.0 * std::f64::consts::PI * A * exact.re,
            2.0 * std::f64::consts::PI * A * exact.im,
            point.eddy_loss_w
        );
        assert!(flux_error < 2e-3, "a/δ = {ratio}: flux error {flux_error:.3e}");
        assert!(loss_error < 5e-3, "a/δ = {ratio}: loss error {loss_error:.3e}");
    }
}

/// The flux and loss errors of the harmonic solve at `a/δ = ratio` on the mesh with `cells`
/// conductor cells (and the outer bands refined alike).
fn skin_errors(cells: usize, order: ElementOrder, ratio: f64) -> (f64, f64) {
    let options = SolverOptions { order, ..SolverOptions::default() };
    let r = radial_lines_refined(cells, cells / 10);
    // The z cells shrink with the radial ones: with two z cells throughout, the triangles grow
    // flat (a 1 mm by 10 µm cell at 80 radial cells) and P2's flux error falls at order 2 only.
    let z = graded_lines(0.0, H, 8 * cells / 10, 1.0);
    let waveform = Waveform::Step { initial: 0.0 };
    let mut dynamics =
        cylinder_on(&r, &z, options, Magnetic::air(), SIGMA, current_drive(), waveform);
    let omega = 2.0 * ratio * ratio / (MU_0 * SIGMA * A * A);
    let frequency = omega / (2.0 * std::f64::consts::PI);
    // The direct solve: the reduced-basis sweep's tolerance would floor the P2 errors.
    let method = mrbrake_magnetics::dynamics::harmonic::HarmonicMethod::Direct;
    let (potentials, _) = dynamics.harmonic_potentials_by(&[frequency], None, method).unwrap();
    let potential = &potentials[0];
    let solver = dynamics.solver();
    let surface = [A, 0.5 * H];
    let re = solver.a_phi_at(&dynamics.solution(potential.re.clone()), surface).unwrap();
    let im = solver.a_phi_at(&dynamics.solution(potential.im.clone()), surface).unwrap();
    let exact = conducting_cylinder_potential(A, A, MU_0, SIGMA, omega, h0());
    let flux_error = (Complex64::new(re, im) - exact).norm() / exact.norm();
    let loss = dynamics.harmonic_point(potential, &[]).unwrap().eddy_loss_w;
    let loss_exact = exact_loss(MU_0, omega);
    (flux_error, (loss - loss_exact).abs() / loss_exact)
}

#[test]
fn skin_effect_converges_in_space() {
    // a/δ = 5: the field decays over a fifth of the radius, resolved by the graded cells. Every
    // cell halves from one mesh to the next, in r and in z. Measured: P1 flux at the surface
    // orders 2.06, 2.02, 2.01 (the potential's L2 order), loss 2.50, 2.40, 2.26; P2 flux 4.53,
    // 4.00, 2.93, loss 3.70, 3.68, 3.83.
    let meshes = [10, 20, 40, 80];
    for (order, expected) in [(ElementOrder::P1, 2.0), (ElementOrder::P2, 3.0)] {
        let runs: Vec<(f64, f64)> = meshes.iter().map(|&n| skin_errors(n, order, 5.0)).collect();
        let rate = |e: fn(&(f64, f64)) -> f64| -> Vec<f64> {
            runs.windows(2).map(|w| (e(&w[0]) / e(&w[1])).log2()).collect()
        };
        let (flux_orders, loss_orders) = (rate(|r| r.0), rate(|r| r.1));
        println!(
            "skin effect a/δ = 5, {order:?}, 10/20/40/80 conductor cells: errors (flux, loss) \
             {runs:?}, orders flux {flux_orders:?}, loss {loss_orders:?}"
        );
        let low = expected - 0.2;
        assert!(flux_orders.iter().all(|&o| o > low), "{order:?} flux orders {flux_orders:?}");
        assert!(loss_orders.iter().all(|&o| o > low), "{order:?} loss orders {loss_orders:?}");
    }
}

/// `2π ∫ J²/σ r dr dz` over the elements for `J` linear on each triangle (vertex values, three
/// per element), exact: `∫ λ_i λ_j λ_k dA = 2|T| i! j! k! / (i + j + k + 2)!` by multiplicity.
fn loss_of_current_density(mesh: &mrbrake_fem::mesh::Mesh, j: &[f64], sigma: f64) -> f64 {
    let mut loss = 0.0;
    for (t, tri) in mesh.triangles.iter().enumerate() {
        let jv = &j[3 * t..3 * t + 3];
        if jv.iter().all(|v| v.abs() < f64::MIN_POSITIVE) {
            continue;
        }
        let area = mesh.signed_area(t).abs();
        let r: Vec<f64> = tri.iter().map(|&v| mesh.nodes[v][0]).collect();
        // ∫ λ_a λ_b λ_c dA: 2|T|·(1/20 for a = b = c, 1/60 for two equal, 1/120 all distinct)·…
        let triple = |a: usize, b: usize, c: usize| -> f64 {
            let same = usize::from(a == b) + usize::from(b == c) + usize::from(a == c);
            area * match same {
                3 => 1.0 / 10.0,
                1 => 1.0 / 30.0,
                _ => 1.0 / 60.0,
            }
        };
        for a in 0..3 {
            for b in 0..3 {
                for c in 0..3 {
                    loss += jv[a] * jv[b] * r[c] * triple(a, b, c);
                }
            }
        }
    }
    2.0 * std::f64::consts::PI * loss / sigma
}

#[test]
fn eddy_current_density_carries_the_eddy_loss() {
    // The current density the step shows (J = −σ ∂A/∂t at the vertices) must dissipate what the
    // transient's eddy loss says, at every step.
    let mut dynamics =
        cylinder(20, Magnetic::air(), SIGMA, current_drive(), Waveform::Step { initial: 0.0 });
    let options = TransientOptions::new(2e-3, Scheme::Bdf2, TimeStep::Fixed { dt_s: 2e-4 });
    let mut from_density = Vec::new();
    let result = dynamics
        .transient_observed(&options, |view: &StepView<'_>| {
            let j = view.dynamics.eddy_current_density(view.rate).expect("one rate per DOF");
            from_density.push(loss_of_current_density(view.dynamics.solver().mesh(), &j, SIGMA));
            Flow::Continue
        })
        .unwrap();
    assert!(from_density[0].abs() < f64::MIN_POSITIVE, "no eddy currents in the DC state");
    for (k, (p_j, p)) in from_density.iter().zip(&result.eddy_loss_w).enumerate().skip(1) {
        let difference = (p_j - p).abs() / p;
        // Not to round-off: the element mass matrices come from the basis's quadrature rule,
        // exact integration here (3.5e-8 seen).
        assert!(difference < 1e-6, "step {k}: {p_j:e} W from J, {p:e} W eddy loss");
    }
    assert!(dynamics.eddy_current_density(&[1.0]).is_err(), "a wrong length is an error");
}

/// Flux `2π a A(a)` through the conductor at every step of a transient.
fn transient_flux(dynamics: &mut Dynamics, options: &TransientOptions) -> (Vec<f64>, Vec<f64>) {
    let mut flux = Vec::new();
    let result = dynamics
        .transient_observed(options, |view: &StepView<'_>| {
            let solution = view.dynamics.solution(view.a.to_vec());
            let a = view.dynamics.solver().a_phi_at(&solution, [A, 0.5 * H]).expect("inside");
            flux.push(2.0 * std::f64::consts::PI * A * a);
            Flow::Continue
        })
        .unwrap();
    (result.time_s, flux)
}

#[test]
fn step_into_a_conductor_follows_the_bessel_series() {
    let tau = MU_0 * SIGMA * A * A;
    let mut dynamics =
        cylinder(60, Magnetic::air(), SIGMA, current_drive(), Waveform::Step { initial: 0.0 });
    let options =
        TransientOptions::new(0.5 * tau, Scheme::Bdf2, TimeStep::Fixed { dt_s: tau / 2000.0 });
    let (time, flux) = transient_flux(&mut dynamics, &options);
    let final_flux = std::f64::consts::PI * A * A * MU_0 * h0();
    let mut worst: f64 = 0.0;
    for (t, phi) in time.iter().zip(&flux).skip(1) {
        if *t < 0.02 * tau {
            continue; // the first steps resolve the jump; the series needs many terms there
        }
        let exact = cylinder_step_flux(*t, A, MU_0, SIGMA, h0(), 200);
        worst = worst.max((phi - exact).abs() / final_flux);
    }
    println!(
        "step into the conductor: largest flux error {worst:.2e} of the final flux (t >= 0.02 τ)"
    );
    assert!(worst < 2e-3, "largest error {worst:.3e}");
}

/// The coil alone (no conductor), driven by a voltage step through a resistance: `i(t) = V/R (1 −
/// e^{−tR/L})` with the coil's own inductance.
fn lr_circuit(resistance: f64, scheme: Scheme, steps: usize) -> (f64, f64, usize) {
    let voltage = 3.0;
    let drive = Drive::Voltage { amplitude_v: voltage, series_resistance_ohm: resistance };
    let mut dynamics =
        cylinder(20, Magnetic::Linear { mu_r: 50.0 }, 0.0, drive, Waveform::Step { initial: 0.0 });
    let inductance = {
        let solution = dynamics.static_solution(&[1.0]).unwrap();
        dynamics.flux_linkage(0, solution.a_phi())
    };
    let tau = inductance / resistance;
    let t_end = 2.0 * tau;
    let options =
        TransientOptions::new(t_end, scheme, TimeStep::Fixed { dt_s: t_end / steps as f64 });
    let result = dynamics.transient(&options).unwrap();
    let current = result.coils[0].current_a[result.time_s.len() - 1];
    let exact = voltage / resistance * (1.0 - (-t_end / tau).exp());
    ((current - exact).abs() / exact, inductance, result.factorizations)
}

#[test]
fn lr_circuit_converges_at_first_and_second_order() {
    for (scheme, expected) in [(Scheme::ImplicitEuler, 1.0), (Scheme::Bdf2, 2.0)] {
        let runs: Vec<(f64, f64, usize)> =
            [20, 40, 80].iter().map(|&n| lr_circuit(0.5, scheme, n)).collect();
        let orders: Vec<f64> = runs.windows(2).map(|w| (w[0].0 / w[1].0).log2()).collect();
        println!(
            "L/R circuit, {scheme:?}: L = {:.4e} H, errors {:?}, orders {orders:?}, factorisations {:?}",
            runs[0].1,
            runs.iter().map(|r| r.0).collect::<Vec<_>>(),
            runs.iter().map(|r| r.2).collect::<Vec<_>>()
        );
        assert!(
            orders.iter().all(|o| (o - expected).abs() < 0.15),
            "{scheme:?}: orders {orders:?}"
        );
        // A linear problem at a fixed step: one factorisation (BDF2: one more for its Euler start).
        let expected_factorisations = if scheme == Scheme::Bdf2 { 2 } else { 1 };
        assert!(runs.iter().all(|r| r.2 == expected_factorisations), "{runs:?}");
    }
}

#[test]
fn eddy_current_transient_converges_at_the_schemes_orders() {
    // A smooth drive (a sine) so that the schemes show their orders; self-convergence of the
    // conductor's flux at t_end.
    let tau = MU_0 * SIGMA * A * A;
    let waveform = Waveform::Sine { frequency_hz: 1.0 / tau, offset: 0.0 };
    let flux_at_end = |scheme: Scheme, n: usize| {
        let mut dynamics = cylinder(20, Magnetic::air(), SIGMA, current_drive(), waveform.clone());
        let dt = 0.5 * tau / n as f64;
        let options = TransientOptions::new(0.5 * tau, scheme, TimeStep::Fixed { dt_s: dt });
        *transient_flux(&mut dynamics, &options).1.last().unwrap()
    };
    // Reference: BDF2 with 16 times the finest step below (its error is ~1/256 of that step's).
    let reference = flux_at_end(Scheme::Bdf2, 25_600);
    for (scheme, expected) in [(Scheme::ImplicitEuler, 1.0), (Scheme::Bdf2, 2.0)] {
        let errors: Vec<f64> = [200, 400, 800, 1600]
            .iter()
            .map(|&n| (flux_at_end(scheme, n) - reference).abs())
            .collect();
        let orders: Vec<f64> = errors.windows(2).map(|w| (w[0] / w[1]).log2()).collect();
        println!(
            "eddy-current transient, {scheme:?}: flux errors at t_end {errors:?}, orders {orders:?}"
        );
        assert!(orders.iter().all(|o| (o - expected).abs() < 0.2), "{scheme:?}: orders {orders:?}");
    }
}

#[test]
fn energy_balances_to_the_schemes_order() {
    // Source energy = change in stored energy + eddy loss, up to the scheme's own dissipation.
    let tau = MU_0 * SIGMA * A * A;
    let imbalance = |steps: usize| {
        let mut dynamics = cylinder(
            20,
            Magnetic::air(),
            SIGMA,
            current_drive(),
            Waveform::Ramp { rise_s: 0.2 * tau },
        );
        let mut options = TransientOptions::new(
            0.5 * tau,
            Scheme::ImplicitEuler,
            TimeStep::Fixed { dt_s: 0.5 * tau / steps as f64 },
        );
        options.energy = true;
        let r = dynamics.transient(&options).unwrap();
        let n = r.time_s.len() - 1;
        let source = r.source_energy_j[n];
        let balance = source - (r.stored_energy_j[n] - r.stored_energy_j[0]) - r.eddy_energy_j[n];
        (balance / source, source)
    };
    let runs: Vec<(f64, f64)> = [50, 100, 200].iter().map(|&n| imbalance(n)).collect();
    let orders: Vec<f64> = runs.windows(2).map(|w| (w[0].0 / w[1].0).log2()).collect();
    println!("energy balance (implicit Euler): relative imbalance {runs:?}, orders {orders:?}");
    assert!(runs.iter().all(|r| r.0 >= 0.0), "implicit Euler dissipates, never creates, energy");
    assert!(orders.iter().all(|o| (o - 1.0).abs() < 0.2), "orders {orders:?}");
}

#[test]
fn transient_tends_to_the_static_solution() {
    let tau = MU_0 * SIGMA * A * A;
    let iron = Magnetic::NonLinear(Arc::new(MarroccoCurve::soft_iron()));
    let mut dynamics = cylinder(20, iron, SIGMA, current_drive(), Waveform::Step { initial: 0.0 });
    let options = TransientOptions::new(
        5000.0 * tau,
        Scheme::Bdf2,
        TimeStep::Adaptive { rtol: 1e-4, dt_initial_s: 1e-3 * tau },
    );
    let result = dynamics.transient(&options).unwrap();
    let static_lambda = {
        let s = dynamics.static_solution(&[CURRENT]).unwrap();
        dynamics.flux_linkage(0, s.a_phi())
    };
    let last = *result.coils[0].flux_linkage_wb.last().unwrap();
    println!(
        "non-linear conducting iron core: λ(t_end) = {last:.8e} Wb, static {static_lambda:.8e} Wb, \
         {} steps ({} rejected), Newton iterations up to {}",
        result.time_s.len() - 1,
        result.rejected_steps,
        result.newton_iterations.iter().max().unwrap()
    );
    assert!((last - static_lambda).abs() <= 1e-6 * static_lambda.abs());
}

#[test]
fn harmonic_and_small_signal_tend_to_the_static_inductances() {
    // Linear: the harmonic flux at a very low frequency is the static flux.
    let mut linear =
        cylinder(20, Magnetic::air(), SIGMA, current_drive(), Waveform::Step { initial: 0.0 });
    let (points, _) = linear.harmonic(&[1e-6], None, &[]).unwrap();
    let static_lambda = {
        let s = linear.static_solution(&[CURRENT]).unwrap();
        linear.flux_linkage(0, s.a_phi())
    };
    let harmonic_lambda = points[0].coils[0].flux_linkage_wb;
    println!("low-frequency harmonic λ {harmonic_lambda:?} Wb, static {static_lambda:.8e} Wb");
    assert!((harmonic_lambda[0] - static_lambda).abs() <= 1e-8 * static_lambda);
    // Saturated iron: the small-signal λ̂/Î at a low frequency is the incremental inductance.
    let iron = Magnetic::NonLinear(Arc::new(MarroccoCurve::soft_iron()));
    let bias = 200.0; // A: saturates the iron core of the solenoid (H0 = 1e6 A/m)
    let mut nonlinear = cylinder(20, iron, SIGMA, current_drive(), Waveform::Step { initial: 0.0 });
    let (points, _) = nonlinear.harmonic(&[1e-6], Some(&[bias]), &[]).unwrap();
    let small_signal = points[0].coils[0].flux_linkage_wb[0] / CURRENT;
    let incremental = {
        let solution = nonlinear.static_solution(&[bias]).unwrap();
        let mut solver =
            Solver::new(nonlinear.solver().problem().clone(), SolverOptions::default()).unwrap();
        solver.set_source(3, Some(Source::Coil { turns: TURNS, current_a: bias })).unwrap();
        solver.incremental_inductance(&solution, 3).unwrap()
    };
    let secant = {
        let solution = nonlinear.static_solution(&[bias]).unwrap();
        nonlinear.flux_linkage(0, solution.a_phi()) / bias
    };
    println!(
        "small-signal L at {bias} A: {small_signal:.8e} H; incremental {incremental:.8e} H; secant {secant:.4e} H"
    );
    assert!((small_signal - incremental).abs() <= 1e-6 * incremental);
    assert!(small_signal < 0.5 * secant, "saturated: the incremental inductance is the smaller");
}

#[test]
fn bad_dynamic_input_is_refused() {
    let drive = Drive::Voltage { amplitude_v: 1.0, series_resistance_ohm: 0.0 };
    let z = graded_lines(0.0, H, 2, 1.0);
    let sides = SideTags { r_min: 10, r_max: 11, z_min: 12, z_max: 13 };
    let mesh = rectangle_mesh(&radial_lines(4), &z, |r, _| band(r), sides).unwrap();
    let problem = Problem {
        mesh: Arc::new(mesh),
        regions: (1..=4)
            .map(|tag| Region { tag, material: Magnetic::air(), source: None })
            .collect(),
        boundaries: vec![Boundary { tag: 11, condition: BoundaryCondition::Dirichlet }],
    };
    let solver = || Solver::new(problem.clone(), SolverOptions::default()).unwrap();
    let coil =
        |drive| Coil { tag: 3, turns: 10.0, drive, waveform: Waveform::Step { initial: 0.0 } };
    let error = Dynamics::new(solver(), &[], vec![coil(drive)]).unwrap_err().to_string();
    assert!(error.contains("series_resistance_ohm"), "{error}");
    let negative = [Conductor { tag: 1, conductivity_s_per_m: -1.0 }];
    let error =
        Dynamics::new(solver(), &negative, vec![coil(current_drive())]).unwrap_err().to_string();
    assert!(error.contains("conductivity"), "{error}");
    let mut dynamics = Dynamics::new(solver(), &[], vec![coil(current_drive())]).unwrap();
    let short = TransientOptions::new(1e-3, Scheme::Bdf2, TimeStep::Fixed { dt_s: 1e-2 });
    let error = dynamics.transient(&short).unwrap_err().to_string();
    assert!(error.contains("shorter than dt"), "{error}");
    let probes = [Probe { name: "outside".into(), point: [1.0, 0.0] }];
    let mut options = TransientOptions::new(1e-3, Scheme::Bdf2, TimeStep::Fixed { dt_s: 1e-4 });
    options.probes = probes.to_vec();
    assert!(dynamics.transient(&options).is_err(), "a probe outside the mesh is an error");
}

/// The largest difference of two harmonic potentials relative to the largest value of `d`.
fn relative_difference(
    r: &mrbrake_magnetics::dynamics::harmonic::HarmonicPotential,
    d: &mrbrake_magnetics::dynamics::harmonic::HarmonicPotential,
) -> f64 {
    let scale = d.re.iter().chain(&d.im).fold(0.0_f64, |m, v| m.max(v.abs()));
    let diff =
        r.re.iter()
            .zip(&d.re)
            .chain(r.im.iter().zip(&d.im))
            .fold(0.0_f64, |m, (a, b)| m.max((a - b).abs()));
    diff / scale
}

#[test]
fn reduced_sweep_matches_the_direct_sweep() {
    use mrbrake_magnetics::dynamics::harmonic::HarmonicMethod;
    let mut dynamics =
        cylinder(40, Magnetic::air(), SIGMA, current_drive(), Waveform::Step { initial: 0.0 });
    // From a/δ ≈ 0.05 to 20: four decades of ω, ten points a decade, and zero.
    let omega_1 = 2.0 / (MU_0 * SIGMA * A * A);
    let mut frequencies = vec![0.0];
    frequencies.extend(
        (0..=40)
            .map(|k| omega_1 * 10f64.powf(k as f64 / 10.0 - 2.5) / (2.0 * std::f64::consts::PI)),
    );
    let (reduced, report) =
        dynamics.harmonic_potentials_by(&frequencies, None, HarmonicMethod::default()).unwrap();
    let (direct, _) =
        dynamics.harmonic_potentials_by(&frequencies, None, HarmonicMethod::Direct).unwrap();
    let report = report.expect("a reduced sweep reports");
    let worst =
        reduced.iter().zip(&direct).fold(0.0_f64, |m, (r, d)| m.max(relative_difference(r, d)));
    println!(
        "reduced sweep: {} shifts, basis {}, residual {:.2e}, energy bound {:.2e}; \
         largest difference from the direct sweep {worst:.2e} of the largest potential",
        report.shifts.len(),
        report.basis,
        report.max_backward_error,
        report.max_energy_error_bound
    );
    assert!(report.max_backward_error <= 1e-7);
    assert!(worst < 1e-7, "reduced vs direct: {worst:.3e}");
}

#[test]
#[cfg_attr(not(heavy_tests), ignore = "release only: a 16 k-node sweep")]
fn reduced_sweep_of_the_pot_core_matches_the_direct_sweep() {
    use mrbrake_magnetics::dynamics::harmonic::HarmonicMethod;
    let mut dynamics = mrbrake_magnetics::benchmark::conducting_pot_core(16_000).unwrap();
    let frequencies: Vec<f64> = (0..31).map(|k| 10f64.powf(k as f64 / 10.0)).collect();
    let method = HarmonicMethod::default();
    let (reduced, report) = dynamics.harmonic_potentials_by(&frequencies, None, method).unwrap();
    let (direct, _) =
        dynamics.harmonic_potentials_by(&frequencies, None, HarmonicMethod::Direct).unwrap();
    let report = report.expect("a reduced sweep reports");
    let (mut worst_potential, mut worst_flux) = (0.0_f64, 0.0_f64);
    for (r, d) in reduced.iter().zip(&direct) {
        worst_potential = worst_potential.max(relative_difference(r, d));
        let flux_r = dynamics.harmonic_point(r, &[]).unwrap().coils[0].flux_linkage_wb;
        let flux_d = dynamics.harmonic_point(d, &[]).unwrap().coils[0].flux_linkage_wb;
        let flux_error =
            ((flux_r[0] - flux_d[0]).hypot(flux_r[1] - flux_d[1])) / flux_d[0].hypot(flux_d[1]);
        worst_flux = worst_flux.max(flux_error);
    }
    println!(
        "pot core sweep: {} rounds, {} shifts, basis {}, backward error {:.2e}, energy bound \
         {:.2e}; against the direct sweep: potential {worst_potential:.2e} of the largest, flux \
         linkage {worst_flux:.2e}",
        report.rounds,
        report.shifts.len(),
        report.basis,
        report.max_backward_error,
        report.max_energy_error_bound
    );
    assert!(worst_potential < 1e-5, "reduced vs direct potential: {worst_potential:.3e}");
    assert!(worst_flux < 1e-8, "reduced vs direct flux linkage: {worst_flux:.3e}");
}
