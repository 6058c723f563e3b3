//! The metrics beyond the static analysis: dynamics (`mrbrake response`), heat (`mrbrake
//! thermal`) and what the hand feels (`mrbrake haptic wall --brake-model`, [`haptic`]), computed for a design only when a study's constraint, objective or `record` asks for
//! them, in a cascade of fidelity levels.
//!
//! Brief overview: [`EXPENSIVE_METRICS`] maps every such metric to the [`Analysis`] that gives it
//! (its name, unit and meaning are in [`crate::evaluate::METRICS`] with the static ones);
//! [`StudyMetrics`] is what a study asks for — the metrics, its constraints (the gates of the
//! cascade) and the [`settings`] of the analyses — and is part of the
//! [`crate::EvaluationSettings`]. The settings of the analyses it runs that differ from their
//! defaults are part of every design key, so a changed setting never reads back a stale metric;
//! the metrics asked for and the constraints are not: a record holds the metrics computed so far,
//! and a study asking for more (`--resume` with a longer list) completes the stored designs with
//! the missing metrics only ([`crate::evaluate::complete`]: no static analysis again, only the
//! analyses whose metrics are missing, and those they need — the small-signal response again for
//! a haptic wall with predicted dynamics). A static-only study has an empty [`StudyMetrics`] and
//! keys, records and cost exactly as before; a study whose analyses run at their default settings
//! has the same keys as the static-only study of the same designs. (A metric that brings in an
//! analysis whose settings are not at their defaults changes the keys: its designs are evaluated
//! again, the static analysis included.)
//!
//! A figure beyond the range an analysis covers is stored as a bound
//! ([`mrbrake_store::MetricValue`]), never as an infinity: a bandwidth above the highest frequency
//! analysed is `AtLeast` that frequency, a step-response time the time steps do not resolve is
//! `AtMost` the end of the step holding the crossing, a warm-up that does not reach the limit
//! within the run is `AtLeast` the run, a coil without a steady state (thermal runaway) is
//! `AtLeast` the insulation limit, a hand that never leaves the wall releases `AtLeast` the time
//! from the withdrawal to the end of the run. A step of a direction the brake does not have, and
//! a release in a scenario without withdrawal, are `NotApplicable`. How constraints and objectives
//! use them: [`crate::problem::Constraint::violation_of`], [`crate::optimize::evaluation_for`].
//!
//! The cascade (`cascade`, run by [`crate::evaluate::evaluate`]): the static analysis first
//! (always); then level 1 (steady temperatures, the small-signal response of each direction asked
//! for: one linear solve per frequency), level 2 (the
//! continuous-current search, the step responses), level 3 (the warm-up transient, the hot
//! torque, the haptic wall: the brake model's torque–current sweep and the simulation; with
//! predicted dynamics it fits the level-1 small-signal response, which it then needs). Before each level the constraints on the metrics known so far are checked: a design
//! that already violates one is stored `infeasible` with its metrics so far and a reason naming
//! the constraint and the analyses skipped. One design meshes once for its expensive analyses:
//! one response model on that mesh for all its step and frequency responses, one heat solver on
//! its device part for all its thermal figures. (The static analysis meshes on its own: the
//! mesh is 0.18 s of its 2.3 s on the default mesh.) A
//! numerical failure of an expensive analysis is stored as `failed` with its reason (the study
//! goes on).

mod compute;
pub mod haptic;
pub mod settings;

use std::collections::BTreeSet;
use std::sync::atomic::{AtomicUsize, Ordering};

use mrbrake_design::spec::BrakeSpec;
use mrbrake_store::MetricValue;
use serde_json::{Value, json};

pub(crate) use compute::cascade;
pub use haptic::{HapticDynamics, HapticSettings};
pub use settings::{ResponseSettings, ThermalSettings};

use crate::ExploreError;
use crate::evaluate::EvaluationSettings;
use crate::problem::Constraint;

/// An analysis beyond the static one, in cascade order (cheapest level first).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Analysis {
    /// Steady temperatures at the study's current and duty (level 1).
    ThermalSteady,
    /// Small-signal frequency response of direction 1 about the bias (level 1).
    Frequency,
    /// Small-signal frequency response of direction 2 about the bias (level 1).
    Frequency2,
    /// Continuous current: steady states searched for the insulation limit (level 2).
    ThermalRating,
    /// Step response up, direction 1 (level 2).
    StepUp1,
    /// Step response up, direction 2 (level 2).
    StepUp2,
    /// Release (step back down), direction 1 (level 2).
    Release1,
    /// Release, direction 2 (level 2).
    Release2,
    /// Warm-up transient to the time to the limit (level 3).
    Warmup,
    /// Hot torque at the continuous current (level 3: a magnetic analysis at the hot currents).
    HotTorque,
    /// The haptic wall of the design's brake model (level 3: the torque–current sweep of the
    /// model, then the simulation).
    Haptic,
}

/// Every analysis, in cascade order.
pub const ANALYSES: [Analysis; 11] = [
    Analysis::ThermalSteady,
    Analysis::Frequency,
    Analysis::Frequency2,
    Analysis::ThermalRating,
    Analysis::StepUp1,
    Analysis::StepUp2,
    Analysis::Release1,
    Analysis::Release2,
    Analysis::Warmup,
    Analysis::HotTorque,
    Analysis::Haptic,
];

impl Analysis {
    /// Its name in records and messages.
    pub fn name(self) -> &'static str {
        match self {
            Self::ThermalSteady => "steady temperatures",
            Self::Frequency => "small-signal response",
            Self::Frequency2 => "small-signal response (direction 2)",
            Self::ThermalRating => "continuous-current search",
            Self::StepUp1 => "step response (direction 1)",
            Self::StepUp2 => "step response (direction 2)",
            Self::Release1 => "release (direction 1)",
            Self::Release2 => "release (direction 2)",
            Self::Warmup => "warm-up",
            Self::HotTorque => "hot torque",
            Self::Haptic => "haptic wall",
        }
    }

    /// Its fidelity level: 1 (cheap), 2, 3 (most expensive); the static analysis is level 0.
    pub fn level(self) -> u8 {
        match self {
            Self::ThermalSteady | Self::Frequency | Self::Frequency2 => 1,
            Self::Warmup | Self::HotTorque | Self::Haptic => 3,
            _ => 2,
        }
    }

    /// True for the analyses of `mrbrake thermal` (the others are `mrbrake response`'s).
    pub fn is_thermal(self) -> bool {
        matches!(self, Self::ThermalSteady | Self::ThermalRating | Self::Warmup | Self::HotTorque)
    }

    fn index(self) -> usize {
        ANALYSES.iter().position(|a| *a == self).unwrap_or(0)
    }
}

/// Every metric beyond the static analysis and the analysis that gives it.
pub const EXPENSIVE_METRICS: &[(&str, Analysis)] = &[
    ("bandwidth_rad_s", Analysis::Frequency),
    ("bandwidth_dir2_rad_s", Analysis::Frequency2),
    ("t63_s", Analysis::StepUp1),
    ("t90_s", Analysis::StepUp1),
    ("t63_dir2_s", Analysis::StepUp2),
    ("t90_dir2_s", Analysis::StepUp2),
    ("t63_fall_s", Analysis::Release1),
    ("t90_fall_s", Analysis::Release1),
    ("t63_fall_dir2_s", Analysis::Release2),
    ("t90_fall_dir2_s", Analysis::Release2),
    ("coil_max_T_C", Analysis::ThermalSteady),
    ("continuous_current_A", Analysis::ThermalRating),
    ("max_duty_at_max_current", Analysis::ThermalRating),
    ("time_to_limit_s", Analysis::Warmup),
    ("continuous_torque_Nm", Analysis::HotTorque),
    ("withdraw_excess_torque_Nm", Analysis::Haptic),
    ("release_time_s", Analysis::Haptic),
    ("displayed_stiffness_Nm_per_rad", Analysis::Haptic),
    ("free_motion_torque_Nm", Analysis::Haptic),
];

/// The analysis a metric needs beyond the static one, `None` for a static metric.
pub fn analysis_of(metric: &str) -> Option<Analysis> {
    EXPENSIVE_METRICS.iter().find(|(name, _)| *name == metric).map(|(_, a)| *a)
}

/// How many times each analysis has run in this process (the cascade's accounting: a test
/// counts them to show what the cascade skips).
static RUNS: [AtomicUsize; ANALYSES.len()] = [const { AtomicUsize::new(0) }; ANALYSES.len()];

/// How many times each analysis has run in this process, in [`ANALYSES`] order.
pub fn analysis_counts() -> Vec<(Analysis, usize)> {
    ANALYSES.iter().map(|a| (*a, RUNS[a.index()].load(Ordering::Relaxed))).collect()
}

fn count_run(analysis: Analysis) {
    RUNS[analysis.index()].fetch_add(1, Ordering::Relaxed);
}

/// What a study asks for beyond the static analysis (module docs). The default asks for nothing:
/// a static-only study.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct StudyMetrics {
    /// The expensive metrics asked for, in [`EXPENSIVE_METRICS`] order.
    requested: Vec<&'static str>,
    /// The study's constraints: the gates of the cascade.
    gates: Vec<Constraint>,
    /// Settings of the dynamics metrics (and the drive of `continuous_torque_Nm`).
    pub response: ResponseSettings,
    /// Settings of the heat metrics.
    pub thermal: ThermalSettings,
    /// Settings of the haptic metrics.
    pub haptic: HapticSettings,
}

impl StudyMetrics {
    /// A study asking for the metrics `asked` (static ones are ignored: they are always
    /// computed), gated by `constraints`.
    pub fn new<'n>(
        asked: impl IntoIterator<Item = &'n str>,
        constraints: &[Constraint],
        response: ResponseSettings,
        thermal: ThermalSettings,
    ) -> Self {
        let asked: BTreeSet<&str> = asked.into_iter().collect();
        let requested: Vec<&'static str> = EXPENSIVE_METRICS
            .iter()
            .filter(|(name, _)| asked.contains(name))
            .map(|(name, _)| *name)
            .collect();
        let gates = if requested.is_empty() { Vec::new() } else { constraints.to_vec() };
        Self { requested, gates, response, thermal, haptic: HapticSettings::default() }
    }

    /// True when nothing beyond the static analysis is asked for.
    pub fn is_static(&self) -> bool {
        self.requested.is_empty()
    }

    /// The expensive metrics asked for.
    pub fn requested(&self) -> &[&'static str] {
        &self.requested
    }

    /// The analyses the asked-for metrics need (the hot torque needs the rating first, the
    /// haptic wall with predicted dynamics the small-signal response), in cascade order.
    pub fn analyses(&self) -> BTreeSet<Analysis> {
        let mut set: BTreeSet<Analysis> =
            self.requested.iter().filter_map(|m| analysis_of(m)).collect();
        if set.contains(&Analysis::HotTorque) {
            set.insert(Analysis::ThermalRating);
        }
        if set.contains(&Analysis::Haptic) && self.haptic.dynamics == HapticDynamics::Predicted {
            set.insert(Analysis::Frequency);
        }
        set
    }

    /// The analyses needed to give the asked-for metrics that `known` lacks (a step direction the
    /// brake does not have is known: stored as not applicable), with the analyses they depend on
    /// (as [`Self::analyses`]), in cascade order.
    pub fn analyses_missing(&self, known: &[(String, MetricValue)]) -> BTreeSet<Analysis> {
        let has = |metric: &str| known.iter().any(|(name, _)| name == metric);
        let mut set: BTreeSet<Analysis> =
            self.requested.iter().filter(|m| !has(m)).filter_map(|m| analysis_of(m)).collect();
        let rating_known = EXPENSIVE_METRICS
            .iter()
            .filter(|(_, a)| *a == Analysis::ThermalRating)
            .all(|(name, _)| has(name));
        if set.contains(&Analysis::HotTorque) && !rating_known {
            set.insert(Analysis::ThermalRating);
        }
        if set.contains(&Analysis::Haptic) && self.haptic.dynamics == HapticDynamics::Predicted {
            set.insert(Analysis::Frequency);
        }
        set
    }

    /// True when a stored `record` of a design lacks metrics this study asks for, or was stopped
    /// by a constraint of another study that this study's constraints do not violate: then
    /// [`crate::evaluate::complete`] completes it. Static failures and infeasible designs, and
    /// numerical failures of an expensive analysis, are final.
    pub fn needs_completion(&self, record: &mrbrake_store::Record) -> bool {
        use mrbrake_store::Status;
        let stopped = record.status == Status::Infeasible && stopped_at_gate(record);
        if self.is_static() || !(record.status == Status::Ok || stopped) {
            return false;
        }
        if stopped {
            // Still stopped under this study's constraints: nothing to compute.
            return self.violated_gate(&record.metrics).is_none();
        }
        self.requested.iter().any(|m| record.metric_value(m).is_none())
    }

    fn needs_dynamics(&self) -> bool {
        self.analyses().iter().any(|a| !a.is_thermal())
    }

    fn needs_heat(&self) -> bool {
        self.analyses().iter().any(|a| a.is_thermal())
    }

    /// The part of the design key (module docs): the settings tables of the analyses that run
    /// and that differ from their defaults; `None` when there are none (then the keys are those
    /// of a static-only study of the same designs). Neither the metrics asked for nor the
    /// constraints are part of it, so asking for one more metric keeps the keys — unless it
    /// brings in an analysis whose settings are not at their defaults: then the key holds them
    /// and the designs are evaluated again.
    pub fn canonical(&self) -> Option<Value> {
        let defaults = Self::default();
        let changed: serde_json::Map<String, Value> = self
            .settings_tables()
            .into_iter()
            .filter(|(table, settings)| {
                let default = match *table {
                    "response" => defaults.response.canonical(),
                    "thermal" => defaults.thermal.canonical(),
                    _ => defaults.haptic.canonical(),
                };
                *settings != default
            })
            .map(|(table, settings)| (table.to_string(), settings))
            .collect();
        (!changed.is_empty()).then_some(Value::Object(changed))
    }

    /// The settings of the analyses that run, by table.
    fn settings_tables(&self) -> Vec<(&'static str, Value)> {
        let mut tables = Vec::new();
        if self.needs_dynamics() || self.requested.contains(&"continuous_torque_Nm") {
            tables.push(("response", self.response.canonical()));
        }
        if self.needs_heat() {
            tables.push(("thermal", self.thermal.canonical()));
        }
        if self.analyses().contains(&Analysis::Haptic) {
            tables.push(("haptic", self.haptic.canonical()));
        }
        tables
    }

    /// What every record of the study keeps beside the static settings (nothing for a
    /// static-only study): the metrics asked for and the settings of the analyses that run, as
    /// flat `response_…` / `thermal_…` entries (one CSV column each in `mrbrake export`).
    pub fn recorded(&self) -> Vec<(String, Value)> {
        if self.is_static() {
            return Vec::new();
        }
        let mut out = vec![("metrics_asked".to_string(), json!(self.requested.join(" ")))];
        for (table, settings) in self.settings_tables() {
            if let Value::Object(settings) = settings {
                out.extend(settings.iter().map(|(k, v)| (format!("{table}_{k}"), v.clone())));
            }
        }
        out
    }

    /// The first gate the known `metrics` violate, as a reason (`None`: none violated). Gates on
    /// metrics not known yet wait for their level; a bound that cannot decide a gate stops the
    /// cascade as a violation ([`Constraint::violation_of`]).
    fn violated_gate(&self, metrics: &[(String, MetricValue)]) -> Option<String> {
        self.gates.iter().find_map(|gate| {
            let (_, value) = metrics.iter().find(|(name, _)| *name == gate.metric)?;
            (gate.violation_of(*value) > 0.0).then(|| {
                let bound = |b: Option<f64>, word: &str| b.map(|v| format!(" {word} {v}"));
                let bounds: String = [bound(gate.min, "min"), bound(gate.max, "max")]
                    .into_iter()
                    .flatten()
                    .collect();
                format!("{} = {value} violates the constraint{bounds}", gate.metric)
            })
        })
    }

    /// Checks, before any analysis, that `spec` (the study's base design) and the settings can
    /// give every asked-for metric: the settings' ranges, the flux path's conductivity for a
    /// dynamics metric, thermal data for a heat metric. The error names the metric and what is
    /// missing.
    pub fn check(
        &self,
        spec: &BrakeSpec,
        evaluation: &EvaluationSettings,
    ) -> Result<(), ExploreError> {
        compute::check(self, spec, evaluation)
    }
}

/// What separates the reason of a design the cascade stopped at a constraint from the analyses
/// it skipped.
pub(crate) const SKIPPED: &str = "; skipped: ";

/// True when `record` is a design the cascade stopped at a violated constraint (its reason names
/// the analyses skipped).
fn stopped_at_gate(record: &mrbrake_store::Record) -> bool {
    record.reason.as_deref().is_some_and(|reason| reason.contains(SKIPPED))
}

/// Checks a study's metrics against its base design before anything is evaluated ([`StudyMetrics::check`]
/// on the base spec, when it is a valid brake); the error names the problem file `path`.
pub fn check_space(space: &crate::DesignSpace, path: &std::path::Path) -> Result<(), ExploreError> {
    let settings = space.settings();
    if settings.study.is_static() {
        return Ok(());
    }
    if let Ok(spec) = space.base_design()?.spec {
        let file = path.display().to_string();
        settings.study.check(&spec, settings).map_err(|e| e.in_file(&file))?;
    }
    Ok(())
}

/// What the optimiser sees of a design the cascade stopped at a violated constraint (stored
/// `infeasible` with its metrics so far): infinite objectives and the violation of the
/// constraints whose metrics are known. `None` for any other record.
pub fn stopped_evaluation(
    record: &mrbrake_store::Record,
    constraints: &[Constraint],
    objectives: usize,
) -> Option<mrbrake_optim::pareto::Evaluation> {
    if record.status != mrbrake_store::Status::Infeasible || record.metrics.is_empty() {
        return None;
    }
    let violation: f64 = constraints
        .iter()
        .filter_map(|c| Some(c.violation_of(record.metric_value(&c.metric)?)))
        .sum();
    (violation > 0.0 && violation.is_finite())
        .then(|| mrbrake_optim::pareto::Evaluation::new(vec![f64::INFINITY; objectives], violation))
}

#[cfg(test)]
mod tests {
    use mrbrake_store::{Record, Status};

    use super::*;
    use crate::problem::Constraint;

    fn record(status: Status, reason: Option<&str>, metrics: &[(&str, f64)]) -> Record {
        Record {
            key: "a".repeat(64),
            status,
            reason: reason.map(str::to_owned),
            variables: Vec::new(),
            metrics: metrics.iter().map(|(n, v)| (n.to_string(), (*v).into())).collect(),
            spec_toml: String::new(),
            eval_seconds: 1.0,
            solver_version: "test".into(),
            settings: Default::default(),
        }
    }

    fn study(metrics: &[&str], constraints: &[Constraint]) -> StudyMetrics {
        StudyMetrics::new(
            metrics.iter().copied(),
            constraints,
            Default::default(),
            Default::default(),
        )
    }

    /// Which stored records a study completes: those lacking an asked-for metric, and those
    /// another study's constraint stopped when this study's constraints let them pass.
    #[test]
    fn a_stored_record_is_completed_only_when_it_lacks_what_the_study_asks() {
        let torque = [("torque_max_Nm", 2.0)];
        let ok = record(Status::Ok, None, &torque);
        assert!(study(&["coil_max_T_C"], &[]).needs_completion(&ok));
        assert!(!study(&[], &[]).needs_completion(&ok), "a static study completes nothing");
        let with = record(Status::Ok, None, &[("torque_max_Nm", 2.0), ("coil_max_T_C", 60.0)]);
        assert!(!study(&["coil_max_T_C"], &[]).needs_completion(&with));
        let failed = record(Status::Failed, Some("steady temperatures: diverged"), &torque);
        assert!(!study(&["coil_max_T_C"], &[]).needs_completion(&failed), "failures are final");
        let reason = format!("torque_max_Nm = 2 violates the constraint min 3{SKIPPED}steady");
        let stopped = record(Status::Infeasible, Some(&reason), &torque);
        let strict = Constraint { metric: "torque_max_Nm".into(), min: Some(3.0), max: None };
        let loose = Constraint { min: Some(1.0), ..strict.clone() };
        assert!(!study(&["coil_max_T_C"], &[strict]).needs_completion(&stopped));
        // Stopped by a constraint this study does not have: completed.
        assert!(study(&["coil_max_T_C"], &[loose]).needs_completion(&stopped));
        assert!(!study(&[], &[]).needs_completion(&stopped), "static: nothing to do");
        let missing = study(&["coil_max_T_C", "t63_s"], &[]);
        let known: Vec<(String, MetricValue)> = with.metrics.clone();
        assert_eq!(
            missing.analyses_missing(&known).into_iter().collect::<Vec<_>>(),
            [Analysis::StepUp1]
        );
    }
}
