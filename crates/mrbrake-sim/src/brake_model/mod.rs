//! The brake model file: what the design predicts (or a lab measured) about one MR brake, in the
//! form the virtual rig and the haptic simulation run.
//!
//! One type, [`BrakeModel`], serialised as JSON with a versioned schema ([`SCHEMA`],
//! [`SCHEMA_VERSION`]). `mrbrake analyze --save-model` writes it from a design's finite-element
//! analysis (the builder is `mrbrake_device::brake_model`, which can reach the design's results,
//! its design key and the model revision); `mrbrake response --save-model` and `mrbrake thermal
//! --save-model` add the predicted dynamics (fitted here, [`fit`], to any frequency-response data)
//! and hot coil, `mrbrake characterize LOG --brake-model` a unit's identified branches
//! ([`BrakeModel::set_identified_branches`]); `mrbrake rig … --brake-model` and `mrbrake haptic …
//! --brake-model` read it, [`apply`] turning each unit into the simulators' runtime forms (the
//! haptic plant's [`crate::haptic::BrakePlant`]).
//! The built-in prototype-like brakes are shipped as model files in `examples/brake-models/`.
//!
//! # Schema (version 3)
//!
//! ```json
//! {
//!   "schema": "mrbrake-brake-model", "schema_version": 3, "name": "…",
//!   "provenance": { "mrbrake_version": "0.1.0", "source": "…", "spec_sha256": "…" | null,
//!                   "model_revision": 3 | null, "predicted": ["…"], "assumed": ["…"] },
//!   "units": [ {
//!     "unit": 1, "current_max_A": 2.0, "rotor_inertia_kg_m2": 3.2e-5 | null,
//!     "static_curve": { "current_A": [0, …, 2], "torque_Nm": [0, …], "source": "…" },
//!     "off_state": { "viscous_Nm_s_per_rad": 0.003, "reference_speed_rad_s": 1.0,
//!                    "seal_friction_Nm": 0.0, "seal_friction_source": "…" },
//!     "hysteresis": { "kind": "none", "note": "…" }
//!                 | { "kind": "polynomial_branches", "rising": [c0, c1, …], "falling": […],
//!                     "source": "…" }
//!                 | { "kind": "preisach", "levels_A": [0, …, I_max], "rising_Nm": […],
//!                     "everett_Nm": [[0], [E10, 0], …], "source": "…" },
//!     "dynamics": { "numerator": […], "denominator": […], "source": "…" } | null,
//!     "thermal": { "hot_temperature_C": …, "hot_resistance_ohm": …, "continuous_current_A": …,
//!                  "source": "…" } | null
//!   } ]
//! }
//! ```
//!
//! Units are in the field names (SI; `_A`, `_Nm`, `_ohm`, `_C`); an unknown field (e.g.
//! `torque_mNm`) is refused, so a file in other units cannot be read silently. Unit 1 resists
//! positive rotation, unit 2 (bidirectional brakes) negative rotation. The static curve is the
//! field-dependent (yield) torque at rest: strictly increasing currents from 0 to `current_max_A`,
//! non-decreasing non-negative torques. The off-state torque is separate: a viscous coefficient
//! (the viscous torque is linear in the shear rate, Bingham law, thesis (3.3)) and a constant
//! seal/bearing friction whose source the file states. Polynomial branches are ascending powers of
//! the current in A giving N·m (1 to 8 coefficients, as the inverse-model file of
//! `characterize --save-model`), each non-decreasing on `[0, current_max_A]`. Dynamics is a
//! continuous transfer function from the static torque to the brake torque (descending powers of
//! s, as sysid's [`TransferFunction`]). `rotor_inertia_kg_m2` is the moment of inertia of the parts
//! that turn with the shaft when the unit resists (its direction's rotor, `mechanics` of `mrbrake
//! analyze`), `null` when unknown.
//!
//! A `preisach` hysteresis is a Preisach model as a tabulated Everett function
//! ([`crate::rig::everett::EverettTable`]: evenly spaced levels from 0 to `current_max_A`, the
//! rising branch from the reference state at 0 A, `everett_Nm[a][b] = E(α_a, α_b)` for `b ≤ a`,
//! a non-negative density), e.g. identified from the design's predicted first-order reversal
//! curves (`analyze --hysteresis --save-model`). Its torques are the field-dependent (yield)
//! torque like the static curve's, so the off-state terms are added as for `none`.
//!
//! Version 3 added the `preisach` kind (a version-1 or -2 file with it is refused); version 2
//! added `rotor_inertia_kg_m2`; version-1 files are still read, their units without a
//! rotor inertia (`None`), and the haptic device then keeps its own inertia (54.8 kg·mm², the
//! thesis prototype's, see [`crate::haptic::device`]) and says so. A version-1 file that carries
//! the version-2 field is refused (it is neither).
//!
//! # How a model drives the simulators
//!
//! Both simulators run polynomial branches (the controller's [`InverseModel`]) and a torque lag.
//! [`UnitModel::branches`] gives them: for `hysteresis = none` the rising and the falling branch are
//! both one least-squares polynomial through the static curve plus the seal friction (the lowest
//! degree 3…7 within [`STATIC_FIT_TOLERANCE`] of the curve's span that is non-decreasing, see
//! [`StaticFit`]), moved to pass through the curve's value at 0 A exactly: the anhysteretic FEA
//! curve, no loop; for `polynomial_branches` the identified
//! branches, used as measured (they already contain the off-state torque the rig saw, so neither
//! the seal friction nor the viscous term is added again); for `preisach` the branches are the
//! model's major loop (rising branch and the falling one from `current_max_A`), each fitted as the
//! static curve is, plus the seal friction: the controller's inverse compensates the predicted
//! loop while the simulators' plants run the Preisach model itself ([`apply`]). Where the model gives no dynamics the
//! simulators keep the thesis prototype's measured lags (5.5)/(5.6) and say so.
//! The haptic brake is a Coulomb element of the branch torque; its viscous coefficient is added to
//! the device's viscous friction (one rotor turns with the shaft in each direction, thesis §4.3).

pub mod apply;
pub mod fit;
pub mod prototype;

use std::path::Path;

use mrbrake_control::InverseModel;
use mrbrake_error::FieldError;
use mrbrake_sysid::polynomial;
use mrbrake_sysid::transfer_function::TransferFunction;
use serde::{Deserialize, Serialize};

use crate::SimError;

/// The schema name every brake model file carries.
pub const SCHEMA: &str = "mrbrake-brake-model";
/// The schema version this build writes.
pub const SCHEMA_VERSION: u32 = 3;
/// The older schema versions this build still reads (module docs: what they lack).
pub const READABLE_VERSIONS: [u32; 3] = [1, 2, 3];
/// Largest rotor inertia a model may declare, kg·m² (a brake rotor of 1 kg·m² is a flywheel).
pub const ROTOR_INERTIA_LIMIT_KG_M2: f64 = 1.0;
/// Largest error of the polynomial through an anhysteretic static curve, as a fraction of the
/// curve's torque span (1 %: below the thesis's 3.07–3.54 % tracking errors, §5.3.2).
pub const STATIC_FIT_TOLERANCE: f64 = 0.01;
/// Largest current a model may declare, A (the controller's bound).
pub const CURRENT_LIMIT_A: f64 = mrbrake_control::CURRENT_LIMIT_A;

/// A brake model (see the module docs for the schema).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BrakeModel {
    /// Always [`SCHEMA`].
    pub schema: String,
    /// Always [`SCHEMA_VERSION`] for files this build writes.
    pub schema_version: u32,
    /// The design's (or brake's) name.
    pub name: String,
    /// Where the numbers come from.
    pub provenance: Provenance,
    /// One entry per coil/direction: unit 1, and unit 2 for a bidirectional brake.
    pub units: Vec<UnitModel>,
}

/// Where a model's numbers come from.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Provenance {
    /// The mrbrake version that wrote the file.
    pub mrbrake_version: String,
    /// What produced it, e.g. `mrbrake analyze examples/specs/x.toml`.
    pub source: String,
    /// SHA-256 of the design (the design key of `mrbrake-explore`: spec, materials, settings,
    /// solver), when the model comes from a spec.
    pub spec_sha256: Option<String>,
    /// `mrbrake_explore::design::MODEL_REVISION` of the analysis, when predicted.
    pub model_revision: Option<u32>,
    /// What was predicted (computed from the design).
    pub predicted: Vec<String>,
    /// What was assumed (defaults, stated values not computed).
    pub assumed: Vec<String>,
    /// What was added after the first save (e.g. `response --save-model`), in order.
    #[serde(default)]
    pub amended: Vec<String>,
}

/// One unit (coil and its gaps) of the brake.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct UnitModel {
    /// 1 (resists positive rotation) or 2 (negative rotation).
    pub unit: u32,
    /// Highest allowed coil current, A.
    #[serde(rename = "current_max_A")]
    pub current_max_a: f64,
    /// Moment of inertia of the parts that turn with the shaft when this unit resists, kg·m²
    /// (`None`: unknown, e.g. a version-1 file or a measured brake whose rotor was not weighed).
    #[serde(default)]
    pub rotor_inertia_kg_m2: Option<f64>,
    /// The field-dependent torque at rest against the current.
    pub static_curve: StaticCurve,
    /// The torque at zero current.
    pub off_state: OffState,
    /// How the torque depends on the current's history.
    pub hysteresis: Hysteresis,
    /// Static torque → brake torque, when known.
    #[serde(default)]
    pub dynamics: Option<Dynamics>,
    /// Hot coil and current limit, when known.
    #[serde(default)]
    pub thermal: Option<Thermal>,
}

/// Sampled static torque–current curve.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StaticCurve {
    /// Currents, A, strictly increasing from 0 to `current_max_A`.
    #[serde(rename = "current_A")]
    pub current_a: Vec<f64>,
    /// Torques, N·m, non-negative and non-decreasing.
    #[serde(rename = "torque_Nm")]
    pub torque_nm: Vec<f64>,
    /// Where the curve comes from.
    pub source: String,
}

/// The off-state (zero-current) torque.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OffState {
    /// Viscous torque per unit shaft speed, N·m·s/rad.
    #[serde(rename = "viscous_Nm_s_per_rad")]
    pub viscous_nm_s_per_rad: f64,
    /// The speed at which the viscous torque was evaluated, rad/s.
    pub reference_speed_rad_s: f64,
    /// Constant seal and bearing friction, N·m.
    #[serde(rename = "seal_friction_Nm")]
    pub seal_friction_nm: f64,
    /// Where the seal friction comes from (a measurement, a datasheet, or "assumed: …").
    pub seal_friction_source: String,
}

/// The hysteresis description: stated, never silently invented.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum Hysteresis {
    /// No hysteresis: the static curve is used for rising and falling current (an anhysteretic
    /// finite-element analysis predicts no loop; `note` says why it is none).
    None {
        /// Why the model has none.
        note: String,
    },
    /// Two polynomial branches (as `characterize --save-model` writes them).
    PolynomialBranches {
        /// Torque while the current increases, ascending powers of the current in A, N·m.
        rising: Vec<f64>,
        /// Torque while the current decreases.
        falling: Vec<f64>,
        /// Identified from which log, or "assumed: …".
        source: String,
    },
    /// A Preisach model as a tabulated Everett function (module docs).
    Preisach {
        /// Evenly spaced levels from 0 to `current_max_A`, A.
        #[serde(rename = "levels_A")]
        levels_a: Vec<f64>,
        /// The rising branch from the reference state at each level, N·m.
        #[serde(rename = "rising_Nm")]
        rising_nm: Vec<f64>,
        /// `E(α_a, α_b)` for `b ≤ a`, N·m.
        #[serde(rename = "everett_Nm")]
        everett_nm: Vec<Vec<f64>>,
        /// Where the table comes from.
        source: String,
    },
}

impl Hysteresis {
    /// The Preisach model's table, for the `preisach` kind.
    pub fn everett(&self) -> Option<crate::rig::everett::EverettTable> {
        match self {
            Self::Preisach { levels_a, rising_nm, everett_nm, .. } => {
                Some(crate::rig::everett::EverettTable {
                    levels_a: levels_a.clone(),
                    rising_nm: rising_nm.clone(),
                    everett_nm: everett_nm.clone(),
                })
            }
            _ => None,
        }
    }
}

/// A low-order continuous transfer function from the static torque to the brake torque.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Dynamics {
    /// Numerator, highest power of s first.
    pub numerator: Vec<f64>,
    /// Denominator, highest power of s first.
    pub denominator: Vec<f64>,
    /// Where it comes from (fit, measurement).
    pub source: String,
}

/// The hot coil.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Thermal {
    /// Temperature of the hot coil, °C.
    #[serde(rename = "hot_temperature_C")]
    pub hot_temperature_c: f64,
    /// Coil resistance at that temperature, Ω.
    pub hot_resistance_ohm: f64,
    /// Largest current the coil carries continuously within its temperature limit, A.
    #[serde(rename = "continuous_current_A")]
    pub continuous_current_a: f64,
    /// Where it comes from.
    pub source: String,
}

/// The most samples a static curve may have: the fits and the simulators' tables are sized by it
/// (issue 33: a 1e8-point curve aborted the process on a failed allocation). The FEA writes tens.
pub const MAX_CURVE_POINTS: usize = 100_000;

/// The polynomial through an anhysteretic static curve (see [`UnitModel::branches`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StaticFit {
    /// Degree of the polynomial.
    pub degree: usize,
    /// Largest |polynomial − curve| over the curve's samples, N·m.
    pub max_error_nm: f64,
}

/// The branches a unit drives the simulators with, and how they were obtained.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct UnitBranches {
    /// Rising and falling branch on `[0, current_max_A]`.
    pub model: InverseModel,
    /// The fit through the static curve (`None` for identified branches).
    pub fit: Option<StaticFit>,
}

impl BrakeModel {
    /// Reads and checks a model file; every error names the file (and the field).
    pub fn read(path: &Path) -> Result<Self, SimError> {
        let text =
            mrbrake_error::read::text(path, mrbrake_error::read::MODEL).map_err(|source| {
                SimError::Io { what: "brake model", path: path.to_path_buf(), source }
            })?;
        Self::from_json(&path.display().to_string(), &text)
    }

    /// Parses and checks model JSON; `file` names it in errors. The schema name and version are
    /// checked before the fields, so a foreign or old file says so rather than "missing field".
    pub fn from_json(file: &str, text: &str) -> Result<Self, SimError> {
        let bad = |field: &str, msg: String| SimError::BrakeModel {
            file: file.to_string(),
            field: field.to_string(),
            message: msg,
        };
        let value: serde_json::Value =
            serde_json::from_str(text).map_err(|e| bad("(document)", format!("not JSON: {e}")))?;
        match value.get("schema").and_then(|s| s.as_str()) {
            Some(SCHEMA) => {}
            Some(other) => {
                return Err(bad(
                    "schema",
                    format!("foreign schema '{other}' (expected '{SCHEMA}')"),
                ));
            }
            None => return Err(bad("schema", format!("missing; a brake model has '{SCHEMA}'"))),
        }
        let version = value.get("schema_version").and_then(serde_json::Value::as_u64);
        match version {
            Some(v) if READABLE_VERSIONS.iter().any(|r| u64::from(*r) == v) => {}
            other => {
                return Err(bad(
                    "schema_version",
                    format!(
                        "{other:?} is not supported: this mrbrake reads versions {READABLE_VERSIONS:?}"
                    ),
                ));
            }
        }
        if version == Some(1) {
            refuse_version2_fields(&value).map_err(|(field, msg)| bad(&field, msg))?;
        }
        if version.is_some_and(|v| v < 3) {
            refuse_version3_fields(&value).map_err(|(field, msg)| bad(&field, msg))?;
        }
        let model: Self = serde_path_to_error::deserialize(value).map_err(|e| {
            let field = e.path().to_string();
            bad(&field, e.into_inner().to_string())
        })?;
        model.validate().map_err(|(field, msg): (String, String)| bad(&field, msg))?;
        Ok(model)
    }

    /// The model as pretty JSON (the file's text).
    pub fn to_json(&self) -> String {
        serde_json::to_string_pretty(self).unwrap_or_default() + "\n"
    }

    /// [`BrakeModel::validate`] as an error naming `origin` (the file, or how a model in memory
    /// was made, e.g. `"(amended with dynamics)"`) and the field.
    pub fn check(&self, origin: &str) -> Result<(), SimError> {
        self.validate().map_err(|(field, message)| SimError::BrakeModel {
            file: origin.to_string(),
            field,
            message,
        })
    }

    /// Checks every value; `Err((field, message))` for the first bad one.
    pub fn validate(&self) -> Result<(), (String, String)> {
        if self.units.is_empty() || self.units.len() > 2 {
            return Err((
                "units".into(),
                format!("{} units; a brake has 1 or 2", self.units.len()),
            ));
        }
        for (k, unit) in self.units.iter().enumerate() {
            let at = |field: &str| format!("units[{k}].{field}");
            if unit.unit as usize != k + 1 {
                return Err((
                    at("unit"),
                    format!("{} must be {} (units in order)", unit.unit, k + 1),
                ));
            }
            unit.validate().map_err(|(field, msg)| (at(&field), msg))?;
            // A model is checked as the simulators will use it, when it is written as when it
            // is read: a curve no branch polynomial fits is refused here, naming the file and
            // the field, not later by a simulator that names neither (issue 33).
            if let Err(e) = unit.branches() {
                let (field, points) = if matches!(unit.hysteresis, Hysteresis::None { .. }) {
                    ("static_curve", unit.static_curve.current_a.len())
                } else {
                    ("hysteresis", 0)
                };
                let hint = if points > 0 {
                    format!(" ({points} points; an analysis with more --points samples it finer)")
                } else {
                    String::new()
                };
                return Err((at(field), format!("the simulators cannot run it: {e}{hint}")));
            }
        }
        Ok(())
    }

    /// Unit `unit` (1 or 2); a single-unit brake answers unit 2 with its unit 1 (the same brake
    /// mounted the other way).
    pub fn unit(&self, unit: u32) -> Result<&UnitModel, SimError> {
        match (unit, self.units.as_slice()) {
            (1, [first, ..]) | (2, [first]) => Ok(first),
            (2, [_, second]) => Ok(second),
            _ => Err(no_unit(&self.name, unit, self.units.len())),
        }
    }
}

/// A version-1 document must not carry the fields version 2 added (`units[k].rotor_inertia_kg_m2`).
fn refuse_version2_fields(value: &serde_json::Value) -> Result<(), (String, String)> {
    let units = value.get("units").and_then(serde_json::Value::as_array);
    for (k, unit) in units.into_iter().flatten().enumerate() {
        if unit.get("rotor_inertia_kg_m2").is_some() {
            return Err((
                format!("units[{k}].rotor_inertia_kg_m2"),
                "is a version-2 field in a version-1 file: set schema_version to 2".into(),
            ));
        }
    }
    Ok(())
}

/// A version-1 or -2 document must not carry what version 3 added (the `preisach` hysteresis).
fn refuse_version3_fields(value: &serde_json::Value) -> Result<(), (String, String)> {
    let units = value.get("units").and_then(serde_json::Value::as_array);
    for (k, unit) in units.into_iter().flatten().enumerate() {
        let kind = unit.get("hysteresis").and_then(|h| h.get("kind"));
        if kind.and_then(serde_json::Value::as_str) == Some("preisach") {
            return Err((
                format!("units[{k}].hysteresis.kind"),
                "'preisach' is a version-3 kind in an older file: set schema_version to 3".into(),
            ));
        }
    }
    Ok(())
}

/// The error of a unit number the model `name` (with `count` units) does not have.
fn no_unit(name: &str, unit: u32, count: usize) -> SimError {
    FieldError::new("unit", format!("brake model '{name}' ({count} unit(s)) has no such unit"))
        .with_value(unit)
        .with_allowed("1 or 2")
        .into()
}

impl BrakeModel {
    /// Replaces unit `unit`'s hysteresis by identified branches (e.g. `mrbrake characterize` of
    /// a rig log of this brake); `source` names the log. The branches must be non-decreasing on
    /// the unit's `[0, current_max_A]`.
    pub fn set_identified_branches(
        &mut self,
        unit: u32,
        branches: &InverseModel,
        source: &str,
    ) -> Result<(), SimError> {
        let (name, count) = (self.name.clone(), self.units.len());
        let target = self
            .units
            .iter_mut()
            .find(|u| u.unit == unit)
            .ok_or_else(|| no_unit(&name, unit, count))?;
        let trimmed = |branch| {
            let c = branches.branch(branch).coefficients();
            let used = c.iter().rposition(|v| v.abs() > 0.0).map_or(1, |p| p + 1);
            c[..used].to_vec()
        };
        target.hysteresis = Hysteresis::PolynomialBranches {
            rising: trimmed(mrbrake_control::Branch::Rising),
            falling: trimmed(mrbrake_control::Branch::Falling),
            source: format!("identified: {source}"),
        };
        self.provenance.amended.push(format!("hysteresis of unit {unit}: identified, {source}"));
        self.check("(with identified branches)")
    }
}

/// `Ok` for a finite `value` in `[min, max]`, else `(field, message)`.
fn in_range(field: &str, value: f64, min: f64, max: f64) -> Result<(), (String, String)> {
    if value.is_finite() && value >= min && value <= max {
        Ok(())
    } else {
        Err((field.into(), format!("{value} is outside [{min}, {max}]")))
    }
}

impl UnitModel {
    /// Checks the unit's values; `Err((field, message))` for the first bad one.
    fn validate(&self) -> Result<(), (String, String)> {
        in_range("current_max_A", self.current_max_a, f64::MIN_POSITIVE, CURRENT_LIMIT_A)?;
        if let Some(j) = self.rotor_inertia_kg_m2 {
            in_range("rotor_inertia_kg_m2", j, f64::MIN_POSITIVE, ROTOR_INERTIA_LIMIT_KG_M2)?;
        }
        self.static_curve
            .validate(self.current_max_a)
            .map_err(|(f, m)| (format!("static_curve.{f}"), m))?;
        let o = &self.off_state;
        in_range("off_state.viscous_Nm_s_per_rad", o.viscous_nm_s_per_rad, 0.0, 100.0)?;
        in_range("off_state.reference_speed_rad_s", o.reference_speed_rad_s, 1e-9, 1e6)?;
        in_range("off_state.seal_friction_Nm", o.seal_friction_nm, 0.0, 1e4)?;
        if let Hysteresis::PolynomialBranches { rising, falling, .. } = &self.hysteresis {
            InverseModel::new(rising, falling, 0.0, self.current_max_a).map_err(|e| {
                (
                    "hysteresis".into(),
                    format!(
                        "{e} (1 to 8 finite coefficients, non-decreasing on [0, current_max_A])"
                    ),
                )
            })?;
        }
        if let Some(table) = self.hysteresis.everett() {
            table.check(self.current_max_a).map_err(|(f, m)| (format!("hysteresis.{f}"), m))?;
        }
        if let Some(d) = &self.dynamics {
            d.transfer_function().map_err(|e| ("dynamics".into(), e.to_string()))?;
        }
        if let Some(t) = &self.thermal {
            in_range("thermal.hot_temperature_C", t.hot_temperature_c, -273.15, 1000.0)?;
            in_range("thermal.hot_resistance_ohm", t.hot_resistance_ohm, 1e-9, 1e9)?;
            in_range("thermal.continuous_current_A", t.continuous_current_a, 0.0, CURRENT_LIMIT_A)?;
        }
        Ok(())
    }

    /// The rising and falling branches the simulators run (see the module docs).
    pub fn branches(&self) -> Result<UnitBranches, SimError> {
        let model = |rising: &[f64], falling: &[f64]| {
            InverseModel::new(rising, falling, 0.0, self.current_max_a)
                .map_err(|source| SimError::Control { what: "brake model branches", source })
        };
        match &self.hysteresis {
            Hysteresis::PolynomialBranches { rising, falling, .. } => {
                Ok(UnitBranches { model: model(rising, falling)?, fit: None })
            }
            Hysteresis::None { .. } => {
                let (coefficients, fit) = self.static_curve.fit(self.off_state.seal_friction_nm)?;
                Ok(UnitBranches { model: model(&coefficients, &coefficients)?, fit: Some(fit) })
            }
            Hysteresis::Preisach { levels_a, rising_nm, everett_nm, .. } => {
                let table = crate::rig::everett::EverettTable {
                    levels_a: levels_a.clone(),
                    rising_nm: rising_nm.clone(),
                    everett_nm: everett_nm.clone(),
                };
                let branch = |torque_nm: Vec<f64>, what: &str| {
                    let curve =
                        StaticCurve { current_a: levels_a.clone(), torque_nm, source: what.into() };
                    curve.fit(self.off_state.seal_friction_nm)
                };
                let (rising, fit_up) = branch(rising_nm.clone(), "rising")?;
                let (falling, fit_down) = branch(table.falling_nm(), "falling")?;
                let fit =
                    if fit_down.max_error_nm > fit_up.max_error_nm { fit_down } else { fit_up };
                Ok(UnitBranches { model: model(&rising, &falling)?, fit: Some(fit) })
            }
        }
    }

    /// Whether the off-state terms are added to the branches (for an anhysteretic curve and a
    /// Preisach table of yield torques: identified branches already contain them).
    pub fn adds_off_state(&self) -> bool {
        matches!(self.hysteresis, Hysteresis::None { .. } | Hysteresis::Preisach { .. })
    }
}

impl Dynamics {
    /// The transfer function (checked: proper, finite, positive DC gain, stable: every pole in
    /// the open left half-plane, since a brake's torque settles after a current step).
    pub fn transfer_function(&self) -> Result<TransferFunction, SimError> {
        let tf = TransferFunction::new(self.numerator.clone(), self.denominator.clone())
            .map_err(|source| SimError::Model { what: "brake model dynamics", source })?;
        let gain = tf.dc_gain();
        if !(gain.is_finite() && gain > 0.0) {
            return Err(FieldError::new("numerator", "the DC gain")
                .with_value(gain)
                .with_allowed("finite, > 0")
                .into());
        }
        let poles = tf
            .poles()
            .map_err(|source| SimError::Model { what: "brake model dynamics", source })?;
        if let Some(p) = poles.iter().find(|p| p.re >= 0.0 || p.re.is_nan()) {
            return Err(FieldError::new(
                "denominator",
                format!("an unstable brake (denominator {:?})", self.denominator),
            )
            .with_value(format!("a pole at {:.6e}{:+.6e}j rad/s", p.re, p.im))
            .with_allowed("poles in the left half-plane (negative real parts)")
            .into());
        }
        Ok(tf)
    }
}

impl StaticCurve {
    /// Checks the samples against the unit's current range.
    fn validate(&self, current_max_a: f64) -> Result<(), (String, String)> {
        let (i, t) = (&self.current_a, &self.torque_nm);
        if i.len() < 2 || i.len() != t.len() || i.len() > MAX_CURVE_POINTS {
            let msg = format!(
                "{} currents and {} torques; need ≥ 2 of each, as many, at most {MAX_CURVE_POINTS}",
                i.len(),
                t.len()
            );
            return Err(("current_A".into(), msg));
        }
        if let Some(k) = i.iter().chain(t).position(|v| !v.is_finite()) {
            let field = if k < i.len() {
                format!("current_A[{k}]")
            } else {
                format!("torque_Nm[{}]", k - i.len())
            };
            return Err((field, "must be a finite number".into()));
        }
        let tol = 1e-9 * current_max_a;
        if i[0].abs() > tol || (i[i.len() - 1] - current_max_a).abs() > tol {
            let msg = format!(
                "must run from 0 to current_max_A = {current_max_a} A, runs {}..{}",
                i[0],
                i[i.len() - 1]
            );
            return Err(("current_A".into(), msg));
        }
        if let Some(k) = i.windows(2).position(|w| w[1] <= w[0]) {
            return Err((
                format!("current_A[{}]", k + 1),
                "currents must be strictly increasing".into(),
            ));
        }
        if t[0] < 0.0 {
            return Err(("torque_Nm[0]".into(), format!("{} must be ≥ 0", t[0])));
        }
        if let Some(k) = t.windows(2).position(|w| w[1] < w[0]) {
            let msg =
                format!("{} < {}: the torque must not decrease with the current", t[k + 1], t[k]);
            return Err((format!("torque_Nm[{}]", k + 1), msg));
        }
        Ok(())
    }

    /// The lowest-degree (3…7) non-decreasing least-squares polynomial, moved to pass through the
    /// curve's first point (0 A), within [`STATIC_FIT_TOLERANCE`] of the curve's span, shifted by
    /// `offset_nm`; if none is within the tolerance, the closest non-decreasing one.
    fn fit(&self, offset_nm: f64) -> Result<(Vec<f64>, StaticFit), SimError> {
        let (i, t) = (&self.current_a, &self.torque_nm);
        let span = t[t.len() - 1] - t[0];
        let i_max = i[i.len() - 1];
        let max_degree = mrbrake_control::MAX_DEGREE.min(i.len() - 1);
        let mut best: Option<(Vec<f64>, StaticFit)> = None;
        for degree in max_degree.min(3)..=max_degree {
            let mut c = polynomial::fit(i, t, degree)?.coefficients;
            // Pinned at 0 A: the off-state torque (what the hand feels in free motion) is the
            // curve's, not the fit's error there.
            c[0] += offset_nm + (t[0] - c[0]);
            let Some(candidate) = mrbrake_control::BranchPolynomial::from_ascending(&c) else {
                continue;
            };
            if !candidate.is_non_decreasing(0.0, i_max, 512) {
                continue;
            }
            let max_error_nm = i
                .iter()
                .zip(t)
                .map(|(x, y)| (candidate.torque_nm(*x) - offset_nm - y).abs())
                .fold(0.0, f64::max);
            let fit = StaticFit { degree, max_error_nm };
            if max_error_nm <= STATIC_FIT_TOLERANCE * span {
                return Ok((c, fit));
            }
            if best.as_ref().is_none_or(|(_, b)| max_error_nm < b.max_error_nm) {
                best = Some((c, fit));
            }
        }
        best.ok_or_else(|| {
            SimError::from(FieldError::new(
                "static_curve",
                "brake model: no non-decreasing polynomial of degree ≤ 7 fits the static curve",
            ))
        })
    }
}

#[cfg(test)]
mod tests {
    use super::prototype::haptic_prototype;
    use super::*;
    use mrbrake_control::Branch;

    /// A unit with an anhysteretic saturating curve `T = 4 (1 − e^{−i})` on 0–2 A.
    fn saturating_unit() -> UnitModel {
        let mut unit = haptic_prototype().units[0].clone();
        let current_a: Vec<f64> = (0..=20).map(|k| 0.1 * k as f64).collect();
        unit.static_curve.torque_nm = current_a.iter().map(|i| 4.0 * (1.0 - (-i).exp())).collect();
        unit.static_curve.current_a = current_a;
        unit.hysteresis = Hysteresis::None { note: "test".into() };
        unit.off_state.seal_friction_nm = 0.05;
        unit
    }

    #[test]
    fn an_anhysteretic_curve_becomes_one_monotone_branch_within_tolerance() {
        let unit = saturating_unit();
        let b = unit.branches().unwrap();
        let fit = b.fit.unwrap();
        let span = 4.0 * (1.0 - (-2.0f64).exp());
        assert!(fit.max_error_nm <= STATIC_FIT_TOLERANCE * span, "{fit:?}");
        assert!((3..=7).contains(&fit.degree));
        for k in 0..=40 {
            let i = 0.05 * k as f64;
            let exact = 4.0 * (1.0 - (-i).exp()) + 0.05;
            let rising = b.model.torque_nm(Branch::Rising, i);
            assert!((rising - exact).abs() <= 1.5 * STATIC_FIT_TOLERANCE * span, "{i} A");
            assert!((b.model.torque_nm(Branch::Falling, i) - rising).abs() < 1e-15);
        }
        assert!(unit.adds_off_state());
    }

    #[test]
    fn reader_refuses_foreign_old_and_invalid_files_naming_the_field() {
        let good = haptic_prototype().to_json();
        assert!(BrakeModel::from_json("m.json", &good).is_ok());
        let err = |text: &str| BrakeModel::from_json("m.json", text).unwrap_err().to_string();
        let foreign = good.replace("\"mrbrake-brake-model\"", "\"other\"");
        assert!(err(&foreign).contains("foreign schema 'other'"), "{}", err(&foreign));
        let newer = good.replace("\"schema_version\": 3", "\"schema_version\": 4");
        assert!(err(&newer).contains("schema_version"));
        let units = good.replacen("\"torque_Nm\"", "\"torque_kNm\"", 1);
        assert!(err(&units).contains("torque_kNm"), "{}", err(&units));
        let mut m = haptic_prototype();
        m.units[0].static_curve.current_a[3] = m.units[0].static_curve.current_a[2];
        let e = BrakeModel::from_json("m.json", &m.to_json()).unwrap_err();
        assert!(e.to_string().contains("units[0].static_curve.current_A[3]"), "{e}");
        assert!(mrbrake_error::Kind::is_input_error(&e));
        let mut m = haptic_prototype();
        m.units[1].unit = 3;
        assert!(
            BrakeModel::from_json("m.json", &m.to_json())
                .unwrap_err()
                .to_string()
                .contains("units[1].unit")
        );
        let mut m = haptic_prototype();
        m.units[0].dynamics.as_mut().unwrap().numerator = vec![1.0, 0.0, 0.0, 0.0];
        assert!(
            BrakeModel::from_json("m.json", &m.to_json())
                .unwrap_err()
                .to_string()
                .contains("units[0].dynamics")
        );
        // An unstable lag (a two-pole fit with a negative s² coefficient: one pole at +1.5e5
        // rad/s, as an unconstrained fit beyond its band can return) is refused, naming the field.
        let mut m = haptic_prototype();
        m.units[0].dynamics.as_mut().unwrap().denominator = vec![-6.3e-8, 0.0095, 1.0];
        let e = BrakeModel::from_json("m.json", &m.to_json()).unwrap_err();
        assert!(e.to_string().contains("units[0].dynamics"), "{e}");
        assert!(e.to_string().contains("left half-plane"), "{e}");
        assert!(mrbrake_error::Kind::is_input_error(&e));
    }

    #[test]
    fn identified_branches_replace_the_hysteresis_and_are_used_as_measured() {
        let mut m = haptic_prototype();
        m.units[0].hysteresis = Hysteresis::None { note: "test".into() };
        let identified = InverseModel::new(&[0.1, 1.5, 0.2], &[0.2, 1.6, 0.1], 0.0, 2.0).unwrap();
        m.set_identified_branches(1, &identified, "log.csv").unwrap();
        let b = m.units[0].branches().unwrap();
        assert_eq!(b.model, identified);
        assert!(b.fit.is_none() && !m.units[0].adds_off_state());
        // Non-decreasing on the log's 0–1 A, decreasing beyond 1.25 A: refused for a 2 A unit.
        let falling = InverseModel::new(&[0.1, 1.5], &[0.2, 2.0, -0.8], 0.0, 1.0).unwrap();
        let e = m.set_identified_branches(2, &falling, "bad.csv").unwrap_err().to_string();
        assert!(e.contains("units[1].hysteresis"), "{e}");
        assert!(m.set_identified_branches(3, &identified, "x").is_err());
    }

    #[test]
    fn version_1_files_are_read_without_a_rotor_inertia_and_refuse_its_field() {
        let mut v2: serde_json::Value =
            serde_json::from_str(&haptic_prototype().to_json()).unwrap();
        v2["schema_version"] = serde_json::json!(1);
        let with_field = v2.to_string();
        let e = BrakeModel::from_json("old.json", &with_field).unwrap_err().to_string();
        assert!(e.contains("units[0].rotor_inertia_kg_m2") && e.contains("version-2"), "{e}");
        for unit in v2["units"].as_array_mut().unwrap() {
            unit.as_object_mut().unwrap().remove("rotor_inertia_kg_m2");
        }
        let old = BrakeModel::from_json("old.json", &v2.to_string()).unwrap();
        assert_eq!(old.schema_version, 1);
        assert!(old.units.iter().all(|u| u.rotor_inertia_kg_m2.is_none()));
        let mut bad = haptic_prototype();
        bad.units[1].rotor_inertia_kg_m2 = Some(-1e-6);
        let e = BrakeModel::from_json("m.json", &bad.to_json()).unwrap_err().to_string();
        assert!(e.contains("units[1].rotor_inertia_kg_m2"), "{e}");
    }

    /// The prototype with a Preisach hysteresis on `levels` levels, identified from the FORCs
    /// of the rig's branch + prior Preisach model (the prototype-like loop).
    fn preisach_prototype(levels: usize) -> BrakeModel {
        use crate::rig::everett::EverettTable;
        use crate::rig::preisach::{HysteresisConfig, HysteresisKind, PreisachHysteresis};
        let config = HysteresisConfig { model: HysteresisKind::Preisach, ..Default::default() };
        let b = crate::rig::config::BrakeConfig::default();
        let mut p = PreisachHysteresis::new(&config, &b.rising, &b.falling, 2.0).unwrap();
        let level = |k: usize| 2.0 * k as f64 / levels as f64;
        let forcs: Vec<Vec<f64>> = (0..=levels)
            .map(|k| {
                p.settle(0.0);
                let mut forc: Vec<f64> = (0..=k).map(|a| p.torque_nm(level(a))).collect();
                for j in (0..k).rev() {
                    forc[j] = p.torque_nm(level(j));
                }
                forc
            })
            .collect();
        let levels_a: Vec<f64> = (0..=levels).map(level).collect();
        let t = EverettTable::from_forcs(&levels_a, &forcs).unwrap().table;
        let mut m = haptic_prototype();
        for unit in &mut m.units {
            unit.current_max_a = 2.0;
            unit.off_state.seal_friction_nm = 0.0;
            unit.hysteresis = Hysteresis::Preisach {
                levels_a: t.levels_a.clone(),
                rising_nm: t.rising_nm.clone(),
                everett_nm: t.everett_nm.clone(),
                source: "test".into(),
            };
        }
        m
    }

    #[test]
    fn a_preisach_model_round_trips_and_its_branches_are_its_major_loop() {
        let m = preisach_prototype(12);
        let back = BrakeModel::from_json("p.json", &m.to_json()).unwrap();
        // JSON keeps every value to the last bit or so (serde_json's float parsing).
        let (a, b) =
            (m.units[0].hysteresis.everett().unwrap(), back.units[0].hysteresis.everett().unwrap());
        let close = |x: &[f64], y: &[f64]| {
            x.len() == y.len()
                && x.iter().zip(y).all(|(p, q)| (p - q).abs() <= 1e-15 * p.abs().max(1.0))
        };
        assert!(close(&a.levels_a, &b.levels_a) && close(&a.rising_nm, &b.rising_nm));
        assert!(a.everett_nm.iter().zip(&b.everett_nm).all(|(x, y)| close(x, y)));
        assert_eq!(back.units[1].hysteresis.everett().map(|t| t.levels()), Some(12));
        let unit = &back.units[0];
        assert!(unit.adds_off_state());
        let b = unit.branches().unwrap();
        let table = unit.hysteresis.everett().unwrap();
        let (up, down) = (table.rising_nm.clone(), table.falling_nm());
        let span = up[12] - up[0];
        for (k, i) in table.levels_a.iter().enumerate() {
            let rising = b.model.torque_nm(Branch::Rising, *i);
            let falling = b.model.torque_nm(Branch::Falling, *i);
            assert!((rising - up[k]).abs() <= STATIC_FIT_TOLERANCE * span, "{i} A");
            assert!((falling - down[k]).abs() <= STATIC_FIT_TOLERANCE * span, "{i} A");
        }
        // The rig: the plant runs the table (with the seal friction), the controller the fit.
        let mut config = crate::rig::RigConfig::default();
        let notes = apply::apply_to_rig(&back, 1, &mut config).unwrap();
        assert_eq!(config.brake.everett.as_ref().map(|t| t.levels()), Some(12));
        assert!(notes.iter().any(|n| n.contains("Preisach hysteresis (12 levels)")), "{notes:?}");
    }

    #[test]
    fn bad_preisach_tables_are_refused_naming_the_field() {
        let field = |m: &BrakeModel| m.validate().unwrap_err().0;
        /// Edits `(rising_Nm, everett_Nm, levels_A)`.
        type Edit = dyn Fn(&mut Vec<f64>, &mut Vec<Vec<f64>>, &mut Vec<f64>);
        let set = |edit: &Edit| {
            let mut m = preisach_prototype(6);
            if let Hysteresis::Preisach { levels_a, rising_nm, everett_nm, .. } =
                &mut m.units[0].hysteresis
            {
                edit(rising_nm, everett_nm, levels_a);
            }
            m
        };
        let nan = set(&|_, e, _| e[3][1] = f64::NAN);
        assert_eq!(field(&nan), "units[0].hysteresis.everett_Nm[3][1]");
        let short = set(&|_, e, _| {
            e[4].pop();
        });
        assert_eq!(field(&short), "units[0].hysteresis.everett_Nm[4]");
        let rows = set(&|_, e, _| {
            e.pop();
        });
        assert_eq!(field(&rows), "units[0].hysteresis.everett_Nm");
        // E(4, 0) far below E(3, 0): a negative weight, the Everett function not monotone.
        let dip = set(&|_, e, _| e[4][0] = 0.0);
        assert!(field(&dip).starts_with("units[0].hysteresis.everett_Nm[4]"), "{}", field(&dip));
        let uneven = set(&|_, _, l| l[2] = 0.5);
        assert_eq!(field(&uneven), "units[0].hysteresis.levels_A[2]");
        let wrong_end = set(&|_, _, l| l.iter_mut().for_each(|v| *v *= 0.5));
        assert_eq!(field(&wrong_end), "units[0].hysteresis.levels_A");
        let negative = set(&|r, _, _| r[0] = -1.0);
        assert_eq!(field(&negative), "units[0].hysteresis.rising_Nm[0]");
        // Refused on reading too, naming the file; and a version-2 file may not carry the kind.
        let e = BrakeModel::from_json("p.json", &nan.to_json()).unwrap_err();
        assert!(mrbrake_error::Kind::is_input_error(&e), "{e}");
        let old = preisach_prototype(6)
            .to_json()
            .replace("\"schema_version\": 3", "\"schema_version\": 2");
        let e = BrakeModel::from_json("old.json", &old).unwrap_err().to_string();
        assert!(e.contains("units[0].hysteresis.kind") && e.contains("version-3"), "{e}");
    }

    #[test]
    fn a_single_unit_brake_serves_both_directions() {
        let mut m = haptic_prototype();
        m.units.truncate(1);
        assert_eq!(m.unit(2).unwrap(), &m.units[0]);
        assert!(m.unit(3).is_err());
    }
}
