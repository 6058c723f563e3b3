//! The solver: setup once per mesh (DOF numbering, sparsity pattern, symbolic Cholesky), then Newton
//! solves that can be repeated with new sources and a warm start.
//!
//! Newton–Raphson with line search (Dennis & Schnabel, Numerical Methods for Unconstrained
//! Optimization and Nonlinear Equations, §6.3):
//!
//! 1. assemble the residual `R(A)` and the exact Jacobian `K(A)` on the free nodes;
//! 2. stop when `‖R‖₂ <= rtol · s`, where the scale `s = ‖F‖₂ + ‖R(A_D)‖₂` is the norm of the source
//!    load vector plus that of the residual of the Dirichlet lifting `A_D` (interior zero) evaluated
//!    in the *linear* (initial-reluctivity) state — both independent of the iterate;
//! 3. factorise `K` (numeric Cholesky on the stored symbolic analysis) and solve `K δ = −R`;
//! 4. line search on the energy `W(A)` whose gradient is `R` (see [`crate::assembly`]): `W` is convex
//!    for a monotone B-H curve, so along the Newton direction `g(α) = δ · R(A + αδ) = dW/dα` is
//!    increasing, with `g(0) = −δᵀKδ < 0`. The full step is accepted when `g(1) <= 0` (W decreases on
//!    the whole step) or `|g(1)| <= 0.3 |g(0)|`; otherwise the root of `g` in `(0, 1)` is bracketed
//!    and approached until `|g(α)| <= 0.3 |g(0)|` (an approximate exact line search; steps with
//!    `g(α) < 0` lower W on all of `[0, α]`). Each trial is a Newton step on `g` itself,
//!    `α ← α − g(α)/g'(α)` with `g'(α) = δᵀ K(A + αδ) δ` (one product with the Jacobian that the
//!    trial assembled anyway), kept when it falls inside the bracket; otherwise Illinois false
//!    position (or bisection while the bracket is open on the right) — a safeguarded Newton
//!    iteration (Dennis & Schnabel §6.3.2; Press et al., Numerical Recipes, `rtsafe`). Only
//!    residuals and Jacobians are needed, no energy values. This is what makes saturated problems
//!    converge from `A = 0`, where the first Newton step (with the initial permeability of the
//!    iron) overshoots by orders of magnitude; `g` is then flat up to the onset of saturation and
//!    steep beyond it, so false position alone creeps in from the left (five extra assemblies on
//!    the first step of the saturating benchmark) where Newton from the overshoot side lands near
//!    the root at once.
//!
//! Tail phase (inexact Newton–Krylov, Eisenstat & Walker, SIAM J. Sci. Comput. 17(1) 1996, 16–32):
//! once a full Newton step has cut the residual at least tenfold (`‖R_k‖ <= 0.1 ‖R_{k−1}‖`, the
//! quadratic phase has begun), the Jacobian changes little between iterations, so the new system
//! `K_k δ = −R_k` is first solved by conjugate gradients preconditioned with the *previous* Cholesky
//! factor (rounded to single precision, `SparseCholesky::precondition_in_place`: the preconditioner
//! stays symmetric positive definite and its triangular solves, bound by reading the factor, take
//! half the memory traffic), to the forcing tolerance `‖K_k δ + R_k‖ <= η_k ‖R_k‖`,
//! `η_k = min(0.1, max(0.9 (‖R_k‖/‖R_{k−1}‖)², 0.5 rtol s / ‖R_k‖))` (Eisenstat–Walker choice 2,
//! which keeps the local convergence superlinear, floored where a more accurate step could not
//! change the outcome of the stopping test). If CG has not reached `η_k` within
//! [`TAIL_CG_MAX_ITERATIONS`] iterations, the Jacobian is factorised and the step solved exactly as
//! before. The CG step starts from 0, so it minimises the quadratic model on a Krylov space and is a
//! descent direction (`δ·R = −δᵀK_kδ < 0` at every CG iterate): the line search and its guarantee
//! are unchanged, and so is the stopping rule (always evaluated on the true residual).
//!
//! A step that cannot be found (40 trials), a non-finite residual, a failed factorisation or the
//! iteration limit gives [`MagneticsError::NotConverged`] with the whole residual history.
//!
//! Linear problems converge in one iteration. The accepted trial point's Jacobian is the next
//! iteration's, so each Newton iteration costs one parallel assembly, one numeric factorisation and
//! one triangular solve (plus one assembly per rejected line-search step).

use std::sync::Arc;
use std::time::Instant;

use mrbrake_fem::cholesky::SparseCholesky;
use mrbrake_fem::dofs::{DofMap, ElementOrder};
use mrbrake_fem::mesh::Mesh;
use mrbrake_fem::ordering::nested_dissection;
use mrbrake_fem::pattern::{CONSTRAINED, SymmetricPattern};
use mrbrake_fem::quadrature::{TrianglePoint, gauss_legendre_unit, triangle_rule};
use serde::Serialize;

use crate::MagneticsError;
use crate::assembly::{
    ElementData, assemble_elements, by_order, linear_jacobians, pairs, scatter_residual,
};
use crate::field::Solution;
use crate::material::{MU_0, MagneticMaterial};
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

/// Line-search acceptance: `|g(α)| <= LINE_SEARCH_SLOPE |g(0)|` (see the module docs).
const LINE_SEARCH_SLOPE: f64 = 0.3;

/// Largest number of conjugate-gradient iterations (each costs one pair of single-precision
/// triangular solves, about a tenth of a numeric factorisation) tried with the previous factor
/// before refactorising.
pub const TAIL_CG_MAX_ITERATIONS: usize = 4;

/// Residual reduction of a full Newton step that marks the start of the tail phase (module docs).
const TAIL_PHASE_REDUCTION: f64 = 0.1;

/// One Newton iteration in the history.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct NewtonStep {
    /// Residual norm `‖R‖₂` before the step (A·m, i.e. the units of the weak form without 2π).
    pub residual: f64,
    /// Residual relative to the scale `s` of the stopping rule.
    pub relative_residual: f64,
    /// Accepted line-search factor α.
    pub step_length: f64,
    /// `‖α δ‖∞ / ‖A‖∞` after the step.
    pub relative_update: f64,
    /// Conjugate-gradient iterations that gave the step with the previous factor (tail phase), or 0
    /// when the Jacobian was factorised and the step solved directly.
    pub cg_iterations: usize,
}

/// Timings of one solve (seconds).
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize)]
pub struct SolveTimings {
    /// Assembly of residuals and Jacobians.
    pub assemble_s: f64,
    /// Numeric Cholesky factorisations.
    pub factor_s: f64,
    /// Triangular solves.
    pub solve_s: f64,
    /// Whole Newton loop.
    pub total_s: f64,
}

/// Outcome of the Newton iterations.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct NewtonReport {
    /// Number of Newton steps (linear systems solved, directly or by preconditioned CG).
    pub iterations: usize,
    /// Number of numeric Cholesky factorisations (at most `iterations`).
    pub factorizations: usize,
    /// True when the stopping rule was met.
    pub converged: bool,
    /// Residual scale `s` of the stopping rule.
    pub residual_scale: f64,
    /// Final relative residual.
    pub final_relative_residual: f64,
    /// History, one entry per iteration.
    pub history: Vec<NewtonStep>,
    /// Time split.
    pub timings: SolveTimings,
}

/// A reusable solver for one mesh and one set of materials and boundary conditions.
#[derive(Debug)]
pub struct Solver {
    pub(crate) problem: Problem,
    pub(crate) options: SolverOptions,
    pub(crate) rule: Vec<TrianglePoint>,
    pub(crate) materials: Vec<MagneticMaterial>,
    pub(crate) data: ElementData,
    pub(crate) region_index: Vec<u32>,
    pub(crate) region_area: Vec<f64>,
    /// Global DOF numbering (vertices, then edges for P2).
    pub(crate) dofs: DofMap,
    /// Free-DOF index of each global DOF, or CONSTRAINED.
    pub(crate) dof: Vec<usize>,
    /// Prescribed values (used at constrained DOFs).
    pub(crate) fixed_values: Vec<f64>,
    pub(crate) n_free: usize,
    pub(crate) pattern: SymmetricPattern,
    pub(crate) cholesky: SparseCholesky,
    /// Open-boundary contributions (constant).
    pub(crate) open_terms: OpenTerms,
    pub(crate) any_nonlinear: bool,
    pub(crate) symbolic_s: f64,
    /// Point-location and recovery tables, built on the first point query.
    pub(crate) queries: crate::field::QueryCache,
    element_residual: Vec<f64>,
    element_jacobian: Vec<f64>,
    values: Vec<f64>,
    /// Jacobian of the linear-material elements plus the open-boundary terms: constant, so it is
    /// assembled once and each Newton Jacobian starts from a copy of it.
    linear_values: Vec<f64>,
    /// Triangles with a non-linear material (the only element Jacobians assembled per iteration).
    nonlinear_triangles: Vec<usize>,
}

impl Solver {
    /// Checks the problem and does the per-mesh work: DOF numbering, pattern, symbolic factorisation.
    pub fn new(problem: Problem, options: SolverOptions) -> Result<Self, MagneticsError> {
        let mesh = problem.mesh.clone();
        mesh.validate()?;
        let mut sorted_tags: Vec<u32> = problem.regions.iter().map(|r| r.tag).collect();
        sorted_tags.sort_unstable();
        if let Some(w) = sorted_tags.windows(2).find(|w| w[0] == w[1]) {
            return Err(MagneticsError::Input(format!("region {} is defined twice", w[0])));
        }
        let mesh_tags = mesh.region_tags();
        for tag in &mesh_tags {
            if problem.region(*tag).is_none() {
                return Err(MagneticsError::Input(format!(
                    "mesh region (physical surface) {tag} has no material: add a region with physical = {tag}"
                )));
            }
        }
        let edge_tags = mesh.boundary_tags();
        for region in &problem.regions {
            if mesh_tags.binary_search(&region.tag).is_err() {
                return Err(MagneticsError::Input(format!(
                    "region physical = {} is not a surface of the mesh (mesh surfaces: {mesh_tags:?})",
                    region.tag
                )));
            }
            if let MagneticMaterial::Linear { mu_r } = region.material
                && !(mu_r.is_finite() && mu_r > 0.0)
            {
                return Err(MagneticsError::Input(format!(
                    "region {}: mu_r = {mu_r} must be finite and > 0",
                    region.tag
                )));
            }
        }
        for boundary in &problem.boundaries {
            if edge_tags.binary_search(&boundary.tag).is_err() {
                return Err(MagneticsError::Input(format!(
                    "boundary physical = {} is not a curve of the mesh (mesh curves: {edge_tags:?})",
                    boundary.tag
                )));
            }
        }
        let region_index: Vec<u32> = mesh
            .triangle_tags
            .iter()
            .map(|t| {
                problem
                    .regions
                    .iter()
                    .position(|r| r.tag == *t)
                    .expect("every mesh tag has a region (checked)") as u32
            })
            .collect();
        let mut region_area = vec![0.0; problem.regions.len()];
        for (t, &ri) in region_index.iter().enumerate() {
            region_area[ri as usize] += mesh.signed_area(t);
        }
        let materials: Vec<MagneticMaterial> =
            problem.regions.iter().map(|r| r.material.clone()).collect();
        let any_nonlinear = materials.iter().any(MagneticMaterial::is_nonlinear);

        // Constrained DOFs: the axis, Dirichlet edges (vertices and, for P2, midpoints), nodes not
        // in any triangle.
        let dofs = DofMap::new(mesh.clone(), options.order);
        let n = dofs.len();
        let coordinates = dofs.coordinates();
        let mut constrained = vec![true; n];
        for &d in dofs.element_dofs() {
            constrained[d] = false;
        }
        let mut fixed_values = vec![0.0; n];
        let axis = dofs.axis_dofs();
        for &d in &axis {
            constrained[d] = true;
        }
        for boundary in &problem.boundaries {
            match &boundary.condition {
                BoundaryCondition::Dirichlet => {
                    for d in dofs.boundary_dofs(boundary.tag) {
                        constrained[d] = true;
                    }
                }
                BoundaryCondition::Prescribed(g) => {
                    // Nodal interpolation of g: its values at the vertices and edge midpoints.
                    for d in dofs.boundary_dofs(boundary.tag) {
                        constrained[d] = true;
                        fixed_values[d] = g(coordinates[d]);
                    }
                }
                BoundaryCondition::Open { .. } => {}
            }
        }
        for &d in &axis {
            fixed_values[d] = 0.0;
        }
        let mut dof = vec![CONSTRAINED; n];
        let mut n_free = 0;
        for v in 0..n {
            if !constrained[v] {
                dof[v] = n_free;
                n_free += 1;
            }
        }
        if n_free == 0 {
            return Err(MagneticsError::Input(
                "every node is constrained: nothing to solve".into(),
            ));
        }
        let k = dofs.dofs_per_triangle();
        let element_dofs: Vec<usize> = dofs.element_dofs().iter().map(|&d| dof[d]).collect();
        let pattern = SymmetricPattern::new(n_free, k, &element_dofs);
        let open_terms = open_boundary_terms(&mesh, &problem, &dofs, &dof, &pattern)?;
        let start = Instant::now();
        // Nested dissection on the DOF coordinates: less work per numeric factorisation than AMD
        // on 2D meshes (see mrbrake_fem::ordering).
        let free_coordinates: Vec<[f64; 2]> =
            (0..n).filter(|&v| dof[v] != CONSTRAINED).map(|v| coordinates[v]).collect();
        let order = nested_dissection(&pattern, &free_coordinates);
        let cholesky = SparseCholesky::with_order(&pattern, options.threads, Some(&order))?;
        let symbolic_s = start.elapsed().as_secs_f64();
        let n_tri = mesh.triangles.len();
        let rule = triangle_rule(options.rule_degree());
        let data = by_order!(options.order, ElementData::new(&mesh, &rule, region_index.clone()));
        let mut element_jacobian = vec![0.0; pairs(k) * n_tri];
        linear_jacobians(&materials, &data, pairs(k), &mut element_jacobian);
        let mut linear_values = vec![0.0; pattern.nnz()];
        pattern.assemble(&element_jacobian, &mut linear_values);
        for &(pos, value) in &open_terms.matrix {
            linear_values[pos as usize] += value;
        }
        let nonlinear_triangles: Vec<usize> =
            (0..n_tri).filter(|&t| materials[region_index[t] as usize].is_nonlinear()).collect();
        let mut solver = Self {
            rule,
            materials,
            data,
            region_index,
            region_area,
            dofs,
            dof,
            fixed_values,
            n_free,
            element_residual: vec![0.0; k * n_tri],
            element_jacobian,
            values: vec![0.0; pattern.nnz()],
            linear_values,
            nonlinear_triangles,
            pattern,
            cholesky,
            open_terms,
            any_nonlinear,
            symbolic_s,
            queries: Default::default(),
            problem,
            options,
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

    /// Number of free unknowns.
    pub fn unknowns(&self) -> usize {
        self.n_free
    }

    /// The element order of the solver (from [`SolverOptions::order`]).
    pub fn order(&self) -> ElementOrder {
        self.options.order
    }

    /// Number of degrees of freedom, free and constrained: the length of [`Solution::a_phi`]
    /// (mesh nodes for P1; nodes then edges for P2).
    pub fn dof_count(&self) -> usize {
        self.dofs.len()
    }

    /// `[r, z]` (m) of every degree of freedom, in the order of [`Solution::a_phi`]: the mesh nodes,
    /// then (P2) the edge midpoints.
    pub fn dof_coordinates(&self) -> &[[f64; 2]] {
        self.dofs.coordinates()
    }

    /// Seconds spent in the symbolic factorisation (once per solver).
    pub fn symbolic_factorisation_s(&self) -> f64 {
        self.symbolic_s
    }

    /// Stored entries of the Cholesky factor (fill-in measure).
    pub fn factor_nnz(&self) -> usize {
        self.cholesky.factor_nnz()
    }

    /// Replaces the source of region `tag` (e.g. the next current of a sweep). The mesh, pattern and
    /// symbolic factorisation are kept.
    pub fn set_source(&mut self, tag: u32, source: Option<Source>) -> Result<(), MagneticsError> {
        let region = self.problem.regions.iter_mut().find(|r| r.tag == tag).ok_or_else(|| {
            MagneticsError::Input(format!("set_source: no region with physical = {tag}"))
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
                        return Err(MagneticsError::Input(format!(
                            "coil region {} has zero area: it needs triangles in the mesh",
                            region.tag
                        )));
                    }
                    turns * current_a / self.region_area[i]
                }
            };
            if !density[i].is_finite() {
                return Err(MagneticsError::Input(format!(
                    "region {}: source is not finite",
                    region.tag
                )));
            }
        }
        for (t, &ri) in self.region_index.iter().enumerate() {
            self.data.current_density[t] = density[ri as usize];
        }
        Ok(())
    }

    /// Assembles the residual on the free DOFs (and the Jacobian values in `self.values` when
    /// asked); `a` holds the value of every DOF.
    fn assemble(&mut self, a: &[f64], jacobian: bool, residual_free: &mut [f64]) {
        let mesh = self.problem.mesh.clone();
        by_order!(
            self.options.order,
            assemble_elements(
                &mesh,
                self.dofs.element_dofs(),
                &self.rule,
                &self.materials,
                &self.data,
                a,
                &mut self.element_residual,
                if jacobian { Some(&mut self.element_jacobian) } else { None },
            )
        );
        let (element_dofs, dof) = (self.dofs.element_dofs(), &self.dof);
        match self.options.order {
            ElementOrder::P1 => {
                scatter_residual::<3>(element_dofs, dof, &self.element_residual, residual_free)
            }
            ElementOrder::P2 => {
                scatter_residual::<6>(element_dofs, dof, &self.element_residual, residual_free)
            }
        }
        for &(i, j, value) in &self.open_terms.residual {
            let d = self.dof[i];
            if d != CONSTRAINED {
                residual_free[d] += value * a[j];
            }
        }
        if jacobian {
            self.values.copy_from_slice(&self.linear_values);
            self.pattern.add_elements(
                &self.nonlinear_triangles,
                &self.element_jacobian,
                &mut self.values,
            );
        }
    }

    /// Residual scale `s = ‖F‖ + ‖R_lin(A_D)‖` of the stopping rule (see the module docs).
    fn residual_scale(&mut self) -> f64 {
        let saved = std::mem::take(&mut self.materials);
        // Linear state: every material at its B = 0 reluctivity.
        self.materials = saved
            .iter()
            .map(|m| MagneticMaterial::Linear { mu_r: 1.0 / (MU_0 * m.nu_and_dnu_db2(0.0).0) })
            .collect();
        let mut lifting = self.fixed_values.clone();
        for (v, d) in self.dof.iter().enumerate() {
            if *d != CONSTRAINED {
                lifting[v] = 0.0;
            }
        }
        let mut residual = vec![0.0; self.n_free];
        let density = std::mem::replace(
            &mut self.data.current_density,
            vec![0.0; self.problem.mesh.triangles.len()],
        );
        self.assemble(&lifting, false, &mut residual);
        let dirichlet_norm = norm2(&residual);
        self.data.current_density = density;
        let zero = vec![0.0; lifting.len()];
        self.assemble(&zero, false, &mut residual);
        let source_norm = norm2(&residual);
        self.materials = saved;
        source_norm + dirichlet_norm
    }

    /// Solves from `A = 0` (or from `initial`, e.g. a previous solution of a sweep: warm start,
    /// one value per DOF as in [`Solution::a_phi`]). Prescribed boundary values are imposed on
    /// the start vector.
    pub fn solve(&mut self, initial: Option<&[f64]>) -> Result<Solution, MagneticsError> {
        let start = Instant::now();
        let n_dofs = self.dofs.len();
        let mut a = match initial {
            Some(init) if init.len() == n_dofs => init.to_vec(),
            Some(init) => {
                return Err(MagneticsError::Input(format!(
                    "warm start has {} values but the {} solver has {n_dofs} degrees of freedom \
                     (one per mesh node for P1; nodes then edges for P2)",
                    init.len(),
                    self.options.order
                )));
            }
            None => vec![0.0; n_dofs],
        };
        for v in 0..n_dofs {
            if self.dof[v] == CONSTRAINED {
                a[v] = self.fixed_values[v];
            }
        }
        let mut timings = SolveTimings::default();
        let t = Instant::now();
        let scale = self.residual_scale().max(f64::MIN_POSITIVE);
        let mut residual = vec![0.0; self.n_free];
        self.assemble(&a, true, &mut residual);
        timings.assemble_s += t.elapsed().as_secs_f64();
        let mut history: Vec<NewtonStep> = Vec::new();
        let rtol = self.options.residual_tolerance;
        let mut trial = a.clone();
        let mut trial_residual = vec![0.0; self.n_free];
        let mut delta = vec![0.0; self.n_free];
        let mut slope_work = vec![0.0; self.n_free];
        let mut converged = false;
        let mut iterations = 0;
        let mut factorizations = 0;
        // Residual norm before the previous step, and whether that step was a full step.
        let mut previous: Option<(f64, bool)> = None;
        let mut cg = ConjugateGradientWork::default();
        loop {
            let r_norm = norm2(&residual);
            if !r_norm.is_finite() {
                return Err(self.failure(
                    "the residual is not finite (NaN or infinite B-H value?)",
                    history,
                    scale,
                ));
            }
            if r_norm <= rtol * scale {
                converged = true;
                break;
            }
            if iterations >= self.options.max_iterations {
                break;
            }
            iterations += 1;
            // Tail phase: try CG preconditioned by the previous factor (module docs).
            let mut cg_iterations = 0;
            if let Some((previous_norm, true)) = previous
                && factorizations > 0
                && r_norm <= TAIL_PHASE_REDUCTION * previous_norm
            {
                let ratio = r_norm / previous_norm;
                let forcing = (0.9 * ratio * ratio).max(0.5 * rtol * scale / r_norm).min(0.1);
                let t = Instant::now();
                let outcome = self.stale_factor_cg(&residual, forcing, &mut delta, &mut cg)?;
                timings.solve_s += t.elapsed().as_secs_f64();
                cg_iterations = outcome.unwrap_or(0);
            }
            if cg_iterations == 0 {
                let t = Instant::now();
                if let Err(e) = self.cholesky.factorize(&self.values) {
                    return Err(self.failure(
                        &format!(
                            "{e} (Jacobian not positive definite: is a B-H curve non-monotone?)"
                        ),
                        history,
                        scale,
                    ));
                }
                factorizations += 1;
                timings.factor_s += t.elapsed().as_secs_f64();
                let t = Instant::now();
                for (d, r) in delta.iter_mut().zip(&residual) {
                    *d = -r;
                }
                self.cholesky.solve_in_place(&mut delta)?;
                timings.solve_s += t.elapsed().as_secs_f64();
            }

            // Line search on the convex energy (module docs): g(α) = δ·R(A + αδ) = dW/dα is
            // increasing in α with g(0) = −δᵀKδ < 0. The full step is tried first.
            let g0: f64 = delta.iter().zip(&residual).map(|(d, r)| d * r).sum();
            let mut alpha = 1.0;
            let mut accepted = false;
            let (mut lo, mut g_lo) = (0.0, g0);
            let (mut hi, mut g_hi) = (1.0, f64::INFINITY);
            let mut last_moved = 0i8;
            for trial_count in 0..40 {
                for v in 0..n_dofs {
                    let d = self.dof[v];
                    trial[v] = if d == CONSTRAINED { a[v] } else { a[v] + alpha * delta[d] };
                }
                let t = Instant::now();
                self.assemble(&trial, true, &mut trial_residual);
                timings.assemble_s += t.elapsed().as_secs_f64();
                let g: f64 = delta.iter().zip(&trial_residual).map(|(d, r)| d * r).sum();
                if g.is_finite()
                    && (g.abs() <= LINE_SEARCH_SLOPE * g0.abs() || (trial_count == 0 && g <= 0.0))
                {
                    accepted = true;
                    break;
                }
                // Slope g'(α) = δᵀ K(A + αδ) δ with the Jacobian this trial assembled.
                self.pattern.symmetric_mul(&self.values, &delta, &mut slope_work);
                let slope: f64 = delta.iter().zip(&slope_work).map(|(d, k)| d * k).sum();
                let newton_alpha = alpha - g / slope;
                if !g.is_finite() || g > 0.0 {
                    hi = alpha;
                    g_hi = if g.is_finite() { g } else { f64::INFINITY };
                    if last_moved == 1 {
                        g_lo *= 0.5; // Illinois: the same end moved twice, halve the other end's weight
                    }
                    last_moved = 1;
                } else {
                    lo = alpha;
                    g_lo = g;
                    if last_moved == -1 {
                        g_hi *= 0.5;
                    }
                    last_moved = -1;
                }
                // Newton on g when it stays inside the bracket [lo, hi], else false position
                // (bisection while the right end is unbounded); the trial is kept off the ends by
                // 1 % of the bracket so that the bracket always shrinks.
                let margin = 0.01 * (hi - lo);
                alpha = if slope > 0.0 && newton_alpha > lo + margin && newton_alpha < hi - margin {
                    newton_alpha
                } else if g_hi.is_finite() {
                    lo - g_lo * (hi - lo) / (g_hi - g_lo)
                } else {
                    0.5 * (lo + hi)
                };
                alpha = alpha.clamp(lo + margin, hi - margin);
            }
            let a_max = a.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
            let d_max = delta.iter().fold(0.0_f64, |m, x| m.max(x.abs())) * alpha;
            history.push(NewtonStep {
                residual: r_norm,
                relative_residual: r_norm / scale,
                step_length: if accepted { alpha } else { 0.0 },
                relative_update: d_max / a_max.max(f64::MIN_POSITIVE),
                cg_iterations,
            });
            if !accepted {
                return Err(self.failure(
                    "the line search found no step lowering the energy",
                    history,
                    scale,
                ));
            }
            previous = Some((r_norm, trial_is_full_step(alpha)));
            std::mem::swap(&mut a, &mut trial);
            std::mem::swap(&mut residual, &mut trial_residual);
            // With only linear materials the first solve is exact up to the round-off of the direct
            // solver; accept it unless that round-off is abnormal (ill-conditioning).
            if !self.any_nonlinear && norm2(&residual) <= 1e-6 * scale {
                converged = true;
                break;
            }
        }
        let final_relative = norm2(&residual) / scale;
        timings.total_s = start.elapsed().as_secs_f64();
        let report = NewtonReport {
            iterations,
            factorizations,
            converged,
            residual_scale: scale,
            final_relative_residual: final_relative,
            history: history.clone(),
            timings,
        };
        if !converged {
            return Err(MagneticsError::NotConverged {
                reason: format!(
                    "no convergence in {} Newton iterations",
                    self.options.max_iterations
                ),
                history,
                residual_scale: scale,
            });
        }
        Ok(Solution::new(a, self.dofs.n_vertices(), report))
    }

    /// Preconditioned conjugate gradients on `K δ = −R` (`K` the current Jacobian in `self.values`,
    /// the preconditioner the Cholesky factor of an earlier Jacobian rounded to single precision),
    /// from `δ = 0`, until
    /// `‖K δ + R‖ <= forcing ‖R‖`. Returns the iteration count, or `None` (and `delta` undefined)
    /// when [`TAIL_CG_MAX_ITERATIONS`] did not suffice or the curvature `pᵀKp` was not positive.
    fn stale_factor_cg(
        &mut self,
        residual: &[f64],
        forcing: f64,
        delta: &mut [f64],
        work: &mut ConjugateGradientWork,
    ) -> Result<Option<usize>, MagneticsError> {
        let n = residual.len();
        work.resize(n);
        let ConjugateGradientWork { r, z, p, kp } = work;
        delta.iter_mut().for_each(|d| *d = 0.0);
        for (ri, res) in r.iter_mut().zip(residual) {
            *ri = -res;
        }
        let target = forcing * norm2(r);
        z.copy_from_slice(r);
        self.cholesky.precondition_in_place(z)?;
        p.copy_from_slice(z);
        let mut rz = dot(r, z);
        for iteration in 1..=TAIL_CG_MAX_ITERATIONS {
            self.pattern.symmetric_mul(&self.values, p, kp);
            let curvature = dot(p, kp);
            if !(curvature > 0.0 && curvature.is_finite()) {
                return Ok(None);
            }
            let step = rz / curvature;
            for i in 0..n {
                delta[i] += step * p[i];
                r[i] -= step * kp[i];
            }
            if norm2(r) <= target {
                return Ok(Some(iteration));
            }
            if iteration == TAIL_CG_MAX_ITERATIONS {
                break;
            }
            z.copy_from_slice(r);
            self.cholesky.precondition_in_place(z)?;
            let rz_next = dot(r, z);
            let beta = rz_next / rz;
            rz = rz_next;
            for i in 0..n {
                p[i] = z[i] + beta * p[i];
            }
        }
        Ok(None)
    }

    fn failure(&self, reason: &str, history: Vec<NewtonStep>, scale: f64) -> MagneticsError {
        MagneticsError::NotConverged { reason: reason.to_string(), history, residual_scale: scale }
    }

    /// Incremental inductance `dλ/dI` (H) of the coil region `tag` at the solution: one extra
    /// factorisation of the Jacobian at `solution` and one solve `K dA/dI = ∂F/∂I`, then
    /// `dλ/dI = (N/S) ∫ 2π r dA/dI dS` (the small-signal inductance seen by the current controller).
    pub fn incremental_inductance(
        &mut self,
        solution: &Solution,
        tag: u32,
    ) -> Result<f64, MagneticsError> {
        let ri = self
            .problem
            .regions
            .iter()
            .position(|r| r.tag == tag)
            .ok_or_else(|| MagneticsError::Input(format!("no region with physical = {tag}")))?;
        let Some(Source::Coil { turns, .. }) = self.problem.regions[ri].source else {
            return Err(MagneticsError::Input(format!(
                "region {tag} is not a coil (turns × current)"
            )));
        };
        let mut residual = vec![0.0; self.n_free];
        self.assemble(solution.a_phi(), true, &mut residual);
        self.cholesky.factorize(&self.values)?;
        // ∂F_i/∂I = (N/S) ∫_coil φ_i r dS = (N/S) Σ_elements f_i (the unit loads).
        let coil_density = turns / self.region_area[ri];
        let mut rhs = vec![0.0; self.n_free];
        let k = self.dofs.dofs_per_triangle();
        for (t, dofs) in self.dofs.element_dofs().chunks_exact(k).enumerate() {
            if self.region_index[t] as usize != ri {
                continue;
            }
            for (i, &global) in dofs.iter().enumerate() {
                let d = self.dof[global];
                if d != CONSTRAINED {
                    rhs[d] += coil_density * self.data.unit_load[k * t + i];
                }
            }
        }
        self.cholesky.solve_in_place(&mut rhs)?;
        let mut da = vec![0.0; self.dofs.len()];
        for v in 0..da.len() {
            if self.dof[v] != CONSTRAINED {
                da[v] = rhs[self.dof[v]];
            }
        }
        Ok(crate::field::coil_flux(self, &da, ri, turns))
    }
}

fn norm2(v: &[f64]) -> f64 {
    v.iter().map(|x| x * x).sum::<f64>().sqrt()
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// True when the accepted line-search factor is the full Newton step.
fn trial_is_full_step(alpha: f64) -> bool {
    (alpha - 1.0).abs() <= f64::EPSILON
}

/// Work vectors of [`Solver::stale_factor_cg`], kept between iterations.
#[derive(Debug, Default)]
struct ConjugateGradientWork {
    r: Vec<f64>,
    z: Vec<f64>,
    p: Vec<f64>,
    kp: Vec<f64>,
}

impl ConjugateGradientWork {
    fn resize(&mut self, n: usize) {
        for v in [&mut self.r, &mut self.z, &mut self.p, &mut self.kp] {
            v.resize(n, 0.0);
        }
    }
}

/// Open-boundary (asymptotic) terms `ν0/R ∫_edge φ_a φ_b r dl` over the DOFs of each edge: its two
/// vertices (P1: `φ = 1 − t, t` along the edge, 2-point Gauss, exact for the cubic integrand), plus
/// the midpoint for P2 (`φ = (1 − t)(1 − 2t), t(2t − 1), 4t(1 − t)`, 3-point Gauss, exact for the
/// quintic integrand). Residual couplings `(i, j, m_ij)` in both orders (global DOFs), and matrix
/// entries `(position, m_ij)` once per upper-triangle pair of free DOFs.
fn open_boundary_terms(
    mesh: &Mesh,
    problem: &Problem,
    dofs: &DofMap,
    dof: &[usize],
    pattern: &SymmetricPattern,
) -> Result<OpenTerms, MagneticsError> {
    let mut terms = OpenTerms::default();
    let quadratic = dofs.order() == ElementOrder::P2;
    let (x, w) = gauss_legendre_unit(if quadratic { 3 } else { 2 });
    for boundary in &problem.boundaries {
        let BoundaryCondition::Open { centre_z_m } = boundary.condition else { continue };
        let radius = |p: [f64; 2]| p[0].hypot(p[1] - centre_z_m);
        let edges: Vec<[usize; 2]> = mesh
            .edges
            .iter()
            .zip(&mesh.edge_tags)
            .filter(|(_, t)| **t == boundary.tag)
            .map(|(e, _)| *e)
            .collect();
        let radii: Vec<f64> = edges.iter().flat_map(|e| e.map(|v| radius(mesh.nodes[v]))).collect();
        let r_min = radii.iter().cloned().fold(f64::INFINITY, f64::min);
        let r_max = radii.iter().cloned().fold(0.0, f64::max);
        if r_min.is_nan() || r_min <= 0.0 || (r_max - r_min) > 0.02 * r_max {
            return Err(MagneticsError::Input(format!(
                "open boundary {}: its nodes must lie on a circle centred on the axis at z = {centre_z_m} m \
                 (distances range from {r_min:.4e} to {r_max:.4e} m)",
                boundary.tag
            )));
        }
        for e in edges {
            let (pa, pb) = (mesh.nodes[e[0]], mesh.nodes[e[1]]);
            let length = (pb[0] - pa[0]).hypot(pb[1] - pa[1]);
            let big_r = 0.5 * (radius(pa) + radius(pb));
            let mut e = vec![e[0], e[1]];
            if quadratic {
                e.push(dofs.edge_dof(e[0], e[1]).ok_or_else(|| {
                    MagneticsError::Input(format!(
                        "open boundary {}: edge ({}, {}) is not the side of a triangle",
                        boundary.tag, e[0], e[1]
                    ))
                })?);
            }
            let k = e.len();
            let mut m = [[0.0; 3]; 3];
            for (xq, wq) in x.iter().zip(&w) {
                let t = *xq;
                let phi = if quadratic {
                    [(1.0 - t) * (1.0 - 2.0 * t), t * (2.0 * t - 1.0), 4.0 * t * (1.0 - t)]
                } else {
                    [1.0 - t, t, 0.0]
                };
                let r = pa[0] * (1.0 - t) + pb[0] * t;
                for i in 0..k {
                    for j in 0..k {
                        m[i][j] += wq * length * r * phi[i] * phi[j] / (MU_0 * big_r);
                    }
                }
            }
            for i in 0..k {
                for j in 0..k {
                    terms.residual.push((e[i], e[j], m[i][j]));
                    let (di, dj) = (dof[e[i]], dof[e[j]]);
                    if di != CONSTRAINED && dj != CONSTRAINED && i <= j {
                        let (row, col) = if di <= dj { (di, dj) } else { (dj, di) };
                        let rows = &pattern.row_idx[pattern.col_ptr[col]..pattern.col_ptr[col + 1]];
                        let k = rows.binary_search(&row).map_err(|_| {
                            MagneticsError::Numerical(
                                "open-boundary edge is not an edge of a triangle".into(),
                            )
                        })?;
                        terms.matrix.push(((pattern.col_ptr[col] + k) as u32, m[i][j]));
                    }
                }
            }
        }
    }
    Ok(terms)
}

/// Constant contributions of the open boundary.
#[derive(Debug, Clone, Default)]
pub(crate) struct OpenTerms {
    /// `(i, j, m_ij)` DOF couplings for the residual, both orders.
    pub residual: Vec<(usize, usize, f64)>,
    /// `(value position, m_ij)` for the Jacobian (upper triangle, once per pair).
    pub matrix: Vec<(u32, f64)>,
}
