//! The crate's error type. Each variant keeps its kind: the spec's invalid fields as a list
//! ([`FieldErrors`], each naming the file and line when the spec came from a file), the TOML
//! parser's and the I/O layer's errors as they are, and the field solver's, the mesher's and the
//! material library's errors wrapped typed (a Newton failure keeps its residual history) with their
//! [`Kind`] delegated.
//!
//! Errors of a spec (`Read`, `Parse`, `Spec`) and of arguments (`Input`) say everything in their own
//! text. Wrapped errors say where they happened ("field solution", "meshing the brake") and chain
//! to the cause through [`std::error::Error::source`], as the `{:#}` of the CLI prints them.

use std::path::PathBuf;

use mrbrake_error::{ErrorKind, FieldError, FieldErrors, Kind};

/// Errors of this crate.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum DesignError {
    /// A spec file could not be read (a missing file is an input error, a failing disk I/O).
    #[error("{}: cannot read the spec", path.display())]
    Read {
        /// The file.
        path: PathBuf,
        /// The I/O error.
        source: std::io::Error,
    },
    /// A spec is not TOML, or has an unknown or mistyped field or a quantity with a wrong unit;
    /// the parser's error shows the line.
    #[error("{origin}: {error}")]
    Parse {
        /// Where the text came from (a file name).
        origin: String,
        /// The TOML parser's error (it names the field and shows the line).
        error: Box<toml::de::Error>,
    },
    /// A spec with invalid fields: every one of them, each naming its field and allowed range (and
    /// the file and line when the spec was read from a file).
    #[error("invalid brake spec '{name}':{}", list(errors))]
    Spec {
        /// The spec's name.
        name: String,
        /// The invalid fields.
        errors: FieldErrors,
    },
    /// An argument of a formula, an analysis option, or a spec field the analysis cannot take
    /// (a material without the data it needs, a part too thin for the mesh): the field (an
    /// argument such as `r1`, an option such as `points`, a spec path such as `materials.fluid`),
    /// the value and what is allowed. The front ends rename the field to their flag or keyword
    /// ([`DesignError::with_field_names`]). Fields of an invalid spec are reported by
    /// [`DesignError::Spec`].
    #[error(transparent)]
    Input(Box<FieldError>),
    /// The field solution failed: an invalid problem, or Newton did not converge (the wrapped
    /// error keeps the residual history).
    #[error("field solution")]
    FieldSolution(#[from] mrbrake_magnetics::MagneticsError),
    /// A step of a quasi-static hysteresis loop ([`crate::hysteresis`]) failed: which step, at
    /// what current (the wrapped error keeps Newton's residual history).
    #[error("hysteresis loop: step {step} at {current_a} A")]
    LoopStep {
        /// The step (1-based) of the current history.
        step: usize,
        /// Its current, A.
        current_a: f64,
        /// The field solution's error.
        source: Box<DesignError>,
    },
    /// The mesher could not mesh the brake's geometry.
    #[error("meshing the brake")]
    Mesh(#[from] mrbrake_fem::FemError),
    /// A material of the library (an unknown name, a material that does not suit its use).
    #[error(transparent)]
    Material(#[from] mrbrake_materials::MaterialError),
    /// The material of one part of the geometry.
    #[error("material of part '{part}'")]
    PartMaterial {
        /// The part (region) name, e.g. `unit1.core`.
        part: String,
        /// The library's error.
        source: mrbrake_materials::MaterialError,
    },
    /// A row of a design study (the study's label, the analysis's error).
    #[error("study row '{label}'")]
    StudyRow {
        /// The row, e.g. `d = 1.5 mm`.
        label: String,
        /// Why its analysis failed.
        source: Box<DesignError>,
    },
    /// The planar graph of a validated geometry was refused (a defect of mrbrake, not of the
    /// spec: please report the spec).
    #[error("geometry → {stage} (please report this spec)")]
    GeometryGraph {
        /// What was being built, e.g. `mesh` or `.geo`.
        stage: &'static str,
        /// The mesher's error.
        source: mrbrake_fem::FemError,
    },
    /// A spec could not be written as TOML.
    #[error("cannot write spec '{name}' as TOML")]
    WriteToml {
        /// The spec's name.
        name: String,
        /// The TOML writer's error.
        source: toml::ser::Error,
    },
    /// The caller's observer stopped the analysis's current sweep
    /// ([`crate::analysis::AnalysisRequest::observe`]); the curve points solved so far are kept.
    #[error("the analysis was stopped after {} of {total} currents", curve.len())]
    Stopped {
        /// Direction 1's curve points solved before the stop, in sweep order.
        curve: Vec<crate::analysis::CurvePoint>,
        /// Currents the sweep would have solved.
        total: usize,
    },
    /// A broken internal contract (a bug in mrbrake: please report it).
    #[error("internal error: {0}")]
    Internal(String),
}

/// One invalid field per line, indented under the spec's name.
fn list(errors: &FieldErrors) -> String {
    errors.errors().iter().map(|e| format!("\n  {e}")).collect()
}

impl Kind for DesignError {
    /// Input for specs and arguments; the kind of the wrapped error for the field solution, the
    /// mesher, materials, study rows and unreadable files; internal for defects. A stop is the
    /// caller's own request, not a failure: input, the kind a caller can act on by asking again.
    fn kind(&self) -> ErrorKind {
        match self {
            Self::Parse { .. } | Self::Spec { .. } | Self::Input(_) | Self::Stopped { .. } => {
                ErrorKind::Input
            }
            Self::Read { source, .. } => Kind::kind(source),
            Self::FieldSolution(e) => e.kind(),
            Self::Mesh(e) => e.kind(),
            Self::Material(e) | Self::PartMaterial { source: e, .. } => e.kind(),
            Self::StudyRow { source, .. } | Self::LoopStep { source, .. } => source.kind(),
            Self::GeometryGraph { .. } | Self::WriteToml { .. } | Self::Internal(_) => {
                ErrorKind::Internal
            }
        }
    }
}

impl From<FieldError> for DesignError {
    fn from(error: FieldError) -> Self {
        Self::Input(Box::new(error))
    }
}

impl DesignError {
    /// The same error with the field of an input error named as a front end names it (see
    /// [`FieldError::renamed`]: the CLI's `--points` for `points`); other errors are unchanged.
    pub fn with_field_names(self, names: &[(&str, &str)]) -> Self {
        match self {
            Self::Input(field) => Self::Input(Box::new(field.renamed(names))),
            Self::StudyRow { label, source } => {
                Self::StudyRow { label, source: Box::new(source.with_field_names(names)) }
            }
            other => other,
        }
    }

    /// The invalid fields, when this is a [`DesignError::Spec`] (or a study row that failed for one).
    pub fn field_errors(&self) -> Option<&FieldErrors> {
        match self {
            Self::Spec { errors, .. } => Some(errors),
            Self::StudyRow { source, .. } => source.field_errors(),
            _ => None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spec_errors_list_every_field_and_wrapped_errors_keep_their_kind() {
        let mut errors = FieldErrors::new();
        errors.push(FieldError::new("drum.gap", "must be > 0").in_file("a.toml", Some(12)));
        errors.add("coil.turns", "must be at least 1");
        let e = DesignError::Spec { name: "b".into(), errors };
        assert_eq!(
            e.to_string(),
            "invalid brake spec 'b':\n  a.toml:12: drum.gap: must be > 0\n  coil.turns: must be at least 1"
        );
        assert_eq!(e.kind(), ErrorKind::Input);
        assert_eq!(e.field_errors().map(FieldErrors::len), Some(2));
        let numerical = DesignError::FieldSolution(mrbrake_magnetics::MagneticsError::Numerical(
            "singular".into(),
        ));
        let row = DesignError::StudyRow { label: "d = 1 mm".into(), source: Box::new(numerical) };
        assert_eq!(row.kind(), ErrorKind::Numerical);
        let missing = DesignError::Read {
            path: "x.toml".into(),
            source: std::io::ErrorKind::NotFound.into(),
        };
        assert!(missing.is_input_error());
    }

    #[test]
    fn an_input_error_names_its_field_as_the_front_end_does() {
        let e = DesignError::from(FieldError::out_of_range("points", 1, ">= 2"));
        assert_eq!(e.kind(), ErrorKind::Input);
        let row = DesignError::StudyRow { label: "d = 1 mm".into(), source: Box::new(e) };
        let renamed = row.with_field_names(&[("points", "--points")]);
        let DesignError::StudyRow { source, .. } = renamed else { panic!("{renamed:?}") };
        assert_eq!(source.to_string(), "--points: got 1; allowed: >= 2");
    }
}
