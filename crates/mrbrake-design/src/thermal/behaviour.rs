//! What heat does to the brake, at the steady state of the run's current and duty:
//!
//! - **off-state (viscous) torque**: the analysis's viscous torque at the speed (the per-gap
//!   Newtonian laws of [`crate::formula`], (3.4) of the thesis, with the library's 30 °C
//!   viscosity) is linear in the viscosity, so at a fluid temperature `T` it is scaled by
//!   `η(T)/η(30 °C)`, `η(T)` by Andrade's law
//!   ([`mrbrake_materials::thermal::fluid_viscosity_at`], low trust); the yield stress is taken
//!   independent of temperature (the carrier sets the temperature dependence; see that module);
//!   "cold" is the fluid at the ambient, "hot" at its steady mean temperature;
//! - **coil**: resistance `R(T̄) = R20 (1 + α (T̄ − 20 °C))` at the ambient and at the coil's
//!   steady mean temperature, and the power `I² R` when on;
//! - **voltage drive**: a supply set to give the current at the ambient, `V = I R(T_amb)`, drives
//!   `I_hot = V / R(T̄_hot)` once the coil is warm. The hot state is self-consistent: the coil's
//!   temperature follows its power `V²/R` (secant iteration on `I = V/R(T̄(I))`, to 1e-9
//!   relative). The torque at the hot current is the yield torque of a magnetic analysis at that
//!   very current (local Bingham, direction 1; [`crate::analysis::direction1_points`] solves only
//!   the currents needed: 0, the run's current and the hot current) plus the viscous torque at
//!   the hot fluid temperature.

use mrbrake_materials::thermal::{ViscosityAtTemperature, fluid_viscosity_at};
use mrbrake_materials::wire::COPPER_TEMPERATURE_COEFFICIENT_PER_K;
use serde::Serialize;

use super::{
    Housing, SteadyTemperatures, ThermalError, ThermalOptions, ThermalParts, set_current, steady_of,
};
use crate::analysis::{AnalysisOptions, direction1_points};
use crate::spec::{BrakeSpec, Current};
use mrbrake_heat::{HeatError, HeatSolver};

/// The brake warm and cold.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct HotBehaviour {
    /// Speed of the viscous torque \[rad/s\] (the run's speed, else the analysis default 1 rad/s).
    pub speed_rad_s: f64,
    /// Fluid viscosity at the ambient.
    pub viscosity_cold: ViscosityAtTemperature,
    /// Fluid viscosity at its steady mean temperature.
    pub viscosity_hot: ViscosityAtTemperature,
    /// Off-state torque, fluid at the ambient \[N·m\].
    #[serde(rename = "off_state_torque_cold_Nm")]
    pub off_state_torque_cold_nm: f64,
    /// Off-state torque, fluid at its steady mean temperature \[N·m\].
    #[serde(rename = "off_state_torque_hot_Nm")]
    pub off_state_torque_hot_nm: f64,
    /// Coil resistance at the ambient \[Ω\].
    #[serde(rename = "coil_resistance_cold_ohm")]
    pub coil_resistance_cold_ohm: f64,
    /// Coil resistance at its steady mean temperature \[Ω\].
    #[serde(rename = "coil_resistance_hot_ohm")]
    pub coil_resistance_hot_ohm: f64,
    /// Coil power at the current, cold \[W\].
    #[serde(rename = "coil_power_cold_W")]
    pub coil_power_cold_w: f64,
    /// Coil power at the current, hot \[W\].
    #[serde(rename = "coil_power_hot_W")]
    pub coil_power_hot_w: f64,
    /// Torque at the current with a current drive, cold fluid \[N·m\].
    #[serde(rename = "torque_cold_Nm")]
    pub torque_cold_nm: f64,
    /// Torque at the current with a current drive, hot fluid \[N·m\].
    #[serde(rename = "torque_hot_current_drive_Nm")]
    pub torque_hot_current_drive_nm: f64,
    /// The voltage-driven brake when hot.
    pub voltage_drive: VoltageDrive,
    /// Seconds of the magnetic analysis.
    pub analysis_s: f64,
}

/// A voltage drive set for the current at the ambient, at its self-consistent hot state.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct VoltageDrive {
    /// Supply voltage `I R(T_amb)` \[V\].
    #[serde(rename = "voltage_V")]
    pub voltage_v: f64,
    /// Current when hot \[A\].
    #[serde(rename = "current_hot_A")]
    pub current_hot_a: f64,
    /// Coil mean temperature \[°C\].
    #[serde(rename = "coil_mean_T_C")]
    pub coil_mean_t_c: f64,
    /// Coil hot spot \[°C\].
    #[serde(rename = "coil_max_T_C")]
    pub coil_max_t_c: f64,
    /// Fluid mean temperature \[°C\].
    #[serde(rename = "fluid_mean_T_C")]
    pub fluid_mean_t_c: f64,
    /// Torque at the hot current, hot fluid \[N·m\].
    #[serde(rename = "torque_hot_Nm")]
    pub torque_hot_nm: f64,
    /// `(torque_hot − torque_cold)/torque_cold` in percent.
    pub torque_change_percent: f64,
}

/// The coil's resistance at `t_c` from its 20 °C value.
fn resistance(r20: f64, t_c: f64) -> f64 {
    r20 * (1.0 + COPPER_TEMPERATURE_COEFFICIENT_PER_K * (t_c - 20.0))
}

/// The steady state at the mean current `i √d`.
fn steady_at(
    solver: &mut HeatSolver,
    parts: &ThermalParts,
    housing: &mut Housing,
    current: f64,
    duty: f64,
) -> Result<SteadyTemperatures, ThermalError> {
    set_current(solver, parts, current * duty.sqrt())?;
    steady_of(solver, parts, housing)?.map(|s| s.0).ok_or_else(|| {
        HeatError::LimitCrossed(format!(
            "voltage drive: no steady state at {current:.4} A (runaway or beyond the air table)"
        ))
        .into()
    })
}

/// The self-consistent hot state of a voltage drive `v` (secant on `I − V/R(T̄(I))`), from the
/// current-driven state `start` at `current`.
fn voltage_hot_state(
    solver: &mut HeatSolver,
    parts: &ThermalParts,
    housing: &mut Housing,
    v: f64,
    duty: f64,
    (current, start): (f64, &SteadyTemperatures),
) -> Result<(f64, SteadyTemperatures), ThermalError> {
    let r20: f64 = parts.coils.iter().map(|c| c.1).sum();
    let residual = |i: f64, s: &SteadyTemperatures| i - v / resistance(r20, s.coil_mean_t_c);
    let (mut a, mut fa) = (current, residual(current, start));
    let mut b = v / resistance(r20, start.coil_mean_t_c);
    let mut state = steady_at(solver, parts, housing, b, duty)?;
    for _ in 0..50 {
        let fb = residual(b, &state);
        if fb.abs() <= 1e-9 * b || (fb - fa).abs() < f64::MIN_POSITIVE {
            return Ok((b, state));
        }
        let next = b - fb * (b - a) / (fb - fa);
        (a, fa) = (b, fb);
        b = next;
        state = steady_at(solver, parts, housing, b, duty)?;
    }
    Err(HeatError::LimitCrossed("voltage drive: the hot current did not settle".into()).into())
}

/// What heat does to the brake (module docs); `steady` is the state at `options`' current.
pub(super) fn hot_behaviour(
    spec: &BrakeSpec,
    options: &ThermalOptions,
    solver: &mut HeatSolver,
    parts: &ThermalParts,
    housing: &mut Housing,
    steady: &SteadyTemperatures,
) -> Result<HotBehaviour, ThermalError> {
    let fluid = mrbrake_materials::library::fluid(&spec.materials.fluid)?;
    let speed = if options.speed_rad_s > 0.0 {
        options.speed_rad_s
    } else {
        AnalysisOptions::default().speed_rad_s
    };
    let r20: f64 = parts.coils.iter().map(|c| c.1).sum();
    let r_cold = resistance(r20, options.ambient_c);
    let current = options.current_a;
    let v = current * r_cold;
    let (i_hot, hot) =
        voltage_hot_state(solver, parts, housing, v, options.duty, (current, steady))?;
    let start = std::time::Instant::now();
    let mut swept = spec.clone();
    swept.coil.max_current = Current(spec.coil.max_current.a().max(current).max(i_hot));
    let analysis_options = AnalysisOptions {
        mesh: options.mesh,
        speed_rad_s: speed,
        temperature_c: options.ambient_c,
        ..AnalysisOptions::default()
    };
    let points = direction1_points(&swept, &analysis_options, &[0.0, current, i_hot])?;
    let analysis_s = start.elapsed().as_secs_f64();
    let [off, at_current, at_hot] = [points[0], points[1], points[2]];
    let viscous_30 = off.torque_nm;
    let eta_30 = fluid.viscosity_pa_s();
    let viscous_at = |t_c: f64| -> Result<(f64, ViscosityAtTemperature), ThermalError> {
        let eta = fluid_viscosity_at(fluid, t_c)?;
        Ok((viscous_30 * eta.pa_s / eta_30, eta))
    };
    let (off_cold, viscosity_cold) = viscous_at(options.ambient_c)?;
    let (off_hot, viscosity_hot) = viscous_at(steady.fluid_mean_t_c)?;
    let torque_cold = at_current.yield_torque_nm + off_cold;
    let torque_hot = at_hot.yield_torque_nm + viscous_at(hot.fluid_mean_t_c)?.0;
    Ok(HotBehaviour {
        speed_rad_s: speed,
        viscosity_cold,
        viscosity_hot,
        off_state_torque_cold_nm: off_cold,
        off_state_torque_hot_nm: off_hot,
        coil_resistance_cold_ohm: r_cold,
        coil_resistance_hot_ohm: steady.coil_resistance_ohm,
        coil_power_cold_w: current * current * r_cold,
        coil_power_hot_w: current * current * steady.coil_resistance_ohm,
        torque_cold_nm: torque_cold,
        torque_hot_current_drive_nm: at_current.yield_torque_nm + off_hot,
        voltage_drive: VoltageDrive {
            voltage_v: v,
            current_hot_a: i_hot,
            coil_mean_t_c: hot.coil_mean_t_c,
            coil_max_t_c: hot.coil_max_t_c,
            fluid_mean_t_c: hot.fluid_mean_t_c,
            torque_hot_nm: torque_hot,
            torque_change_percent: 100.0 * (torque_hot - torque_cold) / torque_cold,
        },
        analysis_s,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn resistance_follows_copper() {
        assert!((resistance(10.0, 20.0) - 10.0).abs() < 1e-12);
        let expected = 10.0 * (1.0 + COPPER_TEMPERATURE_COEFFICIENT_PER_K * 100.0);
        assert!((resistance(10.0, 120.0) - expected).abs() < 1e-12);
    }

    /// The points solved on their own equal the sweep's at the same currents (same mesh and
    /// model; Newton from another start, so to its tolerance).
    #[test]
    fn direction1_points_match_the_sweep() {
        let spec = crate::spec::default_spec();
        let options = AnalysisOptions {
            mesh: crate::mesh_build::MeshLevel::Coarse,
            points: 3,
            ..AnalysisOptions::default()
        };
        let sweep = crate::analysis::AnalysisRequest::of(&spec)
            .options(options)
            .run()
            .unwrap()
            .torque_current_curve;
        let currents: Vec<f64> = sweep.iter().rev().map(|p| p.current_a).collect();
        let points = direction1_points(&spec, &options, &currents).unwrap();
        for (p, s) in points.iter().zip(sweep.iter().rev()) {
            let scale = s.torque_nm.abs().max(1e-3);
            assert!((p.torque_nm - s.torque_nm).abs() < 1e-6 * scale, "{p:?} vs {s:?}");
            assert!((p.yield_torque_nm - s.yield_torque_nm).abs() < 1e-6 * scale);
        }
        let too_high = direction1_points(&spec, &options, &[3.0]).unwrap_err();
        assert_eq!(mrbrake_error::Kind::kind(&too_high), mrbrake_error::ErrorKind::Input);
    }
}
