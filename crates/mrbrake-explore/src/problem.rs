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
//! [[variable]]
//! name = "materials.bobbin"                    # the material of a part: a categorical variable
//! values = ["aluminium", "pom"]                # library materials that suit the part
//! [[variable]]
//! name = "g"
//! value = "0.5mm"                              # fixed (as min = max): set, not varied
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
//! [haptic]                                     # settings of the haptic metrics, as
//! scenario = "press-withdraw"                  # `mrbrake haptic wall` (crate::metrics::haptic)
//! [algorithm]
//! kind = "nsga2"                               # or "surrogate", "pattern-search" (one objective)
//! population = 24
//! generations = 10
//! seed = 1
//! # pattern-search only: max_evaluations = 200, poll = "compass" | "random",
//! # start = "centre" | "base" (the base spec's values) | { R0 = "20mm", n = 2 } (per variable;
//! # the others at the centre of their bounds)
//! # surrogate only: max_evaluations = 200, initial_size = 10 x variables, batch = --jobs,
//! # acquisition = "ehvi", stall_iterations = 15, stall_tolerance = 1e-3
//! # any kind: hypervolume_reference = [..] (one value per objective, in its metric's unit)
//! ```
//!
//! `manufacturing_resolution = "0.01mm"` (the default; 0 writes the designs as evaluated) is the
//! resolution the front designs' lengths are rounded to when they are written (see
//! [`crate::front`]).
//!
//! Every field is checked when the file is read; an error names the file, the table and the field
//! and what is allowed. A fixed variable (`value = …`, `min = max`, or one material) joins the
//! fixed changes (`[set]`) and is not varied; so does a variable that `mrbrake optimize --set`
//! names ([`OptimizationProblem::apply_set`]). Counts are bounded before anything is sized by
//! them: `population` ≤ [`MAX_POPULATION`], `generations` and `max_evaluations` ≤
//! [`MAX_EVALUATIONS`] designs, the surrogate's `max_evaluations` ≤ [`MAX_SURROGATE_EVALUATIONS`]
//! (its models grow with the data).

use std::path::{Path, PathBuf};

use mrbrake_design::analysis::ElementOrder;
use mrbrake_design::mesh_build::MeshLevel;
use mrbrake_error::FieldError;
use mrbrake_store::MetricValue;
use mrbrake_units::{Dimension, parse};
use schemars::JsonSchema;
use serde::Deserialize;

use crate::ExploreError;
use crate::evaluate::{EvaluationSettings, METRICS, current_metric_name, metric_info};
use crate::variable::Variable;

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
    /// Settings of the haptic metrics (`mrbrake haptic wall`'s options and defaults).
    #[serde(default)]
    haptic: Option<crate::metrics::haptic::RawHaptic>,
    /// The optimiser and its budget.
    algorithm: RawAlgorithm,
    /// The resolution the lengths of the front designs are rounded to when they are written
    /// (`designs/front-NN.toml`, re-evaluated after rounding); 0 writes them as evaluated, in SI.
    #[serde(default)]
    #[schemars(schema_with = "resolution_quantity")]
    manufacturing_resolution: Option<RawQuantity>,
}

/// `manufacturing_resolution`: a length.
fn resolution_quantity(_: &mut schemars::SchemaGenerator) -> schemars::Schema {
    let mut schema = mrbrake_schema::quantity(Dimension::Length, "0.01mm");
    if let Some(object) = schema.as_object_mut() {
        object.insert("default".into(), serde_json::json!("0.01mm"));
    }
    schema
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
    /// A spec field (`drum.r0`), a thesis symbol (`R0`) or a material field (`materials.bobbin`).
    name: String,
    /// Lower bound (SI number or quantity with unit).
    #[serde(default)]
    min: Option<RawQuantity>,
    /// Upper bound (equal to `min`: the variable is fixed).
    #[serde(default)]
    max: Option<RawQuantity>,
    /// A material field's materials (library names that suit the part): a categorical variable.
    #[serde(default)]
    values: Option<Vec<String>>,
    /// A fixed value instead of a range: the field is set, not varied (a quantity, or a material).
    #[serde(default)]
    value: Option<RawQuantity>,
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
    /// `nsga2` (NSGA-II, one or more objectives), `surrogate` (Gaussian-process models and
    /// expected hypervolume improvement: far fewer evaluations) or `pattern-search` (one objective).
    #[schemars(schema_with = "algorithm_kind")]
    kind: String,
    /// NSGA-II: the population, an even number from 4.
    #[serde(default)]
    population: Option<usize>,
    /// NSGA-II: generations after the initial population.
    #[serde(default)]
    generations: Option<usize>,
    /// Pattern search and surrogate: the most designs evaluated (default 200).
    #[serde(default)]
    max_evaluations: Option<usize>,
    /// Seed of the random numbers (reproducible runs).
    #[serde(default)]
    seed: Option<u64>,
    /// Pattern search: `compass` or `random` polling.
    #[serde(default)]
    #[schemars(schema_with = "poll")]
    poll: Option<String>,
    /// Pattern search: start at the `centre` of the bounds, at the `base` spec's values, or at the
    /// values of a table `{ R0 = "20mm", n = 2 }` (variables not named start at their centre).
    #[serde(default)]
    #[schemars(schema_with = "start")]
    start: Option<RawStart>,
    /// Surrogate: designs of the initial space-filling (Sobol') plan; default 10 × variables, at
    /// least variables + 1.
    #[serde(default)]
    initial_size: Option<usize>,
    /// Surrogate: designs chosen per iteration, 1 to 1024; default `--jobs` (one per core), so
    /// every core analyses.
    #[serde(default)]
    batch: Option<usize>,
    /// Surrogate: the acquisition, `ehvi` (expected hypervolume improvement × probability of
    /// feasibility).
    #[serde(default)]
    #[schemars(schema_with = "acquisition")]
    acquisition: Option<String>,
    /// Surrogate: stop when the hypervolume grew by at most `stall_tolerance` over this many
    /// iterations (default 15; 0 never stops on a stall).
    #[serde(default)]
    stall_iterations: Option<usize>,
    /// Surrogate: the relative hypervolume growth that counts as a stall (default 1e-3).
    #[serde(default)]
    stall_tolerance: Option<f64>,
    /// Any kind: the hypervolume's reference point, one value per objective in its metric's unit
    /// (a number in SI or a quantity such as `"3Nm"`). Default: 10 % of the feasible designs'
    /// range beyond their worst value, fixed at the first batch with a feasible design.
    #[serde(default)]
    hypervolume_reference: Option<Vec<RawQuantity>>,
}

/// `algorithm.start`: a named start or a value per variable.
#[derive(Debug, Clone, Deserialize)]
#[serde(untagged)]
enum RawStart {
    /// `centre` or `base`.
    Named(String),
    /// Variable names to values.
    Values(toml::Table),
}

fn algorithm_kind(_: &mut schemars::SchemaGenerator) -> schemars::Schema {
    mrbrake_schema::choice(&["nsga2", "surrogate", "pattern-search"], None)
}

fn acquisition(_: &mut schemars::SchemaGenerator) -> schemars::Schema {
    mrbrake_schema::choice(&["ehvi"], Some("ehvi"))
}

fn poll(_: &mut schemars::SchemaGenerator) -> schemars::Schema {
    mrbrake_schema::choice(&["compass", "random"], Some("compass"))
}

fn start(_: &mut schemars::SchemaGenerator) -> schemars::Schema {
    let named = mrbrake_schema::choice(&["centre", "base"], Some("centre"));
    schemars::json_schema!({
        "anyOf": [
            named,
            {
                "type": "object",
                "description": "A start value per variable name (a number in SI or a quantity).",
                "additionalProperties": { "type": ["number", "string", "integer"] },
            },
        ],
        "default": "centre",
    })
}

/// The JSON Schema of an optimisation problem file (`mrbrake optimize`); counts bounded by
/// [`MAX_POPULATION`], [`MAX_EVALUATIONS`], [`MAX_BATCH`] and [`MAX_INITIAL_SIZE`], the limits the
/// reader checks.
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
    order::<crate::metrics::haptic::RawHaptic>(&mut schema, "haptic");
    let counts = [
        ("algorithm.population", Bounds::closed(4.0, MAX_POPULATION as f64)),
        ("algorithm.generations", Bounds::closed(0.0, MAX_EVALUATIONS as f64)),
        ("algorithm.max_evaluations", Bounds::closed(1.0, MAX_EVALUATIONS as f64)),
        ("algorithm.batch", Bounds::closed(1.0, MAX_BATCH as f64)),
        ("algorithm.initial_size", Bounds::closed(2.0, MAX_INITIAL_SIZE as f64)),
        ("algorithm.stall_tolerance", Bounds::closed(0.0, 1.0)),
    ];
    for (path, bounds) in counts {
        if let Some(node) = node_mut(&mut schema, path) {
            annotate(node, "", bounds);
        }
    }
    schema
}

/// A design variable with its bounds (SI), or a material variable with its materials.
#[derive(Debug, Clone, PartialEq)]
pub struct VariableBounds {
    /// The name (spec field, thesis symbol or material field).
    pub name: String,
    /// Lower bound (SI; 0, the first material's index, for a material variable).
    pub min: f64,
    /// Upper bound (SI; the last material's index for a material variable).
    pub max: f64,
    /// A material variable's materials (library names, the levels of a categorical variable);
    /// empty for a numeric variable.
    pub levels: Vec<String>,
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

    /// The normalised violation of a stored metric, which may be a bound beyond the analysed
    /// range (`mrbrake_store::MetricValue`). The rules:
    /// * a value: [`Self::violation`];
    /// * a bound that already satisfies the constraint satisfies it (0): `AtLeast(b)` with
    ///   `b ≥ min` and no `max`, `AtMost(b)` with `b ≤ max` and no `min`;
    /// * a bound that already violates it violates it at least as far as the bound does
    ///   (`AtLeast(b)` with `b > max`): the violation of `b`, a lower bound on the true one;
    /// * a bound that cannot decide (`AtLeast(b)` with `b < min`, or with a `max` above `b`):
    ///   infinite, as for a metric that could not be computed — widen the analysed range (the
    ///   `[response]` duration, the `[haptic]` duration, …) to decide it;
    /// * a metric that does not apply (a second direction of a one-way brake): satisfied (0).
    pub fn violation_of(&self, value: MetricValue) -> f64 {
        match self.bound_decides(value) {
            Decided::Value(v) => self.violation(v),
            Decided::Satisfied => 0.0,
            Decided::Undecided => f64::INFINITY,
        }
    }

    /// The signed margin of a stored metric (see [`Self::violation_of`]): of the value, or of the
    /// bound when the bound decides the constraint (then a bound on the margin); infinite for a
    /// metric that does not apply, `−∞` when the bound cannot decide.
    pub fn margin_of(&self, value: MetricValue) -> f64 {
        match (value, self.bound_decides(value)) {
            (MetricValue::NotApplicable, _) => f64::INFINITY,
            (_, Decided::Undecided) => f64::NEG_INFINITY,
            (v, _) => v.number().map_or(f64::INFINITY, |x| self.margin(x)),
        }
    }

    fn bound_decides(&self, value: MetricValue) -> Decided {
        match value {
            MetricValue::Value(v) => Decided::Value(v),
            MetricValue::NotApplicable => Decided::Satisfied,
            MetricValue::AtLeast(b) => {
                if self.max.is_some_and(|hi| b > hi) {
                    Decided::Value(b)
                } else if self.max.is_none() && self.min.is_none_or(|lo| b >= lo) {
                    Decided::Satisfied
                } else {
                    Decided::Undecided
                }
            }
            MetricValue::AtMost(b) => {
                if self.min.is_some_and(|lo| b < lo) {
                    Decided::Value(b)
                } else if self.min.is_none() && self.max.is_none_or(|hi| b <= hi) {
                    Decided::Satisfied
                } else {
                    Decided::Undecided
                }
            }
        }
    }
}

/// What a stored metric says about a constraint ([`Constraint::violation_of`]).
enum Decided {
    /// Judge this number (a value, or a bound already beyond a limit).
    Value(f64),
    /// The bound satisfies the constraint, or the metric does not apply.
    Satisfied,
    /// The bound cannot decide.
    Undecided,
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
    /// Surrogate-assisted (Bayesian) optimisation, [`mrbrake_optim::surrogate`]: Gaussian-process
    /// models of every objective and constraint choose each batch by expected hypervolume
    /// improvement.
    Surrogate(SurrogateSettings),
    /// Pattern search (one objective).
    PatternSearch {
        /// Evaluation budget.
        max_evaluations: usize,
        /// Seed of the random poll bases (no effect with compass polls).
        seed: u64,
        /// Poll with a fresh random orthogonal basis each iteration instead of the coordinate
        /// directions: slower, but it can follow constraints oblique to the axes.
        random_poll: bool,
        /// Where the search starts.
        start: Start,
    },
}

/// The settings of a surrogate-assisted run (`kind = "surrogate"`), checked when the file is read.
#[derive(Debug, Clone, PartialEq)]
pub struct SurrogateSettings {
    /// Budget: designs evaluated by the algorithm, those of an earlier run on the same store
    /// included (default 200).
    pub max_evaluations: usize,
    /// Designs of the initial space-filling plan (`None`: 10 × variables).
    pub initial_size: Option<usize>,
    /// Designs per iteration (`None`: the run's `--jobs`, one per core by default).
    pub batch: Option<usize>,
    /// The acquisition.
    pub acquisition: mrbrake_optim::surrogate::Acquisition,
    /// Stall rule: iterations without relative hypervolume growth above `stall_tolerance` (0: off).
    pub stall_iterations: usize,
    /// Stall rule: the relative growth that counts as none.
    pub stall_tolerance: f64,
    /// Seed of every random choice.
    pub seed: u64,
}

/// Where a pattern search starts.
#[derive(Debug, Clone, PartialEq)]
pub enum Start {
    /// The centre of the bounds (integers rounded).
    Centre,
    /// The base spec's values, clamped into the bounds.
    Base,
    /// A value per variable, in the problem's order (SI); `None` for the centre of its bounds.
    Values(Vec<Option<f64>>),
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
    /// The hypervolume's reference point given in the file (`algorithm.hypervolume_reference`),
    /// in minimised units (a maximised objective's value negated); `None`: the run fixes it
    /// ([`crate::hypervolume`]).
    pub hypervolume_reference: Option<Vec<f64>>,
    /// The resolution (m) the lengths of the written front designs are rounded to; 0: written as
    /// evaluated ([`crate::front`]).
    pub manufacturing_resolution: f64,
    /// Notes for the user that do not stop the run: a metric named by its legacy name (see
    /// [`crate::evaluate::LEGACY_METRIC_NAMES`]), with its current name; a fixed variable.
    pub notes: Vec<String>,
}

impl OptimizationProblem {
    /// Reads and checks a problem file.
    pub fn from_path(path: &Path) -> Result<Self, ExploreError> {
        let text = mrbrake_error::read::text(path, mrbrake_error::read::SETTINGS).map_err(|e| {
            ExploreError::input("", format!("cannot read the problem file: {e}"))
                .in_file(&path.display().to_string())
        })?;
        Self::from_toml_str(&text, path)
    }

    /// Parses problem-file text; `path` locates the spec and names the file in messages.
    pub fn from_toml_str(text: &str, path: &Path) -> Result<Self, ExploreError> {
        let origin = path.display().to_string();
        let bad = |e: ExploreError| e.in_file(&origin);
        let raw: RawProblem =
            toml::from_str(text).map_err(|e| bad(ExploreError::input("", e.to_string())))?;
        let folder = path.parent().unwrap_or_else(|| Path::new("."));
        let mut settings = settings_of(&raw).map_err(bad)?;
        let (variables, fixed) = variables_of(&raw.variables).map_err(bad)?;
        let constraints = constraints_of(&raw.constraints).map_err(bad)?;
        let objectives = objectives_of(&raw.objectives).map_err(bad)?;
        settings.study = crate::metrics::settings::study_of(
            &raw.record,
            &raw.response,
            &raw.thermal,
            &raw.haptic,
            &constraints,
            &objectives,
        )
        // The metric settings' readers name the key in their text.
        .map_err(|e| bad(ExploreError::input("", e)))?;
        let mut notes = legacy_name_notes(&raw, &origin);
        notes.extend(fixed.iter().map(|(name, value)| {
            format!("{origin}: variable '{name}' is fixed at {value}: set, not varied")
        }));
        let algorithm = algorithm_of(&raw.algorithm, &objectives, &variables).map_err(bad)?;
        check_categorical_search(&variables, &algorithm).map_err(bad)?;
        let hypervolume_reference =
            hypervolume_reference_of(&raw.algorithm, &objectives).map_err(bad)?;
        let manufacturing_resolution =
            resolution_of(raw.manufacturing_resolution.as_ref()).map_err(bad)?;
        let mut overrides = overrides_of(&raw.set);
        overrides.extend(fixed);
        Ok(Self {
            path: path.to_path_buf(),
            spec_path: folder.join(&raw.spec),
            overrides,
            reference: raw.reference.unwrap_or(true),
            settings,
            variables,
            constraints,
            objectives,
            algorithm,
            hypervolume_reference,
            manufacturing_resolution,
            notes,
        })
    }
}

impl OptimizationProblem {
    /// Applies fixed changes given with the run, not in the file (`mrbrake optimize --set
    /// PATH=VALUE`, the Python package's `optimize(..., set=...)`; [`crate::variable::parse_sets`]
    /// reads the arguments): each overrides the base spec after the file's `[set]`, as `mrbrake
    /// sweep --set` does, and a variable of the problem naming the same field (by path or
    /// symbol) is fixed at that value instead of varied, with a note. At least one variable must
    /// remain.
    pub fn apply_set(&mut self, sets: &[(String, String)]) -> Result<(), ExploreError> {
        // The base spec's configuration decides what a symbol names; a spec that cannot be read
        // is reported by the run itself, and names are then compared as written.
        let is_drum = mrbrake_error::read::text(&self.spec_path, mrbrake_error::read::SETTINGS)
            .ok()
            .and_then(|text| mrbrake_design::spec::BrakeSpec::from_toml_str(&text, "spec").ok())
            .map(|spec| spec.configuration.is_drum());
        let path_of = |name: &str| {
            is_drum.and_then(|drum| crate::variable::resolve(name, drum).ok()).map(|v| v.path())
        };
        for (path, value) in sets {
            let target = path_of(path);
            let same = |v: &VariableBounds| {
                v.name.trim() == path.trim() || (target.is_some() && path_of(&v.name) == target)
            };
            if let Some(index) = self.variables.iter().position(same) {
                let fixed = self.variables.remove(index);
                self.notes.push(format!(
                    "--set {path}={value}: variable '{}' is fixed at {value}: set, not varied",
                    fixed.name
                ));
            }
            self.overrides.push((path.clone(), value.clone()));
        }
        if self.variables.is_empty() {
            let e = ExploreError::input(
                "set",
                "fixes every variable of the problem: nothing to optimise",
            );
            return Err(e.in_file(&self.path.display().to_string()));
        }
        Ok(())
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

// The readers of each part of the file return what is wrong, naming the key (`algorithm.poll`,
// `variable[2].min`); the caller locates it in the file.

/// The error of a variable, argument or metric (its field named as written, `g`) moved to the
/// key of the problem file that gave it (`variable[1].min`), keeping the name in the message.
fn at_key(e: ExploreError, key: &str) -> ExploreError {
    e.map_field(|mut f| {
        if !f.field.is_empty() && f.field != key {
            f.message = format!("'{}': {}", f.field, f.message);
        }
        f.field = key.to_string();
        f
    })
}

/// Mesh level, element order and speed over the defaults.
fn settings_of(raw: &RawProblem) -> Result<EvaluationSettings, ExploreError> {
    let mut settings = EvaluationSettings::default();
    if let Some(mesh) = &raw.mesh {
        settings.mesh = MeshLevel::parse(mesh)?;
    }
    if let Some(degree) = raw.order {
        settings.order = ElementOrder::try_from(degree)?;
    }
    if let Some(speed) = &raw.speed {
        settings.speed_rad_s = parse(speed, Dimension::AngularVelocity)
            .map_err(|e| ExploreError::input("speed", e.to_string()))?;
    }
    settings.check()?;
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

/// The variables with their bounds in SI, read with each variable's own unit, and the fixed ones
/// as `(name, value)` overrides.
fn variables_of(raw: &[RawVariable]) -> Result<(Vec<VariableBounds>, Overrides), ExploreError> {
    if raw.is_empty() {
        return Err(ExploreError::input(
            "variable",
            "no [[variable]]: give at least one design variable",
        ));
    }
    let (mut variables, mut fixed) = (Vec::new(), Vec::new());
    for (i, v) in raw.iter().enumerate() {
        let key = format!("variable[{}]", i + 1);
        // Bounds read with the variable's own unit; the symbol resolves against the spec
        // later, so read them with the field the name denotes for either configuration.
        let variable = crate::variable::resolve(&v.name, true)
            .or_else(|_| crate::variable::resolve(&v.name, false))
            .map_err(|e| at_key(e, &format!("{key}.name")))?;
        match variable_of(v, &variable).map_err(|e| e.under(&key))? {
            Read::Varied(bounds) => variables.push(bounds),
            Read::Fixed(value) => fixed.push((v.name.clone(), value)),
        }
    }
    if variables.is_empty() {
        return Err(ExploreError::input(
            "variable",
            format!(
                "every [[variable]] is fixed ({}): nothing to optimise; vary at least one, or \
                 analyse the design with mrbrake analyze",
                fixed.iter().map(|(n, _)| n.as_str()).collect::<Vec<_>>().join(", ")
            ),
        ));
    }
    Ok((variables, fixed))
}

/// Fixed changes `(PATH, VALUE)` to the base spec, in order.
type Overrides = Vec<(String, String)>;

/// A `[[variable]]` as read: varied within bounds, or fixed at a value (the override's text).
enum Read {
    Varied(VariableBounds),
    Fixed(String),
}

/// One `[[variable]]` of the resolved `variable`: `min`/`max` (equal: fixed) or `value` for a
/// numeric field, `values` (one: fixed) or `value` for a material; the error names the key
/// (`min`, or none for the whole table).
fn variable_of(v: &RawVariable, variable: &Variable) -> Result<Read, ExploreError> {
    let text_of = |q: &RawQuantity| match q {
        RawQuantity::Number(x) => x.to_string(),
        RawQuantity::Integer(i) => i.to_string(),
        RawQuantity::Text(t) => t.clone(),
    };
    let given = (v.min.is_some() || v.max.is_some(), v.values.is_some(), v.value.is_some());
    match given {
        (false, false, true) => {
            let value = text_of(v.value.as_ref().expect("matched Some"));
            check_fixed(variable, &value).map_err(|e| at_key(e, "value"))?;
            return Ok(Read::Fixed(value));
        }
        (false, true, false) if variable.is_categorical() => {}
        (true, false, false) if !variable.is_categorical() => {}
        _ if variable.is_categorical() => {
            return Err(ExploreError::input(
                "",
                "a material takes values = [\"…\", …] (its materials) or value",
            ));
        }
        _ if v.values.is_some() => {
            return Err(ExploreError::input(
                "values",
                format!(
                    "a list of values is for the material of a part ({}); '{}' is a number: give \
                     min and max, or value (a fixed variable)",
                    material_paths(),
                    variable.path()
                ),
            ));
        }
        _ => return Err(ExploreError::input("", "give min and max, or value (a fixed variable)")),
    }
    if let Some(levels) = &v.values {
        let variable = variable.clone().with_levels(levels).map_err(|e| at_key(e, "values"))?;
        return Ok(match variable.levels() {
            [only] => Read::Fixed(only.clone()),
            levels => Read::Varied(VariableBounds {
                name: v.name.clone(),
                min: 0.0,
                max: (levels.len() - 1) as f64,
                levels: levels.to_vec(),
            }),
        });
    }
    let read = |q: &Option<RawQuantity>, which: &str| -> Result<f64, ExploreError> {
        let q = q.as_ref().ok_or_else(|| {
            ExploreError::input("", format!("give both min and max (no {which})"))
        })?;
        match q {
            RawQuantity::Number(x) => Ok(*x),
            RawQuantity::Integer(i) => Ok(*i as f64),
            RawQuantity::Text(t) => variable.parse_value(t).map_err(|e| at_key(e, which)),
        }
    };
    let (min, max) = (read(&v.min, "min")?, read(&v.max, "max")?);
    if !(min.is_finite() && max.is_finite() && min <= max) {
        let e =
            FieldError::new("max", "needs min ≤ max").with_value(format!("min {min}, max {max}"));
        return Err(e.into());
    }
    if (max - min).abs() <= 0.0 {
        return Ok(Read::Fixed(text_of(v.min.as_ref().expect("read above"))));
    }
    Ok(Read::Varied(VariableBounds { name: v.name.clone(), min, max, levels: Vec::new() }))
}

/// The material fields a categorical variable may name, for messages.
fn material_paths() -> String {
    mrbrake_design::spec::MATERIAL_FIELDS.iter().map(|f| f.path).collect::<Vec<_>>().join(", ")
}

/// Checks a fixed value: a material that suits the part, or a number the field reads.
fn check_fixed(variable: &Variable, value: &str) -> Result<(), ExploreError> {
    if variable.is_categorical() {
        variable.clone().with_levels(&[value.to_string()]).map(|_| ())
    } else {
        variable.parse_value(value).map(|_| ())
    }
}

/// The constraints, each with a min, a max or both, in the metric's unit.
fn constraints_of(raw: &[RawConstraint]) -> Result<Vec<Constraint>, ExploreError> {
    let mut constraints = Vec::new();
    for (i, c) in raw.iter().enumerate() {
        let key = format!("constraint[{}]", i + 1);
        let info = known_metric(&c.metric).map_err(|e| e.under(&key))?;
        let read = |q: &Option<RawQuantity>, which: &str| -> Result<Option<f64>, ExploreError> {
            q.as_ref()
                .map(|q| {
                    metric_value(q, info.unit)
                        .map_err(|e| e.under(&format!("{key}.{which}")).for_metric(info.name))
                })
                .transpose()
        };
        let (min, max) = (read(&c.min, "min")?, read(&c.max, "max")?);
        if min.is_none() && max.is_none() {
            let e = ExploreError::input(&key, "give min, max or both");
            return Err(e.for_metric(info.name));
        }
        if let (Some(lo), Some(hi)) = (min, max) {
            if lo > hi {
                let e = FieldError::new(format!("{key}.min"), "above max")
                    .with_value(lo)
                    .with_allowed(format!("<= max = {hi}"));
                return Err(ExploreError::from(e).for_metric(info.name));
            }
        }
        constraints.push(Constraint { metric: info.name.to_string(), min, max });
    }
    Ok(constraints)
}

/// At least one objective, each minimised or maximised.
fn objectives_of(raw: &[RawObjective]) -> Result<Vec<Objective>, ExploreError> {
    if raw.is_empty() {
        return Err(ExploreError::input(
            "objective",
            "no [[objective]]: give one (pattern search) or more (nsga2)",
        ));
    }
    let mut objectives = Vec::new();
    for (i, o) in raw.iter().enumerate() {
        let key = format!("objective[{}]", i + 1);
        let info = known_metric(&o.metric).map_err(|e| e.under(&key))?;
        let goal = match o.goal.trim().to_ascii_lowercase().as_str() {
            "minimize" | "minimise" | "min" => Goal::Minimize,
            "maximize" | "maximise" | "max" => Goal::Maximize,
            other => {
                let e = FieldError::out_of_range(
                    format!("{key}.goal"),
                    format!("'{other}'"),
                    "minimize or maximize",
                );
                return Err(ExploreError::from(e).for_metric(info.name));
            }
        };
        objectives.push(Objective { metric: info.name.to_string(), goal });
    }
    Ok(objectives)
}

/// A budget override from the command line (`mrbrake optimize --generations N
/// --max-evaluations M --seed S`), for a quick run of a problem file without editing it.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct BudgetOverride {
    /// NSGA-II generations after the initial population.
    pub generations: Option<usize>,
    /// The most designs evaluated: the budget of pattern search and of the surrogate; for NSGA-II,
    /// the generations are cut to the most whose `population × (generations + 1)` designs fit.
    pub max_evaluations: Option<usize>,
    /// The seed, overriding `algorithm.seed` (e.g. repeated runs of a benchmark).
    pub seed: Option<u64>,
}

impl Algorithm {
    /// The algorithm with `budget` applied; an override the algorithm has no use for
    /// (`--generations` for pattern search) or out of range is an input error naming the flag.
    pub fn with_budget(&self, budget: BudgetOverride) -> Result<Algorithm, ExploreError> {
        let not_nsga2 = |kind: &str, max_evaluations: usize| {
            if budget.generations.is_some() {
                let e = FieldError::new(
                    "generations",
                    format!(
                        "applies to NSGA-II; {kind} takes a number of evaluations (max_evaluations)"
                    ),
                );
                return Err(ExploreError::from(e));
            }
            let max = budget.max_evaluations.unwrap_or(max_evaluations);
            let limit =
                if kind == "surrogate" { MAX_SURROGATE_EVALUATIONS } else { MAX_EVALUATIONS };
            if max == 0 || max > limit {
                let e = FieldError::out_of_range("max_evaluations", max, format!("1 to {limit}"));
                return Err(e.into());
            }
            Ok(max)
        };
        match self.clone() {
            Algorithm::Nsga2 { population, mut generations, seed } => {
                if let Some(g) = budget.generations {
                    generations = g;
                }
                if let Some(max) = budget.max_evaluations {
                    if max < population {
                        let e = FieldError::new(
                            "max_evaluations",
                            format!(
                                "less than one generation of NSGA-II (population {population})"
                            ),
                        )
                        .with_value(max)
                        .with_allowed(format!(">= {population}"));
                        return Err(e.into());
                    }
                    generations = generations.min(max / population - 1);
                }
                let designs = generations.checked_add(1).and_then(|g| g.checked_mul(population));
                if designs.is_none_or(|d| d > MAX_EVALUATIONS) {
                    return Err(too_many_generations("generations", generations, population).into());
                }
                Ok(Algorithm::Nsga2 { population, generations, seed: budget.seed.unwrap_or(seed) })
            }
            Algorithm::Surrogate(mut settings) => {
                settings.max_evaluations = not_nsga2("surrogate", settings.max_evaluations)?;
                settings.seed = budget.seed.unwrap_or(settings.seed);
                Ok(Algorithm::Surrogate(settings))
            }
            Algorithm::PatternSearch { max_evaluations, seed, random_poll, start } => {
                let max_evaluations = not_nsga2("pattern search", max_evaluations)?;
                let seed = budget.seed.unwrap_or(seed);
                Ok(Algorithm::PatternSearch { max_evaluations, seed, random_poll, start })
            }
        }
    }

    /// The algorithm's key in problem files (`nsga2`, `surrogate`, `pattern-search`).
    pub fn kind(&self) -> &'static str {
        match self {
            Algorithm::Nsga2 { .. } => "nsga2",
            Algorithm::Surrogate(_) => "surrogate",
            Algorithm::PatternSearch { .. } => "pattern-search",
        }
    }
}

/// The error of `field` (`generations`, `algorithm.generations`) when `generations` of
/// `population` are more than [`MAX_EVALUATIONS`] designs.
fn too_many_generations(field: &str, generations: usize, population: usize) -> FieldError {
    FieldError::new(field, format!("generations of {population} designs are too many; use fewer"))
        .with_value(generations)
        .with_allowed(format!("(generations + 1) × {population} <= {MAX_EVALUATIONS} designs"))
}

/// The largest NSGA-II population (each generation holds and sorts it in memory).
pub const MAX_POPULATION: usize = 100_000;

/// The most designs one optimisation may evaluate (`population × (generations + 1)` or
/// `max_evaluations`); every design is a finite-element analysis, so this is far beyond any
/// study that can finish, and it keeps every count the optimisers allocate from sane.
pub const MAX_EVALUATIONS: usize = 10_000_000;

/// The most designs of a surrogate-assisted run: its models train on at most 300 designs
/// ([`mrbrake_optim::surrogate::SurrogateOptions::max_training`]) but it keeps every design and
/// compares each proposal with all of them, and its point is to need few.
pub const MAX_SURROGATE_EVALUATIONS: usize = 100_000;

/// The largest initial plan of a surrogate-assisted run (at least variables + 1 designs).
pub const MAX_INITIAL_SIZE: usize = 100_000;

/// The most surrogate designs per iteration ([`mrbrake_optim::surrogate::SurrogateOptions::batch`]).
pub const MAX_BATCH: usize = 1024;

/// The keys of `[algorithm]` each kind reads (besides `kind`, `seed` and `hypervolume_reference`).
const KEYS: [(&str, &[&str]); 3] = [
    ("nsga2", &["population", "generations"]),
    (
        "surrogate",
        &[
            "max_evaluations",
            "initial_size",
            "batch",
            "acquisition",
            "stall_iterations",
            "stall_tolerance",
        ],
    ),
    ("pattern-search", &["max_evaluations", "poll", "start"]),
];

/// The `[algorithm]` table, for a problem with these objectives and variables.
fn algorithm_of(
    a: &RawAlgorithm,
    objectives: &[Objective],
    variables: &[VariableBounds],
) -> Result<Algorithm, ExploreError> {
    let seed = a.seed.unwrap_or(1);
    let kind = match a.kind.trim().to_ascii_lowercase().as_str() {
        "nsga2" | "nsga-ii" => "nsga2",
        "surrogate" | "bayesian" => "surrogate",
        "pattern-search" | "pattern_search" => "pattern-search",
        other => {
            let allowed = "nsga2, surrogate or pattern-search";
            return Err(
                FieldError::out_of_range("algorithm.kind", format!("'{other}'"), allowed).into()
            );
        }
    };
    check_keys_of(a, kind)?;
    match kind {
        "nsga2" => nsga2_of(a, seed),
        "surrogate" => surrogate_of(a, variables.len(), seed),
        _ => pattern_search_of(a, objectives.len(), variables, seed),
    }
}

/// Pattern search polls a variable in ordered steps, which a material's unordered levels do not
/// have: a problem that varies a material needs NSGA-II (random resetting of the level).
fn check_categorical_search(
    variables: &[VariableBounds],
    algorithm: &Algorithm,
) -> Result<(), ExploreError> {
    let material = variables.iter().find(|v| !v.levels.is_empty());
    match (material, algorithm) {
        (Some(v), Algorithm::PatternSearch { .. }) => Err(ExploreError::input(
            "algorithm.kind",
            format!(
                "pattern-search steps each variable along an order, and the materials of '{}' \
                 ({}) have none; use nsga2, or fix the material (value = \"…\")",
                v.name,
                v.levels.join(", ")
            ),
        )),
        _ => Ok(()),
    }
}

/// Refuses a key of another kind of algorithm that would otherwise be silently ignored: a
/// surrogate key (`batch`) with another kind, any other kind's key with the surrogate. (NSGA-II and
/// pattern search keep ignoring each other's keys, as files written before the surrogate expect.)
fn check_keys_of(a: &RawAlgorithm, kind: &str) -> Result<(), ExploreError> {
    let given = [
        ("population", a.population.is_some()),
        ("generations", a.generations.is_some()),
        ("max_evaluations", a.max_evaluations.is_some()),
        ("poll", a.poll.is_some()),
        ("start", a.start.is_some()),
        ("initial_size", a.initial_size.is_some()),
        ("batch", a.batch.is_some()),
        ("acquisition", a.acquisition.is_some()),
        ("stall_iterations", a.stall_iterations.is_some()),
        ("stall_tolerance", a.stall_tolerance.is_some()),
    ];
    let keys_of =
        |k: &str| KEYS.iter().find(|(name, _)| *name == k).map_or(&[][..], |(_, keys)| *keys);
    let surrogate = keys_of("surrogate");
    let foreign = |key: &&str| {
        if kind == "surrogate" {
            !surrogate.contains(key)
        } else {
            !keys_of(kind).contains(key) && surrogate.contains(key)
        }
    };
    let Some((key, _)) = given.iter().find(|(key, set)| *set && foreign(key)) else {
        return Ok(());
    };
    let owners: Vec<String> = KEYS
        .iter()
        .filter(|(_, keys)| keys.contains(key))
        .map(|(k, _)| format!("\"{k}\""))
        .collect();
    Err(ExploreError::input(
        format!("algorithm.{key}"),
        format!("applies to kind = {}, not to kind = \"{kind}\"", owners.join(" or ")),
    ))
}

fn nsga2_of(a: &RawAlgorithm, seed: u64) -> Result<Algorithm, ExploreError> {
    let population = a.population.unwrap_or(24);
    if population < 4 || population % 2 == 1 || population > MAX_POPULATION {
        let allowed = format!("an even number from 4 to {MAX_POPULATION}");
        return Err(FieldError::out_of_range("algorithm.population", population, allowed).into());
    }
    let generations = a.generations.unwrap_or(10);
    let designs = generations.checked_add(1).and_then(|g| g.checked_mul(population));
    if designs.is_none_or(|d| d > MAX_EVALUATIONS) {
        return Err(too_many_generations("algorithm.generations", generations, population).into());
    }
    Ok(Algorithm::Nsga2 { population, generations, seed })
}

/// The surrogate's settings, each checked against the range
/// [`mrbrake_optim::surrogate::SurrogateOptions::validate`] allows (which checks them again).
fn surrogate_of(a: &RawAlgorithm, variables: usize, seed: u64) -> Result<Algorithm, ExploreError> {
    let out_of_range = |key: &str, value: &dyn std::fmt::Display, allowed: String| {
        Err(FieldError::out_of_range(format!("algorithm.{key}"), value, allowed).into())
    };
    let max_evaluations = a.max_evaluations.unwrap_or(200);
    if max_evaluations == 0 || max_evaluations > MAX_SURROGATE_EVALUATIONS {
        return out_of_range(
            "max_evaluations",
            &max_evaluations,
            format!("1 to {MAX_SURROGATE_EVALUATIONS}"),
        );
    }
    if let Some(n) = a.initial_size {
        if n <= variables || n > MAX_INITIAL_SIZE {
            return out_of_range(
                "initial_size",
                &n,
                format!("{} (variables + 1) to {MAX_INITIAL_SIZE} designs", variables + 1),
            );
        }
    }
    if let Some(b) = a.batch {
        if b == 0 || b > MAX_BATCH {
            return out_of_range("batch", &b, format!("1 to {MAX_BATCH} designs per iteration"));
        }
    }
    let acquisition = match a.acquisition.as_deref() {
        None => mrbrake_optim::surrogate::Acquisition::default(),
        Some(text) => text
            .parse()
            .map_err(|e| ExploreError::input("algorithm.acquisition", format!("{e}")))?,
    };
    let stall_tolerance = a.stall_tolerance.unwrap_or(1e-3);
    if !(stall_tolerance.is_finite() && (0.0..=1.0).contains(&stall_tolerance)) {
        return out_of_range(
            "stall_tolerance",
            &stall_tolerance,
            "a relative growth from 0 to 1".into(),
        );
    }
    Ok(Algorithm::Surrogate(SurrogateSettings {
        max_evaluations,
        initial_size: a.initial_size,
        batch: a.batch,
        acquisition,
        stall_iterations: a.stall_iterations.unwrap_or(15),
        stall_tolerance,
        seed,
    }))
}

fn pattern_search_of(
    a: &RawAlgorithm,
    objectives: usize,
    variables: &[VariableBounds],
    seed: u64,
) -> Result<Algorithm, ExploreError> {
    if objectives != 1 {
        return Err(ExploreError::input(
            "algorithm.kind",
            format!(
                "pattern-search optimises one objective; {objectives} are given (use nsga2 or \
                 surrogate for several)"
            ),
        ));
    }
    let random_poll = match a.poll.as_deref().map(str::trim) {
        None | Some("compass") => false,
        Some("random" | "random-orthogonal") => true,
        Some(other) => {
            let e = FieldError::out_of_range(
                "algorithm.poll",
                format!("'{other}'"),
                "compass or random",
            );
            return Err(e.into());
        }
    };
    let start = start_of(a.start.as_ref(), variables)?;
    let max_evaluations = a.max_evaluations.unwrap_or(200);
    if max_evaluations == 0 || max_evaluations > MAX_EVALUATIONS {
        let allowed = format!("1 to {MAX_EVALUATIONS}");
        let e = FieldError::out_of_range("algorithm.max_evaluations", max_evaluations, allowed);
        return Err(e.into());
    }
    Ok(Algorithm::PatternSearch { max_evaluations, seed, random_poll, start })
}

/// `algorithm.start`: `centre`, `base`, or a table of values by variable name (each inside its
/// bounds, read with the variable's unit).
fn start_of(raw: Option<&RawStart>, variables: &[VariableBounds]) -> Result<Start, ExploreError> {
    let table = match raw {
        None => return Ok(Start::Centre),
        Some(RawStart::Named(name)) => {
            return match name.trim() {
                "centre" | "center" => Ok(Start::Centre),
                "base" => Ok(Start::Base),
                other => Err(FieldError::out_of_range(
                    "algorithm.start",
                    format!("'{other}'"),
                    "centre, base or a table of values by variable name",
                )
                .into()),
            };
        }
        Some(RawStart::Values(table)) => table,
    };
    let mut values = vec![None; variables.len()];
    for (name, value) in table {
        let key = format!("algorithm.start.{name}");
        let index =
            variables.iter().position(|v| v.name.trim() == name.trim()).ok_or_else(|| {
                let names: Vec<&str> = variables.iter().map(|v| v.name.as_str()).collect();
                FieldError::new(&key, "not a variable of this problem")
                    .with_allowed(names.join(", "))
            })?;
        let variable = &variables[index];
        let field = crate::variable::resolve(name, true)
            .or_else(|_| crate::variable::resolve(name, false))
            .map_err(|e| at_key(e, &key))?;
        let si = match value {
            toml::Value::Float(x) => *x,
            toml::Value::Integer(i) => *i as f64,
            toml::Value::String(text) => field.parse_value(text).map_err(|e| at_key(e, &key))?,
            other => {
                let e = FieldError::new(&key, "not a number or a quantity").with_value(other);
                return Err(e.into());
            }
        };
        if field.quantity() == Some(crate::variable::Quantity::Integer)
            && (si - si.round()).abs() > 1e-9
        {
            let e = FieldError::new(&key, "not a whole number (this field counts something)")
                .with_value(si);
            return Err(e.into());
        }
        if !(si.is_finite() && (variable.min..=variable.max).contains(&si)) {
            let e = FieldError::new(&key, "outside the variable's bounds")
                .with_value(field.display_value(si))
                .with_allowed(format!(
                    "{} to {}",
                    field.display_value(variable.min),
                    field.display_value(variable.max)
                ));
            return Err(e.into());
        }
        values[index] = Some(si);
    }
    Ok(Start::Values(values))
}

/// `algorithm.hypervolume_reference`, one value per objective in its metric's unit, returned in
/// minimised units (a maximised objective's value negated).
fn hypervolume_reference_of(
    a: &RawAlgorithm,
    objectives: &[Objective],
) -> Result<Option<Vec<f64>>, ExploreError> {
    let Some(raw) = &a.hypervolume_reference else { return Ok(None) };
    if raw.len() != objectives.len() {
        let e = FieldError::new(
            "algorithm.hypervolume_reference",
            "one value per objective, in the order of the [[objective]] tables",
        )
        .with_value(format!("{} values", raw.len()))
        .with_allowed(format!("{} values", objectives.len()));
        return Err(e.into());
    }
    let mut reference = Vec::with_capacity(raw.len());
    for (k, (q, objective)) in raw.iter().zip(objectives).enumerate() {
        let key = format!("algorithm.hypervolume_reference[{}]", k + 1);
        let unit = metric_info(&objective.metric).map_or("", |m| m.unit);
        let value =
            metric_value(q, unit).map_err(|e| e.under(&key).for_metric(&objective.metric))?;
        if !value.is_finite() {
            let e = FieldError::out_of_range(&key, value, "finite");
            return Err(ExploreError::from(e).for_metric(&objective.metric));
        }
        reference.push(match objective.goal {
            Goal::Minimize => value,
            Goal::Maximize => -value,
        });
    }
    Ok(Some(reference))
}

/// The largest manufacturing resolution (1 mm): a coarser rounding would move a design far from
/// the one the optimiser evaluated.
pub const MAX_MANUFACTURING_RESOLUTION: f64 = 1e-3;

/// `manufacturing_resolution`: a length from 0 to [`MAX_MANUFACTURING_RESOLUTION`] (default
/// 0.01 mm).
fn resolution_of(raw: Option<&RawQuantity>) -> Result<f64, ExploreError> {
    let Some(q) = raw else { return Ok(DEFAULT_MANUFACTURING_RESOLUTION) };
    let value = match q {
        RawQuantity::Number(x) => *x,
        RawQuantity::Integer(i) => *i as f64,
        RawQuantity::Text(text) => parse(text, Dimension::Length)
            .map_err(|e| ExploreError::input("manufacturing_resolution", e.to_string()))?,
    };
    if !(value.is_finite() && (0.0..=MAX_MANUFACTURING_RESOLUTION).contains(&value)) {
        let e = FieldError::out_of_range(
            "manufacturing_resolution",
            format!("{value} m"),
            "0 (no rounding) to 1mm",
        );
        return Err(e.into());
    }
    Ok(value)
}

/// The default manufacturing resolution of the written front designs: 0.01 mm.
pub const DEFAULT_MANUFACTURING_RESOLUTION: f64 = 1e-5;

/// The metric called `name` (its current name or a legacy one); an error names the field
/// `metric`, the name and the metrics there are.
pub fn known_metric(name: &str) -> Result<&'static crate::evaluate::MetricInfo, ExploreError> {
    metric_info(current_metric_name(name.trim()).0).ok_or_else(|| {
        FieldError::new("metric", "unknown metric")
            .with_value(format!("'{name}'"))
            .with_allowed(METRICS.iter().map(|m| m.name).collect::<Vec<_>>().join(", "))
            .into()
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
                        FieldError::new("", format!("give a bare number in {unit} for this metric"))
                            .with_value(format!("'{text}'"))
                            .into()
                    });
                }
            };
            parse(text, dimension).map_err(|e| ExploreError::input("", e.to_string()))
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
        assert!(text.contains("p.toml: constraint[1].metric: unknown metric"), "{text}");
        assert!(text.contains("got 'torque_maximum'"), "{text}");
        assert!(e.is_input_error());
        let odd = GOOD.replace("population = 8", "population = 7");
        let text = OptimizationProblem::from_toml_str(&odd, Path::new("p.toml")).unwrap_err();
        assert!(text.to_string().contains("algorithm.population"), "{text}");
        let ps = GOOD.replace("kind = \"nsga2\"", "kind = \"pattern-search\"");
        assert!(OptimizationProblem::from_toml_str(&ps, Path::new("p.toml")).is_err());
        let cubic = GOOD.replace("mesh = \"coarse\"", "mesh = \"coarse\"\norder = 3");
        let text = OptimizationProblem::from_toml_str(&cubic, Path::new("p.toml")).unwrap_err();
        assert!(text.to_string().contains("p.toml: order: got 3; allowed: 1 or 2"), "{text}");
        let ps_zero = ps
            .replace("[[objective]]\nmetric = \"volume_m3\"\n", "")
            .replace("kind = \"pattern-search\"", "kind = \"pattern-search\"\nmax_evaluations = 0");
        let text = OptimizationProblem::from_toml_str(&ps_zero, Path::new("p.toml")).unwrap_err();
        assert!(text.to_string().contains("algorithm.max_evaluations: got 0"), "{text}");
        let quadratic = GOOD.replace("mesh = \"coarse\"", "mesh = \"coarse\"\norder = 2");
        let p = OptimizationProblem::from_toml_str(&quadratic, Path::new("p.toml")).unwrap();
        assert_eq!(p.settings.order, ElementOrder::P2);
    }

    /// Issue 19: `--generations` / `--max-evaluations` shorten a run without editing the file.
    #[test]
    fn budget_overrides_shorten_the_run() {
        let nsga = Algorithm::Nsga2 { population: 8, generations: 10, seed: 1 };
        let quick = |g, m| {
            nsga.with_budget(BudgetOverride { generations: g, max_evaluations: m, seed: None })
        };
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
        assert!(e.starts_with("max_evaluations: less than one generation"), "{e}");
        assert!(e.contains("got 7; allowed: >= 8"), "{e}");
        assert!(quick(Some(usize::MAX), None).is_err());
        let ps = Algorithm::PatternSearch {
            max_evaluations: 200,
            seed: 1,
            random_poll: false,
            start: Start::Centre,
        };
        let b = |g, m| {
            ps.with_budget(BudgetOverride { generations: g, max_evaluations: m, seed: Some(5) })
        };
        assert!(matches!(
            b(None, Some(12)).unwrap(),
            Algorithm::PatternSearch { max_evaluations: 12, .. }
        ));
        assert!(
            b(Some(3), None)
                .unwrap_err()
                .to_string()
                .starts_with("generations: applies to NSGA-II")
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

    /// `kind = "surrogate"`: defaults, every setting, and each bad setting named by its key.
    #[test]
    fn surrogate_settings_read_and_bad_ones_name_their_key() {
        let surrogate = GOOD
            .replace("kind = \"nsga2\"\npopulation = 8\ngenerations = 2", "kind = \"surrogate\"");
        let p = OptimizationProblem::from_toml_str(&surrogate, Path::new("p.toml")).unwrap();
        let Algorithm::Surrogate(s) = &p.algorithm else { panic!("{:?}", p.algorithm) };
        assert_eq!((s.max_evaluations, s.initial_size, s.batch), (200, None, None));
        assert_eq!((s.stall_iterations, s.seed), (15, 1));
        assert_eq!(p.algorithm.kind(), "surrogate");
        assert!((p.manufacturing_resolution - 1e-5).abs() < 1e-18);
        let full = surrogate.replace(
            "kind = \"surrogate\"",
            "kind = \"surrogate\"\nmax_evaluations = 60\ninitial_size = 12\nbatch = 3\n\
             acquisition = \"ehvi\"\nstall_iterations = 0\nstall_tolerance = 0.01\nseed = 9\n\
             hypervolume_reference = [\"0.001\", 5e-4]",
        );
        let p = OptimizationProblem::from_toml_str(&full, Path::new("p.toml")).unwrap();
        let Algorithm::Surrogate(s) = &p.algorithm else { panic!() };
        assert_eq!((s.max_evaluations, s.initial_size, s.batch), (60, Some(12), Some(3)));
        assert_eq!((s.stall_iterations, s.seed), (0, 9));
        assert_eq!(p.hypervolume_reference, Some(vec![1e-3, 5e-4]));
        let quick = p.algorithm.with_budget(BudgetOverride {
            generations: None,
            max_evaluations: Some(30),
            seed: Some(4),
        });
        assert!(matches!(
            quick,
            Ok(Algorithm::Surrogate(SurrogateSettings { max_evaluations: 30, seed: 4, .. }))
        ));
        let bad = |line: &str, key: &str| {
            let text =
                surrogate.replace("kind = \"surrogate\"", &format!("kind = \"surrogate\"\n{line}"));
            let e = OptimizationProblem::from_toml_str(&text, Path::new("p.toml")).unwrap_err();
            assert!(e.is_input_error(), "{e}");
            let text = e.to_string();
            assert!(text.contains("p.toml") && text.contains(key), "{line}: {text}");
        };
        bad("batch = 0", "algorithm.batch");
        bad("batch = 5000", "algorithm.batch");
        bad("initial_size = 2", "algorithm.initial_size");
        bad("acquisition = \"qparego\"", "acquisition");
        bad("max_evaluations = 0", "algorithm.max_evaluations");
        bad("stall_tolerance = -1.0", "algorithm.stall_tolerance");
        bad("population = 8", "algorithm.population: applies to kind = \"nsga2\"");
        bad("start = \"base\"", "algorithm.start");
        bad("hypervolume_reference = [1.0]", "algorithm.hypervolume_reference");
        let nsga_batch = GOOD.replace("population = 8", "population = 8\nbatch = 2");
        let e = OptimizationProblem::from_toml_str(&nsga_batch, Path::new("p.toml")).unwrap_err();
        assert!(e.to_string().contains("algorithm.batch: applies to kind = \"surrogate\""), "{e}");
        let coarse = GOOD.replace(
            "mesh = \"coarse\"",
            "mesh = \"coarse\"\nmanufacturing_resolution = \"0.1mm\"",
        );
        let p = OptimizationProblem::from_toml_str(&coarse, Path::new("p.toml")).unwrap();
        assert!((p.manufacturing_resolution - 1e-4).abs() < 1e-18);
        let huge = GOOD
            .replace("mesh = \"coarse\"", "mesh = \"coarse\"\nmanufacturing_resolution = \"2mm\"");
        let e = OptimizationProblem::from_toml_str(&huge, Path::new("p.toml")).unwrap_err();
        assert!(e.to_string().contains("manufacturing_resolution"), "{e}");
    }

    /// `start` of a pattern search: a name, or values by variable name inside the bounds.
    #[test]
    fn a_pattern_search_starts_where_the_file_says() {
        let single = GOOD.replace("[[objective]]\nmetric = \"volume_m3\"\n", "").replace(
            "kind = \"nsga2\"\npopulation = 8\ngenerations = 2",
            "kind = \"pattern-search\"",
        );
        let with = |start: &str| {
            let text = single.replace(
                "kind = \"pattern-search\"",
                &format!("kind = \"pattern-search\"\nstart = {start}"),
            );
            OptimizationProblem::from_toml_str(&text, Path::new("p.toml"))
        };
        let start_of = |p: OptimizationProblem| match p.algorithm {
            Algorithm::PatternSearch { start, .. } => start,
            other => panic!("{other:?}"),
        };
        assert_eq!(start_of(with("\"base\"").unwrap()), Start::Base);
        assert_eq!(start_of(with("\"centre\"").unwrap()), Start::Centre);
        let values = start_of(with("{ R0 = \"20mm\" }").unwrap());
        let Start::Values(v) = values else { panic!() };
        assert!((v[0].unwrap() - 0.02).abs() < 1e-15 && v[1].is_none());
        for (start, key) in [
            ("{ R0 = \"40mm\" }", "outside the variable's bounds"),
            ("{ Q = 1 }", "not a variable of this problem"),
            ("{ n = 2.5 }", "algorithm.start.n"),
            ("\"middle\"", "algorithm.start"),
        ] {
            let e = with(start).unwrap_err().to_string();
            assert!(e.contains(key), "{start}: {e}");
        }
    }

    #[test]
    fn violation_and_margin_are_relative() {
        let c = Constraint { metric: "torque_max_Nm".into(), min: Some(3.0), max: None };
        assert!(c.violation(3.5).abs() < 1e-15);
        assert!((c.violation(1.5) - 0.5).abs() < 1e-12);
        assert!((c.margin(3.3) - 0.1).abs() < 1e-12);
        assert!(c.violation(f64::NAN).is_infinite());
    }

    /// The rules of `violation_of` for bounds beyond the analysed range, one case each.
    #[test]
    fn bounds_satisfy_violate_or_cannot_decide_a_constraint() {
        use MetricValue::{AtLeast, AtMost, NotApplicable, Value};
        let min = Constraint { metric: "bandwidth_rad_s".into(), min: Some(100.0), max: None };
        let max = Constraint { metric: "release_time_s".into(), min: None, max: Some(0.5) };
        let both = Constraint { metric: "t63_s".into(), min: Some(0.1), max: Some(0.5) };
        // A bound that already satisfies the constraint satisfies it.
        assert!(min.violation_of(AtLeast(6283.0)) <= 0.0);
        assert!(max.violation_of(AtMost(0.2)) <= 0.0);
        assert!(min.margin_of(AtLeast(6283.0)) > 0.0);
        // A bound already beyond a limit violates it at least that far (finite, so Deb's rules
        // still rank the design).
        assert!((max.violation_of(AtLeast(1.0)) - 1.0).abs() < 1e-12);
        assert!((min.violation_of(AtMost(50.0)) - 0.5).abs() < 1e-12);
        assert!((both.violation_of(AtLeast(1.0)) - 1.0).abs() < 1e-12);
        // A bound that cannot decide counts as not computed.
        assert!(min.violation_of(AtLeast(50.0)).is_infinite());
        assert!(max.violation_of(AtLeast(0.2)).is_infinite());
        assert!(both.violation_of(AtLeast(0.2)).is_infinite());
        assert!(max.margin_of(AtLeast(0.2)) < 0.0);
        // Not applicable satisfies every constraint; a value is judged as before.
        assert!(max.violation_of(NotApplicable) <= 0.0);
        assert!(max.margin_of(NotApplicable).is_infinite());
        assert!((max.violation_of(Value(1.0)) - 1.0).abs() < 1e-12);
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
            if path.extension().and_then(|e| e.to_str()) != Some("toml") {
                continue; // the benchmark script beside the problem files
            }
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
