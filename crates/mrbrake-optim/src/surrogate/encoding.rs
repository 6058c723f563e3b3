//! The features the Gaussian processes see: every design mapped onto the unit box.
//!
//! A continuous or integer variable becomes `(x − lower) / (upper − lower)` over its feasible range
//! (0 for a fixed variable); an integer is *relaxed* (the GP treats its feature as continuous) and
//! every design the optimiser proposes is decoded and repaired, so it only ever proposes legal,
//! rounded designs. A categorical variable keeps its level index, compared by equality in the
//! kernel ([`super::gp`]).

use crate::space::Bounds;

/// Maps designs to features and back.
#[derive(Debug, Clone)]
pub(crate) struct Encoding {
    bounds: Vec<Bounds>,
    categorical: Vec<bool>,
}

impl Encoding {
    pub fn new(bounds: &[Bounds]) -> Self {
        Self {
            bounds: bounds.to_vec(),
            categorical: bounds.iter().map(Bounds::is_categorical).collect(),
        }
    }

    /// Which features are categorical (the GP's `categorical` argument).
    pub fn categorical(&self) -> &[bool] {
        &self.categorical
    }

    /// Number of features (= variables).
    pub fn dimension(&self) -> usize {
        self.bounds.len()
    }

    /// The features of design `x`.
    pub fn encode(&self, x: &[f64]) -> Vec<f64> {
        x.iter()
            .zip(&self.bounds)
            .map(|(&v, b)| {
                if b.is_categorical() {
                    return b.repair(v);
                }
                let (lo, hi) = b.feasible_range();
                if hi > lo { ((b.repair(v) - lo) / (hi - lo)).clamp(0.0, 1.0) } else { 0.0 }
            })
            .collect()
    }

    /// The legal design nearest to features `z` (clamped, integers rounded, levels rounded).
    pub fn decode(&self, z: &[f64]) -> Vec<f64> {
        z.iter()
            .zip(&self.bounds)
            .map(|(&v, b)| {
                if b.is_categorical() {
                    return b.repair(v);
                }
                let (lo, hi) = b.feasible_range();
                b.repair(lo + v.clamp(0.0, 1.0) * (hi - lo))
            })
            .collect()
    }

    /// The feature step of one unit of an integer variable (`None` for continuous, categorical or
    /// fixed variables).
    pub fn integer_step(&self, k: usize) -> Option<f64> {
        let b = &self.bounds[k];
        let width = b.width();
        (b.is_integer() && width > 0.0).then(|| 1.0 / width)
    }

    /// The number of levels of categorical feature `k` (`None` otherwise).
    pub fn levels(&self, k: usize) -> Option<usize> {
        self.bounds[k].levels()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trip_repairs_to_legal_designs() {
        let bounds =
            [Bounds::continuous(-1.0, 3.0), Bounds::integer(1.0, 5.0), Bounds::categorical(3)];
        let encoding = Encoding::new(&bounds);
        assert_eq!(encoding.categorical(), &[false, false, true]);
        let z = encoding.encode(&[1.0, 2.0, 2.0]);
        assert!(
            (z[0] - 0.5).abs() < 1e-15 && (z[1] - 0.25).abs() < 1e-15 && (z[2] - 2.0).abs() < 1e-15
        );
        assert_eq!(encoding.decode(&z), vec![1.0, 2.0, 2.0]);
        // Off-grid and out-of-box features decode to the nearest legal design.
        assert_eq!(encoding.decode(&[1.7, 0.33, 0.6]), vec![3.0, 2.0, 1.0]);
        assert_eq!(encoding.integer_step(1), Some(0.25));
        assert_eq!(encoding.integer_step(0), None);
        assert_eq!(encoding.levels(2), Some(3));
        let fixed = Encoding::new(&[Bounds::continuous(2.0, 2.0)]);
        assert_eq!(fixed.encode(&[2.0]), vec![0.0]);
        assert_eq!(fixed.decode(&[0.7]), vec![2.0]);
    }
}
