//! A material as the solvers see it: magnetic behaviour, density, conductivity, provenance.

use std::fmt::Debug;
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

/// A non-linear isotropic reluctivity law `H = ν(B²) B`: what a Newton solver needs at every
/// quadrature point (the Jacobian coefficient is `ν I + 2 dν/dB² B⊗B`). The library's
/// [`BhCurve`] implements it; so can an analytic law (e.g. Marrocco's curve in the magnetic
/// solver's validation tests, whose inverse is an independent bisection).
pub trait Reluctivity: Send + Sync + Debug {
    /// `(ν, dν/dB²)` at `b2 = B²` (ν in m/H, dν/dB² in m/(H·T²)).
    fn nu_and_dnu_db2(&self, b2: f64) -> (f64, f64);

    /// Field strength `H(B)` (A/m) for `B >= 0`; defaults to `ν(B²) B`.
    fn h_of_b(&self, b: f64) -> f64 {
        self.nu_and_dnu_db2(b * b).0 * b
    }

    /// Flux density `B(H)` (T) for `H >= 0` (A/m); defaults to bisection of the monotone `H(B)`
    /// on a bracket doubled from `μ0 H` until it holds the root.
    fn b_of_h(&self, h: f64) -> f64 {
        let h = h.abs();
        let (mut lo, mut hi) = (0.0, MU_0 * h + 1e-12);
        while self.h_of_b(hi) < h && hi < 1e6 {
            lo = hi;
            hi *= 2.0;
        }
        for _ in 0..200 {
            let mid = 0.5 * (lo + hi);
            if self.h_of_b(mid) < h { lo = mid } else { hi = mid }
        }
        0.5 * (lo + hi)
    }

    /// The tabulated curve behind the law, when it is one (curve points and provenance for
    /// reports).
    fn as_bh_curve(&self) -> Option<&BhCurve> {
        None
    }
}

impl Reluctivity for BhCurve {
    #[inline]
    fn nu_and_dnu_db2(&self, b2: f64) -> (f64, f64) {
        BhCurve::nu_and_dnu_db2(self, b2)
    }

    fn h_of_b(&self, b: f64) -> f64 {
        BhCurve::h_of_b(self, b)
    }

    fn b_of_h(&self, h: f64) -> f64 {
        BhCurve::b_of_h(self, h)
    }

    fn as_bh_curve(&self) -> Option<&BhCurve> {
        Some(self)
    }
}

/// The magnetic constitutive law `H = ν(B²) B` of a material: the one type the library, the brake
/// geometry and the field solvers share.
#[derive(Debug, Clone)]
pub enum Magnetic {
    /// `B = μ0 μr H` with a constant relative permeability.
    Linear {
        /// Relative permeability (dimensionless).
        mu_r: f64,
    },
    /// A non-linear law: a library or CSV [`BhCurve`], or an analytic [`Reluctivity`].
    NonLinear(Arc<dyn Reluctivity>),
}

impl PartialEq for Magnetic {
    /// Linear laws compare their μr; non-linear ones are equal when they are the same law (one
    /// `Arc`) or equal tabulated curves.
    fn eq(&self, other: &Self) -> bool {
        match (self, other) {
            (Self::Linear { mu_r: a }, Self::Linear { mu_r: b }) => a.to_bits() == b.to_bits(),
            (Self::NonLinear(a), Self::NonLinear(b)) => {
                Arc::ptr_eq(a, b)
                    || matches!((a.as_bh_curve(), b.as_bh_curve()), (Some(x), Some(y)) if x == y)
            }
            _ => false,
        }
    }
}

impl Magnetic {
    /// Air / vacuum (μr = 1).
    pub fn air() -> Self {
        Self::Linear { mu_r: 1.0 }
    }

    /// A non-linear law from a tabulated curve.
    pub fn from_curve(curve: Arc<BhCurve>) -> Self {
        Self::NonLinear(curve)
    }

    /// `(ν, dν/dB²)` at `b2 = B²` (constant `1/(μ0 μr)` and 0 for a linear material).
    #[inline]
    pub fn nu_and_dnu_db2(&self, b2: f64) -> (f64, f64) {
        match self {
            Self::Linear { mu_r } => (1.0 / (MU_0 * mu_r), 0.0),
            Self::NonLinear(curve) => curve.nu_and_dnu_db2(b2),
        }
    }

    /// Reluctivity `ν` \[m/H\] at `b2 = B²`.
    #[inline]
    pub fn nu_of_b2(&self, b2: f64) -> f64 {
        self.nu_and_dnu_db2(b2).0
    }

    /// `dν/dB²` at `b2 = B²` (zero for a linear material).
    #[inline]
    pub fn dnu_db2(&self, b2: f64) -> f64 {
        self.nu_and_dnu_db2(b2).1
    }

    /// True for a non-linear material (the solver needs Newton iterations).
    pub fn is_nonlinear(&self) -> bool {
        matches!(self, Self::NonLinear(_))
    }

    /// Flux density \[T\] at field strength `h` \[A/m\].
    pub fn b_of_h(&self, h: f64) -> f64 {
        match self {
            Self::Linear { mu_r } => MU_0 * mu_r * h,
            Self::NonLinear(curve) => curve.b_of_h(h),
        }
    }

    /// The tabulated B-H curve, for a non-linear material that has one.
    pub fn bh_curve(&self) -> Option<&BhCurve> {
        match self {
            Self::Linear { .. } => None,
            Self::NonLinear(curve) => curve.as_bh_curve(),
        }
    }

    /// Stored energy density `w(B) = ∫_0^B H db` (J/m³); the co-energy density is `H B − w`.
    /// Linear: `ν B²/2`; non-linear: composite 4-point Gauss–Legendre over 8 panels of `[0, B]`.
    pub fn energy_density(&self, b: f64) -> f64 {
        let b = b.abs();
        match self {
            Self::Linear { mu_r } => 0.5 * b * b / (MU_0 * mu_r),
            Self::NonLinear(curve) => {
                const X: [f64; 4] = [
                    0.069_431_844_202_974,
                    0.330_009_478_207_572,
                    0.669_990_521_792_428,
                    0.930_568_155_797_026,
                ];
                const W: [f64; 4] = [
                    0.173_927_422_568_727,
                    0.326_072_577_431_273,
                    0.326_072_577_431_273,
                    0.173_927_422_568_727,
                ];
                let panels = 8;
                let h = b / panels as f64;
                let mut sum = 0.0;
                for p in 0..panels {
                    for q in 0..4 {
                        sum += W[q] * curve.h_of_b(h * (p as f64 + X[q]));
                    }
                }
                sum * h
            }
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
