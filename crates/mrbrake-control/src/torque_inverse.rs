//! The choice of torque → current inverse for one brake: the thesis's polynomial branches
//! ([`InverseModel`], branch chosen by the demand's direction) or the operator model
//! ([`OperatorModel`], exact inverse of a rate-independent hysteresis with minor loops).
//!
//! Both run in the same slot of the controller; [`TorqueInverseState`] carries either one's memory.

use crate::inverse::{Branch, CompensationState, InverseModel};
use crate::operator::{OperatorCompensation, OperatorModel};

/// One brake's inverse model.
// The operator variant is ~1.8 kB against the branches' ~170 B; boxing it would need an allocator,
// which this crate must not use, and the controller holds two of them by value once.
#[allow(clippy::large_enum_variant)]
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum TorqueInverse {
    /// Two polynomial branches (thesis §5.3.2, Fig. 5.7).
    Branches(InverseModel),
    /// The modified Prandtl–Ishlinskii operator model and its analytical inverse.
    Operators(OperatorModel),
}

/// What a [`TorqueInverse`] carries from one demand to the next; the default is the rest state.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct TorqueInverseState {
    /// The branch compensation's state (used by [`TorqueInverse::Branches`]).
    pub branches: CompensationState,
    /// The operator inverse's state (used by [`TorqueInverse::Operators`]).
    pub operators: OperatorCompensation,
}

impl TorqueInverseState {
    /// The branch (direction) in use for the given inverse.
    pub fn branch(&self, inverse: &TorqueInverse) -> Branch {
        match inverse {
            TorqueInverse::Branches(_) => self.branches.branch(),
            TorqueInverse::Operators(_) => self.operators.branch(),
        }
    }
}

impl From<InverseModel> for TorqueInverse {
    fn from(model: InverseModel) -> Self {
        Self::Branches(model)
    }
}

impl From<OperatorModel> for TorqueInverse {
    fn from(model: OperatorModel) -> Self {
        Self::Operators(model)
    }
}

impl TorqueInverse {
    /// Highest current of the model, A.
    pub fn current_max_a(&self) -> f64 {
        match self {
            Self::Branches(m) => m.current_max_a(),
            Self::Operators(m) => m.current_max_a(),
        }
    }

    /// The current in `[0, limit_a]` for `demand_nm` (`deadband_nm` only affects the branch model's
    /// branch switch; the operator model needs none). Never panics; NaN gives 0 A.
    #[inline]
    pub fn compensate(
        &self,
        state: &mut TorqueInverseState,
        demand_nm: f64,
        limit_a: f64,
        deadband_nm: f64,
    ) -> f64 {
        match self {
            Self::Branches(m) => m.compensate(&mut state.branches, demand_nm, limit_a, deadband_nm),
            Self::Operators(m) => m.compensate(&mut state.operators, demand_nm, limit_a),
        }
    }
}
