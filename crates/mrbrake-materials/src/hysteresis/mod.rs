//! Magnetic hysteresis of the flux-path steel: a scalar **energy-based** (dry-friction, play) model,
//! driven by B for an A-formulation FEA, with identification from a measured loop.
//!
//! # Brief overview
//! * [`HysteresisParams`] — the configuration shared by a region: cells with pinning fields `κ_k`
//!   and reversible (anhysteretic) laws `J_k(h)`, each a non-negative sum of Fröhlich–Kennelly terms
//!   ([`Term`]).
//! * [`HysteresisState`] — the small `Copy` state of one quadrature point. [`HysteresisState::step`]
//!   takes `B` and returns `H` and the differential reluctivity `dH/dB` ([`Response`]);
//!   [`HysteresisState::step_h`] is the forward, H-driven form; [`HysteresisState::trial`] evaluates a
//!   step without committing it (Newton trials).
//! * [`identify`] — least-squares identification of a parameter set from measured `(H, B)` paths
//!   (a major loop, a first-magnetisation curve), linear in the term amplitudes on a grid of pinning
//!   fields and term fields, solved as non-negative least squares; CSV reading with file and line in
//!   every error; warnings for what the data do not determine.
//! * [`loop_measures`] — coercivity, remanence, loop area of a simulated or measured loop.
//! * [`library`] — parameter sets for the library's low-carbon steels, with provenance;
//!   [`library::for_material`] is how an FEA selects the law of a region by material name.
//! * [`NormalCurve`] — the model's normal magnetisation curve as a single-valued
//!   [`crate::Reluctivity`], to run the existing anhysteretic solvers on the same law.
//!
//! ```
//! use mrbrake_materials::hysteresis::{HysteresisState, library};
//! let steel = library::for_material("steel-1008").unwrap();
//! let mut point = HysteresisState::demagnetised();
//! let up = point.step(&steel.params, 1.5); // B-driven: returns H and dH/dB
//! let back = point.step(&steel.params, 0.0); // B back to 0 needs a negative H (remanence)
//! assert!(up.h > 0.0 && back.h < 0.0 && back.dh_db > 0.0);
//! ```
//!
//! # How an FEA uses it (the integration point)
//! [`crate::Magnetic`] stays the single-valued law of every region (anhysteretic solves are
//! untouched). A region whose steel is solved with hysteresis additionally gets an
//! `Arc<HysteresisParams>` (from [`library::for_material`], or a fitted set), and the solver keeps one
//! [`HysteresisState`] per quadrature point of that region. In each Newton iteration it calls
//! [`HysteresisState::trial_near`] from the committed state with the trial `B` (the previous
//! iteration's H as the guess) and assembles `H` and the tangent `dH/dB`; after convergence of the
//! step it commits the states returned by the last trials. In the axisymmetric A-formulation B is a
//! 2-vector: the scalar model acts along a per-point axis `e` fixed when the point is first
//! magnetised (`b = B·e`), with the tangent `dH/dB e⊗e + (H/b)(I − e⊗e)`; the vector play rule
//! of Henrotte et al. (2006) is the extension if the field rotates.
//!
//! # The model (Henrotte, Nicolet, Hameyer 2006; Bergqvist 1997)
//! F. Henrotte, A. Nicolet, K. Hameyer, "An energy-based vector hysteresis model for ferromagnetic
//! materials", COMPEL 25(1) (2006) 71–80; A. Bergqvist, "Magnetic vector hysteresis model with
//! dry friction-like pinning", Physica B 233 (1997) 342–347. The polarisation is split over `N`
//! cells, `J = Σ_k J_k`. Each cell stores energy `U_k(J_k)` (convex) and is pinned by dry friction of
//! strength `κ_k`: the applied field splits as `H = h_k + h_k^irr` with the reversible part
//! `h_k = ∂U_k/∂J_k` and the irreversible part bounded, `|h_k^irr| ≤ κ_k`, reaching `±κ_k` only when
//! `J_k` moves. In scalar form this is the play rule `h_k ← clamp(h_k, H − κ_k, H + κ_k)` and
//! `B = μ0 H + Σ_k J_k(h_k)` (see [`HysteresisState`]). With one shared law `J_k = ω_k J_an` this is
//! Henrotte's model exactly; here each cell may carry its own law (a non-negative mixture of terms),
//! which keeps identification linear and changes none of the properties below.
//!
//! # Why this model and not the inverse Jiles–Atherton model
//! The inverse JA model (N. Sadowski, N. J. Batistela, J. P. A. Bastos, M. Lajoie-Mazenc, IEEE Trans.
//! Magn. 38(2) (2002) 797–800; from D. C. Jiles, D. L. Atherton, J. Magn. Magn. Mater. 61 (1986)
//! 48–60) was the alternative. Against the criteria of the FEA:
//! * **Passivity.** Energy-based: by construction, `∮ H dB = Σ κ_k ∫|dJ_k| ≥ 0` for every history,
//!   also for the discretised steps (each cell moves monotonically within a step). JA: not by
//!   construction; without the `δ_M` correction it produces negative susceptibility after reversals,
//!   and its minor loops do not close (S. E. Zirka, Y. I. Moroz, R. G. Harrison, K. Chwastek, "On
//!   physical aspects of the Jiles-Atherton hysteresis models", J. Appl. Phys. 112 (2012) 043916).
//! * **Minor loops and reversals.** Energy-based: return-point memory and wiping-out (the play
//!   operator's), closed minor loops, a finite reversible slope right after a reversal. JA: unclosed
//!   minor loops, a slope discontinuity handled by `δ`/`δ_M` switches.
//! * **Cost per quadrature point.** Energy-based: no ODE; a B-driven step is a scalar monotone root
//!   (a few Newton iterations, each one division per term); exact for the discrete model, no
//!   sub-stepping. Inverse JA: an ODE in B integrated with sub-steps whose number sets the accuracy.
//! * **Identifiability from one major loop.** Energy-based: `B − μ0 H` is *linear* in the term
//!   amplitudes for a given H history (the cells' reversible fields depend only on H and `κ`), so a
//!   loop gives a convex non-negative least-squares problem on a grid of `κ` and term fields. JA: five
//!   coupled non-linear parameters, a non-convex fit with known multiple minima.
//! * **Newton robustness.** Energy-based: the step map `B ↦ H` is strictly increasing with
//!   `0 < dH/dB ≤ 1/μ0`; its tangent is exact. JA: `dH/dB` from the ODE right-hand side, which can
//!   become negative or unbounded near reversals without the corrections.
//! * **Vector extension** (later): the same cells with the vector form of the dry-friction rule (Henrotte et al. 2006).
//!
//! The model's anhysteretic limit (`κ → 0`) is the single-valued curve `μ0 H + Σ_k J_k(H)`; its
//! first-magnetisation curve from the demagnetised state, which is also the locus of the tips of
//! symmetric loops (the normal magnetisation curve), is `μ0 H + Σ_k J_k(max(H − κ_k, 0))`.

pub mod identify;
pub mod library;
mod measures;
mod nnls;
mod normal_curve;
mod params;
mod state;

pub use identify::{Identified, IdentifyOptions, Observation, PathStart};
pub use measures::{LoopMeasures, loop_measures, major_loop};
pub use normal_curve::NormalCurve;
pub use params::{HysteresisParams, MAX_CELLS, MAX_TERMS, Term};
pub use state::{HysteresisState, MAX_FLUX_DENSITY_T, MAX_ITERATIONS, Response};
