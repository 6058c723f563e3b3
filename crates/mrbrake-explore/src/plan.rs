//! Sweep plans: which points of a design space a sweep evaluates, and how a sweep is split into
//! shards for independent processes.
//!
//! Brief overview: each `--vary` argument is a [`VarySpec`]: a list (`g=0.5mm,0.75mm,1mm`), a range
//! with a count (`h=5mm..10mm:6`, both ends included), bounds (`R0=20mm..30mm`) for sampling, or
//! for a material the materials by name (`materials.bobbin=aluminium,pom`, a categorical variable).
//! [`Sampling`] picks the points: the full factorial of the lists, ranges and materials, or `n`
//! Latin hypercube / Sobol' samples over the bounds and materials (a material's levels equally
//! represented, [`mrbrake_optim::sampling`]). [`Shard`] `K/N` keeps
//! the points whose index is `K` modulo `N`, so `N` processes with the same plan cover every point
//! exactly once.

use mrbrake_error::FieldError;
use mrbrake_optim::rng::Rng;
use mrbrake_optim::sampling;
use mrbrake_optim::space::Bounds;

use crate::variable::{Quantity, Variable};
use crate::{Design, DesignSpace, EvaluationSettings, ExploreError};

/// The values of one `--vary` argument.
#[derive(Debug, Clone, PartialEq)]
pub enum Values {
    /// Explicit values (SI).
    List(Vec<f64>),
    /// `count` evenly spaced values from `lower` to `upper` inclusive (SI).
    Range {
        /// First value.
        lower: f64,
        /// Last value.
        upper: f64,
        /// Number of values (≥ 1).
        count: usize,
    },
    /// Bounds for sampling (SI).
    Bounds {
        /// Lower bound.
        lower: f64,
        /// Upper bound.
        upper: f64,
    },
    /// The materials of a material variable, by name (its values are their indices).
    Levels(Vec<String>),
}

/// One `--vary NAME=…` argument, parsed.
#[derive(Debug, Clone, PartialEq)]
pub struct VarySpec {
    /// The variable's name as given.
    pub name: String,
    /// Its values.
    pub values: Values,
}

impl VarySpec {
    /// Splits `NAME=VALUES` into the name and the raw values text.
    pub fn split(argument: &str) -> Result<(String, String), ExploreError> {
        let (name, values) = argument.split_once('=').ok_or_else(|| {
            FieldError::new("vary", "expected NAME=VALUES")
                .with_value(format!("'{argument}'"))
                .with_allowed(
                    "e.g. g=0.5mm,0.75mm,1mm or h=5mm..10mm:6 or R0=20mm..30mm (with --sample)",
                )
        })?;
        Ok((name.trim().to_string(), values.trim().to_string()))
    }

    /// Parses the values text of `variable`: a material variable takes its materials by name,
    /// each checked against the library and the part ([`Variable::with_levels`]).
    pub fn parse(variable: &Variable, text: &str) -> Result<Self, ExploreError> {
        let bad = |why: &str| {
            ExploreError::from(
                FieldError::new("vary", why).with_value(format!("{}={text}", variable.name)),
            )
        };
        if variable.is_categorical() {
            if text.contains("..") {
                return Err(bad(
                    "a material takes a list of names (e.g. aluminium,pom), not a range",
                ));
            }
            let names: Vec<String> = text
                .split(',')
                .map(str::trim)
                .filter(|s| !s.is_empty())
                .map(String::from)
                .collect();
            let levels = variable.clone().with_levels(&names)?.levels().to_vec();
            return Ok(Self { name: variable.name.clone(), values: Values::Levels(levels) });
        }
        let values = if let Some((lower, rest)) = text.split_once("..") {
            let (upper, count) = match rest.split_once(':') {
                Some((upper, count)) => {
                    let count: usize = count
                        .trim()
                        .parse()
                        .map_err(|_| bad("the count after ':' must be a whole number ≥ 1"))?;
                    (upper, Some(count))
                }
                None => (rest, None),
            };
            let lower = variable.parse_value(lower)?;
            let upper = variable.parse_value(upper)?;
            if upper < lower {
                return Err(bad("the range's upper end is below its lower end"));
            }
            match count {
                Some(0) => return Err(bad("the count after ':' must be ≥ 1")),
                Some(count) if count > MAX_PLAN_POINTS => {
                    return Err(bad(&format!(
                        "the count after ':' must be at most {MAX_PLAN_POINTS} (a sweep's limit)"
                    )));
                }
                Some(count) => {
                    if variable.quantity() == Some(Quantity::Integer)
                        && count > 1
                        && ((upper - lower) / (count - 1) as f64).fract().abs() > 1e-9
                    {
                        return Err(bad("an integer range must have whole steps"));
                    }
                    Values::Range { lower, upper, count }
                }
                None => Values::Bounds { lower, upper },
            }
        } else {
            let list: Vec<f64> = text
                .split(',')
                .filter(|s| !s.trim().is_empty())
                .map(|s| variable.parse_value(s))
                .collect::<Result<_, _>>()?;
            if list.is_empty() {
                return Err(bad("no values"));
            }
            Values::List(list)
        };
        Ok(Self { name: variable.name.clone(), values })
    }

    /// The levels of a list or range (`None` for bounds).
    pub fn levels(&self) -> Option<Vec<f64>> {
        match &self.values {
            Values::List(list) => Some(list.clone()),
            Values::Range { lower, upper, count } => Some(if *count == 1 {
                vec![*lower]
            } else {
                (0..*count)
                    .map(|k| lower + (upper - lower) * k as f64 / (*count - 1) as f64)
                    .collect()
            }),
            Values::Bounds { .. } => None,
            Values::Levels(levels) => Some((0..levels.len()).map(|k| k as f64).collect()),
        }
    }
}

/// How the points of a sweep are chosen.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Sampling {
    /// Every combination of the variables' lists and ranges.
    FullFactorial,
    /// `n` Latin hypercube samples (McKay, Beckman & Conover 1979) over the bounds, seeded.
    LatinHypercube {
        /// Number of samples.
        n: usize,
        /// Seed of the generator.
        seed: u64,
    },
    /// The first `n` points of the Sobol' sequence (Joe & Kuo 2008 direction numbers).
    Sobol {
        /// Number of samples.
        n: usize,
    },
}

impl Sampling {
    /// Parses `lhs:N` or `sobol:N` (the seed comes separately).
    pub fn parse(text: &str, seed: u64) -> Result<Self, ExploreError> {
        let bad = || {
            ExploreError::from(
                FieldError::new("sample", "not a sampling")
                    .with_value(format!("'{text}'"))
                    .with_allowed("lhs:N or sobol:N with N ≥ 1 (e.g. lhs:64)"),
            )
        };
        let (kind, n) = text.split_once(':').ok_or_else(bad)?;
        let n: usize = n.trim().parse().map_err(|_| bad())?;
        if n == 0 {
            return Err(bad());
        }
        match kind.trim().to_ascii_lowercase().as_str() {
            "lhs" | "latin" => Ok(Self::LatinHypercube { n, seed }),
            "sobol" => Ok(Self::Sobol { n }),
            _ => Err(bad()),
        }
    }
}

/// The most points one sweep plan may have (full factorial product or samples): the plan is
/// held in memory and each point is a finite-element analysis, so this is far beyond a sweep that
/// can finish; a larger plan is an input error before anything is allocated.
pub const MAX_PLAN_POINTS: usize = 10_000_000;

/// The number of points of a plan as a checked count, or an input error of `field` (`vary`,
/// `sample`) above [`MAX_PLAN_POINTS`].
fn check_plan_size(count: Option<usize>, field: &str) -> Result<(), ExploreError> {
    match count {
        Some(n) if n <= MAX_PLAN_POINTS => Ok(()),
        _ => Err(FieldError::new(field, "the plan has too many points; sweep fewer")
            .with_value(count.map_or_else(|| "more than usize::MAX".to_string(), |n| n.to_string()))
            .with_allowed(format!("<= {MAX_PLAN_POINTS} points"))
            .into()),
    }
}

/// The points (SI values, one per variable) of a sweep.
pub fn points(
    variables: &[Variable],
    specs: &[VarySpec],
    sampling: Sampling,
) -> Result<Vec<Vec<f64>>, ExploreError> {
    match sampling {
        Sampling::FullFactorial => {
            let mut levels = Vec::with_capacity(specs.len());
            for spec in specs {
                levels.push(spec.levels().ok_or_else(|| {
                    FieldError::new(
                        "vary",
                        "bounds without a count need --sample lhs:N or sobol:N; for a grid give \
                         lower..upper:count",
                    )
                    .with_value(&spec.name)
                })?);
            }
            let count = levels.iter().try_fold(1usize, |n, l| n.checked_mul(l.len()));
            check_plan_size(count, "vary")?;
            Ok(sampling::full_factorial(&levels))
        }
        Sampling::LatinHypercube { n, .. } | Sampling::Sobol { n } => {
            check_plan_size(Some(n), "sample")?;
            let mut bounds = Vec::with_capacity(specs.len());
            for (variable, spec) in variables.iter().zip(specs) {
                match &spec.values {
                    &Values::Bounds { lower, upper } | &Values::Range { lower, upper, .. } => {
                        bounds.push(variable.bounds(lower, upper));
                    }
                    Values::Levels(levels) => bounds.push(Bounds::categorical(levels.len())),
                    Values::List(_) => {
                        let e = FieldError::new(
                            "vary",
                            "sampling needs bounds lower..upper, not a list",
                        )
                        .with_value(&spec.name);
                        return Err(e.into());
                    }
                }
            }
            for (i, b) in bounds.iter().enumerate() {
                b.validate(i)?;
            }
            match sampling {
                Sampling::LatinHypercube { seed, .. } => {
                    let mut rng = Rng::new(seed);
                    Ok(sampling::latin_hypercube(n, &bounds, &mut rng))
                }
                _ => Ok(sampling::sobol(n, &bounds)?),
            }
        }
    }
}

/// A deterministic share of a sweep: shard `index` of `count` (0-based, `0 ≤ index < count`)
/// takes the points whose position in the plan is `index` modulo `count`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Shard {
    /// This shard (0-based).
    pub index: usize,
    /// Number of shards.
    pub count: usize,
}

impl Shard {
    /// The whole plan.
    pub const ALL: Shard = Shard { index: 0, count: 1 };

    /// Parses `K/N` (e.g. `$SLURM_ARRAY_TASK_ID/4`, `$JOB_COMPLETION_INDEX/8`).
    pub fn parse(text: &str) -> Result<Self, ExploreError> {
        let bad = |why: &str| {
            ExploreError::from(
                FieldError::new("shard", why).with_value(format!("'{text}'")).with_allowed(
                    "K/N with 0 ≤ K < N (0-based, as Slurm array indices from 0 and Kubernetes \
                 completion indices are)",
                ),
            )
        };
        let (k, n) = text.split_once('/').ok_or_else(|| bad("no '/'"))?;
        let index: usize = k.trim().parse().map_err(|_| bad("K is not a whole number"))?;
        let count: usize = n.trim().parse().map_err(|_| bad("N is not a whole number"))?;
        if count == 0 || index >= count {
            return Err(bad("K must be below N and N at least 1"));
        }
        Ok(Self { index, count })
    }

    /// True when the point at `position` of the plan belongs to this shard.
    pub fn owns(&self, position: usize) -> bool {
        position % self.count == self.index
    }
}

/// A sweep as the `mrbrake sweep` flags describe it: the base spec, fixed changes, the `--vary`
/// arguments (`NAME=VALUES`), the sampling, the shard and the evaluation settings.
#[derive(Debug, Clone)]
pub struct SweepRequest<'a> {
    /// The base spec's TOML text.
    pub spec_text: &'a str,
    /// Where it came from (for messages and the design keys' provenance).
    pub origin: &'a str,
    /// Fixed changes to the base spec, `(path, value)` (the CLI's `--set`).
    pub overrides: &'a [(String, String)],
    /// The `NAME=VALUES` arguments (the CLI's `--vary`), one per variable.
    pub vary: &'a [String],
    /// Full factorial, Latin hypercube or Sobol'.
    pub sampling: Sampling,
    /// The share of the plan to evaluate.
    pub shard: Shard,
    /// Mesh, order and speed of every analysis.
    pub settings: EvaluationSettings,
}

/// The designs of a sweep: its design space, the number of points of the whole plan, and this
/// shard's designs in plan order.
#[derive(Debug)]
pub struct SweepPlan {
    /// The base spec, the variables and the settings.
    pub space: DesignSpace,
    /// Points in the whole plan (every shard).
    pub plan_points: usize,
    /// This shard's designs.
    pub designs: Vec<Design>,
}

/// The plan of a sweep (shared by the CLI's `sweep` and the Python package's `mrbrake.sweep`).
pub fn sweep_plan(request: &SweepRequest<'_>) -> Result<SweepPlan, ExploreError> {
    if request.vary.is_empty() {
        return Err(ExploreError::input("vary", "give at least one variable (NAME=VALUES)"));
    }
    let pairs: Vec<(String, String)> =
        request.vary.iter().map(|v| VarySpec::split(v)).collect::<Result<_, _>>()?;
    let names: Vec<String> = pairs.iter().map(|(n, _)| n.clone()).collect();
    let mut space = DesignSpace::new(
        request.spec_text,
        request.origin,
        request.overrides,
        &names,
        request.settings.clone(),
    )?;
    let specs: Vec<VarySpec> = space
        .variables()
        .iter()
        .zip(&pairs)
        .map(|(v, (_, text))| VarySpec::parse(v, text))
        .collect::<Result<_, _>>()?;
    for (index, spec) in specs.iter().enumerate() {
        if let Values::Levels(levels) = &spec.values {
            space.set_levels(index, levels)?;
        }
    }
    let points = points(space.variables(), &specs, request.sampling)?;
    let designs = points
        .iter()
        .enumerate()
        .filter(|(i, _)| request.shard.owns(*i))
        .map(|(_, p)| space.design(p))
        .collect::<Result<Vec<_>, _>>()?;
    Ok(SweepPlan { space, plan_points: points.len(), designs })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::variable::resolve;

    #[test]
    fn lists_ranges_and_bounds_parse() {
        let g = resolve("g", true).unwrap();
        let list = VarySpec::parse(&g, "0.5mm,0.75mm,1mm").unwrap();
        assert_eq!(list.levels().unwrap().len(), 3);
        let range = VarySpec::parse(&g, "0.5mm..1mm:6").unwrap();
        let levels = range.levels().unwrap();
        assert_eq!(levels.len(), 6);
        assert!((levels[5] - 1e-3).abs() < 1e-15 && (levels[1] - 0.6e-3).abs() < 1e-15);
        assert!(VarySpec::parse(&g, "1mm..0.5mm:3").is_err());
        assert!(VarySpec::parse(&g, "0.5mm..1mm:0").is_err());
        let n = resolve("n", true).unwrap();
        assert!(VarySpec::parse(&n, "1..4:3").is_err(), "1..4 in 3 steps is not whole");
    }

    /// Issue 18: plan sizes come from the command line; they are bounded before the levels or
    /// samples are allocated.
    #[test]
    fn oversized_plans_are_refused_before_allocating() {
        let g = resolve("g", true).unwrap();
        let h = resolve("h", true).unwrap();
        let e = VarySpec::parse(&g, "0.5mm..1mm:1000000000000").unwrap_err();
        assert!(e.to_string().contains("at most"), "{e}");
        assert!(e.to_string().starts_with("vary: "), "{e}");
        let specs = vec![
            VarySpec::parse(&g, "0.5mm..1mm:10000").unwrap(),
            VarySpec::parse(&h, "5mm..10mm:10000").unwrap(),
        ];
        let vars = [g.clone(), h.clone()];
        let e = points(&vars, &specs, Sampling::FullFactorial).unwrap_err();
        assert!(e.to_string().contains("got 100000000; allowed: <= 10000000 points"), "{e}");
        let sobol = Sampling::parse("sobol:1000000000000", 1).unwrap();
        let e = points(&vars, &specs, sobol).unwrap_err().to_string();
        assert!(e.starts_with("sample: the plan has too many points"), "{e}");
    }

    #[test]
    fn full_factorial_needs_counts_and_covers_every_combination() {
        let g = resolve("g", true).unwrap();
        let h = resolve("h", true).unwrap();
        let specs = vec![
            VarySpec::parse(&g, "0.5mm,1mm").unwrap(),
            VarySpec::parse(&h, "5mm..10mm:3").unwrap(),
        ];
        let pts = points(&[g.clone(), h.clone()], &specs, Sampling::FullFactorial).unwrap();
        assert_eq!(pts.len(), 6);
        let bounds = vec![VarySpec::parse(&g, "0.5mm..1mm").unwrap()];
        assert!(points(std::slice::from_ref(&g), &bounds, Sampling::FullFactorial).is_err());
        let lhs = points(&[g], &bounds, Sampling::LatinHypercube { n: 8, seed: 3 }).unwrap();
        assert_eq!(lhs.len(), 8);
        assert!(lhs.iter().all(|p| (0.5e-3..=1e-3).contains(&p[0])));
    }

    #[test]
    fn shards_partition_the_plan() {
        let shards: Vec<Shard> = (0..3).map(|k| Shard::parse(&format!("{k}/3")).unwrap()).collect();
        for position in 0..20 {
            assert_eq!(shards.iter().filter(|s| s.owns(position)).count(), 1);
        }
        assert!(Shard::parse("3/3").is_err());
        assert!(Shard::parse("1").is_err());
    }
}
