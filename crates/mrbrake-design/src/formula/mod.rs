//! Closed-form models of the thesis (Karabulut 2017): Bingham-plastic brake torque for every
//! configuration, coil winding and current density, and the passivity condition of a sampled
//! virtual wall.
//!
//! Equation numbers refer to the thesis ("Development of MR-fluid based semi-active dampers to be used
//! in haptic devices", 2017). All inputs and outputs are SI (m, Pa, Pa·s, rad/s, A, N·m).
//!
//! The MR fluid is a Bingham plastic (3.3)/(3.4): `tau = tau_y(H) + eta * omega * r / g`, and the torque
//! of a sheared surface is `dT = r * tau * dA` (3.5). Integrating over the fluid surfaces gives:
//!
//! | configuration | yield torque | viscous torque at speed `omega` |
//! |---|---|---|
//! | single disc (3.6, 3.7) | `4 pi tau_y (R2^3 - R1^3) / 3` | `pi eta omega (R2^4 - R1^4) / g` |
//! | multi-disc, n discs (3.8) | `n` times the single disc | `n` times the single disc |
//! | drum (3.9) | `4 pi tau_y R^2 h` | `4 pi eta omega R^3 h / g` |
//! | multi-drum (4.4, 4.5) | `2 pi h tau_y sum_k R_k^2` | `2 pi h eta omega sum_k R_k^3 / g` |
//!
//! The laws of one sheared surface, which the configurations above and the finite-element analysis
//! ([`crate::analysis`]) both sum, are [`annulus_yield_torque`] and [`annulus_viscous_torque`] (an
//! annular face, as on a disc) and [`cylinder_yield_torque`] and [`cylinder_viscous_torque`] (a
//! cylindrical surface, as on a drum).
//!
//! A front end asks through a [`TorqueRequest`] ([`torque`]) or a [`CoilRequest`] ([`coil`]),
//! which hold every range rule of the arguments (the CLI's `formula` commands and the Python
//! `mrbrake.formula` functions only translate theirs).
//!
//! ```
//! use mrbrake_design::formula::{single_disc, Viscous};
//! let t = single_disc(0.0225, 0.0275, 24_315.0, None).unwrap();
//! assert!((t.total_nm - 0.958).abs() < 5e-4); // thesis 4.2.3: 0.958 N·m
//! ```

use std::f64::consts::PI;

use mrbrake_error::FieldError;
use mrbrake_materials::CopperWire;
use serde::Serialize;

use crate::DesignError;

mod request;

pub use request::{
    ClosedFormBrake, ClosedFormCoil, ClosedFormTorque, CoilRequest, DEFAULT_COIL_CURRENT_A,
    DEFAULT_COIL_INNER_RADIUS_M, DEFAULT_COPPER_TEMPERATURE_C, DEFAULT_FLUID, FluidSource,
    MAX_FLUX_DENSITY_T, TorqueRequest, WireChoice, YieldStress, coil, rating_warning,
    surface_radii, torque, turns_warning,
};

/// The viscous (Newtonian) part of the Bingham model (3.4): fluid viscosity, relative speed and gap.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Viscous {
    /// Off-state (Newtonian) viscosity eta (Pa·s).
    pub eta_pa_s: f64,
    /// Relative angular speed omega between the rotating and static surfaces (rad/s).
    pub omega_rad_s: f64,
    /// Fluid gap g across which the fluid is sheared (m).
    pub gap_m: f64,
}

/// Brake torque split into its field-dependent (yield) and speed-dependent (viscous) parts.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct BrakeTorque {
    /// Torque from the yield stress alone (N·m).
    pub yield_nm: f64,
    /// Torque from viscous shear at the given speed (N·m) (0 when no speed was given).
    pub viscous_nm: f64,
    /// Sum of both (N·m).
    pub total_nm: f64,
}

impl BrakeTorque {
    fn new(yield_nm: f64, viscous_nm: f64) -> Self {
        Self { yield_nm, viscous_nm, total_nm: yield_nm + viscous_nm }
    }
}

/// `value` in `unit` (SI) when it is `ok`, else the field error of `field` (the argument's name,
/// `r1`), described as `what` (`inner disc radius`), with the value and `allowed` in `unit`.
fn checked(
    ok: bool,
    (field, what): (&str, &str),
    value: f64,
    unit: &str,
    allowed: &str,
) -> Result<f64, DesignError> {
    if ok {
        return Ok(value);
    }
    let with_unit = |text: String| if unit.is_empty() { text } else { format!("{text} {unit}") };
    let e = FieldError::new(field, what)
        .with_value(with_unit(value.to_string()))
        .with_allowed(with_unit(allowed.to_string()));
    Err(e.into())
}

/// Checks that `value` (in `unit`) is finite and strictly positive; the error names `field`
/// (the argument, e.g. `r2`) and what it is (`outer disc radius`).
pub(crate) fn positive(
    field: &str,
    what: &str,
    value: f64,
    unit: &str,
) -> Result<f64, DesignError> {
    checked(value.is_finite() && value > 0.0, (field, what), value, unit, "finite, > 0")
}

/// Checks that `value` (in `unit`) is finite and not negative; the error names `field` and what
/// it is.
pub(crate) fn non_negative(
    field: &str,
    what: &str,
    value: f64,
    unit: &str,
) -> Result<f64, DesignError> {
    checked(value.is_finite() && value >= 0.0, (field, what), value, unit, "finite, >= 0")
}

/// Checks that `value` (in `unit`) is finite; the error names `field` and what it is.
pub(crate) fn finite(field: &str, what: &str, value: f64, unit: &str) -> Result<f64, DesignError> {
    checked(value.is_finite(), (field, what), value, unit, "finite")
}

fn check_viscous(v: Option<Viscous>) -> Result<Option<Viscous>, DesignError> {
    if let Some(v) = v {
        non_negative("eta", "viscosity", v.eta_pa_s, "Pa·s")?;
        finite("speed", "relative speed", v.omega_rad_s, "rad/s")?;
        positive("gap", "fluid gap", v.gap_m, "m")?;
    }
    Ok(v)
}

fn check_radii(r1: f64, r2: f64) -> Result<(), DesignError> {
    non_negative("r1", "inner disc radius", r1, "m")?;
    positive("r2", "outer disc radius", r2, "m")?;
    if r2 <= r1 {
        let e = FieldError::new("r2", "the outer disc radius must be larger than the inner one")
            .with_value(format!("{r2} m"))
            .with_allowed(format!("> r1 = {r1} m"));
        return Err(e.into());
    }
    Ok(())
}

/// Yield torque of `faces` annular fluid faces between radii `r_inner_m` and `r_outer_m`, one face
/// of thesis (3.6)/(3.7) each: `faces · 2π τ_y (R2³ − R1³)/3` (`∫_{R1}^{R2} 2π r² τ_y dr` per face).
///
/// A disc shears two faces, so (3.7) is `faces = 2` and (3.8) `faces = 2n`. No input checks: the
/// configuration functions check theirs, the analysis takes radii from a validated geometry.
pub fn annulus_yield_torque(faces: f64, r_inner_m: f64, r_outer_m: f64, tau_y_pa: f64) -> f64 {
    faces * 2.0 * PI * tau_y_pa * (r_outer_m.powi(3) - r_inner_m.powi(3)) / 3.0
}

/// Viscous torque of `faces` annular fluid faces between radii `r_inner_m` and `r_outer_m`, the
/// viscous term of thesis (3.6) per face: `faces · π η ω (R2⁴ − R1⁴)/(2 g)`
/// (`∫_{R1}^{R2} 2π r³ η ω / g dr` per face, from (3.4)).
pub fn annulus_viscous_torque(
    faces: f64,
    r_inner_m: f64,
    r_outer_m: f64,
    viscous: &Viscous,
) -> f64 {
    faces * PI * viscous.eta_pa_s * viscous.omega_rad_s * (r_outer_m.powi(4) - r_inner_m.powi(4))
        / (2.0 * viscous.gap_m)
}

/// Yield torque of cylindrical fluid surfaces of height `h_m` sheared at radii `R_k`, thesis (4.4):
/// `2π h τ_y Σ_k R_k²`, from the sum of the squared radii (`R²` for one surface, (3.5) integrated
/// over the cylinder).
pub fn cylinder_yield_torque(h_m: f64, tau_y_pa: f64, sum_of_squared_radii_m2: f64) -> f64 {
    2.0 * PI * h_m * tau_y_pa * sum_of_squared_radii_m2
}

/// Viscous torque of one cylindrical fluid surface of radius `r_m` and height `h_m`, from (3.4):
/// `2π R³ h η ω / g` (the shear stress `η ω R / g` on the area `2π R h`, at arm `R`).
pub fn cylinder_viscous_torque(r_m: f64, h_m: f64, viscous: &Viscous) -> f64 {
    2.0 * PI * r_m.powi(3) * h_m * viscous.eta_pa_s * viscous.omega_rad_s / viscous.gap_m
}

/// Single-disc brake torque, thesis (3.6) with its viscous term and (3.7) without it.
///
/// `T = 2 ∫_{R1}^{R2} 2π (τ_y r² + η ω r³ / g) dr = 4π τ_y (R2³ − R1³)/3 + π η ω (R2⁴ − R1⁴)/g`:
/// the disc shears fluid on both faces (the factor 2).
pub fn single_disc(
    r1_m: f64,
    r2_m: f64,
    tau_y_pa: f64,
    viscous: Option<Viscous>,
) -> Result<BrakeTorque, DesignError> {
    multi_disc(1, r1_m, r2_m, tau_y_pa, viscous)
}

/// The most discs of a multi-disc brake, or fluid surfaces of a multi-drum brake, the formulas
/// accept: far beyond any brake that can be built (the thesis's designs have 1 to 4), and it keeps
/// a typo such as 100000000 from sizing a list of radii.
pub const MAX_SURFACES: u32 = 100;

/// Multi-disc brake torque with `n` rotating discs, thesis (3.8): `n` times the single disc (3.6).
pub fn multi_disc(
    n: u32,
    r1_m: f64,
    r2_m: f64,
    tau_y_pa: f64,
    viscous: Option<Viscous>,
) -> Result<BrakeTorque, DesignError> {
    if !(1..=MAX_SURFACES).contains(&n) {
        let e = FieldError::new("discs", "rotating discs of a multi-disc brake")
            .with_value(n)
            .with_allowed(format!("1 to {MAX_SURFACES}"));
        return Err(e.into());
    }
    check_radii(r1_m, r2_m)?;
    non_negative("tau_y", "yield stress", tau_y_pa, "Pa")?;
    let viscous = check_viscous(viscous)?;
    // Each disc shears fluid on both faces.
    let faces = 2.0 * f64::from(n);
    let yield_nm = annulus_yield_torque(faces, r1_m, r2_m, tau_y_pa);
    let viscous_nm = viscous.map_or(0.0, |v| annulus_viscous_torque(faces, r1_m, r2_m, &v));
    Ok(BrakeTorque::new(yield_nm, viscous_nm))
}

/// Drum brake torque, thesis (3.9): `T = 4π τ_y R² h` (fluid on both cylindrical faces of the drum,
/// both taken at radius R); viscous part `4π η ω R³ h / g` from (3.4) at the same radius.
pub fn drum(
    r_m: f64,
    h_m: f64,
    tau_y_pa: f64,
    viscous: Option<Viscous>,
) -> Result<BrakeTorque, DesignError> {
    positive("r", "drum radius", r_m, "m")?;
    positive("h", "drum height", h_m, "m")?;
    non_negative("tau_y", "yield stress", tau_y_pa, "Pa")?;
    let viscous = check_viscous(viscous)?;
    let yield_nm = 4.0 * PI * tau_y_pa * r_m * r_m * h_m;
    let viscous_nm = viscous
        .map_or(0.0, |v| 4.0 * PI * v.eta_pa_s * v.omega_rad_s * r_m.powi(3) * h_m / v.gap_m);
    Ok(BrakeTorque::new(yield_nm, viscous_nm))
}

/// Radii of the fluid surfaces of a multi-drum brake, thesis (4.5): `R_k = R_{k−1} + d + g`,
/// starting at `R_0`.
pub fn multi_drum_radii(r0_m: f64, d_m: f64, g_m: f64, surfaces: u32) -> Vec<f64> {
    (0..surfaces).map(|k| r0_m + f64::from(k) * (d_m + g_m)).collect()
}

/// Multi-drum brake torque, thesis (4.4): `T = 2π h τ_y Σ_k R_k²` over the fluid surfaces
/// `k = 0 … surfaces−1` with radii from (4.5); viscous part `2π h η ω Σ_k R_k³ / g` from (3.4).
///
/// The thesis's final design (R0 = 25 mm, h = 9 mm, d = 1 mm, g = 0.5 mm, four surfaces,
/// τ_y = 25.67 kPa) gives 4.33 N·m.
pub fn multi_drum(
    r0_m: f64,
    h_m: f64,
    d_m: f64,
    g_m: f64,
    surfaces: u32,
    tau_y_pa: f64,
    viscous_eta_omega: Option<(f64, f64)>,
) -> Result<BrakeTorque, DesignError> {
    positive("r0", "innermost fluid-surface radius", r0_m, "m")?;
    positive("h", "cylinder height", h_m, "m")?;
    positive("d", "cylinder thickness", d_m, "m")?;
    positive("g", "fluid gap", g_m, "m")?;
    non_negative("tau_y", "yield stress", tau_y_pa, "Pa")?;
    if !(1..=MAX_SURFACES).contains(&surfaces) {
        let e = FieldError::new(
            "surfaces",
            "fluid surfaces of a multi-drum brake (the thesis's final design has 4)",
        )
        .with_value(surfaces)
        .with_allowed(format!("1 to {MAX_SURFACES}"));
        return Err(e.into());
    }
    let viscous = check_viscous(viscous_eta_omega.map(|(eta_pa_s, omega_rad_s)| Viscous {
        eta_pa_s,
        omega_rad_s,
        gap_m: g_m,
    }))?;
    let radii = multi_drum_radii(r0_m, d_m, g_m, surfaces);
    let sum_r2: f64 = radii.iter().map(|r| r * r).sum();
    let sum_r3: f64 = radii.iter().map(|r| r * r * r).sum();
    let yield_nm = cylinder_yield_torque(h_m, tau_y_pa, sum_r2);
    let viscous_nm =
        viscous.map_or(0.0, |v| 2.0 * PI * h_m * v.eta_pa_s * v.omega_rad_s * sum_r3 / v.gap_m);
    Ok(BrakeTorque::new(yield_nm, viscous_nm))
}

/// Coil current density as the thesis defines it, (4.1): `J_D = I / (√3 d²)` (A/m²), the current
/// spread over the cell a wire of diameter `d` occupies in the winding (Figure 4.5).
///
/// 2 A in 0.5 mm wire gives 4.62 A/mm² (thesis 4.2.2). Note that the current density in the copper
/// itself is `I / (π d²/4)` ([`conductor_current_density`]), 10.2 A/mm² for the same wire.
pub fn current_density_thesis(current_a: f64, wire_diameter_m: f64) -> Result<f64, DesignError> {
    finite("current", "coil current", current_a, "A")?;
    positive("wire_diameter", "wire diameter", wire_diameter_m, "m")?;
    Ok(current_a.abs() / (3f64.sqrt() * wire_diameter_m * wire_diameter_m))
}

/// Current density in the copper cross-section, `I / (π d² / 4)` (A/m²).
pub fn conductor_current_density(current_a: f64, wire_diameter_m: f64) -> Result<f64, DesignError> {
    finite("current", "coil current", current_a, "A")?;
    positive("wire_diameter", "wire diameter", wire_diameter_m, "m")?;
    Ok(current_a.abs() / (PI * wire_diameter_m * wire_diameter_m / 4.0))
}

/// Turns that fit a winding window, thesis (4.2) and (4.3), for round wire in a staggered
/// (hexagonal) lay-up.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct WindowTurns {
    /// `i = ⌊(C_h − 2r)/(√3 r)⌋` (4.2): how many wire layers beyond the first fit the window height.
    pub layers_i: u32,
    /// `N_c = C_w/(2r)·(i + 1) − i/2` (4.3), before rounding.
    pub turns_exact: f64,
    /// `⌊N_c⌋`, the whole number of turns that fit.
    pub turns: u32,
}

/// Number of turns of wire of radius `wire_radius_m` in a `window_width_m × window_height_m`
/// window, thesis (4.2) and (4.3).
pub fn turns_in_window(
    window_width_m: f64,
    window_height_m: f64,
    wire_radius_m: f64,
) -> Result<WindowTurns, DesignError> {
    positive("window_width", "winding window width", window_width_m, "m")?;
    positive("window_height", "winding window height", window_height_m, "m")?;
    positive("wire_radius", "wire radius", wire_radius_m, "m")?;
    let r = wire_radius_m;
    for (field, side) in [("window_width", window_width_m), ("window_height", window_height_m)] {
        if side < 2.0 * r {
            let e = FieldError::new(
                field,
                format!(
                    "the winding window {:.3} mm × {:.3} mm is smaller than one wire",
                    window_width_m * 1e3,
                    window_height_m * 1e3,
                ),
            )
            .with_value(format!("{:.3} mm", side * 1e3))
            .with_allowed(format!(">= the wire diameter, {:.3} mm", 2.0 * r * 1e3));
            return Err(e.into());
        }
    }
    // (4.2): i ∈ Z+, the whole number of staggered layers; a tiny tolerance keeps exact fits exact.
    let i = ((window_height_m - 2.0 * r) / (3f64.sqrt() * r) + 1e-9).floor();
    let turns_exact = window_width_m / (2.0 * r) * (i + 1.0) - i / 2.0;
    Ok(WindowTurns { layers_i: i as u32, turns_exact, turns: (turns_exact + 1e-9).floor() as u32 })
}

/// The copper fill factor of a winding, `λ = N · π d²/4 / (C_w C_h)`: the bare copper area of
/// `turns` round wires of diameter `wire_diameter_m` over the window's area (the definition of the
/// winding trade, e.g. KUK Group, *Orthocyclic vs wild (random) winding*, mycoil.info: `F_u =
/// A_copper / A_window` with the bare conductor diameter). The thesis's turn formula (4.2), (4.3)
/// packs bare wires hexagonally and approaches π/√12 ≈ 0.907 in a large window; see
/// [`FILL_FACTOR_LIMIT`] for what a real winding reaches.
pub fn copper_fill_factor(
    turns: u32,
    wire_diameter_m: f64,
    window_width_m: f64,
    window_height_m: f64,
) -> f64 {
    f64::from(turns) * PI * wire_diameter_m * wire_diameter_m
        / 4.0
        / (window_width_m * window_height_m)
}

/// The largest copper fill factor a winding of round enamelled wire reaches in practice: 0.75,
/// the top of the 70–75 % an orthocyclic (layer-by-layer, in the grooves) winding achieves (KUK
/// Group coil-winding glossary, mycoil.info/glossary, "orthocyclic winding"); a wild (random)
/// winding reaches about 0.45–0.50 (same source). The geometric limit of hexagonally packed bare
/// wire, π/√12 ≈ 0.907, is not manufacturable: the enamel, the winding's crossovers and the
/// tolerances of wire and bobbin take the rest. A design above this limit gets a warning.
pub const FILL_FACTOR_LIMIT: f64 = 0.75;

/// Electrical figures of a coil of `turns` turns of round copper wire wound between two radii.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct CoilElectrics {
    /// Number of turns.
    pub turns: u32,
    /// Wire length `N · 2π r_mean` (m).
    pub wire_length_m: f64,
    /// Resistance at 20 °C (Ω).
    pub resistance_20c_ohm: f64,
    /// Resistance at the given temperature (Ω).
    pub resistance_ohm: f64,
    /// Current density by the thesis's definition (4.1) (A/mm²).
    pub current_density_a_per_mm2: f64,
    /// Current density in the copper (A/mm²).
    pub conductor_current_density_a_per_mm2: f64,
    /// Ohmic power `I² R` at the given current and temperature (W).
    pub power_w: f64,
    /// Supply voltage `I R` (V).
    pub voltage_v: f64,
}

/// Mean radius of a winding (m) that fills a window of radial width `window_width_m` from
/// `inner_radius_m`: the radius of the mean turn, whose length sets the wire length (4.1)–(4.3).
pub fn coil_mean_radius(inner_radius_m: f64, window_width_m: f64) -> f64 {
    inner_radius_m + window_width_m / 2.0
}

/// Wire length, resistance, current density and power of a coil (thesis 4.2.2, (4.1)).
///
/// `mean_radius_m` is the mean radius of the winding (each turn is a circle about the axis); the
/// wire's resistance is taken at `temperature_c` (copper temperature coefficient, see
/// [`CopperWire::resistance_ohm_per_m_at`]).
pub fn coil_electrics(
    turns: u32,
    mean_radius_m: f64,
    wire: &CopperWire,
    current_a: f64,
    temperature_c: f64,
) -> Result<CoilElectrics, DesignError> {
    if turns == 0 {
        return Err(FieldError::out_of_range("turns", turns, ">= 1").into());
    }
    positive("mean_radius", "coil mean radius", mean_radius_m, "m")?;
    let r_per_m = wire.resistance_ohm_per_m_at(temperature_c)?;
    let wire_length_m = f64::from(turns) * 2.0 * PI * mean_radius_m;
    let resistance_20c_ohm = wire_length_m * wire.resistance_ohm_per_m_20c;
    let resistance_ohm = wire_length_m * r_per_m;
    let j = current_density_thesis(current_a, wire.diameter_m)?;
    let jc = conductor_current_density(current_a, wire.diameter_m)?;
    Ok(CoilElectrics {
        turns,
        wire_length_m,
        resistance_20c_ohm,
        resistance_ohm,
        current_density_a_per_mm2: j * 1e-6,
        conductor_current_density_a_per_mm2: jc * 1e-6,
        power_w: current_a * current_a * resistance_ohm,
        voltage_v: current_a.abs() * resistance_ohm,
    })
}

/// Passivity of a sampled virtual wall (Colgate & Brown 1994), thesis (2.2)–(2.4):
/// the wall of stiffness `K` and damping `B` rendered with sample period `T` is passive when
/// `b + b_c > K T / 2 + B`, with `b` the device's physical damping and `b_c` a controllable
/// (e.g. MR) damping; (2.2) is the case `b_c = 0`, (2.4) the case `b_c = b_c(H)`.
pub fn wall_is_passive(
    physical_damping: f64,
    controllable_damping: f64,
    stiffness: f64,
    virtual_damping: f64,
    sample_period_s: f64,
) -> bool {
    physical_damping + controllable_damping > stiffness * sample_period_s / 2.0 + virtual_damping
}

/// The largest passive virtual stiffness, from (2.3): `K_max = 2 (b + b_c − B) / T` (0 if negative).
pub fn max_passive_stiffness(
    physical_damping: f64,
    controllable_damping: f64,
    virtual_damping: f64,
    sample_period_s: f64,
) -> f64 {
    (2.0 * (physical_damping + controllable_damping - virtual_damping) / sample_period_s).max(0.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rel(a: f64, b: f64) -> f64 {
        (a - b).abs() / b.abs()
    }

    #[test]
    fn single_disc_reference_0958() {
        let t = single_disc(22.5e-3, 27.5e-3, 24_315.0, None).unwrap();
        assert!((t.total_nm - 0.958).abs() < 5e-4, "{}", t.total_nm);
    }

    #[test]
    fn single_disc_viscous_term_matches_numerical_integral() {
        let v = Viscous { eta_pa_s: 0.056, omega_rad_s: 10.0, gap_m: 0.5e-3 };
        let t = single_disc(0.01, 0.03, 0.0, Some(v)).unwrap();
        // Midpoint rule of 2 ∫ 2π η ω r³ / g dr.
        let n = 20_000;
        let dr = 0.02 / n as f64;
        let num: f64 = (0..n)
            .map(|i| {
                let r = 0.01 + (i as f64 + 0.5) * dr;
                2.0 * 2.0 * PI * v.eta_pa_s * v.omega_rad_s * r.powi(3) / v.gap_m * dr
            })
            .sum();
        assert!(rel(t.viscous_nm, num) < 1e-8);
        assert!(t.yield_nm.abs() < 1e-15);
    }

    #[test]
    fn multi_drum_reference_433() {
        let t = multi_drum(25e-3, 9e-3, 1e-3, 0.5e-3, 4, 25_670.0, None).unwrap();
        assert!((t.total_nm - 4.33).abs() < 5e-3, "{}", t.total_nm);
        let radii = multi_drum_radii(25e-3, 1e-3, 0.5e-3, 4);
        assert!((radii[3] - 29.5e-3).abs() < 1e-12);
    }

    #[test]
    fn drum_is_two_surfaces_of_multi_drum() {
        let a = drum(0.025, 0.009, 1000.0, None).unwrap();
        // A drum with both faces at R equals two surfaces at the same radius (d + g = 0 limit).
        let b = 2.0 * multi_drum(0.025, 0.009, 1e-12, 1e-12, 1, 1000.0, None).unwrap().total_nm;
        assert!(rel(a.total_nm, b) < 1e-9);
    }

    /// The analysis summed its gaps, and `multi_disc` its discs, with these expressions before
    /// they called the per-surface laws; the laws give the same bits, so no result moved.
    #[test]
    fn per_surface_laws_reproduce_the_analysis_expressions_bit_for_bit() {
        for k in 0..200 {
            let x = f64::from(k);
            let (r0, r1, h, g) =
                (0.01 + 1e-4 * x, 0.02 + 3e-4 * x, 0.009 - 2e-5 * x, 5e-4 + 1e-6 * x);
            let (tau, eta, omega) = (1e3 + 157.0 * x, 0.05 + 1e-3 * x, -3.0 + 0.07 * x);
            let v = Viscous { eta_pa_s: eta, omega_rad_s: omega.abs(), gap_m: g };
            let pairs = [
                (
                    cylinder_viscous_torque(r1, h, &v),
                    2.0 * PI * r1.powi(3) * h * eta * omega.abs() / g,
                ),
                (
                    annulus_viscous_torque(1.0, r0, r1, &v),
                    PI * eta * omega.abs() * (r1.powi(4) - r0.powi(4)) / (2.0 * g),
                ),
                (cylinder_yield_torque(h, tau, r1.powi(2)), 2.0 * PI * h * tau * r1.powi(2)),
                (
                    annulus_yield_torque(1.0, r0, r1, tau),
                    2.0 * PI * tau * (r1.powi(3) - r0.powi(3)) / 3.0,
                ),
            ];
            // multi_disc summed n discs as `n · 4π …` and `n · π … / g` before it called the laws.
            let n = 1 + k % 9;
            let t = multi_disc(n, r0, r1, tau, Some(v)).unwrap();
            let n = f64::from(n);
            let discs = [
                (t.yield_nm, n * 4.0 * PI * tau * (r1.powi(3) - r0.powi(3)) / 3.0),
                (t.viscous_nm, n * PI * eta * omega.abs() * (r1.powi(4) - r0.powi(4)) / g),
            ];
            for (law, before) in pairs.into_iter().chain(discs) {
                assert_eq!(law.to_bits(), before.to_bits(), "{law:e} vs {before:e} at k = {k}");
            }
        }
    }

    /// (3.8) is 2n annular faces, (3.9) two cylindrical surfaces at R, (4.4) the sum over R_k.
    #[test]
    fn configurations_are_sums_of_the_per_surface_laws() {
        let v = Viscous { eta_pa_s: 0.11, omega_rad_s: 6.0, gap_m: 0.5e-3 };
        let discs = multi_disc(5, 0.012, 0.02, 24e3, Some(v)).unwrap();
        assert!(rel(discs.yield_nm, 10.0 * annulus_yield_torque(1.0, 0.012, 0.02, 24e3)) < 1e-14);
        assert!(rel(discs.viscous_nm, 10.0 * annulus_viscous_torque(1.0, 0.012, 0.02, &v)) < 1e-14);
        let one = drum(0.025, 0.009, 25e3, Some(v)).unwrap();
        assert!(rel(one.yield_nm, 2.0 * cylinder_yield_torque(0.009, 25e3, 0.025 * 0.025)) < 1e-14);
        assert!(rel(one.viscous_nm, 2.0 * cylinder_viscous_torque(0.025, 0.009, &v)) < 1e-14);
        let stack = multi_drum(25e-3, 9e-3, 1e-3, 0.5e-3, 4, 25.67e3, Some((0.11, 6.0))).unwrap();
        let radii = multi_drum_radii(25e-3, 1e-3, 0.5e-3, 4);
        let yield_sum: f64 =
            radii.iter().map(|&r| cylinder_yield_torque(9e-3, 25.67e3, r * r)).sum();
        let viscous_sum: f64 = radii.iter().map(|&r| cylinder_viscous_torque(r, 9e-3, &v)).sum();
        assert!(rel(stack.yield_nm, yield_sum) < 1e-14);
        assert!(rel(stack.viscous_nm, viscous_sum) < 1e-14);
    }

    #[test]
    fn thesis_current_density_462() {
        let j = current_density_thesis(2.0, 0.5e-3).unwrap() * 1e-6;
        assert!((j - 4.62).abs() < 5e-3, "{j}");
    }

    #[test]
    fn window_turns_counts_staggered_layers() {
        // Height fits exactly 2r + 2·√3 r: i = 2 layers beyond the first; width 10 wires.
        let r = 0.25e-3;
        let w = turns_in_window(10.0 * 2.0 * r, 2.0 * r + 2.0 * 3f64.sqrt() * r, r).unwrap();
        assert_eq!(w.layers_i, 2);
        assert!((w.turns_exact - 29.0).abs() < 1e-9);
        assert_eq!(w.turns, 29);
        assert!(turns_in_window(0.1e-3, 1e-3, r).is_err());
    }

    #[test]
    fn bad_radii_are_named() {
        let e = single_disc(0.03, 0.02, 1000.0, None).unwrap_err().to_string();
        assert!(e.contains("r2") && e.contains("r1"), "{e}");
        let e = single_disc(-0.01, 0.02, 1000.0, None).unwrap_err().to_string();
        assert!(e.contains("r1"), "{e}");
        assert!(drum(0.02, f64::NAN, 1.0, None).is_err());
    }

    #[test]
    fn passivity_boundary() {
        // b = 0.5, T = 1 ms, B = 0: K_max = 1000.
        assert!((max_passive_stiffness(0.5, 0.0, 0.0, 1e-3) - 1000.0).abs() < 1e-9);
        assert!(wall_is_passive(0.5, 0.0, 999.0, 0.0, 1e-3));
        assert!(!wall_is_passive(0.5, 0.0, 1001.0, 0.0, 1e-3));
        assert!(wall_is_passive(0.5, 0.1, 1100.0, 0.0, 1e-3));
    }

    #[test]
    fn coil_resistance_scales_with_temperature() {
        let wire = CopperWire::from_diameter(0.5e-3).unwrap();
        let c20 = coil_electrics(450, 0.02, &wire, 2.0, 20.0).unwrap();
        let c70 = coil_electrics(450, 0.02, &wire, 2.0, 70.0).unwrap();
        assert!(rel(c20.wire_length_m, 450.0 * 2.0 * PI * 0.02) < 1e-12);
        // R(T) = R20 (1 + α (T − 20 °C)) with α = 0.00393 /K for annealed copper.
        assert!(rel(c70.resistance_ohm, c20.resistance_ohm * (1.0 + 50.0 * 0.00393)) < 1e-9);
        assert!(rel(c20.power_w, 4.0 * c20.resistance_ohm) < 1e-12);
        assert!(coil_electrics(450, 0.02, &wire, 2.0, 1000.0).is_err());
    }
}
