//! The uncertain inputs of a study: a TOML file next to the spec (`--inputs FILE`), kept apart from
//! the spec so that the spec stays one design (its key, every command's reading) and the same
//! declarations serve `uncertainty` and `calibrate`.
//!
//! ```toml
//! [[input]]
//! path = "fluid.yield_stress_scale"   # any numeric spec field (as sweep variables are named)
//! distribution = "normal"             # normal | uniform | triangular | log-normal
//! mean = 1.0
//! std = 0.1
//! truncate = [0.7, 1.3]               # optional: [lower, upper], values or quantities
//!
//! [[input]]
//! path = "drum.gap"
//! distribution = "uniform"
//! lower = "0.45mm"                    # a quantity with its unit, or a bare SI number
//! upper = "0.55mm"
//! ```
//!
//! Parameters by law: normal `mean`, `std`; uniform `lower`, `upper`; triangular `lower`, `mode`,
//! `upper`; log-normal `mean`, `std` (of the variable itself, not of its logarithm). Every value is
//! read as the field reads it (a length with its unit, a bare SI number). A law whose support
//! (after truncation) leaves the field's valid range — a normal without `truncate` on a field that
//! must be positive, a fill fraction above 1 — is refused: each sample must be a valid brake.
//! Errors name the file and the key (`input[2].std`).

use serde::Deserialize;

use mrbrake_uq::distribution::{Distribution, Law};

use crate::ExploreError;
use crate::variable::{Variable, VariableKind, resolve};

/// Most uncertain inputs of one study (a sanity bound; the Sobol' generator has more dimensions).
pub const MAX_INPUTS: usize = 32;

/// One declared uncertain input: the spec field and its law (SI).
#[derive(Debug, Clone)]
pub struct UncertainInput {
    /// The field's dotted path (`drum.gap`).
    pub path: String,
    /// The law, in the field's SI unit.
    pub distribution: Distribution,
    /// The variable that writes a value into a spec.
    pub variable: Variable,
}

/// The declarations of one file.
#[derive(Debug, Clone)]
pub struct Declarations {
    /// The file they were read from (for messages).
    pub origin: String,
    /// The inputs, in file order.
    pub inputs: Vec<UncertainInput>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct RawFile {
    #[serde(default)]
    input: Vec<RawInput>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct RawInput {
    path: String,
    distribution: String,
    mean: Option<toml::Value>,
    std: Option<toml::Value>,
    lower: Option<toml::Value>,
    upper: Option<toml::Value>,
    mode: Option<toml::Value>,
    truncate: Option<[toml::Value; 2]>,
}

impl Declarations {
    /// Reads declarations from TOML `text`; `origin` names the file; `is_drum` resolves thesis
    /// symbols as the spec's configuration does.
    pub fn from_toml_str(text: &str, origin: &str, is_drum: bool) -> Result<Self, ExploreError> {
        let raw: RawFile = toml::from_str(text)
            .map_err(|e| ExploreError::input("", e.to_string().trim_end()).in_file(origin))?;
        let bad = |key: String, why: String| ExploreError::input(key, why).in_file(origin);
        if raw.input.is_empty() {
            return Err(bad("input".into(), "declares no [[input]]".into()));
        }
        if raw.input.len() > MAX_INPUTS {
            return Err(bad("input".into(), format!("at most {MAX_INPUTS} inputs")));
        }
        let mut inputs: Vec<UncertainInput> = Vec::with_capacity(raw.input.len());
        for (k, input) in raw.input.iter().enumerate() {
            let key = |field: &str| format!("input[{}].{field}", k + 1);
            let variable =
                resolve(&input.path, is_drum).map_err(|e| bad(key("path"), e.to_string()))?;
            if variable.is_categorical() {
                return Err(bad(
                    key("path"),
                    "a material is not a number; name a numeric field".into(),
                ));
            }
            if inputs.iter().any(|i| i.variable.path() == variable.path()) {
                return Err(bad(key("path"), format!("{} is declared twice", variable.path())));
            }
            let distribution =
                input.distribution(&variable).map_err(|(field, why)| bad(key(field), why))?;
            check_support(&variable, &distribution).map_err(|why| bad(key("distribution"), why))?;
            inputs.push(UncertainInput {
                path: variable.path().to_string(),
                distribution,
                variable,
            });
        }
        Ok(Self { origin: origin.to_string(), inputs })
    }

    /// Reads a declarations file.
    pub fn from_path(path: &std::path::Path, is_drum: bool) -> Result<Self, ExploreError> {
        let origin = path.display().to_string();
        let text = mrbrake_error::read::text(path, mrbrake_error::read::SETTINGS)
            .map_err(|e| ExploreError::input("", format!("cannot read: {e}")).in_file(&origin))?;
        Self::from_toml_str(&text, &origin, is_drum)
    }

    /// The inputs' laws, in order.
    pub fn distributions(&self) -> Vec<Distribution> {
        self.inputs.iter().map(|i| i.distribution).collect()
    }
}

impl RawInput {
    /// The law, or the key at fault and why.
    fn distribution(&self, variable: &Variable) -> Result<Distribution, (&'static str, String)> {
        let value = |name: &'static str,
                     v: &Option<toml::Value>|
         -> Result<f64, (&'static str, String)> {
            let v =
                v.as_ref().ok_or((name, format!("required for a {} law", self.distribution)))?;
            quantity(variable, v).map_err(|why| (name, why))
        };
        let law = match self.distribution.trim() {
            "normal" => {
                Law::Normal { mean: value("mean", &self.mean)?, std_dev: value("std", &self.std)? }
            }
            "uniform" => Law::Uniform {
                lower: value("lower", &self.lower)?,
                upper: value("upper", &self.upper)?,
            },
            "triangular" => Law::Triangular {
                lower: value("lower", &self.lower)?,
                mode: value("mode", &self.mode)?,
                upper: value("upper", &self.upper)?,
            },
            "log-normal" | "lognormal" => {
                let (mean, std) = (value("mean", &self.mean)?, value("std", &self.std)?);
                return with_truncation(
                    Distribution::log_normal_from_mean_std(mean, std)
                        .map_err(|e| ("std", e.to_string()))?,
                    self.truncation(variable)?,
                );
            }
            other => {
                return Err((
                    "distribution",
                    format!("'{other}' is not a law: normal, uniform, triangular or log-normal"),
                ));
            }
        };
        let truncation = self.truncation(variable)?;
        Distribution::new(law, truncation).map_err(|e| {
            let key = if e.to_string().contains("trunc") { "truncate" } else { "distribution" };
            (key, e.to_string())
        })
    }

    fn truncation(
        &self,
        variable: &Variable,
    ) -> Result<Option<(f64, f64)>, (&'static str, String)> {
        let Some([lower, upper]) = &self.truncate else { return Ok(None) };
        let lower = quantity(variable, lower).map_err(|why| ("truncate", why))?;
        let upper = quantity(variable, upper).map_err(|why| ("truncate", why))?;
        Ok(Some((lower, upper)))
    }
}

fn with_truncation(
    distribution: Distribution,
    truncation: Option<(f64, f64)>,
) -> Result<Distribution, (&'static str, String)> {
    match truncation {
        None => Ok(distribution),
        Some((lower, upper)) => {
            distribution.truncated(lower, upper).map_err(|e| ("truncate", e.to_string()))
        }
    }
}

/// A parameter value: a number (SI) or a quantity string the field reads.
fn quantity(variable: &Variable, value: &toml::Value) -> Result<f64, String> {
    match value {
        toml::Value::Float(x) => Ok(*x),
        toml::Value::Integer(i) => Ok(*i as f64),
        toml::Value::String(text) => variable.parse_value(text).map_err(|e| e.to_string()),
        other => Err(format!("{other} is not a number or a quantity")),
    }
}

/// The law's support (after truncation) inside the field's valid range.
fn check_support(variable: &Variable, distribution: &Distribution) -> Result<(), String> {
    let VariableKind::Numeric(field) = &variable.kind else { return Ok(()) };
    let (low, high) = distribution.support();
    if field.bounds.contains(low) && field.bounds.contains(high) {
        return Ok(());
    }
    Err(format!(
        "its values span [{low}, {high}], outside {}'s valid range {}; truncate it \
         (truncate = [lower, upper]) within that range",
        field.path,
        field.bounds.describe(field.quantity.unit())
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn read(text: &str) -> Result<Declarations, ExploreError> {
        Declarations::from_toml_str(text, "u.toml", true)
    }

    #[test]
    fn laws_read_with_units_and_truncation() {
        let d = read(
            "[[input]]\npath = \"drum.gap\"\ndistribution = \"uniform\"\nlower = \"0.45mm\"\n\
             upper = \"0.55mm\"\n[[input]]\npath = \"fluid.fill_fraction\"\n\
             distribution = \"normal\"\nmean = 0.9\nstd = 0.05\ntruncate = [0.7, 1.0]\n",
        )
        .unwrap();
        assert_eq!(d.inputs.len(), 2);
        let (low, high) = d.inputs[0].distribution.support();
        assert!((low - 0.45e-3).abs() < 1e-15 && (high - 0.55e-3).abs() < 1e-15);
        assert_eq!(d.inputs[1].distribution.support(), (0.7, 1.0));
    }

    #[test]
    fn bad_declarations_name_the_file_and_key() {
        let cases = [
            (
                "[[input]]\npath = \"drum.gapp\"\ndistribution = \"uniform\"\nlower = 1\nupper = 2\n",
                "input[1].path",
            ),
            (
                "[[input]]\npath = \"drum.gap\"\ndistribution = \"normal\"\nmean = \"0.5mm\"\nstd = -1\n",
                "input[1].",
            ),
            (
                "[[input]]\npath = \"fluid.fill_fraction\"\ndistribution = \"uniform\"\nlower = 0.8\nupper = 1.2\n",
                "input[1].distribution",
            ),
            (
                "[[input]]\npath = \"drum.gap\"\ndistribution = \"normal\"\nmean = \"0.5mm\"\nstd = \"0.01mm\"\n",
                "input[1].distribution",
            ),
            (
                "[[input]]\npath = \"drum.gap\"\ndistribution = \"cauchy\"\n",
                "input[1].distribution",
            ),
        ];
        for (text, key) in cases {
            let e = read(text).unwrap_err().to_string();
            assert!(e.starts_with("u.toml: ") && e.contains(key), "{e}");
        }
    }
}
