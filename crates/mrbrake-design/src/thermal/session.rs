//! The parts of [`super::analyze_thermal`] one at a time on one heat solver, for a design study
//! that asks only for some of the thermal figures: the steady state at the run's current, the
//! continuous current (and so the largest duty at the maximum current), the warm-up's time to
//! the limit, and the hot torque at a chosen current.
//!
//! Each figure is computed by the same functions, in the same order, as `mrbrake thermal`
//! computes it: a [`ThermalSession`] is set up as the command is (steady state at the run's
//! current first, which fixes a natural-convection `h`), and every later figure starts from
//! that state's `h`, as the command resets it. So `continuous_current_a` equals the command's
//! `continuous_current_A`, `time_to_limit_s` its `time_to_limit_s`, and
//! [`ThermalSession::hot_behaviour_at`] `mrbrake thermal --current I --duty 1`'s `behaviour`
//! (to the heat solver's Newton tolerance: the steady solve at `I` starts from this session's
//! last state).

use mrbrake_heat::{HeatSolver, SolverOptions};

use super::behaviour::{HotBehaviour, hot_behaviour};
use super::{
    HOUSING_TAG, Housing, NEWTON_TOLERANCE, SteadyTemperatures, ThermalError, ThermalOptions,
    ThermalParts, continuous_current, crossing, set_current, steady_of, thermal_problem_on_mesh,
    validate_options, warmup,
};
use crate::geometry::{BrakeGeometry, PartKind};
use crate::mesh_build::mesh_spec;
use crate::spec::BrakeSpec;
use mrbrake_fem::mesh::Mesh;

/// One design's heat model, solved step by step (module docs).
pub struct ThermalSession<'a> {
    spec: &'a BrakeSpec,
    options: ThermalOptions,
    solver: HeatSolver,
    parts: ThermalParts,
    housing: Housing,
    steady: Option<SteadyTemperatures>,
    steady_h: f64,
    continuous_a: Option<f64>,
}

impl<'a> ThermalSession<'a> {
    /// Checks `options`, builds the heat problem of `spec` and solves its steady state at the
    /// options' current and duty.
    pub fn new(spec: &'a BrakeSpec, options: &ThermalOptions) -> Result<Self, ThermalError> {
        validate_options(options)?;
        let geometry = spec.validate()?.geometry;
        let full = mesh_spec(spec, &geometry, options.mesh)?;
        Self::on_mesh(spec, options, &geometry, &full)
    }

    /// The session on the magnetic mesh `full` of `geometry` built before (at the options'
    /// level, shared with the design's other analyses).
    pub fn on_mesh(
        spec: &'a BrakeSpec,
        options: &ThermalOptions,
        geometry: &BrakeGeometry,
        full: &Mesh,
    ) -> Result<Self, ThermalError> {
        validate_options(options)?;
        let (problem, parts) = thermal_problem_on_mesh(spec, options, geometry, full)?;
        let mut housing = Housing::new(&problem.mesh, options);
        let solver_options =
            SolverOptions { tolerance: NEWTON_TOLERANCE, ..SolverOptions::default() };
        let mut solver = HeatSolver::new(problem, solver_options)?;
        let steady = steady_of(&mut solver, &parts, &mut housing)?.map(|s| s.0);
        let steady_h = housing.h;
        Ok(Self {
            spec,
            options: *options,
            solver,
            parts,
            housing,
            steady,
            steady_h,
            continuous_a: None,
        })
    }

    /// The steady state at the options' current and duty (`None`: thermal runaway).
    pub fn steady(&self) -> Option<&SteadyTemperatures> {
        self.steady.as_ref()
    }

    /// The housing's cooling back at the steady state's `h`, and the run's current.
    fn reset(&mut self) -> Result<(), ThermalError> {
        self.housing.h = self.steady_h;
        self.solver.set_convection(HOUSING_TAG, self.steady_h, self.housing.ambient_k)?;
        Ok(())
    }

    /// The current whose steady hot spot is the insulation limit (A), searched once.
    pub fn continuous_current_a(&mut self) -> Result<f64, ThermalError> {
        if let Some(current) = self.continuous_a {
            return Ok(current);
        }
        let max_current = self.spec.coil.max_current.a();
        let limit = self.options.limit_c;
        let current = continuous_current(
            &mut self.solver,
            &self.parts,
            &mut self.housing,
            limit,
            max_current,
        )?;
        self.reset()?;
        self.continuous_a = Some(current);
        Ok(current)
    }

    /// The largest duty cycle at the spec's maximum current, `(I_cont / I_max)²` capped at 1.
    pub fn max_duty_at_max_current(&mut self) -> Result<f64, ThermalError> {
        let max_current = self.spec.coil.max_current.a();
        Ok((self.continuous_current_a()? / max_current).powi(2).min(1.0))
    }

    /// The time the warm-up's hot spot reaches the limit (s), `None` if not within the run.
    pub fn time_to_limit_s(&mut self) -> Result<Option<f64>, ThermalError> {
        self.reset()?;
        let (curve, _) = warmup(&mut self.solver, &self.parts, &self.options)?;
        Ok(crossing(&curve, self.options.limit_c))
    }

    /// What heat does to the brake held at `current` amperes for ever (duty 1): the steady state
    /// at that current and [`super::behaviour`] from it; `None` when it has no steady state.
    pub fn hot_behaviour_at(&mut self, current: f64) -> Result<Option<HotBehaviour>, ThermalError> {
        let options = ThermalOptions { current_a: current, duty: 1.0, ..self.options };
        validate_options(&options)?;
        self.reset()?;
        set_current(&mut self.solver, &self.parts, current)?;
        let steady = steady_of(&mut self.solver, &self.parts, &mut self.housing)?.map(|s| s.0);
        let behaviour = match steady {
            Some(s) => Some(hot_behaviour(
                self.spec,
                &options,
                &mut self.solver,
                &self.parts,
                &mut self.housing,
                &s,
            )?),
            None => None,
        };
        self.reset()?;
        set_current(
            &mut self.solver,
            &self.parts,
            self.options.current_a * self.options.duty.sqrt(),
        )?;
        Ok(behaviour)
    }
}

/// Checks that every part of `spec` that the heat model needs has thermal data (the winding's
/// comes from the wire), without meshing: a study asking for a heat metric stops before its
/// first design instead of failing every one.
pub fn check_thermal_data(spec: &BrakeSpec) -> Result<(), ThermalError> {
    let geometry = spec.validate()?.geometry;
    let needed =
        geometry.regions.iter().filter(|r| !matches!(r.kind, PartKind::Air | PartKind::Coil));
    for part in needed {
        mrbrake_materials::thermal::thermal(&part.material).map_err(|e| {
            super::no_thermal_data(spec, &format!("part '{}'", part.name), &part.material, &e)
        })?;
    }
    mrbrake_materials::library::fluid(&spec.materials.fluid)?;
    Ok(())
}
