//! Heat in time on the core's integrator (`mrbrake_fem::workflow::time`): the heat problem is a
//! [`TransientProblem`] whose mass is the capacity matrix `C = ∫ ρc φ_i φ_j r dr dz` and whose
//! static residual is the steady one (conduction, the affine source, the boundary fluxes), so the
//! step of rate `ρ` and history `h` solves
//!
//! `R(T) = ∫ [k ∇T·∇φ_i − (q0 + q1 T) φ_i] r dr dz + ∮ g(T) φ_i r ds + ρ C (T − h) = 0`.
//!
//! The loads do not depend on time (a run's sources and boundaries are fixed; [`HeatSolver::
//! set_source`] between runs), so there are no step loads and no auxiliary states. Without
//! radiation the step is linear (the core's fast path: one capacity product and one solve per
//! step); with radiation Newton solves each step, its stopping scale `‖R_static(T_c)‖` (the
//! fluxes and sources at the fixed temperatures, zero elsewhere, in kelvin: never zero with a
//! radiating boundary). Fixed or adaptive steps as the options say; a Jacobian that stops being
//! positive definite under a Joule feedback is a thermal runaway ([`HeatError::Runaway`]).

use mrbrake_fem::discretisation::dofs::ElementOrder;
use mrbrake_fem::workflow::assemble::element_matrix_product;
use mrbrake_fem::workflow::constraints::Constraints;
use mrbrake_fem::workflow::newton::{NewtonOptions, NewtonSolver, NonlinearSystem, norm2};
use mrbrake_fem::workflow::time::{
    Event, Level, Outcome, Step, TimeOptions, TransientProblem, integrate,
};
use mrbrake_observe::Observer;

use crate::HeatError;
use crate::form::Capacity;
use crate::solver::{HeatSolver, HeatSystem};

impl HeatSolver {
    /// Integrates from `initial` (kelvin per DOF; fixed temperatures are imposed) at `t = 0` to
    /// `options.t_end_s`, showing `observer` the initial level and every accepted step (the
    /// solver in the event gives the step's post-processing: balances, region statistics); a
    /// `Flow::Stop` ends the run after that level ([`Outcome::stopped`]). Returns the outcome: the
    /// final temperature, steps, factorisations (linear problems) and Newton iterations.
    pub fn transient<O>(
        &mut self,
        initial: &[f64],
        options: &TimeOptions,
        observer: O,
    ) -> Result<Outcome, HeatError>
    where
        O: for<'a> Observer<Event<'a, HeatSolver>>,
    {
        integrate(self, initial.to_vec(), options, observer).map_err(|e| self.runaway_or(e))
    }

    /// The system of the form as it stands (steady, or the step its capacity says).
    fn system(&mut self) -> (&mut NewtonSolver, HeatSystem<'_>) {
        let system = HeatSystem {
            assembly: &mut self.assembly,
            form: &self.form,
            edges: &self.edges,
            laws: &self.laws,
            linear: !self.radiation,
        };
        (&mut self.newton, system)
    }
}

impl TransientProblem for HeatSolver {
    type Error = HeatError;
    type System<'a> = HeatSystem<'a>;

    fn constraints(&self) -> &Constraints {
        self.assembly.constraints()
    }

    fn newton(&mut self) -> &mut NewtonSolver {
        &mut self.newton
    }

    fn newton_options(&self) -> NewtonOptions {
        self.newton_settings()
    }

    fn residual_scale(&mut self) -> f64 {
        let lifting = self.assembly.constraints().lifting();
        norm2(&self.static_residual(&lifting)).max(f64::MIN_POSITIVE)
    }

    fn prepare(&mut self, step: &Step) {
        self.form.capacity = Some(Capacity { rate: step.rate, history: step.history.clone() });
        self.assembly.prepare(&self.form);
        self.prepared = Some(Some(step.rate));
    }

    fn step_system<'a>(&'a mut self, step: &'a Step) -> (&'a mut NewtonSolver, HeatSystem<'a>) {
        self.form.capacity = Some(Capacity { rate: step.rate, history: step.history.clone() });
        self.system()
    }

    fn is_linear(&self) -> bool {
        !self.radiation
    }

    fn static_residual(&mut self, u: &[f64]) -> Vec<f64> {
        let capacity = self.form.capacity.take();
        let (_, mut system) = self.system();
        let mut residual = vec![0.0; system.assembly.n_free()];
        system.evaluate(u, &mut residual, None);
        self.form.capacity = capacity;
        residual
    }

    fn mass_product(&self, x: &[f64]) -> Vec<f64> {
        let mut y = vec![0.0; x.len()];
        let dofs = self.assembly.basis().dofs().element_dofs();
        let matrices = &self.capacity_matrices;
        match self.options.order {
            ElementOrder::P1 => element_matrix_product::<3>(dofs, matrices, |_| 1.0, x, &mut y),
            ElementOrder::P2 => element_matrix_product::<6>(dofs, matrices, |_| 1.0, x, &mut y),
        }
        y
    }

    /// None: a run's sources and boundaries do not change in time.
    fn add_step_loads(&self, _step: &Step, _u: &[f64], _residual: &mut [f64]) {}

    /// Keeps the accepted step's capacity term, so that the post-processing of the level (the
    /// energy balance's stored heat) uses its rate and history.
    fn accept(&mut self, level: &Level<'_>) -> Result<(), HeatError> {
        if level.index > 0 {
            let history = level.history.to_vec();
            self.form.capacity = Some(Capacity { rate: level.rate, history });
        }
        Ok(())
    }
}
