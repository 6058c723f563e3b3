//! Material-level factors of a spec: the optional `[fluid]` and `[steel]` tables that scale the
//! library's curves of the fluid in the gaps and the flux-path steel, declare the share of each
//! gap wetted by fluid, and override a conductivity. They exist so that uncertainty studies and
//! calibration (issue 29) can vary what a material library cannot know about one prototype: the
//! fluid batch, a gap not completely filled (Karabulut 2017, §5.3.1, blamed "remaining air inside
//! the MR-fluid gap" for the measured 3.84 N·m against 4.33 N·m predicted), the steel's heat
//! treatment.
//!
//! Every factor defaults to the library's value (scales 1, fill fraction 1, no override); a table
//! at its defaults is not written (`skip_serializing_if`), so the JSON a design key hashes, and
//! every result, are those of a spec without the table. What each factor does to the analysis is
//! in [`crate::material_factors`].

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use super::{Bounds, Quantity, SpecField, validate::Problems};

/// A scale of a curve (yield stress, polarisation): positive, at most 5 (a sanity bound; batch
/// spreads are a few ten per cent).
pub const SCALE_BOUNDS: Bounds = Bounds::open_closed(0.0, 5.0);
/// The share of a gap's surface wetted by fluid: above 0 (a dry gap transmits nothing and is not
/// a brake), at most 1.
pub const FILL_FRACTION_BOUNDS: Bounds = Bounds::open_closed(0.0, 1.0);
/// An electrical conductivity (S/m): 0 (an insulator) to 1e8 S/m (above silver's 6.3e7 S/m).
pub const CONDUCTIVITY_BOUNDS: Bounds = Bounds::closed(0.0, 1e8);

/// The fluid in the gaps (`[fluid]`): factors on the library fluid of `materials.fluid`.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct FluidFactors {
    /// Factor on the yield stress τ_y(B) of the library fluid (dimensionless, (0, 5], default 1):
    /// the batch-to-batch spread of the fluid's on-state strength.
    #[serde(default = "one")]
    pub yield_stress_scale: f64,
    /// Factor on the fluid's magnetic polarisation J = B − μ0 H, the B–H curve becoming
    /// B = μ0 H + s·J(H) (dimensionless, (0, 5], default 1): the spread of its iron content.
    #[serde(default = "one", rename = "B_scale")]
    pub b_scale: f64,
    /// Share of each gap's surface wetted by fluid, the rest air (dimensionless, (0, 1], default
    /// 1): the gap's yield and viscous torques scale by it and its magnetic law is the fluid's and
    /// air's in parallel (`material_factors`).
    #[serde(default = "one")]
    pub fill_fraction: f64,
    /// Electrical conductivity of the fluid (S/m, [0, 1e8]); default: the library's (none: the
    /// fluid carries no eddy currents in `response`).
    #[serde(default, rename = "conductivity_S_per_m", skip_serializing_if = "Option::is_none")]
    pub conductivity_s_per_m: Option<f64>,
}

/// The flux-path steel (`[steel]`): factors on the library steel of `materials.flux_path`, in every
/// part made of it.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SteelFactors {
    /// Factor on the steel's magnetic polarisation J = B − μ0 H, so on its saturation
    /// polarisation (dimensionless, (0, 5], default 1): the spread of the grade's saturation with
    /// composition and annealing.
    #[serde(default = "one", rename = "B_scale")]
    pub b_scale: f64,
    /// Electrical conductivity of the steel (S/m, [0, 1e8]); default: the library's. The
    /// `response --conductivity` option still takes precedence.
    #[serde(default, rename = "conductivity_S_per_m", skip_serializing_if = "Option::is_none")]
    pub conductivity_s_per_m: Option<f64>,
}

fn one() -> f64 {
    1.0
}

/// Whether `x` is exactly 1 (the factors' default; compared by bits, as written).
fn is_one(x: f64) -> bool {
    x.to_bits() == 1.0f64.to_bits()
}

impl Default for FluidFactors {
    fn default() -> Self {
        Self {
            yield_stress_scale: 1.0,
            b_scale: 1.0,
            fill_fraction: 1.0,
            conductivity_s_per_m: None,
        }
    }
}

impl Default for SteelFactors {
    fn default() -> Self {
        Self { b_scale: 1.0, conductivity_s_per_m: None }
    }
}

impl FluidFactors {
    /// The numeric fields of `[fluid]`.
    pub const FIELDS: &'static [SpecField] = &[
        SpecField::factor("fluid.yield_stress_scale", SCALE_BOUNDS),
        SpecField::factor("fluid.B_scale", SCALE_BOUNDS),
        SpecField::factor("fluid.fill_fraction", FILL_FRACTION_BOUNDS),
        SpecField::conductivity("fluid.conductivity_S_per_m"),
    ];

    /// True when every factor is at its default (the table is then not written).
    pub fn is_default(&self) -> bool {
        is_one(self.yield_stress_scale)
            && is_one(self.b_scale)
            && is_one(self.fill_fraction)
            && self.conductivity_s_per_m.is_none()
    }
}

impl SteelFactors {
    /// The numeric fields of `[steel]`.
    pub const FIELDS: &'static [SpecField] = &[
        SpecField::factor("steel.B_scale", SCALE_BOUNDS),
        SpecField::conductivity("steel.conductivity_S_per_m"),
    ];

    /// True when every factor is at its default (the table is then not written).
    pub fn is_default(&self) -> bool {
        is_one(self.b_scale) && self.conductivity_s_per_m.is_none()
    }
}

impl SpecField {
    const fn factor(path: &'static str, bounds: Bounds) -> Self {
        Self { path, quantity: Quantity::Factor, bounds }
    }

    const fn conductivity(path: &'static str) -> Self {
        Self { path, quantity: Quantity::Conductivity, bounds: CONDUCTIVITY_BOUNDS }
    }
}

/// Checks every factor against its bounds (NaN is outside every range).
pub(super) fn check(fluid: &FluidFactors, steel: &SteelFactors, p: &mut Problems) {
    let values = [
        (&FluidFactors::FIELDS[0], Some(fluid.yield_stress_scale)),
        (&FluidFactors::FIELDS[1], Some(fluid.b_scale)),
        (&FluidFactors::FIELDS[2], Some(fluid.fill_fraction)),
        (&FluidFactors::FIELDS[3], fluid.conductivity_s_per_m),
        (&SteelFactors::FIELDS[0], Some(steel.b_scale)),
        (&SteelFactors::FIELDS[1], steel.conductivity_s_per_m),
    ];
    for (field, value) in values {
        let Some(value) = value else { continue };
        if !field.bounds.contains(value) {
            let unit = field.quantity.unit();
            p.error(field.path, format!("{value} must be in {}", field.bounds.describe(unit)));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_are_the_library_and_are_not_written() {
        assert!(FluidFactors::default().is_default());
        assert!(SteelFactors::default().is_default());
        let half = FluidFactors { fill_fraction: 0.5, ..FluidFactors::default() };
        assert!(!half.is_default());
    }

    #[test]
    fn out_of_range_factors_name_their_field_and_range() {
        let fluid = FluidFactors {
            fill_fraction: 1.2,
            yield_stress_scale: f64::NAN,
            ..FluidFactors::default()
        };
        let steel = SteelFactors { b_scale: 0.9, conductivity_s_per_m: Some(-1.0) };
        let mut p = Problems::default();
        check(&fluid, &steel, &mut p);
        let text = p.errors.to_string();
        assert_eq!(p.errors.len(), 3, "{text}");
        assert!(text.contains("fluid.fill_fraction") && text.contains("(0, 1]"), "{text}");
        assert!(text.contains("fluid.yield_stress_scale"), "{text}");
        assert!(text.contains("steel.conductivity_S_per_m"), "{text}");
    }
}
