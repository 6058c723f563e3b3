//! Per-run measures of the interaction, accumulated on the plant's fine step.
//!
//! With the wall on the positive side (`s = +1`), penetration `p = s·(θ − θ_wall)`, device torque
//! `τ_d` (actuator + the device's own friction) and hand torque `τ_h`:
//! - **withdrawing** is every instant with `p > 0` and the hand pulling out (`s·τ_h < 0`);
//! - **resisting torque** while withdrawing is `max(0, s·τ_d)` (the device pulling the hand back
//!   into the wall) — the sticky-wall measure; its peak and its time-mean are reported, and also its
//!   excess over the device's free-motion drag in the outward direction (the brake's off-state torque
//!   and bearing friction, felt anywhere, not only at the wall);
//! - **withdraw energy** `−∫ τ_d ω dt` over the withdrawing instants: the work the user spends
//!   against the device to get out;
//! - **release time**: from the start of the withdrawal (scenario) to the first `p ≤ 0`;
//! - **device energy** `∫ τ_d ω dt` over the run and its running maximum: a passive device never
//!   supplies net energy, `max_t ∫₀ᵗ τ_d ω ≤ 0` (Colgate & Schenkel 1997);
//! - **displayed stiffness**: least-squares slope of the felt wall torque `−s·τ_d` against `p`
//!   while the hand presses in (`s·τ_h > 0`, `p > 0`);
//! - **free-motion torque**: the peak over the free-motion instants (`p ≤ 0`) of the torque the
//!   hand exerts on the handle, `|J θ̈ − τ_d|` (Newton's second law of the device's rotating parts,
//!   inertia `J`, under the grip torque and `τ_d`): the off-state drag (brake viscous + seal
//!   friction + bearing) plus the rotor's inertia times the motion's acceleration — what makes a
//!   heavy or draggy device feel heavy where there is no wall;
//! - **drag after the run**: the device's free-motion drag against outward and inward motion at the
//!   end of the run (the brakes' torque capacity at their final current, plus bearing friction):
//!   after a wall was left, what a remanent brake still resists with ([`super::remanence`]).

use serde::Serialize;

/// Peak and mean of a torque over the withdrawing instants, Nm.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct PeakMean {
    /// Largest value, Nm.
    pub peak: f64,
    /// Time-mean, Nm.
    pub mean: f64,
}

/// The device's free-motion drag against each direction, N·m.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct DragAfter {
    /// Against outward (negative) motion, out of the wall.
    pub outward: f64,
    /// Against inward (positive) motion, toward the wall.
    pub inward: f64,
}

/// The measures of one run (JSON field names carry their units).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct WallMetrics {
    /// Device name.
    pub device: &'static str,
    /// Scenario name.
    pub scenario: &'static str,
    /// Largest penetration into the wall, rad.
    pub max_penetration_rad: f64,
    /// Felt stiffness while pressing in, Nm/rad (`None` without enough contact samples).
    #[serde(rename = "displayed_stiffness_Nm_per_rad")]
    pub displayed_stiffness_nm_per_rad: Option<f64>,
    /// Torque resisting the withdrawal (peak and mean), Nm.
    #[serde(rename = "withdraw_resisting_torque_Nm")]
    pub withdraw_resisting_torque_nm: PeakMean,
    /// Resisting torque in excess of the free-motion outward drag (peak and mean), Nm.
    #[serde(rename = "withdraw_excess_torque_Nm")]
    pub withdraw_excess_torque_nm: PeakMean,
    /// The device's free-motion drag against outward motion (off-state brake + bearing), Nm.
    #[serde(rename = "outward_drag_Nm")]
    pub outward_drag_nm: f64,
    /// Peak torque the hand exerts on the handle in free motion, `|J θ̈ − τ_d|` (module docs), Nm.
    #[serde(rename = "free_motion_torque_Nm")]
    pub free_motion_torque_nm: f64,
    /// The free-motion drag at the end of the run (module docs), N·m.
    #[serde(rename = "drag_after_Nm")]
    pub drag_after_nm: DragAfter,
    /// Work the user spends against the device while withdrawing, J.
    #[serde(rename = "withdraw_energy_J")]
    pub withdraw_energy_j: f64,
    /// Total time spent withdrawing while in contact, s.
    pub withdraw_duration_s: f64,
    /// Time from the start of the withdrawal to leaving the wall, s (`None` if never left or the
    /// scenario has no withdrawal).
    pub release_time_s: Option<f64>,
    /// Net energy supplied by the device over the run, J (≤ 0 for a passive device).
    #[serde(rename = "device_energy_J")]
    pub device_energy_j: f64,
    /// Largest running total of the energy supplied by the device, J.
    #[serde(rename = "device_energy_peak_J")]
    pub device_energy_peak_j: f64,
    /// The device supplied no net energy at any time of this run (running total ≤ 1 µJ) and the run
    /// stayed stable. A run-level check: worst-case passivity over all motions is what
    /// [`super::zwidth`] tests.
    pub passive: bool,
    /// The run stayed finite and bounded (|ω| < 100 rad/s, |θ| < 2π).
    pub stable: bool,
    /// Largest commanded coil current over the run, A (both brakes).
    #[serde(rename = "current_peak_A")]
    pub current_peak_a: f64,
    /// Controller ticks that ended in a fault.
    pub fault_ticks: u32,
}

/// Accumulates the measures sample by sample.
#[derive(Debug, Clone, Default)]
pub struct MetricsAccumulator {
    max_penetration_rad: f64,
    resisting_peak_nm: f64,
    resisting_integral_nms: f64,
    excess_peak_nm: f64,
    excess_integral_nms: f64,
    outward_drag_nm: f64,
    free_motion_peak_nm: f64,
    withdraw_time_s: f64,
    withdraw_energy_j: f64,
    device_energy_j: f64,
    device_energy_peak_j: f64,
    release_at_s: Option<f64>,
    fit: [f64; 5], // n, Σx, Σy, Σxy, Σx²
    stable: bool,
    current_peak_a: f64,
}

/// One fine-step sample.
#[derive(Debug, Clone, Copy)]
pub struct Sample {
    /// Time at the end of the step, s.
    pub time_s: f64,
    /// Penetration, rad.
    pub penetration_rad: f64,
    /// Wall side sign `s`.
    pub side: f64,
    /// Shaft angle, rad.
    pub angle_rad: f64,
    /// Shaft velocity during the step, rad/s.
    pub velocity_rad_s: f64,
    /// Device torque during the step, Nm.
    pub device_torque_nm: f64,
    /// Hand torque during the step, Nm.
    pub hand_torque_nm: f64,
    /// The device's inertial torque `J θ̈` over the step (`J` the device's, without the hand), Nm.
    pub inertial_torque_nm: f64,
}

impl MetricsAccumulator {
    /// An empty accumulator; `outward_drag_nm` is the device's free-motion drag against outward
    /// motion, subtracted for the excess resisting torque.
    pub fn new(outward_drag_nm: f64) -> Self {
        Self {
            stable: true,
            max_penetration_rad: f64::NEG_INFINITY,
            outward_drag_nm,
            ..Self::default()
        }
    }

    /// Records the commanded currents of a tick.
    pub fn add_currents(&mut self, current_a: [f64; 2]) {
        self.current_peak_a = self.current_peak_a.max(current_a[0]).max(current_a[1]);
    }

    /// Adds one step of length `dt_s`; `withdraw_start_s` is the scenario's withdrawal start.
    #[inline]
    pub fn add(&mut self, s: &Sample, dt_s: f64, withdraw_start_s: Option<f64>) {
        if !(s.angle_rad.is_finite() && s.velocity_rad_s.is_finite())
            || s.velocity_rad_s.abs() > 100.0
            || s.angle_rad.abs() > core::f64::consts::TAU
        {
            self.stable = false;
        }
        let p = s.penetration_rad;
        self.max_penetration_rad = self.max_penetration_rad.max(p);
        let power_w = s.device_torque_nm * s.velocity_rad_s;
        self.device_energy_j += power_w * dt_s;
        self.device_energy_peak_j = self.device_energy_peak_j.max(self.device_energy_j);
        if p > 0.0 {
            let pulling_out = s.side * s.hand_torque_nm < 0.0;
            if pulling_out {
                let resisting = (s.side * s.device_torque_nm).max(0.0);
                self.resisting_peak_nm = self.resisting_peak_nm.max(resisting);
                self.resisting_integral_nms += resisting * dt_s;
                let excess = (resisting - self.outward_drag_nm).max(0.0);
                self.excess_peak_nm = self.excess_peak_nm.max(excess);
                self.excess_integral_nms += excess * dt_s;
                self.withdraw_time_s += dt_s;
                self.withdraw_energy_j -= power_w * dt_s;
            } else {
                let felt = -s.side * s.device_torque_nm;
                self.fit[0] += 1.0;
                self.fit[1] += p;
                self.fit[2] += felt;
                self.fit[3] += p * felt;
                self.fit[4] += p * p;
            }
        } else {
            let grip = (s.inertial_torque_nm - s.device_torque_nm).abs();
            self.free_motion_peak_nm = self.free_motion_peak_nm.max(grip);
            if let Some(start) = withdraw_start_s
                && s.time_s >= start
                && self.release_at_s.is_none()
            {
                self.release_at_s = Some(s.time_s - start);
            }
        }
    }

    /// The final measures; `drag_after` is the free-motion drag at the end of the run.
    pub fn finish(
        &self,
        device: &'static str,
        scenario: &'static str,
        fault_ticks: u32,
        drag_after: DragAfter,
    ) -> WallMetrics {
        let [n, sx, sy, sxy, sxx] = self.fit;
        let denominator = n * sxx - sx * sx;
        let displayed = if n >= 10.0 && denominator > 1e-18 * n * n {
            Some((n * sxy - sx * sy) / denominator)
        } else {
            None
        };
        let mean_of = |integral: f64| {
            if self.withdraw_time_s > 0.0 { integral / self.withdraw_time_s } else { 0.0 }
        };
        WallMetrics {
            device,
            scenario,
            max_penetration_rad: self.max_penetration_rad,
            displayed_stiffness_nm_per_rad: displayed,
            withdraw_resisting_torque_nm: PeakMean {
                peak: self.resisting_peak_nm,
                mean: mean_of(self.resisting_integral_nms),
            },
            withdraw_excess_torque_nm: PeakMean {
                peak: self.excess_peak_nm,
                mean: mean_of(self.excess_integral_nms),
            },
            outward_drag_nm: self.outward_drag_nm,
            free_motion_torque_nm: self.free_motion_peak_nm,
            drag_after_nm: drag_after,
            withdraw_energy_j: self.withdraw_energy_j,
            withdraw_duration_s: self.withdraw_time_s,
            release_time_s: self.release_at_s,
            device_energy_j: self.device_energy_j,
            device_energy_peak_j: self.device_energy_peak_j,
            passive: self.stable && self.device_energy_peak_j <= 1e-6,
            stable: self.stable,
            current_peak_a: self.current_peak_a,
            fault_ticks,
        }
    }
}
