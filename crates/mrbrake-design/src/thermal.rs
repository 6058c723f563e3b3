//! The brake's thermal model: its geometry and mesh as a heat problem (`mrbrake-heat`), the coil's
//! Joule loss `I² R(T)`, viscous dissipation in the gaps, convection from the housing; steady hot
//! spot, warm-up, continuous current rating, largest duty cycle at the maximum current and the
//! time to the insulation limit.
//!
//! Model (stated so its limits are visible):
//! - the device only: the air box of the magnetic mesh is dropped; every outer surface of the
//!   device (not the axis) loses heat by convection `h (T − T_∞)` with one coefficient `h` (the
//!   shaft ends included); internal contacts are perfect;
//! - the winding is homogenised (`mrbrake_materials::thermal::Winding`, copper in impregnating
//!   resin) with the fill factor `N π d²/4 / (C_w C_h)` of the spec's wire and turns;
//! - the Joule loss of the energised unit's coil(s) at the local temperature (`R20 = ρ20 N 2π r̄ /
//!   (π d²/4)`, IACS copper, `r̄` the window's centre radius); a bidirectional brake energises one
//!   unit at a time (as its controller does), unit 1 here;
//! - viscous dissipation in each gap at the speed `ω`, uniform at the Couette rate of the gap's
//!   mean radius: `q = η (ω r_m / g)²`, η the fluid's off-state viscosity of the library (30 °C);
//! - a duty cycle `d` at current `I` is its mean power: the warm-up uses `I √d` (valid when the
//!   period is much shorter than the thermal time constant, minutes here; the ripple is not
//!   resolved), and the largest duty at the maximum current is `(I_cont / I_max)²`.

use std::collections::HashMap;
use std::sync::Arc;
use std::time::Instant;

use mrbrake_fem::mesh::Mesh;
use mrbrake_heat::{
    Boundary, BoundaryCondition, HeatError, HeatProblem, HeatSolver, Region, SolverOptions, Source,
    TimeScheme, TransientSettings, celsius, kelvin,
};
use mrbrake_materials::thermal::{Winding, thermal};
use mrbrake_materials::wire::{COPPER_RESISTIVITY_20C_OHM_M, COPPER_TEMPERATURE_COEFFICIENT_PER_K};
use serde::Serialize;

use crate::DesignError;
use crate::geometry::{BrakeGeometry, PartKind};
use crate::mesh_build::{MeshLevel, mesh};
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
    /// A material without thermal data, or a bad option.
    #[error("{0}")]
    Input(String),
}

impl mrbrake_error::Kind for ThermalError {
    fn kind(&self) -> mrbrake_error::ErrorKind {
        match self {
            Self::Design(e) => e.kind(),
            Self::Heat(e) => e.kind(),
            Self::Input(_) => mrbrake_error::ErrorKind::Input,
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
    /// Ambient \[°C\].
    pub ambient_c: f64,
    /// Housing heat-transfer coefficient \[W/(m² K)\].
    pub h_w_per_m2k: f64,
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
}

impl Default for ThermalOptions {
    fn default() -> Self {
        Self {
            current_a: 2.0,
            duty: 1.0,
            ambient_c: 25.0,
            h_w_per_m2k: 10.0,
            limit_c: 155.0,
            time_s: 7200.0,
            dt_s: 10.0,
            speed_rad_s: 0.0,
            mesh: MeshLevel::Default,
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
            .ok_or_else(|| ThermalError::Input(format!("coil region {tag} has no coil")))?;
        let d = spec.wire_diameter_m();
        let fill =
            (f64::from(coil.turns) * std::f64::consts::PI * d * d / 4.0 / coil.rect.area_m2())
                .min(0.9);
        let w = Winding::impregnated(fill)
            .and_then(|w| w.properties())
            .map_err(|e| ThermalError::Input(format!("coil winding: {e}")))?;
        return Ok(Region {
            tag,
            k_radial: w.k_radial_w_per_mk,
            k_axial: w.k_axial_w_per_mk,
            rho_c: w.rho_c,
            source: Source::None,
        });
    }
    let p = thermal(material).map_err(|e| {
        ThermalError::Input(format!("part {tag} ({material}): no thermal data: {e}"))
    })?;
    Ok(Region::isotropic(tag, p.k_w_per_mk, p.volumetric_heat_capacity()))
}

/// The heat problem of the brake `spec` at `options` (current, speed, ambient, h).
pub fn thermal_problem(
    spec: &BrakeSpec,
    options: &ThermalOptions,
) -> Result<(HeatProblem, ThermalParts), ThermalError> {
    let validated = spec.validate()?;
    let geometry = validated.geometry;
    let full = mesh(&geometry, options.mesh)?;
    let device = device_mesh(&geometry, &full);
    let d = spec.wire_diameter_m();
    let mut regions = Vec::new();
    let mut parts = ThermalParts { coils: Vec::new(), gaps: Vec::new(), fill_factor: 0.0 };
    let eta = mrbrake_materials::library::fluid(&spec.materials.fluid)
        .map(|f| f.viscosity_pa_s())
        .map_err(|e| ThermalError::Input(e.to_string()))?;
    for part in geometry.regions.iter().filter(|r| r.kind != PartKind::Air) {
        let mut region = region_of(spec, &geometry, part.tag, part.kind, &part.material)?;
        if let Some(coil) = geometry.coils.iter().find(|c| c.tag == part.tag) {
            parts.fill_factor =
                (f64::from(coil.turns) * std::f64::consts::PI * d * d / 4.0 / coil.rect.area_m2())
                    .min(0.9);
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
    let boundaries = vec![Boundary {
        tag: HOUSING_TAG,
        condition: BoundaryCondition::Convection {
            h_w_per_m2k: options.h_w_per_m2k,
            ambient_k: kelvin(options.ambient_c),
        },
    }];
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
    /// Mesh nodes of the device.
    pub nodes: usize,
    /// Seconds.
    pub timings_s: ThermalTimings,
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

fn steady_of(
    solver: &mut HeatSolver,
    parts: &ThermalParts,
) -> Result<Option<SteadyTemperatures>, ThermalError> {
    let t = match solver.steady(None) {
        Ok((t, _)) => t,
        Err(HeatError::Runaway(_)) => return Ok(None),
        Err(e) => return Err(e.into()),
    };
    let stats = solver.region_stats(&t);
    let coil_tags: Vec<u32> = parts.coils.iter().map(|c| c.0).collect();
    let gap_tags: Vec<u32> = parts.gaps.iter().map(|g| g.0).collect();
    let (coil_max, coil_mean) = tags_max_mean(&stats, &coil_tags);
    let (fluid_max, fluid_mean) = tags_max_mean(&stats, &gap_tags);
    let housing = solver
        .basis()
        .dofs()
        .boundary_dofs(HOUSING_TAG)
        .iter()
        .map(|&d| t[d])
        .fold(f64::NEG_INFINITY, f64::max);
    let balance = solver.energy_balance(&t);
    let r20: f64 = parts.coils.iter().map(|c| c.1).sum();
    Ok(Some(SteadyTemperatures {
        coil_max_t_c: celsius(coil_max),
        coil_mean_t_c: celsius(coil_mean),
        fluid_mean_t_c: celsius(fluid_mean),
        fluid_max_t_c: celsius(fluid_max),
        housing_max_t_c: celsius(housing),
        heat_w: balance.generated_w,
        energy_balance_w: balance.imbalance_w,
        coil_resistance_ohm: r20
            * (1.0 + COPPER_TEMPERATURE_COEFFICIENT_PER_K * (celsius(coil_mean) - 20.0)),
    }))
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

/// The current whose steady hot spot is `limit_c` (bisection on the monotone `T_max(I)`; a
/// runaway counts as above the limit), to 1e-4 relative.
fn continuous_current(
    solver: &mut HeatSolver,
    parts: &ThermalParts,
    limit_c: f64,
    start: f64,
) -> Result<f64, ThermalError> {
    let above = |solver: &mut HeatSolver, current: f64| -> Result<bool, ThermalError> {
        set_current(solver, parts, current)?;
        Ok(steady_of(solver, parts)?.is_none_or(|s| s.coil_max_t_c > limit_c))
    };
    let (mut lo, mut hi) = (0.0, start.max(0.1));
    while !above(solver, hi)? {
        lo = hi;
        hi *= 2.0;
        if hi > 1e4 {
            return Err(ThermalError::Input("the coil never reaches the limit below 10 kA".into()));
        }
    }
    while hi - lo > 1e-4 * hi {
        let mid = 0.5 * (lo + hi);
        if above(solver, mid)? { hi = mid } else { lo = mid }
    }
    Ok(0.5 * (lo + hi))
}

fn warmup(
    solver: &mut HeatSolver,
    parts: &ThermalParts,
    options: &ThermalOptions,
) -> Result<Warmup, ThermalError> {
    set_current(solver, parts, options.current_a * options.duty.sqrt())?;
    let coil_tags: Vec<u32> = parts.coils.iter().map(|c| c.0).collect();
    let start = solver.uniform(kelvin(options.ambient_c));
    let mut curve = Warmup { time_s: vec![0.0], coil_max_t_c: vec![options.ambient_c] };
    let settings =
        TransientSettings { dt_s: options.dt_s, t_end_s: options.time_s, scheme: TimeScheme::Bdf2 };
    solver.transient(&start, &settings, |time, t, s| {
        let stats = s.region_stats(t);
        curve.time_s.push(time);
        curve.coil_max_t_c.push(celsius(tags_max_mean(&stats, &coil_tags).0));
        Ok(())
    })?;
    Ok(curve)
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

/// The thermal analysis of `spec` (module docs).
pub fn analyze_thermal(
    spec: &BrakeSpec,
    options: &ThermalOptions,
) -> Result<ThermalResult, ThermalError> {
    let start = Instant::now();
    if !(options.duty > 0.0 && options.duty <= 1.0) {
        return Err(ThermalError::Input(format!("duty = {} must be in (0, 1]", options.duty)));
    }
    if !(options.dt_s > 0.0 && options.time_s >= options.dt_s) {
        return Err(ThermalError::Input(format!(
            "time step {} s and duration {} s must be > 0 (step <= duration)",
            options.dt_s, options.time_s
        )));
    }
    let (problem, parts) = thermal_problem(spec, options)?;
    let nodes = problem.mesh.nodes.len();
    let mut solver = HeatSolver::new(problem, SolverOptions::default())?;
    let steady = steady_of(&mut solver, &parts)?;
    let max_current_a = spec.coil.max_current.a();
    let continuous_current_a =
        continuous_current(&mut solver, &parts, options.limit_c, max_current_a)?;
    let warmup = warmup(&mut solver, &parts, options)?;
    Ok(ThermalResult {
        current_a: options.current_a,
        duty: options.duty,
        limit_c: options.limit_c,
        coil_resistance_20c_ohm: parts.coils.iter().map(|c| c.1).sum(),
        fill_factor: parts.fill_factor,
        steady,
        continuous_current_a,
        max_duty_at_max_current: (continuous_current_a / max_current_a).powi(2).min(1.0),
        max_current_a,
        time_to_limit_s: crossing(&warmup, options.limit_c),
        warmup,
        nodes,
        timings_s: ThermalTimings { total: start.elapsed().as_secs_f64() },
    })
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
#[cfg_attr(debug_assertions, ignore)]
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
