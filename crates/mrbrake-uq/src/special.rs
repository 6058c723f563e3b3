//! The standard normal law to full double precision: density, CDF, survival function, quantile,
//! and the probability of an interval without cancellation.
//!
//! * CDF and survival function from the complementary error function,
//!   `Φ(z) = ½ erfc(−z/√2)`, `1 − Φ(z) = ½ erfc(z/√2)` (Abramowitz & Stegun 1964, §26.2),
//!   so both tails keep their relative accuracy far out (`erfc` of the `libm` crate, a port of
//!   FreeBSD's `s_erf.c`, error below 1 ulp).
//! * Quantile by Wichura's algorithm AS 241 (`PPND16`: M. J. Wichura, "The percentage points of the
//!   normal distribution", Applied Statistics 37(3), 477–484, 1988; relative error about 1e-16),
//!   then one Newton step on `Φ(z) = p` with the CDF above, so that `Φ(Φ⁻¹(p)) = p` holds to the
//!   CDF's own rounding.

use std::f64::consts::{FRAC_1_SQRT_2, PI};

/// The standard normal density `φ(z) = exp(−z²/2)/√(2π)`.
pub fn std_normal_pdf(z: f64) -> f64 {
    (-0.5 * z * z).exp() / (2.0 * PI).sqrt()
}

/// The standard normal CDF `Φ(z)` (accurate relative to itself in the lower tail).
pub fn std_normal_cdf(z: f64) -> f64 {
    0.5 * libm::erfc(-z * FRAC_1_SQRT_2)
}

/// The standard normal survival function `1 − Φ(z)` (accurate relative to itself in the upper
/// tail).
pub fn std_normal_sf(z: f64) -> f64 {
    0.5 * libm::erfc(z * FRAC_1_SQRT_2)
}

/// `Φ(β) − Φ(α)` for `α ≤ β`, computed from whichever tail avoids cancellation: survival functions
/// when the interval lies above 0, CDFs when it lies below, and `1 − Φ(α) − (1 − Φ(β))` when it
/// straddles 0 (then the mass is at least that of `[0, min(|α|, β)]`, never tiny).
pub fn std_normal_mass(alpha: f64, beta: f64) -> f64 {
    if alpha >= 0.0 {
        std_normal_sf(alpha) - std_normal_sf(beta)
    } else if beta <= 0.0 {
        std_normal_cdf(beta) - std_normal_cdf(alpha)
    } else {
        1.0 - std_normal_cdf(alpha) - std_normal_sf(beta)
    }
}

/// The standard normal quantile `Φ⁻¹(p)` for `p ∈ [0, 1]` (`−∞` at 0, `+∞` at 1; NaN for a `p`
/// outside, which callers exclude).
pub fn std_normal_quantile(p: f64) -> f64 {
    if p <= 0.0 {
        return if p < 0.0 { f64::NAN } else { f64::NEG_INFINITY };
    }
    if p >= 1.0 {
        return if p > 1.0 { f64::NAN } else { f64::INFINITY };
    }
    if p.is_nan() {
        return f64::NAN;
    }
    // Work in the lower half: for p > 1/2, 1 − p is exact (Sterbenz), and Φ⁻¹(p) = −Φ⁻¹(1 − p).
    let (q, sign) = if p > 0.5 { (1.0 - p, -1.0) } else { (p, 1.0) };
    let z = ppnd16(q);
    sign * newton_polish(z, q)
}

/// The standard normal upper quantile: `z` with `1 − Φ(z) = q` (`= −Φ⁻¹(q)`, accurate for tiny `q`).
pub fn std_normal_isf(q: f64) -> f64 {
    -std_normal_quantile(q)
}

/// One Newton step on `Φ(z) = q` for `z ≤ 0` (`q ≤ 1/2`), where `Φ` is accurate relative to itself.
/// Skipped where the density underflows (|z| > 37): AS 241 is already accurate there.
fn newton_polish(z: f64, q: f64) -> f64 {
    let density = std_normal_pdf(z);
    if density < 1e-290 {
        return z;
    }
    z - (std_normal_cdf(z) - q) / density
}

/// Wichura's AS 241 `PPND16` for `0 < p < 1`: rational approximations in `r = 0.180625 − (p − ½)²`
/// for `|p − ½| ≤ 0.425`, else in `r = √(−ln min(p, 1 − p))`, split at `r = 5`; coefficients as
/// published (Wichura 1988, Table/Algorithm listing).
// The coefficients keep all the published digits (more than an f64 holds) so the transcription
// can be checked against the paper digit by digit.
#[allow(clippy::excessive_precision)]
fn ppnd16(p: f64) -> f64 {
    const A: [f64; 8] = [
        3.387_132_872_796_366_608,
        1.331_416_678_917_843_774_5e2,
        1.971_590_950_306_551_442_7e3,
        1.373_169_376_550_946_112_5e4,
        4.592_195_393_154_987_145_7e4,
        6.726_577_092_700_870_085_3e4,
        3.343_057_558_358_812_810_5e4,
        2.509_080_928_730_122_672_7e3,
    ];
    const B: [f64; 8] = [
        1.0,
        4.231_333_070_160_091_125_2e1,
        6.871_870_074_920_579_083e2,
        5.394_196_021_424_751_107_7e3,
        2.121_379_430_158_659_586_7e4,
        3.930_789_580_009_271_061e4,
        2.872_908_573_572_194_267_4e4,
        5.226_495_278_852_854_561e3,
    ];
    const C: [f64; 8] = [
        1.423_437_110_749_683_577_34,
        4.630_337_846_156_545_295_9,
        5.769_497_221_460_691_405_5,
        3.647_848_324_763_204_605_04,
        1.270_458_252_452_368_382_58,
        2.417_807_251_774_506_117_7e-1,
        2.272_384_498_926_918_458_33e-2,
        7.745_450_142_783_414_076_4e-4,
    ];
    const D: [f64; 8] = [
        1.0,
        2.053_191_626_637_758_821_87,
        1.676_384_830_183_803_849_4,
        6.897_673_349_851_000_045_5e-1,
        1.481_039_764_274_800_745_9e-1,
        1.519_866_656_361_645_719_66e-2,
        5.475_938_084_995_344_946e-4,
        1.050_750_071_644_416_843_24e-9,
    ];
    const E: [f64; 8] = [
        6.657_904_643_501_103_777_2,
        5.463_784_911_164_114_369_9,
        1.784_826_539_917_291_335_8,
        2.965_605_718_285_048_912_3e-1,
        2.653_218_952_657_612_309_3e-2,
        1.242_660_947_388_078_438_6e-3,
        2.711_555_568_743_487_578_15e-5,
        2.010_334_399_292_288_132_65e-7,
    ];
    const F: [f64; 8] = [
        1.0,
        5.998_322_065_558_879_376_9e-1,
        1.369_298_809_227_358_053_1e-1,
        1.487_536_129_085_061_485_25e-2,
        7.868_691_311_456_132_591e-4,
        1.846_318_317_510_054_681_8e-5,
        1.421_511_758_316_445_888_7e-7,
        2.044_263_103_389_939_785_64e-15,
    ];
    let q = p - 0.5;
    if q.abs() <= 0.425 {
        let r = 0.180_625 - q * q;
        return q * horner(&A, r) / horner(&B, r);
    }
    let tail = if q < 0.0 { p } else { 1.0 - p };
    let r = (-tail.ln()).sqrt();
    let z = if r <= 5.0 {
        let s = r - 1.6;
        horner(&C, s) / horner(&D, s)
    } else {
        let s = r - 5.0;
        horner(&E, s) / horner(&F, s)
    };
    if q < 0.0 { -z } else { z }
}

/// `Σ c_k x^k` by Horner's rule (coefficients in ascending powers).
fn horner(coefficients: &[f64], x: f64) -> f64 {
    coefficients.iter().rev().fold(0.0, |acc, &c| acc * x + c)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn known_quantiles() {
        // Reference values: mpmath (50 digits) roots of ncdf(z) = p for the double nearest each p
        // (0.999999999 is 1 − 1.00000008e-9 as a double, hence not Φ⁻¹(1 − 1e-9)).
        let cases = [
            (0.5, 0.0),
            (0.975, 1.959_963_984_540_054),
            (0.95, 1.644_853_626_951_472_7),
            (0.05, -1.644_853_626_951_472_7),
            (0.841_344_746_068_542_9, 1.0),
            (1e-10, -6.361_340_902_404_056),
            (1e-300, -37.047_096_299_361_2),
            (0.999_999_999, 5.997_807_019_601_637),
        ];
        for (p, z) in cases {
            let got = std_normal_quantile(p);
            assert!((got - z).abs() <= 1e-13 * (1.0 + z.abs()), "p = {p}: {got} vs {z}");
        }
        assert!(std_normal_quantile(0.0).is_infinite() && std_normal_quantile(0.0) < 0.0);
        assert!(std_normal_quantile(1.0).is_infinite() && std_normal_quantile(1.0) > 0.0);
        assert!(std_normal_quantile(1.5).is_nan() && std_normal_quantile(f64::NAN).is_nan());
    }

    #[test]
    fn cdf_known_values_and_tails() {
        assert!((std_normal_cdf(1.959_963_984_540_054) - 0.975).abs() < 1e-15);
        // Φ(−10) = 7.619853024160526e-24 (mpmath), kept to full relative precision.
        assert!((std_normal_cdf(-10.0) / 7.619_853_024_160_526e-24 - 1.0).abs() < 1e-13);
        assert!((std_normal_sf(10.0) / 7.619_853_024_160_526e-24 - 1.0).abs() < 1e-13);
        let mass = std_normal_mass(8.0, 9.0);
        let expected = std_normal_sf(8.0) - std_normal_sf(9.0);
        assert!(mass > 0.0 && (mass / expected - 1.0).abs() < 1e-14);
    }
}
