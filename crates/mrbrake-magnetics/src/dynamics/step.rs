//! Magnetodynamics as a physics in time ([`TransientProblem`]): the static A_phi form plus the
//! eddy-current mass `σ M`, and the coils as step loads, their flux linkages the auxiliary states.
//!
//! With the scheme's `ȧ ≈ ρ (a − h)` a step's residual is (see [`super::transient`])
//!
//! `R(a) = K(a) a + ρ σ M (a − h) − Σ_k i_k(a) c_k`,
//!
//! `i_k = I_k w(t)` for a current drive, `i_k(a) = [v_k(t) − ρ (λ_k(a) − λ_h,k)]/R_k` for a
//! voltage drive (its Jacobian term `(2πρ/R_k) c_k c_kᵀ` is a [`LowRankTerm`]).

use mrbrake_fem::linalg::low_rank::LowRankTerm;
use mrbrake_fem::workflow::assemble::Assembly;
use mrbrake_fem::workflow::constraints::Constraints;
use mrbrake_fem::workflow::newton::{NewtonOptions, NewtonSolver, NonlinearSystem};
use mrbrake_fem::workflow::time::{Step, TransientProblem};

use super::form::TransientForm;
use super::{CoilData, Drive, Dynamics, TWO_PI, dot};
use crate::MagneticsError;
use crate::form::AphiForm;
use crate::solver::Solver;

/// The coil terms of one step.
#[derive(Debug, Clone, Copy)]
pub(crate) enum StepDrive {
    Current(f64),
    Circuit { voltage: f64, resistance: f64, rate: f64, lambda_history: f64 },
}

impl StepDrive {
    /// The current for the flux linkage `lambda`.
    pub(crate) fn current(&self, lambda: f64) -> f64 {
        match *self {
            Self::Current(i) => i,
            Self::Circuit { voltage, resistance, rate, lambda_history } => {
                (voltage - rate * (lambda - lambda_history)) / resistance
            }
        }
    }
}

/// The drive of `coil` in a step to `t` with the rate `rate` and its flux-linkage history.
pub(crate) fn step_drive(coil: &CoilData, t: f64, rate: f64, lambda_history: f64) -> StepDrive {
    let w = coil.coil.waveform.value(t);
    match coil.coil.drive {
        Drive::Current { amplitude_a } => StepDrive::Current(amplitude_a * w),
        Drive::Voltage { amplitude_v, series_resistance_ohm } => StepDrive::Circuit {
            voltage: amplitude_v * w,
            resistance: series_resistance_ohm,
            rate,
            lambda_history,
        },
    }
}

/// The coil terms of `step`.
fn step_drives(coils: &[CoilData], step: &Step) -> Vec<StepDrive> {
    coils
        .iter()
        .enumerate()
        .map(|(k, coil)| step_drive(coil, step.t, step.rate, step.auxiliary_history[k]))
        .collect()
}

/// `residual −= i_k(a) c_k` for every coil.
fn subtract_coil_currents(
    coils: &[CoilData],
    drives: &[StepDrive],
    a: &[f64],
    residual: &mut [f64],
) {
    for (coil, drive) in coils.iter().zip(drives) {
        let current = drive.current(TWO_PI * dot(&coil.full, a));
        for (r, c) in residual.iter_mut().zip(&coil.free) {
            *r -= current * c;
        }
    }
}

/// The non-linear system of one time step: the transient form plus the coil terms.
pub struct StepSystem<'a> {
    assembly: &'a mut Assembly,
    form: TransientForm<'a>,
    coils: &'a [CoilData],
    drives: Vec<StepDrive>,
    terms: Vec<LowRankTerm>,
}

impl NonlinearSystem for StepSystem<'_> {
    fn constraints(&self) -> &Constraints {
        self.assembly.constraints()
    }

    fn evaluate(&mut self, u: &[f64], residual: &mut [f64], jacobian: Option<&mut [f64]>) {
        self.assembly.evaluate(&self.form, u, residual, jacobian);
        subtract_coil_currents(self.coils, &self.drives, u, residual);
    }

    fn is_linear(&self) -> bool {
        self.assembly.is_linear()
    }

    fn low_rank(&self) -> &[LowRankTerm] {
        &self.terms
    }
}

/// The rank-one Jacobian terms `(2πρ/R) c cᵀ` of the voltage-driven coils.
fn low_rank_terms(coils: &[CoilData], drives: &[StepDrive]) -> Vec<LowRankTerm> {
    coils
        .iter()
        .zip(drives)
        .filter_map(|(coil, drive)| match *drive {
            StepDrive::Circuit { resistance, rate, .. } => {
                Some(LowRankTerm { vector: coil.free.clone(), weight: TWO_PI * rate / resistance })
            }
            StepDrive::Current(_) => None,
        })
        .collect()
}

/// The solver parts a step borrows.
fn parts(solver: &mut Solver) -> (&mut Assembly, &AphiForm, &mut NewtonSolver) {
    (&mut solver.assembly, &solver.form, &mut solver.newton)
}

impl TransientProblem for Dynamics {
    type Error = MagneticsError;
    type System<'a> = StepSystem<'a>;

    fn constraints(&self) -> &Constraints {
        self.solver.assembly.constraints()
    }

    fn newton(&mut self) -> &mut NewtonSolver {
        &mut self.solver.newton
    }

    fn newton_options(&self) -> NewtonOptions {
        self.solver.options.newton()
    }

    /// The static scale (non-coil sources and boundary values) plus `Σ_k |I_k| ‖c_k‖` at each
    /// coil's reference current (its amplitude, or `V/R`).
    fn residual_scale(&mut self) -> f64 {
        let mut scale = self.solver.residual_scale();
        for coil in &self.coils {
            let reference = match coil.coil.drive {
                Drive::Current { amplitude_a } => amplitude_a.abs(),
                Drive::Voltage { amplitude_v, series_resistance_ohm } => {
                    (amplitude_v / series_resistance_ohm).abs()
                }
            };
            scale += reference * dot(&coil.free, &coil.free).sqrt();
        }
        scale.max(f64::MIN_POSITIVE)
    }

    fn prepare(&mut self, step: &Step) {
        let (assembly, statics, _) = parts(&mut self.solver);
        assembly.prepare(&TransientForm {
            statics,
            sigma: &self.sigma,
            mass: &self.mass,
            history: &step.history,
            rate: step.rate,
        });
    }

    fn step_system<'a>(&'a mut self, step: &'a Step) -> (&'a mut NewtonSolver, StepSystem<'a>) {
        let drives = step_drives(&self.coils, step);
        let terms = low_rank_terms(&self.coils, &drives);
        let Dynamics { solver, sigma, mass, coils } = self;
        let (assembly, statics, newton) = parts(solver);
        let form = TransientForm { statics, sigma, mass, history: &step.history, rate: step.rate };
        (newton, StepSystem { assembly, form, coils, drives, terms })
    }

    fn is_linear(&self) -> bool {
        self.solver.assembly.is_linear()
    }

    fn static_residual(&mut self, u: &[f64]) -> Vec<f64> {
        let (assembly, statics, _) = parts(&mut self.solver);
        let mut residual = vec![0.0; assembly.constraints().n_free()];
        assembly.evaluate(statics, u, &mut residual, None);
        residual
    }

    fn mass_product(&self, x: &[f64]) -> Vec<f64> {
        self.mass_mul(x)
    }

    fn add_step_loads(&self, step: &Step, u: &[f64], residual: &mut [f64]) {
        subtract_coil_currents(&self.coils, &step_drives(&self.coils, step), u, residual);
    }

    /// The flux linkages of the coils.
    fn auxiliary(&self, u: &[f64]) -> Vec<f64> {
        (0..self.coils.len()).map(|k| self.flux_linkage(k, u)).collect()
    }

    /// The waveforms' corners.
    fn breakpoints(&self, t_end: f64) -> Vec<f64> {
        self.coils.iter().flat_map(|c| c.coil.waveform.breakpoints(t_end)).collect()
    }
}
