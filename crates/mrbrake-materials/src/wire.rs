//! Round copper magnet wire: by AWG gauge (18–32, vendored table) or by bare diameter.
//!
//! * AWG diameter (ASTM B258): `d = 0.127 mm · 92^((36 − n)/39)`.
//! * Resistance per metre at 20 °C: `R' = ρ20 / A`, `A = π d²/4`, with `ρ20 = 1/58 Ω·mm²/m`
//!   (58 MS/m, 100 % IACS: the International Annealed Copper Standard, IEC 60028:1925).
//! * At another temperature: `R'(T) = R'20 · (1 + α20 (T − 20 °C))` with `α20 = 0.00393 /K`, the
//!   temperature coefficient of IACS annealed copper at 20 °C (IEC 60028:1925; same value in
//!   ASTM B193). The linear law is used within −50…200 °C, the range of magnet-wire insulation classes.
//!
//! The values are for **bare** copper; enamel adds to the outer diameter (not included). The thesis's
//! Table 4.6 current ratings (AWG 20–26, its source not named) are attached for reference only.

use std::sync::OnceLock;

use serde::Serialize;

use crate::{MaterialError, Provenance, Trust};

/// Resistivity of IACS annealed copper at 20 °C \[Ω·m\] (IEC 60028:1925: 1/58 Ω·mm²/m).
pub const COPPER_RESISTIVITY_20C_OHM_M: f64 = 1.0 / 58.0e6;

/// Temperature coefficient of resistance of IACS annealed copper at 20 °C \[1/K\] (IEC 60028:1925).
pub const COPPER_TEMPERATURE_COEFFICIENT_PER_K: f64 = 0.00393;

/// Smallest and largest AWG gauge in the vendored table.
pub const AWG_RANGE: std::ops::RangeInclusive<u32> = 18..=32;

/// Temperatures \[°C\] where the linear resistance law is used.
pub const TEMPERATURE_RANGE_C: std::ops::RangeInclusive<f64> = -50.0..=200.0;

const AWG_CSV: &str = include_str!("../data/awg_copper_18_32.csv");
const AWG_FILE: &str = "data/awg_copper_18_32.csv";

/// Current ratings from the thesis's Table 4.6 (AWG, A); the thesis does not name their source.
const THESIS_TABLE_4_6_RATINGS_A: [(u32, f64); 7] =
    [(20, 7.5), (21, 6.3), (22, 5.0), (23, 3.5), (24, 2.1), (25, 1.7), (26, 1.3)];

/// One row of the vendored AWG table (`data/awg_copper_18_32.csv`).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct AwgRow {
    /// Gauge number.
    pub awg: u32,
    /// Diameter from the AWG definition \[m\].
    pub d_m: f64,
    /// Area `π d²/4` \[m²\].
    pub a_m2: f64,
    /// `ρ20/A` \[Ω/m\].
    pub r_ohm_per_m_20c: f64,
    /// Diameter FEMM stores for the even gauges \[m\].
    pub d_femm_m: Option<f64>,
    /// Diameter copied from a public AWG table \[m\].
    pub d_table_m: f64,
    /// Area copied from the same table \[m²\].
    pub a_table_m2: f64,
    /// Resistance copied from the same table \[Ω/m\].
    pub r_table_ohm_per_m: f64,
}

/// A round bare copper wire.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CopperWire {
    /// AWG gauge, when the wire was chosen by gauge.
    pub awg: Option<u32>,
    /// Bare diameter \[m\].
    pub diameter_m: f64,
    /// Conductor cross-section \[m²\].
    pub area_m2: f64,
    /// Resistance per metre at 20 °C \[Ω/m\].
    pub resistance_ohm_per_m_20c: f64,
    /// Current rating from the thesis's Table 4.6 \[A\] (AWG 20–26 only; unsourced there: low trust).
    pub thesis_current_rating_a: Option<f64>,
}

impl CopperWire {
    /// The wire of gauge `awg` (18–32) from the vendored table.
    pub fn awg(awg: u32) -> Result<Self, MaterialError> {
        let row = awg_table()?.iter().find(|r| r.awg == awg).ok_or_else(|| {
            MaterialError::OutOfRange {
                quantity: "AWG gauge".to_string(),
                value: f64::from(awg),
                allowed: format!(
                    "{}..={} (the vendored table)",
                    AWG_RANGE.start(),
                    AWG_RANGE.end()
                ),
            }
        })?;
        Ok(Self {
            awg: Some(awg),
            diameter_m: row.d_m,
            area_m2: row.a_m2,
            resistance_ohm_per_m_20c: row.r_ohm_per_m_20c,
            thesis_current_rating_a: thesis_current_rating_a(awg),
        })
    }

    /// A wire of bare diameter `diameter_m` (0 < d ≤ 10 mm).
    pub fn from_diameter(diameter_m: f64) -> Result<Self, MaterialError> {
        if !(diameter_m.is_finite() && diameter_m > 0.0 && diameter_m <= 0.01) {
            return Err(MaterialError::OutOfRange {
                quantity: "wire diameter [m]".to_string(),
                value: diameter_m,
                allowed: "0 < d <= 0.01 m".to_string(),
            });
        }
        let area_m2 = std::f64::consts::PI * diameter_m * diameter_m / 4.0;
        Ok(Self {
            awg: None,
            diameter_m,
            area_m2,
            resistance_ohm_per_m_20c: COPPER_RESISTIVITY_20C_OHM_M / area_m2,
            thesis_current_rating_a: None,
        })
    }

    /// Resistance per metre \[Ω/m\] at `temperature_c` \[°C\]: `R'20 (1 + α20 (T − 20))`.
    pub fn resistance_ohm_per_m_at(&self, temperature_c: f64) -> Result<f64, MaterialError> {
        if !TEMPERATURE_RANGE_C.contains(&temperature_c) {
            return Err(MaterialError::OutOfRange {
                quantity: "copper temperature [°C]".to_string(),
                value: temperature_c,
                allowed: format!(
                    "{}..={} °C (where the linear resistance law is used)",
                    TEMPERATURE_RANGE_C.start(),
                    TEMPERATURE_RANGE_C.end()
                ),
            });
        }
        Ok(self.resistance_ohm_per_m_20c
            * (1.0 + COPPER_TEMPERATURE_COEFFICIENT_PER_K * (temperature_c - 20.0)))
    }

    /// The AWG gauge (18–32) whose diameter is nearest to this wire's, on a log scale.
    pub fn nearest_awg(&self) -> Option<u32> {
        AWG_RANGE.min_by(|&a, &b| {
            let da = (awg_diameter_m(a) / self.diameter_m).ln().abs();
            let db = (awg_diameter_m(b) / self.diameter_m).ln().abs();
            da.total_cmp(&db)
        })
    }

    /// Provenance of the wire data.
    pub fn provenance() -> Provenance {
        Provenance::new(
            "AWG definition (ASTM B258) with IACS copper, rho20 = 1/58e6 Ohm.m (IEC 60028); \
             vendored table data/awg_copper_18_32.csv, cross-checked with FEMM matlib WireD and a public \
             AWG table (R within 0.03 %)",
            "computed from the definition; temperature law R'20 (1 + 0.00393 (T - 20))",
            Trust::High,
        )
    }
}

/// AWG diameter by definition (ASTM B258): `0.127 mm · 92^((36 − n)/39)` \[m\].
pub fn awg_diameter_m(awg: u32) -> f64 {
    0.127e-3 * 92f64.powf((36.0 - f64::from(awg)) / 39.0)
}

/// The thesis's Table 4.6 current rating \[A\] for AWG 20–26 (the thesis does not name its source).
pub fn thesis_current_rating_a(awg: u32) -> Option<f64> {
    THESIS_TABLE_4_6_RATINGS_A.iter().find(|r| r.0 == awg).map(|r| r.1)
}

/// The vendored AWG 18–32 table, parsed once.
pub fn awg_table() -> Result<&'static [AwgRow], MaterialError> {
    static TABLE: OnceLock<Result<Vec<AwgRow>, MaterialError>> = OnceLock::new();
    TABLE
        .get_or_init(|| parse_awg_table(AWG_CSV, AWG_FILE).map_err(MaterialError::builtin))
        .as_deref()
        .map_err(Clone::clone)
}

fn parse_awg_table(text: &str, file: &str) -> Result<Vec<AwgRow>, MaterialError> {
    const HEADER: [&str; 8] = [
        "AWG",
        "d_m",
        "A_m2",
        "R_ohm_per_m_20C",
        "d_femm_m",
        "d_table_m",
        "A_table_m2",
        "R_table_ohm_per_m",
    ];
    crate::table::read_rows(text, file, &HEADER)?
        .into_iter()
        .map(|row| {
            let awg = row.text(0).parse::<u32>().map_err(|_| MaterialError::Parse {
                file: file.to_string(),
                line: row.line,
                message: format!("field `AWG` is `{}`, which is not a whole number", row.text(0)),
            })?;
            Ok(AwgRow {
                awg,
                d_m: row.number(1, HEADER[1], file)?,
                a_m2: row.number(2, HEADER[2], file)?,
                r_ohm_per_m_20c: row.number(3, HEADER[3], file)?,
                d_femm_m: row.optional_number(4, HEADER[4], file)?,
                d_table_m: row.number(5, HEADER[5], file)?,
                a_table_m2: row.number(6, HEADER[6], file)?,
                r_table_ohm_per_m: row.number(7, HEADER[7], file)?,
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use mrbrake_error::Kind as _;

    #[test]
    fn awg_24_matches_the_table_and_the_thesis() {
        let w = CopperWire::awg(24).unwrap();
        // Vendored CSV: 0.0842151 Ω/m; thesis Table 4.6: 84.22 mΩ/m, 0.511 mm, 2.1 A.
        assert!((w.resistance_ohm_per_m_20c - 0.0842151).abs() < 1e-9);
        assert!((w.resistance_ohm_per_m_20c / 0.08422 - 1.0).abs() < 1e-3);
        assert!((w.diameter_m - 0.511e-3).abs() < 0.001e-3);
        assert_eq!(w.thesis_current_rating_a, Some(2.1));
    }

    #[test]
    fn table_is_consistent_with_the_definition() {
        for row in awg_table().unwrap() {
            let d = awg_diameter_m(row.awg);
            assert!((row.d_m / d - 1.0).abs() < 1e-5, "AWG {}", row.awg);
            let by_diameter = CopperWire::from_diameter(row.d_m).unwrap();
            assert!(
                (by_diameter.resistance_ohm_per_m_20c / row.r_ohm_per_m_20c - 1.0).abs() < 1e-5
            );
            assert!(
                (row.r_table_ohm_per_m / row.r_ohm_per_m_20c - 1.0).abs() < 3e-4,
                "AWG {}",
                row.awg
            );
            assert_eq!(by_diameter.nearest_awg(), Some(row.awg));
        }
        assert_eq!(awg_table().unwrap().len(), 15);
    }

    #[test]
    fn thesis_table_4_6_resistances_agree() {
        // Thesis Table 4.6, mΩ/m.
        for (awg, r_mohm) in [
            (20, 33.31),
            (21, 42.00),
            (22, 52.96),
            (23, 66.79),
            (24, 84.22),
            (25, 106.2),
            (26, 133.9),
        ] {
            let w = CopperWire::awg(awg).unwrap();
            assert!((w.resistance_ohm_per_m_20c * 1e3 / r_mohm - 1.0).abs() < 1e-3, "AWG {awg}");
        }
    }

    #[test]
    fn temperature_law_and_ranges() {
        let w = CopperWire::awg(24).unwrap();
        let hot = w.resistance_ohm_per_m_at(120.0).unwrap();
        assert!((hot / w.resistance_ohm_per_m_20c - 1.393).abs() < 1e-12);
        assert!(w.resistance_ohm_per_m_at(500.0).unwrap_err().is_input_error());
        assert!(CopperWire::awg(40).unwrap_err().to_string().contains("18..=32"));
        assert!(CopperWire::from_diameter(-1e-3).is_err());
        assert!(CopperWire::from_diameter(f64::NAN).is_err());
        // The thesis's 0.5 mm wire is closest to AWG 24.
        assert_eq!(CopperWire::from_diameter(0.5e-3).unwrap().nearest_awg(), Some(24));
    }
}
