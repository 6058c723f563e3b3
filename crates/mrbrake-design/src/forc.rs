//! First-order reversal curves (FORCs) of a design's torque in the unipolar current range the
//! controller drives, `[0, I_max]`, from the quasi-static hysteretic field solution of
//! [`crate::hysteresis`]: the data a Preisach model is identified from (Mayergoyz 1991,
//! *Mathematical Models of Hysteresis*, Springer, §1.3; the identification itself is
//! `mrbrake_sim::rig::everett`).
//!
//! **Grid.** `n` levels `α_k = k I_max / n`, `k = 0 … n`. FORC `k` (`k = 1 … n`) rises to `α_k`
//! and falls through every lower level `β_j = α_j`, `j = k−1 … 0`; its torques are
//! `T(α_k, β_j)`, and its top `T(α_k)` is the rising branch.
//!
//! **Reference state.** Mayergoyz's FORCs start from negative saturation, the state where every
//! relay is off. In the unipolar range the lowest input is 0 A, and the state the brake is in at
//! 0 A in use is the one after a current peak: the FORCs here start from the state at 0 A after
//! `0 → I_max → 0` from the demagnetised steel (the major loop's lower reversal point, the state of
//! the `rising` branch of [`crate::hysteresis`]). The first magnetisation from the demagnetised
//! state is not part of the unipolar model (it would need the states reached below 0 A).
//!
//! **Chains.** The FORCs are solved in `chains` independent sequences, in parallel (rayon), each
//! on its own field model: demagnetise, the reference path, then its FORCs one after the other,
//! each ending at 0 A. A FORC that starts where the previous one ended relies on the steel law's
//! return-point memory (the play/hysteron states at 0 A after an excursion below the previous
//! peak are those before it; exact for the play model at fixed field, approximate through the
//! field coupling): the difference `T(α_k, 0) − T(0)` is reported as
//! [`ForcSet::wiping_out_defect_nm`]. With `chains = n` every FORC starts from a freshly
//! demagnetised model (no shared path).
//!
//! Each level step is split into [`ForcOptions::steps_per_level`] current steps (Newton started
//! from a prediction of the previous solutions, material states committed after each, as in
//! [`crate::hysteresis`]). Torques are the gaps' yield torques (the field-dependent part; viscous
//! and constant friction are the brake model's off-state terms).

use std::sync::Arc;
use std::time::Instant;

use mrbrake_error::FieldError;
use rayon::prelude::*;
use serde::Serialize;

use crate::DesignError;
use crate::analysis::{AnalysisOptions, Model};
use crate::hysteresis::{QuasiStatic, SolveTotals, SteelLaw, set_steel_laws};
use crate::mesh_build;
use crate::spec::BrakeSpec;

/// Levels by default (`n`: 66 FORC nodes).
pub const DEFAULT_LEVELS: usize = 11;
/// Fewest levels.
pub const MIN_LEVELS: usize = 2;
/// Most levels (the solves grow as `n²`: 64 levels are about 2 100 level steps).
pub const MAX_LEVELS: usize = 64;
/// Current steps per level step by default.
pub const DEFAULT_STEPS_PER_LEVEL: usize = 2;
/// Most current steps per level step.
pub const MAX_STEPS_PER_LEVEL: usize = 16;

/// Options of the FORC set.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ForcOptions {
    /// Levels `n` of the grid on `[0, I_max]`.
    pub levels: usize,
    /// Current steps per level step.
    pub steps_per_level: usize,
    /// Independent sequences solved in parallel (module docs), `1 ..= levels`; `None`: rayon's
    /// thread count.
    pub chains: Option<usize>,
}

impl Default for ForcOptions {
    fn default() -> Self {
        Self { levels: DEFAULT_LEVELS, steps_per_level: DEFAULT_STEPS_PER_LEVEL, chains: None }
    }
}

impl ForcOptions {
    /// Checks the ranges; returns the number of chains.
    pub fn check(&self) -> Result<usize, DesignError> {
        if !(MIN_LEVELS..=MAX_LEVELS).contains(&self.levels) {
            let e = FieldError::out_of_range(
                "forc_levels",
                self.levels.to_string(),
                format!("{MIN_LEVELS}..={MAX_LEVELS} levels"),
            );
            return Err(e.into());
        }
        if !(1..=MAX_STEPS_PER_LEVEL).contains(&self.steps_per_level) {
            let e = FieldError::out_of_range(
                "forc_steps",
                self.steps_per_level.to_string(),
                format!("1..={MAX_STEPS_PER_LEVEL} current steps per level"),
            );
            return Err(e.into());
        }
        let chains = self.chains.unwrap_or_else(rayon::current_num_threads);
        if !(1..=self.levels).contains(&chains) {
            let e = FieldError::out_of_range(
                "forc_chains",
                chains.to_string(),
                format!("1..={} (at most one per FORC)", self.levels),
            );
            return Err(e.into());
        }
        Ok(chains)
    }
}

/// Seconds spent.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ForcTimings {
    /// Wall-clock seconds of the whole set.
    pub wall: f64,
    /// The chains' own seconds added up (set-up and solves; on an idle machine the CPU time).
    pub chains: f64,
}

/// The FORC set of a design (module docs).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ForcSet {
    /// The levels `α_0 = 0 … α_n = I_max`, A.
    #[serde(rename = "levels_A")]
    pub levels_a: Vec<f64>,
    /// `T(α_k)`, the rising branch from the reference state at each level (`k = 0`: the
    /// reference state's torque at 0 A), N·m.
    #[serde(rename = "rising_Nm")]
    pub rising_nm: Vec<f64>,
    /// `forcs[k][j] = T(α_k, β_j)`, `j = 0 … k`, with `forcs[k][k] = T(α_k)` (row 0: `[T(0)]`),
    /// N·m.
    #[serde(rename = "forcs_Nm")]
    pub forcs_nm: Vec<Vec<f64>>,
    /// Largest `|T(α_k, 0) − T(0)|` over the FORCs (module docs), N·m.
    #[serde(rename = "wiping_out_defect_Nm")]
    pub wiping_out_defect_nm: f64,
    /// The steels' hysteresis laws.
    pub steels: Vec<SteelLaw>,
    /// Current steps per level step.
    pub steps_per_level: usize,
    /// Independent sequences solved.
    pub chains: usize,
    /// Field solves in all.
    pub solves: usize,
    /// Newton iterations and factorisations of the solves, over every chain.
    pub work: SolveTotals,
    /// Seconds spent.
    pub timings_s: ForcTimings,
}

/// The FORCs solved by one chain.
struct ChainResult {
    /// `(k, forc)` for each FORC of the chain.
    forcs: Vec<(usize, Vec<f64>)>,
    /// The torque at 0 A of the reference state.
    reference_nm: f64,
    steels: Vec<SteelLaw>,
    solves: usize,
    work: SolveTotals,
    seconds: f64,
}

/// The FORC levels each chain solves: FORC `k` costs about `2k` level steps, so the largest go
/// first, each to the chain with the least work so far (longest processing time first).
fn assign(levels: usize, chains: usize) -> Vec<Vec<usize>> {
    let mut work = vec![0usize; chains];
    let mut assigned = vec![Vec::new(); chains];
    for k in (1..=levels).rev() {
        let c = (0..chains).min_by_key(|&c| (work[c], c)).unwrap_or(0);
        work[c] += 2 * k;
        assigned[c].push(k);
    }
    for list in &mut assigned {
        list.sort_unstable();
    }
    assigned
}

/// The FORC set of `spec` (module docs) with the analysis options `options` (mesh, order).
pub fn run(
    spec: &BrakeSpec,
    options: &AnalysisOptions,
    forc_options: &ForcOptions,
) -> Result<ForcSet, DesignError> {
    let start = Instant::now();
    options.check()?;
    let chains = forc_options.check()?;
    let geometry = spec.validate()?.geometry;
    let mesh = Arc::new(mesh_build::mesh_spec(spec, &geometry, options.mesh)?);
    let n = forc_options.levels;
    let levels_a: Vec<f64> =
        (0..=n).map(|k| spec.coil.max_current.a() * k as f64 / n as f64).collect();
    let results: Vec<ChainResult> = assign(n, chains)
        .into_par_iter()
        .map(|forcs| {
            let chain_start = Instant::now();
            let mut model = Model::new(spec, geometry.clone(), Arc::clone(&mesh), options)?;
            let steels = set_steel_laws(spec, &mut model)?;
            let mut walk = Walk::new(model, options, forc_options.steps_per_level);
            walk.walk_to(&levels_a, n)?;
            let reference_nm = walk.walk_to(&levels_a, 0)?;
            let mut solved = Vec::with_capacity(forcs.len());
            for k in forcs {
                let mut forc = vec![0.0; k + 1];
                forc[k] = walk.walk_to(&levels_a, k)?;
                for j in (0..k).rev() {
                    forc[j] = walk.walk_to(&levels_a, j)?;
                }
                solved.push((k, forc));
            }
            let seconds = chain_start.elapsed().as_secs_f64();
            let work = walk.steps.totals;
            Ok(ChainResult {
                forcs: solved,
                reference_nm,
                steels,
                solves: walk.solves,
                work,
                seconds,
            })
        })
        .collect::<Result<_, DesignError>>()?;
    Ok(gather(levels_a, results, forc_options.steps_per_level, start))
}

/// The set from the chains' FORCs (the reference torque is chain 0's; the chains start alike).
fn gather(
    levels_a: Vec<f64>,
    results: Vec<ChainResult>,
    steps_per_level: usize,
    start: Instant,
) -> ForcSet {
    let n = levels_a.len() - 1;
    let reference_nm = results.first().map_or(0.0, |r| r.reference_nm);
    let mut forcs_nm = vec![Vec::new(); n + 1];
    forcs_nm[0] = vec![reference_nm];
    for (k, forc) in results.iter().flat_map(|r| r.forcs.iter()) {
        forcs_nm[*k].clone_from(forc);
    }
    let rising_nm = forcs_nm.iter().enumerate().map(|(k, f)| f[k]).collect();
    let wiping_out_defect_nm =
        forcs_nm[1..].iter().map(|f| (f[0] - reference_nm).abs()).fold(0.0, f64::max);
    ForcSet {
        levels_a,
        rising_nm,
        forcs_nm,
        wiping_out_defect_nm,
        steels: results.first().map(|r| r.steels.clone()).unwrap_or_default(),
        steps_per_level,
        chains: results.len(),
        solves: results.iter().map(|r| r.solves).sum(),
        work: SolveTotals {
            newton_iterations: results.iter().map(|r| r.work.newton_iterations).sum(),
            factorizations: results.iter().map(|r| r.work.factorizations).sum(),
        },
        timings_s: ForcTimings {
            wall: start.elapsed().as_secs_f64(),
            chains: results.iter().map(|r| r.seconds).sum(),
        },
    }
}

/// A field model walked quasi-statically along the level grid.
struct Walk<'o> {
    model: Model,
    options: &'o AnalysisOptions,
    steps_per_level: usize,
    /// The present level and the steps so far (none: demagnetised at 0 A).
    level: usize,
    steps: QuasiStatic,
    solves: usize,
}

impl<'o> Walk<'o> {
    fn new(model: Model, options: &'o AnalysisOptions, steps_per_level: usize) -> Self {
        Self { model, options, steps_per_level, level: 0, steps: QuasiStatic::default(), solves: 0 }
    }

    /// Walks from the present level to `target` in level steps of `steps_per_level` current
    /// steps each, committing the material state after each; returns the yield torque there.
    fn walk_to(&mut self, levels_a: &[f64], target: usize) -> Result<f64, DesignError> {
        let mut torque = None;
        while self.level != target {
            let next = if target > self.level { self.level + 1 } else { self.level - 1 };
            let (from, to) = (levels_a[self.level], levels_a[next]);
            for s in 1..=self.steps_per_level {
                let current = from + (to - from) * s as f64 / self.steps_per_level as f64;
                let step = |e: DesignError| DesignError::LoopStep {
                    step: self.solves + 1,
                    current_a: current,
                    source: Box::new(e),
                };
                let (point, _) =
                    self.steps.step(&mut self.model, current, self.options).map_err(step)?;
                self.solves += 1;
                torque = Some(point.yield_torque_nm);
            }
            self.level = next;
        }
        // At the demagnetised start (no step taken) the field is zero and so is the torque.
        Ok(torque.unwrap_or(0.0))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn chains_share_the_work_and_cover_every_forc_once() {
        let a = assign(11, 2);
        let mut all: Vec<usize> = a.iter().flatten().copied().collect();
        all.sort_unstable();
        assert_eq!(all, (1..=11).collect::<Vec<_>>());
        let work: Vec<usize> = a.iter().map(|c| c.iter().map(|k| 2 * k).sum()).collect();
        assert!(work[0].abs_diff(work[1]) <= 2, "{work:?}");
        assert_eq!(assign(4, 4).iter().filter(|c| c.len() == 1).count(), 4);
    }

    #[test]
    fn options_out_of_range_name_their_field() {
        let e = |o: ForcOptions| o.check().unwrap_err().to_string();
        assert!(e(ForcOptions { levels: 1, ..ForcOptions::default() }).contains("forc_levels"));
        assert!(e(ForcOptions { levels: 65, ..ForcOptions::default() }).contains("forc_levels"));
        let steps = ForcOptions { steps_per_level: 0, ..ForcOptions::default() };
        assert!(e(steps).contains("forc_steps"));
        let chains = ForcOptions { chains: Some(12), ..ForcOptions::default() };
        assert!(e(chains).contains("forc_chains"));
        assert_eq!(ForcOptions { chains: Some(3), ..ForcOptions::default() }.check().unwrap(), 3);
    }
}
