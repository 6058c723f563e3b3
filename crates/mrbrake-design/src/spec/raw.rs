//! The file's flat form of a spec: `configuration = "…"` beside optional `[drum]`, `[disc]` and
//! `[spacer]` tables. A [`BrakeSpec`] is read and written through it, so the TOML files and the
//! JSON of a spec (which the results store's design keys hash: field names, `null` for an absent
//! table) stay what they were before the configuration carried its tables; a missing or
//! superfluous table is reported here, naming it.

use schemars::JsonSchema;
use serde::{Deserialize, Deserializer, Serialize, Serializer};

use mrbrake_error::{FieldError, FieldErrors};

use super::{
    BrakeSpec, Coil, Configuration, ConfigurationKind, Disc, Drum, Envelope, FluidFactors, Housing,
    Materials, Model, Shaft, Spacer, SpecSource, SteelFactors,
};
use crate::DesignError;
use crate::drag::Drag;

/// A spec as the file writes it. The field order is the file's and the JSON's.
#[derive(Debug, Clone, Deserialize, Serialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub(super) struct RawSpec {
    /// A short name for reports.
    name: String,
    /// The brake configuration; it decides which of `[drum]`, `[disc]` and `[spacer]` the file
    /// has (drums: `drum`, `multi-drum`, `bidirectional` with `[drum]`; discs: `single-disc`,
    /// `multi-disc` with `[disc]`; the bidirectional brake also `[spacer]`).
    configuration: ConfigurationKind,
    /// Material of each part, by name in the material library (`mrbrake materials list`).
    materials: Materials,
    /// The shaft.
    shaft: Shaft,
    /// The static magnetic circuit and the non-magnetic closures around the working surfaces.
    housing: Housing,
    /// The cylindrical working surfaces (drum configurations only).
    #[serde(default)]
    drum: Option<Drum>,
    /// The annular working surfaces (disc configurations only).
    #[serde(default)]
    disc: Option<Disc>,
    /// The coil (one per unit).
    coil: Coil,
    /// The spacer between the two units (the bidirectional brake only).
    #[serde(default)]
    spacer: Option<Spacer>,
    /// The envelope the device must fit in.
    envelope: Envelope,
    /// Model (not device) settings.
    #[serde(default)]
    model: Model,
    /// Factors on the library fluid of the gaps (uncertainty and calibration); written only when
    /// one differs from its default, so a spec without them keeps its design key.
    #[serde(default, skip_serializing_if = "FluidFactors::is_default")]
    fluid: FluidFactors,
    /// Factors on the library steel of the flux path; written only when one differs from its
    /// default.
    #[serde(default, skip_serializing_if = "SteelFactors::is_default")]
    steel: SteelFactors,
    /// The mechanical drag besides the fluid: seals, bearings, one-way bearings (optional; an
    /// absent table is left out of the JSON, so design keys of specs without it do not move).
    #[serde(default, skip_serializing_if = "Drag::is_default")]
    drag: Drag,
}

impl RawSpec {
    /// The spec, or an input error naming each missing or superfluous table (located in `source`).
    pub(super) fn into_spec(self, source: SpecSource) -> Result<BrakeSpec, DesignError> {
        let Self {
            name,
            configuration,
            materials,
            shaft,
            housing,
            drum,
            disc,
            coil,
            spacer,
            envelope,
            model,
            fluid,
            steel,
            drag,
        } = self;
        let mut errors = FieldErrors::new();
        let tables = Tables { drum, disc, spacer };
        match tables.configuration(configuration, &source, &mut errors) {
            Some(configuration) if errors.is_empty() => Ok(BrakeSpec {
                name,
                configuration,
                materials,
                shaft,
                housing,
                coil,
                envelope,
                model,
                fluid,
                steel,
                drag,
                source,
            }),
            _ => Err(DesignError::Spec { name, errors: source.locate(errors) }),
        }
    }
}

/// The tables a configuration may carry, as read.
struct Tables {
    drum: Option<Drum>,
    disc: Option<Disc>,
    spacer: Option<Spacer>,
}

impl Tables {
    /// The configuration `kind` with its tables; every missing or superfluous table is added to
    /// `errors` (a missing one located at the `configuration` line, a superfluous one at its own).
    fn configuration(
        self,
        kind: ConfigurationKind,
        source: &SpecSource,
        errors: &mut FieldErrors,
    ) -> Option<Configuration> {
        let Self { drum, disc, spacer } = self;
        let rules = [
            ("drum", drum.is_some(), kind.requires_table("drum"), "its working surfaces"),
            ("disc", disc.is_some(), kind.requires_table("disc"), "its working surfaces"),
            (
                "spacer",
                spacer.is_some(),
                kind.requires_table("spacer"),
                "the spacer between the units",
            ),
        ];
        for (table, present, needed, what) in rules {
            let message = match (present, needed) {
                (false, true) => format!(
                    "required for configuration \"{}\": add a [{table}] table ({what})",
                    kind.name()
                ),
                (true, false) => format!(
                    "configuration \"{}\" has no {table}{}; remove the [{table}] table",
                    kind.name(),
                    if table == "spacer" { " (only the bidirectional brake has one)" } else { "" }
                ),
                _ => continue,
            };
            let anchor = if present { table } else { "configuration" };
            errors.push(FieldError {
                line: source.line_of(anchor),
                ..FieldError::new(table, message)
            });
        }
        Some(match kind {
            ConfigurationKind::SingleDisc => Configuration::SingleDisc(disc?),
            ConfigurationKind::MultiDisc => Configuration::MultiDisc(disc?),
            ConfigurationKind::Drum => Configuration::Drum(drum?),
            ConfigurationKind::MultiDrum => Configuration::MultiDrum(drum?),
            ConfigurationKind::Bidirectional => {
                Configuration::Bidirectional { drum: drum?, spacer: spacer? }
            }
        })
    }
}

impl From<&BrakeSpec> for RawSpec {
    fn from(spec: &BrakeSpec) -> Self {
        let c = &spec.configuration;
        Self {
            name: spec.name.clone(),
            configuration: c.kind(),
            materials: spec.materials.clone(),
            shaft: spec.shaft.clone(),
            housing: spec.housing.clone(),
            drum: c.drum().cloned(),
            disc: c.disc().cloned(),
            coil: spec.coil.clone(),
            spacer: c.spacer().cloned(),
            envelope: spec.envelope.clone(),
            model: spec.model.clone(),
            fluid: spec.fluid.clone(),
            steel: spec.steel.clone(),
            drag: spec.drag.clone(),
        }
    }
}

impl Serialize for BrakeSpec {
    /// The file's flat form (see the module docs).
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        RawSpec::from(self).serialize(serializer)
    }
}

impl<'de> Deserialize<'de> for BrakeSpec {
    /// The file's flat form; a missing or superfluous table is an error naming it. No file or line
    /// is recorded: [`BrakeSpec::from_toml_str`] records them.
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        RawSpec::deserialize(deserializer)?
            .into_spec(SpecSource::default())
            .map_err(serde::de::Error::custom)
    }
}
