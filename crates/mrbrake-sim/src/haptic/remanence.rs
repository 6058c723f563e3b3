//! The steel's remanence in the haptic plant, and the demagnetising release that removes it.
//!
//! The brake branches of [`super::brake`] come from a characterisation or from the design's
//! anhysteretic curve: at 0 A they give the off-state torque `T₀ = T_rise(I_min)` whatever the
//! history. The hysteretic FEA (`mrbrake analyze --hysteresis`) predicts that after a current peak
//! `I_p` the steel keeps a remanent flux whose yield torque `R₀` the brake still produces at 0 A
//! (0.175 N·m for the thesis brake after 2 A). [`PlantRemanence`] adds it to the plant:
//!
//! * **Magnetising.** The remanent torque of the present history is `r = max(r, R₀ min(1, I_pk/I_ref))`
//!   with `I_pk` the largest current since the last demagnetisation and `I_ref` the peak `R₀` was
//!   predicted for (linear in the peak: an approximation, which `mrbrake analyze --demag`'s check at
//!   half the peak measures).
//! * **Falling.** The falling branch is raised by the remanence, fading linearly to nothing at
//!   `I_max`: `T_s ← clamp(T_s, T_rise(i), T_fall(i) + r (1 − i/I_max))`, so a release to 0 A ends
//!   at `T₀ + r` (the free-motion drag after a wall is left: off-state drag plus remanent torque).
//! * **Reverse current** (only a demagnetising release drives one). At the excursion's start the
//!   current passes through 0 A and the magnetic part there, `m = T_s − T₀`, is kept; at reverse depth `d` (the largest `|i|` so far) the
//!   static torque is `T₀ + m·(1 − (1 − ρ) min(d/a_ref, 1))`, where `ρ = R(a*)/R₀` is the fraction the
//!   FEA predicts the chosen reverse pulse `a*` leaves (`mrbrake analyze --hysteresis --demag`) and
//!   `a_ref = a* min(1, I_pk/I_ref)` the amplitude the controller scales it to. Back at `i ≥ 0` the
//!   remaining magnetic part is the new `r` and `I_pk` restarts from 0.
//!
//! Limits of the model: the torque *during* the reverse pulse is taken as the recoiled value (the
//! FEA's yield torque at the reverse peak, `yield_torque_at_reverse_peak_Nm`, is lower still, so the
//! plant's torque falls a little slower than predicted); a reverse current beyond `a_ref` is held at
//! `ρ` (the FEA shows the remanence rising again when the steel is magnetised the other way; the
//! controller never goes beyond `a_ref`); the release model is calibrated for a reverse pulse, a
//! decaying alternating current's positive half cycles are treated as ordinary current.
//!
//! Without a [`PlantRemanence`] the plant is exactly [`super::brake::BrakePlant::apply_current`].

use mrbrake_control::{Branch, DemagSettings, DemagWaveform};

use super::brake::{BrakePlant, BrakeState};

/// The demagnetising release of a run: the controller's settings and what the FEA predicts it leaves.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ReleaseModel {
    /// The controller's release (its `reference_peak_a` is also the plant's `I_ref`).
    pub settings: DemagSettings,
    /// `ρ = R(a*)/R₀`: the remanent torque after the pulse over that without it (from the FEA).
    pub remanence_fraction: f64,
}

/// The predicted remanence of the brakes in a haptic run (module docs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlantRemanence {
    /// Remanent yield torque `R₀` at 0 A after the reference peak, N·m.
    pub remanent_torque_nm: f64,
    /// The peak `I_ref` it was predicted after, A.
    pub reference_peak_a: f64,
    /// The demagnetising release, if the controller applies one.
    pub release: Option<ReleaseModel>,
}

/// Per-brake remanence state.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct RemanenceState {
    /// Largest current since the last demagnetisation, A.
    peak_current_a: f64,
    /// Remanent torque of the present history, N·m.
    remanent_nm: f64,
    /// During a reverse excursion: the magnetic part at its start and the depth so far.
    excursion: Option<(f64, f64)>,
}

impl RemanenceState {
    /// The remanent torque of the present history (what 0 A leaves), N·m.
    pub fn remanent_nm(&self) -> f64 {
        self.remanent_nm
    }
}

impl PlantRemanence {
    /// The amplitude `a*` of the release's waveform (its first reverse amplitude), A.
    fn release_amplitude_a(release: &ReleaseModel) -> f64 {
        match release.settings.waveform {
            DemagWaveform::ReversePulse { amplitude_a, .. } => amplitude_a,
            DemagWaveform::DecayingAc { first_amplitude_a, .. } => first_amplitude_a,
        }
    }

    /// Applies coil current `current_a` to `brake`'s static torque (module docs).
    #[inline]
    pub fn apply_current(
        &self,
        brake: &BrakePlant,
        state: &mut BrakeState,
        remanence: &mut RemanenceState,
        current_a: f64,
    ) {
        let rest_nm = brake.branches.torque_nm(Branch::Rising, brake.branches.current_min_a());
        if current_a < 0.0 {
            let Some(release) = &self.release else {
                // No release model: a reverse current acts as 0 A.
                return self.apply_current(brake, state, remanence, 0.0);
            };
            if remanence.excursion.is_none() {
                // The coil current passes through 0 A on its way to the reverse pulse.
                self.apply_current(brake, state, remanence, 0.0);
            }
            let (magnetic, depth) =
                remanence.excursion.unwrap_or(((state.static_torque_nm - rest_nm).max(0.0), 0.0));
            let depth = depth.max(-current_a);
            remanence.excursion = Some((magnetic, depth));
            let scale = (remanence.peak_current_a / self.reference_peak_a).clamp(0.0, 1.0);
            let reference = Self::release_amplitude_a(release) * scale;
            let reached = if reference > 0.0 { (depth / reference).min(1.0) } else { 1.0 };
            let fraction = 1.0 - (1.0 - release.remanence_fraction) * reached;
            state.static_torque_nm = rest_nm + magnetic * fraction;
            return;
        }
        if remanence.excursion.take().is_some() {
            remanence.remanent_nm = (state.static_torque_nm - rest_nm).max(0.0);
            remanence.peak_current_a = 0.0;
        }
        if current_a > remanence.peak_current_a {
            remanence.peak_current_a = current_a;
            let scale = (current_a / self.reference_peak_a).clamp(0.0, 1.0);
            remanence.remanent_nm = remanence.remanent_nm.max(self.remanent_torque_nm * scale);
        }
        let current_max_a = brake.branches.current_max_a();
        let fade = (1.0 - current_a / current_max_a).clamp(0.0, 1.0);
        let lower = brake.branches.torque_nm(Branch::Rising, current_a);
        let upper =
            brake.branches.torque_nm(Branch::Falling, current_a) + remanence.remanent_nm * fade;
        state.static_torque_nm = state.static_torque_nm.max(lower).min(upper.max(lower));
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::haptic::TorqueLag;
    use crate::haptic::prototype::prototype_model;

    fn brake() -> BrakePlant {
        BrakePlant { branches: prototype_model(), lag: TorqueLag::BRAKE_1 }
    }

    fn pulse(fraction: f64) -> ReleaseModel {
        ReleaseModel {
            settings: DemagSettings {
                waveform: DemagWaveform::ReversePulse { amplitude_a: 0.4, duration_s: 5e-3 },
                reverse_limit_a: 1.0,
                arm_above_nm: 0.5,
                release_below_nm: 0.0,
                reference_peak_a: 2.0,
            },
            remanence_fraction: fraction,
        }
    }

    #[test]
    fn a_release_to_zero_keeps_the_remanent_torque_and_a_pulse_removes_its_share() {
        let b = brake();
        let model = PlantRemanence {
            remanent_torque_nm: 0.2,
            reference_peak_a: 2.0,
            release: Some(pulse(0.25)),
        };
        let rest = b.rest_state().static_torque_nm;
        let (mut s, mut r) = (b.rest_state(), RemanenceState::default());
        for i in [0.5, 1.0, 2.0, 1.0, 0.0] {
            model.apply_current(&b, &mut s, &mut r, i);
        }
        assert!((s.static_torque_nm - (rest + 0.2)).abs() < 1e-12, "{}", s.static_torque_nm);
        // Half the pulse: half the way to ρ; the full pulse: ρ; back at 0 A it stays.
        model.apply_current(&b, &mut s, &mut r, -0.2);
        assert!((s.static_torque_nm - (rest + 0.2 * (1.0 - 0.75 * 0.5))).abs() < 1e-12);
        model.apply_current(&b, &mut s, &mut r, -0.4);
        model.apply_current(&b, &mut s, &mut r, 0.0);
        assert!((s.static_torque_nm - (rest + 0.05)).abs() < 1e-12);
        assert!((r.remanent_nm() - 0.05).abs() < 1e-12);
        // A smaller peak later magnetises to its own (smaller) remanence.
        for i in [1.0, 0.0] {
            model.apply_current(&b, &mut s, &mut r, i);
        }
        assert!((s.static_torque_nm - (rest + 0.1)).abs() < 1e-12);
    }

    #[test]
    fn without_remanence_the_plant_is_the_branch_model() {
        let b = brake();
        let model =
            PlantRemanence { remanent_torque_nm: 0.0, reference_peak_a: 2.0, release: None };
        let (mut s, mut r, mut plain) = (b.rest_state(), RemanenceState::default(), b.rest_state());
        for i in [0.3, 1.7, 0.9, 1.2, 0.0, 0.4] {
            model.apply_current(&b, &mut s, &mut r, i);
            b.apply_current(&mut plain, i);
            assert!((s.static_torque_nm - plain.static_torque_nm).abs() < 1e-12);
        }
    }
}
