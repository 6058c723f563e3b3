//! The inverse (torque → current) model of one brake with hysteresis compensation.
//!
//! The identified model (thesis §5.3.1, Fig. 5.6) is a pair of branches: `T_rise(i)` measured while
//! the current increases and `T_fall(i)` while it decreases. The thesis's torque tracking (§5.3.2,
//! Fig. 5.7) chooses the branch by the sign of the demand's derivative and inverts it; this module does
//! the same: [`InverseModel::current_for`] inverts the selected branch on `[i_min, i_max]`, and
//! [`InverseModel::compensate`] adds the branch selection (with a deadband) and the warm start from the
//! previous current, carried in a [`CompensationState`] from one demand to the next. The controller runs
//! one compensation per brake; the virtual test rig shapes its current with the same one.
//!
//! The model is the one type every stage shares: `mrbrake-sysid` fits it from a rig log, the
//! controller, the haptic simulation and the virtual rig run it, and with the `serde` feature it is read
//! and written as the inverse-model file (schema: [`InverseModelFile`]).

use crate::error::{ControlError, check_range};
use crate::polynomial::BranchPolynomial;

/// Which half of the hysteresis loop the brake is on (the direction in which the current, and with
/// it the torque, last moved).
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
///
/// Always valid: both branches are non-decreasing on `[i_min, i_max]` with `0 ≤ i_min < i_max ≤`
/// [`CURRENT_LIMIT_A`] (checked by every constructor, including deserialisation).
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(try_from = "InverseModelFile", into = "InverseModelFile")
)]
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

    /// [`Self::current_for`] starting the iteration from `guess` (the previous current; ignored unless
    /// it lies strictly inside the range).
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

    /// Hysteresis compensation of one demand (thesis §5.3.2, Fig. 5.7): the current in `[0, limit_a]`
    /// that gives `demand_nm` on the branch the demand's change selects.
    ///
    /// A rise of the demand by more than `deadband_nm` since the reference demand selects the rising
    /// branch, a fall by more than `deadband_nm` the falling one; smaller changes keep the branch, so
    /// velocity noise does not flip it. The reference moves only with such larger changes (a slow drift
    /// still accumulates into a switch) or when the demand is zero. The branch inversion starts from the
    /// previous current (a warm start: the demand of a 1 kHz loop changes little between ticks, so
    /// Newton needs about two evaluations of the branch instead of three). A non-positive demand gives
    /// 0 A; a non-finite result gives 0 A.
    #[inline]
    pub fn compensate(
        &self,
        state: &mut CompensationState,
        demand_nm: f64,
        limit_a: f64,
        deadband_nm: f64,
    ) -> f64 {
        let change = demand_nm - state.reference_demand_nm;
        if change > deadband_nm {
            state.branch = Branch::Rising;
        } else if change < -deadband_nm {
            state.branch = Branch::Falling;
        }
        let mut current_a = 0.0;
        if demand_nm > 0.0 {
            let guess = Some(state.current_a);
            current_a = self.current_for_from(state.branch, demand_nm, limit_a, guess);
        }
        // Belt and braces: the output range is an invariant whatever the model returned.
        current_a =
            if current_a.is_finite() { current_a.clamp(0.0, limit_a.max(0.0)) } else { 0.0 };
        if change.abs() > deadband_nm || demand_nm <= 0.0 {
            state.reference_demand_nm = demand_nm;
        }
        state.current_a = current_a;
        current_a
    }
}

/// What the hysteresis compensation of one brake carries from one demand to the next
/// ([`InverseModel::compensate`]). The default is the state at rest: rising branch, no demand, 0 A.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct CompensationState {
    /// The demand the last branch decision was measured from, Nm.
    reference_demand_nm: f64,
    /// The last current, A: the warm start of the next inversion.
    current_a: f64,
    /// The branch in use.
    branch: Branch,
}

impl CompensationState {
    /// The branch in use.
    pub fn branch(&self) -> Branch {
        self.branch
    }

    /// The last current, A (the warm start of the next inversion).
    pub fn current_a(&self) -> f64 {
        self.current_a
    }
}

/// The parts of an [`InverseModel`] before validation: what the inverse-model file holds.
///
/// With the `serde` feature this is the file's schema (JSON field names in brackets; other fields,
/// such as the fit statistics `mrbrake characterize --save-model` also writes, are ignored):
///
/// ```json
/// { "rising":  { "coefficients": [c0, c1, ...] },
///   "falling": { "coefficients": [c0, c1, ...] },
///   "current_min_A": 0.0, "current_max_A": 2.0 }
/// ```
///
/// Coefficients are ascending powers of the current in A giving torque in N·m, 1 to
/// [`crate::MAX_DEGREE`]` + 1` finite numbers per branch; both branches must be non-decreasing on
/// `[current_min_A, current_max_A]`, with `0 ≤ current_min_A < current_max_A ≤ 100`. Converting
/// to an [`InverseModel`] (`TryFrom`) checks the range and the monotonicity with a typed
/// [`ControlError`].
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct InverseModelFile {
    /// Torque while the current increases.
    pub rising: BranchPolynomial,
    /// Torque while the current decreases.
    pub falling: BranchPolynomial,
    /// Lowest current of the identified range, A.
    #[cfg_attr(feature = "serde", serde(rename = "current_min_A"))]
    pub current_min_a: f64,
    /// Highest current of the identified range, A.
    #[cfg_attr(feature = "serde", serde(rename = "current_max_A"))]
    pub current_max_a: f64,
}

impl TryFrom<InverseModelFile> for InverseModel {
    type Error = ControlError;

    fn try_from(file: InverseModelFile) -> Result<Self, ControlError> {
        Self::from_branches(file.rising, file.falling, file.current_min_a, file.current_max_a)
    }
}

impl From<InverseModel> for InverseModelFile {
    fn from(model: InverseModel) -> Self {
        Self {
            rising: model.rising,
            falling: model.falling,
            current_min_a: model.current_min_a,
            current_max_a: model.current_max_a,
        }
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
    fn compensation_switches_branch_beyond_the_deadband_and_warm_starts() {
        let model = InverseModel::new(&[0.15, 1.5, 0.3], &[0.35, 1.5, 0.3], 0.0, 2.0).unwrap();
        let mut state = CompensationState::default();
        let up = model.compensate(&mut state, 2.0, 2.0, 0.01);
        assert_eq!(state.branch(), Branch::Rising);
        assert!((model.torque_nm(Branch::Rising, up) - 2.0).abs() < 1e-3);
        assert!((state.current_a() - up).abs() < 1e-300);
        // A fall inside the deadband keeps the branch; beyond it the falling branch takes over.
        model.compensate(&mut state, 1.995, 2.0, 0.01);
        assert_eq!(state.branch(), Branch::Rising);
        let down = model.compensate(&mut state, 1.98, 2.0, 0.01);
        assert_eq!(state.branch(), Branch::Falling);
        assert!((model.torque_nm(Branch::Falling, down) - 1.98).abs() < 1e-3);
        // No demand, no current; the limit caps it.
        assert!(model.compensate(&mut state, 0.0, 2.0, 0.01).abs() < 1e-300);
        assert!((model.compensate(&mut state, 50.0, 1.5, 0.01) - 1.5).abs() < 1e-12);
    }

    #[test]
    fn file_parts_convert_with_typed_errors() {
        let model = InverseModel::new(&[0.15, 1.5], &[0.35, 1.5], 0.0, 2.0).unwrap();
        let file = InverseModelFile::from(model);
        assert_eq!(InverseModel::try_from(file), Ok(model));
        let backwards = InverseModelFile { current_min_a: 2.0, current_max_a: 1.0, ..file };
        assert!(matches!(
            InverseModel::try_from(backwards),
            Err(ControlError::OutOfRange { field: "current_max_a", .. })
        ));
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
