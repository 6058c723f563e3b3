//! Characterisation of the static torque–current hysteresis loop from a repeated-ramp log (thesis §5.3.1).
//!
//! Protocol in the thesis: the current rises from 0 to 2 A in 1 mA steps every 10 ms, falls back the
//! same way, pauses 5 s, and the sequence repeats ten times while the torque is sampled at 1 kHz.
//! The analysis here does not assume those numbers:
//!
//! 1. **Segmentation** with a Schmitt trigger on the current (10 % and 90 % of its range): every excursion
//!    low → high → low is one repetition. Its rising part runs from the (last) lowest-current sample of
//!    the low phase before the excursion to the current's peak; its falling part from the peak to the
//!    first lowest-current sample of the following low phase. Samples resting within 1 % of the range
//!    of the minimum between repetitions give the off-state torque.
//! 2. **Averaging**: the samples of all repetitions are binned by current (default 200 bins) and the
//!    torque averaged per bin and branch, the mean torque signal of the thesis.
//! 3. **Branch fits**: a polynomial (default quintic, as in the thesis) through each averaged branch,
//!    solved in a scaled variable ([`crate::polynomial::fit`]) and reported in ascending powers of the
//!    current in A. The fit percentage is 100·(1 − ‖T − T̂‖/‖T − mean T‖) over the **raw** samples of
//!    the branch (all repetitions), like the thesis's fit to the raw torque signal.

use mrbrake_control::{ControlError, InverseModel};
use mrbrake_error::FieldError;

use crate::SysidError;
use crate::polynomial::{Polynomial, fit};

/// The branches' default polynomial order: quintic, as the thesis (§5.3.1).
pub const DEFAULT_ORDER: usize = 5;
/// The default number of current bins the repetitions are averaged in.
pub const DEFAULT_BINS: usize = 200;

/// Settings of the characterisation.
#[derive(Debug, Clone, Copy)]
pub struct CharacterizeOptions {
    /// Polynomial order of each branch (thesis: 5).
    pub order: usize,
    /// Number of current bins used to average the repetitions.
    pub bins: usize,
}

impl Default for CharacterizeOptions {
    fn default() -> Self {
        Self { order: DEFAULT_ORDER, bins: DEFAULT_BINS }
    }
}

impl CharacterizeOptions {
    /// The highest branch order: beyond it the Chebyshev fit of a loop's few current levels is
    /// interpolation of noise.
    pub const MAX_ORDER: usize = 12;

    /// Checks the order (`1..=12`) and the bins (at least two per coefficient): the field errors
    /// name `order` and `bins`. [`characterize`] checks them too; a front end calls this before
    /// reading a log, whose minimum length depends on the order.
    pub fn check(&self) -> Result<(), SysidError> {
        if !(1..=Self::MAX_ORDER).contains(&self.order) {
            let allowed = format!("1..={}", Self::MAX_ORDER);
            return Err(FieldError::out_of_range("order", self.order, allowed).into());
        }
        if self.bins < 2 * (self.order + 1) {
            return Err(FieldError::new("bins", format!("too few for order {}", self.order))
                .with_value(self.bins)
                .with_allowed(format!(">= {}", 2 * (self.order + 1)))
                .into());
        }
        Ok(())
    }
}

/// One fitted branch.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct BranchFit {
    /// Torque in N·m as a polynomial in the current in A, ascending powers.
    pub coefficients: Vec<f64>,
    /// 100·(1 − ‖T − T̂‖/‖T − mean T‖) over the raw samples of this branch, all repetitions.
    pub fit_percent: f64,
    /// The same measure against the repetition-averaged branch.
    pub fit_percent_mean: f64,
    /// Raw samples used.
    pub samples: usize,
}

/// Result of a characterisation (serialised as the `characterize` JSON and the inverse-model file,
/// whose reader is [`crate::model_file`]).
#[derive(Debug, Clone, serde::Serialize)]
pub struct Characterization {
    /// Branch while the current increases.
    pub rising: BranchFit,
    /// Branch while the current decreases.
    pub falling: BranchFit,
    /// Lowest current in the log, A.
    #[serde(rename = "current_min_A")]
    pub current_min_a: f64,
    /// Highest current in the log, A.
    #[serde(rename = "current_max_A")]
    pub current_max_a: f64,
    /// Mean torque while the current rests at its minimum between repetitions, N·m (thesis: 0.15 N·m).
    #[serde(rename = "off_state_torque_Nm")]
    pub off_state_torque_nm: f64,
    /// Largest torque of the fitted branches over the current range, N·m (thesis: 3.84 N·m at 2 A);
    /// taken from the fits rather than the raw peak so that sensor noise does not inflate it.
    #[serde(rename = "max_torque_Nm")]
    pub max_torque_nm: f64,
    /// Largest |T_falling(I) − T_rising(I)| of the fitted branches over the current range, N·m.
    #[serde(rename = "max_hysteresis_Nm")]
    pub max_hysteresis_nm: f64,
    /// Current at which that width occurs, A.
    #[serde(rename = "max_hysteresis_current_A")]
    pub max_hysteresis_current_a: f64,
    /// Number of complete repetitions found.
    pub repetitions: usize,
    /// Repetition-averaged rising branch, (current A, torque N·m) per non-empty bin.
    #[serde(skip)]
    pub rising_mean: Vec<(f64, f64)>,
    /// Repetition-averaged falling branch.
    #[serde(skip)]
    pub falling_mean: Vec<(f64, f64)>,
}

impl Characterization {
    /// The two fitted branches as the controller's [`InverseModel`]. Fails when a branch does not
    /// fit the controller's fixed-size tables (order above [`mrbrake_control::MAX_DEGREE`]) or
    /// decreases somewhere on the current range, so that its inverse is not unique.
    pub fn model(&self) -> Result<InverseModel, ControlError> {
        InverseModel::new(
            &self.rising.coefficients,
            &self.falling.coefficients,
            self.current_min_a,
            self.current_max_a,
        )
    }
}

/// One repetition: index ranges (inclusive start, exclusive end) of its rising and falling parts.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Repetition {
    /// Samples of the rising part.
    pub rising: (usize, usize),
    /// Samples of the falling part.
    pub falling: (usize, usize),
}

/// Finds the repetitions of a ramp-up/ramp-down current sequence (step 1 of the module docs).
pub fn segment(current_a: &[f64]) -> Result<(Vec<Repetition>, f64, f64), SysidError> {
    let (lo, hi) = current_a
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), v| (l.min(*v), h.max(*v)));
    let range = hi - lo;
    if range.is_nan() || range <= 0.0 {
        return Err(FieldError::new(
            "current",
            "characterize: the current never changes, there is no ramp to analyse",
        )
        .with_value(format!("{lo} A throughout"))
        .into());
    }
    let low_th = lo + 0.1 * range;
    let high_th = lo + 0.9 * range;
    let n = current_a.len();
    let mut reps = Vec::new();
    // Index of the lowest current of the current low phase (the last one when several are equal).
    let mut low_phase_min: Option<usize> = None;
    let mut i = 0;
    while i < n {
        if low_phase_min.is_none_or(|k| current_a[i] <= current_a[k]) {
            low_phase_min = Some(i);
        }
        if current_a[i] > high_th {
            let start = low_phase_min.unwrap_or(0);
            // High phase: peak until the current falls below the low threshold.
            let mut peak = i;
            let mut j = i;
            while j < n && current_a[j] >= low_th {
                if current_a[j] > current_a[peak] {
                    peak = j;
                }
                j += 1;
            }
            // Falling end: the first sample at the lowest current before the current rises again.
            let next_rise = (j..n).find(|&k| current_a[k] > high_th).unwrap_or(n);
            if next_rise == n && j == n {
                break; // incomplete last repetition
            }
            let end = (j..next_rise)
                .fold(j, |best, k| if current_a[k] < current_a[best] { k } else { best });
            if current_a[end] > lo + 0.05 * range {
                break; // the log ends before the current is back at the bottom
            }
            reps.push(Repetition { rising: (start, peak + 1), falling: (peak, end + 1) });
            low_phase_min = None;
            i = end;
            continue;
        }
        i += 1;
    }
    if reps.is_empty() {
        return Err(FieldError::new(
            "current",
            format!(
                "characterize: no complete ramp found (the current must rise from near {lo:.4} A \
                 to above {high_th:.4} A and come back)"
            ),
        )
        .into());
    }
    Ok((reps, lo, hi))
}

/// 100·(1 − ‖y − ŷ‖/‖y − mean y‖), the fit percentage used throughout (MATLAB's NRMSE fit).
pub fn fit_percent(y: &[f64], y_hat: &[f64]) -> f64 {
    let mean = y.iter().sum::<f64>() / y.len().max(1) as f64;
    let err: f64 = y.iter().zip(y_hat).map(|(a, b)| (a - b) * (a - b)).sum::<f64>().sqrt();
    let spread: f64 = y.iter().map(|a| (a - mean) * (a - mean)).sum::<f64>().sqrt();
    100.0 * (1.0 - err / spread)
}

/// Characterises the loop from current (A) and torque (N·m) samples.
pub fn characterize(
    current_a: &[f64],
    torque_nm: &[f64],
    options: CharacterizeOptions,
) -> Result<Characterization, SysidError> {
    check_options(current_a, torque_nm, options)?;
    let (reps, lo, hi) = segment(current_a)?;
    let samples = Samples { current_a, torque_nm, reps: &reps, lo, hi };
    let (rising, rising_mean) = samples.fit_branch(|r| r.rising, options)?;
    let (falling, falling_mean) = samples.fit_branch(|r| r.falling, options)?;
    let p_up = Polynomial::new(rising.coefficients.clone());
    let p_down = Polynomial::new(falling.coefficients.clone());
    let off_state_torque_nm = samples.off_state_torque_nm().unwrap_or_else(|| p_up.eval(lo));
    let extremes = loop_extremes(&p_up, &p_down, lo, hi);
    if ![extremes.max_torque_nm, rising.fit_percent, falling.fit_percent]
        .iter()
        .all(|v| v.is_finite())
    {
        return Err(non_finite_fit(torque_nm).into());
    }
    Ok(Characterization {
        rising,
        falling,
        current_min_a: lo,
        current_max_a: hi,
        off_state_torque_nm,
        max_torque_nm: extremes.max_torque_nm,
        max_hysteresis_nm: extremes.max_hysteresis_nm,
        max_hysteresis_current_a: extremes.max_hysteresis_current_a,
        repetitions: reps.len(),
        rising_mean,
        falling_mean,
    })
}

/// Why a fit came out non-finite: the largest torque sample (issue 18: one 1e308 sample).
fn non_finite_fit(torque_nm: &[f64]) -> FieldError {
    let (k, v) = torque_nm
        .iter()
        .enumerate()
        .max_by(|a, b| a.1.abs().total_cmp(&b.1.abs()))
        .map_or((0, f64::NAN), |(k, v)| (k, *v));
    FieldError::new(
        format!("torque[{k}]"),
        "characterize: the branch fit is not finite: remove the corrupted samples",
    )
    .with_value(format!("{v} N·m (the largest sample)"))
}

/// Checks that the signals match and the order and bin count are usable.
fn check_options(
    current_a: &[f64],
    torque_nm: &[f64],
    options: CharacterizeOptions,
) -> Result<(), SysidError> {
    if current_a.len() != torque_nm.len() {
        return Err(FieldError::new("torque", "characterize: current and torque differ in length")
            .with_value(format!("{} samples", torque_nm.len()))
            .with_allowed(format!("{} samples, as the current", current_a.len()))
            .into());
    }
    options.check()
}

/// The log's samples with its repetitions and current range.
struct Samples<'a> {
    current_a: &'a [f64],
    torque_nm: &'a [f64],
    reps: &'a [Repetition],
    lo: f64,
    hi: f64,
}

impl Samples<'_> {
    /// Steps 2 and 3 of the module docs for the branch that `pick` selects from each repetition:
    /// the fit and the repetition-averaged (current, torque) points.
    fn fit_branch(
        &self,
        pick: fn(&Repetition) -> (usize, usize),
        options: CharacterizeOptions,
    ) -> Result<(BranchFit, Vec<(f64, f64)>), SysidError> {
        let mean = self.bin_average(pick, options.bins);
        if mean.len() < options.order + 1 {
            return Err(FieldError::new(
                "current",
                format!("characterize: too few current levels visited for order {}", options.order),
            )
            .with_value(format!("{} levels", mean.len()))
            .with_allowed(format!(">= {} levels", options.order + 1))
            .into());
        }
        let (xs, ys): (Vec<f64>, Vec<f64>) = mean.iter().copied().unzip();
        let p = fit(&xs, &ys, options.order)?;
        let fitted_mean: Vec<f64> = xs.iter().map(|x| p.eval(*x)).collect();
        let (mut raw_t, mut raw_hat) = (Vec::new(), Vec::new());
        for r in self.reps {
            let (a, b) = pick(r);
            for k in a..b {
                raw_t.push(self.torque_nm[k]);
                raw_hat.push(p.eval(self.current_a[k]));
            }
        }
        let branch = BranchFit {
            fit_percent: fit_percent(&raw_t, &raw_hat),
            fit_percent_mean: fit_percent(&ys, &fitted_mean),
            samples: raw_t.len(),
            coefficients: p.coefficients,
        };
        Ok((branch, mean))
    }

    /// The branch's samples of all repetitions averaged per current bin: (mean current, mean torque)
    /// of each non-empty bin, in current order.
    fn bin_average(&self, pick: fn(&Repetition) -> (usize, usize), bins: usize) -> Vec<(f64, f64)> {
        let (lo, hi) = (self.lo, self.hi);
        let bin_of = |i: f64| (((i - lo) / (hi - lo) * bins as f64) as usize).min(bins - 1);
        let mut sum_i = vec![0.0; bins];
        let mut sum_t = vec![0.0; bins];
        let mut count = vec![0usize; bins];
        for r in self.reps {
            let (a, b) = pick(r);
            for k in a..b {
                let bin = bin_of(self.current_a[k]);
                sum_i[bin] += self.current_a[k];
                sum_t[bin] += self.torque_nm[k];
                count[bin] += 1;
            }
        }
        (0..bins)
            .filter(|b| count[*b] > 0)
            .map(|b| (sum_i[b] / count[b] as f64, sum_t[b] / count[b] as f64))
            .collect()
    }

    /// Mean torque of the samples resting at the bottom (within 1 % of the range of the minimum)
    /// between and after the repetitions; `None` when there are none.
    fn off_state_torque_nm(&self) -> Option<f64> {
        let bottom = self.lo + 0.01 * (self.hi - self.lo);
        let mut off = (0.0, 0usize);
        for (w, r) in self.reps.iter().enumerate() {
            let from = r.falling.1;
            let to = self.reps.get(w + 1).map_or(self.current_a.len(), |next| next.rising.0);
            for k in from..to {
                if self.current_a[k] <= bottom {
                    off.0 += self.torque_nm[k];
                    off.1 += 1;
                }
            }
        }
        (off.1 > 0).then(|| off.0 / off.1 as f64)
    }
}

/// Largest torque and widest hysteresis of the fitted branches over the current range.
struct LoopExtremes {
    max_torque_nm: f64,
    max_hysteresis_nm: f64,
    max_hysteresis_current_a: f64,
}

/// [`LoopExtremes`] of the fitted branches, sampled at 1001 currents over `[lo, hi]`.
fn loop_extremes(p_up: &Polynomial, p_down: &Polynomial, lo: f64, hi: f64) -> LoopExtremes {
    let (mut max_h, mut max_h_i) = (0.0_f64, lo);
    let mut max_torque_nm = f64::NEG_INFINITY;
    for k in 0..=1000 {
        let i = lo + (hi - lo) * k as f64 / 1000.0;
        max_torque_nm = max_torque_nm.max(p_up.eval(i)).max(p_down.eval(i));
        let w = (p_down.eval(i) - p_up.eval(i)).abs();
        if w > max_h {
            max_h = w;
            max_h_i = i;
        }
    }
    LoopExtremes { max_torque_nm, max_hysteresis_nm: max_h, max_hysteresis_current_a: max_h_i }
}

#[cfg(test)]
mod tests {
    use super::*;
    use mrbrake_error::Kind as _;

    /// The thesis protocol with a static loop (no dynamics, no noise): rising T = 0.15 + 1.8 I,
    /// falling T = 0.15 + 1.8 I + 0.3 I (2 − I).
    fn protocol(reps: usize) -> (Vec<f64>, Vec<f64>) {
        let (mut i_a, mut t_nm) = (Vec::new(), Vec::new());
        for _ in 0..reps {
            for k in 0..=2000 {
                for _ in 0..10 {
                    let i = k as f64 * 1e-3;
                    i_a.push(i);
                    t_nm.push(0.15 + 1.8 * i);
                }
            }
            for k in (0..2000).rev() {
                for _ in 0..10 {
                    let i = k as f64 * 1e-3;
                    i_a.push(i);
                    t_nm.push(0.15 + 1.8 * i + 0.3 * i * (2.0 - i));
                }
            }
            for _ in 0..5000 {
                i_a.push(0.0);
                t_nm.push(0.15);
            }
        }
        (i_a, t_nm)
    }

    #[test]
    fn an_order_outside_its_range_names_the_field_value_and_range() {
        let (i_a, t_nm) = protocol(3);
        let e =
            characterize(&i_a, &t_nm, CharacterizeOptions { order: 13, bins: 200 }).unwrap_err();
        let SysidError::Input(f) = &e else { panic!("{e:?}") };
        assert_eq!((f.field.as_str(), f.value.as_deref()), ("order", Some("13")));
        assert_eq!(f.allowed.as_deref(), Some("1..=12"));
        let e = characterize(&i_a, &t_nm, CharacterizeOptions { order: 5, bins: 3 }).unwrap_err();
        let SysidError::Input(f) = &e else { panic!("{e:?}") };
        assert_eq!((f.field.as_str(), f.allowed.as_deref()), ("bins", Some(">= 12")));
    }

    #[test]
    fn segmentation_counts_repetitions() {
        let (i, _) = protocol(3);
        let (reps, lo, hi) = segment(&i).unwrap();
        assert_eq!(reps.len(), 3);
        assert!(lo.abs() < 1e-15 && (hi - 2.0).abs() < 1e-12);
        // Each rising part ends at the peak (2 A).
        for r in &reps {
            assert!((i[r.rising.1 - 1] - 2.0).abs() < 1e-12);
            assert!(i[r.falling.1 - 1].abs() < 1e-12);
        }
    }

    #[test]
    fn static_loop_is_recovered_exactly() {
        let (i, t) = protocol(2);
        let c = characterize(&i, &t, CharacterizeOptions { order: 2, bins: 200 }).unwrap();
        assert_eq!(c.repetitions, 2);
        let up = Polynomial::new(c.rising.coefficients.clone());
        let down = Polynomial::new(c.falling.coefficients.clone());
        // Averaging within 10 mA bins biases a curved branch by T''·h²/24 ≈ 2.5e-6 N·m.
        for k in 0..=20 {
            let x = k as f64 * 0.1;
            assert!((up.eval(x) - (0.15 + 1.8 * x)).abs() < 1e-9);
            assert!((down.eval(x) - (0.15 + 1.8 * x + 0.3 * x * (2.0 - x))).abs() < 1e-5);
        }
        assert!(c.rising.fit_percent > 99.999);
        assert!((c.off_state_torque_nm - 0.15).abs() < 1e-12);
        assert!((c.max_torque_nm - 3.75).abs() < 1e-5);
        assert!(
            (c.max_hysteresis_nm - 0.3).abs() < 1e-5
                && (c.max_hysteresis_current_a - 1.0).abs() < 1e-2
        );
    }

    #[test]
    fn constant_current_is_an_input_error() {
        let err =
            characterize(&[1.0; 100], &[0.5; 100], CharacterizeOptions::default()).unwrap_err();
        assert!(err.is_input_error());
    }
}
