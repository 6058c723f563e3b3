//! Optimisation problem files (TOML): the base spec, design variables with bounds, constraints on
//! metrics, objectives, and the algorithm.
//!
//! ```toml
//! spec = "../specs/thesis-bidirectional.toml"   # relative to this file
//! mesh = "default"                             # coarse | default | fine
//! order = 1                                    # element order: 1 (linear) or 2 (quadratic)
//! [set]                                        # fixed changes to the base spec
//! "coil.turns" = "fill"                        # the turns fill the window, (4.2), (4.3)
//! [[variable]]
//! name = "drum.r0"                             # a spec field or a thesis symbol (R0)
//! min = "18mm"
//! max = "30mm"
//! [[constraint]]
//! metric = "torque_max_Nm"                     # any metric of `mrbrake optimize --list-metrics`
//! min = "3Nm"                                  # and/or max; a number (SI) or a quantity with unit
//! [[objective]]
//! metric = "rotor_inertia_kg_m2"
//! goal = "minimize"                            # or "maximize"
//! record = ["t63_fall_s"]                      # more metrics to store (top-level key)
//! [response]                                   # settings of the dynamics metrics, as
//! duration = "100ms"                           # `mrbrake response` (crate::metrics::settings)
//! [thermal]                                    # settings of the heat metrics, as
//! ambient = "25C"                              # `mrbrake thermal`
//! [algorithm]
//! kind = "nsga2"                               # or "pattern-search" (one objective)
//! population = 24
//! generations = 10
//! seed = 1
//! # pattern-search only: max_evaluations = 200, poll = "compass" | "random",
//! # start = "centre" | "base" (the base spec's values)
//! ```
//!
//! Every field is checked when the file is read; an error names the file, the table and the field
//! and what is allowed. Counts are bounded before anything is sized by them: `population` ≤
//! [`MAX_POPULATION`], `generations` and `max_evaluations` ≤ [`MAX_EVALUATIONS`] designs.

use std::path::{Path, PathBuf};

use mrbrake_design::analysis::ElementOrder;
use mrbrake_design::mesh_build::MeshLevel;
use mrbrake_units::{Dimension, parse};
use schemars::JsonSchema;
use serde::Deserialize;

use crate::ExploreError;
use crate::evaluate::{EvaluationSettings, METRICS, current_metric_name, metric_info};

/// A number (SI) or a quantity with its unit.
#[derive(Debug, Clone, PartialEq, Deserialize, JsonSchema)]
#[serde(untagged)]
enum RawQuantity {
    /// A number in SI units.
    Number(f64),
    /// A whole number in SI units.
    Integer(i64),
    /// A quantity with its unit (`"18mm"`, `"3Nm"`).
    Text(String),
}

/// An optimisation problem file.
#[derive(Debug, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
struct RawProblem {
    /// The base spec, relative to this file.
    spec: String,
    /// Mesh density of every evaluation.
    #[serde(default)]
    #[schemars(schema_with = "mesh_level")]
    mesh: Option<String>,
    /// Relative speed of the viscous torque (e.g. `"1rad/s"`, `"60rpm"`; default 1 rad/s).
    #[serde(default)]
    speed: Option<String>,
    /// Element order of the field solution: 1 (linear) or 2 (quadratic).
    #[serde(default)]
    #[schemars(schema_with = "element_order")]
    order: Option<i64>,
    /// Fixed changes to the base spec: spec paths (`"coil.turns"`) to values (`"fill"` lets the
    /// turns fill the window, (4.2), (4.3)).
    #[serde(default)]
    #[schemars(schema_with = "set_table")]
    set: toml::Table,
    /// Evaluate the base spec too, as the reference of the front.
    #[serde(default)]
    reference: Option<bool>,
    /// The design variables: spec fields (`drum.r0`) or thesis symbols (`R0`) with bounds.
    #[serde(default, rename = "variable")]
    variables: Vec<RawVariable>,
    /// Bounds on metrics (`mrbrake optimize --list-metrics`).
    #[serde(default, rename = "constraint")]
    constraints: Vec<RawConstraint>,
    /// The objectives: one (pattern search) or more (NSGA-II).
    #[serde(default, rename = "objective")]
    objectives: Vec<RawObjective>,
    /// Metrics to compute and store for every design besides those of the constraints and
    /// objectives (e.g. `["t63_fall_s", "coil_max_T_C"]`): a dynamics or heat metric is computed
    /// only when named here, in a constraint or in an objective.
    #[serde(default)]
    record: Vec<String>,
    /// Settings of the dynamics metrics (`mrbrake response`'s options and defaults).
    #[serde(default)]
    response: Option<crate::metrics::settings::RawResponse>,
    /// Settings of the heat metrics (`mrbrake thermal`'s options and defaults).
    #[serde(default)]
    thermal: Option<crate::metrics::settings::RawThermal>,
    /// The optimiser and its budget.
    algorithm: RawAlgorithm,
}

/// `mesh`: coarse, default or fine.
fn mesh_level(_: &mut schemars::SchemaGenerator) -> schemars::Schema {
    mrbrake_schema::choice(&["coarse", "default", "fine"], Some("default"))
}

/// `order`: 1 or 2.
fn element_order(_: &mut schemars::SchemaGenerator) -> schemars::Schema {
    mrbrake_schema::element_order()
}

/// `[set]`: spec paths to values.
fn set_table(_: &mut schemars::SchemaGenerator) -> schemars::Schema {
    schemars::json_schema!({
        "type": "object",
        "additionalProperties": { "type": ["number", "string", "integer"] },
    })
}

/// `[[variable]]`: a design variable.
#[derive(Debug, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
struct RawVariable {
    /// A spec field (`drum.r0`) or a thesis symbol (`R0`).
    name: String,
    /// Lower bound (SI number or quantity with unit).
    min: RawQuantity,
    /// Upper bound.
    max: RawQuantity,
}

/// `[[constraint]]`: bounds on a metric.
#[derive(Debug, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
struct RawConstraint {
    /// The metric.
    #[schemars(schema_with = "metric_name")]
    metric: String,
    /// Its lower limit.
    #[serde(default)]
    min: Option<RawQuantity>,
    /// Its upper limit.
    #[serde(default)]
    max: Option<RawQuantity>,
}

/// A metric's name, one of [`METRICS`].
fn metric_name(_: &mut schemars::SchemaGenerator) -> schemars::Schema {
    let names: Vec<&str> = METRICS.iter().map(|m| m.name).collect();
    mrbrake_schema::choice(&names, None)
}

/// `[[objective]]`.
#[derive(Debug, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
struct RawObjective {
    /// The metric.
    #[schemars(schema_with = "metric_name")]
    metric: String,
    /// `minimize` or `maximize`.
    #[serde(default = "minimize")]
    #[schemars(schema_with = "goal")]
    goal: String,
}

fn goal(_: &mut schemars::SchemaGenerator) -> schemars::Schema {
    mrbrake_schema::choice(&["minimize", "maximize"], Some("minimize"))
}

fn minimize() -> String {
    "minimize".into()
}

/// `[algorithm]`.
#[derive(Debug, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
struct RawAlgorithm {
    /// `nsga2` (NSGA-II, one or more objectives) or `pattern-search` (one objective).
    #[schemars(schema_with = "algorithm_kind")]
    kind: String,
    /// NSGA-II: the population, an even number from 4.
    #[serde(default)]
    population: Option<usize>,
    /// NSGA-II: generations after the initial population.
    #[serde(default)]
    generations: Option<usize>,
    /// Pattern search: the most designs evaluated.
    #[serde(default)]
    max_evaluations: Option<usize>,
    /// Seed of the random numbers (reproducible runs).
    #[serde(default)]
    seed: Option<u64>,
    /// Pattern search: `compass` or `random` polling.
    #[serde(default)]
    #[schemars(schema_with = "poll")]
    poll: Option<String>,
    /// Pattern search: start at the `centre` of the bounds or at the `base` spec's values.
    #[serde(default)]
    #[schemars(schema_with = "start")]
    start: Option<String>,
}

fn algorithm_kind(_: &mut schemars::SchemaGenerator) -> schemars::Schema {
    mrbrake_schema::choice(&["nsga2", "pattern-search"], None)
}

fn poll(_: &mut schemars::SchemaGenerator) -> schemars::Schema {
    mrbrake_schema::choice(&["compass", "random"], Some("compass"))
}

fn start(_: &mut schemars::SchemaGenerator) -> schemars::Schema {
    mrbrake_schema::choice(&["centre", "base"], Some("centre"))
}

/// The JSON Schema of an optimisation problem file (`mrbrake optimize`); counts bounded by
/// [`MAX_POPULATION`] and [`MAX_EVALUATIONS`], the limits the reader checks.
pub fn schema() -> serde_json::Value {
    use mrbrake_schema::{Bounds, annotate, node_mut, order};
    let mut schema = mrbrake_schema::generate::<RawProblem>();
    schema["$id"] = serde_json::json!("https://mrbrake.invalid/schema/study.json");
    schema["title"] = serde_json::json!("mrbrake optimisation problem");
    schema["description"] = serde_json::json!(
        "A constrained design optimisation for `mrbrake optimize`: a base spec, design variables \
         with bounds, constraints on metrics, objectives and the algorithm."
    );
    order::<RawVariable>(&mut schema, "variable");
    order::<RawConstraint>(&mut schema, "constraint");
    order::<RawObjective>(&mut schema, "objective");
    order::<RawAlgorithm>(&mut schema, "algorithm");
    order::<crate::metrics::settings::RawResponse>(&mut schema, "response");
    order::<crate::metrics::settings::RawThermal>(&mut schema, "thermal");
    let counts = [
        ("algorithm.population", Bounds::closed(4.0, MAX_POPULATION as f64)),
        ("algorithm.generations", Bounds::closed(0.0, MAX_EVALUATIONS as f64)),
        ("algorithm.max_evaluations", Bounds::closed(1.0, MAX_EVALUATIONS as f64)),
    ];
    for (path, bounds) in counts {
        if let Some(node) = node_mut(&mut schema, path) {
            annotate(node, "", bounds);
        }
    }
    schema
}

/// A design variable with its bounds (SI).
#[derive(Debug, Clone, PartialEq)]
pub struct VariableBounds {
    /// The name (spec field or thesis symbol).
    pub name: String,
    /// Lower bound (SI).
    pub min: f64,
    /// Upper bound (SI).
    pub max: f64,
}

/// A bound on a metric (SI).
#[derive(Debug, Clone, PartialEq)]
pub struct Constraint {
    /// The metric.
    pub metric: String,
    /// Lower limit.
    pub min: Option<f64>,
    /// Upper limit.
    pub max: Option<f64>,
}

impl Constraint {
    /// The normalised violation of `value`: 0 when within the limits, else the distance to the
    /// violated limit relative to its magnitude (so constraints of different units add up, as in
    /// Deb 2000, *An efficient constraint handling method for genetic algorithms*, eq. 2).
    pub fn violation(&self, value: f64) -> f64 {
        // An infinite value (a time never reached) satisfies the bound on its other side.
        if value.is_nan() {
            return f64::INFINITY;
        }
        let scale = |limit: f64| limit.abs().max(1e-12);
        let below = self.min.map_or(0.0, |lo| ((lo - value) / scale(lo)).max(0.0));
        let above = self.max.map_or(0.0, |hi| ((value - hi) / scale(hi)).max(0.0));
        below + above
    }

    /// The signed margin to the nearest limit, relative to its magnitude: positive inside, zero on
    /// the limit (an active constraint), negative when violated.
    pub fn margin(&self, value: f64) -> f64 {
        let scale = |limit: f64| limit.abs().max(1e-12);
        let lo = self.min.map_or(f64::INFINITY, |lo| (value - lo) / scale(lo));
        let hi = self.max.map_or(f64::INFINITY, |hi| (hi - value) / scale(hi));
        lo.min(hi)
    }
}

/// Minimise or maximise.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Goal {
    /// Smaller is better.
    Minimize,
    /// Larger is better.
    Maximize,
}

/// An objective.
#[derive(Debug, Clone, PartialEq)]
pub struct Objective {
    /// The metric.
    pub metric: String,
    /// Its goal.
    pub goal: Goal,
}

/// The optimisation algorithm.
#[derive(Debug, Clone, PartialEq)]
pub enum Algorithm {
    /// NSGA-II (Deb et al. 2002).
    Nsga2 {
        /// Population size (even, ≥ 4).
        population: usize,
        /// Generations after the initial population.
        generations: usize,
        /// Seed.
        seed: u64,
    },
    /// Pattern search (one objective).
    PatternSearch {
        /// Evaluation budget.
        max_evaluations: usize,
        /// Seed of the random poll bases (no effect with compass polls).
        seed: u64,
        /// Poll with a fresh random orthogonal basis each iteration instead of the coordinate
        /// directions: slower, but it can follow constraints oblique to the axes.
        random_poll: bool,
        /// Start at the base spec's values (clamped into the bounds) instead of the bounds' centre.
        start_at_base: bool,
    },
}

/// A whole, checked problem file.
#[derive(Debug, Clone, PartialEq)]
pub struct OptimizationProblem {
    /// The problem file.
    pub path: PathBuf,
    /// The base spec file (resolved against the problem file's folder).
    pub spec_path: PathBuf,
    /// Fixed overrides `PATH = VALUE` applied to the base spec.
    pub overrides: Vec<(String, String)>,
    /// Evaluate the base spec too and show it as the reference design.
    pub reference: bool,
    /// The evaluation settings.
    pub settings: EvaluationSettings,
    /// Variables.
    pub variables: Vec<VariableBounds>,
    /// Constraints.
    pub constraints: Vec<Constraint>,
    /// Objectives.
    pub objectives: Vec<Objective>,
    /// Algorithm.
    pub algorithm: Algorithm,
    /// Notes for the user that do not stop the run: a metric named by its legacy name (see
    /// [`crate::evaluate::LEGACY_METRIC_NAMES`]), with its current name.
    pub notes: Vec<String>,
}

impl OptimizationProblem {
    /// Reads and checks a problem file.
    pub fn from_path(path: &Path) -> Result<Self, ExploreError> {
        let text = std::fs::read_to_string(path).map_err(|e| {
            ExploreError::Input(format!("{}: cannot read the problem file: {e}", path.display()))
        })?;
        Self::from_toml_str(&text, path)
    }

    /// Parses problem-file text; `path` locates the spec and names the file in messages.
    pub fn from_toml_str(text: &str, path: &Path) -> Result<Self, ExploreError> {
        let origin = path.display().to_string();
        let bad = |what: String| ExploreError::Input(format!("{origin}: {what}"));
        let raw: RawProblem = toml::from_str(text).map_err(|e| bad(e.to_string()))?;
        let folder = path.parent().unwrap_or_else(|| Path::new("."));
        let mut settings = settings_of(&raw).map_err(bad)?;
        let variables = variables_of(&raw.variables).map_err(bad)?;
        let constraints = constraints_of(&raw.constraints).map_err(bad)?;
        let objectives = objectives_of(&raw.objectives).map_err(bad)?;
        settings.study = crate::metrics::settings::study_of(
            &raw.record,
            &raw.response,
            &raw.thermal,
            &constraints,
            &objectives,
        )
        .map_err(bad)?;
        let notes = legacy_name_notes(&raw, &origin);
        let algorithm = algorithm_of(&raw.algorithm, objectives.len()).map_err(bad)?;
        Ok(Self {
            path: path.to_path_buf(),
            spec_path: folder.join(&raw.spec),
            overrides: overrides_of(&raw.set),
            reference: raw.reference.unwrap_or(true),
            settings,
            variables,
            constraints,
            objectives,
            algorithm,
            notes,
        })
    }
}

/// A note for every constraint or objective that names a metric by its legacy name.
fn legacy_name_notes(raw: &RawProblem, origin: &str) -> Vec<String> {
    let constraints = raw.constraints.iter().map(|c| ("constraint", c.metric.trim()));
    let objectives = raw.objectives.iter().map(|o| ("objective", o.metric.trim()));
    let mut notes = Vec::new();
    let mut counts = [0usize; 2];
    for (table, name) in constraints.chain(objectives) {
        let count = &mut counts[usize::from(table == "objective")];
        *count += 1;
        if let (new, true) = current_metric_name(name) {
            notes.push(format!(
                "{origin}: {table} {count}: metric '{name}' is now named '{new}' (the old name \
                 still works; see docs/CONVENTIONS.md)"
            ));
        }
    }
    notes
}

// The readers of each part of the file return what is wrong, naming the table and the field; the
// caller prefixes the file.

/// Mesh level, element order and speed over the defaults.
fn settings_of(raw: &RawProblem) -> Result<EvaluationSettings, String> {
    let mut settings = EvaluationSettings::default();
    if let Some(mesh) = &raw.mesh {
        settings.mesh = MeshLevel::parse(mesh).map_err(|e| format!("mesh: {e}"))?;
    }
    if let Some(degree) = raw.order {
        settings.order = ElementOrder::from_degree(degree)
            .ok_or_else(|| format!("order: {degree} is not allowed; use 1 or 2"))?;
    }
    if let Some(speed) = &raw.speed {
        settings.speed_rad_s =
            parse(speed, Dimension::AngularVelocity).map_err(|e| format!("speed: {e}"))?;
    }
    settings.check().map_err(|e| e.to_string())?;
    Ok(settings)
}

/// The `[set]` table as `PATH`, `VALUE` pairs (strings unquoted, other values as TOML).
fn overrides_of(set: &toml::Table) -> Vec<(String, String)> {
    set.iter()
        .map(|(field, value)| {
            let text = match value {
                toml::Value::String(s) => s.clone(),
                other => other.to_string(),
            };
            (field.clone(), text)
        })
        .collect()
}

/// The variables with their bounds in SI, read with each variable's own unit.
fn variables_of(raw: &[RawVariable]) -> Result<Vec<VariableBounds>, String> {
    if raw.is_empty() {
        return Err("no [[variable]]: give at least one design variable".into());
    }
    let mut variables = Vec::new();
    for (i, v) in raw.iter().enumerate() {
        let where_ = format!("variable {} ('{}')", i + 1, v.name);
        // Bounds read with the variable's own unit; the symbol resolves against the spec
        // later, so read them with the field the name denotes for either configuration.
        let field_quantity = crate::variable::resolve(&v.name, true)
            .or_else(|_| crate::variable::resolve(&v.name, false))
            .map_err(|e| format!("{where_}: {e}"))?;
        let read = |q: &RawQuantity, which: &str| -> Result<f64, String> {
            let text = match q {
                RawQuantity::Number(x) => return Ok(*x),
                RawQuantity::Integer(i) => return Ok(*i as f64),
                RawQuantity::Text(t) => t,
            };
            field_quantity.parse_value(text).map_err(|e| format!("{where_}.{which}: {e}"))
        };
        let (min, max) = (read(&v.min, "min")?, read(&v.max, "max")?);
        if !(min.is_finite() && max.is_finite() && min < max) {
            return Err(format!("{where_}: needs min < max, got {min} and {max}"));
        }
        variables.push(VariableBounds { name: v.name.clone(), min, max });
    }
    Ok(variables)
}

/// The constraints, each with a min, a max or both, in the metric's unit.
fn constraints_of(raw: &[RawConstraint]) -> Result<Vec<Constraint>, String> {
    let mut constraints = Vec::new();
    for (i, c) in raw.iter().enumerate() {
        let where_ = format!("constraint {} ('{}')", i + 1, c.metric);
        let info = known_metric(&c.metric).map_err(|e| format!("{where_}: {e}"))?;
        let read = |q: &Option<RawQuantity>, which: &str| -> Result<Option<f64>, String> {
            q.as_ref()
                .map(|q| metric_value(q, info.unit).map_err(|e| format!("{where_}.{which}: {e}")))
                .transpose()
        };
        let (min, max) = (read(&c.min, "min")?, read(&c.max, "max")?);
        if min.is_none() && max.is_none() {
            return Err(format!("{where_}: give min, max or both"));
        }
        if let (Some(lo), Some(hi)) = (min, max) {
            if lo > hi {
                return Err(format!("{where_}: min {lo} is above max {hi}"));
            }
        }
        constraints.push(Constraint { metric: info.name.to_string(), min, max });
    }
    Ok(constraints)
}

/// At least one objective, each minimised or maximised.
fn objectives_of(raw: &[RawObjective]) -> Result<Vec<Objective>, String> {
    if raw.is_empty() {
        return Err("no [[objective]]: give one (pattern search) or more (nsga2)".into());
    }
    let mut objectives = Vec::new();
    for (i, o) in raw.iter().enumerate() {
        let where_ = format!("objective {} ('{}')", i + 1, o.metric);
        let info = known_metric(&o.metric).map_err(|e| format!("{where_}: {e}"))?;
        let goal = match o.goal.trim().to_ascii_lowercase().as_str() {
            "minimize" | "minimise" | "min" => Goal::Minimize,
            "maximize" | "maximise" | "max" => Goal::Maximize,
            other => {
                return Err(format!(
                    "{where_}.goal: '{other}' is not allowed; use minimize or maximize"
                ));
            }
        };
        objectives.push(Objective { metric: info.name.to_string(), goal });
    }
    Ok(objectives)
}

/// A budget override from the command line (`mrbrake optimize --generations N
/// --max-evaluations M`), for a quick run of a problem file without editing it.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct BudgetOverride {
    /// NSGA-II generations after the initial population.
    pub generations: Option<usize>,
    /// The most designs evaluated: pattern search's budget; for NSGA-II, the generations are cut
    /// to the most whose `population × (generations + 1)` designs fit.
    pub max_evaluations: Option<usize>,
}

impl Algorithm {
    /// The algorithm with `budget` applied; an override the algorithm has no use for
    /// (`--generations` for pattern search) or out of range is an input error naming the flag.
    pub fn with_budget(&self, budget: BudgetOverride) -> Result<Algorithm, ExploreError> {
        let bad = |what: String| Err(ExploreError::Input(what));
        match *self {
            Algorithm::Nsga2 { population, mut generations, seed } => {
                if let Some(g) = budget.generations {
                    generations = g;
                }
                if let Some(max) = budget.max_evaluations {
                    if max < population {
                        return bad(format!(
                            "--max-evaluations {max} is less than one generation of NSGA-II \
                             (population {population}); use at least {population}"
                        ));
                    }
                    generations = generations.min(max / population - 1);
                }
                let designs = generations.checked_add(1).and_then(|g| g.checked_mul(population));
                if designs.is_none_or(|d| d > MAX_EVALUATIONS) {
                    return bad(format!(
                        "--generations {generations} of {population} is more than \
                         {MAX_EVALUATIONS} designs; use fewer"
                    ));
                }
                Ok(Algorithm::Nsga2 { population, generations, seed })
            }
            Algorithm::PatternSearch { max_evaluations, seed, random_poll, start_at_base } => {
                if budget.generations.is_some() {
                    return bad("--generations applies to NSGA-II; pattern search takes \
                                --max-evaluations"
                        .into());
                }
                let max_evaluations = budget.max_evaluations.unwrap_or(max_evaluations);
                if max_evaluations == 0 || max_evaluations > MAX_EVALUATIONS {
                    return bad(format!(
                        "--max-evaluations {max_evaluations} is not allowed; use 1 to \
                         {MAX_EVALUATIONS}"
                    ));
                }
                Ok(Algorithm::PatternSearch { max_evaluations, seed, random_poll, start_at_base })
            }
        }
    }
}

/// The largest NSGA-II population (each generation holds and sorts it in memory).
pub const MAX_POPULATION: usize = 100_000;

/// The most designs one optimisation may evaluate (`population × (generations + 1)` or
/// `max_evaluations`); every design is a finite-element analysis, so this is far beyond any
/// study that can finish, and it keeps every count the optimisers allocate from sane.
pub const MAX_EVALUATIONS: usize = 10_000_000;

/// The `[algorithm]` table, for a problem with `objectives` objectives.
fn algorithm_of(a: &RawAlgorithm, objectives: usize) -> Result<Algorithm, String> {
    let seed = a.seed.unwrap_or(1);
    match a.kind.trim().to_ascii_lowercase().as_str() {
        "nsga2" | "nsga-ii" => {
            let population = a.population.unwrap_or(24);
            if population < 4 || population % 2 == 1 || population > MAX_POPULATION {
                return Err(format!(
                    "algorithm.population: {population} is not allowed; use an even number from 4 \
                     to {MAX_POPULATION}"
                ));
            }
            let generations = a.generations.unwrap_or(10);
            let designs = generations.checked_add(1).and_then(|g| g.checked_mul(population));
            if designs.is_none_or(|d| d > MAX_EVALUATIONS) {
                return Err(format!(
                    "algorithm.generations: {generations} generations of {population} is more than \
                     {MAX_EVALUATIONS} designs; use fewer"
                ));
            }
            Ok(Algorithm::Nsga2 { population, generations, seed })
        }
        "pattern-search" | "pattern_search" => pattern_search_of(a, objectives, seed),
        other => {
            Err(format!("algorithm.kind: '{other}' is not allowed; use nsga2 or pattern-search"))
        }
    }
}

fn pattern_search_of(a: &RawAlgorithm, objectives: usize, seed: u64) -> Result<Algorithm, String> {
    if objectives != 1 {
        return Err(format!(
            "algorithm.kind = pattern-search optimises one objective; {objectives} are given \
             (use nsga2 for several)"
        ));
    }
    let random_poll = match a.poll.as_deref().map(str::trim) {
        None | Some("compass") => false,
        Some("random" | "random-orthogonal") => true,
        Some(other) => {
            return Err(format!("algorithm.poll: '{other}' is not allowed; use compass or random"));
        }
    };
    let start_at_base = match a.start.as_deref().map(str::trim) {
        None | Some("centre" | "center") => false,
        Some("base") => true,
        Some(other) => {
            return Err(format!("algorithm.start: '{other}' is not allowed; use centre or base"));
        }
    };
    let max_evaluations = a.max_evaluations.unwrap_or(200);
    if max_evaluations == 0 || max_evaluations > MAX_EVALUATIONS {
        return Err(format!(
            "algorithm.max_evaluations: {max_evaluations} is not allowed; use 1 to {MAX_EVALUATIONS}"
        ));
    }
    Ok(Algorithm::PatternSearch { max_evaluations, seed, random_poll, start_at_base })
}

pub(crate) fn known_metric(
    name: &str,
) -> Result<&'static crate::evaluate::MetricInfo, ExploreError> {
    metric_info(current_metric_name(name.trim()).0).ok_or_else(|| {
        ExploreError::Input(format!(
            "unknown metric '{name}'; allowed: {}",
            METRICS.iter().map(|m| m.name).collect::<Vec<_>>().join(", ")
        ))
    })
}

/// A metric limit: a bare number in the metric's SI unit, or a quantity with a unit of the
/// metric's dimension (`"3Nm"`, `"80mm"`, `"1.6T"`).
fn metric_value(q: &RawQuantity, unit: &str) -> Result<f64, ExploreError> {
    match q {
        RawQuantity::Number(x) => Ok(*x),
        RawQuantity::Integer(i) => Ok(*i as f64),
        RawQuantity::Text(text) => {
            let dimension = match unit {
                "m" => Dimension::Length,
                "T" => Dimension::FluxDensity,
                "A" => Dimension::Current,
                "N·m" => Dimension::Torque,
                "s" => Dimension::Time,
                "rad/s" => Dimension::AngularVelocity,
                "°C" => Dimension::TemperatureCelsius,
                _ => {
                    return text.trim().parse::<f64>().map_err(|_| {
                        ExploreError::Input(format!(
                            "'{text}': give a bare number in {unit} for this metric"
                        ))
                    });
                }
            };
            parse(text, dimension).map_err(|e| ExploreError::Input(e.to_string()))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use mrbrake_error::Kind as _;

    const GOOD: &str = r#"
spec = "../specs/thesis-bidirectional.toml"
mesh = "coarse"
[set]
"coil.turns" = "fill"
[[variable]]
name = "R0"
min = "18mm"
max = "30mm"
[[variable]]
name = "n"
min = 1
max = 3
[[constraint]]
metric = "torque_max_Nm"
min = "3Nm"
[[constraint]]
metric = "outer_diameter_m"
max = "80mm"
[[objective]]
metric = "rotor_inertia_kg_m2"
[[objective]]
metric = "volume_m3"
[algorithm]
kind = "nsga2"
population = 8
generations = 2
"#;

    #[test]
    fn a_good_file_reads_with_units() {
        let p = OptimizationProblem::from_toml_str(GOOD, Path::new("ex/p.toml")).unwrap();
        assert_eq!(p.spec_path, Path::new("ex/../specs/thesis-bidirectional.toml"));
        assert!((p.variables[0].min - 0.018).abs() < 1e-15);
        assert!((p.constraints[0].min.unwrap() - 3.0).abs() < 1e-12);
        assert!((p.constraints[1].max.unwrap() - 0.08).abs() < 1e-15);
        assert_eq!(p.overrides, vec![("coil.turns".to_string(), "fill".to_string())]);
        assert_eq!(p.settings.mesh, MeshLevel::Coarse);
    }

    #[test]
    fn legacy_metric_names_still_work_with_a_note_naming_the_new_name() {
        let good = OptimizationProblem::from_toml_str(GOOD, Path::new("p.toml")).unwrap();
        assert!(good.notes.is_empty(), "{:?}", good.notes);
        let old = GOOD.replace("torque_max_Nm", "torque_max_nm");
        let p = OptimizationProblem::from_toml_str(&old, Path::new("p.toml")).unwrap();
        assert_eq!(p.constraints, good.constraints, "the old name reads as the new one");
        assert_eq!(p.notes.len(), 1, "{:?}", p.notes);
        let note = &p.notes[0];
        assert!(note.contains("p.toml") && note.contains("constraint 1"), "{note}");
        assert!(note.contains("'torque_max_nm'") && note.contains("'torque_max_Nm'"), "{note}");
    }

    #[test]
    fn errors_name_the_file_and_field() {
        let bad = GOOD.replace("torque_max_Nm", "torque_maximum");
        let e = OptimizationProblem::from_toml_str(&bad, Path::new("p.toml")).unwrap_err();
        let text = e.to_string();
        assert!(text.contains("p.toml") && text.contains("constraint 1"), "{text}");
        assert!(e.is_input_error());
        let odd = GOOD.replace("population = 8", "population = 7");
        let text = OptimizationProblem::from_toml_str(&odd, Path::new("p.toml")).unwrap_err();
        assert!(text.to_string().contains("algorithm.population"), "{text}");
        let ps = GOOD.replace("kind = \"nsga2\"", "kind = \"pattern-search\"");
        assert!(OptimizationProblem::from_toml_str(&ps, Path::new("p.toml")).is_err());
        let cubic = GOOD.replace("mesh = \"coarse\"", "mesh = \"coarse\"\norder = 3");
        let text = OptimizationProblem::from_toml_str(&cubic, Path::new("p.toml")).unwrap_err();
        assert!(text.to_string().contains("order: 3 is not allowed; use 1 or 2"), "{text}");
        let ps_zero = ps
            .replace("[[objective]]\nmetric = \"volume_m3\"\n", "")
            .replace("kind = \"pattern-search\"", "kind = \"pattern-search\"\nmax_evaluations = 0");
        let text = OptimizationProblem::from_toml_str(&ps_zero, Path::new("p.toml")).unwrap_err();
        assert!(text.to_string().contains("algorithm.max_evaluations: 0"), "{text}");
        let quadratic = GOOD.replace("mesh = \"coarse\"", "mesh = \"coarse\"\norder = 2");
        let p = OptimizationProblem::from_toml_str(&quadratic, Path::new("p.toml")).unwrap();
        assert_eq!(p.settings.order, ElementOrder::P2);
    }

    /// Issue 19: `--generations` / `--max-evaluations` shorten a run without editing the file.
    #[test]
    fn budget_overrides_shorten_the_run() {
        let nsga = Algorithm::Nsga2 { population: 8, generations: 10, seed: 1 };
        let quick = |g, m| nsga.with_budget(BudgetOverride { generations: g, max_evaluations: m });
        assert_eq!(
            quick(Some(2), None).unwrap(),
            Algorithm::Nsga2 { population: 8, generations: 2, seed: 1 }
        );
        // 20 designs hold two generations of 8 (the initial one and one more).
        assert_eq!(
            quick(None, Some(20)).unwrap(),
            Algorithm::Nsga2 { population: 8, generations: 1, seed: 1 }
        );
        assert_eq!(quick(None, None).unwrap(), nsga);
        let e = quick(None, Some(7)).unwrap_err().to_string();
        assert!(e.contains("--max-evaluations 7") && e.contains("at least 8"), "{e}");
        assert!(quick(Some(usize::MAX), None).is_err());
        let ps = Algorithm::PatternSearch {
            max_evaluations: 200,
            seed: 1,
            random_poll: false,
            start_at_base: false,
        };
        let b = |g, m| ps.with_budget(BudgetOverride { generations: g, max_evaluations: m });
        assert!(matches!(
            b(None, Some(12)).unwrap(),
            Algorithm::PatternSearch { max_evaluations: 12, .. }
        ));
        assert!(
            b(Some(3), None).unwrap_err().to_string().contains("--generations applies to NSGA-II")
        );
        assert!(b(None, Some(0)).is_err());
    }

    /// Issue 18: a population of 10¹² aborted on its allocation; counts are bounded first.
    #[test]
    fn huge_counts_are_refused_before_allocating() {
        let p = |text: String| OptimizationProblem::from_toml_str(&text, Path::new("p.toml"));
        let huge = GOOD.replace("population = 8", "population = 1000000000000");
        let e = p(huge).unwrap_err();
        assert!(e.is_input_error() && e.to_string().contains("algorithm.population"), "{e}");
        let long = GOOD.replace("generations = 2", "generations = 9223372036854775807");
        let e = p(long).unwrap_err();
        assert!(e.to_string().contains("algorithm.generations"), "{e}");
        let ps = GOOD.replace("[[objective]]\nmetric = \"volume_m3\"\n", "").replace(
            "kind = \"nsga2\"",
            "kind = \"pattern-search\"\nmax_evaluations = 99999999999",
        );
        let e = p(ps).unwrap_err();
        assert!(e.to_string().contains("algorithm.max_evaluations"), "{e}");
        assert!(
            p(GOOD.replace("population = 8", &format!("population = {MAX_POPULATION}"))).is_ok()
        );
    }

    #[test]
    fn violation_and_margin_are_relative() {
        let c = Constraint { metric: "torque_max_Nm".into(), min: Some(3.0), max: None };
        assert!(c.violation(3.5).abs() < 1e-15);
        assert!((c.violation(1.5) - 0.5).abs() < 1e-12);
        assert!((c.margin(3.3) - 0.1).abs() < 1e-12);
        assert!(c.violation(f64::NAN).is_infinite());
    }
}

#[cfg(test)]
mod schema_tests {
    use super::*;

    /// Every key of the example problem files is in the schema, with its doc text.
    #[test]
    fn the_schema_covers_the_examples() {
        let schema = schema();
        assert_eq!(schema["required"], serde_json::json!(["spec", "algorithm"]));
        let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/../../examples/optimize");
        for entry in std::fs::read_dir(dir).unwrap() {
            let path = entry.unwrap().path();
            let table: toml::Table =
                toml::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
            for (key, value) in &table {
                let node = &schema["properties"][key];
                assert!(node["description"].is_string(), "{}: {key}", path.display());
                let items = node.get("items").unwrap_or(node);
                let inner: Vec<&toml::Table> = match value {
                    toml::Value::Table(t) if key != "set" => vec![t],
                    toml::Value::Array(a) => a.iter().filter_map(|v| v.as_table()).collect(),
                    _ => vec![],
                };
                for t in inner {
                    for k in t.keys() {
                        assert!(
                            items["properties"][k].is_object(),
                            "{}: {key}.{k}",
                            path.display()
                        );
                    }
                }
            }
        }
        assert_eq!(
            schema["properties"]["algorithm"]["properties"]["population"]["maximum"],
            MAX_POPULATION
        );
    }
}
