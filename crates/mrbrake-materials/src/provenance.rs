//! Where a number comes from and how far to trust it.
//!
//! Every built-in curve and property carries a [`Provenance`]: its source (file, library, paper), the
//! method that produced the numbers (copied, fit formula evaluated, estimated) and a [`Trust`] level.
//! The scale follows `data/SOURCES.md`: **high** = library or standard data checked against a second
//! source; **medium** = standard data of unknown measurement origin or a single copy; **low** = unclear
//! provenance or a fit used beyond what it was built for.

use serde::Serialize;

/// How far a number can be trusted (ordered from least to most).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Trust {
    /// Supplied by the user; mrbrake cannot rate it.
    User,
    /// Unclear provenance, or a fit used beyond what it was built for.
    Low,
    /// Between low and medium: a generic fit, or a single undocumented copy.
    MediumLow,
    /// Standard library data of unknown measurement origin, or only one copy.
    Medium,
    /// Two independent copies agree, measurement origin undocumented.
    MediumHigh,
    /// Library or standard data, checked against a second source.
    High,
}

impl Trust {
    /// The level in words, as used in `data/SOURCES.md`.
    pub fn as_str(self) -> &'static str {
        match self {
            Trust::User => "user-supplied (not rated)",
            Trust::Low => "low",
            Trust::MediumLow => "medium-low",
            Trust::Medium => "medium",
            Trust::MediumHigh => "medium-high",
            Trust::High => "high",
        }
    }
}

impl std::fmt::Display for Trust {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.as_str())
    }
}

/// Source, method and trust of a curve or a property.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct Provenance {
    /// Where the numbers come from (library, file, commit, paper).
    pub source: String,
    /// How they were obtained (copied, fit formula evaluated, estimated) and how mrbrake uses them.
    pub method: String,
    /// How far to trust them.
    pub trust: Trust,
}

impl Provenance {
    /// A provenance record.
    pub fn new(source: impl Into<String>, method: impl Into<String>, trust: Trust) -> Self {
        Self { source: source.into(), method: method.into(), trust }
    }

    /// The provenance of a user file: the path is the source, trust is [`Trust::User`].
    pub fn user_file(file: &str) -> Self {
        Self::new(file, "read from a user CSV file and validated", Trust::User)
    }
}

/// A value together with its provenance (a density, a viscosity, a conductivity).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Sourced<T> {
    /// The value in SI units.
    pub value: T,
    /// Where it comes from.
    pub provenance: Provenance,
}

impl<T> Sourced<T> {
    /// Pairs a value with its provenance.
    pub fn new(value: T, provenance: Provenance) -> Self {
        Self { value, provenance }
    }
}
