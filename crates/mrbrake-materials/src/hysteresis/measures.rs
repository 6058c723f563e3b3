//! The figures of a hysteresis loop: coercivity, remanence, loop area (hysteresis loss per cycle),
//! and the simulated major loop of a parameter set.
//!
//! A loop is a sequence of `(H, B)` samples in the order they were traversed. Coercivity `H_c` is
//! `|H|` where B crosses zero on the descending branch, remanence `B_r` is B where H crosses zero on the
//! descending branch (both by linear interpolation between samples); the loop area
//! `∮ H dB` (J/m³ per cycle, the hysteresis loss) is the trapezoidal rule over the samples.

use serde::Serialize;

use super::{HysteresisParams, HysteresisState};

/// Figures of a closed loop.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct LoopMeasures {
    /// Coercivity `H_c` on the descending branch, A/m (`None` when B does not cross zero).
    #[serde(rename = "coercivity_A_per_m")]
    pub coercivity_a_per_m: Option<f64>,
    /// Remanence `B_r` on the descending branch, T (`None` when H does not cross zero).
    #[serde(rename = "remanence_T")]
    pub remanence_t: Option<f64>,
    /// Largest |B| of the loop, T.
    #[serde(rename = "peak_B_T")]
    pub peak_b_t: f64,
    /// Largest |H| of the loop, A/m.
    #[serde(rename = "peak_H_A_per_m")]
    pub peak_h_a_per_m: f64,
    /// `∮ H dB` over the samples (trapezoidal), J/m³ per cycle.
    #[serde(rename = "area_J_per_m3")]
    pub area_j_per_m3: f64,
}

/// Measures a loop given as `(H, B)` samples in traversal order.
pub fn loop_measures(samples: &[(f64, f64)]) -> LoopMeasures {
    let mut coercivity = None;
    let mut remanence = None;
    let mut area = 0.0;
    for pair in samples.windows(2) {
        let ((h0, b0), (h1, b1)) = (pair[0], pair[1]);
        area += 0.5 * (h0 + h1) * (b1 - b0);
        let descending = h1 < h0;
        if descending && coercivity.is_none() && b0 > 0.0 && b1 <= 0.0 {
            coercivity = Some((h0 + (h1 - h0) * b0 / (b0 - b1)).abs());
        }
        if descending && remanence.is_none() && h0 > 0.0 && h1 <= 0.0 {
            remanence = Some(b0 + (b1 - b0) * h0 / (h0 - h1));
        }
    }
    LoopMeasures {
        coercivity_a_per_m: coercivity,
        remanence_t: remanence,
        peak_b_t: samples.iter().map(|s| s.1.abs()).fold(0.0, f64::max),
        peak_h_a_per_m: samples.iter().map(|s| s.0.abs()).fold(0.0, f64::max),
        area_j_per_m3: area,
    }
}

/// The symmetric major loop of `params` at field amplitude `h_max` (A/m), H-driven: from the
/// demagnetised state up to `h_max`, then one full cycle `h_max → −h_max → h_max` with
/// `points_per_branch` steps per branch; returns the cycle's `2·points_per_branch + 1` samples,
/// starting and ending at the tip.
pub fn major_loop(
    params: &HysteresisParams,
    h_max: f64,
    points_per_branch: usize,
) -> Vec<(f64, f64)> {
    let n = points_per_branch.max(1);
    let mut state = HysteresisState::demagnetised();
    for i in 1..=n {
        state.step_h(params, h_max * i as f64 / n as f64);
    }
    let mut samples = Vec::with_capacity(2 * n + 1);
    samples.push((state.h(), state.b()));
    for i in 1..=2 * n {
        // Down from h_max to −h_max, then back up.
        let phase = i as f64 / n as f64;
        let h = if i <= n { h_max * (1.0 - 2.0 * phase) } else { h_max * (2.0 * phase - 3.0) };
        let r = state.step_h(params, h);
        samples.push((r.h, r.b));
    }
    samples
}
