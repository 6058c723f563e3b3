//! One design of a study: a base spec with variables set, and its canonical key.
//!
//! Brief overview: a [`DesignSpace`] holds the base spec (as a TOML table, after fixed overrides),
//! the study's [`Variable`]s and the [`EvaluationSettings`]; a material variable gets its levels
//! with [`DesignSpace::set_levels`]. [`DesignSpace::design`] sets the variables to a point (SI
//! values, a material's level index) and returns a [`Design`]: the spec text (ready to analyse),
//! the parsed spec or the reason it is invalid, the variables' values as a record keeps them (a
//! material by name), and the key under which the results store keeps it.
//!
//! # The key
//! The SHA-256 (FIPS 180-4) of a canonical JSON document holding everything the result depends on:
//! * the parsed spec with every length and current in SI (so `"25mm"` and `0.025` are one design)
//!   and without its `name` (a label, not a property); an optional field left out (e.g.
//!   `materials.bobbin`, the non-magnetic material by default) is not written, so a spec that
//!   does not name it keeps the key it had before the field existed;
//! * a signature of every material the spec names: its B-H curve (ν(B²) at 48 flux densities), its
//!   density, and for the fluid τ_y(B) at the same flux densities and the viscosity. The signature
//!   samples the curves rather than hashing the data files, so it also changes when the
//!   interpolation code changes the curve;
//! * the [`EvaluationSettings`] (mesh level, speed, friction, temperature, convection) and the
//!   settings of the dynamics, heat and haptic analyses the study runs that differ from their
//!   defaults — not the
//!   metrics a study asks for nor its constraints, so a study asking for more metrics finds the
//!   stored designs and completes them ([`crate::metrics`]). (Before, a study asking for such
//!   metrics keyed its designs with its metric list and constraints too: those records are not
//!   found by the current keys and are evaluated again; static-only keys are unchanged.)
//! * [`MODEL_REVISION`] and this crate's version.
//!
//! JSON objects are written with sorted keys and floats in Rust's shortest round-trip form, so the
//! document, and hence the key, is the same on every machine.

use std::sync::Arc;

use mrbrake_design::DesignError;
use mrbrake_design::spec::BrakeSpec;
use mrbrake_store::VariableValue;
use serde_json::{Value, json};
use sha2::{Digest, Sha256};

use crate::ExploreError;
use crate::evaluate::EvaluationSettings;
use crate::variable::{Variable, apply_override};

/// Bumped whenever the analysis would give a different answer for the same inputs (a new torque
/// model, a mesher change): stored results of older revisions then no longer match any key.
pub const MODEL_REVISION: u32 = 3;

/// The solver version written with every record.
pub fn solver_version() -> String {
    format!("mrbrake {} (model revision {MODEL_REVISION})", env!("CARGO_PKG_VERSION"))
}

/// The space a study explores: a base spec and the variables it varies.
#[derive(Debug, Clone)]
pub struct DesignSpace {
    base: toml::Table,
    base_name: String,
    is_drum: bool,
    variables: Vec<Variable>,
    settings: EvaluationSettings,
}

/// One point of a [`DesignSpace`].
#[derive(Debug, Clone)]
pub struct Design {
    /// The variables' values (name, SI value or material), in the space's order.
    pub variables: Vec<(String, VariableValue)>,
    /// The full spec as TOML (lengths in metres), ready for `mrbrake analyze`.
    pub spec_toml: String,
    /// The parsed and validated spec, or why this point is not a valid brake (the design
    /// crate's error, typed: its invalid fields as a list).
    pub spec: Result<BrakeSpec, Arc<DesignError>>,
    /// The results-store key (64 hex digits).
    pub key: String,
}

impl DesignSpace {
    /// A space over `base_toml` (a spec file's text; `origin` names it in messages) with fixed
    /// `overrides` (`PATH`, `VALUE` pairs, see [`apply_override`]) and the given variables (names
    /// resolved by [`crate::variable::resolve`]).
    pub fn new(
        base_toml: &str,
        origin: &str,
        overrides: &[(String, String)],
        variable_names: &[String],
        settings: EvaluationSettings,
    ) -> Result<Self, ExploreError> {
        settings.check()?;
        // Parse once to learn the configuration and to report a broken base spec early (with its
        // file and line); text the spec reader accepts is a TOML table.
        let spec = BrakeSpec::from_toml_str(base_toml, origin)?;
        let mut base: toml::Table = toml::from_str(base_toml).map_err(internal)?;
        let is_drum = spec.configuration.is_drum();
        for (path, value) in overrides {
            apply_override(&mut base, path, value, is_drum).map_err(|e| {
                // The change's field (its spec path) with the value it was given.
                e.map_field(|f| {
                    let f = if f.value.is_none() { f.with_value(value) } else { f };
                    f.in_file(origin, None)
                })
            })?;
        }
        let mut variables = Vec::with_capacity(variable_names.len());
        for name in variable_names {
            let variable = crate::variable::resolve(name, is_drum)?;
            if variables.iter().any(|v: &Variable| v.path() == variable.path()) {
                let message = format!("variable ({}): given twice", variable.path());
                return Err(ExploreError::input(name, message));
            }
            variables.push(variable);
        }
        Ok(Self { base, base_name: spec.name, is_drum, variables, settings })
    }

    /// Gives the material variable at `index` its levels (library materials that suit the part:
    /// [`Variable::with_levels`]); its values are then the levels' indices.
    pub fn set_levels(&mut self, index: usize, levels: &[String]) -> Result<(), ExploreError> {
        let variable = self.variables.get(index).ok_or_else(|| {
            ExploreError::Internal(format!(
                "no variable {index} in a space of {}",
                self.variables.len()
            ))
        })?;
        self.variables[index] = variable.clone().with_levels(levels)?;
        Ok(())
    }

    /// The variables.
    pub fn variables(&self) -> &[Variable] {
        &self.variables
    }

    /// The evaluation settings.
    pub fn settings(&self) -> &EvaluationSettings {
        &self.settings
    }

    /// True when the base spec is a drum brake (symbols resolve to drum fields).
    pub fn is_drum(&self) -> bool {
        self.is_drum
    }

    /// The base design itself (no variable set): the reference a study compares with.
    pub fn base_design(&self) -> Result<Design, ExploreError> {
        self.build(&[], self.base.clone(), self.base_name.clone())
    }

    /// The design at `values` (SI, one per variable, in order).
    pub fn design(&self, values: &[f64]) -> Result<Design, ExploreError> {
        if values.len() != self.variables.len() {
            let e =
                mrbrake_error::FieldError::new("values", "one value per variable of the design")
                    .with_value(values.len())
                    .with_allowed(self.variables.len().to_string());
            return Err(e.into());
        }
        let mut table = self.base.clone();
        let mut named = Vec::with_capacity(values.len());
        let mut label = Vec::with_capacity(values.len());
        for (variable, &value) in self.variables.iter().zip(values) {
            variable.set(&mut table, value)?;
            named.push((variable.name.clone(), variable.value(value)?));
            label.push(format!("{}={}", variable.name, variable.display_value(value)));
        }
        let name = if label.is_empty() {
            self.base_name.clone()
        } else {
            format!("{} [{}]", self.base_name, label.join(", "))
        };
        self.build(&named, table, name)
    }

    fn build(
        &self,
        variables: &[(String, VariableValue)],
        mut table: toml::Table,
        name: String,
    ) -> Result<Design, ExploreError> {
        table.insert("name".into(), toml::Value::String(name));
        let text = toml::to_string(&table)
            .map_err(|e| ExploreError::Internal(format!("cannot write a design as TOML: {e}")))?;
        // A generated spec: its errors name fields, not lines of a text the user never wrote.
        let parsed = BrakeSpec::from_generated_toml(&text, "design")
            .and_then(|spec| spec.validate().map(|_| spec))
            .map_err(Arc::new);
        let (spec_toml, key) = match &parsed {
            // A valid design is written and keyed from the parsed spec: SI numbers, canonical.
            Ok(spec) => (spec.to_toml_string()?, design_key(spec, &self.settings)?),
            // An invalid one is keyed by its table (it can't be parsed), so it is stored once too.
            Err(_) => {
                let mut canonical = table.clone();
                canonical.remove("name");
                let document = json!({
                    "invalid_spec": serde_json::to_value(&canonical).map_err(internal)?,
                    "settings": self.settings.canonical(),
                    "solver": solver_version(),
                });
                (text, sha256_hex(&document.to_string()))
            }
        };
        Ok(Design { variables: variables.to_vec(), spec_toml, spec: parsed, key })
    }
}

fn internal(e: impl std::fmt::Display) -> ExploreError {
    ExploreError::Internal(e.to_string())
}

/// The identity of the design `spec` analysed with `options` (`mrbrake analyze`): its design key
/// under the equivalent static study settings and [`MODEL_REVISION`], as a predicted brake model
/// records it ([`mrbrake_device::brake_model::from_analysis`]).
pub fn analysis_identity(
    spec: &BrakeSpec,
    options: &mrbrake_design::analysis::AnalysisOptions,
) -> Result<mrbrake_device::brake_model::DesignIdentity, ExploreError> {
    let settings = EvaluationSettings {
        mesh: options.mesh,
        speed_rad_s: options.speed_rad_s,
        seal_friction_nm: options.seal_friction_nm,
        temperature_c: options.temperature_c,
        order: options.order,
        ..EvaluationSettings::default()
    };
    Ok(mrbrake_device::brake_model::DesignIdentity {
        spec_sha256: design_key(spec, &settings)?,
        model_revision: MODEL_REVISION,
    })
}

/// The key of a valid spec under the given settings (see the module docs).
pub fn design_key(spec: &BrakeSpec, settings: &EvaluationSettings) -> Result<String, ExploreError> {
    let mut spec_value = serde_json::to_value(spec).map_err(internal)?;
    if let Value::Object(map) = &mut spec_value {
        map.remove("name");
    }
    let m = &spec.materials;
    let mut names: Vec<&str> =
        vec![&m.flux_path, &m.non_magnetic, &m.shaft, &m.fluid, &m.coil, &m.surroundings];
    if let Some(spacer) = &m.spacer {
        names.push(spacer);
    }
    if let Some(bobbin) = &m.bobbin {
        names.push(bobbin);
    }
    names.sort_unstable();
    names.dedup();
    let materials: Vec<Value> =
        names.iter().map(|n| material_signature(n)).collect::<Result<_, _>>()?;
    let document = json!({
        "spec": spec_value,
        "materials": materials,
        "settings": settings.canonical(),
        "solver": solver_version(),
    });
    Ok(sha256_hex(&document.to_string()))
}

/// Flux densities at which material curves are sampled for the signature (T): 0.05 … 2.4.
fn signature_flux_densities() -> impl Iterator<Item = f64> {
    (1..=48).map(|k| 0.05 * k as f64)
}

fn material_signature(name: &str) -> Result<Value, ExploreError> {
    let material = mrbrake_materials::library::get(name)?;
    let nu: Vec<f64> =
        signature_flux_densities().map(|b| material.magnetic.nu_of_b2(b * b)).collect();
    let mut signature = json!({
        "name": name.trim().to_ascii_lowercase(),
        "nu_of_b": nu,
        "density": material.density_kg_m3.as_ref().map(|d| d.value),
    });
    if let Some(fluid) = &material.fluid {
        let tau: Vec<f64> = signature_flux_densities().map(|b| fluid.tau_y_of_b(b)).collect();
        signature["tau_y_of_b"] = json!(tau);
        signature["viscosity"] = json!(fluid.viscosity_pa_s());
    }
    Ok(signature)
}

/// Lower-case hex SHA-256 of a text.
pub fn sha256_hex(text: &str) -> String {
    let digest = Sha256::digest(text.as_bytes());
    digest.iter().map(|b| format!("{b:02x}")).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn space(vars: &[&str]) -> DesignSpace {
        DesignSpace::new(
            mrbrake_design::spec::DEFAULT_SPEC_TOML,
            "default",
            &[],
            &vars.iter().map(|s| s.to_string()).collect::<Vec<_>>(),
            EvaluationSettings::default(),
        )
        .unwrap()
    }

    #[test]
    fn the_key_ignores_units_and_names_but_not_values() {
        let s = space(&["g"]);
        let a = s.design(&[0.5e-3]).unwrap();
        let base = s.base_design().unwrap();
        // The thesis spec writes g = "0.5mm"; setting 0.5e-3 m is the same design.
        assert_eq!(a.key, base.key);
        let b = s.design(&[0.6e-3]).unwrap();
        assert_ne!(a.key, b.key);
        assert_eq!(a.key.len(), 64);
    }

    #[test]
    fn settings_change_the_key() {
        let s = space(&[]);
        let coarse = EvaluationSettings {
            mesh: mrbrake_design::mesh_build::MeshLevel::Coarse,
            ..EvaluationSettings::default()
        };
        let s2 = DesignSpace::new(mrbrake_design::spec::DEFAULT_SPEC_TOML, "d", &[], &[], coarse)
            .unwrap();
        assert_ne!(s.base_design().unwrap().key, s2.base_design().unwrap().key);
    }

    #[test]
    fn an_invalid_point_is_a_design_with_a_reason() {
        let s = space(&["drum.gap"]);
        let d = s.design(&[-1e-3]).unwrap();
        let reason = d.spec.unwrap_err();
        let fields = reason.field_errors().expect("an invalid field");
        assert_eq!(fields.errors()[0].field, "drum.gap");
        assert!(fields.errors()[0].file.is_none(), "a generated spec has no file: {reason}");
        assert!(reason.to_string().contains("drum.gap"), "{reason}");
        assert_eq!(d.key.len(), 64);
    }

    #[test]
    fn sha256_matches_the_fips_example() {
        // FIPS 180-4 example "abc".
        assert_eq!(
            sha256_hex("abc"),
            "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad"
        );
    }
}
