//! How fast a brake's torque follows its current: the step response and the small-signal
//! frequency response predicted from the design (eddy currents in the solid flux path, the coil
//! circuit, an optional first-order lag of the fluid itself).
//!
//! The brake's field problem (the same mesh, materials and coils as [`crate::analysis`]) gets the
//! electrical conductivity of every solid part from the material library (each value with its
//! source: FEMM gives 5.8 MS/m for its 1006–1020 steels, the ANSYS 1008 curve 2 MS/m; the spread is
//! real material and data uncertainty, so [`ResponseOptions::flux_path_conductivity_s_per_m`]
//! overrides the flux-path steel's value to show how the prediction moves); the MR fluid and the
//! air do not conduct (the fluid's conductivity is orders below the steel's; no source in the
//! library), the coils are stranded. The transient and harmonic solves are those of
//! [`mrbrake_magnetics::dynamics`].
//!
//! - Step response: the direction's coils driven by a current step (`from → to`, the thesis's
//!   linear current amplifier, 3.3, 5.3) or a voltage step through the coil's resistance;
//!   every accepted time step gives the local Bingham yield torque from `B(t)` in the direction's
//!   gaps (the integral of [`crate::analysis`]), then the fluid's lag, a first-order filter of time
//!   constant `τ_f` integrated exactly for a piecewise-linear input. Rise times `t63`, `t90`: the
//!   first times the torque has covered 63 % and 90 % of its change. A step down to zero current
//!   (a release, `--step 2A..0A`) gives the fall times the same way: how long the brake keeps
//!   holding after its controller lets go.
//! - Frequency response: the field linearised about the DC bias (half the maximum current by
//!   default, the middle of the thesis's test range); per frequency the incremental potential
//!   `δÂ` per ampere, and the torque phasor `δT̂ = dT/dA · δÂ` by a central difference of the torque
//!   integral along `Re δÂ` and `Im δÂ` (a relative step of 1e-3 of the bias field; the torque is
//!   smooth in A). The magnitude is normalised by the zero-frequency gain (as the thesis's (5.5),
//!   (5.6) are, DC gain ≈ 1); the bandwidth is the first frequency where it falls 3 dB below
//!   (log-log interpolation between the computed points, 0.1–1000 rad/s, ten a decade as in the
//!   thesis, 5.3.2). The response is sysid's frequency-response data
//!   ([`mrbrake_sysid::frd::Frd`]), the type of a measured response too: `mrbrake tfest` fits it
//!   and a Bode plot overlays it on a measurement as it is.
//!
//! Default fluid lag: MRF-132DG's measured response time T90 ≈ 0.8–1.4 ms (Kubík et al., Sci.
//! Rep. 12:10612, 2022); a first-order lag with T90 = 1.1 ms has `τ_f = 1.1 ms / ln 10 = 0.48 ms`.

use std::sync::Arc;
use std::time::Instant;

use mrbrake_error::FieldError;
use mrbrake_fem::workflow::time::{Scheme, TimeStep};
use mrbrake_magnetics::dynamics::transient::{StepView, TransientOptions, TransientResult};
use mrbrake_magnetics::dynamics::{Coil, Conductor, Drive, Dynamics, Waveform};
use mrbrake_magnetics::{Solution, Solver, SolverOptions};
use mrbrake_materials::{CopperWire, library};
use mrbrake_observe::Flow;
use mrbrake_sysid::frd::{Frd, FrequencyPoint, MINUS_3_DB};
use num_complex::Complex64;
use rayon::prelude::*;
use serde::Serialize;

use crate::DesignError;
use crate::analysis::{gap_yield_torque, numerical, problem_with};
use crate::formula;
use crate::geometry::{BrakeGeometry, CoilInfo, GapInfo, PartKind};
use crate::material_factors::{GapMedium, RegionLaws, conductivity_override};
use crate::mesh_build::{self, MeshLevel};
use crate::spec::BrakeSpec;

pub use mrbrake_magnetics::ElementOrder;

/// The fluid's default first-order lag (s): T90 = 1.1 ms (Kubík et al. 2022) over ln 10.
pub const DEFAULT_FLUID_LAG_S: f64 = 1.1e-3 / std::f64::consts::LN_10;

/// How the coil is driven.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ResponseDrive {
    /// A current amplifier (the thesis's rig): the current follows the demand at once.
    Current,
    /// A voltage source through the coil's own resistance (at the analysis temperature): the
    /// coil's `L/R` adds to the eddy currents.
    Voltage,
}

impl ResponseDrive {
    /// `current` or `voltage` (the `--drive` of `mrbrake response` and a study's
    /// `response.drive`); the error says what is allowed.
    pub fn parse(text: &str) -> Result<Self, String> {
        match text.trim() {
            "current" => Ok(Self::Current),
            "voltage" => Ok(Self::Voltage),
            other => Err(format!("'{other}' (use current or voltage)")),
        }
    }
}

/// A current step `FROM..TO` with units (`"0A..2A"`; `TO` may be 0 for a release) as
/// `(from, to)` amperes; the error says what is wrong.
pub fn parse_step(text: &str) -> Result<(f64, f64), String> {
    use mrbrake_units::{Dimension, parse};
    let (from, to) =
        text.split_once("..").ok_or_else(|| format!("'{text}' (write FROM..TO, e.g. 0A..2A)"))?;
    let current = |t: &str| parse(t, Dimension::Current).map_err(|e| e.to_string());
    Ok((current(from)?, current(to)?))
}

/// Settings of a response prediction.
#[derive(Debug, Clone, PartialEq)]
pub struct ResponseOptions {
    /// Mesh density.
    pub mesh: MeshLevel,
    /// Element order.
    pub order: ElementOrder,
    /// Drive.
    pub drive: ResponseDrive,
    /// Step from this current (A)…
    pub step_from_a: f64,
    /// …to this one (A); `None`: the spec's maximum current.
    pub step_to_a: Option<f64>,
    /// DC bias of the frequency response (A); `None`: half the maximum current.
    pub bias_a: Option<f64>,
    /// Duration of the step response (s).
    pub duration_s: f64,
    /// Relative tolerance of the adaptive time steps.
    pub rtol: f64,
    /// First-order lag of the fluid (s), 0 for none.
    pub fluid_lag_s: f64,
    /// Conductivity of the flux-path steel (S/m) instead of its library value.
    pub flux_path_conductivity_s_per_m: Option<f64>,
    /// Angular frequencies of the frequency response (rad/s).
    pub omegas_rad_s: Vec<f64>,
    /// Copper temperature for the coil resistance of a voltage drive (°C).
    pub temperature_c: f64,
    /// Keep the eddy-current density of direction 1's step at the first time level at or after
    /// this instant (s), for a map ([`Response::eddy`]); `None`: keep none.
    pub eddy_at_s: Option<f64>,
}

impl Default for ResponseOptions {
    fn default() -> Self {
        Self {
            mesh: MeshLevel::Default,
            order: ElementOrder::P1,
            drive: ResponseDrive::Current,
            step_from_a: 0.0,
            step_to_a: None,
            bias_a: None,
            duration_s: 0.1,
            rtol: 1e-3,
            fluid_lag_s: DEFAULT_FLUID_LAG_S,
            flux_path_conductivity_s_per_m: None,
            omegas_rad_s: decades(0.1, 1000.0, 10),
            temperature_c: 20.0,
            eddy_at_s: None,
        }
    }
}

impl ResponseOptions {
    /// The instant of the eddy-current map when none is given: a fiftieth of the duration (2 ms
    /// of the default 100 ms, while the flux is still diffusing into the steel).
    pub fn default_eddy_at_s(&self) -> f64 {
        self.duration_s / 50.0
    }
}

/// `per_decade` log-spaced points from `from` to `to` inclusive.
pub fn decades(from: f64, to: f64, per_decade: usize) -> Vec<f64> {
    let n = ((to / from).log10() * per_decade as f64).round() as usize;
    (0..=n).map(|k| from * 10f64.powf(k as f64 / per_decade as f64)).collect()
}

/// The torque step response of one direction.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct StepResponse {
    /// Direction (1 or 2).
    pub direction: usize,
    /// Times (s).
    pub time_s: Vec<f64>,
    /// Coil current (A).
    #[serde(rename = "current_A")]
    pub current_a: Vec<f64>,
    /// Torque after the fluid's lag (N·m): yield torque of the direction's gaps.
    #[serde(rename = "torque_Nm")]
    pub torque_nm: Vec<f64>,
    /// Time to 63 % of the torque change (s), `None` if not reached or not resolved by the time
    /// steps ([`resolved_rise_time`]).
    pub t63_s: Option<f64>,
    /// Time to 90 % (s), `None` as `t63_s`.
    pub t90_s: Option<f64>,
    /// Time steps taken (accepted, rejected).
    pub steps: [usize; 2],
}

/// The predicted dynamics of a brake.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Response {
    /// Design name.
    pub name: String,
    /// Drive.
    pub drive: ResponseDrive,
    /// Step responses (direction 1, and 2 for the bidirectional brake).
    pub step: Vec<StepResponse>,
    /// Bias of the frequency response (A).
    #[serde(rename = "bias_A")]
    pub bias_a: f64,
    /// Small-signal gain `dT/dI` at zero frequency (N·m/A).
    #[serde(rename = "dc_gain_Nm_per_A")]
    pub dc_gain_nm_per_a: f64,
    /// Frequency response of direction 1: torque per current normalised by the DC gain, `G/G0`
    /// (in JSON the list of points, `omega_rad_s`, `magnitude_dB`, `phase_deg`, `re`, `im`).
    pub frequency_response: Frd,
    /// −3 dB bandwidth (rad/s), `None` above the highest frequency.
    pub bandwidth_rad_s: Option<f64>,
    /// The bidirectional brake's direction 2 about the same bias: its own coils driven, the
    /// torque of its gaps (absent for a one-direction brake; the study metric
    /// `bandwidth_dir2_rad_s` is its bandwidth).
    #[serde(rename = "direction_2", skip_serializing_if = "Option::is_none")]
    pub direction_2: Option<SmallSignal>,
    /// Conductivity of the flux-path steel used (S/m), and where it comes from.
    #[serde(rename = "flux_path_conductivity_S_per_m")]
    pub flux_path_conductivity_s_per_m: f64,
    /// Source of that value.
    pub conductivity_source: String,
    /// Fluid lag (s).
    pub fluid_lag_s: f64,
    /// Mesh nodes.
    pub nodes: usize,
    /// Timings (s).
    pub timings_s: ResponseTimings,
    /// The eddy-current density at the instant asked for ([`ResponseOptions::eddy_at_s`]); not in
    /// the JSON (a field over the mesh: the map shows it).
    #[serde(skip)]
    pub eddy: Option<EddyField>,
}

/// One direction's small-signal torque/current response about a bias, as the top level of
/// [`Response`] gives direction 1's.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SmallSignal {
    /// `dT/dI` at zero frequency (N·m/A).
    #[serde(rename = "dc_gain_Nm_per_A")]
    pub dc_gain_nm_per_a: f64,
    /// Torque per current normalised by the DC gain.
    pub frequency_response: Frd,
    /// −3 dB bandwidth (rad/s), `None` above the highest frequency.
    pub bandwidth_rad_s: Option<f64>,
}

/// The induced azimuthal current density `J_φ = −σ ∂A/∂t` over the brake's section at one
/// instant of a step response.
#[derive(Debug, Clone, PartialEq)]
pub struct EddyField {
    /// The time level shown (s): the first at or after the instant asked for.
    pub time_s: f64,
    /// The direction whose step it is (1-based).
    pub direction: usize,
    /// The mesh: node coordinates `[r, z]` (m).
    pub nodes: Vec<[f64; 2]>,
    /// Triangles (node indices).
    pub triangles: Vec<[usize; 3]>,
    /// Region tag per triangle.
    pub region_tags: Vec<u32>,
    /// True for the triangles of conducting parts (the only ones that carry `J`).
    pub conducting: Vec<bool>,
    /// `J_φ` (A/m²) at the three vertices of every triangle, in the triangle's node order.
    pub j_a_per_m2: Vec<[f64; 3]>,
}

/// Wall times (s).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ResponseTimings {
    /// Step responses.
    pub step: f64,
    /// Frequency response.
    pub frequency: f64,
    /// Everything.
    pub total: f64,
}

/// Predicts the step and frequency responses of `spec` (module docs).
pub fn response(spec: &BrakeSpec, options: &ResponseOptions) -> Result<Response, DesignError> {
    let start = Instant::now();
    let max_current = spec.coil.max_current.a();
    let to = options.step_to_a.unwrap_or(max_current);
    step_drive(options.step_from_a, to)?;
    let bias = options.bias_a.unwrap_or(0.5 * max_current);
    check_bias(bias, max_current)?;
    let model = ResponseModel::new(spec, options)?.model;
    // The frequency response first: a bias without small-signal gain is an input error, found
    // before the (longer) transients.
    let t0 = Instant::now();
    // The two directions' small-signal responses are independent solves: one thread each.
    let (first, second) = rayon::join(
        || model.frequency_response(0, bias),
        || (model.geometry.units > 1).then(|| model.frequency_response(1, bias)).transpose(),
    );
    let (dc_gain, frequency_response) = first?;
    let direction_2 = second?.map(|(gain, frd)| SmallSignal {
        dc_gain_nm_per_a: gain,
        bandwidth_rad_s: frd.bandwidth_rad_s(MINUS_3_DB),
        frequency_response: frd,
    });
    let frequency_s = t0.elapsed().as_secs_f64();
    let t0 = Instant::now();
    // The directions' transients are independent: one thread each (on two cores the step
    // responses of the bidirectional brake take the time of one).
    let steps: Vec<Result<(StepResponse, Option<EddyField>), DesignError>> =
        (0..model.geometry.units)
            .into_par_iter()
            .map(|unit| {
                let keep_at = if unit == 0 { options.eddy_at_s } else { None };
                model.step_response(unit, options.step_from_a, to, keep_at)
            })
            .collect();
    let mut step = Vec::with_capacity(steps.len());
    let mut eddy = None;
    for outcome in steps {
        let (response, field) = outcome?;
        step.push(response);
        eddy = eddy.or(field);
    }
    let step_s = t0.elapsed().as_secs_f64();
    Ok(Response {
        name: spec.name.clone(),
        drive: options.drive,
        step,
        bias_a: bias,
        dc_gain_nm_per_a: dc_gain,
        bandwidth_rad_s: frequency_response.bandwidth_rad_s(MINUS_3_DB),
        frequency_response,
        direction_2,
        flux_path_conductivity_s_per_m: model.flux_path_sigma.0,
        conductivity_source: model.flux_path_sigma.1.clone(),
        fluid_lag_s: options.fluid_lag_s,
        nodes: model.mesh.nodes.len(),
        timings_s: ResponseTimings {
            step: step_s,
            frequency: frequency_s,
            total: start.elapsed().as_secs_f64(),
        },
        eddy,
    })
}

/// Checks the ranges of `options` (durations, currents, lag, conductivity, frequencies). The
/// errors name the options as the `[response]` table of a study does (`duration`, `step`,
/// `bias`, `conductivity`, `fluid_lag`), and `rtol`, `eddy_at`, `frequencies`.
pub fn check_options(options: &ResponseOptions) -> Result<(), DesignError> {
    use formula::{finite, non_negative, positive};
    positive("duration", "duration of the step response", options.duration_s, "s")?;
    positive("rtol", "relative tolerance of the time steps", options.rtol, "")?;
    // Currents are magnitudes of one unit's drive (the other direction is the other unit's coil).
    non_negative("step", "FROM, the current before the step", options.step_from_a, "A")?;
    if let Some(to) = options.step_to_a {
        finite("step", "TO, the current after the step", to, "A")?;
    }
    if let Some(bias) = options.bias_a {
        non_negative("bias", "DC bias of the frequency response", bias, "A")?;
    }
    non_negative("fluid_lag", "first-order lag of the fluid", options.fluid_lag_s, "s")?;
    if let Some(s) = options.flux_path_conductivity_s_per_m {
        positive("conductivity", "conductivity of the flux-path steel", s, "S/m")?;
    }
    if let Some(t) = options.eddy_at_s
        && !(t >= 0.0 && t <= options.duration_s)
    {
        let e = FieldError::new("eddy_at", "the eddy-current instant lies in the step response")
            .with_value(format!("{t} s"))
            .with_allowed(format!("[0, duration = {} s]", options.duration_s));
        return Err(e.into());
    }
    for (k, &w) in options.omegas_rad_s.iter().enumerate() {
        positive(&format!("frequencies[{k}]"), "angular frequency", w, "rad/s")?;
    }
    Ok(())
}

/// A brake's field model with conductivities, meshed once, for any of its responses: the parts of
/// [`response`] one at a time (a design study asks only for what its metrics need: one step
/// direction, a release, the frequency response), each computed exactly as [`response`] does.
pub struct ResponseModel<'a> {
    model: Model<'a>,
}

impl<'a> ResponseModel<'a> {
    /// Checks `options`, meshes `spec` and assigns its conductivities.
    pub fn new(spec: &'a BrakeSpec, options: &'a ResponseOptions) -> Result<Self, DesignError> {
        check_options(options)?;
        let geometry = spec.validate()?.geometry;
        let mesh = Arc::new(mesh_build::mesh_spec(spec, &geometry, options.mesh)?);
        Ok(Self { model: Model::new(spec, geometry, mesh, options)? })
    }

    /// The model on a mesh of `spec` built before (`mesh_build::mesh_spec` of `geometry` at the
    /// options' level, shared with the design's other analyses).
    pub fn on_mesh(
        spec: &'a BrakeSpec,
        options: &'a ResponseOptions,
        geometry: BrakeGeometry,
        mesh: Arc<mrbrake_fem::mesh::Mesh>,
    ) -> Result<Self, DesignError> {
        check_options(options)?;
        Ok(Self { model: Model::new(spec, geometry, mesh, options)? })
    }

    /// Units (directions) of the brake: 1, or 2 for the bidirectional brake.
    pub fn units(&self) -> usize {
        self.model.geometry.units
    }

    /// Mesh nodes.
    pub fn nodes(&self) -> usize {
        self.model.mesh.nodes.len()
    }

    /// The torque step response of direction `unit + 1` from `from` to `to` amperes (`to` = 0: a
    /// release from `from`), as in [`Response::step`].
    pub fn step(&self, unit: usize, from: f64, to: f64) -> Result<StepResponse, DesignError> {
        self.check_unit(unit)?;
        self.model.step_response(unit, from, to, None).map(|(step, _)| step)
    }

    /// The small-signal response of direction 1 about `bias` amperes: the DC gain (N·m/A), the
    /// normalised frequency response and its −3 dB bandwidth (rad/s), as in [`Response`].
    pub fn frequency_response(&self, bias: f64) -> Result<(f64, Frd, Option<f64>), DesignError> {
        self.frequency_response_of(0, bias)
    }

    /// The small-signal response of direction `unit + 1` about `bias` amperes of that
    /// direction's coils, computed as [`Self::frequency_response`] on that direction's magnetic
    /// circuit: its coils driven, the torque of its gaps (for direction 1 the same numbers).
    pub fn frequency_response_of(
        &self,
        unit: usize,
        bias: f64,
    ) -> Result<(f64, Frd, Option<f64>), DesignError> {
        self.check_unit(unit)?;
        let (gain, frd) = self.model.frequency_response(unit, bias)?;
        let bandwidth = frd.bandwidth_rad_s(MINUS_3_DB);
        Ok((gain, frd, bandwidth))
    }

    /// A direction (`unit + 1`) the brake has, else an input error naming `direction`.
    fn check_unit(&self, unit: usize) -> Result<(), DesignError> {
        if unit >= self.units() {
            let e = FieldError::new("direction", "a direction of the brake")
                .with_value(unit + 1)
                .with_allowed(format!("1 to {}", self.units()));
            return Err(e.into());
        }
        Ok(())
    }
}

/// The bias of a frequency response must lie within the coil's rating (above it the prediction
/// is of a coil the spec does not allow).
fn check_bias(bias: f64, max_current: f64) -> Result<(), DesignError> {
    if bias > max_current {
        let e = FieldError::new("bias", "above the spec's maximum current (coil.max_current)")
            .with_value(format!("{bias} A"))
            .with_allowed(format!("0 < bias <= {max_current} A"));
        return Err(e.into());
    }
    Ok(())
}

/// The drive amplitude and waveform of a step from `from` to `to` amperes: `to · Step(from/to)`,
/// or `from · Release` for a step down to rest; an error when the current does not change.
fn step_drive(from: f64, to: f64) -> Result<(f64, Waveform), DesignError> {
    if to.abs() >= f64::MIN_POSITIVE {
        return Ok((to, Waveform::Step { initial: from / to }));
    }
    if from.abs() >= f64::MIN_POSITIVE {
        return Ok((from, Waveform::Release));
    }
    let e = FieldError::new("step", "the step must change the current (FROM != TO)")
        .with_value(format!("{from} A..{to} A"));
    Err(e.into())
}

/// The brake's field model with conductivities.
struct Model<'a> {
    spec: &'a BrakeSpec,
    geometry: BrakeGeometry,
    mesh: Arc<mrbrake_fem::mesh::Mesh>,
    fluid: GapMedium,
    conductors: Vec<Conductor>,
    /// The flux-path steel's conductivity and its source.
    flux_path_sigma: (f64, String),
    options: &'a ResponseOptions,
}

impl<'a> Model<'a> {
    fn new(
        spec: &'a BrakeSpec,
        geometry: BrakeGeometry,
        mesh: Arc<mrbrake_fem::mesh::Mesh>,
        options: &'a ResponseOptions,
    ) -> Result<Self, DesignError> {
        let fluid = GapMedium::of(spec)?;
        let (conductors, flux_path_sigma) = conductors(spec, &geometry, options)?;
        Ok(Self { spec, geometry, mesh, fluid, conductors, flux_path_sigma, options })
    }

    /// The dynamics of `unit`'s coils, each driven by `drive(sign, coil resistance)`.
    fn dynamics(
        &self,
        unit: usize,
        drive: impl Fn(f64, f64) -> Drive,
        waveform: Waveform,
    ) -> Result<Dynamics, DesignError> {
        let laws = RegionLaws::new(self.spec, &self.fluid)?;
        let problem = problem_with(&laws, &self.geometry, Arc::clone(&self.mesh))?;
        let solver_options =
            SolverOptions { order: self.options.order, ..SolverOptions::default() };
        let solver = Solver::new(problem, solver_options).map_err(numerical)?;
        let mut coils = Vec::new();
        for coil in self.geometry.coils.iter().filter(|c| c.unit == unit) {
            coils.push(Coil {
                tag: coil.tag,
                turns: f64::from(coil.turns),
                drive: drive(coil.current_sign, self.coil_resistance(coil)?),
                waveform: waveform.clone(),
            });
        }
        Dynamics::new(solver, &self.conductors, coils).map_err(numerical)
    }

    /// The yield torque of `unit`'s gaps for the potential `a`.
    fn torque(&self, dynamics: &Dynamics, unit: usize, a: Vec<f64>) -> Result<f64, DesignError> {
        let solution: Solution = dynamics.solution(a);
        let gaps: Vec<&GapInfo> = self.geometry.gaps.iter().filter(|g| g.unit == unit).collect();
        let mut torque = 0.0;
        for gap in gaps {
            torque += gap_yield_torque(dynamics.solver(), &solution, gap, &self.fluid)?;
        }
        Ok(torque)
    }
}

/// The conductors of the brake: every part's library conductivity (0 when the library has none:
/// air, coils), or the spec's override (`steel.conductivity_S_per_m`, and
/// `fluid.conductivity_S_per_m`, the only way the gaps conduct); the flux-path steel's overridable
/// by the option above both.
fn conductors(
    spec: &BrakeSpec,
    geometry: &BrakeGeometry,
    options: &ResponseOptions,
) -> Result<(Vec<Conductor>, (f64, String)), DesignError> {
    let mut out = Vec::new();
    let mut flux_path = (0.0, String::from("no flux-path steel"));
    for region in &geometry.regions {
        let spec_value = conductivity_override(spec, region);
        if matches!(region.kind, PartKind::Coil | PartKind::Air)
            || (region.kind == PartKind::Fluid && spec_value.is_none())
        {
            continue;
        }
        let library_value = match region.kind {
            PartKind::Fluid => None,
            _ => library::get(&region.material)
                .map_err(|source| DesignError::PartMaterial { part: region.name.clone(), source })?
                .conductivity_s_per_m
                .clone(),
        };
        let mut sigma = spec_value.or(library_value.as_ref().map(|s| s.value)).unwrap_or(0.0);
        if region.kind == PartKind::FluxPath {
            let source = match (options.flux_path_conductivity_s_per_m, spec_value, library_value) {
                (Some(s), _, _) => {
                    sigma = s;
                    "given (--conductivity)".to_string()
                }
                (None, Some(_), _) => "given (steel.conductivity_S_per_m)".to_string(),
                (None, None, Some(s)) => format!("{}: {}", region.material, s.provenance.source),
                (None, None, None) => format!("{}: none in the library (0)", region.material),
            };
            flux_path = (sigma, source);
        }
        out.push(Conductor { tag: region.tag, conductivity_s_per_m: sigma });
    }
    Ok((out, flux_path))
}

impl Model<'_> {
    /// The torque step response of `unit` from `from` to `to` amperes, and the eddy-current
    /// density at the first level at or after `keep_at` (s) when asked for.
    fn step_response(
        &self,
        unit: usize,
        from: f64,
        to: f64,
        keep_at: Option<f64>,
    ) -> Result<(StepResponse, Option<EddyField>), DesignError> {
        let (amplitude, waveform) = step_drive(from, to)?;
        let drive = |sign: f64, resistance: f64| match self.options.drive {
            ResponseDrive::Current => Drive::Current { amplitude_a: sign * amplitude },
            ResponseDrive::Voltage => Drive::Voltage {
                amplitude_v: sign * amplitude * resistance,
                series_resistance_ohm: resistance,
            },
        };
        let mut dynamics = self.dynamics(unit, drive, waveform)?;
        let duration = self.options.duration_s;
        let step =
            TimeStep::Adaptive { rtol: self.options.rtol, dt_initial_s: self.first_step_s() };
        let transient = TransientOptions::new(duration, Scheme::Bdf2, step);
        let (result, yield_torque, eddy) =
            self.observed_transient(&mut dynamics, &transient, unit, keep_at)?;
        let time = result.time_s;
        let torque = first_order_lag(&time, &yield_torque, self.options.fluid_lag_s);
        let sign =
            self.geometry.coils.iter().find(|c| c.unit == unit).map_or(1.0, |c| c.current_sign);
        let current = result.coils[0].current_a.iter().map(|i| i * sign).collect();
        let response = StepResponse {
            direction: unit + 1,
            t63_s: resolved_rise_time(&time, &torque, 0.63),
            t90_s: resolved_rise_time(&time, &torque, 0.90),
            steps: [time.len() - 1, result.rejected_steps],
            time_s: time,
            current_a: current,
            torque_nm: torque,
        };
        Ok((response, eddy))
    }

    /// The first step of the adaptive transient: a ten-thousandth of the duration, but at most a
    /// tenth of the fastest time scale the torque output can follow — the fluid's lag (the output
    /// is filtered by it), or without a lag the magnetic diffusion time `μ0 σ d²` of the thinnest
    /// conducting part (a lower bound since μr ≥ 1) — so that a long duration cannot step over
    /// the whole rise in one implicit step (the step controller only grows a step it has
    /// resolved, issue 33).
    fn first_step_s(&self) -> f64 {
        let first = 1e-4 * self.options.duration_s;
        if self.options.fluid_lag_s > 0.0 {
            return first.min(0.1 * self.options.fluid_lag_s);
        }
        let mut first = first;
        for c in self.conductors.iter().filter(|c| c.conductivity_s_per_m > 0.0) {
            if let Some(d) = thinnest_extent_m(&self.mesh, c.tag) {
                let diffusion = mrbrake_materials::MU_0 * c.conductivity_s_per_m * d * d;
                if diffusion > 0.0 {
                    first = first.min(0.1 * diffusion);
                }
            }
        }
        first
    }

    /// The transient of `dynamics` with the yield torque of every level and the eddy-current
    /// field of the first level at or after `keep_at`; the first failure of either stops the run
    /// and is returned.
    fn observed_transient(
        &self,
        dynamics: &mut Dynamics,
        transient: &TransientOptions,
        unit: usize,
        keep_at: Option<f64>,
    ) -> Result<(TransientResult, Vec<f64>, Option<EddyField>), DesignError> {
        let mut yield_torque = Vec::new();
        let mut failure = None;
        let mut eddy = None;
        let result = dynamics
            .transient_observed(transient, |view: &StepView<'_>| {
                let level = self.torque(view.dynamics, unit, view.a.to_vec()).and_then(|t| {
                    yield_torque.push(t);
                    if eddy.is_none() && keep_at.is_some_and(|k| view.t >= k * (1.0 - 1e-12)) {
                        let j = view.dynamics.eddy_current_density(view.rate).map_err(numerical)?;
                        eddy = Some(self.eddy_field(unit, view.t, &j));
                    }
                    Ok(())
                });
                level.map_or_else(
                    |e| {
                        failure = Some(e);
                        Flow::Stop
                    },
                    |()| Flow::Continue,
                )
            })
            .map_err(numerical)?;
        match failure {
            Some(e) => Err(e),
            None => Ok((result, yield_torque, eddy)),
        }
    }

    /// The [`EddyField`] of `unit`'s step at `t` from the vertex values `j` (three per element).
    fn eddy_field(&self, unit: usize, t: f64, j: &[f64]) -> EddyField {
        let conducting_tags: Vec<u32> = self
            .conductors
            .iter()
            .filter(|c| c.conductivity_s_per_m > 0.0)
            .map(|c| c.tag)
            .collect();
        EddyField {
            time_s: t,
            direction: unit + 1,
            nodes: self.mesh.nodes.clone(),
            triangles: self.mesh.triangles.clone(),
            region_tags: self.mesh.triangle_tags.clone(),
            conducting: self
                .mesh
                .triangle_tags
                .iter()
                .map(|t| conducting_tags.contains(t))
                .collect(),
            j_a_per_m2: j.chunks_exact(3).map(|v| [v[0], v[1], v[2]]).collect(),
        }
    }

    /// The small-signal torque per current of direction `unit + 1` (its coils, its gaps) about
    /// `bias` amperes: the DC gain and the normalised response at the options' frequencies.
    fn frequency_response(&self, unit: usize, bias: f64) -> Result<(f64, Frd), DesignError> {
        let max_current = self.spec.coil.max_current.a();
        check_bias(bias, max_current)?;
        let drive = |sign: f64, _| Drive::Current { amplitude_a: sign };
        let mut dynamics = self.dynamics(unit, drive, Waveform::Step { initial: 0.0 })?;
        let signs: Vec<f64> =
            self.geometry.coils.iter().filter(|c| c.unit == unit).map(|c| c.current_sign).collect();
        let bias_currents: Vec<f64> = signs.iter().map(|s| s * bias).collect();
        let two_pi = 2.0 * std::f64::consts::PI;
        let mut frequencies = vec![0.0];
        frequencies.extend(self.options.omegas_rad_s.iter().map(|w| w / two_pi));
        let potentials =
            dynamics.harmonic_potentials(&frequencies, Some(&bias_currents)).map_err(numerical)?;
        let a0 = dynamics.static_solution(&bias_currents).map_err(numerical)?.a_phi().to_vec();
        let mut gains = Vec::with_capacity(potentials.len());
        for p in &potentials {
            let torque = Complex64::new(
                self.torque_derivative(&dynamics, unit, &a0, &p.re)?,
                self.torque_derivative(&dynamics, unit, &a0, &p.im)?,
            );
            let lag = Complex64::new(1.0, two_pi * p.frequency_hz * self.options.fluid_lag_s);
            let mut gain = torque / lag;
            if self.options.drive == ResponseDrive::Voltage {
                gain *= self.voltage_factor(&dynamics, unit, p)?;
            }
            gains.push(gain);
        }
        let dc = gains[0];
        if !(dc.norm() > 0.0 && dc.re.is_finite() && dc.im.is_finite()) {
            let e = FieldError::new(
                "bias",
                format!(
                    "no small-signal gain there (dT/dI = {} N·m/A): the yield torque has no slope \
                     (at 0 A it grows as the square of the current)",
                    dc.re
                ),
            )
            .with_value(format!("{bias} A"))
            .with_allowed(format!("a bias with a torque slope, 0 < bias <= {max_current} A"));
            return Err(e.into());
        }
        let points = self
            .options
            .omegas_rad_s
            .iter()
            .zip(&gains[1..])
            .map(|(&omega, g)| FrequencyPoint::new(omega, g / dc))
            .collect();
        Ok((dc.re, Frd::new(points)))
    }

    /// `dT/dA · x` of `unit`'s gaps by a central difference about `a0` (module docs).
    fn torque_derivative(
        &self,
        dynamics: &Dynamics,
        unit: usize,
        a0: &[f64],
        x: &[f64],
    ) -> Result<f64, DesignError> {
        let scale = a0.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
        let size = x.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
        if size <= 0.0 {
            return Ok(0.0);
        }
        let eps = 1e-3 * scale.max(size) / size;
        let shifted = |s: f64| a0.iter().zip(x).map(|(a, x)| a + s * eps * x).collect::<Vec<f64>>();
        let plus = self.torque(dynamics, unit, shifted(1.0))?;
        let minus = self.torque(dynamics, unit, shifted(-1.0))?;
        Ok((plus - minus) / (2.0 * eps))
    }

    /// `R / (R + Z)`: the coil current per `V/R` of a voltage drive (`unit`'s coils in series).
    fn voltage_factor(
        &self,
        dynamics: &Dynamics,
        unit: usize,
        p: &mrbrake_magnetics::dynamics::harmonic::HarmonicPotential,
    ) -> Result<Complex64, DesignError> {
        let point = dynamics.harmonic_point(p, &[]).map_err(numerical)?;
        let impedance: Complex64 = point
            .coils
            .iter()
            .map(|c| Complex64::new(c.impedance_ohm[0], c.impedance_ohm[1]))
            .sum();
        let mut resistance = 0.0;
        for coil in self.geometry.coils.iter().filter(|c| c.unit == unit) {
            resistance += self.coil_resistance(coil)?;
        }
        Ok(Complex64::new(resistance, 0.0) / (resistance + impedance))
    }

    /// The resistance of one coil at the options' temperature (the thesis's coil formulas).
    fn coil_resistance(&self, coil: &CoilInfo) -> Result<f64, DesignError> {
        let wire = CopperWire::from_diameter(self.spec.wire_diameter_m())
            .map_err(DesignError::Material)?;
        let mean_radius = 0.5 * (coil.rect.r0 + coil.rect.r1);
        let max = self.spec.coil.max_current.a();
        let electrics = formula::coil_electrics(
            coil.turns,
            mean_radius,
            &wire,
            max,
            self.options.temperature_c,
        )?;
        Ok(electrics.resistance_ohm)
    }
}

/// `y' = (u − y)/τ` from `y(0) = u(0)`, exact for `u` linear between the samples:
/// `y₁ = u₁ + (y₀ − u₀) e^{−h/τ} − (u₁ − u₀)(τ/h)(1 − e^{−h/τ})`.
pub fn first_order_lag(time: &[f64], input: &[f64], tau: f64) -> Vec<f64> {
    if tau <= 0.0 || input.is_empty() {
        return input.to_vec();
    }
    let mut out = Vec::with_capacity(input.len());
    out.push(input[0]);
    for k in 1..input.len() {
        let h = time[k] - time[k - 1];
        let decay = (-h / tau).exp();
        let (u0, u1, y0) = (input[k - 1], input[k], out[k - 1]);
        out.push(u1 + (y0 - u0) * decay - (u1 - u0) * (tau / h) * (1.0 - decay));
    }
    out
}

/// The smaller side of the bounding box of the triangles tagged `tag` (m), `None` without any.
fn thinnest_extent_m(mesh: &mrbrake_fem::mesh::Mesh, tag: u32) -> Option<f64> {
    let mut lo = [f64::INFINITY; 2];
    let mut hi = [f64::NEG_INFINITY; 2];
    for (triangle, _) in mesh.triangles.iter().zip(&mesh.triangle_tags).filter(|(_, t)| **t == tag)
    {
        for &node in triangle {
            for axis in 0..2 {
                lo[axis] = lo[axis].min(mesh.nodes[node][axis]);
                hi[axis] = hi[axis].max(mesh.nodes[node][axis]);
            }
        }
    }
    let extent = (hi[0] - lo[0]).min(hi[1] - lo[1]);
    extent.is_finite().then_some(extent)
}

/// [`rise_time`] when the steps resolve it: the step holding the crossing spans at most a quarter
/// of the time from the start to the crossing, so the interpolated instant is not an artefact of
/// one long step (issue 33: a 1e6 s run used to report a t63 interpolated inside its first step);
/// `None` otherwise, as when the level is not reached.
pub fn resolved_rise_time(time: &[f64], y: &[f64], fraction: f64) -> Option<f64> {
    let t = rise_time(time, y, fraction)?;
    let start = *time.first()?;
    let k = time.partition_point(|&s| s < t).clamp(1, time.len().max(2) - 1);
    let step = time.get(k)? - time.get(k - 1)?;
    (step <= 0.25 * (t - start)).then_some(t)
}

/// The first time `y` has covered `fraction` of its change from the first to the last sample
/// (linear interpolation), or `None`.
pub fn rise_time(time: &[f64], y: &[f64], fraction: f64) -> Option<f64> {
    let (first, last) = (*y.first()?, *y.last()?);
    let target = first + fraction * (last - first);
    let rising = last >= first;
    let reached = |v: f64| if rising { v >= target } else { v <= target };
    let k = y.iter().position(|&v| reached(v))?;
    if k == 0 {
        return Some(time[0]);
    }
    let (y0, y1) = (y[k - 1], y[k]);
    let s = if (y1 - y0).abs() > 0.0 { (target - y0) / (y1 - y0) } else { 1.0 };
    Some(time[k - 1] + s * (time[k] - time[k - 1]))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lag_rise_time_and_bandwidth_helpers() {
        // A first-order lag of a step reaches 63.2 % at τ.
        let time: Vec<f64> = (0..=4000).map(|k| k as f64 * 1e-5).collect();
        let step: Vec<f64> = time.iter().map(|&t| if t > 0.0 { 1.0 } else { 0.0 }).collect();
        let y = first_order_lag(&time, &step, 5e-3);
        let t63 = rise_time(&time, &y, 1.0 - (-1.0f64).exp()).unwrap();
        assert!((t63 - 5e-3).abs() < 2e-5, "t63 = {t63}");
        // |1/(1 + jω/ω_c)| is −3.01 dB at ω_c.
        let response = Frd::sample(&decades(1.0, 1000.0, 20), |w| {
            Complex64::new(1.0, 0.0) / Complex64::new(1.0, w / 50.0)
        });
        let bw = response.bandwidth_rad_s(MINUS_3_DB).unwrap();
        assert!((bw / 50.0 - 1.0).abs() < 0.01, "bandwidth {bw}");
    }
}
