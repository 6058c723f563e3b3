//! One branch of a brake's torque–current characteristic as a fixed-size polynomial, and its
//! bounded-iteration inverse.
//!
//! The identification (thesis §5.3.1) fits a quintic `T(i) = Σ c_k i^k` (torque in Nm, current in A,
//! ascending powers) to the rising and to the falling half of the hysteresis loop. The controller needs
//! the inverse `i(T)`; it solves `T(i) = T_target` on `[i_min, i_max]` with a safeguarded Newton
//! iteration that never leaves the bracket (each step falls back to bisection when Newton would jump
//! out of it or stall), so it always terminates within [`MAX_INVERSE_ITERATIONS`] and always returns a
//! current inside the range.

/// Highest polynomial degree a branch may have (the thesis uses 5; 7 leaves room for richer fits).
pub const MAX_DEGREE: usize = 7;

/// Upper bound on the iterations of [`BranchPolynomial::invert`]; a hard real-time bound.
pub const MAX_INVERSE_ITERATIONS: usize = 24;

/// Relative torque tolerance at which the inverse stops early (0.01 % of the branch span).
const INVERSE_RELATIVE_TOLERANCE: f64 = 1e-4;

/// A torque–current branch `T(i) = Σ_{k=0}^{degree} c_k i^k` with coefficients in ascending powers
/// (Nm/A^k). Unused higher coefficients are zero.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BranchPolynomial {
    coefficients: [f64; MAX_DEGREE + 1],
    /// Number of coefficients in use (trailing zeros are not evaluated).
    len: usize,
}

impl BranchPolynomial {
    /// A branch from up to `MAX_DEGREE + 1` ascending coefficients. Returns `None` when there are too
    /// many coefficients, none at all, or a coefficient is not finite.
    pub fn from_ascending(coefficients: &[f64]) -> Option<Self> {
        if coefficients.is_empty() || coefficients.len() > MAX_DEGREE + 1 {
            return None;
        }
        let mut stored = [0.0; MAX_DEGREE + 1];
        for (slot, &c) in stored.iter_mut().zip(coefficients) {
            if !c.is_finite() {
                return None;
            }
            *slot = c;
        }
        let mut len = coefficients.len();
        // Exactly ±0.0 (sign bit shifted out): trailing zero coefficients need no evaluation.
        while len > 1 && stored[len - 1].to_bits() << 1 == 0 {
            len -= 1;
        }
        Some(Self { coefficients: stored, len })
    }

    /// The ascending coefficients (always `MAX_DEGREE + 1` of them, trailing zeros included).
    pub fn coefficients(&self) -> &[f64; MAX_DEGREE + 1] {
        &self.coefficients
    }

    /// Torque `T(i)` in Nm at current `current_a` (Horner's scheme).
    #[inline]
    pub fn torque_nm(&self, current_a: f64) -> f64 {
        self.coefficients[..self.len].iter().rev().fold(0.0, |acc, &c| acc * current_a + c)
    }

    /// Torque and its slope `dT/di` (Nm/A) at `current_a`, evaluated together by Horner's scheme.
    #[inline]
    pub fn torque_and_slope(&self, current_a: f64) -> (f64, f64) {
        let mut value = 0.0;
        let mut slope = 0.0;
        for &c in self.coefficients[..self.len].iter().rev() {
            slope = slope * current_a + value;
            value = value * current_a + c;
        }
        (value, slope)
    }

    /// True when the branch does not decrease on `[current_min_a, current_max_a]`, checked on
    /// `samples` equally spaced points (host-side validation of an identified model).
    pub fn is_non_decreasing(
        &self,
        current_min_a: f64,
        current_max_a: f64,
        samples: usize,
    ) -> bool {
        let n = samples.max(2);
        let mut previous = self.torque_nm(current_min_a);
        for k in 1..n {
            let i = current_min_a + (current_max_a - current_min_a) * k as f64 / (n - 1) as f64;
            let t = self.torque_nm(i);
            // Allow round-off-sized dips only.
            if t < previous - 1e-12 * (1.0 + previous.abs()) {
                return false;
            }
            previous = t;
        }
        true
    }

    /// The current in `[current_min_a, current_max_a]` at which the branch gives `target_nm`.
    ///
    /// Targets below `T(i_min)` give `i_min` (the brake cannot produce less than its off-state torque)
    /// and targets above `T(i_max)` give `i_max` (saturation). In between, a safeguarded Newton
    /// iteration keeps a bracket `[lo, hi]` with `T(lo) ≤ target ≤ T(hi)`; a Newton step that leaves
    /// the bracket or has a non-positive slope is replaced by bisection. A non-decreasing branch is
    /// required for a unique answer (checked on the host by [`Self::is_non_decreasing`]); for any
    /// other branch the result is still a current inside the range. Non-finite targets give `i_min`.
    pub fn invert(&self, target_nm: f64, current_min_a: f64, current_max_a: f64) -> f64 {
        let t_lo = self.torque_nm(current_min_a);
        let t_hi = self.torque_nm(current_max_a);
        self.invert_from(target_nm, (current_min_a, t_lo), (current_max_a, t_hi), None)
    }

    /// [`Self::invert`] with the end-point torques already known (`(i_min, T(i_min))`,
    /// `(i_max, T(i_max))`) and an optional first guess (e.g. the previous tick's current), which
    /// lets Newton converge in one or two steps when the demand changes little between ticks.
    #[inline]
    pub fn invert_from(
        &self,
        target_nm: f64,
        low: (f64, f64),
        high: (f64, f64),
        guess: Option<f64>,
    ) -> f64 {
        let (current_min_a, t_lo) = low;
        let (current_max_a, t_hi) = high;
        let mut lo = current_min_a;
        let mut hi = current_max_a;
        if !target_nm.is_finite() || target_nm <= t_lo {
            return lo;
        }
        if target_nm >= t_hi {
            return hi;
        }
        let tolerance = INVERSE_RELATIVE_TOLERANCE * (t_hi - t_lo).abs().max(1e-9);
        // Start from the guess if it lies strictly inside, else interpolate between the end points.
        let mut i = match guess {
            Some(g) if g > lo && g < hi => g,
            _ => lo + (hi - lo) * (target_nm - t_lo) / (t_hi - t_lo),
        };
        for _ in 0..MAX_INVERSE_ITERATIONS {
            let (t, slope) = self.torque_and_slope(i);
            let residual = t - target_nm;
            if residual.abs() <= tolerance {
                break;
            }
            if residual < 0.0 {
                lo = i;
            } else {
                hi = i;
            }
            let newton = i - residual / slope;
            i = if slope > 0.0 && newton > lo && newton < hi { newton } else { 0.5 * (lo + hi) };
        }
        i.clamp(current_min_a, current_max_a)
    }
}

/// `{"coefficients": [c0, c1, ...]}` (ascending powers, trailing zeros dropped), the branch objects of
/// the inverse-model file ([`crate::InverseModelFile`]); reading checks the count (1 to
/// `MAX_DEGREE + 1`) and that every coefficient is finite, without allocating.
#[cfg(feature = "serde")]
mod serde_impl {
    use core::fmt;

    use serde::de::{self, Deserialize, Deserializer, SeqAccess, Visitor};
    use serde::ser::{Serialize, SerializeStruct, Serializer};

    use super::{BranchPolynomial, MAX_DEGREE};

    impl Serialize for BranchPolynomial {
        fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
            let mut branch = serializer.serialize_struct("BranchPolynomial", 1)?;
            branch.serialize_field("coefficients", &self.coefficients[..self.len])?;
            branch.end()
        }
    }

    /// The coefficient list, read into a fixed-size array.
    struct Coefficients(BranchPolynomial);

    impl<'de> Deserialize<'de> for Coefficients {
        fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
            deserializer.deserialize_seq(CoefficientsVisitor)
        }
    }

    struct CoefficientsVisitor;

    impl<'de> Visitor<'de> for CoefficientsVisitor {
        type Value = Coefficients;

        fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
            write!(
                f,
                "a list of 1 to {} finite numbers (ascending powers of current)",
                MAX_DEGREE + 1
            )
        }

        fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Coefficients, A::Error> {
            let mut stored = [0.0; MAX_DEGREE + 1];
            let mut len = 0;
            while let Some(c) = seq.next_element::<f64>()? {
                if len == stored.len() {
                    // Count the rest so the message says how many there were.
                    let mut total = len + 1;
                    while seq.next_element::<de::IgnoredAny>()?.is_some() {
                        total += 1;
                    }
                    return Err(de::Error::invalid_length(total, &self));
                }
                if !c.is_finite() {
                    return Err(de::Error::invalid_value(de::Unexpected::Float(c), &self));
                }
                stored[len] = c;
                len += 1;
            }
            BranchPolynomial::from_ascending(&stored[..len])
                .map(Coefficients)
                .ok_or_else(|| de::Error::invalid_length(len, &self))
        }
    }

    /// The branch object; other fields (fit statistics) are ignored.
    #[derive(serde::Deserialize)]
    struct BranchObject {
        coefficients: Coefficients,
    }

    impl<'de> Deserialize<'de> for BranchPolynomial {
        fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
            BranchObject::deserialize(deserializer).map(|branch| branch.coefficients.0)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn horner_and_slope_match_direct_evaluation() {
        let p = BranchPolynomial::from_ascending(&[0.15, 1.2, 0.3, -0.1]).unwrap();
        let i: f64 = 1.3;
        let direct = 0.15 + 1.2 * i + 0.3 * i * i - 0.1 * i * i * i;
        let (t, s) = p.torque_and_slope(i);
        assert!((t - direct).abs() < 1e-12);
        assert!((p.torque_nm(i) - direct).abs() < 1e-12);
        assert!((s - (1.2 + 0.6 * i - 0.3 * i * i)).abs() < 1e-12);
    }

    #[test]
    fn inverse_round_trips_inside_the_range() {
        let p = BranchPolynomial::from_ascending(&[0.15, 1.5, 0.4, -0.2]).unwrap();
        assert!(p.is_non_decreasing(0.0, 2.0, 200));
        for k in 0..=40 {
            let i = 2.0 * k as f64 / 40.0;
            let back = p.invert(p.torque_nm(i), 0.0, 2.0);
            assert!((back - i).abs() < 1e-3, "i = {i}, back = {back}");
        }
    }

    #[test]
    fn inverse_saturates_at_the_ends_and_rejects_non_finite() {
        let p = BranchPolynomial::from_ascending(&[0.15, 1.0]).unwrap();
        assert!(p.invert(-5.0, 0.0, 2.0).abs() < 1e-15);
        assert!((p.invert(50.0, 0.0, 2.0) - 2.0).abs() < 1e-15);
        assert!(p.invert(f64::NAN, 0.0, 2.0).abs() < 1e-15);
    }

    #[test]
    fn warm_start_gives_the_same_current() {
        let p = BranchPolynomial::from_ascending(&[0.15, 1.5, 0.4, -0.2]).unwrap();
        let ends = ((0.0, p.torque_nm(0.0)), (2.0, p.torque_nm(2.0)));
        for guess in [None, Some(0.3), Some(1.9), Some(5.0), Some(f64::NAN)] {
            let i = p.invert_from(2.0, ends.0, ends.1, guess);
            assert!((p.torque_nm(i) - 2.0).abs() < 1e-3, "{guess:?}");
        }
    }

    #[test]
    fn invalid_coefficients_are_rejected() {
        assert!(BranchPolynomial::from_ascending(&[]).is_none());
        assert!(BranchPolynomial::from_ascending(&[0.0; 9]).is_none());
        assert!(BranchPolynomial::from_ascending(&[0.0, f64::INFINITY]).is_none());
    }

    #[test]
    fn non_monotone_branch_still_returns_an_in_range_current() {
        let p = BranchPolynomial::from_ascending(&[0.0, 3.0, -2.0, 0.5]).unwrap();
        for k in 0..50 {
            let i = p.invert(-1.0 + 0.1 * k as f64, 0.0, 2.0);
            assert!((0.0..=2.0).contains(&i));
        }
    }
}
