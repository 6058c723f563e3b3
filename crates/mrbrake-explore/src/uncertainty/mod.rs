//! Uncertainty propagation through the real FEA (issue 29): the declared uncertain inputs
//! ([`declarations`]) sampled by scrambled Sobol' points ([`mrbrake_uq::qmc`]), each sample a
//! design of a [`DesignSpace`] evaluated by the [`Runner`] into the results store (so a run is
//! resumable and a stored sample is never analysed twice), then per output metric its mean,
//! standard deviation and 5/50/95 % percentiles ([`mrbrake_uq::statistics`]) and its first-order
//! and total Sobol' indices with bootstrap intervals from a polynomial-chaos surrogate fitted to the
//! same samples ([`mrbrake_uq::sensitivity`]; its leave-one-out error says how far to trust them).
//!
//! The torque–current band ([`band`]) comes from each sample's stored curve: a study keeping
//! curves ([`EvaluationSettings::curve_points`] above 2) stores every point of it as a metric,
//! else the band has the two points every record holds (0 A and the maximum current).
//!
//! Samples that are not valid brakes or whose analysis failed are left out of the statistics and
//! counted; the Sobol' indices are fitted on the remaining samples (the surrogate does not need the
//! Sobol' sequence's balance, only the inputs' CDF values).

pub mod band;
pub mod declarations;

use std::time::Instant;

use serde::Serialize;

use mrbrake_observe::Observer;
use mrbrake_store::{Record, Status, Store};
use mrbrake_uq::distribution::Distribution;
use mrbrake_uq::sensitivity::{InputIndices, SensitivityOptions, SurrogateSummary, sobol_indices};
use mrbrake_uq::statistics::{Summary, summarize};

use crate::evaluate::torque_curve;
use crate::variable::Quantity;
use crate::{DesignSpace, EvaluationSettings, ExploreError, Progress, Runner};
pub use band::{BandPoint, torque_band};
pub use declarations::{Declarations, UncertainInput};

/// The metrics summarised when none are asked for: the static torques and the coil's dynamics
/// figures; a study's dynamics or heat metrics are added when it records them.
pub const DEFAULT_METRICS: &[&str] = &[
    "torque_max_Nm",
    "torque_off_Nm",
    "dynamic_range",
    "thesis_torque_Nm",
    "mean_B_fluid_T",
    "flux_path_max_B_T",
    "inductance_H",
    "time_constant_s",
];

/// Currents of each sample's torque–current curve the front ends ask for by default
/// ([`EvaluationSettings::curve_points`]): 0 to 2 A in 0.25 A steps on the thesis brake, one field
/// solve each (an analysis of the thesis brake takes 0.63 s instead of 0.33 s with 2).
pub const DEFAULT_CURVE_POINTS: usize = 9;

/// Most samples of one study (the store keeps each one).
pub const MAX_SAMPLES: usize = 1 << 16;

/// What to propagate.
#[derive(Debug, Clone)]
pub struct UncertaintyRequest<'a> {
    /// The spec's text and where it was read from.
    pub spec_toml: &'a str,
    /// The spec's file name, for messages.
    pub spec_origin: &'a str,
    /// The uncertain inputs.
    pub declarations: &'a Declarations,
    /// Number of samples (a power of two keeps the Sobol' points balanced).
    pub samples: usize,
    /// Seed of the scrambling and of the bootstrap.
    pub seed: u64,
    /// The analyses' settings.
    pub settings: EvaluationSettings,
    /// Metrics to summarise (empty: [`DEFAULT_METRICS`] and the study's recorded metrics).
    pub metrics: Vec<String>,
    /// Bootstrap replicates of the Sobol' intervals.
    pub bootstrap: usize,
    /// Worker threads (0: one per core).
    pub jobs: usize,
}

/// One declared input as reported.
#[derive(Debug, Clone, Serialize)]
pub struct InputReport {
    /// The spec path.
    pub name: String,
    /// The law's name (`normal`, `uniform`, `triangular`, `log-normal`).
    pub distribution: &'static str,
    /// The law (its parameters in the field's SI unit) and its truncation.
    pub law: Distribution,
    /// The field's SI unit (empty for factors and counts).
    pub unit: &'static str,
    /// The law's mean and standard deviation (after truncation).
    pub mean: f64,
    /// Standard deviation.
    pub std: f64,
}

/// The global sensitivity of one output to every input.
#[derive(Debug, Clone, Serialize)]
pub struct OutputSensitivity {
    /// Per input (by path): first-order and total indices with their intervals.
    pub inputs: Vec<(String, InputIndices)>,
    /// The polynomial-chaos surrogate behind them.
    pub surrogate: SurrogateSummary,
}

/// The result of a propagation.
#[derive(Debug, Clone, Serialize)]
pub struct Uncertainty {
    /// Samples drawn.
    pub samples: usize,
    /// Samples that were valid brakes with an analysis (the statistics' sample).
    pub evaluated: usize,
    /// Samples left out: not a valid brake, or a failed analysis (with the first reason).
    pub left_out: usize,
    /// The first left-out sample's reason.
    pub left_out_reason: Option<String>,
    /// The inputs.
    pub inputs: Vec<InputReport>,
    /// Per metric: its statistics over the evaluated samples.
    pub outputs: Vec<(String, Summary)>,
    /// Per metric with a spread: the Sobol' indices.
    pub sobol: Vec<(String, OutputSensitivity)>,
    /// The nominal design's metrics (the spec without any input changed).
    pub nominal: Vec<(String, f64)>,
    /// The torque–current band: per current of the nominal curve, the samples' torques.
    pub torque_band: Vec<BandPoint>,
    /// The evaluated samples' input values (SI, one row per sample, inputs in order).
    pub values: Vec<Vec<f64>>,
    /// Wall time of the propagation (s) and of the analyses summed over workers.
    pub total_s: f64,
    /// Sum of the analyses' own times (s).
    pub evaluation_s: f64,
    /// Designs analysed in this run (the others came from the store).
    pub computed: usize,
}

/// Propagates the declared inputs through the FEA into `store` (see the module docs); `observer`
/// sees the runner's [`Progress`] and may stop it (the designs done stay stored).
pub fn propagate(
    store: &mut Store,
    request: &UncertaintyRequest<'_>,
    observer: &mut impl Observer<Progress>,
) -> Result<Uncertainty, ExploreError> {
    let start = Instant::now();
    if !(2..=MAX_SAMPLES).contains(&request.samples) {
        return Err(mrbrake_error::FieldError::out_of_range(
            "samples",
            request.samples,
            format!("2..={MAX_SAMPLES}"),
        )
        .into());
    }
    let declarations = request.declarations;
    let names: Vec<String> = declarations.inputs.iter().map(|i| i.path.clone()).collect();
    let space = DesignSpace::new(
        request.spec_toml,
        request.spec_origin,
        &[],
        &names,
        request.settings.clone(),
    )?;
    let laws = declarations.distributions();
    let sample = mrbrake_uq::qmc::sample(&laws, request.samples, request.seed).map_err(uq)?;
    let values: Vec<Vec<f64>> =
        sample.values.iter().map(|x| whole_counts(declarations, x)).collect();
    let mut designs = vec![space.base_design()?];
    for x in &values {
        designs.push(space.design(x)?);
    }
    let mut runner = Runner::new(store, request.settings.clone(), request.jobs);
    let (records, summary) = runner.run(&designs, observer)?;
    // The nominal design's values (a bound beyond the analysed range is no value to show).
    let nominal: Vec<(String, f64)> =
        records[0].metrics.iter().filter_map(|(n, v)| Some((n.clone(), v.value()?))).collect();
    let metrics = metric_names(request, &records[0]);
    let kept: Vec<usize> =
        (1..records.len()).filter(|&k| records[k].status == Status::Ok).collect();
    let left_out_reason =
        (1..records.len()).find(|k| !kept.contains(k)).and_then(|k| records[k].reason.clone());
    if kept.len() < 2 {
        return Err(ExploreError::input(
            "input",
            format!(
                "only {} of {} samples are valid brakes with an analysis (first reason: {}); \
                 narrow the declared spreads",
                kept.len(),
                request.samples,
                left_out_reason.as_deref().unwrap_or("none")
            ),
        )
        .in_file(&declarations.origin));
    }
    let unit: Vec<Vec<f64>> = kept.iter().map(|&k| sample.unit[k - 1].clone()).collect();
    let kept_records: Vec<&Record> = kept.iter().map(|&k| &records[k]).collect();
    let (outputs, sobol) = summaries(&metrics, &kept_records, &names, &unit, request)?;
    let curves: Vec<_> = kept_records.iter().filter_map(|r| torque_curve(&r.metrics)).collect();
    let nominal_curve = torque_curve(&records[0].metrics);
    let torque_band = torque_band(nominal_curve.as_deref(), &curves).map_err(uq)?;
    Ok(Uncertainty {
        samples: request.samples,
        evaluated: kept.len(),
        left_out: request.samples - kept.len(),
        left_out_reason,
        inputs: declarations.inputs.iter().map(report_input).collect(),
        outputs,
        sobol,
        nominal,
        torque_band,
        values: kept.iter().map(|&k| values[k - 1].clone()).collect(),
        total_s: start.elapsed().as_secs_f64(),
        evaluation_s: summary.evaluation_s,
        computed: summary.progress.computed,
    })
}

/// Per metric with a spread: its Sobol' indices.
type Sensitivities = Vec<(String, OutputSensitivity)>;

/// Per metric that every kept record has: its statistics and, when it varies, its Sobol' indices.
fn summaries(
    metrics: &[String],
    kept: &[&Record],
    names: &[String],
    unit: &[Vec<f64>],
    request: &UncertaintyRequest<'_>,
) -> Result<(Vec<(String, Summary)>, Sensitivities), ExploreError> {
    let mut outputs = Vec::new();
    let mut sobol = Vec::new();
    for metric in metrics {
        let y: Vec<f64> = kept.iter().filter_map(|r| metric_of(r, metric)).collect();
        if y.len() != kept.len() {
            continue;
        }
        outputs.push((metric.clone(), summarize(&y).map_err(uq)?));
        if y.iter().any(|v| (v - y[0]).abs() > 1e-12 * y[0].abs().max(1e-300)) {
            sobol.push((metric.clone(), sensitivity(names, unit, &y, request)?));
        }
    }
    Ok((outputs, sobol))
}

/// The Sobol' indices of one output.
fn sensitivity(
    names: &[String],
    unit: &[Vec<f64>],
    y: &[f64],
    request: &UncertaintyRequest<'_>,
) -> Result<OutputSensitivity, ExploreError> {
    let options = SensitivityOptions {
        bootstrap: request.bootstrap,
        seed: request.seed,
        ..SensitivityOptions::default()
    };
    let s = sobol_indices(unit, y, &options).map_err(uq)?;
    Ok(OutputSensitivity {
        inputs: names.iter().cloned().zip(s.inputs).collect(),
        surrogate: s.surrogate,
    })
}

/// The metrics to summarise: the request's, or the defaults and the study's recorded ones that
/// the nominal record has.
fn metric_names(request: &UncertaintyRequest<'_>, nominal: &Record) -> Vec<String> {
    if !request.metrics.is_empty() {
        return request.metrics.clone();
    }
    let mut names: Vec<String> = DEFAULT_METRICS.iter().map(|s| s.to_string()).collect();
    for (name, _) in &nominal.metrics {
        let known = DEFAULT_METRICS.contains(&name.as_str());
        if !known && crate::metrics::analysis_of(name).is_some() {
            names.push(name.clone());
        }
    }
    names
}

fn metric_of(record: &Record, name: &str) -> Option<f64> {
    record.metric(name).filter(|v| v.is_finite())
}

/// The sample with whole-number fields (turns, cylinders) rounded, as a spec holds them.
fn whole_counts(declarations: &Declarations, x: &[f64]) -> Vec<f64> {
    x.iter()
        .zip(&declarations.inputs)
        .map(|(&v, input)| match input.variable.quantity() {
            Some(Quantity::Integer) => v.round(),
            _ => v,
        })
        .collect()
}

fn report_input(input: &UncertainInput) -> InputReport {
    let d = &input.distribution;
    InputReport {
        name: input.path.clone(),
        distribution: d.law().name(),
        law: *d,
        unit: input.variable.quantity().map_or("", Quantity::unit),
        mean: d.mean(),
        std: d.std_dev(),
    }
}

fn uq(e: mrbrake_uq::UqError) -> ExploreError {
    ExploreError::Uq(e)
}
