//! Hysteresis model (rising and falling torque–current branches) and its inverse for control.
//!
//! The thesis (§5.3.2, Figure 5.7) drives the brake with the current that the quintic branch model says
//! produces the desired torque, choosing the rising branch while the torque demand increases and the
//! falling branch while it decreases. [`InverseModel`] does the same with two guarantees the raw
//! polynomial inverse lacks: the inverse is **monotone** (each branch is replaced by its running maximum
//! on a fine grid, so a fitted wiggle cannot make the current jump back) and **clamped** to the
//! identified current range.

use crate::SysidError;
use crate::polynomial::Polynomial;

/// One branch of the hysteresis loop: torque in N·m as a polynomial in the current in A.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct BranchPolynomial {
    /// Coefficients in ascending powers of the current in A; torque in N·m.
    pub coefficients: Vec<f64>,
}

/// The static hysteresis model: two branches over a current range (the JSON model file).
///
/// This is the subset of the `characterize` JSON that a controller needs; the other fields of that file
/// are ignored when it is read back.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct HysteresisModel {
    /// Torque while the current increases.
    pub rising: BranchPolynomial,
    /// Torque while the current decreases.
    pub falling: BranchPolynomial,
    /// Lowest current of the identified range, A.
    #[serde(rename = "current_min_A")]
    pub current_min_a: f64,
    /// Highest current of the identified range, A.
    #[serde(rename = "current_max_A")]
    pub current_max_a: f64,
}

/// Which branch of the loop is active.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Direction {
    /// Current (and torque demand) increasing.
    Rising,
    /// Current (and torque demand) decreasing.
    Falling,
}

impl HysteresisModel {
    /// Checks the range and coefficients; `source` names the data in the error.
    pub fn validate(&self, source: &str) -> Result<(), SysidError> {
        if !(self.current_min_a.is_finite()
            && self.current_max_a.is_finite()
            && self.current_max_a > self.current_min_a)
        {
            return Err(SysidError::Input(format!(
                "{source}: current_min_A ({}) must be finite and below current_max_A ({})",
                self.current_min_a, self.current_max_a
            )));
        }
        for (name, b) in [("rising", &self.rising), ("falling", &self.falling)] {
            if b.coefficients.is_empty() || b.coefficients.iter().any(|c| !c.is_finite()) {
                return Err(SysidError::Input(format!(
                    "{source}: {name}.coefficients must be a non-empty list of finite numbers"
                )));
            }
        }
        Ok(())
    }

    /// Reads a model from JSON text (e.g. the output of `mrbrake characterize --save-model`).
    pub fn from_json(source: &str, text: &str) -> Result<Self, SysidError> {
        let model: Self = serde_json::from_str(text).map_err(|e| SysidError::File {
            file: source.into(),
            line: Some(e.line() as u64),
            message: format!("not a hysteresis model ({e}); expected rising.coefficients, falling.coefficients, current_min_A, current_max_A"),
        })?;
        model.validate(source)?;
        Ok(model)
    }

    /// Torque in N·m of branch `direction` at current `current_a`.
    pub fn torque(&self, current_a: f64, direction: Direction) -> f64 {
        let b = match direction {
            Direction::Rising => &self.rising,
            Direction::Falling => &self.falling,
        };
        Polynomial::new(b.coefficients.clone()).eval(current_a)
    }
}

/// Number of grid intervals used to tabulate each branch for the inverse.
const INVERSE_GRID: usize = 2048;

/// Monotone, clamped inverse of a [`HysteresisModel`].
#[derive(Debug, Clone)]
pub struct InverseModel {
    current_a: Vec<f64>,
    rising_nm: Vec<f64>,
    falling_nm: Vec<f64>,
}

impl InverseModel {
    /// Tabulates both branches on a fine grid and makes each monotone (running maximum).
    pub fn new(model: &HysteresisModel) -> Result<Self, SysidError> {
        model.validate("hysteresis model")?;
        let (lo, hi) = (model.current_min_a, model.current_max_a);
        let current_a: Vec<f64> =
            (0..=INVERSE_GRID).map(|k| lo + (hi - lo) * k as f64 / INVERSE_GRID as f64).collect();
        let table = |b: &BranchPolynomial| {
            let p = Polynomial::new(b.coefficients.clone());
            let mut running = f64::NEG_INFINITY;
            current_a
                .iter()
                .map(|i| {
                    running = running.max(p.eval(*i));
                    running
                })
                .collect::<Vec<f64>>()
        };
        Ok(Self { rising_nm: table(&model.rising), falling_nm: table(&model.falling), current_a })
    }

    /// Current in A that produces `torque_nm` on branch `direction`, clamped to the current range.
    pub fn current_for(&self, torque_nm: f64, direction: Direction) -> f64 {
        let t = match direction {
            Direction::Rising => &self.rising_nm,
            Direction::Falling => &self.falling_nm,
        };
        let n = t.len();
        if torque_nm.is_nan() || torque_nm <= t[0] {
            return self.current_a[0];
        }
        if torque_nm >= t[n - 1] {
            return self.current_a[n - 1];
        }
        // First index with t[k] > torque (t is non-decreasing); torque lies in [t[k-1], t[k]).
        let k = t.partition_point(|v| *v <= torque_nm);
        let (t0, t1) = (t[k - 1], t[k]);
        let (i0, i1) = (self.current_a[k - 1], self.current_a[k]);
        i0 + (i1 - i0) * (torque_nm - t0) / (t1 - t0)
    }

    /// Torque range (min, max) in N·m reachable on branch `direction`.
    pub fn torque_range(&self, direction: Direction) -> (f64, f64) {
        let t = match direction {
            Direction::Rising => &self.rising_nm,
            Direction::Falling => &self.falling_nm,
        };
        (t[0], t[t.len() - 1])
    }
}

/// Chooses the branch from the sign of the torque demand's derivative and inverts (thesis Figure 5.7).
///
/// A demand that does not change keeps the previous branch; the first call uses the rising branch.
#[derive(Debug, Clone)]
pub struct InverseTracker {
    inverse: InverseModel,
    last_demand_nm: Option<f64>,
    direction: Direction,
}

impl InverseTracker {
    /// A tracker starting on the rising branch.
    pub fn new(inverse: InverseModel) -> Self {
        Self { inverse, last_demand_nm: None, direction: Direction::Rising }
    }

    /// Current for the next torque demand.
    pub fn current_for(&mut self, demand_nm: f64) -> f64 {
        if let Some(last) = self.last_demand_nm {
            if demand_nm > last {
                self.direction = Direction::Rising;
            } else if demand_nm < last {
                self.direction = Direction::Falling;
            }
        }
        self.last_demand_nm = Some(demand_nm);
        self.inverse.current_for(demand_nm, self.direction)
    }

    /// The branch in use.
    pub fn direction(&self) -> Direction {
        self.direction
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn model() -> HysteresisModel {
        HysteresisModel {
            rising: BranchPolynomial { coefficients: vec![0.15, 3.69, -1.38375, 0.230625] },
            falling: BranchPolynomial { coefficients: vec![0.15, 4.29, -1.68375, 0.230625] },
            current_min_a: 0.0,
            current_max_a: 2.0,
        }
    }

    #[test]
    fn inverse_undoes_each_branch() {
        let m = model();
        let inv = InverseModel::new(&m).unwrap();
        for k in 0..=40 {
            let i = 2.0 * k as f64 / 40.0;
            for d in [Direction::Rising, Direction::Falling] {
                let back = inv.current_for(m.torque(i, d), d);
                assert!((back - i).abs() < 1e-6, "{d:?} at {i}: {back}");
            }
        }
    }

    #[test]
    fn inverse_is_clamped() {
        let inv = InverseModel::new(&model()).unwrap();
        assert!((inv.current_for(-1.0, Direction::Rising) - 0.0).abs() < 1e-15);
        assert!((inv.current_for(100.0, Direction::Falling) - 2.0).abs() < 1e-15);
    }

    #[test]
    fn non_monotone_branch_gets_monotone_inverse() {
        // A branch with a local maximum inside the range: T = I (2 − I)·2 + sin bump.
        let m = HysteresisModel {
            rising: BranchPolynomial { coefficients: vec![0.0, 3.0, -2.5, 0.6] },
            falling: BranchPolynomial { coefficients: vec![0.0, 3.0, -2.5, 0.6] },
            current_min_a: 0.0,
            current_max_a: 3.0,
        };
        let inv = InverseModel::new(&m).unwrap();
        let mut last = -1.0;
        for k in 0..=300 {
            let i = inv.current_for(k as f64 * 0.02, Direction::Rising);
            assert!(i >= last - 1e-12);
            last = i;
        }
    }

    #[test]
    fn tracker_switches_branch_with_demand_derivative() {
        let m = model();
        let mut tr = InverseTracker::new(InverseModel::new(&m).unwrap());
        tr.current_for(1.0);
        let up = tr.current_for(2.0);
        assert_eq!(tr.direction(), Direction::Rising);
        let down = tr.current_for(1.999);
        assert_eq!(tr.direction(), Direction::Falling);
        // Falling branch carries more torque per ampere: less current for nearly the same torque.
        assert!(down < up);
    }

    #[test]
    fn model_json_round_trip_ignores_extra_fields() {
        let text = r#"{"rising":{"coefficients":[0.1,1.0],"fit_percent":99.0},"falling":{"coefficients":[0.2,1.0]},
            "current_min_A":0.0,"current_max_A":2.0,"repetitions":10}"#;
        let m = HysteresisModel::from_json("m.json", text).unwrap();
        assert!((m.torque(1.0, Direction::Falling) - 1.2).abs() < 1e-15);
        let bad =
            HysteresisModel::from_json("m.json", r#"{"rising":{"coefficients":[]}}"#).unwrap_err();
        assert!(bad.to_string().contains("m.json"));
    }
}
