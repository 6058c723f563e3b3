//! Demagnetising release waveforms judged on the predicted loop: the remanent yield torque the
//! brake keeps at 0 A after a current peak, without demagnetisation and after a reverse pulse or a
//! decaying alternating current, and the reverse-pulse amplitude that leaves the least.
//!
//! Each candidate is one quasi-static history of the hysteretic FEA of [`crate::hysteresis`] (same
//! steel laws, same Newton solve per current, states committed after each), started from the
//! demagnetised steel:
//!
//! `0 → I_p → 0` (the remanent state of a release without demagnetisation, yield torque `R₀`), then
//! the waveform's extrema (`−a → 0` for a reverse pulse of amplitude `a`; `−a₀ → +a₀r → −a₀r² → … → 0`
//! for a decaying alternating current, Bozorth 1951, Jiles 1998: see `mrbrake_control::demag`),
//! and the yield torque at the final 0 A, `R(a)`.
//!
//! The hysteresis law is rate-independent, so only the sequence of extrema matters, not the pulse
//! length or the half period: the candidates hold for any waveform timing slow enough for the flux
//! to follow the current. What the rate adds is not modelled here: eddy currents in the solid steel
//! (`mrbrake response` predicts their lag) delay the flux behind the coil current, so a pulse shorter
//! than that lag reverses less flux than predicted; the controller's pulse lasts several
//! milliseconds for that reason.
//!
//! **The chosen pulse.** `R(a)` falls from `R₀` as the reverse field brings the remanent flux down,
//! reaches its least near the current whose recoil ends at `B ≈ 0` in the gaps (a little above the
//! coercive current: the recoil from the reverse peak gives back part of the flux), and rises again
//! as the steel is magnetised the other way. A coarse scan of `a` over `(0, min(I_p, a_max)]` (a
//! pulse of at least the peak leaves the mirror image of `R₀`, never less) finds the
//! bracket of the least value and a golden-section search (Kiefer 1953; Press et al., *Numerical
//! Recipes*, 3rd ed., §10.2) refines it within the bracket. A check at half the peak current with
//! half the amplitude tells how well the controller's linear scaling of the amplitude with the peak
//! holds.

use std::sync::Arc;
use std::time::Instant;

use mrbrake_error::FieldError;
use serde::Serialize;

use crate::DesignError;
use crate::analysis::{AnalysisOptions, Model};
use crate::hysteresis::{QuasiStatic, set_steel_laws};
use crate::mesh_build;
use crate::spec::BrakeSpec;

/// Most amplitudes of the coarse scan and most golden-section steps.
pub const MAX_SCAN_POINTS: usize = 64;

/// Most half cycles of the decaying alternating current.
pub const MAX_AC_HALF_CYCLES: usize = 64;

/// Options of the demagnetisation scan.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DemagOptions {
    /// Peak current `I_p` (A) before the release; `None`: the coil's maximum current.
    pub peak_current_a: Option<f64>,
    /// Largest reverse current the driver delivers (A); `None`: the coil's maximum current.
    pub reverse_limit_a: Option<f64>,
    /// Currents per leg `0 → I_p` and `I_p → 0` (≥ 2); a waveform leg spanning `Δ` gets
    /// `⌈points_per_leg·Δ/I_p⌉` (at least 2).
    pub points_per_leg: usize,
    /// Amplitudes of the coarse scan, evenly spaced over `(0, a_max]` (2 ..= [`MAX_SCAN_POINTS`]).
    pub scan_points: usize,
    /// Golden-section steps after the scan (0 ..= [`MAX_SCAN_POINTS`]).
    pub golden_steps: usize,
    /// Ratio `r` of successive half-cycle amplitudes of the decaying alternating current, in (0, 1).
    pub ac_decay_ratio: f64,
    /// Half cycles of the decaying alternating current (1 ..= [`MAX_AC_HALF_CYCLES`]); its first
    /// amplitude is `min(I_p, a_max)`.
    pub ac_half_cycles: usize,
}

impl Default for DemagOptions {
    fn default() -> Self {
        Self {
            peak_current_a: None,
            reverse_limit_a: None,
            points_per_leg: 10,
            scan_points: 8,
            golden_steps: 6,
            ac_decay_ratio: 0.6,
            ac_half_cycles: 8,
        }
    }
}

/// A field out of its range, as an input error.
fn out_of_range(field: &str, value: impl ToString, allowed: impl Into<String>) -> DesignError {
    FieldError::out_of_range(field, value.to_string(), allowed.into()).into()
}

impl DemagOptions {
    /// `(I_p, a_max)` for a coil whose maximum is `max_current_a`, every option checked (the errors
    /// name the option and its range).
    pub fn check(&self, max_current_a: f64) -> Result<(f64, f64), DesignError> {
        let current = |field: &str, value: Option<f64>| {
            let v = value.unwrap_or(max_current_a);
            if v.is_finite() && v > 0.0 && v <= max_current_a {
                Ok(v)
            } else {
                Err(out_of_range(field, format!("{v} A"), format!("(0, {max_current_a}] A")))
            }
        };
        let peak = current("peak", self.peak_current_a)?;
        let limit = current("demag_reverse_limit", self.reverse_limit_a)?;
        let counts = [
            ("demag_points", self.points_per_leg, 2, crate::hysteresis::MAX_POINTS_PER_LEG),
            ("demag_scan_points", self.scan_points, 2, MAX_SCAN_POINTS),
            ("demag_golden_steps", self.golden_steps, 0, MAX_SCAN_POINTS),
            ("demag_ac_half_cycles", self.ac_half_cycles, 1, MAX_AC_HALF_CYCLES),
        ];
        for (field, value, min, max) in counts {
            if !(min..=max).contains(&value) {
                return Err(out_of_range(field, value, format!("{min}..={max}")));
            }
        }
        let r = self.ac_decay_ratio;
        if !(r.is_finite() && r > 0.0 && r < 1.0) {
            return Err(out_of_range("demag_ac_decay_ratio", r, "(0, 1)"));
        }
        Ok((peak, limit))
    }
}

/// The release a candidate applies after the peak.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Release {
    /// The current simply returns to 0 A.
    None,
    /// One reverse pulse.
    ReversePulse {
        /// Its amplitude, A.
        #[serde(rename = "amplitude_A")]
        amplitude_a: f64,
    },
    /// A decaying alternating current `−a₀, +a₀r, …`.
    DecayingAc {
        /// First (reverse) amplitude, A.
        #[serde(rename = "first_amplitude_A")]
        first_amplitude_a: f64,
        /// Ratio of successive amplitudes.
        decay_ratio: f64,
        /// Number of half cycles.
        half_cycles: usize,
    },
}

impl Release {
    /// The signed extrema the current visits after the peak's return to 0 A, ending at 0.
    fn extrema(&self) -> Vec<f64> {
        let mut points = match *self {
            Self::None => Vec::new(),
            Self::ReversePulse { amplitude_a } => vec![-amplitude_a],
            Self::DecayingAc { first_amplitude_a, decay_ratio, half_cycles } => (0..half_cycles)
                .map(|k| {
                    let sign = if k % 2 == 0 { -1.0 } else { 1.0 };
                    sign * first_amplitude_a * decay_ratio.powi(k as i32)
                })
                .collect(),
        };
        points.push(0.0);
        points
    }
}

/// One release and what it leaves.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Candidate {
    /// The release.
    pub release: Release,
    /// Yield torque at 0 A after it, N·m.
    #[serde(rename = "remanent_torque_Nm")]
    pub remanent_torque_nm: f64,
    /// That over the remanent torque without demagnetisation (`R/R₀`).
    pub remanence_fraction: f64,
    /// Yield torque at the release's reverse peak (its first extremum), N·m (`R₀` without one).
    #[serde(rename = "yield_torque_at_reverse_peak_Nm")]
    pub yield_torque_at_reverse_peak_nm: f64,
    /// Field solves of the history.
    pub solves: usize,
}

/// The linear-scaling check at half the peak (module docs).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct HalfPeakCheck {
    /// The peak, A (`I_p / 2`).
    #[serde(rename = "peak_current_A")]
    pub peak_current_a: f64,
    /// Remanent torque without demagnetisation, N·m.
    #[serde(rename = "no_release_Nm")]
    pub no_release_nm: f64,
    /// Remanent torque after the chosen pulse at half its amplitude, N·m.
    #[serde(rename = "half_pulse_Nm")]
    pub half_pulse_nm: f64,
}

/// The scan's result.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Demagnetisation {
    /// In words: quasi-static, rate-independent (module docs).
    pub model: String,
    /// Peak current before the release, A.
    #[serde(rename = "peak_current_A")]
    pub peak_current_a: f64,
    /// Largest reverse current considered, A.
    #[serde(rename = "reverse_limit_A")]
    pub reverse_limit_a: f64,
    /// Remanent yield torque without demagnetisation `R₀`, N·m.
    #[serde(rename = "remanent_torque_without_Nm")]
    pub remanent_torque_without_nm: f64,
    /// Every candidate in the order solved: no release, the scan, the golden-section steps, the
    /// decaying alternating current.
    pub candidates: Vec<Candidate>,
    /// The reverse pulse with the least remanent torque.
    pub chosen_pulse: Candidate,
    /// The decaying alternating current.
    pub decaying_ac: Candidate,
    /// The scaling check at half the peak.
    pub half_peak_check: HalfPeakCheck,
    /// Seconds spent.
    pub seconds: f64,
}

/// The field model with the hysteretic steels, and the options of its solves.
struct Runner<'a> {
    model: Model,
    options: &'a AnalysisOptions,
    points_per_leg: usize,
}

impl Runner<'_> {
    /// Yield torques after `0 → peak → 0` and the release: (at the first extremum, at the end,
    /// solves). Starts from the demagnetised steel.
    fn history(&mut self, peak: f64, release: &Release) -> Result<(f64, f64, usize), DesignError> {
        self.model.solver.demagnetise();
        let mut history = QuasiStatic::default();
        let mut current = 0.0;
        let mut solves = 0;
        let mut targets = vec![peak, 0.0];
        targets.extend(release.extrema());
        let mut at_first_extremum = 0.0;
        let mut last = 0.0;
        for (index, &target) in targets.iter().enumerate() {
            let span = (target - current).abs();
            // A leg of zero length (no release: the history ends at the first 0 A) needs no solve.
            let steps = if span > 0.0 {
                ((self.points_per_leg as f64 * span / peak).ceil() as usize).max(2)
            } else {
                0
            };
            for k in 1..=steps {
                let i = current + (target - current) * k as f64 / steps as f64;
                solves += 1;
                let step = |e: DesignError| DesignError::LoopStep {
                    step: solves,
                    current_a: i,
                    source: Box::new(e),
                };
                let (point, _) = history.step(&mut self.model, i, self.options).map_err(step)?;
                last = point.yield_torque_nm;
            }
            current = target;
            // Index 2 is the release's first extremum (`R₀` again without a release).
            if index == 2 {
                at_first_extremum = last;
            }
        }
        Ok((at_first_extremum, last, solves))
    }

    /// The candidate of `release` after `peak`, its fraction relative to `without`.
    fn candidate(
        &mut self,
        peak: f64,
        release: Release,
        without: f64,
    ) -> Result<Candidate, DesignError> {
        let (at_reverse_peak, remanent, solves) = self.history(peak, &release)?;
        Ok(Candidate {
            release,
            remanent_torque_nm: remanent,
            remanence_fraction: if without > 0.0 { remanent / without } else { 0.0 },
            yield_torque_at_reverse_peak_nm: at_reverse_peak,
            solves,
        })
    }
}

/// Runs the scan on `spec` with the analysis options `options` (mesh, order) and `demag`.
pub fn run(
    spec: &BrakeSpec,
    options: &AnalysisOptions,
    demag: &DemagOptions,
) -> Result<Demagnetisation, DesignError> {
    let start = Instant::now();
    options.check()?;
    let geometry = spec.validate()?.geometry;
    let (peak, limit) = demag.check(spec.coil.max_current.a())?;
    let mesh = Arc::new(mesh_build::mesh_spec(spec, &geometry, options.mesh)?);
    let mut model = Model::new(spec, geometry, mesh, options)?;
    set_steel_laws(spec, &mut model)?;
    let mut runner = Runner { model, options, points_per_leg: demag.points_per_leg };
    let none = runner.candidate(peak, Release::None, 0.0)?;
    let without = none.remanent_torque_nm;
    let mut candidates = vec![Candidate { remanence_fraction: 1.0, ..none }];
    let pulse = |runner: &mut Runner, a: f64| {
        runner.candidate(peak, Release::ReversePulse { amplitude_a: a }, without)
    };
    // Coarse scan over (0, min(I_p, a_max)] (a reverse pulse of at least the peak leaves the mirror
    // image of the remanence: never less), then golden section in the bracket of its least value.
    let n = demag.scan_points;
    let span = peak.min(limit);
    let mut scan = Vec::with_capacity(n);
    for k in 1..=n {
        scan.push(pulse(&mut runner, span * k as f64 / n as f64)?);
    }
    let best = least(&scan);
    let low = if best == 0 { 0.0 } else { span * best as f64 / n as f64 };
    let high = span * ((best + 2).min(n)) as f64 / n as f64;
    candidates.extend(scan);
    let refined = golden_section(low, high, demag.golden_steps, |a| pulse(&mut runner, a))?;
    candidates.extend(refined);
    // The scan has at least 2 pulses (checked), so the fallback to "no release" never applies.
    let chosen_pulse =
        candidates[1..].iter().min_by(|a, b| order(a, b)).unwrap_or(&candidates[0]).clone();
    let ac = Release::DecayingAc {
        first_amplitude_a: peak.min(limit),
        decay_ratio: demag.ac_decay_ratio,
        half_cycles: demag.ac_half_cycles,
    };
    let decaying_ac = runner.candidate(peak, ac, without)?;
    candidates.push(decaying_ac.clone());
    let half_peak_check = half_peak(&mut runner, peak, &chosen_pulse)?;
    Ok(Demagnetisation {
        model:
            "quasi-static, rate-independent: the hysteretic FEA of `analyze --hysteresis` along \
                each release's extrema; eddy currents in the solid steel (not modelled here) delay \
                the flux behind a fast pulse"
                .into(),
        peak_current_a: peak,
        reverse_limit_a: limit,
        remanent_torque_without_nm: without,
        candidates,
        chosen_pulse,
        decaying_ac,
        half_peak_check,
        seconds: start.elapsed().as_secs_f64(),
    })
}

/// The check at half the peak with the chosen pulse at half its amplitude.
fn half_peak(
    runner: &mut Runner,
    peak: f64,
    chosen: &Candidate,
) -> Result<HalfPeakCheck, DesignError> {
    let half = 0.5 * peak;
    let amplitude = match chosen.release {
        Release::ReversePulse { amplitude_a } => 0.5 * amplitude_a,
        _ => 0.0,
    };
    let (_, no_release_nm, _) = runner.history(half, &Release::None)?;
    let (_, half_pulse_nm, _) =
        runner.history(half, &Release::ReversePulse { amplitude_a: amplitude })?;
    Ok(HalfPeakCheck { peak_current_a: half, no_release_nm, half_pulse_nm })
}

/// Orders candidates by remanent torque (NaN last).
fn order(a: &Candidate, b: &Candidate) -> std::cmp::Ordering {
    a.remanent_torque_nm.total_cmp(&b.remanent_torque_nm)
}

/// Index of the candidate with the least remanent torque.
fn least(candidates: &[Candidate]) -> usize {
    (0..candidates.len()).min_by(|&i, &j| order(&candidates[i], &candidates[j])).unwrap_or(0)
}

/// `steps` golden-section evaluations of `f` in `[low, high]` (Press et al. §10.2), every one
/// returned.
fn golden_section(
    mut low: f64,
    mut high: f64,
    steps: usize,
    mut f: impl FnMut(f64) -> Result<Candidate, DesignError>,
) -> Result<Vec<Candidate>, DesignError> {
    const INVERSE_PHI: f64 = 0.618_033_988_749_894_8;
    let mut evaluated: Vec<Candidate> = Vec::with_capacity(steps);
    if steps == 0 {
        return Ok(evaluated);
    }
    let mut x1 = high - INVERSE_PHI * (high - low);
    let mut x2 = low + INVERSE_PHI * (high - low);
    let mut f1 = f(x1)?;
    evaluated.push(f1.clone());
    if steps == 1 {
        return Ok(evaluated);
    }
    let mut f2 = f(x2)?;
    evaluated.push(f2.clone());
    while evaluated.len() < steps {
        if f1.remanent_torque_nm <= f2.remanent_torque_nm {
            (high, x2, f2) = (x2, x1, f1);
            x1 = high - INVERSE_PHI * (high - low);
            f1 = f(x1)?;
            evaluated.push(f1.clone());
        } else {
            (low, x1, f1) = (x1, x2, f2);
            x2 = low + INVERSE_PHI * (high - low);
            f2 = f(x2)?;
            evaluated.push(f2.clone());
        }
    }
    Ok(evaluated)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn fake(a: f64) -> Result<Candidate, DesignError> {
        Ok(Candidate {
            release: Release::ReversePulse { amplitude_a: a },
            remanent_torque_nm: (a - 0.37).abs() + 0.01,
            remanence_fraction: 0.0,
            yield_torque_at_reverse_peak_nm: 0.0,
            solves: 0,
        })
    }

    #[test]
    fn golden_section_closes_on_the_least_value() {
        let found = golden_section(0.0, 1.0, 20, fake).unwrap();
        let best = &found[least(&found)];
        let Release::ReversePulse { amplitude_a } = best.release else { panic!() };
        assert!((amplitude_a - 0.37).abs() < 1e-3, "{amplitude_a}");
    }

    #[test]
    fn extrema_alternate_and_end_at_zero() {
        let ac = Release::DecayingAc { first_amplitude_a: 2.0, decay_ratio: 0.5, half_cycles: 3 };
        assert_eq!(ac.extrema(), vec![-2.0, 1.0, -0.5, 0.0]);
        assert_eq!(Release::None.extrema(), vec![0.0]);
    }

    #[test]
    fn bad_options_name_their_field() {
        let check = |o: DemagOptions| o.check(2.0).unwrap_err().to_string();
        let base = DemagOptions::default();
        assert!(
            check(DemagOptions { reverse_limit_a: Some(-1.0), ..base })
                .contains("demag_reverse_limit")
        );
        assert!(
            check(DemagOptions { ac_decay_ratio: f64::NAN, ..base })
                .contains("demag_ac_decay_ratio")
        );
        assert!(check(DemagOptions { scan_points: 100_000, ..base }).contains("demag_scan_points"));
        assert!(check(DemagOptions { ac_half_cycles: 0, ..base }).contains("demag_ac_half_cycles"));
        assert!(check(DemagOptions { peak_current_a: Some(3.0), ..base }).contains("peak"));
        assert_eq!(base.check(2.0).unwrap(), (2.0, 2.0));
    }
}
