//! The per-point state of the energy-based model and its B-driven and H-driven updates.
//!
//! # One step
//! From the committed state (reversible fields `h_k`, applied field `H₀`, flux density `B₀`) to a new
//! applied field `H`, every cell follows the dry-friction (play) rule of Henrotte et al. (2006) in
//! scalar form, `h_k ← clamp(h_k, H − κ_k, H + κ_k)`, and
//! `B(H) = μ0 H + Σ_k J_k(h_k)`. Along one step the map `H ↦ B` is continuous,
//! piecewise smooth and strictly increasing (slope `≥ μ0`), so a **B-driven** step (what an
//! A-formulation FEA needs) solves `B(H) = B_new` for the unique `H` by Halley's/Newton's method safeguarded by
//! bisection on a bracket that always holds the root (`[H₀, H₀ + ΔB/μ0]` for `ΔB > 0`). No ODE is
//! integrated, so no sub-steps: the update is exact for the discretised model (up to the root
//! tolerance, [`TOLERANCE_T`]), and the number of iterations is bounded ([`MAX_ITERATIONS`]).
//!
//! The returned `dH/dB` is the derivative of this step map at `B_new` (one-sided, in the direction of
//! the step): `1 / (μ0 + Σ_{moving k} J_k'(h_k))`, where a cell moves when it sits on the edge of its
//! band, `s (H − h_k) = κ_k`, `s` the direction. It is the consistent tangent Newton needs.
//!
//! # Energy
//! The work per volume of one step splits exactly into a change of free energy and dissipation:
//! `∫H dB = Δ(μ0 H²/2) + Σ_k ΔU_k + Σ_k κ_k |ΔJ_k|` (the energy balance of Henrotte et al. 2006 and Bergqvist 1997); the
//! dissipation `κ_k |ΔJ_k| ≥ 0` is exact for the discrete step because each cell moves
//! monotonically within a step. Over a closed cycle `∮ H dB = Σ κ_k ∫|dJ_k| ≥ 0`: the model is
//! passive by construction.

use super::params::{HysteresisParams, MAX_CELLS};
use crate::MU_0;

/// Most Newton/bisection iterations of one B-driven step. Bisection alone halves the bracket each
/// time, so 200 iterations resolve any bracket of finite floating-point width.
pub const MAX_ITERATIONS: u32 = 200;

/// Tolerance of the B-driven root, T (relative to `1 + |B|`).
pub const TOLERANCE_T: f64 = 1e-10;

/// Largest |B| a step accepts, T: a flux density beyond it (or not finite) is a caller's bug; the
/// step then leaves the state unchanged and reports `accepted = false`.
pub const MAX_FLUX_DENSITY_T: f64 = 100.0;

/// What one step returns.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Response {
    /// Field strength H at the new state, A/m.
    pub h: f64,
    /// Flux density B at the new state, T.
    pub b: f64,
    /// Differential reluctivity `dH/dB` of the step map at the new state, A/(m·T) (`> 0`, `≤ 1/μ0`).
    pub dh_db: f64,
    /// Newton/bisection iterations used (0 for an H-driven step).
    pub iterations: u32,
    /// False when the input was rejected (not finite or beyond [`MAX_FLUX_DENSITY_T`]): the state was
    /// kept and `h`, `b`, `dh_db` describe it.
    pub accepted: bool,
}

/// The state of one quadrature point: the reversible field of every cell, the applied field, the flux
/// density and the last direction of motion. `Default` is the demagnetised state.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct HysteresisState {
    reversible: [f64; MAX_CELLS],
    h: f64,
    b: f64,
    /// +1 or −1: the direction of the last step that moved; 0 before any.
    direction: f64,
    /// `dH/dB` of the last step (0 before any): the start of the next root search.
    tangent_dh_db: f64,
    /// `J_k(h_k)` of every cell at its reversible field, T (zero when demagnetised): the cells a
    /// step does not move keep it, so an evaluation computes the terms of the moving cells only.
    cell_polarisation: [f64; MAX_CELLS],
}

impl HysteresisState {
    /// The demagnetised state (every cell at zero field).
    pub fn demagnetised() -> Self {
        Self::default()
    }

    /// Applied field H, A/m.
    pub fn h(&self) -> f64 {
        self.h
    }

    /// Flux density B, T.
    pub fn b(&self) -> f64 {
        self.b
    }

    /// The reversible field of every cell, A/m.
    pub fn reversible_a_per_m(&self) -> &[f64; MAX_CELLS] {
        &self.reversible
    }

    /// B-driven step to `b_new` (T): updates the state and returns H, `dH/dB` (see the module docs).
    pub fn step(&mut self, params: &HysteresisParams, b_new: f64) -> Response {
        let delta = b_new - self.b;
        if !(b_new.is_finite() && b_new.abs() <= MAX_FLUX_DENSITY_T) || delta == 0.0 {
            return self.without_step(params, delta == 0.0);
        }
        let s = delta.signum();
        let solved = self.solve_field(params, b_new, s, None);
        self.commit(solved, b_new, s)
    }

    /// The B-driven step to `b_new` without committing it: the response and the state it would leave
    /// (for the trial evaluations of a Newton iteration; commit by assigning the returned state).
    pub fn trial(&self, params: &HysteresisParams, b_new: f64) -> (Response, Self) {
        let mut next = *self;
        let response = next.step(params, b_new);
        (response, next)
    }

    /// [`HysteresisState::trial`] with a guess of the field (A/m), e.g. the field of the previous
    /// Newton iteration at this point: the root search starts there (clamped into its bracket), which
    /// saves iterations when successive trials are close. The result is the same.
    pub fn trial_near(
        &self,
        params: &HysteresisParams,
        b_new: f64,
        h_guess: f64,
    ) -> (Response, Self) {
        let mut next = *self;
        let response = match self.solve_near(params, b_new, h_guess) {
            Some((solved, s)) => next.commit(solved, b_new, s),
            None => next.step(params, b_new),
        };
        (response, next)
    }

    /// The response of [`HysteresisState::trial_near`] alone, without building the state the step
    /// would leave: for evaluations whose state is discarded (the Newton iterations of a field
    /// solve). The same response.
    pub fn response_near(&self, params: &HysteresisParams, b_new: f64, h_guess: f64) -> Response {
        match self.solve_near(params, b_new, h_guess) {
            Some((solved, _)) => solved.response(b_new),
            None => self.trial(params, b_new).0,
        }
    }

    /// The root search of the B-driven step to `b_new` started at `h_guess`, with the step's
    /// direction; `None` where the plain step applies (a bad or unchanged B, a non-finite guess).
    fn solve_near(
        &self,
        params: &HysteresisParams,
        b_new: f64,
        h_guess: f64,
    ) -> Option<(Solved, f64)> {
        let delta = b_new - self.b;
        if !(b_new.is_finite() && b_new.abs() <= MAX_FLUX_DENSITY_T)
            || delta == 0.0
            || !h_guess.is_finite()
        {
            return None;
        }
        let s = delta.signum();
        Some((self.solve_field(params, b_new, s, Some(h_guess)), s))
    }

    /// H-driven step to `h_new` (A/m): the forward form of the model. Returns B and `dH/dB` (the
    /// inverse of `dB/dH` of the step). A non-finite `h_new` is rejected like a bad B.
    pub fn step_h(&mut self, params: &HysteresisParams, h_new: f64) -> Response {
        let delta = h_new - self.h;
        if !(h_new.is_finite() && h_new.abs() <= super::params::MAX_FIELD_A_PER_M * 10.0)
            || delta == 0.0
        {
            return self.without_step(params, delta == 0.0);
        }
        let s = delta.signum();
        let (reversible, moving, changed) = played(params, &self.reversible, h_new, s);
        let (cells, dj, _) =
            params.cell_polarisations(&reversible, moving, !changed, &self.cell_polarisation);
        self.reversible = reversible;
        self.cell_polarisation = cells;
        self.h = h_new;
        self.direction = s;
        let j: f64 = cells.iter().sum();
        self.b = MU_0 * h_new + j;
        self.tangent_dh_db = 1.0 / (MU_0 + dj);
        Response { h: h_new, b: self.b, dh_db: self.tangent_dh_db, iterations: 0, accepted: true }
    }

    /// The response when the state does not move: its tangent, `accepted` false for rejected input.
    fn without_step(&self, params: &HysteresisParams, accepted: bool) -> Response {
        Response { accepted, ..self.tangent(params) }
    }

    /// H, B and the tangent `dH/dB` for a continued motion in the last direction (at the demagnetised
    /// state: only cells without pinning move).
    pub fn tangent(&self, params: &HysteresisParams) -> Response {
        let moving = moving_cells(params, &self.reversible, self.h, self.direction);
        let (_, dj, _) =
            params.cell_polarisations(&self.reversible, moving, !0, &self.cell_polarisation);
        Response { h: self.h, b: self.b, dh_db: 1.0 / (MU_0 + dj), iterations: 0, accepted: true }
    }

    /// Energy dissipated per volume from this state to `next` (J/m³): `Σ_k κ_k |J_k(next) − J_k(self)|`.
    pub fn dissipation_to(&self, params: &HysteresisParams, next: &Self) -> f64 {
        (0..params.cells())
            .map(|k| {
                let change = next.cell_polarisation[k] - self.cell_polarisation[k];
                params.pinning_a_per_m()[k] * change.abs()
            })
            .sum()
    }

    /// Free energy per volume stored in the state (J/m³): `μ0 H²/2 + Σ_k U_k(h_k)`.
    pub fn free_energy(&self, params: &HysteresisParams) -> f64 {
        0.5 * MU_0 * self.h * self.h
            + (0..params.cells())
                .map(|k| params.cell_free_energy(k, self.reversible[k]))
                .sum::<f64>()
    }

    /// Solves `B(H) = b_new` along the step from this state in direction `s` (safeguarded Newton,
    /// started at `guess` when given, else one step along the last tangent). Returns the cells at
    /// the root as evaluated there (no second evaluation).
    fn solve_field(
        &self,
        params: &HysteresisParams,
        b_new: f64,
        s: f64,
        guess: Option<f64>,
    ) -> Solved {
        let evaluate = |h: f64| {
            let (reversible, moving, changed) = played(params, &self.reversible, h, s);
            let (cells, dj, d2j) =
                params.cell_polarisations(&reversible, moving, !changed, &self.cell_polarisation);
            let j: f64 = cells.iter().sum();
            (Cells { reversible, polarisation: cells }, MU_0 * h + j - b_new, dj, d2j)
        };
        // The root lies between H₀ (residual B₀ − b_new) and H₀ + ΔB/μ0 (slope ≥ μ0).
        let far = self.h + (b_new - self.b) / MU_0;
        let (mut lo, mut hi) = if s > 0.0 { (self.h, far) } else { (far, self.h) };
        let tolerance = TOLERANCE_T * (1.0 + b_new.abs());
        let start = guess.unwrap_or(self.h + (b_new - self.b) * self.tangent_dh_db);
        let mut h = start.clamp(lo, hi);
        let mut iterations = 0;
        loop {
            iterations += 1;
            let (cells, r, dj, d2j) = evaluate(h);
            let narrow = hi - lo <= f64::EPSILON * hi.abs().max(lo.abs());
            if r.abs() <= tolerance || narrow || iterations >= MAX_ITERATIONS {
                return Solved { h, cells, dj, iterations };
            }
            if r > 0.0 {
                hi = h
            } else {
                lo = h
            }
            h = next_iterate(h, r, MU_0 + dj, d2j, lo, hi);
        }
    }

    /// Commits a solved B-driven step and returns its response.
    fn commit(&mut self, solved: Solved, b_new: f64, s: f64) -> Response {
        let response = solved.response(b_new);
        self.reversible = solved.cells.reversible;
        self.cell_polarisation = solved.cells.polarisation;
        self.h = solved.h;
        self.b = b_new;
        self.direction = s;
        self.tangent_dh_db = response.dh_db;
        response
    }
}

/// The next iterate of the root search: Halley's step (cubic convergence on a smooth piece, using
/// `F'' = d²J/dH²`), else Newton's, else bisection — whichever first lies inside the bracket.
#[inline]
fn next_iterate(h: f64, r: f64, slope: f64, curvature: f64, lo: f64, hi: f64) -> f64 {
    let inside = |x: f64| x > lo && x < hi;
    let denominator = 2.0 * slope * slope - r * curvature;
    let halley = h - 2.0 * r * slope / denominator;
    if denominator > 0.0 && inside(halley) {
        return halley;
    }
    let newton = h - r / slope;
    if inside(newton) { newton } else { 0.5 * (lo + hi) }
}

/// The reversible fields of the cells and their polarisations, T.
struct Cells {
    reversible: [f64; MAX_CELLS],
    polarisation: [f64; MAX_CELLS],
}

/// A solved B-driven step: the field, the cells there, and `dJ/dH` of the moving cells.
struct Solved {
    h: f64,
    cells: Cells,
    dj: f64,
    iterations: u32,
}

impl Solved {
    /// The response of the step to `b_new` this root solves.
    fn response(&self, b_new: f64) -> Response {
        Response {
            h: self.h,
            b: b_new,
            dh_db: 1.0 / (MU_0 + self.dj),
            iterations: self.iterations,
            accepted: true,
        }
    }
}

/// The reversible fields after the applied field moves to `h` (the play rule of each cell), the
/// cells then on the leading edge of their band for a motion in direction `s` (bit `k` set: they
/// follow a further change of the applied field with slope 1) and the cells whose reversible field
/// changed (bit `k` set). One pass over the cells.
#[inline]
fn played(
    params: &HysteresisParams,
    reversible: &[f64; MAX_CELLS],
    h: f64,
    s: f64,
) -> ([f64; MAX_CELLS], u32, u32) {
    let mut next = *reversible;
    let (mut moving, mut changed) = (0u32, 0u32);
    for (k, &kappa) in params.pinning_a_per_m().iter().enumerate() {
        // max/min rather than clamp: no check that the bounds are ordered (they are, κ ≥ 0).
        next[k] = next[k].max(h - kappa).min(h + kappa);
        if leads(next[k], h, kappa, s) {
            moving |= 1 << k;
        }
        if next[k].to_bits() != reversible[k].to_bits() {
            changed |= 1 << k;
        }
    }
    (next, moving, changed)
}

/// The cells on the leading edge of their band for a motion in direction `s` (bit `k` set).
#[inline]
fn moving_cells(params: &HysteresisParams, reversible: &[f64; MAX_CELLS], h: f64, s: f64) -> u32 {
    let mut moving = 0u32;
    for (k, &kappa) in params.pinning_a_per_m().iter().enumerate() {
        if leads(reversible[k], h, kappa, s) {
            moving |= 1 << k;
        }
    }
    moving
}

/// Whether a cell at reversible field `reversible` is on the leading edge of its band `[h − κ, h + κ]`
/// for a motion in direction `s`; before any motion (`s = 0`) only cells without pinning follow.
#[inline]
fn leads(reversible: f64, h: f64, kappa: f64, s: f64) -> bool {
    // The play rule puts a moving cell exactly at h − s κ; allow rounding.
    let lag = if s == 0.0 { (h - reversible).abs() } else { s * (h - reversible) };
    lag >= kappa - 1e-9 * (kappa + h.abs())
}
