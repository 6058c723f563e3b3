//! Settings of a surrogate-assisted run and their validation.

use std::str::FromStr;

use super::gp::FitSettings;
use crate::OptimError;
use crate::space::{Bounds, validate_bounds};

/// The multi-objective acquisition that chooses the next designs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[non_exhaustive]
pub enum Acquisition {
    /// Expected hypervolume improvement times the probability of feasibility (key `"ehvi"`); the
    /// expected improvement for one objective (module docs).
    #[default]
    ExpectedHypervolumeImprovement,
}

impl Acquisition {
    /// The key a problem file names it by.
    pub fn key(self) -> &'static str {
        match self {
            Self::ExpectedHypervolumeImprovement => "ehvi",
        }
    }
}

impl FromStr for Acquisition {
    type Err = OptimError;

    /// `"ehvi"` (or `"expected-hypervolume-improvement"`); anything else is an
    /// [`OptimError::UnknownChoice`] naming the key `acquisition`.
    fn from_str(value: &str) -> Result<Self, OptimError> {
        match value.trim().to_ascii_lowercase().as_str() {
            "ehvi" | "expected-hypervolume-improvement" => Ok(Self::ExpectedHypervolumeImprovement),
            _ => Err(OptimError::UnknownChoice {
                name: "acquisition",
                value: value.to_owned(),
                allowed: "\"ehvi\" (expected hypervolume improvement)",
            }),
        }
    }
}

/// The space-filling plan of the initial design.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum InitialPlan {
    /// Sobol' points (Joe & Kuo 2008) under a random shift modulo 1 (Cranley & Patterson 1976),
    /// drawn from the seed. The default: the best space filling for a given size, and the sequence
    /// continues for the space-filling fallback.
    #[default]
    Sobol,
    /// A Latin hypercube (McKay et al. 1979); also used for more than 32 variables, beyond the
    /// built-in Sobol' table.
    LatinHypercube,
}

/// Settings of [`super::run`].
#[derive(Debug, Clone, PartialEq)]
pub struct SurrogateOptions {
    /// Designs in the initial space-filling plan; `None` means 10 × variables (Loeppky, Sacks &
    /// Welch 2009, "Choosing the sample size of a computer experiment: a practical guide",
    /// Technometrics 51(4), 366–376). At least variables + 1, at most 100 000; the plan is cut short
    /// if `max_evaluations` is smaller.
    pub initial_size: Option<usize>,
    /// Sobol' (default) or Latin hypercube.
    pub initial_plan: InitialPlan,
    /// Designs chosen per iteration (the study's parallelism, `--jobs`); 1 to 1 024. Default 1.
    pub batch: usize,
    /// Budget: designs in the data (those given to [`super::run`] plus those it evaluates), at
    /// least 1. Default 200.
    pub max_evaluations: usize,
    /// Stall rule: stop when the hypervolume has grown by at most `stall_tolerance` (relative)
    /// over this many iterations; 0 disables it. Default 15.
    pub stall_iterations: usize,
    /// Relative hypervolume growth under which iterations count as stalled; finite, `>= 0`.
    /// Default 1e-3.
    pub stall_tolerance: f64,
    /// The acquisition (default expected hypervolume improvement).
    pub acquisition: Acquisition,
    /// Reference point of the hypervolume (one value per objective, minimised units). `None`:
    /// fixed at the first iteration with a feasible design, 10 % of the feasible designs' range
    /// beyond their worst value in each objective (Ishibuchi et al. 2018, "How to specify a
    /// reference point in hypervolume calculation for fair performance comparison", Evol. Comput.
    /// 26(3)).
    pub reference: Option<Vec<f64>>,
    /// Space-filling candidates the acquisition is screened on per iteration (plus as many local
    /// ones around the current front); 1 to 100 000. Default 500.
    pub candidates: usize,
    /// Largest training set of a model: beyond it the best designs by constrained non-dominated
    /// rank are kept (module docs). At least variables + 1, at most 2 000. Default 300.
    pub max_training: usize,
    /// Hyper-parameter search effort (restarts up to 100, iterations 1 to 1 000, re-optimisation
    /// growth 0 to 10).
    pub fit: FitSettings,
    /// Seed of every random choice. Default 0.
    pub seed: u64,
}

impl Default for SurrogateOptions {
    fn default() -> Self {
        Self {
            initial_size: None,
            initial_plan: InitialPlan::Sobol,
            batch: 1,
            max_evaluations: 200,
            stall_iterations: 15,
            stall_tolerance: 1e-3,
            acquisition: Acquisition::ExpectedHypervolumeImprovement,
            reference: None,
            candidates: 500,
            max_training: 300,
            fit: FitSettings::default(),
            seed: 0,
        }
    }
}

impl SurrogateOptions {
    /// The initial design's size for `variables` variables (before the budget cut).
    pub fn initial_design_size(&self, variables: usize) -> usize {
        self.initial_size.unwrap_or(10 * variables).max(variables + 1)
    }

    /// Checks every setting against the problem's bounds and number of objectives. Errors name the
    /// option (`batch`, `initial_size`, ...) and its allowed range.
    pub fn validate(&self, bounds: &[Bounds], objectives: usize) -> Result<(), OptimError> {
        validate_bounds(bounds)?;
        if objectives == 0 {
            return Err(OptimError::ObjectiveCount {
                method: "the surrogate optimiser",
                got: 0,
                allowed: "at least 1",
            });
        }
        let d = bounds.len();
        let count = |name, value: usize, ok: bool, allowed| {
            if ok {
                Ok(())
            } else {
                Err(OptimError::InvalidOption { name, value: value as f64, allowed })
            }
        };
        count("batch", self.batch, (1..=1024).contains(&self.batch), "1 to 1024 designs")?;
        if let Some(n) = self.initial_size {
            count("initial_size", n, n > d && n <= 100_000, "(variables + 1) to 100000 designs")?;
        }
        count("max_evaluations", self.max_evaluations, self.max_evaluations >= 1, "at least 1")?;
        count(
            "candidates",
            self.candidates,
            (1..=100_000).contains(&self.candidates),
            "1 to 100000",
        )?;
        let training = self.max_training > d && self.max_training <= 2000;
        count("max_training", self.max_training, training, "(variables + 1) to 2000 designs")?;
        count("fit.restarts", self.fit.restarts, self.fit.restarts <= 100, "0 to 100")?;
        let iterations = (1..=1000).contains(&self.fit.max_iterations);
        count("fit.max_iterations", self.fit.max_iterations, iterations, "1 to 1000")?;
        let growth = self.fit.reoptimise_growth;
        if !(growth.is_finite() && (0.0..=10.0).contains(&growth)) {
            return Err(OptimError::InvalidOption {
                name: "fit.reoptimise_growth",
                value: growth,
                allowed: "a relative growth from 0 to 10",
            });
        }
        if !(self.stall_tolerance.is_finite() && self.stall_tolerance >= 0.0) {
            return Err(OptimError::InvalidOption {
                name: "stall_tolerance",
                value: self.stall_tolerance,
                allowed: "a finite relative growth >= 0",
            });
        }
        if let Some(reference) = &self.reference {
            if reference.len() != objectives || reference.iter().any(|v| !v.is_finite()) {
                return Err(OptimError::InvalidOption {
                    name: "reference",
                    value: reference.len() as f64,
                    allowed: "one finite value per objective",
                });
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use mrbrake_error::Kind as _;

    #[test]
    fn bad_settings_name_their_key() {
        let bounds = vec![Bounds::continuous(0.0, 1.0); 3];
        assert!(SurrogateOptions::default().validate(&bounds, 2).is_ok());
        let cases = [
            (SurrogateOptions { batch: 0, ..Default::default() }, "batch"),
            (SurrogateOptions { initial_size: Some(3), ..Default::default() }, "initial_size"),
            (SurrogateOptions { max_evaluations: 0, ..Default::default() }, "max_evaluations"),
            (SurrogateOptions { candidates: 0, ..Default::default() }, "candidates"),
            (SurrogateOptions { max_training: 2, ..Default::default() }, "max_training"),
            (
                SurrogateOptions { stall_tolerance: f64::NAN, ..Default::default() },
                "stall_tolerance",
            ),
            (SurrogateOptions { reference: Some(vec![1.0]), ..Default::default() }, "reference"),
        ];
        for (options, key) in cases {
            let error = options.validate(&bounds, 2).unwrap_err();
            assert!(error.is_input_error(), "{error}");
            assert!(error.to_string().contains(&format!("`{key}`")), "{key}: {error}");
        }
        assert!(SurrogateOptions::default().validate(&bounds, 0).is_err());
        assert_eq!(SurrogateOptions::default().initial_design_size(3), 30);
        let small = SurrogateOptions { initial_size: Some(4), ..Default::default() };
        assert_eq!(small.initial_design_size(3), 4);
    }

    #[test]
    fn acquisition_keys_parse_and_unknown_ones_name_the_key() {
        assert_eq!("ehvi".parse::<Acquisition>(), Ok(Acquisition::ExpectedHypervolumeImprovement));
        assert_eq!(" EHVI ".parse::<Acquisition>().map(Acquisition::key), Ok("ehvi"));
        let error = "qparego".parse::<Acquisition>().unwrap_err();
        assert!(error.is_input_error());
        assert!(
            error.to_string().contains("`acquisition`") && error.to_string().contains("qparego")
        );
    }
}
