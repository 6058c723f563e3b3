//! Magnetodynamics: eddy currents in solid conductors and coils driven by a current or a voltage,
//! in time (transient) and in frequency (time-harmonic, and small-signal about a saturated DC
//! operating point), on the magnetostatic solver's set-up.
//!
//! Magnetoquasistatics in `A_phi(r, z, t)` (e.g. Meunier (ed.), *The Finite Element Method for
//! Electromagnetic Modeling*, ISTE/Wiley 2008, ch. 5; Dular et al., IEEE Trans. Magn. 34(5) 1998
//! for the axisymmetric eddy-current formulation):
//!
//! `curl(ν curl A) + σ ∂A/∂t = Σ_k (N_k i_k / S_k) χ_k`,
//!
//! with `σ` the electrical conductivity of solid regions (an axisymmetric solid ring carries the
//! induced azimuthal current density `−σ ∂A/∂t`; a closed ring needs no net-current constraint)
//! and stranded coils `k` (no eddy currents in the winding: the current density `N i / S` is
//! uniform over the coil section `S`, `χ_k` its indicator). Galerkin with the r-weight (2π dropped
//! from both sides, as in [`crate::form`]) gives
//!
//! `R(a) = K(a) a + M_σ ȧ − Σ_k i_k c_k = 0`,  `M_σ,ij = ∫ σ φ_i φ_j r dr dz`,
//! `c_k,i = (N_k/S_k) ∫_{S_k} φ_i r dr dz`,
//!
//! and the flux linkage of coil `k` is `λ_k = 2π c_k · a` (the flux `2π r A` through the circle
//! of radius `r`, averaged over the section and multiplied by the turns). A coil is driven either
//! by a prescribed current `i_k(t)` or by a voltage source with a series resistance `R_k` (the
//! winding's own plus the source's), the circuit equation `v_k(t) = R_k i_k + dλ_k/dt` solved with
//! the field (see [`transient`]). Time-harmonic solves use the time factor `exp(+jωt)`, so
//! `∂/∂t → jω` and `(K + jω M_σ) â = Σ_k Î_k c_k` (see [`harmonic`]).
//!
//! Module map:
//! - [`Dynamics`]: the set-up shared by both (the static [`Solver`], conductivities per element,
//!   the element mass matrices, the coil vectors `c_k`), with flux linkage and eddy loss;
//! - [`transient`]: transients on the core's time integrator (implicit Euler and BDF2, fixed or
//!   adaptive steps, Newton per step), recorded per level; `step` makes [`Dynamics`] the
//!   integrator's physics (`mrbrake_fem::workflow::time::TransientProblem`: the eddy-current mass,
//!   the coils as step loads and their flux linkages as auxiliary states);
//! - [`harmonic`]: complex solves (linear, or linearised about a DC bias);
//! - [`waveform`]: the drive waveforms.

pub(crate) mod form;
pub mod harmonic;
mod step;
pub mod transient;
pub mod waveform;

use mrbrake_fem::by_order;
use mrbrake_fem::discretisation::element::TriangleBasis;
use mrbrake_fem::workflow::assemble::{
    element_matrices, element_matrix_product, packed_len, unpack_symmetric,
};

use crate::MagneticsError;
use crate::field::Solution;
use crate::problem::Source;
use crate::solver::Solver;
use mrbrake_error::FieldError;
pub use waveform::Waveform;

const TWO_PI: f64 = 2.0 * std::f64::consts::PI;

/// Electrical conductivity of a region (solid conductor).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Conductor {
    /// Physical tag of the region.
    pub tag: u32,
    /// Conductivity σ (S/m), finite and >= 0.
    pub conductivity_s_per_m: f64,
}

/// How a coil is driven.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Drive {
    /// Prescribed current `i(t) = amplitude_a · w(t)`.
    Current {
        /// Amplitude (A).
        amplitude_a: f64,
    },
    /// Voltage source `v(t) = amplitude_v · w(t)` in series with `series_resistance_ohm`.
    Voltage {
        /// Amplitude (V).
        amplitude_v: f64,
        /// Total series resistance of the circuit (Ω), > 0.
        series_resistance_ohm: f64,
    },
}

/// A stranded coil (a region of the problem) and its drive.
#[derive(Debug, Clone, PartialEq)]
pub struct Coil {
    /// Physical tag of the coil region.
    pub tag: u32,
    /// Number of turns.
    pub turns: f64,
    /// The drive.
    pub drive: Drive,
    /// The waveform scaling the drive's amplitude.
    pub waveform: Waveform,
}

impl Coil {
    /// The DC current (A) of the drive at time `t` (`v(t)/R` for a voltage drive).
    pub fn dc_current_a(&self, t: f64) -> f64 {
        let w = self.waveform.value(t);
        match self.drive {
            Drive::Current { amplitude_a } => amplitude_a * w,
            Drive::Voltage { amplitude_v, series_resistance_ohm } => {
                amplitude_v * w / series_resistance_ohm
            }
        }
    }
}

/// A coil with its vectors `c` (every DOF, and the free DOFs).
#[derive(Debug, Clone)]
pub(crate) struct CoilData {
    pub coil: Coil,
    pub full: Vec<f64>,
    pub free: Vec<f64>,
}

/// The shared set-up of transient and harmonic solves on one static [`Solver`].
#[derive(Debug)]
pub struct Dynamics {
    pub(crate) solver: Solver,
    /// σ (S/m) of every element.
    pub(crate) sigma: Vec<f64>,
    /// `∫ φ_i φ_j r dr dz` of every element (packed upper triangles; zero-σ elements included).
    pub(crate) mass: Vec<f64>,
    pub(crate) coils: Vec<CoilData>,
}

impl Dynamics {
    /// The dynamics of `solver`'s problem with the `conductors` and the driven `coils`. The coil
    /// regions' static sources are replaced by the drives (they act through the coil vectors);
    /// a coil region cannot be a conductor (stranded winding).
    pub fn new(
        mut solver: Solver,
        conductors: &[Conductor],
        coils: Vec<Coil>,
    ) -> Result<Self, MagneticsError> {
        let region_sigma = region_conductivities(&solver, conductors, &coils)?;
        let sigma: Vec<f64> =
            solver.form.element_region.iter().map(|&ri| region_sigma[ri as usize]).collect();
        let mass = by_order!(solver.order(), mass_matrices(solver.basis()));
        let mut data = Vec::with_capacity(coils.len());
        for coil in coils {
            check_coil(&coil)?;
            solver.set_source(coil.tag, None)?;
            let region = region_index(&solver, coil.tag)?;
            let (full, free) = coil_vectors(&solver, region, coil.turns)?;
            data.push(CoilData { coil, full, free });
        }
        Ok(Self { solver, sigma, mass, coils: data })
    }

    /// The static solver underneath (mesh, basis, post-processing of a potential).
    pub fn solver(&self) -> &Solver {
        &self.solver
    }

    /// The driven coils.
    pub fn coils(&self) -> impl Iterator<Item = &Coil> {
        self.coils.iter().map(|c| &c.coil)
    }

    /// True when some element conducts.
    pub fn has_conductors(&self) -> bool {
        self.sigma.iter().any(|&s| s > 0.0)
    }

    /// Flux linkage `λ = 2π c · a` (Wb) of coil `k` for the DOF values `a`.
    pub fn flux_linkage(&self, k: usize, a: &[f64]) -> f64 {
        TWO_PI * dot(&self.coils[k].full, a)
    }

    /// Eddy-current loss `P = ∫ σ (∂A/∂t)² 2π r dr dz` (W) for the DOF rates `rate` (Wb/(m s)).
    pub fn eddy_loss(&self, rate: &[f64]) -> f64 {
        TWO_PI * self.mass_norm2(rate)
    }

    /// The induced azimuthal current density `J_φ = −σ ∂A/∂t` (A/m²) at the three vertices of
    /// every element (`3 × elements` values, element order; 0 in non-conducting elements), for the
    /// DOF rates `rate` (e.g. [`transient::StepView::rate`]). Per element, not per node: `σ` jumps
    /// between regions, and so does `J`.
    pub fn eddy_current_density(&self, rate: &[f64]) -> Result<Vec<f64>, MagneticsError> {
        let dofs = self.solver.basis().dofs();
        if rate.len() != self.solver.dof_count() {
            return Err(MagneticsError::field(
                "rate",
                format!(
                    "eddy current density: {} rates for {} DOFs",
                    rate.len(),
                    self.solver.dof_count()
                ),
            ));
        }
        let per_element = dofs.element_dofs().len() / self.sigma.len().max(1);
        let mut out = Vec::with_capacity(3 * self.sigma.len());
        // The first three DOFs of an element are its vertices (P1 and P2 alike).
        for (element, &sigma) in dofs.element_dofs().chunks_exact(per_element).zip(&self.sigma) {
            out.extend(element[..3].iter().map(|&d| -sigma * rate[d]));
        }
        Ok(out)
    }

    /// `y = Σ_e σ_e M_e x_e` at every DOF (the eddy-current mass matrix times `x`; conducting
    /// elements only, so its cost is the conductors' share of the mesh).
    pub(crate) fn mass_mul(&self, x: &[f64]) -> Vec<f64> {
        match self.solver.order() {
            mrbrake_fem::discretisation::dofs::ElementOrder::P1 => mass_product::<3>(self, x),
            mrbrake_fem::discretisation::dofs::ElementOrder::P2 => mass_product::<6>(self, x),
        }
    }

    /// `Σ_e σ_e x_eᵀ M_e x_e` (element order: the sum does not depend on threads).
    pub(crate) fn mass_norm2(&self, x: &[f64]) -> f64 {
        match self.solver.order() {
            mrbrake_fem::discretisation::dofs::ElementOrder::P1 => mass_quadratic::<3>(self, x),
            mrbrake_fem::discretisation::dofs::ElementOrder::P2 => mass_quadratic::<6>(self, x),
        }
    }

    /// A [`Solution`] of this solver holding the potential `a` (for point queries).
    pub fn solution(&self, a: Vec<f64>) -> Solution {
        Solution::from_potential(a, self.solver.basis().dofs().n_vertices())
    }

    /// The static solution with every coil at its DC current `currents[k]` (A); the coils'
    /// sources are reset afterwards.
    pub fn static_solution(&mut self, currents: &[f64]) -> Result<Solution, MagneticsError> {
        if currents.iter().all(|i| i.abs() < f64::MIN_POSITIVE) {
            return Ok(self.solution(vec![0.0; self.solver.dof_count()]));
        }
        for (data, &current_a) in self.coils.iter().zip(currents) {
            let source = Source::Coil { turns: data.coil.turns, current_a };
            self.solver.set_source(data.coil.tag, Some(source))?;
        }
        let solved = self.solver.solve(None);
        for data in &self.coils {
            self.solver.set_source(data.coil.tag, None)?;
        }
        solved
    }
}

fn check_coil(coil: &Coil) -> Result<(), MagneticsError> {
    coil.waveform.validate()?;
    if !(coil.turns > 0.0 && coil.turns.is_finite()) {
        let e = FieldError::out_of_range(
            format!("coil[{}].turns", coil.tag),
            coil.turns,
            "finite, > 0",
        );
        return Err(e.into());
    }
    match coil.drive {
        Drive::Current { amplitude_a } if !amplitude_a.is_finite() => {
            let e = FieldError::out_of_range(
                format!("coil[{}].current_A", coil.tag),
                amplitude_a,
                "finite",
            );
            Err(e.into())
        }
        Drive::Voltage { amplitude_v, series_resistance_ohm } => {
            if !amplitude_v.is_finite() {
                let e = FieldError::out_of_range(
                    format!("coil[{}].voltage_V", coil.tag),
                    amplitude_v,
                    "finite",
                );
                return Err(e.into());
            }
            if !(series_resistance_ohm > 0.0 && series_resistance_ohm.is_finite()) {
                let field = format!("coil[{}].series_resistance_ohm", coil.tag);
                let e = FieldError::out_of_range(field, series_resistance_ohm, "finite, > 0 Ω");
                return Err(e.into());
            }
            Ok(())
        }
        _ => Ok(()),
    }
}

fn region_index(solver: &Solver, tag: u32) -> Result<usize, MagneticsError> {
    solver
        .problem
        .regions
        .iter()
        .position(|r| r.tag == tag)
        .ok_or_else(|| MagneticsError::field("tag", format!("no region with physical = {tag}")))
}

/// σ of every region (0 unless listed), checked.
fn region_conductivities(
    solver: &Solver,
    conductors: &[Conductor],
    coils: &[Coil],
) -> Result<Vec<f64>, MagneticsError> {
    let mut sigma = vec![0.0; solver.problem.regions.len()];
    for conductor in conductors {
        let s = conductor.conductivity_s_per_m;
        if !(s >= 0.0 && s.is_finite()) {
            let field = format!("conductor[{}].conductivity_S_per_m", conductor.tag);
            return Err(FieldError::out_of_range(field, s, "finite, >= 0 S/m").into());
        }
        if s > 0.0 && coils.iter().any(|c| c.tag == conductor.tag) {
            return Err(MagneticsError::field(
                format!("conductor[{}]", conductor.tag),
                format!(
                    "region {} is a stranded coil: it cannot also be a solid conductor (set its \
                 conductivity to 0)",
                    conductor.tag
                ),
            ));
        }
        sigma[region_index(solver, conductor.tag)?] = s;
    }
    Ok(sigma)
}

/// The coil vector `c = (N/S) ∫_coil φ r` on every DOF and on the free DOFs.
fn coil_vectors(
    solver: &Solver,
    region: usize,
    turns: f64,
) -> Result<(Vec<f64>, Vec<f64>), MagneticsError> {
    let area = solver.region_area[region];
    if area <= 0.0 {
        return Err(MagneticsError::field(
            "coils",
            format!(
                "coil region {} has zero area: it needs triangles in the mesh",
                solver.problem.regions[region].tag
            ),
        ));
    }
    let density = turns / area;
    let regions = &solver.form.element_region;
    let scale = |t: usize| if regions[t] as usize == region { density } else { 0.0 };
    let free = solver.assembly.vector(&solver.form.unit_load, scale);
    let dofs = solver.basis().dofs();
    let k = dofs.dofs_per_triangle();
    let mut full = vec![0.0; dofs.len()];
    for (t, (element, load)) in
        dofs.element_dofs().chunks_exact(k).zip(solver.form.unit_load.chunks_exact(k)).enumerate()
    {
        let s = scale(t);
        for (&d, &f) in element.iter().zip(load) {
            full[d] += s * f;
        }
    }
    Ok((full, free))
}

/// `∫ φ_i φ_j r dr dz` of every element.
fn mass_matrices<E: TriangleBasis<N>, const N: usize>(
    basis: &mrbrake_fem::discretisation::basis::Basis,
) -> Vec<f64> {
    element_matrices::<E, N>(basis, |_, q, m| {
        let mut p = 0;
        for i in 0..N {
            for j in i..N {
                m[p] += q.weight * q.phi[i] * q.phi[j];
                p += 1;
            }
        }
    })
}

/// Calls `f(σ_e, element DOFs, M_e, x_e)` for every conducting element, in element order.
fn for_conductors<const N: usize>(
    dynamics: &Dynamics,
    x: &[f64],
    mut f: impl FnMut(f64, &[usize], [[f64; N]; N], [f64; N]),
) {
    let dofs = dynamics.solver.basis().dofs().element_dofs();
    for (t, element) in dofs.chunks_exact(N).enumerate() {
        let sigma = dynamics.sigma[t];
        if sigma <= 0.0 {
            continue;
        }
        let m = unpack_symmetric::<N>(&dynamics.mass[packed_len(N) * t..packed_len(N) * (t + 1)]);
        let local: [f64; N] = std::array::from_fn(|i| x[element[i]]);
        f(sigma, element, m, local);
    }
}

fn mass_product<const N: usize>(dynamics: &Dynamics, x: &[f64]) -> Vec<f64> {
    let mut y = vec![0.0; x.len()];
    let dofs = dynamics.solver.basis().dofs().element_dofs();
    element_matrix_product::<N>(dofs, &dynamics.mass, |t| dynamics.sigma[t].max(0.0), x, &mut y);
    y
}

fn mass_quadratic<const N: usize>(dynamics: &Dynamics, x: &[f64]) -> f64 {
    let mut sum = 0.0;
    for_conductors::<N>(dynamics, x, |sigma, _, m, local| {
        let mut q = 0.0;
        for i in 0..N {
            for j in 0..N {
                q += local[i] * m[i][j] * local[j];
            }
        }
        sum += sigma * q;
    });
    sum
}

pub(crate) fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}
