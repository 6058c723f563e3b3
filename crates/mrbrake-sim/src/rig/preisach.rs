//! A discrete Preisach model of the brake's static hysteresis, whose major loop is the configured pair
//! of branches and whose minor loops lie inside it, with return-point memory and wiping-out.
//!
//! **Model** (Preisach 1935, "Über die magnetische Nachwirkung", Z. Physik 94, 277–302; in the form of
//! Mayergoyz 1986, "Mathematical models of hysteresis", IEEE Trans. Magn. 22(5), 603–608, and
//! Mayergoyz 1991, *Mathematical Models of Hysteresis*, Springer, ch. 1). The normalised current
//! `u = I/I_max ∈ [0, 1]` drives a continuum of 0/1 relays `γ_αβ` (on when `u ≥ α`, off when `u ≤ β`,
//! `β < α`) weighted by a density `μ(α, β) ≥ 0`. The torque is
//!
//! ```text
//! T(t) = T_rev(u(t)) + ∬_{α>β} μ(α,β) γ_αβ[u](t) dα dβ,        T_rev(u) = T_up(u) − E(u, 0)
//! ```
//!
//! where `E(α, β) = ∬_{β ≤ β' < α' ≤ α} μ` is the Everett function. The relay integral follows from
//! the alternating turning points `m₀ = 0 < … ` of the input's history (Mayergoyz 1991, eqs. (1.27)–
//! (1.30) in 0/1 form): each rising segment `p → q` adds `E(q, p)`, each falling segment `p → q`
//! subtracts `E(p, q)`. Dominated turning points are erased (the wiping-out property, Mayergoyz's
//! theorem 1.1), so the state is a short stack of nested turning points.
//!
//! **Discretisation** (bounded number of cells): `μ` is piecewise constant on the `n × n` grid of
//! cells of side `1/n` strictly above the diagonal (`n(n−1)/2` cells; relays narrower than one cell
//! carry no weight, so `E(u, u) = 0` and the output is continuous). `E` is tabulated at the grid nodes
//! and interpolated bilinearly, which is exact for a density constant in each cell.
//!
//! **Weight.** The rising major branch is reproduced exactly by `T_rev`. The falling branch from
//! `u = 1` is `T_rev(u) + E(1,0) − E(1,u)`, so the major loop is the configured one when, at every
//! grid level `u_k`, the weight of the rectangle `{β < u_k < α}` equals the loop width
//! `w(u_k) = T_down(u_k) − T_up(u_k)`. The weight is a parametrised prior shape over the relay width
//! `α − β`, a Gaussian or a Lorentzian (the interaction-field distributions of magnetic Preisach
//! modelling, e.g. Bertotti 1998, *Hysteresis in Magnetism*, §13.3), times a non-negative profile
//! over the relay centre `(α + β)/2`; the conditions are linear in the profile, which is found by
//! non-negative least squares (Lawson & Hanson 1974, *Solving Least Squares Problems*, ch. 23) as
//! the profile closest to the loop width at the centre that meets them. The prior's width sets how
//! flat the minor loops are; the major loop does not depend on it. The falling branch must not lie below the rising one
//! (`μ ≥ 0`).

use serde::{Deserialize, Serialize};

use super::everett::EverettTable;
use crate::SimError;
use mrbrake_error::FieldError;
use mrbrake_sysid::polynomial::Polynomial;

/// Most turning points remembered; beyond this the smallest inner loop is forgotten (its weight is
/// below a cell's, so the error is under the grid resolution).
pub const MAX_TURNING_POINTS: usize = 256;

/// Relative tolerance on the loop width at the grid levels.
const WIDTH_TOLERANCE: f64 = 1e-6;

/// Which static hysteresis the virtual rig's brake has.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum HysteresisKind {
    /// Play-type clamp between the two branches (the rig's original model): exact full loops, but a
    /// reversal inside the loop holds the torque flat until the other branch is reached.
    #[default]
    Clamp,
    /// The discrete Preisach model of this module: minor loops inside the major loop.
    Preisach,
}

/// Shape of the Preisach prior over the relay width `α − β`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum WeightShape {
    /// `exp(−½((α−β−h₀)/σ)²)`.
    #[default]
    Gaussian,
    /// `1/(1 + ((α−β−h₀)/σ)²)`.
    Lorentzian,
}

/// `[hysteresis]` of the rig configuration.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct HysteresisConfig {
    /// `clamp` (default, the original rig) or `preisach`.
    pub model: HysteresisKind,
    /// Grid levels `n` of the Preisach plane over `[0, I_max]` (cells: `n(n−1)/2`), 4..=256.
    pub levels: usize,
    /// Prior shape over the relay width.
    pub weight: WeightShape,
    /// Centre `h₀` of the prior over the relay width, as a fraction of `I_max`, in [0, 1].
    pub width_mean: f64,
    /// Spread `σ` of the prior over the relay width, as a fraction of `I_max`, in (0, 1].
    pub width_spread: f64,
}

impl Default for HysteresisConfig {
    /// Clamp model; for the Preisach model 64 levels and a Gaussian prior over the relay width centred at
    /// 20 % of `I_max` with 10 % spread. Narrower relays need more relay weight for the same loop width
    /// and make the reversible part decrease (refused by the model, see
    /// `PreisachHysteresis::new`); 20 % keeps it increasing for the prototype-like loop (10 % does
    /// too, with a total relay weight of 1.7 N·m instead of 1.0 N·m).
    fn default() -> Self {
        Self {
            model: HysteresisKind::Clamp,
            levels: 64,
            weight: WeightShape::Gaussian,
            width_mean: 0.20,
            width_spread: 0.10,
        }
    }
}

impl HysteresisConfig {
    /// Checks ranges; `Err((field, message))` for the first bad field.
    pub fn check(&self) -> Result<(), (&'static str, String)> {
        if !(4..=256).contains(&self.levels) {
            return Err(("hysteresis.levels", format!("{} is outside 4..=256", self.levels)));
        }
        if !(self.width_mean.is_finite() && (0.0..=1.0).contains(&self.width_mean)) {
            return Err((
                "hysteresis.width_mean",
                format!("{} is outside [0, 1]", self.width_mean),
            ));
        }
        if !(self.width_spread.is_finite() && self.width_spread > 0.0 && self.width_spread <= 1.0) {
            let msg = format!("{} is outside (0, 1]", self.width_spread);
            return Err(("hysteresis.width_spread", msg));
        }
        self.check_prior_support()
    }

    /// The prior `g(d/n)` of the relay width `d` cells (`d = 1 … n−1`).
    fn prior(&self, d: usize) -> f64 {
        let z = (d as f64 / self.levels as f64 - self.width_mean) / self.width_spread;
        match self.weight {
            WeightShape::Gaussian => (-0.5 * z * z).exp(),
            WeightShape::Lorentzian => 1.0 / (1.0 + z * z),
        }
    }

    /// Two individually valid prior parameters can be jointly degenerate: a spread much narrower
    /// than one cell (`1/levels`) centred between the grid's relay widths leaves every relay
    /// without weight, and the fit then divides by zero (issue 33: 30 000 NaN torques in a rig
    /// log). Refused, for the Preisach model, with both values and what would do.
    fn check_prior_support(&self) -> Result<(), (&'static str, String)> {
        let peak = (1..self.levels).map(|d| self.prior(d)).fold(0.0_f64, f64::max);
        if self.model != HysteresisKind::Preisach || peak >= MIN_PRIOR_PEAK {
            return Ok(());
        }
        let (n, cell) = (self.levels, 1.0 / self.levels as f64);
        Err((
            "hysteresis.width_spread",
            format!(
                "with width_mean = {} and width_spread = {}, no relay width of the {n}-level grid \
                 (multiples of 1/{n}) has prior weight: the spread is far narrower than a cell; \
                 allowed: width_spread >= {cell} (one cell), or width_mean on a multiple of {cell}",
                self.width_mean, self.width_spread
            ),
        ))
    }
}

/// The smallest largest prior weight over the grid's relay widths that still fits a loop: below
/// it the conditions' rows are numerically zero and the profile that meets them is unbounded.
const MIN_PRIOR_PEAK: f64 = 1e-12;

/// The reversible part `T_rev(u) = T_up(u) − E(u, 0)` of a model.
#[derive(Debug, Clone, PartialEq)]
enum Reversible {
    /// From the rising branch polynomial (the branch + prior model).
    Rising(Polynomial),
    /// Tabulated at the grid's nodes, interpolated linearly (the Everett-table model).
    Nodes(Vec<f64>),
}

/// The Preisach brake hysteresis: Everett table, reversible part, turning-point memory (the one
/// Preisach operator of the simulators: the virtual rig's plant and the haptic plant,
/// [`crate::haptic::brake`], run it).
///
/// **Cost.** The memory is the staircase of alternating, nested turning points; each
/// [`Self::torque_nm`] sums the Everett function over it, `O(k)` for `k` remembered points, and
/// `k ≤` [`MAX_TURNING_POINTS`] whatever the history's length (beyond it the smallest inner loop
/// is forgotten), so a step's cost is bounded.
#[derive(Debug, Clone, PartialEq)]
pub struct PreisachHysteresis {
    levels: usize,
    /// `E` at grid nodes `(a, b)`, index `a·(n+1) + b`; zero for `b ≥ a`.
    everett: Vec<f64>,
    reversible: Reversible,
    current_max_a: f64,
    /// Alternating turning points of the normalised input, starting with `m₀ = 0`.
    points: Vec<f64>,
    /// The last normalised input.
    input: f64,
}

impl PreisachHysteresis {
    /// Builds the model whose major loop is `rising`/`falling` on `[0, current_max_a]`.
    pub fn new(
        config: &HysteresisConfig,
        rising: &[f64],
        falling: &[f64],
        current_max_a: f64,
    ) -> Result<Self, SimError> {
        config.check().map_err(|(f, m)| SimError::from(FieldError::new(f, m)))?;
        let n = config.levels;
        let (up, down) = (Polynomial::new(rising.to_vec()), Polynomial::new(falling.to_vec()));
        let width = loop_widths(&up, &down, n, current_max_a)?;
        let weight = fit_weight(config, &width)?;
        let model = Self {
            levels: n,
            everett: everett_table(&weight, n),
            reversible: Reversible::Rising(up),
            current_max_a,
            points: vec![0.0],
            input: 0.0,
        };
        if model.everett.iter().any(|e| !e.is_finite()) {
            return Err(FieldError::new(
                "hysteresis",
                "the Preisach weight of this loop and prior is not finite: try a wider width_spread",
            )
            .with_value(format!(
                "width_mean = {}, width_spread = {}, levels = {n}",
                config.width_mean, config.width_spread
            ))
            .into());
        }
        model.check_reversible_part()?;
        Ok(model)
    }

    /// The model of a tabulated Everett function (e.g. identified from first-order reversal
    /// curves, [`super::everett`]), with `offset_nm` (a constant friction) added to its torque.
    /// Its reversible part is `T_rev(α_a) = T_up(α_a) − E(α_a, 0)` at the nodes, linear between.
    pub fn from_everett(table: &EverettTable, offset_nm: f64) -> Result<Self, SimError> {
        let current_max_a = table.levels_a.last().copied().unwrap_or(0.0);
        table
            .check(current_max_a)
            .map_err(|(field, message)| SimError::from(FieldError::new(field, message)))?;
        let n = table.levels();
        let mut everett = vec![0.0; (n + 1) * (n + 1)];
        for (a, row) in table.everett_nm.iter().enumerate() {
            for (b, e) in row.iter().enumerate().take(a) {
                everett[a * (n + 1) + b] = *e;
            }
        }
        let nodes =
            (0..=n).map(|a| table.rising_nm[a] + offset_nm - everett[a * (n + 1)]).collect();
        let model = Self {
            levels: n,
            everett,
            reversible: Reversible::Nodes(nodes),
            current_max_a,
            points: vec![0.0],
            input: 0.0,
        };
        model.check_reversible_part()?;
        Ok(model)
    }

    /// `T_rev(u)` at the normalised input `u ∈ [0, 1]`.
    fn reversible_at(&self, u: f64) -> f64 {
        match &self.reversible {
            Reversible::Rising(p) => p.eval(u * self.current_max_a) - self.everett_at(u, 0.0),
            Reversible::Nodes(v) => {
                let s = (u * self.levels as f64).clamp(0.0, self.levels as f64);
                let k = (s.floor() as usize).min(self.levels - 1);
                v[k] + (s - k as f64) * (v[k + 1] - v[k])
            }
        }
    }

    /// The reversible part `T_rev(u) = T_up(u) − E(u, 0)` must not decrease: otherwise the torque would
    /// rise right after the current turns down. It decreases when the relays are too narrow for the
    /// loop width (the relay mass per unit `α`, about `w/h₀`, exceeds the rising branch's slope).
    fn check_reversible_part(&self) -> Result<(), SimError> {
        let samples = 8 * self.levels;
        let reversible = |k: usize| self.reversible_at(k as f64 / samples as f64);
        let scale = reversible(samples).abs().max(1e-300);
        for k in 1..=samples {
            if reversible(k) < reversible(k - 1) - 1e-9 * scale {
                let i = self.current_max_a * k as f64 / samples as f64;
                return Err(FieldError::new(
                    "hysteresis.width_mean",
                    format!(
                        "the Preisach relays are too narrow for the loop width: the reversible \
                         torque decreases near {i:.3} A, so the torque would rise when the current \
                         turns down; increase it"
                    ),
                )
                .into());
            }
        }
        Ok(())
    }

    /// Forgets the history (as after a descent to 0 A) and rises to `current_a`.
    pub fn settle(&mut self, current_a: f64) -> f64 {
        self.points.clear();
        self.points.push(0.0);
        self.input = 0.0;
        self.torque_nm(current_a)
    }

    /// Static torque after the input moves to `current_a` (clamped to `[0, I_max]`; NaN counts as 0).
    pub fn torque_nm(&mut self, current_a: f64) -> f64 {
        let u = (current_a / self.current_max_a).clamp(0.0, 1.0);
        let u = if u.is_nan() { 0.0 } else { u };
        self.advance(u);
        self.reversible_at(u) + self.relay_sum()
    }

    /// The turning points remembered (normalised input), oldest first.
    pub fn turning_points(&self) -> &[f64] {
        &self.points
    }

    /// The largest current of the model's range `[0, I_max]`, A.
    pub fn current_max_a(&self) -> f64 {
        self.current_max_a
    }

    /// The Everett function `E(α, β)` at currents `α ≥ β` (each clamped to `[0, I_max]`), N·m:
    /// the weight of the relays with thresholds `β ≤ β' < α' ≤ α` (module docs), interpolated as
    /// the torque is.
    pub fn everett_nm(&self, alpha_a: f64, beta_a: f64) -> f64 {
        let u = |i: f64| (i / self.current_max_a).clamp(0.0, 1.0);
        let (alpha, beta) = (u(alpha_a), u(beta_a));
        if alpha > beta { self.everett_at(alpha, beta) } else { 0.0 }
    }

    /// Updates the turning-point stack for the new input `u` (wiping-out included).
    fn advance(&mut self, u: f64) {
        let rising = self.points.len() % 2 == 1;
        if (rising && u < self.input) || (!rising && u > self.input) {
            // Reversal: the previous input is the new turning point.
            self.points.push(self.input);
        }
        while self.points.len() >= 2 {
            let len = self.points.len();
            let before = self.points[len - 2];
            let wipes = if len % 2 == 1 { u >= before } else { u <= before };
            if !wipes {
                break;
            }
            self.points.truncate(len - 2);
            if self.points.is_empty() {
                self.points.push(0.0);
            }
        }
        self.input = u;
        if self.points.len() > MAX_TURNING_POINTS {
            self.forget_smallest_loop();
        }
    }

    /// Drops the adjacent pair of inner turning points that are closest together (not `m₀`, not the
    /// start of the present segment), keeping the alternation.
    fn forget_smallest_loop(&mut self) {
        let p = &self.points;
        let k = (1..p.len() - 2)
            .min_by(|&a, &b| (p[a] - p[a + 1]).abs().total_cmp(&(p[b] - p[b + 1]).abs()))
            .unwrap_or(1);
        self.points.drain(k..k + 2);
    }

    /// The relay integral from the turning points and the present input.
    fn relay_sum(&self) -> f64 {
        let mut sum = 0.0;
        let mut prev = self.points[0];
        for &q in self.points[1..].iter().chain(core::iter::once(&self.input)) {
            sum += if q >= prev { self.everett_at(q, prev) } else { -self.everett_at(prev, q) };
            prev = q;
        }
        sum
    }

    /// `E(α, β)` by bilinear interpolation of the node table (`α, β ∈ [0, 1]`).
    fn everett_at(&self, alpha: f64, beta: f64) -> f64 {
        let n = self.levels;
        let locate = |x: f64| {
            let s = (x * n as f64).clamp(0.0, n as f64);
            let k = (s.floor() as usize).min(n - 1);
            (k, s - k as f64)
        };
        let ((a, ta), (b, tb)) = (locate(alpha), locate(beta));
        let e = |i: usize, j: usize| self.everett[i * (n + 1) + j];
        if a == b {
            // A diagonal cell: linear on its triangle below the diagonal, whose corners are
            // E(a, a) = 0, E(a+1, a) and E(a+1, a+1) = 0 (so E(u, u) = 0 inside the cell too).
            return (ta - tb).max(0.0) * e(a + 1, a);
        }
        (1.0 - ta) * ((1.0 - tb) * e(a, b) + tb * e(a, b + 1))
            + ta * ((1.0 - tb) * e(a + 1, b) + tb * e(a + 1, b + 1))
    }
}

/// Loop width `T_down − T_up` at the inner grid levels `k = 1 … n−1` (index `k − 1`); fails when the
/// falling branch lies below the rising one.
fn loop_widths(
    up: &Polynomial,
    down: &Polynomial,
    n: usize,
    current_max_a: f64,
) -> Result<Vec<f64>, SimError> {
    let scale =
        (1..n).map(|k| up.eval(current_max_a * k as f64 / n as f64).abs()).fold(1e-300, f64::max);
    (1..n)
        .map(|k| {
            let i = current_max_a * k as f64 / n as f64;
            let w = down.eval(i) - up.eval(i);
            if w < -1e-12 * scale {
                return Err(FieldError::new(
                    "brake.falling",
                    format!(
                        "hysteresis.model = \"preisach\": the falling branch lies {:.3e} N·m below \
                         the rising branch at {i:.4} A",
                        -w
                    ),
                )
                .with_allowed(">= brake.rising at every current")
                .into());
            }
            Ok(w.max(0.0))
        })
        .collect()
}

/// Cell weights `μ[i·n + j]` (`i > j`) of the form `g(i − j)·s(i + j)`: the prior shape `g` over the
/// relay width times a non-negative profile `s` over the relay centre, chosen so that the rectangle
/// `{j < k ≤ i}` of every inner level `k` carries the loop width `width[k − 1]` (linear in `s`). The
/// conditions are fewer than the unknowns; among the non-negative profiles that meet them the model
/// takes the one closest to `s₀(c) ∝ w(c)` (the loop width at the relay's centre), by non-negative
/// least squares (Lawson & Hanson 1974, ch. 23) with the conditions as a heavily weighted block.
fn fit_weight(config: &HysteresisConfig, width: &[f64]) -> Result<Vec<f64>, SimError> {
    let n = width.len() + 1;
    let shape = |d: usize| config.prior(d);
    // Centre index c = i + j − 1 ∈ [0, 2n − 4] for 0 ≤ j < i ≤ n − 1.
    let centres = 2 * n - 3;
    let mut kernel = vec![0.0; (n - 1) * centres];
    for k in 1..n {
        for c in rectangle(n, k) {
            let (i, j) = (c / n, c % n);
            kernel[(k - 1) * centres + i + j - 1] += shape(i - j);
        }
    }
    let peak = width.iter().fold(0.0_f64, |a, w| a.max(*w));
    if peak <= 0.0 {
        return Ok(vec![0.0; n * n]);
    }
    let prior = prior_profile(width, &kernel, centres);
    let profile = constrained_profile(&kernel, width, &prior, centres)?;
    let residual = (1..n)
        .map(|k| {
            let row = &kernel[(k - 1) * centres..k * centres];
            (row.iter().zip(&profile).map(|(a, b)| a * b).sum::<f64>() - width[k - 1]).abs()
        })
        .fold(0.0_f64, f64::max);
    if residual > WIDTH_TOLERANCE * peak {
        return Err(FieldError::new(
            "hysteresis.width_spread",
            format!(
                "no non-negative Preisach weight with this width prior reproduces the loop width \
                 (residual {residual:.3e} N·m); try another width_mean/width_spread"
            ),
        )
        .into());
    }
    let mut mu = vec![0.0; n * n];
    for i in 0..n {
        for j in 0..i {
            mu[i * n + j] = shape(i - j) * profile[i + j - 1];
        }
    }
    Ok(mu)
}

/// `s₀(c)`: the loop width at each relay centre, scaled so that it carries the loop's area.
fn prior_profile(width: &[f64], kernel: &[f64], centres: usize) -> Vec<f64> {
    let n = width.len() + 1;
    let at = |x: f64| {
        let s = (x * n as f64).clamp(0.0, n as f64);
        let k = (s.floor() as usize).min(n - 1);
        let w = |k: usize| if k == 0 || k == n { 0.0 } else { width[k - 1] };
        w(k) + (s - k as f64) * (w(k + 1) - w(k))
    };
    let raw: Vec<f64> = (0..centres).map(|c| at((c + 2) as f64 / (2 * n) as f64)).collect();
    let carried: f64 = (0..n - 1)
        .map(|k| {
            kernel[k * centres..(k + 1) * centres].iter().zip(&raw).map(|(a, b)| a * b).sum::<f64>()
        })
        .sum();
    let scale = width.iter().sum::<f64>() / carried.max(1e-300);
    raw.into_iter().map(|v| v * scale).collect()
}

/// `min ρ²‖K s − w‖² + ‖s − s₀‖²` over `s ≥ 0` (NNLS on the normal equations).
fn constrained_profile(
    kernel: &[f64],
    width: &[f64],
    prior: &[f64],
    centres: usize,
) -> Result<Vec<f64>, SimError> {
    let rows = width.len();
    let prior_scale = prior.iter().fold(1e-300, |a: f64, v| a.max(*v));
    let peak = width.iter().fold(1e-300, |a: f64, v| a.max(*v));
    // Unknowns σ = s/prior_scale; conditions in units of the peak width, weighted by ρ² = 10¹².
    let rho2 = 1e12 * (prior_scale / peak).powi(2);
    let mut gram = vec![0.0; centres * centres];
    let mut rhs: Vec<f64> = prior.iter().map(|v| v / prior_scale).collect();
    for a in 0..centres {
        gram[a * centres + a] += 1.0;
    }
    for k in 0..rows {
        let row = &kernel[k * centres..(k + 1) * centres];
        for a in 0..centres {
            if row[a] == 0.0 {
                continue;
            }
            rhs[a] += rho2 * row[a] * width[k] / prior_scale;
            for b in 0..centres {
                gram[a * centres + b] += rho2 * row[a] * row[b];
            }
        }
    }
    let sigma = mrbrake_sysid::operator_fit::nnls_gram(&gram, &rhs, centres).map_err(|e| {
        SimError::from(FieldError::new("hysteresis", format!("Preisach weight: {e}")))
    })?;
    Ok(sigma.into_iter().map(|v| v * prior_scale).collect())
}

/// Indices of the cells `(i, j)` with `j < k ≤ i`: the relays on the falling but off on the rising
/// major branch at level `k`.
fn rectangle(n: usize, k: usize) -> impl Iterator<Item = usize> {
    (k..n).flat_map(move |i| (0..k).map(move |j| i * n + j))
}

/// `E` at the nodes: `E[a][b] = Σ μ(i, j)` over cells with `b ≤ j < i < a`.
fn everett_table(mu: &[f64], n: usize) -> Vec<f64> {
    let mut e = vec![0.0; (n + 1) * (n + 1)];
    for a in 1..=n {
        for b in (0..a).rev() {
            // Cells of row a−1 with j ≥ b, plus everything below row a−1.
            let row: f64 = (b..a - 1).map(|j| mu[(a - 1) * n + j]).sum();
            e[a * (n + 1) + b] = e[(a - 1) * (n + 1) + b.min(a - 1)] + row;
        }
    }
    e
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    const RISING: [f64; 4] = [0.15, 3.69, -1.38375, 0.230625];
    const FALLING: [f64; 4] = [0.15, 4.29, -1.68375, 0.230625];

    fn model() -> PreisachHysteresis {
        static MODEL: std::sync::OnceLock<PreisachHysteresis> = std::sync::OnceLock::new();
        MODEL
            .get_or_init(|| {
                let config =
                    HysteresisConfig { model: HysteresisKind::Preisach, ..Default::default() };
                PreisachHysteresis::new(&config, &RISING, &FALLING, 2.0).unwrap()
            })
            .clone()
    }

    #[test]
    fn the_major_loop_is_the_configured_one() {
        let mut p = model();
        let (up, down) = (Polynomial::new(RISING.to_vec()), Polynomial::new(FALLING.to_vec()));
        p.settle(0.0);
        for k in 0..=400 {
            let i = k as f64 * 0.005;
            assert!((p.torque_nm(i) - up.eval(i)).abs() < 1e-12, "rising at {i}");
        }
        let mut worst = 0.0_f64;
        for k in (0..=400).rev() {
            let i = k as f64 * 0.005;
            worst = worst.max((p.torque_nm(i) - down.eval(i)).abs());
        }
        // Exact at the 64 levels; between them the bilinear Everett function interpolates the width
        // 0.3·I·(2 − I) linearly: error ≤ h²·|w''|/8 = (2/64)²·0.6/8 ≈ 7.3e-5 N·m.
        assert!(worst < 8e-5, "falling branch error {worst}");
        assert_eq!(p.turning_points(), &[0.0]);
    }

    #[test]
    fn a_falling_branch_below_the_rising_one_is_refused() {
        let config = HysteresisConfig { model: HysteresisKind::Preisach, ..Default::default() };
        let e = PreisachHysteresis::new(&config, &FALLING, &RISING, 2.0).unwrap_err().to_string();
        assert!(e.starts_with("brake.falling: ") && e.contains("allowed: >= brake.rising"), "{e}");
    }

    #[test]
    fn minor_loop_lies_inside_and_leaves_the_flat_clamp() {
        let mut p = model();
        let (up, down) = (Polynomial::new(RISING.to_vec()), Polynomial::new(FALLING.to_vec()));
        p.settle(1.5);
        let top = p.torque_nm(1.5);
        // A small reversal: the clamp model would hold the torque; a Preisach loop falls at once.
        let t = p.torque_nm(1.4);
        assert!(t < top - 0.02, "{t} vs {top}");
        assert!(t >= up.eval(1.4) - 1e-12 && t <= down.eval(1.4) + 1e-12);
    }

    /// Inputs in [0, 2] A with a step no larger than 0.3 A.
    fn path() -> impl Strategy<Value = Vec<f64>> {
        proptest::collection::vec(0.0..2.0f64, 2..40)
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(64))]

        #[test]
        fn every_state_lies_inside_the_major_loop(inputs in path()) {
            let mut p = model();
            let (up, down) = (Polynomial::new(RISING.to_vec()), Polynomial::new(FALLING.to_vec()));
            for i in inputs {
                let t = p.torque_nm(i);
                prop_assert!(t >= up.eval(i) - 1e-9 && t <= down.eval(i) + 8e-5, "{t} at {i}");
            }
        }

        /// Return-point memory (Mayergoyz 1991, §1.2): after any excursion that stays between the
        /// last two turning points, returning to the turning point restores its torque.
        #[test]
        fn return_point_memory(history in path(), lo in 0.0..1.0f64, span in 0.05..1.0f64,
                               inner in proptest::collection::vec(0.0..1.0f64, 1..20)) {
            let mut p = model();
            for i in history {
                p.torque_nm(i);
            }
            let hi = (lo + span).min(2.0);
            p.torque_nm(lo);
            let at_hi = p.torque_nm(hi);
            let at_lo = p.torque_nm(lo);
            for f in &inner {
                p.torque_nm(lo + f * (hi - lo));
            }
            prop_assert!((p.torque_nm(hi) - at_hi).abs() < 1e-9);
            for f in &inner {
                p.torque_nm(lo + f * (hi - lo));
            }
            prop_assert!((p.torque_nm(lo) - at_lo).abs() < 1e-9);
        }

        /// Wiping-out: once the input passes a previous maximum, the history dominated by it no
        /// longer matters; the same holds from below at 0 A.
        #[test]
        fn wiping_out(first in path(), second in path(), top in 0.0..2.0f64) {
            let (mut a, mut b) = (model(), model());
            let top = first.iter().chain(&second).fold(top, |m, v| m.max(*v));
            for i in &first { a.torque_nm(*i); }
            for i in &second { b.torque_nm(*i); }
            // Both rise to the common maximum: identical states from here on.
            prop_assert!((a.torque_nm(top) - b.torque_nm(top)).abs() < 1e-9);
            for i in [0.7 * top, 0.3 * top, 0.5 * top, 0.0, 1.1] {
                prop_assert!((a.torque_nm(i) - b.torque_nm(i)).abs() < 1e-9);
            }
        }
    }
}
