//! Magnetorheological fluids: B-H curve, yield stress `τ_y(B)` and `τ_y(H)`, viscosity, density.
//!
//! A fluid's yield stress is stored in the variable its data were given in (B for MRF-122EG, whose
//! points come from the thesis; H for the Carlson fits) and converted through the fluid's own B-H curve
//! for the other: `τ_y(H) = τ_y(B(H))` or `τ_y(B) = τ_y(H(B))`. The two views are therefore
//! consistent by construction.

use std::sync::Arc;

use serde::Serialize;

use crate::yield_stress::{FieldVariable, YieldStressCurve};
use crate::{BhCurve, Provenance, Sourced};

/// Off-state (zero-field) dynamic viscosity at a stated temperature.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Viscosity {
    /// Viscosity \[Pa·s\].
    #[serde(rename = "viscosity_Pa_s")]
    pub pa_s: f64,
    /// Temperature of the measurement \[°C\].
    #[serde(rename = "temperature_C")]
    pub temperature_c: f64,
    /// Where the number comes from.
    pub provenance: Provenance,
}

/// A published or quoted `(field, τ_y)` point the fluid model can be compared against.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ReferencePoint {
    /// Flux density \[T\], if given.
    #[serde(rename = "B_T")]
    pub b_t: Option<f64>,
    /// Field strength \[A/m\], if given.
    #[serde(rename = "H_A_per_m")]
    pub h_a_per_m: Option<f64>,
    /// Yield stress \[Pa\].
    #[serde(rename = "tau_y_Pa")]
    pub tau_y_pa: f64,
    /// Where the point comes from.
    pub source: String,
}

/// One comparison of the model against a [`ReferencePoint`].
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ReferenceCheck {
    /// The reference point.
    pub reference: ReferencePoint,
    /// The model's `τ_y` \[Pa\] at the point's B (or at its H when no B is given).
    #[serde(rename = "model_tau_y_Pa")]
    pub model_tau_y_pa: f64,
    /// `(model − reference)/reference` in percent.
    pub error_percent: f64,
}

/// An MR fluid with its curves and properties.
#[derive(Debug, Clone, PartialEq)]
pub struct MrFluid {
    name: String,
    bh: Arc<BhCurve>,
    yield_stress: YieldStressCurve,
    /// Iron volume fraction φ (0..1) with its source.
    pub iron_volume_fraction: Sourced<f64>,
    /// The carrier liquid in words.
    pub carrier: String,
    /// Off-state viscosities, the first at 30 °C (the default used by [`MrFluid::viscosity_pa_s`]).
    pub viscosities: Vec<Viscosity>,
    /// Density \[kg/m³\] with its source.
    pub density_kg_m3: Sourced<f64>,
    /// Points to compare the model against.
    pub reference_points: Vec<ReferencePoint>,
}

impl MrFluid {
    /// Assembles a fluid. `viscosities` must not be empty (the first is the default).
    pub fn new(
        name: impl Into<String>,
        bh: Arc<BhCurve>,
        yield_stress: YieldStressCurve,
        iron_volume_fraction: Sourced<f64>,
        carrier: impl Into<String>,
        viscosities: Vec<Viscosity>,
        density_kg_m3: Sourced<f64>,
    ) -> Self {
        Self {
            name: name.into(),
            bh,
            yield_stress,
            iron_volume_fraction,
            carrier: carrier.into(),
            viscosities,
            density_kg_m3,
            reference_points: Vec::new(),
        }
    }

    /// The fluid's library name (e.g. `mrf-122eg`).
    pub fn name(&self) -> &str {
        &self.name
    }

    /// The fluid's B-H curve.
    pub fn bh(&self) -> &Arc<BhCurve> {
        &self.bh
    }

    /// The yield-stress table in the variable it was given in.
    pub fn yield_stress(&self) -> &YieldStressCurve {
        &self.yield_stress
    }

    /// Yield stress `τ_y` \[Pa\] at flux density `b` \[T\] in the fluid; any `b` (saturates above the data).
    pub fn tau_y_of_b(&self, b: f64) -> f64 {
        match self.yield_stress.variable() {
            FieldVariable::FluxDensity => self.yield_stress.tau_y(b),
            FieldVariable::FieldStrength => self.yield_stress.tau_y(self.bh.h_of_b(b)),
        }
    }

    /// Yield stress `τ_y` \[Pa\] at field strength `h` \[A/m\] in the fluid, through the B-H curve.
    pub fn tau_y_of_h(&self, h: f64) -> f64 {
        match self.yield_stress.variable() {
            FieldVariable::FluxDensity => self.yield_stress.tau_y(self.bh.b_of_h(h)),
            FieldVariable::FieldStrength => self.yield_stress.tau_y(h),
        }
    }

    /// The value `τ_y` tends to at high field \[Pa\].
    pub fn tau_y_ceiling_pa(&self) -> f64 {
        self.yield_stress.ceiling_pa()
    }

    /// The default off-state viscosity \[Pa·s\] (the first listed, at 30 °C).
    pub fn viscosity_pa_s(&self) -> f64 {
        self.viscosities.first().map(|v| v.pa_s).unwrap_or(f64::NAN)
    }

    /// The model against every reference point (at B when the point gives B, else at H).
    pub fn reference_checks(&self) -> Vec<ReferenceCheck> {
        self.reference_points
            .iter()
            .map(|p| {
                let model = match (p.b_t, p.h_a_per_m) {
                    (Some(b), _) => self.tau_y_of_b(b),
                    (None, Some(h)) => self.tau_y_of_h(h),
                    (None, None) => f64::NAN,
                };
                ReferenceCheck {
                    reference: p.clone(),
                    model_tau_y_pa: model,
                    error_percent: 100.0 * (model - p.tau_y_pa) / p.tau_y_pa,
                }
            })
            .collect()
    }
}
