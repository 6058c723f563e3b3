//! The magnetostatic solver: the A_phi form ([`crate::form`]) and the open boundary
//! ([`crate::open_boundary`]) on the FEM core — a basis, constraints (the axis and the Dirichlet
//! boundaries), an assembly with the free-DOF pattern, and the core's Newton solver
//! ([`mrbrake_fem::workflow::newton`]: safeguarded line search on the magnetic energy, preconditioned-CG
//! tail). Set up once per mesh (DOF numbering, pattern, symbolic Cholesky, the linear elements'
//! matrices), then solves that can be repeated with new sources and a warm start, as a current
//! sweep does.
//!
//! Stopping rule: `‖R‖₂ <= rtol · s`, where the scale `s = ‖F‖₂ + ‖R(A_D)‖₂` is the norm of the
//! source load vector plus that of the residual of the Dirichlet lifting `A_D` (interior zero)
//! evaluated in the *linear* (initial-reluctivity) state — both independent of the iterate.
//!
//! With hysteretic regions ([`crate::hysteresis`]) `s` is the largest scale of the current history
//! so far: at 0 A after a peak the remanent field has no source of its own, and its residual is
//! measured against the excitation that made it.
//!
//! A failed solve gives [`MagneticsError::NotConverged`] with the whole residual history.

use std::sync::Arc;
use std::time::Instant;

use mrbrake_fem::discretisation::basis::{Basis, Weighting};
use mrbrake_fem::discretisation::dofs::ElementOrder;
use mrbrake_fem::mesh::Mesh;
use mrbrake_fem::workflow::assemble::Assembly;
use mrbrake_fem::workflow::constraints::Constraints;
use mrbrake_fem::workflow::newton::{AssembledSystem, NewtonOptions, NewtonSolver, norm2};
use mrbrake_materials::{MU_0, Magnetic};

pub use mrbrake_fem::workflow::newton::{NewtonReport, NewtonStep, SolveTimings};

use crate::MagneticsError;
use crate::field::Solution;
use crate::form::AphiForm;
use crate::open_boundary::open_boundary_couplings;
use crate::problem::{BoundaryCondition, Problem, Source};

/// Solver settings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SolverOptions {
    /// Element order: linear (P1, the default) or quadratic (P2, 6-node) triangles. P2 has about
    /// four times the unknowns of P1 on the same mesh and converges one order faster (A in L2 at
    /// O(h³), B at O(h²)) where the field is smooth and the material interfaces are meshed
    /// exactly; a curved interface meshed by chords (straight-sided elements) limits it to O(h²)
    /// in A, as the permeable-sphere validation shows.
    pub order: ElementOrder,
    /// Degree of the triangle quadrature rule (2 by default; 4 for more accuracy on coarse meshes).
    /// P2 elements use at least degree 4 (a lower request is raised to 4: the 3-point rule cannot
    /// integrate their stiffness matrix), see [`SolverOptions::rule_degree`].
    pub quadrature_degree: usize,
    /// Maximum Newton iterations.
    pub max_iterations: usize,
    /// Relative residual tolerance `rtol` of the stopping rule.
    pub residual_tolerance: f64,
    /// Threads for faer's numeric factorisation (0: rayon's global pool; assembly always uses the
    /// pool, and so do the triangular solves, which run the two halves of the top
    /// nested-dissection separator in parallel). The default is 1: on the 2-core machines we
    /// measure on, faer's sequential supernodal factorisation of the 96.7 k-node benchmark took
    /// 0.49 s for 7 factorisations against 1.02 s with two threads (faer parallelises the dense
    /// kernels inside each supernode, which are small here); on a larger machine try 0.
    pub threads: usize,
}

impl Default for SolverOptions {
    fn default() -> Self {
        Self {
            order: ElementOrder::P1,
            quadrature_degree: 2,
            max_iterations: 50,
            residual_tolerance: 1e-9,
            threads: 1,
        }
    }
}

impl SolverOptions {
    /// Lowest quadrature degree used with P2 elements.
    pub const P2_MIN_QUADRATURE_DEGREE: usize = 4;

    /// The degree of the triangle rule actually used: `quadrature_degree` for P1, at least
    /// [`Self::P2_MIN_QUADRATURE_DEGREE`] for P2.
    pub fn rule_degree(&self) -> usize {
        match self.order {
            ElementOrder::P1 => self.quadrature_degree,
            ElementOrder::P2 => self.quadrature_degree.max(Self::P2_MIN_QUADRATURE_DEGREE),
        }
    }
}

/// Largest number of conjugate-gradient iterations tried with the previous factor before
/// refactorising (see [`mrbrake_fem::workflow::newton`]).
pub const TAIL_CG_MAX_ITERATIONS: usize = 4;

impl SolverOptions {
    /// The options of the core's Newton iteration.
    pub(crate) fn newton(&self) -> NewtonOptions {
        NewtonOptions {
            max_iterations: self.max_iterations,
            residual_tolerance: self.residual_tolerance,
            tail_cg_max_iterations: TAIL_CG_MAX_ITERATIONS,
            ..NewtonOptions::default()
        }
    }
}

/// A reusable solver for one mesh and one set of materials and boundary conditions.
#[derive(Debug)]
pub struct Solver {
    pub(crate) problem: Problem,
    pub(crate) options: SolverOptions,
    /// Basis, constraints, pattern and the constant part of the Jacobian.
    pub(crate) assembly: Assembly,
    /// Materials, region of every element, sources, linear-element matrices.
    pub(crate) form: AphiForm,
    /// Cholesky factorisation and Newton work arrays.
    pub(crate) newton: NewtonSolver,
    /// Cross-section area (m²) of every region.
    pub(crate) region_area: Vec<f64>,
    /// Point-location and recovery tables, built on the first point query.
    pub(crate) queries: crate::field::QueryCache,
}

impl Solver {
    /// Checks the problem and does the per-mesh work: DOF numbering, pattern, symbolic
    /// factorisation, the linear elements' matrices.
    pub fn new(problem: Problem, options: SolverOptions) -> Result<Self, MagneticsError> {
        let element_region = problem.element_regions()?;
        let mesh = problem.mesh.clone();
        let mut region_area = vec![0.0; problem.regions.len()];
        for (t, &ri) in element_region.iter().enumerate() {
            region_area[ri as usize] += mesh.signed_area(t);
        }
        let basis = Basis::new(mesh, options.order, options.rule_degree(), Weighting::Axisymmetric);
        let constraints = constraints_of(&problem, &basis);
        let mut assembly = Assembly::new(basis, constraints)?;
        let couplings = open_boundary_couplings(assembly.basis(), &problem)?;
        assembly.set_couplings(&couplings)?;
        let newton = NewtonSolver::for_assembly(&assembly, options.threads)?;
        let materials = problem.regions.iter().map(|r| r.material.clone()).collect();
        let form = AphiForm::new(assembly.basis(), materials, element_region);
        assembly.prepare(&form);
        let mut solver = Self {
            problem,
            options,
            assembly,
            form,
            newton,
            region_area,
            queries: Default::default(),
        };
        solver.update_sources()?;
        Ok(solver)
    }

    /// The problem being solved.
    pub fn problem(&self) -> &Problem {
        &self.problem
    }

    /// The mesh.
    pub fn mesh(&self) -> &Arc<Mesh> {
        &self.problem.mesh
    }

    /// The basis (DOF numbering, quadrature rule) of the solver.
    pub fn basis(&self) -> &Basis {
        self.assembly.basis()
    }

    /// Number of free unknowns.
    pub fn unknowns(&self) -> usize {
        self.assembly.n_free()
    }

    /// The element order of the solver (from [`SolverOptions::order`]).
    pub fn order(&self) -> ElementOrder {
        self.options.order
    }

    /// Number of degrees of freedom, free and constrained: the length of [`Solution::a_phi`]
    /// (mesh nodes for P1; nodes then edges for P2).
    pub fn dof_count(&self) -> usize {
        self.basis().dofs().len()
    }

    /// `[r, z]` (m) of every degree of freedom, in the order of [`Solution::a_phi`]: the mesh nodes,
    /// then (P2) the edge midpoints.
    pub fn dof_coordinates(&self) -> &[[f64; 2]] {
        self.basis().dofs().coordinates()
    }

    /// Seconds spent in the ordering and the symbolic factorisation (once per solver).
    pub fn symbolic_factorisation_s(&self) -> f64 {
        self.newton.symbolic_factorisation_s()
    }

    /// Stored entries of the Cholesky factor (fill-in measure).
    pub fn factor_nnz(&self) -> usize {
        self.newton.factor_nnz()
    }

    /// The region index (into the problem's regions) of triangle `t`.
    #[inline]
    pub(crate) fn region_of(&self, t: usize) -> usize {
        self.form.element_region[t] as usize
    }

    /// Replaces the source of region `tag` (e.g. the next current of a sweep). The mesh, pattern and
    /// symbolic factorisation are kept.
    pub fn set_source(&mut self, tag: u32, source: Option<Source>) -> Result<(), MagneticsError> {
        let region = self.problem.regions.iter_mut().find(|r| r.tag == tag).ok_or_else(|| {
            MagneticsError::field("tag", format!("set_source: no region with physical = {tag}"))
        })?;
        region.source = source;
        self.update_sources()
    }

    /// Current density (A/m²) of each region from its source (`N I / S` for coils).
    fn update_sources(&mut self) -> Result<(), MagneticsError> {
        let mut density = vec![0.0; self.problem.regions.len()];
        for (i, region) in self.problem.regions.iter().enumerate() {
            density[i] = match region.source {
                None => 0.0,
                Some(Source::CurrentDensity { a_per_m2 }) => a_per_m2,
                Some(Source::Coil { turns, current_a }) => {
                    if self.region_area[i] <= 0.0 {
                        return Err(MagneticsError::field(
                            "regions",
                            format!(
                                "coil region {} has zero area: it needs triangles in the mesh",
                                region.tag
                            ),
                        ));
                    }
                    turns * current_a / self.region_area[i]
                }
            };
            if !density[i].is_finite() {
                return Err(MagneticsError::field(
                    format!("region[physical={}].source", region.tag),
                    format!("region {}: source is not finite", region.tag),
                ));
            }
        }
        for (j, &ri) in self.form.current_density.iter_mut().zip(&self.form.element_region) {
            *j = density[ri as usize];
        }
        Ok(())
    }

    /// Residual scale `s = ‖F‖ + ‖R_lin(A_D)‖` of the stopping rule (see the module docs).
    pub(crate) fn residual_scale(&mut self) -> f64 {
        // Linear state: every material at its B = 0 reluctivity.
        let linear = self
            .form
            .materials
            .iter()
            .map(|m| Magnetic::Linear { mu_r: 1.0 / (MU_0 * m.nu_and_dnu_db2(0.0).0) })
            .collect();
        let saved = std::mem::replace(&mut self.form.materials, linear);
        // The scale is that of the linear problem: hysteretic points take their linear law too.
        let hysteresis = self.form.hysteresis.take();
        let lifting = self.assembly.constraints().lifting();
        let mut residual = vec![0.0; self.assembly.n_free()];
        let n_elements = self.form.current_density.len();
        let density = std::mem::replace(&mut self.form.current_density, vec![0.0; n_elements]);
        self.assembly.evaluate(&self.form, &lifting, &mut residual, None);
        let dirichlet_norm = norm2(&residual);
        self.form.current_density = density;
        let zero = vec![0.0; lifting.len()];
        self.assembly.evaluate(&self.form, &zero, &mut residual, None);
        let source_norm = norm2(&residual);
        self.form.materials = saved;
        self.form.hysteresis = hysteresis;
        source_norm + dirichlet_norm
    }

    /// Solves from `A = 0` (or from `initial`, e.g. a previous solution of a sweep: warm start,
    /// one value per DOF as in [`Solution::a_phi`]). Prescribed boundary values are imposed on
    /// the start vector.
    pub fn solve(&mut self, initial: Option<&[f64]>) -> Result<Solution, MagneticsError> {
        self.solve_with(initial, false)
    }

    /// [`Self::solve`], with `reuse_factor` passed to Newton ([`NewtonOptions::reuse_factor`]:
    /// the first step tries CG with the last factor before factorising; the stopping rule is the
    /// same). Shared by [`Self::solve`] and the quasi-static hysteresis steps.
    pub(crate) fn solve_with(
        &mut self,
        initial: Option<&[f64]>,
        reuse_factor: bool,
    ) -> Result<Solution, MagneticsError> {
        let start = Instant::now();
        let n_dofs = self.dof_count();
        let mut a = match initial {
            Some(init) if init.len() == n_dofs => init.to_vec(),
            Some(init) => {
                return Err(MagneticsError::field(
                    "init",
                    format!(
                        "warm start has {} values but the {} solver has {n_dofs} degrees of freedom \
                     (one per mesh node for P1; nodes then edges for P2)",
                        init.len(),
                        self.options.order
                    ),
                ));
            }
            None => vec![0.0; n_dofs],
        };
        let t = Instant::now();
        let mut scale = self.residual_scale().max(f64::MIN_POSITIVE);
        if let Some(field) = &mut self.form.hysteresis {
            // A remanent field has no source of its own (0 A): scale by the history's largest.
            scale = field.history_scale(scale);
        }
        let scale_s = t.elapsed().as_secs_f64();
        let options = NewtonOptions { reuse_factor, ..self.options.newton() };
        let mut system = AssembledSystem { assembly: &mut self.assembly, form: &self.form };
        let mut report = self.newton.solve(&mut system, &mut a, scale, &options)?;
        report.timings.assemble_s += scale_s;
        report.timings.total_s = start.elapsed().as_secs_f64();
        Ok(Solution::new(a, self.basis().dofs().n_vertices(), report))
    }

    /// Incremental inductance `dλ/dI` (H) of the coil region `tag` at the solution: one extra
    /// factorisation of the Jacobian at `solution` and one solve `K dA/dI = ∂F/∂I`, then
    /// `dλ/dI = (N/S) ∫ 2π r dA/dI dS` (the small-signal inductance seen by the current controller).
    pub fn incremental_inductance(
        &mut self,
        solution: &Solution,
        tag: u32,
    ) -> Result<f64, MagneticsError> {
        let ri = self.problem.regions.iter().position(|r| r.tag == tag).ok_or_else(|| {
            MagneticsError::field("tag", format!("no region with physical = {tag}"))
        })?;
        let Some(Source::Coil { turns, .. }) = self.problem.regions[ri].source else {
            return Err(MagneticsError::field(
                "tag",
                format!("region {tag} is not a coil (turns × current)"),
            ));
        };
        let mut system = AssembledSystem { assembly: &mut self.assembly, form: &self.form };
        self.newton.factorize_at(&mut system, solution.a_phi())?;
        // ∂F_i/∂I = (N/S) ∫_coil φ_i r dS = (N/S) Σ_elements f_i (the unit loads).
        let coil_density = turns / self.region_area[ri];
        let regions = &self.form.element_region;
        let mut rhs = self.assembly.vector(&self.form.unit_load, |t| {
            if regions[t] as usize == ri { coil_density } else { 0.0 }
        });
        self.newton.solve_in_place(&mut rhs)?;
        let da = self.assembly.constraints().extend_with_zeros(&rhs);
        Ok(crate::field::coil_flux(self, &da, ri, turns))
    }
}

/// The constraints of `problem` on `basis`: Dirichlet (`A = 0`) and prescribed boundaries in the
/// problem's order, then the axis (`A = 0` there whatever the boundaries say).
fn constraints_of(problem: &Problem, basis: &Basis) -> Constraints {
    let mut builder = Constraints::builder(basis.dofs());
    for boundary in &problem.boundaries {
        builder = match &boundary.condition {
            BoundaryCondition::Dirichlet => builder.fix(boundary.tag),
            BoundaryCondition::Prescribed(g) => builder.prescribe(boundary.tag, |p| g(p)),
            BoundaryCondition::Open { .. } => builder,
        };
    }
    builder.axis(0.0).build()
}
