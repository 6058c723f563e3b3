//! A material as the solvers see it: magnetic behaviour, density, conductivity, provenance.

use std::sync::Arc;

use serde::Serialize;

use crate::{BhCurve, MU_0, MrFluid, Provenance, Sourced};

/// What kind of material an entry is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum MaterialKind {
    /// Soft-magnetic steel with a non-linear B-H curve.
    Steel,
    /// Non-magnetic material with a constant relative permeability (air, aluminium, stainless, copper).
    Linear,
    /// Magnetorheological fluid (non-linear B-H curve plus yield stress and viscosity).
    MrFluid,
}

impl MaterialKind {
    /// The kind in words.
    pub fn as_str(self) -> &'static str {
        match self {
            MaterialKind::Steel => "steel",
            MaterialKind::Linear => "linear",
            MaterialKind::MrFluid => "mr-fluid",
        }
    }
}

/// The magnetic constitutive law `H = ν(B²) B`.
#[derive(Debug, Clone, PartialEq)]
pub enum Magnetic {
    /// `B = μ0 μr H` with a constant relative permeability.
    Linear {
        /// Relative permeability (dimensionless).
        mu_r: f64,
    },
    /// A non-linear B-H curve.
    NonLinear(Arc<BhCurve>),
}

impl Magnetic {
    /// Reluctivity `ν` \[m/H\] at `b2 = B²` (constant `1/(μ0 μr)` for a linear material).
    #[inline]
    pub fn nu_of_b2(&self, b2: f64) -> f64 {
        match self {
            Magnetic::Linear { mu_r } => 1.0 / (MU_0 * mu_r),
            Magnetic::NonLinear(curve) => curve.nu_of_b2(b2),
        }
    }

    /// `dν/dB²` at `b2 = B²` (zero for a linear material).
    #[inline]
    pub fn dnu_db2(&self, b2: f64) -> f64 {
        match self {
            Magnetic::Linear { .. } => 0.0,
            Magnetic::NonLinear(curve) => curve.dnu_db2(b2),
        }
    }

    /// True for a non-linear material (the solver needs Newton iterations).
    pub fn is_nonlinear(&self) -> bool {
        matches!(self, Magnetic::NonLinear(_))
    }

    /// Flux density \[T\] at field strength `h` \[A/m\].
    pub fn b_of_h(&self, h: f64) -> f64 {
        match self {
            Magnetic::Linear { mu_r } => MU_0 * mu_r * h,
            Magnetic::NonLinear(curve) => curve.b_of_h(h),
        }
    }
}

/// One entry of the material library.
#[derive(Debug, Clone, PartialEq)]
pub struct Material {
    /// Library name (lower case, e.g. `steel-1008`).
    pub name: String,
    /// Kind of material.
    pub kind: MaterialKind,
    /// One line saying what it is.
    pub description: String,
    /// Magnetic behaviour.
    pub magnetic: Magnetic,
    /// Where the magnetic data come from.
    pub provenance: Provenance,
    /// Density \[kg/m³\], when known.
    pub density_kg_m3: Option<Sourced<f64>>,
    /// Electrical conductivity \[S/m\], when known.
    pub conductivity_s_per_m: Option<Sourced<f64>>,
    /// The constant μr the source library uses for linear solves of a steel (not part of its curve).
    pub mu_r_linear: Option<f64>,
    /// The fluid data, for an MR fluid.
    pub fluid: Option<Arc<MrFluid>>,
}
