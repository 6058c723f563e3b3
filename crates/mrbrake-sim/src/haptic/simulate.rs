//! The haptic loop: controller at 1 kHz with zero-order hold, plant on a finer step.
//!
//! Each control tick (period `T`, 1 ms by default; thesis §2.1: haptic loops run at 1 kHz):
//! read the encoder (quantised angle), estimate the velocity, run the controller (brake devices:
//! [`mrbrake_control::DirectionalController`]; motor: the ideal wall torque
//! [`mrbrake_control::VirtualWall::ideal_torque_nm`] clipped to the motor's limit), apply the currents
//! to the brakes' hysteresis, and hold everything for `T`. Within the tick the plant advances in
//! `substeps` steps of `dt = T / substeps` (0.1 ms by default): the brakes' torque lag exactly
//! ([`super::brake`]), then the shaft + hand with
//!
//! `(J + dt(b + B_h)) ω⁺ = J ω + dt(K_h(θ_i − θ) + B_h ω_i + τ_motor) + dt τ_f`,   `θ⁺ = θ + dt ω⁺`,
//!
//! viscous terms implicit and the set-valued brake/bearing torque `τ_f` from the implicit Coulomb step
//! of [`super::bearing`] (exact sticking, one-way bearings). `J = J_device + J_hand`.

use mrbrake_control::{
    BrakeLayout, ControlInput, ControllerState, DirectionalController, InputLimits, InverseModel,
    VelocityEstimator, VelocityState, VirtualWall, WallSide,
};

use super::bearing::friction_step;
use super::brake::{BrakePlant, BrakeState, DiscreteLag, TorqueLag};
use super::check_range;
use super::device::{DeviceKind, DeviceParameters, encoder_counts};
use super::hand::HandModel;
use super::metrics::{DragAfter, MetricsAccumulator, Sample, WallMetrics};
use super::prototype::prototype_model;
use super::remanence::{PlantRemanence, RemanenceState};
use super::scenario::Scenario;
use crate::SimError;
use mrbrake_error::FieldError;

/// Everything that defines one haptic run.
#[derive(Debug, Clone, PartialEq)]
pub struct HapticConfig {
    /// The actuator.
    pub device: DeviceKind,
    /// The device's mechanics and encoder.
    pub device_parameters: DeviceParameters,
    /// The user's hand.
    pub hand: HandModel,
    /// What the user does.
    pub scenario: Scenario,
    /// Run length, s.
    pub duration_s: f64,
    /// Virtual wall stiffness `K`, Nm/rad.
    pub wall_stiffness_nm_per_rad: f64,
    /// Virtual wall damping `B`, Nm·s/rad.
    pub wall_damping_nms_per_rad: f64,
    /// The plant's brakes (brake 1 resists positive motion, brake 2 negative; a brake with a
    /// Preisach model runs it, [`super::brake`]).
    pub brakes: [BrakePlant; 2],
    /// The inverse models the controller uses (normally the same branches as the plant).
    pub controller_models: [InverseModel; 2],
    /// Control period `T`, s.
    pub control_period_s: f64,
    /// Plant steps per control period.
    pub substeps: u32,
    /// Velocity low-pass cut-off, Hz (0: plain backward difference).
    pub velocity_cutoff_hz: f64,
    /// Demand change that switches the hysteresis branch, Nm.
    pub branch_deadband_nm: f64,
    /// The steel's predicted remanence in the plant and the controller's demagnetising release
    /// ([`super::remanence`]); `None`: the branches alone.
    pub remanence: Option<PlantRemanence>,
}

impl HapticConfig {
    /// Defaults: prototype-like brakes with the thesis's lags (5.5)/(5.6), K = 30 Nm/rad,
    /// B = 0.02 Nm·s/rad, T = 1 ms, 10 plant steps per tick, 200 Hz velocity filter.
    pub fn new(device: DeviceKind, scenario: Scenario) -> Self {
        let model = prototype_model();
        Self {
            device,
            device_parameters: DeviceParameters::default(),
            hand: HandModel::default(),
            scenario,
            duration_s: scenario.default_duration_s(),
            wall_stiffness_nm_per_rad: 30.0,
            wall_damping_nms_per_rad: 0.02,
            brakes: [
                BrakePlant::clamp(model, TorqueLag::BRAKE_1),
                BrakePlant::clamp(model, TorqueLag::BRAKE_2),
            ],
            controller_models: [model, model],
            control_period_s: 1e-3,
            substeps: 10,
            velocity_cutoff_hz: 200.0,
            branch_deadband_nm: 0.005,
            remanence: None,
        }
    }

    /// Uses `model` (a characterisation's inverse model) for both brakes, in the plant (the clamp
    /// between its branches) and in the controller, instead of the built-in prototype-like branches.
    pub fn use_inverse_model(&mut self, model: InverseModel) {
        for brake in &mut self.brakes {
            brake.branches = model;
            brake.preisach = None;
        }
        self.controller_models = [model, model];
    }

    /// Checks every number; the error names the field and the allowed range.
    pub fn validate(&self) -> Result<(), SimError> {
        let check = |field: &str, value, min, max| check_range("haptic", field, value, min, max);
        check("duration_s", self.duration_s, 1e-3, 3600.0)?;
        check("wall_stiffness_nm_per_rad", self.wall_stiffness_nm_per_rad, 0.0, 1e5)?;
        check("wall_damping_nms_per_rad", self.wall_damping_nms_per_rad, 0.0, 100.0)?;
        check("control_period_s", self.control_period_s, 1e-5, 0.1)?;
        check("substeps", f64::from(self.substeps), 1.0, 1000.0)?;
        check("velocity_cutoff_hz", self.velocity_cutoff_hz, 0.0, 1e6)?;
        check("branch_deadband_nm", self.branch_deadband_nm, 0.0, 100.0)?;
        let d = &self.device_parameters;
        check("device.inertia_kg_m2", d.inertia_kg_m2, 1e-9, 100.0)?;
        check("device.viscous_nms_per_rad", d.viscous_nms_per_rad, 0.0, 100.0)?;
        check("device.coulomb_nm", d.coulomb_nm, 0.0, 100.0)?;
        check("device.encoder_counts_per_rev", f64::from(d.encoder_counts_per_rev), 1.0, 1e9)?;
        check("device.motor_torque_max_nm", d.motor_torque_max_nm, 0.0, 1e4)?;
        let h = &self.hand;
        check("hand.mass_kg", h.mass_kg, 0.0, 100.0)?;
        check("hand.damping_ns_per_m", h.damping_ns_per_m, 0.0, 1e4)?;
        check("hand.stiffness_n_per_m", h.stiffness_n_per_m, 0.0, 1e6)?;
        check("hand.lever_arm_m", h.lever_arm_m, 1e-3, 10.0)?;
        for (k, brake) in self.brakes.iter().enumerate() {
            check(&format!("brakes[{k}].lag.gain"), brake.lag.gain, 0.0, 10.0)?;
            check(&format!("brakes[{k}].lag.a_s2"), brake.lag.a_s2, 1e-12, 10.0)?;
            check(&format!("brakes[{k}].lag.b_s"), brake.lag.b_s, 0.0, 10.0)?;
        }
        if let Some(r) = &self.remanence {
            check("remanence.remanent_torque_nm", r.remanent_torque_nm, 0.0, 1e3)?;
            check("remanence.reference_peak_a", r.reference_peak_a, 1e-9, 100.0)?;
            if let Some(release) = &r.release {
                let fraction = release.remanence_fraction;
                check("remanence.release.remanence_fraction", fraction, 0.0, 1.0)?;
            } else if self.brakes.iter().any(|b| b.preisach.is_some()) {
                return Err(FieldError::new(
                    "remanence",
                    "the brake's Preisach table already holds the remanence (its torque at 0 A \
                     after a peak); a predicted remanence without a demagnetising release would \
                     add it twice",
                )
                .with_allowed("no remanence, or a remanence with its release (the table magnetises, the release model demagnetises)")
                .into());
            }
        }
        Ok(())
    }
}

/// Time histories at the control rate (one row per tick, values at the end of the tick; torques are
/// tick averages).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Trace {
    /// Time, s.
    pub time_s: Vec<f64>,
    /// Handle angle, rad.
    pub angle_rad: Vec<f64>,
    /// Intended angle of the hand, rad.
    pub intended_rad: Vec<f64>,
    /// Wall surface position, rad.
    pub wall_rad: Vec<f64>,
    /// Coil currents of brake 1 and brake 2, A.
    pub current_a: [Vec<f64>; 2],
    /// Torque capacity of brake 1 and brake 2 after the lag, Nm.
    pub capacity_nm: [Vec<f64>; 2],
    /// Torque of the actuator on the shaft (brakes or motor), Nm.
    pub actuator_torque_nm: Vec<f64>,
    /// Total device torque on the shaft (actuator + friction), Nm.
    pub device_torque_nm: Vec<f64>,
    /// Hand torque on the shaft, Nm.
    pub hand_torque_nm: Vec<f64>,
    /// Torque the ideal wall would render at the true angle and velocity, Nm.
    pub ideal_wall_torque_nm: Vec<f64>,
}

impl Trace {
    /// The trace as CSV text with a header naming the units.
    pub fn to_csv(&self) -> String {
        let mut out = String::from(
            "time_s,angle_rad,intended_rad,wall_rad,current1_A,current2_A,capacity1_Nm,capacity2_Nm,\
             actuator_torque_Nm,device_torque_Nm,hand_torque_Nm,ideal_wall_torque_Nm\n",
        );
        for k in 0..self.time_s.len() {
            use std::fmt::Write;
            let _ = writeln!(
                out,
                "{:.4},{:.7},{:.7},{:.7},{:.5},{:.5},{:.5},{:.5},{:.5},{:.5},{:.5},{:.5}",
                self.time_s[k],
                self.angle_rad[k],
                self.intended_rad[k],
                self.wall_rad[k],
                self.current_a[0][k],
                self.current_a[1][k],
                self.capacity_nm[0][k],
                self.capacity_nm[1][k],
                self.actuator_torque_nm[k],
                self.device_torque_nm[k],
                self.hand_torque_nm[k],
                self.ideal_wall_torque_nm[k],
            );
        }
        out
    }
}

/// The result of a run.
#[derive(Debug, Clone, PartialEq)]
pub struct HapticRun {
    /// The measures.
    pub metrics: WallMetrics,
    /// Time histories, when requested.
    pub trace: Option<Trace>,
}

/// Runs one haptic interaction. `record` keeps the time histories (off for benchmarks and sweeps).
pub fn simulate(config: &HapticConfig, record: bool) -> Result<HapticRun, SimError> {
    config.validate()?;
    let haptic_loop = HapticLoop::new(config)?;
    // The controller's state and the plant's are separate locals: the plant's never leaves this
    // function (every method that touches it is inlined), so it stays in registers.
    let mut control = ControlState::default();
    let mut plant = haptic_loop.rest_state();
    let mut metrics = MetricsAccumulator::new(haptic_loop.outward_drag_nm(&plant));
    let period = config.control_period_s;
    let ticks = (config.duration_s / period).round() as u64;
    let mut trace = if record { Some(Trace::default()) } else { None };
    for tick in 0..ticks {
        let t0 = tick as f64 * period;
        let command = haptic_loop.control(t0, &mut control, &mut plant);
        metrics.add_currents(command.current_a);
        let sums = haptic_loop.hold(t0, &command, &mut plant, &mut metrics);
        if let Some(trace) = trace.as_mut() {
            haptic_loop.record(trace, t0 + period, &command, &plant, sums);
        }
    }
    Ok(HapticRun {
        metrics: metrics.finish(
            config.device.name(),
            config.scenario.name(),
            control.controller.fault_count(),
            haptic_loop.drag(&plant),
        ),
        trace,
    })
}

/// What one control tick commands, held for the tick.
struct Command {
    /// The wall rendered this tick.
    wall: VirtualWall,
    /// Coil currents of brake 1 and brake 2, A.
    current_a: [f64; 2],
    /// Motor torque (motor device), Nm.
    motor_torque_nm: f64,
}

/// Sums of the actuator, device and hand torques over a tick's plant steps, Nm.
#[derive(Clone, Copy, Default)]
struct TorqueSums {
    actuator_nm: f64,
    device_nm: f64,
    hand_nm: f64,
}

/// The closed loop of one run: the configuration and its derived constants (the states are
/// [`ControlState`] and [`PlantState`]).
struct HapticLoop<'a> {
    config: &'a HapticConfig,
    controller: DirectionalController,
    estimator: VelocityEstimator,
    lags: [DiscreteLag; 2],
    /// Which brakes exist on the shaft.
    brake_present: [bool; 2],
    /// Plant step `dt = T / substeps`, s.
    dt_s: f64,
    /// `J = J_device + J_hand`, kg·m².
    inertia: f64,
    /// `J + dt (b + B_h)`, the implicit step's inertia.
    implicit_inertia: f64,
    hand_k: f64,
    hand_b: f64,
    /// The scenario's start of the withdrawal, s.
    withdraw_start_s: Option<f64>,
}

/// The state of the controller and its velocity estimator.
#[derive(Default)]
struct ControlState {
    controller: ControllerState,
    velocity: VelocityState,
}

/// The state of the brakes and the shaft.
#[derive(Clone)]
struct PlantState {
    brakes: [BrakeState; 2],
    remanence: [RemanenceState; 2],
    angle_rad: f64,
    velocity_rad_s: f64,
}

impl<'a> HapticLoop<'a> {
    /// The loop at rest at the scenario's start angle.
    fn new(config: &'a HapticConfig) -> Result<Self, SimError> {
        let d = &config.device_parameters;
        let hand = &config.hand;
        let period = config.control_period_s;
        let dt_s = period / f64::from(config.substeps);
        let inertia = d.inertia_kg_m2 + hand.inertia_kg_m2();
        let hand_b = hand.damping_nms_per_rad();
        let layout = match config.device {
            DeviceKind::Conventional => BrakeLayout::Conventional,
            _ => BrakeLayout::Bidirectional,
        };
        let current_max_a = config.controller_models[0]
            .current_max_a()
            .min(config.controller_models[1].current_max_a());
        let controller = DirectionalController::new(
            layout,
            config.controller_models,
            current_max_a,
            d.encoder_counts_per_rev,
            InputLimits::default(),
            config.branch_deadband_nm,
        )
        .map_err(|source| SimError::Control { what: "haptic controller", source })?;
        let controller = match config.remanence.as_ref().and_then(|r| r.release.as_ref()) {
            Some(release) => controller
                .with_demagnetisation(&release.settings, period)
                .map_err(|source| SimError::Control { what: "demagnetising release", source })?,
            None => controller,
        };
        let estimator =
            VelocityEstimator::new(period, config.velocity_cutoff_hz).ok_or_else(|| {
                let e = mrbrake_error::FieldError::new(
                    "velocity_cutoff_hz",
                    "haptic: invalid velocity estimator settings",
                );
                SimError::from(e.with_value(config.velocity_cutoff_hz))
            })?;
        Ok(Self {
            config,
            controller,
            estimator,
            lags: [config.brakes[0].lag.discretise(dt_s), config.brakes[1].lag.discretise(dt_s)],
            brake_present: match config.device {
                DeviceKind::Conventional => [true, false],
                DeviceKind::Bidirectional => [true, true],
                DeviceKind::Motor => [false, false],
            },
            dt_s,
            inertia,
            implicit_inertia: inertia + dt_s * (d.viscous_nms_per_rad + hand_b),
            hand_k: hand.stiffness_nm_per_rad(),
            hand_b,
            withdraw_start_s: config.scenario.withdraw_start_s(),
        })
    }

    /// The plant at rest at the scenario's start angle, the brakes at zero current.
    fn rest_state(&self) -> PlantState {
        let brakes = &self.config.brakes;
        PlantState {
            brakes: [brakes[0].rest_state(), brakes[1].rest_state()],
            remanence: [RemanenceState::default(); 2],
            angle_rad: self.config.scenario.start_angle_rad(),
            velocity_rad_s: 0.0,
        }
    }

    /// Free-motion drag against outward (negative) motion: the brake coupled for negative motion at
    /// rest current, plus bearing friction, Nm.
    fn outward_drag_nm(&self, plant: &PlantState) -> f64 {
        self.config.device_parameters.coulomb_nm
            + match self.config.device {
                DeviceKind::Conventional => plant.brakes[0].lag[0],
                DeviceKind::Bidirectional => plant.brakes[1].lag[0],
                DeviceKind::Motor => 0.0,
            }
    }

    /// Free-motion drag against either direction in the plant's present state (brake capacity and
    /// bearing friction), N·m.
    fn drag(&self, plant: &PlantState) -> DragAfter {
        let capacity = |k: usize| plant.brakes[k].lag[0].max(0.0);
        let coulomb = self.config.device_parameters.coulomb_nm;
        let (outward, inward) = match self.config.device {
            DeviceKind::Conventional => (capacity(0), capacity(0)),
            DeviceKind::Bidirectional => (capacity(1), capacity(0)),
            DeviceKind::Motor => (0.0, 0.0),
        };
        DragAfter { outward: outward + coulomb, inward: inward + coulomb }
    }

    /// The control tick at `t0`: read the encoder, estimate the velocity, run the controller (or the
    /// ideal motor wall) and apply the currents to the brakes' hysteresis.
    #[inline]
    fn control(&self, t0: f64, control: &mut ControlState, plant: &mut PlantState) -> Command {
        let config = self.config;
        let d = &config.device_parameters;
        let counts = encoder_counts(plant.angle_rad, d.encoder_counts_per_rev);
        let measured_angle = counts as f64 * self.controller.radians_per_count();
        let velocity_estimate = self.estimator.update(&mut control.velocity, measured_angle);
        let (wall_position, _) = config.scenario.wall_position_and_rate(t0);
        let wall = VirtualWall::new(
            wall_position,
            WallSide::Positive,
            config.wall_stiffness_nm_per_rad,
            config.wall_damping_nms_per_rad,
        );
        let mut current_a = [0.0; 2];
        let mut motor_torque_nm = 0.0;
        if config.device == DeviceKind::Motor {
            let limit = d.motor_torque_max_nm;
            motor_torque_nm =
                wall.ideal_torque_nm(measured_angle, velocity_estimate).clamp(-limit, limit);
        } else {
            // The controller's encoder counts are relative to its own zero: the same reference here.
            let output = self.controller.step(
                &mut control.controller,
                &ControlInput { encoder_counts: counts, velocity_rad_s: velocity_estimate, wall },
            );
            current_a = output.current_a;
        }
        for k in 0..2 {
            if !self.brake_present[k] {
                continue;
            }
            match &config.remanence {
                Some(model) => model.apply_current(
                    &config.brakes[k],
                    &mut plant.brakes[k],
                    &mut plant.remanence[k],
                    current_a[k],
                ),
                None => config.brakes[k].apply_current(&mut plant.brakes[k], current_a[k]),
            }
        }
        Command { wall, current_a, motor_torque_nm }
    }

    /// Holds `command` for the tick starting at `t0`: the plant's `substeps` steps (module docs: the
    /// brakes' lag, then the shaft and hand with the implicit Coulomb step), each added to `metrics`;
    /// returns the tick's torque sums.
    #[inline]
    fn hold(
        &self,
        t0: f64,
        command: &Command,
        plant: &mut PlantState,
        metrics: &mut MetricsAccumulator,
    ) -> TorqueSums {
        let config = self.config;
        let d = &config.device_parameters;
        let (dt, motor_torque, side) = (self.dt_s, command.motor_torque_nm, WallSide::Positive);
        let (lags, present) = (&self.lags, self.brake_present);
        let mut sums = TorqueSums::default();
        for sub in 0..config.substeps {
            let t = t0 + f64::from(sub) * dt;
            let mut capacity = [0.0; 2];
            for k in 0..2 {
                if present[k] {
                    lags[k].advance(&mut plant.brakes[k].lag, plant.brakes[k].static_torque_nm);
                    capacity[k] = plant.brakes[k].lag[0].max(0.0);
                }
            }
            let (intended, intended_rate) = config.scenario.intended(t + dt);
            let explicit_hand =
                self.hand_k * (intended - plant.angle_rad) + self.hand_b * intended_rate;
            let free = (self.inertia * plant.velocity_rad_s + dt * (explicit_hand + motor_torque))
                / self.implicit_inertia;
            let (resist_positive, resist_negative) = match config.device {
                DeviceKind::Conventional => (capacity[0], capacity[0]),
                DeviceKind::Bidirectional => (capacity[0], capacity[1]),
                DeviceKind::Motor => (0.0, 0.0),
            };
            let step = friction_step(
                free,
                resist_positive + d.coulomb_nm,
                resist_negative + d.coulomb_nm,
                self.implicit_inertia,
                dt,
            );
            let inertial_torque =
                d.inertia_kg_m2 * (step.velocity_rad_s - plant.velocity_rad_s) / dt;
            plant.velocity_rad_s = step.velocity_rad_s;
            plant.angle_rad += dt * plant.velocity_rad_s;
            let (angle, velocity) = (plant.angle_rad, plant.velocity_rad_s);
            // Share of the set-valued torque taken by the brakes (the rest is bearing friction).
            let brake_capacity =
                if step.torque_nm < 0.0 { resist_positive } else { resist_negative };
            let brake_share = if brake_capacity > 0.0 {
                brake_capacity / (brake_capacity + d.coulomb_nm)
            } else {
                0.0
            };
            let actuator_torque = step.torque_nm * brake_share + motor_torque;
            let device_torque = step.torque_nm + motor_torque - d.viscous_nms_per_rad * velocity;
            let hand_torque = explicit_hand - self.hand_b * velocity;
            let (wall_now, _) = config.scenario.wall_position_and_rate(t + dt);
            let sample = Sample {
                time_s: t + dt,
                penetration_rad: side.sign() * (angle - wall_now),
                side: side.sign(),
                angle_rad: angle,
                velocity_rad_s: velocity,
                device_torque_nm: device_torque,
                hand_torque_nm: hand_torque,
                inertial_torque_nm: inertial_torque,
            };
            metrics.add(&sample, dt, self.withdraw_start_s);
            sums.actuator_nm += actuator_torque;
            sums.device_nm += device_torque;
            sums.hand_nm += hand_torque;
        }
        sums
    }

    /// Appends the tick ending at `t1` to the trace (torques as tick averages).
    fn record(
        &self,
        trace: &mut Trace,
        t1: f64,
        command: &Command,
        plant: &PlantState,
        sums: TorqueSums,
    ) {
        let scenario = self.config.scenario;
        let n = f64::from(self.config.substeps);
        let (wall_now, _) = scenario.wall_position_and_rate(t1);
        trace.time_s.push(t1);
        trace.angle_rad.push(plant.angle_rad);
        trace.intended_rad.push(scenario.intended(t1).0);
        trace.wall_rad.push(wall_now);
        for k in 0..2 {
            trace.current_a[k].push(command.current_a[k]);
            let capacity =
                if self.brake_present[k] { plant.brakes[k].lag[0].max(0.0) } else { 0.0 };
            trace.capacity_nm[k].push(capacity);
        }
        trace.actuator_torque_nm.push(sums.actuator_nm / n);
        trace.device_torque_nm.push(sums.device_nm / n);
        trace.hand_torque_nm.push(sums.hand_nm / n);
        let wall = VirtualWall { position_rad: wall_now, ..command.wall };
        trace
            .ideal_wall_torque_nm
            .push(wall.ideal_torque_nm(plant.angle_rad, plant.velocity_rad_s));
    }
}
