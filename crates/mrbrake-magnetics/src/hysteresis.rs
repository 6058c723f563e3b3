//! Magnetic hysteresis in the magnetostatic solve: the energy-based law of
//! [`mrbrake_materials::hysteresis`] with a state per quadrature point, for quasi-static solves
//! along a current history (`0 → I_max → 0 → −I_max → …`).
//!
//! # How a step is solved
//! A quasi-static step is one ordinary Newton solve of [`crate::Solver::solve`] on the same
//! assembly: within the step the law of every point of a hysteretic region is the model's B-driven
//! step map *from the committed state* ([`HysteresisState::trial`]), a function of the trial B only.
//! It is the gradient of a convex energy (the step's `∫H db` along the axis plus the quadratic
//! perpendicular term below), so the Newton Jacobian stays symmetric positive definite and the core's
//! Cholesky, line search and CG tail apply unchanged. After the step has converged,
//! [`crate::Solver::commit_hysteresis`] makes the states at the converged B the committed ones.
//! Nothing else in the solver changes; without hysteretic regions the form takes its old path.
//!
//! # The vector law at a point (A-formulation, B in the r–z plane)
//! The material model is scalar. Each point gets an **axis** `e` when it is first magnetised (the
//! direction of its first committed B); the model acts on `b = B·e`, and the perpendicular part
//! `B⊥ = B − b e` sees a reluctivity `ν⊥` frozen for the step (the secant `H/B` of the model's normal
//! curve at the committed |b|, at least its initial slope):
//!
//! `H = h(b) e + ν⊥ B⊥`,  `∂H/∂B = (dh/db) e⊗e + ν⊥ (I − e⊗e)`.
//!
//! Before its first commit a point is demagnetised and isotropic: `H = h(|B|) B/|B|` with the tangent
//! `(dh/db) e⊗e + (h/|B|)(I − e⊗e)`, `e = B/|B|` (the model's first-magnetisation curve, `h/|B| > 0`).
//! With a single coil the field at a point of the steel keeps its direction up to the sign when the
//! material is linear, and turns a little with saturation; [`HysteresisCommit::max_perpendicular_b_t`]
//! reports how much (the largest `|B⊥|`) so that a user sees when the scalar treatment is stretched. The vector
//! dry-friction rule of Henrotte, Nicolet and Hameyer (COMPEL 25(1) (2006) 71–80) is the extension for
//! rotating fields.
//!
//! # Jacobian
//! The exact derivative of the step map (`dh/db` of the trial, one-sided in the direction of the
//! step) is assembled: Newton. A chord iteration with the committed state's tangent (a fixed-point
//! fallback) was tried and dropped: on the long solenoid it did not converge where Newton takes
//! 3–6 iterations per step (the committed tangent after a reversal is far from the step's secant).
//!
//! # Energy
//! [`crate::Solver::commit_hysteresis`] returns the energy the step dissipated in the hysteretic
//! regions, `2π Σ_q w_q Σ_k κ_k |ΔJ_k|` (the model's exact per-step dissipation, Henrotte et al.
//! 2006; Bergqvist, Physica B 233 (1997) 342–347): over a closed current cycle the electrical work
//! `∮ I dλ` equals its sum (the stored energy returns), which the validation tests check.

use std::sync::Arc;
use std::sync::atomic::{AtomicU64, Ordering};

use mrbrake_fem::by_order;
use mrbrake_fem::discretisation::basis::{Basis, Element};
use mrbrake_fem::discretisation::element::TriangleBasis;
use mrbrake_fem::workflow::assemble::{MAX_PACKED_LEN, packed_len};
use mrbrake_materials::MU_0;
use mrbrake_materials::hysteresis::{HysteresisParams, HysteresisState, Response};

use crate::form::{curls, flux_density};
use crate::{MagneticsError, Solution};

/// Below this |B| (T) a point has no direction of its own: it stays demagnetised and isotropic.
pub const AXIS_MIN_B_T: f64 = 1e-9;

/// The state of one quadrature point: the model's state, its axis and the perpendicular reluctivity.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
struct PointState {
    state: HysteresisState,
    /// The unit axis `e` ([r, z]) once the point has been magnetised.
    axis: Option<[f64; 2]>,
    /// `ν⊥` for the next step, A/(m·T).
    nu_perpendicular: f64,
}

/// The hysteretic regions of a solver: per element the law (or none) and per point the state.
#[derive(Debug, Clone)]
pub(crate) struct HysteresisField {
    laws: Vec<Arc<HysteresisParams>>,
    /// Law index of every element, `u32::MAX` for an element without hysteresis.
    element_law: Vec<u32>,
    /// First point index of every element (valid where `element_law` is set).
    element_offset: Vec<u32>,
    points_per_element: usize,
    points: Vec<PointState>,
    /// The last evaluation of every point (the start of its next root search).
    last: LastEvaluations,
    /// The largest residual scale of the history since the last demagnetisation.
    largest_scale: f64,
}

/// The last evaluation of the law at every point: the flux density along its axis (or `|B|` before
/// it has one), `H` and `dH/dB` there, each an `f64` in an atomic (NaN: none yet).
///
/// Successive evaluations at a point (the Newton iterations and line-search trials of a step, then
/// its commit) differ by a small change of B, so the root search of the B-driven step map starts
/// from the first-order prediction `H + (b − b_last) dH/dB` instead of the committed state's
/// tangent ([`HysteresisState::trial_near`]: the same root, up to the model's root tolerance, in
/// fewer iterations). The elements are evaluated in parallel; each point belongs to one element, so
/// a slot is only ever written by the evaluation of its own element (relaxed ordering suffices) and
/// the results do not depend on the schedule.
#[derive(Debug, Default)]
struct LastEvaluations(Vec<[AtomicU64; 3]>);

impl LastEvaluations {
    fn new(points: usize) -> Self {
        let nan = f64::NAN.to_bits();
        Self((0..points).map(|_| [nan, nan, nan].map(AtomicU64::new)).collect())
    }

    /// Forgets every evaluation (the states changed other than by a small step).
    fn clear(&mut self) {
        for slot in &mut self.0 {
            for value in slot.iter_mut() {
                *value.get_mut() = f64::NAN.to_bits();
            }
        }
    }

    /// The start of the root search at point `k` for `b`: the first-order prediction from the last
    /// evaluation, `NaN` when there is none.
    #[inline]
    fn guess(&self, k: usize, b: f64) -> f64 {
        let [b_last, h, dh_db] =
            self.0[k].each_ref().map(|v| f64::from_bits(v.load(Ordering::Relaxed)));
        h + (b - b_last) * dh_db
    }

    #[inline]
    fn record(&self, k: usize, b: f64, h: f64, dh_db: f64) {
        for (slot, value) in self.0[k].iter().zip([b, h, dh_db]) {
            slot.store(value.to_bits(), Ordering::Relaxed);
        }
    }
}

impl Clone for LastEvaluations {
    fn clone(&self) -> Self {
        Self(
            self.0
                .iter()
                .map(|slot| slot.each_ref().map(|v| AtomicU64::new(v.load(Ordering::Relaxed))))
                .collect(),
        )
    }
}

/// What committing a converged step did.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct HysteresisCommit {
    /// Energy dissipated by the step in the hysteretic regions, J (over the full 2π ring).
    pub dissipated_j: f64,
    /// Largest `|B⊥|` over the magnetised points, T (0: every point's field along its axis).
    pub max_perpendicular_b_t: f64,
    /// Most B-driven root iterations of one point in the commit.
    pub max_point_iterations: u32,
}

/// The law of a point: `H` and the packed symmetric tangent `[T_rr, T_rz, T_zz]`.
struct PointLaw {
    h: [f64; 2],
    tangent: [f64; 3],
}

impl HysteresisField {
    /// Demagnetised states for the elements whose region index has a law in `region_laws`.
    pub(crate) fn new(
        basis: &Basis,
        element_region: &[u32],
        region_laws: &[Option<usize>],
        laws: Vec<Arc<HysteresisParams>>,
    ) -> Self {
        let points_per_element = basis.rule().len();
        let mut element_law = vec![u32::MAX; element_region.len()];
        let mut element_offset = vec![0u32; element_region.len()];
        let mut count = 0usize;
        for (t, &ri) in element_region.iter().enumerate() {
            if let Some(law) = region_laws[ri as usize] {
                element_law[t] = law as u32;
                element_offset[t] = (count * points_per_element) as u32;
                count += 1;
            }
        }
        let points: Vec<PointState> = (0..count * points_per_element)
            .map(|_| PointState { nu_perpendicular: f64::NAN, ..PointState::default() })
            .collect();
        let last = LastEvaluations::new(points.len());
        let mut field = Self {
            laws,
            element_law,
            element_offset,
            points_per_element,
            points,
            last,
            largest_scale: 0.0,
        };
        field.reset_perpendicular();
        field
    }

    /// The residual scale of a step whose own scale is `scale`: the largest of the history
    /// (see [`crate::solver`]).
    pub(crate) fn history_scale(&mut self, scale: f64) -> f64 {
        self.largest_scale = self.largest_scale.max(scale);
        self.largest_scale
    }

    /// Every point back to the demagnetised state.
    pub(crate) fn demagnetise(&mut self) {
        self.largest_scale = 0.0;
        for p in &mut self.points {
            *p = PointState::default();
        }
        self.last.clear();
        self.reset_perpendicular();
    }

    /// `ν⊥` of demagnetised points: the initial slope of their law.
    fn reset_perpendicular(&mut self) {
        for t in 0..self.element_law.len() {
            let Some(params) = self.law(t) else { continue };
            let nu0 = HysteresisState::demagnetised().tangent(params).dh_db;
            let first = self.element_offset[t] as usize;
            for p in &mut self.points[first..first + self.points_per_element] {
                p.nu_perpendicular = nu0;
            }
        }
    }

    /// The law of element `t`, if it is hysteretic.
    #[inline(always)]
    pub(crate) fn law(&self, t: usize) -> Option<&HysteresisParams> {
        let law = *self.element_law.get(t)?;
        (law != u32::MAX).then(|| &*self.laws[law as usize])
    }

    /// Residual and packed Jacobian of hysteretic element `element` (the quadrature kernel of
    /// [`crate::form`] with the point law of the module docs).
    pub(crate) fn element_kernel<E: TriangleBasis<N>, const N: usize>(
        &self,
        element: &Element<'_, E, N>,
        params: &HysteresisParams,
        current_density: f64,
        a: [f64; N],
        residual: &mut [f64],
        jacobian: Option<&mut [f64]>,
    ) {
        let mut res = [0.0; N];
        let mut jac = [0.0; MAX_PACKED_LEN];
        let want_jacobian = jacobian.is_some();
        let geometry = element.geometry();
        let first = self.element_offset[element.index] as usize;
        for (k, q) in element.points(&geometry).enumerate() {
            let curl = curls(&q);
            let b = flux_density(&curl, a);
            let law = point_law(params, &self.points[first + k], b, &self.last, first + k);
            for i in 0..N {
                let h_dot_curl = law.h[0] * curl[i][0] + law.h[1] * curl[i][1];
                res[i] += q.weight * (h_dot_curl - current_density * q.phi[i]);
            }
            if want_jacobian {
                let [trr, trz, tzz] = law.tangent;
                let mut p = 0;
                for i in 0..N {
                    let tc =
                        [trr * curl[i][0] + trz * curl[i][1], trz * curl[i][0] + tzz * curl[i][1]];
                    for j in i..N {
                        jac[p] += q.weight * (tc[0] * curl[j][0] + tc[1] * curl[j][1]);
                        p += 1;
                    }
                }
            }
        }
        residual.copy_from_slice(&res);
        if let Some(out) = jacobian {
            out.copy_from_slice(&jac[..packed_len(N)]);
        }
    }

    /// Free energy stored in the committed states, J (over the full 2π ring).
    fn stored_energy(&self, basis: &Basis) -> f64 {
        by_order!(basis.order(), Self::stored_energy_order(self, basis))
    }

    fn stored_energy_order<E: TriangleBasis<N>, const N: usize>(&self, basis: &Basis) -> f64 {
        let mut stored = 0.0;
        for t in 0..self.element_law.len() {
            let Some(params) = self.law(t) else { continue };
            let element = basis.element::<E, N>(t);
            let geometry = element.geometry();
            let first = self.element_offset[t] as usize;
            for (k, q) in element.points(&geometry).enumerate() {
                let volume = 2.0 * std::f64::consts::PI * q.weight;
                stored += volume * self.points[first + k].state.free_energy(params);
            }
        }
        stored
    }

    /// Commits the states at the potential `a` (one value per DOF) of a converged step.
    pub(crate) fn commit(&mut self, basis: &Basis, a: &[f64]) -> HysteresisCommit {
        by_order!(basis.order(), Self::commit_order(self, basis, a))
    }

    fn commit_order<E: TriangleBasis<N>, const N: usize>(
        &mut self,
        basis: &Basis,
        a: &[f64],
    ) -> HysteresisCommit {
        let mut summary = HysteresisCommit::default();
        for t in 0..self.element_law.len() {
            let law = self.element_law[t];
            if law == u32::MAX {
                continue;
            }
            let params = Arc::clone(&self.laws[law as usize]);
            let element = basis.element::<E, N>(t);
            let local = element.dofs().map(|d| a[d]);
            let geometry = element.geometry();
            let first = self.element_offset[t] as usize;
            for (k, q) in element.points(&geometry).enumerate() {
                let b = flux_density(&curls(&q), local);
                let point = &mut self.points[first + k];
                let volume = 2.0 * std::f64::consts::PI * q.weight;
                let step = commit_point(&params, point, b, &self.last, first + k);
                summary.dissipated_j += volume * step.dissipated;
                summary.max_perpendicular_b_t =
                    summary.max_perpendicular_b_t.max(step.perpendicular);
                summary.max_point_iterations = summary.max_point_iterations.max(step.iterations);
            }
        }
        summary
    }
}

/// What committing one point did: dissipation per volume (J/m³), `|B⊥|` (T), root iterations.
struct PointCommit {
    dissipated: f64,
    perpendicular: f64,
    iterations: u32,
}

/// Commits one point (slot `k` of `last`) at flux density `b` (module docs: the axis is fixed at
/// the first commit).
fn commit_point(
    params: &HysteresisParams,
    point: &mut PointState,
    b: [f64; 2],
    last: &LastEvaluations,
    k: usize,
) -> PointCommit {
    let (axis, perpendicular) = match point.axis {
        Some(e) => {
            // |B − (B·e) e| = |B × e| for the unit axis e.
            (Some(e), (b[1] * e[0] - b[0] * e[1]).abs())
        }
        None => {
            let magnitude = b[0].hypot(b[1]);
            let axis = (magnitude > AXIS_MIN_B_T).then(|| [b[0] / magnitude, b[1] / magnitude]);
            (axis, 0.0)
        }
    };
    let Some(e) = axis else {
        return PointCommit { dissipated: 0.0, perpendicular: 0.0, iterations: 0 };
    };
    let along = b[0] * e[0] + b[1] * e[1];
    let (response, next) = trial_from(&point.state, params, along, last, k);
    let dissipated = point.state.dissipation_to(params, &next);
    point.state = next;
    point.axis = Some(e);
    point.nu_perpendicular = normal_secant(params, along.abs(), point.nu_perpendicular);
    PointCommit { dissipated, perpendicular, iterations: response.iterations }
}

/// The B-driven trial step of `state` to `b` at point `k`, its root search started from the
/// point's last evaluation ([`LastEvaluations`]), which it then replaces.
#[inline]
fn trial_from(
    state: &HysteresisState,
    params: &HysteresisParams,
    b: f64,
    last: &LastEvaluations,
    k: usize,
) -> (Response, HysteresisState) {
    let (response, next) = state.trial_near(params, b, last.guess(k, b));
    last.record(k, response.b, response.h, response.dh_db);
    (response, next)
}

/// [`trial_from`] for an evaluation whose state is discarded: the response alone.
#[inline]
fn response_from(
    state: &HysteresisState,
    params: &HysteresisParams,
    b: f64,
    last: &LastEvaluations,
    k: usize,
) -> Response {
    let response = state.response_near(params, b, last.guess(k, b));
    last.record(k, response.b, response.h, response.dh_db);
    response
}

/// The secant reluctivity `H/B` of the model's normal curve at `|b|`, at least its initial slope
/// (the frozen `ν⊥` of the next step). `previous`, the secant at the point's last commit (NaN: none),
/// starts the root search: the same root, fewer iterations when `|b|` moved little.
fn normal_secant(params: &HysteresisParams, b_abs: f64, previous: f64) -> f64 {
    let demagnetised = HysteresisState::demagnetised();
    let initial = demagnetised.tangent(params).dh_db;
    if b_abs <= AXIS_MIN_B_T {
        return initial;
    }
    let response = demagnetised.response_near(params, b_abs, previous * b_abs);
    (response.h / b_abs).max(initial).min(1.0 / MU_0)
}

/// `H` and `∂H/∂B` of a point (slot `k` of `last`) at trial flux density `b` (module docs).
#[inline]
fn point_law(
    params: &HysteresisParams,
    point: &PointState,
    b: [f64; 2],
    last: &LastEvaluations,
    k: usize,
) -> PointLaw {
    if let Some(e) = point.axis {
        let along = b[0] * e[0] + b[1] * e[1];
        let response = response_from(&point.state, params, along, last, k);
        let perpendicular = [b[0] - along * e[0], b[1] - along * e[1]];
        let nu = point.nu_perpendicular;
        let h =
            [response.h * e[0] + nu * perpendicular[0], response.h * e[1] + nu * perpendicular[1]];
        return PointLaw { h, tangent: axial_tangent(e, response.dh_db, nu) };
    }
    let magnitude = b[0].hypot(b[1]);
    if magnitude <= AXIS_MIN_B_T {
        let initial = point.state.tangent(params).dh_db;
        return PointLaw { h: [initial * b[0], initial * b[1]], tangent: [initial, 0.0, initial] };
    }
    let e = [b[0] / magnitude, b[1] / magnitude];
    let response = response_from(&point.state, params, magnitude, last, k);
    let h = [response.h * e[0], response.h * e[1]];
    PointLaw { h, tangent: axial_tangent(e, response.dh_db, response.h / magnitude) }
}

/// `slope e⊗e + perpendicular (I − e⊗e)` packed as `[T_rr, T_rz, T_zz]`.
#[inline(always)]
fn axial_tangent(e: [f64; 2], slope: f64, perpendicular: f64) -> [f64; 3] {
    let d = slope - perpendicular;
    [perpendicular + d * e[0] * e[0], d * e[0] * e[1], perpendicular + d * e[1] * e[1]]
}

impl crate::Solver {
    /// Solves the regions `regions` (physical tag, parameter set) with hysteresis from now on, every
    /// point demagnetised; an empty list switches hysteresis off (the anhysteretic solve of the
    /// regions' `Magnetic`, unchanged). A tag without a region is an input error.
    pub fn set_hysteresis(
        &mut self,
        regions: &[(u32, Arc<HysteresisParams>)],
    ) -> Result<(), MagneticsError> {
        if regions.is_empty() {
            self.form.hysteresis = None;
            self.assembly.prepare(&self.form);
            return Ok(());
        }
        let mut region_laws = vec![None; self.problem.regions.len()];
        let mut laws = Vec::with_capacity(regions.len());
        for (k, (tag, params)) in regions.iter().enumerate() {
            let ri = self.problem.regions.iter().position(|r| r.tag == *tag).ok_or_else(|| {
                MagneticsError::field(
                    format!("hysteresis[{k}].tag"),
                    format!("no region with physical = {tag}"),
                )
            })?;
            region_laws[ri] = Some(laws.len());
            laws.push(Arc::clone(params));
        }
        let field = HysteresisField::new(
            self.assembly.basis(),
            &self.form.element_region,
            &region_laws,
            laws,
        );
        self.form.hysteresis = Some(Box::new(field));
        self.assembly.prepare(&self.form);
        Ok(())
    }

    /// Whether regions are solved with hysteresis ([`crate::Solver::set_hysteresis`]).
    pub fn has_hysteresis(&self) -> bool {
        self.form.hysteresis.is_some()
    }

    /// Every hysteretic point back to the demagnetised state.
    pub fn demagnetise(&mut self) {
        if let Some(field) = &mut self.form.hysteresis {
            field.demagnetise();
        }
    }

    /// Commits the hysteretic states at `solution`, a converged solve of this step (module docs);
    /// without hysteretic regions nothing happens and the summary is zero.
    pub fn commit_hysteresis(&mut self, solution: &Solution) -> HysteresisCommit {
        match &mut self.form.hysteresis {
            Some(field) => field.commit(self.assembly.basis(), solution.a_phi()),
            None => HysteresisCommit::default(),
        }
    }

    /// Free energy stored in the hysteretic regions' committed states, J (over the full 2π ring;
    /// 0 without hysteretic regions): `2π Σ_q w_q (μ0 H²/2 + Σ_k U_k(h_k))` (the stored part of the
    /// energy balance of [`mrbrake_materials::hysteresis`]).
    pub fn stored_hysteresis_energy_j(&self) -> f64 {
        self.form
            .hysteresis
            .as_ref()
            .map_or(0.0, |field| field.stored_energy(self.assembly.basis()))
    }

    /// [`crate::Solver::solve`] for one step of a quasi-static history (from `initial`, e.g. the
    /// last step's solution or a prediction from it): Newton's first step is solved by conjugate
    /// gradients preconditioned with the factor the previous solve left, the core's warm start
    /// ([`mrbrake_fem::workflow::newton::NewtonOptions::reuse_factor`]; a factorisation when CG
    /// does not reach the warm start's forcing tolerance within its few iterations). A step's Jacobian differs from the last one's
    /// by the change of the material states over one step, so the old factor usually suffices.
    /// The stopping rule is that of [`crate::Solver::solve`]: the converged steps agree to the
    /// solver's tolerance, only the work differs.
    pub fn solve_quasi_static(
        &mut self,
        initial: Option<&[f64]>,
    ) -> Result<Solution, MagneticsError> {
        self.solve_with(initial, true)
    }

    /// One quasi-static step: a solve warm-started from `initial`
    /// ([`crate::Solver::solve_quasi_static`]), then its commit.
    pub fn solve_step(
        &mut self,
        initial: Option<&[f64]>,
    ) -> Result<(Solution, HysteresisCommit), MagneticsError> {
        let solution = self.solve_quasi_static(initial)?;
        let commit = self.commit_hysteresis(&solution);
        Ok((solution, commit))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use mrbrake_materials::hysteresis::library;

    fn steel() -> Arc<HysteresisParams> {
        Arc::clone(&library::for_material("steel-1008").unwrap().params)
    }

    /// The point law is the gradient of its energy: the tangent matches central differences of H,
    /// for a magnetised point off its axis and for a demagnetised one.
    #[test]
    fn tangent_matches_finite_differences() {
        let params = steel();
        let last = LastEvaluations::new(1);
        let mut magnetised = PointState::default();
        commit_point(&params, &mut magnetised, [0.3, 1.2], &last, 0);
        commit_point(&params, &mut magnetised, [0.1, 0.5], &last, 0);
        let nu0 = normal_secant(&params, 0.0, f64::NAN);
        let demagnetised = PointState { nu_perpendicular: nu0, ..PointState::default() };
        // Each evaluation from a fresh start: the derivative of the law itself.
        let evaluate =
            |point: &PointState, b| point_law(&params, point, b, &LastEvaluations::new(1), 0);
        for (point, b) in [(magnetised, [0.12, 0.35]), (demagnetised, [0.4, 0.9])] {
            let law = evaluate(&point, b);
            let full = [[law.tangent[0], law.tangent[1]], [law.tangent[1], law.tangent[2]]];
            for j in 0..2 {
                let step = 1e-7;
                let (mut bp, mut bm) = (b, b);
                bp[j] += step;
                bm[j] -= step;
                let hp = evaluate(&point, bp).h;
                let hm = evaluate(&point, bm).h;
                for i in 0..2 {
                    let fd = (hp[i] - hm[i]) / (2.0 * step);
                    let scale = full[0][0].abs() + full[1][1].abs();
                    assert!(
                        (fd - full[i][j]).abs() <= 1e-4 * scale,
                        "({i},{j}) {fd} vs {:?}",
                        full
                    );
                }
            }
        }
    }

    /// Along its axis a point is the material model itself: remanence after a peak.
    #[test]
    fn a_point_along_its_axis_is_the_material_model() {
        let params = steel();
        let mut point = PointState::default();
        let mut model = HysteresisState::demagnetised();
        let e = [0.6, 0.8];
        let last = LastEvaluations::new(1);
        for b in [0.5, 1.4, 0.7, 0.0, -1.0] {
            commit_point(&params, &mut point, [b * e[0], b * e[1]], &last, 0);
            let expected = model.step(&params, b).h;
            assert!((point.state.h() - expected).abs() <= 1e-9 * (1.0 + expected.abs()));
        }
        assert_eq!(point.axis, Some(e));
    }
}
