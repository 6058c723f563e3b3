//! Brake analysis, end to end: spec → geometry → mesh → non-linear field at each current of a sweep →
//! torque (local Bingham integration and the thesis's mean-B method), coil, mechanics.
//!
//! Brief overview: an [`AnalysisRequest`] of a validated [`BrakeSpec`] with [`AnalysisOptions`]
//! (and, if wanted, an observer of the sweep) runs to an [`Analysis`]: the torque–current curve,
//! per-gap results at the maximum current, per-direction torque for the bidirectional brake, the
//! coil's electrical figures and inductance, and the mechanical figures (mass, volume, rotor
//! inertia, torque density). Run with the field ([`AnalysisRequest::run_with_field`]) it also
//! returns the field at the maximum current as plain data ([`FieldAtMaxCurrent`]: mesh, region
//! names and roles, B per triangle, flux function per node) for field maps and other front ends;
//! the solver itself stays inside.
//!
//! # Torque models
//! * **Local Bingham torque** (beyond the thesis): the yield stress follows the local flux density,
//!   `τ_y(|B(r, z)|)`. For a cylindrical (drum) gap at shear radius `R` and height `h` the yield torque
//!   is `T = ∫₀ʰ 2π R² τ_y(|B(z)|) dz` (thesis (3.5) integrated over the cylinder); for an annular
//!   (disc) gap it is `T = ∫_{R1}^{R2} 2π r² τ_y(|B(r)|) dr` (one face of (3.6)). B varies a little
//!   across the gap's width `g` too, so the integrand is averaged over it: `T = (1/g) ∫∫ 2π R² τ_y
//!   dr dz` (cylindrical; `r²` for annular) over the gap's cross-section, by the solver's quadrature
//!   on the exact field (`Solver::integrate_over_region`). Sampling B on the gap's mid-line instead
//!   made the torque depend on where the mesh put its edges (B tangential to an element edge jumps
//!   across it): 0.2-0.7 % between the two mirror-image units of the bidirectional brake, whose mean
//!   B agreed to 2e-5. The mid-line samples ([`GAP_SAMPLES`] intervals) remain the |B| profile.
//! * **Thesis method**: the volume-mean |B| over all fluid gaps of a direction → `τ_y` from the fluid's
//!   curve → (4.4) for drums (`2π h τ_y Σ R_k²`) and (3.7)/(3.8) for discs (per face: `2π τ_y (R2³ −
//!   R1³)/3`), as the thesis did with ANSYS's mean B (4.4.1).
//! * **Viscous torque** at the speed `ω` of the options (3.4): `2π R³ h η ω / g` per cylindrical gap
//!   and `π η ω (R2⁴ − R1⁴) / (2 g)` per annular gap; plus a constant seal-friction torque.
//!   The off-state torque is the total at zero current.
//!
//! The per-gap laws of the thesis method and of the viscous torque are those of [`formula`]
//! ([`formula::cylinder_yield_torque`], [`formula::annulus_yield_torque`],
//! [`formula::cylinder_viscous_torque`], [`formula::annulus_viscous_torque`]), the same that its
//! closed-form configurations sum.
//!
//! For the bidirectional brake the sweep energises the coil of unit 1 only (the controller drives one
//! brake at a time); the torque of direction 1 is that of unit 1's gaps. Unit 2 is solved once at the
//! maximum current with its own coil, and the torque that leaks into the idle unit's gaps (through the
//! shaft and spacer) is reported as cross-coupling.

use std::sync::Arc;
use std::time::Instant;

use mrbrake_error::FieldError;
use mrbrake_fem::mesh::Mesh;
/// The element order of [`AnalysisOptions::order`] (re-exported from `mrbrake_magnetics`).
pub use mrbrake_magnetics::ElementOrder;
use mrbrake_magnetics::problem::{Boundary, BoundaryCondition, Problem, Region, Source};
use mrbrake_magnetics::{Solution, Solver, SolverOptions};
use mrbrake_materials::{CopperWire, library};
use mrbrake_observe::{Count, Observer, Silent};
use serde::Serialize;

use crate::DesignError;
use crate::drag::{DragInputs, OffStateTorque};
use crate::formula;
use crate::geometry::{BrakeGeometry, Direction, GapInfo, GapOrientation, PartKind};
use crate::material_factors::{GapMedium, RegionLaws};
use crate::mesh_build::{self, MeshLevel};
use crate::spec::BrakeSpec;

/// Number of intervals of the |B| profile sampled along each gap's mid-line.
pub const GAP_SAMPLES: usize = 64;

/// Density of annealed copper (kg/m³) (IEC 60028: 8.89 g/cm³ at 20 °C).
const COPPER_DENSITY_KG_M3: f64 = 8890.0;

/// What to compute.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AnalysisOptions {
    /// Mesh density.
    pub mesh: MeshLevel,
    /// Number of currents in the torque–current sweep, from 0 to the maximum current (≥ 2).
    pub points: usize,
    /// Relative speed for the viscous torque (rad/s).
    pub speed_rad_s: f64,
    /// Constant seal / bearing friction added to every torque (N·m).
    pub seal_friction_nm: f64,
    /// Copper temperature for the resistance (°C).
    pub temperature_c: f64,
    /// Finite-element order of the field solution: linear (P1) or quadratic (P2, 6-node)
    /// triangles on the same mesh (about four times the unknowns; B converges one order faster).
    pub order: ElementOrder,
}

impl AnalysisOptions {
    /// Checks every option's range (the one place these rules live; front ends only parse):
    /// at least 2 points, a speed and a seal friction that are finite and not negative.
    pub fn check(&self) -> Result<(), DesignError> {
        if self.points < 2 {
            let e = FieldError::new(
                "points",
                "the torque–current sweep needs 0 A and the maximum current",
            )
            .with_value(self.points)
            .with_allowed(">= 2");
            return Err(e.into());
        }
        self.check_torque_terms()
    }

    /// The rules of the viscous and friction terms (all that [`direction1_points`] uses).
    fn check_torque_terms(&self) -> Result<(), DesignError> {
        // The viscous torque opposes the motion whichever way it turns: the speed is its
        // magnitude, and a negative one is a mistake rather than a direction.
        formula::non_negative("speed", "relative speed", self.speed_rad_s, "rad/s")?;
        formula::non_negative("seal_friction", "seal friction", self.seal_friction_nm, "N·m")?;
        Ok(())
    }
}

impl Default for AnalysisOptions {
    fn default() -> Self {
        // 1 rad/s: a slow hand motion on a haptic knob; it makes the viscous term visible without
        // dominating (the thesis quotes torques at rest, (3.7)).
        Self {
            mesh: MeshLevel::Default,
            points: 21,
            speed_rad_s: 1.0,
            seal_friction_nm: 0.0,
            temperature_c: 20.0,
            order: ElementOrder::P1,
        }
    }
}

/// One point of the torque–current curve.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct CurvePoint {
    /// Coil current (A).
    #[serde(rename = "current_A")]
    pub current_a: f64,
    /// Total braking torque of direction 1 (local Bingham + viscous + seal) (N·m).
    #[serde(rename = "torque_Nm")]
    pub torque_nm: f64,
    /// Yield torque from the local |B| alone (N·m).
    #[serde(rename = "yield_torque_Nm")]
    pub yield_torque_nm: f64,
    /// Thesis method at this current (N·m).
    #[serde(rename = "thesis_formula_Nm")]
    pub thesis_formula_nm: f64,
    /// Volume-mean |B| over direction 1's gaps (T).
    #[serde(rename = "mean_B_T")]
    pub mean_b_t: f64,
    /// Flux linkage of the energised coil (Wb).
    #[serde(rename = "flux_linkage_Wb")]
    pub flux_linkage_wb: f64,
    /// Newton iterations of this solve.
    pub newton_iterations: usize,
}

/// Serialises a 0-based index as the 1-based number the reports show.
fn one_based<S: serde::Serializer>(index: &usize, serializer: S) -> Result<S::Ok, S::Error> {
    serializer.serialize_u64(*index as u64 + 1)
}

/// One fluid gap at the maximum current.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct GapResult {
    /// Global gap index, 0-based here; serialised 1-based (`gap 1` is the first), as every
    /// report numbers gaps and units (docs/CONVENTIONS.md).
    #[serde(serialize_with = "one_based")]
    pub index: usize,
    /// Unit, 0 or 1 here; serialised 1-based (unit 1 resists positive rotation, 2 negative).
    #[serde(serialize_with = "one_based")]
    pub unit: usize,
    /// Shear radius R (drums: R_k of (4.4); discs: mean radius) (m).
    pub r_m: f64,
    /// Sheared height (drums) or radial span (discs) (m).
    pub height_m: f64,
    /// Gap width g (m).
    pub width_m: f64,
    /// `cylindrical` or `annular`.
    pub orientation: &'static str,
    /// Volume-mean |B| in the gap (T).
    #[serde(rename = "mean_B_T")]
    pub mean_b_t: f64,
    /// Largest |B| in the gap (T).
    #[serde(rename = "max_B_T")]
    pub max_b_t: f64,
    /// Yield stress at the mean |B| (Pa).
    #[serde(rename = "tau_y_Pa")]
    pub tau_y_pa: f64,
    /// Local Bingham yield torque (N·m).
    #[serde(rename = "torque_Nm")]
    pub torque_nm: f64,
    /// Viscous torque at the analysis speed (N·m).
    #[serde(rename = "viscous_torque_Nm")]
    pub viscous_torque_nm: f64,
    /// |B| along the mid-line: (position along the gap (m), |B| (T)).
    #[serde(skip)]
    pub profile: Vec<(f64, f64)>,
}

/// Torque summary.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct TorqueSummary {
    /// Total torque of direction 1 at the maximum current (N·m).
    #[serde(rename = "at_max_current_Nm")]
    pub at_max_current_nm: f64,
    /// Torque at zero current (viscous + seal) (N·m).
    #[serde(rename = "off_state_Nm")]
    pub off_state_nm: f64,
    /// Thesis method at the maximum current (N·m).
    #[serde(rename = "thesis_formula_Nm")]
    pub thesis_formula_nm: f64,
    /// Mean |B| over direction 1's gaps at the maximum current (T).
    #[serde(rename = "mean_B_T")]
    pub mean_b_t: f64,
    /// Dynamic range T_on / T_off (infinite when the off-state torque is 0).
    pub dynamic_range: f64,
    /// Direction 2's torque at the maximum current with its own coil (bidirectional only) (N·m).
    #[serde(rename = "direction2_at_max_current_Nm")]
    pub direction2_at_max_current_nm: Option<f64>,
    /// Yield torque that appears in the idle unit's gaps when only unit 1 is energised, as a fraction
    /// of unit 1's yield torque (bidirectional only).
    pub cross_coupling: Option<f64>,
}

/// The axial magnetic pull on the rotating parts at the maximum current: the part of the
/// bearings' load that the field makes ([`crate::drag`]).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RotorForces {
    /// Coil current of unit 1 (unit 2 idle) (A).
    #[serde(rename = "current_A")]
    pub current_a: f64,
    /// The rotating steel of each unit.
    pub units: Vec<RotorForce>,
    /// Their sum: the axial load the field puts on the shaft's bearings (N, + along +z).
    #[serde(rename = "total_axial_force_N")]
    pub total_axial_force_n: f64,
    /// The bearings' friction under the external load plus this pull, `½ μ P d` (N·m; 0 without
    /// bearings in `[drag]`).
    #[serde(rename = "bearing_friction_Nm")]
    pub bearing_friction_nm: f64,
}

/// The axial magnetic force on one unit's rotating steel.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RotorForce {
    /// Unit, 0-based here; serialised 1-based.
    #[serde(serialize_with = "one_based")]
    pub unit: usize,
    /// The parts of the body.
    pub parts: Vec<String>,
    /// Axial force (N, + along +z).
    #[serde(rename = "axial_force_N")]
    pub axial_force_n: f64,
}

/// Coil figures.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct CoilResult {
    /// Turns.
    pub turns: u32,
    /// Bare wire diameter (m).
    pub wire_diameter_m: f64,
    /// Wire length of one coil (m).
    pub wire_length_m: f64,
    /// Resistance at 20 °C (Ω).
    #[serde(rename = "resistance_20C_ohm")]
    pub resistance_20c_ohm: f64,
    /// Resistance at the analysis temperature (Ω).
    pub resistance_ohm: f64,
    /// Thesis current density (4.1) at the maximum current (A/mm²).
    #[serde(rename = "current_density_A_per_mm2")]
    pub current_density_a_per_mm2: f64,
    /// Ohmic power at the maximum current (W).
    #[serde(rename = "power_W")]
    pub power_w: f64,
    /// Secant inductance λ/I at the maximum current (H).
    #[serde(rename = "inductance_H")]
    pub inductance_h: f64,
    /// Incremental inductance dλ/dI at the maximum current (H).
    #[serde(rename = "incremental_inductance_H")]
    pub incremental_inductance_h: f64,
    /// L/R time constant with the secant inductance (s).
    pub time_constant_s: f64,
    /// Copper fill factor: copper area / window area ([`formula::copper_fill_factor`]); above
    /// [`formula::FILL_FACTOR_LIMIT`] the spec's warnings say so.
    pub fill_factor: f64,
}

/// Mechanical figures.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Mechanics {
    /// Mass of all modelled parts (air excluded) (kg).
    pub mass_kg: f64,
    /// Envelope volume of the device (its bounding cylinder) (m³).
    pub volume_m3: f64,
    /// Outer diameter of the modelled device (m).
    pub outer_diameter_m: f64,
    /// Axial length of the modelled device (m).
    pub length_m: f64,
    /// Moment of inertia of the parts that turn with the shaft in direction 1 (kg·m²).
    pub rotor_inertia_kg_m2: f64,
    /// The same for direction 2 (bidirectional only) (kg·m²).
    pub rotor_inertia_direction2_kg_m2: Option<f64>,
    /// Torque at the maximum current per envelope volume (N·m/m³).
    #[serde(rename = "torque_density_Nm_per_m3")]
    pub torque_density_nm_per_m3: f64,
    /// Torque at the maximum current per mass (N·m/kg).
    #[serde(rename = "torque_density_Nm_per_kg")]
    pub torque_density_nm_per_kg: f64,
}

/// Flux density in the steel flux path at the maximum current: how close the circuit is to saturation
/// (the thesis sized the flux path by hand so that the steel stays near 1 T, 4.4.1).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct FluxPathField {
    /// Largest |B| at any quadrature point of any flux-path part (T). Re-entrant steel corners make
    /// this a local, mesh-dependent peak.
    #[serde(rename = "max_B_T")]
    pub max_b_t: f64,
    /// The largest of the parts' volume-weighted 90 % quantiles of |B| (T): the level that a tenth
    /// of the most loaded part exceeds; robust to corner peaks, so better for a saturation limit.
    #[serde(rename = "q90_B_T")]
    pub q90_b_t: f64,
    /// Volume-weighted mean |B| over all flux-path parts (T).
    #[serde(rename = "mean_B_T")]
    pub mean_b_t: f64,
}

/// Mesh size.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct MeshSummary {
    /// Nodes.
    pub nodes: usize,
    /// Triangles.
    pub elements: usize,
    /// Element order of the field solution (1 or 2).
    pub order: usize,
    /// Unknowns of the field solution (free degrees of freedom).
    pub unknowns: usize,
}

/// Wall-clock split of an analysis (s).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Default)]
pub struct AnalysisTimings {
    /// Geometry and mesh.
    pub mesh: f64,
    /// Solver set-up (pattern, symbolic factorisation).
    pub setup: f64,
    /// All non-linear solves of the sweep.
    pub solve: f64,
    /// Torque, coil and mechanics post-processing.
    pub post: f64,
    /// Whole analysis.
    pub total: f64,
}

/// Everything an analysis computes ([`AnalysisRequest::run`]).
#[derive(Debug, Clone, Serialize)]
pub struct Analysis {
    /// Spec name.
    pub name: String,
    /// Configuration name.
    pub configuration: &'static str,
    /// Maximum current (A).
    #[serde(rename = "max_current_A")]
    pub max_current_a: f64,
    /// The sweep, direction 1.
    pub torque_current_curve: Vec<CurvePoint>,
    /// Torque summary.
    pub torque: TorqueSummary,
    /// The off-state torque of direction 1 and its terms, each with its source.
    pub torque_off: OffStateTorque,
    /// The axial magnetic pull on the rotating parts at the maximum current.
    pub rotor_forces: RotorForces,
    /// Per-gap results at the maximum current (all gaps; for the bidirectional brake unit 2's gaps are
    /// taken from the unit-2 solve).
    pub gaps: Vec<GapResult>,
    /// Coil.
    pub coil: CoilResult,
    /// Mechanics.
    pub mechanics: Mechanics,
    /// |B| in the steel flux path at the maximum current (unit 1 energised).
    pub flux_path: FluxPathField,
    /// Mesh size.
    pub mesh: MeshSummary,
    /// Analysis speed for the viscous term (rad/s).
    pub speed_rad_s: f64,
    /// Timings.
    pub timings_s: AnalysisTimings,
    /// Spec warnings (e.g. current above the wire rating).
    pub warnings: Vec<String>,
}

/// The magnetic field at the maximum current (unit 1 energised) as owned plain data, with no solver
/// attached: what a field map, a matplotlib `tripcolor` of a future Python `.field()` or an HTML
/// report needs. [`AnalysisRequest::run_with_field`] returns it; [`AnalysisRequest::run`] does not
/// build it (design studies run thousands of analyses and never draw the field).
///
/// The triangles are those of the mesh's vertices for both element orders: with quadratic (P2)
/// elements `A_phi` and the flux function are given at the vertices and B at the centroids, so a
/// P2 field is drawn on the same triangles as a P1 one.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FieldAtMaxCurrent {
    /// Coil current of unit 1 at which the field was solved (A).
    #[serde(rename = "current_A")]
    pub current_a: f64,
    /// Element order of the solution (1 or 2).
    pub order: usize,
    /// Node coordinates `[r, z]` (m).
    pub nodes: Vec<[f64; 2]>,
    /// Triangles (node indices, counter-clockwise).
    pub triangles: Vec<[usize; 3]>,
    /// Region tag of every triangle (named in [`Self::regions`]).
    pub region_tags: Vec<u32>,
    /// Every region of the geometry: its tag, part name and material.
    pub regions: Vec<FieldRegion>,
    /// `[B_r, B_z]` at the centroid of every triangle (T).
    #[serde(rename = "b_T")]
    pub b_t: Vec<[f64; 2]>,
    /// `|B|` at the centroid of every triangle (T).
    #[serde(rename = "b_abs_T")]
    pub b_abs_t: Vec<f64>,
    /// `A_phi` at the nodes (Wb/m).
    #[serde(rename = "a_phi_Wb_per_m")]
    pub a_phi_wb_per_m: Vec<f64>,
    /// Flux function `ψ = r A_phi` at the nodes (Wb/rad): the flux through the disc of radius r at
    /// height z is `2π ψ`, so flux lines are its level lines.
    #[serde(rename = "flux_function_Wb")]
    pub flux_function_wb: Vec<f64>,
}

/// One region of a [`FieldAtMaxCurrent`]: a part of the brake geometry (or the air around it).
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct FieldRegion {
    /// The tag that [`FieldAtMaxCurrent::region_tags`] refers to.
    pub tag: u32,
    /// Part name (e.g. `"shaft"`, `"gap 3"`).
    pub name: String,
    /// Library material of the part.
    pub material: String,
    /// What the part does (from the geometry, so a report never guesses it from the name);
    /// serialised in snake case (`"flux_path"`, `"fluid"`, `"coil"`, …).
    #[serde(serialize_with = "part_kind_name")]
    pub kind: PartKind,
}

/// Serialises a [`PartKind`] as its snake-case name.
fn part_kind_name<S: serde::Serializer>(kind: &PartKind, serializer: S) -> Result<S::Ok, S::Error> {
    serializer.serialize_str(match kind {
        PartKind::Shaft => "shaft",
        PartKind::FluxPath => "flux_path",
        PartKind::NonMagnetic => "non_magnetic",
        PartKind::Bobbin => "bobbin",
        PartKind::Coil => "coil",
        PartKind::Fluid => "fluid",
        PartKind::Spacer => "spacer",
        PartKind::Air => "air",
    })
}

impl FieldAtMaxCurrent {
    /// The field of `solution` on `model`'s mesh, the regions named after its parts.
    fn new(model: &Model, solution: &Solution) -> Self {
        let snapshot = model.solver.field_snapshot(solution);
        let regions = model
            .geometry
            .regions
            .iter()
            .map(|r| FieldRegion {
                tag: r.tag,
                name: r.name.clone(),
                material: r.material.clone(),
                kind: r.kind,
            })
            .collect();
        Self {
            current_a: model.max_current,
            order: model.order.degree(),
            nodes: snapshot.nodes,
            triangles: snapshot.triangles,
            region_tags: snapshot.region_tags,
            regions,
            b_t: snapshot.element_b_t,
            b_abs_t: snapshot.element_b_abs_t,
            a_phi_wb_per_m: snapshot.a_phi_wb_per_m,
            flux_function_wb: snapshot.flux_function_wb,
        }
    }

    /// The part name of region `tag` (`None` for a tag no region has).
    pub fn region_name(&self, tag: u32) -> Option<&str> {
        self.regions.iter().find(|r| r.tag == tag).map(|r| r.name.as_str())
    }
}

/// The analysis of one spec, as a request: [`AnalysisRequest::of`] the spec, with its
/// [`options`](AnalysisRequest::options) ([`AnalysisOptions::default`] unless given) and an
/// [`observer`](AnalysisRequest::observe) of the torque–current sweep (none unless given), then
/// [`run`](AnalysisRequest::run) for the [`Analysis`] or
/// [`run_with_field`](AnalysisRequest::run_with_field) for the field at the maximum current too.
///
/// ```no_run
/// use mrbrake_design::analysis::{AnalysisOptions, AnalysisRequest};
/// use mrbrake_observe::{Count, Flow};
/// let spec = mrbrake_design::spec::default_spec();
/// let options = AnalysisOptions { points: 5, ..AnalysisOptions::default() };
/// let (analysis, field) = AnalysisRequest::of(&spec)
///     .options(options)
///     .observe(|c: &Count| {
///         eprintln!("{}/{} currents", c.done, c.total);
///         Flow::Continue
///     })
///     .run_with_field()?;
/// assert_eq!(field.current_a, analysis.max_current_a);
/// # Ok::<(), mrbrake_design::DesignError>(())
/// ```
#[derive(Debug, Clone)]
#[must_use = "a request does nothing until it is run"]
pub struct AnalysisRequest<'s, O = Silent> {
    spec: &'s BrakeSpec,
    options: AnalysisOptions,
    observer: O,
}

impl<'s> AnalysisRequest<'s, Silent> {
    /// The analysis of `spec` with the default options and no observer.
    pub fn of(spec: &'s BrakeSpec) -> Self {
        Self { spec, options: AnalysisOptions::default(), observer: Silent }
    }
}

impl<'s, O: Observer<Count>> AnalysisRequest<'s, O> {
    /// Analyses with `options`.
    pub fn options(self, options: AnalysisOptions) -> Self {
        Self { options, ..self }
    }

    /// Calls `observer` with the currents done ([`Count`]) after each current of the
    /// torque–current sweep (for a front end's progress display on long sweeps, e.g.
    /// `--points 2000`). [`Flow::Stop`](mrbrake_observe::Flow::Stop) ends the analysis after that
    /// current with [`DesignError::Stopped`], which keeps the curve points solved so far.
    pub fn observe<P: Observer<Count>>(self, observer: P) -> AnalysisRequest<'s, P> {
        AnalysisRequest { spec: self.spec, options: self.options, observer }
    }

    /// Runs the whole analysis.
    pub fn run(mut self) -> Result<Analysis, DesignError> {
        run_analysis(self.spec, &self.options, &mut self.observer, |_, _| ())
            .map(|(analysis, ())| analysis)
    }

    /// Runs the analysis and also returns the field at the maximum current (for field maps;
    /// studies, which never draw it, use [`run`](Self::run)).
    pub fn run_with_field(mut self) -> Result<(Analysis, FieldAtMaxCurrent), DesignError> {
        run_analysis(self.spec, &self.options, &mut self.observer, FieldAtMaxCurrent::new)
    }
}

/// Direction 1's curve points (unit 1 energised) at the given `currents` (A, each in
/// `[0, max_current]`), solved in the order given, each Newton solve started from the previous
/// one: the torques at a few chosen currents without the whole sweep and direction 2 (e.g. the
/// hot current of [`crate::thermal`]), exactly where a sweep's curve would be interpolated.
/// `options.points` is not used.
pub fn direction1_points(
    spec: &BrakeSpec,
    options: &AnalysisOptions,
    currents: &[f64],
) -> Result<Vec<CurvePoint>, DesignError> {
    options.check_torque_terms()?;
    let geometry = spec.validate()?.geometry;
    let mesh = Arc::new(mesh_build::mesh_spec(spec, &geometry, options.mesh)?);
    let mut model = Model::new(spec, geometry, mesh, options)?;
    let mut previous: Option<Solution> = None;
    let mut points = Vec::with_capacity(currents.len().min(1024));
    for (k, &current) in currents.iter().enumerate() {
        if !(current.is_finite() && (0.0..=model.max_current).contains(&current)) {
            let e = FieldError::out_of_range(
                format!("currents[{k}]"),
                format!("{current} A"),
                format!("[0, {}] A (the coil's maximum current)", model.max_current),
            );
            return Err(e.into());
        }
        let (point, _, solution) = model.direction1_point(current, previous.as_ref(), options)?;
        points.push(point);
        previous = Some(solution);
    }
    Ok(points)
}

/// The analysis; `keep_field` takes what the caller wants of the field at the maximum current
/// (unit 1 energised) before the solver is dropped.
fn run_analysis<F>(
    spec: &BrakeSpec,
    options: &AnalysisOptions,
    observer: &mut dyn Observer<Count>,
    keep_field: impl FnOnce(&Model, &Solution) -> F,
) -> Result<(Analysis, F), DesignError> {
    let t_start = Instant::now();
    options.check()?;
    let validated = spec.validate()?;
    let warnings: Vec<String> =
        validated.warnings.iter().map(|w| format!("{}: {}", w.field, w.message)).collect();
    let geometry = validated.geometry;
    let mesh = Arc::new(mesh_build::mesh_spec(spec, &geometry, options.mesh)?);
    let t_mesh = t_start.elapsed().as_secs_f64();

    let t0 = Instant::now();
    let mut model = Model::new(spec, geometry, Arc::clone(&mesh), options)?;
    let t_setup = t0.elapsed().as_secs_f64();

    let t0 = Instant::now();
    let sweep = model.sweep(options, observer)?;
    let solved = model.direction2(sweep, options)?;
    let t_solve = t0.elapsed().as_secs_f64();

    // Coil: figures from the formulas plus the field's inductance.
    let t0 = Instant::now();
    let coil = coil_result(
        spec,
        &model.geometry,
        &mut model.solver,
        &solved.solution_at_max,
        &model.unit_coils[0],
        model.max_current,
        options,
    )?;
    let last = *solved.curve.last().expect("the sweep has at least two points");
    let mechanics = mechanics(&model.geometry, spec, last.torque_nm)?;
    let flux_path = flux_path_field(&model.solver, &solved.solution_at_max, &model.geometry)?;
    let torque = torque_summary(&solved);
    let rotor_forces = rotor_forces(
        &model.solver,
        &solved.solution_at_max,
        &model.geometry,
        spec,
        model.max_current,
    )?;
    let t_post = t0.elapsed().as_secs_f64();
    let analysis = Analysis {
        name: spec.name.clone(),
        configuration: spec.configuration.name(),
        max_current_a: model.max_current,
        torque_current_curve: solved.curve,
        torque,
        torque_off: model.off_state.clone(),
        rotor_forces,
        gaps: solved.gaps,
        coil,
        mechanics,
        flux_path,
        mesh: MeshSummary {
            nodes: mesh.nodes.len(),
            elements: mesh.triangles.len(),
            order: options.order.degree(),
            unknowns: model.solver.unknowns(),
        },
        speed_rad_s: options.speed_rad_s,
        timings_s: AnalysisTimings {
            mesh: t_mesh,
            setup: t_setup,
            solve: t_solve,
            post: t_post,
            total: t_start.elapsed().as_secs_f64(),
        },
        warnings,
    };
    let field = keep_field(&model, &solved.solution_at_max);
    Ok((analysis, field))
}

/// The field solver of one brake, with the coils of each unit and the fluid of its gaps.
pub(crate) struct Model {
    pub(crate) geometry: BrakeGeometry,
    fluid: GapMedium,
    pub(crate) solver: Solver,
    /// Coil tags of unit 1 and unit 2 (empty for a single brake).
    unit_coils: [Vec<u32>; 2],
    pub(crate) max_current: f64,
    turns: u32,
    order: ElementOrder,
    /// The off-state torque's breakdown; its terms besides the viscous one are the constant
    /// friction added to every torque.
    pub(crate) off_state: OffStateTorque,
}

/// The direction-1 sweep: the curve, unit 1's gaps and the solution at the maximum current.
struct Sweep {
    curve: Vec<CurvePoint>,
    gaps_at_max: Vec<GapResult>,
    solution_at_max: Solution,
}

/// Both directions solved: the sweep's curve, every gap at the maximum current, direction 2's
/// torque and the cross-coupling into the idle unit (bidirectional brakes only).
struct Solved {
    curve: Vec<CurvePoint>,
    gaps: Vec<GapResult>,
    solution_at_max: Solution,
    direction2_nm: Option<f64>,
    cross_coupling: Option<f64>,
}

impl Model {
    /// The magnetostatic problem of `geometry` on `mesh` and its solver.
    pub(crate) fn new(
        spec: &BrakeSpec,
        geometry: BrakeGeometry,
        mesh: Arc<Mesh>,
        options: &AnalysisOptions,
    ) -> Result<Self, DesignError> {
        let fluid = GapMedium::of(spec)?;
        let problem = problem_with(&RegionLaws::new(spec, &fluid)?, &geometry, mesh)?;
        let solver_options = SolverOptions { order: options.order, ..SolverOptions::default() };
        let solver = Solver::new(problem, solver_options).map_err(numerical)?;
        let unit_coils = |unit: usize| -> Vec<u32> {
            geometry.coils.iter().filter(|c| c.unit == unit).map(|c| c.tag).collect()
        };
        let unit_coils = [unit_coils(0), unit_coils(1)];
        let off_state = off_state_torque(spec, &geometry, &fluid, options);
        Ok(Self {
            off_state,
            fluid,
            solver,
            unit_coils,
            max_current: spec.coil.max_current.a(),
            turns: spec.turns(),
            order: options.order,
            geometry,
        })
    }

    /// Drives unit 1's coils with `i1` and unit 2's with `i2`.
    pub(crate) fn energise(&mut self, i1: f64, i2: f64) -> Result<(), DesignError> {
        let [unit1, unit2] = &self.unit_coils;
        set_coils(&mut self.solver, &self.geometry, unit1, unit2, i1, i2, self.turns)
    }

    /// The fluid gaps of `unit` (0 or 1).
    fn unit_gaps(&self, unit: usize) -> Vec<&GapInfo> {
        self.geometry.gaps.iter().filter(|g| g.unit == unit).collect()
    }

    /// The torque–current sweep: unit 1 energised, warm-started from the previous current.
    /// `observer` sees each current done and may stop the sweep ([`DesignError::Stopped`]).
    fn sweep(
        &mut self,
        options: &AnalysisOptions,
        observer: &mut dyn Observer<Count>,
    ) -> Result<Sweep, DesignError> {
        let mut curve = Vec::with_capacity(options.points);
        let mut previous: Option<Solution> = None;
        let mut gaps_at_max = Vec::new();
        for k in 0..options.points {
            let current = self.max_current * k as f64 / (options.points - 1) as f64;
            let (point, gaps, solution) =
                self.direction1_point(current, previous.as_ref(), options)?;
            curve.push(point);
            if k + 1 == options.points {
                gaps_at_max = gaps;
            }
            previous = Some(solution);
            let done = k + 1;
            let flow = observer.observe(&Count { done, total: options.points });
            if flow.is_stop() && done < options.points {
                return Err(DesignError::Stopped { curve, total: options.points });
            }
        }
        let solution_at_max = previous.expect("the sweep has at least two points");
        Ok(Sweep { curve, gaps_at_max, solution_at_max })
    }

    /// Direction 1 (unit 1 energised) at `current`, Newton started from `previous`: the curve
    /// point, unit 1's gaps and the solution.
    pub(crate) fn direction1_point(
        &mut self,
        current: f64,
        previous: Option<&Solution>,
        options: &AnalysisOptions,
    ) -> Result<(CurvePoint, Vec<GapResult>, Solution), DesignError> {
        self.energise(current, 0.0)?;
        let solution = self.solver.solve(previous.map(|s| s.a_phi())).map_err(numerical)?;
        let (point, gaps) = self.direction1_torque(current, &solution, options)?;
        Ok((point, gaps, solution))
    }

    /// The curve point and unit 1's gaps of direction 1 at `current` from its field `solution`.
    pub(crate) fn direction1_torque(
        &self,
        current: f64,
        solution: &Solution,
        options: &AnalysisOptions,
    ) -> Result<(CurvePoint, Vec<GapResult>), DesignError> {
        let dir1_gaps = self.unit_gaps(0);
        let speed = options.speed_rad_s;
        let gaps = gap_results(&self.solver, solution, &dir1_gaps, &self.fluid, speed)?;
        let friction = self.off_state.constant_friction_nm();
        let point =
            curve_point(&self.solver, solution, &gaps, &dir1_gaps, &self.fluid, current, friction)?;
        Ok((point, gaps))
    }

    /// Cross-coupling into the idle unit, and direction 2 with its own coil (bidirectional brakes);
    /// leaves the solver energised as for the sweep's maximum current.
    fn direction2(
        &mut self,
        sweep: Sweep,
        options: &AnalysisOptions,
    ) -> Result<Solved, DesignError> {
        let Sweep { curve, gaps_at_max: mut gaps, solution_at_max } = sweep;
        let mut solved = Solved {
            curve,
            gaps: Vec::new(),
            solution_at_max,
            direction2_nm: None,
            cross_coupling: None,
        };
        if self.unit_gaps(1).is_empty() {
            solved.gaps = gaps;
            return Ok(solved);
        }
        let dir2_gaps = self.unit_gaps(1);
        let solution_max = &solved.solution_at_max;
        let idle = gap_results(&self.solver, solution_max, &dir2_gaps, &self.fluid, 0.0)?;
        let idle_yield: f64 = idle.iter().map(|g| g.torque_nm).sum();
        let active_yield: f64 = gaps.iter().map(|g| g.torque_nm).sum();
        solved.cross_coupling =
            Some(if active_yield > 0.0 { idle_yield / active_yield } else { 0.0 });
        self.energise(0.0, self.max_current)?;
        // Unit 2 is unit 1 mirrored, so direction 1's field mirrored is direction 2's up to the
        // mesh (the mesher need not be symmetric): a start a few Newton steps from the answer.
        let start = match self.geometry.mirror_z {
            Some(z) => mirrored_potential(&self.solver, solution_max, z),
            None => solution_max.a_phi().to_vec(),
        };
        let s2 = self.solver.solve(Some(&start)).map_err(numerical)?;
        // Taken again: the list borrows the model, which `energise` changed in between.
        let dir2_gaps = self.unit_gaps(1);
        let g2 = gap_results(&self.solver, &s2, &dir2_gaps, &self.fluid, options.speed_rad_s)?;
        solved.direction2_nm = Some(
            g2.iter().map(|g| g.torque_nm + g.viscous_torque_nm).sum::<f64>()
                + self.off_state.constant_friction_nm(),
        );
        gaps.extend(g2);
        solved.gaps = gaps;
        // Leave the solver energised as for the returned solution.
        self.energise(self.max_current, 0.0)?;
        Ok(solved)
    }
}

/// The torque summary from the solved curve and directions.
fn torque_summary(solved: &Solved) -> TorqueSummary {
    let last = *solved.curve.last().expect("the sweep has at least two points");
    let first = solved.curve[0];
    TorqueSummary {
        at_max_current_nm: last.torque_nm,
        off_state_nm: first.torque_nm,
        thesis_formula_nm: last.thesis_formula_nm,
        mean_b_t: last.mean_b_t,
        dynamic_range: if first.torque_nm > 0.0 {
            last.torque_nm / first.torque_nm
        } else {
            f64::INFINITY
        },
        direction2_at_max_current_nm: solved.direction2_nm,
        cross_coupling: solved.cross_coupling,
    }
}

/// The off-state torque of direction 1 and its terms ([`crate::drag`]): the viscous drag of the
/// turning rotor's gaps and of the idle one's (the bidirectional brake's freewheel), with the
/// spec's `[drag]` and the analysis's constant friction.
fn off_state_torque(
    spec: &BrakeSpec,
    geometry: &BrakeGeometry,
    fluid: &GapMedium,
    options: &AnalysisOptions,
) -> OffStateTorque {
    let eta = fluid.surface_viscosity_pa_s();
    let unit_viscous = |unit: usize| -> f64 {
        let gaps = geometry.gaps.iter().filter(|g| g.unit == unit);
        gaps.map(|g| viscous_torque(g, eta, options.speed_rad_s)).sum()
    };
    let idle = geometry.gaps.iter().any(|g| g.unit == 1).then(|| unit_viscous(1));
    spec.drag.off_state(&DragInputs {
        viscous_nm: unit_viscous(0),
        idle_viscous_nm: idle,
        shaft_diameter_m: 2.0 * spec.shaft.radius.m(),
        extra_friction_nm: options.seal_friction_nm,
    })
}

/// The axial magnetic force on each unit's rotating steel at the maximum current (unit 1
/// energised), by virtual work on the layer of elements around it
/// ([`mrbrake_magnetics::Solver::axial_force`]), and the bearing friction that load adds.
/// Only the rotating flux-path parts form the body: they are surrounded by fluid and
/// non-magnetic parts, as the layer method needs (a non-magnetic rotor disc pressed against a
/// steel shaft is not, and carries no magnetic force of its own).
fn rotor_forces(
    solver: &Solver,
    solution: &Solution,
    geometry: &BrakeGeometry,
    spec: &BrakeSpec,
    current_a: f64,
) -> Result<RotorForces, DesignError> {
    let mut units = Vec::new();
    for unit in 0..geometry.units {
        let parts: Vec<_> = geometry
            .regions
            .iter()
            .filter(|r| r.rotates.is_some() && r.unit == Some(unit) && r.kind == PartKind::FluxPath)
            .collect();
        if parts.is_empty() {
            continue;
        }
        let tags: Vec<u32> = parts.iter().map(|r| r.tag).collect();
        let force = solver.axial_force(solution, &tags).map_err(numerical)?;
        let parts = parts.iter().map(|r| r.name.clone()).collect();
        units.push(RotorForce { unit, parts, axial_force_n: force });
    }
    let total: f64 = units.iter().map(|u| u.axial_force_n).sum();
    let load = spec.drag.external_bearing_load_n() + total.abs();
    let bearing = spec.drag.bearing_torque_nm(load, 2.0 * spec.shaft.radius.m());
    Ok(RotorForces { current_a, units, total_axial_force_n: total, bearing_friction_nm: bearing })
}

/// |B| statistics over the flux-path parts ([`PartKind::FluxPath`]).
fn flux_path_field(
    solver: &Solver,
    solution: &Solution,
    geometry: &BrakeGeometry,
) -> Result<FluxPathField, DesignError> {
    let mut field = FluxPathField { max_b_t: 0.0, q90_b_t: 0.0, mean_b_t: 0.0 };
    let mut volume = 0.0;
    for region in geometry.regions.iter().filter(|r| r.kind == PartKind::FluxPath) {
        let stats = solver.region_stats(solution, region.tag).map_err(numerical)?;
        field.max_b_t = field.max_b_t.max(stats.max_b_t);
        field.q90_b_t = field.q90_b_t.max(stats.quantiles_b_t[2]);
        field.mean_b_t += stats.mean_b_t * stats.volume_m3;
        volume += stats.volume_m3;
    }
    if volume > 0.0 {
        field.mean_b_t /= volume;
    }
    Ok(field)
}

pub(crate) fn numerical(e: mrbrake_magnetics::MagneticsError) -> DesignError {
    DesignError::FieldSolution(e)
}

fn material_error(e: mrbrake_materials::MaterialError) -> DesignError {
    DesignError::Material(e)
}

/// The magnetostatic problem: a library material per region, A = 0 on the axis and the air box.
pub fn problem_of(geometry: &BrakeGeometry, mesh: Arc<Mesh>) -> Result<Problem, DesignError> {
    let mut regions = Vec::with_capacity(geometry.regions.len());
    for region in &geometry.regions {
        let material = library::get(&region.material)
            .map_err(|source| DesignError::PartMaterial { part: region.name.clone(), source })?;
        regions.push(Region { tag: region.tag, material: material.magnetic.clone(), source: None });
    }
    Ok(problem_with_regions(geometry, mesh, regions))
}

/// The magnetostatic problem with the spec's material factors ([`RegionLaws`]).
pub(crate) fn problem_with(
    laws: &RegionLaws<'_>,
    geometry: &BrakeGeometry,
    mesh: Arc<Mesh>,
) -> Result<Problem, DesignError> {
    let regions = geometry
        .regions
        .iter()
        .map(|region| Ok(Region { tag: region.tag, material: laws.of(region)?, source: None }))
        .collect::<Result<Vec<_>, DesignError>>()?;
    Ok(problem_with_regions(geometry, mesh, regions))
}

fn problem_with_regions(
    geometry: &BrakeGeometry,
    mesh: Arc<Mesh>,
    regions: Vec<Region>,
) -> Problem {
    let boundaries = vec![
        Boundary { tag: geometry.axis_tag, condition: BoundaryCondition::Dirichlet },
        Boundary { tag: geometry.outer_tag, condition: BoundaryCondition::Dirichlet },
    ];
    Problem { mesh, regions, boundaries }
}

/// Drives the coils of unit 1 with `i1` and those of unit 2 with `i2` (each with its sign).
fn set_coils(
    solver: &mut Solver,
    geometry: &BrakeGeometry,
    unit1: &[u32],
    unit2: &[u32],
    i1: f64,
    i2: f64,
    turns: u32,
) -> Result<(), DesignError> {
    for coil in &geometry.coils {
        let current = if unit1.contains(&coil.tag) {
            i1
        } else if unit2.contains(&coil.tag) {
            i2
        } else {
            0.0
        };
        let source =
            Source::Coil { turns: f64::from(turns), current_a: coil.current_sign * current };
        solver.set_source(coil.tag, Some(source)).map_err(numerical)?;
    }
    Ok(())
}

/// `solution`'s potential mirrored about the plane `z = z_mirror`, at every degree of freedom of
/// `solver` (a DOF whose image falls outside the mesh starts at 0).
fn mirrored_potential(solver: &Solver, solution: &Solution, z_mirror: f64) -> Vec<f64> {
    solver
        .dof_coordinates()
        .iter()
        .map(|p| solver.a_phi_at(solution, [p[0], 2.0 * z_mirror - p[1]]).unwrap_or(0.0))
        .collect()
}

/// Local Bingham torque, mean |B| and |B| profile of each gap.
fn gap_results(
    solver: &Solver,
    solution: &Solution,
    gaps: &[&GapInfo],
    fluid: &GapMedium,
    speed_rad_s: f64,
) -> Result<Vec<GapResult>, DesignError> {
    let eta = fluid.surface_viscosity_pa_s();
    gaps.iter()
        .map(|gap| {
            let stats = solver.region_stats(solution, gap.tag).map_err(numerical)?;
            let torque = gap_yield_torque(solver, solution, gap, fluid)?;
            // The |B| profile along the mid-line, for plots.
            let line =
                solver.b_along(solution, &gap.sample_line, GAP_SAMPLES).map_err(numerical)?;
            let [p0, p1] = gap.sample_line;
            let ds = (p1[0] - p0[0]).hypot(p1[1] - p0[1]) / GAP_SAMPLES as f64;
            let profile =
                line.iter().enumerate().map(|(k, p)| (k as f64 * ds, p.b_abs_t)).collect();
            let viscous = viscous_torque(gap, eta, speed_rad_s);
            Ok(GapResult {
                index: gap.index,
                unit: gap.unit,
                r_m: gap.shear_radius_m,
                height_m: gap.height_m,
                width_m: gap.width_m,
                orientation: match gap.orientation {
                    GapOrientation::Cylindrical => "cylindrical",
                    GapOrientation::Annular => "annular",
                },
                mean_b_t: stats.mean_b_t,
                max_b_t: stats.max_b_t,
                tau_y_pa: fluid.tau_y_of_b(stats.mean_b_t),
                torque_nm: torque,
                viscous_torque_nm: viscous,
                profile,
            })
        })
        .collect()
}

/// The local Bingham yield torque of one gap: `(1/g) ∫∫ 2π r² τ_y(|B|) dr dz` over its
/// cross-section (module docs).
pub(crate) fn gap_yield_torque(
    solver: &Solver,
    solution: &Solution,
    gap: &GapInfo,
    fluid: &GapMedium,
) -> Result<f64, DesignError> {
    let two_pi = 2.0 * std::f64::consts::PI;
    let integral = solver
        .integrate_over_region(solution, gap.tag, |p, b| {
            let r = match gap.orientation {
                GapOrientation::Cylindrical => gap.shear_radius_m,
                GapOrientation::Annular => p[0],
            };
            two_pi * r * r * fluid.surface_tau_y_of_b(b[0].hypot(b[1]))
        })
        .map_err(numerical)?;
    Ok(integral / gap.width_m)
}

/// Viscous torque of one gap at relative speed `omega` (3.4), by the per-surface laws of
/// [`formula`]: cylindrical `2π R³ h η ω / g`; annular (one face of (3.6)) `π η ω (R2⁴ − R1⁴)/(2 g)`.
fn viscous_torque(gap: &GapInfo, eta: f64, omega: f64) -> f64 {
    let viscous = formula::Viscous { eta_pa_s: eta, omega_rad_s: omega.abs(), gap_m: gap.width_m };
    match gap.orientation {
        GapOrientation::Cylindrical => {
            formula::cylinder_viscous_torque(gap.shear_radius_m, gap.height_m, &viscous)
        }
        GapOrientation::Annular => {
            formula::annulus_viscous_torque(1.0, gap.rect.r0, gap.rect.r1, &viscous)
        }
    }
}

/// The thesis's method: volume-mean |B| over the direction's gaps → τ_y → (4.4) for cylindrical
/// surfaces, one face of (3.7) for annular ones (the laws of [`formula`]).
fn thesis_torque(gaps: &[GapResult], infos: &[&GapInfo], fluid: &GapMedium) -> (f64, f64) {
    let mut weighted = 0.0;
    let mut volume = 0.0;
    for info in infos {
        let v = info.rect.ring_volume_m3();
        let g = gaps.iter().find(|g| g.index == info.index).expect("a result for every gap");
        weighted += g.mean_b_t * v;
        volume += v;
    }
    let mean_b = if volume > 0.0 { weighted / volume } else { 0.0 };
    let tau = fluid.surface_tau_y_of_b(mean_b);
    let torque = infos
        .iter()
        .map(|g| match g.orientation {
            GapOrientation::Cylindrical => {
                formula::cylinder_yield_torque(g.height_m, tau, g.shear_radius_m.powi(2))
            }
            GapOrientation::Annular => {
                formula::annulus_yield_torque(1.0, g.rect.r0, g.rect.r1, tau)
            }
        })
        .sum();
    (mean_b, torque)
}

fn curve_point(
    solver: &Solver,
    solution: &Solution,
    gaps: &[GapResult],
    infos: &[&GapInfo],
    fluid: &GapMedium,
    current: f64,
    friction_nm: f64,
) -> Result<CurvePoint, DesignError> {
    let yield_nm: f64 = gaps.iter().map(|g| g.torque_nm).sum();
    let viscous: f64 = gaps.iter().map(|g| g.viscous_torque_nm).sum();
    let (mean_b, thesis) = thesis_torque(gaps, infos, fluid);
    let flux = solver
        .coils(solution)
        .iter()
        .filter(|c| c.current_a.abs() > 0.0)
        .map(|c| c.flux_linkage_wb * c.current_a.signum())
        .next()
        .unwrap_or(0.0);
    Ok(CurvePoint {
        current_a: current,
        torque_nm: yield_nm + viscous + friction_nm,
        yield_torque_nm: yield_nm,
        thesis_formula_nm: thesis,
        mean_b_t: mean_b,
        flux_linkage_wb: flux,
        newton_iterations: solution.report.iterations,
    })
}

/// The figures of a design that need no field solve, exactly as [`AnalysisRequest::run`] reports them: the
/// mechanics (torque densities NaN: no torque yet) and unit 1's coil at the maximum current
/// (turns, wire, resistance, current density, power; the inductances and time constant NaN), at
/// the copper temperature `temperature_c`. For a front end that shows them while the field is
/// being solved.
pub fn instant_figures(
    spec: &BrakeSpec,
    geometry: &BrakeGeometry,
    temperature_c: f64,
) -> Result<(Mechanics, CoilResult), DesignError> {
    let unit1: Vec<u32> = geometry.coils.iter().filter(|c| c.unit == 0).map(|c| c.tag).collect();
    let coil = coil_electrics(spec, geometry, &unit1, spec.coil.max_current.a(), temperature_c)?;
    Ok((mechanics(geometry, spec, f64::NAN)?, coil))
}

/// Unit 1's coil from the formulas (4.1)–(4.3) and the wire: everything of [`CoilResult`] but the
/// inductances and the time constant (NaN).
fn coil_electrics(
    spec: &BrakeSpec,
    geometry: &BrakeGeometry,
    unit1: &[u32],
    max_current: f64,
    temperature_c: f64,
) -> Result<CoilResult, DesignError> {
    let wire = CopperWire::from_diameter(spec.wire_diameter_m()).map_err(material_error)?;
    let coil = geometry
        .coils
        .iter()
        .find(|c| unit1.contains(&c.tag))
        .ok_or_else(|| DesignError::Internal("the geometry has no coil in unit 1".into()))?;
    let mean_radius = 0.5 * (coil.rect.r0 + coil.rect.r1);
    let e = formula::coil_electrics(coil.turns, mean_radius, &wire, max_current, temperature_c)?;
    let coils_in_series = unit1.len() as f64;
    Ok(CoilResult {
        turns: coil.turns,
        wire_diameter_m: wire.diameter_m,
        wire_length_m: e.wire_length_m,
        resistance_20c_ohm: e.resistance_20c_ohm,
        resistance_ohm: e.resistance_ohm,
        current_density_a_per_mm2: e.current_density_a_per_mm2,
        power_w: e.power_w * coils_in_series,
        inductance_h: f64::NAN,
        incremental_inductance_h: f64::NAN,
        time_constant_s: f64::NAN,
        fill_factor: spec.fill_factor(),
    })
}

fn coil_result(
    spec: &BrakeSpec,
    geometry: &BrakeGeometry,
    solver: &mut Solver,
    solution: &Solution,
    unit1: &[u32],
    max_current: f64,
    options: &AnalysisOptions,
) -> Result<CoilResult, DesignError> {
    let electrics = coil_electrics(spec, geometry, unit1, max_current, options.temperature_c)?;
    // Flux linkage of every energised coil of unit 1 (two-sided coils are in series).
    let flux: f64 = solver
        .coils(solution)
        .iter()
        .filter(|c| unit1.contains(&c.physical))
        .map(|c| c.flux_linkage_wb * c.current_a.signum())
        .sum();
    let secant = if max_current > 0.0 { flux / max_current } else { f64::NAN };
    let mut incremental = 0.0;
    for &tag in unit1 {
        let sign = geometry.coils.iter().find(|c| c.tag == tag).map_or(1.0, |c| c.current_sign);
        incremental +=
            sign * sign * solver.incremental_inductance(solution, tag).map_err(numerical)?;
    }
    let resistance = electrics.resistance_ohm * unit1.len() as f64;
    Ok(CoilResult {
        inductance_h: secant,
        incremental_inductance_h: incremental,
        time_constant_s: secant / resistance,
        ..electrics
    })
}

/// Density of a library material (kg/m³) (0 for air / unknown with a clear error otherwise).
fn density(spec: &BrakeSpec, material: &str) -> Result<f64, DesignError> {
    let m = library::get(material).map_err(material_error)?;
    if let Some(fluid) = &m.fluid {
        return Ok(fluid.density_kg_m3.value);
    }
    m.density_kg_m3.as_ref().map(|d| d.value).ok_or_else(|| {
        let field = spec.materials.key_of(material).unwrap_or("materials");
        let e = FieldError::new(field, "the material has no density in the library; pick another")
            .with_value(format!("'{material}'"));
        spec.invalid(e.into())
    })
}

/// Mass, envelope volume, rotor inertia per direction and torque density.
///
/// Each rectangle of a part sweeps a ring of volume `π (r1² − r0²) Δz` and inertia
/// `ρ π (r1⁴ − r0⁴) Δz / 2` about the axis. A coil counts its copper only
/// (`N · π d²/4 · 2π r_mean`). The fluid is not counted in the rotor inertia (it is sheared, not
/// carried).
fn mechanics(
    geometry: &BrakeGeometry,
    spec: &BrakeSpec,
    torque_nm: f64,
) -> Result<Mechanics, DesignError> {
    let pi = std::f64::consts::PI;
    let mut mass = 0.0;
    let mut inertia = [0.0f64; 2];
    for region in &geometry.regions {
        match region.kind {
            PartKind::Air => continue,
            PartKind::Coil => {
                let d = spec.wire_diameter_m();
                for coil in geometry.coils.iter().filter(|c| c.tag == region.tag) {
                    let r_mean = 0.5 * (coil.rect.r0 + coil.rect.r1);
                    mass += COPPER_DENSITY_KG_M3 * f64::from(coil.turns) * pi * d * d / 4.0
                        * 2.0
                        * pi
                        * r_mean;
                }
                continue;
            }
            _ => {}
        }
        let rho = density(spec, &region.material)?;
        mass += rho * region.volume_m3();
        if let Some(direction) = region.rotates {
            let j: f64 = region
                .rects
                .iter()
                .map(|r| rho * pi * (r.r1.powi(4) - r.r0.powi(4)) * (r.z1 - r.z0) / 2.0)
                .sum();
            match direction {
                Direction::Both => {
                    inertia[0] += j;
                    inertia[1] += j;
                }
                Direction::Clockwise => inertia[0] += j,
                Direction::CounterClockwise => inertia[1] += j,
            }
        }
    }
    let d = geometry.device;
    let volume = pi * d.r1 * d.r1 * (d.z1 - d.z0);
    Ok(Mechanics {
        mass_kg: mass,
        volume_m3: volume,
        outer_diameter_m: 2.0 * d.r1,
        length_m: d.z1 - d.z0,
        rotor_inertia_kg_m2: inertia[0],
        rotor_inertia_direction2_kg_m2: (geometry.units > 1).then_some(inertia[1]),
        torque_density_nm_per_m3: torque_nm / volume,
        torque_density_nm_per_kg: torque_nm / mass,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The field product is the solution at the maximum current on the mesh, with every region
    /// named, and asking for it changes no result.
    #[test]
    fn the_field_at_max_current_is_plain_data_of_the_last_solve() {
        let spec = crate::spec::default_spec();
        let options = AnalysisOptions { mesh: MeshLevel::Coarse, points: 2, ..Default::default() };
        let (analysis, field) =
            AnalysisRequest::of(&spec).options(options).run_with_field().unwrap();
        let alone = AnalysisRequest::of(&spec).options(options).run().unwrap();
        assert_eq!(
            alone.torque.at_max_current_nm.to_bits(),
            analysis.torque.at_max_current_nm.to_bits()
        );
        assert_eq!(field.current_a.to_bits(), analysis.max_current_a.to_bits());
        assert_eq!(
            (field.nodes.len(), field.triangles.len()),
            (analysis.mesh.nodes, analysis.mesh.elements)
        );
        assert_eq!(field.order, 1);
        let n = field.nodes.len();
        assert_eq!(field.flux_function_wb.len(), n);
        assert_eq!(field.a_phi_wb_per_m.len(), n);
        for (k, p) in field.nodes.iter().enumerate() {
            let psi = p[0] * field.a_phi_wb_per_m[k];
            assert!((field.flux_function_wb[k] - psi).abs() <= 1e-15 * psi.abs().max(1e-30));
        }
        assert_eq!(field.b_abs_t.len(), field.triangles.len());
        for (b, b_abs) in field.b_t.iter().zip(&field.b_abs_t) {
            assert!((b[0].hypot(b[1]) - b_abs).abs() <= 1e-15 * b_abs.max(1e-30));
        }
        assert!(field.triangles.iter().flatten().all(|&v| v < n));
        assert!(field.region_tags.iter().all(|&tag| field.region_name(tag).is_some()));
        // The centroid values sample the field of the flux-path statistics: their peak reaches
        // the most loaded steel part's 90 % quantile.
        let b_max = field.b_abs_t.iter().fold(0.0_f64, |m, &b| m.max(b));
        assert!(b_max >= analysis.flux_path.q90_b_t, "{b_max} < {}", analysis.flux_path.q90_b_t);
        assert!(field.region_name(u32::MAX).is_none());
    }

    /// Direction 2 warm-started from direction 1's field mirrored (the bidirectional brake's unit
    /// 2 is unit 1 mirrored) converges to the same field as a cold start, in fewer iterations.
    #[test]
    fn the_mirrored_warm_start_reaches_the_cold_start_answer_sooner() {
        let spec = crate::spec::default_spec();
        let geometry = crate::geometry::build(&spec).unwrap();
        let z = geometry.mirror_z.expect("the thesis brake is bidirectional");
        let mesh = Arc::new(mesh_build::mesh(&geometry, MeshLevel::Coarse).unwrap());
        let problem = problem_of(&geometry, mesh).unwrap();
        let mut solver = Solver::new(problem, SolverOptions::default()).unwrap();
        let unit = |u: usize| -> Vec<u32> {
            geometry.coils.iter().filter(|c| c.unit == u).map(|c| c.tag).collect()
        };
        let (unit1, unit2) = (unit(0), unit(1));
        let (i, turns) = (spec.coil.max_current.a(), spec.turns());
        set_coils(&mut solver, &geometry, &unit1, &unit2, i, 0.0, turns).unwrap();
        let direction1 = solver.solve(None).unwrap();
        set_coils(&mut solver, &geometry, &unit1, &unit2, 0.0, i, turns).unwrap();
        let cold = solver.solve(None).unwrap();
        let warm = solver.solve(Some(&mirrored_potential(&solver, &direction1, z))).unwrap();
        assert!(warm.report.converged && cold.report.converged);
        assert!(
            warm.report.iterations < cold.report.iterations,
            "mirrored start {} iterations, cold start {}",
            warm.report.iterations,
            cold.report.iterations
        );
        let scale = cold.a_phi().iter().fold(0.0_f64, |m, a| m.max(a.abs()));
        let diff =
            cold.a_phi().iter().zip(warm.a_phi()).fold(0.0_f64, |m, (a, b)| m.max((a - b).abs()));
        assert!(diff <= 1e-6 * scale, "max |ΔA| {diff:e} of max |A| {scale:e}");
    }
}
