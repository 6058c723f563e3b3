//! The design space: one [`Bounds`] per variable, continuous, integer or categorical.
//!
//! Optimisers work on real numbers; an integer variable (number of discs, wire gauge, turns) is varied
//! like a continuous one and then *repaired* ([`Bounds::repair`]): clamped into its bounds and rounded
//! to the nearest integer, the usual treatment of integer variables in evolutionary and pattern
//! methods (Deb & Goyal 1996 apply the same rounding after polynomial mutation).
//!
//! A categorical variable (a material out of a list) takes one of `n` unordered levels, stored as
//! the level's index `0, 1, …, n − 1`. Sampling plans and repair treat the index like an integer (so
//! every level is equally represented and a design always holds a valid index), but the order of the
//! indices means nothing: variation operators must not interpolate between levels. NSGA-II recombines
//! a categorical by uniform choice and mutates it by random reset ([`crate::nsga2`]); the surrogate's
//! Gaussian processes measure only whether two levels differ ([`crate::surrogate`]).

use crate::OptimError;

/// Whether a variable takes any real value, only integers, or one of a few unordered levels.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum VariableKind {
    /// Any real value within the bounds.
    Continuous,
    /// Only integers within the bounds.
    Integer,
    /// One of `upper + 1` unordered levels, stored as the index `0 ..= upper` (`lower` is 0).
    Categorical,
}

/// The closed interval `[lower, upper]` of one design variable and its kind.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Bounds {
    /// Smallest allowed value (0 for a categorical variable).
    pub lower: f64,
    /// Largest allowed value (the last level's index for a categorical variable).
    pub upper: f64,
    /// Continuous, integer or categorical.
    pub kind: VariableKind,
}

impl Bounds {
    /// A continuous variable in `[lower, upper]`.
    pub fn continuous(lower: f64, upper: f64) -> Self {
        Self { lower, upper, kind: VariableKind::Continuous }
    }

    /// An integer variable taking the integers in `[lower, upper]`.
    pub fn integer(lower: f64, upper: f64) -> Self {
        Self { lower, upper, kind: VariableKind::Integer }
    }

    /// A categorical variable with `levels` unordered levels, indexed `0 .. levels` (at least one
    /// level; [`Bounds::validate`] rejects `levels == 0`).
    pub fn categorical(levels: usize) -> Self {
        Self { lower: 0.0, upper: levels as f64 - 1.0, kind: VariableKind::Categorical }
    }

    /// True for an integer variable.
    pub fn is_integer(&self) -> bool {
        self.kind == VariableKind::Integer
    }

    /// True for a categorical variable.
    pub fn is_categorical(&self) -> bool {
        self.kind == VariableKind::Categorical
    }

    /// True for a variable that takes whole numbers only (integer or categorical).
    pub fn is_discrete(&self) -> bool {
        self.kind != VariableKind::Continuous
    }

    /// The number of levels of a categorical variable (`None` for the other kinds).
    pub fn levels(&self) -> Option<usize> {
        let (lo, hi) = self.feasible_range();
        // Validated bounds hold whole numbers from 0 here, so the conversion is exact.
        self.is_categorical().then(|| (hi - lo + 1.0).max(0.0) as usize)
    }

    /// Checks that both bounds are finite, `lower <= upper`, and that an integer variable's interval
    /// holds at least one integer; `index` names the variable in the error.
    pub fn validate(&self, index: usize) -> Result<(), OptimError> {
        let reject = |reason| OptimError::InvalidBounds {
            index,
            lower: self.lower,
            upper: self.upper,
            reason,
        };
        if !self.lower.is_finite() || !self.upper.is_finite() {
            return Err(reject("both bounds must be finite numbers"));
        }
        if self.lower > self.upper {
            return Err(reject("the lower bound must not exceed the upper bound"));
        }
        if self.is_integer() && self.lower.ceil() > self.upper.floor() {
            return Err(reject("an integer variable's interval must contain an integer"));
        }
        let whole = |v: f64| (v - v.round()).abs() <= 0.0;
        if self.is_categorical() && !(self.lower.abs() <= 0.0 && whole(self.upper)) {
            return Err(reject(
                "a categorical variable's levels are indexed 0 to (levels - 1), at least one level",
            ));
        }
        Ok(())
    }

    /// The smallest and largest values a design may actually take: the bounds themselves for a
    /// continuous variable, the smallest and largest integers inside them for an integer one.
    pub fn feasible_range(&self) -> (f64, f64) {
        match self.kind {
            VariableKind::Continuous => (self.lower, self.upper),
            VariableKind::Integer | VariableKind::Categorical => {
                (self.lower.ceil(), self.upper.floor())
            }
        }
    }

    /// The width of [`Bounds::feasible_range`].
    pub fn width(&self) -> f64 {
        let (lo, hi) = self.feasible_range();
        hi - lo
    }

    /// `x` clamped into the bounds and, for an integer or categorical variable, rounded to the
    /// nearest integer inside them. A NaN becomes the lower end of the range (a defined, in-bounds value: the
    /// evaluator then sees a legal design rather than NaN).
    pub fn repair(&self, x: f64) -> f64 {
        let (lo, hi) = self.feasible_range();
        if x.is_nan() {
            return lo;
        }
        let clamped = x.clamp(lo.min(hi), hi.max(lo));
        match self.kind {
            VariableKind::Continuous => clamped,
            VariableKind::Integer | VariableKind::Categorical => {
                clamped.round().clamp(lo, hi.max(lo))
            }
        }
    }

    /// Maps `u` in `[0, 1)` onto the variable. Continuous: `lower + u (upper − lower)`. Integer (and
    /// categorical, by level index): the interval is widened by half a unit on each side before
    /// rounding, so every integer in range gets the same share of `[0, 1)` (plain rounding would give
    /// the two end integers half a share).
    pub fn from_unit(&self, u: f64) -> f64 {
        let (lo, hi) = self.feasible_range();
        match self.kind {
            VariableKind::Continuous => self.repair(lo + u * (hi - lo)),
            VariableKind::Integer | VariableKind::Categorical => {
                let count = hi - lo + 1.0;
                self.repair(lo + (u * count).floor())
            }
        }
    }

    /// True when `x` is inside the bounds (and integral for an integer or categorical variable,
    /// within 1e-9).
    pub fn contains(&self, x: f64) -> bool {
        let inside = x >= self.lower && x <= self.upper;
        match self.kind {
            VariableKind::Continuous => inside,
            VariableKind::Integer | VariableKind::Categorical => {
                inside && (x - x.round()).abs() <= 1e-9
            }
        }
    }
}

/// Validates every variable's bounds and requires at least one variable.
pub fn validate_bounds(bounds: &[Bounds]) -> Result<(), OptimError> {
    if bounds.is_empty() {
        return Err(OptimError::NoVariables);
    }
    bounds.iter().enumerate().try_for_each(|(index, b)| b.validate(index))
}

/// Repairs every coordinate of `x` in place (see [`Bounds::repair`]).
pub fn repair_point(bounds: &[Bounds], x: &mut [f64]) {
    for (value, b) in x.iter_mut().zip(bounds) {
        *value = b.repair(*value);
    }
}

/// Checks a caller-supplied design (`which` names it in the error): right length, finite, inside the
/// bounds, integral where required.
pub fn validate_design(bounds: &[Bounds], x: &[f64], which: &str) -> Result<(), OptimError> {
    if x.len() != bounds.len() {
        return Err(OptimError::InvalidDesign {
            which: which.to_owned(),
            reason: format!(
                "it has {} values but the problem has {} variables",
                x.len(),
                bounds.len()
            ),
        });
    }
    for (index, (&value, b)) in x.iter().zip(bounds).enumerate() {
        if !b.contains(value) {
            let kind = match b.kind {
                VariableKind::Continuous => "",
                VariableKind::Integer => "an integer ",
                VariableKind::Categorical => "a level index ",
            };
            return Err(OptimError::InvalidDesign {
                which: which.to_owned(),
                reason: format!(
                    "variable {index} = {value} must be {kind}in [{}, {}]",
                    b.lower, b.upper
                ),
            });
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use mrbrake_error::Kind as _;

    #[test]
    fn validate_rejects_reversed_non_finite_and_empty_integer_bounds() {
        assert!(Bounds::continuous(0.0, 1.0).validate(0).is_ok());
        assert!(Bounds::continuous(2.0, 2.0).validate(0).is_ok());
        let e = Bounds::continuous(1.0, 0.0).validate(3).unwrap_err();
        assert!(e.is_input_error());
        assert!(e.to_string().contains("variable 3"), "{e}");
        assert!(Bounds::continuous(f64::NAN, 1.0).validate(0).is_err());
        assert!(Bounds::continuous(0.0, f64::INFINITY).validate(0).is_err());
        assert!(Bounds::integer(0.2, 0.8).validate(0).is_err());
        assert!(Bounds::integer(0.2, 1.0).validate(0).is_ok());
        assert!(matches!(validate_bounds(&[]), Err(OptimError::NoVariables)));
    }

    #[test]
    fn repair_clamps_and_rounds() {
        let c = Bounds::continuous(-1.0, 2.0);
        approx::assert_abs_diff_eq!(c.repair(5.0), 2.0);
        approx::assert_abs_diff_eq!(c.repair(-5.0), -1.0);
        approx::assert_abs_diff_eq!(c.repair(0.25), 0.25);
        approx::assert_abs_diff_eq!(c.repair(f64::NAN), -1.0);
        let i = Bounds::integer(0.5, 4.7);
        approx::assert_abs_diff_eq!(i.repair(0.6), 1.0);
        approx::assert_abs_diff_eq!(i.repair(4.6), 4.0);
        approx::assert_abs_diff_eq!(i.repair(2.4), 2.0);
        approx::assert_abs_diff_eq!(i.repair(-3.0), 1.0);
    }

    #[test]
    fn integer_from_unit_gives_every_value_an_equal_share() {
        let b = Bounds::integer(1.0, 4.0);
        let mut counts = [0usize; 4];
        let n = 400;
        for k in 0..n {
            let u = (k as f64 + 0.5) / n as f64;
            let x = b.from_unit(u);
            counts[(x - 1.0) as usize] += 1;
        }
        assert_eq!(counts, [100, 100, 100, 100]);
    }

    #[test]
    fn categorical_levels_are_indices_sampled_evenly_and_validated() {
        let material = Bounds::categorical(3);
        assert!(material.validate(0).is_ok());
        assert_eq!(material.levels(), Some(3));
        assert_eq!(Bounds::integer(0.0, 2.0).levels(), None);
        assert!(material.is_categorical() && material.is_discrete() && !material.is_integer());
        approx::assert_abs_diff_eq!(material.repair(1.6), 2.0);
        approx::assert_abs_diff_eq!(material.repair(7.0), 2.0);
        let mut counts = [0usize; 3];
        for k in 0..300 {
            counts[material.from_unit((k as f64 + 0.5) / 300.0) as usize] += 1;
        }
        assert_eq!(counts, [100, 100, 100]);
        assert!(Bounds::categorical(0).validate(4).is_err());
        let shifted = Bounds { lower: 1.0, ..Bounds::categorical(3) };
        assert!(shifted.validate(0).is_err());
        let e = validate_design(&[material], &[0.5], "start").unwrap_err();
        assert!(e.to_string().contains("level index"), "{e}");
    }

    #[test]
    fn validate_design_names_the_variable() {
        let bounds = [Bounds::continuous(0.0, 1.0), Bounds::integer(1.0, 3.0)];
        assert!(validate_design(&bounds, &[0.5, 2.0], "start").is_ok());
        let e = validate_design(&bounds, &[0.5, 2.5], "start").unwrap_err();
        assert!(e.to_string().contains("variable 1"), "{e}");
        assert!(validate_design(&bounds, &[0.5], "start").is_err());
        assert!(validate_design(&bounds, &[f64::NAN, 2.0], "start").is_err());
    }
}
