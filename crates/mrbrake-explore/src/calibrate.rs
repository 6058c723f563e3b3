//! Calibration against a rig (issue 29 §3): the spec fields chosen as parameters are fitted so
//! that the design's predicted static torque–current curve — the real FEA at every trial point —
//! matches the loop measured on a rig, with standard errors, correlations and the parameter
//! groups the data cannot separate.
//!
//! Brief overview:
//! 1. **The measurement** ([`MeasuredLoop`]): the log is characterised as `mrbrake characterize`
//!    does ([`mrbrake_sysid::request::CharacterizationRequest`]: ramps segmented, samples binned
//!    by current per branch). The anhysteretic FEA predicts one curve, so it is compared with the
//!    **middle of the loop**, the mean of the rising and the falling branch at each current (the
//!    classical estimate of the anhysteretic curve from a symmetric loop; Jiles & Atherton,
//!    J. Magn. Magn. Mater. 61, 48–60, 1986, §2), each branch's binned means interpolated
//!    linearly at the analysis currents. The measurement noise is estimated from the raw torque
//!    samples by the median absolute deviation of their first differences, `σ = MAD(ΔT) /
//!    (0.6745 √2)` (robust to the slow ramp and to outliers; Hampel, JASA 69, 383–393, 1974; the
//!    differences of white noise have variance 2σ²), and that of a compared point as σ over the
//!    root of the samples averaged into it.
//! 2. **The model**: a [`DesignSpace`] over the spec (with the fixed `--set` changes) whose
//!    variables are the parameters; a trial point is a design analysed by
//!    [`mrbrake_design::analysis::AnalysisRequest`] with `points` currents from 0 to the spec's
//!    maximum current (direction 1: the unit the rig drives first); the residual at each current
//!    is predicted − measured torque. A trial point that is not a valid brake gives a non-finite
//!    residual, which only rejects that step.
//! 3. **The fit**: [`mrbrake_uq::calibration::calibrate`], projected Levenberg–Marquardt in the
//!    bound-normalised parameters with a finite-difference Jacobian whose columns are analysed in
//!    parallel. Chosen over a surrogate because each static evaluation costs about a second and
//!    a fit with three parameters needs a few tens of them: the surrogate's own training set
//!    would cost as much, and its error would enter the standard errors.
//! 4. **Statistics**: the standard errors use the residual's own scale `s² = ‖r‖²/(m − p)`
//!    (Bates & Watts 1988, ch. 2), which includes the model's misfit and is the honest scale when
//!    the model cannot reach the noise; the ratio `s / σ_point` is reported as the lack of fit
//!    (≈ 1: the model explains the loop to within the noise). A pair the curve cannot separate is
//!    named by [`mrbrake_uq::identifiability`] with the data that would separate it.

use std::path::{Path, PathBuf};
use std::time::Instant;

use serde::Serialize;
use toml_edit::{DocumentMut, Value};

use mrbrake_design::analysis::{Analysis, AnalysisOptions, AnalysisRequest};
use mrbrake_design::response::{ResponseModel, ResponseOptions};
use mrbrake_design::spec::{BrakeSpec, Quantity};
use mrbrake_sysid::characterize::Characterization;
use mrbrake_sysid::frd::Frd;
use mrbrake_sysid::request::CharacterizationRequest;
use mrbrake_uq::RunError;
use mrbrake_uq::calibration::{Calibration, CalibrationOptions, Parameter, calibrate};

use crate::variable::{Variable, resolve};
use crate::{DesignSpace, EvaluationSettings, ExploreError};

/// Currents compared by default: every 0.1 of the maximum current.
pub const DEFAULT_POINTS: usize = 11;

/// How far the log's highest current may fall short of the spec's maximum current (relative):
/// the rig's ramps stop at the last step below it.
pub const CURRENT_COVERAGE_TOLERANCE: f64 = 0.02;

/// The factor on the nominal value that bounds a parameter given without bounds: `[½, 1½] ×`
/// nominal, inside the field's own range.
pub const DEFAULT_SPAN: f64 = 0.5;

/// One parameter to fit: a numeric spec field (its path as given and as resolved) with bounds.
#[derive(Debug, Clone)]
pub struct ParameterRequest {
    /// As given, without its bounds (`drum.gap`, or the thesis symbol `g`).
    pub name: String,
    /// The spec field.
    pub variable: Variable,
    /// Lower bound (SI).
    pub lower: f64,
    /// Upper bound (SI).
    pub upper: f64,
    /// Start: the spec's value (the field's default when the spec leaves it out), moved into the
    /// bounds.
    pub start: f64,
}

/// What to calibrate.
#[derive(Debug, Clone)]
pub struct CalibrationRequest {
    /// The spec's text.
    pub spec_toml: String,
    /// Where it came from (messages, the calibrated spec's provenance).
    pub spec_origin: String,
    /// Fixed changes applied before calibrating (`--set PATH=VALUE`).
    pub overrides: Vec<(String, String)>,
    /// The parameters, each `PATH` or `PATH=LOW..HIGH` (values with units).
    pub parameters: Vec<String>,
    /// The rig log (the characterisation's CSV).
    pub log: PathBuf,
    /// Frequency-response data of the same brake (an FRD CSV, `mrbrake freqresp`), fitted too.
    pub frd: Option<PathBuf>,
    /// Currents compared, from 0 to the maximum current (≥ 3).
    pub points: usize,
    /// The analyses' settings (mesh, order, speed, temperature); the dynamics or heat metrics its
    /// `study` asks for (e.g. `bandwidth_rad_s`) are predicted for the start and the calibrated
    /// design after the fit (an independent check against a measured value).
    pub settings: EvaluationSettings,
    /// Worker threads for the Jacobian's columns (0: one per core).
    pub jobs: usize,
    /// The fit's budget and tolerances.
    pub options: CalibrationOptions,
}

/// The loop measured on the rig, at the compared currents.
#[derive(Debug, Clone, Serialize)]
pub struct MeasuredLoop {
    /// The log.
    pub source: String,
    /// Compared currents (A).
    pub current_a: Vec<f64>,
    /// Middle of the loop at them (N·m).
    pub torque_nm: Vec<f64>,
    /// Rising and falling branch at them (N·m).
    pub rising_nm: Vec<f64>,
    /// Falling branch at them (N·m).
    pub falling_nm: Vec<f64>,
    /// Noise of one torque sample (N·m).
    pub sample_noise_nm: f64,
    /// Noise of one compared point (N·m).
    pub point_noise_nm: f64,
    /// The log's current range (A).
    pub current_range_a: (f64, f64),
    /// Repetitions of the ramp in the log.
    pub repetitions: usize,
}

/// One fitted parameter.
#[derive(Debug, Clone, Serialize)]
pub struct FittedParameter {
    /// As given to `--parameter`.
    pub name: String,
    /// The spec path.
    pub path: String,
    /// Its SI unit ("" for factors and counts).
    pub unit: &'static str,
    /// Start value (SI).
    pub start: f64,
    /// Estimate (SI).
    pub estimate: f64,
    /// Standard error (SI; infinite for a parameter the curve does not depend on).
    pub standard_error: f64,
    /// Lower bound.
    pub lower: f64,
    /// Upper bound.
    pub upper: f64,
    /// True when it ended on a bound.
    pub at_bound: bool,
}

/// The measured and predicted frequency responses (normalised to unit DC gain), compared at the
/// measured frequencies.
#[derive(Debug, Clone)]
pub struct FrequencyFit {
    /// The FRD file.
    pub source: String,
    /// The measured response.
    pub measured: Frd,
    /// Predicted at the start.
    pub before: Frd,
    /// Predicted at the estimate.
    pub after: Frd,
    /// The DC bias of the predicted small-signal response (A).
    pub bias_a: f64,
}

impl FrequencyFit {
    /// RMS of the complex difference of `predicted` from the measured response (dimensionless).
    pub fn rms(&self, predicted: &Frd) -> f64 {
        let n = self.measured.len().max(1) as f64;
        let sum: f64 = predicted
            .responses()
            .zip(self.measured.responses())
            .map(|(p, m)| (p - m).norm_sqr())
            .sum();
        (sum / n).sqrt()
    }
}

/// A metric predicted before and after the calibration.
#[derive(Debug, Clone, Serialize)]
pub struct Prediction {
    /// The metric's name (as in the store).
    pub metric: String,
    /// At the parameters' start.
    pub before: Option<f64>,
    /// At the estimate.
    pub after: Option<f64>,
}

/// The outcome of a calibration.
#[derive(Debug, Clone)]
pub struct Calibrated {
    /// The parameters with their estimates.
    pub parameters: Vec<FittedParameter>,
    /// The fit itself (correlations, identifiability, history).
    pub fit: Calibration,
    /// Unidentifiable groups by parameter name.
    pub unidentifiable: Vec<Vec<String>>,
    /// The measured loop.
    pub measured: MeasuredLoop,
    /// The prediction at the start and at the estimate (N·m, at the compared currents).
    pub predicted_before_nm: Vec<f64>,
    /// At the estimate.
    pub predicted_after_nm: Vec<f64>,
    /// RMS of predicted − measured torque at the start (N·m).
    pub torque_rms_before_nm: f64,
    /// At the estimate (N·m).
    pub torque_rms_after_nm: f64,
    /// The frequency response compared, when `--frd` data were given.
    pub frequency_response: Option<FrequencyFit>,
    /// The study metrics asked for, predicted at the start and at the estimate (`None` where
    /// the evaluation gave none).
    pub predictions: Vec<Prediction>,
    /// `s / σ_point` at the estimate, of the torque curve (module docs).
    pub lack_of_fit: f64,
    /// The spec's text with the fixed changes and the estimates, each with its provenance.
    pub calibrated_spec: String,
    /// The calibrated design's analysis and its options (for a brake model).
    pub analysis: Analysis,
    /// Its options.
    pub analysis_options: AnalysisOptions,
    /// The calibrated spec.
    pub spec: BrakeSpec,
    /// Wall time (s).
    pub total_s: f64,
}

/// Runs the calibration of `request` (module docs).
pub fn run(request: &CalibrationRequest) -> Result<Calibrated, ExploreError> {
    let start = Instant::now();
    check_request(request)?;
    let (parameters, space, start_spec) = parameter_space(request)?;
    let start_values: Vec<f64> = parameters.iter().map(|p| p.start).collect();
    let options = analysis_options(request);
    let currents = compared_currents(start_spec.coil.max_current.a(), request.points);
    let measured = measure(&request.log, &currents)?;
    let frd = match &request.frd {
        Some(path) => Some(frequency_target(request, path, &start_spec, &measured)?),
        None => None,
    };
    let model = Model { space: &space, options, measured: &measured.torque_nm, frd: frd.as_ref() };
    let fit = fit(&model, &parameters, request)?;
    let (_, before_analysis, before_frd) = model.analyse(&start_values)?;
    let before = torques(&before_analysis);
    let (spec, analysis, after_frd) = model.analyse(&fit.estimate)?;
    let after = torques(&analysis);
    let frequency_response = match (frd, before_frd, after_frd) {
        (Some(target), Some(before), Some(after)) => Some(FrequencyFit {
            source: target.source,
            measured: target.measured,
            before,
            after,
            bias_a: target.bias_a,
        }),
        _ => None,
    };
    let fitted = fitted_parameters(&parameters, &fit);
    let unidentifiable = fit
        .identifiability
        .unidentifiable
        .iter()
        .map(|group| group.iter().map(|&j| parameters[j].name.clone()).collect())
        .collect();
    let rms = |predicted: &[f64]| {
        let sum: f64 =
            predicted.iter().zip(&measured.torque_nm).map(|(p, m)| (p - m).powi(2)).sum();
        (sum / predicted.len() as f64).sqrt()
    };
    let (torque_rms_before_nm, torque_rms_after_nm) = (rms(&before), rms(&after));
    let s = torque_rms_after_nm * residual_scale(after.len(), parameters.len());
    let calibrated_spec = calibrated_text(request, &fitted, &measured, space.is_drum())?;
    let predictions = predictions(&request.settings, &start_spec, &spec);
    Ok(Calibrated {
        predictions,
        frequency_response,
        torque_rms_before_nm,
        torque_rms_after_nm,
        lack_of_fit: s / measured.point_noise_nm.max(f64::MIN_POSITIVE),
        parameters: fitted,
        fit,
        unidentifiable,
        measured,
        predicted_before_nm: before,
        predicted_after_nm: after,
        calibrated_spec,
        analysis,
        analysis_options: options,
        spec,
        total_s: start.elapsed().as_secs_f64(),
    })
}

/// The parameters of `request`, the design space over them and the design at their start values.
/// The base spec may be invalid until the parameters have their start values (a seal count set by
/// `--set` whose torque is a parameter): only the start design must be a brake.
fn parameter_space(
    request: &CalibrationRequest,
) -> Result<(Vec<ParameterRequest>, DesignSpace, BrakeSpec), ExploreError> {
    let space_of = |names: &[String]| {
        DesignSpace::new(
            &request.spec_toml,
            &request.spec_origin,
            &request.overrides,
            names,
            request.settings.clone(),
        )
    };
    let probe = space_of(&[])?;
    let base = probe.base_design()?;
    let parameters = request
        .parameters
        .iter()
        .map(|text| parse_parameter(text, &base.spec_toml, probe.is_drum()))
        .collect::<Result<Vec<_>, _>>()?;
    let names: Vec<String> = parameters.iter().map(|p| p.variable.path().to_string()).collect();
    let space = space_of(&names)?;
    let start: Vec<f64> = parameters.iter().map(|p| p.start).collect();
    let start_spec = space.design(&start)?.spec.map_err(|source| ExploreError::InvalidBase {
        what: "mrbrake calibrate (at the parameters' start)",
        source,
    })?;
    Ok((parameters, space, start_spec))
}

/// The least-squares fit of `model` over `parameters` on `request.jobs` threads.
fn fit(
    model: &Model<'_>,
    parameters: &[ParameterRequest],
    request: &CalibrationRequest,
) -> Result<Calibration, ExploreError> {
    let bounds: Vec<Parameter> = parameters
        .iter()
        .map(|p| Parameter { start: p.start, lower: p.lower, upper: p.upper })
        .collect();
    with_threads(request.jobs, || calibrate(|x| model.residual(x), &bounds, &request.options))?
        .map_err(|e| match e {
            RunError::Uq(e) => ExploreError::Uq(e),
            RunError::Model(e) => e,
        })
}

/// The study's recorded metrics of the start and the calibrated design (module docs).
fn predictions(
    settings: &EvaluationSettings,
    start: &BrakeSpec,
    end: &BrakeSpec,
) -> Vec<Prediction> {
    if settings.study.is_static() {
        return Vec::new();
    }
    let [before, after] =
        [start, end].map(|spec| crate::evaluate::evaluate(spec, settings).metrics);
    settings
        .study
        .requested()
        .iter()
        .map(|&metric| {
            let find = |m: &[(String, mrbrake_store::MetricValue)]| {
                m.iter()
                    .find(|(n, _)| n == metric)
                    .and_then(|(_, v)| v.value())
                    .filter(|v| v.is_finite())
            };
            Prediction { metric: metric.to_string(), before: find(&before), after: find(&after) }
        })
        .collect()
}

/// `√(m / (m − p))`: the factor from the residual RMS to the estimate `s` of its scale.
fn residual_scale(m: usize, p: usize) -> f64 {
    if m > p { (m as f64 / (m - p) as f64).sqrt() } else { f64::INFINITY }
}

fn check_request(request: &CalibrationRequest) -> Result<(), ExploreError> {
    if request.parameters.is_empty() {
        return Err(ExploreError::input("parameter", "give at least one parameter to fit"));
    }
    if !(3..=201).contains(&request.points) {
        let e = mrbrake_error::FieldError::out_of_range("points", request.points, "3..=201");
        return Err(e.into());
    }
    if request.points <= request.parameters.len() {
        return Err(ExploreError::input(
            "points",
            format!(
                "{} compared currents cannot determine {} parameters with their errors; \
                 give more points",
                request.points,
                request.parameters.len()
            ),
        ));
    }
    Ok(())
}

/// The study's analysis options with the compared currents.
fn analysis_options(request: &CalibrationRequest) -> AnalysisOptions {
    AnalysisOptions { points: request.points, ..request.settings.analysis_options() }
}

/// The analysis's currents: `points` from 0 to `max_current` evenly.
fn compared_currents(max_current: f64, points: usize) -> Vec<f64> {
    (0..points).map(|k| max_current * k as f64 / (points - 1) as f64).collect()
}

/// Runs `f` on a pool of `jobs` threads (0: rayon's default pool).
fn with_threads<T: Send>(jobs: usize, f: impl FnOnce() -> T + Send) -> Result<T, ExploreError> {
    if jobs == 0 {
        return Ok(f());
    }
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(jobs)
        .build()
        .map_err(|e| ExploreError::Internal(format!("cannot start {jobs} threads: {e}")))?;
    Ok(pool.install(f))
}

/// The frequency-response data a calibration fits: the measured response, the response options
/// of the prediction (at the measured frequencies) and the block's weight in the residual.
struct FrequencyTarget {
    source: String,
    measured: Frd,
    options: ResponseOptions,
    bias_a: f64,
    /// Scale of the complex differences in the residual: the measured torque at the maximum
    /// current (a 10 % error of the response weighs like a 10 % error of the full-scale torque)
    /// times `√(n_torque / 2 n_frequency)` (both blocks weigh alike in the cost whatever their
    /// sizes).
    weight: f64,
}

/// The frequency-response target of `path` for a design like `start`.
fn frequency_target(
    request: &CalibrationRequest,
    path: &Path,
    start: &BrakeSpec,
    measured: &MeasuredLoop,
) -> Result<FrequencyTarget, ExploreError> {
    let source = path.display().to_string();
    let frd = mrbrake_sysid::frd::read_frd(path, None)?;
    if frd.len() < 2 {
        return Err(
            ExploreError::input("--frd", "at least two frequencies are needed").in_file(&source)
        );
    }
    let mut options = request.settings.study.response.options(&request.settings);
    options.omegas_rad_s = frd.omegas().collect();
    let bias_a = options.bias_a.unwrap_or(0.5 * start.coil.max_current.a());
    let full_scale = measured.torque_nm.iter().copied().fold(0.0, f64::max).max(f64::MIN_POSITIVE);
    let weight = full_scale * (measured.torque_nm.len() as f64 / (2.0 * frd.len() as f64)).sqrt();
    Ok(FrequencyTarget { source, measured: frd, options, bias_a, weight })
}

/// The torques of an analysis's curve.
fn torques(analysis: &Analysis) -> Vec<f64> {
    analysis.torque_current_curve.iter().map(|p| p.torque_nm).collect()
}

/// The design model: a trial point's predicted curve (and frequency response).
struct Model<'a> {
    space: &'a DesignSpace,
    options: AnalysisOptions,
    measured: &'a [f64],
    frd: Option<&'a FrequencyTarget>,
}

impl Model<'_> {
    /// The spec, analysis and (with frequency data) predicted response of a valid brake.
    fn run(&self, spec: &BrakeSpec) -> Result<(Analysis, Option<Frd>), ExploreError> {
        let analysis = AnalysisRequest::of(spec).options(self.options).run()?;
        let frd = match self.frd {
            Some(target) => {
                let model = ResponseModel::new(spec, &target.options)?;
                Some(model.frequency_response(target.bias_a)?.1)
            }
            None => None,
        };
        Ok((analysis, frd))
    }

    /// The spec, analysis and predicted response at `x`.
    fn analyse(&self, x: &[f64]) -> Result<(BrakeSpec, Analysis, Option<Frd>), ExploreError> {
        let design = self.space.design(x)?;
        let spec = design.spec.map_err(|source| ExploreError::InvalidBase {
            what: "the calibrated design",
            source,
        })?;
        let (analysis, frd) = self.run(&spec)?;
        Ok((spec, analysis, frd))
    }

    /// Predicted − measured (the frequency block weighted, [`FrequencyTarget::weight`]); NaN at
    /// a point that is not a valid brake (the step is rejected).
    fn residual(&self, x: &[f64]) -> Result<Vec<f64>, ExploreError> {
        let n = self.measured.len() + self.frd.map_or(0, |t| 2 * t.measured.len());
        let design = self.space.design(x)?;
        let Ok(spec) = design.spec else {
            return Ok(vec![f64::NAN; n]);
        };
        let (analysis, frd) = self.run(&spec)?;
        let curve = &analysis.torque_current_curve;
        if curve.len() != self.measured.len() {
            return Err(ExploreError::Internal(format!(
                "the analysis gave {} points, {} asked for",
                curve.len(),
                self.measured.len()
            )));
        }
        let mut r: Vec<f64> =
            curve.iter().zip(self.measured).map(|(p, m)| p.torque_nm - m).collect();
        if let (Some(target), Some(predicted)) = (self.frd, frd) {
            for (p, m) in predicted.responses().zip(target.measured.responses()) {
                let d = p - m;
                r.extend([target.weight * d.re, target.weight * d.im]);
            }
        }
        Ok(r)
    }
}

/// Reads `text` (`PATH` or `PATH=LOW..HIGH`) as a parameter of the spec `spec_toml` (SI TOML).
pub fn parse_parameter(
    text: &str,
    spec_toml: &str,
    is_drum: bool,
) -> Result<ParameterRequest, ExploreError> {
    let bad = |why: String| ExploreError::input("--parameter", format!("'{text}': {why}"));
    let (path, range) = match text.split_once('=') {
        Some((p, r)) => (p.trim(), Some(r.trim())),
        None => (text.trim(), None),
    };
    let variable = resolve(path, is_drum)?;
    let field = match variable.quantity() {
        Some(Quantity::Integer) => {
            return Err(bad("a whole-number field cannot be fitted by least squares".into()));
        }
        None => return Err(bad("a material cannot be fitted by least squares".into())),
        Some(_) => field_bounds(&variable),
    };
    let nominal = nominal_value(spec_toml, &variable)?;
    // Given bounds must lie in the field's range; the default ones are cut to it (a fill
    // fraction of 1 gets [0.5, 1]).
    let (lower, upper) = match range {
        Some(range) => {
            let (lo, hi) = range
                .split_once("..")
                .ok_or_else(|| bad("bounds are written LOW..HIGH, e.g. 0.5..1.2".into()))?;
            (variable.parse_value(lo)?, variable.parse_value(hi)?)
        }
        None => match nominal {
            Some(v) if v > 0.0 => (
                (v * (1.0 - DEFAULT_SPAN)).max(field.min),
                (v * (1.0 + DEFAULT_SPAN)).min(field.max),
            ),
            _ => {
                return Err(bad(
                    "its value is zero or not given: give bounds, PATH=LOW..HIGH".into()
                ));
            }
        },
    };
    let inside = field.contains(lower) && field.contains(upper);
    if !(lower.is_finite() && upper.is_finite() && lower < upper && inside) {
        return Err(bad(format!(
            "the bounds must satisfy LOW < HIGH inside the field's range {}",
            field.describe(variable.quantity().map_or("", Quantity::unit))
        )));
    }
    let start = nominal.unwrap_or(0.5 * (lower + upper)).clamp(lower, upper);
    Ok(ParameterRequest { name: path.to_string(), variable, lower, upper, start })
}

/// The field's own range.
fn field_bounds(variable: &Variable) -> mrbrake_design::spec::Bounds {
    mrbrake_design::spec::numeric_fields()
        .find(|f| f.path == variable.path())
        .map_or(mrbrake_design::spec::Bounds::closed(f64::MIN, f64::MAX), |f| f.bounds)
}

/// The value of `variable`'s field in a spec's TOML (a number in SI or a quantity with its unit),
/// or the default of a factor table's field the spec leaves out (1 for the factors, 0 for a drag
/// torque not given, the library's for a conductivity); `None` when neither is known.
fn nominal_value(spec_toml: &str, variable: &Variable) -> Result<Option<f64>, ExploreError> {
    let path = variable.path();
    let table: toml::Table = toml::from_str(spec_toml)
        .map_err(|e| ExploreError::Internal(format!("a design's TOML does not parse: {e}")))?;
    let mut value = toml::Value::Table(table.clone());
    for part in path.split('.') {
        match value.get(part) {
            Some(v) => value = v.clone(),
            None => return Ok(default_value(path, &table)),
        }
    }
    Ok(match value {
        toml::Value::Float(x) => Some(x),
        toml::Value::Integer(i) => Some(i as f64),
        toml::Value::String(text) => Some(variable.parse_value(&text)?),
        _ => None,
    })
}

fn default_value(path: &str, spec: &toml::Table) -> Option<f64> {
    // A conductivity the spec does not give is its material's in the library.
    let material = match path {
        "steel.conductivity_S_per_m" => Some("flux_path"),
        "fluid.conductivity_S_per_m" => Some("fluid"),
        _ => None,
    };
    if let Some(role) = material {
        let name = spec.get("materials")?.get(role)?.as_str()?;
        let material = mrbrake_materials::library::get(name).ok()?;
        return material.conductivity_s_per_m.as_ref().map(|c| c.value);
    }
    let (table, key) = path.split_once('.')?;
    let defaults = match table {
        "fluid" => serde_json::to_value(mrbrake_design::spec::FluidFactors::default()).ok()?,
        "steel" => serde_json::to_value(mrbrake_design::spec::SteelFactors::default()).ok()?,
        "drag" => return Some(0.0),
        _ => return None,
    };
    defaults.get(key)?.as_f64()
}

/// The loop of the log at `currents` (module docs).
fn measure(log: &Path, currents: &[f64]) -> Result<MeasuredLoop, ExploreError> {
    let source = log.display().to_string();
    let characterized = CharacterizationRequest::new(log).run().map_err(|e| match e {
        // A loop the characterisation cannot read names its column; the log names the file.
        mrbrake_sysid::SysidError::Input(f) if f.file.is_none() => {
            ExploreError::Input(Box::new(f.in_file(&source, None)))
        }
        other => ExploreError::Sysid(other),
    })?;
    let c = &characterized.characterization;
    let max_current = currents[currents.len() - 1];
    if c.current_max_a < max_current * (1.0 - CURRENT_COVERAGE_TOLERANCE) {
        return Err(log_error(
            &source,
            format!(
                "its currents reach {:.4} A, short of the spec's maximum current {max_current} A: \
                 the loop must cover the range the model predicts",
                c.current_max_a
            ),
        ));
    }
    let rising: Vec<f64> = currents.iter().map(|&i| interpolate(&c.rising_mean, i)).collect();
    let falling: Vec<f64> = currents.iter().map(|&i| interpolate(&c.falling_mean, i)).collect();
    let torque: Vec<f64> = rising.iter().zip(&falling).map(|(r, f)| 0.5 * (r + f)).collect();
    let sample_noise_nm = sample_noise(characterized.torque_nm());
    let averaged = averaged_samples(c);
    Ok(MeasuredLoop {
        source,
        current_a: currents.to_vec(),
        torque_nm: torque,
        rising_nm: rising,
        falling_nm: falling,
        sample_noise_nm,
        point_noise_nm: sample_noise_nm / averaged.sqrt(),
        current_range_a: (c.current_min_a, c.current_max_a),
        repetitions: c.repetitions,
    })
}

fn log_error(source: &str, message: String) -> ExploreError {
    ExploreError::input("--log", message).in_file(source)
}

/// Samples averaged into one compared point: the two branches' samples per bin, summed.
fn averaged_samples(c: &Characterization) -> f64 {
    let per_bin = |samples: usize, bins: usize| samples as f64 / bins.max(1) as f64;
    (per_bin(c.rising.samples, c.rising_mean.len())
        + per_bin(c.falling.samples, c.falling_mean.len()))
    .max(1.0)
}

/// `MAD(ΔT) / (0.6745 √2)` (module docs).
fn sample_noise(torque: &[f64]) -> f64 {
    // A log's samples are finite (the reader's rule); no differences (one sample) is no noise.
    let median = |v: &[f64]| mrbrake_uq::statistics::percentile(v, 0.5).unwrap_or(0.0);
    let differences: Vec<f64> = torque.windows(2).map(|w| w[1] - w[0]).collect();
    let centre = median(&differences);
    let deviations: Vec<f64> = differences.iter().map(|d| (d - centre).abs()).collect();
    median(&deviations) / (0.674_489_750_196_081_7 * std::f64::consts::SQRT_2)
}

/// Linear interpolation in a branch's binned means (sorted by current), held at the ends.
fn interpolate(points: &[(f64, f64)], x: f64) -> f64 {
    let (Some(first), Some(last)) = (points.first(), points.last()) else { return f64::NAN };
    crate::uncertainty::band::torque_at(points, x.clamp(first.0, last.0)).unwrap_or(f64::NAN)
}

fn fitted_parameters(parameters: &[ParameterRequest], fit: &Calibration) -> Vec<FittedParameter> {
    parameters
        .iter()
        .enumerate()
        .map(|(j, p)| FittedParameter {
            name: p.name.clone(),
            path: p.variable.path().to_string(),
            unit: p.variable.quantity().map_or("", Quantity::unit),
            start: p.start,
            estimate: fit.estimate[j],
            standard_error: fit.standard_error[j],
            lower: p.lower,
            upper: p.upper,
            at_bound: fit.at_bound[j],
        })
        .collect()
}

/// The spec's own text with the fixed changes and the estimates set in place (SI numbers), each
/// estimate with a comment saying where it came from; every other line kept.
fn calibrated_text(
    request: &CalibrationRequest,
    fitted: &[FittedParameter],
    measured: &MeasuredLoop,
    is_drum: bool,
) -> Result<String, ExploreError> {
    let mut document: DocumentMut =
        request.spec_toml.parse().map_err(|e: toml_edit::TomlError| {
            ExploreError::input("", e.to_string()).in_file(&request.spec_origin)
        })?;
    for (path, text) in &request.overrides {
        let (path, value) = crate::front::override_value(path, text, is_drum)?;
        crate::front::set_value(&mut document, &path, value)?;
    }
    for p in fitted {
        // Removed first: a replaced value would keep its old comment, and the provenance
        // replaces it.
        let mut value = Value::from(p.estimate);
        let unit = if p.unit.is_empty() { String::new() } else { format!(" {}", p.unit) };
        value.decor_mut().set_suffix(format!(
            "  # calibrated: {:.6e} ± {:.2e}{unit} (1 s.e.), from {:.6e}; mrbrake calibrate on {}",
            p.estimate, p.standard_error, p.start, measured.source
        ));
        crate::front::set_value(&mut document, &p.path, None)?;
        crate::front::set_value(&mut document, &p.path, Some(value))?;
    }
    Ok(document.to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    const SPEC: &str = include_str!("../../../examples/specs/thesis-bidirectional.toml");

    fn si_spec() -> String {
        let space = DesignSpace::new(SPEC, "thesis", &[], &[], EvaluationSettings::default());
        space.unwrap().base_design().unwrap().spec_toml
    }

    #[test]
    fn the_noise_of_white_samples_on_a_ramp_is_found() {
        // Deterministic pseudo-normal noise (sum of 12 uniforms − 6) of σ = 0.01 on a slow ramp.
        let mut state = 0x2545_f491_4f6c_dd1du64;
        let mut uniform = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        let torque: Vec<f64> = (0..20_000)
            .map(|k| 1e-4 * k as f64 + 0.01 * ((0..12).map(|_| uniform()).sum::<f64>() - 6.0))
            .collect();
        let sigma = sample_noise(&torque);
        assert!((sigma - 0.01).abs() < 0.0005, "{sigma}");
        assert!(sample_noise(&[1.0]).abs() < 1e-300);
    }

    #[test]
    fn branches_are_interpolated_linearly_and_held_at_their_ends() {
        let points = [(0.0, 1.0), (1.0, 3.0), (2.0, 4.0)];
        assert!((interpolate(&points, 0.5) - 2.0).abs() < 1e-12);
        assert!((interpolate(&points, 1.5) - 3.5).abs() < 1e-12);
        assert!((interpolate(&points, -1.0) - 1.0).abs() < 1e-12);
        assert!((interpolate(&points, 9.0) - 4.0).abs() < 1e-12);
        assert!(interpolate(&[], 1.0).is_nan());
    }

    #[test]
    fn parameters_take_their_start_from_the_spec_and_default_bounds_around_it() {
        let spec = si_spec();
        let gap = parse_parameter("drum.gap", &spec, true).unwrap();
        assert!((gap.start - 0.5e-3).abs() < 1e-15);
        assert!((gap.lower - 0.25e-3).abs() < 1e-15 && (gap.upper - 0.75e-3).abs() < 1e-15);
        // A factor the spec leaves out starts at its default, its bounds inside its range.
        let fill = parse_parameter("fluid.fill_fraction", &spec, true).unwrap();
        assert!((fill.start - 1.0).abs() < 1e-15 && (fill.upper - 1.0).abs() < 1e-15);
        let seal = parse_parameter("drag.seal_torque=0..50mNm", &spec, true).unwrap();
        assert_eq!(seal.name, "drag.seal_torque");
        assert!(seal.start.abs() < 1e-15 && (seal.upper - 0.05).abs() < 1e-15);
        assert!(parse_parameter("drag.seal_torque", &spec, true).is_err());
        // The spec's own text (an invalid base is kept as written): a quantity with its unit.
        let written = parse_parameter("drum.gap=0.3mm..1.2mm", SPEC, true).unwrap();
        assert!((written.start - 0.5e-3).abs() < 1e-15, "{}", written.start);
        // A conductivity the spec does not give starts at the library's value of its steel.
        let sigma = parse_parameter("steel.conductivity_S_per_m", &spec, true).unwrap();
        let library = mrbrake_materials::library::get("steel-1008").unwrap();
        let expected = library.conductivity_s_per_m.as_ref().unwrap().value;
        assert!((sigma.start - expected).abs() < 1e-6 * expected, "{}", sigma.start);
        assert!(parse_parameter("drum.gap=1mm..0.5mm", &spec, true).is_err());
        assert!(parse_parameter("fluid.fill_fraction=0.5..2", &spec, true).is_err());
        assert!(parse_parameter("fluid.yield_stress_scale=0..1", &spec, true).is_err());
        assert!(parse_parameter("coil.turns", &spec, true).is_err());
    }

    #[test]
    fn the_compared_currents_run_from_zero_to_the_maximum() {
        let c = compared_currents(2.0, 5);
        assert_eq!(c.len(), 5);
        assert!(c[0].abs() < 1e-15 && (c[4] - 2.0).abs() < 1e-15 && (c[1] - 0.5).abs() < 1e-15);
        assert!((residual_scale(10, 2) - (10.0f64 / 8.0).sqrt()).abs() < 1e-15);
        assert!(residual_scale(2, 2).is_infinite());
    }
}
