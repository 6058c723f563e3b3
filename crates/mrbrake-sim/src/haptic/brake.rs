//! MR brake dynamics in the haptic loop: current-driven hysteresis followed by the identified torque
//! lag.
//!
//! 1. **Hysteresis** (rate-independent, current-driven), one of two plants:
//!    * **Clamp between the branches** (polynomial branches, e.g. identified on a rig, or a model
//!      without a loop): the static torque `T_s` stays between the rising branch (lower) and the
//!      falling branch (upper) of the loop (thesis Fig. 5.6): `T_s ← clamp(T_s, T_rise(i), T_fall(i))`.
//!      Increasing current drags `T_s` up along the rising branch, decreasing current drags it down
//!      along the falling branch, and on a reversal it stays constant until it meets the other branch
//!      (a flat minor loop).
//!    * **Preisach** (a brake model whose unit carries a `preisach` table, e.g. the design's
//!      predicted first-order reversal curves): `T_s` is the output of the Preisach operator of
//!      that table, [`PreisachHysteresis`] — the type the virtual rig's plant runs
//!      ([`crate::rig::preisach`], [`crate::rig::everett`]; Mayergoyz 1991, *Mathematical Models of
//!      Hysteresis*, ch. 1) — plus the unit's seal friction, so reversals, minor loops (with
//!      return-point memory and wiping-out) and the torque left at low current after any peak are
//!      the table's. The table covers the unipolar currents `[0, I_max]` the brake is driven with,
//!      from its reference state: the state at 0 A after a full `0 → I_max → 0` (the FORCs'
//!      reference, `mrbrake_design::forc`), whose torque at 0 A is the table's `T(0)`, the remanent
//!      yield torque of a brake that has been used. A descent to 0 A wipes the memory out to that
//!      state (Mayergoyz's wiping-out property at the lowest input), so after *any* peak the torque
//!      at 0 A is `T(0)`: what a peak changes is the way down (the reversal curve `T(p, β)`), not the
//!      end point. **Currents outside `[0, I_max]`:** the table knows no state below its reference
//!      (reaching one needs a reverse current), so the Preisach input is the current clamped to
//!      `[0, I_max]` — a reverse current acts on it as 0 A — and what a demagnetising release's
//!      reverse current does to the remanence comes from the FEA's release model
//!      ([`super::remanence`]). The plant starts in the reference state. The memory is bounded
//!      ([`PreisachHysteresis`]: at most [`crate::rig::preisach::MAX_TURNING_POINTS`] turning points),
//!      so a tick's cost is bounded whatever the run's length.
//! 2. **Lag**: the torque capacity `C` follows `T_s` through the identified transfer function
//!    `C(s)/T_s(s) = k / (a s² + b s + 1)` — brake 1: `1/(1.791e-5 s² + 0.01702 s + 1)` (5.5),
//!    brake 2: `0.9818/(2.309e-5 s² + 0.01726 s + 1)` (5.6). The ODE is advanced with its exact
//!    zero-order-hold discretisation (the matrix exponential [`crate::lti::expm`] of the augmented
//!    system), so the plant step does not limit its accuracy.
//!
//! The brake then acts as a set-valued Coulomb element of capacity `max(C, 0)` on the shaft (see
//! [`super::bearing`]).

use mrbrake_control::{Branch, InverseModel};
use mrbrake_sysid::SysidError;
use mrbrake_sysid::transfer_function::TransferFunction;

use crate::SimError;
use crate::lti::expm;
use crate::rig::everett::EverettTable;
use crate::rig::preisach::PreisachHysteresis;

/// A second-order lag `k / (a s² + b s + 1)` as identified in thesis (5.5)/(5.6).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TorqueLag {
    /// Static gain `k`.
    pub gain: f64,
    /// `a`, s².
    pub a_s2: f64,
    /// `b`, s.
    pub b_s: f64,
}

impl TorqueLag {
    /// Brake 1 of the prototype, thesis (5.5).
    pub const BRAKE_1: Self = Self { gain: 1.0, a_s2: 1.791e-5, b_s: 0.01702 };
    /// Brake 2 of the prototype, thesis (5.6).
    pub const BRAKE_2: Self = Self { gain: 0.9818, a_s2: 2.309e-5, b_s: 0.01726 };

    /// The lag as a transfer function, `k / (a s² + b s + 1)` in descending powers of s (the one
    /// continuous-time model type, evaluated at jω by
    /// [`TransferFunction::response`](mrbrake_sysid::transfer_function::TransferFunction::response)).
    pub fn transfer_function(&self) -> Result<TransferFunction, SysidError> {
        TransferFunction::new(vec![self.gain], vec![self.a_s2, self.b_s, 1.0])
    }

    /// Exact ZOH discretisation over `dt_s`: `x⁺ = Φ x + Γ u` with `x = [y, ẏ]`.
    pub fn discretise(&self, dt_s: f64) -> DiscreteLag {
        // Continuous state space: ẋ = A x + B u, A = [[0, 1], [−1/a, −b/a]], B = [0, k/a].
        // exp([[A, B], [0, 0]]·dt) = [[Φ, Γ], [0, 1]].
        let a = self.a_s2;
        #[rustfmt::skip]
        let m = [
            0.0, dt_s, 0.0,
            -dt_s / a, -self.b_s * dt_s / a, self.gain * dt_s / a,
            0.0, 0.0, 0.0,
        ];
        let e = expm(&m, 3);
        DiscreteLag { phi: [[e[0], e[1]], [e[3], e[4]]], gamma: [e[2], e[5]] }
    }
}

/// The discretised lag `x⁺ = Φ x + Γ u`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DiscreteLag {
    phi: [[f64; 2]; 2],
    gamma: [f64; 2],
}

impl DiscreteLag {
    /// Advances the state `[y, ẏ]` by one step with input `u` held constant.
    #[inline]
    pub fn advance(&self, state: &mut [f64; 2], input: f64) {
        let y = self.phi[0][0] * state[0] + self.phi[0][1] * state[1] + self.gamma[0] * input;
        let v = self.phi[1][0] * state[0] + self.phi[1][1] * state[1] + self.gamma[1] * input;
        *state = [y, v];
    }
}

/// The Preisach hysteresis of a brake whose model carries a table (module docs).
#[derive(Debug, Clone, PartialEq)]
pub struct PreisachBrake {
    /// The Preisach model (with the friction added) in its reference state.
    pub model: PreisachHysteresis,
    /// The constant friction added to the table's yield torques (the unit's seal friction): the
    /// torque of the demagnetised brake at 0 A, N·m.
    pub friction_nm: f64,
    /// The table's `T(0)`: the yield torque the reference state keeps at 0 A (its remanence), N·m.
    pub remanent_nm: f64,
}

impl PreisachBrake {
    /// The plant of `table` (yield torques) with `friction_nm` added: the same model the virtual
    /// rig builds from it ([`crate::brake_model::apply::apply_to_rig`]). An error names the
    /// table's bad field.
    pub fn from_table(table: &EverettTable, friction_nm: f64) -> Result<Self, SimError> {
        let model = PreisachHysteresis::from_everett(&table.with_offset(friction_nm), 0.0)?;
        let remanent_nm = table.rising_nm.first().copied().unwrap_or(0.0);
        Ok(Self { model, friction_nm, remanent_nm })
    }

    /// The share of the table's relays along the rising branch that current `current_a` has
    /// switched on, `E(i, 0) / E(I_max, 0)` in `[0, 1]` (1 for a table without relays).
    pub fn rising_share(&self, current_a: f64) -> f64 {
        let full = self.model.everett_nm(self.model.current_max_a(), 0.0);
        if full > 0.0 {
            (self.model.everett_nm(current_a, 0.0) / full).clamp(0.0, 1.0)
        } else {
            1.0
        }
    }
}

/// One MR brake as the haptic plant runs it: forward hysteresis branches, the Preisach model when
/// the brake model has one, and the torque lag (the runtime form of a unit of a
/// [`crate::brake_model::BrakeModel`] file, built by
/// [`crate::brake_model::apply::apply_to_haptic`]).
#[derive(Debug, Clone, PartialEq)]
pub struct BrakePlant {
    /// The hysteresis branches (the same polynomials the identification produces; with a Preisach
    /// model, its major loop fitted, which the plant's rest state and the controller use).
    pub branches: InverseModel,
    /// The torque lag.
    pub lag: TorqueLag,
    /// The Preisach model the plant runs instead of the clamp between the branches (module docs).
    pub preisach: Option<PreisachBrake>,
}

/// State of one brake during a run.
#[derive(Debug, Clone, PartialEq)]
pub struct BrakeState {
    /// Static (hysteretic) torque `T_s`, Nm.
    pub static_torque_nm: f64,
    /// Lag state `[C, dC/dt]`, Nm and Nm/s.
    pub lag: [f64; 2],
    /// The Preisach model's memory (its turning points), for a Preisach plant.
    pub preisach: Option<PreisachHysteresis>,
}

impl BrakePlant {
    /// The clamp plant of `branches` with `lag` (no Preisach model).
    pub fn clamp(branches: InverseModel, lag: TorqueLag) -> Self {
        Self { branches, lag, preisach: None }
    }

    /// The state at rest with zero current for a long time: `T_s = C = T(0)` (for a Preisach
    /// plant, its reference state).
    pub fn rest_state(&self) -> BrakeState {
        let (t0, memory) = match &self.preisach {
            Some(p) => {
                let mut memory = p.model.clone();
                (memory.torque_nm(0.0), Some(memory))
            }
            None => (self.branches.torque_nm(Branch::Rising, self.branches.current_min_a()), None),
        };
        BrakeState { static_torque_nm: t0, lag: [self.lag.gain * t0, 0.0], preisach: memory }
    }

    /// Applies a new coil current to the hysteresis: the Preisach model's output for the current
    /// clamped to `[0, I_max]`, or `T_s ← clamp(T_s, T_rise(i), T_fall(i))` (module docs).
    #[inline]
    pub fn apply_current(&self, state: &mut BrakeState, current_a: f64) {
        if let Some(memory) = state.preisach.as_mut() {
            state.static_torque_nm = memory.torque_nm(current_a.max(0.0));
            return;
        }
        let lower = self.branches.torque_nm(Branch::Rising, current_a);
        let upper = self.branches.torque_nm(Branch::Falling, current_a);
        state.static_torque_nm = state.static_torque_nm.max(lower).min(upper.max(lower));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Step response of `1/((1 + s/p1)(1 + s/p2))` in closed form.
    fn step_response(lag: &TorqueLag, t: f64) -> f64 {
        let disc = (lag.b_s * lag.b_s - 4.0 * lag.a_s2).sqrt();
        let p1 = (-lag.b_s + disc) / (2.0 * lag.a_s2);
        let p2 = (-lag.b_s - disc) / (2.0 * lag.a_s2);
        lag.gain * (1.0 + (p2 * (p1 * t).exp() - p1 * (p2 * t).exp()) / (p1 - p2))
    }

    #[test]
    fn discretised_lag_matches_the_closed_form_step_response() {
        for lag in [TorqueLag::BRAKE_1, TorqueLag::BRAKE_2] {
            let dt = 1e-4;
            let d = lag.discretise(dt);
            let mut x = [0.0, 0.0];
            let mut worst: f64 = 0.0;
            for n in 1..=1000 {
                d.advance(&mut x, 1.0);
                worst = worst.max((x[0] - step_response(&lag, n as f64 * dt)).abs());
            }
            assert!(worst < 1e-10, "worst error {worst}");
        }
        // Brake 1's slow pole is at 62.9 rad/s (thesis: bandwidth 62.92 rad/s): 63 % at ~ 1/p + fast lag.
        let y = step_response(&TorqueLag::BRAKE_1, 1.0 / 62.92);
        assert!(y > 0.55 && y < 0.63, "{y}");
    }

    #[test]
    fn hysteresis_follows_the_rising_then_the_falling_branch() {
        let model =
            BrakePlant::clamp(super::super::prototype::prototype_model(), TorqueLag::BRAKE_1);
        let mut s = model.rest_state();
        model.apply_current(&mut s, 1.0);
        let up = s.static_torque_nm;
        assert!((up - model.branches.torque_nm(Branch::Rising, 1.0)).abs() < 1e-12);
        model.apply_current(&mut s, 2.0);
        model.apply_current(&mut s, 1.0);
        let down = s.static_torque_nm;
        assert!((down - model.branches.torque_nm(Branch::Falling, 1.0)).abs() < 1e-12);
        // Reversal inside the loop: flat until the rising branch is met.
        model.apply_current(&mut s, 1.05);
        assert!((s.static_torque_nm - down).abs() < 1e-12);
    }
}
