//! The brake's thermal model: its geometry and mesh as a heat problem (`mrbrake-heat`), the coil's
//! Joule loss `I² R(T)`, viscous dissipation in the gaps, convection from the housing; steady hot
//! spot, warm-up, continuous current rating, largest duty cycle at the maximum current and the
//! time to the insulation limit.
//!
//! Model (stated so its limits are visible):
//! - the device only: the air box of the magnetic mesh is dropped; every outer surface of the
//!   device (not the axis) loses heat by convection `h (T − T_∞)` with one coefficient `h` (the
//!   shaft ends included), and optionally by radiation `ε σ (T⁴ − T_∞⁴)` to surroundings at the
//!   ambient; internal contacts are perfect;
//! - the winding is homogenised (`mrbrake_materials::thermal::Winding`, copper in impregnating
//!   resin) with the fill factor `N π d²/4 / (C_w C_h)` of the spec's wire and turns;
//! - the Joule loss of the energised unit's coil(s) at the local temperature (`R20 = ρ20 N 2π r̄ /
//!   (π d²/4)`, IACS copper, `r̄` the window's centre radius); a bidirectional brake energises one
//!   unit at a time (as its controller does), unit 1 here;
//! - viscous dissipation in each gap at the speed `ω`, uniform at the Couette rate of the gap's
//!   mean radius: `q = η (ω r_m / g)²`, η the fluid's off-state viscosity of the library (30 °C);
//! - a duty cycle `d` at current `I` is its mean power: the warm-up uses `I √d` (valid when the
//!   period is much shorter than the thermal time constant, minutes here; the ripple is not
//!   resolved), and the largest duty at the maximum current is `(I_cont / I_max)²`;
//! - the housing's `h` is given, or from natural convection to still air ([`Cooling::Natural`]:
//!   Churchill–Chu correlations of `mrbrake_heat::convection` for a horizontal axis, the device's
//!   outer diameter and length, iterated with the housing's mean surface temperature until `h`
//!   changes by less than 1e-6 relative); the warm-up keeps the steady state's `h` (a cooler surface
//!   convects less, so early in the warm-up the model cools slightly too well);
//! - what heat does to the brake ([`behaviour`]): the fluid's off-state viscosity at its temperature
//!   (`mrbrake_materials::thermal::fluid_viscosity_at`, low trust), the coil's hot resistance and
//!   power, and the torque from a voltage drive sized for the current at the ambient.

pub mod behaviour;
pub mod session;

use std::collections::HashMap;
use std::sync::Arc;
use std::time::Instant;

use mrbrake_error::FieldError;
use mrbrake_fem::mesh::Mesh;
use mrbrake_fem::workflow::time::{Event, Scheme, TimeOptions, TimeStep};
use mrbrake_heat::{
    Boundary, BoundaryCondition, HeatError, HeatProblem, HeatSolver, Region, SolverOptions, Source,
    celsius, convection, kelvin,
};
use mrbrake_materials::thermal::{Winding, thermal};
use mrbrake_materials::wire::{COPPER_RESISTIVITY_20C_OHM_M, COPPER_TEMPERATURE_COEFFICIENT_PER_K};
use mrbrake_observe::Flow;
use serde::Serialize;

use crate::DesignError;
use crate::geometry::{BrakeGeometry, PartKind};
use crate::mesh_build::{MeshLevel, mesh_spec};
use crate::spec::BrakeSpec;

/// Edge tag of the device's outer surface in the thermal mesh.
pub const HOUSING_TAG: u32 = 100;

/// Errors of the thermal model.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ThermalError {
    /// The design (spec, geometry, mesh).
    #[error(transparent)]
    Design(#[from] DesignError),
    /// The heat solver.
    #[error(transparent)]
    Heat(#[from] HeatError),
    /// An option outside its range, or an operating point the model cannot reach: the option
    /// (named as the `[thermal]` table of a study names it: `duty`, `insulation_class`), the
    /// value and what is allowed. The front ends rename it ([`ThermalError::with_field_names`]).
    /// A part without thermal data is an invalid spec ([`DesignError::Spec`]).
    #[error(transparent)]
    Input(Box<FieldError>),
    /// A material's data (e.g. a viscosity outside its temperature range).
    #[error(transparent)]
    Material(#[from] mrbrake_materials::MaterialError),
}

impl mrbrake_error::Kind for ThermalError {
    fn kind(&self) -> mrbrake_error::ErrorKind {
        match self {
            Self::Design(e) => e.kind(),
            Self::Heat(e) => e.kind(),
            Self::Input(_) => mrbrake_error::ErrorKind::Input,
            Self::Material(e) => e.kind(),
        }
    }
}

impl From<FieldError> for ThermalError {
    fn from(error: FieldError) -> Self {
        Self::Input(Box::new(error))
    }
}

impl ThermalError {
    /// The same error with the field of an input error named as a front end names it (see
    /// [`FieldError::renamed`]: the CLI's `--insulation-class` for `insulation_class`); other
    /// errors are unchanged.
    pub fn with_field_names(self, names: &[(&str, &str)]) -> Self {
        match self {
            Self::Input(field) => Self::Input(Box::new(field.renamed(names))),
            Self::Design(e) => Self::Design(e.with_field_names(names)),
            other => other,
        }
    }
}

/// Operating point and settings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ThermalOptions {
    /// Coil current when on \[A\].
    pub current_a: f64,
    /// Duty cycle in (0, 1].
    pub duty: f64,
    /// Period of the duty cycle \[s\], if known (checked against the thermal time constant).
    pub period_s: Option<f64>,
    /// Ambient \[°C\].
    pub ambient_c: f64,
    /// Cooling of the housing.
    pub cooling: Cooling,
    /// Emissivity of the housing for radiation to surroundings at the ambient, in [0, 1] (0: no
    /// radiation).
    pub emissivity: f64,
    /// Insulation limit (hot-spot) \[°C\].
    pub limit_c: f64,
    /// Warm-up duration \[s\].
    pub time_s: f64,
    /// Warm-up step \[s\].
    pub dt_s: f64,
    /// Shaft speed for viscous dissipation \[rad/s\].
    pub speed_rad_s: f64,
    /// Mesh level.
    pub mesh: MeshLevel,
    /// Also compute what heat does to the brake ([`behaviour`]: a magnetic analysis more).
    pub behaviour: bool,
}

/// How the housing loses heat.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Cooling {
    /// A given heat-transfer coefficient.
    Fixed {
        /// \[W/(m² K)\]
        h_w_per_m2k: f64,
    },
    /// Natural convection to still air, axis horizontal (module docs).
    Natural,
}

impl Cooling {
    /// A heat-transfer coefficient with its unit (a bare number is W/(m²·K)) or `natural` (the
    /// `--h` of `mrbrake thermal` and a study's `thermal.h`); the error says what is allowed.
    pub fn parse(text: &str) -> Result<Self, String> {
        if text.trim().eq_ignore_ascii_case("natural") {
            return Ok(Self::Natural);
        }
        mrbrake_units::parse(text, mrbrake_units::Dimension::HeatTransferCoefficient)
            .map(|h_w_per_m2k| Self::Fixed { h_w_per_m2k })
            .map_err(|e| format!("{e} (in (0, 1e5] W/(m²·K)), or `natural`"))
    }
}

/// The insulation limit (°C) of an IEC 60085 thermal class letter (A 105, E 120, B 130, F 155,
/// H 180 °C) or of a temperature with its unit (the `--insulation-class` of `mrbrake thermal`
/// and a study's `thermal.insulation_class`).
pub fn insulation_limit_c(text: &str) -> Result<f64, String> {
    let class = match text.trim().to_ascii_uppercase().as_str() {
        "A" => Some(105.0),
        "E" => Some(120.0),
        "B" => Some(130.0),
        "F" => Some(155.0),
        "H" => Some(180.0),
        _ => None,
    };
    match class {
        Some(t) => Ok(t),
        None => mrbrake_units::parse(text, mrbrake_units::Dimension::TemperatureCelsius)
            .map_err(|e| format!("{e} (or a class letter A, E, B, F, H)")),
    }
}

impl Default for ThermalOptions {
    fn default() -> Self {
        Self {
            current_a: 2.0,
            duty: 1.0,
            period_s: None,
            ambient_c: 25.0,
            cooling: Cooling::Fixed { h_w_per_m2k: 10.0 },
            emissivity: 0.0,
            limit_c: 155.0,
            time_s: 7200.0,
            dt_s: 10.0,
            speed_rad_s: 0.0,
            mesh: MeshLevel::Default,
            behaviour: false,
        }
    }
}

/// The device part of the magnetic mesh: air triangles dropped, nodes renumbered, the outer
/// surface (edges of one device triangle, off the axis) tagged [`HOUSING_TAG`].
pub fn device_mesh(geometry: &BrakeGeometry, full: &Mesh) -> Mesh {
    let air: Vec<u32> =
        geometry.regions.iter().filter(|r| r.kind == PartKind::Air).map(|r| r.tag).collect();
    let mut index = vec![usize::MAX; full.nodes.len()];
    let mut out = Mesh::default();
    for (tri, &tag) in
        full.triangles.iter().zip(&full.triangle_tags).filter(|(_, t)| !air.contains(t))
    {
        let renumbered = tri.map(|n| {
            if index[n] == usize::MAX {
                index[n] = out.nodes.len();
                out.nodes.push(full.nodes[n]);
            }
            index[n]
        });
        out.triangles.push(renumbered);
        out.triangle_tags.push(tag);
    }
    let mut count: HashMap<[usize; 2], usize> = HashMap::new();
    for tri in &out.triangles {
        for k in 0..3 {
            let (a, b) = (tri[k], tri[(k + 1) % 3]);
            *count.entry([a.min(b), a.max(b)]).or_default() += 1;
        }
    }
    let scale = geometry.device.r1.max(1e-9);
    let mut edges: Vec<[usize; 2]> =
        count.into_iter().filter(|(_, c)| *c == 1).map(|(e, _)| e).collect();
    edges.sort_unstable();
    for e in edges {
        let on_axis = out.nodes[e[0]][0] < 1e-9 * scale && out.nodes[e[1]][0] < 1e-9 * scale;
        out.edges.push(e);
        out.edge_tags.push(if on_axis { crate::geometry::AXIS_TAG } else { HOUSING_TAG });
    }
    out
}

/// What the thermal problem knows about the brake's parts.
#[derive(Debug, Clone, PartialEq)]
pub struct ThermalParts {
    /// Energised coil tags with their resistance at 20 °C \[Ω\].
    pub coils: Vec<(u32, f64)>,
    /// Fluid-gap tags with their viscous heat at the speed \[W/m³\].
    pub gaps: Vec<(u32, f64)>,
    /// Copper fill factor of the winding.
    pub fill_factor: f64,
}

/// The copper fill factor of a coil's winding ([`crate::formula::copper_fill_factor`]), capped at
/// 0.9 (just below hexagonal packing, π/√12) for the homogenised winding.
fn winding_fill(spec: &BrakeSpec, coil: &crate::geometry::CoilInfo) -> f64 {
    let (w, h) = (coil.rect.r1 - coil.rect.r0, coil.rect.z1 - coil.rect.z0);
    crate::formula::copper_fill_factor(coil.turns, spec.wire_diameter_m(), w, h).min(0.9)
}

fn region_of(
    spec: &BrakeSpec,
    geometry: &BrakeGeometry,
    tag: u32,
    kind: PartKind,
    material: &str,
) -> Result<Region, ThermalError> {
    if kind == PartKind::Coil {
        let coil = geometry
            .coils
            .iter()
            .find(|c| c.tag == tag)
            .ok_or_else(|| DesignError::Internal(format!("coil region {tag} has no coil")))?;
        let fill = winding_fill(spec, coil);
        let w = Winding::impregnated(fill).and_then(|w| w.properties()).map_err(|e| {
            let e = FieldError::new("coil", format!("the winding's thermal model: {e}"))
                .with_value(format!("a copper fill factor of {fill:.3}"));
            spec.invalid(e.into())
        })?;
        return Ok(Region {
            tag,
            k_radial: w.k_radial_w_per_mk,
            k_axial: w.k_axial_w_per_mk,
            rho_c: w.rho_c,
            source: Source::None,
        });
    }
    let p = thermal(material)
        .map_err(|e| no_thermal_data(spec, &format!("part {tag}"), material, &e))?;
    Ok(Region::isotropic(tag, p.k_w_per_mk, p.volumetric_heat_capacity()))
}

/// The invalid-spec error of `part` (`part 3`, `part 'unit1.core'`), made of `material` that has
/// no thermal data: the `materials` key that names it, the material and why.
fn no_thermal_data(
    spec: &BrakeSpec,
    part: &str,
    material: &str,
    why: &mrbrake_materials::MaterialError,
) -> DesignError {
    let field = spec.materials.key_of(material).unwrap_or("materials");
    let e = FieldError::new(field, format!("{part}: no thermal data: {why}"))
        .with_value(format!("'{material}'"));
    spec.invalid(e.into())
}

/// The heat problem of the brake `spec` at `options` (current, speed, ambient, h).
pub fn thermal_problem(
    spec: &BrakeSpec,
    options: &ThermalOptions,
) -> Result<(HeatProblem, ThermalParts), ThermalError> {
    let geometry = spec.validate()?.geometry;
    let full = mesh_spec(spec, &geometry, options.mesh)?;
    thermal_problem_on_mesh(spec, options, &geometry, &full)
}

/// [`thermal_problem`] on the magnetic mesh `full` of `geometry` built before (shared with the
/// design's other analyses).
pub fn thermal_problem_on_mesh(
    spec: &BrakeSpec,
    options: &ThermalOptions,
    geometry: &BrakeGeometry,
    full: &Mesh,
) -> Result<(HeatProblem, ThermalParts), ThermalError> {
    let device = device_mesh(geometry, full);
    let d = spec.wire_diameter_m();
    let mut regions = Vec::new();
    let mut parts = ThermalParts { coils: Vec::new(), gaps: Vec::new(), fill_factor: 0.0 };
    let eta = mrbrake_materials::library::fluid(&spec.materials.fluid)
        .map(|f| f.viscosity_pa_s())
        .map_err(ThermalError::Material)?;
    for part in geometry.regions.iter().filter(|r| r.kind != PartKind::Air) {
        let mut region = region_of(spec, geometry, part.tag, part.kind, &part.material)?;
        if let Some(coil) = geometry.coils.iter().find(|c| c.tag == part.tag) {
            parts.fill_factor = winding_fill(spec, coil);
            if coil.unit == 0 {
                let r20 = COPPER_RESISTIVITY_20C_OHM_M
                    * f64::from(coil.turns)
                    * 2.0
                    * std::f64::consts::PI
                    * coil.rect.centre()[0]
                    / (std::f64::consts::PI * d * d / 4.0);
                parts.coils.push((coil.tag, r20));
                region.source = Source::Joule {
                    current_a: options.current_a * options.duty.sqrt(),
                    resistance_20c_ohm: r20,
                    alpha_per_k: COPPER_TEMPERATURE_COEFFICIENT_PER_K,
                };
            }
        }
        if let Some(gap) = geometry.gaps.iter().find(|g| g.tag == part.tag) {
            let rate = options.speed_rad_s * gap.mean_radius_m / gap.width_m;
            let q = eta * rate * rate;
            parts.gaps.push((gap.tag, q));
            region.source = Source::Uniform { w_per_m3: q };
        }
        regions.push(region);
    }
    let mut boundaries = vec![Boundary {
        tag: HOUSING_TAG,
        condition: BoundaryCondition::Convection {
            h_w_per_m2k: match options.cooling {
                Cooling::Fixed { h_w_per_m2k } => h_w_per_m2k,
                Cooling::Natural => NATURAL_START_H,
            },
            ambient_k: kelvin(options.ambient_c),
        },
    }];
    if options.emissivity > 0.0 {
        boundaries.push(Boundary {
            tag: HOUSING_TAG,
            condition: BoundaryCondition::Radiation {
                emissivity: options.emissivity,
                ambient_k: kelvin(options.ambient_c),
            },
        });
    }
    Ok((HeatProblem { mesh: Arc::new(device), regions, boundaries }, parts))
}

/// Steady temperatures of the brake.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct SteadyTemperatures {
    /// Coil hot spot \[°C\].
    #[serde(rename = "coil_max_T_C")]
    pub coil_max_t_c: f64,
    /// Coil mean \[°C\].
    #[serde(rename = "coil_mean_T_C")]
    pub coil_mean_t_c: f64,
    /// Fluid mean over the gaps \[°C\].
    #[serde(rename = "fluid_mean_T_C")]
    pub fluid_mean_t_c: f64,
    /// Fluid maximum \[°C\].
    #[serde(rename = "fluid_max_T_C")]
    pub fluid_max_t_c: f64,
    /// Hottest point of the outer surface \[°C\].
    #[serde(rename = "housing_max_T_C")]
    pub housing_max_t_c: f64,
    /// Heat generated (Joule + viscous) \[W\].
    #[serde(rename = "heat_W")]
    pub heat_w: f64,
    /// Generated − convected \[W\].
    #[serde(rename = "energy_balance_W")]
    pub energy_balance_w: f64,
    /// Coil resistance at its mean temperature \[Ω\].
    #[serde(rename = "coil_resistance_ohm")]
    pub coil_resistance_ohm: f64,
    /// Area-weighted mean of the outer surface \[°C\].
    #[serde(rename = "housing_mean_T_C")]
    pub housing_mean_t_c: f64,
    /// The housing's heat-transfer coefficient of this state \[W/(m² K)\].
    #[serde(rename = "h_W_per_m2_K")]
    pub h_w_per_m2k: f64,
}

/// The warm-up curve.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Warmup {
    /// Times \[s\].
    pub time_s: Vec<f64>,
    /// Coil hot spot \[°C\].
    #[serde(rename = "coil_max_T_C")]
    pub coil_max_t_c: Vec<f64>,
}

/// The result of `mrbrake thermal`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ThermalResult {
    /// Current when on \[A\].
    #[serde(rename = "current_A")]
    pub current_a: f64,
    /// Duty cycle.
    pub duty: f64,
    /// Insulation limit \[°C\].
    #[serde(rename = "limit_C")]
    pub limit_c: f64,
    /// Coil resistance at 20 °C (energised unit) \[Ω\].
    #[serde(rename = "coil_resistance_20C_ohm")]
    pub coil_resistance_20c_ohm: f64,
    /// Winding fill factor.
    pub fill_factor: f64,
    /// Steady state at the current and duty (`None`: thermal runaway, no steady state).
    pub steady: Option<SteadyTemperatures>,
    /// Current whose steady hot spot is the limit \[A\].
    #[serde(rename = "continuous_current_A")]
    pub continuous_current_a: f64,
    /// Largest duty cycle at the spec's maximum current.
    pub max_duty_at_max_current: f64,
    /// The spec's maximum current \[A\].
    #[serde(rename = "max_current_A")]
    pub max_current_a: f64,
    /// Time until the hot spot reaches the limit in the warm-up (`None`: not within the run).
    pub time_to_limit_s: Option<f64>,
    /// Warm-up from the ambient.
    pub warmup: Warmup,
    /// Ambient \[°C\].
    #[serde(rename = "ambient_C")]
    pub ambient_c: f64,
    /// How the housing was cooled.
    pub cooling: CoolingSummary,
    /// What heat does to the brake (with [`ThermalOptions::behaviour`]).
    pub behaviour: Option<behaviour::HotBehaviour>,
    /// Time constant of the warm-up: when the hot spot has risen by 63 % of its steady rise
    /// (`None`: no steady state, or not within the run) \[s\].
    pub time_constant_s: Option<f64>,
    /// What the model's assumptions do not cover for these options.
    pub warnings: Vec<String>,
    /// Mesh nodes of the device.
    pub nodes: usize,
    /// Seconds.
    pub timings_s: ThermalTimings,
}

/// The housing's cooling at the steady state of the run's current.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct CoolingSummary {
    /// `fixed` or `natural` (still air, axis horizontal).
    pub kind: &'static str,
    /// Heat-transfer coefficient \[W/(m² K)\].
    #[serde(rename = "h_W_per_m2_K")]
    pub h_w_per_m2k: f64,
    /// Natural convection: the lateral surface's coefficient \[W/(m² K)\].
    #[serde(rename = "h_side_W_per_m2_K")]
    pub h_side_w_per_m2k: Option<f64>,
    /// Natural convection: the end faces' coefficient \[W/(m² K)\].
    #[serde(rename = "h_ends_W_per_m2_K")]
    pub h_ends_w_per_m2k: Option<f64>,
    /// Natural convection: Rayleigh number on the outer diameter.
    pub rayleigh_d: Option<f64>,
    /// Emissivity of the housing (0: no radiation).
    pub emissivity: f64,
    /// Outer diameter and axial length used by the correlations \[m\].
    pub diameter_m: f64,
    /// Axial length \[m\].
    pub length_m: f64,
}

/// The steady temperature field at the run's current (or the warm-up's last state when there is
/// no steady state), as plain data for a map: the device's nodes, triangles and region tags, one
/// temperature per node.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TemperatureField {
    /// What the field is (`steady` or `end of warm-up`).
    pub state: &'static str,
    /// Node coordinates `[r, z]` \[m\].
    pub nodes: Vec<[f64; 2]>,
    /// Triangles (node indices).
    pub triangles: Vec<[usize; 3]>,
    /// Region tag per triangle.
    pub region_tags: Vec<u32>,
    /// Temperature per node \[°C\].
    #[serde(rename = "T_C")]
    pub t_c: Vec<f64>,
}

/// Timings of the thermal analysis.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ThermalTimings {
    /// Whole analysis \[s\].
    pub total: f64,
}

fn tags_max_mean(stats: &[mrbrake_heat::post::RegionStats], tags: &[u32]) -> (f64, f64) {
    let chosen: Vec<_> = stats.iter().filter(|s| tags.contains(&s.physical)).collect();
    let volume: f64 = chosen.iter().map(|s| s.volume_m3).sum();
    let mean = chosen.iter().map(|s| s.mean_k * s.volume_m3).sum::<f64>() / volume;
    (chosen.iter().map(|s| s.max_k).fold(f64::NEG_INFINITY, f64::max), mean)
}

/// First `h` of a natural-convection iteration \[W/(m² K)\] (a typical value for still air; the
/// iteration forgets it).
const NATURAL_START_H: f64 = 5.0;

/// Newton's relative residual tolerance with radiation (a linear problem converges in one step
/// anyway): on the brake's default mesh the radiating residual's round-off floor is about 1e-10 of
/// the first residual, the heat solver's default tolerance.
const NEWTON_TOLERANCE: f64 = 1e-9;

/// Relative change of `h` below which the natural-convection iteration stops.
const NATURAL_TOLERANCE: f64 = 1e-6;

/// The housing's cooling during a run: the option, the device's outer size for the
/// correlations, and the `h` the solver holds now.
#[derive(Debug, Clone, Copy)]
struct Housing {
    cooling: Cooling,
    /// Outer diameter and axial length \[m\].
    diameter_m: f64,
    length_m: f64,
    ambient_k: f64,
    h: f64,
}

impl Housing {
    fn new(mesh: &Mesh, options: &ThermalOptions) -> Self {
        let (mut r_max, mut z_lo, mut z_hi) = (0.0f64, f64::INFINITY, f64::NEG_INFINITY);
        for p in &mesh.nodes {
            r_max = r_max.max(p[0]);
            z_lo = z_lo.min(p[1]);
            z_hi = z_hi.max(p[1]);
        }
        let h = match options.cooling {
            Cooling::Fixed { h_w_per_m2k } => h_w_per_m2k,
            Cooling::Natural => NATURAL_START_H,
        };
        Self {
            cooling: options.cooling,
            diameter_m: 2.0 * r_max,
            length_m: z_hi - z_lo,
            ambient_k: kelvin(options.ambient_c),
            h,
        }
    }

    /// The natural-convection coefficients at the mean surface temperature `t_s` (kelvin), the
    /// film temperature held inside the air table; `true` when it had to be held (the surface is
    /// far beyond any insulation limit then).
    fn natural(&self, t_s: f64) -> Result<(convection::NaturalConvection, bool), ThermalError> {
        let [lo, hi] = convection::AIR_TABLE_RANGE_K;
        let held = (2.0 * lo - self.ambient_k).max(t_s.min(2.0 * hi - self.ambient_k));
        let c = convection::horizontal_brake(self.diameter_m, self.length_m, held, self.ambient_k)?;
        Ok((c, held < t_s))
    }
}

/// A steady state: the temperature per DOF (kelvin), and whether natural convection left its
/// air table.
struct SteadyField {
    t: Vec<f64>,
    beyond_air_table: bool,
}

/// The steady temperature at the solver's sources; with natural convection `h` is iterated with
/// the housing's mean surface temperature (fixed point, warm-started from the last `h`). `None`:
/// thermal runaway.
fn solve_steady(
    solver: &mut HeatSolver,
    housing: &mut Housing,
) -> Result<Option<SteadyField>, ThermalError> {
    for _ in 0..100 {
        let t = match solver.steady(None) {
            Ok((t, _)) => t,
            Err(HeatError::Runaway(_)) => return Ok(None),
            Err(e) => return Err(e.into()),
        };
        if housing.cooling != Cooling::Natural {
            return Ok(Some(SteadyField { t, beyond_air_table: false }));
        }
        let (_, t_s) = solver.boundary_mean(HOUSING_TAG, &t);
        let (c, beyond) = housing.natural(t_s)?;
        let h = c.h_mean_w_per_m2k;
        if (h - housing.h).abs() <= NATURAL_TOLERANCE * h {
            return Ok(Some(SteadyField { t, beyond_air_table: beyond }));
        }
        housing.h = h;
        solver.set_convection(HOUSING_TAG, h, housing.ambient_k)?;
    }
    Err(HeatError::LimitCrossed(
        "natural convection: h did not settle in 100 iterations with the surface temperature"
            .into(),
    )
    .into())
}

fn steady_summary(
    solver: &HeatSolver,
    parts: &ThermalParts,
    housing: &Housing,
    t: &[f64],
) -> SteadyTemperatures {
    let stats = solver.region_stats(t);
    let coil_tags: Vec<u32> = parts.coils.iter().map(|c| c.0).collect();
    let gap_tags: Vec<u32> = parts.gaps.iter().map(|g| g.0).collect();
    let (coil_max, coil_mean) = tags_max_mean(&stats, &coil_tags);
    let (fluid_max, fluid_mean) = tags_max_mean(&stats, &gap_tags);
    let housing_max = solver
        .basis()
        .dofs()
        .boundary_dofs(HOUSING_TAG)
        .iter()
        .map(|&d| t[d])
        .fold(f64::NEG_INFINITY, f64::max);
    let balance = solver.energy_balance(t);
    let r20: f64 = parts.coils.iter().map(|c| c.1).sum();
    SteadyTemperatures {
        coil_max_t_c: celsius(coil_max),
        coil_mean_t_c: celsius(coil_mean),
        fluid_mean_t_c: celsius(fluid_mean),
        fluid_max_t_c: celsius(fluid_max),
        housing_max_t_c: celsius(housing_max),
        heat_w: balance.generated_w,
        energy_balance_w: balance.imbalance_w,
        coil_resistance_ohm: r20
            * (1.0 + COPPER_TEMPERATURE_COEFFICIENT_PER_K * (celsius(coil_mean) - 20.0)),
        housing_mean_t_c: celsius(solver.boundary_mean(HOUSING_TAG, t).1),
        h_w_per_m2k: housing.h,
    }
}

/// The steady summary at the solver's sources (`None`: runaway, or a natural-convection state
/// beyond the air table).
fn steady_of(
    solver: &mut HeatSolver,
    parts: &ThermalParts,
    housing: &mut Housing,
) -> Result<Option<(SteadyTemperatures, Vec<f64>)>, ThermalError> {
    Ok(solve_steady(solver, housing)?
        .filter(|f| !f.beyond_air_table)
        .map(|f| (steady_summary(solver, parts, housing, &f.t), f.t)))
}

fn set_current(
    solver: &mut HeatSolver,
    parts: &ThermalParts,
    current: f64,
) -> Result<(), ThermalError> {
    for &(tag, r20) in &parts.coils {
        let source = Source::Joule {
            current_a: current,
            resistance_20c_ohm: r20,
            alpha_per_k: COPPER_TEMPERATURE_COEFFICIENT_PER_K,
        };
        solver.set_source(tag, source)?;
    }
    Ok(())
}

/// The current whose steady hot spot is `limit_c`, to 1e-4 relative: a bracket by doubling from
/// `start`, then regula falsi with the Illinois modification on the hot-spot excess
/// `T_max(I) − limit` (monotone in `I`; Dowell & Jarratt, BIT 11 (1971) 168–174: superlinear,
/// order ≈ 1.44: 10 steady solves for the thesis brake where bisection took 15), bisecting when
/// an end has no value (a runaway counts as above the limit). 0 when the hot spot is above the
/// limit even without current.
fn continuous_current(
    solver: &mut HeatSolver,
    parts: &ThermalParts,
    housing: &mut Housing,
    limit_c: f64,
    start: f64,
) -> Result<f64, ThermalError> {
    let mut excess = |solver: &mut HeatSolver, current: f64| -> Result<Excess, ThermalError> {
        set_current(solver, parts, current)?;
        Ok(steady_of(solver, parts, housing)?.map(|s| s.0.coil_max_t_c - limit_c))
    };
    let (mut lo, mut f_lo) = (0.0, excess(solver, 0.0)?);
    if is_above(f_lo) {
        return Ok(0.0);
    }
    let mut hi = start.max(0.1);
    let mut f_hi = excess(solver, hi)?;
    while !is_above(f_hi) {
        (lo, f_lo) = (hi, f_hi);
        hi *= 2.0;
        if hi > 1e4 {
            let e =
                FieldError::new("insulation_class", "the coil never reaches the limit below 10 kA")
                    .with_value(format!("{limit_c} °C"));
            return Err(e.into());
        }
        f_hi = excess(solver, hi)?;
    }
    let mut replaced_hi = None;
    for _ in 0..200 {
        if hi - lo <= 1e-4 * hi {
            break;
        }
        let x = illinois_point(lo, f_lo, hi, f_hi);
        let f = excess(solver, x)?;
        if f.is_some_and(|e| e.abs() < 1e-9) {
            return Ok(x);
        }
        let above = is_above(f);
        // The Illinois step: an end kept twice in a row (the other replaced twice) has its
        // value halved.
        if replaced_hi == Some(above) {
            if above { f_lo = f_lo.map(|e| 0.5 * e) } else { f_hi = f_hi.map(|e| 0.5 * e) }
        }
        if above {
            (hi, f_hi) = (x, f)
        } else {
            (lo, f_lo) = (x, f)
        }
        replaced_hi = Some(above);
    }
    Ok(0.5 * (lo + hi))
}

/// The hot-spot excess over the limit (K); `None`: runaway or beyond the air table.
type Excess = Option<f64>;

fn is_above(excess: Excess) -> bool {
    excess.is_none_or(|e| e > 0.0)
}

/// The false-position point of the bracket, kept a hundredth of the width inside it; the
/// midpoint when an end has no value.
fn illinois_point(lo: f64, f_lo: Excess, hi: f64, f_hi: Excess) -> f64 {
    let width = hi - lo;
    match (f_lo, f_hi) {
        (Some(a), Some(b)) if b > a => {
            (lo - a * width / (b - a)).clamp(lo + 0.01 * width, hi - 0.01 * width)
        }
        _ => 0.5 * (lo + hi),
    }
}

/// The DOFs of the elements of the regions `tags` (sorted, once each).
fn region_dofs(solver: &HeatSolver, tags: &[u32]) -> Vec<usize> {
    let mesh = &solver.problem().mesh;
    let mut dofs: Vec<usize> = (0..mesh.triangles.len())
        .filter(|&t| tags.contains(&mesh.triangle_tags[t]))
        .flat_map(|t| solver.basis().dofs().element(t).to_vec())
        .collect();
    dofs.sort_unstable();
    dofs.dedup();
    dofs
}

/// The warm-up from the ambient at the mean current `I √d` (with the housing's `h` as it is); the
/// hot spot of every step is the largest coil DOF temperature (as in the region statistics).
fn warmup(
    solver: &mut HeatSolver,
    parts: &ThermalParts,
    options: &ThermalOptions,
) -> Result<(Warmup, Vec<f64>), ThermalError> {
    set_current(solver, parts, options.current_a * options.duty.sqrt())?;
    let coil_tags: Vec<u32> = parts.coils.iter().map(|c| c.0).collect();
    let coil_dofs = region_dofs(solver, &coil_tags);
    let start = solver.uniform(kelvin(options.ambient_c));
    let mut curve = Warmup { time_s: vec![0.0], coil_max_t_c: vec![options.ambient_c] };
    let step = TimeStep::Fixed { dt_s: options.dt_s };
    let time = TimeOptions::new(options.time_s, Scheme::Bdf2, step);
    let outcome = solver.transient(&start, &time, |e: &Event<'_, HeatSolver>| {
        if e.level.index > 0 {
            let t = e.level.u;
            curve.time_s.push(e.level.t);
            curve
                .coil_max_t_c
                .push(celsius(coil_dofs.iter().map(|&d| t[d]).fold(f64::MIN, f64::max)));
        }
        Flow::Continue
    })?;
    Ok((curve, outcome.u))
}

/// The first time the curve crosses `limit` (linear interpolation), if it does.
fn crossing(curve: &Warmup, limit: f64) -> Option<f64> {
    let k = curve.coil_max_t_c.iter().position(|&t| t >= limit)?;
    if k == 0 {
        return Some(0.0);
    }
    let (t0, t1) = (curve.coil_max_t_c[k - 1], curve.coil_max_t_c[k]);
    Some(curve.time_s[k - 1] + (limit - t0) / (t1 - t0) * (curve.time_s[k] - curve.time_s[k - 1]))
}

/// Checks the options, naming the option (as the `[thermal]` table of a study does: `current`,
/// `duty`, `ambient`, `h`, `emissivity`, `insulation_class`, `dt`, `time`, `period`, `speed`),
/// its value and its allowed range.
pub fn validate_options(o: &ThermalOptions) -> Result<(), ThermalError> {
    let bad = |field: &str, value: String, allowed: String| {
        Err(FieldError::out_of_range(field, value, allowed).into())
    };
    if !(o.current_a.is_finite() && o.current_a > 0.0 && o.current_a <= 100.0) {
        return bad("current", format!("{} A", o.current_a), "(0, 100] A".into());
    }
    if !(o.duty > 0.0 && o.duty <= 1.0) {
        return bad("duty", o.duty.to_string(), "(0, 1]".into());
    }
    if !mrbrake_heat::AMBIENT_C.contains(o.ambient_c) {
        let allowed = mrbrake_heat::AMBIENT_C.describe("°C");
        return bad("ambient", format!("{} °C", o.ambient_c), allowed);
    }
    if let Cooling::Fixed { h_w_per_m2k: h } = o.cooling {
        if !(h.is_finite() && h > 0.0 && h <= 1e5) {
            return bad("h", format!("{h} W/(m² K)"), "(0, 1e5] W/(m² K)".into());
        }
    }
    if !(0.0..=1.0).contains(&o.emissivity) {
        return bad("emissivity", o.emissivity.to_string(), "[0, 1]".into());
    }
    if !(o.limit_c.is_finite() && o.limit_c > o.ambient_c && o.limit_c <= 1000.0) {
        let allowed = format!("above the ambient ({} °C) and <= 1000 °C", o.ambient_c);
        return bad("insulation_class", format!("{} °C", o.limit_c), allowed);
    }
    if !(o.dt_s.is_finite() && o.dt_s > 0.0) {
        return bad("dt", format!("{} s", o.dt_s), "> 0 s".into());
    }
    if !(o.time_s.is_finite() && o.time_s >= o.dt_s && o.time_s / o.dt_s <= 1e6) {
        let allowed = format!(">= the step ({} s) and at most 1e6 steps", o.dt_s);
        return bad("time", format!("{} s", o.time_s), allowed);
    }
    if let Some(p) = o.period_s {
        if !(p.is_finite() && p > 0.0) {
            return bad("period", format!("{p} s"), "> 0 s".into());
        }
    }
    if !(o.speed_rad_s.is_finite() && o.speed_rad_s >= 0.0 && o.speed_rad_s <= 1e4) {
        return bad("speed", format!("{} rad/s", o.speed_rad_s), "[0, 1e4] rad/s".into());
    }
    Ok(())
}

/// The assumptions a run's options stretch: a duty period that is not short against the thermal
/// time constant (the mean-power model misses the ripple of the hot spot).
fn warnings(
    o: &ThermalOptions,
    time_constant_s: Option<f64>,
    behaviour: Option<&behaviour::HotBehaviour>,
) -> Vec<String> {
    let mut out = Vec::new();
    if let Some(v) = behaviour.map(|b| &b.viscosity_hot).filter(|v| v.extrapolated_k > 20.0) {
        out.push(format!(
            "the fluid's viscosity at {:.0} °C is extrapolated {:.0} K beyond its data by Andrade's \
             law (low trust): the hot off-state torque is an estimate",
            v.temperature_c, v.extrapolated_k
        ));
    }
    if let (Some(period), Some(tau)) = (o.period_s, time_constant_s) {
        if o.duty < 1.0 && period > 0.1 * tau {
            out.push(format!(
                "the duty period {period} s is not short against the time constant {tau:.0} s: the \
                 mean-power model underestimates the hot spot's peak (ripple not resolved)"
            ));
        }
    }
    out
}

/// The cooling summary of the housing at the mean surface temperature `t_s` (kelvin).
fn cooling_summary(
    housing: &Housing,
    emissivity: f64,
    t_s: Option<f64>,
) -> Result<CoolingSummary, ThermalError> {
    let mut summary = CoolingSummary {
        kind: "fixed",
        h_w_per_m2k: housing.h,
        h_side_w_per_m2k: None,
        h_ends_w_per_m2k: None,
        rayleigh_d: None,
        emissivity,
        diameter_m: housing.diameter_m,
        length_m: housing.length_m,
    };
    if housing.cooling == Cooling::Natural {
        summary.kind = "natural";
        if let Some(t_s) = t_s {
            let (c, _) = housing.natural(t_s)?;
            summary.h_side_w_per_m2k = Some(c.h_side_w_per_m2k);
            summary.h_ends_w_per_m2k = Some(c.h_ends_w_per_m2k);
            summary.rayleigh_d = Some(c.rayleigh_d);
        }
    }
    Ok(summary)
}

/// The thermal analysis of `spec` (module docs).
pub fn analyze_thermal(
    spec: &BrakeSpec,
    options: &ThermalOptions,
) -> Result<ThermalResult, ThermalError> {
    analyze_thermal_with_field(spec, options).map(|(r, _)| r)
}

/// [`analyze_thermal`] and the temperature field for a map.
pub fn analyze_thermal_with_field(
    spec: &BrakeSpec,
    options: &ThermalOptions,
) -> Result<(ThermalResult, TemperatureField), ThermalError> {
    let start = Instant::now();
    validate_options(options)?;
    let (problem, parts) = thermal_problem(spec, options)?;
    let mesh = Arc::clone(&problem.mesh);
    let mut housing = Housing::new(&mesh, options);
    let solver_options = SolverOptions { tolerance: NEWTON_TOLERANCE, ..SolverOptions::default() };
    let mut solver = HeatSolver::new(problem, solver_options)?;
    let steady = steady_of(&mut solver, &parts, &mut housing)?;
    let steady_h = housing.h;
    let t_s = steady.as_ref().map(|s| kelvin(s.0.housing_mean_t_c));
    let cooling = cooling_summary(&housing, options.emissivity, t_s)?;
    let max_current_a = spec.coil.max_current.a();
    let continuous_current_a =
        continuous_current(&mut solver, &parts, &mut housing, options.limit_c, max_current_a)?;
    housing.h = steady_h;
    solver.set_convection(HOUSING_TAG, steady_h, housing.ambient_k)?;
    let behaviour = match (&steady, options.behaviour) {
        (Some((s, _)), true) => {
            Some(behaviour::hot_behaviour(spec, options, &mut solver, &parts, &mut housing, s)?)
        }
        _ => None,
    };
    housing.h = steady_h;
    solver.set_convection(HOUSING_TAG, steady_h, housing.ambient_k)?;
    let (warmup, end) = warmup(&mut solver, &parts, options)?;
    let (state, t) = match &steady {
        Some((_, t)) => ("steady", t.as_slice()),
        None => ("end of warm-up", end.as_slice()),
    };
    let field = TemperatureField {
        state,
        nodes: mesh.nodes.clone(),
        triangles: mesh.triangles.clone(),
        region_tags: mesh.triangle_tags.clone(),
        t_c: t[..mesh.nodes.len()].iter().map(|&v| celsius(v)).collect(),
    };
    let time_constant_s = steady
        .as_ref()
        .and_then(|(st, _)| crossing(&warmup, 0.63 * st.coil_max_t_c + 0.37 * options.ambient_c));
    let notes = warnings(options, time_constant_s, behaviour.as_ref());
    let result = ThermalResult {
        current_a: options.current_a,
        duty: options.duty,
        limit_c: options.limit_c,
        coil_resistance_20c_ohm: parts.coils.iter().map(|c| c.1).sum(),
        fill_factor: parts.fill_factor,
        steady: steady.map(|s| s.0),
        continuous_current_a,
        max_duty_at_max_current: (continuous_current_a / max_current_a).powi(2).min(1.0),
        max_current_a,
        time_to_limit_s: crossing(&warmup, options.limit_c),
        warmup,
        ambient_c: options.ambient_c,
        cooling,
        behaviour,
        warnings: notes,
        time_constant_s,
        nodes: mesh.nodes.len(),
        timings_s: ThermalTimings { total: start.elapsed().as_secs_f64() },
    };
    Ok((result, field))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The thesis brake at 2 A: the energy balance closes, the hot spot is the coil, the rating
    /// is consistent with the steady state (above the limit at 2 A iff the rating is below 2 A),
    /// and the warm-up rises monotonically towards the steady hot spot.
    #[test]
    fn thesis_brake_at_2_a() {
        let spec = crate::spec::default_spec();
        let options = ThermalOptions {
            mesh: MeshLevel::Coarse,
            time_s: 1800.0,
            dt_s: 30.0,
            ..ThermalOptions::default()
        };
        let result = analyze_thermal(&spec, &options).unwrap();
        let steady = result.steady.expect("a steady state at 2 A");
        println!(
            "thesis brake (coarse mesh), 2 A: {steady:?}; continuous {:.3} A, max duty {:.3}, time to 155 °C {:?} s, R20 {:.3} Ω, fill {:.3}",
            result.continuous_current_a,
            result.max_duty_at_max_current,
            result.time_to_limit_s,
            result.coil_resistance_20c_ohm,
            result.fill_factor
        );
        assert!(steady.energy_balance_w.abs() < 1e-9 * steady.heat_w);
        assert!(
            steady.coil_max_t_c >= steady.fluid_max_t_c
                && steady.coil_max_t_c >= steady.housing_max_t_c
        );
        let joule = 4.0 * steady.coil_resistance_ohm;
        assert!(
            (steady.heat_w - joule).abs() < 1e-6 * joule,
            "{} vs I²R(T̄) = {joule}",
            steady.heat_w
        );
        assert_eq!(steady.coil_max_t_c > 155.0, result.continuous_current_a < 2.0);
        let curve = &result.warmup.coil_max_t_c;
        assert!(curve.windows(2).all(|w| w[1] >= w[0] - 1e-9));
        assert!(*curve.last().unwrap() <= steady.coil_max_t_c + 1e-6);
    }

    /// Natural convection: the converged h is the correlation's at the housing's mean surface
    /// temperature, the energy balance closes with it; the voltage-driven hot state is
    /// self-consistent (`I = V / R(T̄)` to 1e-9) and cooler and weaker than the current-driven one.
    #[test]
    fn natural_convection_and_voltage_drive_are_self_consistent() {
        let spec = crate::spec::default_spec();
        let options = ThermalOptions {
            mesh: MeshLevel::Coarse,
            cooling: Cooling::Natural,
            time_s: 600.0,
            dt_s: 60.0,
            behaviour: true,
            ..ThermalOptions::default()
        };
        let result = analyze_thermal(&spec, &options).unwrap();
        let steady = result.steady.expect("a steady state");
        let c = result.cooling;
        let expected = convection::horizontal_brake(
            c.diameter_m,
            c.length_m,
            kelvin(steady.housing_mean_t_c),
            kelvin(25.0),
        )
        .unwrap();
        assert!((c.h_w_per_m2k / expected.h_mean_w_per_m2k - 1.0).abs() < 1e-5, "{c:?}");
        assert!(steady.energy_balance_w.abs() < 1e-9 * steady.heat_w);
        let b = result.behaviour.expect("behaviour");
        let v = b.voltage_drive;
        let r_hot = result.coil_resistance_20c_ohm
            * (1.0 + COPPER_TEMPERATURE_COEFFICIENT_PER_K * (v.coil_mean_t_c - 20.0));
        assert!((v.current_hot_a - v.voltage_v / r_hot).abs() < 1e-8 * v.current_hot_a);
        assert!(v.current_hot_a < 2.0 && v.coil_mean_t_c < steady.coil_mean_t_c);
        assert!(v.torque_hot_nm < b.torque_cold_nm);
        assert!(b.off_state_torque_hot_nm < b.off_state_torque_cold_nm);
        println!("natural convection (coarse): {c:?}; steady {steady:?}; behaviour {b:?}");
    }

    #[test]
    fn bad_duty_is_input() {
        let spec = crate::spec::default_spec();
        let e = analyze_thermal(&spec, &ThermalOptions { duty: 1.5, ..ThermalOptions::default() })
            .unwrap_err();
        assert_eq!(mrbrake_error::Kind::kind(&e), mrbrake_error::ErrorKind::Input);
    }
}

/// The thesis brake on the default mesh, 2 h warm-up at 10 s steps (slow in debug builds).
#[cfg(test)]
#[test]
#[cfg_attr(not(heavy_tests), ignore)]
fn thesis_brake_default_mesh_two_hours() {
    let spec = crate::spec::default_spec();
    let result = analyze_thermal(&spec, &ThermalOptions::default()).unwrap();
    let steady = result.steady.expect("steady at 2 A");
    let end = result.warmup.coil_max_t_c.last().copied().unwrap_or(f64::NAN);
    println!(
        "thesis brake (default mesh, {} nodes), 2 A, h = 10: steady {steady:?}; after 2 h {end:.1} °C; \
         continuous {:.3} A; max duty at {} A {:.3}; time to 155 °C {:?} s; {:.2} s",
        result.nodes,
        result.continuous_current_a,
        result.max_current_a,
        result.max_duty_at_max_current,
        result.time_to_limit_s,
        result.timings_s.total
    );
    assert!(steady.energy_balance_w.abs() < 1e-9 * steady.heat_w);
}
