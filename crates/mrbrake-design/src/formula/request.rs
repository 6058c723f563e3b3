//! Closed-form requests: what a front end asks of the thesis's models (a brake's torque, a coil in
//! a winding window), with every range rule of their arguments, so the CLI's `formula` commands
//! and the Python `mrbrake.formula` functions only translate their arguments.
//!
//! Brief overview: a [`TorqueRequest`] names a [`ClosedFormBrake`] (discs, drum or multi-drum
//! with its dimensions), where the yield stress comes from (given, or the fluid's τ_y(B) curve
//! at a flux density), and the optional viscous term (speed, viscosity, gap); [`torque`] checks
//! it and answers a [`ClosedFormTorque`] (the torque split, the yield stress and viscosity with
//! their sources). A [`CoilRequest`] (window, wire, turns, current, temperature) answers a
//! [`ClosedFormCoil`] from [`coil`], with the warnings a designer should see (more turns than fit,
//! a current above the wire's rating).

use mrbrake_error::FieldError;
use mrbrake_materials::{CopperWire, MrFluid, library};

use super::{
    BrakeTorque, CoilElectrics, Viscous, WindowTurns, coil_electrics, coil_mean_radius, drum,
    multi_disc, multi_drum, multi_drum_radii, turns_in_window,
};
use crate::DesignError;

/// The fluid of a closed-form torque when none is named: the thesis's MRF-122EG (LORD).
pub const DEFAULT_FLUID: &str = "mrf-122eg";

/// The highest mean flux density (T) at which a fluid's τ_y(B) curve is read: beyond every
/// fluid's saturation (the library's curves end below 2 T).
pub const MAX_FLUX_DENSITY_T: f64 = 3.0;

/// A brake of the closed-form models, with its dimensions (m).
#[derive(Debug, Clone, PartialEq)]
pub enum ClosedFormBrake {
    /// `discs` rotating discs sheared on both faces between radii `r1_m` and `r2_m`: the single
    /// disc (3.6)/(3.7) for one, the multi-disc brake (3.8) for more.
    Discs {
        /// Number of rotating discs n.
        discs: u32,
        /// Inner radius R1 of the fluid annulus (m).
        r1_m: f64,
        /// Outer radius R2 of the fluid annulus (m).
        r2_m: f64,
    },
    /// The drum brake (3.9): both fluid faces at radius `r_m`, height `h_m`.
    Drum {
        /// Drum radius R (m).
        r_m: f64,
        /// Drum height h (m).
        h_m: f64,
    },
    /// The multi-drum brake (4.4)/(4.5): `surfaces` cylindrical fluid surfaces from `r0_m`,
    /// `R_k = R_(k−1) + d + g`.
    MultiDrum {
        /// Radius R0 of the innermost fluid surface (m).
        r0_m: f64,
        /// Cylinder height h (m).
        h_m: f64,
        /// Cylinder wall thickness d (m).
        d_m: f64,
        /// Fluid gap g (m), also the gap of the viscous term.
        g_m: f64,
        /// Number of fluid surfaces.
        surfaces: u32,
    },
}

impl ClosedFormBrake {
    /// The configuration's name (`single-disc`, `multi-disc`, `drum`, `multi-drum`).
    pub fn name(&self) -> &'static str {
        match self {
            Self::Discs { discs: 1, .. } => "single-disc",
            Self::Discs { .. } => "multi-disc",
            Self::Drum { .. } => "drum",
            Self::MultiDrum { .. } => "multi-drum",
        }
    }

    /// The thesis's equation numbers of the configuration.
    pub fn equation(&self) -> &'static str {
        match self {
            Self::Discs { discs: 1, .. } => "(3.6)/(3.7)",
            Self::Discs { .. } => "(3.8)",
            Self::Drum { .. } => "(3.9)",
            Self::MultiDrum { .. } => "(4.4)/(4.5)",
        }
    }
}

/// Where a closed-form torque's yield stress comes from.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum YieldStress {
    /// τ_y given directly (Pa).
    Given(f64),
    /// τ_y read from the fluid's τ_y(B) curve at this mean flux density (T).
    AtFluxDensity(f64),
}

/// The torque of a brake by the closed-form models: what to compute, as a front end was asked.
#[derive(Debug, Clone, PartialEq)]
pub struct TorqueRequest {
    /// The brake and its dimensions.
    pub brake: ClosedFormBrake,
    /// The yield stress τ_y (Pa), if given; exactly one of it and `b_t`.
    pub tau_y_pa: Option<f64>,
    /// The mean flux density in the fluid (T) to read τ_y from the fluid's curve, in
    /// `[0, MAX_FLUX_DENSITY_T]`.
    pub b_t: Option<f64>,
    /// The MR fluid of the τ_y(B) curve and of the default viscosity; `None`: [`DEFAULT_FLUID`].
    pub fluid: Option<String>,
    /// Relative speed of the viscous term (rad/s); `None`: the yield torque alone.
    pub speed_rad_s: Option<f64>,
    /// Newtonian viscosity of the viscous term (Pa·s), ≥ 0; `None`: the fluid's off-state
    /// viscosity.
    pub eta_pa_s: Option<f64>,
    /// The fluid gap sheared at the speed (m), needed with a speed by discs and drums (the
    /// multi-drum brake's gap is its `g_m`).
    pub gap_m: Option<f64>,
}

/// Where the yield stress (and the viscosity of the viscous term) of a closed-form torque came
/// from.
#[derive(Debug, Clone, PartialEq)]
pub struct FluidSource {
    /// Yield stress τ_y (Pa).
    pub tau_y_pa: f64,
    /// Its origin: `"given"`, or the fluid's τ_y(B) curve at a flux density.
    pub tau_y_source: String,
    /// The flux density τ_y was read at (T); `None` when τ_y was given.
    pub b_t: Option<f64>,
    /// The fluid whose curve and viscosity were used.
    pub fluid: String,
    /// Origin of the viscosity: `"given"` or the fluid's off-state viscosity.
    pub eta_source: String,
}

impl FluidSource {
    /// The yield stress of `fluid` (given, or from its τ_y(B) curve) and its source, with the
    /// viscosity of the viscous term (Pa·s): `eta_pa_s` when given, else the fluid's off-state
    /// viscosity. No range checks ([`torque`] makes them).
    pub fn resolve(
        fluid: &MrFluid,
        yield_stress: YieldStress,
        eta_pa_s: Option<f64>,
    ) -> (Self, f64) {
        let (tau_y_pa, tau_y_source, b_t) = match yield_stress {
            YieldStress::Given(tau) => (tau, "given".to_string(), None),
            YieldStress::AtFluxDensity(b) => {
                (fluid.tau_y_of_b(b), format!("{} tau_y(B) at {b} T", fluid.name()), Some(b))
            }
        };
        let (eta, eta_source) = match eta_pa_s {
            Some(eta) => (eta, "given".to_string()),
            None => (fluid.viscosity_pa_s(), format!("{} off-state viscosity", fluid.name())),
        };
        let source =
            Self { tau_y_pa, tau_y_source, b_t, fluid: fluid.name().to_string(), eta_source };
        (source, eta)
    }
}

/// The answer to a [`TorqueRequest`].
#[derive(Debug, Clone, PartialEq)]
pub struct ClosedFormTorque {
    /// The brake asked about.
    pub brake: ClosedFormBrake,
    /// The yield stress and the viscosity with their sources.
    pub fluid: FluidSource,
    /// The viscous term's inputs, when a speed was given.
    pub viscous: Option<Viscous>,
    /// The torque split.
    pub torque: BrakeTorque,
}

/// The yield stress a request names: exactly one of `tau_y_pa` (≥ 0) and `b_t` (in
/// `[0, MAX_FLUX_DENSITY_T]`).
fn yield_stress(request: &TorqueRequest) -> Result<YieldStress, DesignError> {
    match (request.tau_y_pa, request.b_t) {
        (Some(_), Some(_)) => Err(FieldError::new("b", "give tau_y or b, not both").into()),
        (Some(tau), None) => {
            super::non_negative("tau_y", "yield stress", tau, "Pa").map(YieldStress::Given)
        }
        (None, Some(b)) if (0.0..=MAX_FLUX_DENSITY_T).contains(&b) => {
            Ok(YieldStress::AtFluxDensity(b))
        }
        (None, Some(b)) => Err(FieldError::new("b", "mean flux density in the fluid")
            .with_value(format!("{b} T"))
            .with_allowed(format!("between 0 T and {MAX_FLUX_DENSITY_T} T"))
            .into()),
        (None, None) => Err(FieldError::new(
            "tau_y",
            "give tau_y or b: the yield stress (e.g. 24.315kPa), or the mean flux density in the \
             fluid (e.g. 0.46T) to read it from the fluid's τ_y(B) curve",
        )
        .into()),
    }
}

/// Answers a closed-form torque request: the rules of every argument (the yield stress given
/// once and in range, a viscosity ≥ 0 even when no speed uses it, a finite speed, a gap with a
/// speed), then the configuration's formula with its own checks of the dimensions.
pub fn torque(request: &TorqueRequest) -> Result<ClosedFormTorque, DesignError> {
    let fluid = library::fluid(request.fluid.as_deref().unwrap_or(DEFAULT_FLUID))?;
    let yield_stress = yield_stress(request)?;
    if let Some(eta) = request.eta_pa_s {
        super::non_negative("eta", "viscosity", eta, "Pa·s")?;
    }
    if let Some(speed) = request.speed_rad_s {
        super::finite("speed", "relative speed", speed, "rad/s")?;
    }
    let (source, eta_pa_s) = FluidSource::resolve(fluid, yield_stress, request.eta_pa_s);
    let tau = source.tau_y_pa;
    let viscous_at = |gap_m: Option<f64>| -> Result<Option<Viscous>, DesignError> {
        let Some(omega_rad_s) = request.speed_rad_s else { return Ok(None) };
        let gap_m = gap_m.ok_or_else(|| {
            FieldError::new("gap", "speed needs gap (the fluid gap sheared at that speed)")
        })?;
        Ok(Some(Viscous { eta_pa_s, omega_rad_s, gap_m }))
    };
    let (viscous, torque) = match request.brake {
        ClosedFormBrake::Discs { discs, r1_m, r2_m } => {
            let viscous = viscous_at(request.gap_m)?;
            (viscous, multi_disc(discs, r1_m, r2_m, tau, viscous)?)
        }
        ClosedFormBrake::Drum { r_m, h_m } => {
            let viscous = viscous_at(request.gap_m)?;
            (viscous, drum(r_m, h_m, tau, viscous)?)
        }
        ClosedFormBrake::MultiDrum { r0_m, h_m, d_m, g_m, surfaces } => {
            let viscous = viscous_at(Some(g_m))?;
            let eta_omega = viscous.map(|v| (v.eta_pa_s, v.omega_rad_s));
            (viscous, multi_drum(r0_m, h_m, d_m, g_m, surfaces, tau, eta_omega)?)
        }
    };
    Ok(ClosedFormTorque { brake: request.brake.clone(), fluid: source, viscous, torque })
}

/// The radii of a multi-drum brake's fluid surfaces (4.5), for its report; empty for other
/// brakes.
pub fn surface_radii(brake: &ClosedFormBrake) -> Vec<f64> {
    match *brake {
        ClosedFormBrake::MultiDrum { r0_m, d_m, g_m, surfaces, .. } => {
            multi_drum_radii(r0_m, d_m, g_m, surfaces)
        }
        _ => Vec::new(),
    }
}

/// The wire of a coil: an AWG gauge or a bare diameter.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum WireChoice {
    /// An AWG gauge (18–32, the library's table).
    Awg(u32),
    /// A bare copper diameter (m).
    Diameter(f64),
}

/// The default inner radius of a coil's winding (m): the shaft radius of the thesis's Table 4.5,
/// where the concept design winds the coil directly on the shaft.
pub const DEFAULT_COIL_INNER_RADIUS_M: f64 = 5e-3;

/// The default coil current (A): the thesis's design current.
pub const DEFAULT_COIL_CURRENT_A: f64 = 2.0;

/// The default copper temperature (°C) of a coil's resistance.
pub const DEFAULT_COPPER_TEMPERATURE_C: f64 = 20.0;

/// A coil in a winding window, as a front end was asked.
#[derive(Debug, Clone, PartialEq)]
pub struct CoilRequest {
    /// Radial width C_w of the window (m).
    pub window_width_m: f64,
    /// Axial height C_h of the window (m).
    pub window_height_m: f64,
    /// The wire; `None` is an error naming both ways to give it.
    pub wire: Option<WireChoice>,
    /// Inner radius of the winding (m); `None`: [`DEFAULT_COIL_INNER_RADIUS_M`].
    pub inner_radius_m: Option<f64>,
    /// Turns; `None`: as many as fit the window by (4.2)/(4.3).
    pub turns: Option<u32>,
    /// Coil current (A); `None`: [`DEFAULT_COIL_CURRENT_A`].
    pub current_a: Option<f64>,
    /// Copper temperature (°C); `None`: [`DEFAULT_COPPER_TEMPERATURE_C`].
    pub temperature_c: Option<f64>,
}

/// The answer to a [`CoilRequest`].
#[derive(Debug, Clone, PartialEq)]
pub struct ClosedFormCoil {
    /// Radial width C_w of the window (m).
    pub window_width_m: f64,
    /// Axial height C_h of the window (m).
    pub window_height_m: f64,
    /// Inner radius of the winding (m).
    pub inner_radius_m: f64,
    /// The wire.
    pub wire: CopperWire,
    /// Coil current (A).
    pub current_a: f64,
    /// Copper temperature (°C).
    pub temperature_c: f64,
    /// Turns that fit the window.
    pub window: WindowTurns,
    /// Turns used.
    pub turns: u32,
    /// Mean radius of the winding (m).
    pub mean_radius_m: f64,
    /// Wire length, resistance, current density, power.
    pub electrics: CoilElectrics,
    /// What a designer should know: more turns than fit the window, a current above the wire's
    /// rating.
    pub warnings: Vec<String>,
}

/// Answers a coil request: the wire, the turns that fit the window (4.2)/(4.3) (or the given
/// ones), and the electrical figures (4.1) at the current and temperature.
pub fn coil(request: &CoilRequest) -> Result<ClosedFormCoil, DesignError> {
    let (cw, ch) = (request.window_width_m, request.window_height_m);
    let wire = match request.wire {
        Some(WireChoice::Awg(awg)) => CopperWire::awg(awg)?,
        Some(WireChoice::Diameter(d)) => CopperWire::from_diameter(d)?,
        None => {
            let e = FieldError::new(
                "awg",
                "give the wire: awg (a gauge, 18-32) or wire_diameter (bare copper)",
            );
            return Err(e.into());
        }
    };
    let window = turns_in_window(cw, ch, wire.diameter_m / 2.0)?;
    let turns = request.turns.unwrap_or(window.turns);
    let inner = request.inner_radius_m.unwrap_or(DEFAULT_COIL_INNER_RADIUS_M);
    super::non_negative("inner_radius", "inner radius of the winding", inner, "m")?;
    let current_a = request.current_a.unwrap_or(DEFAULT_COIL_CURRENT_A);
    let temperature_c = request.temperature_c.unwrap_or(DEFAULT_COPPER_TEMPERATURE_C);
    let mean_radius_m = coil_mean_radius(inner, cw);
    let electrics = coil_electrics(turns, mean_radius_m, &wire, current_a, temperature_c)?;
    let warnings =
        turns_warning(turns, &window).into_iter().chain(rating_warning(&wire, current_a));
    Ok(ClosedFormCoil {
        window_width_m: cw,
        window_height_m: ch,
        inner_radius_m: inner,
        wire,
        current_a,
        temperature_c,
        window,
        turns,
        mean_radius_m,
        electrics,
        warnings: warnings.collect(),
    })
}

/// The warning for more turns than fit the window by (4.2)/(4.3), if there are.
pub fn turns_warning(turns: u32, window: &WindowTurns) -> Option<String> {
    (turns > window.turns).then(|| {
        format!(
            "{turns} turns do not fit the window by (4.2)/(4.3) (at most {} turns)",
            window.turns
        )
    })
}

/// The warning for a current above the wire's rating (thesis Table 4.6), if it is.
pub fn rating_warning(wire: &CopperWire, current_a: f64) -> Option<String> {
    wire.thesis_current_rating_a.filter(|&limit| current_a > limit).map(|limit| {
        format!("{current_a} A exceeds the wire's rating of {limit} A (thesis Table 4.6)")
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn disc(tau_y_pa: Option<f64>, b_t: Option<f64>) -> TorqueRequest {
        TorqueRequest {
            brake: ClosedFormBrake::Discs { discs: 1, r1_m: 0.0225, r2_m: 0.0275 },
            tau_y_pa,
            b_t,
            fluid: None,
            speed_rad_s: None,
            eta_pa_s: None,
            gap_m: None,
        }
    }

    fn input_error(request: &TorqueRequest) -> String {
        let e = torque(request).unwrap_err();
        assert!(mrbrake_error::Kind::is_input_error(&e), "{e}");
        e.to_string()
    }

    #[test]
    fn the_yield_stress_is_given_once_and_in_range() {
        let t = torque(&disc(Some(24_315.0), None)).unwrap();
        assert!((t.torque.total_nm - 0.958).abs() < 5e-4, "{t:?}");
        assert_eq!((t.brake.name(), t.brake.equation()), ("single-disc", "(3.6)/(3.7)"));
        assert!(input_error(&disc(None, None)).contains("tau_y or b"));
        assert!(input_error(&disc(Some(1.0), Some(0.4))).contains("not both"));
        assert!(input_error(&disc(Some(-1.0), None)).contains("tau_y"));
        assert!(input_error(&disc(Some(f64::NAN), None)).contains("tau_y"));
        assert!(input_error(&disc(None, Some(3.5))).contains("between 0 T and 3 T"));
        assert!(input_error(&disc(None, Some(f64::NAN))).contains("between 0 T and 3 T"));
        let from_curve = torque(&disc(None, Some(0.46))).unwrap();
        assert_eq!(from_curve.fluid.b_t, Some(0.46));
        assert!(from_curve.fluid.tau_y_source.contains("mrf-122eg"));
    }

    /// A NaN or negative viscosity is refused whether or not a speed uses it (the CLI once
    /// accepted it without a speed, the Python binding refused it).
    #[test]
    fn the_viscous_term_needs_a_valid_viscosity_speed_and_gap() {
        for eta in [f64::NAN, -0.1] {
            let request = TorqueRequest { eta_pa_s: Some(eta), ..disc(Some(1e4), None) };
            assert!(input_error(&request).contains("eta"), "{eta}");
        }
        let no_gap = TorqueRequest { speed_rad_s: Some(10.0), ..disc(Some(1e4), None) };
        assert!(input_error(&no_gap).contains("needs gap"));
        let nan_speed = TorqueRequest {
            speed_rad_s: Some(f64::NAN),
            gap_m: Some(5e-4),
            ..disc(Some(1e4), None)
        };
        assert!(input_error(&nan_speed).contains("speed"));
        let multi_drum = TorqueRequest {
            brake: ClosedFormBrake::MultiDrum {
                r0_m: 25e-3,
                h_m: 9e-3,
                d_m: 1e-3,
                g_m: 0.5e-3,
                surfaces: 4,
            },
            speed_rad_s: Some(6.0),
            ..disc(Some(25_670.0), None)
        };
        let t = torque(&multi_drum).unwrap();
        assert_eq!(t.viscous.map(|v| v.gap_m), Some(0.5e-3), "the multi-drum's gap is g");
        assert_eq!(surface_radii(&t.brake).len(), 4);
    }

    #[test]
    fn a_coil_needs_a_wire_and_warns_about_what_does_not_fit() {
        let request = CoilRequest {
            window_width_m: 10e-3,
            window_height_m: 14.4e-3,
            wire: Some(WireChoice::Diameter(0.5e-3)),
            inner_radius_m: None,
            turns: None,
            current_a: None,
            temperature_c: None,
        };
        let c = coil(&request).unwrap();
        assert_eq!((c.window.turns, c.turns), (644, 644));
        assert!(c.warnings.is_empty(), "{:?}", c.warnings);
        let over = coil(&CoilRequest { turns: Some(700), ..request.clone() }).unwrap();
        assert!(over.warnings[0].contains("at most 644 turns"));
        let hot = CoilRequest {
            wire: Some(WireChoice::Awg(24)),
            current_a: Some(3.0),
            ..request.clone()
        };
        assert!(coil(&hot).unwrap().warnings.iter().any(|w| w.contains("rating of 2.1 A")));
        let e = coil(&CoilRequest { wire: None, ..request }).unwrap_err().to_string();
        assert!(e.contains("awg") && e.contains("wire_diameter"), "{e}");
    }
}
