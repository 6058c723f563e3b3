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
use super::brake::{BrakeModel, BrakeState, TorqueLag};
use super::device::{DeviceKind, DeviceParameters, encoder_counts};
use super::hand::HandModel;
use super::metrics::{MetricsAccumulator, Sample, WallMetrics};
use super::prototype::prototype_model;
use super::scenario::Scenario;
use crate::SimError;

/// Everything that defines one haptic run.
#[derive(Debug, Clone, Copy, PartialEq)]
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
    /// The plant's brakes (brake 1 resists positive motion, brake 2 negative).
    pub brakes: [BrakeModel; 2],
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
                BrakeModel { branches: model, lag: TorqueLag::BRAKE_1 },
                BrakeModel { branches: model, lag: TorqueLag::BRAKE_2 },
            ],
            controller_models: [model, model],
            control_period_s: 1e-3,
            substeps: 10,
            velocity_cutoff_hz: 200.0,
            branch_deadband_nm: 0.005,
        }
    }

    /// Checks every number; the error names the field and the allowed range.
    pub fn validate(&self) -> Result<(), SimError> {
        let check = |field: &str, value: f64, min: f64, max: f64| {
            if value.is_finite() && value >= min && value <= max {
                Ok(())
            } else {
                Err(SimError::Input(format!("haptic: {field} = {value} is outside [{min}, {max}]")))
            }
        };
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
    let d = &config.device_parameters;
    let hand = &config.hand;
    let period = config.control_period_s;
    let dt = period / f64::from(config.substeps);
    let inertia = d.inertia_kg_m2 + hand.inertia_kg_m2();
    let hand_k = hand.stiffness_nm_per_rad();
    let hand_b = hand.damping_nms_per_rad();
    let implicit_inertia = inertia + dt * (d.viscous_nms_per_rad + hand_b);

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
    .map_err(|e| SimError::Input(format!("haptic controller: {e}")))?;
    let estimator = VelocityEstimator::new(period, config.velocity_cutoff_hz)
        .ok_or_else(|| SimError::Input("haptic: invalid velocity estimator settings".into()))?;
    let lags = [config.brakes[0].lag.discretise(dt), config.brakes[1].lag.discretise(dt)];
    // Which brakes exist on the shaft.
    let brake_present = match config.device {
        DeviceKind::Conventional => [true, false],
        DeviceKind::Bidirectional => [true, true],
        DeviceKind::Motor => [false, false],
    };

    let mut control_state = ControllerState::default();
    let mut velocity_state = VelocityState::default();
    let mut brakes: [BrakeState; 2] =
        [config.brakes[0].rest_state(), config.brakes[1].rest_state()];
    let mut angle = config.scenario.start_angle_rad();
    let mut velocity = 0.0;
    // Free-motion drag against outward (negative) motion: the brake coupled for negative motion at
    // rest current, plus bearing friction.
    let outward_drag = d.coulomb_nm
        + match config.device {
            DeviceKind::Conventional => brakes[0].lag[0],
            DeviceKind::Bidirectional => brakes[1].lag[0],
            DeviceKind::Motor => 0.0,
        };
    let mut metrics = MetricsAccumulator::new(outward_drag);
    let withdraw_start = config.scenario.withdraw_start_s();
    let side = WallSide::Positive;
    let ticks = (config.duration_s / period).round() as u64;
    let mut trace = if record { Some(Trace::default()) } else { None };
    let rad_per_count = controller.radians_per_count();

    for tick in 0..ticks {
        let t0 = tick as f64 * period;
        let counts = encoder_counts(angle, d.encoder_counts_per_rev);
        let measured_angle = counts as f64 * rad_per_count;
        let velocity_estimate = estimator.update(&mut velocity_state, measured_angle);
        let (wall_position, _) = config.scenario.wall_position_and_rate(t0);
        let wall = VirtualWall {
            position_rad: wall_position,
            side,
            stiffness_nm_per_rad: config.wall_stiffness_nm_per_rad,
            damping_nms_per_rad: config.wall_damping_nms_per_rad,
            field_damping_nms_per_rad: 0.0,
        };
        let mut current = [0.0; 2];
        let mut motor_torque = 0.0;
        if config.device == DeviceKind::Motor {
            let limit = d.motor_torque_max_nm;
            motor_torque =
                wall.ideal_torque_nm(measured_angle, velocity_estimate).clamp(-limit, limit);
        } else {
            // The controller's encoder counts are relative to its own zero: the same reference here.
            let output = controller.step(
                &mut control_state,
                &ControlInput { encoder_counts: counts, velocity_rad_s: velocity_estimate, wall },
            );
            current = output.current_a;
        }
        metrics.add_currents(current);
        for k in 0..2 {
            if brake_present[k] {
                config.brakes[k].apply_current(&mut brakes[k], current[k]);
            }
        }

        let mut actuator_sum = 0.0;
        let mut device_sum = 0.0;
        let mut hand_sum = 0.0;
        for sub in 0..config.substeps {
            let t = t0 + f64::from(sub) * dt;
            let mut capacity = [0.0; 2];
            for k in 0..2 {
                if brake_present[k] {
                    lags[k].advance(&mut brakes[k].lag, brakes[k].static_torque_nm);
                    capacity[k] = brakes[k].lag[0].max(0.0);
                }
            }
            let (intended, intended_rate) = config.scenario.intended(t + dt);
            let explicit_hand = hand_k * (intended - angle) + hand_b * intended_rate;
            let free =
                (inertia * velocity + dt * (explicit_hand + motor_torque)) / implicit_inertia;
            let (resist_positive, resist_negative) = match config.device {
                DeviceKind::Conventional => (capacity[0], capacity[0]),
                DeviceKind::Bidirectional => (capacity[0], capacity[1]),
                DeviceKind::Motor => (0.0, 0.0),
            };
            let step = friction_step(
                free,
                resist_positive + d.coulomb_nm,
                resist_negative + d.coulomb_nm,
                implicit_inertia,
                dt,
            );
            velocity = step.velocity_rad_s;
            angle += dt * velocity;
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
            let hand_torque = explicit_hand - hand_b * velocity;
            let (wall_now, _) = config.scenario.wall_position_and_rate(t + dt);
            metrics.add(
                &Sample {
                    time_s: t + dt,
                    penetration_rad: side.sign() * (angle - wall_now),
                    side: side.sign(),
                    angle_rad: angle,
                    velocity_rad_s: velocity,
                    device_torque_nm: device_torque,
                    hand_torque_nm: hand_torque,
                },
                dt,
                withdraw_start,
            );
            actuator_sum += actuator_torque;
            device_sum += device_torque;
            hand_sum += hand_torque;
        }
        if let Some(trace) = trace.as_mut() {
            let n = f64::from(config.substeps);
            let t1 = t0 + period;
            let (wall_now, _) = config.scenario.wall_position_and_rate(t1);
            trace.time_s.push(t1);
            trace.angle_rad.push(angle);
            trace.intended_rad.push(config.scenario.intended(t1).0);
            trace.wall_rad.push(wall_now);
            for k in 0..2 {
                trace.current_a[k].push(current[k]);
                trace.capacity_nm[k].push(if brake_present[k] {
                    brakes[k].lag[0].max(0.0)
                } else {
                    0.0
                });
            }
            trace.actuator_torque_nm.push(actuator_sum / n);
            trace.device_torque_nm.push(device_sum / n);
            trace.hand_torque_nm.push(hand_sum / n);
            trace.ideal_wall_torque_nm.push(
                VirtualWall { position_rad: wall_now, ..wall }.ideal_torque_nm(angle, velocity),
            );
        }
    }
    Ok(HapticRun {
        metrics: metrics.finish(
            config.device.name(),
            config.scenario.name(),
            control_state.fault_count(),
        ),
        trace,
    })
}
