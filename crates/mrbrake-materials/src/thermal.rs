//! Thermal properties: conductivity, density and specific heat of the library's materials, and the
//! homogenised winding.
//!
//! * [`thermal`] — the properties of a built-in material by name (the names of [`crate::library`]
//!   plus `impregnation-resin`), vendored in `data/thermal_properties.csv` with source and trust
//!   per row (`data/SOURCES.md`, section 5). Values are at room temperature (300 K); mrbrake uses
//!   them as constants.
//! * [`fluid_viscosity_at`] — the off-state viscosity of an MR fluid at a temperature (module
//!   section "Viscosity and temperature" below).
//! * [`Winding`] — a coil of round copper wire with an insulating matrix (enamel and impregnating
//!   resin, or air) as one homogeneous, anisotropic material:
//!   - across the wires (the r–z plane of an axisymmetric coil, whose wires run azimuthally), the
//!     Hashin–Shtrikman lower bound for a two-phase composite of parallel cylinders in a matrix,
//!     `k⊥ = k_m [(1 + λ) k_c + (1 − λ) k_m] / [(1 − λ) k_c + (1 + λ) k_m]` (Z. Hashin and
//!     S. Shtrikman, J. Appl. Phys. 33 (1962) 3125, eq. (22) in 2D form; identical to Rayleigh's
//!     first-order result for a square array of cylinders, Lord Rayleigh, Phil. Mag. 34 (1892)
//!     481, and to the Maxwell-Garnett formula), with `λ` the copper fill factor. For a conductor
//!     far better than its matrix it reduces to `k_m (1 + λ)/(1 − λ)`. Simpson, Wrobel and Mellor
//!     (IEEE Trans. Ind. Appl. 49(6) 2013, 2505–2515) compare it with measured windings;
//!   - with layer insulation (a sheet of thickness fraction `t` of the layer pitch between
//!     radial layers), the radial conductivity is the series combination
//!     `1/k_r = (1 − t)/k⊥ + t/k_sheet`; the axial one stays `k⊥`;
//!   - along the wires (azimuthal: no conduction in an axisymmetric model, reported for
//!     completeness), the rule of mixtures `k∥ = λ k_c + (1 − λ) k_m`;
//!   - heat capacity per volume by the rule of mixtures, `ρc = λ ρ_c c_c + (1 − λ) ρ_m c_m`.
//!
//! # Viscosity and temperature
//!
//! The off-state viscosity of an MR fluid follows its carrier liquid; the particles' magnetic
//! properties, and so the yield stress, change little over the working range (the review in
//! J. Mater. Sci. 57 (2022), doi:10.1007/s10853-022-08044-4, introduction and its eq. (1)). The
//! carrier is modelled by Andrade's (Arrhenius-type) law `η(T) = η_ref exp[B (1/T − 1/T_ref)]`
//! (E. N. da C. Andrade, Nature 125 (1930) 309; T in kelvin), with the activation temperature
//! `B = E_a/R`:
//! - from the fluid's own two viscosities when the library has them at two temperatures (MRF-132DG:
//!   0.156 Pa·s at 30 °C and 0.112 Pa·s at 40 °C give `B` ≈ 3150 K, i.e. `E_a` ≈ 26 kJ/mol, in the
//!   usual range of light hydrocarbon oils);
//! - otherwise from the reference fluid [`VISCOSITY_REFERENCE_FLUID`] (same hydrocarbon carrier
//!   family, the suspension's relative viscosity taken independent of temperature).
//!
//! Trust is **low**: the two MRF-132DG values come from different sources with no shear rate
//! stated, and a two-point fit extrapolated to 100 °C or more is an estimate, not data. Replace it
//! with a datasheet curve when one is available.

use std::sync::OnceLock;

use serde::Serialize;

use crate::{MaterialError, MrFluid, Provenance, Trust};

const THERMAL_CSV: &str = include_str!("../data/thermal_properties.csv");
const THERMAL_FILE: &str = "data/thermal_properties.csv";

/// Header of `data/thermal_properties.csv`.
pub const THERMAL_HEADER: &str = "name,k_W_per_mK,rho_kg_per_m3,c_J_per_kgK,trust,source";

/// Thermal conductivity, density and specific heat of an isotropic material.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ThermalProperties {
    /// Library name (lower case).
    pub name: String,
    /// Thermal conductivity \[W/(m·K)\].
    pub k_w_per_mk: f64,
    /// Density \[kg/m³\].
    pub rho_kg_per_m3: f64,
    /// Specific heat capacity \[J/(kg·K)\].
    pub c_j_per_kgk: f64,
    /// Where the numbers come from.
    pub provenance: Provenance,
}

impl ThermalProperties {
    /// Heat capacity per volume `ρ c` \[J/(m³·K)\].
    pub fn volumetric_heat_capacity(&self) -> f64 {
        self.rho_kg_per_m3 * self.c_j_per_kgk
    }
}

fn trust_of(word: &str) -> Option<Trust> {
    Some(match word {
        "low" => Trust::Low,
        "medium-low" => Trust::MediumLow,
        "medium" => Trust::Medium,
        "medium-high" => Trust::MediumHigh,
        "high" => Trust::High,
        _ => return None,
    })
}

/// One data line `name,k,rho,c,trust,"source"` (the source may be quoted and contain commas).
fn parse_line(line: &str, number: u64) -> Result<ThermalProperties, MaterialError> {
    let bad =
        |message: String| MaterialError::Parse { file: THERMAL_FILE.into(), line: number, message };
    let fields: Vec<&str> = line.splitn(6, ',').collect();
    if fields.len() != 6 {
        return Err(bad(format!("expected 6 fields ({THERMAL_HEADER})")));
    }
    let value =
        |k: usize| -> Result<f64, MaterialError> {
            fields[k].trim().parse::<f64>().ok().filter(|v| v.is_finite() && *v > 0.0).ok_or_else(
                || bad(format!("field {} = `{}` must be a number > 0", k + 1, fields[k])),
            )
        };
    let trust = trust_of(fields[4].trim())
        .ok_or_else(|| bad(format!("trust `{}` is not a trust level", fields[4])))?;
    Ok(ThermalProperties {
        name: fields[0].trim().to_ascii_lowercase(),
        k_w_per_mk: value(1)?,
        rho_kg_per_m3: value(2)?,
        c_j_per_kgk: value(3)?,
        provenance: Provenance::new(
            fields[5].trim().trim_matches('"'),
            "copied (room-temperature value, used as a constant)",
            trust,
        ),
    })
}

fn parse_table() -> Result<Vec<ThermalProperties>, MaterialError> {
    let mut lines = THERMAL_CSV.lines().enumerate();
    match lines.next() {
        Some((_, header)) if header.trim() == THERMAL_HEADER => {}
        _ => {
            return Err(MaterialError::Parse {
                file: THERMAL_FILE.into(),
                line: 1,
                message: format!("expected the header `{THERMAL_HEADER}`"),
            });
        }
    }
    lines.filter(|(_, l)| !l.trim().is_empty()).map(|(k, l)| parse_line(l, k as u64 + 1)).collect()
}

fn table() -> Result<&'static [ThermalProperties], MaterialError> {
    static TABLE: OnceLock<Result<Vec<ThermalProperties>, MaterialError>> = OnceLock::new();
    TABLE
        .get_or_init(|| parse_table().map_err(MaterialError::builtin))
        .as_deref()
        .map_err(Clone::clone)
}

/// Every material with built-in thermal data, in table order.
pub fn thermal_names() -> Result<Vec<&'static str>, MaterialError> {
    Ok(table()?.iter().map(|p| p.name.as_str()).collect())
}

/// The thermal properties of the built-in material `name` (case-insensitive); an unknown name
/// lists the materials with thermal data.
pub fn thermal(name: &str) -> Result<&'static ThermalProperties, MaterialError> {
    let wanted = name.trim().to_ascii_lowercase();
    let rows = table()?;
    rows.iter().find(|p| p.name == wanted).ok_or_else(|| MaterialError::UnknownMaterial {
        name: name.to_string(),
        known: rows.iter().map(|p| p.name.clone()).collect(),
    })
}

/// The Hashin–Shtrikman lower bound (Rayleigh, Maxwell-Garnett) for the conductivity across
/// parallel cylinders of conductivity `k_c` filling the fraction `fill` of a matrix `k_m` (see the
/// module docs).
pub fn transverse_conductivity(fill: f64, k_c: f64, k_m: f64) -> f64 {
    k_m * ((1.0 + fill) * k_c + (1.0 - fill) * k_m) / ((1.0 - fill) * k_c + (1.0 + fill) * k_m)
}

/// A winding: copper fill factor and the insulating matrix between the wires.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Winding {
    /// Copper area fraction of the winding cross-section (0 < λ < π/4·… in practice ≤ 0.9).
    pub fill_factor: f64,
    /// Conductivity of the matrix (enamel + resin, or air) \[W/(m·K)\].
    pub matrix_k_w_per_mk: f64,
    /// Heat capacity per volume of the matrix \[J/(m³·K)\].
    pub matrix_rho_c: f64,
    /// Layer insulation: thickness as a fraction of the layer pitch and its conductivity, or none.
    pub layer_sheet: Option<(f64, f64)>,
}

/// The homogenised properties of a [`Winding`].
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct WindingProperties {
    /// Radial conductivity \[W/(m·K)\].
    pub k_radial_w_per_mk: f64,
    /// Axial conductivity \[W/(m·K)\].
    pub k_axial_w_per_mk: f64,
    /// Conductivity along the wires (azimuthal) \[W/(m·K)\].
    pub k_along_wire_w_per_mk: f64,
    /// Heat capacity per volume \[J/(m³·K)\].
    pub rho_c: f64,
}

impl Winding {
    /// A winding in impregnating resin (the library's `impregnation-resin`), no layer sheets.
    pub fn impregnated(fill_factor: f64) -> Result<Self, MaterialError> {
        let resin = thermal("impregnation-resin")?;
        Ok(Self {
            fill_factor,
            matrix_k_w_per_mk: resin.k_w_per_mk,
            matrix_rho_c: resin.volumetric_heat_capacity(),
            layer_sheet: None,
        })
    }

    /// The homogenised properties (module docs). Fails for a fill factor outside (0, 0.95), a
    /// non-positive matrix conductivity or heat capacity, or a layer fraction outside [0, 1).
    pub fn properties(&self) -> Result<WindingProperties, MaterialError> {
        let out = |quantity: &str, value: f64, allowed: &str| MaterialError::OutOfRange {
            quantity: quantity.into(),
            value,
            allowed: allowed.into(),
        };
        let fill = self.fill_factor;
        if !(fill > 0.0 && fill < 0.95) {
            return Err(out("winding fill factor", fill, "0 < fill < 0.95"));
        }
        if !(self.matrix_k_w_per_mk > 0.0 && self.matrix_k_w_per_mk.is_finite()) {
            return Err(out("winding matrix conductivity", self.matrix_k_w_per_mk, "> 0 W/(m K)"));
        }
        if !(self.matrix_rho_c > 0.0 && self.matrix_rho_c.is_finite()) {
            return Err(out("winding matrix heat capacity", self.matrix_rho_c, "> 0 J/(m3 K)"));
        }
        let copper = thermal("copper")?;
        let k_c = copper.k_w_per_mk;
        let k_t = transverse_conductivity(fill, k_c, self.matrix_k_w_per_mk);
        let k_radial = match self.layer_sheet {
            None => k_t,
            Some((t, k_sheet)) => {
                if !(0.0..1.0).contains(&t) || k_sheet <= 0.0 {
                    return Err(out("layer sheet fraction", t, "0 <= t < 1 with k_sheet > 0"));
                }
                1.0 / ((1.0 - t) / k_t + t / k_sheet)
            }
        };
        Ok(WindingProperties {
            k_radial_w_per_mk: k_radial,
            k_axial_w_per_mk: k_t,
            k_along_wire_w_per_mk: fill * k_c + (1.0 - fill) * self.matrix_k_w_per_mk,
            rho_c: fill * copper.volumetric_heat_capacity() + (1.0 - fill) * self.matrix_rho_c,
        })
    }
}

/// The library fluid whose two viscosities give the carrier's activation temperature for fluids
/// known at one temperature only (module docs, "Viscosity and temperature").
pub const VISCOSITY_REFERENCE_FLUID: &str = "mrf-132dg";

/// 0 °C in kelvin.
const ZERO_CELSIUS_K: f64 = 273.15;

/// An off-state viscosity at a temperature, with the law's constant and where it comes from.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ViscosityAtTemperature {
    /// Viscosity \[Pa·s\].
    #[serde(rename = "viscosity_Pa_s")]
    pub pa_s: f64,
    /// Temperature \[°C\].
    #[serde(rename = "temperature_C")]
    pub temperature_c: f64,
    /// Activation temperature `B = E_a/R` of Andrade's law \[K\].
    #[serde(rename = "activation_temperature_K")]
    pub activation_temperature_k: f64,
    /// How far the temperature lies outside the temperatures of the viscosities the law was
    /// fitted to \[K\] (0 inside them): the law is an extrapolation there.
    #[serde(rename = "extrapolated_K")]
    pub extrapolated_k: f64,
    /// Where `B` and the reference viscosity come from.
    pub provenance: Provenance,
}

/// `B = ln(η1/η2) / (1/T1 − 1/T2)` through the first two viscosities of `fluid` at distinct
/// temperatures, if it has them.
fn two_point_activation(fluid: &MrFluid) -> Option<f64> {
    let v = &fluid.viscosities;
    let first = v.first()?;
    let second = v.iter().find(|w| (w.temperature_c - first.temperature_c).abs() > 1e-6)?;
    let (t1, t2) = (first.temperature_c + ZERO_CELSIUS_K, second.temperature_c + ZERO_CELSIUS_K);
    let b = (first.pa_s / second.pa_s).ln() / (1.0 / t1 - 1.0 / t2);
    (b.is_finite() && b > 0.0).then_some(b)
}

/// The off-state viscosity of `fluid` at `temperature_c` by Andrade's law through its first
/// (30 °C) viscosity (module docs, "Viscosity and temperature"). The law is evaluated wherever it
/// is defined (above absolute zero, up to 1000 °C); how far it is extrapolated is in the result.
pub fn fluid_viscosity_at(
    fluid: &MrFluid,
    temperature_c: f64,
) -> Result<ViscosityAtTemperature, MaterialError> {
    if !(temperature_c > -ZERO_CELSIUS_K && temperature_c <= 1000.0) {
        return Err(MaterialError::OutOfRange {
            quantity: "fluid temperature (°C)".into(),
            value: temperature_c,
            allowed: "above -273.15 °C, at most 1000 °C".into(),
        });
    }
    let reference = fluid.viscosities.first().ok_or_else(|| MaterialError::OutOfRange {
        quantity: format!("viscosities listed for {}", fluid.name()),
        value: 0.0,
        allowed: "at least one".into(),
    })?;
    let (b, source, data) = match two_point_activation(fluid) {
        Some(b) => {
            (b, format!("two-point Andrade fit through {}'s own viscosities", fluid.name()), fluid)
        }
        None => {
            let donor = crate::library::fluid(VISCOSITY_REFERENCE_FLUID)?;
            let b = two_point_activation(donor).ok_or_else(|| MaterialError::MissingRow {
                file: "data/mrf_properties.csv".into(),
                row: format!("{VISCOSITY_REFERENCE_FLUID} at a second temperature"),
            })?;
            let source = format!(
                "Andrade's law with the activation temperature of {VISCOSITY_REFERENCE_FLUID}'s two \
                 viscosities (same hydrocarbon carrier family) through {}'s {} °C value",
                fluid.name(),
                reference.temperature_c
            );
            (b, source, donor)
        }
    };
    let temperatures = data.viscosities.iter().chain(&fluid.viscosities).map(|v| v.temperature_c);
    let (lo, hi) =
        temperatures.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), t| (a.min(t), b.max(t)));
    let extrapolated_k = (lo - temperature_c).max(temperature_c - hi).max(0.0);
    let (t, t_ref) = (temperature_c + ZERO_CELSIUS_K, reference.temperature_c + ZERO_CELSIUS_K);
    Ok(ViscosityAtTemperature {
        pa_s: reference.pa_s * (b * (1.0 / t - 1.0 / t_ref)).exp(),
        temperature_c,
        activation_temperature_k: b,
        extrapolated_k,
        provenance: Provenance::new(
            "E. N. da C. Andrade, Nature 125 (1930) 309; viscosities of data/mrf_properties.csv",
            source,
            Trust::Low,
        ),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_row_parses_and_every_library_material_has_thermal_data() {
        let names = thermal_names().unwrap();
        for (name, _) in crate::library::names() {
            assert!(names.contains(&name), "{name} has no thermal data");
        }
        let steel = thermal("Steel-1008").unwrap();
        assert!((steel.k_w_per_mk - 63.9).abs() < 1e-12);
        assert!((steel.volumetric_heat_capacity() - 7832.0 * 434.0).abs() < 1e-6);
        assert!(matches!(thermal("unobtainium"), Err(MaterialError::UnknownMaterial { .. })));
    }

    /// The bound lies between the series and parallel (Wiener) bounds, equals the matrix at
    /// λ → 0, and tends to `k_m (1 + λ)/(1 − λ)` for a perfect conductor.
    #[test]
    fn transverse_conductivity_bounds_and_limits() {
        let (k_c, k_m) = (401.0, 0.2);
        for fill in [0.1, 0.4, 0.6, 0.8] {
            let k = transverse_conductivity(fill, k_c, k_m);
            let series = 1.0 / (fill / k_c + (1.0 - fill) / k_m);
            let parallel = fill * k_c + (1.0 - fill) * k_m;
            assert!(k > series && k < parallel, "{fill}: {series} < {k} < {parallel}");
            let perfect = k_m * (1.0 + fill) / (1.0 - fill);
            assert!((k - perfect).abs() / perfect < 1e-2, "{fill}: {k} vs {perfect}");
        }
        assert!((transverse_conductivity(1e-12, k_c, k_m) - k_m).abs() < 1e-9);
    }

    #[test]
    fn winding_properties_and_layer_sheets() {
        let plain = Winding::impregnated(0.6).unwrap().properties().unwrap();
        assert!((plain.k_radial_w_per_mk - plain.k_axial_w_per_mk).abs() < 1e-12);
        // 0.2 · 1.6/0.4 = 0.8 W/(m K) for a perfect conductor; copper gives slightly less.
        assert!(plain.k_axial_w_per_mk > 0.79 && plain.k_axial_w_per_mk < 0.8);
        assert!(plain.k_along_wire_w_per_mk > 240.0);
        let sheets =
            Winding { layer_sheet: Some((0.1, 0.15)), ..Winding::impregnated(0.6).unwrap() };
        let layered = sheets.properties().unwrap();
        assert!(layered.k_radial_w_per_mk < plain.k_radial_w_per_mk);
        assert!(Winding::impregnated(0.99).unwrap().properties().is_err());
    }

    /// MRF-132DG's law passes through both of its library viscosities; MRF-122EG's through its
    /// 30 °C value with the same activation temperature; viscosity falls with temperature.
    #[test]
    fn andrade_law_through_the_library_viscosities() {
        let f132 = crate::library::fluid("mrf-132dg").unwrap();
        let at30 = fluid_viscosity_at(f132, 30.0).unwrap();
        let at40 = fluid_viscosity_at(f132, 40.0).unwrap();
        assert!((at30.pa_s - 0.156).abs() < 1e-12 && (at40.pa_s - 0.112).abs() < 1e-12);
        assert!((at30.activation_temperature_k - 3146.0).abs() < 5.0, "{at30:?}");
        let f122 = crate::library::fluid("mrf-122eg").unwrap();
        let cold = fluid_viscosity_at(f122, 30.0).unwrap();
        let hot = fluid_viscosity_at(f122, 100.0).unwrap();
        assert!((cold.pa_s - f122.viscosity_pa_s()).abs() < 1e-12);
        assert!((hot.activation_temperature_k - at30.activation_temperature_k).abs() < 1e-9);
        assert!(hot.pa_s < 0.2 * cold.pa_s && hot.pa_s > 0.05 * cold.pa_s, "{hot:?}");
        assert_eq!(hot.provenance.trust, Trust::Low);
        assert!((hot.extrapolated_k - 60.0).abs() < 1e-12 && cold.extrapolated_k.abs() < 1e-12);
        assert!(fluid_viscosity_at(f122, -300.0).is_err());
    }
}
