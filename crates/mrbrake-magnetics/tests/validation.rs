//! Validation against closed-form solutions, with refinement studies asserting the observed order
//! of convergence (P1: ≈ 2 for A_phi in L2).
//!
//! Every case prints its measured errors (`cargo test -p mrbrake-magnetics --test validation -- --nocapture`).

use std::sync::Arc;

use mrbrake_fem::mesh::Mesh;
use mrbrake_fem::structured::{SideTags, graded_lines, half_disc_mesh, join_lines, rectangle_mesh};
use mrbrake_magnetics::exact::{
    CoilSection, long_solenoid_a_phi, long_solenoid_bz, loop_a_phi, sphere_a_phi, thick_coil_a_phi,
    thick_coil_axis_bz,
};
use mrbrake_magnetics::material::{MU_0, MagneticMaterial, MarroccoCurve, Reluctivity};
use mrbrake_magnetics::problem::{Boundary, BoundaryCondition, Problem, Region, Source};
use mrbrake_magnetics::{Solver, SolverOptions};

const AXIS: u32 = 100;
const OUTER: u32 = 101;
const BOTTOM: u32 = 102;
const TOP: u32 = 103;
const SIDES: SideTags = SideTags { r_min: AXIS, r_max: OUTER, z_min: BOTTOM, z_max: TOP };

fn sci(values: &[f64]) -> String {
    let items: Vec<String> = values.iter().map(|v| format!("{v:.3e}")).collect();
    format!("[{}]", items.join(", "))
}

fn observed_orders(errors: &[f64]) -> Vec<f64> {
    errors.windows(2).map(|w| (w[0] / w[1]).log2()).collect()
}

fn air(tag: u32) -> Region {
    Region { tag, material: MagneticMaterial::air(), source: None }
}

fn prescribed(tag: u32, g: impl Fn([f64; 2]) -> f64 + Send + Sync + 'static) -> Boundary {
    Boundary { tag, condition: BoundaryCondition::Prescribed(Arc::new(g)) }
}

/// Infinitely long thick solenoid: a slab in z with natural (B normal) top and bottom, exact A on the
/// outer radius. Refinement h, h/2, h/4.
#[test]
fn long_solenoid_converges_at_second_order() {
    let (j, r1, r2, r_box) = (2e6, 0.01, 0.015, 0.03);
    let mut errors = Vec::new();
    let mut b_errors = Vec::new();
    let mut coil_errors = Vec::new();
    for level in 0..3 {
        let n = 4 << level;
        let r = join_lines(&[
            graded_lines(0.0, r1, 2 * n, 1.0),
            graded_lines(r1, r2, n, 1.0),
            graded_lines(r2, r_box, 3 * n, 1.0),
        ]);
        let z = graded_lines(0.0, 0.005, n, 1.0);
        let mesh =
            rectangle_mesh(&r, &z, |rc, _| if rc > r1 && rc < r2 { 2 } else { 1 }, SIDES).unwrap();
        let problem = Problem {
            mesh: Arc::new(mesh),
            regions: vec![
                air(1),
                Region {
                    tag: 2,
                    material: MagneticMaterial::air(),
                    source: Some(Source::CurrentDensity { a_per_m2: j }),
                },
            ],
            boundaries: vec![prescribed(OUTER, move |p| long_solenoid_a_phi(j, r1, r2, p[0]))],
        };
        let mut solver = Solver::new(problem, SolverOptions::default()).unwrap();
        let solution = solver.solve(None).unwrap();
        assert_eq!(solution.report.iterations, 1);
        let e = solver.l2_error(&solution, |p| long_solenoid_a_phi(j, r1, r2, p[0]), &[]);
        let scale = solver.l2_error(&solution, |_| 0.0, &[]);
        errors.push(e / scale);
        let centre = solver.b_at(&solution, [0.0, 0.0025]).unwrap();
        let b0 = long_solenoid_bz(j, r1, r2, 0.0);
        b_errors.push(((centre.b_z_t - b0) / b0).abs());
        let p_coil = 0.3 * r1 + 0.7 * r2;
        let in_coil = solver.b_at(&solution, [p_coil, 0.0025]).unwrap();
        let b_coil = long_solenoid_bz(j, r1, r2, p_coil);
        coil_errors.push((in_coil.b_z_t - b_coil).abs() / b0);
    }
    let orders = observed_orders(&errors);
    println!(
        "long solenoid: relative L2(A) errors {}, orders {orders:.2?}; axis B errors {}, B in coil errors {}",
        sci(&errors),
        sci(&b_errors),
        sci(&coil_errors)
    );
    assert!(coil_errors[2] < 0.01);
    assert!(errors[2] < 2e-4, "finest relative L2 error {}", errors[2]);
    assert!(orders.iter().all(|&p| p > 1.9), "orders {orders:?}");
    assert!(b_errors[2] < 1e-3, "B on axis relative error {}", b_errors[2]);
}

/// Rectangular-section coil in a box whose boundary carries the exact (integrated-loop) potential:
/// A at nodes away from the coil and B on the axis against the closed forms.
#[test]
fn finite_thick_coil_axis_field_and_convergence() {
    let coil = CoilSection { r1: 0.01, r2: 0.02, z1: -0.01, z2: 0.01, j: 1e6 };
    let (r_box, z_box) = (0.05, 0.05);
    let mut errors = Vec::new();
    let mut axis_errors = Vec::new();
    for level in 0..3 {
        let n = 2 << level;
        let r = join_lines(&[
            graded_lines(0.0, coil.r1, 2 * n, 1.0),
            graded_lines(coil.r1, coil.r2, 2 * n, 1.0),
            graded_lines(coil.r2, r_box, 6 * n, 1.0),
        ]);
        let z = join_lines(&[
            graded_lines(-z_box, coil.z1, 8 * n, 1.0),
            graded_lines(coil.z1, coil.z2, 4 * n, 1.0),
            graded_lines(coil.z2, z_box, 8 * n, 1.0),
        ]);
        let inside = |r: f64, z: f64| r > coil.r1 && r < coil.r2 && z > coil.z1 && z < coil.z2;
        let mesh =
            rectangle_mesh(&r, &z, |rc, zc| if inside(rc, zc) { 2 } else { 1 }, SIDES).unwrap();
        let reference = move |p: [f64; 2]| thick_coil_a_phi(&coil, p[0], p[1], 2);
        let problem = Problem {
            mesh: Arc::new(mesh.clone()),
            regions: vec![
                air(1),
                Region {
                    tag: 2,
                    material: MagneticMaterial::air(),
                    source: Some(Source::CurrentDensity { a_per_m2: coil.j }),
                },
            ],
            boundaries: vec![
                prescribed(OUTER, reference),
                prescribed(TOP, reference),
                prescribed(BOTTOM, reference),
            ],
        };
        let mut solver = Solver::new(problem, SolverOptions::default()).unwrap();
        let solution = solver.solve(None).unwrap();
        // Discrete L2 error at the nodes on a fixed coarse sub-grid (the level-0 grid points), away
        // from the coil section where the loop integral is singular.
        let mut sum = 0.0;
        let mut norm = 0.0;
        for (v, p) in mesh.nodes.iter().enumerate() {
            let on_coarse = |x: f64, step: f64| ((x / step).round() * step - x).abs() < 1e-12;
            let away =
                p[0] < coil.r1 - 1e-9 || p[0] > coil.r2 + 0.004 || p[1].abs() > coil.z2 + 0.004;
            if away && on_coarse(p[0], 0.005) && on_coarse(p[1], 0.005) && p[0] > 0.0 {
                let exact = reference(*p);
                sum += (solution.a_phi()[v] - exact).powi(2) * p[0];
                norm += exact * exact * p[0];
            }
        }
        errors.push((sum / norm).sqrt());
        let mut worst: f64 = 0.0;
        for z in [0.0, 0.01, 0.02, 0.03] {
            let b = solver.b_at(&solution, [0.0, z]).unwrap();
            let exact = thick_coil_axis_bz(&coil, z);
            worst = worst.max(((b.b_z_t - exact) / thick_coil_axis_bz(&coil, 0.0)).abs());
        }
        axis_errors.push(worst);
    }
    let orders = observed_orders(&errors);
    println!(
        "thick coil: nodal relative L2(A) errors {}, orders {orders:.2?}; axis B errors {}",
        sci(&errors),
        sci(&axis_errors)
    );
    assert!(orders.iter().all(|&p| p > 1.8), "orders {orders:?}");
    assert!(errors[2] < 1e-3);
    assert!(axis_errors[2] < 5e-3, "axis B relative error {}", axis_errors[2]);
    assert!(axis_errors[2] < axis_errors[0]);
}

/// Thin coil (1 mm × 1 mm section, radius 20 mm) against the elliptic-integral loop potential, with
/// the exact potential on a box boundary, and then with the open (asymptotic) boundary on a half disc.
#[test]
fn current_loop_matches_elliptic_integrals() {
    let (a, side, current) = (0.02, 0.001, 10.0);
    let j = current / (side * side);
    let coil =
        CoilSection { r1: a - 0.5 * side, r2: a + 0.5 * side, z1: -0.5 * side, z2: 0.5 * side, j };
    let r = join_lines(&[
        graded_lines(0.0, coil.r1, 40, 1.0),
        graded_lines(coil.r1, coil.r2, 4, 1.0),
        graded_lines(coil.r2, 0.1, 60, 1.0),
    ]);
    let z = join_lines(&[
        graded_lines(-0.1, coil.z1, 60, 1.0 / 8.0),
        graded_lines(coil.z1, coil.z2, 4, 1.0),
        graded_lines(coil.z2, 0.1, 60, 8.0),
    ]);
    let in_coil = move |r: f64, z: f64| r > coil.r1 && r < coil.r2 && z > coil.z1 && z < coil.z2;
    let mesh = rectangle_mesh(&r, &z, |rc, zc| if in_coil(rc, zc) { 2 } else { 1 }, SIDES).unwrap();
    let filament = move |p: [f64; 2]| loop_a_phi(a, current, p[0], p[1]);
    let problem = Problem {
        mesh: Arc::new(mesh),
        regions: vec![
            air(1),
            Region {
                tag: 2,
                material: MagneticMaterial::air(),
                source: Some(Source::Coil { turns: 1.0, current_a: current }),
            },
        ],
        boundaries: vec![
            prescribed(OUTER, filament),
            prescribed(TOP, filament),
            prescribed(BOTTOM, filament),
        ],
    };
    let mut solver = Solver::new(problem, SolverOptions::default()).unwrap();
    let solution = solver.solve(None).unwrap();
    let probes = [[0.01, 0.0], [0.03, 0.0], [0.02, 0.015], [0.0, 0.01], [0.04, -0.02]];
    let mut worst: f64 = 0.0;
    for p in probes {
        let b = solver.b_at(&solution, p).unwrap();
        // Exact B from the loop potential by central differences of r A (B_z) and A (B_r).
        let h = 1e-6;
        let bz = if p[0] > 0.0 {
            ((p[0] + h) * filament([p[0] + h, p[1]]) - (p[0] - h) * filament([p[0] - h, p[1]]))
                / (2.0 * h * p[0])
        } else {
            2.0 * filament([h, p[1]]) / h
        };
        let br = -(filament([p[0], p[1] + h]) - filament([p[0], p[1] - h])) / (2.0 * h);
        let err = (b.b_r_t - br).hypot(b.b_z_t - bz) / br.hypot(bz);
        println!(
            "  loop probe {p:?}: B = ({:.4e}, {:.4e}) exact ({br:.4e}, {bz:.4e}), error {err:.2e}",
            b.b_r_t, b.b_z_t
        );
        worst = worst.max(err);
    }
    let l2 = solver.l2_error(&solution, filament, &[1]) / solver.l2_error(&solution, |_| 0.0, &[1]);
    println!(
        "current loop (box with exact boundary): relative L2(A) error {l2:.3e}, worst probe |B| error {worst:.3e}"
    );
    assert!(worst < 0.03, "probe B error {worst}");
    assert!(l2 < 5e-3);
}

/// A ring current on a polar block `ρ ∈ [18, 22] mm`, `θ ∈ π/2 ± π/16` (exactly meshed by the polar
/// grid), in a half disc of radius 100 mm = 5 × the ring radius: A = 0 on the circle (truncation)
/// versus the asymptotic open boundary, both against the exact potential (loop formula integrated
/// over the block).
#[test]
fn open_boundary_beats_truncation() {
    let j = 1e6;
    let (rho1, rho2) = (0.018, 0.022);
    let half = std::f64::consts::PI / 16.0;
    let (t1, t2) = (std::f64::consts::FRAC_PI_2 - half, std::f64::consts::FRAC_PI_2 + half);
    let reference = move |p: [f64; 2]| {
        let (x, w) = mrbrake_fem::quadrature::gauss_legendre_unit(12);
        let mut sum = 0.0;
        for (xr, wr) in x.iter().zip(&w) {
            for (xt, wt) in x.iter().zip(&w) {
                let rho = rho1 + (rho2 - rho1) * xr;
                let theta = t1 + (t2 - t1) * xt;
                sum += wr
                    * wt
                    * rho
                    * loop_a_phi(rho * theta.sin(), 1.0, p[0], p[1] - rho * theta.cos());
            }
        }
        sum * j * (rho2 - rho1) * (t2 - t1)
    };
    let radii = join_lines(&[
        graded_lines(0.001, rho1, 17, 1.0),
        graded_lines(rho1, rho2, 4, 1.0),
        graded_lines(rho2, 0.1, 40, 6.0),
    ]);
    let in_block = move |r: f64, z: f64| {
        let (rho, theta) = (r.hypot(z), r.atan2(z));
        rho > rho1 && rho < rho2 && theta > t1 && theta < t2
    };
    let mut errors = Vec::new();
    for open in [false, true] {
        let mesh =
            half_disc_mesh(&radii, 128, |rc, zc| if in_block(rc, zc) { 2 } else { 1 }, OUTER, AXIS)
                .unwrap();
        let condition = if open {
            BoundaryCondition::Open { centre_z_m: 0.0 }
        } else {
            BoundaryCondition::Dirichlet
        };
        let problem = Problem {
            mesh: Arc::new(mesh),
            regions: vec![
                air(1),
                Region {
                    tag: 2,
                    material: MagneticMaterial::air(),
                    source: Some(Source::CurrentDensity { a_per_m2: j }),
                },
            ],
            boundaries: vec![Boundary { tag: OUTER, condition }],
        };
        let mut solver = Solver::new(problem, SolverOptions::default()).unwrap();
        let solution = solver.solve(None).unwrap();
        let b_centre = 2.0 * reference([1e-7, 0.0]) / 1e-7;
        let mut worst: f64 = 0.0;
        for p in [[0.0, 0.0], [0.0, 0.03], [0.01, 0.01], [0.04, 0.0], [0.05, 0.05], [0.0, -0.06]] {
            let b = solver.b_at(&solution, p).unwrap();
            let h = 1e-6;
            let bz = if p[0] > 0.0 {
                ((p[0] + h) * reference([p[0] + h, p[1]])
                    - (p[0] - h) * reference([p[0] - h, p[1]]))
                    / (2.0 * h * p[0])
            } else {
                2.0 * reference([h, p[1]]) / h
            };
            worst = worst.max((b.b_z_t - bz).abs() / b_centre);
        }
        errors.push(worst);
    }
    println!(
        "ring current in a half disc of radius 5 × ring radius: worst B_z error / B_centre: A = 0 boundary {:.3e}, open boundary {:.3e}",
        errors[0], errors[1]
    );
    assert!(
        errors[1] < 0.2 * errors[0],
        "open boundary should cut the truncation error: {errors:?}"
    );
    assert!(errors[1] < 5e-3);
}

/// Permeable sphere (μr = 1000) in a uniform field, exact potential on the outer circle.
#[test]
fn permeable_sphere_in_uniform_field() {
    let (b0, mu_r, a) = (0.1, 1000.0, 0.01);
    let mut errors = Vec::new();
    let mut inside_errors = Vec::new();
    for level in 0..3 {
        let n = 4 << level;
        let radii = join_lines(&[
            graded_lines(a / (2 * n) as f64, a, 2 * n, 1.0),
            graded_lines(a, 4.0 * a, 3 * n, 3.0),
        ]);
        let mesh = half_disc_mesh(
            &radii,
            8 * n,
            |rc, zc| if rc.hypot(zc) < a { 2 } else { 1 },
            OUTER,
            AXIS,
        )
        .unwrap();
        let exact = move |p: [f64; 2]| sphere_a_phi(b0, mu_r, a, p[0], p[1]);
        let problem = Problem {
            mesh: Arc::new(mesh),
            regions: vec![
                air(1),
                Region { tag: 2, material: MagneticMaterial::Linear { mu_r }, source: None },
            ],
            boundaries: vec![prescribed(OUTER, exact)],
        };
        let mut solver = Solver::new(problem, SolverOptions::default()).unwrap();
        let solution = solver.solve(None).unwrap();
        errors.push(
            solver.l2_error(&solution, exact, &[]) / solver.l2_error(&solution, |_| 0.0, &[]),
        );
        let b_in = 3.0 * mu_r / (mu_r + 2.0) * b0;
        let stats = solver.region_stats(&solution, 2).unwrap();
        inside_errors.push((stats.mean_b_t - b_in).abs() / b_in);
    }
    let orders = observed_orders(&errors);
    println!(
        "sphere mu_r = {mu_r}: relative L2(A) errors {}, orders {orders:.2?}; mean B inside errors {}",
        sci(&errors),
        sci(&inside_errors)
    );
    assert!(orders.iter().all(|&p| p > 1.7), "orders {orders:?}");
    assert!(inside_errors[2] < 5e-3, "B inside error {}", inside_errors[2]);
}

/// Non-linear iron rod in an infinitely long solenoid: `H = J (r2 − r1)` everywhere inside the coil
/// (Ampère), so `B_rod = B_Fe(H)`, found here by bisection of the analytic curve, independent of the
/// solver. Driven into saturation (B ≈ 2 T) from A = 0.
#[test]
fn nonlinear_iron_rod_in_long_solenoid() {
    let curve = MarroccoCurve::soft_iron();
    let (r_rod, r1, r2, r_box) = (0.008, 0.01, 0.015, 0.025);
    let h0 = curve.h_of_b(2.0);
    let j = h0 / (r2 - r1);
    let b_rod = curve.b_of_h(h0);
    // Exact B(r) and A(r) = (1/r) ∫_0^r B s ds.
    let b_exact = move |r: f64| {
        if r < r_rod {
            b_rod
        } else if r < r1 {
            MU_0 * h0
        } else if r < r2 {
            MU_0 * j * (r2 - r)
        } else {
            0.0
        }
    };
    let a_exact = move |r: f64| {
        if r <= 0.0 {
            return 0.0;
        }
        let seg = |s0: f64, s1: f64| -> f64 {
            let (x, w) = mrbrake_fem::quadrature::gauss_legendre_unit(6);
            x.iter()
                .zip(&w)
                .map(|(x, w)| {
                    let s = s0 + (s1 - s0) * x;
                    w * b_exact(s) * s
                })
                .sum::<f64>()
                * (s1 - s0)
        };
        let mut total = 0.0;
        let mut lo = 0.0;
        for edge in [r_rod, r1, r2, f64::INFINITY] {
            let hi = edge.min(r);
            if hi > lo {
                total += seg(lo, hi);
            }
            lo = edge;
            if edge >= r {
                break;
            }
        }
        total / r
    };
    let mut errors = Vec::new();
    let mut b_errors = Vec::new();
    let mut iterations = Vec::new();
    for level in 0..3 {
        let n = 4 << level;
        let r = join_lines(&[
            graded_lines(0.0, r_rod, 2 * n, 1.0),
            graded_lines(r_rod, r1, n, 1.0),
            graded_lines(r1, r2, n, 1.0),
            graded_lines(r2, r_box, 2 * n, 1.0),
        ]);
        let z = graded_lines(0.0, 0.004, n, 1.0);
        let tag = |rc: f64, _z: f64| {
            if rc < r_rod {
                3
            } else if rc > r1 && rc < r2 {
                2
            } else {
                1
            }
        };
        let mesh = rectangle_mesh(&r, &z, tag, SIDES).unwrap();
        let problem = Problem {
            mesh: Arc::new(mesh),
            regions: vec![
                air(1),
                Region {
                    tag: 2,
                    material: MagneticMaterial::air(),
                    source: Some(Source::CurrentDensity { a_per_m2: j }),
                },
                Region {
                    tag: 3,
                    material: MagneticMaterial::NonLinear(Arc::new(curve)),
                    source: None,
                },
            ],
            boundaries: vec![prescribed(OUTER, move |p| a_exact(p[0]))],
        };
        let mut solver = Solver::new(problem, SolverOptions::default()).unwrap();
        let solution = solver.solve(None).unwrap();
        iterations.push(solution.report.iterations);
        errors.push(
            solver.l2_error(&solution, |p| a_exact(p[0]), &[])
                / solver.l2_error(&solution, |_| 0.0, &[]),
        );
        let stats = solver.region_stats(&solution, 3).unwrap();
        b_errors.push((stats.mean_b_t - b_rod).abs() / b_rod);
    }
    let orders = observed_orders(&errors);
    println!(
        "iron rod (B = {b_rod:.4} T, H = {h0:.0} A/m): relative L2(A) errors {}, orders {orders:.2?}; \
         mean B in rod errors {}; Newton iterations {iterations:?}",
        sci(&errors),
        sci(&b_errors)
    );
    assert!(orders.iter().all(|&p| p > 1.8), "orders {orders:?}");
    assert!(b_errors[2] < 1e-3);
    assert!(iterations.iter().all(|&k| k <= 25));
}

/// Mesh with the rod problem reused for a current sweep: warm start needs fewer iterations.
#[test]
fn warm_start_and_source_update_reuse_the_solver() {
    let curve = MarroccoCurve::soft_iron();
    let r = join_lines(&[
        graded_lines(0.0, 0.008, 8, 1.0),
        graded_lines(0.008, 0.01, 4, 1.0),
        graded_lines(0.01, 0.015, 4, 1.0),
        graded_lines(0.015, 0.025, 8, 1.0),
    ]);
    let z = graded_lines(0.0, 0.004, 4, 1.0);
    let tag = |rc: f64, _z: f64| {
        if rc < 0.008 {
            3
        } else if rc > 0.01 && rc < 0.015 {
            2
        } else {
            1
        }
    };
    let mesh: Mesh = rectangle_mesh(&r, &z, tag, SIDES).unwrap();
    let problem = Problem {
        mesh: Arc::new(mesh),
        regions: vec![
            air(1),
            Region {
                tag: 2,
                material: MagneticMaterial::air(),
                source: Some(Source::Coil { turns: 500.0, current_a: 0.0 }),
            },
            Region { tag: 3, material: MagneticMaterial::NonLinear(Arc::new(curve)), source: None },
        ],
        boundaries: vec![Boundary { tag: OUTER, condition: BoundaryCondition::Dirichlet }],
    };
    let mut solver = Solver::new(problem, SolverOptions::default()).unwrap();
    let mut previous: Option<Vec<f64>> = None;
    let mut cold_total = 0;
    let mut warm_total = 0;
    let mut fluxes = Vec::new();
    for step in 1..=5 {
        let current = 0.5 * step as f64;
        solver.set_source(2, Some(Source::Coil { turns: 500.0, current_a: current })).unwrap();
        let cold = solver.solve(None).unwrap();
        let warm = solver.solve(previous.as_deref()).unwrap();
        cold_total += cold.report.iterations;
        warm_total += warm.report.iterations;
        let b_cold = solver.b_at(&cold, [0.0, 0.002]).unwrap().b_z_t;
        let b_warm = solver.b_at(&warm, [0.0, 0.002]).unwrap().b_z_t;
        assert!((b_cold - b_warm).abs() < 1e-7 * b_cold.abs().max(1.0));
        fluxes.push(solver.coils(&warm)[0].flux_linkage_wb);
        previous = Some(warm.a_phi().to_vec());
    }
    println!("sweep: cold-start iterations {cold_total}, warm-start iterations {warm_total}");
    assert!(warm_total < cold_total);
    // Saturation: flux linkage grows sub-linearly with current.
    assert!(fluxes[4] / fluxes[0] < 5.0 && fluxes.windows(2).all(|w| w[1] > w[0]));
    let _ = curve.nu_and_dnu_db2(0.0);
}

/// The library's steel-1010 B-H curve (materials crate) in the long-solenoid rod: `B_rod = B(H0)` by
/// Ampère's law, at the knee (H = 2 kA/m, where dB/dH amplifies any error in H) and deep in
/// saturation, with one refinement step to show the error is discretisation (order ≈ 2).
#[test]
fn library_steel_rod_follows_its_bh_curve() {
    let steel = mrbrake_materials::library::get("steel-1010").unwrap();
    let mrbrake_materials::Magnetic::NonLinear(curve) = &steel.magnetic else {
        panic!("steel-1010 is non-linear")
    };
    let (r_rod, r1, r2, r_box) = (0.008, 0.01, 0.015, 0.025);
    for h0 in [2_000.0, 200_000.0] {
        let j = h0 / (r2 - r1);
        let b_rod = curve.b_of_h(h0);
        let mut errors = Vec::new();
        for n in [8, 16] {
            let r = join_lines(&[
                graded_lines(0.0, r_rod, 2 * n, 1.0),
                graded_lines(r_rod, r1, n / 2, 1.0),
                graded_lines(r1, r2, n, 1.0),
                graded_lines(r2, r_box, n, 1.0),
            ]);
            let z = graded_lines(0.0, 0.002, 2, 1.0);
            let tag = |rc: f64, _z: f64| {
                if rc < r_rod {
                    3
                } else if rc > r1 && rc < r2 {
                    2
                } else {
                    1
                }
            };
            let problem = Problem {
                mesh: Arc::new(rectangle_mesh(&r, &z, tag, SIDES).unwrap()),
                regions: vec![
                    air(1),
                    Region {
                        tag: 2,
                        material: MagneticMaterial::air(),
                        source: Some(Source::CurrentDensity { a_per_m2: j }),
                    },
                    Region {
                        tag: 3,
                        material: MagneticMaterial::from_library(&steel.magnetic),
                        source: None,
                    },
                ],
                // Outside the coil H = 0, so the natural condition (n × H = 0) on the outer radius is exact.
                boundaries: vec![],
            };
            let mut solver = Solver::new(problem, SolverOptions::default()).unwrap();
            let solution = solver.solve(None).unwrap();
            let stats = solver.region_stats(&solution, 3).unwrap();
            errors.push((stats.mean_b_t - b_rod).abs() / b_rod);
        }
        let order = (errors[0] / errors[1]).log2();
        println!(
            "steel-1010 rod at H = {h0} A/m (B(H) = {b_rod:.5} T): relative errors {}, order {order:.2}",
            sci(&errors)
        );
        assert!(errors[1] < 3e-3, "relative error {}", errors[1]);
        assert!(order > 1.8 || errors[1] < 1e-6, "order {order}");
    }
}
