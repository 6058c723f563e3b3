//! Demagnetising release: drive a brake's coil through zero when its demand is released, so the
//! remanence of the steel flux path does not leave a torque at 0 A (the "sticky at 0 A" feel).
//!
//! **Why.** After a current peak the solid-steel flux path keeps a remanent flux density, and the
//! MR fluid in the gaps yields under it: the brake resists at 0 A (the thesis prototype measured
//! 0.15 N·m off-state; `mrbrake analyze --hysteresis` predicts the remanent part). Magnetic practice
//! removes remanence in two ways (Bozorth, *Ferromagnetism*, Van Nostrand 1951, on
//! demagnetisation; Jiles, *Introduction to Magnetism and Magnetic Materials*, 2nd ed., Chapman &
//! Hall 1998, on the ac-demagnetised state and minor loops):
//!
//! * a **reverse pulse**: a field against the remanent magnetisation. A reverse field of exactly the
//!   coercive field `H_c` holds `B = 0` only while it is applied; on its removal the material
//!   recoils to a smaller remanence of the same sign (TWI, "What are the principles of
//!   demagnetisation?", FAQ), so the pulse that leaves the least remanence is somewhat above the
//!   coercive current and depends on the history; too large a pulse magnetises the steel the other
//!   way;
//! * a **decaying alternating current**: a field that alternates with an amplitude decreasing from
//!   at least the last peak to zero walks the material down a shrinking sequence of nested minor
//!   loops to the origin ("ac demagnetisation", Bozorth; Jiles; TWI: "a reversing and reducing
//!   magnetising force"); insensitive to the history, but longer and it needs a bipolar driver.
//!
//! In an MR brake the remanent flux crosses the fluid gaps, so the fluid keeps a yield stress at
//! 0 A: the hysteresis of the brake's torque comes mostly from its steel (Shiao & Gadde,
//! "Investigation of Hysteresis Effect in Torque Performance for a Magnetorheological Brake",
//! *Actuators* 10 (2021) 271). The amplitudes come from the predicted loop
//! (`mrbrake analyze --hysteresis --demag`, `mrbrake_design::demag`): the reverse-pulse amplitude
//! that leaves the least remanent torque after the loop's peak current.
//!
//! **Shape.** Both waveforms are held piecewise constant over whole control ticks (square half
//! cycles). The predicted magnetic hysteresis is rate-independent (a play/Preisach-type law): the
//! state it ends in depends only on the sequence of the current's extrema, not on their timing, so a
//! square half cycle does what a sinusoidal one with the same extremum does; the coil's `L/R` and the
//! driver round the edges anyway. What the rate adds (eddy currents in the solid steel delaying the
//! flux) is why a pulse lasts several milliseconds rather than one tick.
//!
//! **Trigger.** A brake is *armed* when its demand exceeds [`DemagSettings::arm_above_nm`]; an armed
//! brake whose demand falls to [`DemagSettings::release_below_nm`] or below starts the sequence. The
//! waveform's amplitudes are scaled by `min(1, I_peak / I_ref)` with `I_peak` the largest current
//! commanded since arming and `I_ref` [`DemagSettings::reference_peak_a`] (the peak the amplitudes
//! were predicted for): a smaller peak leaves less remanence and needs a smaller reverse field (a
//! linear approximation of the recoil; the FEA scan at several peaks checks it). A demand above the
//! release level during the sequence interrupts it at once (the brake is needed again). After the
//! last waveform tick the output is exactly 0 A for one tick and the brake is idle.
//!
//! **Output contract.** With demagnetisation the controller's currents lie in
//! `[−reverse_limit_a, I_max]`: negative only during a brake's sequence. A unipolar driver (a
//! low-side switch, a buck stage) cannot reverse the current: `reverse_limit_a = 0` disables the
//! release and every output stays in `[0, I_max]`, bit-identical to the controller without it.

use crate::error::{ControlError, check_range};
use crate::inverse::CURRENT_LIMIT_A;

/// Most ticks of one demagnetising sequence (10 s at 1 kHz): a bound on the state's counter.
pub const MAX_DEMAG_TICKS: u32 = 10_000;

/// Most half cycles of a decaying alternating current.
pub const MAX_HALF_CYCLES: u32 = 64;

/// The demagnetising current waveform.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum DemagWaveform {
    /// One reverse pulse `−amplitude_a` held for `duration_s` (rounded up to whole ticks).
    ReversePulse {
        /// Pulse amplitude, A (> 0, at most the driver's reverse limit).
        amplitude_a: f64,
        /// Pulse length, s.
        duration_s: f64,
    },
    /// Square half cycles `−a₀, +a₀r, −a₀r², …` each held for `half_period_s`.
    DecayingAc {
        /// First (reverse) amplitude `a₀`, A (> 0, at most the reverse limit and `I_max`).
        first_amplitude_a: f64,
        /// Amplitude ratio `r` of successive half cycles, in (0, 1).
        decay_ratio: f64,
        /// Length of one half cycle, s.
        half_period_s: f64,
        /// Number of half cycles (1 ..= [`MAX_HALF_CYCLES`]).
        half_cycles: u32,
    },
}

/// The demagnetisation settings as given (checked by [`Demagnetiser::new`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DemagSettings {
    /// The waveform.
    pub waveform: DemagWaveform,
    /// Largest reverse current the coil driver can deliver, A (0: a unipolar driver, which disables
    /// the release).
    pub reverse_limit_a: f64,
    /// A demand above this arms the release, N·m (> 0).
    pub arm_above_nm: f64,
    /// An armed brake whose demand falls to this or below is released, N·m (`[0, arm_above_nm)`).
    pub release_below_nm: f64,
    /// The peak current the amplitudes were predicted for, A (> 0).
    pub reference_peak_a: f64,
}

/// Checked demagnetisation configuration (immutable, `Copy`, no allocation).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Demagnetiser {
    settings: Option<DemagSettings>,
    /// Ticks of one half cycle (the whole pulse for a reverse pulse).
    ticks_per_half: u32,
    /// Half cycles (1 for a reverse pulse).
    half_cycles: u32,
    current_max_a: f64,
}

/// Where a brake is in its demagnetising release.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
enum Phase {
    /// Not armed.
    #[default]
    Idle,
    /// The demand exceeded the arming level; the largest current since.
    Armed { peak_current_a: f64 },
    /// Releasing: the next waveform tick and the amplitude scale.
    Releasing { tick: u32, scale: f64 },
}

/// Per-brake state of the release (part of [`crate::ControllerState`]).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct DemagState {
    phase: Phase,
}

impl DemagState {
    /// Whether the brake is in its demagnetising sequence.
    pub fn is_releasing(&self) -> bool {
        matches!(self.phase, Phase::Releasing { .. })
    }
}

/// What [`Demagnetiser::apply`] did on a tick.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DemagOutput {
    /// The brake's current, A.
    pub current_a: f64,
    /// The sequence ended on this tick (the output is 0 A and the brake's loop is back near its
    /// demagnetised origin).
    pub completed: bool,
}

/// `ticks = ⌈duration / period⌉` within `1 ..= MAX_DEMAG_TICKS`, else an error naming `field`.
fn whole_ticks(field: &'static str, duration_s: f64, period_s: f64) -> Result<u32, ControlError> {
    let max = f64::from(MAX_DEMAG_TICKS) * period_s;
    let duration_s = check_range(field, duration_s, f64::MIN_POSITIVE, max)?;
    // Rounded before the ceiling so that 5 ms / 1 ms is 5 ticks, not 6 by a rounding error.
    let ratio = duration_s / period_s;
    let ticks = libm::ceil(ratio - 1e-9 * ratio.max(1.0));
    Ok((ticks as u32).clamp(1, MAX_DEMAG_TICKS))
}

impl Demagnetiser {
    /// No demagnetisation: the controller's outputs stay in `[0, I_max]`.
    pub const fn disabled() -> Self {
        Self { settings: None, ticks_per_half: 0, half_cycles: 0, current_max_a: 0.0 }
    }

    /// Checks `settings` for a controller with tick `control_period_s` and maximum current
    /// `current_max_a`; every error names the field and its range. `reverse_limit_a = 0` gives the
    /// disabled release (the waveform is still checked for finite, non-negative values).
    pub fn new(
        settings: &DemagSettings,
        control_period_s: f64,
        current_max_a: f64,
    ) -> Result<Self, ControlError> {
        let period = check_range("control_period_s", control_period_s, 1e-6, 1.0)?;
        let current_max_a =
            check_range("current_max_a", current_max_a, f64::MIN_POSITIVE, CURRENT_LIMIT_A)?;
        let limit = check_range("reverse_limit_a", settings.reverse_limit_a, 0.0, CURRENT_LIMIT_A)?;
        let arm = check_range("arm_above_nm", settings.arm_above_nm, f64::MIN_POSITIVE, 1e6)?;
        check_range("release_below_nm", settings.release_below_nm, 0.0, arm * (1.0 - 1e-12))?;
        check_range(
            "reference_peak_a",
            settings.reference_peak_a,
            f64::MIN_POSITIVE,
            CURRENT_LIMIT_A,
        )?;
        let enabled = limit > 0.0;
        // A disabled release still rejects nonsense, but not an amplitude above a zero limit.
        let amplitude_max = if enabled { limit } else { CURRENT_LIMIT_A };
        let amplitude_min = if enabled { f64::MIN_POSITIVE } else { 0.0 };
        let (ticks_per_half, half_cycles) = match settings.waveform {
            DemagWaveform::ReversePulse { amplitude_a, duration_s } => {
                check_range("amplitude_a", amplitude_a, amplitude_min, amplitude_max)?;
                (whole_ticks("duration_s", duration_s, period)?, 1)
            }
            DemagWaveform::DecayingAc {
                first_amplitude_a,
                decay_ratio,
                half_period_s,
                half_cycles,
            } => {
                let max = amplitude_max.min(if enabled { current_max_a } else { amplitude_max });
                check_range("first_amplitude_a", first_amplitude_a, amplitude_min, max)?;
                check_range("decay_ratio", decay_ratio, f64::MIN_POSITIVE, 1.0 - f64::EPSILON)?;
                let ticks = whole_ticks("half_period_s", half_period_s, period)?;
                let most = (MAX_DEMAG_TICKS / ticks).clamp(1, MAX_HALF_CYCLES);
                check_range("half_cycles", f64::from(half_cycles), 1.0, f64::from(most))?;
                (ticks, half_cycles)
            }
        };
        if !enabled {
            return Ok(Self::disabled());
        }
        Ok(Self { settings: Some(*settings), ticks_per_half, half_cycles, current_max_a })
    }

    /// Whether the release is on (a bipolar driver and a waveform).
    pub fn is_enabled(&self) -> bool {
        self.settings.is_some()
    }

    /// The settings, when enabled.
    pub fn settings(&self) -> Option<&DemagSettings> {
        self.settings.as_ref()
    }

    /// Waveform ticks of one sequence (the sequence then ends with one tick at 0 A).
    pub fn sequence_ticks(&self) -> u32 {
        self.ticks_per_half * self.half_cycles
    }

    /// The waveform's current at waveform tick `tick` with amplitudes scaled by `scale` ∈ [0, 1],
    /// clamped to `[−reverse_limit_a, I_max]`; 0 past the end or when disabled.
    pub fn waveform_current_a(&self, tick: u32, scale: f64) -> f64 {
        let Some(settings) = &self.settings else { return 0.0 };
        if tick >= self.sequence_ticks() {
            return 0.0;
        }
        let half = tick / self.ticks_per_half.max(1);
        let current = match settings.waveform {
            DemagWaveform::ReversePulse { amplitude_a, .. } => -amplitude_a,
            DemagWaveform::DecayingAc { first_amplitude_a, decay_ratio, .. } => {
                // Half cycle 0 is reverse (against the remanence of the positive drive).
                let sign = if half % 2 == 0 { -1.0 } else { 1.0 };
                sign * first_amplitude_a * libm::pow(decay_ratio, f64::from(half))
            }
        };
        (current * scale.clamp(0.0, 1.0)).clamp(-settings.reverse_limit_a, self.current_max_a)
    }

    /// One tick of a brake: `demand_nm` its demand, `compensated_a` the current the hysteresis
    /// compensation gives for it. Disabled: `compensated_a` unchanged (bit for bit).
    pub fn apply(&self, state: &mut DemagState, demand_nm: f64, compensated_a: f64) -> DemagOutput {
        let unchanged = DemagOutput { current_a: compensated_a, completed: false };
        let Some(settings) = &self.settings else { return unchanged };
        let demanded = demand_nm > settings.release_below_nm;
        let arming = demand_nm > settings.arm_above_nm;
        match state.phase {
            Phase::Idle => {
                if arming {
                    state.phase = Phase::Armed { peak_current_a: compensated_a.max(0.0) };
                }
                unchanged
            }
            Phase::Armed { peak_current_a } => {
                if demanded {
                    let peak_current_a = peak_current_a.max(compensated_a);
                    state.phase = Phase::Armed { peak_current_a };
                    return unchanged;
                }
                let scale = (peak_current_a / settings.reference_peak_a).clamp(0.0, 1.0);
                state.phase = Phase::Releasing { tick: 0, scale };
                self.release_tick(state, 0, scale)
            }
            Phase::Releasing { tick, scale } => {
                if demanded {
                    // A new demand: the brake is needed again, the release stops at once.
                    state.phase = if arming {
                        Phase::Armed { peak_current_a: compensated_a.max(0.0) }
                    } else {
                        Phase::Idle
                    };
                    return unchanged;
                }
                self.release_tick(state, tick, scale)
            }
        }
    }

    /// Waveform tick `tick` of a release, or its closing 0 A tick.
    fn release_tick(&self, state: &mut DemagState, tick: u32, scale: f64) -> DemagOutput {
        if tick >= self.sequence_ticks() {
            state.phase = Phase::Idle;
            return DemagOutput { current_a: 0.0, completed: true };
        }
        state.phase = Phase::Releasing { tick: tick + 1, scale };
        DemagOutput { current_a: self.waveform_current_a(tick, scale), completed: false }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pulse(amplitude_a: f64, duration_s: f64, reverse_limit_a: f64) -> DemagSettings {
        DemagSettings {
            waveform: DemagWaveform::ReversePulse { amplitude_a, duration_s },
            reverse_limit_a,
            arm_above_nm: 0.5,
            release_below_nm: 0.0,
            reference_peak_a: 2.0,
        }
    }

    #[test]
    fn a_pulse_of_five_ticks_then_exactly_zero() {
        let d = Demagnetiser::new(&pulse(0.4, 5e-3, 1.0), 1e-3, 2.0).unwrap();
        assert_eq!(d.sequence_ticks(), 5);
        let mut s = DemagState::default();
        assert!((d.apply(&mut s, 2.0, 2.0).current_a - 2.0).abs() < 1e-15);
        assert!((d.apply(&mut s, 3.0, 2.0).current_a - 2.0).abs() < 1e-15);
        for _ in 0..5 {
            let out = d.apply(&mut s, 0.0, 0.0);
            assert!((out.current_a + 0.4).abs() < 1e-15 && !out.completed);
        }
        let end = d.apply(&mut s, 0.0, 0.0);
        assert!(end.completed && end.current_a.abs() < f64::MIN_POSITIVE);
        assert!(!s.is_releasing());
    }

    #[test]
    fn decaying_ac_alternates_and_shrinks() {
        let settings = DemagSettings {
            waveform: DemagWaveform::DecayingAc {
                first_amplitude_a: 1.0,
                decay_ratio: 0.5,
                half_period_s: 2e-3,
                half_cycles: 4,
            },
            ..pulse(0.1, 1e-3, 1.0)
        };
        let d = Demagnetiser::new(&settings, 1e-3, 2.0).unwrap();
        let currents: [f64; 8] = core::array::from_fn(|k| d.waveform_current_a(k as u32, 1.0));
        let expected = [-1.0, -1.0, 0.5, 0.5, -0.25, -0.25, 0.125, 0.125];
        for (c, e) in currents.iter().zip(expected) {
            assert!((c - e).abs() < 1e-12, "{currents:?}");
        }
    }

    #[test]
    fn a_zero_reverse_limit_disables_and_bad_fields_are_named() {
        let off = Demagnetiser::new(&pulse(0.4, 5e-3, 0.0), 1e-3, 2.0).unwrap();
        assert!(!off.is_enabled());
        let mut s = DemagState::default();
        assert!((off.apply(&mut s, 0.0, 0.7).current_a - 0.7).abs() < f64::MIN_POSITIVE);
        let field = |s: DemagSettings| match Demagnetiser::new(&s, 1e-3, 2.0) {
            Err(ControlError::OutOfRange { field, .. }) => field,
            other => panic!("{other:?}"),
        };
        assert_eq!(field(pulse(-0.4, 5e-3, 1.0)), "amplitude_a");
        assert_eq!(field(pulse(1.5, 5e-3, 1.0)), "amplitude_a");
        assert_eq!(field(pulse(0.4, f64::NAN, 1.0)), "duration_s");
        assert_eq!(field(pulse(0.4, 100.0, 1.0)), "duration_s");
        assert_eq!(field(pulse(0.4, 5e-3, -1.0)), "reverse_limit_a");
        assert_eq!(
            field(DemagSettings { release_below_nm: 0.5, ..pulse(0.4, 5e-3, 1.0) }),
            "release_below_nm"
        );
        let many = DemagSettings {
            waveform: DemagWaveform::DecayingAc {
                first_amplitude_a: 1.0,
                decay_ratio: 0.5,
                half_period_s: 1e-3,
                half_cycles: 1000,
            },
            ..pulse(0.4, 5e-3, 1.0)
        };
        assert_eq!(field(many), "half_cycles");
    }
}
