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
//! **With a Preisach brake** ([`super::brake::PreisachBrake`]) the table already holds the
//! magnetising part: its reference state keeps `R = T(0)` (yield) at 0 A after any peak. So `R₀`
//! and the linear-in-peak rule are not used (adding them would count the remanence twice; a
//! remanence without a release is refused by [`super::HapticConfig::validate`]); only the release
//! is, on the Preisach torque `T_P(i)` (the current clamped to `[0, I_max]`, friction `f`):
//!
//! * **Reverse current**: as above, with the magnetic part `m = T_s − f` at 0 A (the demagnetised
//!   brake's torque at 0 A is its friction) and `T_s = f + m·(1 − (1 − ρ) min(d/a_ref, 1))`.
//! * **After the release** the steel lies below the table's reference state by the deficit
//!   `D = R − (T_s − f)`: in a bipolar Preisach picture the pulse switched off relays with
//!   thresholds `β ∈ [−a, 0)`, which the unipolar table does not resolve. They switch on again as
//!   the current rises past their `α`; the plant assumes them distributed over `α` as the table's
//!   relays switched on along its rising branch, so a peak `I_pk` since the release restores the
//!   share `g(I_pk) = E(I_pk, 0)/E(I_max, 0)` of `D`:
//!   `T_s = max(f, T_P(i) − D (1 − g(I_pk)))`. A peak at `I_max` restores the reference state.
//!
//! Without a [`PlantRemanence`] the plant is exactly [`super::brake::BrakePlant::apply_current`].

use mrbrake_control::{Branch, DemagSettings, DemagWaveform};

use mrbrake_error::FieldError;

use super::brake::{BrakePlant, BrakeState, PreisachBrake};
use crate::SimError;

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
    /// Preisach brake: the remanence the last release removed from the reference state, N·m.
    deficit_nm: f64,
}

impl RemanenceState {
    /// The remanent torque of the present history (what 0 A leaves), N·m.
    pub fn remanent_nm(&self) -> f64 {
        self.remanent_nm
    }
}

impl PlantRemanence {
    /// The plant's remanence from the JSON `text` of `mrbrake analyze --hysteresis --demag --json`
    /// (its remanent torque after the peak); with `pulse_duration_s`, the chosen reverse pulse as
    /// the controller's release (armed above the remanent torque: a smaller demand leaves less than
    /// the remanence it would remove). An error names the missing JSON pointer.
    pub fn from_analysis_json(text: &str, pulse_duration_s: Option<f64>) -> Result<Self, SimError> {
        let value: serde_json::Value = serde_json::from_str(text)
            .map_err(|e| FieldError::new("", format!("not JSON: {e}")))?;
        let number = |pointer: &str| {
            value.pointer(pointer).and_then(serde_json::Value::as_f64).ok_or_else(|| {
                SimError::from(FieldError::new(
                    pointer,
                    "no number here (the JSON of `mrbrake analyze --hysteresis --demag --json`)",
                ))
            })
        };
        let remanent_torque_nm = number("/hysteresis/remanent_torque_Nm")?;
        let reference_peak_a = number("/hysteresis/peak_current_A")?;
        let release = match pulse_duration_s {
            Some(duration_s) => {
                let chosen = "/hysteresis/demagnetisation/chosen_pulse";
                let amplitude_a = number(&format!("{chosen}/release/amplitude_A"))?;
                Some(ReleaseModel {
                    settings: DemagSettings {
                        waveform: DemagWaveform::ReversePulse { amplitude_a, duration_s },
                        reverse_limit_a: number("/hysteresis/demagnetisation/reverse_limit_A")?,
                        arm_above_nm: remanent_torque_nm.max(1e-6),
                        release_below_nm: 0.0,
                        reference_peak_a,
                    },
                    remanence_fraction: number(&format!("{chosen}/remanence_fraction"))?,
                })
            }
            None => None,
        };
        Ok(Self { remanent_torque_nm, reference_peak_a, release })
    }

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
        if let Some(preisach) = &brake.preisach {
            return self.apply_preisach(preisach, state, remanence, current_a);
        }
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
            self.reverse_excursion(release, state, remanence, rest_nm, current_a);
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

    /// A reverse current `current_a < 0` during a release (module docs): the static torque recoils
    /// from `floor_nm` plus the magnetic part at the excursion's start towards `ρ` of it.
    fn reverse_excursion(
        &self,
        release: &ReleaseModel,
        state: &mut BrakeState,
        remanence: &mut RemanenceState,
        floor_nm: f64,
        current_a: f64,
    ) {
        let (magnetic, depth) =
            remanence.excursion.unwrap_or(((state.static_torque_nm - floor_nm).max(0.0), 0.0));
        let depth = depth.max(-current_a);
        remanence.excursion = Some((magnetic, depth));
        let scale = (remanence.peak_current_a / self.reference_peak_a).clamp(0.0, 1.0);
        let reference = Self::release_amplitude_a(release) * scale;
        let reached = if reference > 0.0 { (depth / reference).min(1.0) } else { 1.0 };
        let fraction = 1.0 - (1.0 - release.remanence_fraction) * reached;
        state.static_torque_nm = floor_nm + magnetic * fraction;
    }

    /// [`Self::apply_current`] on a Preisach brake (module docs: the table magnetises, the
    /// release model demagnetises).
    fn apply_preisach(
        &self,
        preisach: &PreisachBrake,
        state: &mut BrakeState,
        remanence: &mut RemanenceState,
        current_a: f64,
    ) {
        let floor_nm = preisach.friction_nm;
        if let (true, Some(release)) = (current_a < 0.0, &self.release) {
            if remanence.excursion.is_none() {
                self.apply_preisach(preisach, state, remanence, 0.0);
            }
            self.reverse_excursion(release, state, remanence, floor_nm, current_a);
            return;
        }
        if remanence.excursion.take().is_some() {
            let left = (state.static_torque_nm - floor_nm).max(0.0);
            remanence.deficit_nm = (preisach.remanent_nm - left).max(0.0);
            remanence.peak_current_a = 0.0;
        }
        let current_a = current_a.max(0.0);
        remanence.peak_current_a = remanence.peak_current_a.max(current_a);
        let missing = if remanence.deficit_nm > 0.0 {
            remanence.deficit_nm * (1.0 - preisach.rising_share(remanence.peak_current_a))
        } else {
            0.0
        };
        remanence.remanent_nm = (preisach.remanent_nm - missing).max(0.0);
        let Some(memory) = state.preisach.as_mut() else {
            // A state not made by this brake's `rest_state`: nothing to run.
            return;
        };
        state.static_torque_nm = (memory.torque_nm(current_a) - missing).max(floor_nm);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::haptic::TorqueLag;
    use crate::haptic::prototype::prototype_model;

    fn brake() -> BrakePlant {
        BrakePlant::clamp(prototype_model(), TorqueLag::BRAKE_1)
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
