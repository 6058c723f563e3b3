//! Steady and transient heat solves on the FEM core.
//!
//! Set-up once per problem: the basis (P1 or P2, axisymmetric weight), the constraints (fixed
//! temperatures; the axis is a natural symmetry boundary for a scalar), the assembly prepared with
//! the [`HeatForm`], the boundary fluxes (convection and radiation) as the core's
//! [`EdgeFlux`], and the Newton solver (nested-dissection order and symbolic Cholesky once).
//!
//! - **Steady**: `R(T) = 0` by Newton; without radiation the system is linear and one step solves
//!   it (the Joule coupling is affine in `T`).
//! - **Transient** on the core's time integrator (`mrbrake_fem::workflow::time`, see
//!   [`crate::transient`]): implicit Euler or BDF2, fixed or adaptive steps; the capacity matrix is
//!   the integrator's mass. Without radiation every step is linear with one matrix per step size
//!   (factorised once for a fixed-step run, twice with BDF2's Euler start) and costs one product
//!   with the capacity matrix and one pair of triangular solves; with radiation each step is a
//!   Newton solve that starts from the previous step's factor as a CG preconditioner.

use std::sync::Arc;

use mrbrake_fem::discretisation::basis::{Basis, Weighting};
use mrbrake_fem::discretisation::dofs::ElementOrder;
use mrbrake_fem::mesh::locate::PointLocator;
use mrbrake_fem::workflow::assemble::{Assembly, element_matrices};
use mrbrake_fem::workflow::boundary::EdgeFlux;
use mrbrake_fem::workflow::constraints::Constraints;
use mrbrake_fem::workflow::newton::{
    NewtonFailure, NewtonOptions, NewtonReport, NewtonSolver, NonlinearSystem, norm2,
};
use mrbrake_fem::workflow::time::TimeError;

use crate::form::{Coefficients, HeatForm};
use crate::problem::{BoundaryCondition, HeatProblem};
use crate::{HeatError, STEFAN_BOLTZMANN};
use mrbrake_error::FieldError;

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
    /// True when a boundary radiates (the only non-linearity: Newton per step).
    pub(crate) radiation: bool,
    /// The rate `ρ` the assembly was last prepared with (`None`: steady).
    pub(crate) prepared: Option<Option<f64>>,
    /// The capacity matrix `∫ ρc φ_i φ_j r dr dz` of every element (packed upper triangles).
    pub(crate) capacity_matrices: Vec<f64>,
}

/// The system of one solve (steady, or a time step): the assembly with the form and the boundary
/// fluxes.
pub struct HeatSystem<'a> {
    pub(crate) assembly: &'a mut Assembly,
    pub(crate) form: &'a HeatForm,
    pub(crate) edges: &'a EdgeFlux,
    pub(crate) laws: &'a [(u32, FluxLaw)],
    pub(crate) linear: bool,
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
        let k = self.problem.regions.iter().position(|r| r.tag == tag).ok_or_else(|| {
            let e = FieldError::new("tag", "no region with this physical tag").with_value(tag);
            HeatError::from(e)
        })?;
        self.problem.regions[k].source = source;
        let volume = self.volumes.iter().find(|(t, _)| *t == tag).map_or(1.0, |v| v.1);
        let (q0, q1) = source.affine(volume);
        let changed_jacobian = (self.form.coefficients[k].q1 - q1).abs() > 0.0;
        self.form.coefficients[k].q0 = q0;
        self.form.coefficients[k].q1 = q1;
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
            let value = format!("h = {h_w_per_m2k} W/(m² K), T_amb = {ambient_k} K");
            let e = FieldError::new("h_w_per_m2k", format!("convection on boundary {tag}"));
            return Err(e.with_value(value).with_allowed("h >= 0, T_amb finite").into());
        }
        let boundary = self
            .problem
            .boundaries
            .iter_mut()
            .find(|b| b.tag == tag && matches!(b.condition, BoundaryCondition::Convection { .. }))
            .ok_or_else(|| {
                let e = FieldError::new("tag", "no convection boundary with this tag");
                HeatError::from(e.with_value(tag))
            })?;
        boundary.condition = BoundaryCondition::Convection { h_w_per_m2k, ambient_k };
        self.laws = flux_laws(&self.problem);
        self.prepared = None;
        Ok(())
    }

    /// A steady state needs a way out for heat: a convection (h > 0), radiation (ε > 0) or
    /// fixed-temperature boundary. With every boundary adiabatic the steady problem is singular
    /// (its matrix has the constants as null space, and with a source there is no solution at
    /// all); this is said before a solve that would only report a zero pivot (issue 33).
    fn check_heat_path(&self) -> Result<(), HeatError> {
        let way_out = self.problem.boundaries.iter().any(|b| match b.condition {
            BoundaryCondition::Convection { h_w_per_m2k, .. } => h_w_per_m2k > 0.0,
            BoundaryCondition::Radiation { emissivity, .. } => emissivity > 0.0,
            BoundaryCondition::Temperature { .. } => true,
            BoundaryCondition::Adiabatic => false,
        });
        if way_out {
            return Ok(());
        }
        let e = FieldError::new(
            "boundary",
            "no heat leaves the problem: every boundary is adiabatic (or has h = 0, emissivity = \
             0), so there is no steady temperature; give a convection, radiation or \
             fixed-temperature boundary, or solve a [transient]",
        )
        .with_allowed("at least one boundary with h > 0, emissivity > 0 or a fixed T_C");
        Err(e.into())
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

    /// A Jacobian that is not positive definite with a positive source feedback is a thermal
    /// runaway.
    pub(crate) fn runaway_or(&self, error: HeatError) -> HeatError {
        let not_positive_definite = |e: &mrbrake_fem::workflow::newton::NewtonError| {
            matches!(e.failure, NewtonFailure::NotPositiveDefinite { .. })
        };
        let runaway = match &error {
            HeatError::NotConverged(e) | HeatError::Time(TimeError::Step { source: e, .. }) => {
                not_positive_definite(e)
            }
            HeatError::Fem(mrbrake_fem::FemError::NotPositiveDefinite { .. }) => true,
            _ => false,
        };
        if runaway && self.has_joule_feedback() {
            HeatError::Runaway(format!("the system matrix is not positive definite ({error})"))
        } else {
            error
        }
    }

    /// Prepares the assembly for the steady form when it was prepared for something else.
    fn prepare_steady(&mut self) {
        if self.prepared != Some(None) {
            self.assembly.prepare(&self.form);
            self.prepared = Some(None);
        }
    }

    /// Newton's settings (a transient's steps start from the previous step's factor: the
    /// integrator sets `reuse_factor`).
    pub(crate) fn newton_settings(&self) -> NewtonOptions {
        NewtonOptions {
            max_iterations: self.options.max_iterations,
            residual_tolerance: self.options.tolerance,
            ..NewtonOptions::default()
        }
    }

    /// Solves the steady system from `u` by Newton.
    fn newton_solve(&mut self, u: &mut Vec<f64>) -> Result<NewtonReport, HeatError> {
        let options = self.newton_settings();
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
        self.check_heat_path()?;
        self.form.capacity = None;
        self.prepare_steady();
        let mut u = match initial {
            Some(t) => t.to_vec(),
            None => self.uniform(self.reference_temperature()),
        };
        match self.newton_solve(&mut u) {
            Ok(report) => Ok((u, report)),
            Err(e) => Err(self.runaway_or(e)),
        }
    }
}
