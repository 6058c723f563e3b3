//! The cascade of one design (see the module docs of [`super`]): each level's analyses on one
//! response model and one heat solver, the gates between levels, and the check of a study's
//! metrics before its first design.
//!
//! Every metric is the value of the command's JSON for the same design and settings:
//! `bandwidth_rad_s` of `mrbrake response --bias B` (`bandwidth_dir2_rad_s` the same analysis of
//! direction 2's coils and gaps: [`ResponseModel::frequency_response_of`]), `t63_s`/`t90_s` of `step[d]` of `mrbrake
//! response --step FROM..TO`, the fall times of `--step TO..FROM`; `coil_max_T_C` is
//! `steady.coil_max_T_C`, `continuous_current_A`, `max_duty_at_max_current` and
//! `time_to_limit_s` those of `mrbrake thermal`, and `continuous_torque_Nm` is
//! `behaviour.torque_hot_current_drive_Nm` (current drive) or
//! `behaviour.voltage_drive.torque_hot_Nm` (voltage drive) of `mrbrake thermal --current
//! <continuous_current_A> --duty 1`. A figure the command gives as `null` — a time not reached
//! within the run or not resolved by its steps, a bandwidth above the highest frequency, a coil
//! without a steady state (thermal runaway) — is stored as the bound the analysis does give
//! (module docs of [`super`]).

use std::sync::Arc;

use mrbrake_design::geometry::BrakeGeometry;
use mrbrake_design::mesh_build;
use mrbrake_design::response::{ResponseDrive, ResponseModel, ResponseOptions, check_options};
use mrbrake_design::spec::BrakeSpec;
use mrbrake_design::thermal::ThermalOptions;
use mrbrake_design::thermal::session::{ThermalSession, check_thermal_data};
use mrbrake_fem::mesh::Mesh;
use mrbrake_store::{MetricValue, Status};

use mrbrake_sysid::frd::Frd;

use super::{Analysis, HapticDynamics, StudyMetrics, count_run};
use crate::ExploreError;
use crate::evaluate::{EvaluationSettings, Outcome, with_causes};

/// A figure that may be beyond the analysed range (`None`) as a metric: its value, or `beyond`.
fn or_bound(value: Option<f64>, beyond: MetricValue) -> MetricValue {
    value.map_or(beyond, MetricValue::Value)
}

/// A step response's rise time to `fraction` (`t63_s`, `t90_s`), or its bound when the response
/// gives none: `AtMost` the end of the time step holding the crossing when the steps do not
/// resolve it, `AtLeast` the run when it is not reached
/// ([`mrbrake_design::response::resolved_rise_time`]).
fn rise_time_metric(
    resolved: Option<f64>,
    time: &[f64],
    torque: &[f64],
    fraction: f64,
) -> MetricValue {
    if let Some(t) = resolved {
        return MetricValue::Value(t);
    }
    let end = time.last().copied().unwrap_or(0.0);
    match mrbrake_design::response::rise_time(time, torque, fraction) {
        Some(t) => {
            let k = time.partition_point(|&s| s < t).min(time.len().saturating_sub(1));
            MetricValue::AtMost(time.get(k).copied().unwrap_or(end))
        }
        None => MetricValue::AtLeast(end),
    }
}

/// What one analysis gives, or why it could not: the error text and whether it was the design's
/// (input: infeasible) or numerical (failed).
type Figures = Result<Vec<(&'static str, MetricValue)>, (String, bool)>;

fn failure<E: std::error::Error + mrbrake_error::Kind>(e: E) -> (String, bool) {
    (with_causes(&e), e.is_input_error())
}

/// One design's models, built when an analysis first needs them.
struct Models<'s> {
    spec: &'s BrakeSpec,
    response_options: &'s ResponseOptions,
    thermal_options: ThermalOptions,
    drive: ResponseDrive,
    /// The geometry and its mesh at the study's level, one for every analysis of the design.
    mesh: Option<(BrakeGeometry, Arc<Mesh>)>,
    response: Option<ResponseModel<'s>>,
    thermal: Option<ThermalSession<'s>>,
    /// The small-signal frequency response and its bias (A), once computed (the haptic wall's
    /// predicted dynamics are fitted to it).
    frequency_response: Option<(Frd, f64)>,
    /// The study's settings (the haptic wall analyses the design's brake model with them).
    evaluation: &'s EvaluationSettings,
}

impl<'s> Models<'s> {
    fn mesh(&mut self) -> Result<(BrakeGeometry, Arc<Mesh>), (String, bool)> {
        if self.mesh.is_none() {
            let geometry = self.spec.validate().map_err(failure)?.geometry;
            let level = self.response_options.mesh;
            let mesh = mesh_build::mesh_spec(self.spec, &geometry, level).map_err(failure)?;
            self.mesh = Some((geometry, Arc::new(mesh)));
        }
        let (geometry, mesh) = self.mesh.as_ref().expect("built above");
        Ok((geometry.clone(), Arc::clone(mesh)))
    }

    fn response(&mut self) -> Result<&ResponseModel<'s>, (String, bool)> {
        if self.response.is_none() {
            let (geometry, mesh) = self.mesh()?;
            let model = ResponseModel::on_mesh(self.spec, self.response_options, geometry, mesh);
            self.response = Some(model.map_err(failure)?);
        }
        Ok(self.response.as_ref().expect("built above"))
    }

    fn thermal(&mut self) -> Result<&mut ThermalSession<'s>, (String, bool)> {
        if self.thermal.is_none() {
            let (geometry, mesh) = self.mesh()?;
            let session =
                ThermalSession::on_mesh(self.spec, &self.thermal_options, &geometry, &mesh);
            self.thermal = Some(session.map_err(failure)?);
        }
        Ok(self.thermal.as_mut().expect("built above"))
    }

    /// The step currents (from, to) of the step up.
    fn step_currents(&self) -> (f64, f64) {
        let o = self.response_options;
        (o.step_from_a, o.step_to_a.unwrap_or_else(|| self.spec.coil.max_current.a()))
    }

    fn run(&mut self, analysis: Analysis) -> Figures {
        match analysis {
            Analysis::StepUp1 | Analysis::StepUp2 | Analysis::Release1 | Analysis::Release2 => {
                let (from, to) = self.step_currents();
                self.steps(analysis, from, to)
            }
            Analysis::Frequency | Analysis::Frequency2 => self.bandwidth(analysis),
            _ => {
                count_run(analysis);
                self.run_counted(analysis)
            }
        }
    }

    /// The step responses: up from `from` to `to` amperes, or the release back.
    fn steps(&mut self, analysis: Analysis, from: f64, to: f64) -> Figures {
        match analysis {
            Analysis::StepUp1 => self.step(analysis, (0, from, to), ["t63_s", "t90_s"]),
            Analysis::StepUp2 => self.step(analysis, (1, from, to), ["t63_dir2_s", "t90_dir2_s"]),
            Analysis::Release1 => self.step(analysis, (0, to, from), ["t63_fall_s", "t90_fall_s"]),
            _ => self.step(analysis, (1, to, from), ["t63_fall_dir2_s", "t90_fall_dir2_s"]),
        }
    }

    /// The analyses other than the step responses.
    fn run_counted(&mut self, analysis: Analysis) -> Figures {
        match analysis {
            Analysis::ThermalSteady => {
                let limit = self.thermal_options.limit_c;
                let steady = self.thermal()?.steady().map(|s| s.coil_max_t_c);
                Ok(vec![("coil_max_T_C", or_bound(steady, MetricValue::AtLeast(limit)))])
            }
            Analysis::ThermalRating => {
                let session = self.thermal()?;
                let current = session.continuous_current_a().map_err(failure)?;
                let duty = session.max_duty_at_max_current().map_err(failure)?;
                Ok(vec![
                    ("continuous_current_A", current.into()),
                    ("max_duty_at_max_current", duty.into()),
                ])
            }
            Analysis::Warmup => {
                let run = self.thermal_options.time_s;
                let time = self.thermal()?.time_to_limit_s().map_err(failure)?;
                Ok(vec![("time_to_limit_s", or_bound(time, MetricValue::AtLeast(run)))])
            }
            Analysis::HotTorque => self.hot_torque(),
            _ => {
                let study = &self.evaluation.study;
                let frd = match study.haptic.dynamics {
                    HapticDynamics::Predicted => {
                        let (frd, bias) = self.frequency_response.as_ref().ok_or_else(|| {
                            ("the haptic wall ran before the small-signal response".into(), false)
                        })?;
                        Some((frd, *bias, self.drive))
                    }
                    HapticDynamics::Thesis => None,
                };
                super::haptic::haptic_metrics(self.spec, self.evaluation, &study.haptic, frd)
            }
        }
    }

    /// The step response (`analysis`) of direction `unit + 1` from `from` to `to` amperes: its
    /// t63 and t90 under `names`; nothing for a direction the brake does not have (as `torque_dir2_Nm`).
    fn step(
        &mut self,
        analysis: Analysis,
        (unit, from, to): (usize, f64, f64),
        names: [&'static str; 2],
    ) -> Figures {
        let model = self.response()?;
        if unit >= model.units() {
            let none = MetricValue::NotApplicable;
            return Ok(vec![(names[0], none), (names[1], none)]);
        }
        count_run(analysis);
        let step = model.step(unit, from, to).map_err(failure)?;
        let (time, torque) = (&step.time_s, &step.torque_nm);
        Ok(vec![
            (names[0], rise_time_metric(step.t63_s, time, torque, 0.63)),
            (names[1], rise_time_metric(step.t90_s, time, torque, 0.9)),
        ])
    }

    /// The −3 dB bandwidth of direction 1 (`bandwidth_rad_s`; its response is kept for the
    /// haptic wall) or 2 (`bandwidth_dir2_rad_s`; not applicable to a brake with one direction),
    /// each from the small-signal response of its own coils and gaps at the study's bias.
    fn bandwidth(&mut self, analysis: Analysis) -> Figures {
        let max = self.spec.coil.max_current.a();
        let bias = self.response_options.bias_a.unwrap_or(0.5 * max);
        let (unit, name) = match analysis {
            Analysis::Frequency => (0, "bandwidth_rad_s"),
            _ => (1, "bandwidth_dir2_rad_s"),
        };
        let model = self.response()?;
        if unit >= model.units() {
            return Ok(vec![(name, MetricValue::NotApplicable)]);
        }
        count_run(analysis);
        let (_, frd, bandwidth) = model.frequency_response_of(unit, bias).map_err(failure)?;
        let highest = frd.points.last().map_or(0.0, |p| p.omega_rad_s);
        let metric = or_bound(bandwidth, MetricValue::AtLeast(highest));
        if unit == 0 {
            self.frequency_response = Some((frd, bias));
        }
        Ok(vec![(name, metric)])
    }

    /// The torque held for ever: at the continuous current, hot coil and fluid (module docs).
    fn hot_torque(&mut self) -> Figures {
        let drive = self.drive;
        let session = self.thermal()?;
        let current = session.continuous_current_a().map_err(failure)?;
        if current <= 0.0 {
            return Err((
                "the coil reaches its limit without current: no continuous torque".into(),
                true,
            ));
        }
        let behaviour = session.hot_behaviour_at(current).map_err(failure)?.ok_or_else(|| {
            (format!("no steady state at the continuous current {current} A"), false)
        })?;
        let torque = match drive {
            ResponseDrive::Current => behaviour.torque_hot_current_drive_nm,
            ResponseDrive::Voltage => behaviour.voltage_drive.torque_hot_nm,
        };
        Ok(vec![("continuous_torque_Nm", torque.into())])
    }
}

/// The expensive levels of one design whose static `metrics` are known (module docs of
/// [`super`]): the outcome with every metric computed, or why the cascade stopped.
pub(crate) fn cascade(
    spec: &BrakeSpec,
    settings: &EvaluationSettings,
    mut metrics: Vec<(String, MetricValue)>,
) -> Outcome {
    let study = &settings.study;
    // Only what the known metrics lack (all of the asked-for ones for a new design).
    let analyses = study.analyses_missing(&metrics);
    let response_options = study.response.options(settings);
    let mut models = Models {
        spec,
        response_options: &response_options,
        thermal_options: study.thermal.options(spec, settings),
        drive: study.response.drive,
        mesh: None,
        response: None,
        thermal: None,
        frequency_response: None,
        evaluation: settings,
    };
    for level in 1..=3 {
        let at_level: Vec<Analysis> =
            analyses.iter().copied().filter(|a| a.level() == level).collect();
        if at_level.is_empty() {
            continue;
        }
        if let Some(reason) = study.violated_gate(&metrics) {
            let skipped: Vec<&str> =
                analyses.iter().filter(|a| a.level() >= level).map(|a| a.name()).collect();
            let reason = format!("{reason}{}{}", super::SKIPPED, skipped.join(", "));
            return Outcome { status: Status::Infeasible, reason: Some(reason), metrics };
        }
        for analysis in at_level {
            match models.run(analysis) {
                Ok(figures) => {
                    // An analysis run again for another's sake (the small-signal response for
                    // the haptic wall) keeps the stored figures.
                    for (name, value) in figures {
                        if !metrics.iter().any(|(known, _)| known == name) {
                            metrics.push((name.to_string(), value));
                        }
                    }
                }
                Err((error, input)) => {
                    let status = if input { Status::Infeasible } else { Status::Failed };
                    let reason = format!("{}: {error}", analysis.name());
                    return Outcome { status, reason: Some(reason), metrics };
                }
            }
        }
    }
    if let Some((name, value)) = metrics.iter().find(|(_, v)| v.number().is_some_and(f64::is_nan)) {
        let reason = format!("the analysis gave {name} = {value}: not a result");
        return Outcome { status: Status::Failed, reason: Some(reason), metrics };
    }
    Outcome { status: Status::Ok, reason: None, metrics }
}

/// See [`StudyMetrics::check`].
pub(super) fn check(
    study: &StudyMetrics,
    spec: &BrakeSpec,
    evaluation: &EvaluationSettings,
) -> Result<(), ExploreError> {
    let analyses = study.analyses();
    let first = |thermal: bool| {
        study
            .requested()
            .iter()
            .find(|m| super::analysis_of(m).is_some_and(|a| a.is_thermal() == thermal))
            .copied()
            .unwrap_or("")
    };
    if analyses.iter().any(|a| !a.is_thermal() && *a != Analysis::Haptic) {
        let metric = first(false);
        check_options(&study.response.options(evaluation))
            .map_err(|e| ExploreError::from(e).under("response").for_metric(metric))?;
        if study.response.conductivity_s_per_m.is_none() {
            let name = &spec.materials.flux_path;
            let material = mrbrake_materials::library::get(name)?;
            if material.conductivity_s_per_m.is_none() {
                return Err(ExploreError::input(
                    "response.conductivity",
                    format!(
                        "metric '{metric}' needs the electrical conductivity of the flux-path \
                         steel '{name}', which the material library does not give: set [response] \
                         conductivity (e.g. \"5.8MS/m\")"
                    ),
                ));
            }
        }
    }
    if analyses.contains(&Analysis::Haptic) {
        let metric = study
            .requested()
            .iter()
            .find(|m| super::analysis_of(m) == Some(Analysis::Haptic))
            .copied()
            .unwrap_or("");
        study
            .haptic
            .config()
            .map_err(|e| ExploreError::input("haptic", e.to_string()).for_metric(metric))?;
    }
    if analyses.iter().any(|a| a.is_thermal()) {
        let metric = first(true);
        let options = study.thermal.options(spec, evaluation);
        mrbrake_design::thermal::validate_options(&options).map_err(|e| match e {
            mrbrake_design::thermal::ThermalError::Input(field) => {
                ExploreError::Input(field).under("thermal").for_metric(metric)
            }
            other => ExploreError::input("thermal", other.to_string()).for_metric(metric),
        })?;
        if spec.validate().is_ok() {
            check_thermal_data(spec).map_err(|e| {
                ExploreError::input("", format!("metric '{metric}' needs thermal data: {e}"))
            })?;
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A rise time the steps resolve is the value; one they do not is at most the end of the step
    /// holding the crossing (a first-order lag with τ = 1 ms sampled every 5 ms).
    #[test]
    fn an_unresolved_rise_time_is_an_upper_bound() {
        let time: Vec<f64> = (0..20).map(|k| 5e-3 * k as f64).collect();
        let torque: Vec<f64> = time.iter().map(|t| 1.0 - (-t / 1e-3).exp()).collect();
        let resolved = mrbrake_design::response::resolved_rise_time(&time, &torque, 0.63);
        assert_eq!(resolved, None, "a 5 ms step does not resolve a 1 ms crossing");
        let metric = rise_time_metric(resolved, &time, &torque, 0.63);
        assert_eq!(metric, MetricValue::AtMost(5e-3));
        assert_eq!(rise_time_metric(Some(2e-3), &time, &torque, 0.63), MetricValue::Value(2e-3));
    }
}
