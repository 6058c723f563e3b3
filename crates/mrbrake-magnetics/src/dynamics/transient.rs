//! Transient magnetodynamics on the core's time integrator ([`mrbrake_fem::workflow::time`]:
//! implicit Euler and variable-step BDF2, fixed or adaptive steps, Newton in every step, the linear
//! fast path), with the coils' circuits as the integrator's auxiliary states.
//!
//! Both schemes write `ȧ_{n+1} ≈ ρ (a_{n+1} − h)` with the rate `ρ = γ/Δt` and the history `h`;
//! the same discretisation is applied to the flux linkages in the circuit equations.
//!
//! Coils: a current-driven coil adds `−i(t_{n+1}) c` to the residual. For a voltage-driven coil,
//! the discrete circuit equation `v = R i + ρ (λ(a) − λ_h)` with `λ(a) = 2π c · a` gives the current
//! as a function of the field, `i(a) = [v + ρ λ_h − 2πρ c·a]/R`, which is eliminated: the residual
//! gains `−i(a) c` and the Jacobian the dense rank-one term `(2πρ/R) c cᵀ` (applied with the sparse
//! factor by the Woodbury formula, [`mrbrake_fem::linalg::low_rank`]). The step's system stays the
//! gradient of a convex energy, so the core's Newton solver and line search apply unchanged, and
//! the coil's own `L/R` and the eddy currents both appear in the response. The flux linkages are
//! the integrator's auxiliary states
//! ([`mrbrake_fem::workflow::time::TransientProblem::auxiliary`]) and the waveforms' corners
//! its breakpoints.
//!
//! A linear problem (linear materials) has the same Jacobian in every step at one rate: the core
//! factorises it once per rate and a step is one conductor mass product and one solve. Every
//! accepted level is recorded ([`TransientResult`]: currents, flux linkages, voltages, losses,
//! energies, probes, snapshots) and shown to the caller's observer ([`StepView`]); a
//! [`Flow::Stop`] ends the run after that level with [`TransientResult::stopped`] set.

use std::time::Instant;

use mrbrake_fem::mesh::locate::Probe;
use mrbrake_fem::workflow::time::{Event, Level, Scheme, TimeOptions, TimeStep, integrate};
use mrbrake_observe::{Flow, Observer, Silent};
use serde::Serialize;

use super::step::{StepDrive, step_drive};
use super::{Drive, Dynamics};
use crate::MagneticsError;
use crate::force::ForceLayer;

/// Settings of a transient solve.
#[derive(Debug, Clone, PartialEq)]
pub struct TransientOptions {
    /// End time, scheme, steps; the solve starts at 0 from the DC state of the drives at `t = 0`.
    pub time: TimeOptions,
    /// B probes.
    pub probes: Vec<Probe>,
    /// Record the stored magnetic energy every step (one quadrature loop per step).
    pub energy: bool,
    /// Keep the potential at the first step at or after each of these times (s).
    pub snapshot_times_s: Vec<f64>,
    /// Record the axial force on each of these regions (physical tags) every step
    /// ([`crate::force`]; one pass over the mesh per region and step).
    pub force_regions: Vec<u32>,
}

impl TransientOptions {
    /// Options with no probes, no energy, no snapshots and the default step bound.
    pub fn new(t_end_s: f64, scheme: Scheme, step: TimeStep) -> Self {
        Self {
            time: TimeOptions::new(t_end_s, scheme, step),
            probes: Vec::new(),
            energy: false,
            snapshot_times_s: Vec::new(),
            force_regions: Vec::new(),
        }
    }
}

/// A coil's current, flux linkage and terminal voltage over time.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CoilTrace {
    /// Physical tag of the coil region.
    pub physical: u32,
    /// Current (A).
    #[serde(rename = "current_A")]
    pub current_a: Vec<f64>,
    /// Flux linkage (Wb).
    #[serde(rename = "flux_linkage_Wb")]
    pub flux_linkage_wb: Vec<f64>,
    /// Voltage (V): the source voltage of a voltage drive; `dλ/dt` (the induced EMF, no winding
    /// resistance) for a current drive.
    #[serde(rename = "voltage_V")]
    pub voltage_v: Vec<f64>,
}

/// B at a probe over time.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ProbeTrace {
    /// Probe name.
    pub name: String,
    /// `B_r` (T).
    #[serde(rename = "B_r_T")]
    pub b_r_t: Vec<f64>,
    /// `B_z` (T).
    #[serde(rename = "B_z_T")]
    pub b_z_t: Vec<f64>,
}

/// The axial force on a region over time.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ForceTrace {
    /// Physical tag of the region.
    pub physical: u32,
    /// Axial force (N, +z) at each level, by virtual work ([`crate::force`]).
    #[serde(rename = "force_z_N")]
    pub force_z_n: Vec<f64>,
}

/// The outcome of a transient solve: one entry per accepted time level, `t = 0` first.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TransientResult {
    /// Times (s).
    pub time_s: Vec<f64>,
    /// Every driven coil.
    pub coils: Vec<CoilTrace>,
    /// Every probe.
    pub probes: Vec<ProbeTrace>,
    /// The force on every region of [`TransientOptions::force_regions`].
    pub forces: Vec<ForceTrace>,
    /// Eddy-current loss of all conductors (W) at each level.
    #[serde(rename = "eddy_loss_W")]
    pub eddy_loss_w: Vec<f64>,
    /// `R i²` of the voltage-driven circuits (W).
    #[serde(rename = "winding_loss_W")]
    pub winding_loss_w: Vec<f64>,
    /// Stored magnetic energy (J), when asked for.
    #[serde(rename = "stored_energy_J", skip_serializing_if = "Vec::is_empty")]
    pub stored_energy_j: Vec<f64>,
    /// Energy delivered to the field by the coils, `Σ_k Σ_n i_k (λ_k,n+1 − λ_k,n)` (J).
    #[serde(rename = "source_energy_J")]
    pub source_energy_j: Vec<f64>,
    /// Energy dissipated by eddy currents, `Σ_n Δt_n P_n+1` (J).
    #[serde(rename = "eddy_energy_J")]
    pub eddy_energy_j: Vec<f64>,
    /// Newton iterations of each step (0 at `t = 0`).
    pub newton_iterations: Vec<usize>,
    /// Numeric factorisations of the whole run (sparse part).
    pub factorizations: usize,
    /// Rejected adaptive steps.
    pub rejected_steps: usize,
    /// Potentials kept at the requested snapshot times: `(t, a at every DOF)`.
    #[serde(skip)]
    pub snapshots: Vec<(f64, Vec<f64>)>,
    /// True when the observer stopped the run (`time_s` then ends before `t_end`).
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub stopped: bool,
    /// Wall time of the solve (s).
    pub total_s: f64,
}

/// What an observer sees after every accepted step (and at `t = 0`).
pub struct StepView<'a> {
    /// Time (s).
    pub t: f64,
    /// The potential at every DOF.
    pub a: &'a [f64],
    /// Coil currents (A), in the order of the coils.
    pub currents: &'a [f64],
    /// `∂A/∂t` at every DOF as the scheme discretises it (`ρ (a − h)`, Wb/(m s)); zero at `t = 0`
    /// (the DC state). With [`Dynamics::eddy_current_density`] it gives the eddy currents.
    pub rate: &'a [f64],
    /// The dynamics (solver, post-processing).
    pub dynamics: &'a Dynamics,
}

impl Dynamics {
    /// Integrates from the DC state at `t = 0` to `options.time.t_end_s`.
    pub fn transient(
        &mut self,
        options: &TransientOptions,
    ) -> Result<TransientResult, MagneticsError> {
        self.transient_observed(options, Silent)
    }

    /// [`Self::transient`], showing `observer` the level at `t = 0` and every accepted step (e.g.
    /// to compute a torque from the field); a [`Flow::Stop`] ends the run after that level
    /// ([`TransientResult::stopped`]). An observer that fails keeps its error, stops the run and
    /// returns it afterwards.
    pub fn transient_observed<O>(
        &mut self,
        options: &TransientOptions,
        mut observer: O,
    ) -> Result<TransientResult, MagneticsError>
    where
        O: for<'a> Observer<StepView<'a>>,
    {
        options.time.validate()?;
        let start = Instant::now();
        let currents: Vec<f64> = self.coils.iter().map(|c| c.coil.dc_current_a(0.0)).collect();
        let initial = self.static_solution(&currents)?.a_phi().to_vec();
        let mut recorder = Recorder::new(self, options);
        let outcome = integrate(self, initial, &options.time, |event: &Event<'_, Dynamics>| {
            if let Err(e) = recorder.record(event.problem, &event.level) {
                recorder.failure = Some(e);
                return Flow::Stop;
            }
            observer.observe(&StepView {
                t: event.level.t,
                a: event.level.u,
                currents: &recorder.currents,
                rate: &recorder.rate,
                dynamics: event.problem,
            })
        });
        // Leave the static solver as it was (its form's constant Jacobian).
        self.solver.assembly.prepare(&self.solver.form);
        let outcome = outcome?;
        if let Some(e) = recorder.failure {
            return Err(e);
        }
        let mut result = recorder.result;
        result.factorizations = outcome.factorizations;
        result.rejected_steps = outcome.rejected_steps;
        result.stopped = outcome.stopped;
        result.total_s = start.elapsed().as_secs_f64();
        Ok(result)
    }
}

/// Records every accepted level into a [`TransientResult`].
struct Recorder<'o> {
    options: &'o TransientOptions,
    result: TransientResult,
    next_snapshot: usize,
    /// The coil currents of the newest level (A).
    currents: Vec<f64>,
    /// `∂A/∂t` of the newest level (zero at `t = 0`).
    rate: Vec<f64>,
    /// A failure of the recording (a probe outside the mesh), returned after the run.
    failure: Option<MagneticsError>,
    /// The element layer of each of [`TransientOptions::force_regions`], built at the first level.
    force_layers: Vec<ForceLayer>,
}

impl<'o> Recorder<'o> {
    fn new(dynamics: &Dynamics, options: &'o TransientOptions) -> Self {
        let result = TransientResult {
            time_s: Vec::new(),
            coils: dynamics
                .coils
                .iter()
                .map(|c| CoilTrace {
                    physical: c.coil.tag,
                    current_a: Vec::new(),
                    flux_linkage_wb: Vec::new(),
                    voltage_v: Vec::new(),
                })
                .collect(),
            probes: options
                .probes
                .iter()
                .map(|p| ProbeTrace { name: p.name.clone(), b_r_t: Vec::new(), b_z_t: Vec::new() })
                .collect(),
            forces: options
                .force_regions
                .iter()
                .map(|&physical| ForceTrace { physical, force_z_n: Vec::new() })
                .collect(),
            eddy_loss_w: Vec::new(),
            winding_loss_w: Vec::new(),
            stored_energy_j: Vec::new(),
            source_energy_j: Vec::new(),
            eddy_energy_j: Vec::new(),
            newton_iterations: Vec::new(),
            factorizations: 0,
            rejected_steps: 0,
            snapshots: Vec::new(),
            stopped: false,
            total_s: 0.0,
        };
        Self {
            options,
            result,
            next_snapshot: 0,
            currents: Vec::new(),
            rate: Vec::new(),
            failure: None,
            force_layers: Vec::new(),
        }
    }

    /// Records a level: the DC state at `t = 0`, a step after it.
    fn record(&mut self, dynamics: &Dynamics, level: &Level<'_>) -> Result<(), MagneticsError> {
        if level.index == 0 {
            self.record_initial(dynamics, level);
        } else {
            self.record_step(dynamics, level);
        }
        self.currents =
            self.result.coils.iter().map(|c| c.current_a[c.current_a.len() - 1]).collect();
        self.record_field(dynamics, level)
    }

    /// The level at `t = 0` (the DC state: no rates, no losses but the windings').
    fn record_initial(&mut self, dynamics: &Dynamics, level: &Level<'_>) {
        let mut winding_loss = 0.0;
        for (k, coil) in dynamics.coils.iter().enumerate() {
            let current = coil.coil.dc_current_a(0.0);
            let voltage = match coil.coil.drive {
                Drive::Current { .. } => 0.0,
                Drive::Voltage { amplitude_v, series_resistance_ohm } => {
                    winding_loss += series_resistance_ohm * current * current;
                    amplitude_v * coil.coil.waveform.value(0.0)
                }
            };
            let trace = &mut self.result.coils[k];
            trace.current_a.push(current);
            trace.flux_linkage_wb.push(level.auxiliary[k]);
            trace.voltage_v.push(voltage);
        }
        self.rate = vec![0.0; level.u.len()];
        let r = &mut self.result;
        r.eddy_loss_w.push(0.0);
        r.winding_loss_w.push(winding_loss);
        r.source_energy_j.push(0.0);
        r.eddy_energy_j.push(0.0);
        r.newton_iterations.push(0);
    }

    /// An accepted step: coil currents, flux linkages and voltages, losses and energies.
    fn record_step(&mut self, dynamics: &Dynamics, level: &Level<'_>) {
        let lambda = level.auxiliary;
        let (mut source_energy, mut winding_loss) = (0.0, 0.0);
        for (k, coil) in dynamics.coils.iter().enumerate() {
            let drive = step_drive(coil, level.t, level.rate, level.auxiliary_history[k]);
            let current = drive.current(lambda[k]);
            let trace = &mut self.result.coils[k];
            let previous = trace.flux_linkage_wb[trace.flux_linkage_wb.len() - 1];
            source_energy += current * (lambda[k] - previous);
            let voltage = match drive {
                StepDrive::Current(_) => level.auxiliary_derivative(k),
                StepDrive::Circuit { voltage, resistance, .. } => {
                    winding_loss += resistance * current * current;
                    voltage
                }
            };
            trace.current_a.push(current);
            trace.flux_linkage_wb.push(lambda[k]);
            trace.voltage_v.push(voltage);
        }
        self.rate = level.derivative();
        let eddy = dynamics.eddy_loss(&self.rate);
        let r = &mut self.result;
        r.eddy_loss_w.push(eddy);
        r.winding_loss_w.push(winding_loss);
        r.source_energy_j.push(r.source_energy_j[r.source_energy_j.len() - 1] + source_energy);
        r.eddy_energy_j.push(r.eddy_energy_j[r.eddy_energy_j.len() - 1] + level.dt * eddy);
        r.newton_iterations.push(level.newton_iterations);
    }

    /// Time, probes, stored energy and snapshots of a level.
    fn record_field(
        &mut self,
        dynamics: &Dynamics,
        level: &Level<'_>,
    ) -> Result<(), MagneticsError> {
        self.result.time_s.push(level.t);
        let options = self.options;
        if !options.probes.is_empty() || options.energy || !options.force_regions.is_empty() {
            let solution = dynamics.solution(level.u.to_vec());
            if self.force_layers.len() < options.force_regions.len() {
                self.force_layers = (options.force_regions.iter())
                    .map(|&tag| dynamics.solver.force_layer(&[tag]))
                    .collect::<Result<_, _>>()?;
            }
            for (trace, layer) in self.result.forces.iter_mut().zip(&self.force_layers) {
                let force = dynamics.solver.layer_axial_force(layer, &[(&solution, 1.0)]);
                trace.force_z_n.push(force);
            }
            for (trace, probe) in self.result.probes.iter_mut().zip(&options.probes) {
                let b = dynamics.solver.b_at(&solution, probe.point)?;
                trace.b_r_t.push(b.b_r_t);
                trace.b_z_t.push(b.b_z_t);
            }
            if options.energy {
                self.result.stored_energy_j.push(dynamics.solver.energy(&solution).0);
            }
        }
        while let Some(&t) = options.snapshot_times_s.get(self.next_snapshot) {
            if level.t < t * (1.0 - 1e-12) {
                break;
            }
            self.result.snapshots.push((level.t, level.u.to_vec()));
            self.next_snapshot += 1;
        }
        Ok(())
    }
}
