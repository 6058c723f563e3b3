//! The off-state torque as a sum the user can read: what the hand feels when the brake is off.
//!
//! The thesis prototype measured 0.15 N·m at 0 A (§5.3.1) and blamed the rotary shaft seals for
//! much of it ("the usage of the rotary shaft seals increases the off-state torque because of the
//! friction between the seals and the rotary part", §5.2). A field analysis alone sees only the
//! fluid's viscous drag, so every other term is a spec input (`[drag]`, [`Drag`]) and the
//! breakdown ([`OffStateTorque`]) says where each number comes from; a term nobody gave is
//! reported as `0` with the words "not given", never silently.
//!
//! # Terms, in direction 1 (the bidirectional brake is symmetric)
//! * **Viscous**: the Newtonian drag of the fluid gaps that turn, thesis (3.4), at the analysis
//!   speed ([`crate::analysis`]).
//! * **Seals**: `seals_per_rotor × seal_torque` for the rotor that turns. A lip seal's friction
//!   depends on its lip load, lubrication and speed, which only its maker's data or a
//!   measurement give; the spec takes the drag torque of one seal as such a value and its source.
//! * **Bearings**: the constant-coefficient estimate of the frictional moment of a rolling
//!   bearing, `M = ½ μ P d` (SKF, *Rolling bearings* catalogue, 2016, "Friction — Estimating the
//!   frictional moment", eq. and Table 1: μ = 0.0015 for deep groove ball bearings; Koyo's
//!   catalogue gives 0.0010–0.0015). `P` is the equivalent load on the bearings and `d` their bore.
//!   The catalogue states its conditions: a load of about 0.1 C, good lubrication, normal
//!   speeds; a haptic knob runs far below that load, where the load-independent part of the
//!   friction (grease churning, the SKF model's `M_rr` and `M_drag`) dominates and this estimate
//!   is low. Trust: medium at rated load, low at the light loads of a haptic device.
//!   In an energised brake part of the load is the magnetic axial pull on the rotor
//!   ([`crate::analysis::RotorForce`]).
//! * **Freewheel** (the bidirectional brake): the shaft turns inside the idle unit's one-way
//!   bearing, which drags its rotor with it until that rotor's own resistance (its viscous and
//!   seal drag) holds it still; the hand feels the smaller of the two,
//!   `min(freewheel_drag, T_idle rotor)`.
//! * **Remanent**: the torque of the field the steel keeps at 0 A after a current peak. The field
//!   solution is anhysteretic (no remanence), so this term is stated as not modelled.
//!
//! The terms other than the viscous one do not depend on the current in this model, so the
//! analysis adds their sum to every point of the torque–current curve, as it adds the constant
//! friction of [`crate::analysis::AnalysisOptions::seal_friction_nm`].

use schemars::JsonSchema;
use serde::{Deserialize, Deserializer, Serialize};

use crate::spec::Length;

/// Largest count of seals per rotor or of bearings a spec may give (a sanity bound).
pub const MAX_COUNT: u32 = 64;

/// Largest drag torque of one seal or one freewheel a spec may give (N·m): far above any
/// catalogue value for the shaft sizes of a haptic brake (a sanity bound, not physics).
pub const MAX_ITEM_TORQUE_NM: f64 = 100.0;

/// Largest external bearing load a spec may give (N): a sanity bound.
pub const MAX_BEARING_LOAD_N: f64 = 1.0e6;

/// Longest source text (characters).
pub const MAX_SOURCE_CHARS: usize = 300;

/// A torque read from TOML: a string with a unit (`"0.02 N·m"`, `"20 mNm"`) or a bare number in
/// N·m. Serialised as a bare SI number.
#[derive(Debug, Clone, Copy, PartialEq, PartialOrd, Serialize)]
pub struct Torque(pub f64);

/// A force read from TOML: a string with a unit (`"5 N"`, `"0.2 kN"`) or a bare number in N.
/// Serialised as a bare SI number.
#[derive(Debug, Clone, Copy, PartialEq, PartialOrd, Serialize)]
pub struct Force(pub f64);

impl<'de> Deserialize<'de> for Torque {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        crate::spec::quantity(d, mrbrake_units::Dimension::Torque).map(Torque)
    }
}

impl<'de> Deserialize<'de> for Force {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        crate::spec::quantity(d, mrbrake_units::Dimension::Force).map(Force)
    }
}

impl JsonSchema for Torque {
    fn schema_name() -> std::borrow::Cow<'static, str> {
        "Torque".into()
    }

    fn inline_schema() -> bool {
        true
    }

    fn json_schema(_: &mut schemars::SchemaGenerator) -> schemars::Schema {
        mrbrake_schema::quantity(mrbrake_units::Dimension::Torque, "0.02 N·m")
    }
}

impl JsonSchema for Force {
    fn schema_name() -> std::borrow::Cow<'static, str> {
        "Force".into()
    }

    fn inline_schema() -> bool {
        true
    }

    fn json_schema(_: &mut schemars::SchemaGenerator) -> schemars::Schema {
        mrbrake_schema::quantity(mrbrake_units::Dimension::Force, "5 N")
    }
}

/// The kind of the rolling bearings, for the friction coefficient of SKF's Table 1.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Deserialize, Serialize, JsonSchema)]
#[serde(rename_all = "kebab-case")]
pub enum BearingKind {
    /// Deep groove ball bearing, μ = 0.0015.
    #[default]
    DeepGrooveBall,
    /// Single-row angular contact ball bearing, μ = 0.0020.
    AngularContactBall,
    /// Self-aligning ball bearing, μ = 0.0010.
    SelfAligningBall,
    /// Cylindrical roller bearing with a cage, μ = 0.0011.
    CylindricalRoller,
    /// Needle roller bearing with a cage, μ = 0.0020.
    NeedleRoller,
    /// Thrust ball bearing, μ = 0.0013.
    ThrustBall,
}

impl BearingKind {
    /// The constant coefficient of friction of SKF's Table 1 (open bearings, no contact seals).
    pub fn friction_coefficient(self) -> f64 {
        match self {
            BearingKind::DeepGrooveBall => 0.0015,
            BearingKind::AngularContactBall => 0.0020,
            BearingKind::SelfAligningBall => 0.0010,
            BearingKind::CylindricalRoller => 0.0011,
            BearingKind::NeedleRoller => 0.0020,
            BearingKind::ThrustBall => 0.0013,
        }
    }

    /// The name as the spec writes it.
    pub fn name(self) -> &'static str {
        match self {
            BearingKind::DeepGrooveBall => "deep-groove-ball",
            BearingKind::AngularContactBall => "angular-contact-ball",
            BearingKind::SelfAligningBall => "self-aligning-ball",
            BearingKind::CylindricalRoller => "cylindrical-roller",
            BearingKind::NeedleRoller => "needle-roller",
            BearingKind::ThrustBall => "thrust-ball",
        }
    }
}

/// `[drag]`: the mechanical drag of the device besides its fluid (module docs). Every field is
/// optional; an absent table is a brake with no seals, no bearing load and no freewheel drag,
/// which the breakdown reports as "not given".
#[derive(Debug, Clone, Default, PartialEq, Deserialize, Serialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Drag {
    /// Lip seals rubbing on each rotor (between a rotating part and the housing); the thesis
    /// brake has rotary shaft seals there (§4.3.2, Fig. 4.13).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub seals_per_rotor: u32,
    /// Drag torque of one seal at the service speed: its maker's friction data or a measurement.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub seal_torque: Option<Torque>,
    /// Where `seal_torque` comes from (a datasheet, a measurement), printed in the breakdown.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub seal_source: Option<String>,
    /// Rolling bearings that carry the rotating parts.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub bearings: u32,
    /// Their kind (SKF's Table 1 coefficient): `deep-groove-ball` unless given.
    #[serde(default, skip_serializing_if = "is_default_kind")]
    pub bearing_kind: BearingKind,
    /// Their bore `d`: the shaft's diameter unless given.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub bearing_bore: Option<Length>,
    /// Equivalent load on each bearing from outside the brake (the handle, a belt), N; 0 unless
    /// given (the magnetic pull is added by the analysis at the maximum current).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub bearing_load: Option<Force>,
    /// Drag torque of one one-way bearing while it overruns (the bidirectional brake):
    /// its maker's value or a measurement.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub freewheel_drag: Option<Torque>,
    /// Where `freewheel_drag` comes from, printed in the breakdown.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub freewheel_source: Option<String>,
}

fn is_zero(n: &u32) -> bool {
    *n == 0
}

fn is_default_kind(kind: &BearingKind) -> bool {
    *kind == BearingKind::default()
}

impl Drag {
    /// The numeric fields of `[drag]` a study or a calibration may vary: the seals per rotor and
    /// the drag torques of one seal and of one freewheel (the bearings' count and load stay
    /// fixed: their friction is negligible beside the seals', [`OffStateTorque`]).
    pub const FIELDS: &'static [crate::spec::SpecField] = &[
        crate::spec::SpecField {
            path: "drag.seals_per_rotor",
            quantity: crate::spec::Quantity::Integer,
            bounds: crate::spec::Bounds::closed(0.0, MAX_COUNT as f64),
        },
        crate::spec::SpecField {
            path: "drag.seal_torque",
            quantity: crate::spec::Quantity::Torque,
            bounds: crate::spec::Bounds::closed(0.0, MAX_ITEM_TORQUE_NM),
        },
        crate::spec::SpecField {
            path: "drag.freewheel_drag",
            quantity: crate::spec::Quantity::Torque,
            bounds: crate::spec::Bounds::closed(0.0, MAX_ITEM_TORQUE_NM),
        },
    ];

    /// True for the table an absent `[drag]` stands for (the spec's JSON, which design keys hash,
    /// then leaves it out, so the keys of every spec without `[drag]` stay what they were).
    pub fn is_default(&self) -> bool {
        *self == Drag::default()
    }

    /// Every field against its range, into `errors` (fields named `drag.…`).
    pub fn check(&self, errors: &mut mrbrake_error::FieldErrors) {
        let count = |field: &str, n: u32, errors: &mut mrbrake_error::FieldErrors| {
            if n > MAX_COUNT {
                errors.add(field, format!("{n} is outside the allowed range 0..={MAX_COUNT}"));
            }
        };
        count("drag.seals_per_rotor", self.seals_per_rotor, errors);
        count("drag.bearings", self.bearings, errors);
        let torque = |field: &str, t: Option<Torque>, errors: &mut mrbrake_error::FieldErrors| {
            if let Some(Torque(v)) = t
                && !(v.is_finite() && (0.0..=MAX_ITEM_TORQUE_NM).contains(&v))
            {
                errors.add(
                    field,
                    format!("{v} N·m is outside the allowed range [0, {MAX_ITEM_TORQUE_NM}] N·m"),
                );
            }
        };
        torque("drag.seal_torque", self.seal_torque, errors);
        torque("drag.freewheel_drag", self.freewheel_drag, errors);
        if let Some(Force(v)) = self.bearing_load
            && !(v.is_finite() && (0.0..=MAX_BEARING_LOAD_N).contains(&v))
        {
            errors.add(
                "drag.bearing_load",
                format!("{v} N is outside the allowed range [0, {MAX_BEARING_LOAD_N}] N"),
            );
        }
        if let Some(bore) = self.bearing_bore
            && !crate::spec::LENGTH_BOUNDS.contains(bore.m())
        {
            let max = crate::spec::LENGTH_BOUNDS.max;
            errors.add("drag.bearing_bore", format!("{} m must be in (0, {max} m)", bore.m()));
        }
        for (field, text) in [
            ("drag.seal_source", &self.seal_source),
            ("drag.freewheel_source", &self.freewheel_source),
        ] {
            if text.as_ref().is_some_and(|t| t.chars().count() > MAX_SOURCE_CHARS) {
                errors.add(field, format!("longer than {MAX_SOURCE_CHARS} characters"));
            }
        }
        if self.seals_per_rotor > 0 && self.seal_torque.is_none() {
            errors.add(
                "drag.seal_torque",
                "required when drag.seals_per_rotor > 0 (the drag torque of one seal, N·m)",
            );
        }
    }
}

/// What the breakdown needs besides the spec's `[drag]`: the viscous drag of each rotor (from
/// the analysis) and the bearings' bore default.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DragInputs {
    /// Viscous torque of the rotor that turns in direction 1 at the analysis speed (N·m).
    pub viscous_nm: f64,
    /// Viscous torque of the idle rotor (the bidirectional brake's unit 2), `None` without one.
    pub idle_viscous_nm: Option<f64>,
    /// Shaft diameter (m): the bearing bore unless `[drag]` gives one.
    pub shaft_diameter_m: f64,
    /// Constant friction given as an analysis option (`--seal-friction`), N·m.
    pub extra_friction_nm: f64,
}

/// Where each term of an [`OffStateTorque`] comes from.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct OffStateSources {
    /// The viscous term.
    pub viscous: String,
    /// The seal term.
    pub seal: String,
    /// The bearing term.
    pub bearing: String,
    /// The freewheel term.
    pub freewheel: String,
    /// The remanent term.
    pub remanent: String,
}

/// The off-state torque of direction 1 and its terms (module docs), N·m.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct OffStateTorque {
    /// Fluid drag of the turning rotor's gaps, thesis (3.4).
    #[serde(rename = "viscous_Nm")]
    pub viscous_nm: f64,
    /// Lip seals of the turning rotor (plus the constant friction of `--seal-friction`).
    #[serde(rename = "seal_Nm")]
    pub seal_nm: f64,
    /// Rolling bearings, `½ μ P d` at the external load.
    #[serde(rename = "bearing_Nm")]
    pub bearing_nm: f64,
    /// The idle unit's overrunning one-way bearing (bidirectional brakes).
    #[serde(rename = "freewheel_Nm")]
    pub freewheel_nm: f64,
    /// Magnetic remanence (not modelled: 0).
    #[serde(rename = "remanent_Nm")]
    pub remanent_nm: f64,
    /// The sum.
    #[serde(rename = "total_Nm")]
    pub total_nm: f64,
    /// Where each term comes from.
    pub sources: OffStateSources,
}

/// One term of an [`OffStateTorque`]: its name, its JSON key, its value (N·m) and its source.
pub type OffStateTerm<'a> = (&'static str, &'static str, f64, &'a str);

impl OffStateTorque {
    /// The terms in print order, for every report of the breakdown.
    pub fn terms(&self) -> [OffStateTerm<'_>; 5] {
        let s = &self.sources;
        [
            ("viscous", "viscous_Nm", self.viscous_nm, &s.viscous),
            ("seals", "seal_Nm", self.seal_nm, &s.seal),
            ("bearings", "bearing_Nm", self.bearing_nm, &s.bearing),
            ("freewheel", "freewheel_Nm", self.freewheel_nm, &s.freewheel),
            ("remanent", "remanent_Nm", self.remanent_nm, &s.remanent),
        ]
    }

    /// The terms other than the viscous one: the constant friction the analysis adds to every
    /// point of the torque–current curve.
    pub fn constant_friction_nm(&self) -> f64 {
        self.seal_nm + self.bearing_nm + self.freewheel_nm + self.remanent_nm
    }
}

/// Not given: the words every absent input is reported with.
const NOT_GIVEN: &str = "not given in [drag]: 0, assumed";

impl Drag {
    /// The bearings' frictional moment (N·m) under a total equivalent load `load_n` shared by
    /// them: `½ μ P d` summed over the bearings, `½ μ d Σ P_i` (SKF, module docs).
    pub fn bearing_torque_nm(&self, load_n: f64, shaft_diameter_m: f64) -> f64 {
        if self.bearings == 0 {
            return 0.0;
        }
        let d = self.bearing_bore.map_or(shaft_diameter_m, Length::m);
        0.5 * self.bearing_kind.friction_coefficient() * load_n * d
    }

    /// The external load on all bearings together (N).
    pub fn external_bearing_load_n(&self) -> f64 {
        self.bearing_load.map_or(0.0, |f| f.0) * f64::from(self.bearings)
    }

    /// The seal drag of one rotor (N·m).
    fn seal_torque_nm(&self) -> f64 {
        f64::from(self.seals_per_rotor) * self.seal_torque.map_or(0.0, |t| t.0)
    }

    /// The breakdown of the off-state torque in direction 1 (module docs).
    pub fn off_state(&self, inputs: &DragInputs) -> OffStateTorque {
        let seal_nm = self.seal_torque_nm() + inputs.extra_friction_nm;
        let bearing_nm =
            self.bearing_torque_nm(self.external_bearing_load_n(), inputs.shaft_diameter_m);
        let freewheel_nm = match (inputs.idle_viscous_nm, self.freewheel_drag) {
            (Some(idle_viscous), Some(Torque(drag))) => {
                drag.min(idle_viscous + self.seal_torque_nm())
            }
            _ => 0.0,
        };
        let remanent_nm = 0.0;
        let total_nm = inputs.viscous_nm + seal_nm + bearing_nm + freewheel_nm + remanent_nm;
        OffStateTorque {
            viscous_nm: inputs.viscous_nm,
            seal_nm,
            bearing_nm,
            freewheel_nm,
            remanent_nm,
            total_nm,
            sources: self.sources(inputs),
        }
    }

    /// The source text of every term.
    fn sources(&self, inputs: &DragInputs) -> OffStateSources {
        let viscous = "thesis (3.4): Newtonian drag of the turning rotor's gaps at the analysis \
                       speed, the fluid's library viscosity"
            .to_string();
        let mut seal = if self.seals_per_rotor == 0 {
            NOT_GIVEN.to_string()
        } else {
            format!(
                "{} seal(s) × {} N·m: {}",
                self.seals_per_rotor,
                self.seal_torque.map_or(0.0, |t| t.0),
                self.seal_source.as_deref().unwrap_or("source not stated")
            )
        };
        if inputs.extra_friction_nm > 0.0 {
            seal.push_str(&format!(
                "; plus {} N·m of constant friction given as an analysis option",
                inputs.extra_friction_nm
            ));
        }
        let bearing = if self.bearings == 0 || self.external_bearing_load_n() <= 0.0 {
            format!("{NOT_GIVEN} (no bearings or no external load; SKF ½ μ P d is 0 at P = 0)")
        } else {
            format!(
                "SKF Rolling bearings (2016), ½ μ P d, Table 1: {} bearing(s), {}, μ = {}; \
                 low at light loads (load-independent friction not modelled)",
                self.bearings,
                self.bearing_kind.name(),
                self.bearing_kind.friction_coefficient()
            )
        };
        let freewheel = match (inputs.idle_viscous_nm, self.freewheel_drag) {
            (None, _) => "no freewheel: a single-unit brake".to_string(),
            (Some(_), None) => NOT_GIVEN.to_string(),
            (Some(_), Some(_)) => format!(
                "min(one-way bearing drag, idle rotor's viscous + seal drag): {}",
                self.freewheel_source.as_deref().unwrap_or("source not stated")
            ),
        };
        let remanent = "not modelled: the field solution is anhysteretic (no remanence in the \
                        steel); stated as 0"
            .to_string();
        OffStateSources { viscous, seal, bearing, freewheel, remanent }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn inputs() -> DragInputs {
        DragInputs {
            viscous_nm: 1e-3,
            idle_viscous_nm: Some(2e-3),
            shaft_diameter_m: 0.01,
            extra_friction_nm: 0.0,
        }
    }

    #[test]
    fn no_drag_table_is_the_viscous_torque_alone_with_every_term_stated() {
        let b = Drag::default().off_state(&inputs());
        assert!((b.total_nm - 1e-3).abs() < 1e-15);
        assert!(b.sources.seal.contains("not given"));
        assert!(b.sources.bearing.contains("not given"));
        assert!(b.sources.freewheel.contains("not given"));
        assert!(b.sources.remanent.contains("not modelled"));
    }

    #[test]
    fn bearing_friction_is_half_mu_p_d() {
        let drag = Drag {
            bearings: 2,
            bearing_load: Some(Force(50.0)),
            bearing_bore: Some(Length(0.012)),
            ..Drag::default()
        };
        let b = drag.off_state(&inputs());
        // ½ × 0.0015 × (2 × 50 N) × 0.012 m = 9e-4 N·m.
        assert!((b.bearing_nm - 9e-4).abs() < 1e-15, "{}", b.bearing_nm);
    }

    #[test]
    fn the_freewheel_drags_the_idle_rotor_only_up_to_its_own_resistance() {
        let seal = |fw: f64| Drag {
            seals_per_rotor: 1,
            seal_torque: Some(Torque(0.01)),
            freewheel_drag: Some(Torque(fw)),
            ..Drag::default()
        };
        // A weak freewheel slips: its drag is felt.
        assert!((seal(0.005).off_state(&inputs()).freewheel_nm - 0.005).abs() < 1e-15);
        // A stiff one carries the idle rotor along: its viscous + seal drag is felt.
        assert!((seal(1.0).off_state(&inputs()).freewheel_nm - 0.012).abs() < 1e-15);
        // A single-unit brake has none.
        let single = DragInputs { idle_viscous_nm: None, ..inputs() };
        assert!(seal(1.0).off_state(&single).freewheel_nm.abs() < 1e-15);
    }

    #[test]
    fn the_constant_friction_is_the_total_without_the_viscous_term() {
        let drag = Drag { seals_per_rotor: 2, seal_torque: Some(Torque(0.03)), ..Drag::default() };
        let b = drag.off_state(&DragInputs { extra_friction_nm: 0.01, ..inputs() });
        assert!((b.constant_friction_nm() - 0.07).abs() < 1e-15);
        assert!((b.total_nm - b.viscous_nm - b.constant_friction_nm()).abs() < 1e-15);
        assert!(b.sources.seal.contains("analysis option"));
    }

    #[test]
    fn out_of_range_fields_are_named() {
        let drag = Drag {
            seals_per_rotor: 1,
            seal_torque: None,
            bearings: 1000,
            bearing_load: Some(Force(f64::NAN)),
            freewheel_drag: Some(Torque(-1.0)),
            ..Drag::default()
        };
        let mut errors = mrbrake_error::FieldErrors::new();
        drag.check(&mut errors);
        let text = format!("{errors:?}");
        for field in
            ["drag.seal_torque", "drag.bearings", "drag.bearing_load", "drag.freewheel_drag"]
        {
            assert!(text.contains(field), "{field} not named in {text}");
        }
    }
}
