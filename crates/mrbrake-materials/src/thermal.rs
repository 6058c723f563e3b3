//! Thermal properties: conductivity, density and specific heat of the library's materials, and the
//! homogenised winding.
//!
//! * [`thermal`] — the properties of a built-in material by name (the names of [`crate::library`]
//!   plus `impregnation-resin`), vendored in `data/thermal_properties.csv` with source and trust
//!   per row (`data/SOURCES.md`, section 5). Values are at room temperature (300 K); mrbrake uses
//!   them as constants.
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

use std::sync::OnceLock;

use serde::Serialize;

use crate::{MaterialError, Provenance, Trust};

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
}
