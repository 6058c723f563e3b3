//! The inverse (torque → current) model of one brake with hysteresis compensation.
//!
//! The identified model (thesis §5.3.1, Fig. 5.6) is a pair of branches: `T_rise(i)` measured while
//! the current increases and `T_fall(i)` while it decreases. The thesis's torque tracking (§5.3.2,
//! Fig. 5.7) chooses the branch by the sign of the demand's derivative and inverts it; this module does
//! the same: [`InverseModel::current_for`] inverts the selected branch on `[i_min, i_max]`.

use crate::error::{ControlError, check_range};
use crate::polynomial::BranchPolynomial;

/// Which half of the hysteresis loop the brake is on.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Branch {
    /// Current (and torque) increasing: the lower half of an MR brake's loop.
    #[default]
    Rising = 0,
    /// Current (and torque) decreasing: the upper half of the loop.
    Falling = 1,
}

/// Samples used to check that a branch is non-decreasing when a model is built (host side).
const MONOTONICITY_SAMPLES: usize = 512;

/// Largest current a model may declare, A (well above the 2 A of the thesis's coils; a sanity bound).
pub const CURRENT_LIMIT_A: f64 = 100.0;

/// Inverse model of one brake: both hysteresis branches and the current range they were fitted on.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct InverseModel {
    rising: BranchPolynomial,
    falling: BranchPolynomial,
    current_min_a: f64,
    current_max_a: f64,
    /// `T(i_min)` and `T(i_max)` of the rising and the falling branch (precomputed for the step).
    end_torques_nm: [(f64, f64); 2],
}

impl InverseModel {
    /// Builds and validates a model from ascending coefficients (torque in Nm, current in A) and the
    /// current range of the fit. Both branches must be non-decreasing on the range.
    pub fn new(
        rising_coefficients: &[f64],
        falling_coefficients: &[f64],
        current_min_a: f64,
        current_max_a: f64,
    ) -> Result<Self, ControlError> {
        let rising = BranchPolynomial::from_ascending(rising_coefficients)
            .ok_or(ControlError::InvalidPolynomial { branch: "rising" })?;
        let falling = BranchPolynomial::from_ascending(falling_coefficients)
            .ok_or(ControlError::InvalidPolynomial { branch: "falling" })?;
        Self::from_branches(rising, falling, current_min_a, current_max_a)
    }

    /// Builds and validates a model from two branch polynomials.
    pub fn from_branches(
        rising: BranchPolynomial,
        falling: BranchPolynomial,
        current_min_a: f64,
        current_max_a: f64,
    ) -> Result<Self, ControlError> {
        let current_min_a = check_range("current_min_a", current_min_a, 0.0, CURRENT_LIMIT_A)?;
        let current_max_a =
            check_range("current_max_a", current_max_a, current_min_a, CURRENT_LIMIT_A)?;
        if current_max_a - current_min_a <= 0.0 {
            return Err(ControlError::OutOfRange {
                field: "current_max_a",
                value: current_max_a,
                min: current_min_a,
                max: CURRENT_LIMIT_A,
            });
        }
        if !rising.is_non_decreasing(current_min_a, current_max_a, MONOTONICITY_SAMPLES) {
            return Err(ControlError::NonMonotoneBranch { branch: "rising" });
        }
        if !falling.is_non_decreasing(current_min_a, current_max_a, MONOTONICITY_SAMPLES) {
            return Err(ControlError::NonMonotoneBranch { branch: "falling" });
        }
        let ends = |p: &BranchPolynomial| (p.torque_nm(current_min_a), p.torque_nm(current_max_a));
        let end_torques_nm = [ends(&rising), ends(&falling)];
        Ok(Self { rising, falling, current_min_a, current_max_a, end_torques_nm })
    }

    /// The branch polynomial for `branch`.
    pub fn branch(&self, branch: Branch) -> &BranchPolynomial {
        match branch {
            Branch::Rising => &self.rising,
            Branch::Falling => &self.falling,
        }
    }

    /// Lowest current of the fit, A.
    pub fn current_min_a(&self) -> f64 {
        self.current_min_a
    }

    /// Highest current of the fit, A.
    pub fn current_max_a(&self) -> f64 {
        self.current_max_a
    }

    /// Forward model: torque in Nm on `branch` at `current_a` (clamped to the fitted range).
    pub fn torque_nm(&self, branch: Branch, current_a: f64) -> f64 {
        self.branch(branch).torque_nm(current_a.clamp(self.current_min_a, self.current_max_a))
    }

    /// Inverse model: the current in `[i_min, min(i_max, limit_a)]` that gives `target_nm` on
    /// `branch`. Demands below the off-state torque give `i_min`, above the capacity the upper limit.
    #[inline]
    pub fn current_for(&self, branch: Branch, target_nm: f64, limit_a: f64) -> f64 {
        self.current_for_from(branch, target_nm, limit_a, None)
    }

    /// [`Self::current_for`] starting the iteration from `guess` (the previous current).
    #[inline]
    pub fn current_for_from(
        &self,
        branch: Branch,
        target_nm: f64,
        limit_a: f64,
        guess: Option<f64>,
    ) -> f64 {
        let polynomial = self.branch(branch);
        let (t_min, t_max) = self.end_torques_nm[branch as usize];
        let upper = self.current_max_a.min(limit_a).max(self.current_min_a);
        // The precomputed end torque holds unless a lower limit cuts the range.
        let t_upper = if upper < self.current_max_a { polynomial.torque_nm(upper) } else { t_max };
        polynomial.invert_from(target_nm, (self.current_min_a, t_min), (upper, t_upper), guess)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rejects_a_decreasing_branch_and_a_bad_range() {
        let err = InverseModel::new(&[1.0, -0.5], &[1.0, 1.0], 0.0, 2.0).unwrap_err();
        assert_eq!(err, ControlError::NonMonotoneBranch { branch: "rising" });
        assert!(InverseModel::new(&[0.1, 1.0], &[0.1, 1.0], 1.0, 0.5).is_err());
        assert!(InverseModel::new(&[0.1, 1.0], &[0.1, 1.0], -1.0, 2.0).is_err());
        assert!(InverseModel::new(&[0.1, 1.0], &[0.1, 1.0], 0.0, f64::NAN).is_err());
    }

    #[test]
    fn branches_are_inverted_separately() {
        let model = InverseModel::new(&[0.15, 1.5], &[0.35, 1.5], 0.0, 2.0).unwrap();
        let i_rise = model.current_for(Branch::Rising, 1.65, 2.0);
        let i_fall = model.current_for(Branch::Falling, 1.65, 2.0);
        assert!((i_rise - 1.0).abs() < 1e-3);
        assert!((i_fall - 0.866_666).abs() < 1e-3);
        // The limit caps the current below the model's range.
        assert!((model.current_for(Branch::Rising, 3.0, 1.5) - 1.5).abs() < 1e-12);
    }
}
