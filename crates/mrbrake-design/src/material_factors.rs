//! The spec's material factors (`[fluid]`, `[steel]`, [`crate::spec::FluidFactors`]) applied to the
//! library's materials: the magnetic law of every region, the gap medium whose yield stress the
//! torque integrates, and the conductivities of the dynamic analysis.
//!
//! * **Polarisation scale** (`fluid.B_scale`, `steel.B_scale`, factor `s`): the curve's
//!   polarisation `J = B − μ0 H` is scaled, `B'(H) = μ0 H + s J(H)` (B = μ0 (H + M), Bertotti,
//!   *Hysteresis in Magnetism*, 1998, eq. 2.6): the saturation polarisation `J_s` scales by `s`,
//!   the vacuum part is kept, so the curve still tends to the slope μ0 and stays monotone. A linear
//!   material's `μr` becomes `1 + s (μr − 1)`.
//! * **Fill fraction** (`fluid.fill_fraction`, `f`): the gap's surface is wetted by fluid over a
//!   share `f`, the rest is air. The flux crosses the gap's width; fluid and air patches side by
//!   side across the surface carry it in **parallel** (same magnetic potential drop, so the same H
//!   across the width; fluxes add): `B_gap(H) = f B_fluid(H) + (1 − f) μ0 H`, the upper Wiener
//!   bound of a two-phase mixture (Wiener 1912; Sihvola, *Electromagnetic Mixing Formulas and
//!   Applications*, 1999, §3.1). That is the polarisation scale `f` on the fluid's law, so the gap
//!   region's law is `B = μ0 H + f s J_fluid(H)`. The alternative, an air layer on a wall (series,
//!   the lower bound), would describe an unfilled strip along the whole surface, which a drum
//!   turning in the fluid does not keep. The yield stress acts only on the wetted share: at a
//!   point of the gap with the field solution's (mean) `B_gap`, `H = H_gap(B_gap)`, the fluid there
//!   has `B_fluid(H)` and the shear stress per unit of gap surface is `f τ_y(B_fluid)`; the viscous
//!   torque scales by `f` too (air's viscosity, 1.8e-5 Pa·s, is four orders below the fluid's).
//! * **Yield-stress scale** (`fluid.yield_stress_scale`, `k`): `τ_y → k τ_y`, in the variable
//!   (B or H) the datasheet tabulates it in.
//!
//! At the defaults (`s = f = k = 1`, no override) every law is the library's own object and every
//! stress is multiplied by exactly 1.0, so results are bit-identical to a spec without factors.

use std::sync::Arc;

use mrbrake_materials::{BhCurve, FieldVariable, MU_0, Magnetic, MrFluid, library};

use crate::DesignError;
use crate::geometry::{PartKind, Region};
use crate::spec::BrakeSpec;
use mrbrake_error::FieldError;

/// What fills the gaps, as the torque sees it: the library fluid with the spec's factors.
#[derive(Debug, Clone)]
pub struct GapMedium {
    fluid: Arc<MrFluid>,
    yield_scale: f64,
    fill_fraction: f64,
    /// The fluid's polarisation scale `s`.
    b_scale: f64,
    /// The gap region's law `μ0 H + f s J(H)` unless `f = s = 1`.
    gap_law: Option<Arc<BhCurve>>,
}

impl GapMedium {
    /// The gap medium of `spec`: `materials.fluid` with the `[fluid]` factors.
    pub fn of(spec: &BrakeSpec) -> Result<Self, DesignError> {
        let fluid = library_fluid(spec)?;
        let f = &spec.fluid;
        let gap_law = if is_one(f.fill_fraction) && is_one(f.b_scale) {
            None
        } else {
            let combined = f.fill_fraction * f.b_scale;
            Some(Arc::new(scaled_curve(fluid.bh(), combined, "fluid")?))
        };
        Ok(Self {
            fluid,
            yield_scale: f.yield_stress_scale,
            fill_fraction: f.fill_fraction,
            b_scale: f.b_scale,
            gap_law,
        })
    }

    /// The library fluid.
    pub fn fluid(&self) -> &MrFluid {
        &self.fluid
    }

    /// The share of each gap's surface wetted by fluid.
    pub fn fill_fraction(&self) -> f64 {
        self.fill_fraction
    }

    /// The gap region's magnetic law (the fluid's, or the fluid–air parallel law with the scales).
    pub fn magnetic(&self) -> Magnetic {
        match &self.gap_law {
            Some(curve) => Magnetic::from_curve(Arc::clone(curve)),
            None => Magnetic::from_curve(Arc::clone(self.fluid.bh())),
        }
    }

    /// The fluid's yield stress τ_y (Pa) where the gap's field solution has flux density `b_gap`
    /// (T): the library's `τ_y(b_gap)` at the defaults; else `k τ_y` of the fluid's own B (or H)
    /// at the field strength `H_gap(b_gap)` (module docs).
    pub fn tau_y_of_b(&self, b_gap: f64) -> f64 {
        let Some(gap_law) = &self.gap_law else {
            return self.yield_scale * self.fluid.tau_y_of_b(b_gap);
        };
        let h = gap_law.h_of_b(b_gap);
        let tau = match self.fluid.yield_stress().variable() {
            FieldVariable::FieldStrength => self.fluid.yield_stress().tau_y(h),
            FieldVariable::FluxDensity => {
                let b_lib = self.fluid.bh().b_of_h(h);
                self.fluid.yield_stress().tau_y(MU_0 * h + self.b_scale * (b_lib - MU_0 * h))
            }
        };
        self.yield_scale * tau
    }

    /// The shear stress per unit of gap surface (Pa): the wetted share times
    /// [`Self::tau_y_of_b`].
    pub fn surface_tau_y_of_b(&self, b_gap: f64) -> f64 {
        self.fill_fraction * self.tau_y_of_b(b_gap)
    }

    /// The off-state viscosity per unit of gap surface (Pa·s): the wetted share times the fluid's.
    pub fn surface_viscosity_pa_s(&self) -> f64 {
        self.fill_fraction * self.fluid.viscosity_pa_s()
    }
}

/// The library fluid of `materials.fluid`.
pub(crate) fn library_fluid(spec: &BrakeSpec) -> Result<Arc<MrFluid>, DesignError> {
    let material = library::get(&spec.materials.fluid)?;
    material.fluid.clone().ok_or_else(|| {
        let e =
            FieldError::new("materials.fluid", "not an MR fluid (see `mrbrake materials list`)")
                .with_value(format!("'{}'", spec.materials.fluid));
        spec.invalid(e.into())
    })
}

/// The magnetic law of each region of a spec: the library's, the gaps' with the fluid factors,
/// the flux-path steel's with `steel.B_scale`.
pub struct RegionLaws<'s> {
    spec: &'s BrakeSpec,
    gap: Magnetic,
    steel: Option<Magnetic>,
}

impl<'s> RegionLaws<'s> {
    /// The laws of `spec` (the gap medium's law is `medium`'s).
    pub fn new(spec: &'s BrakeSpec, medium: &GapMedium) -> Result<Self, DesignError> {
        let s = spec.steel.b_scale;
        let steel = if is_one(s) {
            None
        } else {
            let material = library::get(&spec.materials.flux_path)?;
            Some(scaled_magnetic(&material.magnetic, s, "steel")?)
        };
        Ok(Self { spec, gap: medium.magnetic(), steel })
    }

    /// The law of `region`.
    pub fn of(&self, region: &Region) -> Result<Magnetic, DesignError> {
        if region.kind == PartKind::Fluid {
            return Ok(self.gap.clone());
        }
        if let Some(steel) = &self.steel
            && region.material == self.spec.materials.flux_path
        {
            return Ok(steel.clone());
        }
        let material = library::get(&region.material)
            .map_err(|source| DesignError::PartMaterial { part: region.name.clone(), source })?;
        Ok(material.magnetic.clone())
    }
}

/// The conductivity (S/m) the spec gives a region's material, overriding the library's: the
/// fluid's for the gaps, the steel's for parts of the flux-path material.
pub fn conductivity_override(spec: &BrakeSpec, region: &Region) -> Option<f64> {
    if region.kind == PartKind::Fluid {
        spec.fluid.conductivity_s_per_m
    } else if region.material == spec.materials.flux_path {
        spec.steel.conductivity_s_per_m
    } else {
        None
    }
}

/// `magnetic` with its polarisation scaled by `s`; `what` names the material for errors.
fn scaled_magnetic(magnetic: &Magnetic, s: f64, what: &str) -> Result<Magnetic, DesignError> {
    match magnetic {
        Magnetic::Linear { mu_r } => Ok(Magnetic::Linear { mu_r: 1.0 + s * (mu_r - 1.0) }),
        Magnetic::NonLinear(law) => match law.as_bh_curve() {
            Some(curve) => Ok(Magnetic::from_curve(Arc::new(scaled_curve(curve, s, what)?))),
            None => Err(FieldError::new(
                format!("{what}.B_scale"),
                format!(
                    "the {what}'s magnetic law is analytic, not a tabulated curve; only tabulated \
                     curves can be scaled"
                ),
            )
            .with_value(s)
            .into()),
        },
    }
}

/// The curve `B'(H) = μ0 H + s (B(H) − μ0 H)` through the scaled points of `curve`.
fn scaled_curve(curve: &BhCurve, s: f64, what: &str) -> Result<BhCurve, DesignError> {
    let points: Vec<(f64, f64)> =
        curve.points().iter().map(|&(h, b)| (h, MU_0 * h + s * (b - MU_0 * h))).collect();
    let mut provenance = curve.provenance().clone();
    provenance.method =
        format!("{}; polarisation scaled by {s} ({what} factors)", provenance.method);
    BhCurve::from_points(&points, provenance).map_err(|e| {
        FieldError::new(format!("{what}.B_scale"), format!("the scaled B-H curve is invalid: {e}"))
            .with_value(s)
            .into()
    })
}

/// Whether `x` is exactly 1 (a factor at its default).
fn is_one(x: f64) -> bool {
    x.to_bits() == 1.0f64.to_bits()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spec::default_spec;

    #[test]
    fn defaults_are_the_library_fluid() {
        let spec = default_spec();
        let medium = GapMedium::of(&spec).unwrap();
        for b in [0.0, 0.2, 0.5, 0.9, 1.4] {
            let lib = medium.fluid().tau_y_of_b(b);
            assert_eq!(medium.surface_tau_y_of_b(b).to_bits(), lib.to_bits());
        }
        assert!(medium.gap_law.is_none());
    }

    #[test]
    fn a_half_filled_gap_is_fluid_and_air_in_parallel() {
        let mut spec = default_spec();
        spec.fluid.fill_fraction = 0.5;
        let medium = GapMedium::of(&spec).unwrap();
        let law = medium.gap_law.as_ref().unwrap();
        let fluid = medium.fluid().bh();
        for h in [1e3, 2e4, 1e5, 3e5] {
            let expected = 0.5 * fluid.b_of_h(h) + 0.5 * MU_0 * h;
            assert!((law.b_of_h(h) - expected).abs() < 1e-3 * expected, "H = {h}");
            // The stress per unit surface: half the fluid's at the fluid's own B.
            let tau = medium.surface_tau_y_of_b(law.b_of_h(h));
            let full = medium.fluid().tau_y_of_b(fluid.b_of_h(h));
            assert!((tau - 0.5 * full).abs() < 2e-3 * full, "H = {h}: {tau} vs {full}");
        }
    }

    #[test]
    fn the_polarisation_scale_keeps_the_vacuum_slope() {
        let steel = library::get("steel-1008").unwrap();
        let Magnetic::NonLinear(law) = scaled_magnetic(&steel.magnetic, 0.9, "steel").unwrap()
        else {
            panic!("a curve")
        };
        let Magnetic::NonLinear(library_law) = &steel.magnetic else { panic!("a curve") };
        let curve = library_law.as_bh_curve().unwrap();
        let h = 2e5;
        let expected = MU_0 * h + 0.9 * (curve.b_of_h(h) - MU_0 * h);
        assert!((law.b_of_h(h) - expected).abs() < 1e-3 * expected);
        let Magnetic::Linear { mu_r } =
            scaled_magnetic(&Magnetic::Linear { mu_r: 3.0 }, 0.5, "x").unwrap()
        else {
            panic!("linear")
        };
        assert!((mu_r - 2.0).abs() < 1e-15);
    }
}
