//! Natural (free) convection from a device's outer surface to still air: empirical correlations
//! for the heat-transfer coefficient `h` as a function of the surface temperature, and the air
//! properties they need.
//!
//! All equations are from F. P. Incropera, D. P. DeWitt, T. L. Bergman and A. S. Lavine,
//! *Fundamentals of Heat and Mass Transfer*, 6th ed., Wiley 2007, chapter 9:
//! - the Rayleigh number `Ra_L = g β (T_s − T_∞) L³ / (ν α)` (eq. 9.25), with `β = 1/T_f` for an
//!   ideal gas and every property at the film temperature `T_f = (T_s + T_∞)/2`;
//! - a long horizontal cylinder of diameter `D`, Churchill and Chu (1975):
//!   `Nu_D = {0.60 + 0.387 Ra_D^(1/6) / [1 + (0.559/Pr)^(9/16)]^(8/27)}²`, `Ra_D ≤ 10¹²` (eq. 9.34);
//! - a vertical plate of height `L`, Churchill and Chu (1975), the whole laminar and turbulent
//!   range: `Nu_L = {0.825 + 0.387 Ra_L^(1/6) / [1 + (0.492/Pr)^(9/16)]^(8/27)}²` (eq. 9.26).
//!
//! [`horizontal_brake`] combines them for a cylindrical device with a horizontal axis: the lateral
//! surface as a horizontal cylinder, the two end faces as vertical plates of height `D`, and one
//! area-weighted mean `h` for the whole surface (the thermal model has one convection boundary; the
//! ends and the side differ by about 10 %, which the mean hides). Radiation is separate (a
//! radiation boundary with an emissivity).

use crate::HeatError;
use mrbrake_error::FieldError;

/// Standard gravity \[m/s²\] (CGPM 1901, exact).
pub const STANDARD_GRAVITY: f64 = 9.806_65;

/// Air at 1 atm (Incropera et al. 6th ed., Table A.4): `(T [K], ν [m²/s], k [W/(m·K)], α [m²/s])`,
/// interpolated linearly in T. Trust: medium (textbook table, values copied from the printed table,
/// not vendored as a file).
const AIR: [(f64, f64, f64, f64); 11] = [
    (200.0, 7.590e-6, 18.1e-3, 10.3e-6),
    (250.0, 11.44e-6, 22.3e-3, 15.9e-6),
    (300.0, 15.89e-6, 26.3e-3, 22.5e-6),
    (350.0, 20.92e-6, 30.0e-3, 29.9e-6),
    (400.0, 26.41e-6, 33.8e-3, 38.3e-6),
    (450.0, 32.39e-6, 37.3e-3, 47.2e-6),
    (500.0, 38.79e-6, 40.7e-3, 56.7e-6),
    (600.0, 52.69e-6, 46.9e-3, 76.9e-6),
    (700.0, 68.10e-6, 52.4e-3, 98.0e-6),
    (800.0, 84.93e-6, 57.3e-3, 120.0e-6),
    (1000.0, 121.9e-6, 66.7e-3, 168.0e-6),
];

/// The film temperatures the air table covers \[K\].
pub const AIR_TABLE_RANGE_K: [f64; 2] = [200.0, 1000.0];

/// Air properties at one temperature.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Air {
    /// Kinematic viscosity \[m²/s\].
    pub nu_m2_per_s: f64,
    /// Thermal conductivity \[W/(m·K)\].
    pub k_w_per_mk: f64,
    /// Thermal diffusivity \[m²/s\].
    pub alpha_m2_per_s: f64,
}

impl Air {
    /// Prandtl number `ν/α`.
    pub fn prandtl(&self) -> f64 {
        self.nu_m2_per_s / self.alpha_m2_per_s
    }
}

/// Air at `t_k` ([`AIR_TABLE_RANGE_K`], linear interpolation in Table A.4).
pub fn air(t_k: f64) -> Result<Air, HeatError> {
    let (lo, hi) = (AIR[0].0, AIR[AIR.len() - 1].0);
    if !(lo..=hi).contains(&t_k) {
        let celsius = |t: f64| t - crate::ZERO_CELSIUS_K;
        return Err(FieldError::new(
            "t_k",
            "natural convection: film temperature outside the air table",
        )
        .with_value(format!("{:.1} °C", celsius(t_k)))
        .with_allowed(format!("{:.0} to {:.0} °C", celsius(lo), celsius(hi)))
        .into());
    }
    let k = AIR.windows(2).position(|w| t_k <= w[1].0).unwrap_or(AIR.len() - 2);
    let (a, b) = (AIR[k], AIR[k + 1]);
    let f = (t_k - a.0) / (b.0 - a.0);
    let mix = |u: f64, v: f64| u + f * (v - u);
    Ok(Air { nu_m2_per_s: mix(a.1, b.1), k_w_per_mk: mix(a.2, b.2), alpha_m2_per_s: mix(a.3, b.3) })
}

/// The Rayleigh number (eq. 9.25) of length `l` at surface `t_s` and ambient `t_inf` (kelvin),
/// with the air at the film temperature.
pub fn rayleigh(l: f64, t_s: f64, t_inf: f64) -> Result<(f64, Air), HeatError> {
    let film = 0.5 * (t_s + t_inf);
    let a = air(film)?;
    let ra = STANDARD_GRAVITY / film * (t_s - t_inf).abs() * l.powi(3)
        / (a.nu_m2_per_s * a.alpha_m2_per_s);
    Ok((ra, a))
}

/// Churchill–Chu for a horizontal cylinder (eq. 9.34): `Nu_D`.
pub fn nusselt_horizontal_cylinder(ra_d: f64, pr: f64) -> f64 {
    let shape = (1.0 + (0.559 / pr).powf(9.0 / 16.0)).powf(8.0 / 27.0);
    (0.60 + 0.387 * ra_d.powf(1.0 / 6.0) / shape).powi(2)
}

/// Churchill–Chu for a vertical plate (eq. 9.26): `Nu_L`.
pub fn nusselt_vertical_plate(ra_l: f64, pr: f64) -> f64 {
    let shape = (1.0 + (0.492 / pr).powf(9.0 / 16.0)).powf(8.0 / 27.0);
    (0.825 + 0.387 * ra_l.powf(1.0 / 6.0) / shape).powi(2)
}

/// The natural-convection coefficients of a cylindrical device with a horizontal axis.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NaturalConvection {
    /// Lateral surface (horizontal cylinder, eq. 9.34) \[W/(m²·K)\].
    pub h_side_w_per_m2k: f64,
    /// End faces (vertical plates of height D, eq. 9.26) \[W/(m²·K)\].
    pub h_ends_w_per_m2k: f64,
    /// Area-weighted mean over side and ends \[W/(m²·K)\].
    pub h_mean_w_per_m2k: f64,
    /// Rayleigh number on the diameter.
    pub rayleigh_d: f64,
}

/// `h` of a cylinder of diameter `d` and length `length` (metres), axis horizontal, surface at
/// `t_s` in air at `t_inf` (kelvin; see the module docs). A surface at the ambient gets the limit
/// `ΔT → 0` of the correlations (conduction only).
pub fn horizontal_brake(
    d: f64,
    length: f64,
    t_s: f64,
    t_inf: f64,
) -> Result<NaturalConvection, HeatError> {
    let positive_finite = |v: f64| v.is_finite() && v > 0.0;
    if !(positive_finite(d) && positive_finite(length)) {
        let (field, value) = if positive_finite(d) { ("length", length) } else { ("d", d) };
        let e = FieldError::out_of_range(field, format!("{value} m"), "finite, > 0 m");
        return Err(e.into());
    }
    let (ra, a) = rayleigh(d, t_s, t_inf)?;
    let pr = a.prandtl();
    let h_side = nusselt_horizontal_cylinder(ra, pr) * a.k_w_per_mk / d;
    let h_ends = nusselt_vertical_plate(ra, pr) * a.k_w_per_mk / d;
    let (a_side, a_ends) = (std::f64::consts::PI * d * length, std::f64::consts::PI * d * d / 2.0);
    Ok(NaturalConvection {
        h_side_w_per_m2k: h_side,
        h_ends_w_per_m2k: h_ends,
        h_mean_w_per_m2k: (h_side * a_side + h_ends * a_ends) / (a_side + a_ends),
        rayleigh_d: ra,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Incropera et al. 6th ed., Example 9.3: a horizontal steam pipe, D = 0.1 m, surface 165 °C
    /// in quiescent air at 23 °C, properties at T_f = 367 K: Ra_D = 5.073·10⁶, Nu_D = 23.3,
    /// h = 7.29 W/(m²·K) (the interpolated table reproduces the example's properties).
    #[test]
    fn textbook_horizontal_pipe() {
        let (ts, tinf) = (438.15, 296.15);
        let (ra, a) = rayleigh(0.1, ts, tinf).unwrap();
        assert!((ra / 5.073e6 - 1.0).abs() < 0.01, "Ra_D = {ra}");
        let nu = nusselt_horizontal_cylinder(ra, a.prandtl());
        assert!((nu / 23.3 - 1.0).abs() < 0.015, "Nu_D = {nu}");
        let h = nu * a.k_w_per_mk / 0.1;
        assert!((h / 7.29 - 1.0).abs() < 0.015, "h = {h}");
    }

    /// The vertical-plate correlation at Ra = 10⁹, Pr = 0.7 (hand-evaluated: 122.6); without a
    /// temperature difference the limits 0.60² and 0.825².
    #[test]
    fn plate_and_limits() {
        let nu = nusselt_vertical_plate(1e9, 0.7);
        assert!((nu / 122.6 - 1.0).abs() < 2e-3, "{nu}");
        assert!((nusselt_horizontal_cylinder(0.0, 0.7) - 0.36).abs() < 1e-12);
        assert!((nusselt_vertical_plate(0.0, 0.7) - 0.825f64.powi(2)).abs() < 1e-12);
        assert!(air(1200.0).is_err() && air(150.0).is_err());
        assert!(horizontal_brake(0.0, 0.05, 350.0, 300.0).is_err());
    }
}
