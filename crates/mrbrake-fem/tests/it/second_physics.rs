//! A second physics through the FEM core, in one file: proof that a new physics is a form and
//! nothing else (issue 12).
//!
//! Axisymmetric steady diffusion with a cubic reaction (e.g. a heat-conduction problem with a
//! temperature-dependent sink),
//!
//! `−(1/r) ∂_r(r ∂_r u) − ∂_z² u + c u³ = q` on `(r, z) ∈ [0, 1] × [0, 1]`,
//!
//! the stationarity condition of the convex energy `∫ (½|∇u|² + ¼ c u⁴ − q u) r dr dz`, so its
//! Jacobian `∫ (∇φ_i·∇φ_j + 3 c u² φ_i φ_j) r dr dz` is symmetric positive definite and the core's
//! Newton solver applies. Manufactured solution `u = cos(a r) e^z` with `a = π/2`:
//! `q = e^z [a sin(a r)/r + (a² − 1) cos(a r)] + c u³`. `u` is prescribed on `r = 1` (where it is
//! zero), `z = 0` and `z = 1`; the axis is a natural (symmetry) boundary, as a temperature is.
//!
//! Checked: the observed L2 convergence orders under uniform refinement (2 for P1, 3 for P2; the
//! theory for smooth solutions, e.g. Brenner & Scott, *The Mathematical Theory of Finite Element
//! Methods*, Thm 5.4.8), for the linear (`c = 0`, one Newton step) and the non-linear (`c = 1`)
//! problem; and, for the transient `∂u/∂t − Δu = q` on the core's time integrator
//! (`mrbrake_fem::workflow::time`: the physics says its static form, its mass and its time-dependent
//! load), first-order convergence in time for implicit Euler and second-order for BDF2, each with
//! one factorisation per step size (e.g. Thomée, *Galerkin Finite Element Methods for Parabolic
//! Problems*, 2nd ed., Thm 1.5 and §10).

use std::f64::consts::FRAC_PI_2 as A;
use std::sync::Arc;

use mrbrake_fem::discretisation::basis::{Basis, Element, Weighting};
use mrbrake_fem::discretisation::dofs::ElementOrder;
use mrbrake_fem::discretisation::element::{ElementTriP2, TriangleBasis};
use mrbrake_fem::mesh::structured::{SideTags, graded_lines, rectangle_mesh};
use mrbrake_fem::workflow::assemble::{
    Assembly, ElementForm, MAX_PACKED_LEN, element_matrices, element_matrix_product,
    element_vectors, packed_len,
};
use mrbrake_fem::workflow::constraints::Constraints;
use mrbrake_fem::workflow::newton::{
    AssembledSystem, EliminationOrder, NewtonOptions, NewtonSolver, NonlinearSystem, norm2,
};
use mrbrake_fem::workflow::time::{
    Outcome, Scheme, Step, TimeOptions, TimeStep, TransientProblem, integrate,
};
use mrbrake_observe::Silent;

fn exact(p: [f64; 2]) -> f64 {
    (A * p[0]).cos() * p[1].exp()
}

fn source(p: [f64; 2], c: f64) -> f64 {
    let (r, z) = (p[0], p[1]);
    let u = exact(p);
    z.exp() * (A * (A * r).sin() / r + (A * A - 1.0) * (A * r).cos()) + c * u * u * u
}

/// The weak form `∫ (∇u·∇φ_i + c u³ φ_i − q φ_i) r dr dz` and its Jacobian.
struct DiffusionReaction {
    c: f64,
    linear: bool,
}

impl ElementForm for DiffusionReaction {
    fn element<E: TriangleBasis<N>, const N: usize>(
        &self,
        element: &Element<'_, E, N>,
        local: [f64; N],
        residual: &mut [f64],
        jacobian: Option<&mut [f64]>,
    ) {
        let (mut res, mut jac) = ([0.0; N], [0.0; MAX_PACKED_LEN]);
        let geometry = element.geometry();
        for q in element.points(&geometry) {
            let u: f64 = (0..N).map(|i| local[i] * q.phi[i]).sum();
            let grad_u = (0..N).fold([0.0; 2], |g, i| {
                [g[0] + local[i] * q.grad[i][0], g[1] + local[i] * q.grad[i][1]]
            });
            let f = source(q.point, self.c);
            let mut p = 0;
            for i in 0..N {
                let (gi, phi_i) = (q.grad[i], q.phi[i]);
                let flux = grad_u[0] * gi[0] + grad_u[1] * gi[1];
                res[i] += q.weight * (flux + self.c * u * u * u * phi_i - f * phi_i);
                for j in i..N {
                    let stiffness = gi[0] * q.grad[j][0] + gi[1] * q.grad[j][1];
                    jac[p] += q.weight * (stiffness + 3.0 * self.c * u * u * phi_i * q.phi[j]);
                    p += 1;
                }
            }
        }
        residual.copy_from_slice(&res);
        if let Some(out) = jacobian {
            out.copy_from_slice(&jac[..packed_len(N)]);
        }
    }

    fn has_constant_jacobian(&self, _index: usize) -> bool {
        self.linear
    }

    fn constant_jacobian<E: TriangleBasis<N>, const N: usize>(
        &self,
        element: &Element<'_, E, N>,
        jacobian: &mut [f64],
    ) {
        let mut residual = [0.0; N];
        self.element(element, [0.0; N], &mut residual, Some(jacobian));
    }
}

/// Solves on an `n × n` grid and returns the L2 error `(∫ (u_h − u)² r dr dz)^{1/2}` (degree-5
/// rule) and the Newton iterations.
fn solve(n: usize, order: ElementOrder, c: f64) -> (f64, usize) {
    let lines = graded_lines(0.0, 1.0, n, 1.0);
    let sides = SideTags { r_min: 1, r_max: 2, z_min: 3, z_max: 4 };
    let mesh = Arc::new(rectangle_mesh(&lines, &lines, |_, _| 1, sides).unwrap());
    let basis = Basis::new(mesh.clone(), order, 5, Weighting::Axisymmetric);
    let constraints = Constraints::builder(basis.dofs())
        .prescribe(2, exact)
        .prescribe(3, exact)
        .prescribe(4, exact)
        .build();
    let mut assembly = Assembly::new(basis, constraints).unwrap();
    let form = DiffusionReaction { c, linear: c.abs() < f64::EPSILON };
    assembly.prepare(&form);
    // Stopping scale: the residual at the lifting (the loads and the boundary values).
    let lifting = assembly.constraints().lifting();
    let mut residual = vec![0.0; assembly.n_free()];
    assembly.evaluate(&form, &lifting, &mut residual, None);
    let scale = norm2(&residual);
    let mut newton = NewtonSolver::for_assembly(&assembly, 1).unwrap();
    let mut u = lifting;
    let options = NewtonOptions { residual_tolerance: 1e-12, ..NewtonOptions::default() };
    let mut system = AssembledSystem { assembly: &mut assembly, form: &form };
    let report = newton.solve(&mut system, &mut u, scale, &options).unwrap();
    (l2_error(&assembly, &u), report.iterations)
}

fn l2_error(assembly: &Assembly, u: &[f64]) -> f64 {
    let basis = assembly.basis();
    let mut sum = 0.0;
    for t in 0..basis.n_elements() {
        sum += mrbrake_fem::by_order!(basis.order(), element_error(basis, t, u));
    }
    sum.sqrt()
}

fn element_error<E: TriangleBasis<N>, const N: usize>(basis: &Basis, t: usize, u: &[f64]) -> f64 {
    let element = basis.element::<E, N>(t);
    let geometry = element.geometry();
    let local = element.dofs().map(|d| u[d]);
    element
        .points(&geometry)
        .map(|q| {
            let uh: f64 = (0..N).map(|i| local[i] * q.phi[i]).sum();
            q.weight * (uh - exact(q.point)).powi(2)
        })
        .sum()
}

fn observed_orders(order: ElementOrder, c: f64) -> (Vec<f64>, Vec<usize>) {
    let runs: Vec<(f64, usize)> = [4, 8, 16].iter().map(|&n| solve(n, order, c)).collect();
    let orders = runs.windows(2).map(|w| (w[0].0 / w[1].0).log2()).collect();
    println!(
        "{order} c = {c}: L2 errors {:?}, orders {orders:?}",
        runs.iter().map(|r| r.0).collect::<Vec<_>>()
    );
    (orders, runs.iter().map(|r| r.1).collect())
}

#[test]
fn linear_diffusion_converges_at_the_optimal_rates() {
    let (p1, iterations) = observed_orders(ElementOrder::P1, 0.0);
    assert!(p1.iter().all(|&o| o > 1.9 && o < 2.2), "P1 orders {p1:?}");
    assert!(iterations.iter().all(|&k| k == 1), "a linear problem takes one step: {iterations:?}");
    let (p2, _) = observed_orders(ElementOrder::P2, 0.0);
    assert!(p2.iter().all(|&o| o > 2.8 && o < 3.3), "P2 orders {p2:?}");
}

#[test]
fn nonlinear_reaction_converges_by_newton_at_the_optimal_rates() {
    let (p1, iterations) = observed_orders(ElementOrder::P1, 1.0);
    assert!(p1.iter().all(|&o| o > 1.9 && o < 2.2), "P1 orders {p1:?}");
    assert!(iterations.iter().all(|&k| (2..10).contains(&k)), "Newton iterations {iterations:?}");
    let (p2, _) = observed_orders(ElementOrder::P2, 1.0);
    assert!(p2.iter().all(|&o| o > 2.8 && o < 3.3), "P2 orders {p2:?}");
}

/// The same diffusion operator with a time derivative, `∂u/∂t − Δu = q(r, z, t)`, as a physics
/// in time: the static form is the stiffness `K u`, the mass `M = ∫ φ_i φ_j r dr dz`, the load
/// `q = e^{−t} q̂(r, z)` (assembled once as `Q̂ = ∫ q̂ φ_i r dr dz`, scaled per step). A step of the
/// integrator solves `K u + ρ M (u − h) − e^{−t} Q̂ = 0`; its Jacobian `K + ρ M` is constant, so the
/// core factorises it once per step size and every step is one mass product and one solve.
/// Manufactured solution `u = e^{−t} (1 − r²)` (`q̂ = 3 + r²`), zero on `r = 1`, natural on
/// `z = 0` and `z = 1`: it lies in the P2 space at every time and every integrand is a polynomial
/// the degree-5 rule integrates exactly, so the semi-discrete (Galerkin) solution is the exact one
/// and the error measured is the scheme's alone.
struct Diffusion {
    newton: NewtonSolver,
    assembly: Assembly,
    /// Packed `∫ φ_i φ_j r` of every element.
    mass: Vec<f64>,
    /// `Q̂` at the free DOFs.
    load: Vec<f64>,
}

/// The element form of a step: `∫ (∇u·∇φ_i + ρ (u − h) φ_i) r dr dz` (`ρ = 0`: the static form).
struct DiffusionStep<'a> {
    rate: f64,
    history: &'a [f64],
}

impl ElementForm for DiffusionStep<'_> {
    fn element<E: TriangleBasis<N>, const N: usize>(
        &self,
        element: &Element<'_, E, N>,
        local: [f64; N],
        residual: &mut [f64],
        jacobian: Option<&mut [f64]>,
    ) {
        let history = element.dofs().map(|d| self.history[d]);
        let (mut res, mut jac) = ([0.0; N], [0.0; MAX_PACKED_LEN]);
        let geometry = element.geometry();
        for q in element.points(&geometry) {
            let rate: f64 =
                self.rate * (0..N).map(|i| (local[i] - history[i]) * q.phi[i]).sum::<f64>();
            let grad_u = (0..N).fold([0.0; 2], |g, i| {
                [g[0] + local[i] * q.grad[i][0], g[1] + local[i] * q.grad[i][1]]
            });
            let mut p = 0;
            for i in 0..N {
                let (gi, phi_i) = (q.grad[i], q.phi[i]);
                res[i] += q.weight * (rate * phi_i + grad_u[0] * gi[0] + grad_u[1] * gi[1]);
                for j in i..N {
                    let stiffness = gi[0] * q.grad[j][0] + gi[1] * q.grad[j][1];
                    jac[p] += q.weight * (self.rate * phi_i * q.phi[j] + stiffness);
                    p += 1;
                }
            }
        }
        residual.copy_from_slice(&res);
        if let Some(out) = jacobian {
            out.copy_from_slice(&jac[..packed_len(N)]);
        }
    }

    fn has_constant_jacobian(&self, _index: usize) -> bool {
        true
    }

    fn constant_jacobian<E: TriangleBasis<N>, const N: usize>(
        &self,
        element: &Element<'_, E, N>,
        jacobian: &mut [f64],
    ) {
        let mut residual = [0.0; N];
        self.element(element, [0.0; N], &mut residual, Some(jacobian));
    }
}

/// The system of one step: the step's form and the load at its time.
struct DiffusionSystem<'a> {
    assembly: &'a mut Assembly,
    form: DiffusionStep<'a>,
    load: &'a [f64],
    t: f64,
}

impl NonlinearSystem for DiffusionSystem<'_> {
    fn constraints(&self) -> &Constraints {
        self.assembly.constraints()
    }

    fn evaluate(&mut self, u: &[f64], residual: &mut [f64], jacobian: Option<&mut [f64]>) {
        self.assembly.evaluate(&self.form, u, residual, jacobian);
        residual.iter_mut().zip(self.load).for_each(|(r, q)| *r -= (-self.t).exp() * q);
    }

    fn is_linear(&self) -> bool {
        true
    }
}

impl TransientProblem for Diffusion {
    type Error = mrbrake_fem::workflow::time::TimeError;
    type System<'a> = DiffusionSystem<'a>;

    fn constraints(&self) -> &Constraints {
        self.assembly.constraints()
    }

    fn newton(&mut self) -> &mut NewtonSolver {
        &mut self.newton
    }

    fn newton_options(&self) -> NewtonOptions {
        NewtonOptions::default()
    }

    fn residual_scale(&mut self) -> f64 {
        norm2(&self.load)
    }

    fn prepare(&mut self, step: &Step) {
        self.assembly.prepare(&DiffusionStep { rate: step.rate, history: &step.history });
    }

    fn step_system<'a>(
        &'a mut self,
        step: &'a Step,
    ) -> (&'a mut NewtonSolver, DiffusionSystem<'a>) {
        let form = DiffusionStep { rate: step.rate, history: &step.history };
        let system =
            DiffusionSystem { assembly: &mut self.assembly, form, load: &self.load, t: step.t };
        (&mut self.newton, system)
    }

    fn is_linear(&self) -> bool {
        true
    }

    fn static_residual(&mut self, u: &[f64]) -> Vec<f64> {
        let mut residual = vec![0.0; self.assembly.n_free()];
        self.assembly.evaluate(&DiffusionStep { rate: 0.0, history: u }, u, &mut residual, None);
        residual
    }

    fn mass_product(&self, x: &[f64]) -> Vec<f64> {
        let mut y = vec![0.0; x.len()];
        let dofs = self.assembly.basis().dofs().element_dofs();
        element_matrix_product::<6>(dofs, &self.mass, |_| 1.0, x, &mut y);
        y
    }

    fn add_step_loads(&self, step: &Step, _u: &[f64], residual: &mut [f64]) {
        residual.iter_mut().zip(&self.load).for_each(|(r, q)| *r -= (-step.t).exp() * q);
    }
}

fn transient_exact(p: [f64; 2], t: f64) -> f64 {
    (-t).exp() * (1.0 - p[0] * p[0])
}

/// `q̂` with `q = e^{−t} q̂` for the manufactured solution: `∂u/∂t = −e^{−t}(1 − r²)`,
/// `−Δu = −(1/r) ∂_r(r ∂_r u) = 4 e^{−t}`.
fn transient_source(p: [f64; 2]) -> f64 {
    3.0 + p[0] * p[0]
}

/// Integrates to `t = 2` in `steps` steps of `scheme` (P2); returns the L2 error at the end
/// and the run's outcome.
fn transient_error(scheme: Scheme, steps: usize) -> (f64, Outcome) {
    let lines = graded_lines(0.0, 1.0, 4, 1.0);
    let sides = SideTags { r_min: 1, r_max: 2, z_min: 3, z_max: 4 };
    let mesh = Arc::new(rectangle_mesh(&lines, &lines, |_, _| 1, sides).unwrap());
    let basis = Basis::new(mesh, ElementOrder::P2, 5, Weighting::Axisymmetric);
    let constraints = Constraints::builder(basis.dofs()).fix(2).build();
    let assembly = Assembly::new(basis, constraints).unwrap();
    let mass = element_matrices::<ElementTriP2, 6>(assembly.basis(), |_, q, m| {
        let mut p = 0;
        for i in 0..6 {
            for j in i..6 {
                m[p] += q.weight * q.phi[i] * q.phi[j];
                p += 1;
            }
        }
    });
    let vectors = element_vectors::<ElementTriP2, 6>(assembly.basis(), |_, q, v| {
        for i in 0..6 {
            v[i] += q.weight * transient_source(q.point) * q.phi[i];
        }
    });
    let load = assembly.vector(&vectors, |_| 1.0);
    let newton = NewtonSolver::for_assembly(&assembly, 1).unwrap();
    let mut diffusion = Diffusion { newton, assembly, mass, load };
    let coordinates = diffusion.assembly.basis().dofs().coordinates().to_vec();
    let initial: Vec<f64> = coordinates.iter().map(|&p| transient_exact(p, 0.0)).collect();
    let options = TimeOptions::new(2.0, scheme, TimeStep::Fixed { dt_s: 2.0 / steps as f64 });
    let outcome = integrate(&mut diffusion, initial, &options, Silent).unwrap();
    let basis = diffusion.assembly.basis();
    let mut sum = 0.0;
    for t in 0..basis.n_elements() {
        let element = basis.element::<ElementTriP2, 6>(t);
        let geometry = element.geometry();
        let local = element.dofs().map(|d| outcome.u[d]);
        for q in element.points(&geometry) {
            let uh: f64 = (0..6).map(|i| local[i] * q.phi[i]).sum();
            sum += q.weight * (uh - transient_exact(q.point, 2.0)).powi(2);
        }
    }
    (sum.sqrt(), outcome)
}

#[test]
fn transient_diffusion_converges_at_the_schemes_orders_in_time() {
    for (scheme, order, steps) in
        [(Scheme::ImplicitEuler, 1.0, [5, 10, 20]), (Scheme::Bdf2, 2.0, [10, 20, 40])]
    {
        let runs: Vec<(f64, Outcome)> = steps.iter().map(|&n| transient_error(scheme, n)).collect();
        let errors: Vec<f64> = runs.iter().map(|r| r.0).collect();
        let orders: Vec<f64> = errors.windows(2).map(|w| (w[0] / w[1]).log2()).collect();
        println!("{scheme}: L2 errors at t = 2 {errors:?}, orders in time {orders:?}");
        assert!(orders.iter().all(|&o| (o - order).abs() < 0.15 * order), "orders {orders:?}");
        // One factorisation per step size: BDF2's Euler start and the rest.
        let factorizations = runs.iter().map(|r| r.1.factorizations).collect::<Vec<_>>();
        assert!(factorizations.iter().all(|&f| f == scheme.order()), "{factorizations:?}");
    }
}

/// A sequence of nearby non-linear problems (`c` from 1 to 1.5, each solve starting from the last
/// solution), solved cold and with the warm start (`NewtonOptions::reuse_factor`): the same
/// solutions (both meet the stopping rule), fewer factorisations warm; and the two elimination
/// orders give the same solution.
#[test]
fn warm_start_and_elimination_orders_change_the_work_not_the_solution() {
    let lines = graded_lines(0.0, 1.0, 16, 1.0);
    let sides = SideTags { r_min: 1, r_max: 2, z_min: 3, z_max: 4 };
    let mesh = Arc::new(rectangle_mesh(&lines, &lines, |_, _| 1, sides).unwrap());
    let basis = Basis::new(mesh, ElementOrder::P1, 5, Weighting::Axisymmetric);
    let constraints = Constraints::builder(basis.dofs())
        .prescribe(2, exact)
        .prescribe(3, exact)
        .prescribe(4, exact)
        .build();
    let mut assembly = Assembly::new(basis, constraints).unwrap();
    let run = |assembly: &mut Assembly, reuse_factor: bool, order: EliminationOrder| {
        let mut newton = NewtonSolver::for_assembly(assembly, 1).unwrap();
        newton.set_elimination_order(order).unwrap();
        let options =
            NewtonOptions { residual_tolerance: 1e-12, reuse_factor, ..NewtonOptions::default() };
        let mut u = assembly.constraints().lifting();
        let (mut solutions, mut factorizations) = (Vec::new(), 0);
        for k in 0..=10 {
            let form = DiffusionReaction { c: 1.0 + 0.05 * k as f64, linear: false };
            assembly.prepare(&form);
            let mut system = AssembledSystem { assembly: &mut *assembly, form: &form };
            factorizations +=
                newton.solve(&mut system, &mut u, 1.0, &options).unwrap().factorizations;
            solutions.push(u.clone());
        }
        (solutions, factorizations)
    };
    let (cold, cold_factorizations) = run(&mut assembly, false, EliminationOrder::NestedDissection);
    let (warm, warm_factorizations) = run(&mut assembly, true, EliminationOrder::NestedDissection);
    let (amd, _) = run(&mut assembly, false, EliminationOrder::MinimumDegree);
    let gap = |a: &[Vec<f64>], b: &[Vec<f64>]| {
        a.iter().flatten().zip(b.iter().flatten()).fold(0.0_f64, |m, (x, y)| m.max((x - y).abs()))
    };
    println!(
        "factorisations cold {cold_factorizations}, warm {warm_factorizations}; max |warm − cold| \
         {:.2e}, max |AMD − ND| {:.2e}",
        gap(&warm, &cold),
        gap(&amd, &cold)
    );
    assert!(warm_factorizations < cold_factorizations);
    assert!(gap(&warm, &cold) < 1e-9 && gap(&amd, &cold) < 1e-9);
}
