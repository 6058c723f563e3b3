//! The torque–current hysteresis loop of a design, predicted from the magnetic hysteresis of its
//! solid-steel flux path: the remanent torque at 0 A after a current peak and the loop width.
//!
//! Every region of a library steel with a non-linear B–H curve (the flux path, and the shaft when it
//! is such a steel; a stainless shaft stays linear) is solved with
//! the energy-based hysteresis law of [`mrbrake_materials::hysteresis`] (the library's set of that
//! steel, its polarisation scaled by the spec's `steel.B_scale` for the flux-path material), one
//! state per quadrature point ([`mrbrake_magnetics::hysteresis`]). Direction 1's coil is driven
//! quasi-statically along the program
//!
//! `0 → I_p → 0 → I_p → 0 → −I_p → 0 → I_p`
//!
//! with [`LoopOptions::points_per_leg`] currents per leg, one Newton solve per current started from
//! a prediction of the previous ones (`QuasiStatic`) and the material states committed after each.
//! Its branches on the grid
//! `0 … I_p`:
//! * `initial`: the first magnetisation (legs 1), the anhysteretic analysis's curve up to the model's
//!   normal curve;
//! * `falling`: `I_p → 0` after the peak (leg 2); its value at 0 A is the **remanent torque**;
//! * `rising`: `0 → I_p` from the remanent state (leg 3): with `falling`, the loop of a unipolar
//!   current drive, the thesis's characterisation (0 → 2 A and back, repeated);
//! * `bipolar_rising`: `0 → I_p` after the negative peak (leg 7): the loop of a bipolar drive.
//!
//! The loop width at mid current is `falling − rising` at `I_p/2` (linear interpolation on the
//! grid). Torques are those of the analysis's curve points ([`crate::analysis`]: local Bingham yield
//! torque of the gaps at the local |B|, plus viscous and the constant friction of the spec's
//! `[drag]`); the remanent torque is the yield torque alone (the magnetic term of the off-state
//! breakdown, [`crate::drag::OffStateTorque::remanent_nm`]).

use std::sync::Arc;
use std::time::Instant;

use mrbrake_error::FieldError;
use mrbrake_magnetics::Solution;
use mrbrake_magnetics::hysteresis::HysteresisCommit;
use mrbrake_materials::hysteresis::{HysteresisParams, Term, library};
use mrbrake_materials::{MaterialKind, library as materials};
use serde::Serialize;

use crate::DesignError;
use crate::analysis::{AnalysisOptions, CurvePoint, Model};
use crate::drag::OffStateTorque;
use crate::mesh_build;
use crate::spec::BrakeSpec;

/// Currents per leg by default (the "≥ 40 current steps per branch").
pub const DEFAULT_POINTS_PER_LEG: usize = 40;

/// Most currents per leg (7 legs: a bound on the number of solves).
pub const MAX_POINTS_PER_LEG: usize = 1000;

/// The loop's legs as fractions of the peak current: (from, to, name).
const LEGS: [(f64, f64, &str); 7] = [
    (0.0, 1.0, "initial"),
    (1.0, 0.0, "falling"),
    (0.0, 1.0, "rising"),
    (1.0, 0.0, "falling_again"),
    (0.0, -1.0, "negative"),
    (-1.0, 0.0, "negative_return"),
    (0.0, 1.0, "bipolar_rising"),
];

/// Options of the loop.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LoopOptions {
    /// Peak current `I_p` (A), `None`: the coil's maximum current.
    pub peak_current_a: Option<f64>,
    /// Currents per leg (≥ 2).
    pub points_per_leg: usize,
}

impl Default for LoopOptions {
    fn default() -> Self {
        Self { peak_current_a: None, points_per_leg: DEFAULT_POINTS_PER_LEG }
    }
}

impl LoopOptions {
    /// The peak current of a coil whose maximum is `max_current_a`, checking every option: the
    /// peak finite in `(0, max_current]`, `2 ≤ points_per_leg ≤ MAX_POINTS_PER_LEG`.
    pub fn check(&self, max_current_a: f64) -> Result<f64, DesignError> {
        if !(2..=MAX_POINTS_PER_LEG).contains(&self.points_per_leg) {
            let e = FieldError::out_of_range(
                "loop_points",
                self.points_per_leg.to_string(),
                format!("2..={MAX_POINTS_PER_LEG} currents per leg"),
            );
            return Err(e.into());
        }
        let peak = self.peak_current_a.unwrap_or(max_current_a);
        if !(peak.is_finite() && peak > 0.0 && peak <= max_current_a) {
            let e = FieldError::out_of_range(
                "peak",
                format!("{peak} A"),
                format!("(0, {max_current_a}] A (the coil's maximum current)"),
            );
            return Err(e.into());
        }
        Ok(peak)
    }
}

/// One solved current of the program.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct LoopPoint {
    /// The leg (`initial`, `falling`, `rising`, …, module docs).
    pub leg: &'static str,
    /// Coil current, A.
    #[serde(rename = "current_A")]
    pub current_a: f64,
    /// Total torque of direction 1, N·m.
    #[serde(rename = "torque_Nm")]
    pub torque_nm: f64,
    /// Yield torque from the gaps' local |B|, N·m.
    #[serde(rename = "yield_torque_Nm")]
    pub yield_torque_nm: f64,
    /// Volume-mean |B| over direction 1's gaps, T.
    #[serde(rename = "mean_B_T")]
    pub mean_b_t: f64,
    /// Newton iterations of the step.
    pub newton_iterations: usize,
    /// Numeric Cholesky factorisations of the step (the other Newton steps were solved by
    /// conjugate gradients preconditioned with an earlier factor).
    pub factorizations: usize,
    /// Energy the step dissipated in the steel, J.
    #[serde(rename = "dissipated_J")]
    pub dissipated_j: f64,
}

/// The branches on the common current grid `0 … I_p` (module docs), N·m.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct LoopBranches {
    /// The grid, A.
    #[serde(rename = "current_A")]
    pub current_a: Vec<f64>,
    /// First magnetisation.
    #[serde(rename = "initial_Nm")]
    pub initial_nm: Vec<f64>,
    /// `0 → I_p` from the remanent state (unipolar drive).
    #[serde(rename = "rising_Nm")]
    pub rising_nm: Vec<f64>,
    /// `I_p → 0` after the peak.
    #[serde(rename = "falling_Nm")]
    pub falling_nm: Vec<f64>,
    /// `0 → I_p` after the negative peak (bipolar drive).
    #[serde(rename = "bipolar_rising_Nm")]
    pub bipolar_rising_nm: Vec<f64>,
}

/// The hysteresis law of one steel of the design, with its source.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SteelLaw {
    /// Library name.
    pub material: String,
    /// Source of the parameter set.
    pub source: String,
    /// How it was obtained.
    pub method: String,
    /// Trust (`low`, …).
    pub trust: String,
    /// Polarisation scale applied (`steel.B_scale` for the flux-path material, else 1).
    pub polarisation_scale: f64,
    /// Coercivity of the set's major loop (tip 20 kA/m), A/m.
    #[serde(rename = "coercivity_A_per_m")]
    pub coercivity_a_per_m: f64,
    /// Remanence of that loop, T (before the scale).
    #[serde(rename = "remanence_T")]
    pub remanence_t: f64,
}

/// Seconds spent.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct LoopTimings {
    /// Mesh and solver set-up.
    pub setup: f64,
    /// The quasi-static solves and their torques.
    pub solve: f64,
    /// Everything.
    pub total: f64,
}

/// The predicted hysteresis loop of a design.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct HysteresisLoop {
    /// The material model, in words.
    pub material_model: String,
    /// The steels' laws.
    pub steels: Vec<SteelLaw>,
    /// Peak current, A.
    #[serde(rename = "peak_current_A")]
    pub peak_current_a: f64,
    /// The branches.
    #[serde(rename = "loop")]
    pub branches: LoopBranches,
    /// Yield torque at 0 A after the peak, N·m.
    #[serde(rename = "remanent_torque_Nm")]
    pub remanent_torque_nm: f64,
    /// `falling − rising` at `I_p/2` (unipolar drive), N·m.
    #[serde(rename = "width_at_mid_current_Nm")]
    pub width_at_mid_current_nm: f64,
    /// `falling − bipolar_rising` at `I_p/2`, N·m.
    #[serde(rename = "bipolar_width_at_mid_current_Nm")]
    pub bipolar_width_at_mid_current_nm: f64,
    /// Energy dissipated in the steel over the bipolar cycle (legs 4–7), J.
    #[serde(rename = "dissipated_per_bipolar_cycle_J")]
    pub dissipated_per_bipolar_cycle_j: f64,
    /// Largest flux density across a point's axis over the program, T (how far the scalar model
    /// along a fixed axis is stretched: [`mrbrake_magnetics::hysteresis`]).
    #[serde(rename = "max_perpendicular_B_T")]
    pub max_perpendicular_b_t: f64,
    /// Every solved current in program order.
    pub path: Vec<LoopPoint>,
    /// Seconds spent.
    pub timings_s: LoopTimings,
}

/// The hysteresis laws of the steel regions of `model` (module docs), set on its solver.
pub(crate) fn set_steel_laws(
    spec: &BrakeSpec,
    model: &mut Model,
) -> Result<Vec<SteelLaw>, DesignError> {
    let mut laws: Vec<SteelLaw> = Vec::new();
    let mut regions = Vec::new();
    let mut params_of: Vec<(String, Arc<HysteresisParams>)> = Vec::new();
    for region in &model.geometry.regions {
        let material = materials::get(&region.material)
            .map_err(|source| DesignError::PartMaterial { part: region.name.clone(), source })?;
        // A steel with a linear law (stainless) has no curve to build a hysteresis set on.
        if material.kind != MaterialKind::Steel || !material.magnetic.is_nonlinear() {
            continue;
        }
        if let Some((_, params)) = params_of.iter().find(|(name, _)| *name == material.name) {
            regions.push((region.tag, Arc::clone(params)));
            continue;
        }
        let steel = library::for_material(&material.name)?;
        let scale =
            if region.material == spec.materials.flux_path { spec.steel.b_scale } else { 1.0 };
        let params = scaled(&steel.params, scale)?;
        laws.push(SteelLaw {
            material: material.name.clone(),
            source: steel.provenance.source.clone(),
            method: steel.provenance.method.clone(),
            trust: steel.provenance.trust.to_string(),
            polarisation_scale: scale,
            coercivity_a_per_m: steel.fitted_coercivity_a_per_m,
            remanence_t: steel.remanence_t,
        });
        params_of.push((material.name.clone(), Arc::clone(&params)));
        regions.push((region.tag, params));
    }
    if regions.is_empty() {
        let e = FieldError::new(
            "materials.flux_path",
            "the hysteresis loop needs a library steel in the flux path (a material with a \
             hysteresis model)",
        )
        .with_value(format!("'{}'", spec.materials.flux_path));
        return Err(e.into());
    }
    model.solver.set_hysteresis(&regions).map_err(crate::analysis::numerical)?;
    Ok(laws)
}

/// `params` with every term's polarisation times `scale` (`B = μ0 H + s J`, as `steel.B_scale`
/// scales the anhysteretic curve).
fn scaled(
    params: &Arc<HysteresisParams>,
    scale: f64,
) -> Result<Arc<HysteresisParams>, DesignError> {
    if (scale - 1.0).abs() <= f64::EPSILON {
        return Ok(Arc::clone(params));
    }
    let terms: Vec<Term> = params
        .terms()
        .into_iter()
        .map(|t| Term { polarisation_t: t.polarisation_t * scale, ..t })
        .collect();
    Ok(Arc::new(HysteresisParams::new(params.pinning_a_per_m(), &terms)?))
}

/// The program's currents: `(leg, current)` in order, `points_per_leg` per leg (module docs).
fn program(peak: f64, points_per_leg: usize) -> Vec<(&'static str, f64)> {
    let mut currents = Vec::with_capacity(LEGS.len() * points_per_leg);
    for (from, to, name) in LEGS {
        for k in 1..=points_per_leg {
            let fraction = from + (to - from) * k as f64 / points_per_leg as f64;
            currents.push((name, peak * fraction));
        }
    }
    currents
}

/// Predicts the hysteresis loop of `spec` (module docs) with the analysis options `options`
/// (mesh, order, speed, friction) and the loop options `loop_options`.
pub fn run(
    spec: &BrakeSpec,
    options: &AnalysisOptions,
    loop_options: &LoopOptions,
) -> Result<HysteresisLoop, DesignError> {
    let start = Instant::now();
    options.check()?;
    let geometry = spec.validate()?.geometry;
    let peak = loop_options.check(spec.coil.max_current.a())?;
    let mesh = Arc::new(mesh_build::mesh_spec(spec, &geometry, options.mesh)?);
    let mut model = Model::new(spec, geometry, mesh, options)?;
    let steels = set_steel_laws(spec, &mut model)?;
    let setup = start.elapsed().as_secs_f64();
    let solve_start = Instant::now();
    let (path, max_perpendicular) = solve_program(&mut model, peak, loop_options, options)?;
    let solve = solve_start.elapsed().as_secs_f64();
    let n = loop_options.points_per_leg;
    Ok(HysteresisLoop {
        material_model: "energy-based (play) hysteresis model, Henrotte, Nicolet, Hameyer, \
                         COMPEL 25(1) (2006) 71-80, scalar along each point's first field \
                         direction; Newton per current step with the exact tangent"
            .into(),
        steels,
        peak_current_a: peak,
        remanent_torque_nm: path[2 * n].yield_torque_nm,
        dissipated_per_bipolar_cycle_j: path[3 * n + 1..].iter().map(|p| p.dissipated_j).sum(),
        max_perpendicular_b_t: max_perpendicular,
        ..summarise(path, peak, n, setup, solve, start)
    })
}

/// Solves every current of the program; each failure names its step and current.
fn solve_program(
    model: &mut Model,
    peak: f64,
    loop_options: &LoopOptions,
    options: &AnalysisOptions,
) -> Result<(Vec<LoopPoint>, f64), DesignError> {
    let currents = program(peak, loop_options.points_per_leg);
    let mut path = Vec::with_capacity(currents.len() + 1);
    let mut steps = QuasiStatic::default();
    let mut max_perpendicular: f64 = 0.0;
    // The demagnetised start at 0 A (no solve needed: A = 0).
    path.push(LoopPoint {
        leg: "initial",
        current_a: 0.0,
        torque_nm: model.off_state.viscous_nm + model.off_state.constant_friction_nm(),
        yield_torque_nm: 0.0,
        mean_b_t: 0.0,
        newton_iterations: 0,
        factorizations: 0,
        dissipated_j: 0.0,
    });
    for (k, &(leg, current)) in currents.iter().enumerate() {
        let step = |e: DesignError| DesignError::LoopStep {
            step: k + 1,
            current_a: current,
            source: Box::new(e),
        };
        let (point, commit) = steps.step(model, current, options).map_err(step)?;
        max_perpendicular = max_perpendicular.max(commit.max_perpendicular_b_t);
        path.push(LoopPoint {
            leg,
            current_a: current,
            torque_nm: point.torque_nm,
            yield_torque_nm: point.yield_torque_nm,
            mean_b_t: point.mean_b_t,
            newton_iterations: point.newton_iterations,
            factorizations: steps.last_factorizations(),
            dissipated_j: commit.dissipated_j,
        });
    }
    Ok((path, max_perpendicular))
}

/// The quasi-static steps of one current history on one model: each step one Newton solve, the
/// material states committed after it.
///
/// Each solve is [`mrbrake_magnetics::Solver::solve_quasi_static`] (its first Newton step by CG with
/// the last step's factor). Newton starts from a prediction of the step's potential: the last two
/// solutions extrapolated linearly in the current when the step goes on in the last step's
/// direction (along a leg `A(I)` is piecewise smooth, so the start misses by the path's curvature,
/// O(ΔI²), instead of by the step, O(ΔI)); after a reversal (or with one solution only) the last
/// solution, as the law's slope changes there. Only Newton's start changes: its stopping rule, and so the accuracy of the
/// converged step, are those of the plain warm start.
#[derive(Debug, Default)]
pub(crate) struct QuasiStatic {
    /// The last step's current and solution.
    last: Option<(f64, Solution)>,
    /// The current and solution of the step before it.
    before: Option<(f64, Solution)>,
    /// The predicted start (reused storage).
    start: Vec<f64>,
    /// Newton iterations and numeric factorisations of every step so far.
    pub(crate) totals: SolveTotals,
    /// Numeric factorisations of the last step.
    last_factorizations: usize,
}

/// Newton iterations and numeric factorisations of a sequence of solves (the work measure of the
/// quasi-static histories: [`LoopPoint::factorizations`]).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize)]
pub struct SolveTotals {
    /// Newton iterations.
    pub newton_iterations: usize,
    /// Numeric Cholesky factorisations.
    pub factorizations: usize,
}

/// Largest ratio of the new step to the last one that is extrapolated (a longer step starts from
/// the last solution).
const MAX_EXTRAPOLATION: f64 = 2.0;

impl QuasiStatic {
    /// Solves direction 1 at `current` from the prediction and commits the material states: the
    /// curve point and the commit's summary.
    pub(crate) fn step(
        &mut self,
        model: &mut Model,
        current: f64,
        options: &AnalysisOptions,
    ) -> Result<(CurvePoint, HysteresisCommit), DesignError> {
        model.energise(current, 0.0)?;
        let initial = self.prediction(current);
        let solution =
            model.solver.solve_quasi_static(initial).map_err(crate::analysis::numerical)?;
        let (point, _) = model.direction1_torque(current, &solution, options)?;
        let commit = model.solver.commit_hysteresis(&solution);
        let report = &solution.report;
        self.totals.newton_iterations += report.iterations;
        self.totals.factorizations += report.factorizations;
        self.last_factorizations = report.factorizations;
        self.before = self.last.replace((current, solution));
        Ok((point, commit))
    }

    /// Numeric factorisations of the last step.
    pub(crate) fn last_factorizations(&self) -> usize {
        self.last_factorizations
    }

    /// Newton's start for a step to `current` (type docs); `None` before the first step (A = 0).
    fn prediction(&mut self, current: f64) -> Option<&[f64]> {
        let (i1, last) = self.last.as_ref()?;
        let a1 = last.a_phi();
        let Some((i0, before)) = &self.before else { return Some(a1) };
        let a0 = before.a_phi();
        let ratio = (current - i1) / (i1 - i0);
        if !(ratio.is_finite() && ratio > 0.0 && ratio <= MAX_EXTRAPOLATION) {
            return Some(a1);
        }
        self.start.clear();
        self.start.extend(a1.iter().zip(a0).map(|(x1, x0)| x1 + ratio * (x1 - x0)));
        Some(&self.start)
    }
}

/// The branches, widths and timings of a solved program (`path[0]` is the start at 0 A; leg `k`
/// holds `path[k n + 1 ..= (k + 1) n]`).
fn summarise(
    path: Vec<LoopPoint>,
    peak: f64,
    n: usize,
    setup: f64,
    solve: f64,
    start: Instant,
) -> HysteresisLoop {
    let current_a: Vec<f64> = (0..=n).map(|k| peak * k as f64 / n as f64).collect();
    // A leg's torques on the ascending grid, its first point being the previous leg's last.
    let leg = |index: usize| -> Vec<f64> {
        let mut values: Vec<f64> =
            path[index * n..=(index + 1) * n].iter().map(|p| p.torque_nm).collect();
        if LEGS[index].0 > LEGS[index].1 {
            values.reverse();
        }
        values
    };
    let branches = LoopBranches {
        current_a,
        initial_nm: leg(0),
        falling_nm: leg(1),
        rising_nm: leg(2),
        bipolar_rising_nm: leg(6),
    };
    let mid = |values: &[f64]| at(&branches.current_a, values, 0.5 * peak);
    let falling_mid = mid(&branches.falling_nm);
    HysteresisLoop {
        material_model: String::new(),
        steels: Vec::new(),
        peak_current_a: peak,
        width_at_mid_current_nm: falling_mid - mid(&branches.rising_nm),
        bipolar_width_at_mid_current_nm: falling_mid - mid(&branches.bipolar_rising_nm),
        branches,
        remanent_torque_nm: 0.0,
        dissipated_per_bipolar_cycle_j: 0.0,
        max_perpendicular_b_t: 0.0,
        path,
        timings_s: LoopTimings { setup, solve, total: start.elapsed().as_secs_f64() },
    }
}

/// Linear interpolation of `values` on the ascending grid `grid` at `x` (clamped to its ends).
fn at(grid: &[f64], values: &[f64], x: f64) -> f64 {
    let k = grid.partition_point(|&g| g < x).clamp(1, grid.len() - 1);
    let (x0, x1) = (grid[k - 1], grid[k]);
    let w = if x1 > x0 { ((x - x0) / (x1 - x0)).clamp(0.0, 1.0) } else { 0.0 };
    values[k - 1] + w * (values[k] - values[k - 1])
}

impl HysteresisLoop {
    /// The off-state breakdown `off` with this loop's remanent torque as its remanent term (and in
    /// its total), sourced.
    pub fn off_state_with_remanence(&self, off: &OffStateTorque) -> OffStateTorque {
        let mut with = off.clone();
        with.remanent_nm = self.remanent_torque_nm;
        with.total_nm = off.total_nm - off.remanent_nm + self.remanent_torque_nm;
        with.sources.remanent = format!(
            "the yield torque at 0 A after a {} A peak, from the quasi-static hysteretic field \
             solution ({}; steel sets: {})",
            self.peak_current_a,
            self.material_model,
            self.steels
                .iter()
                .map(|s| format!("{} (trust {})", s.material, s.trust))
                .collect::<Vec<_>>()
                .join(", ")
        );
        with
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_program_has_seven_legs_ending_at_the_peak() {
        let p = program(2.0, 4);
        assert_eq!(p.len(), 28);
        assert!((p[3].1 - 2.0).abs() < 1e-12 && p[7].1.abs() < 1e-12);
        assert!((p[19].1 + 2.0).abs() < 1e-12 && (p[27].1 - 2.0).abs() < 1e-12);
        assert_eq!(p[27].0, "bipolar_rising");
    }

    #[test]
    fn options_out_of_range_name_their_field() {
        let bad = LoopOptions { peak_current_a: Some(3.0), ..LoopOptions::default() };
        assert!(bad.check(2.0).unwrap_err().to_string().contains("peak"));
        let nan = LoopOptions { peak_current_a: Some(f64::NAN), ..LoopOptions::default() };
        assert!(nan.check(2.0).is_err());
        let few = LoopOptions { points_per_leg: 1, ..LoopOptions::default() };
        assert!(few.check(2.0).unwrap_err().to_string().contains("loop_points"));
        assert!((LoopOptions::default().check(2.0).unwrap() - 2.0).abs() < 1e-15);
    }

    #[test]
    fn interpolation_on_the_grid() {
        let grid = [0.0, 1.0, 2.0];
        assert!((at(&grid, &[0.0, 10.0, 30.0], 1.5) - 20.0).abs() < 1e-12);
        assert!((at(&grid, &[0.0, 10.0, 30.0], 0.0)).abs() < 1e-12);
    }
}
