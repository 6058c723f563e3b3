//! Material library for mrbrake: B-H curves, MR-fluid yield stress, linear materials, copper wire.
//!
//! # Brief overview
//! * [`BhCurve`] — a validated non-linear B-H curve (from points or a CSV file `H_A_per_m,B_T`), stored
//!   as a monotone C¹ cubic `H(B)` that passes through every data point and continues with slope `μ0`
//!   beyond the last one. It gives `B(H)`, `H(B)` and the reluctivity `ν(B²) = H/B` with its exact
//!   derivative `dν/dB²` for Newton solvers ([`BhCurve::nu_of_b2`], [`BhCurve::dnu_db2`]).
//! * [`YieldStressCurve`] — an MR fluid's `τ_y` of B or H: monotone C¹ through the data, saturating
//!   smoothly above it.
//! * [`MrFluid`] — B-H curve, `τ_y(B)`, `τ_y(H)`, viscosity, density, reference points.
//! * [`Material`] and [`Magnetic`] — what a solver needs per region: `Linear { mu_r }` or
//!   `NonLinear(Arc<BhCurve>)`, density, conductivity.
//! * [`hysteresis`] — magnetic hysteresis of the flux-path steel: a scalar energy-based (play)
//!   model driven by B for an A-formulation FEA (H and `dH/dB` per quadrature point from a small
//!   `Copy` state), identification from measured loops, and parameter sets for the library's steels.
//! * [`library`] — the built-in materials by name (`steel-1008`, `air`, `mrf-122eg`, …), vendored from
//!   `data/` and parsed once.
//! * [`thermal`] — thermal conductivity, density, specific heat (with sources) and the homogenised
//!   winding.
//! * [`wire`] — copper wire by AWG (18–32) or by diameter, resistance at a temperature.
//! * Every curve and property carries a [`Provenance`] (source, method, [`Trust`]).
//!
//! All values are SI: H in A/m, B in T, τ in Pa, ν in m/H, density in kg/m³, σ in S/m.
//!
//! ```
//! use mrbrake_materials::library;
//! let steel = library::bh_curve("steel-1008").unwrap();
//! let b = steel.b_of_h(1000.0); // T at 1 kA/m (1.374 T by linear interpolation of the same points)
//! assert!((b - 1.40).abs() < 0.01);
//! let nu = steel.nu_of_b2(b * b);
//! assert!((nu * b - 1000.0).abs() < 1e-6);
//! ```

mod bh_curve;
mod error;
mod hermite;
pub mod hysteresis;
pub mod library;
mod material;
mod mr_fluid;
mod provenance;
mod table;
pub mod thermal;
pub mod wire;
mod yield_stress;

pub use bh_curve::{BH_HEADER, BhCurve, MIN_BH_POINTS};
pub use error::MaterialError;
pub use material::{Magnetic, Material, MaterialKind, Reluctivity};
pub use mr_fluid::{MrFluid, ReferenceCheck, ReferencePoint, Viscosity};
pub use provenance::{Provenance, Sourced, Trust};
pub use wire::CopperWire;
pub use yield_stress::{FieldVariable, MIN_YIELD_POINTS, YieldStressCurve};

/// Vacuum magnetic permeability μ0 = 1.256 637 062 12(19)·10⁻⁶ N/A² (= H/m), the CODATA 2018
/// recommended value: E. Tiesinga, P. J. Mohr, D. B. Newell, B. N. Taylor, "CODATA recommended
/// values of the fundamental physical constants: 2018", Rev. Mod. Phys. 93 (2021) 025010; NIST
/// reference <https://physics.nist.gov/cgi-bin/cuu/Value?mu0>.
///
/// Since the 2019 redefinition of the SI, μ0 is measured, no longer exactly 4π·10⁻⁷ N/A²; the
/// difference is 5.4·10⁻¹⁰ relative. This is mrbrake's one μ0: every crate uses this constant.
///
/// ```
/// let four_pi_e7 = 4.0 * std::f64::consts::PI * 1e-7;
/// let relative = (mrbrake_materials::MU_0 - four_pi_e7) / four_pi_e7;
/// assert!(relative > 5.4e-10 && relative < 5.5e-10);
/// ```
pub const MU_0: f64 = 1.256_637_062_12e-6;
