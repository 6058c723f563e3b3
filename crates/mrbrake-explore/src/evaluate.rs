//! One design evaluation: the real FEA analysis (`mrbrake analyze` at zero and maximum current)
//! reduced to the named metrics that studies constrain, optimise and store.
//!
//! Brief overview: [`EvaluationSettings`] fixes what every evaluation of a study shares (mesh level,
//! speed for the viscous torque, friction, copper temperature, convection coefficient);
//! [`evaluate`] runs [`mrbrake_design::analysis::AnalysisRequest`] with a two-point sweep (off state and
//! maximum current) and returns an [`Outcome`]: `ok` with [`METRICS`], `infeasible` with the reason
//! (the spec breaks a rule: overlapping parts, a coil that does not fit, …), or `failed` with the
//! numerical error (e.g. Newton not converging, with its history). Nothing is approximated by a
//! surrogate: every number comes from the field solution and the thesis's formulas.

use mrbrake_design::analysis::{Analysis, AnalysisOptions, AnalysisRequest, ElementOrder};
use mrbrake_design::mesh_build::MeshLevel;
use mrbrake_design::spec::{BrakeSpec, WorkingSurfaces};
use mrbrake_error::Kind as _;
use mrbrake_store::{MetricValue, Status};
use serde_json::{Value, json};

use crate::ExploreError;

/// What all evaluations of a study share.
#[derive(Debug, Clone, PartialEq)]
pub struct EvaluationSettings {
    /// Mesh density of every analysis.
    pub mesh: MeshLevel,
    /// Relative speed for the viscous (off-state) torque (rad/s).
    pub speed_rad_s: f64,
    /// Constant seal / bearing friction added to every torque (N·m).
    pub seal_friction_nm: f64,
    /// Copper temperature for the coil resistance (°C).
    pub temperature_c: f64,
    /// Heat-transfer coefficient from the device's outer surface to the room (W/(m²·K)) for the
    /// steady temperature rise; 10 W/(m²·K) is still air (free convection of gases, 2–25 W/(m²·K):
    /// Incropera & DeWitt, *Fundamentals of Heat and Mass Transfer*, Table 1.1).
    pub convection_w_m2k: f64,
    /// Finite-element order of every field solution (P1 or P2).
    pub order: ElementOrder,
    /// The dynamics and heat metrics the study asks for, with their settings (default: none, a
    /// static-only study); see [`crate::metrics`].
    pub study: crate::metrics::StudyMetrics,
    /// Currents of each analysis's torque–current sweep, evenly from 0 A to the maximum current
    /// (2 to [`MAX_CURVE_POINTS`]; default 2: the off state and the maximum current, what every
    /// static metric needs). Above 2 every point is also stored as a metric
    /// ([`torque_curve_metric`]), so a study keeps each design's curve (`mrbrake uncertainty`'s
    /// torque band); the count is part of the design key, as before (`points`).
    pub curve_points: usize,
}

/// Most currents of a study's torque–current sweep ([`EvaluationSettings::curve_points`]): each is
/// a Newton solve of every design.
pub const MAX_CURVE_POINTS: usize = 41;

impl Default for EvaluationSettings {
    fn default() -> Self {
        let analysis = AnalysisOptions::default();
        Self {
            mesh: MeshLevel::Default,
            speed_rad_s: analysis.speed_rad_s,
            seal_friction_nm: analysis.seal_friction_nm,
            temperature_c: analysis.temperature_c,
            convection_w_m2k: 10.0,
            order: analysis.order,
            study: crate::metrics::StudyMetrics::default(),
            curve_points: 2,
        }
    }
}

impl EvaluationSettings {
    /// The settings as a canonical JSON value (part of every design key).
    pub fn canonical(&self) -> Value {
        let mut value = json!({
            "mesh": format!("{:?}", self.mesh).to_ascii_lowercase(),
            "speed_rad_s": self.speed_rad_s,
            "seal_friction_nm": self.seal_friction_nm,
            "temperature_c": self.temperature_c,
            "convection_w_m2k": self.convection_w_m2k,
            "order": self.order.degree(),
            "points": self.curve_points,
        });
        // Only a study asking for more than the static metrics adds its own part, so the keys
        // of static-only studies stay those of before.
        if let Some(study) = self.study.canonical() {
            value["study"] = study;
        }
        value
    }

    /// The settings as every stored record keeps them (`mrbrake export` shows them per row, so
    /// rows of merged stores with different settings can be told apart); names follow
    /// docs/CONVENTIONS.md.
    pub fn recorded(&self) -> serde_json::Map<String, Value> {
        [
            ("mesh_level", json!(format!("{:?}", self.mesh).to_ascii_lowercase())),
            ("element_order", json!(self.order.degree())),
            ("speed_rad_s", json!(self.speed_rad_s)),
            ("seal_friction_Nm", json!(self.seal_friction_nm)),
            ("temperature_C", json!(self.temperature_c)),
            ("convection_W_per_m2_K", json!(self.convection_w_m2k)),
        ]
        .into_iter()
        .map(|(name, value)| (name.to_string(), value))
        // Only a study keeping curves says so: the records of the others stay as before.
        .chain((self.curve_points != 2).then(|| ("curve_points".into(), json!(self.curve_points))))
        .chain(self.study.recorded())
        .collect()
    }

    /// Checks the ranges of the settings (the analysis options' own rules, and a positive,
    /// finite convection coefficient), so a study with a bad setting stops before its first
    /// design instead of storing every design as infeasible.
    pub fn check(&self) -> Result<(), ExploreError> {
        self.analysis_options().check()?;
        if self.curve_points > MAX_CURVE_POINTS {
            let e = mrbrake_error::FieldError::out_of_range(
                "points",
                self.curve_points,
                format!("2..={MAX_CURVE_POINTS}"),
            );
            return Err(e.into());
        }
        let h = self.convection_w_m2k;
        if !(h.is_finite() && h > 0.0) {
            let e = mrbrake_error::FieldError::out_of_range(
                "convection",
                format!("{h} W/(m²·K)"),
                "finite, > 0 W/(m²·K)",
            );
            return Err(e.into());
        }
        Ok(())
    }

    /// The options of the static analysis of every evaluation (`curve_points` currents).
    pub(crate) fn analysis_options(&self) -> AnalysisOptions {
        AnalysisOptions {
            mesh: self.mesh,
            points: self.curve_points,
            speed_rad_s: self.speed_rad_s,
            seal_friction_nm: self.seal_friction_nm,
            temperature_c: self.temperature_c,
            order: self.order,
        }
    }
}

/// A metric's name, unit and meaning.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct MetricInfo {
    /// The name used in stores, CSV files and problem files.
    pub name: &'static str,
    /// SI unit (or `1` for ratios and counts).
    pub unit: &'static str,
    /// What it is.
    pub meaning: &'static str,
}

const fn metric(name: &'static str, unit: &'static str, meaning: &'static str) -> MetricInfo {
    MetricInfo { name, unit, meaning }
}

/// Every metric an `ok` evaluation reports, in store order. `torque_dir2_Nm` and
/// `wire_rated_current_A`/`current_to_rating` appear only where they apply (bidirectional brake; a
/// wire with a known rating).
pub const METRICS: &[MetricInfo] = &[
    metric(
        "torque_max_Nm",
        "N·m",
        "torque at the maximum current, direction 1: local Bingham yield torque + viscous + friction",
    ),
    metric("torque_off_Nm", "N·m", "off-state torque (zero current): viscous (3.4) + friction"),
    metric("dynamic_range", "1", "torque_max_Nm / torque_off_Nm"),
    metric("torque_dir2_Nm", "N·m", "bidirectional: direction 2 with its own coil at max current"),
    metric("thesis_torque_Nm", "N·m", "thesis method: mean |B| in the gaps → τ_y → (4.4)/(3.7)"),
    metric("mean_B_fluid_T", "T", "volume-mean |B| over the direction-1 fluid gaps"),
    metric("max_B_fluid_T", "T", "largest |B| on a gap mid-line"),
    metric("flux_path_max_B_T", "T", "largest |B| at a quadrature point of the steel flux path"),
    metric("flux_path_q90_B_T", "T", "largest per-part 90 % quantile of |B| in the flux path"),
    metric("flux_path_mean_B_T", "T", "volume-mean |B| over the flux path"),
    metric("volume_m3", "m³", "envelope volume of the modelled device (bounding cylinder)"),
    metric("mass_kg", "kg", "mass of all modelled parts"),
    metric("rotor_inertia_kg_m2", "kg·m²", "inertia of the parts turning in direction 1"),
    metric("outer_diameter_m", "m", "outer diameter of the modelled device"),
    metric("length_m", "m", "axial length of the modelled device"),
    metric("torque_density_Nm_per_m3", "N·m/m³", "torque_max_Nm / volume_m3"),
    metric("torque_density_Nm_per_kg", "N·m/kg", "torque_max_Nm / mass_kg"),
    metric("min_gap_m", "m", "narrowest fluid gap"),
    metric(
        "min_wall_m",
        "m",
        "thinnest structural wall: case, end plate, cylinders or discs, covers",
    ),
    metric("max_current_A", "A", "maximum coil current"),
    metric("turns", "1", "turns per coil"),
    metric(
        "fill_factor",
        "1",
        "copper area / window area; above 0.75 (orthocyclic practice) the report warns",
    ),
    metric("current_density_A_per_mm2", "A/mm²", "thesis current density (4.1) at max current"),
    metric("wire_rated_current_A", "A", "the wire's current rating (given or thesis Table 4.6)"),
    metric("current_to_rating", "1", "max_current_A / wire_rated_current_A"),
    metric("resistance_ohm", "Ω", "coil resistance at the settings' temperature"),
    metric("power_W", "W", "ohmic power of one coil at max current"),
    metric(
        "temperature_rise_K",
        "K",
        "steady rise: power_W / (h · outer surface), h = the settings' convection coefficient",
    ),
    metric("inductance_H", "H", "secant inductance λ/I at max current"),
    metric("incremental_inductance_H", "H", "incremental inductance dλ/dI at max current"),
    metric("time_constant_s", "s", "L/R with the secant inductance"),
    metric("nodes", "1", "mesh nodes"),
    metric("newton_iterations", "1", "Newton iterations of the max-current solve"),
    // Dynamics and heat (computed only when asked for: `crate::metrics`; settings in the
    // problem file's [response] and [thermal]).
    metric(
        "bandwidth_rad_s",
        "rad/s",
        "−3 dB bandwidth of the small-signal torque per current at the bias (response, dir. 1)",
    ),
    metric(
        "bandwidth_dir2_rad_s",
        "rad/s",
        "bidirectional: bandwidth_rad_s of direction 2 (its coils and gaps at the same bias)",
    ),
    metric("t63_s", "s", "time to 63 % of the torque change after the current step up"),
    metric("t90_s", "s", "time to 90 % of the torque change after the current step up"),
    metric("t63_dir2_s", "s", "bidirectional: t63_s of direction 2"),
    metric("t90_dir2_s", "s", "bidirectional: t90_s of direction 2"),
    metric(
        "t63_fall_s",
        "s",
        "time to 63 % of the torque change after the step back down (the release)",
    ),
    metric("t90_fall_s", "s", "time to 90 % of the torque change after the release"),
    metric("t63_fall_dir2_s", "s", "bidirectional: t63_fall_s of direction 2"),
    metric("t90_fall_dir2_s", "s", "bidirectional: t90_fall_s of direction 2"),
    metric(
        "coil_max_T_C",
        "°C",
        "steady coil hot spot at the thermal current and duty (runaway: at least the limit)",
    ),
    metric(
        "continuous_current_A",
        "A",
        "current whose steady coil hot spot is the insulation limit",
    ),
    metric(
        "continuous_torque_Nm",
        "N·m",
        "torque at the continuous current, hot coil and fluid (voltage drive: hot resistance)",
    ),
    metric(
        "time_to_limit_s",
        "s",
        "warm-up time of the coil hot spot to the insulation limit (else: at least the run)",
    ),
    metric("max_duty_at_max_current", "1", "largest duty cycle at the maximum current"),
    // Haptics (the design's brake model in `haptic wall`; settings in [haptic]).
    metric(
        "withdraw_excess_torque_Nm",
        "N·m",
        "haptic wall: peak torque holding the hand in the wall beyond the free drag (sticky wall)",
    ),
    metric(
        "release_time_s",
        "s",
        "haptic wall: from the start of the withdrawal to leaving the wall (else: at least the rest)",
    ),
    metric(
        "displayed_stiffness_Nm_per_rad",
        "N·m/rad",
        "haptic wall: stiffness felt while pressing in (least-squares slope)",
    ),
    metric(
        "free_motion_torque_Nm",
        "N·m",
        "haptic wall: peak torque felt in free motion (off-state drag + rotor inertia × acceleration)",
    ),
];

/// Metric names before the unit convention of docs/CONVENTIONS.md (SI symbol with its case after
/// the last underscore), as `(old, new)`. Stores written before keep them in their records and
/// problem files may still name them: [`current_metric_name`] maps them to the current names.
pub const LEGACY_METRIC_NAMES: &[(&str, &str)] = &[
    ("torque_max_nm", "torque_max_Nm"),
    ("torque_off_nm", "torque_off_Nm"),
    ("torque_dir2_nm", "torque_dir2_Nm"),
    ("thesis_torque_nm", "thesis_torque_Nm"),
    ("mean_b_fluid_t", "mean_B_fluid_T"),
    ("max_b_fluid_t", "max_B_fluid_T"),
    ("flux_path_max_b_t", "flux_path_max_B_T"),
    ("flux_path_q90_b_t", "flux_path_q90_B_T"),
    ("flux_path_mean_b_t", "flux_path_mean_B_T"),
    ("torque_density_nm_per_m3", "torque_density_Nm_per_m3"),
    ("torque_density_nm_per_kg", "torque_density_Nm_per_kg"),
    ("max_current_a", "max_current_A"),
    ("current_density_a_per_mm2", "current_density_A_per_mm2"),
    ("wire_rated_current_a", "wire_rated_current_A"),
    ("power_w", "power_W"),
    ("temperature_rise_k", "temperature_rise_K"),
    ("inductance_h", "inductance_H"),
    ("incremental_inductance_h", "incremental_inductance_H"),
];

/// The current name of a metric named `name`, and whether `name` was a legacy name (see
/// [`LEGACY_METRIC_NAMES`]); any other name is returned as it is.
pub fn current_metric_name(name: &str) -> (&str, bool) {
    match LEGACY_METRIC_NAMES.iter().find(|(old, _)| *old == name) {
        Some(&(_, new)) => (new, true),
        None => (name, false),
    }
}

/// Renames a stored record's legacy metric names to the current ones (see
/// [`LEGACY_METRIC_NAMES`]), so a store written before the convention reads like a new one; every
/// reader goes through [`crate::stored`].
pub(crate) fn upgrade_metric_names(record: &mut mrbrake_store::Record) {
    upgrade_metric_list(&mut record.metrics);
}

/// Renames the legacy metric names of a `(name, value)` list to the current ones (see
/// [`upgrade_metric_names`]); the form `mrbrake_store::Store::merge_from_upgrading` takes.
pub(crate) fn upgrade_metric_list(metrics: &mut [(String, MetricValue)]) {
    for (name, _) in metrics {
        if let (new, true) = current_metric_name(name) {
            *name = new.to_string();
        }
    }
}

/// The result of one evaluation.
#[derive(Debug, Clone, PartialEq)]
pub struct Outcome {
    /// ok, infeasible (the design breaks a rule) or failed (numerical failure).
    pub status: Status,
    /// Why it is infeasible or failed.
    pub reason: Option<String>,
    /// The metrics (empty unless ok, or the metrics known when an expensive analysis failed or a
    /// constraint stopped the cascade), in [`METRICS`] order; a dynamics, heat or haptic figure
    /// beyond the analysed range is a bound ([`MetricValue`], see [`crate::metrics`]).
    pub metrics: Vec<(String, MetricValue)>,
}

impl Outcome {
    /// An infeasible design and the rule it breaks.
    pub fn infeasible(reason: impl Into<String>) -> Self {
        Self { status: Status::Infeasible, reason: Some(reason.into()), metrics: Vec::new() }
    }
}

/// Analyses one valid spec and reduces it to metrics. Whatever happens to one design — an input
/// error, a budget, a numerical failure, a NaN metric, even a panic (a defect, reported
/// as such) — is its outcome with the reason, so one bad design never stops a study.
pub fn evaluate(spec: &BrakeSpec, settings: &EvaluationSettings) -> Outcome {
    let run = std::panic::AssertUnwindSafe(|| evaluate_unguarded(spec, settings));
    std::panic::catch_unwind(run).unwrap_or_else(panic_outcome)
}

/// How many static analyses [`evaluate`] has run in this process (a test counts them to show
/// that completing a stored design with more metrics does not analyse it again).
static STATIC_RUNS: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);

/// How many static analyses [`evaluate`] has run in this process.
pub fn static_analysis_count() -> usize {
    STATIC_RUNS.load(std::sync::atomic::Ordering::Relaxed)
}

/// Completes a stored evaluation of `spec` with the expensive metrics the study asks for and
/// `stored` lacks, without analysing the design statically again: the cascade from the stored
/// metrics (see [`crate::metrics`]). Guarded as [`evaluate`].
pub fn complete(
    spec: &BrakeSpec,
    settings: &EvaluationSettings,
    stored: &[(String, MetricValue)],
) -> Outcome {
    let run =
        std::panic::AssertUnwindSafe(|| crate::metrics::cascade(spec, settings, stored.to_vec()));
    // A panic keeps the stored metrics: a completion never drops one.
    std::panic::catch_unwind(run)
        .unwrap_or_else(|payload| Outcome { metrics: stored.to_vec(), ..panic_outcome(payload) })
}

fn panic_outcome(payload: Box<dyn std::any::Any + Send>) -> Outcome {
    let message = payload
        .downcast_ref::<String>()
        .cloned()
        .or_else(|| payload.downcast_ref::<&str>().map(|s| s.to_string()))
        .unwrap_or_default();
    let reason = format!("internal error (a panic, please report this design): {message}");
    Outcome { status: Status::Failed, reason: Some(reason), metrics: vec![] }
}

fn evaluate_unguarded(spec: &BrakeSpec, settings: &EvaluationSettings) -> Outcome {
    STATIC_RUNS.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    match AnalysisRequest::of(spec).options(settings.analysis_options()).run() {
        Ok(analysis) => {
            let metrics = metrics_of(spec, &analysis, settings);
            if let Some((name, value)) =
                metrics.iter().find(|(_, v)| v.number().is_some_and(f64::is_nan))
            {
                let reason = format!("the analysis gave {name} = {value}: not a result");
                return Outcome { status: Status::Failed, reason: Some(reason), metrics: vec![] };
            }
            if settings.study.is_static() {
                return Outcome { status: Status::Ok, reason: None, metrics };
            }
            crate::metrics::cascade(spec, settings, metrics)
        }
        // An input error raised during the analysis (a material that does not suit its part, a
        // mesh the geometry cannot have) is a property of the design: infeasible, not a crash.
        Err(e) if e.is_input_error() => Outcome::infeasible(with_causes(&e)),
        Err(e) => {
            Outcome { status: Status::Failed, reason: Some(with_causes(&e)), metrics: vec![] }
        }
    }
}

/// The error and its causes, `outer: inner: …` (as the CLI prints an error), so that a stored
/// reason keeps what the wrapped error says (e.g. Newton's residual history).
pub(crate) fn with_causes(error: &dyn std::error::Error) -> String {
    let mut text = error.to_string();
    let mut cause = error.source();
    while let Some(e) = cause {
        text.push_str(": ");
        text.push_str(&e.to_string());
        cause = e.source();
    }
    text
}

fn metrics_of(
    spec: &BrakeSpec,
    a: &Analysis,
    settings: &EvaluationSettings,
) -> Vec<(String, MetricValue)> {
    let mut m: Vec<(&'static str, f64)> = Vec::with_capacity(METRICS.len());
    let t = &a.torque;
    m.push(("torque_max_Nm", t.at_max_current_nm));
    m.push(("torque_off_Nm", t.off_state_nm));
    m.push(("dynamic_range", t.dynamic_range));
    if let Some(t2) = t.direction2_at_max_current_nm {
        m.push(("torque_dir2_Nm", t2));
    }
    m.push(("thesis_torque_Nm", t.thesis_formula_nm));
    m.push(("mean_B_fluid_T", t.mean_b_t));
    let max_b_fluid = a.gaps.iter().map(|g| g.max_b_t).fold(0.0, f64::max);
    m.push(("max_B_fluid_T", max_b_fluid));
    m.push(("flux_path_max_B_T", a.flux_path.max_b_t));
    m.push(("flux_path_q90_B_T", a.flux_path.q90_b_t));
    m.push(("flux_path_mean_B_T", a.flux_path.mean_b_t));
    let mech = &a.mechanics;
    m.push(("volume_m3", mech.volume_m3));
    m.push(("mass_kg", mech.mass_kg));
    m.push(("rotor_inertia_kg_m2", mech.rotor_inertia_kg_m2));
    m.push(("outer_diameter_m", mech.outer_diameter_m));
    m.push(("length_m", mech.length_m));
    m.push(("torque_density_Nm_per_m3", mech.torque_density_nm_per_m3));
    m.push(("torque_density_Nm_per_kg", mech.torque_density_nm_per_kg));
    m.push(("min_gap_m", a.gaps.iter().map(|g| g.width_m).fold(f64::INFINITY, f64::min)));
    m.push(("min_wall_m", min_wall_m(spec)));
    m.push(("max_current_A", a.max_current_a));
    let coil = &a.coil;
    m.push(("turns", f64::from(coil.turns)));
    m.push(("fill_factor", coil.fill_factor));
    m.push(("current_density_A_per_mm2", coil.current_density_a_per_mm2));
    if let Some(rating) = spec.coil.wire.rated_current_a() {
        m.push(("wire_rated_current_A", rating));
        m.push(("current_to_rating", a.max_current_a / rating));
    }
    m.push(("resistance_ohm", coil.resistance_ohm));
    m.push(("power_W", coil.power_w));
    // Steady state of a body losing heat through its outer surface only (cylinder side + ends):
    // ΔT = P / (h A) (Newton's law of cooling).
    let (d, l) = (mech.outer_diameter_m, mech.length_m);
    let surface = std::f64::consts::PI * d * l + std::f64::consts::PI * d * d / 2.0;
    m.push(("temperature_rise_K", coil.power_w / (settings.convection_w_m2k * surface)));
    m.push(("inductance_H", coil.inductance_h));
    m.push(("incremental_inductance_H", coil.incremental_inductance_h));
    m.push(("time_constant_s", coil.time_constant_s));
    m.push(("nodes", a.mesh.nodes as f64));
    let iterations = a.torque_current_curve.last().map_or(0, |p| p.newton_iterations);
    m.push(("newton_iterations", iterations as f64));
    let mut metrics: Vec<(String, MetricValue)> =
        m.into_iter().map(|(k, v)| (k.to_string(), MetricValue::Value(v))).collect();
    if a.torque_current_curve.len() > 2 {
        let curve = a.torque_current_curve.iter().enumerate();
        metrics.extend(
            curve.map(|(k, p)| (torque_curve_metric(k + 1), MetricValue::Value(p.torque_nm))),
        );
    }
    metrics
}

/// The stored name of the `point`-th torque of a design's torque–current curve (counted from 1
/// at 0 A; point `n` of `n` is at the maximum current): `torque_curve_3_Nm`. Stored only when a
/// study keeps curves ([`EvaluationSettings::curve_points`] above 2).
pub fn torque_curve_metric(point: usize) -> String {
    format!("torque_curve_{point}_Nm")
}

/// A stored design's torque–current curve as `(current A, torque N·m)` from its metrics: the
/// [`torque_curve_metric`]s at evenly spaced currents up to `max_current_A`, or without them the
/// two points every record has (`torque_off_Nm` at 0 A, `torque_max_Nm` at the maximum current).
/// `None` when a metric it needs is missing, not a value or not finite.
pub fn torque_curve(metrics: &[(String, MetricValue)]) -> Option<Vec<(f64, f64)>> {
    let find = |name: &str| {
        metrics
            .iter()
            .find(|(n, _)| n == name)
            .and_then(|(_, v)| v.value())
            .filter(|v| v.is_finite())
    };
    let max_current = find("max_current_A")?;
    let mut torques: Vec<f64> =
        (1..).map_while(|k| find(&torque_curve_metric(k))).take(MAX_CURVE_POINTS).collect();
    if torques.len() < 2 {
        torques = vec![find("torque_off_Nm")?, find("torque_max_Nm")?];
    }
    let last = (torques.len() - 1) as f64;
    Some(torques.iter().enumerate().map(|(k, &t)| (max_current * k as f64 / last, t)).collect())
}

/// The thinnest structural wall of the spec (m): case shell, end plate, inner case, the drum
/// cylinders or discs, and the rotor disc and cover where given.
fn min_wall_m(spec: &BrakeSpec) -> f64 {
    let h = &spec.housing;
    let mut walls =
        vec![h.case_thickness.m(), h.end_plate_thickness.m(), h.inner_case_thickness.m()];
    walls.extend(h.cover_thickness.map(|l| l.m()));
    walls.extend(h.rotor_disc_thickness.map(|l| l.m()));
    walls.push(match spec.configuration.surfaces() {
        WorkingSurfaces::Drums(d) => d.cylinder_thickness.m(),
        WorkingSurfaces::Discs(d) => d.thickness.m(),
    });
    walls.into_iter().fold(f64::INFINITY, f64::min)
}

/// Looks up a metric's documentation.
pub fn metric_info(name: &str) -> Option<&'static MetricInfo> {
    METRICS.iter().find(|m| m.name == name)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn named(pairs: &[(&str, f64)]) -> Vec<(String, MetricValue)> {
        pairs.iter().map(|(n, v)| (n.to_string(), MetricValue::Value(*v))).collect()
    }

    #[test]
    fn a_stored_curve_reads_back_at_its_currents() {
        let mut metrics = named(&[("max_current_A", 2.0), ("torque_off_Nm", 0.1)]);
        metrics.extend((1..=5).map(|k| (torque_curve_metric(k), MetricValue::Value(k as f64))));
        let curve = torque_curve(&metrics).unwrap();
        assert_eq!(curve, [(0.0, 1.0), (0.5, 2.0), (1.0, 3.0), (1.5, 4.0), (2.0, 5.0)]);
        assert_eq!(torque_curve_metric(3), "torque_curve_3_Nm");
    }

    #[test]
    fn without_a_stored_curve_the_two_points_of_every_record() {
        let metrics =
            named(&[("torque_max_Nm", 5.0), ("torque_off_Nm", 0.1), ("max_current_A", 2.0)]);
        assert_eq!(torque_curve(&metrics).unwrap(), [(0.0, 0.1), (2.0, 5.0)]);
        assert_eq!(torque_curve(&named(&[("torque_max_Nm", 5.0)])), None);
        let nan =
            named(&[("torque_max_Nm", f64::NAN), ("torque_off_Nm", 0.1), ("max_current_A", 2.0)]);
        assert_eq!(torque_curve(&nan), None);
    }

    #[test]
    fn curve_points_are_bounded_and_keyed_only_above_two() {
        let plain = EvaluationSettings::default();
        assert_eq!(plain.canonical()["points"], 2);
        assert!(!plain.recorded().contains_key("curve_points"));
        let curves = EvaluationSettings { curve_points: 9, ..EvaluationSettings::default() };
        assert_eq!(curves.canonical()["points"], 9);
        assert_eq!(curves.recorded()["curve_points"], 9);
        assert!(curves.check().is_ok());
        for bad in [1, MAX_CURVE_POINTS + 1] {
            let settings =
                EvaluationSettings { curve_points: bad, ..EvaluationSettings::default() };
            let e = settings.check().unwrap_err();
            assert!(e.is_input_error() && e.to_string().contains("points"), "{bad}: {e}");
        }
    }
}
