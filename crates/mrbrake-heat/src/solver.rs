//! Steady and transient heat solves on the FEM core.
//!
//! Set-up once per problem: the basis (P1 or P2, axisymmetric weight), the constraints (fixed
//! temperatures; the axis is a natural symmetry boundary for a scalar), the assembly prepared with
//! the [`HeatForm`], the boundary fluxes (convection and radiation) as the core's
//! [`EdgeFlux`], and the Newton solver (nested-dissection order and symbolic Cholesky once).
//!
//! - **Steady**: `R(T) = 0` by Newton; without radiation the system is linear and one step solves
//!   it (the Joule coupling is affine in `T`).
//! - **Transient** by implicit Euler (first order) or BDF2 (second order, started by one implicit
//!   Euler step, which keeps the global order two: its local error is `O(Δt²)`; Hairer, Nørsett
//!   and Wanner, *Solving ODEs I*, §III.3). Without radiation every step is the linear system
//!   `(a/Δt C + K) T_{n+1} = C h/Δt + F` with a fixed matrix: it is factorised once per scheme
//!   (twice for BDF2: the start and the rest). The right-hand side is affine in the history `h`:
//!   its constant part `−R(T_c, h = 0)` (sources, ambient, fixed temperatures `T_c`) is evaluated
//!   once with the factorisation, so a step costs one product with the capacity matrix `C`
//!   (element by element, [`element_matrix_product`]) and one pair of triangular solves. This is
//!   the same step as Newton's `T_{n+1} = T_n − K⁻¹ R(T_n)` on the affine residual (to rounding);
//!   measured on the thesis brake's 2 h warm-up (720 BDF2 steps), it replaced a full residual
//!   evaluation per step. With radiation each step is a Newton solve that starts from the previous
//!   step's factor as a CG preconditioner (`NewtonOptions::reuse_factor`; refactorised when CG
//!   does not reach the forcing tolerance in a few iterations).

use std::sync::Arc;

use mrbrake_fem::discretisation::basis::{Basis, Weighting};
use mrbrake_fem::discretisation::dofs::ElementOrder;
use mrbrake_fem::mesh::locate::PointLocator;
use mrbrake_fem::workflow::assemble::{Assembly, element_matrices, element_matrix_product};
use mrbrake_fem::workflow::boundary::EdgeFlux;
use mrbrake_fem::workflow::constraints::Constraints;
use mrbrake_fem::workflow::newton::{
    EliminationOrder, NewtonOptions, NewtonReport, NewtonSolver, NonlinearSystem, norm2,
};
use serde::Serialize;

use crate::form::{Capacity, Coefficients, HeatForm};
use crate::problem::{BoundaryCondition, HeatProblem};
use crate::{HeatError, STEFAN_BOLTZMANN};

/// Settings of the discretisation and of Newton.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SolverOptions {
    /// Element order.
    pub order: ElementOrder,
    /// Triangle quadrature degree (default: 2 for P1, 4 for P2).
    pub quadrature_degree: Option<usize>,
    /// Newton iterations (radiation).
    pub max_iterations: usize,
    /// Relative residual tolerance of Newton.
    pub tolerance: f64,
    /// Threads of the numeric factorisation.
    pub threads: usize,
}

impl Default for SolverOptions {
    fn default() -> Self {
        Self {
            order: ElementOrder::P1,
            quadrature_degree: None,
            max_iterations: 50,
            tolerance: 1e-10,
            threads: 1,
        }
    }
}

/// Time-integration scheme.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum TimeScheme {
    /// Implicit (backward) Euler: first order, L-stable.
    ImplicitEuler,
    /// Second-order backward differentiation, started by one implicit-Euler step.
    Bdf2,
}

/// A transient run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TransientSettings {
    /// Time step \[s\].
    pub dt_s: f64,
    /// End time \[s\].
    pub t_end_s: f64,
    /// Scheme.
    pub scheme: TimeScheme,
}

/// The outward boundary flux of one tag: `h (T − T_c) + εσ (T⁴ − T_r⁴)`.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub(crate) struct FluxLaw {
    h: f64,
    h_t_ambient: f64,
    eps_sigma: f64,
    eps_sigma_t_r4: f64,
}

impl FluxLaw {
    /// `(g, ∂g/∂T)` at `t` (kelvin).
    #[inline]
    pub(crate) fn eval(&self, t: f64) -> (f64, f64) {
        let t3 = t * t * t;
        (
            self.h * t - self.h_t_ambient + self.eps_sigma * t3 * t - self.eps_sigma_t_r4,
            self.h + 4.0 * self.eps_sigma * t3,
        )
    }
}

/// A heat problem set up on the core, ready for steady and transient solves.
#[derive(Debug)]
pub struct HeatSolver {
    pub(crate) problem: HeatProblem,
    pub(crate) assembly: Assembly,
    pub(crate) form: HeatForm,
    pub(crate) edges: EdgeFlux,
    /// `(tag, law)` sorted by tag.
    pub(crate) laws: Vec<(u32, FluxLaw)>,
    pub(crate) newton: NewtonSolver,
    pub(crate) options: SolverOptions,
    pub(crate) locator: PointLocator,
    /// `(tag, volume in m³)` of every region.
    pub(crate) volumes: Vec<(u32, f64)>,
    radiation: bool,
    /// `a/Δt` the assembly was last prepared with (`None`: steady).
    prepared: Option<Option<f64>>,
    /// The capacity matrix `∫ ρc φ_i φ_j r dr dz` of every element (packed upper triangles).
    capacity_matrices: Vec<f64>,
    /// `R(T_c, h = 0)` at the free DOFs for the factorised step matrix (linear transients), reset
    /// whenever a source, a boundary or `a/Δt` changes.
    step_offset: Option<Vec<f64>>,
}

/// The system of one solve: the assembly with the form and the boundary fluxes.
struct HeatSystem<'a> {
    assembly: &'a mut Assembly,
    form: &'a HeatForm,
    edges: &'a EdgeFlux,
    laws: &'a [(u32, FluxLaw)],
    linear: bool,
}

pub(crate) fn law_of(laws: &[(u32, FluxLaw)], tag: u32) -> FluxLaw {
    laws.iter().find(|(t, _)| *t == tag).map_or(FluxLaw::default(), |(_, l)| *l)
}

impl NonlinearSystem for HeatSystem<'_> {
    fn constraints(&self) -> &Constraints {
        self.assembly.constraints()
    }

    fn evaluate(&mut self, u: &[f64], residual: &mut [f64], mut jacobian: Option<&mut [f64]>) {
        self.assembly.evaluate(self.form, u, residual, jacobian.as_deref_mut());
        let laws = self.laws;
        let free = self.assembly.constraints().free_index();
        self.edges.add(free, u, |tag, _, t| law_of(laws, tag).eval(t), residual, jacobian);
    }

    fn is_linear(&self) -> bool {
        self.linear
    }
}

/// The volume `2π ∫ r dr dz` of every region.
fn region_volumes(problem: &HeatProblem) -> Vec<(u32, f64)> {
    let mesh = &problem.mesh;
    let mut volumes: Vec<(u32, f64)> = mesh.region_tags().into_iter().map(|t| (t, 0.0)).collect();
    for (t, tri) in mesh.triangles.iter().enumerate() {
        let centroid_r =
            (mesh.nodes[tri[0]][0] + mesh.nodes[tri[1]][0] + mesh.nodes[tri[2]][0]) / 3.0;
        let v = 2.0 * std::f64::consts::PI * mesh.signed_area(t).abs() * centroid_r;
        let tag = mesh.triangle_tags[t];
        if let Some(entry) = volumes.iter_mut().find(|(g, _)| *g == tag) {
            entry.1 += v;
        }
    }
    volumes
}

fn build_form(problem: &HeatProblem, volumes: &[(u32, f64)]) -> HeatForm {
    let coefficients: Vec<Coefficients> = problem
        .regions
        .iter()
        .map(|r| {
            let volume = volumes.iter().find(|(t, _)| *t == r.tag).map_or(1.0, |v| v.1);
            let (q0, q1) = r.source.affine(volume);
            Coefficients { k_radial: r.k_radial, k_axial: r.k_axial, rho_c: r.rho_c, q0, q1 }
        })
        .collect();
    let element_region = problem
        .mesh
        .triangle_tags
        .iter()
        .map(|tag| {
            problem
                .regions
                .iter()
                .position(|r| r.tag == *tag)
                .expect("validated: every tag has a region")
        })
        .collect();
    HeatForm { coefficients, element_region, capacity: None }
}

/// `∫ ρc φ_i φ_j r dr dz` of every element (packed upper triangles).
fn capacity_matrices<E: mrbrake_fem::discretisation::element::TriangleBasis<N>, const N: usize>(
    basis: &Basis,
    form: &HeatForm,
) -> Vec<f64> {
    element_matrices::<E, N>(basis, |t, q, m| {
        let rho_c = form.coefficients_of(t).rho_c;
        let mut p = 0;
        for i in 0..N {
            for j in i..N {
                m[p] += q.weight * rho_c * q.phi[i] * q.phi[j];
                p += 1;
            }
        }
    })
}

fn flux_laws(problem: &HeatProblem) -> Vec<(u32, FluxLaw)> {
    let mut laws: Vec<(u32, FluxLaw)> = Vec::new();
    for b in &problem.boundaries {
        let entry = match laws.iter().position(|(t, _)| *t == b.tag) {
            Some(k) => &mut laws[k].1,
            None => {
                laws.push((b.tag, FluxLaw::default()));
                &mut laws.last_mut().expect("just pushed").1
            }
        };
        match b.condition {
            BoundaryCondition::Convection { h_w_per_m2k, ambient_k } => {
                entry.h += h_w_per_m2k;
                entry.h_t_ambient += h_w_per_m2k * ambient_k;
            }
            BoundaryCondition::Radiation { emissivity, ambient_k } => {
                entry.eps_sigma += emissivity * STEFAN_BOLTZMANN;
                entry.eps_sigma_t_r4 += emissivity * STEFAN_BOLTZMANN * ambient_k.powi(4);
            }
            BoundaryCondition::Temperature { .. } | BoundaryCondition::Adiabatic => {}
        }
    }
    laws.sort_by_key(|(t, _)| *t);
    laws
}

impl HeatSolver {
    /// Validates `problem` and sets it up on the core.
    pub fn new(problem: HeatProblem, options: SolverOptions) -> Result<Self, HeatError> {
        problem.validate()?;
        problem.mesh.validate()?;
        let degree = options.quadrature_degree.unwrap_or(match options.order {
            ElementOrder::P1 => 2,
            ElementOrder::P2 => 4,
        });
        let basis =
            Basis::new(Arc::clone(&problem.mesh), options.order, degree, Weighting::Axisymmetric);
        let mut builder = Constraints::builder(basis.dofs());
        for b in &problem.boundaries {
            if let BoundaryCondition::Temperature { t_k } = b.condition {
                builder = builder.prescribe(b.tag, move |_| t_k);
            }
        }
        let constraints = builder.build();
        let assembly = Assembly::new(basis, constraints)?;
        let volumes = region_volumes(&problem);
        let form = build_form(&problem, &volumes);
        let laws = flux_laws(&problem);
        let tags: Vec<u32> = laws.iter().map(|(t, _)| *t).collect();
        let edges = EdgeFlux::new(&assembly, &tags)?;
        let newton = NewtonSolver::for_assembly(&assembly, options.threads)?;
        let locator = PointLocator::new(&problem.mesh);
        let radiation = laws.iter().any(|(_, l)| l.eps_sigma > 0.0);
        let capacity_matrices =
            mrbrake_fem::by_order!(options.order, capacity_matrices(assembly.basis(), &form));
        Ok(Self {
            problem,
            assembly,
            form,
            edges,
            laws,
            newton,
            options,
            locator,
            volumes,
            radiation,
            prepared: None,
            capacity_matrices,
            step_offset: None,
        })
    }

    /// The problem.
    pub fn problem(&self) -> &HeatProblem {
        &self.problem
    }

    /// The basis (mesh, order, DOFs).
    pub fn basis(&self) -> &Basis {
        self.assembly.basis()
    }

    /// Number of unknowns (free DOFs).
    pub fn unknowns(&self) -> usize {
        self.assembly.n_free()
    }

    /// Seconds of the ordering and symbolic factorisation.
    pub fn symbolic_factorisation_s(&self) -> f64 {
        self.newton.symbolic_factorisation_s()
    }

    /// Replaces the source of region `tag` (e.g. a new current) without a new set-up.
    pub fn set_source(&mut self, tag: u32, source: crate::Source) -> Result<(), HeatError> {
        let k = self
            .problem
            .regions
            .iter()
            .position(|r| r.tag == tag)
            .ok_or_else(|| HeatError::Input(format!("no region with physical tag {tag}")))?;
        self.problem.regions[k].source = source;
        let volume = self.volumes.iter().find(|(t, _)| *t == tag).map_or(1.0, |v| v.1);
        let (q0, q1) = source.affine(volume);
        let changed_jacobian = (self.form.coefficients[k].q1 - q1).abs() > 0.0;
        self.form.coefficients[k].q0 = q0;
        self.form.coefficients[k].q1 = q1;
        self.step_offset = None;
        if changed_jacobian {
            self.prepared = None;
        }
        Ok(())
    }

    /// Replaces the heat-transfer coefficient and ambient of the convection boundary `tag` (e.g. a
    /// natural-convection `h` iterated with the surface temperature) without a new set-up.
    pub fn set_convection(
        &mut self,
        tag: u32,
        h_w_per_m2k: f64,
        ambient_k: f64,
    ) -> Result<(), HeatError> {
        if !(h_w_per_m2k.is_finite() && h_w_per_m2k >= 0.0 && ambient_k.is_finite()) {
            return Err(HeatError::Input(format!(
                "convection on boundary {tag}: h = {h_w_per_m2k} W/(m² K) must be >= 0"
            )));
        }
        let boundary = self
            .problem
            .boundaries
            .iter_mut()
            .find(|b| b.tag == tag && matches!(b.condition, BoundaryCondition::Convection { .. }))
            .ok_or_else(|| HeatError::Input(format!("no convection boundary with tag {tag}")))?;
        boundary.condition = BoundaryCondition::Convection { h_w_per_m2k, ambient_k };
        self.laws = flux_laws(&self.problem);
        self.prepared = None;
        self.step_offset = None;
        Ok(())
    }

    /// A uniform start at `t_k` with the fixed temperatures imposed.
    pub fn uniform(&self, t_k: f64) -> Vec<f64> {
        let mut u = vec![t_k; self.assembly.basis().dofs().len()];
        self.assembly.constraints().impose(&mut u);
        u
    }

    /// A reference temperature: the mean of the ambient and fixed temperatures (20 °C if none).
    pub fn reference_temperature(&self) -> f64 {
        let temps: Vec<f64> = self
            .problem
            .boundaries
            .iter()
            .filter_map(|b| match b.condition {
                BoundaryCondition::Convection { ambient_k, .. }
                | BoundaryCondition::Radiation { ambient_k, .. } => Some(ambient_k),
                BoundaryCondition::Temperature { t_k } => Some(t_k),
                BoundaryCondition::Adiabatic => None,
            })
            .collect();
        if temps.is_empty() { crate::T20_K } else { temps.iter().sum::<f64>() / temps.len() as f64 }
    }

    fn has_joule_feedback(&self) -> bool {
        self.form.coefficients.iter().any(|c| c.q1 > 0.0)
    }

    /// A failure of the factorisation with a positive source feedback is a thermal runaway.
    fn runaway_or(&self, error: HeatError) -> HeatError {
        let factorisation = match &error {
            HeatError::NotConverged(e) => {
                e.reason.contains("factorisation") || e.reason.contains("positive")
            }
            HeatError::Fem(mrbrake_fem::FemError::Numerical(_)) => true,
            _ => false,
        };
        if factorisation && self.has_joule_feedback() {
            HeatError::Runaway(format!("the system matrix is not positive definite ({error})"))
        } else {
            error
        }
    }

    /// Prepares the assembly for `a/Δt` (`None`: steady) when it changed.
    fn prepare(&mut self, a_over_dt: Option<f64>) {
        if self.prepared != Some(a_over_dt) {
            self.assembly.prepare(&self.form);
            self.prepared = Some(a_over_dt);
        }
    }

    /// Newton's settings; `warm`: start from the previous solve's factor (the steps of a
    /// transient with radiation, whose Jacobians differ little from step to step).
    fn newton_options(&self, warm: bool) -> NewtonOptions {
        NewtonOptions {
            reuse_factor: warm,
            max_iterations: self.options.max_iterations,
            residual_tolerance: self.options.tolerance,
            ..NewtonOptions::default()
        }
    }

    /// Solves the current system (steady, or a step whose capacity is set) from `u` by Newton.
    fn newton_solve(&mut self, u: &mut Vec<f64>, warm: bool) -> Result<NewtonReport, HeatError> {
        let options = self.newton_options(warm);
        let mut system = HeatSystem {
            assembly: &mut self.assembly,
            form: &self.form,
            edges: &self.edges,
            laws: &self.laws,
            linear: !self.radiation,
        };
        let mut residual = vec![0.0; system.assembly.n_free()];
        system.evaluate(u, &mut residual, None);
        let scale = norm2(&residual).max(f64::MIN_POSITIVE);
        self.newton.solve(&mut system, u, scale, &options).map_err(HeatError::from)
    }

    /// The steady temperature (kelvin, one value per DOF) from the start `initial` (uniform
    /// [`Self::reference_temperature`] when `None`), with Newton's report.
    pub fn steady(
        &mut self,
        initial: Option<&[f64]>,
    ) -> Result<(Vec<f64>, NewtonReport), HeatError> {
        self.form.capacity = None;
        self.prepare(None);
        let mut u = match initial {
            Some(t) => t.to_vec(),
            None => self.uniform(self.reference_temperature()),
        };
        match self.newton_solve(&mut u, false) {
            Ok(report) => Ok((u, report)),
            Err(e) => Err(self.runaway_or(e)),
        }
    }

    /// Sets the capacity term of a step with `a/Δt`, `1/Δt` and history `h`, preparing (and for a
    /// linear problem factorising) when `a/Δt` changed. Returns true when a factorisation was made.
    fn set_step(&mut self, a: f64, dt: f64, history: Vec<f64>) -> Result<bool, HeatError> {
        let a_over_dt = a / dt;
        self.form.capacity = Some(Capacity { a_over_dt, inv_dt: 1.0 / dt, history });
        let changed = self.prepared != Some(Some(a_over_dt));
        self.prepare(Some(a_over_dt));
        if changed && !self.radiation {
            let mut system = HeatSystem {
                assembly: &mut self.assembly,
                form: &self.form,
                edges: &self.edges,
                laws: &self.laws,
                linear: true,
            };
            let u = system.assembly.constraints().lifting();
            // Hundreds of solves per factorisation: the order with the fewest factor entries.
            self.newton.set_elimination_order(EliminationOrder::MinimumDegree)?;
            if let Err(e) = self.newton.factorize_at(&mut system, &u) {
                return Err(self.runaway_or(e.into()));
            }
            self.step_offset = None;
        }
        if !self.radiation && self.step_offset.is_none() {
            self.step_offset = Some(self.offset_without_history());
        }
        Ok(changed && !self.radiation)
    }

    /// `R(T_c, h = 0)` at the free DOFs: the step residual at the fixed temperatures (free DOFs
    /// at zero) without history, the constant part of every linear step's right-hand side.
    fn offset_without_history(&mut self) -> Vec<f64> {
        let zeros = vec![0.0; self.assembly.basis().dofs().len()];
        let history = self.form.capacity.as_mut().map(|c| std::mem::replace(&mut c.history, zeros));
        let mut system = HeatSystem {
            assembly: &mut self.assembly,
            form: &self.form,
            edges: &self.edges,
            laws: &self.laws,
            linear: true,
        };
        let u = system.assembly.constraints().lifting();
        let mut offset = vec![0.0; system.assembly.n_free()];
        system.evaluate(&u, &mut offset, None);
        if let (Some(c), Some(h)) = (self.form.capacity.as_mut(), history) {
            c.history = h;
        }
        offset
    }

    /// One linear step with the stored factorisation: `K T_{n+1} = C h/Δt − R(T_c, h = 0)` at the
    /// free DOFs (the history `h` of the step set by [`Self::set_step`]); the fixed temperatures
    /// of `u` stay. (Solved for the increment `T_{n+1} − T_n` instead, the energy balance of a
    /// step is no better: its round-off comes from the capacity terms `C T/Δt`, large against the
    /// heat flows, whose cancellation the element-wise residual of a Newton step avoided: 2e-12
    /// of the heat out against 2e-14 on the validation cylinder.)
    fn linear_step(&mut self, u: &mut [f64]) -> Result<(), HeatError> {
        let capacity =
            self.form.capacity.as_ref().ok_or_else(|| {
                HeatError::Internal("a linear step without a capacity term".into())
            })?;
        let offset = self
            .step_offset
            .as_ref()
            .ok_or_else(|| HeatError::Internal("a linear step before its factorisation".into()))?;
        let mut c_h = vec![0.0; u.len()];
        let (dofs, matrices) =
            (self.assembly.basis().dofs().element_dofs(), &self.capacity_matrices);
        match self.options.order {
            ElementOrder::P1 => {
                element_matrix_product::<3>(dofs, matrices, |_| 1.0, &capacity.history, &mut c_h)
            }
            ElementOrder::P2 => {
                element_matrix_product::<6>(dofs, matrices, |_| 1.0, &capacity.history, &mut c_h)
            }
        }
        let constraints = self.assembly.constraints();
        let mut rhs = constraints.restrict(&c_h);
        for (r, o) in rhs.iter_mut().zip(offset) {
            *r = capacity.inv_dt * *r - o;
        }
        self.newton.solve_in_place(&mut rhs)?;
        let free = constraints.free_index();
        for (dof, value) in u.iter_mut().enumerate() {
            let d = free[dof];
            if d != mrbrake_fem::linalg::pattern::CONSTRAINED {
                *value = rhs[d];
            }
        }
        Ok(())
    }

    /// Integrates from `initial` (kelvin per DOF; fixed temperatures are imposed) to
    /// `settings.t_end_s`, calling `observe(time, T, solver)` after every step (the solver gives
    /// the step's post-processing: balances, region statistics). Returns the final temperature and
    /// the number of factorisations (linear problems) or Newton iterations (with radiation).
    pub fn transient(
        &mut self,
        initial: &[f64],
        settings: &TransientSettings,
        mut observe: impl FnMut(f64, &[f64], &HeatSolver) -> Result<(), HeatError>,
    ) -> Result<(Vec<f64>, usize), HeatError> {
        let (dt, t_end) = (settings.dt_s, settings.t_end_s);
        if !(dt.is_finite() && dt > 0.0 && t_end.is_finite() && t_end > 0.0) {
            return Err(HeatError::Input(format!(
                "transient: dt = {dt} s and t_end = {t_end} s must be > 0"
            )));
        }
        let steps = (t_end / dt - 1e-9).ceil().max(1.0) as usize;
        let mut u = initial.to_vec();
        self.assembly.constraints().impose(&mut u);
        let mut previous = u.clone();
        let mut work = 0;
        for step in 1..=steps {
            let (a, history) = match (settings.scheme, step) {
                (TimeScheme::Bdf2, s) if s > 1 => {
                    (1.5, u.iter().zip(&previous).map(|(n, m)| 2.0 * n - 0.5 * m).collect())
                }
                _ => (1.0, u.clone()),
            };
            work += usize::from(self.set_step(a, dt, history)?);
            previous.copy_from_slice(&u);
            if self.radiation {
                let report = self.newton_solve(&mut u, step > 1).map_err(|e| self.runaway_or(e))?;
                work += report.iterations;
            } else {
                self.linear_step(&mut u)?;
            }
            observe(step as f64 * dt, &u, self)?;
        }
        Ok((u, work))
    }
}
