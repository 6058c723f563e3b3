//! Z-width: which virtual stiffness / damping pairs a device renders passively or stably.
//!
//! For a sampled wall `τ_k = −(K p_k + B v_k)` (zero-order hold, backward-difference velocity
//! `v_k = (p_k − p_{k−1})/T`) on a device with physical damping `b`, Colgate & Brown (1994) give the
//! passivity condition (thesis (2.2)) `b > K·T/2 + B`. A controllable MR damper adds a physical damping
//! `b_c(H)` (thesis (2.3)/(2.4), An & Kwon): `b + b_c(H) > K·T/2 + B`.
//!
//! Each pair is classified by simulation, independent of the formulas:
//! - **Passive** — the device never supplies net energy under the worst-case test motions: the shaft is
//!   driven through sampled sinusoids `p_k = p₀ + A sin(Ω k T)` (11 frequencies from 1/1000 to
//!   499/1000 of the sample rate, whole periods) with constant velocity between samples, the motion
//!   that minimises the physical dissipation `b ∫ṗ² dt` for given samples (Colgate & Schenkel 1997).
//!   The energy the device delivers, `Σ τ_k Δp_{k+1} − b Σ Δp²/T`, must be ≤ 0 at every frequency.
//! - **Stable** — not passive, but the free response of the device alone (inertia `J`, damping `b`,
//!   the wall engaged, released from 0.01 rad without a hand: the worst case, since a hand adds
//!   damping) loses energy: the stored energy `½Jω² + ½Kp²` in the last 50 ms of a 0.5 s run is below
//!   its initial value.
//! - **Unstable** — otherwise.
//!
//! Three devices: **motor** (an ideal torque source; physical damping `b`), **hybrid** (the same motor
//! plus an MR damper contributing `b_c`, modelled as the continuous viscous damper that (2.4) assumes),
//! and **brake** (the bidirectional MR brake with the controller of `mrbrake-control`, hysteresis and
//! lag; it can only resist motion, so its measured energy is never positive and every pair is passive
//! — the brake's limit is what it can render, not stability).

use mrbrake_control::{
    BrakeLayout, ControlInput, ControllerState, DirectionalController, InputLimits,
    VelocityEstimator, VelocityState, VirtualWall, WallSide,
};
use mrbrake_observe::{Count, Observer};
use serde::Serialize;

use super::brake::BrakePlant;
use super::check_range;
use super::device::encoder_counts;
use super::prototype::prototype_model;
use crate::SimError;

/// Classification of one (K, B) pair.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Interaction {
    /// The device never supplies net energy.
    Passive,
    /// Not passive, but the free response decays.
    Stable,
    /// The free response grows.
    Unstable,
}

impl Interaction {
    /// Lower-case name.
    pub fn name(self) -> &'static str {
        match self {
            Self::Passive => "passive",
            Self::Stable => "stable",
            Self::Unstable => "unstable",
        }
    }
}

/// Settings of a sweep.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ZWidthConfig {
    /// Largest virtual stiffness, Nm/rad (the grid starts at 0).
    pub stiffness_max_nm_per_rad: f64,
    /// Stiffness grid points (≥ 2).
    pub stiffness_points: usize,
    /// Largest virtual damping, Nm·s/rad (the grid starts at 0).
    pub damping_max_nms_per_rad: f64,
    /// Damping grid points (≥ 2).
    pub damping_points: usize,
    /// Sample period `T`, s.
    pub sample_period_s: f64,
    /// Physical damping of the device `b`, Nm·s/rad.
    pub physical_damping_nms_per_rad: f64,
    /// Controllable damping of the MR damper in the hybrid device `b_c`, Nm·s/rad.
    pub controllable_damping_nms_per_rad: f64,
    /// Device inertia `J`, kg·m².
    pub inertia_kg_m2: f64,
}

impl Default for ZWidthConfig {
    /// 50 × 50 grid, K ≤ 100 Nm/rad, B ≤ 0.05 Nm·s/rad, T = 1 ms, b = 0.005 Nm·s/rad (the haptic
    /// device's default), b_c = 0.05 Nm·s/rad, J = 54.8 kg·mm² (thesis §4.3).
    fn default() -> Self {
        Self {
            stiffness_max_nm_per_rad: 100.0,
            stiffness_points: 50,
            damping_max_nms_per_rad: 0.05,
            damping_points: 50,
            sample_period_s: 1e-3,
            physical_damping_nms_per_rad: 0.005,
            controllable_damping_nms_per_rad: 0.05,
            inertia_kg_m2: 54.8e-6,
        }
    }
}

/// One grid cell.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ZWidthCell {
    /// Virtual stiffness `K`, Nm/rad.
    pub stiffness_nm_per_rad: f64,
    /// Virtual damping `B`, Nm·s/rad.
    pub damping_nms_per_rad: f64,
    /// Motor device, simulated.
    pub motor: Interaction,
    /// (2.2) predicts the motor device passive: `b > K T/2 + B`.
    pub motor_predicted_passive: bool,
    /// Largest net energy the motor device supplied over the test motions, J (≤ 0: passive).
    #[serde(rename = "motor_energy_J")]
    pub motor_energy_j: f64,
    /// Hybrid device (motor + MR damper `b_c`), simulated.
    pub hybrid: Interaction,
    /// (2.4) predicts the hybrid device passive: `b + b_c > K T/2 + B`.
    pub hybrid_predicted_passive: bool,
    /// Bidirectional MR brake device, simulated.
    pub brake: Interaction,
    /// Largest net energy the brake device supplied over its test motions, J.
    #[serde(rename = "brake_energy_J")]
    pub brake_energy_j: f64,
}

/// A map: every cell of the grid, or the finished stiffness rows of a stopped sweep.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ZWidthMap {
    /// The sweep settings.
    pub config: ZWidthConfig,
    /// Cells, stiffness-major (`damping_points` per stiffness row).
    pub cells: Vec<ZWidthCell>,
    /// True when the observer stopped the sweep: `cells` then holds the first
    /// `cells.len() / damping_points` stiffness rows only.
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub stopped: bool,
}

impl ZWidthMap {
    /// CSV with one row per cell.
    pub fn to_csv(&self) -> String {
        use std::fmt::Write;
        let mut out = String::from(
            "stiffness_Nm_per_rad,damping_Nms_per_rad,motor,motor_predicted_passive_2_2,motor_energy_J,\
             hybrid,hybrid_predicted_passive_2_4,brake,brake_energy_J\n",
        );
        for c in &self.cells {
            let _ = writeln!(
                out,
                "{},{},{},{},{:.6e},{},{},{},{:.6e}",
                c.stiffness_nm_per_rad,
                c.damping_nms_per_rad,
                c.motor.name(),
                c.motor_predicted_passive,
                c.motor_energy_j,
                c.hybrid.name(),
                c.hybrid_predicted_passive,
                c.brake.name(),
                c.brake_energy_j,
            );
        }
        out
    }
}

/// Test frequencies as multiples of `f_s / SAMPLES_PER_WINDOW`.
const TEST_CYCLES: [u32; 11] = [1, 3, 10, 30, 100, 200, 300, 400, 450, 490, 499];
/// Samples per test window (whole periods of every test frequency).
const SAMPLES_PER_WINDOW: u32 = 1000;
/// Test amplitude and offset, rad (the shaft stays inside the wall).
const TEST_AMPLITUDE_RAD: f64 = 0.01;

/// Position of the test motion at sample `k` for `cycles` periods per window.
fn test_position(k: i64, cycles: u32) -> f64 {
    let phase =
        core::f64::consts::TAU * f64::from(cycles) * k as f64 / f64::from(SAMPLES_PER_WINDOW);
    TEST_AMPLITUDE_RAD * (2.0 + phase.sin())
}

/// Largest net energy (J) a motor-rendered wall with physical damping `b` supplies over the test
/// motions. Uses the controller crate's wall and velocity estimator, so it tests the code that runs.
pub fn motor_test_energy(k: f64, b_virtual: f64, b_physical: f64, period_s: f64) -> f64 {
    let wall = wall(k, b_virtual);
    let estimator = VelocityEstimator::new(period_s, 0.0).expect("positive period");
    let mut worst = f64::NEG_INFINITY;
    for cycles in TEST_CYCLES {
        let mut state = VelocityState::default();
        estimator.update(&mut state, test_position(-1, cycles));
        let mut energy = 0.0;
        for n in 0..i64::from(SAMPLES_PER_WINDOW) {
            let p = test_position(n, cycles);
            let v = estimator.update(&mut state, p);
            let torque = wall.ideal_torque_nm(p, v);
            let step = test_position(n + 1, cycles) - p;
            // Constant velocity over the hold: actuator work τ·Δp, physical dissipation b Δp²/T.
            energy += torque * step - b_physical * step * step / period_s;
        }
        worst = worst.max(energy);
    }
    worst
}

/// Largest net energy (J) the bidirectional brake device supplies over the test motions (three
/// frequencies), with the real controller, hysteresis and lag, substepped 10× per sample.
pub fn brake_test_energy(
    k: f64,
    b_virtual: f64,
    b_physical: f64,
    period_s: f64,
    brakes: &[BrakePlant; 2],
) -> f64 {
    let wall = wall(k, b_virtual);
    let controller = DirectionalController::new(
        BrakeLayout::Bidirectional,
        [brakes[0].branches, brakes[1].branches],
        brakes[0].branches.current_max_a().min(brakes[1].branches.current_max_a()),
        80_000,
        InputLimits::default(),
        0.005,
    )
    .expect("prototype models are valid");
    let estimator = VelocityEstimator::new(period_s, 0.0).expect("positive period");
    let substeps = 10;
    let dt = period_s / f64::from(substeps);
    let lags = [brakes[0].lag.discretise(dt), brakes[1].lag.discretise(dt)];
    let mut worst = f64::NEG_INFINITY;
    for cycles in [1, 30, 499] {
        let mut control = ControllerState::default();
        let mut velocity_state = VelocityState::default();
        let mut states = [brakes[0].rest_state(), brakes[1].rest_state()];
        estimator.update(&mut velocity_state, test_position(-1, cycles));
        let mut energy = 0.0;
        for n in 0..i64::from(SAMPLES_PER_WINDOW) {
            let p = test_position(n, cycles);
            let counts = encoder_counts(p, 80_000);
            let measured = counts as f64 * controller.radians_per_count();
            let v = estimator.update(&mut velocity_state, measured);
            let out = controller.step(
                &mut control,
                &ControlInput { encoder_counts: counts, velocity_rad_s: v, wall },
            );
            for j in 0..2 {
                brakes[j].apply_current(&mut states[j], out.current_a[j]);
            }
            let step = (test_position(n + 1, cycles) - p) / f64::from(substeps);
            for _ in 0..substeps {
                for j in 0..2 {
                    lags[j].advance(&mut states[j].lag, states[j].static_torque_nm);
                }
                // Brake 1 resists positive motion, brake 2 negative (one-way bearings).
                let capacity = if step > 0.0 { states[0].lag[0] } else { states[1].lag[0] };
                energy += -capacity.max(0.0) * step.abs() - b_physical * step * step / dt;
            }
        }
        worst = worst.max(energy);
    }
    worst
}

/// The test wall: at 0 rad on the positive side (the test motions stay inside it).
fn wall(k: f64, b: f64) -> VirtualWall {
    VirtualWall::new(0.0, WallSide::Positive, k, b)
}

/// Free response of the device alone with the sampled wall engaged: true when it loses energy.
pub fn free_response_decays(
    k: f64,
    b_virtual: f64,
    b_physical: f64,
    inertia: f64,
    period_s: f64,
) -> bool {
    let substeps = 10;
    let dt = period_s / f64::from(substeps);
    let estimator = VelocityEstimator::new(period_s, 0.0).expect("positive period");
    let mut state = VelocityState::default();
    let (mut p, mut w) = (0.01, 0.0);
    let stored = |p: f64, w: f64| 0.5 * inertia * w * w + 0.5 * k * p * p;
    let initial = stored(p, w).max(1e-12);
    let ticks = (0.5 / period_s).round() as u64;
    let tail = (0.05 / period_s).round() as u64;
    let mut tail_max: f64 = 0.0;
    estimator.update(&mut state, p);
    for tick in 0..ticks {
        let v = estimator.update(&mut state, p);
        // Linear wall on both sides of the surface (engaged throughout).
        let torque = -(k * p + b_virtual * v);
        for _ in 0..substeps {
            // Velocity exact for constant torque (J ẇ = τ − b w); position by the trapezoidal rule
            // (second order: a first-order position update misstates the loop gain by ~10 % here).
            let previous = w;
            w = if b_physical > 0.0 {
                let decay = (-b_physical * dt / inertia).exp();
                decay * w + (1.0 - decay) * torque / b_physical
            } else {
                w + dt * torque / inertia
            };
            p += 0.5 * dt * (previous + w);
        }
        if !(p.is_finite() && w.is_finite()) || stored(p, w) > 1e6 * initial {
            return false;
        }
        if tick + tail >= ticks {
            tail_max = tail_max.max(stored(p, w));
        }
    }
    tail_max < initial
}

/// Runs the sweep, calling `observer` with the stiffness rows done ([`Count`]) after each row of
/// the grid (for a front end's progress display on long sweeps). [`Flow::Stop`] ends the sweep
/// after that row: the map then holds the finished rows and [`ZWidthMap::stopped`] is set.
///
/// [`Flow::Stop`]: mrbrake_observe::Flow::Stop
pub fn sweep(
    config: &ZWidthConfig,
    observer: &mut impl Observer<Count>,
) -> Result<ZWidthMap, SimError> {
    check_config(config)?;
    let model = prototype_model();
    let brakes = [
        BrakePlant::clamp(model, super::brake::TorqueLag::BRAKE_1),
        BrakePlant::clamp(model, super::brake::TorqueLag::BRAKE_2),
    ];
    let mut cells = Vec::with_capacity(config.stiffness_points * config.damping_points);
    let total = config.stiffness_points;
    let mut stopped = false;
    for i in 0..total {
        let k = config.stiffness_max_nm_per_rad * i as f64 / (total - 1) as f64;
        for j in 0..config.damping_points {
            let bv = config.damping_max_nms_per_rad * j as f64 / (config.damping_points - 1) as f64;
            cells.push(cell(config, &brakes, k, bv));
        }
        let done = i + 1;
        if observer.observe(&Count { done, total }).is_stop() && done < total {
            stopped = true;
            break;
        }
    }
    Ok(ZWidthMap { config: *config, cells, stopped })
}

/// Checks the ranges of every setting.
fn check_config(config: &ZWidthConfig) -> Result<(), SimError> {
    let check = |field, value, min, max| check_range("zwidth", field, value, min, max);
    check("stiffness_max_nm_per_rad", config.stiffness_max_nm_per_rad, 1e-9, 1e6)?;
    check("damping_max_nms_per_rad", config.damping_max_nms_per_rad, 0.0, 1e3)?;
    check("stiffness_points", config.stiffness_points as f64, 2.0, 1000.0)?;
    check("damping_points", config.damping_points as f64, 2.0, 1000.0)?;
    check("sample_period_s", config.sample_period_s, 1e-6, 0.1)?;
    check("physical_damping_nms_per_rad", config.physical_damping_nms_per_rad, 0.0, 1e3)?;
    check("controllable_damping_nms_per_rad", config.controllable_damping_nms_per_rad, 0.0, 1e3)?;
    check("inertia_kg_m2", config.inertia_kg_m2, 1e-12, 1e3)
}

/// The motor device with physical damping `b_phys` classified at (K, B) = (`k`, `bv`), and the
/// largest energy it supplied over the test motions.
fn classify_motor(config: &ZWidthConfig, k: f64, bv: f64, b_phys: f64) -> (Interaction, f64) {
    let t = config.sample_period_s;
    let energy = motor_test_energy(k, bv, b_phys, t);
    // Round-off allowance: 1e-12 of the stored-energy scale of the test.
    let passive = energy <= 1e-12 * (1.0 + k) * TEST_AMPLITUDE_RAD * TEST_AMPLITUDE_RAD;
    let class = if passive {
        Interaction::Passive
    } else if free_response_decays(k, bv, b_phys, config.inertia_kg_m2, t) {
        Interaction::Stable
    } else {
        Interaction::Unstable
    };
    (class, energy)
}

/// One cell of the grid: the three devices at (K, B) = (`k`, `bv`).
fn cell(config: &ZWidthConfig, brakes: &[BrakePlant; 2], k: f64, bv: f64) -> ZWidthCell {
    let t = config.sample_period_s;
    let b = config.physical_damping_nms_per_rad;
    let b_hybrid = b + config.controllable_damping_nms_per_rad;
    let (motor, motor_energy_j) = classify_motor(config, k, bv, b);
    let (hybrid, _) = classify_motor(config, k, bv, b_hybrid);
    let brake_energy_j = brake_test_energy(k, bv, b, t, brakes);
    let brake = if brake_energy_j <= 0.0 {
        Interaction::Passive
    } else if free_response_decays(k, bv, b, config.inertia_kg_m2, t) {
        Interaction::Stable
    } else {
        Interaction::Unstable
    };
    ZWidthCell {
        stiffness_nm_per_rad: k,
        damping_nms_per_rad: bv,
        motor,
        motor_predicted_passive: b > k * t / 2.0 + bv,
        motor_energy_j,
        hybrid,
        hybrid_predicted_passive: b_hybrid > k * t / 2.0 + bv,
        brake,
        brake_energy_j,
    }
}
